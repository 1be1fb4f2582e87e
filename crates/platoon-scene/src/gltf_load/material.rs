//! glTF materials and textures in platoon's terms.

use glam::{Vec3, Vec4};

use super::validate::Check;
use crate::*;

fn wrap(mode: gltf::texture::WrappingMode) -> Wrap {
    match mode {
        gltf::texture::WrappingMode::ClampToEdge => Wrap::ClampToEdge,
        gltf::texture::WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
        gltf::texture::WrappingMode::Repeat => Wrap::Repeat,
    }
}

/// The image a texture shows: KHR_texture_basisu's or EXT_texture_webp's source where the file
/// gives one (its `source` is then a fallback, or absent), else its own.
pub fn texture_image(t: &gltf::Texture, images: usize) -> Check<usize> {
    let extension_source = |name: &str| {
        t.extension_value(name)
            .and_then(|e| e.get("source"))
            .map(|s| {
                s.as_u64()
                    .ok_or(format!("{name}'s source is not an image index"))
            })
            .transpose()
    };
    let chosen = match extension_source("KHR_texture_basisu")? {
        Some(k) => Some(k),
        None => extension_source("EXT_texture_webp")?,
    };
    let index = match (chosen, own_image(t)) {
        (Some(w), _) => w as usize,
        (None, Some(image)) => image.index(),
        (None, None) => return Err(format!("texture {} has no image", t.index())),
    };
    if index >= images {
        return Err(format!(
            "texture {} shows image {index}; the file has {images}",
            t.index()
        ));
    }
    Ok(index)
}

/// The texture's own image (glTF's `source`), absent only where the loader takes textures
/// without one (the feature `gltf-textures-without-source`).
fn own_image<'a>(t: &gltf::Texture<'a>) -> Option<gltf::Image<'a>> {
    #[cfg(feature = "gltf-textures-without-source")]
    return t.source();
    #[cfg(not(feature = "gltf-textures-without-source"))]
    return Some(t.source());
}

/// Texture `t`, showing a `width` x `height` image of RGBA8 `pixels`.
pub fn texture(t: &gltf::Texture, width: u32, height: u32, pixels: Vec<u8>) -> Texture {
    let sampler = t.sampler();
    Texture {
        name: t
            .name()
            .or(own_image(t).and_then(|s| s.name()))
            .unwrap_or("")
            .to_string(),
        width,
        height,
        rgba8: pixels,
        wrap_s: wrap(sampler.wrap_s()),
        wrap_t: wrap(sampler.wrap_t()),
        // Minification needs no filter of its own: a pixel's many samples average the texels
        // (unless `--texture-lod ray-cone` makes mip levels, texture_levels).
        nearest: sampler.mag_filter() == Some(gltf::texture::MagFilter::Nearest),
        mips: Vec::new(),
    }
}

fn tex_ref(info: Option<gltf::texture::Info>, what: &str) -> Check<Option<TextureRef>> {
    let Some(info) = info else {
        return Ok(None);
    };
    let transform = info.extension_value("KHR_texture_transform");
    texture_ref(info.texture().index(), info.tex_coord(), transform, what).map(Some)
}

