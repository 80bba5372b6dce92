//! Unit tests of the follower dynamics (the Python tests compare with scipy).

use std::f64::consts::{PI, TAU};

use proptest::prelude::*;

use super::*;

/// The cycloidal rise's closed form (undamped): R = 8π²|sin(τ/2)|/(τ|4π² − τ²|).
fn cycloidal(tau: f64) -> f64 {
    8.0 * PI * PI * (tau / 2.0).sin().abs() / (tau * (4.0 * PI * PI - tau * tau).abs())
}

#[test]
fn cycloidal_closed_form() {
    let f = LawForce::new("cycloidal").unwrap();
    let mut worst: f64 = 0.0;
    for i in 1..=400 {
        let tau = 0.5 * i as f64 + 0.123;
        let r = f.residual_ratio(tau, 0.0).unwrap();
        let want = cycloidal(tau);
        // Relative to the envelope 8π²/(τ|4π² − τ²|) (the closed form has zeros).
        let env = 8.0 * PI * PI / (tau * (4.0 * PI * PI - tau * tau).abs());
        worst = worst.max((r - want).abs() / env);
    }
    // ~1.5e-9 at τ = 200 (the O(h⁴τ²) term left by the extrapolation).
    assert!(worst < 1e-8, "worst {worst}");
    for k in 2..=10 {
        let r = f.residual_ratio(TAU * k as f64, 0.0).unwrap();
        assert!(r < 1e-9, "k = {k}: {r}");
    }
}

#[test]
fn small_tau_limit() {
    for zeta in [0.0, 0.3] {
        for law in crate::motion::NAMES {
            let r = residual_ratio(law, 1e-6, zeta).unwrap();
            let want = 1.0 / (1.0 - zeta * zeta).sqrt();
            assert!((r - want).abs() < 1e-5, "{law} {zeta}: {r}");
        }
    }
}

#[test]
fn batch_equals_single() {
    let taus: Vec<f64> = (1..100).map(|i| 0.37 * i as f64).collect();
    let mut out = vec![0.0; taus.len()];
    residual_ratio_batch("modified_sine", &taus, 0.1, Some(2), &mut out).unwrap();
    for (t, o) in taus.iter().zip(&out) {
        assert_eq!(*o, residual_ratio("modified_sine", *t, 0.1).unwrap());
    }
}

#[test]
fn bad_inputs_are_errors() {
    assert!(residual_ratio("cycloidal", 1.0, 1.0).is_err());
    assert!(residual_ratio("cycloidal", 1.0, -0.1).is_err());
    assert!(residual_ratio("cycloidal", 1.0, f64::NAN).is_err());
    assert!(residual_ratio("cycloidal", 0.0, 0.0).is_err());
    assert!(residual_ratio("nope", 1.0, 0.0).is_err());
    assert!(min_tau("cycloidal", 0.0, 0.0).is_err());
    assert!(min_tau("cycloidal", f64::NAN, 0.0).is_err());
    let mut out = [0.0; 3];
    let e = residual_ratio_batch("harmonic", &[1.0, -1.0, 2.0], 0.0, None, &mut out);
    assert!(e.unwrap_err().to_string().contains("case 1"));
}

#[test]
fn min_tau_cycloidal() {
    let f = LawForce::new("cycloidal").unwrap();
    for limit in [0.3, 0.05, 0.01, 1e-3] {
        let t = min_tau("cycloidal", limit, 0.0).unwrap();
        let r = f.residual_ratio(t, 0.0).unwrap();
        assert!((r - limit).abs() <= 1e-9 * limit, "{limit}: R({t}) = {r}");
        assert!(f.residual_ratio(t * (1.0 - 1e-6), 0.0).unwrap() > limit);
        // R stays below the limit beyond τ* (dense check).
        for i in 1..4000 {
            let tau = t + 0.01 * i as f64;
            assert!(f.residual_ratio(tau, 0.0).unwrap() <= limit * (1.0 + 1e-12));
        }
    }
    // Above R(0+) = 1: no bound.
    assert_eq!(min_tau("cycloidal", 1.5, 0.0).unwrap(), 0.0);
}

