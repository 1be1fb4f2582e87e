//! The path tracer on one device: one kernel (shaders/path/pathtrace.comp) adding
//! `samples_per_pass` samples per dispatch, and no buffers of its own.

use std::time::Duration;

use platoon_core::{KernelVariant, SceneFeatures};

use super::{MethodPasses, Recorder};
use crate::dispatch::record_dispatch;
use crate::globals::Push;
use crate::kernel::{spirv, Sampling};
use crate::Result;

const PATHTRACE: &str = "path/pathtrace.comp";

pub(crate) struct PathPasses;

impl MethodPasses for PathPasses {
    fn kernels(&self) -> &'static [&'static str] {
        &[PATHTRACE]
    }

    fn pass(&mut self, rec: &mut Recorder, push: &Push, groups: (u32, u32)) -> Result<Duration> {
        let kernel = rec.kernel(PATHTRACE);
        // Earlier passes wrote the accumulation buffer: record_dispatch's barrier orders them.
        rec.gpu
            .timed(|d, cb| unsafe { record_dispatch(d, cb, kernel, push, groups) })
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
