//! The single case's chunked scan ([`scan`]) against the sequential recurrence
//! ([`run`]) and against closed forms.

use super::*;
use proptest::prelude::*;

/// The sequential loop's (q, v) and the scan's, on one grid and force.
fn both(t: &[f64], f: &[f64], osc: &Oscillator, q0: f64, v0: f64) -> [Vec<f64>; 4] {
    let n = t.len();
    let (mode, inv_m) = (osc.mode(), 1.0 / osc.mass);
    let (mut q, mut v) = (vec![0.0; n], vec![0.0; n]);
    run(t, f, &mode, inv_m, q0, v0, &mut q, Some(&mut v)).unwrap();
    let (mut qs, mut vs) = (vec![f64::NAN; n], vec![f64::NAN; n]);
    assert!(scan::<true>(t, f, &mode, inv_m, (q0, v0), &mut qs, &mut vs));
    [q, v, qs, vs]
}

/// max |a − b| / max |b|.
fn rel(a: &[f64], b: &[f64]) -> f64 {
    let peak = b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
        / peak
}

/// max |a − b| / scale.
fn abs_err(a: &[f64], b: &[f64], scale: f64) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
        / scale
}

/// max |x|.
fn peak(a: &[f64]) -> f64 {
    a.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// np.linspace-like grid: t_k = t0 + k·h rounded, steps a few ulps apart.
fn grid(n: usize, t0: f64, h: f64) -> Vec<f64> {
    (0..n).map(|k| t0 + h * k as f64).collect()
}

#[test]
fn step_force_matches_the_closed_form_and_the_sequential_loop() {
    // A unit step from rest, undamped: q = (1 − cos ωt)/(mω²).
    let (w, m) = (2.0 * std::f64::consts::PI * 297.0, 7.4e-3);
    let osc = Oscillator::new(w, 0.0, m).unwrap();
    let n = 10_001;
    let t = grid(n, 0.0, 2e-6);
    let f = vec![1.0; n];
    let [q, v, qs, vs] = both(&t, &f, &osc, 0.0, 0.0);
    let exact: Vec<f64> = t
        .iter()
        .map(|&x| (1.0 - (w * x).cos()) / (m * w * w))
        .collect();
    let dexact: Vec<f64> = t.iter().map(|&x| (w * x).sin() / (m * w)).collect();
    assert!(rel(&qs, &q) < 1e-12, "{}", rel(&qs, &q));
    assert!(rel(&vs, &v) < 1e-12);
    assert!(rel(&qs, &exact) < 1e-12, "{}", rel(&qs, &exact));
    assert!(rel(&vs, &dexact) < 1e-12, "{}", rel(&vs, &dexact));
}

#[test]
fn short_ragged_or_jumping_grids_are_left_to_the_sequential_loop() {
    let osc = Oscillator::new(100.0, 0.1, 1.0).unwrap();
    let (mode, inv_m) = (osc.mode(), 1.0);
    let go = |t: &[f64], f: &[f64]| {
        let n = t.len();
        scan::<false>(t, f, &mode, inv_m, (0.0, 0.0), &mut vec![0.0; n], &mut [])
    };
    let n = SCAN * SCAN_MIN_BLOCK + 1;
    let t = grid(n, 0.0, 1e-4);
    let f = vec![1.0; n];
    assert!(go(&t, &f));
    // Too short.
    assert!(!go(&t[..n - 2], &f[..n - 2]));
    // A repeated time (a force jump), a ragged step, a NaN time, a NaN force.
    for (i, bad) in [(500, t[499]), (700, t[700] + 1e-9), (900, f64::NAN)] {
        let mut tb = t.clone();
        tb[i] = bad;
        assert!(!go(&tb, &f), "t[{i}] = {bad}");
    }
    let mut fb = f.clone();
    fb[333] = f64::NAN;
    assert!(!go(&t, &fb));
    let mut fb = f.clone();
    fb[n - 1] = f64::INFINITY;
    assert!(!go(&t, &fb));
}

#[test]
fn lightly_damped_million_steps_stay_on_the_closed_form() {
    // ζ = 1e-4, 1e6 steps of a free vibration from q0 = 1: the stitching's
    // Φ(T) must not add error growth to the sequential loop's.
    let (w, z) = (2.0 * std::f64::consts::PI * 297.0, 1e-4);
    let osc = Oscillator::new(w, z, 1.0).unwrap();
    let n = 1_000_001;
    let t = grid(n, 0.0, 2e-6);
    let f = vec![0.0; n];
    let [q, _, qs, _] = both(&t, &f, &osc, 1.0, 0.0);
    let (s, wd) = (z * w, w * (1.0 - z * z).sqrt());
    let exact: Vec<f64> = t
        .iter()
        .map(|&x| (-s * x).exp() * ((wd * x).cos() + s / wd * (wd * x).sin()))
        .collect();
    let (e_seq, e_scan) = (rel(&q, &exact), rel(&qs, &exact));
    eprintln!(
        "1e6 steps: sequential {e_seq:.2e}, scan {e_scan:.2e}, apart {:.2e}",
        rel(&qs, &q)
    );
    assert!(e_scan <= 2.0 * e_seq + 1e-13, "{e_scan} vs {e_seq}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Damping from none to heavy, steps from 1e-4 to 2 radians of the
    /// natural period, smooth and rough forces, any start, block sizes with
    /// and without steps left over: the scan is the sequential loop to 1e-12
    /// of the state's peak (max |q| + max |v|/ω), in q and in v/ω.
    #[test]
    fn the_scan_is_the_sequential_loop_up_to_rounding(
        zeta in prop_oneof![Just(0.0), Just(1.0), 0.0f64..0.2, 0.2f64..3.0],
        wh in 1e-4f64..2.0,
        log_omega in 0.0f64..4.0,
        extra in 0usize..3000,
        shape in 0usize..3,
        seed in any::<u64>(),
        q0 in -1.0f64..1.0,
        v0 in -1.0f64..1.0,
        t0 in -1.0f64..1.0,
    ) {
        let omega = 10f64.powf(log_omega);
        let osc = Oscillator::new(omega, zeta, 0.3).unwrap();
        let n = SCAN * SCAN_MIN_BLOCK + 1 + extra;
        let t = grid(n, t0, wh / omega);
        let mut state = seed | 1;
        let mut rnd = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let f: Vec<f64> = match shape {
            0 => vec![1.0; n],
            1 => t.iter().map(|&x| (x - t0) * omega).collect(),
            _ => (0..n).map(|_| rnd()).collect(),
        };
        let [q, v, qs, vs] = both(&t, &f, &osc, q0 / omega, v0);
        // Errors on the state's scale: q and v/ω exchange through the
        // oscillation, so an error of ε·|q| in q is one of ε·ω|q| in v.
        let scale = peak(&q) + peak(&v) / omega;
        let (eq, ev) = (abs_err(&qs, &q, scale), abs_err(&vs, &v, omega * scale));
        prop_assert!(eq < 1e-12 && ev < 1e-12, "q: {:e}, v: {:e}", eq, ev);
    }
}

#[test]
fn every_instruction_set_agrees() {
    let osc = Oscillator::new(500.0, 0.02, 1.0).unwrap();
    let (mode, n) = (osc.mode(), 4001);
    let t = grid(n, 0.0, 1e-4);
    let f: Vec<f64> = t.iter().map(|&x| (700.0 * x).sin()).collect();
    let drift = Drift::new(&mode, t[1] - t[0], 1.0).unwrap();
    let m = (n - 1) / SCAN;
    let q0: [f64; SCAN] = std::array::from_fn(|l| l as f64 * 1e-3);
    let all = on_each_isa!(|s| {
        let mut q = vec![0.0; n];
        let out = pulp::WithSimd::with_simd(
            ScanPass::<false> {
                t: &t,
                force: &f,
                m,
                drift: &drift,
                q0,
                v0: [0.0; SCAN],
                q_out: &mut q,
                v_out: &mut [],
            },
            s,
        );
        (q, out)
    });
    let (q_ref, end) = &all[0].1;
    assert!(end.ok);
    for (isa, (q, end)) in &all {
        assert!(end.ok, "{isa}");
        assert!(
            rel(&q[1..SCAN * m + 1], &q_ref[1..SCAN * m + 1]) < 1e-13,
            "{isa}"
        );
    }
}

/// Timing of the two paths on the benchmark's grid (ignored: run with
/// `cargo test --release -p cyclomech-core scan_timing -- --ignored --nocapture`).
#[test]
#[ignore]
fn scan_timing() {
    let (w, m) = (2.0 * std::f64::consts::PI * 297.0, 7.4e-3);
    let osc = Oscillator::new(w, 0.05, m).unwrap();
    let (mode, inv_m) = (osc.mode(), 1.0 / m);
    let n = 10_001;
    let t = grid(n, 0.0, 2e-6);
    let f: Vec<f64> = t
        .iter()
        .map(|&x| 3.5 * (1.0 - x / t[325]).max(0.0))
        .collect();
    let mut q = vec![0.0; n];
    let best = |g: &mut dyn FnMut()| {
        (0..2000)
            .map(|_| {
                let s = std::time::Instant::now();
                g();
                s.elapsed().as_secs_f64()
            })
            .fold(f64::INFINITY, f64::min)
    };
    let seq = best(&mut || run(&t, &f, &mode, inv_m, 0.0, 0.0, &mut q, None).unwrap());
    let sc = best(&mut || {
        assert!(scan::<false>(
            &t,
            &f,
            &mode,
            inv_m,
            (0.0, 0.0),
            &mut q,
            &mut []
        ))
    });
    eprintln!("sequential {:.2} us, scan {:.2} us", seq * 1e6, sc * 1e6);
}
