//! Layered hit buffers' measuring: the build and the lookups against the path tracer's rays
//! (`bench`), its scenes (`scenes`) and plots (`plot`), and `platoon bench lhb` (`command`).

pub mod bench;
pub mod command;
pub mod plot;
pub mod scenes;
