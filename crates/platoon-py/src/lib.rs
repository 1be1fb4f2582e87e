//! platoon for Python: `platoon.render(scene, spp=..., width=..., method=..., devices=...,
//! aovs=[...], denoise=...)` returning the image as a float32 H x W x 3 array of linear
//! radiance with its AOVs and metadata, `platoon.devices()`, `platoon.methods()`, and
//! `platoon.read_exr`. A thin layer over the facade's front door (`platoon::Request`): the
//! keyword arguments make a request ([`keywords`]), whose rules raise `ValueError` naming the
//! argument; other failures raise `platoon.PlatoonError` naming the file and the problem.

mod arrays;
mod display;
mod game;
mod keywords;
mod progressive;
mod rendered;

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc, Mutex, OnceLock};
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
pub(crate) fn to_py(e: anyhow::Error) -> PyErr {
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
#[pyo3(signature = (scene=None, **kwargs))]
fn render(
    py: Python<'_>,
    scene: Option<PathBuf>,
    kwargs: Option<&Bound<'_, PyDict>>,
) -> PyResult<Rendered> {
    let request = keywords::request(py, scene, kwargs, platoon::Request::default().spp)?;
    let still = render_interruptibly(py, request)?;
    Rendered::of(py, still)
}

/// A render asked of the worker, whether Ctrl-C withdrew it, and where its result goes.
type Job = (
    platoon::Request,
    Arc<AtomicBool>,
    mpsc::Sender<anyhow::Result<platoon::Still>>,
);

/// Whether a thread of this module should start a call's work: not when Ctrl-C withdrew the
/// call before it began. A stop asked for earlier (`platoon::tracer::stop`, which every band
/// reads) was an earlier call's, perhaps after that one had ended: it is withdrawn, so that
/// only a Ctrl-C from now on stops this call.
pub(crate) fn begin(withdrawn: &AtomicBool) -> bool {
    if withdrawn.load(Ordering::SeqCst) {
        return false;
    }
    platoon::tracer::stop::clear();
    true
}

/// After Ctrl-C in a wait for `withdrawn`'s call: the call is withdrawn if it has not begun,
/// and the devices stop after their current pass if it has.
pub(crate) fn withdraw(withdrawn: &AtomicBool) {
    withdrawn.store(true, Ordering::SeqCst);
    platoon::tracer::stop::request();
}

/// The one thread that renders for this process: made once, so that renders do not each
/// leave a thread's memory arena behind.
fn worker() -> &'static Mutex<mpsc::Sender<Job>> {
    static WORKER: OnceLock<Mutex<mpsc::Sender<Job>>> = OnceLock::new();
    WORKER.get_or_init(|| {
        let (jobs, incoming) = mpsc::channel::<Job>();
        std::thread::spawn(move || {
            for (request, withdrawn, reply) in incoming {
                if begin(&withdrawn) {
                    let _ = reply.send(request.render(&mut |_| {}));
                }
            }
        });
        Mutex::new(jobs)
    })
}

/// Renders on the worker thread with the GIL released, looking for Ctrl-C meanwhile.
fn render_interruptibly(py: Python<'_>, request: platoon::Request) -> PyResult<platoon::Still> {
    let (done, result) = mpsc::channel();
    let withdrawn = Arc::new(AtomicBool::new(false));
    worker()
        .lock()
        .map_err(|_| PlatoonError::new_err("the render thread failed earlier"))?
        .send((request, withdrawn.clone(), done))
        .map_err(|_| PlatoonError::new_err("the render thread has ended"))?;
    match wait(py, result) {
        Err(e) if e.is_instance_of::<pyo3::exceptions::PyKeyboardInterrupt>(py) => {
            // The devices stop after their current pass, not after the render's samples.
            withdraw(&withdrawn);
            Err(e)
        }
        waited => waited?.map_err(to_py),
    }
}

/// What another thread sends on `result`, waited for with the GIL released; Ctrl-C raises
/// KeyboardInterrupt at once (the other thread finishes its work behind).
pub(crate) fn wait<T: Send>(py: Python<'_>, mut result: mpsc::Receiver<T>) -> PyResult<T> {
    loop {
        // The receiver goes into the GIL-free wait and back (it may move between threads but
        // not be shared by them).
        let (back, waited) = py.detach(move || {
            let waited = result.recv_timeout(Duration::from_millis(50));
            (result, waited)
        });
        result = back;
        match waited {
            Ok(value) => return Ok(value),
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
/// list of dicts (index, name, type, driver, api, ray_queries: whether it offers them,
/// auto_traversal: what `traversal="auto"` takes on it).
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
        entry.set_item("ray_queries", d.ray_queries)?;
        let auto = platoon::tracer::Traversal::Auto.resolved(&d, 0);
        entry.set_item("auto_traversal", auto.name())?;
        list.append(entry)?;
    }
    Ok(list)
}

/// The frame's options `render` takes as keyword arguments, from the request's table
/// (`platoon::request::options`): {keyword: help}.
#[pyfunction]
fn options(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let all = PyDict::new(py);
    for o in platoon::request::options::OPTIONS {
        all.set_item(o.key, o.help)?;
    }
    Ok(all)
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
    m.add_function(wrap_pyfunction!(options, m)?)?;
    m.add_function(wrap_pyfunction!(read_exr, m)?)?;
    m.add_function(wrap_pyfunction!(display::display, m)?)?;
    m.add_class::<Rendered>()?;
    m.add_class::<progressive::Renderer>()?;
    m.add_class::<game::Game>()?;
    m.add_class::<game::Frame>()?;
    m.add("PlatoonError", m.py().get_type::<PlatoonError>())?;
    Ok(())
}

/// A thread of this module that holds devices (a `Renderer`'s, a `Game`'s), ended and waited
/// for when its owner goes: its tracers are destroyed before the interpreter exits, not while
/// the process tears down the driver under them (a crash at exit otherwise).
pub(crate) struct DeviceThread<T> {
    pub(crate) sender: Mutex<mpsc::Sender<T>>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl<T: Send + 'static> DeviceThread<T> {
    /// `run` on a thread of its own, taking what `sender` sends until it goes.
    pub(crate) fn spawn(run: impl FnOnce(mpsc::Receiver<T>) + Send + 'static) -> Self {
        let (sender, incoming) = mpsc::channel();
        DeviceThread {
            sender: Mutex::new(sender),
            thread: Some(std::thread::spawn(move || run(incoming))),
        }
    }
}

impl<T> Drop for DeviceThread<T> {
    fn drop(&mut self) {
        // The thread ends when its channel closes: replace the one sender with an unused one.
        if let Ok(mut sender) = self.sender.lock() {
            *sender = mpsc::channel().0;
        }
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}
