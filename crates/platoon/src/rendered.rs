//! A frame's result (`Rendered`): the film, its sums and what the frame cost, packed in one
//! place (`pack`) whether one tracer or many rendered it.

use std::time::Duration;

use platoon_core::frame::{FrameParams, MethodReport};
use platoon_core::output::Film;

/// A rendered frame and what it cost.
pub struct Rendered {
    pub film: Film,
    /// Samples per pixel reached (below `FrameParams::spp` when a time limit ended it).
    pub spp: u32,
    /// Time until the last band was done (the slowest tracer's time).
    pub wall_time: Duration,
    /// GPU time of all dispatches, summed over tracers.
    pub gpu_time: Duration,
    pub rays: u64,
    pub rejected_samples: u64,
    /// Megakernel passes the device cut short and the streaming kernels finished
    /// (`Band::kernel_fallbacks`: llvmpipe's loop limit on big scenes; the image is the same).
    pub kernel_fallbacks: u32,
    /// The devices, comma-separated.
    pub device: String,
    pub kernel_defines: Vec<&'static str>,
    /// How each device found what a ray hits (`Tracer::traversal`), in the order of `device`.
    pub traversals: Vec<&'static str>,
    /// Per-tracer statistics of a multi-device frame (empty for one device).
    pub tracers: Vec<platoon_schedule::renderer::TracerStats>,
    pub balancer: Option<&'static str>,
    /// What the Khronos validation layer reported (with validation on).
    pub validation_messages: Vec<String>,
    /// The method's own metadata entries (`RenderMethod::metadata`: what its preparation
    /// did, e.g. vertex links' update; and its report's, `RenderMethod::report_metadata`).
    pub method_metadata: Vec<(String, String)>,
    /// What the method's passes reported of the frame's first band (`Band::method_report`).
    pub method_report: MethodReport,
    /// The radiance sums behind `film` (row-major; they include `FrameParams::accumulated`).
    pub sums: Vec<[f32; 3]>,
    /// What a frame rendered in batches (`crate::batched`) knows of each pixel.
    pub batched: Option<BatchedStats>,
    /// A frame over the ranks of a job (`crate::distributed`): each rank's part and the
    /// communication; `tracers` then holds one entry per rank.
    pub ranks: Option<crate::distributed::RanksReport>,
}

/// Per-pixel statistics of a frame rendered in batches.
#[derive(Clone, Debug)]
pub struct BatchedStats {
    /// The adaptive sampling it was rendered with, if any.
    pub adaptive: Option<platoon_core::frame::adaptive::Adaptive>,
    /// Samples each pixel took (row-major).
    pub samples: Vec<u32>,
    /// The variance of each pixel's mean (per channel), when asked for.
    pub variance: Option<Vec<[f32; 3]>>,
}

impl Rendered {
    /// The film made the mean of the sums over `spp` samples a pixel: what a render that
    /// continued earlier sums (`FilmState::accumulated`) shows of all of them.
    pub fn average_over(&mut self, spp: u32) {
        self.spp = spp;
        let inv = 1.0 / spp as f32;
        self.film.pixels = self.sums.iter().map(|s| s.map(|v| v * inv)).collect();
    }

    pub fn rays(&self) -> u64 {
        self.rays
    }
    pub fn rejected_samples(&self) -> u64 {
        self.rejected_samples
    }
    pub fn gpu_time(&self) -> Duration {
        self.gpu_time
    }
    /// Samples per pixel on average (below `spp` where adaptive sampling stopped pixels).
    pub fn mean_spp(&self) -> f64 {
        match &self.batched {
            Some(b) if !b.samples.is_empty() => {
                b.samples.iter().map(|&n| n as f64).sum::<f64>() / b.samples.len() as f64
            }
            _ => self.spp as f64,
        }
    }
}

/// What a frame measured, on one tracer or many.
pub(crate) struct Measured {
    pub(crate) film: Film,
    pub(crate) sums: Vec<[f32; 3]>,
    pub(crate) spp: u32,
    pub(crate) wall_time: Duration,
    pub(crate) gpu_time: Duration,
    pub(crate) rays: u64,
    pub(crate) rejected_samples: u64,
    pub(crate) kernel_fallbacks: u32,
    pub(crate) method_report: MethodReport,
    pub(crate) tracers: Vec<platoon_schedule::renderer::TracerStats>,
}

/// What rendered it.
pub(crate) struct Devices {
    pub(crate) names: Vec<String>,
    pub(crate) kernel_defines: Vec<&'static str>,
    pub(crate) traversals: Vec<&'static str>,
    pub(crate) balancer: Option<&'static str>,
    pub(crate) validation_messages: Vec<String>,
}

/// The one place a frame's result is packed (batches and ranks then add their parts).
pub(crate) fn pack(params: &FrameParams, m: Measured, d: Devices) -> Rendered {
    let unit = params.method.unit();
    Rendered {
        film: m.film,
        sums: m.sums,
        batched: None,
        spp: m.spp,
        wall_time: m.wall_time,
        gpu_time: m.gpu_time,
        rays: m.rays,
        rejected_samples: m.rejected_samples,
        kernel_fallbacks: m.kernel_fallbacks,
        device: d.names.join(", "),
        kernel_defines: d.kernel_defines,
        traversals: d.traversals,
        tracers: m.tracers,
        balancer: d.balancer,
        validation_messages: d.validation_messages,
        method_metadata: [unit.metadata(), unit.report_metadata(&m.method_report)].concat(),
        method_report: m.method_report,
        ranks: None,
    }
}
