//! Unit tests of the servo kernels: the batch against the sample-by-sample
//! reference, and a closed form (the Python tests check against independent
//! references too).

use std::f64::consts::{PI, TAU};

use proptest::prelude::*;

use super::*;

/// A cycloidal rise of `h` [rad] over half the cycle and a dwell: φ′, φ″.
fn rise_dwell(n: usize, h: f64) -> (Vec<f64>, Vec<f64>) {
    let beta = PI;
    let (mut v, mut a) = (vec![0.0; n], vec![0.0; n]);
    for k in 0..n {
        let t = TAU * k as f64 / n as f64;
        if t < beta {
            let x = TAU * t / beta;
            v[k] = h / beta * (1.0 - x.cos());
            a[k] = TAU * h / (beta * beta) * x.sin();
        }
    }
    (v, a)
}

fn duty(load: &Load<'_>, ratio: f64, j: f64, omegas: &[f64]) -> Vec<f64> {
    let mut stats = vec![0.0; omegas.len() * N_DUTY];
    duty_into(load, ratio, j, omegas, &mut stats, None, Some(1)).unwrap();
    stats
}

#[test]
fn a_pure_inertia_peaks_at_the_cycloids_acceleration() {
    // T_m = (J_m + J_L/i²)·i·φ″ω²; the cycloid's φ″ peaks at 2πh/β².
    let (n, h) = (3600, 2.0);
    let (v, a) = rise_dwell(n, h);
    let load = Load {
        vel: &v,
        acc: &a,
        inertia: 0.5,
        torque: 0.0,
        efficiency: 1.0,
    };
    let (i, jm, w) = (4.0, 0.01, 10.0);
    let s = duty(&load, i, jm, &[w]);
    let want = (jm + 0.5 / (i * i)) * i * TAU * h / (PI * PI) * w * w;
    assert!((s[0] - want).abs() < 1e-9 * want);
    // Peak motor speed: i·ω·2h/β.
    assert!((s[2] - i * w * 2.0 * h / PI).abs() < 1e-9);
}

fn margins_by_duty(
    load: &Load<'_>,
    ratios: &[f64],
    jg: f64,
    motors: &Motors<'_>,
    omegas: &[f64],
    limit: f64,
) -> Vec<f64> {
    let mut out = Vec::new();
    for m in 0..motors.inertia.len() {
        for &i in ratios {
            let s = duty(load, i, motors.inertia[m] + jg, omegas);
            let mut worst = [f64::INFINITY; N_CHECKS];
            for row in s.chunks_exact(N_DUTY) {
                let used = [row[0], row[1], row[2]];
                let avail = [
                    motors.peak_torque[m],
                    motors.rated_torque[m],
                    motors.max_speed[m],
                ];
                for c in 0..3 {
                    worst[c] = worst[c].min(1.0 - used[c] / avail[c]);
                }
            }
            worst[3] = 1.0 - (load.inertia / (i * i) + jg) / motors.inertia[m] / limit;
            out.extend(worst);
        }
    }
    out
}

proptest! {
    #[test]
    fn the_batch_matches_the_reference(
        inertia in 0.0f64..2.0,
        torque in -5.0f64..5.0,
        efficiency in 0.3f64..=1.0,
        jm in proptest::collection::vec(1e-4f64..1e-1, 1..5),
        ratios in proptest::collection::vec(0.5f64..20.0, 1..4),
        omegas in proptest::collection::vec(1.0f64..60.0, 1..4),
        h in 0.1f64..4.0,
        n in 8usize..200,
    ) {
        let (v, a) = rise_dwell(n, h);
        let load = Load { vel: &v, acc: &a, inertia, torque, efficiency };
        let peak: Vec<f64> = jm.iter().map(|j| 100.0 * j.sqrt()).collect();
        let rated: Vec<f64> = peak.iter().map(|p| p / 3.0).collect();
        let max_speed = vec![300.0; jm.len()];
        let motors = Motors { inertia: &jm, peak_torque: &peak, rated_torque: &rated, max_speed: &max_speed };
        let c = jm.len() * ratios.len() * N_CHECKS;
        let (mut got, mut worst) = (vec![0.0; c], vec![0; c]);
        size_into(&load, &ratios, 1e-4, &motors, &omegas, 10.0, &mut got, &mut worst, Some(2)).unwrap();
        let want = margins_by_duty(&load, &ratios, 1e-4, &motors, &omegas, 10.0);
        for (g, w) in got.iter().zip(&want) {
            prop_assert!((g - w).abs() <= 1e-9 * (1.0 + w.abs()), "{g} vs {w}");
        }
        prop_assert!(worst.iter().all(|&s| s >= 0 && (s as usize) < omegas.len()));
    }
}

