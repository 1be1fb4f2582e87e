//! `platoon.Game`: the game loop over a living scene. The frame driver runs on a thread of the
//! game's own; each `frame(camera)` starts this frame and returns the previous one (the game
//! goes on while the devices render), edits (`add_instance`, `move`, `remove`, `set_time`)
//! reach the next frame's generation.

use std::path::PathBuf;
use std::sync::mpsc;
use std::time::Duration;

use glam::{DVec3, Quat, Vec3};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use platoon::core::scene::camera::Camera;
use platoon::core::scene::Placement;
use platoon::drive::{Edit, FinishedFrame};

use crate::{arrays, keywords, to_py, wait, DeviceThread, PlatoonError};

type Reply<T> = mpsc::Sender<anyhow::Result<T>>;

enum Command {
    Frame(Camera, Reply<Option<FinishedFrame>>),
    Edit(Edit, Reply<Option<usize>>),
    Finish(Reply<Option<FinishedFrame>>),
}

/// A game loop: `Game(scene, target_ms=None, **the arguments of render)` (spp: samples a
/// frame, 1 by default; target_ms: a frame time held by scaling them instead).
#[pyclass(module = "platoon", name = "Game")]
pub struct Game {
    commands: DeviceThread<Command>,
}

/// A finished frame: `image` (the film after it joined, float32 H x W x 3), `denoised` (with
/// a denoiser), what it was and cost.
#[pyclass(frozen, module = "platoon", name = "Frame")]
pub struct Frame {
    image: Py<PyAny>,
    denoised: Option<Py<PyAny>>,
    /// The game frame (counting calls from 0).
    #[pyo3(get)]
    frame: u32,
    /// Samples per pixel this frame took.
    #[pyo3(get)]
    spp: u32,
    /// Samples per pixel behind the film when it holds exact sums (None after a blend).
    #[pyo3(get)]
    film_samples: Option<u32>,
    /// The render thread's time for the frame, in milliseconds.
    #[pyo3(get)]
    busy_ms: f64,
    /// The share of the frame the devices waited for each other.
    #[pyo3(get)]
    idle: f64,
}

#[pymethods]
impl Frame {
    #[getter]
    fn image(&self, py: Python<'_>) -> Py<PyAny> {
        self.image.clone_ref(py)
    }

    #[getter]
    fn denoised(&self, py: Python<'_>) -> Option<Py<PyAny>> {
        self.denoised.as_ref().map(|d| d.clone_ref(py))
    }
}

fn frame_of(py: Python<'_>, done: FinishedFrame) -> PyResult<Frame> {
    let s = &done.stats;
    Ok(Frame {
        image: arrays::image(py, &done.film)?,
        denoised: done
            .denoised
            .as_ref()
            .map(|f| arrays::image(py, f))
            .transpose()?,
        frame: s.frame,
        spp: s.plan.spp,
        film_samples: s.film_samples,
        busy_ms: s.busy.as_secs_f64() * 1e3,
        idle: s.idle_fraction,
    })
}

/// Where a node goes: a position, and a rotation quaternion (x, y, z, w) and a scale.
fn placement(
    position: (f64, f64, f64),
    rotation: Option<(f32, f32, f32, f32)>,
    scale: Option<(f32, f32, f32)>,
) -> Placement {
    let (x, y, z) = position;
    Placement {
        translation: DVec3::new(x, y, z),
        rotation: rotation.map_or(Quat::IDENTITY, |(x, y, z, w)| Quat::from_xyzw(x, y, z, w)),
        scale: scale.map_or(Vec3::ONE, |(x, y, z)| Vec3::new(x, y, z)),
    }
}

impl Game {
    fn ask<T: Send>(
        &self,
        py: Python<'_>,
        command: impl FnOnce(Reply<T>) -> Command,
    ) -> PyResult<T> {
        let (reply, result) = mpsc::channel();
        self.commands
            .sender
            .lock()
            .map_err(|_| PlatoonError::new_err("the game failed earlier"))?
            .send(command(reply))
            .map_err(|_| PlatoonError::new_err("the game's thread has ended"))?;
        wait(py, result)?.map_err(to_py)
    }
}

