//! Path tracing: the default method and the reference every other is measured against. Its
//! state (`PathTracing`) holds what only it does: how its work is cut into kernels
//! ([`PathKernel`], `kernel`; the same image either way), the last paths of a pass cut
//! short, resampled direct light, and what its frames carry from one to the next (the world
//! cache's table, light reuse's reservoirs). The path loop it shares with the methods that
//! continue its paths (depth, roulette, clamp...) is the frame's (`frame::PathLoop`). What it
//! learns over a game loop's frames is here too: the world cache (`world_cache`), light reuse
//! (`light_reuse`) and the learner that carries them from frame to frame (`learning.rs`).

use std::sync::LazyLock;

use crate::flatten::features::{KernelOption, SceneFeatures};
use crate::frame::{FrameParams, MethodReport, Output};
use crate::method::kind::MethodKind;
use crate::method::learning::FrameLearning;
use crate::method::render_method::{RenderMethod, Report};
use crate::method::Method;

mod kernel;
mod kind;
mod learning;
pub mod light_reuse;
mod state;
pub mod world_cache;

pub use kernel::PathKernel;
pub use kind::PathKind;
pub use learning::{Learned, PathLearning};
pub use state::{LearningOptions, PathTracing, ResampledLight};

/// Candidate lights of a game's resampled direct light (`RenderMethod::realtime`): most of the
/// gain in the many-light hall (tests/kernel/estimators.rs) for a few evaluations of the BSDF.
pub const REALTIME_CANDIDATES: u32 = 8;

static PATH_TRACING: LazyLock<Method> = LazyLock::new(|| Method::new(PathTracing::default()));

impl Method {
    /// Path tracing with its defaults, the reference.
    pub fn path_tracing() -> Method {
        PATH_TRACING.clone()
    }

    /// Whether this is path tracing.
    pub fn is_path_tracing(&self) -> bool {
        self.state::<PathTracing>().is_some()
    }

    /// The path tracer's state; its defaults for another method, whose frames take none of
    /// its options.
    pub fn path(&self) -> &PathTracing {
        let defaults = || PATH_TRACING.state().expect("path tracing's state");
        self.state::<PathTracing>().unwrap_or_else(defaults)
    }

    /// The path tracer's state to change, when this is path tracing.
    pub fn path_mut(&mut self) -> Option<&mut PathTracing> {
        self.state_mut::<PathTracing>()
    }
}

impl Default for Method {
    fn default() -> Method {
        Method::path_tracing()
    }
}

