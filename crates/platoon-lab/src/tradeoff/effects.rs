//! What each effect a scene calls for is worth: the scene rendered without it, replaced by its
//! cheapest stand-in (textures by their mean colour, normal maps off, transmission opaque, the
//! environment map by its mean radiance, each material extension off). The row's time says what
//! the effect costs (its code leaves the kernel too), its error what removing it would do to the
//! image.

use glam::{Vec3, Vec4};
use platoon_core::scene::environment::Environment;
use platoon_core::scene::{Material, Scene, Texture};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Effect {
    Textures,
    NormalMaps,
    Transmission,
    EnvironmentMap,
    /// KHR_materials_clearcoat.
    Clearcoat,
    /// KHR_materials_diffuse_transmission.
    DiffuseTransmission,
    /// KHR_materials_sheen.
    Sheen,
    /// KHR_materials_volume's absorption.
    Volume,
    /// KHR_materials_iridescence.
    Iridescence,
    /// KHR_materials_anisotropy.
    Anisotropy,
    /// KHR_materials_dispersion.
    Dispersion,
}

impl Effect {
    /// The technique's name: `no-textures`, `no-normal-maps`, `opaque`, `env-mean`,
    /// `no-clearcoat`, `no-diffuse-transmission`, `no-sheen`, `no-volume`, `no-iridescence`,
    /// `no-anisotropy`, `no-dispersion`.
    pub fn name(self) -> &'static str {
        match self {
            Effect::Textures => "no-textures",
            Effect::NormalMaps => "no-normal-maps",
            Effect::Transmission => "opaque",
            Effect::EnvironmentMap => "env-mean",
            Effect::Clearcoat => "no-clearcoat",
            Effect::DiffuseTransmission => "no-diffuse-transmission",
            Effect::Sheen => "no-sheen",
            Effect::Volume => "no-volume",
            Effect::Iridescence => "no-iridescence",
            Effect::Anisotropy => "no-anisotropy",
            Effect::Dispersion => "no-dispersion",
        }
    }

    pub fn parse(name: &str) -> Option<Effect> {
        [
            Effect::Textures,
            Effect::NormalMaps,
            Effect::Transmission,
            Effect::EnvironmentMap,
            Effect::Clearcoat,
            Effect::DiffuseTransmission,
            Effect::Sheen,
            Effect::Volume,
            Effect::Iridescence,
            Effect::Anisotropy,
            Effect::Dispersion,
        ]
        .into_iter()
        .find(|e| e.name() == name)
    }

    /// Replaces the effect in `scene` by its stand-in; false when the scene does not use it.
    pub fn remove(self, scene: &mut Scene) -> bool {
        match self {
            Effect::Textures => remove_textures(scene),
            Effect::NormalMaps => {
                let mut any = false;
                for m in &mut scene.materials {
                    any |= m.normal_texture.take().is_some();
                    any |= m.clearcoat_normal_texture.take().is_some();
                }
                any
            }
            Effect::Transmission => turn_off(
                scene,
                |m| m.transmission > 0.0,
                |m| {
                    m.transmission = 0.0;
                    m.transmission_texture = None;
                },
            ),
            Effect::Clearcoat => turn_off(scene, Material::has_clearcoat, |m| {
                m.clearcoat = 0.0;
                m.clearcoat_texture = None;
                m.clearcoat_roughness_texture = None;
                m.clearcoat_normal_texture = None;
            }),
            Effect::DiffuseTransmission => {
                turn_off(scene, Material::has_diffuse_transmission, |m| {
                    m.diffuse_transmission = 0.0;
                    m.diffuse_transmission_texture = None;
                    m.diffuse_transmission_color_texture = None;
                })
            }
            Effect::Sheen => turn_off(scene, Material::has_sheen, |m| {
                m.sheen_color = Vec3::ZERO;
                m.sheen_color_texture = None;
                m.sheen_roughness_texture = None;
            }),
            // Thin walls: the glass stays, its inside absorbs nothing.
            Effect::Volume => turn_off(scene, Material::absorbs, |m| m.thickness = 0.0),
            Effect::Iridescence => turn_off(scene, Material::has_iridescence, |m| {
                m.iridescence = 0.0;
                m.iridescence_texture = None;
                m.iridescence_thickness_texture = None;
            }),
            Effect::Anisotropy => turn_off(scene, Material::has_anisotropy, |m| {
                m.anisotropy_strength = 0.0;
                m.anisotropy_texture = None;
            }),
            Effect::Dispersion => turn_off(scene, Material::has_dispersion, |m| m.dispersion = 0.0),
            Effect::EnvironmentMap => match &scene.environment {
                Some(Environment::Map(map)) => {
                    scene.environment = Some(Environment::Constant(map.mean_radiance()));
                    true
                }
                _ => false,
            },
        }
    }
}