/// A texture reference with its UV set and KHR_texture_transform (`transform`, the extension's
/// JSON object, whose texCoord overrides the reference's).
fn texture_ref(
    texture: usize,
    tex_coord: u32,
    transform: Option<&serde_json::Value>,
    what: &str,
) -> Check<TextureRef> {
    let mut r = TextureRef::new(texture as u32);
    r.tex_coord = tex_coord;
    if let Some(t) = transform {
        let numbers = |key: &str, default: &[f32]| -> Check<Vec<f32>> {
            match t.get(key) {
                None => Ok(default.to_vec()),
                Some(v) => {
                    let parsed: Option<Vec<f32>> = match v {
                        serde_json::Value::Array(a) => {
                            a.iter().map(|x| x.as_f64().map(|x| x as f32)).collect()
                        }
                        x => x.as_f64().map(|x| vec![x as f32]),
                    };
                    match parsed {
                        Some(p) if p.len() == default.len() && p.iter().all(|x| x.is_finite()) => {
                            Ok(p)
                        }
                        _ => Err(format!(
                            "{what}: KHR_texture_transform {key} is not {} finite number(s)",
                            default.len()
                        )),
                    }
                }
            }
        };
        let offset = numbers("offset", &[0.0, 0.0])?;
        let rotation = numbers("rotation", &[0.0])?[0];
        let scale = numbers("scale", &[1.0, 1.0])?;
        // uv' = T(offset) R(rotation) S(scale) uv, with the spec's rotation matrix
        // [cos sin; -sin cos] (counter-clockwise in UV space, whose v points down).
        let (s, c) = rotation.sin_cos();
        r.transform = [
            [c * scale[0], s * scale[1], offset[0]],
            [-s * scale[0], c * scale[1], offset[1]],
        ];
        if let Some(set) = t.get("texCoord") {
            r.tex_coord = set.as_u64().ok_or(format!(
                "{what}: KHR_texture_transform texCoord is not an index"
            ))? as u32;
        }
    }
    if r.tex_coord > 1 {
        return Err(format!(
            "{what} reads TEXCOORD_{}; platoon reads TEXCOORD_0 and TEXCOORD_1",
            r.tex_coord
        ));
    }
    Ok(r)
}

/// A texture reference the `gltf` crate does not model (an extension's `textureInfo` or
/// `normalTextureInfo` JSON object), checked against the file's `textures`; with a normal
/// texture's scale.
fn json_tex_ref(
    info: Option<&serde_json::Value>,
    what: &str,
    textures: usize,
) -> Check<Option<(TextureRef, f32)>> {
    let Some(info) = info else {
        return Ok(None);
    };
    let index = info
        .get("index")
        .and_then(|i| i.as_u64())
        .ok_or(format!("{what} has no texture index"))? as usize;
    if index >= textures {
        return Err(format!(
            "{what} names texture {index}; the file has {textures}"
        ));
    }
    let tex_coord = match info.get("texCoord") {
        None => 0,
        Some(t) => t
            .as_u64()
            .ok_or(format!("{what}: texCoord is not an index"))? as u32,
    };
    let transform = info
        .get("extensions")
        .and_then(|e| e.get("KHR_texture_transform"));
    let scale = match info.get("scale") {
        None => 1.0,
        Some(s) => s.as_f64().ok_or(format!("{what}: scale is not a number"))? as f32,
    };
    Ok(Some((
        texture_ref(index, tex_coord, transform, what)?,
        scale,
    )))
}

/// A number of an extension's JSON object, `default` when absent.
fn json_number(ext: &serde_json::Value, key: &str, default: f32, what: &str) -> Check<f32> {
    match ext.get(key) {
        None => Ok(default),
        Some(v) => v
            .as_f64()
            .map(|x| x as f32)
            .ok_or(format!("{what}: {key} is not a number")),
    }
}

/// A colour (three numbers) of an extension's JSON object, `default` when absent.
fn json_rgb(ext: &serde_json::Value, key: &str, default: Vec3, what: &str) -> Check<Vec3> {
    let Some(c) = ext.get(key) else {
        return Ok(default);
    };
    let c: Option<Vec<f32>> = c
        .as_array()
        .and_then(|a| a.iter().map(|x| x.as_f64().map(|x| x as f32)).collect());
    match c.as_deref() {
        Some(&[r, g, b]) => Ok(Vec3::new(r, g, b)),
        _ => Err(format!("{what}: {key} is not three numbers")),
    }
}

/// KHR_materials_sheen (the `gltf` crate does not model it) onto `mat`.
fn sheen(m: &gltf::Material, mat: &mut Material, textures: usize) -> Check<()> {
    let Some(ext) = m.extension_value("KHR_materials_sheen") else {
        return Ok(());
    };
    let what = "KHR_materials_sheen";
    mat.sheen_color = json_rgb(ext, "sheenColorFactor", Vec3::ZERO, what)?;
    mat.sheen_roughness = json_number(ext, "sheenRoughnessFactor", 0.0, what)?;
    let tex = |key: &str| json_tex_ref(ext.get(key), &format!("{what} {key}"), textures);
    mat.sheen_color_texture = tex("sheenColorTexture")?.map(|t| t.0);
    mat.sheen_roughness_texture = tex("sheenRoughnessTexture")?.map(|t| t.0);
    Ok(())
}

