//! Path tracing: the default method and the reference every other is measured against. Its
//! options are `FrameParams`' estimator knobs (shared with the methods that reuse the path loop,
//! shaders/path/), so the method itself adds no defines and no pass after assembly; and
//! [`PathKernel`] (`path_kernel`), how its work is cut into kernels on a device (the same image
//! either way).

use std::sync::LazyLock;

use crate::flatten::features::KernelOption;
use crate::frame::FrameParams;
use crate::method::render_method::RenderMethod;
use crate::method::Method;

/// The path tracer (`Method::path_tracing()`).
#[derive(Debug, PartialEq)]
pub struct PathTracing;

static PATH_TRACING: LazyLock<Method> = LazyLock::new(|| Method::new(PathTracing));

impl Method {
    /// Path tracing, the default and the reference.
    pub fn path_tracing() -> Method {
        PATH_TRACING.clone()
    }

    /// Whether this is plain path tracing.
    pub fn is_path_tracing(&self) -> bool {
        self.state::<PathTracing>().is_some()
    }
}

impl Default for Method {
    fn default() -> Method {
        Method::path_tracing()
    }
}

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
    fn unit<'a>(&self, method: &'a Method) -> Option<&'a dyn RenderMethod> {
        method
            .state::<PathTracing>()
            .map(|s| s as &dyn RenderMethod)
    }
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
        Ok(Method::path_tracing())
    }
    fn settings_of(&self, _method: &crate::method::Method) -> crate::method::settings::Settings {
        Default::default()
    }
    /// Its estimators against each other, a short path and no regeneration.
    fn sweep(&self) -> &'static [&'static str] {
        &["mis", "bsdf", "light", "max-depth=2", "no-regeneration"]
    }
}
