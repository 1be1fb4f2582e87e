//! The path tracer's state in a frame: its options and what its frames carry.

use std::sync::Arc;

use super::kernel::PathKernel;
use super::light_reuse::{LightReuse, ReservoirHistory};
use super::world_cache::{CacheTable, WorldCacheOptions};
use crate::frame::Output;

/// The path tracer's state in a frame (`Method::path_tracing()` is its defaults); between
/// ranks as serde derives it (`PathKind::state_bytes`).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
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
    /// (`method::path::world_cache`; biased). None: paths go on. Compiled in only when set.
    pub world_cache: Option<Arc<CacheTable>>,
    /// With resampled light by contribution: the first vertex's light sample reuses the
    /// previous frame's reservoirs around the pixel's reprojection (`method::path::light_reuse`;
    /// ReSTIR DI's temporal and spatial reuse; unbiased unless its options say otherwise).
    /// Compiled in only when set.
    pub light_reuse: Option<Arc<ReservoirHistory>>,
    /// What it learns over a game loop's frames (the world cache, light reuse), which the
    /// frame driver's learner (`RenderMethod::learning`) gives each frame as the two above.
    pub learning: LearningOptions,
}

/// Next-event estimation by resampled importance sampling (Talbot et al. 2005).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
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

    /// What is wrong with it, if anything (one rule for the settings, the request and the
    /// band).
    pub fn check(&self) -> Result<(), String> {
        if self.candidates == 0 {
            return Err("resampled light needs at least one candidate light".into());
        }
        Ok(())
    }

    /// Whether it can weigh the lights of a scene with punctual lights (`punctual`): by
    /// emitted luminance it weighs them in solid angle, where a point, spot or directional light
    /// has no density. What the tracer refuses and the lab skips (one rule).
    pub fn check_lights(&self, punctual: bool) -> Result<(), String> {
        if punctual && !self.contribution {
            return Err(
                "resampled light selection by emitted luminance weighs lights in solid angle: \
                 the scene's punctual lights have no such density (weigh by contribution)"
                    .into(),
            );
        }
        Ok(())
    }
}

impl PathTracing {
    /// How its paths pick lights where it picks them its own way (resampled light), as an
    /// image's metadata says it; None: as the path loop picks them.
    pub fn light_selection(&self) -> Option<String> {
        self.resampled_light.map(|r| {
            format!(
                "{} over {} candidates{}",
                if r.mis { "MIS+RIS" } else { "RIS" },
                r.candidates,
                if r.contribution {
                    " weighed by contribution"
                } else {
                    ""
                }
            )
        })
    }

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

/// What the path tracer learns over a game loop's frames; nothing by default (a still has no
/// frames to learn over and refuses it).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LearningOptions {
    /// The bounces after the first read a world cache trained as the frames go
    /// (`method::path::world_cache`; biased).
    pub world_cache: Option<WorldCacheOptions>,
    /// With resampled light: the first vertex's light sample reuses the previous frame's
    /// reservoirs where its surface was and around it (`method::path::light_reuse`, ReSTIR DI's
    /// temporal and spatial reuse).
    pub light_reuse: Option<LightReuse>,
}

impl LearningOptions {
    pub fn any(&self) -> bool {
        self.world_cache.is_some() || self.light_reuse.is_some()
    }
}
