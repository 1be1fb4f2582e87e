//! One frame, split into bands of pixels (runs of whole lines, cut within a line where the
//! balancer wants it). A tracer (one device) renders bands; the core assembles them. Keeping this interface free of Vulkan lets the core drive any number of
//! tracers and lets the balancer live here.

pub mod adaptive;
pub mod aov_params;
mod film_state;
mod kernel_word;
pub mod method_report;
mod options;
mod path_loop;
pub mod pixel_data;
mod pixel_filter;
pub(crate) mod pod_bytes;

use std::time::Duration;

pub use crate::balance::Span;
pub use film_state::FilmState;
pub use kernel_word::KernelWord;
pub use method_report::{MethodReport, ReportValue};
pub use options::{FrameOptions, DEFAULT_AO_DISTANCE, OPTION_WORDS};
pub use path_loop::{
    Knob, KnobValue, PathLoop, DEFAULT_MAX_DEPTH, DEFAULT_RR_DEPTH, KNOBS, LOOP_WORDS,
};
pub use pixel_data::{PixelData, PixelRecord};
pub use pixel_filter::PixelFilter;
pub use platoon_aov::{aov, cryptomatte, hit_geometry, light_pass, motion};
pub use platoon_aov::{Crop, Region};

use crate::output::Film;
use crate::scene::camera::Camera;

/// Samples each kernel dispatch adds per pixel. Fixed per frame, never derived from the band,
/// so that floating-point summation order (and so the image, bit for bit) is the same whatever
/// the split of the frame between devices. 16 rather than 4: the kernel regenerates paths within
/// a pass, and longer passes keep SIMD lanes busier (14% less CPU time on lavapipe, measured in
/// docs/PERFORMANCE.md).
pub const DEFAULT_SAMPLES_PER_PASS: u32 = 16;

/// What one frame renders: the same on every device and rank. Its encoding between ranks is
/// derived (serde), but for the method (sent by its settings and state,
/// `platoon-distribute`'s `method_wire`) and the film (each rank's span only).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FrameParams {
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    /// How the path loop every method's kernels run ends, weighs and picks (`path_loop`).
    pub path_loop: PathLoop,
    /// The rendering method and its options (`crate::method`; path tracing by default, whose
    /// own options are its state: `method::path::PathTracing`).
    #[serde(skip, default = "crate::method::Method::path_tracing")]
    pub method: crate::method::Method,
    /// The frame number in the random numbers' key. The frame driver keeps it at the frame of
    /// the last restart while a view converges, so that continuing sample indices never repeat.
    pub frame: u32,
    /// Index of the first sample: the frame renders samples [first_sample, first_sample + spp)
    /// of each pixel (wrapping at 2^32, which a converging view does not reach).
    pub first_sample: u32,
    /// The film this frame continues (its earlier sums, its converged pixels).
    #[serde(skip)]
    pub film: FilmState,
    pub samples_per_pass: u32,
    pub camera: Camera,
    /// The options a request sets as they are: the seed, the pixel filter, a transparent film,
    /// the AO pass's distance, a time limit (`options.rs`).
    pub options: FrameOptions,
    /// A border render: the frame's `width` x `height` pixels are a window of a larger image
    /// (the camera frames that image). None: the frame is the whole image.
    pub crop: Option<Crop>,
    pub output: Output,
}

/// What the frame's pixels hold.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Output {
    /// Radiance (the render).
    #[default]
    Radiance,
    /// The first hit of the ray through each pixel's centre, as (t, instance, triangle) with
    /// -1 for a miss (instance and triangle in BLAS leaf order, exact as floats below 2^24): what
    /// the CPU ray queries are checked against. One sample per pixel.
    PrimaryHit,
    /// The BSDF probe of the surface the ray through each pixel's centre hits first (the tests'
    /// window on the kernel's own BSDF code, `shaders/bsdf_probe.glsl`): one direction sampled
    /// per pixel, in the hit's shading frame (x, y, z; zero when sampling failed). One sample
    /// per pixel; the pixel and the seed pick the random numbers.
    BsdfSample,
    /// ... its sampling pdf and values at the direction a pixel stands for: pixel (x, y) of a
    /// W x H image is cos θ = 1 - 2 (y + 0.5) / H, φ = 2π (x + 0.5) / W in the shading frame;
    /// written are (pdf, luminance of f(wo, wi), luminance of f(wi, wo)), f without the cosine.
    BsdfValue,
    /// A pass of the AOVs (`aov::AovPass`): albedo and normal averaged over the samples as the
    /// radiance is, position and ids one sample through the pixel centre.
    Aov(aov::AovPass),
}

