//! Path tracing: the default method and the reference every other is measured against. Its
//! options are `FrameParams`' estimator knobs (shared with the methods that reuse the path loop,
//! shaders/path/), so the method itself adds no defines and no pass after assembly; and
//! [`PathKernel`] (`path_kernel`), how its work is cut into kernels on a device (the same image
//! either way).

use crate::flatten::features::KernelOption;
use crate::frame::FrameParams;
use crate::method::render_method::RenderMethod;

/// The path tracer (`Method::path_tracing()`).
#[derive(Debug, PartialEq)]
pub struct PathTracing;

impl RenderMethod for PathTracing {
    fn name(&self) -> &'static str {
        "path"
    }
    fn describe(&self) -> String {
        "path tracing".into()
    }
    fn validate(&self, params: &FrameParams) -> Result<(), String> {
        if params.cut_last_paths && params.kernel == PathKernel::Streaming {
            return Err("cutting the last paths of a pass (NOP) is the megakernel's: the streaming kernels follow every path to its end".into());
        }
        Ok(())
    }
    fn kernel_options(&self) -> Vec<KernelOption> {
        Vec::new()
    }
    fn approximations(&self) -> Vec<String> {
        Vec::new()
    }
}

pub use super::path_kernel::PathKernel;

/// The path tracer as a user chooses it: no settings of its own (its knobs are the frame's).
pub struct PathKind;

impl crate::method::kind::MethodKind for PathKind {
    fn name(&self) -> &'static str {
        "path"
    }
    fn title(&self) -> &'static str {
        "path tracing"
    }
    fn summary(&self) -> &'static str {
        "Path tracing with NEE and MIS: unbiased, the reference."
    }
    fn settings(&self) -> &'static [crate::method::settings::Setting] {
        &[]
    }
    fn build(
        &self,
        _given: &crate::method::settings::Settings,
    ) -> Result<crate::method::Method, String> {
        Ok(crate::method::Method::path_tracing())
    }
    fn settings_of(&self, _method: &crate::method::Method) -> crate::method::settings::Settings {
        Default::default()
    }
    /// Its estimators against each other, a short path and no regeneration.
    fn sweep(&self) -> &'static [&'static str] {
        &["mis", "bsdf", "light", "max-depth=2", "no-regeneration"]
    }
}
