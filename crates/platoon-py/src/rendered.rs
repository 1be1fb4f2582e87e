//! What `platoon.render` returns: the image, the AOVs and the metadata, with what it cost.

use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays;

/// A rendered still. `image`: float32 H x W x 3, linear radiance (denoised when a denoiser was
/// asked for; `raw` is then the render). `aovs`: {name: float32 H x W x C}. `metadata`: the
/// entries platoon writes into its EXR files (scene, method, approximations, devices...,
/// Cryptomatte's `cryptomatte/KEY/manifest`).
#[pyclass(frozen, module = "platoon", name = "Rendered")]
pub struct Rendered {
    image: Py<PyAny>,
    alpha: Option<Py<PyAny>>,
    raw: Option<Py<PyAny>>,
    aovs: Py<PyDict>,
    metadata: Py<PyDict>,
    #[pyo3(get)]
    spp: u32,
    /// Seconds until the last device was done.
    #[pyo3(get)]
    seconds: f64,
    #[pyo3(get)]
    rays: u64,
    #[pyo3(get)]
    width: u32,
    #[pyo3(get)]
    height: u32,
}

impl Rendered {
    pub fn of(py: Python<'_>, still: platoon::Still) -> PyResult<Rendered> {
        let (w, h) = (still.image.width, still.image.height);
        let aovs = PyDict::new(py);
        for l in &still.layers {
            aovs.set_item(&l.name, arrays::layer(py, l, w, h)?)?;
        }
        // The layers' header attributes too (Cryptomatte's manifests), as the EXR has them.
        let mut metadata = still.metadata.clone();
        metadata.extend(still.layers.iter().flat_map(|l| l.attributes.clone()));
        Ok(Rendered {
            image: arrays::image(py, &still.image)?,
            alpha: (still.alpha.as_ref())
                .map(|a| arrays::plane(py, a, w, h))
                .transpose()?,
            raw: still
                .raw
                .as_ref()
                .map(|f| arrays::image(py, f))
                .transpose()?,
            aovs: aovs.unbind(),
            metadata: arrays::metadata(py, &metadata)?.unbind(),
            spp: still.rendered.spp,
            seconds: still.rendered.wall_time.as_secs_f64(),
            rays: still.rendered.rays,
            width: w,
            height: h,
        })
    }
}

#[pymethods]
impl Rendered {
    #[getter]
    fn image(&self, py: Python<'_>) -> Py<PyAny> {
        self.image.clone_ref(py)
    }

    /// A transparent film's alpha, float32 H x W (the image premultiplied by it); None for
    /// an opaque film.
    #[getter]
    fn alpha(&self, py: Python<'_>) -> Option<Py<PyAny>> {
        self.alpha.as_ref().map(|a| a.clone_ref(py))
    }

    #[getter]
    fn raw(&self, py: Python<'_>) -> Option<Py<PyAny>> {
        self.raw.as_ref().map(|r| r.clone_ref(py))
    }

    #[getter]
    fn aovs(&self, py: Python<'_>) -> Py<PyDict> {
        self.aovs.clone_ref(py)
    }

    #[getter]
    fn metadata(&self, py: Python<'_>) -> Py<PyDict> {
        self.metadata.clone_ref(py)
    }

    fn __repr__(&self) -> String {
        format!(
            "<platoon.Rendered {}x{} at {} spp in {:.2} s>",
            self.width, self.height, self.spp, self.seconds
        )
    }
}
