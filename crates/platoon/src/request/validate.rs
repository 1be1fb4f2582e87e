//! Every rule of a render request, once, each error naming the option it is about (the CLI
//! writes it as a flag, a binding as a keyword argument).

use std::time::Duration;

use platoon_core::frame::aov::Aov;
use platoon_core::method::registry;
use platoon_core::scene::camera::Camera;

use super::error::RequestError;
use super::form::{CameraChoice, Request};
use super::options::OPTIONS;

fn refuse(option: &'static str, problem: impl Into<String>) -> Result<(), RequestError> {
    Err(RequestError {
        option,
        problem: problem.into(),
    })
}

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

    /// Every rule that needs neither the scene nor the devices: each frame option's own
    /// (`options::OPTIONS`), then those of the options outside the table and between options.
    pub fn validate(&self) -> Result<(), RequestError> {
        for o in OPTIONS {
            if let Err(problem) = (o.rule)(self) {
                refuse(o.key, problem)?;
            }
        }
        // The path loop's knobs no flag or keyword sets (an embedder's); its depth is the table's.
        if let Err(e) = self.path_loop.check() {
            refuse("path_loop", e)?;
        }
        // The method's own rules (the path tracer's resampled light and what it learns over
        // a game's frames).
        if let Err((option, problem)) = self.method.unit().check_options() {
            refuse(option, problem)?;
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
        if let CameraChoice::Given(c) = &self.camera {
            if !c.camera_to_world.is_finite() {
                refuse("camera", "the given camera's transform is not finite")?;
            }
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
        if self.batching().is_some() && self.frame.time_limit.is_some() {
            refuse(
                "time_limit",
                "cannot end adaptive sampling or the variance AOV's batches early",
            )?;
        }
        if self.aovs.iter().any(|a| a.is_light()) {
            // Each pass renders the beauty's paths again: they sum to the beauty only when
            // every pixel takes the same samples, on the paths the method's beauty is.
            let method = self.method.unit();
            let why = if !method.splits_into_light_passes() {
                let able = registry::names_that(|m| m.splits_into_light_passes());
                Some(format!(
                    "the light passes split the image of the paths they render again: method \
                     {}'s is not theirs (render with method {able})",
                    method.name()
                ))
            } else if self.adaptive.is_some() {
                Some(
                    "the light passes take every pixel's samples: not with adaptive sampling"
                        .into(),
                )
            } else if self.frame.time_limit.is_some() {
                Some("the light passes take every pixel's samples: not with a time limit".into())
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

    /// A still or a progressive render has no frames to learn over (the path tracer's world
    /// cache, a previous frame's reservoirs to reuse): refused, naming the method's learning
    /// setting.
    pub fn refuse_frame_to_frame(&self) -> Result<(), RequestError> {
        match self.method.kind().learning_of(&self.method).0.first() {
            Some((option, _)) => Err(RequestError {
                option,
                problem: "learns over a game loop's frames (view, the game): a still has none \
                          to learn from"
                    .into(),
            }),
            None => Ok(()),
        }
    }

    /// The rules that need the number of devices the request renders on.
    pub fn validate_devices(&self, tracers: usize) -> Result<(), RequestError> {
        let params = self.frame_params(Camera::look_at(glam::Vec3::Z, glam::Vec3::ZERO, 1.0));
        params
            .check_split(tracers)
            .or_else(|e| refuse("time_limit", e))
    }
}