impl Output {
    /// Whether the output is one sample per pixel (the tests' probes, the unfiltered AOVs).
    pub fn one_sample(self) -> bool {
        match self {
            Output::Radiance => false,
            Output::Aov(pass) => pass.spp(u32::MAX) == 1,
            _ => true,
        }
    }
}

/// The accessors of the words the kernel reads of a frame (`FrameParams::kernel_words`), in
/// the same order: each one's name and whether it is an f32.
pub fn kernel_word_names() -> impl Iterator<Item = (&'static str, bool)> {
    let options = OPTION_WORDS.iter().map(|w| (w.name, w.float));
    options.chain(LOOP_WORDS.iter().map(|w| (w.name, w.float)))
}

impl FrameParams {
    /// The words the kernel reads of this frame's options and path loop, the options' first
    /// (`OPTION_WORDS`, then `LOOP_WORDS`): what the tracer pushes, read by the accessors
    /// `kernel_word_names` names.
    pub fn kernel_words(&self) -> impl Iterator<Item = u32> + '_ {
        let options = OPTION_WORDS.iter().map(|w| (w.of)(&self.options));
        options.chain(LOOP_WORDS.iter().map(|w| (w.of)(&self.path_loop)))
    }

    /// What is wrong with the frame, if anything: the rules every tracer holds a band to (the
    /// renderer checks them once before a frame goes to its tracers, so a wrong frame is
    /// refused rather than failing, and dropping, every tracer; the tracer checks them again
    /// for a caller who renders bands on it directly). A request's rules say more, naming its
    /// options (`platoon::Request::validate`).
    pub fn check(&self) -> Result<(), String> {
        if self.output.one_sample() && self.spp != 1 {
            return Err(format!(
                "the {:?} output is one sample per pixel: set spp to 1",
                self.output
            ));
        }
        self.path_loop.check()?;
        let pixels = self.width as usize * self.height as usize;
        if let Some(sums) = &self.film.accumulated {
            if sums.len() != pixels {
                return Err(format!(
                    "the accumulated sums hold {} pixels, the frame {}x{}",
                    sums.len(),
                    self.width,
                    self.height
                ));
            }
        }
        if let Some(c) = &self.film.converged {
            if self.film.accumulated.is_none() || c.len() != pixels {
                return Err(
                    "converged pixels need the accumulated sums, one flag per pixel".into(),
                );
            }
            if !self.method.unit().skips_converged_pixels() {
                return Err(format!(
                    "converged pixels: method {}'s kernels render every pixel's samples",
                    self.method.unit().name()
                ));
            }
        }
        self.method.unit().validate(self)
    }

    /// Whether the frame may be split between `devices`: a time limit cuts one device's
    /// frame only (bands cut at different times would break the image's independence from
    /// the split).
    pub fn check_split(&self, devices: usize) -> Result<(), String> {
        if devices > 1 && self.options.time_limit.is_some() {
            return Err(
                "a time limit renders on one device: bands cut at different times \
                        would break the image's independence from the device split"
                    .into(),
            );
        }
        Ok(())
    }

    /// The frame's placement in the image its camera frames (the whole image without a crop).
    pub fn image_crop(&self) -> Crop {
        self.crop.unwrap_or(Crop {
            x: 0,
            y: 0,
            image_width: self.width,
            image_height: self.height,
        })
    }

    pub fn new(width: u32, height: u32, spp: u32, camera: Camera) -> FrameParams {
        FrameParams {
            width,
            height,
            spp,
            path_loop: PathLoop::default(),
            method: crate::method::Method::path_tracing(),
            frame: 0,
            first_sample: 0,
            film: FilmState::default(),
            samples_per_pass: DEFAULT_SAMPLES_PER_PASS,
            camera,
            options: FrameOptions::default(),
            crop: None,
            output: Output::Radiance,
        }
    }
}

