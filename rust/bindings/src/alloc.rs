//! Output arrays: sized before they are allocated, allocated without panicking.
//!
//! A caller picks the size of most outputs (the angles of a grid, the geometries
//! of a sweep, the points kept). A size that cannot fit is refused before any
//! allocation by `cyclomech._arrays.check_bytes` (one rule for the Python layer
//! and the bindings: the results must fit in the memory available), and numpy's
//! own failure to allocate (`MemoryError`) becomes the same `InputError`, never a
//! Rust panic: `PyArray::zeros` panics on numpy's null pointer, so the arrays are
//! made by `numpy.zeros` through the interpreter, whose failure is a `PyErr`.

use numpy::ndarray::Dimension;
use numpy::{Element, PyArray};
use pyo3::exceptions::PyMemoryError;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::IntoPyDict;

/// Bytes of arrays of the given shapes and item sizes; `f64::INFINITY` if the
/// count overflows (such a size cannot fit anywhere).
pub fn nbytes(arrays: &[(&[usize], usize)]) -> f64 {
    arrays
        .iter()
        .try_fold(0usize, |total, (shape, item)| {
            shape
                .iter()
                .try_fold(*item, |n, &d| n.checked_mul(d))
                .and_then(|n| total.checked_add(n))
        })
        .map_or(f64::INFINITY, |n| n as f64)
}

/// Refuse results of `bytes` bytes that cannot fit, naming `what` and `hint`.
pub fn check(py: Python<'_>, what: &str, bytes: f64, hint: &str) -> PyResult<()> {
    call_check(py, what, bytes, hint, false)
}

fn call_check(py: Python<'_>, what: &str, bytes: f64, hint: &str, failed: bool) -> PyResult<()> {
    static CHECK: PyOnceLock<Py<PyAny>> = PyOnceLock::new();
    let f = CHECK.get_or_try_init(py, || {
        py.import("cyclomech._arrays")?
            .getattr("check_bytes")
            .map(Bound::unbind)
    })?;
    let kwargs = [("failed", failed)].into_py_dict(py)?;
    f.bind(py).call((what, bytes, hint), Some(&kwargs))?;
    Ok(())
}

/// A new zero-filled C-order array of `shape`; an allocation failure is the
/// `InputError` of [`check`] with `hint`.
pub fn zeros<'py, T: Element, D: Dimension>(
    py: Python<'py>,
    shape: &[usize],
    what: &str,
    hint: &str,
) -> PyResult<Bound<'py, PyArray<T, D>>> {
    static ZEROS: PyOnceLock<Py<PyAny>> = PyOnceLock::new();
    let f = ZEROS.get_or_try_init(py, || {
        py.import("numpy")?.getattr("zeros").map(Bound::unbind)
    })?;
    match f.bind(py).call1((shape.to_vec(), T::get_dtype(py))) {
        Ok(a) => Ok(a.cast_into::<PyArray<T, D>>()?),
        Err(e) if e.is_instance_of::<PyMemoryError>(py) => {
            // Numpy could not allocate: report it as a size that does not fit.
            let bytes = nbytes(&[(shape, std::mem::size_of::<T>())]);
            call_check(py, what, bytes, hint, true)?;
            Err(e)
        }
        Err(e) => Err(e),
    }
}
