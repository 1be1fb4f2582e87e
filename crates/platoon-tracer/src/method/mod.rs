//! Rendering methods on one device. A method's device side is one module here implementing
//! `MethodPasses` (the kernels it registers, the buffers it owns, how it records a band's
//! passes, what it leaves per pixel for its pass after assembly) and one arm of `passes_of`;
//! its options, validation and that pass are the core's (`platoon_core::method`), its kernels
//! a folder of shaders/.

mod igi;
mod lhb;
mod links;
mod passes;
mod path;
mod stream;

pub use path::{kernel_label, kernel_spirv, path_kernel};

use platoon_core::method::Method;

pub(crate) use passes::{ensure, MethodPasses, Recorder};

/// The device side of `method`: the registration of every method.
pub(crate) fn passes_of(method: &Method) -> Box<dyn MethodPasses> {
    match method {
        Method::PathTracing => Box::<path::PathPasses>::default(),
        Method::Igi(_) => Box::<igi::IgiPasses>::default(),
        Method::Links(_) => Box::<links::LinksPasses>::default(),
        Method::Lhb(_) => Box::<lhb::LhbPasses>::default(),
        // A method registered at run time renders with the path kernel (its kernel options
        // as defines) and does its own work after assembly (`RenderMethod::finish`).
        Method::External(_) => Box::<path::PathPasses>::default(),
    }
}