/// What a tracer returns for its span: per-pixel radiance sums over all samples.
#[derive(Clone, Debug, Default)]
pub struct Band {
    pub span: Span,
    /// One sum per pixel of the span.
    pub sums: Vec<[f32; 3]>,
    /// Samples per pixel this frame added to `sums` (fewer than `FrameParams::spp` when a time
    /// limit cut the render short); 0 means `FrameParams::spp`. The sums also hold
    /// `FrameParams::accumulated` when it is given.
    pub samples: u32,
    pub rays: u64,
    /// Rays traced in each line the span touches (from its first line; a line the span cuts
    /// counts only the span's pixels): the relative cost of the lines.
    pub line_rays: Vec<u64>,
    /// Samples whose radiance was NaN or Inf, zeroed by the kernel.
    pub rejected_samples: u64,
    /// Passes the path tracer's megakernel ran past the device's loop limit on (llvmpipe ends
    /// an invocation's loops after 65535 iterations in all); their pixels were rendered by the
    /// streaming kernels, and the tracer's later passes too. The image is the same either way.
    pub kernel_fallbacks: u32,
    /// What the method leaves per pixel of the span for its work after assembly
    /// (`RenderMethod::finish`, a method's preparation, the world cache and light reuse), as
    /// records of its own types (IGI's `IgiTexel`); empty for methods without any.
    pub per_pixel: PixelData,
    /// What the method's passes on this device report (layered hit buffers' build: bytes,
    /// overflow, time), of the method's own type.
    pub method_report: MethodReport,
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

/// A frame whose rules passed (`FrameParams::check`): what a renderer hands its tracers, which
/// trust it rather than check it again. Only `ValidatedFrame::new` makes one; it reads as the
/// frame's parameters.
#[derive(Clone, Debug)]
pub struct ValidatedFrame(FrameParams);

impl ValidatedFrame {
    /// `params`, if its rules pass; else what is wrong with it.
    pub fn new(params: FrameParams) -> Result<ValidatedFrame, String> {
        params.check()?;
        Ok(ValidatedFrame(params))
    }
}

impl std::ops::Deref for ValidatedFrame {
    type Target = FrameParams;
    fn deref(&self) -> &FrameParams {
        &self.0
    }
}

/// A device that renders bands of pixels. Implemented by platoon-tracer for Vulkan devices.
pub trait BandTracer {
    /// Renders the pixels `span` of `frame` (its rules checked: the tracer trusts them);
    /// `progress` hears the samples each pixel holds as passes end.
    fn render_band(
        &mut self,
        frame: &ValidatedFrame,
        span: Span,
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
    /// A whole frame filtered by the à-trous kernel on this tracer's device
    /// (`Denoiser::AtrousDevice`); tracers without one refuse.
    fn filter_atrous(
        &mut self,
        _film: &Film,
        _guides: &crate::denoise::Guides,
    ) -> Result<Film, TracerError> {
        Err("this tracer has no device to filter a frame on".into())
    }
}

/// The bands' sums as one image (row-major, width x height).
pub fn gather_sums(params: &FrameParams, bands: &[Band]) -> Vec<[f32; 3]> {
    let mut sums = vec![[0.0f32; 3]; params.width as usize * params.height as usize];
    for b in bands {
        let start = b.span.begin as usize;
        sums[start..start + b.sums.len()].copy_from_slice(&b.sums);
    }
    sums
}

/// Assembles bands covering the frame into its average radiance.
pub fn assemble(params: &FrameParams, bands: &[Band]) -> Film {
    let w = params.width as usize;
    let mut pixels = vec![[0.0f32; 3]; w * params.height as usize];
    for b in bands {
        let inv = 1.0 / b.spp(params).max(1) as f32;
        let start = b.span.begin as usize;
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
