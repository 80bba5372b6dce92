//! Bindings of the six-bar dwell kernel (`cyclomech_core::synthesis::dwell`): a
//! batch of candidate four-bars with coupler points evaluated in parallel, the
//! GIL released; and the circle fit.

use cyclomech_core::parallel::{pool, resolve_threads};
use cyclomech_core::synthesis::dwell::{self, Spec, FIELDS, PARAMS};
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;

use crate::convert;
use crate::errors::{input_error, run};

/// Rows (a, b, c, d, u, v, θm) → rows of `dwell_fields()` (see the core's docs).
#[pyfunction]
#[pyo3(signature = (params, sigma, span, swing, min_mu, max_ratio, n_dwell, n_turn, *, n_threads=None))]
#[allow(clippy::too_many_arguments)]
pub fn dwell_batch<'py>(
    py: Python<'py>,
    params: PyReadonlyArray2<'py, f64>,
    sigma: f64,
    span: f64,
    swing: f64,
    min_mu: f64,
    max_ratio: f64,
    n_dwell: usize,
    n_turn: usize,
    n_threads: Option<i64>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let shape = params.shape().to_vec();
    if shape[1] != PARAMS {
        return Err(input_error(
            py,
            format!(
                "params must have {PARAMS} columns (a, b, c, d, u, v, theta_mid); got {}",
                shape[1]
            ),
        ));
    }
    let flat = params
        .as_slice()
        .map_err(|_| input_error(py, "params must be C-contiguous".to_string()))?;
    let spec = Spec {
        span,
        swing,
        min_mu,
        max_ratio,
        n_dwell,
        n_turn,
    };
    let threads = run(py, "dwell_batch", || resolve_threads(n_threads))?;
    let pool = run(py, "dwell_batch", || pool(threads))?;
    let out = run(py, "dwell_batch", || {
        dwell::dwell_batch(flat, sigma, &spec, &pool)
    })?;
    Ok(convert::shaped(py, shape[0], FIELDS.len(), out)?.into_pyarray(py))
}

/// The names of `dwell_batch`'s columns.
#[pyfunction]
pub fn dwell_fields() -> Vec<&'static str> {
    FIELDS.to_vec()
}

/// The least-squares circle (centre x, centre y, radius) [m] through the points,
/// or None (fewer than three, collinear or non-finite points).
#[pyfunction]
pub fn fit_circle(points: Vec<(f64, f64)>) -> Option<(f64, f64, f64)> {
    let pts: Vec<[f64; 2]> = points.iter().map(|&(x, y)| [x, y]).collect();
    dwell::fit_circle(&pts).map(|c| (c.centre[0], c.centre[1], c.radius))
}
