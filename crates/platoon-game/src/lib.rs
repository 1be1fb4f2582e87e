//! A small real game on platoon, headless: boxes and spheres simulated by rapier3d are tossed
//! onto a ground and a stack of boxes, skinned characters walk their animation along circles, a
//! scripted camera alternates between following a character and resting, and a CPU ray query
//! through the screen centre highlights the character it sees. It is the test and the benchmark
//! of the frame driver (`platoon bench game`) and the scene of the game example.

pub mod game;
pub mod physics;
pub mod play;
pub mod world;

pub use game::{Game, GameOptions, Step};
pub use play::{play, FrameRecord, KeptFrame, PlayOptions, Played};
