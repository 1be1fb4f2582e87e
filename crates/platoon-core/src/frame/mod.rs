//! One frame, split into bands of pixel lines. A tracer (one device) renders bands; the core
//! assembles them. Keeping this interface free of Vulkan lets the core drive any number of
//! tracers and lets the balancer live here.

pub mod fault;
pub mod renderer;
mod workers;

use std::sync::Arc;
use std::time::Duration;

use crate::output::Film;
use crate::scene::camera::Camera;

/// Samples each kernel dispatch adds per pixel. Fixed per frame, never derived from the band,
/// so that floating-point summation order (and so the image, bit for bit) is the same whatever
/// the split of the frame between devices. 16 rather than 4: the kernel regenerates paths within
/// a pass, and longer passes keep SIMD lanes busier (14% less CPU time on lavapipe, measured in
/// docs/PERFORMANCE.md).
pub const DEFAULT_SAMPLES_PER_PASS: u32 = 16;

/// Default path-length limit: high enough to be unbounded in practice (Russian roulette ends
/// paths long before), low enough to stop a pathological scene. Reported in the output metadata.
pub const DEFAULT_MAX_DEPTH: u32 = 1024;

#[derive(Clone, Debug, PartialEq)]
pub struct FrameParams {
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    /// Longest path in segments (Mitsuba's convention: 1 = emitters seen directly, 2 = direct light).
    pub max_depth: u32,
    /// Depth from which Russian roulette may end a path.
    pub rr_depth: u32,
    pub seed: u32,
    /// The frame number in the random numbers' key. The frame driver keeps it at the frame of
    /// the last restart while a view converges, so that continuing sample indices never repeat.
    pub frame: u32,
    /// Index of the first sample: the frame renders samples [first_sample, first_sample + spp)
    /// of each pixel (wrapping at 2^32, which a converging view does not reach).
    pub first_sample: u32,
    /// Radiance sums of earlier samples of every pixel (row-major, width x height) that this
    /// frame's samples are added onto, one by one in sample order, so that frames continuing a
    /// sum are bit for bit one longer render. The bands' sums then include them.
    pub accumulated: Option<Arc<[[f32; 3]]>>,
    pub samples_per_pass: u32,
    /// Stop adding passes once this much wall time has gone (at least one pass is rendered):
    /// `spp` is then an upper bound and each band reports the samples it holds. For one
    /// device; bands cut at different times would break the bit-identity of device splits.
    pub time_limit: Option<Duration>,
    pub camera: Camera,
    pub output: Output,
}

/// What the frame's pixels hold.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Output {
    /// Radiance (the render).
    #[default]
    Radiance,
    /// The first hit of the ray through each pixel's centre, as (t, instance, triangle) with
    /// -1 for a miss (instance and triangle in BLAS leaf order, exact as floats below 2^24): what
    /// the CPU ray queries are checked against. One sample per pixel.
    PrimaryHit,
}

impl FrameParams {
    pub fn new(width: u32, height: u32, spp: u32, camera: Camera) -> FrameParams {
        FrameParams {
            width,
            height,
            spp,
            max_depth: DEFAULT_MAX_DEPTH,
            rr_depth: 3,
            seed: 0,
            frame: 0,
            first_sample: 0,
            accumulated: None,
            samples_per_pass: DEFAULT_SAMPLES_PER_PASS,
            time_limit: None,
            camera,
            output: Output::Radiance,
        }
    }
}

/// What a tracer returns for lines [y0, y1): per-pixel radiance sums over all samples.
#[derive(Clone, Debug, Default)]
pub struct Band {
    pub y0: u32,
    pub y1: u32,
    pub sums: Vec<[f32; 3]>,
    /// Samples per pixel this frame added to `sums` (fewer than `FrameParams::spp` when a time
    /// limit cut the render short); 0 means `FrameParams::spp`. The sums also hold
    /// `FrameParams::accumulated` when it is given.
    pub samples: u32,
    pub rays: u64,
    /// Rays traced in each line of the band: the relative cost of the lines.
    pub line_rays: Vec<u64>,
    /// Samples whose radiance was NaN or Inf, zeroed by the kernel.
    pub rejected_samples: u64,
    pub gpu_time: Duration,
    pub wall_time: Duration,
}

impl Band {
    /// Samples per pixel the band's sums hold (`samples`, or `params.spp` when it is 0).
    pub fn spp(&self, params: &FrameParams) -> u32 {
        if self.samples > 0 {
            self.samples
        } else {
            params.spp
        }
    }
}

pub type TracerError = Box<dyn std::error::Error + Send + Sync>;

/// A device that renders bands of lines. Implemented by platoon-tracer for Vulkan devices.
pub trait BandTracer {
    fn render_band(
        &mut self,
        params: &FrameParams,
        y0: u32,
        y1: u32,
        progress: &mut dyn FnMut(u32),
    ) -> Result<Band, TracerError>;

    /// Brings the tracer's copy of the scene to the next generation, `commit` being what
    /// changed since the one it holds; returns the bytes it uploaded. Called between frames.
    /// Tracers that hold no scene (test fakes) have nothing to do.
    fn apply_commit(
        &mut self,
        _commit: &crate::flatten::commit::Commit,
    ) -> Result<u64, TracerError> {
        Ok(0)
    }
    /// Warnings and errors the device has reported so far (its validation layer's); none for
    /// tracers without one.
    fn messages(&self) -> Vec<String> {
        Vec::new()
    }
}

/// Assembles bands covering [0, height) into the frame's average radiance.
pub fn assemble(params: &FrameParams, bands: &[Band]) -> Film {
    let w = params.width as usize;
    let mut pixels = vec![[0.0f32; 3]; w * params.height as usize];
    for b in bands {
        let inv = 1.0 / b.spp(params).max(1) as f32;
        let start = b.y0 as usize * w;
        for (i, s) in b.sums.iter().enumerate() {
            pixels[start + i] = s.map(|v| v * inv);
        }
    }
    Film {
        width: params.width,
        height: params.height,
        pixels,
    }
}
