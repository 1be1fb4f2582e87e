//! `platoon.render`'s keyword arguments made into a request (`platoon::Request`): the
//! method's options by their setting names, from the method's own description.

use std::path::PathBuf;

use pyo3::conversion::FromPyObjectOwned;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use platoon::core::frame::aov::Aov;
use platoon::core::frame::Region;
use platoon::core::method::registry;
use platoon::core::method::settings::{Settings, Value, ValueKind};
use platoon::core::scene::camera::Camera;
use platoon::core::scene::gltf_load::LoadOptions;
use platoon::core::scene::texture_levels::{TextureLod, TextureOptions};
use platoon::request::options::OPTIONS;
use platoon::{CameraChoice, EnvChoice, Request, SceneSource};

/// A keyword argument taken out of `kwargs` (so that what is left are the method's options),
/// converted; a value of the wrong type raises ValueError naming the argument.
fn take<'py, T: FromPyObjectOwned<'py>>(
    kwargs: &Bound<'py, PyDict>,
    key: &str,
    expects: &str,
) -> PyResult<Option<T>> {
    let Some(value) = kwargs.get_item(key)? else {
        return Ok(None);
    };
    kwargs.del_item(key)?;
    if value.is_none() {
        return Ok(None);
    }
    value
        .extract::<T>()
        .map(Some)
        .map_err(|_| bad(key, format!("expects {expects}, not {value}")))
}

fn bad(argument: &str, problem: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(format!("{argument}: {problem}"))
}

/// The request `render(scene, **kwargs)` asks for: the arguments `platoon.render` documents,
/// and the method's options by their setting names. `spp` defaults to `default_spp`.
pub fn request(
    py: Python<'_>,
    scene: Option<PathBuf>,
    kwargs: Option<&Bound<'_, PyDict>>,
    default_spp: u32,
) -> PyResult<Request> {
    let kwargs = match kwargs {
        Some(k) => k.copy()?,
        None => PyDict::new(py),
    };
    let k = &kwargs;
    let d = Request::default();
    let method: String = take(k, "method", "a method's name")?.unwrap_or("path".into());
    let aovs: Vec<String> = take(k, "aovs", "a list of AOV names")?.unwrap_or_default();
    let env: Option<PathBuf> = take(k, "env", "a path")?;
    let env_color: Option<(f32, f32, f32)> = take(k, "env_color", "(r, g, b)")?;
    let camera = match k.get_item("camera")? {
        Some(c) => {
            k.del_item("camera")?;
            camera(&c)?
        }
        None => CameraChoice::Scene(None),
    };
    let mut request = Request {
        scene: match scene {
            Some(p) => SceneSource::File(p),
            None => SceneSource::BuiltIn,
        },
        load: LoadOptions {
            allow_external_files: take(k, "allow_external_files", "True or False")?
                .unwrap_or(false),
            variant: take(k, "variant", "a variant's name")?,
            textures: TextureOptions {
                lod: match take::<String>(k, "texture_lod", "off or ray-cone")? {
                    Some(name) => TextureLod::parse(&name).map_err(|e| bad("texture_lod", e))?,
                    None => TextureLod::Off,
                },
                budget: take(k, "texture_budget", "a number of bytes")?,
            },
        },
        env: match (env, env_color) {
            (Some(p), None) => EnvChoice::File(p),
            (None, Some((r, g, b))) => EnvChoice::Color(glam::Vec3::new(r, g, b)),
            (None, None) => EnvChoice::Scene,
            (Some(_), Some(_)) => return Err(bad("env", "give env or env_color, not both")),
        },
        env_light: platoon::EnvLight {
            strength: take(k, "env_strength", "a factor")?.unwrap_or(1.0),
            rotation: take(k, "env_rotation", "degrees")?.unwrap_or(0.0),
        },
        time: take(k, "time", "seconds")?.unwrap_or(d.time),
        frame_interval: take(k, "frame_interval", "seconds")?.unwrap_or(d.frame_interval),
        camera,
        crop: take::<(u32, u32, u32, u32)>(k, "crop", "(x, y, width, height)")?.map(
            |(x, y, width, height)| Region {
                x,
                y,
                width,
                height,
            },
        ),
        spp: default_spp,
        device_memory_limit: take(k, "device_memory_limit", "a number of bytes")?,
        aovs: aovs
            .iter()
            .map(|a| Aov::parse_list(a).map_err(|e| bad("aovs", e)))
            .collect::<PyResult<Vec<Vec<Aov>>>>()?
            .concat(),
        ..d
    };
    // The frame's options by the request's table (`crop` was taken above: a tuple here).
    for option in OPTIONS {
        if let Some(value) = kwargs.get_item(option.key)? {
            kwargs.del_item(option.key)?;
            if value.is_none() {
                continue;
            }
            let value = value_of(option.kind, &value).map_err(|e| bad(option.key, e))?;
            (option.set)(&mut request, &value).map_err(|e| bad(option.key, e))?;
        }
    }
    request.method = method_of(&method, k)?;
    Ok(request)
}

