//! `platoon.display`: a linear image as the display pixels platoon's PNG output would hold,
//! under a view transform and an exposure (`platoon::core::colour`), so a notebook shows what
//! `platoon render --out x.png` writes.

use numpy::{PyArray1, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use platoon::core::colour::{View, ViewTransform};

/// `image` (float32 H x W x 3, scene-linear) as sRGB display pixels under `view_transform`
/// (standard, agx, pbr-neutral, aces) after `exposure` stops: uint8 H x W x 3, or uint16 with
/// `bits=16`, the bytes of platoon's PNG of the same image.
#[pyfunction]
#[pyo3(signature = (image, view_transform="aces", exposure=0.0, bits=8))]
pub fn display(
    py: Python<'_>,
    image: PyReadonlyArrayDyn<'_, f32>,
    view_transform: &str,
    exposure: f32,
    bits: u8,
) -> PyResult<Py<PyAny>> {
    let bad = |what: &str, e: String| PyValueError::new_err(format!("{what}: {e}"));
    let transform = ViewTransform::parse(view_transform).map_err(|e| bad("view_transform", e))?;
    if !exposure.is_finite() {
        return Err(bad("exposure", format!("must be finite, not {exposure}")));
    }
    let shape = image.shape().to_vec();
    let [h, w, 3] = shape[..] else {
        return Err(bad("image", format!("must be H x W x 3, not {shape:?}")));
    };
    let view = View {
        transform,
        exposure,
    };
    let pixels = image.as_array();
    let rgb = (0..h * w).map(|i| {
        let (y, x) = (i / w, i % w);
        [0, 1, 2].map(|c| pixels[[y, x, c]])
    });
    let array = match bits {
        8 => PyArray1::from_vec(py, rgb.flat_map(|p| view.srgb8(p)).collect())
            .reshape([h, w, 3])?
            .into_any(),
        16 => PyArray1::from_vec(py, rgb.flat_map(|p| view.srgb16(p)).collect())
            .reshape([h, w, 3])?
            .into_any(),
        _ => return Err(bad("bits", format!("8 or 16, not {bits}"))),
    };
    Ok(array.unbind())
}
