//! Materials and textures as the kernel reads them: one material array, and every texture's
//! RGBA8 texels in one texel array.

use super::layout::{
    GpuMaterial, GpuTexture, MATERIAL_ALPHA_BLEND, MATERIAL_ALPHA_MASK, MATERIAL_DOUBLE_SIDED,
    MATERIAL_UNLIT, MATERIAL_USES_UV1, NO_TEXTURE, TEXTURE_MIPS_SHIFT, TEXTURE_SLOTS,
};
use super::GpuScene;
use platoon_scene::{AlphaMode, Scene, Wrap};

/// Appends the scene's materials and textures to `g`; first, where a material has a sheen, the
/// sheen's albedo table (the kernel reads it at texel 0).
pub(super) fn add(scene: &Scene, g: &mut GpuScene) {
    g.materials = scene.materials.iter().map(gpu_material).collect();
    if scene.materials.iter().any(|m| m.has_sheen()) {
        g.texels.extend(super::sheen_albedo::texels());
    }
    for t in &scene.textures {
        g.textures.push(GpuTexture {
            offset: g.texels.len() as u32,
            width: t.width,
            height: t.height,
            wrap: wrap_code(t.wrap_s)
                | wrap_code(t.wrap_t) << 2
                | (t.nearest as u32) << 4
                | (t.mips.len() as u32) << TEXTURE_MIPS_SHIFT,
        });
        // The image, then each level below it (textures.glsl's texture_level finds them).
        for level in std::iter::once(&t.rgba8).chain(t.mips.iter().map(|m| &m.rgba8)) {
            g.texels.extend(
                level
                    .chunks_exact(4)
                    .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])),
            );
        }
    }
}

fn tex(t: Option<platoon_scene::TextureRef>) -> i32 {
    t.map(|t| t.texture as i32).unwrap_or(NO_TEXTURE)
}

fn wrap_code(w: Wrap) -> u32 {
    match w {
        Wrap::Repeat => 0,
        Wrap::MirroredRepeat => 1,
        Wrap::ClampToEdge => 2,
    }
}

fn gpu_material(m: &platoon_scene::Material) -> GpuMaterial {
    let mut flags = 0;
    if m.double_sided {
        flags |= MATERIAL_DOUBLE_SIDED;
    }
    let cutoff = match m.alpha_mode {
        AlphaMode::Mask(c) => {
            flags |= MATERIAL_ALPHA_MASK;
            c
        }
        AlphaMode::Blend => {
            flags |= MATERIAL_ALPHA_BLEND;
            0.0
        }
        AlphaMode::Opaque => 0.0,
    };
    if m.unlit {
        flags |= MATERIAL_UNLIT;
    }
    if m.textures().any(|t| t.tex_coord == 1) {
        flags |= MATERIAL_USES_UV1;
    }
    let mut uv_rows = [[0.0; 4]; 2 * TEXTURE_SLOTS];
    for (k, slot) in m.texture_slots().iter().enumerate() {
        let r = slot.unwrap_or(platoon_scene::TextureRef::new(0));
        let [a, b] = r.transform;
        uv_rows[2 * k] = [a[0], a[1], a[2], r.tex_coord as f32];
        uv_rows[2 * k + 1] = [b[0], b[1], b[2], 0.0];
    }
    GpuMaterial {
        base_color: m.base_color.to_array(),
        emissive: m.emissive.extend(m.normal_scale).to_array(),
        params: [
            m.metallic.clamp(0.0, 1.0),
            m.roughness.clamp(0.0, 1.0),
            m.transmission.clamp(0.0, 1.0),
            m.ior.max(1.0),
        ],
        specular: m.specular_color.extend(m.specular.max(0.0)).to_array(),
        textures0: [
            tex(m.base_color_texture),
            tex(m.metallic_roughness_texture),
            tex(m.normal_texture),
            tex(m.emissive_texture),
        ],
        textures1: [
            tex(m.specular_texture),
            tex(m.specular_color_texture),
            tex(m.transmission_texture),
            flags,
        ],
        misc: [
            cutoff,
            m.anisotropy_strength.clamp(0.0, 1.0),
            m.anisotropy_rotation,
            m.dispersion.max(0.0),
        ],
        clearcoat: [
            m.clearcoat.clamp(0.0, 1.0),
            m.clearcoat_roughness.clamp(0.0, 1.0),
            m.clearcoat_normal_scale,
            0.0,
        ],
        textures2: [
            tex(m.clearcoat_texture),
            tex(m.clearcoat_roughness_texture),
            tex(m.clearcoat_normal_texture),
            tex(m.diffuse_transmission_texture),
        ],
        diffuse_transmission: m
            .diffuse_transmission_color
            .max(glam::Vec3::ZERO)
            .extend(m.diffuse_transmission.clamp(0.0, 1.0))
            .to_array(),
        textures3: [
            tex(m.diffuse_transmission_color_texture),
            tex(m.sheen_color_texture),
            tex(m.sheen_roughness_texture),
            tex(m.iridescence_texture),
        ],
        sheen: m
            .sheen_color
            .clamp(glam::Vec3::ZERO, glam::Vec3::ONE)
            .extend(m.sheen_roughness.clamp(0.0, 1.0))
            .to_array(),
        volume: m
            .absorption()
            .extend(if m.has_volume() { 1.0 } else { 0.0 })
            .to_array(),
        textures4: [
            tex(m.iridescence_thickness_texture),
            tex(m.anisotropy_texture),
            NO_TEXTURE,
            NO_TEXTURE,
        ],
        iridescence: [
            m.iridescence.clamp(0.0, 1.0),
            m.iridescence_ior.max(1.0),
            m.iridescence_thickness_min.max(0.0),
            m.iridescence_thickness_max.max(0.0),
        ],
        uv_rows,
    }
}