#[pymethods]
impl Game {
    #[new]
    #[pyo3(signature = (scene=None, target_ms=None, **kwargs))]
    fn new(
        py: Python<'_>,
        scene: Option<PathBuf>,
        target_ms: Option<f64>,
        kwargs: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Game> {
        let request = keywords::request(py, scene, kwargs, 1)?;
        let target = target_ms.map(|ms| Duration::from_secs_f64(ms.max(0.0) * 1e-3));
        let (ready, started) = mpsc::channel::<anyhow::Result<()>>();
        let commands = DeviceThread::spawn(move |incoming: mpsc::Receiver<Command>| {
            let mut driver = match request.start_game(target) {
                Ok(d) => d,
                Err(e) => {
                    let _ = ready.send(Err(e));
                    return;
                }
            };
            let _ = ready.send(Ok(()));
            for command in incoming {
                match command {
                    Command::Frame(camera, reply) => {
                        // A stop left by an interrupted render is not this frame's (`begin`).
                        platoon::tracer::stop::clear();
                        let out = driver.frame(camera).map(|o| o.finished);
                        let _ = reply.send(out.map_err(anyhow::Error::new));
                    }
                    Command::Edit(edit, reply) => {
                        let out = driver.scene().push(edit);
                        let _ = reply.send(out.map_err(anyhow::Error::new));
                    }
                    Command::Finish(reply) => {
                        let _ = reply.send(driver.finish().map_err(anyhow::Error::new));
                    }
                }
            }
        });
        wait(py, started)?.map_err(to_py)?;
        Ok(Game { commands })
    }

    /// Renders this frame from `camera` ((eye, target, fov_degrees) in world space) while
    /// the game goes on; returns the previous frame (None on the first call).
    fn frame(&self, py: Python<'_>, camera: &Bound<'_, PyAny>) -> PyResult<Option<Frame>> {
        let camera = keywords::look_at(camera)?;
        self.ask(py, |r| Command::Frame(camera, r))?
            .map(|done| frame_of(py, done))
            .transpose()
    }

    /// Waits for the last frame and returns it.
    fn finish(&self, py: Python<'_>) -> PyResult<Option<Frame>> {
        self.ask(py, Command::Finish)?
            .map(|done| frame_of(py, done))
            .transpose()
    }

    /// A new instance of the scene's mesh `mesh` at `position` (a rotation quaternion
    /// (x, y, z, w) and a scale optional); its node, for `move` and `remove`.
    #[pyo3(signature = (mesh, position, rotation=None, scale=None))]
    fn add_instance(
        &self,
        py: Python<'_>,
        mesh: usize,
        position: (f64, f64, f64),
        rotation: Option<(f32, f32, f32, f32)>,
        scale: Option<(f32, f32, f32)>,
    ) -> PyResult<usize> {
        let placement = placement(position, rotation, scale);
        self.ask(py, |r| {
            Command::Edit(Edit::AddInstance { mesh, placement }, r)
        })?
        .ok_or_else(|| PlatoonError::new_err("the new instance has no node"))
    }

    /// Moves the node `node` (of the scene, or from `add_instance`).
    #[pyo3(name = "move", signature = (node, position, rotation=None, scale=None))]
    fn move_node(
        &self,
        py: Python<'_>,
        node: usize,
        position: (f64, f64, f64),
        rotation: Option<(f32, f32, f32, f32)>,
        scale: Option<(f32, f32, f32)>,
    ) -> PyResult<()> {
        let placement = placement(position, rotation, scale);
        self.ask(py, |r| {
            Command::Edit(Edit::Placement { node, placement }, r)
        })?;
        Ok(())
    }

    /// Takes the instance of `node` out of the scene.
    fn remove(&self, py: Python<'_>, node: usize) -> PyResult<()> {
        self.ask(py, |r| Command::Edit(Edit::RemoveInstance(node), r))?;
        Ok(())
    }

    /// The scene's animation time, in seconds.
    fn set_time(&self, py: Python<'_>, seconds: f32) -> PyResult<()> {
        self.ask(py, |r| Command::Edit(Edit::Time(seconds), r))?;
        Ok(())
    }
}
