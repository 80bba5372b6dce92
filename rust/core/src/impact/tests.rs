use std::f64::consts::PI;

use super::contact::*;
use super::error::*;
use super::oscillator::*;
use super::*;
use crate::input::InvalidInput;

/// Issue 16 item 15: a ramp of 1e9 N/s over 1 ns (c = slope/(mω²) = 1e9
/// against q̇ ~ 1e-10) hung with `maximum` and put the minimum inside the
/// ramp without. By hand (Taylor): on the ramp q̇ ≈ −0.75τ + 5e8τ², still
/// −2.5e-10 at 1 ns; then q̈ ≈ 1 − 0.75 = 0.25 brings it to 0 about 1 ns
/// later: the minimum is at ≈ 2 ns, and over-damped (ζ = 10) q then creeps
/// to q_s = 1 with no maximum.
#[test]
fn item15_steep_short_ramp_neither_hangs_nor_turns_inside_the_ramp() {
    let osc = Oscillator::new(1.0, 10.0, 1.0).unwrap();
    let (t, f) = ([0.0, 1e-9], [0.0, 1.0]);
    let max = first_turn(&t, &f, &osc, 0.75, 0.0, true).unwrap();
    assert_eq!(max.time, f64::INFINITY);
    assert!((max.q - 1.0).abs() < 1e-12);
    let min = first_turn(&t, &f, &osc, 0.75, 0.0, false).unwrap();
    assert!((1.9e-9..2.1e-9).contains(&min.time), "{min:?}");
}

/// The undamped oscillator from rest at q0 under the ramp F = r·s (c = r/(mω²)):
/// q = q0 cos ωs + c (s − sin(ωs)/ω), q̇ = −q0 ω sin ωs + c (1 − cos ωs), zero
/// again where tan(ωs/2) = q0 ω/c. Returns (s*, q(s*)).
fn undamped_dip_turn(w: f64, m: f64, r: f64, q0: f64) -> (f64, f64) {
    let c = r / (m * w * w);
    let x = 2.0 * (q0 * w / c).atan();
    // x − sin x, by its series where it cancels.
    let x_sin = if x < 1e-2 {
        let x2 = x * x;
        x * x2 / 6.0 * (1.0 - x2 / 20.0 * (1.0 - x2 / 42.0))
    } else {
        x - x.sin()
    };
    (x / w, q0 * x.cos() + c * x_sin / w)
}

/// A start from rest at q0 > 0 under a ramp: q̇ dips by about q0²ω⁴m/(2r) and
/// turns back through 0 at s* ≈ 2q0mω²/r, a real minimum. The closed form
/// q̇ = c + y lost such a dip below ~1e-10·c (turn time off, or at q̇'s most
/// negative point, or a stalled maximum search); it is found on q̇/s now.
#[test]
fn shallow_dip_from_rest_turns_at_the_undamped_closed_form() {
    for (w, m) in [(1.0, 1.0), (300.0, 0.0074), (1e-3, 20.0)] {
        let osc = Oscillator::new(w, 0.0, m).unwrap();
        let ramp = 0.0078125 / w;
        let peak = m * w * w; // c = peak/(ramp m ω²) = 128 ω
        for q0 in [
            1e-2,
            0.001953125,
            1e-4,
            1e-6,
            1e-100,
            5.479484529262842e-207,
        ] {
            let (t, f) = ([0.0, ramp], [0.0, peak]);
            let (ts, qs) = undamped_dip_turn(w, m, peak / ramp, q0);
            assert!(ts < ramp);
            let r = first_rebound(&t, &f, &osc, q0, 0.0).unwrap();
            assert!(
                (r.time - ts).abs() <= 1e-9 * ts,
                "ω {w}, q0 {q0}: {} vs {ts}",
                r.time
            );
            assert!(
                (r.q - qs).abs() <= 1e-12 * qs,
                "ω {w}, q0 {q0}: q {} vs {qs}",
                r.q
            );
        }
    }
}

/// The same dip over-damped, with `maximum`: the dip's minimum is passed over
/// and q then creeps to q_s = 1 with no maximum, as from q0 = 0 or q0 < 0
/// (the search used to stall on the dip it could not see).
#[test]
fn shallow_dip_from_rest_overdamped_has_no_maximum() {
    let osc = Oscillator::new(1.0, 10.0, 1.0).unwrap();
    let (t, f) = ([0.0, 0.0078125], [0.0, 1.0]);
    for q0 in [1.8e-5, 1e-6, 1e-8, 5.479484529262842e-207] {
        for q in [q0, 0.0, -q0] {
            let r = first_turn(&t, &f, &osc, q, 0.0, true).unwrap();
            assert_eq!(r.time, f64::INFINITY, "q0 {q}");
            assert!((r.q - 1.0).abs() < 1e-12, "q0 {q}: {r:?}");
        }
        // The minimum itself: at −2a/j = 2q0/(128 + 20q0), to O(ζωs*).
        let r = first_turn(&t, &f, &osc, q0, 0.0, false).unwrap();
        let ts = 2.0 * q0 / (128.0 + 20.0 * q0);
        assert!(
            (r.time - ts).abs() <= 1e-4 * ts,
            "q0 {q0}: {} vs {ts}",
            r.time
        );
    }
}

/// Issue 16 item 15: k/m overflowing hung the crossing search; ω outside
/// [1e-150, 1e150] rad/s is refused.
#[test]
fn item15_overflowing_k_over_m_is_refused() {
    let stop = Contact {
        mass: 1e-300,
        k_free: 1e300,
        k_stop: 1e300,
        preload: 0.1,
        zeta_free: 0.0,
        zeta_contact: 0.0,
    };
    let e = contact_response(&stop, 1.0, -1.0, f64::INFINITY, 3, 100).unwrap_err();
    assert!(matches!(
        e,
        ImpactError::Param {
            field: "sqrt(k_free / mass)",
            ..
        }
    ));
}
use proptest::prelude::*;

// ---------------------------------------------------------------------
// Independent references: textbook closed forms, one per damping case.

/// Free vibration from (q0, v0), written out per damping case.
fn free(w: f64, z: f64, q0: f64, v0: f64, t: f64) -> (f64, f64) {
    if z < 1.0 {
        let (sg, wd) = (z * w, w * (1.0 - z * z).sqrt());
        let (a, b) = (q0, (v0 + sg * q0) / wd);
        let e = (-sg * t).exp();
        let (c, s) = ((wd * t).cos(), (wd * t).sin());
        let q = e * (a * c + b * s);
        let v = e * ((-sg * a + wd * b) * c + (-sg * b - wd * a) * s);
        (q, v)
    } else if z == 1.0 {
        let b = v0 + w * q0;
        let e = (-w * t).exp();
        (e * (q0 + b * t), e * (b - w * (q0 + b * t)))
    } else {
        let r = w * (z * z - 1.0).sqrt();
        let (r1, r2) = (-z * w + r, -z * w - r);
        let a = (v0 - r2 * q0) / (r1 - r2);
        let b = q0 - a;
        let (e1, e2) = ((r1 * t).exp(), (r2 * t).exp());
        (a * e1 + b * e2, a * r1 * e1 + b * r2 * e2)
    }
}

/// Response from rest to a step F0 applied at t = 0.
fn step_ref(w: f64, z: f64, m: f64, f0: f64, t: f64) -> (f64, f64) {
    let qs = f0 / (m * w * w);
    let (q, v) = free(w, z, -qs, 0.0, t);
    (qs + q, v)
}

/// Response from rest to the ramp F = r·t.
fn ramp_ref(w: f64, z: f64, m: f64, r: f64, t: f64) -> (f64, f64) {
    let k = m * w * w;
    let (qp, vp) = ((r / k) * (t - 2.0 * z / w), r / k);
    let (q, v) = free(w, z, 2.0 * z * r / (k * w), -r / k, t);
    (qp + q, vp + v)
}

fn respond(t: &[f64], f: &[f64], osc: &Oscillator, q0: f64, v0: f64) -> (Vec<f64>, Vec<f64>) {
    let (mut q, mut v) = (vec![0.0; t.len()], vec![0.0; t.len()]);
    response_into(t, f, osc, q0, v0, &mut q, Some(&mut v)).unwrap();
    (q, v)
}

/// max |a − b| over max |b|.
fn rel_err(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
        / scale
}

fn coarse(w: f64, periods: f64) -> Vec<f64> {
    // 10 steps per natural period.
    let h = 2.0 * PI / w / 10.0;
    (0..=(10.0 * periods) as usize)
        .map(|k| k as f64 * h)
        .collect()
}

/// Non-uniform, with repeated times and long and short steps.
fn ragged(w: f64, t_end: f64) -> Vec<f64> {
    let mut t = vec![0.0];
    let mut k = 0usize;
    while *t.last().unwrap() < t_end {
        k += 1;
        let h = match k % 7 {
            0 => 0.0,
            1 => 1.7,
            2 => 0.013,
            3 => 0.61,
            4 => 2.9,
            5 => 0.2,
            _ => 0.0071,
        } / w;
        t.push(t.last().unwrap() + h);
    }
    t
}

const ZETAS: [f64; 4] = [0.0, 0.05, 1.0, 2.0];

#[test]
fn free_vibration_matches_closed_forms() {
    for &z in &ZETAS {
        for (w, m) in [(1.0, 1.0), (37.0, 0.2)] {
            let osc = Oscillator::new(w, z, m).unwrap();
            for t in [coarse(w, 6.0), ragged(w, 40.0 / w)] {
                let (q0, v0) = (0.3, -1.7 * w);
                let (q, v) = respond(&t, &vec![0.0; t.len()], &osc, q0, v0);
                let rq: Vec<f64> = t.iter().map(|&x| free(w, z, q0, v0, x).0).collect();
                let rv: Vec<f64> = t.iter().map(|&x| free(w, z, q0, v0, x).1).collect();
                assert!(
                    rel_err(&q, &rq) < 1e-12,
                    "z {z} w {w}: q {}",
                    rel_err(&q, &rq)
                );
                assert!(
                    rel_err(&v, &rv) < 1e-12,
                    "z {z} w {w}: v {}",
                    rel_err(&v, &rv)
                );
            }
        }
    }
}