#[test]
fn steady_state_is_periodic_and_matches_the_residual() {
    let seg = |kind, deg: f64, stroke| SegmentSpec {
        kind,
        angle: deg.to_radians(),
        stroke,
        law: "cycloidal".into(),
        unit: None,
    };
    let specs = [
        seg(Kind::Dwell, 200.0, 0.0),
        seg(Kind::Rise, 60.0, 0.01),
        seg(Kind::Dwell, 40.0, 0.0),
        seg(Kind::Return, 60.0, 0.01),
    ];
    let (omega, omega_n, zeta) = (10.0, 400.0, 0.1);
    let st = steady_response(&specs, omega, omega_n, zeta, &[0.0, TAU, 1.0]).unwrap();
    assert!((st.x[0] - st.x[1]).abs() < 1e-12 * st.residual[1].max(1e-12));
    assert!((st.rate[0] - st.rate[1]).abs() < 1e-9 * omega_n * st.residual[1]);
    // After a long dwell the rise starts from (nearly) rest: its residual is h·R.
    let tau = omega_n * 60f64.to_radians() / omega;
    let want = 0.01 * residual_ratio("cycloidal", tau, zeta).unwrap();
    assert!(
        (st.residual[1] - want).abs() < 1e-9 * want,
        "{} {want}",
        st.residual[1]
    );
}

#[test]
fn resonance_is_an_error() {
    let seg = |kind, deg: f64| SegmentSpec {
        kind,
        angle: deg.to_radians(),
        stroke: 0.01,
        law: "harmonic".into(),
        unit: None,
    };
    let specs = [seg(Kind::Rise, 180.0), seg(Kind::Return, 180.0)];
    let e = steady_response(&specs, 10.0, 30.0, 0.0, &[0.0]).unwrap_err();
    assert!(e.to_string().contains("resonance"), "{e}");
    assert!(steady_response(&specs, 10.0, 30.0, 0.01, &[0.0]).is_ok());
    assert!(steady_response(&specs, 10.0, 30.5, 0.0, &[0.0]).is_ok());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// τ* is the last crossing: R(τ*) = limit and R ≤ limit on samples beyond.
    #[test]
    fn min_tau_is_the_last_crossing(
        li in 0usize..6,
        limit in 0.002f64..0.9,
        zeta in 0.0f64..0.5,
    ) {
        let law = crate::motion::NAMES[li];
        let f = LawForce::new(law).unwrap();
        let t = min_tau(law, limit, zeta).unwrap();
        prop_assert!(t > 0.0);
        let r = f.residual_ratio(t, zeta).unwrap();
        prop_assert!((r - limit).abs() <= 1e-9 * limit, "R({}) = {}", t, r);
        for i in 1..600 {
            let tau = t + 0.037 * i as f64;
            prop_assert!(f.residual_ratio(tau, zeta).unwrap() <= limit * (1.0 + 1e-9));
        }
    }
}

/// R's envelope for a law: the small-τ value where the law's force has not yet
/// averaged out, then c/τ² (every built-in law's z' is continuous).
fn envelope(tau: f64, zeta: f64) -> f64 {
    (1.0 / ((1.0 - zeta) * (1.0 + zeta)).sqrt()).min(100.0 / (tau * tau))
}

#[test]
fn closed_forms_match_the_sampled_duhamel_path() {
    for law in crate::motion::NAMES {
        let closed = ClosedResidual::new(law).unwrap();
        let sampled = LawForce::new(law).unwrap();
        for zeta in [0.0, 0.01, 0.2, 0.7, 0.99] {
            let mut worst: f64 = 0.0;
            for i in 0..300 {
                // 1e-3 to 200, log-spaced, plus the resonances of the sines.
                let tau = 1e-3 * (2e5f64).powf(i as f64 / 299.0);
                let (c, s) = (
                    closed.ratio(tau, zeta),
                    sampled.residual_ratio(tau, zeta).unwrap(),
                );
                worst = worst.max((c - s).abs() / envelope(tau, zeta));
            }
            for k in 1..=12 {
                let tau = PI * k as f64;
                let (c, s) = (
                    closed.ratio(tau, zeta),
                    sampled.residual_ratio(tau, zeta).unwrap(),
                );
                worst = worst.max((c - s).abs() / envelope(tau, zeta));
            }
            // The sampled path's own error (O(h⁴τ²) after extrapolation) dominates.
            assert!(worst < 1e-8, "{law} zeta {zeta}: {worst}");
        }
    }
}