impl RenderMethod for PathTracing {
    fn kind(&self) -> &'static dyn MethodKind {
        &PathKind
    }
    fn check_scene(&self, features: &SceneFeatures) -> Result<(), String> {
        match self.resampled_light {
            Some(r) => r.check_lights(features.punctual_lights),
            None => Ok(()),
        }
    }
    fn describe(&self) -> String {
        "path tracing".into()
    }
    fn validate(&self, params: &FrameParams) -> Result<(), String> {
        if self.cut_last_paths && self.kernel == PathKernel::Streaming {
            return Err("cutting the last paths of a pass (NOP) is the megakernel's: the streaming kernels follow every path to its end".into());
        }
        // Its options' own rules, as a request checks them before loading (a frame may come
        // from an embedder who built the state by hand).
        self.check_options()
            .map_err(|(key, problem)| format!("{key}: {problem}"))?;
        if let Some(h) = &self.light_reuse {
            let by_contribution = self.resampled_light.is_some_and(|r| r.contribution);
            light_reuse::check_context(by_contribution, true)?;
            if params.crop.is_some() {
                return Err(
                    "light reuse finds the previous frame's reservoirs in the whole \
                            image: a border render has none"
                        .into(),
                );
            }
            h.options.validate()?;
        }
        if self.world_cache.as_ref().is_some_and(|t| {
            !t.slots.len().is_power_of_two() || t.cell_size.is_nan() || t.cell_size <= 0.0
        }) {
            return Err(
                "the world cache's table must hold a power of two of slots and cells \
                        of a positive size"
                    .into(),
            );
        }
        Ok(())
    }
    fn kernel_options(&self, params: &FrameParams) -> Vec<KernelOption> {
        let ris = self.resampled_light;
        let reuse = self.reused_light(params.output).map(|h| h.options);
        vec![
            ("last-paths-cut", "LAST_PATH_CUT", self.cut_last_paths),
            ("ris-lights", "LIGHT_SELECT_RIS", ris.is_some()),
            ("ris-mis", "RIS_MIS", ris.is_some_and(|r| r.mis)),
            (
                "ris-contribution",
                "RIS_CONTRIBUTION",
                ris.is_some_and(|r| r.contribution),
            ),
            // The beauty's paths read it (a light pass's too, so that the passes sum to it).
            (
                "world-cache",
                "WORLD_CACHE",
                self.world_cache.is_some()
                    && matches!(
                        params.output,
                        Output::Radiance | Output::Aov(crate::frame::aov::AovPass::Light(_))
                    ),
            ),
            // The beauty's first vertices only: the reservoirs it leaves are the next frame's.
            ("light-reuse", "LIGHT_REUSE", reuse.is_some()),
            (
                "light-reuse-biased",
                "LIGHT_REUSE_BIASED",
                reuse.is_some_and(|o| !o.unbiased),
            ),
        ]
    }
    fn approximations(&self) -> Vec<String> {
        let cut = "the last path of a pass cut where its SIMD group stopped (NOP)";
        let cut = self.cut_last_paths.then_some(cut);
        cut.into_iter().map(String::from).collect()
    }
    /// The kernel asked for.
    fn metadata(&self) -> Vec<(String, String)> {
        vec![("path_kernel".into(), self.kernel.label())]
    }
    /// Its kernels read the scene on the devices only.
    fn reads_scene_on_host(&self) -> bool {
        false
    }
    /// Its megakernel skips converged pixels (`FrameParams::converged`).
    fn skips_converged_pixels(&self) -> bool {
        true
    }
    /// Its beauty is the paths the light passes render again.
    fn splits_into_light_passes(&self) -> bool {
        true
    }
    fn check_options(&self) -> Result<(), (&'static str, String)> {
        if let Some(Err(e)) = self.resampled_light.map(|r| r.check()) {
            return Err(("resampled_light", e));
        }
        learning::check(self)
    }
    fn light_selection(&self) -> Option<String> {
        PathTracing::light_selection(self)
    }
    /// Resampled direct light over [`REALTIME_CANDIDATES`] lights where it has none.
    fn realtime(&self) -> Option<Method> {
        let mut path = self.clone();
        (path.resampled_light).get_or_insert(ResampledLight::new(REALTIME_CANDIDATES));
        Some(Method::new(path))
    }
    fn learning(&self, scene_radius: f32) -> Result<Option<Box<dyn FrameLearning>>, String> {
        if !self.learning.any() {
            return Ok(None);
        }
        let learner = PathLearning::new(self, scene_radius)?;
        Ok(Some(Box::new(learner)))
    }
    /// What a game loop's frame taught (`Learned`): the cache's cells, the light reused.
    fn report(&self, report: &MethodReport) -> Report {
        let Some(learned) = report.value::<Learned>() else {
            return Report::default();
        };
        let mut lines = Vec::new();
        if let Some(c) = learned.world_cache {
            lines.push(format!("world cache ({} cells)", c.cells));
        }
        if let (Some(_), Some(r)) = (learned.light_reuse, self.learning.light_reuse) {
            lines.push(r.label().into());
        }
        Report {
            lines,
            warnings: Vec::new(),
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::frame::FrameParams;
    use crate::method::path::{LearningOptions, ResampledLight};
    use crate::scene::camera::Camera;

    /// A frame holds the path tracer's options to the rules a request checks before it loads
    /// anything (`check_options`): a frame may come from an embedder who built the state by
    /// hand, and the refusal names the setting.
    #[test]
    fn a_frame_holds_the_options_rules_a_request_checks() {
        let camera = Camera::look_at(glam::Vec3::Z, glam::Vec3::ZERO, 1.0);
        let mut params = FrameParams::new(4, 4, 1, camera);
        assert!(params.check().is_ok());
        let path = params.method.path_mut().unwrap();
        path.resampled_light = Some(ResampledLight::new(0));
        let e = params.check().unwrap_err();
        assert!(e.starts_with("resampled_light"), "{e}");
        let path = params.method.path_mut().unwrap();
        path.resampled_light = None;
        path.learning = LearningOptions {
            light_reuse: Some(Default::default()),
            ..Default::default()
        };
        let e = params.check().unwrap_err();
        assert!(e.starts_with("light_reuse"), "{e}");
    }
}
