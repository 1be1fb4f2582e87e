//! How a render's samples are batched (`platoon_core::frame::adaptive`): adaptive sampling
//! from `--adaptive-threshold`, the variance AOV's batches from `--aov variance`, and what
//! they refuse.

use anyhow::{bail, Result};
use platoon::core::frame::adaptive::{Adaptive, Batching};
use platoon::core::frame::aov::Aov;
use platoon::core::frame::FrameParams;
use platoon::core::output::{check_image_path, ImageFormat};

/// The batching of a render of `params` to `out` with `adaptive` and `aovs`; an EXR output of
/// an adaptive render gets the sample-count layer.
pub fn of(
    adaptive: Option<Adaptive>,
    params: &FrameParams,
    out: &std::path::Path,
    aovs: &mut Vec<Aov>,
) -> Result<Batching> {
    if let Some(a) = &adaptive {
        a.validate(params.spp)
            .map_err(|e| anyhow::anyhow!("--adaptive-threshold: {e}"))?;
        if matches!(check_image_path(out)?, ImageFormat::Exr) && !aovs.contains(&Aov::SampleCount) {
            aovs.push(Aov::SampleCount);
        }
    }
    let batching = Batching {
        adaptive,
        variance: aovs.contains(&Aov::Variance),
    };
    if batching.is_some() && params.time_limit.is_some() {
        bail!("--time-limit cannot end adaptive sampling or the variance AOV's batches early");
    }
    if batching.adaptive.is_some() && params.method != platoon::core::Method::PathTracing {
        bail!("--adaptive-threshold: adaptive sampling is the path tracer's (no --method)");
    }
    if batching.variance && params.spp < 2 {
        bail!("the variance AOV needs at least 2 samples per pixel");
    }
    Ok(batching)
}
