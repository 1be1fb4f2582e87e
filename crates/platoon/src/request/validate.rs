//! Every rule of a render request, once, each error naming the option it is about (the CLI
//! writes it as a flag, a binding as a keyword argument).

use std::time::Duration;

use platoon_core::frame::aov::Aov;
use platoon_core::scene::camera::Camera;

use super::error::RequestError;
use super::form::{CameraChoice, Request};

fn refuse(option: &'static str, problem: impl Into<String>) -> Result<(), RequestError> {
    Err(RequestError {
        option,
        problem: problem.into(),
    })
}

/// The most pixels a frame may have: a frame's sample and line counts are 32-bit.
pub const MAX_PIXELS: u64 = 1 << 28;

impl Request {
    /// A time limit given in seconds (a command line's, a binding's): refused unless a
    /// positive finite number, as `validate` refuses a zero one.
    pub fn time_limit_secs(seconds: Option<f64>) -> Result<Option<Duration>, RequestError> {
        match seconds {
            Some(t) if !(t.is_finite() && t > 0.0) => Err(RequestError {
                option: "time_limit",
                problem: "must be a positive number of seconds".into(),
            }),
            t => Ok(t.map(Duration::from_secs_f64)),
        }
    }

    /// Every rule that needs neither the scene nor the devices.
    pub fn validate(&self) -> Result<(), RequestError> {
        for (option, v) in [
            ("width", self.width),
            ("height", self.height),
            ("spp", self.spp),
        ] {
            if v == 0 {
                refuse(option, "must be positive")?;
            }
        }
        let pixels = self.width as u64 * self.height as u64;
        if pixels > MAX_PIXELS {
            refuse(
                "width",
                format!(
                    "{} x {} is {pixels} pixels, more than the {MAX_PIXELS} a frame may have",
                    self.width, self.height
                ),
            )?;
        }
        if let Some(r) = &self.crop {
            if let Err(e) = r.check(self.width, self.height) {
                refuse("crop", e)?;
            }
        }
        if let Some(Err(e)) = self.method.path().resampled_light.map(|r| r.check()) {
            refuse("resampled_light", e)?;
        }
        if let Some(c) = &self.world_cache {
            if let Err(e) = c.validate() {
                refuse("world_cache", e)?;
            }
            if self.method.unit().name() != "path" {
                refuse(
                    "world_cache",
                    format!(
                        "caches the path tracer's bounces; {} gathers its light its own way",
                        self.method.unit().name()
                    ),
                )?;
            }
        }
        if let Some(o) = &self.light_reuse {
            if let Err(e) = o.validate() {
                refuse("light_reuse", e)?;
            }
            if self.method.path().resampled_light.is_none() {
                refuse(
                    "light_reuse",
                    "reuses resampled light's reservoirs: set resampled_light (8 candidates \
                     are a game's choice)",
                )?;
            }
        }
        if self.max_depth == Some(0) {
            refuse(
                "max_depth",
                "a path has at least one segment (1: emitters seen directly)",
            )?;
        }
        if let Some(t) = self.time_limit {
            if t.is_zero() {
                refuse("time_limit", "must be a positive number of seconds")?;
            }
        }
        if !(self.ao_distance.is_finite() && self.ao_distance > 0.0) {
            refuse(
                "ao_distance",
                format!("must be a positive distance, not {}", self.ao_distance),
            )?;
        }
        if !(self.frame_interval.is_finite() && self.frame_interval > 0.0) {
            refuse(
                "frame_interval",
                format!(
                    "must be a positive number of seconds, not {}",
                    self.frame_interval
                ),
            )?;
        }
        if !(self.time.is_finite()) {
            refuse(
                "time",
                format!("must be a finite number of seconds, not {}", self.time),
            )?;
        }
        if let Err((option, problem)) = self.env_light.check() {
            refuse(option, problem)?;
        }
        if !(self.aperture.is_finite() && self.aperture >= 0.0) {
            refuse(
                "aperture",
                format!(
                    "must be a radius >= 0 (0: a pinhole), not {}",
                    self.aperture
                ),
            )?;
        }
        if let Some(f) = self.focus_distance {
            if !(f.is_finite() && f > 0.0) {
                refuse("focus_distance", format!("must be positive, not {f}"))?;
            }
        }
        if let CameraChoice::Given(c) = &self.camera {
            if !c.camera_to_world.is_finite() {
                refuse("camera", "the given camera's transform is not finite")?;
            }
        }
        if platoon_core::balance::by_name(&self.balancer).is_none() {
            refuse(
                "balancer",
                format!(
                    "unknown balancer {}: {}",
                    self.balancer,
                    platoon_core::balance::names_help()
                ),
            )?;
        }
        if let Err(e) = self.denoiser.available() {
            refuse("denoiser", e)?;
        }
        self.validate_batching()
    }

    /// The rules of adaptive sampling and the variance AOV's batches.
    fn validate_batching(&self) -> Result<(), RequestError> {
        if let Some(a) = &self.adaptive {
            if let Err(e) = a.validate(self.spp, &self.method) {
                refuse("adaptive", e)?;
            }
            if let Some(w) = a.idle(self.spp) {
                log::warn!("{w}");
            }
        }
        if self.batching().is_some() && self.time_limit.is_some() {
            refuse(
                "time_limit",
                "cannot end adaptive sampling or the variance AOV's batches early",
            )?;
        }
        if self.aovs.iter().any(|a| a.is_light()) {
            // Each pass renders the beauty's paths again: they sum to the beauty only when
            // every pixel takes the same samples, traced by the path tracer.
            let why = if !self.method.is_path_tracing() {
                Some("the light passes split the path tracer's image: render with method path")
            } else if self.adaptive.is_some() {
                Some("the light passes take every pixel's samples: not with adaptive sampling")
            } else if self.time_limit.is_some() {
                Some("the light passes take every pixel's samples: not with a time limit")
            } else {
                None
            };
            if let Some(why) = why {
                refuse("aovs", why)?;
            }
        }
        if self.aovs.contains(&Aov::Variance) && self.spp < 2 {
            refuse(
                "aovs",
                "the variance AOV needs at least 2 samples per pixel",
            )?;
        }
        Ok(())
    }

    /// A still or a progressive render has no frames to train a world cache with, nor a
    /// previous frame's reservoirs to reuse.
    pub fn refuse_frame_to_frame(&self) -> Result<(), RequestError> {
        if self.world_cache.is_some() {
            return Err(RequestError {
                option: "world_cache",
                problem: "the cache learns over a game loop's frames (view, the game): a still \
                          has none to train it"
                    .into(),
            });
        }
        if self.light_reuse.is_some() {
            return Err(RequestError {
                option: "light_reuse",
                problem: "reuses the previous frame's reservoirs over a game loop's frames \
                          (view, the game): a still has none"
                    .into(),
            });
        }
        Ok(())
    }

    /// The rules that need the number of devices the request renders on.
    pub fn validate_devices(&self, tracers: usize) -> Result<(), RequestError> {
        let params = self.frame_params(Camera::look_at(glam::Vec3::Z, glam::Vec3::ZERO, 1.0));
        params
            .check_split(tracers)
            .or_else(|e| refuse("time_limit", e))
    }
}
