//! `platoon.Renderer`: a render that goes on across calls. The scene is prepared and the
//! tracers made once, on a thread of the renderer's own; each `render(spp)` adds samples to
//! the film, which then holds the same bits as one render of all of them. Ctrl-C raises
//! KeyboardInterrupt at once and stops the devices after their current pass; the interrupted
//! call's samples are not kept, so the film goes on as if it had not been made.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::sync::{mpsc, Arc};

use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::rendered::Rendered;
use crate::{begin, keywords, to_py, wait, withdraw, DeviceThread, PlatoonError};

/// Samples to add, whether Ctrl-C withdrew the call, and where the still of all of them goes.
type Add = (
    u32,
    Arc<AtomicBool>,
    mpsc::Sender<anyhow::Result<platoon::Still>>,
);

/// A progressive render: `Renderer(scene, **the arguments of render but spp)`, then
/// `render(spp)` as often as wanted, each returning the image of every sample so far.
#[pyclass(module = "platoon", name = "Renderer")]
pub struct Renderer {
    jobs: DeviceThread<Add>,
    /// The film's samples a pixel, as the renderer's thread keeps them (also after a call
    /// that Ctrl-C interrupted, whose samples may or may not have been in by then).
    spp: Arc<AtomicU32>,
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
        let (ready, made) = mpsc::channel::<anyhow::Result<()>>();
        let spp = Arc::new(AtomicU32::new(0));
        let film_spp = spp.clone();
        let jobs = DeviceThread::spawn(move |incoming: mpsc::Receiver<Add>| {
            let mut progressive = match platoon::Progressive::new(request) {
                Ok(p) => p,
                Err(e) => {
                    let _ = ready.send(Err(e));
                    return;
                }
            };
            let _ = ready.send(Ok(()));
            for (spp, withdrawn, reply) in incoming {
                if !begin(&withdrawn) {
                    continue;
                }
                let result = progressive.add(spp, &mut |_| {});
                // Before the reply: the caller reads the count once it has the still.
                film_spp.store(progressive.spp(), Ordering::SeqCst);
                let _ = reply.send(result);
            }
        });
        wait(py, made)?.map_err(to_py)?;
        Ok(Renderer { jobs, spp })
    }

    /// Adds `spp` samples to every pixel and returns the still of all the samples so far
    /// (`Rendered`, its `spp` the total). Ctrl-C raises KeyboardInterrupt at once; the film
    /// then keeps none of this call's samples.
    fn render(&self, py: Python<'_>, spp: u32) -> PyResult<Rendered> {
        let (done, result) = mpsc::channel();
        let withdrawn = Arc::new(AtomicBool::new(false));
        self.jobs
            .sender
            .lock()
            .map_err(|_| PlatoonError::new_err("the renderer failed earlier"))?
            .send((spp, withdrawn.clone(), done))
            .map_err(|_| PlatoonError::new_err("the renderer's thread has ended"))?;
        let still = match wait(py, result) {
            Err(e) if e.is_instance_of::<pyo3::exceptions::PyKeyboardInterrupt>(py) => {
                withdraw(&withdrawn);
                return Err(e);
            }
            waited => waited?.map_err(to_py)?,
        };
        Rendered::of(py, still)
    }

    /// Samples per pixel so far.
    #[getter]
    fn spp(&self) -> u32 {
        self.spp.load(Ordering::SeqCst)
    }
}
