//! Bindings of the servo axes: one motor and ratio at many speeds, and the
//! sizing batch over motors × ratios × speeds (see `cyclomech.servo`).

use cyclomech_core::servo::{duty_into, size_into, Load, Motors, ServoError, N_CHECKS, N_DUTY};
use numpy::ndarray::{Ix2, Ix3};
use numpy::{PyArray2, PyArray3, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;

use crate::convert::{self, LayoutError};
use crate::errors::run;

/// `servo_duty`'s result: the statistics per speed and the torque curves.
type DutyArrays<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>);

/// `servo_size`'s result: the smallest margins and the speeds where they are.
type SizeArrays<'py> = (Bound<'py, PyArray3<f64>>, Bound<'py, PyArray3<i64>>);

/// (S, 4) duty statistics (peak |T_m| [N·m], RMS T_m [N·m], peak |ω_m| [rad/s],
/// regenerated energy per cycle [J]) of the load `vel`, `acc` (φ_L′, φ_L″ at N
/// uniform master angles) with inertia `inertia` [kg·m²], torque `torque` [N·m]
/// and drive efficiency `efficiency`, through `ratio` with `drive_inertia` =
/// J_motor + J_gear [kg·m²], at master speeds `omegas` [rad/s]; and T_m at every
/// angle, (S, N) if `curves` else (0, N) [N·m].
#[pyfunction]
#[pyo3(signature = (vel, acc, inertia, torque, efficiency, ratio, drive_inertia, omegas, *, curves=false, n_threads=None))]
#[allow(clippy::too_many_arguments)]
pub fn servo_duty<'py>(
    py: Python<'py>,
    vel: PyReadonlyArray1<'py, f64>,
    acc: PyReadonlyArray1<'py, f64>,
    inertia: f64,
    torque: f64,
    efficiency: f64,
    ratio: f64,
    drive_inertia: f64,
    omegas: PyReadonlyArray1<'py, f64>,
    curves: bool,
    n_threads: Option<i64>,
) -> PyResult<DutyArrays<'py>> {
    let load = Load {
        vel: ServoError::slice(py, "vel", &vel)?,
        acc: ServoError::slice(py, "acc", &acc)?,
        inertia,
        torque,
        efficiency,
    };
    let w = ServoError::slice(py, "omegas", &omegas)?;
    let hint = "ask for fewer speeds at a time";
    let stats = convert::zeros::<f64, Ix2>(py, &[w.len(), N_DUTY], "servo_duty", hint)?;
    let rows = if curves { w.len() } else { 0 };
    let torques =
        convert::zeros::<f64, Ix2>(py, &[rows, load.vel.len()], "servo_duty curves", hint)?;
    {
        let mut s = stats.readwrite();
        let mut t = torques.readwrite();
        let s = convert::output(py, &mut s)?;
        let t = convert::output(py, &mut t)?;
        let t = curves.then_some(t);
        run(py, "servo_duty", || {
            duty_into(&load, ratio, drive_inertia, w, s, t, n_threads)
        })?;
    }
    Ok((stats, torques))
}

/// For every motor × ratio (M, R, 4) the smallest margin of each check (peak
/// torque, RMS torque, speed, inertia ratio) over the master speeds `omegas`
/// [rad/s], and (M, R, 4) the index of the speed where it is smallest. The load
/// as in `servo_duty`; the motors' rotor inertia [kg·m²], peak and rated torque
/// [N·m] and maximum speed [rad/s]; `gear_inertia` [kg·m²]; the inertia ratio's
/// limit `inertia_limit`.
#[pyfunction]
#[pyo3(signature = (vel, acc, inertia, torque, efficiency, ratios, gear_inertia, motor_inertia, peak_torque, rated_torque, max_speed, omegas, inertia_limit, *, n_threads=None))]
#[allow(clippy::too_many_arguments)]
pub fn servo_size<'py>(
    py: Python<'py>,
    vel: PyReadonlyArray1<'py, f64>,
    acc: PyReadonlyArray1<'py, f64>,
    inertia: f64,
    torque: f64,
    efficiency: f64,
    ratios: PyReadonlyArray1<'py, f64>,
    gear_inertia: f64,
    motor_inertia: PyReadonlyArray1<'py, f64>,
    peak_torque: PyReadonlyArray1<'py, f64>,
    rated_torque: PyReadonlyArray1<'py, f64>,
    max_speed: PyReadonlyArray1<'py, f64>,
    omegas: PyReadonlyArray1<'py, f64>,
    inertia_limit: f64,
    n_threads: Option<i64>,
) -> PyResult<SizeArrays<'py>> {
    let load = Load {
        vel: ServoError::slice(py, "vel", &vel)?,
        acc: ServoError::slice(py, "acc", &acc)?,
        inertia,
        torque,
        efficiency,
    };
    let motors = Motors {
        inertia: ServoError::slice(py, "motor_inertia", &motor_inertia)?,
        peak_torque: ServoError::slice(py, "peak_torque", &peak_torque)?,
        rated_torque: ServoError::slice(py, "rated_torque", &rated_torque)?,
        max_speed: ServoError::slice(py, "max_speed", &max_speed)?,
    };
    let r = ServoError::slice(py, "ratios", &ratios)?;
    let w = ServoError::slice(py, "omegas", &omegas)?;
    let shape = [motors.inertia.len(), r.len(), N_CHECKS];
    let hint = "size fewer motors or ratios at a time";
    let margins = convert::zeros::<f64, Ix3>(py, &shape, "servo_size", hint)?;
    let worst = convert::zeros::<i64, Ix3>(py, &shape, "servo_size", hint)?;
    {
        let mut m = margins.readwrite();
        let mut s = worst.readwrite();
        let m = convert::output(py, &mut m)?;
        let s = convert::output(py, &mut s)?;
        run(py, "servo_size", || {
            size_into(
                &load,
                r,
                gear_inertia,
                &motors,
                w,
                inertia_limit,
                m,
                s,
                n_threads,
            )
        })?;
    }
    Ok((margins, worst))
}
