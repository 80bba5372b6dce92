//! Bindings of function generation (`cyclomech_core::synthesis::function`):
//! the Freudenstein fit (and the slider-crank's), the branch at each precision
//! point, the structural error on a grid and the Chebyshev spacing. Small
//! kernels: no GIL release needed.

use cyclomech_core::synthesis::function::{self, FunctionError, FunctionFit, Generator};
use pyo3::prelude::*;

use crate::errors::{input_error, IntoPyErr};

/// (K1, K2, K3), dims (4), flip_in, flip_out of a fit.
type FitTuple = ((f64, f64, f64), (f64, f64, f64, f64), bool, bool);

fn err(py: Python<'_>, e: FunctionError) -> PyErr {
    match e {
        FunctionError::Input(e) => e.into_pyerr(py),
        other => input_error(py, other.to_string()),
    }
}

fn generator(py: Python<'_>, kind: &str) -> PyResult<Generator> {
    match kind {
        "four-bar" => Ok(Generator::FourBar),
        "slider-crank" => Ok(Generator::SliderCrank),
        other => Err(input_error(
            py,
            format!("kind must be 'four-bar' or 'slider-crank'; got {other:?}"),
        )),
    }
}

fn fit(dims: (f64, f64, f64, f64), flip_in: bool, flip_out: bool) -> FunctionFit {
    FunctionFit {
        k: [f64::NAN; 3],
        dims: [dims.0, dims.1, dims.2, dims.3],
        flip_in,
        flip_out,
    }
}

/// n Chebyshev points over [lo, hi], ascending.
#[pyfunction]
pub fn chebyshev_points(py: Python<'_>, lo: f64, hi: f64, n: usize) -> PyResult<Vec<f64>> {
    function::chebyshev_points(lo, hi, n).map_err(|e| e.into_pyerr(py))
}

/// The fit through the precision points (x [rad], y [rad or m]).
#[pyfunction]
pub fn function_fit(
    py: Python<'_>,
    kind: &str,
    x: Vec<f64>,
    y: Vec<f64>,
    ground: f64,
) -> PyResult<FitTuple> {
    let g = generator(py, kind)?;
    let f = function::function_fit(g, &x, &y, ground).map_err(|e| err(py, e))?;
    let [k1, k2, k3] = f.k;
    let [a, b, c, d] = f.dims;
    Ok(((k1, k2, k3), (a, b, c, d), f.flip_in, f.flip_out))
}

/// The branch (±1, 0 where neither assembles) at each precision point.
#[pyfunction]
pub fn function_branches(
    py: Python<'_>,
    kind: &str,
    dims: (f64, f64, f64, f64),
    flip_in: bool,
    flip_out: bool,
    x: Vec<f64>,
    y: Vec<f64>,
) -> PyResult<Vec<f64>> {
    let g = generator(py, kind)?;
    Ok(function::branches(g, &fit(dims, flip_in, flip_out), &x, &y))
}

/// (largest |generated − wanted|, its grid index) on branch `sigma`; +inf at the
/// first grid angle where it does not assemble.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub fn function_error(
    py: Python<'_>,
    kind: &str,
    dims: (f64, f64, f64, f64),
    flip_in: bool,
    flip_out: bool,
    sigma: f64,
    grid: Vec<f64>,
    wanted: Vec<f64>,
) -> PyResult<(f64, usize)> {
    let g = generator(py, kind)?;
    function::structural_error(g, &fit(dims, flip_in, flip_out), sigma, &grid, &wanted)
        .map_err(|e| err(py, e))
}

/// The generated outputs at the input angles `x` [rad] on branch `sigma`
/// (four-bar ψ [rad] wrapped near `near`, slider s [m]); NaN where it does not
/// assemble.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub fn function_generated(
    py: Python<'_>,
    kind: &str,
    dims: (f64, f64, f64, f64),
    flip_in: bool,
    flip_out: bool,
    sigma: f64,
    x: Vec<f64>,
    near: f64,
) -> PyResult<Vec<f64>> {
    let g = generator(py, kind)?;
    let f = fit(dims, flip_in, flip_out);
    Ok(x.iter()
        .map(|&t| function::generated(g, &f, t, sigma, near).unwrap_or(f64::NAN))
        .collect())
}
