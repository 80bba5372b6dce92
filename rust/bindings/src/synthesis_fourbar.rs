//! Bindings of the four-bar's and slider-crank's checks
//! (`cyclomech_core::synthesis::fourbar`): the Grashof type, the transmission
//! angle's extremes over a crank range, the output angle and the slider's
//! position. Small scalar kernels: no GIL release needed.

use cyclomech_core::input::InvalidInput;
use cyclomech_core::synthesis::fourbar::{self, Transmission};
use pyo3::prelude::*;

use crate::errors::IntoPyErr;

/// (ok, x1, x2, x3, x4): (True, μ_min, μ_max, θ at μ_min, θ at μ_max) [rad] where
/// it assembles over the range, else (False, θ where it breaks, cos μ there, NaN, NaN).
type TransmissionTuple = (bool, f64, f64, f64, f64);

fn tuple(t: Transmission) -> TransmissionTuple {
    match t {
        Transmission::Range {
            mu_min,
            mu_max,
            theta_at_min,
            theta_at_max,
        } => (true, mu_min, mu_max, theta_at_min, theta_at_max),
        Transmission::Breaks { theta, cos_mu } => (false, theta, cos_mu, f64::NAN, f64::NAN),
    }
}

fn finite(py: Python<'_>, field: &'static str, v: &[f64]) -> PyResult<()> {
    InvalidInput::check_finite(field, v).map_err(|e| e.into_pyerr(py))
}

/// (kind name, crank turns fully, output turns fully) of the four-bar a, b, c, d [m].
#[pyfunction]
pub fn fourbar_grashof(
    py: Python<'_>,
    a: f64,
    b: f64,
    c: f64,
    d: f64,
) -> PyResult<(&'static str, bool, bool)> {
    let g = fourbar::grashof(a, b, c, d).map_err(|e| e.into_pyerr(py))?;
    Ok((g.kind.name(), g.crank_turns, g.output_turns))
}

/// The four-bar's transmission angle over the crank range [lo, hi] [rad].
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub fn fourbar_transmission(
    py: Python<'_>,
    a: f64,
    b: f64,
    c: f64,
    d: f64,
    lo: f64,
    hi: f64,
) -> PyResult<TransmissionTuple> {
    fourbar::fourbar_transmission(a, b, c, d, lo, hi)
        .map(tuple)
        .map_err(|e| e.into_pyerr(py))
}

/// The output angles θ4 [rad] at the crank angles `theta` [rad] on branch
/// `sigma` (±1); NaN where it does not assemble.
#[pyfunction]
pub fn fourbar_output_angle(
    py: Python<'_>,
    a: f64,
    b: f64,
    c: f64,
    d: f64,
    theta: Vec<f64>,
    sigma: f64,
) -> PyResult<Vec<f64>> {
    fourbar::grashof(a, b, c, d).map_err(|e| e.into_pyerr(py))?;
    finite(py, "theta", &theta)?;
    Ok(theta
        .iter()
        .map(|&t| fourbar::fourbar_output_angle(a, b, c, d, t, sigma).unwrap_or(f64::NAN))
        .collect())
}

/// The offset slider-crank's kind name (r, rod [m] > 0, offset e [m]).
#[pyfunction]
pub fn slider_crank_kind(py: Python<'_>, r: f64, rod: f64, e: f64) -> PyResult<&'static str> {
    fourbar::slider_crank_kind(r, rod, e)
        .map(|k| k.name())
        .map_err(|e| e.into_pyerr(py))
}

/// The slider-crank's transmission angle over the crank range [lo, hi] [rad].
#[pyfunction]
pub fn slider_crank_transmission(
    py: Python<'_>,
    r: f64,
    rod: f64,
    e: f64,
    lo: f64,
    hi: f64,
) -> PyResult<TransmissionTuple> {
    fourbar::slider_crank_transmission(r, rod, e, lo, hi)
        .map(tuple)
        .map_err(|e| e.into_pyerr(py))
}

/// The slider's pin x [m] at the crank angles `theta` [rad] on branch `sigma`
/// (±1); NaN where it does not assemble.
#[pyfunction]
pub fn slider_crank_position(
    py: Python<'_>,
    r: f64,
    rod: f64,
    e: f64,
    theta: Vec<f64>,
    sigma: f64,
) -> PyResult<Vec<f64>> {
    fourbar::slider_crank_kind(r, rod, e).map_err(|e| e.into_pyerr(py))?;
    finite(py, "theta", &theta)?;
    Ok(theta
        .iter()
        .map(|&t| fourbar::slider_crank_position(r, rod, e, t, sigma).unwrap_or(f64::NAN))
        .collect())
}
