//! The kernel variant of a render: the scene's features, the camera and output, the frame's
//! options and path loop knobs that select code and the method's options, each a `#define`,
//! derived once per render from what declares them (`FrameOptions`, `PathLoop` and the method's
//! `RenderMethod::kernel_options`).
//! A scene without (say) transmission, rendered without a clamp, runs a kernel with neither.

use std::fmt;

use crate::flatten::features::{chosen, write_labels, SceneFeatures};
use crate::frame::{FrameParams, Output};

/// The defines of one kernel variant, in a stable order, each with the label `platoon info` and
/// the output's metadata show.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct KernelVariant {
    entries: Vec<(&'static str, &'static str)>,
}

impl KernelVariant {
    /// The variant that renders `params` of a scene with `scene`'s features. With
    /// `generic_kernel` every effect a scene may call for is compiled in, as a renderer that
    /// does not specialise its kernel would run. The thin lens stays a camera option: compiled
    /// in with a closed aperture it moves the camera rays' last bits (the direction is rebuilt
    /// through the focus point), and the generic kernel must render the specialised kernel's
    /// image, bit for bit (tests/lab/tradeoff.rs).
    pub fn new(scene: SceneFeatures, params: &FrameParams) -> KernelVariant {
        let scene = if params.path_loop.generic_kernel {
            scene.generic()
        } else {
            scene
        };
        let orthographic = params.camera.orthographic.is_some();
        let aov_pass = match params.output {
            Output::Aov(pass) => Some(pass),
            _ => None,
        };
        let render_options = [
            // An orthographic camera has no lens.
            (
                "thin-lens",
                "HAS_THIN_LENS",
                params.camera.aperture_radius > 0.0 && !orthographic,
            ),
            ("orthographic", "HAS_ORTHOGRAPHIC", orthographic),
            (
                "primary-hit-output",
                "OUTPUT_PRIMARY_HIT",
                params.output == Output::PrimaryHit,
            ),
            (
                "bsdf-sample-output",
                "OUTPUT_BSDF_SAMPLE",
                params.output == Output::BsdfSample,
            ),
            (
                "bsdf-value-output",
                "OUTPUT_BSDF_VALUE",
                params.output == Output::BsdfValue,
            ),
            (
                "aov-output",
                "OUTPUT_AOV",
                matches!(params.output, Output::Aov(p) if p.in_aov_kernel()),
            ),
        ];
        let options = scene
            .options()
            .into_iter()
            .chain(render_options)
            .chain(params.options.kernel_options())
            .chain(params.path_loop.kernel_options())
            .chain(aov_pass.map(|pass| {
                let (label, define) = pass.kernel_option();
                (label, define, true)
            }))
            .chain(params.method.unit().kernel_options(params));
        KernelVariant {
            entries: chosen(options),
        }
    }

    /// The variant of a plain render of the scene (no render option selecting code, path
    /// tracing): what `platoon info` shows.
    pub fn of_scene(scene: SceneFeatures) -> KernelVariant {
        KernelVariant {
            entries: chosen(scene.options()),
        }
    }

    /// Preprocessor defines selecting the kernel's code paths.
    pub fn defines(&self) -> Vec<&'static str> {
        self.entries.iter().map(|e| e.1).collect()
    }
}

impl fmt::Display for KernelVariant {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write_labels(f, &self.entries)
    }
}
