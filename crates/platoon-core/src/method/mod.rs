//! Rendering methods. Each is one unit: a module here (its options, their validation, the
//! approximations it lists in the output's metadata, its pass after assembly), a module of the
//! tracer (its kernels and buffers on one device, `platoon-tracer/src/method/`), a shader folder
//! and one entry in each layer's registration (`registry::KINDS` here, the tracer's
//! `method::registry::BUILT_IN`). docs/ARCHITECTURE.md, "Adding a rendering method", lists
//! the files. What renders a frame and how a method is chosen (`Method`, `RenderMethod`,
//! `MethodKind`, settings, techniques, learning, the kernel variant) is the frame contract's,
//! crate platoon-frame, re-exported here, with the reference method:
//!
//! - [`path`]: unidirectional path tracing, the default and the reference (platoon-frame's);
//! - [`igi`]: instant global illumination (VPLs) with Marques and Santos' accelerations.
//! - [`links`]: vertex links (Schmitz et al.): indirect diffuse light from per-vertex links.
//! - [`lhb`]: layered hit buffers (Yu): indirect rays answered by lookups in buffers of fixed
//!   directions.

pub mod igi;
pub mod lhb;
pub mod links;
pub mod registry;
#[cfg(test)]
mod tests;

pub use platoon_frame::method::{
    kind, learning, path, render_method, settings, technique, variant, Method, MethodState,
};