/// sRGB-encoded channel to linear.
fn linear(c: u8) -> f32 {
    let c = c as f32 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// The mean of a texture's texels, RGBA, sRGB-decoded for colour textures.
fn mean(t: &Texture, srgb: bool) -> Vec4 {
    let n = (t.rgba8.len() / 4).max(1) as f32;
    let sum = t.rgba8.chunks_exact(4).fold(Vec4::ZERO, |acc, p| {
        let rgb = if srgb {
            Vec3::new(linear(p[0]), linear(p[1]), linear(p[2]))
        } else {
            Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32) / 255.0
        };
        acc + rgb.extend(p[3] as f32 / 255.0)
    });
    sum / n
}

/// Turns a material extension off in every material (`off`); whether some material had it
/// (`has`, asked before).
fn turn_off(
    scene: &mut Scene,
    has: impl Fn(&Material) -> bool,
    off: impl Fn(&mut Material),
) -> bool {
    let mut any = false;
    for m in &mut scene.materials {
        any |= has(m);
        off(m);
    }
    any
}

/// Every texture replaced by its mean folded into the factor it multiplies.
fn remove_textures(scene: &mut Scene) -> bool {
    let textures = &scene.textures;
    let mut any = false;
    let mean_of = |r: Option<platoon_core::scene::TextureRef>, srgb: bool| {
        r.and_then(|r| textures.get(r.texture as usize))
            .map(|t| mean(t, srgb))
    };
    for m in &mut scene.materials {
        if let Some(c) = mean_of(m.base_color_texture.take(), true) {
            m.base_color *= c;
            any = true;
        }
        if let Some(mr) = mean_of(m.metallic_roughness_texture.take(), false) {
            // glTF: roughness in green, metalness in blue.
            m.roughness *= mr.y;
            m.metallic *= mr.z;
            any = true;
        }
        if let Some(e) = mean_of(m.emissive_texture.take(), true) {
            m.emissive *= e.truncate();
            any = true;
        }
        if let Some(s) = mean_of(m.specular_texture.take(), false) {
            m.specular *= s.w;
            any = true;
        }
        if let Some(s) = mean_of(m.specular_color_texture.take(), true) {
            m.specular_color *= s.truncate();
            any = true;
        }
        if let Some(t) = mean_of(m.transmission_texture.take(), false) {
            m.transmission *= t.x;
            any = true;
        }
        if let Some(c) = mean_of(m.clearcoat_texture.take(), false) {
            m.clearcoat *= c.x;
            any = true;
        }
        if let Some(c) = mean_of(m.clearcoat_roughness_texture.take(), false) {
            m.clearcoat_roughness *= c.y;
            any = true;
        }
        if let Some(t) = mean_of(m.diffuse_transmission_texture.take(), false) {
            m.diffuse_transmission *= t.w;
            any = true;
        }
        if let Some(c) = mean_of(m.diffuse_transmission_color_texture.take(), true) {
            m.diffuse_transmission_color *= c.truncate();
            any = true;
        }
        if let Some(c) = mean_of(m.sheen_color_texture.take(), true) {
            m.sheen_color *= c.truncate();
            any = true;
        }
        if let Some(r) = mean_of(m.sheen_roughness_texture.take(), false) {
            m.sheen_roughness *= r.w;
            any = true;
        }
        if let Some(r) = mean_of(m.iridescence_texture.take(), false) {
            m.iridescence *= r.x;
            any = true;
        }
        if let Some(g) = mean_of(m.iridescence_thickness_texture.take(), false) {
            m.iridescence_thickness_max = m.iridescence_thickness_min
                + (m.iridescence_thickness_max - m.iridescence_thickness_min) * g.y;
            any = true;
        }
        // The mean of directions is no direction: the strength keeps its mean, the direction
        // the rotation alone.
        if let Some(b) = mean_of(m.anisotropy_texture.take(), false) {
            m.anisotropy_strength *= b.z;
            any = true;
        }
        // A normal map has no factor to fold into: the coat follows the mesh's normal, as
        // `no-normal-maps` leaves the base.
        any |= m.clearcoat_normal_texture.take().is_some();
    }
    any
}

#[cfg(test)]
mod tests {
    use super::*;
    use platoon_core::scene::{Material, TextureRef, Wrap};

    #[test]
    fn textures_become_their_mean_and_absent_effects_are_reported() {
        let mut scene = Scene::default();
        scene.textures.push(Texture {
            name: "half".into(),
            width: 2,
            height: 1,
            rgba8: vec![255, 255, 255, 255, 0, 0, 0, 255],
            wrap_s: Wrap::Repeat,
            wrap_t: Wrap::Repeat,
            nearest: false,
            mips: Vec::new(),
        });
        scene.materials.push(Material {
            base_color_texture: Some(TextureRef::new(0)),
            ..Material::default()
        });
        assert!(Effect::Textures.remove(&mut scene));
        let m = &scene.materials[0];
        assert!(m.base_color_texture.is_none());
        assert!((m.base_color.x - 0.5).abs() < 1e-6 && m.base_color.w == 1.0);
        for e in [
            Effect::Textures,
            Effect::NormalMaps,
            Effect::Transmission,
            Effect::EnvironmentMap,
            Effect::Clearcoat,
            Effect::DiffuseTransmission,
        ] {
            assert!(!e.remove(&mut scene), "{} found something", e.name());
            assert_eq!(Effect::parse(e.name()), Some(e));
        }
    }
}
