//! Rendering methods on one device. A method's device side is one module here implementing
//! `MethodPasses` (the kernels it registers, the buffers it owns, how it records a band's
//! passes, what it leaves per pixel for its pass after assembly) and one arm of `passes_of`;
//! its options, validation and that pass are the core's (`platoon_core::method`), its kernels
//! a folder of shaders/.

mod igi;
mod lhb;
mod light_reuse;
mod links;
mod passes;
mod path;
mod stream;
mod world_cache;

pub use path::{kernel_label, kernel_spirv, path_kernel};

use platoon_core::method::Method;

pub(crate) use passes::{ensure, MethodPasses, Recorder};

/// The device side of `method`: the registration of every method's kernels, by the name its
/// unit gives (`RenderMethod::name`).
pub(crate) fn passes_of(method: &Method) -> Box<dyn MethodPasses> {
    match method.unit().name() {
        "igi" => Box::<igi::IgiPasses>::default(),
        "links" => Box::<links::LinksPasses>::default(),
        "lhb" => Box::<lhb::LhbPasses>::default(),
        // The path tracer, and a method registered at run time: it renders with the path
        // kernel (its kernel options as defines) and does its own work after assembly
        // (`RenderMethod::finish`).
        _ => Box::<path::PathPasses>::default(),
    }
}
