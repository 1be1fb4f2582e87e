//! The effects a scene calls for, found by the flattener. Each one is a `#define` of the kernel
//! variant (`method::variant`, which adds the render options and the method), so a scene
//! without (say) transmission runs a kernel with no transmission code at all.

use std::fmt;

use platoon_scene::{AlphaMode, Scene};

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct SceneFeatures {
    /// Some used material reflects specularly (a metal, a dielectric's specular layer, glass):
    /// without, every surface is Lambertian and the kernel has no GGX code.
    pub specular_lobes: bool,
    /// Some used material has a texture; then which of its slots are read (a slot no material
    /// fills costs a masked texture fetch per shading point on llvmpipe, so it is compiled out).
    pub textures: bool,
    pub base_color_textures: bool,
    pub metallic_roughness_textures: bool,
    pub emissive_textures: bool,
    /// KHR_materials_specular's specular or specular colour texture.
    pub specular_textures: bool,
    pub transmission_textures: bool,
    pub normal_maps: bool,
    pub transmission: bool,
    pub alpha_mask: bool,
    /// Stochastic transparency (alphaMode BLEND).
    pub alpha_blend: bool,
    /// COLOR_0 multiplies some used material's base colour.
    pub vertex_colors: bool,
    /// Some texture is read at TEXCOORD_1 or through KHR_texture_transform.
    pub uv_transforms: bool,
    /// KHR_materials_unlit.
    pub unlit: bool,
    /// KHR_materials_clearcoat; and some coat texture (factor, roughness or normal map).
    pub clearcoat: bool,
    pub clearcoat_textures: bool,
    /// KHR_materials_diffuse_transmission; and some texture of it.
    pub diffuse_transmission: bool,
    pub diffuse_transmission_textures: bool,
    /// KHR_materials_sheen; and some texture of it.
    pub sheen: bool,
    pub sheen_textures: bool,
    /// KHR_materials_volume absorbing somewhere (a volume that absorbs nothing changes nothing).
    pub volume: bool,
    /// KHR_materials_iridescence; and some texture of it.
    pub iridescence: bool,
    pub iridescence_textures: bool,
    /// KHR_materials_anisotropy; and some texture of it.
    pub anisotropy: bool,
    pub anisotropy_textures: bool,
    /// KHR_materials_dispersion in a transmissive volume: paths carry a wavelength.
    pub dispersion: bool,
    pub emissive_triangles: bool,
    pub punctual_lights: bool,
    pub environment_map: bool,
    /// Some texture has mip levels (`--texture-lod ray-cone`): lookups pick a level by the
    /// path's ray cone.
    pub texture_lod: bool,
}

impl SceneFeatures {
    /// Features of the scene's materials and lights.
    pub fn of_scene(scene: &Scene) -> SceneFeatures {
        let drawn = || scene.nodes.iter().filter_map(|n| n.mesh);
        let used: Vec<&platoon_scene::Material> = {
            let mut used = vec![false; scene.materials.len()];
            for m in drawn() {
                for &t in &scene.meshes[m].triangle_materials {
                    used[t as usize] = true;
                }
            }
            scene
                .materials
                .iter()
                .zip(used)
                .filter(|(_, u)| *u)
                .map(|(m, _)| m)
                .collect()
        };
        SceneFeatures {
            // A texture only scales its factor: a zero factor stays zero.
            specular_lobes: used
                .iter()
                .any(|m| m.metallic > 0.0 || m.specular > 0.0 || m.transmission > 0.0),
            textures: used.iter().any(|m| m.textures().next().is_some()),
            base_color_textures: used.iter().any(|m| m.base_color_texture.is_some()),
            metallic_roughness_textures: used
                .iter()
                .any(|m| m.metallic_roughness_texture.is_some()),
            emissive_textures: used.iter().any(|m| m.emissive_texture.is_some()),
            specular_textures: used
                .iter()
                .any(|m| m.specular_texture.is_some() || m.specular_color_texture.is_some()),
            transmission_textures: used.iter().any(|m| m.transmission_texture.is_some()),
            normal_maps: used.iter().any(|m| m.normal_texture.is_some()),
            transmission: used.iter().any(|m| m.transmission > 0.0),
            alpha_mask: used
                .iter()
                .any(|m| matches!(m.alpha_mode, AlphaMode::Mask(_))),
            alpha_blend: used.iter().any(|m| m.alpha_mode == AlphaMode::Blend),
            vertex_colors: drawn().any(|m| !scene.meshes[m].colors.is_empty()),
            uv_transforms: used.iter().any(|m| m.textures().any(|t| !t.is_plain())),
            unlit: used.iter().any(|m| m.unlit),
            clearcoat: used.iter().any(|m| m.has_clearcoat()),
            clearcoat_textures: used.iter().any(|m| {
                m.has_clearcoat()
                    && (m.clearcoat_texture.is_some()
                        || m.clearcoat_roughness_texture.is_some()
                        || m.clearcoat_normal_texture.is_some())
            }),
            diffuse_transmission: used.iter().any(|m| m.has_diffuse_transmission()),
            diffuse_transmission_textures: used.iter().any(|m| {
                m.has_diffuse_transmission()
                    && (m.diffuse_transmission_texture.is_some()
                        || m.diffuse_transmission_color_texture.is_some())
            }),
            sheen: used.iter().any(|m| m.has_sheen()),
            sheen_textures: used.iter().any(|m| {
                m.has_sheen()
                    && (m.sheen_color_texture.is_some() || m.sheen_roughness_texture.is_some())
            }),
            volume: used.iter().any(|m| m.absorbs()),
            iridescence: used.iter().any(|m| m.has_iridescence()),
            iridescence_textures: used.iter().any(|m| {
                m.has_iridescence()
                    && (m.iridescence_texture.is_some()
                        || m.iridescence_thickness_texture.is_some())
            }),
            anisotropy: used.iter().any(|m| m.has_anisotropy()),
            anisotropy_textures: used
                .iter()
                .any(|m| m.has_anisotropy() && m.anisotropy_texture.is_some()),
            dispersion: used.iter().any(|m| m.has_dispersion()),
            emissive_triangles: used.iter().any(|m| m.is_emissive()),
            punctual_lights: scene.nodes.iter().any(|n| n.light.is_some()),
            environment_map: matches!(
                scene.environment,
                Some(platoon_scene::environment::Environment::Map(_))
            ),
            texture_lod: used.iter().any(|m| {
                m.textures().any(|t| {
                    scene
                        .textures
                        .get(t.texture as usize)
                        .is_some_and(|t| !t.mips.is_empty())
                })
            }),
        }
    }