#[test]
fn closed_cycloidal_is_the_textbook_form() {
    let closed = ClosedResidual::new("cycloidal").unwrap();
    for i in 1..=4000 {
        let tau = 0.05 * i as f64 + 1e-3;
        let env = 8.0 * PI * PI / (tau * (4.0 * PI * PI - tau * tau).abs());
        let r = closed.ratio(tau, 0.0);
        assert!(
            (r - cycloidal(tau)).abs() <= 1e-13 * env.min(1.0),
            "{tau}: {r}"
        );
    }
    // Through the resonance τ = 2π (a removable 0/0) and on its zeros.
    // The textbook form's limit: 8π²·(|τ − 2π|/2)/(2π·4π·|τ − 2π|) = 1/2.
    let at = 0.5;
    let r = closed.ratio(TAU, 0.0);
    assert!((r - at).abs() < 1e-14, "{r} {at}");
    // Near it the textbook form itself loses digits (sin(τ/2), 4π² − τ²): R
    // moves by O(τ − 2π) from 1/2 there, and the textbook form serves farther out.
    for d in [1e-12, 1e-9, 1e-6] {
        for t in [TAU * (1.0 + d), TAU * (1.0 - d)] {
            let r = closed.ratio(t, 0.0);
            assert!((r - at).abs() < 2.0 * d + 1e-14, "{t}: {r}");
        }
    }
    for t in [TAU * (1.0 + 1e-3), TAU * (1.0 - 1e-3)] {
        let want = cycloidal(t);
        assert!((closed.ratio(t, 0.0) - want).abs() < 1e-11 * want, "{t}");
    }
    for k in 2..=40 {
        assert!(closed.ratio(TAU * k as f64, 0.0) < 1e-15);
    }
}

#[test]
fn closed_small_and_huge_tau() {
    for law in crate::motion::NAMES {
        let closed = ClosedResidual::new(law).unwrap();
        for zeta in [0.0f64, 0.5, 0.999] {
            let want = 1.0 / ((1.0 - zeta) * (1.0 + zeta)).sqrt();
            for tau in [1e-150, 1e-9, 1e-4] {
                let r = closed.ratio(tau, zeta);
                // R = |λ|·|1 + O(λ)|/ω_d: within O(τ) of the limit.
                assert!(
                    (r - want).abs() <= tau * want + 1e-14 * want,
                    "{law} {tau}: {r}"
                );
            }
            for tau in [1e6, 1e12, 1e150] {
                let r = closed.ratio(tau, zeta);
                assert!(r.is_finite() && r <= 1e-6, "{law} {tau}: {r}");
            }
        }
    }
}

proptest! {
    #[test]
    fn closed_matches_sampled(law in 0usize..6, tau in 0.01f64..150.0, zeta in 0.0f64..0.995) {
        let name = crate::motion::NAMES[law];
        let c = ClosedResidual::new(name).unwrap().ratio(tau, zeta);
        let s = LawForce::new(name).unwrap().residual_ratio(tau, zeta).unwrap();
        prop_assert!((c - s).abs() <= 1e-8 * envelope(tau, zeta), "{} {} {}: {} {}", name, tau, zeta, c, s);
    }
}

#[test]
fn cycloidal_real_form_equals_the_general_pieces() {
    let closed = ClosedResidual::new("cycloidal").unwrap();
    for zeta in [0.0, 0.05, 0.5, 0.99] {
        for i in 0..2000 {
            let tau = 1e-4 * (1e8f64).powf(i as f64 / 1999.0);
            let (a, b) = (closed.ratio(tau, zeta), closed.general(tau, zeta));
            assert!(
                (a - b).abs() <= 1e-12 * envelope(tau, zeta),
                "{tau} {zeta}: {a} {b}"
            );
        }
    }
    let taus: Vec<f64> = (1..=1000)
        .map(|i| 0.1 * i as f64)
        .chain([3e6, 1e9])
        .collect();
    let mut out = vec![0.0; taus.len()];
    closed.fill(&taus, 0.05, &mut out);
    for (t, o) in taus.iter().zip(&out) {
        assert!(
            (o - closed.ratio(*t, 0.05)).abs() <= 1e-14 * o.max(1e-300),
            "{t}"
        );
    }
}

/// Time per τ of each law's closed form (run by hand:
/// `cargo test --release -p cyclomech-core closed_timing -- --ignored --nocapture`).
#[test]
#[ignore]
fn closed_timing() {
    let taus: Vec<f64> = (0..100_000)
        .map(|i| 0.5 + 99.5 * i as f64 / 99_999.0)
        .collect();
    let mut out = vec![0.0; taus.len()];
    for law in crate::motion::NAMES {
        let closed = ClosedResidual::new(law).unwrap();
        let mut best = f64::INFINITY;
        for _ in 0..20 {
            let t0 = std::time::Instant::now();
            closed.fill(&taus, 0.05, &mut out);
            best = best.min(t0.elapsed().as_secs_f64());
        }
        println!("{law}: {:.1} ns per tau", best / taus.len() as f64 * 1e9);
    }
}

#[test]
fn a_bad_thread_count_is_an_error_for_any_batch() {
    let mut out = [0.0; 2];
    assert!(residual_ratio_batch("cycloidal", &[1.0, 2.0], 0.1, Some(0), &mut out).is_err());
}
