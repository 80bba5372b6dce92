//! Bindings of the shaking force's batch over counterweight designs
//! (`cyclomech.dynamics.balance`, issue 34 item 4).

use cyclomech_core::dynamics::shaking::{
    balance_channels as channels_kernel, balance_stats_into, FormShape, N_STATS,
};
use cyclomech_core::input::InvalidInput;
use numpy::ndarray::Ix2;
use numpy::{
    Element, IntoPyArray, PyArray2, PyArrayMethods, PyReadonlyArray, PyReadonlyArray1,
    PyReadonlyArray2, PyReadonlyArray3, PyReadonlyArray4, PyUntypedArrayMethods,
};
use pyo3::prelude::*;

use crate::convert;
use crate::errors::{run, IntoPyErr};

fn flat<'a, T: Element, D: numpy::ndarray::Dimension>(
    py: Python<'_>,
    field: &'static str,
    a: &'a PyReadonlyArray<'_, T, D>,
) -> PyResult<&'a [T]> {
    a.as_slice().map_err(|_| {
        InvalidInput::bad_value(field, f64::NAN, "the array must be C-contiguous").into_pyerr(py)
    })
}

/// The form's shape (N angles, J counterweights) from `lin` (4, J, N, 2).
fn shape(lin: &PyReadonlyArray4<'_, f64>) -> FormShape {
    let s = lin.shape();
    FormShape { n: s[2], j: s[1] }
}

/// (D, 6) statistics (`SHAKING_STATS`) of D counterweight designs (D, J, 2)
/// [kg·m] of the linear form `base` (4, N), `lin` (4, J, N, 2), `nrm` (4, J, N).
#[pyfunction]
#[pyo3(signature = (base, lin, nrm, designs, *, n_threads=None))]
pub fn shaking_batch<'py>(
    py: Python<'py>,
    base: PyReadonlyArray2<'py, f64>,
    lin: PyReadonlyArray4<'py, f64>,
    nrm: PyReadonlyArray3<'py, f64>,
    designs: PyReadonlyArray3<'py, f64>,
    n_threads: Option<i64>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let sh = shape(&lin);
    let d = designs.shape()[0];
    let (b, l, q, w) = (
        flat(py, "base", &base)?,
        flat(py, "lin", &lin)?,
        flat(py, "nrm", &nrm)?,
        flat(py, "designs", &designs)?,
    );
    let out = convert::zeros::<f64, Ix2>(
        py,
        &[d, N_STATS],
        "shaking_batch",
        "ask for fewer designs at a time",
    )?;
    {
        let mut rw = out.readwrite();
        let slice = convert::output(py, &mut rw)?;
        run(py, "shaking_batch", || {
            balance_stats_into(b, l, q, w, sh, slice, n_threads)
        })?;
    }
    Ok(out)
}

/// The four channels (4, N) of one design `w` (J·2,) [kg·m] of the linear form.
#[pyfunction]
pub fn shaking_channels<'py>(
    py: Python<'py>,
    base: PyReadonlyArray2<'py, f64>,
    lin: PyReadonlyArray4<'py, f64>,
    nrm: PyReadonlyArray3<'py, f64>,
    w: PyReadonlyArray1<'py, f64>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let sh = shape(&lin);
    let (b, l, q, w) = (
        flat(py, "base", &base)?,
        flat(py, "lin", &lin)?,
        flat(py, "nrm", &nrm)?,
        flat(py, "w", &w)?,
    );
    let v = run(py, "shaking_channels", || channels_kernel(b, l, q, w, sh))?;
    let arr = convert::shaped(py, 4, sh.n, v)?;
    Ok(arr.into_pyarray(py))
}
