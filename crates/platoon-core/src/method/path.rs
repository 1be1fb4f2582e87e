//! Path tracing: the default method and the reference every other is measured against. Its
//! state (`PathTracing`) holds what only it does: how its work is cut into kernels
//! ([`PathKernel`], `path_kernel`; the same image either way), the last paths of a pass cut
//! short, resampled direct light, and what its frames carry from one to the next (the world
//! cache's table, light reuse's reservoirs). The path loop it shares with the methods that
//! continue its paths (depth, roulette, clamp...) is the frame's (`frame::PathLoop`).

use std::sync::{Arc, LazyLock};

use crate::flatten::features::KernelOption;
use crate::frame::light_reuse::ReservoirHistory;
use crate::frame::world_cache::CacheTable;
use crate::frame::{FrameParams, Output};
use crate::method::render_method::RenderMethod;
use crate::method::Method;

/// The path tracer's state in a frame (`Method::path_tracing()` is its defaults).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PathTracing {
    /// How its work is cut into kernels (the same image either way).
    pub kernel: PathKernel,
    /// Bikker's NOP, the last path not always completed: once every SIMD lane of a group has
    /// started its pass's last sample, the group stops when the first lane finishes it, the
    /// others' last paths ending where they are (biased low; saves the tail of the pass where
    /// one long path keeps a group busy). The image then depends on which pixels share a SIMD
    /// group (the device and the band's first line): one device, the trade-off tool. The
    /// megakernel's; compiled in only when set.
    pub cut_last_paths: bool,
    /// Next-event estimation by resampled importance sampling over candidate lights; None: one
    /// light drawn by power. Compiled in only when set.
    pub resampled_light: Option<ResampledLight>,
    /// The world cache the bounces after the first read, and its training pattern
    /// (`frame::world_cache`; biased). None: paths go on. Compiled in only when set.
    pub world_cache: Option<Arc<CacheTable>>,
    /// With resampled light by contribution: the first vertex's light sample reuses the
    /// previous frame's reservoirs around the pixel's reprojection (`frame::light_reuse`;
    /// ReSTIR DI's temporal and spatial reuse; unbiased unless its options say otherwise).
    /// Compiled in only when set.
    pub light_reuse: Option<Arc<ReservoirHistory>>,
}

/// Next-event estimation by resampled importance sampling (Talbot et al. 2005).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ResampledLight {
    /// Candidate lights per light sample (at least one).
    pub candidates: u32,
    /// Combine the RIS light sample with BSDF sampling by MIS, weighing with the kept
    /// candidate's own pdf (Bikker's MIS+RIS; still unbiased). Without it, no MIS.
    pub mis: bool,
    /// Weigh each candidate by its unshadowed contribution at the shading point (the BSDF's
    /// f cos times its radiance) instead of its emitted luminance: ReSTIR DI's target (Bitterli
    /// et al. 2020); still unbiased, and punctual lights may take part.
    pub contribution: bool,
}

impl ResampledLight {
    /// Over `candidates` lights, toward each one's unshadowed contribution, combined with BSDF
    /// sampling by MIS: what `--resampled-light` and a game's real-time settings choose.
    pub fn new(candidates: u32) -> ResampledLight {
        ResampledLight {
            candidates,
            mis: true,
            contribution: true,
        }
    }
}

static PATH_TRACING: LazyLock<Method> = LazyLock::new(|| Method::new(PathTracing::default()));
static DEFAULTS: PathTracing = PathTracing {
    kernel: PathKernel::Auto,
    cut_last_paths: false,
    resampled_light: None,
    world_cache: None,
    light_reuse: None,
};

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
        self.state::<PathTracing>().unwrap_or(&DEFAULTS)
    }

    /// The path tracer's state to change, when this is path tracing.
    pub fn path_mut(&mut self) -> Option<&mut PathTracing> {
        self.state_mut::<PathTracing>()
    }
}

impl PathTracing {
    /// The history the frame's first vertices reuse light from, where they do: the beauty's,
    /// with resampled light by contribution (what compiles LIGHT_REUSE in and what the tracer
    /// prepares its buffers for: one rule).
    pub fn reused_light(&self, output: Output) -> Option<&Arc<ReservoirHistory>> {
        let by_contribution = self.resampled_light.is_some_and(|r| r.contribution);
        self.light_reuse
            .as_ref()
            .filter(|_| by_contribution && output == Output::Radiance)
    }
}

impl Default for Method {
    fn default() -> Method {
        Method::path_tracing()
    }
}

impl RenderMethod for PathTracing {
    fn name(&self) -> &'static str {
        "path"
    }
    fn describe(&self) -> String {
        "path tracing".into()
    }
    fn validate(&self, params: &FrameParams) -> Result<(), String> {
        if self.cut_last_paths && self.kernel == PathKernel::Streaming {
            return Err("cutting the last paths of a pass (NOP) is the megakernel's: the streaming kernels follow every path to its end".into());
        }
        if self.resampled_light.is_some_and(|r| r.candidates == 0) {
            return Err("resampled light selection needs at least one candidate".into());
        }
        if let Some(h) = &self.light_reuse {
            let by_contribution = self.resampled_light.is_some_and(|r| r.contribution);
            crate::frame::light_reuse::check_context(by_contribution, true)?;
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
    fn kernel_options(&self) -> Vec<KernelOption> {
        Vec::new()
    }
    fn approximations(&self) -> Vec<String> {
        let cut = "the last path of a pass cut where its SIMD group stopped (NOP)";
        let cut = self.cut_last_paths.then_some(cut);
        cut.into_iter().map(String::from).collect()
    }
}

pub use super::path_kernel::PathKernel;

/// The path tracer as a user chooses it: no settings of its own (its knobs are the frame's).
pub struct PathKind;

impl crate::method::kind::MethodKind for PathKind {
    fn unit<'a>(&self, method: &'a Method) -> Option<&'a dyn RenderMethod> {
        method
            .state::<PathTracing>()
            .map(|s| s as &dyn RenderMethod)
    }
    fn name(&self) -> &'static str {
        "path"
    }
    fn title(&self) -> &'static str {
        "path tracing"
    }
    fn summary(&self) -> &'static str {
        "Path tracing with NEE and MIS: unbiased, the reference."
    }
    fn settings(&self) -> &'static [crate::method::settings::Setting] {
        &[]
    }
    fn build(
        &self,
        _given: &crate::method::settings::Settings,
    ) -> Result<crate::method::Method, String> {
        Ok(Method::path_tracing())
    }
    fn settings_of(&self, _method: &crate::method::Method) -> crate::method::settings::Settings {
        Default::default()
    }
    /// Its estimators against each other, a short path and no regeneration.
    fn sweep(&self) -> &'static [&'static str] {
        &["mis", "bsdf", "light", "max-depth=2", "no-regeneration"]
    }
}