/// KHR_materials_volume (read from its JSON, as the other extensions) onto `mat`.
fn volume(m: &gltf::Material, mat: &mut Material) -> Check<()> {
    let Some(ext) = m.extension_value("KHR_materials_volume") else {
        return Ok(());
    };
    let what = "KHR_materials_volume";
    mat.thickness = json_number(ext, "thicknessFactor", 0.0, what)?;
    mat.attenuation_distance = json_number(ext, "attenuationDistance", f32::INFINITY, what)?;
    mat.attenuation_color = json_rgb(ext, "attenuationColor", Vec3::ONE, what)?;
    if mat.attenuation_distance <= 0.0 {
        return Err(format!("{what}: attenuationDistance is not above 0"));
    }
    Ok(())
}

/// KHR_materials_iridescence (the `gltf` crate does not model it) onto `mat`.
fn iridescence(m: &gltf::Material, mat: &mut Material, textures: usize) -> Check<()> {
    let Some(ext) = m.extension_value("KHR_materials_iridescence") else {
        return Ok(());
    };
    let what = "KHR_materials_iridescence";
    mat.iridescence = json_number(ext, "iridescenceFactor", 0.0, what)?;
    // The ratified spec's key (drafts, and some exporters still, wrote iridescenceIOR).
    let ior_key = match ext.get("iridescenceIor") {
        None if ext.get("iridescenceIOR").is_some() => "iridescenceIOR",
        _ => "iridescenceIor",
    };
    mat.iridescence_ior = json_number(ext, ior_key, 1.3, what)?;
    mat.iridescence_thickness_min = json_number(ext, "iridescenceThicknessMinimum", 100.0, what)?;
    mat.iridescence_thickness_max = json_number(ext, "iridescenceThicknessMaximum", 400.0, what)?;
    let tex = |key: &str| json_tex_ref(ext.get(key), &format!("{what} {key}"), textures);
    mat.iridescence_texture = tex("iridescenceTexture")?.map(|t| t.0);
    mat.iridescence_thickness_texture = tex("iridescenceThicknessTexture")?.map(|t| t.0);
    if mat.iridescence_ior < 1.0 {
        return Err(format!("{what}: iridescenceIor is below 1"));
    }
    if mat.iridescence_thickness_min < 0.0 || mat.iridescence_thickness_max < 0.0 {
        return Err(format!("{what}: a thickness is below 0"));
    }
    Ok(())
}

/// KHR_materials_anisotropy (the `gltf` crate does not model it) onto `mat`.
fn anisotropy(m: &gltf::Material, mat: &mut Material, textures: usize) -> Check<()> {
    let Some(ext) = m.extension_value("KHR_materials_anisotropy") else {
        return Ok(());
    };
    let what = "KHR_materials_anisotropy";
    mat.anisotropy_strength = json_number(ext, "anisotropyStrength", 0.0, what)?;
    mat.anisotropy_rotation = json_number(ext, "anisotropyRotation", 0.0, what)?;
    let tex = |key: &str| json_tex_ref(ext.get(key), &format!("{what} {key}"), textures);
    mat.anisotropy_texture = tex("anisotropyTexture")?.map(|t| t.0);
    Ok(())
}

/// KHR_materials_dispersion (the `gltf` crate does not model it) onto `mat`.
fn dispersion(m: &gltf::Material, mat: &mut Material) -> Check<()> {
    let Some(ext) = m.extension_value("KHR_materials_dispersion") else {
        return Ok(());
    };
    let what = "KHR_materials_dispersion";
    mat.dispersion = json_number(ext, "dispersion", 0.0, what)?;
    if mat.dispersion < 0.0 {
        return Err(format!("{what}: dispersion is below 0"));
    }
    Ok(())
}

