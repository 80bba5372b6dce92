use proptest::prelude::*;

use super::quintic::WEIGHTS16;
use super::*;

/// ∫₀ˣ √(1 + y'²) by composite Simpson on `n` (even) intervals: independent of
/// the Gauss–Legendre rules.
fn simpson(q: &Quintic, x: f64, n: usize) -> f64 {
    let h = x / n as f64;
    let f = |t: f64| (1.0 + q.d(t, 1).powi(2)).sqrt();
    let mut acc = f(0.0) + f(x);
    for i in 1..n {
        acc += f(i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    acc * h / 3.0
}

fn smooth(r: f64, x2: f64) -> Quintic {
    Quintic {
        c: coefficients(r, x2 / (2.0 * r), -3.0 * x2 * x2 / (20.0 * r), x2),
    }
}

#[test]
fn quintic_meets_the_circle_and_the_line() {
    let (r, k, b, x2) = (0.15, 0.2, -0.004, 0.06);
    let q = Quintic {
        c: coefficients(r, k, b, x2),
    };
    assert_eq!(q.d(0.0, 0), 0.0);
    assert_eq!(q.d(0.0, 1), 0.0);
    assert!((q.d(0.0, 2) - 1.0 / r).abs() < 1e-12);
    assert!((q.d(x2, 0) - (k * x2 + b)).abs() < 1e-15);
    assert!((q.d(x2, 1) - k).abs() < 1e-13);
    assert!(q.d(x2, 2).abs() < 1e-9);
    // The smooth member: y''' = 0 at both ends.
    let s = smooth(0.2, 0.05);
    assert!(s.d(0.0, 3).abs() < 1e-9 && s.d(0.05, 3).abs() < 1e-9);
}

#[test]
fn derivatives_match_central_differences() {
    let q = smooth(0.15, 0.05);
    let h = 1e-6;
    for &x in &[0.005, 0.02, 0.037] {
        for order in 1..=3 {
            let fd = (q.d(x + h, order - 1) - q.d(x - h, order - 1)) / (2.0 * h);
            let scale = q.d(x, order).abs().max(1.0);
            assert!(
                (fd - q.d(x, order)).abs() < 1e-6 * scale,
                "order {order} at {x}"
            );
        }
    }
}

#[test]
fn arc_length_against_simpson_and_a_straight_line() {
    for &(r, x2) in &[(0.15, 0.05), (0.05, 0.2), (1e-3, 0.02)] {
        let q = smooth(r, x2);
        let m = q.pieces(x2);
        let want = simpson(&q, x2, 200_000);
        let got = q.arc_from_zero(x2, m);
        assert!(
            (got - want).abs() < 1e-12 * want,
            "{r} {x2}: {got} vs {want}"
        );
        // Along a grid, the 4-point steps add up to the same length.
        let n = 2000;
        let steps: f64 = (0..n)
            .map(|i| q.arc_step(x2 * i as f64 / n as f64, x2 * (i + 1) as f64 / n as f64))
            .sum();
        assert!((steps - want).abs() < 1e-12 * want);
    }
    let flat = Quintic { c: [0.0; 6] };
    assert_eq!(
        flat.arc_from_zero(0.05, 1),
        0.05 * WEIGHTS16.iter().sum::<f64>()
    );
}

/// The README's example path (0.15 and 0.25 m rotors, centres 0.41 m apart,
/// x2 = 0.05 m, 30° leads), worked out as the Python layer does.
fn example() -> PathSpec {
    let r: [f64; 2] = [0.15, 0.25];
    let d: f64 = 0.41;
    let x2: f64 = 0.05;
    let k = r.map(|r| x2 / (2.0 * r));
    let b = r.map(|r| -3.0 * x2 * x2 / (20.0 * r));
    let dist = [0, 1].map(|i| (r[i] - b[i]) / (1.0 + k[i] * k[i]).sqrt());
    let psi = ((dist[0] + dist[1]) / d).asin();
    let u = [psi.cos(), psi.sin()];
    let rot = |v: [f64; 2], a: f64| {
        [
            a.cos() * v[0] - a.sin() * v[1],
            a.sin() * v[0] + a.cos() * v[1],
        ]
    };
    let t = [rot(u, -k[0].atan()), rot([-u[0], -u[1]], -k[1].atan())];
    let centres = [[0.0, 0.0], [d, 0.0]];
    let origin = [0, 1].map(|i| {
        [
            centres[i][0] + r[i] * t[i][1],
            centres[i][1] - r[i] * t[i][0],
        ]
    });
    let ends = [0, 1].map(|i| {
        let y = k[i] * x2 + b[i];
        [
            origin[i][0] + x2 * t[i][0] - y * t[i][1],
            origin[i][1] + x2 * t[i][1] + y * t[i][0],
        ]
    });
    let straight = (ends[1][0] - ends[0][0]) * u[0] + (ends[1][1] - ends[0][1]) * u[1];
    let q = [0, 1].map(|i| Quintic {
        c: coefficients(r[i], k[i], b[i], x2),
    });
    let lead = 30f64.to_radians();
    let len = [0, 1].map(|i| q[i].arc_from_zero(x2, q[i].pieces(x2)));
    let phi_a = (origin[0][1] - centres[0][1]).atan2(origin[0][0] - centres[0][0]);
    let base_t = phi_a + 0.5 * std::f64::consts::PI;
    let head = base_t + k[0].atan();
    let base_p = head - k[1].atan() - std::f64::consts::PI;
    PathSpec {
        centre: centres,
        radius: r,
        lead,
        quintic: q,
        x2: [x2, x2],
        origin,
        t_a: t,
        end_t: ends[0],
        u,
        straight,
        lengths: [r[0] * lead, len[0], straight, len[1], r[1] * lead],
        phi_a,
        base_t,
        head,
        base_p,
        phi_c: base_p + 1.5 * std::f64::consts::PI,
    }
}

struct Sampled {
    points: Vec<f64>,
    s: Vec<f64>,
    heading: Vec<f64>,
    curvature: Vec<f64>,
    rate: Vec<f64>,
    piece: Vec<i8>,
}

fn sample(spec: &PathSpec, counts: [usize; 5], ccw: bool, threads: i64) -> Sampled {
    let n: usize = counts.iter().sum();
    let mut o = Sampled {
        points: vec![0.0; 2 * n],
        s: vec![0.0; n],
        heading: vec![0.0; n],
        curvature: vec![0.0; n],
        rate: vec![0.0; n],
        piece: vec![0; n],
    };
    let out = SampleOut {
        points: &mut o.points,
        s: &mut o.s,
        heading: &mut o.heading,
        curvature: &mut o.curvature,
        rate: &mut o.rate,
        piece: &mut o.piece,
    };
    sample_into(spec, &counts, ccw, out, Some(threads)).unwrap();
    o
}

#[test]
fn sampled_path_is_continuous_and_on_its_circles() {
    let spec = example();
    let counts = [9000, 5000, 1000, 5000, 15001];
    let o = sample(&spec, counts, true, 2);
    let n = o.s.len();
    let total: f64 = spec.lengths.iter().sum();
    assert!((o.s[n - 1] - total).abs() < 1e-12 * total);
    for i in 1..n {
        // Arc length grows by the chord (to second order) and the curve is
        // continuous: no jump between pieces.
        let dx = o.points[2 * i] - o.points[2 * i - 2];
        let dy = o.points[2 * i + 1] - o.points[2 * i - 1];
        let chord = dx.hypot(dy);
        let ds = o.s[i] - o.s[i - 1];
        assert!(
            ds > 0.0 && (ds - chord).abs() < 1e-9,
            "{i}: {ds} vs {chord}"
        );
        assert!((o.heading[i] - o.heading[i - 1]).abs() < 1e-3);
        assert!((o.curvature[i] - o.curvature[i - 1]).abs() < 1e-2);
    }
    for i in 0..n {
        let p = o.piece[i] as usize;
        if p == 0 || p == 4 {
            let c = spec.centre[p / 4];
            let r = (o.points[2 * i] - c[0]).hypot(o.points[2 * i + 1] - c[1]);
            assert!((r - spec.radius[p / 4]).abs() < 1e-15, "{i}: radius {r}");
            // The rotated sine and cosine against the direct ones.
            let phi = o.heading[i] - if p == 0 { 1.0 } else { -1.0 } * std::f64::consts::FRAC_PI_2;
            assert!((o.points[2 * i] - (c[0] + spec.radius[p / 4] * phi.cos())).abs() < 1e-15);
        }
    }
    // Curvature runs +1/R_t → −1/R_p.
    assert!((o.curvature[0] - 1.0 / 0.15).abs() < 1e-12);
    assert!((o.curvature[n - 1] + 1.0 / 0.25).abs() < 1e-12);
}

#[test]
fn sample_does_not_depend_on_the_thread_count_and_mirrors() {
    let spec = example();
    let counts = [20000, 9000, 3000, 9000, 20001];
    let one = sample(&spec, counts, true, 1);
    let two = sample(&spec, counts, true, 2);
    assert_eq!(one.points, two.points);
    assert_eq!(one.s, two.s);
    assert_eq!(one.heading, two.heading);
    assert_eq!(one.rate, two.rate);
    let m = sample(&spec, counts, false, 2);
    for i in 0..one.s.len() {
        assert_eq!(m.points[2 * i], one.points[2 * i]);
        assert_eq!(m.points[2 * i + 1], -one.points[2 * i + 1]);
        assert_eq!(m.curvature[i], -one.curvature[i]);
    }
    assert_eq!(one.piece[0], 0);
    assert_eq!(*one.piece.last().unwrap(), 4);
}

#[test]
fn coarse_grids_take_every_length_from_zero() {
    // Too few points per 16-point piece for 4-point steps: the direct branch.
    let spec = example();
    let o = sample(&spec, [2, 3, 2, 3, 2], true, 1);
    let want = spec.lengths[0] + spec.quintic[0].arc_from_zero(spec.x2[0] * 2.0 / 3.0, 1);
    assert!((o.s[4] - want).abs() < 1e-15);
}

#[test]
fn kinematics_on_circles_and_the_time_at_constant_speed() {
    let spec = example();
    let o = sample(&spec, [3000, 2000, 500, 2000, 5001], true, 2);
    let n = o.s.len();
    let v = 0.3;
    let law = SpeedLaw::new(v, v, spec.lengths[0], 0.1).unwrap();
    let mut out = vec![0.0; N_KINEMATICS * n];
    kinematics_into(&o.s, &o.curvature, &o.rate, &law, &mut out, Some(2)).unwrap();
    let row = |r: usize| &out[r * n..(r + 1) * n];
    for i in 0..n {
        assert!((row(0)[i] - o.s[i] / v).abs() < 1e-12, "time at {i}");
        assert_eq!(row(1)[i], v);
        assert!((row(2)[i] - v * v * o.curvature[i]).abs() < 1e-15);
        assert_eq!(row(3)[i], 0.0);
        // At constant speed the jerk is v³·|(−κ², dκ/ds)|.
        let want = v.powi(3) * (o.curvature[i].powi(2)).hypot(o.rate[i]);
        assert!((row(7)[i] - want).abs() < 1e-12 * want.max(1.0));
    }
}

#[test]
fn speed_law_is_a_quintic_smoothstep() {
    let law = SpeedLaw::new(0.2, 0.3, 1.0, 2.0).unwrap();
    assert_eq!(law.at(0.5), (0.2, 0.0, 0.0));
    assert_eq!(law.at(3.5), (0.3, 0.0, 0.0));
    let (v, dv, ddv) = law.at(2.0);
    assert!((v - 0.25).abs() < 1e-15);
    assert!((dv - 0.1 * 30.0 / 16.0 / 2.0).abs() < 1e-15);
    assert!(ddv.abs() < 1e-15);
    assert!(SpeedLaw::new(0.0, 0.3, 1.0, 2.0).is_err());
}

#[test]
fn bad_inputs_are_errors_not_panics() {
    assert!(PathSpec::from_flat(&[0.0; 3]).is_err());
    let mut flat = [1.0; N_SPEC];
    flat[10] = f64::NAN;
    assert!(matches!(
        PathSpec::from_flat(&flat),
        Err(TransferError::Input(InvalidInput::NotFinite {
            index: 10,
            ..
        }))
    ));
    assert!(peak_jerk([0.15, 0.25], 0.3, &[0.01], [0.1, 0.1], 101, Some(1)).is_err());
    assert!(peak_jerk([0.15, 0.25], 0.41, &[-0.01], [0.1, 0.1], 101, Some(1)).is_err());
    assert!(peak_jerk([0.15, 0.25], 0.41, &[0.01], [0.1, 0.1], 1, Some(1)).is_err());
    assert!(longest([0.15, -0.25], 0.41, [1.0, 1.0]).is_err());
    assert!(quintic(&[1.0; 5]).is_err());
}

#[test]
fn peak_jerk_of_a_short_transition_nears_the_circles_jump_rate() {
    // Constant speed: on the transitions the jerk is v³·|dκ/ds| at most where κ
    // is flat, and infeasible candidates are infinite.
    let (r, d, v) = ([0.15, 0.25], 0.41, 0.2);
    let top = longest(r, d, [1.0, 1.0]).unwrap().unwrap()[0];
    let x2 = [0.01, 0.03, top, 1.5 * top];
    let peaks = peak_jerk(r, d, &x2, [v, v], 801, Some(2)).unwrap();
    assert!(peaks[3].is_infinite());
    assert!(peaks[0] > peaks[1] && peaks[1] > peaks[2], "{peaks:?}");
    // The smooth transition's peak |dκ/ds| is 3/(2R·x2) (at s = x2/2, to first
    // order in the slope): the jerk there is v³·3/(2·R_t·x2) or more.
    let floor = v.powi(3) * 1.5 / (0.15 * 0.01);
    assert!(
        peaks[0] > 0.95 * floor && peaks[0] < 1.2 * floor,
        "{} vs {floor}",
        peaks[0]
    );
}

proptest! {
    #[test]
    fn longest_closes_the_straight(
        rt in 0.01f64..1.0,
        rp in 0.01f64..1.0,
        gap in 1e-3f64..0.5,
        f in 0.2f64..5.0,
    ) {
        let r = [rt, rp];
        let d = rt + rp + gap;
        let ratio = [1.0, f];
        let got = longest(r, d, ratio).unwrap().unwrap();
        let at = geometry(r, d, got);
        prop_assert!(at.feasible && at.straight >= 0.0);
        let past = geometry(r, d, [got[0] * (1.0 + 1e-6), got[1] * (1.0 + 1e-6)]);
        prop_assert!(past.straight < 0.0, "{:?} {:?}", at, past);
        // The straight's length falls as the transitions grow.
        let half = geometry(r, d, [got[0] * 0.5, got[1] * 0.5]);
        prop_assert!(half.straight > at.straight);
    }

    #[test]
    fn peak_jerk_is_finite_positive_and_thread_independent(
        rt in 0.02f64..0.5,
        rp in 0.02f64..0.5,
        gap in 1e-3f64..0.1,
        vt in 0.05f64..2.0,
        vp in 0.05f64..2.0,
    ) {
        let (r, d) = ([rt, rp], rt + rp + gap);
        let top = longest(r, d, [1.0, 1.0]).unwrap().unwrap()[0];
        let x2: Vec<f64> = (1..=7).map(|i| (top * i as f64 / 7.0).min(top)).collect();
        let one = peak_jerk(r, d, &x2, [vt, vp], 64, Some(1)).unwrap();
        let two = peak_jerk(r, d, &x2, [vt, vp], 64, Some(2)).unwrap();
        prop_assert_eq!(&one, &two);
        prop_assert!(one.iter().all(|j| j.is_finite() && *j > 0.0), "{:?}", one);
    }
}

#[test]
fn branchless_atan_is_within_two_ulps_of_the_library() {
    let mut x = -1e3;
    while x < 1e3 {
        for v in [x, 1.0 / x, x * 1e-3, x * 1e5] {
            let (got, want) = (super::path::atan(v), v.atan());
            assert!(
                (got - want).abs() <= 2.0 * f64::EPSILON * want.abs(),
                "{v}: {got} vs {want}"
            );
        }
        x += 0.0137;
    }
    assert_eq!(super::path::atan(0.0), 0.0);
    assert_eq!(
        super::path::atan(f64::INFINITY),
        std::f64::consts::FRAC_PI_2
    );
}

#[test]
fn scan_is_the_same_on_every_instruction_set() {
    use pulp::WithSimd;
    // The lane loops compile to scalar, AVX2 and AVX-512 code; no fused
    // multiply-adds are introduced, so every one gives the same bits.
    for (x2, speed) in [(0.03, [0.1, 0.3]), (0.07, [0.2, 0.2]), (0.005, [1.0, 0.4])] {
        let all = on_each_isa!(|s| super::design::Candidate {
            r: [0.15, 0.25],
            d: 0.41,
            x2,
            speed,
            m: 801,
        }
        .with_simd(s));
        for (name, v) in &all {
            assert_eq!(
                v.to_bits(),
                all[0].1.to_bits(),
                "{name}: {v} vs {}",
                all[0].1
            );
        }
    }
}

/// The ambiguous case: a candidate an ulp shorter than the longest that fits
/// has a straight of −1.6e-16 m by rounding (the straight is not monotone at
/// the ulp). An overlap within 1e-12·d is rounding, as `TransferPath` takes
/// it: the jerk is finite. A real overlap (the longest + 1e-6) is inf.
#[test]
fn an_overlap_of_rounding_size_fits_a_real_one_does_not() {
    let (rt, rp, gap) = (0.4816596191697546, 0.39349413550424783, 0.04701661543068728);
    let (r, d) = ([rt, rp], rt + rp + gap);
    let top = longest(r, d, [1.0, 1.0]).unwrap().unwrap()[0];
    let below = top * 7.0 / 7.0; // one ulp under top
    assert!(below < top);
    let g = geometry(r, d, [below, below]);
    assert!(
        g.feasible && g.straight < 0.0 && g.straight > -1e-15,
        "{g:?}"
    );
    let j = peak_jerk(
        r,
        d,
        &[below, top, top * (1.0 + 1e-6)],
        [0.05, 0.05],
        64,
        Some(1),
    )
    .unwrap();
    assert!(j[0].is_finite() && j[1].is_finite(), "{j:?}");
    assert!((j[0] / j[1] - 1.0).abs() < 1e-9, "{j:?}");
    assert_eq!(j[2], f64::INFINITY);
}
