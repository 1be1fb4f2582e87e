//! platoon's images as numpy arrays: row-major, H x W x channels, float32.

use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use platoon::core::output::{Film, Layer};

/// A film as an H x W x 3 array.
pub fn image(py: Python<'_>, film: &Film) -> PyResult<Py<PyAny>> {
    let flat: Vec<f32> = film.pixels.iter().flatten().copied().collect();
    let shape = [film.height as usize, film.width as usize, 3];
    Ok(PyArray1::from_vec(py, flat)
        .reshape(shape)?
        .into_any()
        .unbind())
}

/// An AOV layer as an H x W x C array, its channels in the layer's order.
pub fn layer(py: Python<'_>, layer: &Layer, width: u32, height: u32) -> PyResult<Py<PyAny>> {
    let pixels = width as usize * height as usize;
    let channels = layer.channels.len();
    let mut flat = vec![0.0f32; pixels * channels];
    for (c, (_, values)) in layer.channels.iter().enumerate() {
        for (p, v) in values.iter().enumerate().take(pixels) {
            flat[p * channels + c] = *v;
        }
    }
    let shape = [height as usize, width as usize, channels];
    Ok(PyArray1::from_vec(py, flat)
        .reshape(shape)?
        .into_any()
        .unbind())
}

/// One value a pixel (a transparent film's alpha) as an H x W array.
pub fn plane(py: Python<'_>, values: &[f32], width: u32, height: u32) -> PyResult<Py<PyAny>> {
    let shape = [height as usize, width as usize];
    Ok(PyArray1::from_vec(py, values.to_vec())
        .reshape(shape)?
        .into_any()
        .unbind())
}

/// Metadata entries as a dict of strings.
pub fn metadata<'py>(py: Python<'py>, meta: &[(String, String)]) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    for (k, v) in meta {
        dict.set_item(k, v)?;
    }
    Ok(dict)
}
