//! platoon-frame: the frame contract, what the tracer and the schedule depend on (no Vulkan).
//!
//! - [`frame`]: what one frame renders (`FrameParams`: the film, camera, crop, the request's
//!   options, the path loop, the method), the bands of pixels a tracer renders of it
//!   (`Band`, `BandTracer`, a `ValidatedFrame` it trusts), adaptive sampling and what a
//!   method leaves per pixel or reports;
//! - [`method`]: what renders a frame (`Method`, the unit's `RenderMethod`), how a method is
//!   chosen (`MethodKind`, its settings and technique strings), what it learns over frames,
//!   the kernel variant a frame runs, and the reference method every other one continues
//!   the paths of: the path tracer (`method::path`), a frame's default.
//!
//! The other methods' core halves, and the list of the built-in ones, are platoon-core's;
//! the core re-exports this crate's modules where they were (`platoon_core::frame`,
//! `platoon_core::method::path`...).

pub mod frame;
pub mod method;

// What the contract is made of, by the names the core gives them too, so that a crate built on
// the contract alone (the schedule) reads it as one.
pub use platoon_accel as flatten;
pub use platoon_aov::denoise;
pub use platoon_balance as balance;
pub use platoon_balance::measure;
pub use platoon_image as output;
pub use platoon_scene as scene;
pub use platoon_scene::error;
