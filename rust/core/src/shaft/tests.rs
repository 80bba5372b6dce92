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

/// The sampled kernel the envelope replaced: one pass over the samples per
/// speed, the reference of the tests.
fn stats_at(a: &[f64], b: &[f64], w: f64, delta: f64) -> [f64; N_STATS] {
    let n = a.len();
    let h = TAU / n as f64;
    let w2 = w * w;
    let t = |k: usize| w2 * a[k % n] + b[k % n];
    let (mut sum, mut peak, mut low) = (0.0, f64::NEG_INFINITY, f64::INFINITY);
    for k in 0..n {
        let v = t(k);
        sum += v;
        peak = peak.max(v);
        low = low.min(v);
    }
    let mean = sum / n as f64;
    let (mut sq, mut e, mut e_max, mut e_min) = (0.0, 0.0, 0.0f64, 0.0f64);
    for k in 0..n {
        let (t0, t1) = (t(k), t(k + 1));
        sq += h * (t0 * t0 + t0 * t1 + t1 * t1) / 3.0;
        let (d0, d1) = (t0 - mean, t1 - mean);
        if (d0 < 0.0) != (d1 < 0.0) && d0 != d1 {
            // E' = T − T̄ crosses 0 inside the step: E's extremum there.
            let f = d0 / (d0 - d1);
            let ex = e + 0.5 * d0 * f * h;
            e_max = e_max.max(ex);
            e_min = e_min.min(ex);
        }
        e += 0.5 * (d0 + d1) * h;
        e_max = e_max.max(e);
        e_min = e_min.min(e);
    }
    let de = e_max - e_min;
    [
        mean,
        peak,
        low,
        (sq / TAU).sqrt(),
        de,
        de / (w2 * delta),
        mean * w,
    ]
}

/// Envelope against the sampled kernel: every column, relative to its scale.
fn check_against_sampled(a: &[f64], b: &[f64], w: &[f64], delta: f64) {
    let mut out = vec![0.0; w.len() * N_STATS];
    stats_into(a, b, w, delta, &mut out, Some(2)).unwrap();
    for (i, &wi) in w.iter().enumerate() {
        let got = &out[i * N_STATS..(i + 1) * N_STATS];
        let want = stats_at(a, b, wi, delta);
        // The torque's scale at this speed, and the energy's (2π·that).
        let u = wi * wi;
        let scale = a
            .iter()
            .zip(b)
            .map(|(x, y)| (u * x).abs() + y.abs())
            .fold(0.0, f64::max)
            .max(f64::MIN_POSITIVE);
        let tol = [1e-12, 1e-13, 1e-13, 1e-7, 1e-10, 0.0, 1e-12];
        for c in 0..N_STATS {
            let s = match c {
                4 => TAU * scale,
                5 => TAU * scale / (u * delta),
                6 => scale * wi,
                _ => scale,
            };
            let t = if c == 5 { tol[4] } else { tol[c] };
            assert!(
                (got[c] - want[c]).abs() <= t * s,
                "{}: column {c} at w = {wi}: {} vs {} (scale {s})",
                STATS[c],
                got[c],
                want[c]
            );
        }
    }
}

#[test]
fn envelope_equals_the_sampled_kernel() {
    let n = 720;
    let th = |k: usize| TAU * k as f64 / n as f64;
    let a: Vec<f64> = (0..n)
        .map(|k| 1e-3 * (2.0 * th(k)).sin() + 5e-4 * (5.0 * th(k)).cos())
        .collect();
    let b: Vec<f64> = (0..n)
        .map(|k| 8.0 + 5.0 * th(k).cos() + 2.0 * (3.0 * th(k)).sin())
        .collect();
    let w: Vec<f64> = (0..5000).map(|i| 1.0 + 0.05 * i as f64).collect();
    check_against_sampled(&a, &b, &w, 0.02);
    // A single speed; equal speeds; unsorted speeds.
    check_against_sampled(&a, &b, &[37.0], 0.02);
    check_against_sampled(&a, &b, &[90.0, 10.0, 90.0, 10.0, 50.0], 0.02);
    // Ties in a and b (plateaus), a constant torque, a ≡ 0.
    let steps: Vec<f64> = (0..n).map(|k| (k / 90) as f64).collect();
    check_against_sampled(&steps, &steps, &w[..50], 0.1);
    check_against_sampled(&vec![1.0; n], &vec![2.0; n], &w[..50], 0.1);
    check_against_sampled(&vec![0.0; n], &b, &w[..50], 0.1);
}

proptest::proptest! {
    #[test]
    fn envelope_matches_sampled(
        n in 3usize..60,
        seed_a in proptest::collection::vec(-3i32..4, 60),
        seed_b in proptest::collection::vec(-50.0f64..50.0, 60),
        speeds in proptest::collection::vec(0.01f64..300.0, 1..40),
        scale in 1e-6f64..1e-2,
    ) {
        // Small integers in a: many ties in a (the hulls' equal abscissae).
        let a: Vec<f64> = seed_a[..n].iter().map(|&v| v as f64 * scale).collect();
        let b = &seed_b[..n];
        check_against_sampled(&a, b, &speeds, 0.05);
    }
}
