//! platoon for Python: `platoon.render(scene, spp=..., width=..., method=..., devices=...,
//! aovs=[...], denoise=...)` returning the image as a float32 H x W x 3 array of linear
//! radiance with its AOVs and metadata, `platoon.devices()`, `platoon.methods()`, and
//! `platoon.read_exr`. A thin layer over the facade's front door (`platoon::Request`): the
//! keyword arguments make a request ([`keywords`]), whose rules raise `ValueError` naming the
//! argument; other failures raise `platoon.PlatoonError` naming the file and the problem.

mod arrays;
mod keywords;
mod rendered;

use std::path::PathBuf;
use std::sync::{mpsc, Mutex, OnceLock};
use std::time::Duration;

use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use platoon::core::method::registry::KINDS;
use rendered::Rendered;

create_exception!(
    platoon,
    PlatoonError,
    PyException,
    "A render that failed: a scene that cannot be read, a device that cannot be made..."
);

/// A failure of the library as a Python exception: the request's rules as `ValueError`
/// (naming the argument), the rest as `PlatoonError` with the whole chain of causes.
fn to_py(e: anyhow::Error) -> PyErr {
    match e.downcast::<platoon::RequestError>() {
        Ok(r) => PyValueError::new_err(format!("{}: {}", r.option, r.problem)),
        Err(e) => PlatoonError::new_err(format!("{e:#}")),
    }
}

/// Renders a scene (a .gltf or .glb file; the built-in Cornell box when None) and returns a
/// `Rendered`: `.image` (float32 H x W x 3, linear), `.aovs`, `.metadata`. The method's own
/// options are keyword arguments by their names (`platoon.methods()` lists them), e.g.
/// `render(method="igi", vpls=180, imperfect_visibility=True)`. The GIL is released while the
/// devices render; Ctrl-C returns at once with KeyboardInterrupt (the frame already on the
/// devices finishes in the background).
#[pyfunction]
#[pyo3(signature = (
    scene=None, *, width=512, height=512, spp=64, method="path", devices="0", aovs=None,
    denoise="none", seed=0, max_depth=None, time_limit=None, env=None, env_color=None,
    time=0.0, camera=None, aperture=0.0, focus_distance=None, balancer="cost-aware",
    sampling="mis", adaptive_threshold=None, variant=None, allow_external_files=false,
    **options
))]
#[allow(clippy::too_many_arguments)]
fn render(
    py: Python<'_>,
    scene: Option<PathBuf>,
    width: u32,
    height: u32,
    spp: u32,
    method: &str,
    devices: &str,
    aovs: Option<Vec<String>>,
    denoise: &str,
    seed: u32,
    max_depth: Option<u32>,
    time_limit: Option<f64>,
    env: Option<PathBuf>,
    env_color: Option<(f32, f32, f32)>,
    time: f32,
    camera: Option<&Bound<'_, PyAny>>,
    aperture: f32,
    focus_distance: Option<f32>,
    balancer: &str,
    sampling: &str,
    adaptive_threshold: Option<f32>,
    variant: Option<String>,
    allow_external_files: bool,
    options: Option<&Bound<'_, PyDict>>,
) -> PyResult<Rendered> {
    let request = keywords::Keywords {
        scene,
        width,
        height,
        spp,
        method,
        devices,
        aovs: aovs.unwrap_or_default(),
        denoise,
        seed,
        max_depth,
        time_limit,
        env,
        env_color,
        time,
        camera,
        aperture,
        focus_distance,
        balancer,
        sampling,
        adaptive_threshold,
        variant,
        allow_external_files,
        options,
    }
    .request()?;
    let still = render_interruptibly(py, request)?;
    Rendered::of(py, still)
}

/// A render asked of the worker, and where its result goes.
type Job = (
    platoon::Request,
    mpsc::Sender<anyhow::Result<platoon::Still>>,
);

/// The one thread that renders for this process: made once, so that renders do not each
/// leave a thread's memory arena behind.
fn worker() -> &'static Mutex<mpsc::Sender<Job>> {
    static WORKER: OnceLock<Mutex<mpsc::Sender<Job>>> = OnceLock::new();
    WORKER.get_or_init(|| {
        let (jobs, incoming) = mpsc::channel::<Job>();
        std::thread::spawn(move || {
            for (request, reply) in incoming {
                let _ = reply.send(request.render(&mut |_| {}));
            }
        });
        Mutex::new(jobs)
    })
}

/// Renders on the worker thread with the GIL released, looking for Ctrl-C meanwhile.
fn render_interruptibly(py: Python<'_>, request: platoon::Request) -> PyResult<platoon::Still> {
    let (done, mut result) = mpsc::channel();
    worker()
        .lock()
        .map_err(|_| PlatoonError::new_err("the render thread failed earlier"))?
        .send((request, done))
        .map_err(|_| PlatoonError::new_err("the render thread has ended"))?;
    loop {
        // The receiver goes into the GIL-free wait and back (it may move between threads but
        // not be shared by them).
        let (back, waited) = py.detach(move || {
            let waited = result.recv_timeout(Duration::from_millis(50));
            (result, waited)
        });
        result = back;
        match waited {
            Ok(still) => return still.map_err(to_py),
            Err(mpsc::RecvTimeoutError::Timeout) => py.check_signals()?,
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                return Err(PlatoonError::new_err(
                    "the render's thread ended without a result",
                ))
            }
        }
    }
}

/// The Vulkan devices platoon can render on, in the order `devices="0,1"` numbers them: a
/// list of dicts (index, name, type, driver, api).
#[pyfunction]
fn devices(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let found = py
        .detach(platoon::tracer::list_devices)
        .map_err(|e| to_py(e.into()))?;
    let list = PyList::empty(py);
    for d in found {
        let entry = PyDict::new(py);
        entry.set_item("index", d.index)?;
        entry.set_item("name", &d.name)?;
        entry.set_item("type", &d.device_type)?;
        entry.set_item("driver", &d.driver)?;
        entry.set_item("api", &d.api_version)?;
        list.append(entry)?;
    }
    Ok(list)
}

/// The rendering methods and the keyword arguments each takes: {name: {option: help}}.
#[pyfunction]
fn methods(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let all = PyDict::new(py);
    for kind in KINDS {
        let options = PyDict::new(py);
        for s in kind.settings() {
            options.set_item(s.key, s.help)?;
        }
        all.set_item(kind.name(), options)?;
    }
    Ok(all)
}

/// An EXR file's first RGB(A) layer as a float32 H x W x 3 array, and its metadata as a dict
/// (platoon's entries under the names `Rendered.metadata` gives them).
#[pyfunction]
fn read_exr(py: Python<'_>, path: PathBuf) -> PyResult<(Py<PyAny>, Bound<'_, PyDict>)> {
    let (film, meta) =
        platoon::core::output::read_exr(&path).map_err(|e| to_py(anyhow::Error::new(e)))?;
    let meta: Vec<(String, String)> = meta
        .into_iter()
        .map(|(k, v)| {
            (
                k.strip_prefix("platoon:").map_or(k.clone(), str::to_string),
                v,
            )
        })
        .collect();
    Ok((arrays::image(py, &film)?, arrays::metadata(py, &meta)?))
}

#[pymodule]
fn _platoon(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(render, m)?)?;
    m.add_function(wrap_pyfunction!(devices, m)?)?;
    m.add_function(wrap_pyfunction!(methods, m)?)?;
    m.add_function(wrap_pyfunction!(read_exr, m)?)?;
    m.add_class::<Rendered>()?;
    m.add("PlatoonError", m.py().get_type::<PlatoonError>())?;
    Ok(())
}
