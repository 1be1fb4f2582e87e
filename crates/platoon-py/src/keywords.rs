//! `platoon.render`'s keyword arguments made into a request (`platoon::Request`): the
//! method's options by their setting names, from the method's own description.

use std::path::PathBuf;
use std::time::Duration;

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use platoon::core::frame::adaptive::Adaptive;
use platoon::core::frame::aov::Aov;
use platoon::core::method::registry;
use platoon::core::method::settings::{Settings, Value, ValueKind};
use platoon::core::scene::camera::Camera;
use platoon::core::scene::gltf_load::LoadOptions;
use platoon::tracer::Sampling;
use platoon::{CameraChoice, EnvChoice, Request, SceneSource};

pub struct Keywords<'a, 'py> {
    pub scene: Option<PathBuf>,
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    pub method: &'a str,
    pub devices: &'a str,
    pub aovs: Vec<String>,
    pub denoise: &'a str,
    pub seed: u32,
    pub max_depth: Option<u32>,
    pub time_limit: Option<f64>,
    pub env: Option<PathBuf>,
    pub env_color: Option<(f32, f32, f32)>,
    pub time: f32,
    pub camera: Option<&'a Bound<'py, PyAny>>,
    pub aperture: f32,
    pub focus_distance: Option<f32>,
    pub balancer: &'a str,
    pub sampling: &'a str,
    pub adaptive_threshold: Option<f32>,
    pub variant: Option<String>,
    pub allow_external_files: bool,
    pub options: Option<&'a Bound<'py, PyDict>>,
}

fn bad(argument: &str, problem: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(format!("{argument}: {problem}"))
}

impl Keywords<'_, '_> {
    pub fn request(&self) -> PyResult<Request> {
        let kind = registry::kind(self.method).ok_or_else(|| {
            bad(
                "method",
                format!(
                    "unknown method {:?}: one of {}",
                    self.method,
                    registry::names()
                ),
            )
        })?;
        let mut given = Settings::default();
        if let Some(options) = self.options {
            for (key, value) in options.iter() {
                let key: String = key.extract()?;
                let setting = kind.setting(&key).ok_or_else(|| {
                    let known: Vec<&str> = kind.settings().iter().map(|s| s.key).collect();
                    bad(
                        &key,
                        format!(
                            "not an argument of render, nor an option of method {:?} ({})",
                            kind.name(),
                            if known.is_empty() {
                                "it has none".into()
                            } else {
                                known.join(", ")
                            }
                        ),
                    )
                })?;
                given.set(
                    setting.key,
                    value_of(setting.kind, &value).map_err(|e| bad(&key, e))?,
                );
            }
        }
        let method = kind.build(&given).map_err(|e| bad("method", e))?;
        let aovs = self
            .aovs
            .iter()
            .map(|a| Aov::parse_list(a).map_err(|e| bad("aovs", e)))
            .collect::<PyResult<Vec<Vec<Aov>>>>()?
            .concat();
        let time_limit = match self.time_limit {
            Some(t) if !(t.is_finite() && t > 0.0) => {
                return Err(bad("time_limit", "must be a positive number of seconds"))
            }
            t => t.map(Duration::from_secs_f64),
        };
        Ok(Request {
            scene: match &self.scene {
                Some(p) => SceneSource::File(p.clone()),
                None => SceneSource::BuiltIn,
            },
            load: LoadOptions {
                allow_external_files: self.allow_external_files,
                variant: self.variant.clone(),
            },
            env: match (&self.env, self.env_color) {
                (Some(p), None) => EnvChoice::File(p.clone()),
                (None, Some((r, g, b))) => EnvChoice::Color(glam::Vec3::new(r, g, b)),
                (None, None) => EnvChoice::Scene,
                (Some(_), Some(_)) => return Err(bad("env", "give env or env_color, not both")),
            },
            time: self.time,
            camera: self.camera()?,
            aperture: self.aperture,
            focus_distance: self.focus_distance,
            width: self.width,
            height: self.height,
            spp: self.spp,
            time_limit,
            max_depth: self.max_depth,
            seed: self.seed,
            method,
            sampling: Sampling::by_name(self.sampling)
                .ok_or_else(|| bad("sampling", "one of mis, bsdf, light"))?,
            devices: self.devices.parse().map_err(|e| bad("devices", e))?,
            balancer: self.balancer.to_string(),
            aovs,
            denoiser: self.denoise.parse().map_err(|e| bad("denoise", e))?,
            adaptive: self.adaptive_threshold.map(|threshold| Adaptive {
                threshold,
                min_spp: None,
            }),
            ..Default::default()
        })
    }

    /// None: the scene's first camera; an int: the scene's camera of that index; a tuple
    /// (eye, target, vertical field of view in degrees): a camera in world space.
    fn camera(&self) -> PyResult<CameraChoice> {
        let Some(c) = self.camera else {
            return Ok(CameraChoice::Scene(None));
        };
        if let Ok(index) = c.extract::<usize>() {
            return Ok(CameraChoice::Scene(Some(index)));
        }
        type LookAt = ((f32, f32, f32), (f32, f32, f32), f32);
        let ((ex, ey, ez), (tx, ty, tz), fov): LookAt = c.extract().map_err(|_| {
            bad(
                "camera",
                "an index of the scene's cameras, or (eye, target, fov_degrees)",
            )
        })?;
        Ok(CameraChoice::Given(Camera::look_at(
            glam::Vec3::new(ex, ey, ez),
            glam::Vec3::new(tx, ty, tz),
            fov.to_radians(),
        )))
    }
}

/// A Python value as a setting of `kind`: a number, a bool, (m, n) or "MxN", a string.
fn value_of(kind: ValueKind, v: &Bound<'_, PyAny>) -> Result<Value, String> {
    let wrong = |what: &str| format!("expects {what}, not {v}");
    match kind {
        ValueKind::Count => v
            .extract::<u32>()
            .map(Value::Count)
            .map_err(|_| wrong("a whole number")),
        ValueKind::Number => match v.extract::<f64>() {
            Ok(x) if x.is_finite() => Ok(Value::Number(x as f32)),
            _ => Err(wrong("a finite number")),
        },
        ValueKind::Switch => v
            .extract::<bool>()
            .map(Value::Switch)
            .map_err(|_| wrong("True or False")),
        ValueKind::Tile => match v.extract::<(u32, u32)>() {
            Ok((m, n)) => Ok(Value::Tile([m, n])),
            Err(_) => match v.extract::<String>() {
                Ok(s) => Value::parse(kind, &s),
                Err(_) => Err(wrong("(m, n) or \"MxN\"")),
            },
        },
        ValueKind::Word(_) => match v.extract::<String>() {
            Ok(s) => Value::parse(kind, &s),
            Err(_) => Err(wrong("a string")),
        },
    }
}