#[test]
fn step_and_ramp_match_closed_forms() {
    for &z in &ZETAS {
        let (w, m) = (12.0, 0.7);
        let osc = Oscillator::new(w, z, m).unwrap();
        for t in [coarse(w, 5.0), ragged(w, 30.0 / w)] {
            // The step starts at t[0]: a jump of the force at the start.
            let (q, v) = respond(&t, &vec![2.5; t.len()], &osc, 0.0, 0.0);
            let r: Vec<(f64, f64)> = t.iter().map(|&x| step_ref(w, z, m, 2.5, x)).collect();
            let (rq, rv): (Vec<f64>, Vec<f64>) = r.into_iter().unzip();
            assert!(rel_err(&q, &rq) < 1e-12, "step z {z}: {}", rel_err(&q, &rq));
            assert!(rel_err(&v, &rv) < 1e-12, "step z {z}: {}", rel_err(&v, &rv));
            // A ramp is linear on any grid: exact with first-order hold.
            let f: Vec<f64> = t.iter().map(|&x| -3.0 * x).collect();
            let (q, v) = respond(&t, &f, &osc, 0.0, 0.0);
            let r: Vec<(f64, f64)> = t.iter().map(|&x| ramp_ref(w, z, m, -3.0, x)).collect();
            let (rq, rv): (Vec<f64>, Vec<f64>) = r.into_iter().unzip();
            assert!(rel_err(&q, &rq) < 1e-12, "ramp z {z}: {}", rel_err(&q, &rq));
            assert!(rel_err(&v, &rv) < 1e-12, "ramp z {z}: {}", rel_err(&v, &rv));
        }
    }
}

#[test]
fn start_time_shifts_the_response() {
    let osc = Oscillator::new(5.0, 0.1, 1.0).unwrap();
    let t: Vec<f64> = (0..60).map(|k| 1000.0 + 0.1 * k as f64).collect();
    let (q, _) = respond(&t, &vec![1.0; 60], &osc, 0.0, 0.0);
    let rq: Vec<f64> = t
        .iter()
        .map(|&x| step_ref(5.0, 0.1, 1.0, 1.0, x - 1000.0).0)
        .collect();
    assert!(rel_err(&q, &rq) < 1e-12);
}

#[test]
fn repeated_time_is_a_jump() {
    let (w, z, m, f0) = (3.0, 0.2, 2.0, 4.0);
    let osc = Oscillator::new(w, z, m).unwrap();
    // Force 0 until 0.5, then F0: the jump at the repeated time.
    let t = [0.0, 0.5, 0.5, 0.9, 3.0];
    let (q, v) = respond(&t, &[0.0, 0.0, f0, f0, f0], &osc, 0.0, 0.0);
    assert_eq!(
        (q[1], v[1]),
        (q[2], v[2]),
        "a zero-length step keeps the state"
    );
    for k in 0..t.len() {
        let (rq, rv) = step_ref(w, z, m, f0, (t[k] - 0.5).max(0.0));
        assert!(
            (q[k] - rq).abs() < 1e-13 && (v[k] - rv).abs() < 1e-13,
            "{k}"
        );
    }
    // A rectangular pulse F0 on [0, τ): step(t) − step(t − τ).
    let tau = 0.4;
    let t = [0.0, tau, tau, 2.0, 5.0];
    let (q, _) = respond(&t, &[f0, f0, 0.0, 0.0, 0.0], &osc, 0.0, 0.0);
    for k in 0..t.len() {
        let mut r = step_ref(w, z, m, f0, t[k]).0;
        if t[k] >= tau {
            r -= step_ref(w, z, m, f0, t[k] - tau).0;
        }
        assert!((q[k] - r).abs() < 1e-13, "{k}: {} vs {r}", q[k]);
    }
}

#[test]
fn continuous_across_critical_damping() {
    let (w, m) = (7.0, 1.3);
    let t = ragged(w, 25.0 / w);
    let f: Vec<f64> = t.iter().map(|&x| (2.0 - x).max(0.0)).collect();
    let at = |z: f64| respond(&t, &f, &Oscillator::new(w, z, m).unwrap(), 0.1, 0.4);
    let (q1, v1) = at(1.0);
    for z in [1.0 - 1e-9, 1.0 + 1e-9, 1.0 - 1e-7, 1.0 + 1e-7] {
        let (q, v) = at(z);
        let d = (z - 1.0f64).abs();
        assert!(rel_err(&q, &q1) < 10.0 * d, "z {z}: q {}", rel_err(&q, &q1));
        assert!(rel_err(&v, &v1) < 10.0 * d, "z {z}: v {}", rel_err(&v, &v1));
    }
    // Every coefficient, for steps from tiny to long.
    for h in [1e-6, 0.1, 1.0, 30.0] {
        let c = Step::new(&Mode::new(w, 1.0), h, 1.0);
        for z in [1.0 - 1e-9, 1.0 + 1e-9] {
            let d = Step::new(&Mode::new(w, z), h, 1.0);
            let (a, b) = (
                [
                    c.p00,
                    c.p01 * w,
                    c.p10 / w,
                    c.p11,
                    c.g0q * w * w,
                    c.g0v * w,
                    c.g1q * w * w,
                    c.g1v * w,
                ],
                [
                    d.p00,
                    d.p01 * w,
                    d.p10 / w,
                    d.p11,
                    d.g0q * w * w,
                    d.g0v * w,
                    d.g1q * w * w,
                    d.g1v * w,
                ],
            );
            let err = a
                .iter()
                .zip(&b)
                .fold(0.0f64, |e, (x, y)| e.max((x - y).abs()));
            assert!(err < 1e-8, "h {h} z {z}: {err}");
        }
    }
}

#[test]
fn large_damping_and_long_steps_stay_finite_and_exact() {
    // ζ = 50 and ω·h up to 1e4: no overflow, and the static deflection.
    for z in [0.0, 0.5, 1.0, 50.0] {
        let osc = Oscillator::new(100.0, z, 1.0).unwrap();
        let t = [0.0, 1e-5, 0.5, 100.0];
        let (q, v) = respond(&t, &[1.0, 1.0, 1.0, 1.0], &osc, 0.0, 0.0);
        assert!(q.iter().chain(&v).all(|x| x.is_finite()));
        if z > 0.0 {
            assert!((q[3] - 1e-4).abs() < 1e-15, "z {z}: {}", q[3]);
        }
    }
}

fn cases_of<'a>(
    w: &'a [f64],
    z: &'a [f64],
    m: &'a [f64],
    q0: &'a [f64],
    v0: &'a [f64],
) -> Cases<'a> {
    Cases {
        omega_n: w,
        zeta: z,
        mass: m,
        q0,
        v0,
    }
}

/// The batch, on one and two threads, equals each case run alone, bit for bit.
fn batch_is_single(t: &[f64], forces: &[f64], cases: &Cases<'_>) {
    let (b, n) = (cases.omega_n.len(), t.len());
    for threads in [1, 2] {
        let mut out = vec![0.0; b * n];
        response_batch_into(t, forces, cases, Some(threads), &mut out).unwrap();
        for i in 0..b {
            let osc = Oscillator::new(cases.omega_n[i], cases.zeta[i], cases.mass[i]).unwrap();
            let row = &forces[i * n..(i + 1) * n];
            let (q, _) = respond(t, row, &osc, cases.q0[i], cases.v0[i]);
            assert_eq!(
                &out[i * n..(i + 1) * n],
                &q[..],
                "case {i}, {threads} threads"
            );
        }
    }
}

#[test]
fn batch_equals_single() {
    let t = ragged(5.0, 20.0);
    let n = t.len();
    let w = [5.0, 1.0, 30.0, 2.0, 9.0, 4.0, 0.3];
    let z = [0.0, 0.05, 1.0, 2.5, 0.7, 1.0 + 1e-9, 3.0];
    let m = [1.0, 2.0, 0.5, 1.0, 3.0, 1.0, 0.1];
    let q0 = [0.0, 0.1, -0.2, 0.0, 1.0, 0.0, 0.3];
    let v0 = [1.0, 0.0, 0.5, -2.0, 0.0, 0.1, 0.0];
    let forces: Vec<f64> = (0..w.len() * n)
        .map(|i| ((i * 7919) % 13) as f64 - 6.0)
        .collect();
    let cases = cases_of(&w, &z, &m, &q0, &v0);
    batch_is_single(&t, &forces, &cases);
    // First rebounds too.
    let k = 4;
    let tk = [0.0, 0.01, 0.03, 0.03];
    let pulses: Vec<f64> = (0..w.len())
        .flat_map(|i| [0.0, 3.0 + i as f64, 1.0, 0.0])
        .collect();
    for threads in [1, 2] {
        let (mut tt, mut qq) = (vec![0.0; w.len()], vec![0.0; w.len()]);
        first_rebound_batch_into(&tk, &pulses, &cases, false, Some(threads), &mut tt, &mut qq)
            .unwrap();
        for i in 0..w.len() {
            let osc = Oscillator::new(w[i], z[i], m[i]).unwrap();
            let r = first_rebound(&tk, &pulses[i * k..(i + 1) * k], &osc, q0[i], v0[i]).unwrap();
            assert_eq!((tt[i], qq[i]), (r.time, r.q), "case {i}");
        }
    }
}

