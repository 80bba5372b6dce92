//! Bindings of the servo axes: one motor and ratio at many speeds, and the
//! sizing batch over motors × ratios × speeds (see `cyclomech.servo`).

use cyclomech_core::motion::MotionError;
use cyclomech_core::servo::{
    duty_into, law_samples, law_weights, min_angles_into, rms_angles_into, rms_speed_limit,
    segment_samples, size_into, speed_limit, Drive, Load, Motors, RmsProgram, ServoError, Shape,
    N_CHECKS, N_DUTY,
};
use numpy::ndarray::{Ix1, Ix2, Ix3};
use numpy::{PyArray1, PyArray2, PyArray3, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;

use crate::convert::{self, LayoutError};
use crate::errors::{run, IntoPyErr};
use crate::motion::ProgramKernel;

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

/// (S, K, 2) smallest phase angles [rad] of the segments `segments` of the
/// motion `program` at master speeds `omegas` [rad/s], per
/// `cyclomech_core::servo::BOUND_CRITERIA` (peak torque, speed): each segment's
/// law on the unit square sampled by `law_samples`, its
/// stroke brought to the load shaft by `shaft` (2π/lead for a screw, 1 for a
/// rotary load). A segment whose shape changes with its angle is refused.
#[pyfunction]
#[pyo3(signature = (program, segments, shaft, inertia, torque, efficiency, ratio, drive_inertia, peak_torque, max_speed, omegas))]
#[allow(clippy::too_many_arguments)]
pub fn servo_min_angles<'py>(
    py: Python<'py>,
    program: PyRef<'py, ProgramKernel>,
    segments: Vec<usize>,
    shaft: f64,
    inertia: f64,
    torque: f64,
    efficiency: f64,
    ratio: f64,
    drive_inertia: f64,
    peak_torque: f64,
    max_speed: f64,
    omegas: PyReadonlyArray1<'py, f64>,
) -> PyResult<Bound<'py, PyArray3<f64>>> {
    let w = ServoError::slice(py, "omegas", &omegas)?;
    let spans = program.program.spans();
    let drive = Drive {
        load_inertia: inertia,
        load_torque: torque,
        efficiency,
        ratio,
        drive_inertia,
        peak_torque,
        max_speed,
    };
    let mut shapes = Vec::with_capacity(segments.len());
    for &k in &segments {
        let law_name = program.program.specs().get(k).map(|s| s.law.clone());
        let refuse = |why: &str| {
            MotionError::BadSegment {
                index: k,
                law: law_name.clone().unwrap_or_default(),
                what: why.to_string(),
            }
            .into_pyerr(py)
        };
        let Some(span) = spans.get(k) else {
            return Err(refuse("no such segment"));
        };
        if !span.scalable || span.at_end[0] == span.at_start[0] {
            return Err(refuse(
                "its shape changes with its angle (moving ends, a constant velocity, a point \
                 table) or it does not move: it has no smallest phase angle",
            ));
        }
        let (_, h, law) = program.program.unit_law(k);
        let (dz, ddz) = law_samples(&law);
        shapes.push((dz, ddz, law.dz_max, shaft * h));
    }
    let out = convert::zeros(
        py,
        &[w.len(), segments.len(), 2],
        "servo_min_angles",
        "fewer speeds",
    )?;
    {
        let mut rw = out.readwrite();
        let slice = convert::output(py, &mut rw)?;
        run(py, "servo_min_angles", || -> Result<(), ServoError> {
            let k = shapes.len();
            let mut row = vec![0.0; 2 * w.len()];
            for (j, (dz, ddz, dz_max, stroke)) in shapes.iter().enumerate() {
                let shape = Shape {
                    dz,
                    ddz,
                    dz_max: *dz_max,
                    stroke: *stroke,
                };
                min_angles_into(&shape, &drive, w, &mut row)?;
                for (s, pair) in row.chunks(2).enumerate() {
                    slice[(s * k + j) * 2..(s * k + j) * 2 + 2].copy_from_slice(pair);
                }
            }
            Ok(())
        })?;
    }
    Ok(out)
}

