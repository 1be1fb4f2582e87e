//! Rendering methods. Each is one unit: a module here (its options, their validation, the
//! approximations it lists in the output's metadata, its pass after assembly), a module of the
//! tracer (its kernels and buffers on one device, `platoon-tracer/src/method/`), a shader folder
//! and one entry in each layer's registration (`registry::KINDS` here, the tracer's
//! `method::passes_of`). docs/ARCHITECTURE.md, "Adding a rendering method", lists the files.
//!
//! - [`path`]: unidirectional path tracing, the default and the reference;
//! - [`igi`]: instant global illumination (VPLs) with Marques and Santos' accelerations.
//! - [`links`]: vertex links (Schmitz et al.): indirect diffuse light from per-vertex links.
//! - [`lhb`]: layered hit buffers (Yu): indirect rays answered by lookups in buffers of fixed
//!   directions.

mod choice;
pub mod igi;
pub mod kind;
pub mod learning;
pub mod lhb;
pub mod links;
pub mod path;
pub mod registry;
pub mod render_method;
pub mod settings;
pub mod technique;
pub mod variant;

pub use choice::{Method, MethodState};
