//! A request as a game loop: its scene lit as a still's would be, the frame driver over its
//! devices, each frame of its size at its samples (or holding a frame time), with its seed,
//! depth, method and denoiser. The camera is each frame's, in world space.

use std::time::Duration;

use anyhow::Result;
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
        let mut scene = self.load_scene()?;
        crate::prepare::light(&mut scene, &self.env, &self.env_light)?;
        for w in &scene.warnings {
            log::warn!("{w}");
        }
        crate::game::start(scene, &self.game_options(target))
    }
}
