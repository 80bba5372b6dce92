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

/// A grid of steps h·(1 + jitter·sin k) from t0: each step within the drift's
/// 2⁻²⁷ of h when |jitter| is, but the offsets within a block wander by up to
/// about jitter·h·√m-ish amounts (sin k sums stay bounded by ~2).
fn wobbly(n: usize, t0: f64, h: f64, jitter: f64) -> Vec<f64> {
    let mut t = Vec::with_capacity(n);
    let mut x = t0;
    for k in 0..n {
        t.push(x);
        x += h * (1.0 + jitter * (k as f64 * 0.7).sin().signum());
    }
    t
}

#[test]
fn the_free_table_is_the_closed_form_transition() {
    // Φ((k + 1)·h̄) by the fine × coarse products, as the free-motion pass
    // applies them, against mode.phi itself, on the state's scale (Φ01 times
    // ω and Φ10 over ω, as q against v/ω).
    for (w, z, h, m) in [
        (1866.0, 0.05, 2e-6, 1250),
        (100.0, 0.0, 1e-2, 1250),
        (100.0, 1.0, 1e-2, 5000),
        (10.0, 3.0, 1e-2, 777),
        (1866.0, 1e-4, 2e-6, 125_000),
        (50.0, 0.1, 1e-3, 128),
    ] {
        let mode = Oscillator::new(w, z, 1.0).unwrap().mode();
        let free = Free::new(&mode, h, m);
        assert_eq!(free.r % 8, 0);
        let mut worst = 0.0f64;
        for k in 0..m {
            // Φ((k + 1)·h̄) column by column: the motion from (1, 0) and (0, 1).
            let (p00, p10) = free.eval(&mode, k, 0.0, (1.0, 0.0));
            let (p01, p11) = free.eval(&mode, k, 0.0, (0.0, 1.0));
            let (e00, e01, e11) = mode.phi((k + 1) as f64 * h);
            let e = (p00 - e00).abs()
                + w * (p01 - e01).abs()
                + (p11 - e11).abs()
                + (p10 + mode.w2 * e01).abs() / w;
            // The reference's own argument (k + 1)·h̄ rounds, by ε·rate·(k + 1)·h̄
            // in the phase; the products' about 2√m rounding errors.
            let j = (k + 1) as f64;
            let tol = 3.0 * (4.0 * (m as f64).sqrt() + 2.0 * mode.rate * j * h);
            worst = worst.max(e / (tol * f64::EPSILON));
        }
        assert!(worst < 1.0, "{w} {z} {m}: {worst}");
    }
}

