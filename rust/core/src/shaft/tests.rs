//! Unit tests of the main shaft's kernels (the Python tests check against
//! independent references).

use std::f64::consts::{PI, TAU};

use super::*;

#[test]
fn a_sinusoidal_ripple_in_closed_form() {
    // T = T0 + A sin(3θ): mean T0, peak T0 + A, RMS √(T0² + A²/2), ΔE = 2A/3.
    let (n, t0, amp) = (36_000, 5.0, 2.0);
    let b: Vec<f64> = (0..n)
        .map(|k| t0 + amp * (3.0 * TAU * k as f64 / n as f64).sin())
        .collect();
    let a = vec![0.0; n];
    let mut out = [0.0; N_STATS];
    stats_into(&a, &b, &[10.0], 0.02, &mut out, Some(1)).unwrap();
    assert!((out[0] - t0).abs() < 1e-12);
    assert!((out[1] - (t0 + amp)).abs() < 1e-6);
    assert!((out[3] - (t0 * t0 + amp * amp / 2.0).sqrt()).abs() < 1e-6);
    assert!((out[4] - 2.0 * amp / 3.0).abs() < 1e-6);
    assert!((out[5] - out[4] / (100.0 * 0.02)).abs() < 1e-12);
    assert!((out[6] - t0 * 10.0).abs() < 1e-10);
}

#[test]
fn a_shift_by_whole_and_half_steps() {
    let n = 8;
    let row: Vec<f64> = (0..n).map(|k| k as f64).collect();
    let h = TAU / n as f64;
    // One step later: the value at θ_k is the curve's at θ_{k−1}.
    let s = shifted_sum(&row, n, &[h]).unwrap();
    assert_eq!(s, vec![7.0, 0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
    // Half a step: the average of the two neighbours.
    let s = shifted_sum(&row, n, &[0.5 * h]).unwrap();
    assert!((s[1] - 0.5).abs() < 1e-15 && (s[0] - 3.5).abs() < 1e-15);
    // A whole turn changes nothing; two rows add.
    let two: Vec<f64> = row.iter().chain(row.iter()).copied().collect();
    let s = shifted_sum(&two, n, &[TAU, 0.0]).unwrap();
    assert!(s.iter().zip(&row).all(|(x, r)| (x - 2.0 * r).abs() < 1e-12));
    let _ = PI;
}

#[test]
fn bad_input_is_an_error() {
    let mut out = [0.0; N_STATS];
    assert!(stats_into(&[0.0; 4], &[0.0; 4], &[1.0], 0.0, &mut out, None).is_err());
    assert!(stats_into(&[0.0; 4], &[0.0; 3], &[1.0], 0.1, &mut out, None).is_err());
    assert!(stats_into(&[0.0; 4], &[0.0; 4], &[-1.0], 0.1, &mut out, None).is_err());
    assert!(shifted_sum(&[0.0; 5], 5, &[f64::NAN]).is_err());
    assert!(shifted_sum(&[0.0; 4], 2, &[0.0, 0.0]).is_err());
}
