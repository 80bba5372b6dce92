//! Bindings of motion generation (`cyclomech_core::synthesis::motion`, three
//! poses; `cyclomech_core::synthesis::burmester`, four and five poses). Small
//! kernels, except the five-pose trace, which runs with the GIL released.

use cyclomech_core::synthesis::burmester;
use cyclomech_core::synthesis::fourbar::Transmission;
use cyclomech_core::synthesis::motion::{self, MotionError, MotionFourBar, Pose};
use pyo3::prelude::*;

use crate::errors::{input_error, run, IntoPyErr};

type P = (f64, f64);

/// A Burmester point: (circle point, centre, radius, residual).
type PointRow = (P, P, f64, f64);

/// (A0, B0, A positions (n), B positions (n), lengths (a, b, c, d), crank angles
/// (n) [rad], direction (±1), branches (n), arc (lo, hi) [rad], transmission
/// (ok, μ_min, μ_max, θ at μ_min, θ at μ_max) or (False, θ break, cos μ, NaN, NaN),
/// in order (the crank meets the poses in their order)).
type MotionTuple = (
    P,
    P,
    Vec<P>,
    Vec<P>,
    (f64, f64, f64, f64),
    Vec<f64>,
    f64,
    Vec<f64>,
    P,
    (bool, f64, f64, f64, f64),
    bool,
);

impl IntoPyErr for MotionError {
    fn into_pyerr(self, py: Python<'_>) -> PyErr {
        match self {
            MotionError::Input(e) => e.into_pyerr(py),
            other => input_error(py, other.to_string()),
        }
    }
}

fn pt(p: [f64; 2]) -> P {
    (p[0], p[1])
}

fn tuple(m: MotionFourBar) -> MotionTuple {
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
    (
        pt(m.crank.centre),
        pt(m.rocker.centre),
        m.crank.circle.into_iter().map(pt).collect(),
        m.rocker.circle.into_iter().map(pt).collect(),
        (a, b, c, d),
        m.crank_angles,
        m.direction,
        m.branches,
        m.arc,
        t,
        m.in_order,
    )
}

fn poses_of(poses: &[(f64, f64, f64)]) -> Vec<Pose> {
    poses.iter().map(|&(x, y, t)| [x, y, t]).collect()
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
    let m = motion::motion_fourbar(&poses, [uv1.0, uv1.1], [uv2.0, uv2.1])
        .map_err(|e| e.into_pyerr(py))?;
    Ok(tuple(m))
}

/// Four-bars of pairs of dyads through n poses: `dyads` are (circle point (u, v)
/// [m, coupler frame], centre (x, y) [m]); `pairs` (crank, rocker) index them.
/// Each pair gives (tuple, None) or (None, the reason it gives no four-bar).
#[pyfunction]
pub fn motion_fourbars(
    py: Python<'_>,
    poses: Vec<(f64, f64, f64)>,
    dyads: Vec<(P, P)>,
    pairs: Vec<(usize, usize)>,
) -> PyResult<Vec<(Option<MotionTuple>, Option<String>)>> {
    let poses = poses_of(&poses);
    run(py, "motion_fourbars", move || {
        let mut out = Vec::with_capacity(pairs.len());
        for (i, j) in pairs {
            let (Some(&d1), Some(&d2)) = (dyads.get(i), dyads.get(j)) else {
                return Err(MotionError::Input(
                    cyclomech_core::input::InvalidInput::bad_value(
                        "pairs",
                        i.max(j) as f64,
                        format!("must index the {} dyads", dyads.len()),
                    ),
                ));
            };
            let m = motion::dyad_through(&poses, [d1.0 .0, d1.0 .1], [d1.1 .0, d1.1 .1], 1)
                .and_then(|a| {
                    let b =
                        motion::dyad_through(&poses, [d2.0 .0, d2.0 .1], [d2.1 .0, d2.1 .1], 2)?;
                    motion::fourbar_of_dyads(&poses, a, b)
                });
            out.push(match m {
                Ok(m) => (Some(tuple(m)), None),
                Err(MotionError::Input(e)) => return Err(MotionError::Input(e)),
                Err(e) => (None, Some(e.to_string())),
            });
        }
        Ok(out)
    })
}

/// Burmester's curves of four poses (x [m], y [m], θ [rad]) sampled at
/// `samples` parameter values per branch: (the parameter's pose index from 1,
/// rows (β [rad], σ, u, v, x, y) with a NaN row between polylines).
#[pyfunction]
pub fn burmester_curves(
    py: Python<'_>,
    poses: Vec<(f64, f64, f64)>,
    samples: usize,
) -> PyResult<(usize, Vec<[f64; 6]>)> {
    let poses = poses_of(&poses);
    run(py, "burmester_curves", move || {
        let c = burmester::burmester_curves(&poses, samples)?;
        let mut rows = Vec::new();
        for (k, br) in c.branches.iter().enumerate() {
            if k > 0 {
                rows.push([f64::NAN; 6]);
            }
            rows.extend(br.iter().map(|p| {
                [
                    p.beta,
                    p.sigma,
                    p.circle[0],
                    p.circle[1],
                    p.centre[0],
                    p.centre[1],
                ]
            }));
        }
        Ok::<_, MotionError>((c.parameter_pose, rows))
    })
}

/// The dyad of four poses at crank rotation `beta` [rad] on branch `sigma`:
/// (circle point (u, v), centre (x, y)) [m], or None.
#[pyfunction]
pub fn burmester_dyad(
    py: Python<'_>,
    poses: Vec<(f64, f64, f64)>,
    beta: f64,
    sigma: f64,
) -> PyResult<Option<(P, P)>> {
    let poses = poses_of(&poses);
    let d = burmester::burmester_dyad(&poses, beta, sigma).map_err(|e| e.into_pyerr(py))?;
    Ok(d.map(|(a, c)| (pt(a), pt(c))))
}

/// The circle-point cubic of four poses at circle point `uv` (normalised; zero
/// on the curve).
#[pyfunction]
pub fn burmester_det(py: Python<'_>, poses: [(f64, f64, f64); 4], uv: P) -> PyResult<f64> {
    let poses = poses.map(|(x, y, t)| [x, y, t]);
    burmester::circle_point_det(&poses, [uv.0, uv.1]).map_err(|e| e.into_pyerr(py))
}

/// Burmester's points of five poses: (rows (circle point (u, v), centre (x, y),
/// radius, residual) [m], whether their count is even).
#[pyfunction]
pub fn burmester_points(
    py: Python<'_>,
    poses: Vec<(f64, f64, f64)>,
) -> PyResult<(Vec<PointRow>, bool)> {
    let poses = poses_of(&poses);
    run(py, "burmester_points", move || {
        let b = burmester::burmester_points(&poses)?;
        let rows = b
            .points
            .iter()
            .map(|p| (pt(p.circle), pt(p.centre), p.radius, p.residual))
            .collect();
        Ok::<_, MotionError>((rows, b.parity_ok))
    })
}
