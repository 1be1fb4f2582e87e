//! The effects a scene calls for. Each one is a `#define` of the path-tracing kernel, so a scene
//! without (say) transmission runs a kernel with no transmission code at all.

use std::fmt;

use crate::scene::{AlphaMode, Scene};

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct FeatureSet {
    pub textures: bool,
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
    pub emissive_triangles: bool,
    pub punctual_lights: bool,
    pub environment_map: bool,
    pub thin_lens: bool,
    /// An orthographic camera (a render option, from the camera).
    pub orthographic: bool,
    /// Max depth 1: the kernel has no bounce code (a render option, set by the caller).
    pub camera_rays_only: bool,
    /// The kernel writes primary hits instead of radiance (`frame::Output::PrimaryHit`).
    pub primary_hit_output: bool,
    /// The kernel samples or evaluates the first hit's BSDF (`frame::Output::BsdfSample`,
    /// `BsdfValue`).
    pub bsdf_sample_output: bool,
    pub bsdf_value_output: bool,
    /// Indirect contributions clamped (`FrameParams::clamp_indirect`; biased).
    pub clamp_indirect: bool,
    /// Russian roulette with a fixed survival probability (`FrameParams::rr_fixed`).
    pub fixed_roulette: bool,
    /// Next-event estimation picks every light alike (`FrameParams::uniform_light_selection`).
    pub uniform_lights: bool,
    /// Bikker's deterministic path termination (`FrameParams::deterministic_termination`).
    pub deterministic_termination: bool,
    /// Paths end at their second non-delta vertex (`FrameParams::single_diffuse_bounce`).
    pub single_diffuse_bounce: bool,
    /// Resampled light selection (`FrameParams::ris_candidates`).
    pub ris_lights: bool,
    /// ... combined with BSDF sampling by MIS (`FrameParams::ris_mis`).
    pub ris_mis: bool,
    /// Instant global illumination (`FrameParams::igi`): the IGI kernels instead of the path
    /// tracer's; the flags below are its options that select code.
    pub igi: bool,
    pub igi_imperfect_visibility: bool,
    pub igi_bounded: bool,
    /// The gather leaves irradiance and a G-buffer for the filters after assembly.
    pub igi_filtered: bool,
    pub igi_downsampled: bool,
    pub igi_interleaved: bool,
}

