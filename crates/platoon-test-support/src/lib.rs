//! What the tests of several crates share and no library ships: CPU fake tracers (`fakes`) for
//! the renderer's rounds and the ranks' splits, and fault injection (`fault`: a tracer that
//! fails when told to, as a lost device would). A crate of its own rather than a feature of the
//! crate it fakes for: a feature that only tests turn on gives that crate, and every crate built
//! on it, one build for tests and another for everything else.

pub mod fakes;
pub mod fault;