#[test]
fn lockstep_batch_equals_single() {
    // A linspace-like grid (a few step lengths ulps apart) with a repeated
    // time (a force jump), and 2·LOCK + 3 cases: two lockstep groups and a
    // remainder, every damping regime in each group.
    let mut t: Vec<f64> = (0..400).map(|k| k as f64 * (0.02 / 399.0)).collect();
    t.insert(150, t[150]);
    let n = t.len();
    let grid = GridSteps::new(&t).unwrap();
    assert!(grid.hs.len() > 2 && grid.hs.contains(&0.0), "{:?}", grid.hs);
    let b = 2 * LOCK + 3;
    let w: Vec<f64> = (0..b).map(|i| 200.0 + 97.0 * i as f64).collect();
    let z: Vec<f64> = (0..b).map(|i| [0.0, 0.05, 1.0, 2.5, 0.7][i % 5]).collect();
    let m: Vec<f64> = (0..b).map(|i| 0.1 + 0.3 * i as f64).collect();
    let q0: Vec<f64> = (0..b).map(|i| 1e-3 * (i as f64 - 9.0)).collect();
    let v0: Vec<f64> = (0..b).map(|i| 0.1 * (i % 3) as f64).collect();
    let forces: Vec<f64> = (0..b * n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
    let cases = cases_of(&w, &z, &m, &q0, &v0);
    batch_is_single(&t, &forces, &cases);
    // The lockstep loop compiled for each instruction set the processor has.
    {
        use pulp::Simd;
        let grid = GridSteps::new(&t).unwrap();
        let (coef, lane_q0, lane_v0) = lane_steps(&grid, &cases, 0).unwrap();
        let runs = on_each_isa!(|simd| {
            let mut out = vec![0.0; LOCK * n];
            Simd::vectorize(
                simd,
                Lockstep {
                    which: &grid.which,
                    coef: &coef,
                    forces: &forces[..LOCK * n],
                    out: &mut out,
                    q0: lane_q0,
                    v0: lane_v0,
                },
            );
            out
        });
        for (isa, out) in runs {
            for i in 0..LOCK {
                let osc = Oscillator::new(w[i], z[i], m[i]).unwrap();
                let (q, _) = respond(&t, &forces[i * n..(i + 1) * n], &osc, q0[i], v0[i]);
                assert_eq!(&out[i * n..(i + 1) * n], &q[..], "{isa}: case {i}");
            }
        }
    }
    // A bad force or case inside a lockstep group is reported by its row.
    for (row, col) in [(10, 7), (3, n - 1)] {
        let mut bad = forces.clone();
        bad[row * n + col] = f64::INFINITY;
        for threads in [1, 2] {
            let mut out = vec![0.0; b * n];
            let e = response_batch_into(&t, &bad, &cases, Some(threads), &mut out);
            assert_eq!(
                e.unwrap_err().to_string(),
                format!("case {row}: force[{col}] must be finite; got inf")
            );
        }
    }
    let mut zb = z.clone();
    zb[12] = f64::NAN;
    let e = response_batch_into(
        &t,
        &forces,
        &cases_of(&w, &zb, &m, &q0, &v0),
        Some(2),
        &mut vec![0.0; b * n],
    );
    assert_eq!(
        e.unwrap_err().to_string(),
        "case 12: zeta must be finite and >= 0; got NaN"
    );
    // A graded grid (every step its own length) goes case by case.
    let graded: Vec<f64> = (0..1000).map(|k| (k as f64).powf(1.5)).collect();
    assert!(GridSteps::new(&graded).is_none());
}

/// The grid's step table against a plain search of the distinct lengths in
/// the order first seen: linspace-like grids (lengths ulps apart), repeated
/// times (h = 0), exactly MAX_DISTINCT lengths and one more.
#[test]
fn grid_steps_are_the_distinct_lengths_in_order() {
    fn by_search(t: &[f64]) -> (Vec<f64>, Vec<u32>) {
        let (mut hs, mut which) = (Vec::<f64>::new(), Vec::new());
        for w in t.windows(2) {
            let h = w[1] - w[0];
            let i = match hs.iter().position(|x| x.to_bits() == h.to_bits()) {
                Some(i) => i,
                None => {
                    hs.push(h);
                    hs.len() - 1
                }
            };
            which.push(i as u32);
        }
        (hs, which)
    }
    let mut lin: Vec<f64> = (0..10_001).map(|k| k as f64 * 2e-6).collect();
    lin.insert(77, lin[77]);
    lin.insert(5000, lin[5000]);
    // 255 and 256 distinct lengths (+ the zero of the repeated time), then 257.
    let sums = |d: usize| -> Vec<f64> {
        let mut t = vec![0.0, 0.0];
        for k in 0..3 * d {
            t.push(t.last().unwrap() + 1.0 + (k % (d - 1)) as f64);
        }
        t
    };
    for t in [lin, sums(255), sums(256)] {
        let g = GridSteps::new(&t).unwrap();
        let (hs, which) = by_search(&t);
        assert!(hs.len() <= 256 && hs.len() > 15, "{}", hs.len());
        assert_eq!(
            g.hs.iter().map(|h| h.to_bits()).collect::<Vec<_>>(),
            hs.iter().map(|h| h.to_bits()).collect::<Vec<_>>()
        );
        assert_eq!(g.which, which);
    }
    assert!(GridSteps::new(&sums(257)).is_none());
}

#[test]
fn batch_errors_name_the_case() {
    let t = [0.0, 0.1, 0.2];
    let w = [1.0; 4];
    let m = [1.0; 4];
    let zero = [0.0; 4];
    let mut forces = vec![0.0; 12];
    forces[2 * 3 + 1] = f64::NAN;
    let cases = cases_of(&w, &zero, &m, &zero, &zero);
    for threads in [1, 2] {
        let mut out = vec![0.0; 12];
        let e = response_batch_into(&t, &forces, &cases, Some(threads), &mut out).unwrap_err();
        assert!(
            matches!(&e, ImpactError::Case { row: 2, error } if matches!(**error, ImpactError::NotFinite { field: "force", index: 1, .. })),
            "{e}"
        );
        assert_eq!(e.to_string(), "case 2: force[1] must be finite; got NaN");
        let (mut a, mut b) = (vec![0.0; 4], vec![0.0; 4]);
        let e = first_rebound_batch_into(&t, &forces, &cases, false, Some(threads), &mut a, &mut b)
            .unwrap_err();
        assert!(matches!(e, ImpactError::Case { row: 2, .. }), "{e}");
    }
    let z = [0.0, 0.0, 0.0, -0.1];
    let e = response_batch_into(
        &t,
        &[0.0; 12],
        &cases_of(&w, &z, &m, &zero, &zero),
        None,
        &mut [0.0; 12],
    )
    .unwrap_err();
    assert_eq!(
        e.to_string(),
        "case 3: zeta must be finite and >= 0; got -0.1"
    );
    let e = response_batch_into(
        &t,
        &[0.0; 12],
        &cases_of(&w, &zero[..3], &m, &zero, &zero),
        None,
        &mut [0.0; 12],
    )
    .unwrap_err();
    assert!(
        matches!(
            e,
            ImpactError::Length {
                field: "zeta",
                got: 3,
                ..
            }
        ),
        "{e}"
    );
    let e = response_batch_into(&t, &[0.0; 11], &cases, None, &mut [0.0; 12]).unwrap_err();
    assert!(
        matches!(
            e,
            ImpactError::Length {
                field: "forces",
                ..
            }
        ),
        "{e}"
    );
    let e = response_batch_into(&[0.0, 0.2, 0.1], &[0.0; 12], &cases, None, &mut [0.0; 12])
        .unwrap_err();
    assert!(matches!(e, ImpactError::Decreasing { index: 2, .. }), "{e}");
    let e = response_batch_into(&t, &[0.0; 12], &cases, Some(0), &mut [0.0; 12]).unwrap_err();
    assert!(
        matches!(e, ImpactError::Input(InvalidInput::Threads(_))),
        "{e}"
    );
}

#[test]
fn input_errors_are_typed_and_name_the_field() {
    let osc = Oscillator::new(2.0, 0.1, 1.0).unwrap();
    let mut q = [0.0; 3];
    let run = |t: &[f64], f: &[f64], o: &Oscillator, q0: f64, q: &mut [f64]| {
        response_into(t, f, o, q0, 0.0, q, None).unwrap_err()
    };
    let t = [0.0, 0.1, 0.2];
    let f = [0.0, 1.0, 0.0];
    let e = run(&[0.0, 0.2, 0.1], &f, &osc, 0.0, &mut q);
    assert_eq!(
        e.to_string(),
        "t must be non-decreasing (a repeated time is a jump of the force); got t[2] = 0.1 after t[1] = 0.2"
    );
    let e = run(&[0.0, f64::NAN, 0.1], &f, &osc, 0.0, &mut q);
    assert!(
        matches!(
            e,
            ImpactError::NotFinite {
                field: "t",
                index: 1,
                ..
            }
        ),
        "{e}"
    );
    let e = run(&[0.0, 0.1, f64::INFINITY], &f, &osc, 0.0, &mut q);
    assert!(
        matches!(
            e,
            ImpactError::NotFinite {
                field: "t",
                index: 2,
                ..
            }
        ),
        "{e}"
    );
    let e = run(&[f64::NAN], &[0.0], &osc, 0.0, &mut q[..1]);
    assert!(matches!(e, ImpactError::Param { field: "t[0]", .. }), "{e}");
    let e = run(&[-1e308, 1e308, 1e308], &f, &osc, 0.0, &mut q);
    assert!(
        matches!(e, ImpactError::StepOverflow { index: 1, .. }),
        "{e}"
    );
    let e = run(&t, &[0.0, f64::NAN, 0.0], &osc, 0.0, &mut q);
    assert_eq!(e.to_string(), "force[1] must be finite; got NaN");
    let e = run(&[0.0], &[f64::NAN], &osc, 0.0, &mut q[..1]);
    assert!(
        matches!(
            e,
            ImpactError::NotFinite {
                field: "force",
                index: 0,
                ..
            }
        ),
        "{e}"
    );
    let e = run(&t, &[0.0, 0.0, f64::NEG_INFINITY], &osc, 0.0, &mut q);
    assert!(
        matches!(
            e,
            ImpactError::NotFinite {
                field: "force",
                index: 2,
                ..
            }
        ),
        "{e}"
    );
    let e = run(
        &t,
        &[0.0, 1e308, 1e308],
        &Oscillator::new(1e-3, 0.0, 1e-300).unwrap(),
        0.0,
        &mut q,
    );
    assert!(matches!(e, ImpactError::Overflow { .. }), "{e}");
    let e = run(&t, &f[..2], &osc, 0.0, &mut q);
    assert!(
        matches!(
            e,
            ImpactError::Length {
                field: "force",
                got: 2,
                ..
            }
        ),
        "{e}"
    );
    let e = run(&t, &f, &osc, 0.0, &mut q[..2]);
    assert!(
        matches!(e, ImpactError::Length { field: "q_out", .. }),
        "{e}"
    );
    let e = run(&[], &[], &osc, 0.0, &mut q[..0]);
    assert!(
        matches!(
            e,
            ImpactError::Length {
                field: "t",
                got: 0,
                ..
            }
        ),
        "{e}"
    );
    let e = run(&t, &f, &osc, f64::NAN, &mut q);
    assert!(matches!(e, ImpactError::Param { field: "q0", .. }), "{e}");
    let e = response_into(&t, &f, &osc, 0.0, 0.0, &mut q, Some(&mut [0.0; 2])).unwrap_err();
    assert!(
        matches!(e, ImpactError::Length { field: "v_out", .. }),
        "{e}"
    );
    for (w, z, m, field) in [
        (0.0, 0.1, 1.0, "omega_n"),
        (-1.0, 0.1, 1.0, "omega_n"),
        (f64::INFINITY, 0.1, 1.0, "omega_n"),
        (1.0, -0.1, 1.0, "zeta"),
        (1.0, f64::NAN, 1.0, "zeta"),
        (1.0, 0.1, 0.0, "mass"),
        (1.0, 0.1, -2.0, "mass"),
        (1.0, 0.1, f64::NAN, "mass"),
    ] {
        let e = Oscillator::new(w, z, m).unwrap_err();
        assert!(
            matches!(e, ImpactError::Param { field: f, .. } if f == field),
            "{e}"
        );
        let o = Oscillator {
            omega_n: w,
            zeta: z,
            mass: m,
        };
        assert!(response_into(&t, &f, &o, 0.0, 0.0, &mut q, None).is_err());
        assert!(first_rebound(&t, &f, &o, 0.0, 0.0).is_err());
    }
    assert_eq!(
        Oscillator::new(1.0, -0.1, 1.0).unwrap_err().to_string(),
        "zeta must be finite and >= 0; got -0.1"
    );
    // first_rebound checks its table up front.
    assert!(matches!(
        first_rebound(&[0.0, 0.2, 0.1], &f, &osc, 0.0, 0.0),
        Err(ImpactError::Decreasing { index: 2, .. })
    ));
    assert!(matches!(
        first_rebound(&t, &[0.0, f64::INFINITY, 0.0], &osc, 0.0, 0.0),
        Err(ImpactError::NotFinite { index: 1, .. })
    ));
    assert!(matches!(
        first_rebound(&[], &[], &osc, 0.0, 0.0),
        Err(ImpactError::Length { .. })
    ));
    assert!(matches!(
        first_rebound(&t, &f[..1], &osc, 0.0, 0.0),
        Err(ImpactError::Length { .. })
    ));
    assert!(matches!(
        first_rebound(&t, &f, &osc, 0.0, f64::NAN),
        Err(ImpactError::Param { field: "v0", .. })
    ));
}

// ---------------------------------------------------------------------
// First rebound.

#[test]
fn first_maximum_passes_over_minima() {
    // Undamped free vibration from q = 0 moving down at 1: the first turn is
    // the minimum −1/ω at a quarter period, the first maximum +1/ω at three.
    let w = 5.0;
    let osc = Oscillator::new(w, 0.0, 1.0).unwrap();
    let r = first_turn(&[0.0], &[0.0], &osc, 0.0, -1.0, true).unwrap();
    assert!((r.time - 1.5 * PI / w).abs() < 1e-14 && (r.q - 1.0 / w).abs() < 1e-15);
    let r = first_turn(&[0.0], &[0.0], &osc, 0.0, -1.0, false).unwrap();
    assert!((r.time - 0.5 * PI / w).abs() < 1e-14 && (r.q + 1.0 / w).abs() < 1e-15);
    // A link pressed into its stop and thrown back by a rectangular pulse: the
    // minimum falls inside the pulse, the maximum after it; against a fine
    // history scan.
    let osc = Oscillator::new(2.0 * PI * 297.0, 0.05, 7.4e-3).unwrap();
    let (tau, v0) = (6.5e-4, 0.2);
    let force = 7.4e-3 * (1.0 + 5.0 / 9.0) * v0 / tau;
    let r = first_turn(&[0.0, tau, tau], &[force, force, 0.0], &osc, 0.0, -v0, true).unwrap();
    // The scan's grid holds τ twice, so that its force jumps there too.
    let (n1, n2) = (13_001, 187_001);
    let dt = (0.01 - tau) / (n2 - 1) as f64;
    let mut t: Vec<f64> = (0..n1).map(|i| tau * i as f64 / (n1 - 1) as f64).collect();
    t.extend((0..n2).map(|i| tau + dt * i as f64));
    let mut f = vec![force; n1];
    f.extend(vec![0.0; n2]);
    let n = t.len();
    let mut q = vec![0.0; n];
    response_into(&t, &f, &osc, 0.0, -v0, &mut q, None).unwrap();
    let i_min = (1..n).find(|&i| q[i] > q[i - 1]).unwrap();
    let i_max = (i_min..n).find(|&i| q[i] < q[i - 1]).unwrap() - 1;
    assert!(t[i_min] < tau && t[i_max] > tau);
    assert!(
        (r.time - t[i_max]).abs() < 2.0 * dt,
        "{} vs {}",
        r.time,
        t[i_max]
    );
    // The scan misses the top by at most (ω·dt)²/2 of it.
    assert!(
        r.q >= q[i_max] && r.q - q[i_max] < 1e-8 * r.q.abs(),
        "{} vs {}",
        r.q,
        q[i_max]
    );
}

#[test]
fn first_rebound_closed_forms() {
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-13 * b.abs().max(1.0);
    // Free vibration released from q0: the far side after half a damped period.
    for z in [0.0f64, 0.05, 0.5] {
        let (w, q0) = (4.0, 0.3);
        let wd = w * (1.0 - z * z).sqrt();
        let osc = Oscillator::new(w, z, 1.0).unwrap();
        let r = first_rebound(&[0.0], &[0.0], &osc, q0, 0.0).unwrap();
        assert!(close(r.time, PI / wd), "z {z}: {}", r.time);
        assert!(close(r.q, -q0 * (-z * w * PI / wd).exp()), "z {z}: {}", r.q);
    }
    // A step from rest: the overshoot 1 + e^{−σπ/ωd} of the static deflection.
    for z in [0.0f64, 0.1] {
        let (w, m, f0) = (10.0, 2.0, 5.0);
        let wd = w * (1.0 - z * z).sqrt();
        let osc = Oscillator::new(w, z, m).unwrap();
        let r = first_rebound(&[0.0, 1.0], &[f0, f0], &osc, 0.0, 0.0).unwrap();
        assert!(close(r.time, PI / wd), "{}", r.time);
        let qs = f0 / (m * w * w);
        assert!(close(r.q, qs * (1.0 + (-z * w * PI / wd).exp())), "{}", r.q);
    }
    // An undamped ramp from rest: q̇ = c(1 − cos ωt) touches zero at 2π/ω.
    let (w, r) = (3.0, 2.0);
    let osc = Oscillator::new(w, 0.0, 1.0).unwrap();
    let tt = 10.0 * 2.0 * PI / w;
    let reb = first_rebound(&[0.0, tt], &[0.0, r * tt], &osc, 0.0, 0.0).unwrap();
    assert!((reb.time - 2.0 * PI / w).abs() < 1e-7, "{}", reb.time);
    assert!(close(reb.q, r / (w * w) * 2.0 * PI / w), "{}", reb.q);
    // No extremum ever: at rest, or an over-damped creep; q is the limit.
    let osc = Oscillator::new(2.0, 2.0, 1.0).unwrap();
    let r = first_rebound(&[0.0, 1.0], &[0.0, 0.0], &osc, 0.0, 0.0).unwrap();
    assert_eq!((r.time, r.q), (f64::INFINITY, 0.0));
    let r = first_rebound(&[0.0, 1.0], &[0.0, 0.0], &osc, 1.0, 0.0).unwrap();
    assert_eq!((r.time, r.q), (f64::INFINITY, 0.0));
    let r = first_rebound(&[0.0, 1.0], &[0.0, 8.0], &osc, 0.0, 0.0).unwrap();
    assert_eq!(r.time, f64::INFINITY);
    assert!(close(r.q, 2.0), "static deflection {}", r.q);
    // At rest under a preload until a pulse comes: the rest stays exact, and
    // the first extremum is that of the pulse's response.
    let osc = Oscillator::new(3.0, 0.0, 1.0).unwrap();
    let qs = 0.7 / 9.0;
    let r = first_rebound(&[0.0, 1.3, 1.3, 5.0], &[0.7, 0.7, 1.7, 1.7], &osc, qs, 0.0).unwrap();
    assert!(close(r.time, 1.3 + PI / 3.0), "{}", r.time);
    assert!(close(r.q, qs + 2.0 / 9.0), "{}", r.q);
    // An over-damped overshoot: critically damped from q0 = 1 with v0 = −5ω.
    for z in [1.0, 1.5] {
        let osc = Oscillator::new(2.0, z, 1.0).unwrap();
        let r = first_rebound(&[0.0], &[0.0], &osc, 1.0, -10.0).unwrap();
        let v = free(2.0, z, 1.0, -10.0, r.time).1;
        assert!(r.time.is_finite() && v.abs() < 1e-13, "z {z}: v {v}");
        assert!(close(r.q, free(2.0, z, 1.0, -10.0, r.time).0));
    }
}

#[test]
fn first_rebound_continuous_across_critical_damping() {
    let f = [0.0, 5.0, 0.0, 0.0];
    let t = [0.0, 0.05, 0.1, 0.1];
    let at =
        |z: f64| first_rebound(&t, &f, &Oscillator::new(6.0, z, 1.0).unwrap(), 1.0, -20.0).unwrap();
    let r1 = at(1.0);
    assert!(r1.time.is_finite());
    for z in [1.0 - 1e-9, 1.0 + 1e-9] {
        let r = at(z);
        assert!(
            (r.time - r1.time).abs() < 1e-8 * r1.time,
            "{} vs {}",
            r.time,
            r1.time
        );
        assert!(
            (r.q - r1.q).abs() < 1e-8 * r1.q.abs(),
            "{} vs {}",
            r.q,
            r1.q
        );
    }
}

/// F(x) of a pulse table (held after its last sample; right limit at jumps).
fn force_at(t: &[f64], f: &[f64], x: f64) -> f64 {
    if x >= t[t.len() - 1] {
        return f[f.len() - 1];
    }
    let j = t.partition_point(|&y| y <= x) - 1;
    let (t0, t1) = (t[j], t[j + 1]);
    if t1 == t0 {
        f[j + 1]
    } else {
        f[j] + (f[j + 1] - f[j]) * (x - t0) / (t1 - t0)
    }
}

/// (q, q̇) at x by the recurrence over the table cut at x (no segment scan).
fn state_at(t: &[f64], f: &[f64], osc: &Oscillator, q0: f64, v0: f64, x: f64) -> (f64, f64) {
    let mut tt: Vec<f64> = t.iter().copied().filter(|&y| y < x).collect();
    let mut ff: Vec<f64> = f[..tt.len()].to_vec();
    tt.push(x);
    ff.push(force_at(t, f, x));
    let (q, v) = respond(&tt, &ff, osc, q0, v0);
    (q[q.len() - 1], v[v.len() - 1])
}

/// An independent search: the recurrence on a dense grid (each segment cut in
/// 200, then 20,000 steps to t_max), returning the grid and the first cell
/// [g[k−1], g[k]] where q̇ returns to zero or changes sign, if any.
fn dense_scan(
    t: &[f64],
    f: &[f64],
    osc: &Oscillator,
    q0: f64,
    v0: f64,
    t_max: f64,
) -> (Vec<f64>, Option<usize>) {
    let t_last = t[t.len() - 1];
    let (mut g, mut gf) = (vec![t[0]], vec![f[0]]);
    for j in 1..t.len() {
        let (a, b) = (t[j - 1], t[j]);
        let pieces = if b > a { 200 } else { 1 };
        for p in 1..=pieces {
            let u = p as f64 / pieces as f64;
            g.push(if p == pieces { b } else { a + (b - a) * u });
            gf.push(if p == pieces {
                f[j]
            } else {
                f[j - 1] + (f[j] - f[j - 1]) * u
            });
        }
    }
    for p in 1..=20_000 {
        g.push(t_last + (t_max - t_last) * p as f64 / 20_000.0);
        gf.push(f[f.len() - 1]);
    }
    let (_, v) = respond(&g, &gf, osc, q0, v0);
    let mut s = sign(v0);
    for (k, &vk) in v.iter().enumerate().skip(1) {
        if s == 0.0 {
            s = sign(vk);
        } else if s * vk <= 0.0 {
            return (g, Some(k));
        }
    }
    (g, None)
}

/// Bisection and Newton steps on q̇(x) computed by [`state_at`].
fn refine(
    t: &[f64],
    f: &[f64],
    osc: &Oscillator,
    q0: f64,
    v0: f64,
    mut lo: f64,
    mut hi: f64,
) -> f64 {
    let s = sign(state_at(t, f, osc, q0, v0, lo).1);
    let mut x = 0.5 * (lo + hi);
    for _ in 0..200 {
        let (q, v) = state_at(t, f, osc, q0, v0, x);
        if s * v > 0.0 {
            lo = x
        } else {
            hi = x
        }
        let a = force_at(t, f, x) / osc.mass
            - 2.0 * osc.zeta * osc.omega_n * v
            - osc.omega_n.powi(2) * q;
        let xn = x - v / a;
        let xn = if xn > lo && xn < hi {
            xn
        } else {
            0.5 * (lo + hi)
        };
        if (xn - x).abs() <= 1e-15 * x.abs() {
            return xn;
        }
        x = xn;
    }
    x
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// The dip from rest under a ramp against the undamped closed form, over
    /// depths from well inside the closed form's reach to below a float's.
    #[test]
    fn shallow_dip_from_rest_matches_the_undamped_closed_form(
        w in 1e-3f64..1e4,
        m in 1e-3f64..1e3,
        log_q0 in -300.0f64..-1.0,
        steps in 1.0f64..8.0,
    ) {
        let osc = Oscillator::new(w, 0.0, m).unwrap();
        let ramp = 2f64.powf(-steps) / w;
        let peak = m * w * w;
        let q0 = 10f64.powf(log_q0) / w;
        let (ts, qs) = undamped_dip_turn(w, m, peak / ramp, q0);
        prop_assume!(ts < 0.5 * ramp);
        let r = first_rebound(&[0.0, ramp], &[0.0, peak], &osc, q0, 0.0).unwrap();
        prop_assert!((r.time - ts).abs() <= 1e-9 * ts, "{} vs {ts}", r.time);
        prop_assert!((r.q - qs).abs() <= 1e-12 * qs, "q {} vs {qs}", r.q);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    #[test]
    fn first_rebound_matches_a_dense_scan(
        w in 1.0f64..20.0,
        z in prop_oneof![Just(0.0), 0.0f64..1.2, Just(1.0)],
        durations in prop::collection::vec(0.0f64..0.4, 2..5),
        heights in prop::collection::vec(-1.0f64..3.0, 5),
        q0 in prop_oneof![Just(0.0), -0.05f64..0.05],
        v0 in prop_oneof![Just(0.0), -1.0f64..1.0],
    ) {
        let osc = Oscillator::new(w, z, 0.5).unwrap();
        let mut t = vec![0.0];
        for d in &durations {
            t.push(t.last().unwrap() + d / w);
        }
        let mut f: Vec<f64> = heights[..t.len()].to_vec();
        *f.last_mut().unwrap() = 0.0; // a pulse: free vibration afterwards
        let r = first_rebound(&t, &f, &osc, q0, v0).unwrap();
        let t_max = t[t.len() - 1] + 40.0 / w;
        let (g, cell) = dense_scan(&t, &f, &osc, q0, v0, t_max);
        let Some(k) = cell else {
            prop_assert!(r.time > t_max, "kernel {} but the scan finds no extremum before {}", r.time, t_max);
            return Ok(());
        };
        // Not after the scan's first sign change.
        prop_assert!(r.time <= g[k] * (1.0 + 1e-12), "kernel {} after the scan's cell [{}, {}]", r.time, g[k - 1], g[k]);
        let (q, v) = state_at(&t, &f, &osc, q0, v0, r.time);
        let vscale = v0.abs().max(heights.iter().fold(0.0f64, |m, h| m.max(h.abs())) / (0.5 * w)).max(q0.abs() * w);
        prop_assert!(v.abs() <= 1e-9 * vscale, "q̇({}) = {} (scale {})", r.time, v, vscale);
        prop_assert!((r.q - q).abs() <= 1e-12 * (vscale / w).max(q.abs()), "q {} vs {}", r.q, q);
        if r.time >= g[k - 1] {
            // The same cell: the kernel's root and an independent refinement agree.
            let x = refine(&t, &f, &osc, q0, v0, g[k - 1], g[k]);
            prop_assert!((r.time - x).abs() <= 1e-10 * t_max, "time {} vs refined {}", r.time, x);
        } else {
            // An earlier extremum inside one scan cell (a short bump of q̇): q̇
            // has opposite signs just before and after it.
            let d = 1e-6 * (g[k] - g[k - 1]).min(r.time - t[0]);
            let (vb, va) = (state_at(&t, &f, &osc, q0, v0, r.time - d).1, state_at(&t, &f, &osc, q0, v0, r.time + d).1);
            prop_assert!(vb * va < 0.0, "no sign change around {}: {} then {}", r.time, vb, va);
        }
    }

    #[test]
    fn recurrence_matches_rk4(
        w in 0.5f64..20.0,
        z in 0.0f64..3.0,
        steps in prop::collection::vec(0.0f64..1.5, 1..6),
        forces in prop::collection::vec(-2.0f64..2.0, 7),
        q0 in -1.0f64..1.0,
        v0 in -1.0f64..1.0,
    ) {
        let m = 0.8;
        let osc = Oscillator::new(w, z, m).unwrap();
        let mut t = vec![0.25];
        for h in &steps {
            t.push(t.last().unwrap() + h / w);
        }
        let f = &forces[..t.len()];
        let (q, v) = respond(&t, f, &osc, q0, v0 * w);
        // RK4 with tiny steps on the piecewise-linear force: independent of Φ, Γ.
        let (mut x, mut y) = (q0, v0 * w);
        let acc = |x: f64, y: f64, p: f64| p / m - 2.0 * z * w * y - w * w * x;
        let scale = q.iter().chain(v.iter().map(|a| a / w).collect::<Vec<_>>().iter()).fold(1e-3f64, |s, a| s.max(a.abs()));
        for k in 1..t.len() {
            let h = t[k] - t[k - 1];
            let n = ((h * w * (1.0 + 2.0 * z)) / 2e-3).ceil().max(1.0) as usize;
            let dt = h / n as f64;
            let p = |s: f64| f[k - 1] + (f[k] - f[k - 1]) * s / h;
            for i in 0..n {
                let s = i as f64 * dt;
                let (k1x, k1v) = (y, acc(x, y, p(s)));
                let (k2x, k2v) = (y + 0.5 * dt * k1v, acc(x + 0.5 * dt * k1x, y + 0.5 * dt * k1v, p(s + 0.5 * dt)));
                let (k3x, k3v) = (y + 0.5 * dt * k2v, acc(x + 0.5 * dt * k2x, y + 0.5 * dt * k2v, p(s + 0.5 * dt)));
                let (k4x, k4v) = (y + dt * k3v, acc(x + dt * k3x, y + dt * k3v, p(s + dt)));
                x += dt / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
                y += dt / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
            }
            if h > 0.0 {
                prop_assert!((q[k] - x).abs() <= 1e-9 * scale, "q[{}] {} vs rk4 {}", k, q[k], x);
                prop_assert!((v[k] - y).abs() <= 1e-9 * scale * w, "v[{}] {} vs rk4 {}", k, v[k], y);
            }
        }
    }

    #[test]
    fn constant_force_is_exact(
        w in 0.5f64..50.0,
        z in prop_oneof![0.0f64..0.99, Just(1.0), 1.01f64..3.0],
        steps in prop::collection::vec(0.0f64..3.0, 1..12),
        f0 in -5.0f64..5.0,
    ) {
        let osc = Oscillator::new(w, z, 1.5).unwrap();
        let mut t = vec![0.0];
        for h in &steps {
            t.push(t.last().unwrap() + h / w);
        }
        let (q, _) = respond(&t, &vec![f0; t.len()], &osc, 0.0, 0.0);
        let r: Vec<f64> = t.iter().map(|&x| step_ref(w, z, 1.5, f0, x).0).collect();
        let scale = (f0 / (1.5 * w * w)).abs().max(1e-300);
        for k in 0..t.len() {
            prop_assert!((q[k] - r[k]).abs() <= 1e-12 * scale, "{}: {} vs {}", k, q[k], r[k]);
        }
    }
}

// ---------------------------------------------------------------------
// Contact oscillator.

fn stop(m: f64, kf: f64, ks: f64, d: f64, zf: f64, zc: f64) -> Contact {
    Contact {
        mass: m,
        k_free: kf,
        k_stop: ks,
        preload: d,
        zeta_free: zf,
        zeta_contact: zc,
    }
}

#[test]
fn undamped_contact_without_preload_conserves_energy() {
    let (m, kf, ks, v0) = (0.5, 200.0, 5000.0, -1.3);
    let c = stop(m, kf, ks, 0.0, 0.0, 0.0);
    let h = contact_response(&c, 0.0, v0, f64::INFINITY, 3, MAX_EVENTS).unwrap();
    let (wf, wc) = ((kf / m).sqrt(), ((kf + ks) / m).sqrt());
    let tc = PI / wc;
    assert_eq!(h.end, ContactEnd::MaxRebounds);
    assert_eq!(h.rebound_height.len(), 3);
    assert_eq!(h.contact_start.len(), 3);
    for i in 0..3 {
        let start = i as f64 * (tc + PI / wf);
        assert!((h.contact_start[i] - start).abs() < 1e-13, "start {i}");
        assert!((h.contact_duration[i] - tc).abs() < 1e-14, "duration {i}");
        assert!((h.exit_velocity[i] + v0).abs() < 1e-13, "exit {i}");
        assert!((h.impact_velocity[i] - v0).abs() < 1e-13, "impact {i}");
        assert!(
            (h.rebound_height[i] - v0.abs() / wf).abs() < 1e-14,
            "height {i}"
        );
        assert!((h.rebound_time[i] - (start + tc + 0.5 * PI / wf)).abs() < 1e-13);
        assert!((h.penetration[i] + v0.abs() / wc).abs() < 1e-14);
        assert!((h.penetration_time[i] - (start + 0.5 * tc)).abs() < 1e-13);
    }
    assert_eq!(
        (h.t_stop, h.x_stop, h.v_stop),
        (h.rebound_time[2], h.rebound_height[2], 0.0)
    );
    assert_eq!(h.n_events, 5);
}

#[test]
fn undamped_contact_with_preload_follows_energy() {
    let (m, kf, ks, d, v0) = (0.02, 300.0, 9000.0, 2.5e-4, -0.4);
    let c = stop(m, kf, ks, d, 0.0, 0.0);
    let h = contact_response(&c, 0.0, v0, f64::INFINITY, 2, MAX_EVENTS).unwrap();
    // ½ m v0² = ½ k_f ((x + δ)² − δ²) at the top of the rebound.
    let top = (d * d + m * v0 * v0 / kf).sqrt() - d;
    let kc = kf + ks;
    let xc = -kf * d / kc;
    let amp = (xc * xc + m * v0 * v0 / kc).sqrt();
    let phi = (xc.abs() / amp).acos();
    let wc = (kc / m).sqrt();
    for i in 0..2 {
        assert!(
            (h.exit_velocity[i] + v0).abs() < 1e-13,
            "{}",
            h.exit_velocity[i]
        );
        assert!(
            (h.rebound_height[i] - top).abs() < 1e-15 + 1e-12 * top,
            "{} vs {top}",
            h.rebound_height[i]
        );
        assert!(
            (h.penetration[i] - (xc - amp)).abs() < 1e-15,
            "{}",
            h.penetration[i]
        );
        let dur = (2.0 * PI - 2.0 * phi) / wc;
        assert!(
            (h.contact_duration[i] - dur).abs() < 1e-13 * dur,
            "{} vs {dur}",
            h.contact_duration[i]
        );
    }
}

#[test]
fn damped_contact_restitution_and_rest() {
    // δ = 0: each contact is half a damped period and scales the speed by
    // e = exp(−ζπ/√(1 − ζ²)).
    let (m, kf, ks, zc) = (1.0, 100.0, 1e4, 0.1);
    let c = stop(m, kf, ks, 0.0, 0.0, zc);
    let h = contact_response(&c, 0.0, -2.0, f64::INFINITY, 4, MAX_EVENTS).unwrap();
    let wd = ((kf + ks) / m).sqrt() * (1.0 - zc * zc).sqrt();
    let e = (-zc * PI / (1.0 - zc * zc).sqrt()).exp();
    for i in 0..4 {
        assert!((h.contact_duration[i] - PI / wd).abs() < 1e-13);
        let ratio = -h.exit_velocity[i] / h.impact_velocity[i];
        assert!((ratio - e).abs() < 1e-13, "{ratio} vs {e}");
    }
    // Over-damped contact: the link never leaves.
    let c = stop(m, kf, ks, 0.0, 0.0, 2.0);
    let h = contact_response(&c, 0.0, -2.0, f64::INFINITY, 4, MAX_EVENTS).unwrap();
    assert_eq!(h.end, ContactEnd::RestInContact);
    assert_eq!((h.t_stop, h.x_stop, h.n_events), (f64::INFINITY, 0.0, 0));
    assert!(h.contact_end.is_empty() && h.penetration.len() == 1);
    // Preload and damping: bounces die out and the link settles in contact.
    let (kf, d) = (100.0, 1e-3);
    let c = stop(m, kf, ks, d, 0.05, 0.05);
    let h = contact_response(&c, 0.0, -2.0, f64::INFINITY, 1000, MAX_EVENTS).unwrap();
    assert_eq!(h.end, ContactEnd::RestInContact);
    assert!(
        h.n_events > 2 && h.n_events.is_multiple_of(2),
        "{}",
        h.n_events
    );
    assert!((h.x_stop + kf * d / (kf + ks)).abs() < 1e-18);
    assert!(h.rebound_height.windows(2).all(|w| w[1] < w[0]));
    // A free flight that never returns: δ = 0 and an over-damped free spring.
    let c = stop(m, kf, ks, 0.0, 1.5, 0.0);
    let h = contact_response(&c, 0.0, -2.0, f64::INFINITY, 5, MAX_EVENTS).unwrap();
    assert_eq!(h.end, ContactEnd::RestFree);
    assert_eq!(
        (h.rebound_height.len(), h.contact_end.len(), h.n_events),
        (1, 1, 1)
    );
    assert_eq!((h.t_stop, h.x_stop), (f64::INFINITY, 0.0));
}

#[test]
fn resting_on_the_stop_does_not_chatter() {
    // Released at rest on the stop with a preload and no contact damping:
    // the contact oscillation touches x = 0 without leaving.
    let c = stop(1.0, 50.0, 500.0, 1e-3, 0.0, 0.0);
    let h = contact_response(&c, 0.0, 0.0, f64::INFINITY, 3, 100).unwrap();
    assert_eq!((h.end, h.n_events), (ContactEnd::RestInContact, 0));
    assert_eq!(h.contact_start, vec![0.0]);
    // No preload: at rest exactly.
    let c = stop(1.0, 50.0, 500.0, 0.0, 0.0, 0.0);
    let h = contact_response(&c, 0.0, 0.0, f64::INFINITY, 3, 100).unwrap();
    assert_eq!(
        (h.end, h.n_events, h.x_stop),
        (ContactEnd::RestInContact, 0, 0.0)
    );
}

#[test]
fn event_cap_and_t_end() {
    // δ = 0, light damping: bounces shrink geometrically at a constant rate,
    // forever: the cap ends the history and sampling past it is an error.
    let c = stop(1.0, 100.0, 1e4, 0.0, 0.01, 0.01);
    let h = contact_response(&c, 0.0, -1.0, f64::INFINITY, 1_000_000, 50).unwrap();
    assert_eq!((h.end, h.n_events), (ContactEnd::MaxEvents, 50));
    let times: Vec<f64> = (0..100).map(|k| k as f64).collect();
    let (mut x, mut v) = (vec![0.0; 100], vec![0.0; 100]);
    let e = contact_sample_into(&c, 0.0, -1.0, &times, 50, &mut x, &mut v).unwrap_err();
    assert!(
        matches!(e, ImpactError::TooManyEvents { max_events: 50, .. }),
        "{e}"
    );
    // t_end: the stop state is the sampled state at t_end.
    let t_end = 0.123;
    let h = contact_response(&c, 0.0, -1.0, t_end, 100, MAX_EVENTS).unwrap();
    assert_eq!((h.end, h.t_stop), (ContactEnd::TEnd, t_end));
    let (mut x, mut v) = ([0.0], [0.0]);
    contact_sample_into(&c, 0.0, -1.0, &[t_end], MAX_EVENTS, &mut x, &mut v).unwrap();
    assert_eq!((h.x_stop, h.v_stop), (x[0], v[0]));
    assert!(h
        .contact_start
        .iter()
        .chain(&h.rebound_time)
        .all(|&s| s <= t_end));
}

#[test]
fn samples_follow_the_events_and_an_rk4_reference() {
    let (m, kf, ks, d, zf, zc) = (0.1, 400.0, 2e4, 5e-4, 0.03, 0.08);
    let c = stop(m, kf, ks, d, zf, zc);
    let (x0, v0) = (0.0, -0.8);
    let h = contact_response(&c, x0, v0, f64::INFINITY, 50, MAX_EVENTS).unwrap();
    // At the events x = 0; at the tops ẋ = 0 and x is the height.
    let mut times: Vec<f64> = h
        .contact_start
        .iter()
        .chain(&h.contact_end)
        .chain(&h.rebound_time)
        .copied()
        .collect();
    times.sort_by(f64::total_cmp);
    let (mut x, mut v) = (vec![0.0; times.len()], vec![0.0; times.len()]);
    contact_sample_into(&c, x0, v0, &times, MAX_EVENTS, &mut x, &mut v).unwrap();
    for (k, &tk) in times.iter().enumerate() {
        if let Some(j) = h.rebound_time.iter().position(|&r| r == tk) {
            assert!(
                (x[k] - h.rebound_height[j]).abs() < 1e-16 && v[k].abs() < 1e-12,
                "top {j}"
            );
        } else {
            assert!(x[k].abs() < 1e-16, "event at {tk}: x {}", x[k]);
        }
    }
    // RK4 on the piecewise-smooth ODE, tiny steps, the regime frozen within a
    // step and each crossing located by bisection on the step's length (the
    // damping makes the acceleration jump there: without the location, RK4
    // would be first order).
    let t_end = 0.3;
    let n = 30_000;
    let dt = t_end / n as f64;
    let (cf, cc) = (
        2.0 * zf * (kf * m).sqrt(),
        2.0 * zc * ((kf + ks) * m).sqrt(),
    );
    let acc = |x: f64, v: f64, contact: bool| {
        if contact {
            (-kf * (x + d) - ks * x - cc * v) / m
        } else {
            (-kf * (x + d) - cf * v) / m
        }
    };
    let rk4 = |x: f64, v: f64, dt: f64, c: bool| {
        let (k1x, k1v) = (v, acc(x, v, c));
        let (k2x, k2v) = (
            v + 0.5 * dt * k1v,
            acc(x + 0.5 * dt * k1x, v + 0.5 * dt * k1v, c),
        );
        let (k3x, k3v) = (
            v + 0.5 * dt * k2v,
            acc(x + 0.5 * dt * k2x, v + 0.5 * dt * k2v, c),
        );
        let (k4x, k4v) = (v + dt * k3v, acc(x + dt * k3x, v + dt * k3v, c));
        (
            x + dt / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x),
            v + dt / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v),
        )
    };
    let (mut x, mut v, mut contact) = (x0, v0, true);
    let samples: Vec<f64> = (1..=30).map(|k| k as f64 * 0.01).collect();
    let (mut xs, mut vs) = (vec![0.0; 30], vec![0.0; 30]);
    contact_sample_into(&c, x0, v0, &samples, MAX_EVENTS, &mut xs, &mut vs).unwrap();
    let amp = v0.abs() / (kf / m).sqrt();
    for i in 1..=n {
        let (x1, v1) = rk4(x, v, dt, contact);
        if (x1 > 0.0) == contact {
            // Crossed x = 0 within the step: land on it, switch, finish the step.
            let (mut lo, mut hi) = (0.0, dt);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if (rk4(x, v, mid, contact).0 > 0.0) == contact {
                    hi = mid
                } else {
                    lo = mid
                }
            }
            let (_, vc) = rk4(x, v, hi, contact);
            contact = !contact;
            (x, v) = rk4(0.0, vc, dt - hi, contact);
        } else {
            (x, v) = (x1, v1);
        }
        if i % 1000 == 0 {
            let j = i / 1000 - 1;
            assert!(
                (xs[j] - x).abs() < 1e-9 * amp,
                "t {}: {} vs rk4 {x}",
                samples[j],
                xs[j]
            );
            assert!(
                (vs[j] - v).abs() < 1e-9 * v0.abs(),
                "t {}: {} vs rk4 {v}",
                samples[j],
                vs[j]
            );
        }
    }
}