impl FeatureSet {
    /// Features of the scene's materials and lights (thin lens, camera rays only and the
    /// environment are render options, set by the caller).
    pub fn of_scene(scene: &Scene) -> FeatureSet {
        let drawn = || scene.nodes.iter().filter_map(|n| n.mesh);
        let used: Vec<&crate::scene::Material> = {
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
        FeatureSet {
            textures: used.iter().any(|m| m.textures().next().is_some()),
            normal_maps: used.iter().any(|m| m.normal_texture.is_some()),
            transmission: used.iter().any(|m| m.transmission > 0.0),
            alpha_mask: used
                .iter()
                .any(|m| matches!(m.alpha_mode, AlphaMode::Mask(_))),
            alpha_blend: used.iter().any(|m| m.alpha_mode == AlphaMode::Blend),
            vertex_colors: drawn().any(|m| !scene.meshes[m].colors.is_empty()),
            uv_transforms: used.iter().any(|m| m.textures().any(|t| !t.is_plain())),
            unlit: used.iter().any(|m| m.unlit),
            emissive_triangles: used.iter().any(|m| m.is_emissive()),
            punctual_lights: scene.nodes.iter().any(|n| n.light.is_some()),
            environment_map: matches!(
                scene.environment,
                Some(crate::scene::environment::Environment::Map(_))
            ),
            thin_lens: false,
            orthographic: false,
            camera_rays_only: false,
            primary_hit_output: false,
            bsdf_sample_output: false,
            bsdf_value_output: false,
            clamp_indirect: false,
            fixed_roulette: false,
            uniform_lights: false,
            deterministic_termination: false,
            single_diffuse_bounce: false,
            ris_lights: false,
            ris_mis: false,
            igi: false,
            igi_imperfect_visibility: false,
            igi_bounded: false,
            igi_filtered: false,
            igi_downsampled: false,
            igi_interleaved: false,
        }
    }

    /// The set with the render options of `params` that select kernel code: a thin lens when
    /// the aperture is open, no bounce code at max depth 1; with `generic_kernel` every effect
    /// a scene may call for, as a renderer that does not specialise its kernel would run. The
    /// thin lens stays a camera option: compiled in with a closed aperture it moves the camera
    /// rays' last bits (the direction is rebuilt through the focus point), and the generic
    /// kernel must render the specialised kernel's image, bit for bit (tests/tradeoff.rs).
    pub fn with_render_options(mut self, params: &crate::frame::FrameParams) -> FeatureSet {
        if params.generic_kernel {
            self.textures = true;
            self.normal_maps = true;
            self.transmission = true;
            self.alpha_mask = true;
            self.alpha_blend = true;
            // Not vertex colours: their code reads the vertex extras, which only a scene with
            // colours or a second UV set has.
            self.uv_transforms = true;
            self.unlit = true;
            self.emissive_triangles = true;
            self.punctual_lights = true;
            self.environment_map = true;
        }
        self.orthographic = params.camera.orthographic.is_some();
        // An orthographic camera has no lens.
        self.thin_lens = params.camera.aperture_radius > 0.0 && !self.orthographic;
        self.camera_rays_only = params.max_depth <= 1;
        self.primary_hit_output = params.output == crate::frame::Output::PrimaryHit;
        self.bsdf_sample_output = params.output == crate::frame::Output::BsdfSample;
        self.bsdf_value_output = params.output == crate::frame::Output::BsdfValue;
        self.clamp_indirect = params.clamp_indirect.is_some();
        self.fixed_roulette = params.rr_fixed.is_some();
        self.uniform_lights = params.uniform_light_selection;
        self.deterministic_termination = params.deterministic_termination;
        self.single_diffuse_bounce = params.single_diffuse_bounce;
        self.ris_lights = params.ris_candidates.is_some();
        self.ris_mis = self.ris_lights && params.ris_mis;
        let igi = params.igi;
        self.igi = igi.is_some();
        self.igi_imperfect_visibility = igi.is_some_and(|o| o.imperfect_visibility);
        self.igi_bounded = igi.is_some_and(|o| o.min_distance > 0.0);
        self.igi_filtered = igi.is_some_and(|o| o.filtered());
        self.igi_downsampled = igi.is_some_and(|o| o.downsample > 1);
        self.igi_interleaved = igi.is_some_and(|o| o.interleave != [1, 1]);
        self
    }

    fn entries(&self) -> [(&'static str, &'static str, bool); 30] {
        [
            ("textures", "HAS_TEXTURES", self.textures),
            ("normal-maps", "HAS_NORMAL_MAPS", self.normal_maps),
            ("transmission", "HAS_TRANSMISSION", self.transmission),
            ("alpha-mask", "HAS_ALPHA_MASK", self.alpha_mask),
            ("alpha-blend", "HAS_ALPHA_BLEND", self.alpha_blend),
            ("vertex-colors", "HAS_VERTEX_COLORS", self.vertex_colors),
            ("uv-transforms", "HAS_UV_TRANSFORMS", self.uv_transforms),
            ("unlit", "HAS_UNLIT", self.unlit),
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
            ("thin-lens", "HAS_THIN_LENS", self.thin_lens),
            ("orthographic", "HAS_ORTHOGRAPHIC", self.orthographic),
            (
                "camera-rays-only",
                "CAMERA_RAYS_ONLY",
                self.camera_rays_only,
            ),
            (
                "primary-hit-output",
                "OUTPUT_PRIMARY_HIT",
                self.primary_hit_output,
            ),
            (
                "bsdf-sample-output",
                "OUTPUT_BSDF_SAMPLE",
                self.bsdf_sample_output,
            ),
            (
                "bsdf-value-output",
                "OUTPUT_BSDF_VALUE",
                self.bsdf_value_output,
            ),
            ("clamp-indirect", "CLAMP_INDIRECT", self.clamp_indirect),
            ("fixed-roulette", "RR_FIXED", self.fixed_roulette),
            (
                "uniform-lights",
                "LIGHT_SELECT_UNIFORM",
                self.uniform_lights,
            ),
            (
                "deterministic-termination",
                "RR_DETERMINISTIC",
                self.deterministic_termination,
            ),
            (
                "single-diffuse-bounce",
                "SINGLE_DIFFUSE_BOUNCE",
                self.single_diffuse_bounce,
            ),
            ("ris-lights", "LIGHT_SELECT_RIS", self.ris_lights),
            ("ris-mis", "RIS_MIS", self.ris_mis),
            ("igi", "METHOD_IGI", self.igi),
            (
                "igi-imperfect-visibility",
                "IGI_IMPERFECT_VISIBILITY",
                self.igi_imperfect_visibility,
            ),
            ("igi-bounded", "IGI_BOUNDED", self.igi_bounded),
            ("igi-filtered", "IGI_FILTERED", self.igi_filtered),
            ("igi-downsampled", "IGI_DOWNSAMPLED", self.igi_downsampled),
            ("igi-interleaved", "IGI_INTERLEAVED", self.igi_interleaved),
        ]
    }

    /// Preprocessor defines selecting the kernel's code paths.
    pub fn defines(&self) -> Vec<&'static str> {
        self.entries().iter().filter(|e| e.2).map(|e| e.1).collect()
    }
}

impl fmt::Display for FeatureSet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names: Vec<&str> = self.entries().iter().filter(|e| e.2).map(|e| e.0).collect();
        if names.is_empty() {
            write!(f, "(none)")
        } else {
            write!(f, "{}", names.join(","))
        }
    }
}
