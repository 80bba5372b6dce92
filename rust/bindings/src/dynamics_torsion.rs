//! Bindings of the main shaft's torsion and the working members' dynamic errors
//! (issue 34 item 3): one steady state, with a motor or at a constant speed, and
//! a sweep of constant speeds.
//!
//! The chain comes as three arrays: `curves` (3n, N), the rows J₁…J_n, J′₁…J′_n,
//! Q₁…Q_n on the N main-shaft angles; `nodes` (n, 6), each node's hub inertia,
//! stiffness and damping of the segment before it, its member's number of
//! coordinates (0: none), the link's ω_n [rad/s] (inf: rigid) and ζ; and
//! `members` (3R, N), the R member coordinates' Π rows, then Π′, then Π″.

use cyclomech_core::dynamics::{
    torsion, torsion_sweep, DriveError, Head, Member, Node, TorsionOptions, SWEEP_COLUMNS,
};
use numpy::ndarray::Ix2;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;

use crate::convert::{self, LayoutError};
use crate::dynamics_shaft::motors;
use crate::errors::{input_error, run};

/// The nodes of the arrays described in the module's docs.
fn chain<'a>(
    py: Python<'_>,
    curves: &'a [f64],
    rows: usize,
    samples: usize,
    nodes: &'a [f64],
    members: &'a [f64],
    member_rows: usize,
) -> PyResult<Vec<Node<'a>>> {
    let n = nodes.len() / 6;
    if nodes.len() != 6 * n || rows != 3 * n || n == 0 {
        return Err(input_error(
            py,
            format!("torsion: need nodes (n, 6) with n >= 1 and curves (3n, N); got {} node values and {rows} curve rows", nodes.len()),
        ));
    }
    let comps: Vec<usize> = (0..n).map(|k| nodes[6 * k + 3] as usize).collect();
    let r: usize = comps.iter().sum();
    if member_rows != 3 * r || members.len() != 3 * r * samples {
        return Err(input_error(
            py,
            format!("torsion: the members have {r} coordinates: members must be ({}, {samples}); got {member_rows} rows", 3 * r),
        ));
    }
    let row = |k: usize| &curves[k * samples..(k + 1) * samples];
    let block = r * samples;
    let mut at = 0;
    let mut out = Vec::with_capacity(n);
    for k in 0..n {
        let p = &nodes[6 * k..6 * k + 6];
        let c = comps[k];
        let member = (c > 0).then(|| {
            let span = at * samples..(at + c) * samples;
            Member {
                pos: &members[span.clone()],
                d1: &members[block + span.start..block + span.end],
                d2: &members[2 * block + span.start..2 * block + span.end],
                components: c,
                omega_n: p[4],
                zeta: p[5],
            }
        });
        at += c;
        out.push(Node {
            j: row(k),
            dj: row(n + k),
            q: row(2 * n + k),
            hub: p[0],
            stiffness: p[1],
            damping: p[2],
            member,
        });
    }
    Ok(out)
}

