//! What every rendering method provides to the core.

use crate::flatten::features::KernelOption;
use crate::frame::{Band, FrameParams};

/// A rendering method as the core sees it: plain data and CPU passes; its device side is the
/// tracer's (`platoon-tracer/src/method/`).
pub trait RenderMethod {
    /// Its name on the command line and in the tracer's registry.
    fn name(&self) -> &'static str;
    /// The method and its options, for the output's metadata.
    fn describe(&self) -> String;
    /// What is wrong with rendering `params` this way, if anything.
    fn validate(&self, params: &FrameParams) -> Result<(), String>;
    /// The kernel defines of its options, each with whether it is on: appended to the scene's
    /// features and the render options in the kernel variant (`variant::KernelVariant`).
    fn kernel_options(&self) -> Vec<KernelOption>;
    /// Its biased parts, for the output's list of approximations.
    fn approximations(&self) -> Vec<String>;
    /// The pass after every band of the frame is in, on the bands' sums (what needs
    /// neighbouring pixels, from the data each band carries in `Band::per_pixel`).
    fn finish(&self, _params: &FrameParams, _bands: &mut [Band]) {}
}