#[test]
fn contact_input_errors() {
    let ok = stop(1.0, 10.0, 100.0, 0.0, 0.0, 0.0);
    for (c, field) in [
        (Contact { mass: 0.0, ..ok }, "mass"),
        (Contact { k_free: 0.0, ..ok }, "k_free"),
        (Contact { k_free: -1.0, ..ok }, "k_free"),
        (Contact { k_stop: 0.0, ..ok }, "k_stop"),
        (
            Contact {
                k_stop: f64::NAN,
                ..ok
            },
            "k_stop",
        ),
        (
            Contact {
                preload: -1e-3,
                ..ok
            },
            "preload",
        ),
        (
            Contact {
                preload: f64::INFINITY,
                ..ok
            },
            "preload",
        ),
        (
            Contact {
                zeta_free: -0.1,
                ..ok
            },
            "zeta_free",
        ),
        (
            Contact {
                zeta_contact: f64::NAN,
                ..ok
            },
            "zeta_contact",
        ),
    ] {
        let e = contact_response(&c, 0.0, -1.0, 1.0, 3, 10).unwrap_err();
        assert!(
            matches!(e, ImpactError::Param { field: f, .. } if f == field),
            "{e}"
        );
        let e = contact_sample_into(&c, 0.0, -1.0, &[0.0], 10, &mut [0.0], &mut [0.0]).unwrap_err();
        assert!(
            matches!(e, ImpactError::Param { field: f, .. } if f == field),
            "{e}"
        );
    }
    assert_eq!(
        contact_response(
            &Contact {
                preload: -1e-3,
                ..ok
            },
            0.0,
            -1.0,
            1.0,
            3,
            10
        )
        .unwrap_err()
        .to_string(),
        "preload must be finite and >= 0; got -0.001"
    );
    let e = |r: Result<ContactHistory, ImpactError>| r.unwrap_err();
    assert!(matches!(
        e(contact_response(&ok, f64::NAN, -1.0, 1.0, 3, 10)),
        ImpactError::Param { field: "x0", .. }
    ));
    assert!(matches!(
        e(contact_response(&ok, 0.0, f64::INFINITY, 1.0, 3, 10)),
        ImpactError::Param { field: "v0", .. }
    ));
    assert!(matches!(
        e(contact_response(&ok, 0.0, -1.0, 0.0, 3, 10)),
        ImpactError::Param { field: "t_end", .. }
    ));
    assert!(matches!(
        e(contact_response(&ok, 0.0, -1.0, f64::NAN, 3, 10)),
        ImpactError::Param { field: "t_end", .. }
    ));
    assert!(matches!(
        e(contact_response(&ok, 0.0, -1.0, 1.0, 0, 10)),
        ImpactError::Count {
            field: "max_rebounds",
            ..
        }
    ));
    assert!(matches!(
        e(contact_response(&ok, 0.0, -1.0, 1.0, 3, 0)),
        ImpactError::Count {
            field: "max_events",
            ..
        }
    ));
    let s =
        |t: &[f64], x: &mut [f64], v: &mut [f64]| contact_sample_into(&ok, 0.0, -1.0, t, 10, x, v);
    assert!(matches!(
        s(&[0.2, 0.1], &mut [0.0; 2], &mut [0.0; 2]),
        Err(ImpactError::Decreasing {
            field: "times",
            index: 1,
            ..
        })
    ));
    assert!(matches!(
        s(&[-0.1, 0.1], &mut [0.0; 2], &mut [0.0; 2]),
        Err(ImpactError::Param {
            field: "times[0]",
            ..
        })
    ));
    assert!(matches!(
        s(&[0.0, f64::NAN], &mut [0.0; 2], &mut [0.0; 2]),
        Err(ImpactError::NotFinite {
            field: "times",
            index: 1,
            ..
        })
    ));
    assert!(matches!(
        s(&[0.0, 0.1], &mut [0.0; 1], &mut [0.0; 2]),
        Err(ImpactError::Length { field: "x_out", .. })
    ));
    assert!(s(&[], &mut [], &mut []).is_ok());
}