/// KHR_materials_clearcoat (the `gltf` crate does not model it) onto `mat`.
fn clearcoat(m: &gltf::Material, mat: &mut Material, textures: usize) -> Check<()> {
    let Some(ext) = m.extension_value("KHR_materials_clearcoat") else {
        return Ok(());
    };
    let what = "KHR_materials_clearcoat";
    mat.clearcoat = json_number(ext, "clearcoatFactor", 0.0, what)?;
    mat.clearcoat_roughness = json_number(ext, "clearcoatRoughnessFactor", 0.0, what)?;
    let tex = |key: &str| json_tex_ref(ext.get(key), &format!("{what} {key}"), textures);
    mat.clearcoat_texture = tex("clearcoatTexture")?.map(|t| t.0);
    mat.clearcoat_roughness_texture = tex("clearcoatRoughnessTexture")?.map(|t| t.0);
    if let Some((t, scale)) = tex("clearcoatNormalTexture")? {
        mat.clearcoat_normal_texture = Some(t);
        mat.clearcoat_normal_scale = scale;
    }
    Ok(())
}

/// KHR_materials_diffuse_transmission (the `gltf` crate does not model it) onto `mat`.
fn diffuse_transmission(m: &gltf::Material, mat: &mut Material, textures: usize) -> Check<()> {
    let Some(ext) = m.extension_value("KHR_materials_diffuse_transmission") else {
        return Ok(());
    };
    let what = "KHR_materials_diffuse_transmission";
    mat.diffuse_transmission = json_number(ext, "diffuseTransmissionFactor", 0.0, what)?;
    mat.diffuse_transmission_color =
        json_rgb(ext, "diffuseTransmissionColorFactor", Vec3::ONE, what)?;
    let tex = |key: &str| json_tex_ref(ext.get(key), &format!("{what} {key}"), textures);
    mat.diffuse_transmission_texture = tex("diffuseTransmissionTexture")?.map(|t| t.0);
    mat.diffuse_transmission_color_texture = tex("diffuseTransmissionColorTexture")?.map(|t| t.0);
    Ok(())
}

/// Roughness textures made from specular-glossiness textures (`spec_gloss`), each once per
/// texture and glossiness factor: (texture, factor bits) -> the made texture.
#[derive(Default)]
pub struct GlossinessTextures {
    made: Vec<((u32, u32), u32)>,
}

impl GlossinessTextures {
    /// The texture whose green channel is the roughness 1 - factor * glossiness of `texture`'s
    /// alpha, appended to `textures` the first time it is asked for.
    fn roughness_of(&mut self, textures: &mut Vec<Texture>, texture: u32, factor: f32) -> u32 {
        let key = (texture, factor.to_bits());
        if let Some(&(_, made)) = self.made.iter().find(|(k, _)| *k == key) {
            return made;
        }
        let source = &textures[texture as usize];
        let rgba8 = source
            .rgba8
            .chunks_exact(4)
            .flat_map(|p| {
                let roughness = 1.0 - factor * p[3] as f32 / 255.0;
                [0, (roughness.clamp(0.0, 1.0) * 255.0).round() as u8, 0, 255]
            })
            .collect();
        textures.push(Texture {
            name: format!("{} (roughness from glossiness)", source.name),
            rgba8,
            ..source.clone()
        });
        let made = textures.len() as u32 - 1;
        self.made.push((key, made));
        made
    }
}

/// KHR_materials_pbrSpecularGlossiness (archived; superseded by KHR_materials_specular) turned
/// into the metallic-roughness material it describes, as glTF-Transform's `metalRough` converts
/// files: a dielectric of the diffuse colour and texture, specular layer of the specular colour
/// (KHR_materials_specular's colour and its texture, the same sRGB RGB channels) at an index
/// of refraction of 1000 (so its f0 is that colour: ((1000 - 1) / 1001)^2 = 0.996), roughness
/// 1 - glossiness (a texture's alpha made into a roughness texture).
fn spec_gloss(
    m: &gltf::Material,
    mat: &mut Material,
    textures: &mut Vec<Texture>,
    glossiness: &mut GlossinessTextures,
) -> Check<()> {
    let Some(sg) = m.pbr_specular_glossiness() else {
        return Ok(());
    };
    mat.base_color = Vec4::from_array(sg.diffuse_factor());
    mat.base_color_texture = tex_ref(sg.diffuse_texture(), "diffuseTexture")?;
    mat.metallic = 0.0;
    mat.metallic_roughness_texture = None;
    mat.specular = 1.0;
    mat.specular_texture = None;
    mat.specular_color = Vec3::from_array(sg.specular_factor());
    mat.ior = 1000.0;
    let gloss = sg.glossiness_factor();
    mat.roughness = 1.0 - gloss;
    mat.specular_color_texture = None;
    if let Some(info) = sg.specular_glossiness_texture() {
        let r = tex_ref(Some(info), "specularGlossinessTexture")?.expect("a texture");
        mat.specular_color_texture = Some(r);
        mat.roughness = 1.0;
        mat.metallic_roughness_texture = Some(TextureRef {
            texture: glossiness.roughness_of(textures, r.texture, gloss),
            ..r
        });
    }
    Ok(())
}

