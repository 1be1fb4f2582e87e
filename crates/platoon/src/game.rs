//! Embedding platoon in a game loop: [`start`] a [`FrameDriver`] over a scene and the devices of
//! a spec, then call [`FrameDriver::frame`] once per game frame.
//!
//! ```no_run
//! # fn main() -> anyhow::Result<()> {
//! use platoon::drive::DriverOptions;
//! use platoon::core::scene::camera::Camera;
//! use platoon::game::{start, GameOptions};
//!
//! let scene = platoon::load_scene(None)?; // the built-in Cornell box
//! let camera = Camera::from_scene(&scene, &scene.pose(0.0), None).map_err(anyhow::Error::msg)?;
//! let mut options = GameOptions::new(DriverOptions::new(320, 240));
//! options.driver.target = Some(std::time::Duration::from_millis(33)); // hold 30 fps
//! let mut driver = start(scene, &options)?;
//! for _ in 0..100 {
//!     // The game's edits for the frame: driver.scene().push(Edit::Placement { node, placement })?, ...
//!     let out = driver.frame(camera)?; // renders this frame, returns the previous one
//!     if let Some(done) = out.finished {
//!         let _image = done.film; // show it; done.stats says what it cost
//!     }
//! }
//! # Ok(())
//! # }
//! ```

use anyhow::Result;
use glam::DVec3;

use crate::devices::{tracer_options, tracers_from_options, DeviceSpec};
use platoon_core::Scene;
use platoon_live::{DriverOptions, FrameDriver, GiUpdate, Pipeline, UpdaterThreads};
use platoon_tracer::{Sampling, Traversal};

/// Everything [`start`] needs besides the scene.
#[derive(Clone, Debug)]
pub struct GameOptions {
    pub driver: DriverOptions,
    pub devices: DeviceSpec,
    pub balancer: String,
    /// The updater's threads (and cores: a game may keep them apart from the tracers').
    pub updater: UpdaterThreads,
    /// The scene's animation time at the start.
    pub time: f32,
    /// Vulkan's validation layer on every tracer (slow; for tests).
    pub validation: bool,
    /// How each device's kernels find what a ray hits (platoon's own BVH or the device's ray
    /// queries; `Traversal::Auto` by default).
    pub traversal: Traversal,
}

impl GameOptions {
    /// Every Vulkan device, cost-aware balancing, one updater thread.
    pub fn new(driver: DriverOptions) -> GameOptions {
        GameOptions {
            driver,
            devices: DeviceSpec::All,
            balancer: "cost-aware".into(),
            updater: UpdaterThreads::default(),
            time: 0.0,
            validation: false,
            traversal: Traversal::Auto,
        }
    }
}

/// Starts the updater on `scene`, a tracer on every device of the spec with the scene's first
/// generation, and the frame driver over them. Over the ranks of a job:
/// `crate::distributed::game::start`.
pub fn start(scene: Scene, options: &GameOptions) -> Result<FrameDriver> {
    let balancer = crate::devices::balancer(&options.balancer)?;
    let (pipeline, first) =
        Pipeline::with_updater_threads(scene, options.time, DVec3::ZERO, &options.updater)?;
    let mut tracer_options = tracer_options(&options.devices, options.validation, Sampling::Mis)?;
    for t in &mut tracer_options {
        t.traversal = options.traversal;
    }
    let tracers = tracers_from_options(&tracer_options, &first)?;
    // A method updated asynchronously (vertex links) gets tracers of its own on the same
    // devices, which hold the update's snapshot while the others render the newest scene.
    let update_tracers = if options.driver.gi_update == GiUpdate::Asynchronous
        && !options.driver.method.unit().ready()
    {
        tracers_from_options(&tracer_options, &first)?
    } else {
        Vec::new()
    };
    Ok(FrameDriver::with_update_tracers(
        pipeline,
        &first,
        tracers,
        update_tracers,
        balancer,
        options.driver.clone(),
    )?)
}
