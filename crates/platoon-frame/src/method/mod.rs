//! What renders a frame and how it is chosen: the frame's `Method` (`choice.rs`), the unit that
//! renders it (`render_method.rs`), its kind (`kind.rs`: name, settings, how they build the
//! method) with its settings (`settings.rs`) and technique strings (`technique.rs`), what a
//! method learns over frames (`learning.rs`), the kernel variant a frame runs (`variant.rs`),
//! and [`path`], unidirectional path tracing: the default and the reference. The other
//! methods and the list of the built-in ones are platoon-core's (`platoon_core::method`).

mod choice;
pub mod kind;
pub mod learning;
pub mod path;
pub mod render_method;
pub mod settings;
pub mod technique;
pub mod variant;

pub use choice::{Method, MethodState};
