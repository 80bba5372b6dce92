//! One motor on one gear ratio at many speeds, sample by sample: the reference
//! the sizing batch is checked against, and the curves a user plots.

use std::f64::consts::TAU;

use rayon::prelude::*;

use super::{positive_entries, Load, ServoError};
use crate::input::InvalidInput;
use crate::parallel::{pool, resolve_threads};

/// The columns of [`duty_into`]'s rows, in order: the peak |T_m| [N·m], the RMS
/// of T_m over the cycle [N·m], the peak |ω_m| [rad/s] and the energy the motor
/// regenerates per cycle, ∫ max(0, −T_m·ω_m) dt [J].
pub const DUTY: [&str; 4] = ["peak_torque", "rms_torque", "peak_speed", "regen_energy"];

/// Values per speed in [`duty_into`].
pub const N_DUTY: usize = DUTY.len();

/// [`DUTY`] of the motor torque T_m at each master speed `omegas` [rad/s], for
/// the gear ratio `ratio` (> 0) and the inertia at the motor shaft
/// `drive_inertia` = J_motor + J_gearbox [kg·m²], into `stats` (row-major
/// (speeds, [`N_DUTY`])); with `torque`, T_m at every sample too (row-major
/// (speeds, N)) [N·m]. Means over the cycle are means over the uniform samples
/// (the rectangle rule, exact for a trigonometric polynomial of degree < N).
pub fn duty_into(
    load: &Load<'_>,
    ratio: f64,
    drive_inertia: f64,
    omegas: &[f64],
    stats: &mut [f64],
    torque: Option<&mut [f64]>,
    n_threads: Option<i64>,
) -> Result<(), ServoError> {
    load.check()?;
    if !(ratio.is_finite() && ratio > 0.0) {
        return Err(InvalidInput::bad_value(
            "ratio",
            ratio,
            "(motor speed / load speed) must be finite and > 0",
        )
        .into());
    }
    if !(drive_inertia.is_finite() && drive_inertia >= 0.0) {
        return Err(InvalidInput::bad_value(
            "drive_inertia",
            drive_inertia,
            "[kg·m²] must be finite and >= 0",
        )
        .into());
    }
    positive_entries("omega", omegas)?;
    let n = load.vel.len();
    debug_assert_eq!(stats.len(), omegas.len() * N_DUTY);
    let pool = pool(resolve_threads(n_threads)?)?;
    let mut scratch;
    let curves: &mut [f64] = match torque {
        Some(t) => {
            debug_assert_eq!(t.len(), omegas.len() * n);
            t
        }
        None => {
            scratch = Vec::new();
            &mut scratch
        }
    };
    let keep = !curves.is_empty();
    pool.install(|| {
        let rows = stats.par_chunks_mut(N_DUTY).zip(omegas.par_iter());
        if keep {
            rows.zip(curves.par_chunks_mut(n))
                .for_each(|((row, &w), curve)| {
                    if !crate::cancel::requested() {
                        row.copy_from_slice(&at_speed(load, ratio, drive_inertia, w, curve));
                    }
                });
        } else {
            rows.for_each_init(
                || vec![0.0; n],
                |curve, (row, &w)| {
                    if !crate::cancel::requested() {
                        row.copy_from_slice(&at_speed(load, ratio, drive_inertia, w, curve));
                    }
                },
            );
        }
    });
    Ok(())
}

/// [`DUTY`] at one master speed `w` [rad/s]; T_m written into `curve` (N).
fn at_speed(load: &Load<'_>, i: f64, j: f64, w: f64, curve: &mut [f64]) -> [f64; N_DUTY] {
    let n = curve.len();
    let w2 = w * w;
    let h = TAU / n as f64;
    let (mut peak, mut sq, mut speed, mut regen) = (0.0f64, 0.0, 0.0f64, 0.0);
    for (k, t) in curve.iter_mut().enumerate() {
        let tm = j * i * load.acc[k] * w2 + load.reduced(k, w2) / i;
        *t = tm;
        peak = peak.max(tm.abs());
        sq += tm * tm;
        speed = speed.max((i * load.vel[k] * w).abs());
        // T_m·ω_m·dt with dt = dθ/ω: T_m·i·φ_L′·dθ.
        regen += (-tm * i * load.vel[k]).max(0.0) * h;
    }
    [peak, (sq / n as f64).sqrt(), speed, regen]
}
