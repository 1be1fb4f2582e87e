//! `platoon.Renderer`: a render that goes on across calls. The scene is prepared and the
//! tracers made once, on a thread of the renderer's own; each `render(spp)` adds samples to
//! the film, which then holds the same bits as one render of all of them.

use std::path::PathBuf;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{mpsc, Mutex};

use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::rendered::Rendered;
use crate::{keywords, to_py, wait, PlatoonError};

/// Samples to add, and where the still of all of them goes.
type Add = (u32, mpsc::Sender<anyhow::Result<platoon::Still>>);

/// A progressive render: `Renderer(scene, **the arguments of render but spp)`, then
/// `render(spp)` as often as wanted, each returning the image of every sample so far.
#[pyclass(module = "platoon", name = "Renderer")]
pub struct Renderer {
    jobs: Mutex<mpsc::Sender<Add>>,
    spp: AtomicU32,
}

#[pymethods]
impl Renderer {
    #[new]
    #[pyo3(signature = (scene=None, **kwargs))]
    fn new(
        py: Python<'_>,
        scene: Option<PathBuf>,
        kwargs: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Renderer> {
        let request = keywords::request(py, scene, kwargs, 1)?;
        let (jobs, incoming) = mpsc::channel::<Add>();
        let (ready, made) = mpsc::channel::<anyhow::Result<()>>();
        std::thread::spawn(move || {
            let mut progressive = match platoon::Progressive::new(request) {
                Ok(p) => p,
                Err(e) => {
                    let _ = ready.send(Err(e));
                    return;
                }
            };
            let _ = ready.send(Ok(()));
            for (spp, reply) in incoming {
                let _ = reply.send(progressive.add(spp, &mut |_| {}));
            }
        });
        wait(py, made)?.map_err(to_py)?;
        Ok(Renderer {
            jobs: Mutex::new(jobs),
            spp: AtomicU32::new(0),
        })
    }

    /// Adds `spp` samples to every pixel and returns the still of all the samples so far
    /// (`Rendered`, its `spp` the total).
    fn render(&self, py: Python<'_>, spp: u32) -> PyResult<Rendered> {
        let (done, result) = mpsc::channel();
        self.jobs
            .lock()
            .map_err(|_| PlatoonError::new_err("the renderer failed earlier"))?
            .send((spp, done))
            .map_err(|_| PlatoonError::new_err("the renderer's thread has ended"))?;
        let still = wait(py, result)?.map_err(to_py)?;
        self.spp.store(still.rendered.spp, Ordering::Relaxed);
        Rendered::of(py, still)
    }

    /// Samples per pixel so far.
    #[getter]
    fn spp(&self) -> u32 {
        self.spp.load(Ordering::Relaxed)
    }
}