#[test]
fn bad_inputs_are_named() {
    let (v, a) = rise_dwell(8, 1.0);
    let load = Load {
        vel: &v,
        acc: &a,
        inertia: 1.0,
        torque: 0.0,
        efficiency: 1.5,
    };
    let mut s = vec![0.0; N_DUTY];
    let e = duty_into(&load, 1.0, 1.0, &[1.0], &mut s, None, Some(1)).unwrap_err();
    assert_eq!(e.to_string(), "efficiency = 1.5 must be in (0, 1]");
    let load = Load {
        efficiency: 1.0,
        ..load
    };
    let e = duty_into(&load, 0.0, 1.0, &[1.0], &mut s, None, Some(1)).unwrap_err();
    assert_eq!(
        e.to_string(),
        "ratio = 0 (motor speed / load speed) must be finite and > 0"
    );
}

#[test]
fn a_load_at_rest_is_held_on_the_motoring_side() {
    // No motion: every line of the envelope has slope 0 (one survives); the motor
    // holds T_ext/(i·η) at every angle, whatever its inertia.
    let (v, a) = (vec![0.0; 16], vec![0.0; 16]);
    let load = Load {
        vel: &v,
        acc: &a,
        inertia: 0.3,
        torque: -2.0,
        efficiency: 0.8,
    };
    let s = duty(&load, 4.0, 1e-3, &[5.0]);
    let hold = 2.0 / (4.0 * 0.8);
    assert!((s[0] - hold).abs() < 1e-15 && (s[1] - hold).abs() < 1e-15);
    assert_eq!((s[2], s[3]), (0.0, 0.0));
    let motors = Motors {
        inertia: &[1e-3, 2e-3],
        peak_torque: &[1.0, 1.0],
        rated_torque: &[0.5, 2.0],
        max_speed: &[100.0, 100.0],
    };
    let (mut m, mut w) = (vec![0.0; 2 * N_CHECKS], vec![0; 2 * N_CHECKS]);
    size_into(
        &load,
        &[4.0],
        0.0,
        &motors,
        &[5.0, 7.0],
        10.0,
        &mut m,
        &mut w,
        Some(1),
    )
    .unwrap();
    let want = margins_by_duty(&load, &[4.0], 0.0, &motors, &[5.0, 7.0], 10.0);
    for (g, w) in m.iter().zip(&want) {
        assert!((g - w).abs() < 1e-12, "{g} vs {w}");
    }
    assert!((m[1] - (1.0 - hold / 0.5)).abs() < 1e-12);
}

proptest! {
    /// Arbitrary samples with many ties (piecewise-constant accelerations, dwells,
    /// equal slopes in the envelope): the batch still matches the reference.
    #[test]
    fn the_batch_matches_the_reference_on_ties(
        samples in proptest::collection::vec((-2i32..=2, -2i32..=2), 2..60),
        torque in -3.0f64..3.0,
        efficiency in 0.5f64..=1.0,
        ratios in proptest::collection::vec(0.5f64..10.0, 1..4),
        omegas in proptest::collection::vec(0.5f64..30.0, 1..4),
    ) {
        let v: Vec<f64> = samples.iter().map(|s| s.0 as f64 * 0.5).collect();
        let a: Vec<f64> = samples.iter().map(|s| s.1 as f64 * 0.25).collect();
        let load = Load { vel: &v, acc: &a, inertia: 0.2, torque, efficiency };
        let jm = [1e-3, 5e-3, 2e-2];
        let motors = Motors {
            inertia: &jm, peak_torque: &[5.0, 10.0, 20.0],
            rated_torque: &[2.0, 4.0, 8.0], max_speed: &[100.0, 200.0, 300.0],
        };
        let c = jm.len() * ratios.len() * N_CHECKS;
        let (mut got, mut worst) = (vec![0.0; c], vec![0; c]);
        size_into(&load, &ratios, 0.0, &motors, &omegas, 5.0, &mut got, &mut worst, Some(1)).unwrap();
        let want = margins_by_duty(&load, &ratios, 0.0, &motors, &omegas, 5.0);
        for (g, w) in got.iter().zip(&want) {
            prop_assert!((g - w).abs() <= 1e-9 * (1.0 + w.abs()), "{g} vs {w}");
        }
    }
}

/// A swing φ_L = sin θ against a constant torque T0 (η = 1, i = 1): the motor
/// torque is −J·ω²·sin θ + T0, its peak J·ω² + |T0|, so the peak torque holds
/// up to ω = √((T_pk − |T0|)/J), and the speed up to ω_max/max|φ_L′| = ω_max.
#[test]
fn the_speed_limit_of_a_swing_is_its_closed_form() {
    let n = 20_000;
    let th: Vec<f64> = (0..n).map(|k| TAU * k as f64 / n as f64).collect();
    let dz: Vec<f64> = th.iter().map(|t| t.cos()).collect();
    let ddz: Vec<f64> = th.iter().map(|t| -t.sin()).collect();
    let drive = Drive {
        load_inertia: 0.02,
        load_torque: 0.5,
        efficiency: 1.0,
        ratio: 1.0,
        drive_inertia: 0.01,
        peak_torque: 3.5,
        max_speed: 300.0,
    };
    let (torque, speed) = speed_limit(&dz, &ddz, &drive).unwrap();
    let exact = ((3.5_f64 - 0.5) / 0.03).sqrt();
    assert!((torque - exact).abs() < 1e-6 * exact, "{torque} vs {exact}");
    assert!((speed - 300.0).abs() < 1e-9);
    // The static torque alone above the peak: no speed holds.
    let stuck = Drive {
        load_torque: 4.0,
        ..drive
    };
    assert_eq!(speed_limit(&dz, &ddz, &stuck).unwrap().0, 0.0);
    // Standing still: no limit.
    let zero = vec![0.0; n];
    assert_eq!(
        speed_limit(&zero, &zero, &drive).unwrap(),
        (f64::INFINITY, f64::INFINITY)
    );
    // Mismatched samples are an error, not a panic.
    assert!(speed_limit(&dz, &ddz[1..], &drive).is_err());
}