/// The method `name` with the options left in `kwargs`, by their setting names.
fn method_of(name: &str, kwargs: &Bound<'_, PyDict>) -> PyResult<platoon::core::Method> {
    let kind = registry::kind(name).ok_or_else(|| {
        bad(
            "method",
            format!("unknown method {name:?}: one of {}", registry::names()),
        )
    })?;
    let mut given = Settings::default();
    for (key, value) in kwargs.iter() {
        let key: String = key.extract()?;
        let setting = kind.setting(&key).ok_or_else(|| {
            let known: Vec<&str> = kind.settings().iter().map(|s| s.key).collect();
            let options = match known.is_empty() {
                true => "it has none".to_string(),
                false => known.join(", "),
            };
            bad(
                &key,
                format!(
                    "not an argument of render, nor an option of method {:?} ({options})",
                    kind.name()
                ),
            )
        })?;
        let value = value_of(setting.kind, &value).map_err(|e| bad(&key, e))?;
        given.set(setting.key, value);
    }
    kind.build(&given)
        .map_err(|e| match kind.split_setting(&e) {
            Some((setting, problem)) => bad(setting.key, problem),
            None => bad("method", e),
        })
}

/// None: the scene's first camera; an int or a string: the scene's camera of that index or
/// name; a tuple
/// (eye, target, vertical field of view in degrees): a camera in world space.
fn camera(c: &Bound<'_, PyAny>) -> PyResult<CameraChoice> {
    if c.is_none() {
        return Ok(CameraChoice::Scene(None));
    }
    if let Ok(index) = c.extract::<usize>() {
        return Ok(CameraChoice::Scene(Some(index)));
    }
    if let Ok(name) = c.extract::<String>() {
        return Ok(CameraChoice::Named(name));
    }
    look_at(c).map(CameraChoice::Given).map_err(|_| {
        bad(
            "camera",
            "a scene camera's index or name, or (eye, target, fov_degrees)",
        )
    })
}

/// A camera in world space from (eye, target, vertical field of view in degrees).
pub fn look_at(c: &Bound<'_, PyAny>) -> PyResult<Camera> {
    type LookAt = ((f32, f32, f32), (f32, f32, f32), f32);
    let ((ex, ey, ez), (tx, ty, tz), fov): LookAt = c
        .extract()
        .map_err(|_| bad("camera", "(eye, target, fov_degrees)"))?;
    Ok(Camera::look_at(
        glam::Vec3::new(ex, ey, ez),
        glam::Vec3::new(tx, ty, tz),
        fov.to_radians(),
    ))
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
        ValueKind::Word(_) | ValueKind::Mode(_) => match v.extract::<String>() {
            Ok(s) => Value::parse(kind, &s),
            Err(_) => Err(wrong("a string")),
        },
    }
}
