//! Rendering methods on one device. A method's device side implements `MethodPasses` (the
//! kernels it runs, the buffers it owns, how it records a band's passes, what it leaves per
//! pixel for its pass after assembly): a built-in method's is one module here and one line of
//! `registry::BUILT_IN`, its kernels a folder of shaders/; a method from outside registers its
//! own with its GLSL (`registry::register`). Its options, validation and that pass are the core's
//! (`platoon_core::method`).

mod igi;
mod lhb;
mod light_reuse;
mod links;
mod passes;
mod path;
pub mod registry;
mod stream;
mod world_cache;

pub use path::{kernel_label, kernel_spirv, path_kernel, path_passes};

use platoon_core::method::Method;

pub use passes::{ensure, MethodPasses, Recorder};

/// The device side of `method`: its registered device half by the name its unit gives
/// (`RenderMethod::name`), built-in (`registry::BUILT_IN`) or from outside.
pub(crate) fn passes_of(method: &Method) -> Box<dyn MethodPasses> {
    match registry::registered(method.unit().name()) {
        Some(kind) => (kind.passes)(),
        // A method registered without a device half renders with the path kernel (its kernel
        // options as defines) and does its own work after assembly (`RenderMethod::finish`).
        None => path_passes(),
    }
}
