//! The path loop every method's kernels run (shaders/path/path.glsl; IGI, vertex links and
//! layered hit buffers continue the path tracer's paths through it): how long a path may be,
//! how Russian roulette ends it, what its contributions are clamped to, how it picks lights,
//! and whether its kernel is specialised. The path tracer's own options (its kernels, resampled
//! and reused light, the world cache) are its method's state (`method::path`).

/// Default path-length limit: high enough to be unbounded in practice (Russian roulette ends
/// paths long before), low enough to stop a pathological scene. Reported in the output metadata.
pub const DEFAULT_MAX_DEPTH: u32 = 1024;
/// The path depth Russian roulette starts at.
pub const DEFAULT_RR_DEPTH: u32 = 3;

#[derive(Clone, Debug, PartialEq)]
pub struct PathLoop {
    /// Longest path in segments (Mitsuba's convention: 1 = emitters seen directly, 2 = direct light).
    pub max_depth: u32,
    /// Depth from which Russian roulette may end a path.
    pub rr_depth: u32,
    /// Russian-roulette survival scale in (0, 1]: a path survives with probability
    /// min(max throughput component x this, 0.95) and survivors are weighted up by its inverse,
    /// so any value is unbiased; below 1 paths are shorter (faster) and the image noisier. What
    /// the frame driver's roulette scaling lowers when one sample a frame is already too slow.
    pub rr_survival: f32,
    /// Russian roulette with this fixed survival probability in (0, 1] instead of one from the
    /// path's throughput (unbiased; Bikker's comparison). Compiled in only when set.
    pub rr_fixed: Option<f32>,
    /// Clamp every contribution after the first bounce to this maximum component (a firefly
    /// suppressor games use; biased, listed as an approximation). Compiled in only when set.
    pub clamp_indirect: Option<f32>,
    /// Next-event estimation picks every light with the same probability instead of by power
    /// (unbiased, usually noisier). Compiled in only when set.
    pub uniform_light_selection: bool,
    /// Compile every effect a scene may call for into the kernel, not only this scene's: what
    /// a renderer without specialisation pays (the image is the same; the time is not).
    pub generic_kernel: bool,
    /// Bikker's deterministic path termination instead of Russian roulette: of a pixel's N
    /// samples N/2 end at the first test, N/4 at the second... (biased: no path outlives log2 N
    /// tests). Compiled in only when set.
    pub deterministic_termination: bool,
    /// Paths end at their second non-delta vertex: direct light and one diffuse bounce of
    /// indirect (Bikker's games; biased). Compiled in only when set.
    pub single_diffuse_bounce: bool,
}

impl Default for PathLoop {
    fn default() -> PathLoop {
        PathLoop {
            max_depth: DEFAULT_MAX_DEPTH,
            rr_depth: DEFAULT_RR_DEPTH,
            rr_survival: 1.0,
            rr_fixed: None,
            clamp_indirect: None,
            uniform_light_selection: false,
            generic_kernel: false,
            deterministic_termination: false,
            single_diffuse_bounce: false,
        }
    }
}

impl PathLoop {
    /// What is wrong with these values, if anything (the tracer's band refuses them too: a
    /// frame may come from an embedder without the request's validation).
    pub fn check(&self) -> Result<(), String> {
        if !(self.rr_survival > 0.0 && self.rr_survival <= 1.0) {
            return Err(format!(
                "the Russian-roulette survival scale must be in (0, 1], not {}",
                self.rr_survival
            ));
        }
        if self.rr_fixed.is_some_and(|p| !(p > 0.0 && p <= 1.0)) {
            return Err("a fixed Russian-roulette survival probability must be in (0, 1]".into());
        }
        if self.clamp_indirect.is_some_and(|c| c.is_nan() || c <= 0.0) {
            return Err("the indirect clamp must be a positive radiance".into());
        }
        Ok(())
    }
}
