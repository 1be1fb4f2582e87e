//! What the tests of several crates share and no library ships: CPU fake tracers (`fakes`) for
//! the renderer's rounds and the ranks' splits. A crate of its own rather than a feature of the
//! crate it fakes for: a feature that only tests turn on gives that crate, and every crate built
//! on it, one build for tests and another for everything else.

pub mod fakes;