#[test]
fn a_drifting_grid_reruns_its_blocks_and_stays_exact() {
    // Steps within 2⁻²⁷ of h (so the scan runs) whose offsets drift past the
    // first-order shift's 2⁻²⁶/rate: the second lane pass, same accuracy.
    let osc = Oscillator::new(1000.0, 0.02, 0.5).unwrap();
    let (mode, inv_m) = (osc.mode(), 2.0);
    let n = 4001;
    for jitter in [2f64.powi(-29), 2f64.powi(-45), 0.0] {
        let t = wobbly(n, 0.25, 1e-4, jitter);
        let f: Vec<f64> = t.iter().map(|&x| (900.0 * x).sin()).collect();
        let [q, v, qs, vs] = both(&t, &f, &osc, 1e-3, 0.2);
        let scale = peak(&q) + peak(&v) / 1000.0;
        let (eq, ev) = (abs_err(&qs, &q, scale), abs_err(&vs, &v, 1000.0 * scale));
        assert!(
            eq < 1e-13 && ev < 1e-13,
            "jitter {jitter:e}: q {eq:e}, v {ev:e}"
        );
        // Without v, q is the same bit for bit.
        let mut q2 = vec![f64::NAN; n];
        assert!(scan::<false>(
            &t,
            &f,
            &mode,
            inv_m,
            (1e-3, 0.2),
            &mut q2,
            &mut []
        ));
        assert_eq!(q2, qs);
    }
    // Beyond 2⁻²⁷ a step: the sequential loop's.
    let t = wobbly(n, 0.25, 1e-4, 2f64.powi(-26));
    let f = vec![1.0; n];
    let mut q = vec![0.0; n];
    assert!(!scan::<false>(
        &t,
        &f,
        &mode,
        inv_m,
        (0.0, 0.0),
        &mut q,
        &mut []
    ));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// The lane pass from rest plus the free-motion correction, around the
    /// scan's threshold (N = 1025) and above, on rounded, slightly wobbly
    /// (first-order shift) and drifting (second lane pass) grids, with and
    /// without v: the sequential loop to 1e-12 of the state's scale; below the
    /// threshold the scan declines.
    #[test]
    fn the_corrected_scan_is_the_sequential_loop(
        zeta in prop_oneof![Just(0.0), Just(1.0), 0.0f64..0.3, 0.3f64..4.0],
        wh in 1e-4f64..2.0,
        log_omega in -1.0f64..5.0,
        n in prop_oneof![1000usize..1050, 1050usize..6000],
        jitter in prop_oneof![Just(0.0), 0.0f64..1e-13, 1e-9f64..7e-9],
        seed in any::<u64>(),
        q0 in -1.0f64..1.0,
        v0 in -1.0f64..1.0,
        t0 in -10.0f64..10.0,
    ) {
        let omega = 10f64.powf(log_omega);
        let osc = Oscillator::new(omega, zeta, 2.0).unwrap();
        let (mode, inv_m) = (osc.mode(), 0.5);
        let t = wobbly(n, t0, wh / omega, jitter);
        let mut state = seed | 1;
        let f: Vec<f64> = (0..n)
            .map(|_| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
            })
            .collect();
        let (q0, v0) = (q0 / omega, v0);
        let (mut qs, mut vs) = (vec![f64::NAN; n], vec![f64::NAN; n]);
        let ran = scan::<true>(&t, &f, &mode, inv_m, (q0, v0), &mut qs, &mut vs);
        // Steps of the rounded grid itself differ from h̄ by ulps of t.
        let hbar = t[1] - t[0];
        let tol = hbar.min(1.0 / mode.rate) * 2f64.powi(-27);
        let ragged = t.windows(2).any(|w| ((w[1] - w[0]) - hbar).abs() > tol);
        prop_assert_eq!(ran, n > SCAN * SCAN_MIN_BLOCK && !ragged);
        if ran {
            let (mut q, mut v) = (vec![0.0; n], vec![0.0; n]);
            run(&t, &f, &mode, inv_m, q0, v0, &mut q, Some(&mut v)).unwrap();
            let scale = peak(&q) + peak(&v) / omega;
            let (eq, ev) = (abs_err(&qs, &q, scale), abs_err(&vs, &v, omega * scale));
            prop_assert!(eq < 1e-12 && ev < 1e-12, "q: {:e}, v: {:e}", eq, ev);
            let mut q2 = vec![f64::NAN; n];
            prop_assert!(scan::<false>(&t, &f, &mode, inv_m, (q0, v0), &mut q2, &mut []));
            prop_assert_eq!(q2, qs);
        }
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

#[test]
fn every_instruction_set_corrects_alike() {
    // The free-motion pass on each instruction set (its vector code and the
    // table's) against the scalar one, with and without v.
    let osc = Oscillator::new(700.0, 0.03, 1.0).unwrap();
    let (mode, n) = (osc.mode(), 4001);
    let t = wobbly(n, 0.5, 1e-4, 2f64.powi(-45));
    let m = (n - 1) / SCAN;
    let free = Free::new(&mode, t[1] - t[0], m);
    let sq: [f64; SCAN] = std::array::from_fn(|l| (l as f64 - 3.0) * 1e-3);
    let sv: [f64; SCAN] = std::array::from_fn(|l| 0.1 * l as f64);
    let all = on_each_isa!(|s| {
        let (mut q, mut v) = (vec![1.0; n], vec![-1.0; n]);
        pulp::WithSimd::with_simd(
            Correct::<true> {
                t: &t,
                m,
                free: &free,
                mode: &mode,
                hbar: t[1] - t[0],
                sq,
                sv,
                q_out: &mut q,
                v_out: &mut v,
            },
            s,
        );
        let mut q1 = vec![1.0; n];
        pulp::WithSimd::with_simd(
            Correct::<false> {
                t: &t,
                m,
                free: &free,
                mode: &mode,
                hbar: t[1] - t[0],
                sq,
                sv,
                q_out: &mut q1,
                v_out: &mut [],
            },
            s,
        );
        assert_eq!(q1, q);
        (q, v)
    });
    let (q_ref, v_ref) = &all[0].1;
    for (isa, (q, v)) in &all {
        assert!(rel(q, q_ref) < 1e-14 && rel(v, v_ref) < 1e-14, "{isa}");
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
    // The two paths alternate, so that both see the same machine (shared
    // and noisy): minimum and median of each, and the ratio of medians.
    let (mut seq, mut sc) = (Vec::new(), Vec::new());
    let time = |g: &mut dyn FnMut()| {
        let s = std::time::Instant::now();
        g();
        s.elapsed().as_secs_f64() * 1e6
    };
    for _ in 0..5000 {
        seq.push(time(&mut || {
            run(&t, &f, &mode, inv_m, 0.0, 0.0, &mut q, None).unwrap()
        }));
        sc.push(time(&mut || {
            assert!(scan::<false>(
                &t,
                &f,
                &mode,
                inv_m,
                (0.0, 0.0),
                &mut q,
                &mut []
            ))
        }));
    }
    seq.sort_by(f64::total_cmp);
    sc.sort_by(f64::total_cmp);
    let (ms, mc) = (seq[seq.len() / 2], sc[sc.len() / 2]);
    eprintln!(
        "sequential {:.2} / {ms:.2} us, scan {:.2} / {mc:.2} us (min / median), scan / sequential {:.3}",
        seq[0],
        sc[0],
        mc / ms
    );
}

#[test]
fn steps_too_short_for_the_drift_bound_go_the_sequential_way() {
    // The lane pass bounds max|d| by √(Σ d²), which needs tol ≥ 2⁻⁵⁰⁰ (no
    // square of a d that matters underflows); below, the sequential loop.
    let osc = Oscillator::new(2.0, 0.1, 1.0).unwrap();
    let mode = osc.mode();
    assert!(Drift::new(&mode, 1e-150, 1.0).is_none());
    assert!(Drift::new(&mode, 1e-130, 1.0).is_some());
    let n = 2001;
    let t = grid(n, 0.0, 1e-150);
    let f = vec![1.0; n];
    let mut q = vec![0.0; n];
    assert!(!scan::<false>(
        &t,
        &f,
        &mode,
        1.0,
        (1.0, 0.0),
        &mut q,
        &mut []
    ));
}

#[test]
fn the_drift_derivative_is_the_central_difference() {
    // dc/dh by the equation of motion against the central difference of two
    // closed-form steps at h ± η (the earlier way), each coefficient on its
    // own scale: |Δc1|·h against max(|c|, |c(h+η)−c(h−η)|·h/2η).
    let all = |s: Step| [s.p00, s.p01, s.p10, s.p11, s.g0q, s.g0v, s.g1q, s.g1v];
    for (w, z, h, m) in [
        (1866.0, 0.05, 2e-6, 7.4e-3),
        (100.0, 0.0, 1e-2, 1.0),
        (100.0, 1.0, 1e-2, 2.0),
        (10.0, 3.0, 5e-2, 0.3),
        (1.0, 0.01, 1.9, 1.0),
        (1e4, 0.7, 1e-7, 1e-3),
    ] {
        let mode = Oscillator::new(w, z, m).unwrap().mode();
        let drift = Drift::new(&mode, h, 1.0 / m).unwrap();
        let eta = h.min(1.0 / mode.rate) * 2f64.powi(-17);
        let (a, b) = (
            all(Step::new(&mode, h + eta, 1.0 / m)),
            all(Step::new(&mode, h - eta, 1.0 / m)),
        );
        let c = all(Step::new(&mode, h, 1.0 / m));
        assert_eq!(drift.c0, c);
        for i in 0..8 {
            let cd = (a[i] - b[i]) / (2.0 * eta);
            let scale = c[i].abs().max(cd.abs() * h);
            let e = (drift.c1[i] - cd).abs() * h / scale;
            assert!(
                e < 1e-7,
                "{w} {z} {h}: c1[{i}] {} vs {cd}: {e:e}",
                drift.c1[i]
            );
        }
    }
}
