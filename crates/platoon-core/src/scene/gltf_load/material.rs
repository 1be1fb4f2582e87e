//! glTF materials and textures in platoon's terms.

use glam::{Vec3, Vec4};

use super::resources::Rgba8;
use super::validate::Check;
use crate::scene::*;

fn wrap(mode: gltf::texture::WrappingMode) -> Wrap {
    match mode {
        gltf::texture::WrappingMode::ClampToEdge => Wrap::ClampToEdge,
        gltf::texture::WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
        gltf::texture::WrappingMode::Repeat => Wrap::Repeat,
    }
}

pub fn texture(t: &gltf::Texture, image: &Rgba8) -> Texture {
    let sampler = t.sampler();
    Texture {
        name: t.name().or(t.source().name()).unwrap_or("").to_string(),
        width: image.width,
        height: image.height,
        rgba8: image.pixels.clone(),
        wrap_s: wrap(sampler.wrap_s()),
        wrap_t: wrap(sampler.wrap_t()),
    }
}

fn tex_ref(
    info: Option<gltf::texture::Info>,
    what: &str,
    warnings: &mut Vec<String>,
) -> Option<TextureRef> {
    let info = info?;
    if info.tex_coord() != 0 {
        warnings.push(format!(
            "{what} uses TEXCOORD_{}; platoon reads TEXCOORD_0",
            info.tex_coord()
        ));
    }
    Some(TextureRef {
        texture: info.texture().index() as u32,
    })
}

/// The material, or why it cannot be rendered (a factor that is not finite: JSON numbers past
/// f32's range read as infinity).
pub fn material(m: &gltf::Material, warnings: &mut Vec<String>) -> Check<Material> {
    let pbr = m.pbr_metallic_roughness();
    let name = m.name().unwrap_or("").to_string();
    let mut mat = Material {
        name: name.clone(),
        base_color: Vec4::from_array(pbr.base_color_factor()),
        base_color_texture: tex_ref(pbr.base_color_texture(), "baseColorTexture", warnings),
        metallic: pbr.metallic_factor(),
        roughness: pbr.roughness_factor(),
        metallic_roughness_texture: tex_ref(
            pbr.metallic_roughness_texture(),
            "metallicRoughnessTexture",
            warnings,
        ),
        normal_texture: None,
        normal_scale: 1.0,
        emissive: Vec3::from_array(m.emissive_factor()) * m.emissive_strength().unwrap_or(1.0),
        emissive_texture: tex_ref(m.emissive_texture(), "emissiveTexture", warnings),
        alpha_mode: match m.alpha_mode() {
            gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
            gltf::material::AlphaMode::Mask => AlphaMode::Mask(m.alpha_cutoff().unwrap_or(0.5)),
            gltf::material::AlphaMode::Blend => {
                warnings.push(format!(
                    "material '{name}': alpha mode BLEND is rendered as OPAQUE"
                ));
                AlphaMode::Blend
            }
        },
        double_sided: m.double_sided(),
        ior: m.ior().unwrap_or(1.5),
        ..Material::default()
    };
    if let Some(n) = m.normal_texture() {
        mat.normal_scale = n.scale();
        mat.normal_texture = Some(TextureRef {
            texture: n.texture().index() as u32,
        });
    }
    if let Some(s) = m.specular() {
        mat.specular = s.specular_factor();
        mat.specular_texture = tex_ref(s.specular_texture(), "specularTexture", warnings);
        mat.specular_color = Vec3::from_array(s.specular_color_factor());
        mat.specular_color_texture =
            tex_ref(s.specular_color_texture(), "specularColorTexture", warnings);
    }
    if let Some(t) = m.transmission() {
        mat.transmission = t.transmission_factor();
        mat.transmission_texture =
            tex_ref(t.transmission_texture(), "transmissionTexture", warnings);
    }
    let factors = [
        mat.base_color.to_array().as_slice(),
        &mat.emissive.to_array(),
        &mat.specular_color.to_array(),
        &[
            mat.metallic,
            mat.roughness,
            mat.normal_scale,
            mat.specular,
            mat.transmission,
            mat.ior,
        ],
    ]
    .concat();
    if factors.iter().any(|f| !f.is_finite()) {
        return Err(format!("material '{name}' has a factor that is not finite"));
    }
    Ok(mat)
}