/// A cycloidal rise on a pure inertia (η = 1, i = 1, no load torque): the
/// energy over the cycle is J²H²ω⁴/β³·∫Z″² du with ∫Z″² = 2π², so the RMS
/// holds from β = (J²H²ω⁴π/T_rated²)^(1/3) up; its dwell holds nothing.
#[test]
fn the_rms_bound_of_a_cycloid_is_its_closed_form() {
    let n = 20_000;
    let u: Vec<f64> = (0..=n).map(|k| k as f64 / n as f64).collect();
    let dz: Vec<f64> = u.iter().map(|x| 1.0 - (TAU * x).cos()).collect();
    let ddz: Vec<f64> = u.iter().map(|x| TAU * (TAU * x).sin()).collect();
    let mut weights = vec![1.0 / n as f64; n + 1];
    (weights[0], weights[n]) = (0.5 / n as f64, 0.5 / n as f64);
    let program = RmsProgram {
        dz: &dz,
        ddz: &ddz,
        weights: &weights,
        stroke: 2.0,
        fixed_v: &[],
        fixed_a: &[],
        fixed_w: &[],
        angle: 1.0,
        dwell: 5.0,
    };
    let drive = Drive {
        load_inertia: 0.05,
        load_torque: 0.0,
        efficiency: 1.0,
        ratio: 1.0,
        drive_inertia: 0.0,
        peak_torque: 100.0,
        max_speed: 300.0,
    };
    let (rated, omegas) = (2.0, [2.0, 4.0, 6.0]);
    let mut out = [0.0; 3];
    rms_angles_into(&program, &drive, rated, &omegas, &mut out).unwrap();
    for (got, w) in out.iter().zip(omegas) {
        let exact = (0.05_f64.powi(2) * 4.0 * w.powi(4) * PI / (rated * rated)).cbrt();
        assert!((got - exact).abs() < 1e-7 * exact, "{got} vs {exact}");
    }
    // Too fast for any angle the dwell can give: NaN; standing: 0.
    let mut far = [0.0];
    rms_angles_into(&program, &drive, rated, &[200.0], &mut far).unwrap();
    assert!(far[0].is_nan());
    let slow = RmsProgram {
        stroke: 0.0,
        ..program
    };
    rms_angles_into(&slow, &drive, rated, &[5.0], &mut far).unwrap();
    assert_eq!(far[0], 0.0);
    // A held load above the rated torque over the whole cycle: no angle.
    let held = Drive {
        load_torque: 3.0,
        ..drive
    };
    rms_angles_into(&slow, &held, rated, &[5.0], &mut far).unwrap();
    assert!(far[0].is_nan());
    assert!(rms_angles_into(&program, &drive, -1.0, &[5.0], &mut far).is_err());
}

/// A swing φ_L = sin θ on a pure inertia (η = 1, i = 1): T_m = −J·ω²·sin θ,
/// RMS = J·ω²/√2, so the RMS holds up to ω = √(√2·T_rated/J); a held load of
/// T0 adds T0² to the mean square: ω = (2·(T_rated² − T0²)/J²)^(1/4).
#[test]
fn the_rms_speed_limit_of_a_swing_is_its_closed_form() {
    let n = 20_000;
    let th: Vec<f64> = (0..n).map(|k| TAU * k as f64 / n as f64).collect();
    let v: Vec<f64> = th.iter().map(|t| t.cos()).collect();
    let a: Vec<f64> = th.iter().map(|t| -t.sin()).collect();
    let w = vec![TAU / n as f64; n];
    let drive = Drive {
        load_inertia: 0.03,
        load_torque: 0.0,
        efficiency: 1.0,
        ratio: 1.0,
        drive_inertia: 0.0,
        peak_torque: 100.0,
        max_speed: 300.0,
    };
    let got = rms_speed_limit(&v, &a, &w, &drive, 1.5, 1e3).unwrap();
    let exact = (2.0_f64.sqrt() * 1.5 / 0.03).sqrt();
    assert!((got - exact).abs() < 1e-9 * exact, "{got} vs {exact}");
    // Below the cap only: a cap under the crossing is no limit.
    assert_eq!(
        rms_speed_limit(&v, &a, &w, &drive, 1.5, 0.5 * exact).unwrap(),
        f64::INFINITY
    );
    // A held torque the rated one cannot carry: 0.
    let held = Drive {
        load_torque: 2.0,
        ..drive
    };
    assert_eq!(rms_speed_limit(&v, &a, &w, &held, 1.5, 1e3).unwrap(), 0.0);
}
