//! platoon: the embedding API. Load a scene (glTF or the built-in Cornell box), choose its
//! environment and camera and flatten it for the devices ([`mod@prepare`]); create tracers from
//! device specs ([`devices`], [`Tracers`]); render a frame on one tracer or many
//! ([`mod@render`]); its AOVs ([`aov`]) and an animation's frames ([`animation`]); describe the
//! result ([`mod@metadata`]); drive a game loop ([`game`]). The `platoon` command line and the
//! examples are thin layers over it; what measures platoon (benches, the trade-off tool, plots)
//! is the lab's crate, platoon-lab. [`core`] and [`tracer`] are the two crates underneath.
//!
//! A still render of the built-in Cornell box on the first Vulkan device, written as an EXR
//! with its metadata:
//!
//! ```no_run
//! # fn main() -> anyhow::Result<()> {
//! use platoon::core::frame::FrameParams;
//! use platoon::devices::{tracer_options, DeviceSpec};
//! use platoon::tracer::Sampling;
//!
//! let scene = platoon::load_scene(None)?; // None: the built-in Cornell box
//! let prepared = platoon::prepare(scene, &platoon::PrepareOptions::default())?;
//! let options = tracer_options(&DeviceSpec::Indices(vec![0]), false, Sampling::Mis)?;
//! let params = FrameParams::new(512, 512, 64, prepared.camera);
//! let rendered = platoon::render(&prepared, &options[0], &params, &mut |_spp_done| {})?;
//! let meta = platoon::metadata(&prepared, &params, &rendered, "mis");
//! platoon::core::output::write_image("box.exr".as_ref(), &rendered.film, &meta)?;
//! # Ok(())
//! # }
//! ```

pub mod animation;
pub mod aov;
pub mod batched;
pub mod cost;
pub mod devices;
pub mod distributed;
pub mod game;
pub mod metadata;
pub mod method_update;
pub mod motion;
pub mod prepare;
mod register;
pub mod render;
mod rendered;
pub mod request;

pub use metadata::{approximations, metadata, metadata_of, SceneFacts};
pub use platoon_core as core;
/// Frames split between processes: the ranks' two levels of balancing and the bytes between
/// them (the crate `platoon-distribute`; `distributed` runs them over MPI).
pub use platoon_distribute as distribute;
/// A living scene: a game's edits, the double-buffered updater, the frame driver (the crate
/// `platoon-live`).
pub use platoon_live as drive;
/// A frame scheduled over its tracers: the renderer, its rounds and workers (the crate
/// `platoon-schedule`).
pub use platoon_schedule as schedule;
pub use platoon_tracer as tracer;
pub use prepare::{
    load_scene, load_scene_with, prepare, EnvChoice, EnvLight, PrepareOptions, Prepared,
    DEFAULT_SKY,
};
pub use register::register_method;
pub use render::{
    render, render_bands, render_frame, whole_frame, BatchedStats, Rendered, Tracers,
};
pub use request::{
    CameraChoice, FrameShown, Interrupted, Progressive, Request, RequestError, SceneSource, Still,
};
