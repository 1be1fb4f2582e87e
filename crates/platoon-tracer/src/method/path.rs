//! The path tracer on one device, in either of its kernels (`PathKernel`): the megakernel
//! (shaders/path/pathtrace.comp) adding `samples_per_pass` samples per dispatch, or the
//! streaming path tracer (`stream`, shaders/path/stream/). The same image either way.

use std::time::Duration;

use platoon_core::frame::{FrameParams, Output};
use platoon_core::method::path::PathKernel;
use platoon_core::{KernelVariant, SceneFeatures};

use super::stream::{self, StreamPasses};
use super::{MethodPasses, Recorder};
use crate::dispatch::record_dispatch;
use crate::globals::Push;
use crate::gpu::Gpu;
use crate::kernel::{spirv, Sampling};
use crate::Result;

const PATHTRACE: &str = "path/pathtrace.comp";

#[derive(Default)]
pub(crate) struct PathPasses {
    stream: StreamPasses,
}

/// The kernel `params` render with on a CPU device (`cpu`) or a GPU: the tests' outputs (one
/// sample through each pixel's centre) are the megakernel's.
pub fn path_kernel(params: &FrameParams, cpu: bool) -> PathKernel {
    match params.output {
        Output::Radiance => params.kernel.resolved(cpu),
        _ => PathKernel::Mega,
    }
}

impl MethodPasses for PathPasses {
    fn kernels(&self, params: &FrameParams, cpu: bool) -> &'static [&'static str] {
        match path_kernel(params, cpu) {
            PathKernel::Streaming => &stream::KERNELS,
            _ => &[PATHTRACE],
        }
    }

    fn pass(&mut self, rec: &mut Recorder, push: &Push, groups: (u32, u32)) -> Result<Duration> {
        if path_kernel(rec.params, rec.gpu.ctx.info.cpu) == PathKernel::Streaming {
            return self.stream.pass(rec, push);
        }
        let kernel = rec.kernel(PATHTRACE);
        // Earlier passes wrote the accumulation buffer: record_dispatch's barrier orders them.
        rec.gpu
            .timed(|d, cb| unsafe { record_dispatch(d, cb, kernel, push, groups) })
    }

    fn destroy(&mut self, gpu: &mut Gpu) {
        self.stream.destroy(gpu);
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
