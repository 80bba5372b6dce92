//! Bindings of the main shaft's forward dynamics (issue 34): the periodic steady
//! state of one design or a batch, and the start-up from rest.
//!
//! Motors come as arrays, one entry per design: `kinds` (0 constant torque,
//! 1 linear, 2 Kloss, 3 table), `params` (D, 3) (the torque; stall torque and
//! no-load speed; breakdown torque, synchronous speed and critical slip; unused
//! for a table), gear `ratio` and `efficiency`, and the tables concatenated in
//! `table_speed` / `table_torque` with design d's rows at
//! `table_offsets[d]..table_offsets[d + 1]`. Speeds on the motor's side [rad/s].

use cyclomech_core::dynamics::{
    start_up, steady_batch, steady_state, Characteristic, Curves, DriveError, Motor,
    StartUpOptions, SteadyOptions, STEADY_COLUMNS,
};
use cyclomech_core::input::InvalidInput;
use numpy::ndarray::Ix2;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;

use crate::convert::{self, LayoutError};
use crate::errors::{input_error, run, IntoPyErr};

impl IntoPyErr for DriveError {
    fn into_pyerr(self, py: Python<'_>) -> PyErr {
        match self {
            DriveError::Input(e) => e.into_pyerr(py),
        }
    }
}

impl LayoutError for DriveError {
    fn layout(field: &'static str) -> Self {
        InvalidInput::bad_value(field, f64::NAN, "must be a C-contiguous array").into()
    }
}

/// The motors of the arrays described in the module's docs.
#[allow(clippy::too_many_arguments)]
pub(crate) fn motors(
    py: Python<'_>,
    kinds: &PyReadonlyArray1<'_, i64>,
    params: &PyReadonlyArray2<'_, f64>,
    ratio: &PyReadonlyArray1<'_, f64>,
    efficiency: &PyReadonlyArray1<'_, f64>,
    offsets: &PyReadonlyArray1<'_, i64>,
    tspeed: &PyReadonlyArray1<'_, f64>,
    ttorque: &PyReadonlyArray1<'_, f64>,
) -> PyResult<Vec<Motor>> {
    let k = DriveError::slice(py, "kinds", kinds)?;
    let (p, _, width) = DriveError::rows(py, "params", params)?;
    let r = DriveError::slice(py, "ratio", ratio)?;
    let e = DriveError::slice(py, "efficiency", efficiency)?;
    let o = DriveError::slice(py, "table_offsets", offsets)?;
    let (ts, tt) = (
        DriveError::slice(py, "table_speed", tspeed)?,
        DriveError::slice(py, "table_torque", ttorque)?,
    );
    let d = k.len();
    if width != 3 || p.len() != 3 * d || r.len() != d || e.len() != d || o.len() != d + 1 {
        return Err(input_error(
            py,
            format!("motor arrays: need kinds (D,), params (D, 3), ratio, efficiency (D,) and table_offsets (D + 1,); D = {d}"),
        ));
    }
    if ts.len() != tt.len() {
        return Err(input_error(
            py,
            "table_speed and table_torque must have the same length".into(),
        ));
    }
    let mut out = Vec::with_capacity(d);
    for i in 0..d {
        let q = &p[3 * i..3 * i + 3];
        let characteristic = match k[i] {
            0 => Characteristic::Constant { torque: q[0] },
            1 => Characteristic::Linear {
                stall: q[0],
                no_load: q[1],
            },
            2 => Characteristic::Kloss {
                breakdown: q[0],
                synchronous: q[1],
                critical_slip: q[2],
            },
            3 => {
                let (a, b) = (o[i], o[i + 1]);
                if a < 0 || b < a || b as usize > ts.len() {
                    return Err(input_error(
                        py,
                        format!(
                            "table_offsets[{i}..{}] = {a}..{b} outside the tables ({})",
                            i + 1,
                            ts.len()
                        ),
                    ));
                }
                let (a, b) = (a as usize, b as usize);
                Characteristic::Table {
                    speed: ts[a..b].to_vec(),
                    torque: tt[a..b].to_vec(),
                }
            }
            other => {
                return Err(input_error(py, format!("kinds[{i}] = {other} must be 0 (constant), 1 (linear), 2 (Kloss) or 3 (table)")));
            }
        };
        out.push(Motor {
            characteristic,
            ratio: r[i],
            efficiency: e[i],
        });
    }
    Ok(out)
}

/// The steady state of one design (the first motor): (row of
/// `DYNAMICS_STEADY_COLUMNS`, ω [rad/s], t [s], motor torque [N·m] at each sample;
/// the arrays empty when not periodic).
#[pyfunction]
#[pyo3(signature = (j, dj, q, extra, kinds, params, ratio, efficiency, table_offsets, table_speed, table_torque, *, tol, max_iter, omega_start))]
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
pub fn dynamics_steady<'py>(
    py: Python<'py>,
    j: PyReadonlyArray1<'py, f64>,
    dj: PyReadonlyArray1<'py, f64>,
    q: PyReadonlyArray1<'py, f64>,
    extra: f64,
    kinds: PyReadonlyArray1<'py, i64>,
    params: PyReadonlyArray2<'py, f64>,
    ratio: PyReadonlyArray1<'py, f64>,
    efficiency: PyReadonlyArray1<'py, f64>,
    table_offsets: PyReadonlyArray1<'py, i64>,
    table_speed: PyReadonlyArray1<'py, f64>,
    table_torque: PyReadonlyArray1<'py, f64>,
    tol: f64,
    max_iter: usize,
    omega_start: f64,
) -> PyResult<(
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
)> {
    let c = Curves {
        j: DriveError::slice(py, "inertia", &j)?,
        dj: DriveError::slice(py, "d_inertia", &dj)?,
        q: DriveError::slice(py, "load_torque", &q)?,
    };
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
    let Some(motor) = m.into_iter().next() else {
        return Err(input_error(py, "dynamics_steady needs one motor".into()));
    };
    let opt = SteadyOptions {
        tol,
        max_iter,
        omega_start,
    };
    let s = run(py, "dynamics_steady", || {
        steady_state(&c, extra, &motor, &opt, true)
    })?;
    Ok((
        s.row.to_vec().into_pyarray(py),
        s.omega.into_pyarray(py),
        s.time.into_pyarray(py),
        s.motor_torque.into_pyarray(py),
    ))
}

