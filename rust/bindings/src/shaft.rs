//! Bindings of the main shaft: the phase-shifted sum of torque curves and the
//! torque statistics, flywheel and motor at many speeds.

use cyclomech_core::shaft::{shifted_sum, stats_into, ShaftError, N_STATS};
use numpy::ndarray::Ix2;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;

use crate::convert::{self, LayoutError};
use crate::errors::run;

/// The sum over the rows of `curves` (M, N) [N·m] at the grid θ_k = 2πk/N,
/// each read at θ_k − `phase`[i] [rad] by periodic linear interpolation.
#[pyfunction]
pub fn shaft_sum<'py>(
    py: Python<'py>,
    curves: PyReadonlyArray2<'py, f64>,
    phase: PyReadonlyArray1<'py, f64>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let (c, _, n) = ShaftError::rows(py, "curves", &curves)?;
    let p = ShaftError::slice(py, "phase", &phase)?;
    let out = run(py, "shaft_sum", || shifted_sum(c, n, p))?;
    Ok(out.into_pyarray(py))
}

/// (S, 7) statistics of T = ω²·`a` + `b` at speeds `omegas` [rad/s] for the
/// coefficient of speed fluctuation `delta` (see `cyclomech.shaft`).
#[pyfunction]
#[pyo3(signature = (a, b, omegas, delta, *, n_threads=None))]
pub fn shaft_stats<'py>(
    py: Python<'py>,
    a: PyReadonlyArray1<'py, f64>,
    b: PyReadonlyArray1<'py, f64>,
    omegas: PyReadonlyArray1<'py, f64>,
    delta: f64,
    n_threads: Option<i64>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let (a, b) = (
        ShaftError::slice(py, "per_omega2", &a)?,
        ShaftError::slice(py, "static", &b)?,
    );
    let w = ShaftError::slice(py, "omegas", &omegas)?;
    let out = convert::zeros::<f64, Ix2>(
        py,
        &[w.len(), N_STATS],
        "shaft_stats",
        "ask for fewer speeds at a time",
    )?;
    {
        let mut rw = out.readwrite();
        let slice = convert::output(py, &mut rw)?;
        run(py, "shaft_stats", || {
            stats_into(a, b, w, delta, slice, n_threads)
        })?;
    }
    Ok(out)
}
