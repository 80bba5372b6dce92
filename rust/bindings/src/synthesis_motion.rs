//! Bindings of three-position motion generation
//! (`cyclomech_core::synthesis::motion`). A small kernel: no GIL release needed.

use cyclomech_core::synthesis::fourbar::Transmission;
use cyclomech_core::synthesis::motion::{self, MotionError};
use pyo3::prelude::*;

use crate::errors::{input_error, IntoPyErr};

type P = (f64, f64);

/// (A0, B0, A positions (3), B positions (3), lengths (a, b, c, d), crank angles
/// (3) [rad], direction (±1), branches (3), arc (lo, hi) [rad], transmission
/// (ok, μ_min, μ_max, θ at μ_min, θ at μ_max) or (False, θ break, cos μ, NaN, NaN)).
type MotionTuple = (
    P,
    P,
    [P; 3],
    [P; 3],
    (f64, f64, f64, f64),
    [f64; 3],
    f64,
    [f64; 3],
    P,
    (bool, f64, f64, f64, f64),
);

fn err(py: Python<'_>, e: MotionError) -> PyErr {
    match e {
        MotionError::Input(e) => e.into_pyerr(py),
        other => input_error(py, other.to_string()),
    }
}

/// The four-bar of circle points `uv1` (crank) and `uv2` (rocker) [m, coupler
/// frame] through three poses (x [m], y [m], θ [rad]).
#[pyfunction]
pub fn motion_fourbar(
    py: Python<'_>,
    poses: [(f64, f64, f64); 3],
    uv1: P,
    uv2: P,
) -> PyResult<MotionTuple> {
    let poses = poses.map(|(x, y, t)| [x, y, t]);
    let m =
        motion::motion_fourbar(&poses, [uv1.0, uv1.1], [uv2.0, uv2.1]).map_err(|e| err(py, e))?;
    let pt = |p: [f64; 2]| (p[0], p[1]);
    let t = match m.transmission {
        Transmission::Range {
            mu_min,
            mu_max,
            theta_at_min,
            theta_at_max,
        } => (true, mu_min, mu_max, theta_at_min, theta_at_max),
        Transmission::Breaks { theta, cos_mu } => (false, theta, cos_mu, f64::NAN, f64::NAN),
    };
    let [a, b, c, d] = m.lengths;
    Ok((
        pt(m.crank.centre),
        pt(m.rocker.centre),
        m.crank.circle.map(pt),
        m.rocker.circle.map(pt),
        (a, b, c, d),
        m.crank_angles,
        m.direction,
        m.branches,
        m.arc,
        t,
    ))
}