// ---------------------------------------------------------------------
// Speed (run with --ignored --nocapture in release).

#[test]
#[ignore]
fn speed_report() {
    use std::time::Instant;
    let osc = Oscillator::new(30.0, 0.05, 2.0).unwrap();
    for (name, n) in [
        ("uniform", 10_000usize),
        ("linspace", 10_000),
        ("uniform", 10_000_000),
    ] {
        let t: Vec<f64> = if name == "uniform" {
            (0..n).map(|k| k as f64 * 0.0001220703125).collect()
        } else {
            (0..n).map(|k| 2.0 * (k as f64 / (n - 1) as f64)).collect()
        };
        let f: Vec<f64> = (0..n).map(|k| ((k % 1000) as f64).sin()).collect();
        let (mut q, mut v) = (vec![1.0; n], vec![1.0; n]);
        let reps = (40_000_000 / n).max(2);
        let t0 = Instant::now();
        for _ in 0..reps {
            response_into(&t, &f, &osc, 0.0, 1.0, &mut q, None).unwrap();
        }
        let a = (n * reps) as f64 / t0.elapsed().as_secs_f64();
        let t0 = Instant::now();
        for _ in 0..reps {
            response_into(&t, &f, &osc, 0.0, 1.0, &mut q, Some(&mut v)).unwrap();
        }
        let b = (n * reps) as f64 / t0.elapsed().as_secs_f64();
        println!("single, {name} N={n}: q {a:.3e} steps/s, q and v {b:.3e} steps/s");
    }
    // Batch: B cases × 10,000 steps, and the peak-only batch on a 3-point pulse.
    let (b, n) = (2000usize, 10_000usize);
    let t: Vec<f64> = (0..n).map(|k| k as f64 * 1e-5).collect();
    let forces: Vec<f64> = (0..b * n)
        .map(|i| if i % n < 200 { 1.0 } else { 0.0 })
        .collect();
    let w: Vec<f64> = (0..b).map(|i| 500.0 + i as f64).collect();
    let z: Vec<f64> = (0..b).map(|i| 0.01 * (i % 300) as f64).collect();
    let ones = vec![1.0; b];
    let zeros = vec![0.0; b];
    let cases = cases_of(&w, &z, &ones, &zeros, &zeros);
    let mut out = vec![0.0; b * n];
    let mut full = [0.0; 2];
    for threads in [1usize, 2] {
        response_batch_into(&t, &forces, &cases, Some(threads as i64), &mut out).unwrap();
        let t0 = Instant::now();
        response_batch_into(&t, &forces, &cases, Some(threads as i64), &mut out).unwrap();
        let dt = t0.elapsed().as_secs_f64();
        full[threads - 1] = dt / b as f64;
        println!(
            "batch full history, {threads} thread(s): {:.3e} case-steps/s ({:.2e} s per case)",
            (b * n) as f64 / dt,
            dt / b as f64
        );
    }
    let bb = 1_000_000;
    let tk = [0.0, 1e-3, 2e-3];
    let pulses: Vec<f64> = (0..bb)
        .flat_map(|i| [0.0, 1.0 + (i % 7) as f64, 0.0])
        .collect();
    let w: Vec<f64> = (0..bb).map(|i| 500.0 + (i % 1000) as f64).collect();
    let z: Vec<f64> = (0..bb).map(|i| 0.003 * (i % 1000) as f64).collect();
    let (ones, zeros) = (vec![1.0; bb], vec![0.0; bb]);
    let cases = cases_of(&w, &z, &ones, &zeros, &zeros);
    let (mut tt, mut qq) = (vec![0.0; bb], vec![0.0; bb]);
    for threads in [1usize, 2] {
        let t0 = Instant::now();
        first_rebound_batch_into(
            &tk,
            &pulses,
            &cases,
            false,
            Some(threads as i64),
            &mut tt,
            &mut qq,
        )
        .unwrap();
        let dt = t0.elapsed().as_secs_f64();
        println!(
            "batch peak-only (3-point pulse, ζ in [0, 3]), {threads} thread(s): {:.3e} cases/s, {:.0}x faster per case than the 10,000-step history",
            bb as f64 / dt,
            full[threads - 1] / (dt / bb as f64)
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]
    /// The lockstep loop (whole tiles of steps and the columns after the last
    /// tile) on each instruction set, against each case run alone by the
    /// sequential loop, bit for bit: any length (under a tile, a tile and one,
    /// several), repeated times (force jumps), every damping regime.
    #[test]
    fn lockstep_tiles_equal_the_single_case_loop(
        steps in prop::collection::vec(prop_oneof![Just(0.0), 1e-4f64..3e-3], 1..40),
        forces in prop::collection::vec(-5.0f64..5.0, LOCK * 41),
        z in prop::collection::vec(prop_oneof![Just(0.0), Just(1.0), 0.0f64..3.0], LOCK),
        q0 in prop::collection::vec(-1e-3f64..1e-3, LOCK),
    ) {
        use pulp::Simd;
        let mut t = vec![0.0];
        for h in &steps {
            t.push(t.last().unwrap() + h);
        }
        let n = t.len();
        let forces = &forces[..LOCK * n];
        let w: Vec<f64> = (0..LOCK).map(|i| 300.0 + 211.0 * i as f64).collect();
        let m = vec![0.02; LOCK];
        let v0: Vec<f64> = q0.iter().map(|q| -40.0 * q).collect();
        let cases = cases_of(&w, &z, &m, &q0, &v0);
        let grid = GridSteps::new(&t).unwrap();
        let (coef, lane_q0, lane_v0) = lane_steps(&grid, &cases, 0).unwrap();
        let runs = on_each_isa!(|simd| {
            let mut out = vec![0.0; LOCK * n];
            let last = Simd::vectorize(
                simd,
                Lockstep {
                    which: &grid.which,
                    coef: &coef,
                    forces,
                    out: &mut out,
                    q0: lane_q0,
                    v0: lane_v0,
                },
            );
            (out, last)
        });
        for (isa, (out, (ql, vl))) in runs {
            for i in 0..LOCK {
                let osc = Oscillator::new(w[i], z[i], m[i]).unwrap();
                let (q, v) = respond(&t, &forces[i * n..(i + 1) * n], &osc, q0[i], v0[i]);
                prop_assert_eq!(&out[i * n..(i + 1) * n], &q[..], "{}: case {}", isa, i);
                prop_assert_eq!((ql[i], vl[i]), (q[n - 1], v[n - 1]), "{}: case {}", isa, i);
            }
        }
    }
}

/// The lockstep loop alone on every instruction set the processor has (the
/// Python API picks the best): 8 cases × 10 001 steps on the issue-37 grid,
/// ns per case-step (run with --ignored --nocapture in release).
#[test]
#[ignore]
fn lockstep_speed_per_isa() {
    use pulp::Simd;
    use std::time::Instant;
    let n = 10_001;
    let t: Vec<f64> = (0..n).map(|k| k as f64 * 2e-6).collect();
    let grid = GridSteps::new(&t).unwrap();
    let w = [1866.0; LOCK];
    let z: Vec<f64> = (0..LOCK).map(|i| 0.01 + 0.01 * i as f64).collect();
    let m = [7.4e-3; LOCK];
    let zero = [0.0; LOCK];
    let cases = cases_of(&w, &z, &m, &zero, &zero);
    let (coef, q0, v0) = lane_steps(&grid, &cases, 0).unwrap();
    let forces: Vec<f64> = (0..LOCK * n)
        .map(|i| ((i * 7919) % 13) as f64 - 6.0)
        .collect();
    let mut out = vec![0.0; LOCK * n];
    let rounds = 200;
    let runs = on_each_isa!(|simd| {
        let mut best = f64::INFINITY;
        for _ in 0..5 {
            let t0 = Instant::now();
            for _ in 0..rounds {
                Simd::vectorize(
                    simd,
                    Lockstep {
                        which: &grid.which,
                        coef: &coef,
                        forces: &forces,
                        out: &mut out,
                        q0,
                        v0,
                    },
                );
            }
            best = best.min(t0.elapsed().as_secs_f64() / (rounds * LOCK * n) as f64);
        }
        best
    });
    for (isa, s) in runs {
        println!("lockstep {isa}: {:.3} ns per case-step", s * 1e9);
    }
}

// ---------------------------------------------------------------------
// The lockstep group's coefficients in vector lanes (`lane_coef`).

/// The group's coefficients on every instruction set against [`Step::new`]
/// lane by lane, bit for bit (`to_bits`, so ±0 count); a group whose
/// coefficients are not all finite must be refused.
fn lane_coef_is_step_new(w: &[f64], z: &[f64], m: &[f64], hs: &[f64]) -> Result<(), String> {
    use super::lane_coef::LaneCoef;
    use pulp::Simd;
    let modes: [Mode; LOCK] = std::array::from_fn(|l| Mode::new(w[l], z[l]));
    let inv_m: [f64; LOCK] = std::array::from_fn(|l| 1.0 / m[l]);
    let runs = on_each_isa!(|simd| {
        let mut coef = vec![LaneStep([[0.0; LOCK]; 8]); hs.len()];
        let finite = Simd::vectorize(
            simd,
            LaneCoef {
                modes: &modes,
                inv_m: &inv_m,
                hs,
                coef: &mut coef,
            },
        );
        (finite, coef)
    });
    for (isa, (finite, coef)) in runs {
        let mut all_finite = true;
        for (j, &h) in hs.iter().enumerate() {
            for l in 0..LOCK {
                let st = Step::new(&modes[l], h, inv_m[l]);
                all_finite &= st.is_finite();
                if !all_finite {
                    break;
                }
                let want = [
                    st.p00, st.p01, st.p10, st.p11, st.g0q, st.g0v, st.g1q, st.g1v,
                ];
                for (i, x) in want.iter().enumerate() {
                    let got = coef[j].0[i][l];
                    if got.to_bits() != x.to_bits() {
                        return Err(format!(
                            "{isa}: h {h}, lane {l} (w {}, z {}), coefficient {i}: {got:e} vs Step::new {x:e}",
                            w[l], z[l]
                        ));
                    }
                }
            }
            if !all_finite {
                break;
            }
        }
        if finite != all_finite {
            return Err(format!("{isa}: finite {finite}, Step::new's {all_finite}"));
        }
    }
    Ok(())
}

#[test]
fn lane_coefficients_take_each_branch_together() {
    use super::lane_coef::together;
    // (ω, ζ per lane, h, together): every branch pair the lanes do side by
    // side, and those they leave to Step::new lane by lane.
    let zs =
        |a: f64, b: f64| -> Vec<f64> { (0..LOCK).map(|l| a + (b - a) * l as f64 / 7.0).collect() };
    let spread =
        |w: f64, r: f64| -> Vec<f64> { (0..LOCK).map(|l| w * r.powf(l as f64 / 7.0)).collect() };
    let rows: Vec<(Vec<f64>, Vec<f64>, f64, bool)> = vec![
        // C, S and the integrals by their series (the issue-37 batch).
        (vec![1866.0; LOCK], zs(0.01, 0.1), 2e-6, true),
        // sin/cos (|λ|h² > 1) with the integrals' series ((σ + ωd)h ≤ 2).
        (vec![1.5; LOCK], zs(0.0, 0.05), 1.0, true),
        // sin/cos with the closed-form integrals.
        (vec![1000.0; LOCK], zs(0.0, 0.9), 0.01, true),
        // Every lane its own pair: series and sin/cos, series and closed.
        (spread(0.1, 1e4), zs(0.0, 0.99), 0.05, true),
        // Critically damped (λ = 0) and over-damped, not split, short steps.
        (vec![50.0; LOCK], zs(1.0, 1.15), 1e-3, true),
        // Over-damped, not split, long steps: cosh/sinh, lane by lane.
        (vec![50.0; LOCK], zs(1.0, 1.15), 1.0, false),
        // One split lane: the group lane by lane.
        (vec![50.0; LOCK], zs(0.0, 3.0), 1e-3, false),
        // h = 0.
        (vec![50.0; LOCK], zs(0.0, 0.5), 0.0, false),
    ];
    for (w, z, h, want) in rows {
        let modes: [Mode; LOCK] = std::array::from_fn(|l| Mode::new(w[l], z[l]));
        assert_eq!(together(&modes, h), want, "w {w:?}, z {z:?}, h {h}");
        let m: Vec<f64> = (0..LOCK).map(|l| 0.01 * (l + 1) as f64).collect();
        lane_coef_is_step_new(&w, &z, &m, &[h, h * (1.0 + 1e-15), 2.0 * h]).unwrap();
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]
    /// The lanes' coefficients equal Step::new's bit for bit for any group:
    /// ω, ζ (under-, critically, over-damped and split), m and h (0, and from
    /// tiny to many periods) drawn per lane, on every instruction set; and
    /// with one ω and ζ near one another, as a batch's groups mostly are.
    #[test]
    fn lane_coefficients_are_step_new_bit_for_bit(
        lw in prop::collection::vec(-2.0f64..6.0, LOCK),
        z in prop::collection::vec(
            prop_oneof![Just(0.0), Just(1.0), Just(2.0 / 3f64.sqrt()), 0.0f64..0.2, 0.0f64..3.0],
            LOCK,
        ),
        lm in prop::collection::vec(-4.0f64..2.0, LOCK),
        lh in prop::collection::vec(prop_oneof![Just(f64::NEG_INFINITY), -9.0f64..1.5], 1..12),
        shared in any::<bool>(),
    ) {
        let mut w: Vec<f64> = lw.iter().map(|x| 10f64.powf(*x)).collect();
        let mut z = z;
        if shared {
            // One ω and ζ from 0.8 to 1.25 of the first lane's (no split lane
            // unless the first is).
            let spread = |l: usize| 0.8 + 0.45 * (lw[l] - -2.0) / 8.0;
            w = (0..LOCK).map(|l| w[0] * spread(l)).collect();
            z = (0..LOCK).map(|l| (z[0] * spread(l)).min(1.1)).collect();
        }
        let m: Vec<f64> = lm.iter().map(|x| 10f64.powf(*x)).collect();
        let hs: Vec<f64> = lh.iter().map(|x| 10f64.powf(*x)).collect();
        prop_assert!(lane_coef_is_step_new(&w, &z, &m, &hs).is_ok(), "{:?}", lane_coef_is_step_new(&w, &z, &m, &hs));
    }
}

/// C and S's series (Horner's rule on reciprocal factorials) against their
/// closed forms over its whole range |u| ≤ 1: cos √−u and sin √−u / √−u for
/// u < 0, cosh √u and sinh √u / √u for u > 0 (libm's, within an ulp or two);
/// dense near 0 and at the ends. (Against mpmath at 200 bits: 0.88 and 0.56
/// ulp at worst over 40 000 points, as the nested form it replaced.)
#[test]
fn cs_series_matches_the_closed_forms() {
    let mut us: Vec<f64> = (-2000..=2000).map(|i| i as f64 / 2000.0).collect();
    us.extend((1..300).flat_map(|k| {
        let x = 10f64.powf(-(k as f64) / 15.0);
        [x, -x]
    }));
    for u in us {
        let (c, s) = cs_series(u);
        let r = u.abs().sqrt();
        let (rc, rs) = if u < 0.0 {
            (r.cos(), r.sin() / r)
        } else if u > 0.0 {
            (r.cosh(), r.sinh() / r)
        } else {
            (1.0, 1.0)
        };
        let (ec, es) = ((c - rc).abs() / rc, (s - rs).abs() / rs);
        assert!(ec <= 4.0 * f64::EPSILON, "u {u}: C {c} vs {rc}");
        assert!(es <= 4.0 * f64::EPSILON, "u {u}: S {s} vs {rs}");
    }
}
