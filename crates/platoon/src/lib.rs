//! platoon: the embedding API. Load a scene (glTF or the built-in Cornell box), choose its
//! environment and camera and flatten it for the devices ([`mod@prepare`]); create tracers from
//! device specs ([`devices`]); render a frame on one tracer or many ([`mod@render`]); describe the
//! result ([`mod@metadata`]); drive a game loop ([`game`]). The `platoon` command line and the
//! examples are thin layers over it; what measures platoon (benches, the trade-off tool, plots)
//! is the lab's crate, platoon-lab.
//! [`core`] and [`tracer`] are the two crates underneath.

pub mod animation;
pub mod aov;
pub mod devices;
pub mod game;
pub mod generated;
pub mod metadata;
pub mod method_update;
pub mod prepare;
pub mod render;

pub use metadata::{approximations, metadata, metadata_of, SceneFacts};
pub use platoon_core as core;
pub use platoon_tracer as tracer;
pub use prepare::{
    load_scene, load_scene_with, prepare, EnvChoice, PrepareOptions, Prepared, DEFAULT_SKY,
};
pub use render::{render, render_bands, render_frame, whole_frame, Rendered, Tracers};