/// The highest master speeds [rad/s] the fixed-shape `segments` of a program
/// allow through a drive (`cyclomech_core::servo::speed_limit`): (peak torque,
/// speed, RMS torque against `rated`; the last inf unless `rms`, the segments
/// then being the whole cycle). `shaft` turns the program's units into the load
/// shaft's radians.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub fn servo_speed_limit(
    py: Python<'_>,
    program: PyRef<'_, ProgramKernel>,
    segments: Vec<usize>,
    shaft: f64,
    inertia: f64,
    torque: f64,
    efficiency: f64,
    ratio: f64,
    drive_inertia: f64,
    peak_torque: f64,
    max_speed: f64,
    rated: f64,
    rms: bool,
) -> PyResult<(f64, f64, f64)> {
    check_segments(py, &program, &segments)?;
    let drive = Drive {
        load_inertia: inertia,
        load_torque: torque,
        efficiency,
        ratio,
        drive_inertia,
        peak_torque,
        max_speed,
    };
    let kernel = &program.program;
    run(py, "servo_speed_limit", || {
        let (v, a, w) = segment_samples(kernel, &segments, shaft);
        let (t, s) = speed_limit(&v, &a, &drive)?;
        let cap = t.min(s);
        let r = if rms && cap > 0.0 {
            rms_speed_limit(
                &v,
                &a,
                &w,
                &drive,
                rated,
                if cap.is_finite() { cap } else { 1e6 },
            )?
        } else {
            f64::INFINITY
        };
        Ok::<_, ServoError>((t, s, r))
    })
}

/// Refuse a segment index the program does not have, naming it.
fn check_segments(py: Python<'_>, program: &ProgramKernel, segments: &[usize]) -> PyResult<()> {
    let n = program.program.spans().len();
    if let Some(&k) = segments.iter().find(|&&k| k >= n) {
        return Err(MotionError::BadSegment {
            index: k,
            law: String::new(),
            what: format!("no such segment (the program has {n})"),
        }
        .into_pyerr(py));
    }
    Ok(())
}

/// The smallest angle [rad] of `segment` by the motor's RMS torque `rated`
/// [N·m] at each master speed `omegas` [rad/s], the dwell `dwell` taking up its
/// change and the rest of the program fixed (`cyclomech_core::servo::rms`).
#[pyfunction]
#[pyo3(signature = (program, segment, dwell, shaft, inertia, torque, efficiency, ratio, drive_inertia, rated, omegas, *, n_threads=None))]
#[allow(clippy::too_many_arguments)]
pub fn servo_rms_angles<'py>(
    py: Python<'py>,
    program: PyRef<'py, ProgramKernel>,
    segment: usize,
    dwell: usize,
    shaft: f64,
    inertia: f64,
    torque: f64,
    efficiency: f64,
    ratio: f64,
    drive_inertia: f64,
    rated: f64,
    omegas: PyReadonlyArray1<'py, f64>,
    n_threads: Option<i64>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    check_segments(py, &program, &[segment, dwell])?;
    let w = ServoError::slice(py, "omegas", &omegas)?;
    let spans = program.program.spans();
    if segment == dwell || !spans[segment].scalable {
        return Err(MotionError::BadSegment {
            index: segment,
            law: program.program.specs()[segment].law.clone(),
            what: "its shape changes with its angle, or it is its own dwell: it has no RMS bound"
                .to_string(),
        }
        .into_pyerr(py));
    }
    let drive = Drive {
        load_inertia: inertia,
        load_torque: torque,
        efficiency,
        ratio,
        drive_inertia,
        peak_torque: 1.0, // (not read by the RMS bound)
        max_speed: 1.0,
    };
    let kernel = &program.program;
    let fixed: Vec<usize> = (0..spans.len())
        .filter(|&i| i != segment && i != dwell)
        .collect();
    let out = convert::zeros::<f64, Ix1>(py, &[w.len()], "servo_rms_angles", "fewer speeds")?;
    {
        let mut rw = out.readwrite();
        let slice = convert::output(py, &mut rw)?;
        run(py, "servo_rms_angles", || -> Result<(), ServoError> {
            let (_, h, law) = kernel.unit_law(segment);
            let (dz, ddz) = law_samples(&law);
            let weights = law_weights(&law);
            let (v, a, fw) = segment_samples(kernel, &fixed, shaft);
            let p = RmsProgram {
                dz: &dz,
                ddz: &ddz,
                weights: &weights,
                stroke: shaft * h,
                fixed_v: &v,
                fixed_a: &a,
                fixed_w: &fw,
                angle: spans[segment].angle,
                dwell: spans[dwell].angle,
            };
            rms_angles_into(&p, &drive, rated, w, slice, n_threads)
        })?;
    }
    Ok(out)
}