    /// Every effect a scene may call for: what a kernel that is not specialised compiles in
    /// (`FrameParams::generic_kernel`). Not vertex colours: their code reads the vertex
    /// extras, which only a scene with colours or a second UV set has.
    pub fn generic(self) -> SceneFeatures {
        SceneFeatures {
            specular_lobes: true,
            textures: true,
            base_color_textures: true,
            metallic_roughness_textures: true,
            emissive_textures: true,
            specular_textures: true,
            transmission_textures: true,
            normal_maps: true,
            transmission: true,
            alpha_mask: true,
            alpha_blend: true,
            uv_transforms: true,
            unlit: true,
            clearcoat: true,
            clearcoat_textures: true,
            diffuse_transmission: true,
            diffuse_transmission_textures: true,
            sheen: true,
            sheen_textures: true,
            volume: true,
            iridescence: true,
            iridescence_textures: true,
            anisotropy: true,
            anisotropy_textures: true,
            dispersion: true,
            emissive_triangles: true,
            punctual_lights: true,
            environment_map: true,
            ..self
        }
    }

    /// Every flag, in a stable order (what a commit sent to another rank carries,
    /// `platoon_distribute::wire`). Written out field by field: a new feature breaks the build
    /// here until it is listed.
    pub fn flags_mut(&mut self) -> [&mut bool; 30] {
        let SceneFeatures {
            specular_lobes,
            textures,
            base_color_textures,
            metallic_roughness_textures,
            emissive_textures,
            specular_textures,
            transmission_textures,
            normal_maps,
            transmission,
            alpha_mask,
            alpha_blend,
            vertex_colors,
            uv_transforms,
            unlit,
            clearcoat,
            clearcoat_textures,
            diffuse_transmission,
            diffuse_transmission_textures,
            sheen,
            sheen_textures,
            volume,
            iridescence,
            iridescence_textures,
            anisotropy,
            anisotropy_textures,
            dispersion,
            emissive_triangles,
            punctual_lights,
            environment_map,
            texture_lod,
        } = self;
        [
            specular_lobes,
            textures,
            base_color_textures,
            metallic_roughness_textures,
            emissive_textures,
            specular_textures,
            transmission_textures,
            normal_maps,
            transmission,
            alpha_mask,
            alpha_blend,
            vertex_colors,
            uv_transforms,
            unlit,
            clearcoat,
            clearcoat_textures,
            diffuse_transmission,
            diffuse_transmission_textures,
            sheen,
            sheen_textures,
            volume,
            iridescence,
            iridescence_textures,
            anisotropy,
            anisotropy_textures,
            dispersion,
            emissive_triangles,
            punctual_lights,
            environment_map,
            texture_lod,
        ]
    }

