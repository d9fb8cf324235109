//! Developed images as NumPy arrays. The values are copied, never
//! recomputed: an array holds what the command line's file of the same
//! mode holds (before a display image's 8-bit quantization).

use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use spar::image::Image;

/// A float64 vector.
pub fn vector(py: Python<'_>, values: Vec<f64>) -> PyObject {
    PyArray1::from_vec(py, values).into_any().unbind()
}

/// A float32 array of `shape` over `values` (row-major).
fn array(py: Python<'_>, values: Vec<f32>, shape: &[usize]) -> PyResult<PyObject> {
    Ok(PyArray1::from_vec(py, values)
        .reshape(shape)?
        .into_any()
        .unbind())
}

/// An image as (height, width, channels): a colour or grey map's RGB.
pub fn interleaved(py: Python<'_>, image: &Image) -> PyResult<PyObject> {
    let shape = [image.height(), image.width(), image.channels().len()];
    array(py, image.data().to_vec(), &shape)
}

/// The stokes mode's image (channels S0..S3 of each of `lambdas`
/// wavelengths, wavelength after wavelength) as (wavelengths, height,
/// width, 4).
pub fn stokes(py: Python<'_>, image: &Image, lambdas: usize) -> PyResult<PyObject> {
    let (w, h) = (image.width(), image.height());
    let nch = image.channels().len();
    if nch != lambdas * 4 {
        return Err(crate::errors::internal(format!(
            "the Stokes image has {nch} channels for {lambdas} wavelength(s)"
        )));
    }
    let data = image.data();
    let mut out = Vec::with_capacity(data.len());
    for l in 0..lambdas {
        for p in 0..w * h {
            out.extend_from_slice(&data[p * nch + l * 4..p * nch + l * 4 + 4]);
        }
    }
    array(py, out, &[lambdas, h, w, 4])
}

/// One-channel images: (height, width) for one, (images, height, width)
/// for several (polcam's four polarizers).
pub fn grey(py: Python<'_>, images: &[Image]) -> PyResult<PyObject> {
    let (w, h) = (images[0].width(), images[0].height());
    let out: Vec<f32> = images.iter().flat_map(|i| i.data().to_vec()).collect();
    if images.len() == 1 {
        array(py, out, &[h, w])
    } else {
        array(py, out, &[images.len(), h, w])
    }
}
