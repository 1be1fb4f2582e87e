//! A request as a game loop: its scene lit as a still's would be, the frame driver over its
//! devices, each frame of its size at its samples (or holding a frame time), with its seed,
//! depth, method and denoiser. The camera is each frame's, in world space.

use std::time::Duration;

use anyhow::Result;
use platoon_core::scene::camera::Camera;
use platoon_core::scene::{Posed, Scene};
use platoon_live::{DriverOptions, FrameDriver};

use super::form::Request;
use crate::game::GameOptions;

impl Request {
    /// The game loop's options for this request; `target`: a frame time to hold by scaling
    /// the samples a frame (None: the request's `spp` every frame).
    pub fn game_options(&self, target: Option<Duration>) -> GameOptions {
        let mut driver = DriverOptions::new(self.width, self.height);
        driver.spp = self.spp;
        driver.target = target;
        driver.options = self.frame;
        driver.path_loop = self.path_loop.clone();
        driver.method = self.method.clone();
        driver.denoise = self.denoiser;
        GameOptions {
            driver,
            devices: self.devices.clone(),
            balancer: self.balancer.clone(),
            time: self.time,
            validation: self.validation,
            traversal: self.traversal,
            ..GameOptions::new(DriverOptions::new(self.width, self.height))
        }
    }

    /// Starts the game loop of this request (validated; its scene loaded and lit).
    pub fn start_game(&self, target: Option<Duration>) -> Result<FrameDriver> {
        self.validate()?;
        for (option, set, why) in [
            ("crop", self.crop.is_some(), "renders whole frames"),
            (
                "transparent_film",
                self.frame.transparent_film,
                "renders opaque frames",
            ),
            (
                "time_limit",
                self.frame.time_limit.is_some(),
                "holds a frame time by the samples a frame (`target`), not by cutting frames",
            ),
        ] {
            if set {
                return Err(super::error::RequestError {
                    option,
                    problem: format!("a game loop {why}"),
                }
                .into());
            }
        }
        crate::game::start(self.game_scene()?, &self.game_options(target))
    }

    /// The scene a game loop of this request starts from: loaded and lit as a still's would
    /// be (its warnings logged), not flattened: the game's updater flattens it.
    pub fn game_scene(&self) -> Result<Scene> {
        let mut scene = self.load_scene()?;
        let (_, note) = crate::prepare::light(&mut scene, &self.env, &self.env_light)?;
        for w in &scene.warnings {
            log::warn!("{w}");
        }
        if let Some(note) = note {
            log::info!("{note}");
        }
        Ok(scene)
    }

    /// The camera a game of `scene` starts with: the request's, in world space (the game's
    /// render space before its origin first moves), in `posed`, the scene posed at the
    /// request's time (`scene.pose(time)`, which the caller may read too: its bounds).
    pub fn game_camera(&self, scene: &Scene, posed: &Posed) -> Result<Camera> {
        let camera = crate::prepare::camera_at(scene, posed, &self.prepare_options(scene)?)?;
        Ok(self.camera.in_render_space(camera, glam::DVec3::ZERO))
    }
}