    /// Each feature with whether the scene has it, in a stable order.
    pub fn options(&self) -> [KernelOption; 30] {
        [
            ("specular-lobes", "HAS_SPECULAR_LOBES", self.specular_lobes),
            ("textures", "HAS_TEXTURES", self.textures),
            (
                "base-color-textures",
                "HAS_BASE_COLOR_TEXTURES",
                self.base_color_textures,
            ),
            (
                "metallic-roughness-textures",
                "HAS_METALLIC_ROUGHNESS_TEXTURES",
                self.metallic_roughness_textures,
            ),
            (
                "emissive-textures",
                "HAS_EMISSIVE_TEXTURES",
                self.emissive_textures,
            ),
            (
                "specular-textures",
                "HAS_SPECULAR_TEXTURES",
                self.specular_textures,
            ),
            (
                "transmission-textures",
                "HAS_TRANSMISSION_TEXTURES",
                self.transmission_textures,
            ),
            ("normal-maps", "HAS_NORMAL_MAPS", self.normal_maps),
            ("transmission", "HAS_TRANSMISSION", self.transmission),
            ("alpha-mask", "HAS_ALPHA_MASK", self.alpha_mask),
            ("alpha-blend", "HAS_ALPHA_BLEND", self.alpha_blend),
            ("vertex-colors", "HAS_VERTEX_COLORS", self.vertex_colors),
            ("uv-transforms", "HAS_UV_TRANSFORMS", self.uv_transforms),
            ("unlit", "HAS_UNLIT", self.unlit),
            ("clearcoat", "HAS_CLEARCOAT", self.clearcoat),
            (
                "clearcoat-textures",
                "HAS_CLEARCOAT_TEXTURES",
                self.clearcoat_textures,
            ),
            (
                "diffuse-transmission",
                "HAS_DIFFUSE_TRANSMISSION",
                self.diffuse_transmission,
            ),
            (
                "diffuse-transmission-textures",
                "HAS_DIFFUSE_TRANSMISSION_TEXTURES",
                self.diffuse_transmission_textures,
            ),
            ("sheen", "HAS_SHEEN", self.sheen),
            ("sheen-textures", "HAS_SHEEN_TEXTURES", self.sheen_textures),
            ("volume", "HAS_VOLUME", self.volume),
            ("iridescence", "HAS_IRIDESCENCE", self.iridescence),
            (
                "iridescence-textures",
                "HAS_IRIDESCENCE_TEXTURES",
                self.iridescence_textures,
            ),
            ("anisotropy", "HAS_ANISOTROPY", self.anisotropy),
            (
                "anisotropy-textures",
                "HAS_ANISOTROPY_TEXTURES",
                self.anisotropy_textures,
            ),
            ("dispersion", "HAS_DISPERSION", self.dispersion),
            (
                "emissive-triangles",
                "HAS_EMISSIVE_TRIANGLES",
                self.emissive_triangles,
            ),
            (
                "punctual-lights",
                "HAS_PUNCTUAL_LIGHTS",
                self.punctual_lights,
            ),
            (
                "environment-map",
                "HAS_ENVIRONMENT_MAP",
                self.environment_map,
            ),
            ("texture-lod", "TEXTURE_LOD", self.texture_lod),
        ]
    }

    /// The defines of the scene's features (the kernel variant adds the render's own).
    pub fn defines(&self) -> Vec<&'static str> {
        chosen(self.options()).iter().map(|e| e.1).collect()
    }
}

impl fmt::Display for SceneFeatures {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write_labels(f, &chosen(self.options()))
    }
}

/// A kernel `#define`: the label `platoon info` and the metadata show, the define, and whether
/// it is on. The scene's features, the render options and a method's options are lists of them
/// (`method::variant::KernelVariant` joins the three).
pub type KernelOption = (&'static str, &'static str, bool);

/// The (label, define) of the options that are on, in their order.
pub fn chosen(
    options: impl IntoIterator<Item = KernelOption>,
) -> Vec<(&'static str, &'static str)> {
    options
        .into_iter()
        .filter(|o| o.2)
        .map(|(label, define, _)| (label, define))
        .collect()
}

/// The labels of `chosen` options, comma-separated, or "(none)".
pub fn write_labels(f: &mut fmt::Formatter<'_>, chosen: &[(&str, &str)]) -> fmt::Result {
    if chosen.is_empty() {
        return write!(f, "(none)");
    }
    let labels: Vec<&str> = chosen.iter().map(|e| e.0).collect();
    write!(f, "{}", labels.join(","))
}

#[cfg(test)]
mod tests {
    use super::*;
    use platoon_scene::{Material, Mesh, Node};
    use std::sync::Arc;

    fn with_material(m: Material) -> Scene {
        let mut node = Node::new("n");
        node.mesh = Some(0);
        Scene {
            nodes: vec![node],
            meshes: vec![Arc::new(Mesh {
                triangle_materials: vec![0],
                indices: vec![[0, 1, 2]],
                ..Default::default()
            })],
            materials: vec![m],
            ..Default::default()
        }
    }

    #[test]
    fn only_lambertian_scenes_go_without_specular_lobes() {
        let lambert = platoon_scene::cornell::lambertian("white", glam::Vec3::splat(0.7));
        assert!(!SceneFeatures::of_scene(&with_material(lambert.clone())).specular_lobes);
        // The glTF default (a dielectric with its specular layer), a metal, glass.
        assert!(SceneFeatures::of_scene(&with_material(Material::default())).specular_lobes);
        for m in [
            Material {
                metallic: 0.3,
                ..lambert.clone()
            },
            Material {
                transmission: 1.0,
                ..lambert.clone()
            },
        ] {
            assert!(SceneFeatures::of_scene(&with_material(m)).specular_lobes);
        }
        assert!(SceneFeatures::default().generic().specular_lobes);
    }
}
