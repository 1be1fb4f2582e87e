//! The path tracer on one device, in either of its kernels (`PathKernel`): the megakernel
//! (shaders/path/pathtrace.comp) adding `samples_per_pass` samples per dispatch, or the
//! streaming path tracer (`stream`, shaders/path/stream/). The same image either way.

use std::time::Duration;

use platoon_core::frame::aov::AovPass;
use platoon_core::frame::{FrameParams, Output, PixelData, Span};
use platoon_core::method::path::PathKernel;
use platoon_core::{KernelVariant, SceneFeatures};

use super::light_reuse::LightReusePasses;
use super::stream::{self, StreamPasses};
use super::world_cache::{self, WorldCachePasses};
use super::{MethodPasses, Recorder};
use crate::dispatch::{record_dispatch, record_to_host};
use crate::globals::{Push, METHOD_WORDS};
use crate::gpu::Gpu;
use crate::kernel::{spirv, Sampling};
use crate::Result;

const PATHTRACE: &str = "path/pathtrace.comp";

#[derive(Default)]
pub(crate) struct PathPasses {
    stream: StreamPasses,
    /// A megakernel pass of this tracer ran past the loop limit: its later passes stream.
    /// (Passes of a render resemble each other: one cut short predicts the next, and a pass
    /// that streams from the start costs less than a megakernel pass streamed again.)
    cut_short: bool,
    /// The world cache's table, training paths and records (PathTracing::world_cache).
    cache: WorldCachePasses,
    /// Light reuse's history and reservoirs (PathTracing::light_reuse).
    reuse: LightReusePasses,
}

/// The path tracer's device half (both kernels, the world cache, light reuse): what a method
/// that renders the path tracer's image and works on its sums wraps.
pub fn path_passes() -> Box<dyn MethodPasses> {
    Box::<PathPasses>::default()
}

/// Turns of the megakernel's loop-limit canary (path.glsl's loop_canary, push word 0).
const CANARY_TURNS: u32 = 2;
/// stats[STAT_CUT_SHORT] of path.glsl: pixels whose megakernel pass was cut short.
const STAT_CUT_SHORT: usize = 1;

/// The kernel `params` render with on a CPU device (`cpu`) or a GPU: the tests' outputs (one
/// sample through each pixel's centre) and the AOVs are the megakernel's; the light passes,
/// the beauty's paths, take the beauty's.
pub fn path_kernel(params: &FrameParams, cpu: bool) -> PathKernel {
    if beauty_paths(params.output) {
        params.method.path().kernel.resolved(cpu)
    } else {
        PathKernel::Mega
    }
}

/// Whether `output` follows the beauty's paths (the beauty, a light pass).
fn beauty_paths(output: Output) -> bool {
    matches!(output, Output::Radiance | Output::Aov(AovPass::Light(_)))
}

impl MethodPasses for PathPasses {
    fn kernels(&self, params: &FrameParams, cpu: bool) -> Vec<&'static str> {
        match (path_kernel(params, cpu), world_cache::trains(params)) {
            (PathKernel::Streaming, _) => stream::KERNELS.to_vec(),
            (_, true) => vec![PATHTRACE, world_cache::TRAIN],
            _ => vec![PATHTRACE],
        }
    }

    fn prepare(&mut self, gpu: &mut Gpu, params: &FrameParams) -> Result<[u64; 4]> {
        let mut buffers = self.cache.prepare(gpu, params)?;
        [buffers[2], buffers[3]] = self.reuse.prepare(gpu, params)?;
        Ok(buffers)
    }

    fn push_words(&self, params: &FrameParams) -> [u32; METHOD_WORDS] {
        let mut words = [0; METHOD_WORDS];
        words[0] = CANARY_TURNS;
        WorldCachePasses::push_words(params, &mut words);
        // Resampled light's candidates (common/lights.glsl's ris_candidates).
        let resampled = params.method.path().resampled_light;
        words[5] = resampled.map_or(1, |r| r.candidates);
        words
    }

    fn begin_band(&mut self, rec: &mut Recorder, push: &Push) -> Result<Duration> {
        self.cache.train(rec, push)
    }

    /// Per pixel, its world cache record and its reservoir, where the frame has them.
    fn per_pixel(&mut self, params: &FrameParams, span: Span) -> PixelData {
        let mut pixels = self.cache.records(params, span);
        pixels.append(self.reuse.reservoirs(params, span));
        pixels
    }

    /// A megakernel pass, or a streaming one. Where the device cut megakernel invocations
    /// short (llvmpipe's loop limit, path/pathtrace.comp), their pixels are flagged with their
    /// sums untouched and streamed again: the image is the streaming kernels' (the same bits),
    /// and the tracer's later passes stream from the start.
    fn pass(&mut self, rec: &mut Recorder, push: &Push, groups: (u32, u32)) -> Result<Duration> {
        let radiance = beauty_paths(rec.params.output);
        if path_kernel(rec.params, rec.cpu()) == PathKernel::Streaming
            || (self.cut_short && radiance)
        {
            return self.stream.pass(rec, push);
        }
        let kernel = rec.kernel(PATHTRACE)?;
        // Earlier passes wrote the accumulation buffer: record_dispatch's barrier orders them.
        let time = rec.gpu.timed(|d, cb| unsafe {
            record_dispatch(d, cb, kernel, push, groups);
            record_to_host(d, cb);
        })?;
        let cut = rec.stat(STAT_CUT_SHORT);
        if cut == 0 {
            return Ok(time);
        }
        rec.set_stat(STAT_CUT_SHORT, 0);
        self.cut_short = true;
        rec.fallbacks += 1;
        Ok(time + self.stream.pass_listed(rec, push, cut)?)
    }

    fn destroy(&mut self, gpu: &mut Gpu) {
        self.stream.destroy(gpu);
        self.cache.destroy(gpu);
        self.reuse.destroy(gpu);
    }
}

/// Human-readable name of the path tracer's kernel for a scene's features (MIS estimator, no
/// render option selecting code): what `platoon info` shows.
pub fn kernel_label(features: SceneFeatures) -> String {
    let d = KernelVariant::of_scene(features).defines();
    if d.is_empty() {
        format!("{PATHTRACE} (no feature defines)")
    } else {
        format!("{PATHTRACE} -D{}", d.join(" -D"))
    }
}

/// The SPIR-V of the path tracer's kernel for a scene's features and an estimator (cached on
/// disk).
pub fn kernel_spirv(features: SceneFeatures, sampling: Sampling) -> Result<Vec<u32>> {
    let mut d = KernelVariant::of_scene(features).defines();
    d.extend(sampling.define());
    spirv(PATHTRACE, &d)
}
