//! Every conversion between numpy arrays and the kernels' slices, in one place.
//!
//! **Inputs.** The Python layer passes C-contiguous arrays; the kernels read them
//! as flat row-major slices. An array that is not contiguous is refused with the
//! calling domain's own error ([`LayoutError`]: its class and message stay the
//! domain's), never copied silently.
//!
//! **Outputs.** A caller picks the size of most outputs (the angles of a grid, the
//! geometries of a sweep, the points kept). A size that cannot fit is refused before
//! any allocation by `cyclomech._arrays.check_bytes` (one rule for the Python layer
//! and the bindings: the results must fit in the memory available), and numpy's
//! own failure to allocate (`MemoryError`) becomes the same `InputError`, never a
//! Rust panic: `PyArray::zeros` panics on numpy's null pointer, so the arrays are
//! made by `numpy.zeros` through the interpreter, whose failure is a `PyErr`.
//! Arrays made here are C-contiguous, so their slices ([`output`]) and the kernels'
//! flat results reshaped ([`shaped`]) can fail only on a bug: an `InternalError`.

use cyclomech_core::cam::CamError;
use cyclomech_core::cyclogram::CyclogramError;
use cyclomech_core::impact::ImpactError;
use cyclomech_core::input::InvalidInput;
use cyclomech_core::linkage::LinkageError;
use cyclomech_core::motion::MotionError;
use cyclomech_core::press::PressError;
use cyclomech_core::servo::ServoError;
use cyclomech_core::shaft::ShaftError;
use numpy::ndarray::{Array2, Dimension, Ix2};
use numpy::{Element, PyArray, PyReadonlyArray, PyReadwriteArray, PyUntypedArrayMethods};
use pyo3::exceptions::PyMemoryError;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::IntoPyDict;

use crate::errors::{internal, IntoPyErr};

/// A domain's error for an input array that is not C-contiguous, and the views
/// that refuse such an array with it (`ImpactError::slice(py, "t", &t)`).
pub trait LayoutError: IntoPyErr + Sized {
    /// The error naming the array `field`.
    fn layout(field: &'static str) -> Self;

    /// Contiguous view of an input array of any rank, flat in C order.
    fn slice<'a, T: Element, D: Dimension>(
        py: Python<'_>,
        field: &'static str,
        a: &'a PyReadonlyArray<'_, T, D>,
    ) -> PyResult<&'a [T]> {
        a.as_slice().map_err(|_| Self::layout(field).into_pyerr(py))
    }

    /// Contiguous mutable view of an array the caller passes in to be filled.
    fn slice_mut<'a, T: Element, D: Dimension>(
        py: Python<'_>,
        field: &'static str,
        a: &'a mut PyReadwriteArray<'_, T, D>,
    ) -> PyResult<&'a mut [T]> {
        a.as_slice_mut()
            .map_err(|_| Self::layout(field).into_pyerr(py))
    }

    /// A (B, N) input array as (flat row-major slice, B, N).
    fn rows<'a, T: Element>(
        py: Python<'_>,
        field: &'static str,
        a: &'a PyReadonlyArray<'_, T, Ix2>,
    ) -> PyResult<(&'a [T], usize, usize)> {
        let (b, n) = (a.shape()[0], a.shape()[1]);
        Ok((Self::slice(py, field, a)?, b, n))
    }
}

impl LayoutError for CamError {
    fn layout(field: &'static str) -> Self {
        CamError::BadFollower {
            field,
            value: f64::NAN,
            why: "must be a C-contiguous array".into(),
        }
    }
}

impl LayoutError for ShaftError {
    fn layout(field: &'static str) -> Self {
        InvalidInput::bad_value(field, f64::NAN, "must be a C-contiguous array").into()
    }
}

impl LayoutError for ServoError {
    fn layout(field: &'static str) -> Self {
        InvalidInput::bad_value(field, f64::NAN, "must be a C-contiguous array").into()
    }
}

impl LayoutError for ImpactError {
    fn layout(field: &'static str) -> Self {
        ImpactError::Layout { field }
    }
}

impl LayoutError for LinkageError {
    fn layout(field: &'static str) -> Self {
        LinkageError::BadProgram {
            step: 0,
            why: format!("{field} must be C-contiguous"),
        }
    }
}

impl LayoutError for MotionError {
    fn layout(field: &'static str) -> Self {
        MotionError::BadLaw {
            what: format!("{field} must be C-contiguous"),
        }
    }
}

impl LayoutError for PressError {
    fn layout(field: &'static str) -> Self {
        PressError::BadSpec(format!("{field} must be C-contiguous"))
    }
}

impl LayoutError for CyclogramError {
    fn layout(field: &'static str) -> Self {
        CyclogramError::bad_scalar(field, f64::NAN, "the array must be C-contiguous")
    }
}

/// Mutable flat view of an output array made by [`zeros`] (C-contiguous by
/// construction: anything else is an `InternalError`).
pub fn output<'a, T: Element, D: Dimension>(
    py: Python<'_>,
    a: &'a mut PyReadwriteArray<'_, T, D>,
) -> PyResult<&'a mut [T]> {
    a.as_slice_mut()
        .map_err(|_| internal(py, "output array not contiguous".into()))
}

/// A kernel's flat row-major result as a (rows, cols) array. The kernels return
/// exactly rows·cols values; a mismatch is a kernel bug: an `InternalError`.
pub fn shaped<T>(py: Python<'_>, rows: usize, cols: usize, flat: Vec<T>) -> PyResult<Array2<T>> {
    Array2::from_shape_vec((rows, cols), flat)
        .map_err(|e| internal(py, format!("batch result shape: {e}")))
}

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
    allocate(py, shape, true, what, hint)
}

/// A new C-order array whose memory nothing writes before the kernel
/// (`numpy.empty`): fresh pages are cleared by the operating system when the
/// kernel's own threads first touch them, and memory the allocator reuses is not
/// cleared at all. For outputs the kernel writes in full; a failure to allocate
/// is the `InputError` of [`check`] with `hint`.
pub fn empty<'py, T: Element, D: Dimension>(
    py: Python<'py>,
    shape: &[usize],
    what: &str,
    hint: &str,
) -> PyResult<Bound<'py, PyArray<T, D>>> {
    allocate(py, shape, false, what, hint)
}

/// The one way outputs are allocated: `numpy.zeros` or `numpy.empty` (numpy's
/// allocator, so numpy owns the memory; from 4 MiB up with its huge-page advice,
/// which makes the kernels' first touch of a large output faster where the
/// kernel finds huge pages).
fn allocate<'py, T: Element, D: Dimension>(
    py: Python<'py>,
    shape: &[usize],
    zeroed: bool,
    what: &str,
    hint: &str,
) -> PyResult<Bound<'py, PyArray<T, D>>> {
    static ZEROS: PyOnceLock<Py<PyAny>> = PyOnceLock::new();
    static EMPTY: PyOnceLock<Py<PyAny>> = PyOnceLock::new();
    let (cell, name) = if zeroed {
        (&ZEROS, "zeros")
    } else {
        (&EMPTY, "empty")
    };
    let f = cell.get_or_try_init(py, || py.import("numpy")?.getattr(name).map(Bound::unbind))?;
    let made = f.bind(py).call1((shape.to_vec(), T::get_dtype(py)));
    match made {
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