/// The steady state of one chain: with `speed` > 0 the head turns at that constant
/// speed [rad/s]; with `speed` NaN the (one) motor of the arrays drives the head's
/// `head_inertia` [kg·m²] from `omega_start` [rad/s]. Returns ([status, cycles,
/// residual, steps], ω, t, twist (n, N), segment torque (n, N), error (R, N),
/// peak error (n,)).
#[pyfunction]
#[pyo3(signature = (curves, nodes, members, speed, kinds, params, ratio, efficiency, table_offsets, table_speed, table_torque, head_inertia, omega_start, *, tol, max_cycles, accuracy))]
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
pub fn dynamics_torsion<'py>(
    py: Python<'py>,
    curves: PyReadonlyArray2<'py, f64>,
    nodes: PyReadonlyArray2<'py, f64>,
    members: PyReadonlyArray2<'py, f64>,
    speed: f64,
    kinds: PyReadonlyArray1<'py, i64>,
    params: PyReadonlyArray2<'py, f64>,
    ratio: PyReadonlyArray1<'py, f64>,
    efficiency: PyReadonlyArray1<'py, f64>,
    table_offsets: PyReadonlyArray1<'py, i64>,
    table_speed: PyReadonlyArray1<'py, f64>,
    table_torque: PyReadonlyArray1<'py, f64>,
    head_inertia: f64,
    omega_start: f64,
    tol: f64,
    max_cycles: usize,
    accuracy: f64,
) -> PyResult<(
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray1<f64>>,
)> {
    let (cv, rows, samples) = DriveError::rows(py, "curves", &curves)?;
    let (nd, _, _) = DriveError::rows(py, "nodes", &nodes)?;
    let (mb, mrows, _) = DriveError::rows(py, "members", &members)?;
    let chain = chain(py, cv, rows, samples, nd, mb, mrows)?;
    let m = motors(
        py,
        &kinds,
        &params,
        &ratio,
        &efficiency,
        &table_offsets,
        &table_speed,
        &table_torque,
    )?;
    let head = if speed.is_nan() {
        let Some(motor) = m.first() else {
            return Err(input_error(
                py,
                "dynamics_torsion: no speed and no motor".into(),
            ));
        };
        Head::Motor {
            motor,
            inertia: head_inertia,
            omega: omega_start,
        }
    } else {
        Head::Speed(speed)
    };
    let opt = TorsionOptions {
        tol,
        max_cycles,
        accuracy,
    };
    let t = run(py, "dynamics_torsion", || torsion(&chain, head, &opt))?;
    let n = chain.len();
    let r = t.error.len() / samples.max(1);
    let meta = vec![t.status as f64, t.cycles as f64, t.residual, t.steps as f64];
    Ok((
        meta.into_pyarray(py),
        t.omega.into_pyarray(py),
        t.time.into_pyarray(py),
        convert::shaped(py, n, samples, t.twist)?.into_pyarray(py),
        convert::shaped(py, n, samples, t.torque)?.into_pyarray(py),
        convert::shaped(py, r, samples, t.error)?.into_pyarray(py),
        t.peak.into_pyarray(py),
    ))
}

/// (S, 3 + 2n) rows: status, cycles, residual, the n peak errors and the n
/// largest |twists| [rad] at each constant head speed of `speeds` [rad/s]; in
/// parallel.
#[pyfunction]
#[pyo3(signature = (curves, nodes, members, speeds, *, tol, max_cycles, accuracy, n_threads=None))]
#[allow(clippy::too_many_arguments)]
pub fn dynamics_torsion_sweep<'py>(
    py: Python<'py>,
    curves: PyReadonlyArray2<'py, f64>,
    nodes: PyReadonlyArray2<'py, f64>,
    members: PyReadonlyArray2<'py, f64>,
    speeds: PyReadonlyArray1<'py, f64>,
    tol: f64,
    max_cycles: usize,
    accuracy: f64,
    n_threads: Option<i64>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let (cv, rows, samples) = DriveError::rows(py, "curves", &curves)?;
    let (nd, _, _) = DriveError::rows(py, "nodes", &nodes)?;
    let (mb, mrows, _) = DriveError::rows(py, "members", &members)?;
    let chain = chain(py, cv, rows, samples, nd, mb, mrows)?;
    let w = DriveError::slice(py, "speeds", &speeds)?;
    let opt = TorsionOptions {
        tol,
        max_cycles,
        accuracy,
    };
    let cols = SWEEP_COLUMNS.len() + 2 * chain.len();
    let out = convert::zeros::<f64, Ix2>(
        py,
        &[w.len(), cols],
        "dynamics_torsion_sweep",
        "ask for fewer speeds at a time",
    )?;
    {
        let mut rw = out.readwrite();
        let slice = convert::output(py, &mut rw)?;
        run(py, "dynamics_torsion_sweep", || {
            torsion_sweep(&chain, w, &opt, slice, n_threads)
        })?;
    }
    Ok(out)
}