/// The material, or why it cannot be rendered (a factor that is not finite: JSON numbers past
/// f32's range read as infinity). `textures`: the file's (for the references the `gltf` crate
/// does not check, an extension's; a specular-glossiness material adds one).
pub fn material(
    m: &gltf::Material,
    textures: &mut Vec<Texture>,
    glossiness: &mut GlossinessTextures,
) -> Check<Material> {
    let pbr = m.pbr_metallic_roughness();
    let name = m.name().unwrap_or("").to_string();
    let mut mat = Material {
        name: name.clone(),
        base_color: Vec4::from_array(pbr.base_color_factor()),
        base_color_texture: tex_ref(pbr.base_color_texture(), "baseColorTexture")?,
        metallic: pbr.metallic_factor(),
        roughness: pbr.roughness_factor(),
        metallic_roughness_texture: tex_ref(
            pbr.metallic_roughness_texture(),
            "metallicRoughnessTexture",
        )?,
        normal_texture: None,
        normal_scale: 1.0,
        emissive: Vec3::from_array(m.emissive_factor()) * m.emissive_strength().unwrap_or(1.0),
        emissive_texture: tex_ref(m.emissive_texture(), "emissiveTexture")?,
        alpha_mode: match m.alpha_mode() {
            gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
            gltf::material::AlphaMode::Mask => AlphaMode::Mask(m.alpha_cutoff().unwrap_or(0.5)),
            gltf::material::AlphaMode::Blend => AlphaMode::Blend,
        },
        double_sided: m.double_sided(),
        ior: m.ior().unwrap_or(1.5),
        unlit: m.extension_value("KHR_materials_unlit").is_some(),
        ..Material::default()
    };
    if let Some(n) = m.normal_texture() {
        mat.normal_scale = n.scale();
        mat.normal_texture = Some(texture_ref(
            n.texture().index(),
            n.tex_coord(),
            n.extension_value("KHR_texture_transform"),
            "normalTexture",
        )?);
    }
    if let Some(s) = m.specular() {
        mat.specular = s.specular_factor();
        mat.specular_texture = tex_ref(s.specular_texture(), "specularTexture")?;
        mat.specular_color = Vec3::from_array(s.specular_color_factor());
        mat.specular_color_texture = tex_ref(s.specular_color_texture(), "specularColorTexture")?;
    }
    if let Some(t) = m.transmission() {
        mat.transmission = t.transmission_factor();
        mat.transmission_texture = tex_ref(t.transmission_texture(), "transmissionTexture")?;
    }
    clearcoat(m, &mut mat, textures.len())?;
    diffuse_transmission(m, &mut mat, textures.len())?;
    sheen(m, &mut mat, textures.len())?;
    volume(m, &mut mat)?;
    iridescence(m, &mut mat, textures.len())?;
    anisotropy(m, &mut mat, textures.len())?;
    dispersion(m, &mut mat)?;
    spec_gloss(m, &mut mat, textures, glossiness)?;
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
            mat.clearcoat,
            mat.clearcoat_roughness,
            mat.clearcoat_normal_scale,
            mat.diffuse_transmission,
            mat.sheen_roughness,
            mat.thickness,
            mat.iridescence,
            mat.iridescence_ior,
            mat.iridescence_thickness_min,
            mat.iridescence_thickness_max,
            mat.anisotropy_strength,
            mat.anisotropy_rotation,
            mat.dispersion,
        ],
        &mat.diffuse_transmission_color.to_array(),
        &mat.sheen_color.to_array(),
    ]
    .concat();
    if factors.iter().any(|f| !f.is_finite()) {
        return Err(format!("material '{name}' has a factor that is not finite"));
    }
    Ok(mat)
}