/// (D, 12) rows of `DYNAMICS_STEADY_COLUMNS`: design d adds `extra[d]` [kg·m²]
/// and runs on motor d; in parallel.
#[pyfunction]
#[pyo3(signature = (j, dj, q, extra, kinds, params, ratio, efficiency, table_offsets, table_speed, table_torque, *, tol, max_iter, omega_start, n_threads=None))]
#[allow(clippy::too_many_arguments)]
pub fn dynamics_steady_batch<'py>(
    py: Python<'py>,
    j: PyReadonlyArray1<'py, f64>,
    dj: PyReadonlyArray1<'py, f64>,
    q: PyReadonlyArray1<'py, f64>,
    extra: PyReadonlyArray1<'py, f64>,
    kinds: PyReadonlyArray1<'py, i64>,
    params: PyReadonlyArray2<'py, f64>,
    ratio: PyReadonlyArray1<'py, f64>,
    efficiency: PyReadonlyArray1<'py, f64>,
    table_offsets: PyReadonlyArray1<'py, i64>,
    table_speed: PyReadonlyArray1<'py, f64>,
    table_torque: PyReadonlyArray1<'py, f64>,
    tol: f64,
    max_iter: usize,
    omega_start: f64,
    n_threads: Option<i64>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let c = Curves {
        j: DriveError::slice(py, "inertia", &j)?,
        dj: DriveError::slice(py, "d_inertia", &dj)?,
        q: DriveError::slice(py, "load_torque", &q)?,
    };
    let e = DriveError::slice(py, "flywheel", &extra)?;
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
    let opt = SteadyOptions {
        tol,
        max_iter,
        omega_start,
    };
    let cols = STEADY_COLUMNS.len();
    let out = convert::zeros::<f64, Ix2>(
        py,
        &[m.len(), cols],
        "dynamics_steady_batch",
        "ask for fewer designs at a time",
    )?;
    {
        let mut rw = out.readwrite();
        let slice = convert::output(py, &mut rw)?;
        run(py, "dynamics_steady_batch", || {
            steady_batch(&c, e, &m, &opt, slice, n_threads)
        })?;
    }
    Ok(out)
}

/// The start-up from rest of one design (the first motor) towards the steady ω
/// `steady` at the samples: (status 0 settled / 1 limit / 2 cannot start, the
/// settle time [s], t [s], φ [rad], ω [rad/s], motor torque [N·m] at each step).
#[pyfunction]
#[pyo3(signature = (j, dj, q, extra, kinds, params, ratio, efficiency, table_offsets, table_speed, table_torque, steady, *, rtol, settle, t_max, max_steps))]
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
pub fn dynamics_start_up<'py>(
    py: Python<'py>,
    j: PyReadonlyArray1<'py, f64>,
    dj: PyReadonlyArray1<'py, f64>,
    q: PyReadonlyArray1<'py, f64>,
    extra: f64,
    kinds: PyReadonlyArray1<'py, i64>,
    params: PyReadonlyArray2<'py, f64>,
    ratio: PyReadonlyArray1<'py, f64>,
    efficiency: PyReadonlyArray1<'py, f64>,
    table_offsets: PyReadonlyArray1<'py, i64>,
    table_speed: PyReadonlyArray1<'py, f64>,
    table_torque: PyReadonlyArray1<'py, f64>,
    steady: PyReadonlyArray1<'py, f64>,
    rtol: f64,
    settle: f64,
    t_max: f64,
    max_steps: usize,
) -> PyResult<(
    u8,
    f64,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
)> {
    let c = Curves {
        j: DriveError::slice(py, "inertia", &j)?,
        dj: DriveError::slice(py, "d_inertia", &dj)?,
        q: DriveError::slice(py, "load_torque", &q)?,
    };
    let w = DriveError::slice(py, "steady", &steady)?;
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
    let Some(motor) = m.into_iter().next() else {
        return Err(input_error(py, "dynamics_start_up needs one motor".into()));
    };
    let opt = StartUpOptions {
        rtol,
        settle,
        t_max,
        max_steps,
    };
    let s = run(py, "dynamics_start_up", || {
        start_up(&c, extra, &motor, w, &opt)
    })?;
    Ok((
        s.status,
        s.settle_time,
        s.t.into_pyarray(py),
        s.phi.into_pyarray(py),
        s.omega.into_pyarray(py),
        s.motor_torque.into_pyarray(py),
    ))
}
