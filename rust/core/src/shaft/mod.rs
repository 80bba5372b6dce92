//! The main shaft (issue 19): the mechanisms' shaft torques over one cycle, each
//! shifted by its phase in the cyclogram, summed; at each speed the mean, peak,
//! lowest and RMS torque, the energy fluctuation, the flywheel and the motor.
//!
//! **Torques against speed.** At a constant shaft speed ω a mechanism's torque
//! is T(θ) = ω²·a(θ) + b(θ): inertia gives the ω² part (its accelerations are
//! ω² times the acceleration analogs), the loads, springs and gravity the rest.
//! A curve is sampled at N points θ_k = 2πk/N over one turn [rad]; between
//! samples it is linear (periodic). Mechanism i is shifted by its phase φ_i: the
//! sum at θ_k reads each curve at θ_k − φ_i by periodic linear interpolation.
//!
//! **Statistics, exact for the piecewise-linear summed torque:** the mean
//! T̄ = (1/2π)∮T (the samples' average), the peak and lowest (samples), the RMS
//! √((1/2π)∮T²) (h(T₀² + T₀T₁ + T₁²)/3 a step), the energy fluctuation
//! ΔE = max E − min E of E(θ) = ∫₀^θ (T − T̄) [J] (E is piecewise quadratic: its
//! extrema inside a step, where T − T̄ crosses 0, are taken too), the flywheel
//! inertia J = ΔE/(ω² δ) for a coefficient of speed fluctuation δ (the energy
//! method: ΔE = J ω² δ with ω the mean speed) and the motor power T̄ ω [W].
//!
//! The statistics at many speeds use the structure T = ω²a + b: each is a
//! function of u = ω² over sums, convex hulls and crossing intervals computed
//! once (`envelope`), O(N log N + S log S) instead of one pass over the N
//! samples per speed.
//!
//! Files: this one (the kernels), `envelope` (the statistics at many speeds)
//! and `tests`.

use std::f64::consts::TAU;

use crate::input::InvalidInput;
use crate::parallel::{pool, resolve_threads};

mod envelope;
#[cfg(test)]
mod tests;

/// The columns of [`stats_into`]'s rows, in order.
pub const STATS: [&str; 7] = [
    "mean_torque",
    "peak_torque",
    "lowest_torque",
    "rms_torque",
    "energy_fluctuation",
    "flywheel_inertia",
    "power",
];

/// Values per speed in [`stats_into`].
pub const N_STATS: usize = STATS.len();

/// Errors of the main shaft: all of them the invalid inputs every domain shares.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ShaftError {
    #[error(transparent)]
    Input(#[from] InvalidInput),
}

crate::input::wraps_invalid_input!(ShaftError);

/// The phase-shifted sum of M curves of N samples (row-major (M, N)) at the
/// grid's points, by periodic linear interpolation at θ_k − φ_i (`phase` [rad]).
pub fn shifted_sum(curves: &[f64], n: usize, phase: &[f64]) -> Result<Vec<f64>, ShaftError> {
    if n < 3 {
        return Err(InvalidInput::BadValue {
            field: "samples",
            value: n as f64,
            why: "must be >= 3 points over the turn".into(),
        }
        .into());
    }
    if curves.len() != n * phase.len() {
        return Err(InvalidInput::BadValue {
            field: "curves",
            value: curves.len() as f64,
            why: format!(
                "values given; need {} (one row of {n} per phase)",
                n * phase.len()
            )
            .into(),
        }
        .into());
    }
    InvalidInput::check_finite("curves", curves)?;
    InvalidInput::check_finite("phase", phase)?;
    let mut out = vec![0.0; n];
    let h = TAU / n as f64;
    for (row, &p) in curves.chunks_exact(n).zip(phase) {
        // θ_k − φ in steps: k − φ/h = k − (j0 + f), read between j and j + 1.
        let s = (p / h).rem_euclid(n as f64);
        let j0 = s.floor();
        let f = s - j0;
        let j0 = j0 as usize % n;
        for (k, o) in out.iter_mut().enumerate() {
            // index of θ_k − φ: k − j0 − f → between (k − j0 − 1) and (k − j0).
            let hi = (k + n - j0) % n;
            let lo = (hi + n - 1) % n;
            *o += row[hi] * (1.0 - f) + row[lo] * f;
        }
    }
    Ok(out)
}

/// [`STATS`] of T = ω²·a + b (N samples over one turn each) at each speed
/// `omegas` [rad/s] for the coefficient of speed fluctuation `delta`, into
/// `out` (row-major (speeds, [`N_STATS`])).
pub fn stats_into(
    a: &[f64],
    b: &[f64],
    omegas: &[f64],
    delta: f64,
    out: &mut [f64],
    n_threads: Option<i64>,
) -> Result<(), ShaftError> {
    let n = a.len();
    if n < 3 || b.len() != n {
        return Err(InvalidInput::BadValue {
            field: "samples",
            value: n as f64,
            why: format!(
                "must be >= 3, the same for both parts (the other has {})",
                b.len()
            )
            .into(),
        }
        .into());
    }
    InvalidInput::check_finite("per_omega2", a)?;
    InvalidInput::check_finite("static", b)?;
    if let Some((index, &value)) = omegas
        .iter()
        .enumerate()
        .find(|(_, w)| !(w.is_finite() && **w > 0.0))
    {
        return Err(InvalidInput::BadValue {
            field: "omega",
            value,
            why: format!("(at index {index}) [rad/s] must be finite and > 0").into(),
        }
        .into());
    }
    if !(delta.is_finite() && delta > 0.0) {
        return Err(InvalidInput::BadValue {
            field: "speed_fluctuation",
            value: delta,
            why: "(δ) must be finite and > 0".into(),
        }
        .into());
    }
    debug_assert_eq!(out.len(), omegas.len() * N_STATS);
    let pool = pool(resolve_threads(n_threads)?)?;
    let threads = pool.current_num_threads();
    // The envelopes take milliseconds for any size: the flag is read once, before
    // (a raised flag leaves the output unwritten, as a cut chunked kernel does).
    if crate::cancel::requested() {
        return Ok(());
    }
    pool.install(|| envelope::stats_envelope(a, b, omegas, delta, out, threads));
    Ok(())
}
