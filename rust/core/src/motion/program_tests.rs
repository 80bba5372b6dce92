//! Motion programs against closed forms, finite differences and their rules.

use super::*;
use std::f64::consts::{PI, TAU};

use proptest::prelude::*;

fn seg(law: &str, deg: f64, start: [Option<f64>; 4], end: [Option<f64>; 4]) -> SegmentSpec {
    SegmentSpec {
        law: law.into(),
        angle: deg.to_radians(),
        start,
        end,
        points: vec![],
        degree: 3,
    }
}

const FREE: [Option<f64>; 4] = [None; 4];

fn at(s: f64) -> [Option<f64>; 4] {
    [Some(s), None, None, None]
}

#[test]
fn a_cycloidal_rise_is_its_closed_form() {
    let h = 0.05;
    let p = Program::new(
        &[
            seg("cycloidal", 90.0, FREE, at(h)),
            seg("dwell", 90.0, FREE, FREE),
            seg("cycloidal", 90.0, FREE, at(0.0)),
            seg("dwell", 90.0, FREE, FREE),
        ],
        2,
        0.0,
    )
    .unwrap();
    // The cycloid's jerk jumps at its ends: continuity to the jerk is refused.
    let specs = [
        seg("cycloidal", 180.0, FREE, at(h)),
        seg("cycloidal", 180.0, FREE, at(0.0)),
    ];
    let e = Program::new(&specs, 3, 0.0).unwrap_err().to_string();
    assert!(
        e.starts_with("segment 1 (cycloidal) → segment 2 (cycloidal) at 180°: the jerk jumps"),
        "{e}"
    );
    let b = PI / 2.0;
    for x in [0.0, 0.1, 0.3, 0.5, 0.77, 0.999] {
        let th = x * b;
        let e = p.eval(th);
        let s = h * (x - (TAU * x).sin() / TAU);
        let v = h / b * (1.0 - (TAU * x).cos());
        let a = h / (b * b) * TAU * (TAU * x).sin();
        let j = h / (b * b * b) * TAU * TAU * (TAU * x).cos();
        for (got, want) in e.iter().zip([s, v, a, j]) {
            assert!(
                (got - want).abs() < 1e-13 * (1.0 + want.abs()),
                "{x}: {e:?}"
            );
        }
    }
    // Taken modulo the cycle.
    assert!((p.eval(0.3 + 2.0 * TAU)[0] - p.eval(0.3)[0]).abs() < 1e-15);
}

#[test]
fn velocity_ends_are_met_and_the_derivatives_are_exact() {
    // Constant velocity, a cycloidal velocity–velocity change, constant
    // velocity, then modified-sine back to rest and a dwell.
    let v1 = 0.04;
    let v2 = 0.01;
    let p = Program::new(
        &[
            seg(
                "constant_velocity",
                60.0,
                [None, Some(v1), None, None],
                FREE,
            ),
            seg("cycloidal", 60.0, FREE, [Some(0.06), Some(v2), None, None]),
            seg("constant_velocity", 60.0, FREE, FREE),
            seg("modified_sine", 60.0, FREE, at(0.2)),
            seg("poly5", 120.0, FREE, [Some(0.0), Some(0.0), None, None]),
        ],
        2,
        0.0,
    );
    // The last poly5 is asked to end at rest, the first segment starts moving:
    // the wrap joins rest to v1 — a velocity jump. (Left free, its end would
    // take the first segment's start, v1.)
    let e = p.unwrap_err().to_string();
    assert!(
        e.contains("segment 5 (poly5) → segment 1 (constant_velocity) at 360°"),
        "{e}"
    );
    assert!(e.contains("velocity jumps from 0 to 0.04"), "{e}");
    let p = Program::new(
        &[
            seg(
                "constant_velocity",
                60.0,
                [None, Some(v1), None, None],
                FREE,
            ),
            seg("cycloidal", 60.0, FREE, [Some(0.06), Some(v2), None, None]),
            seg("constant_velocity", 60.0, FREE, FREE),
            seg("modified_sine", 60.0, FREE, at(0.2)),
            seg("poly5", 120.0, FREE, [Some(0.0), Some(v1), None, None]),
        ],
        2,
        0.0,
    )
    .unwrap();
    let d = 60f64.to_radians();
    let e1 = p.eval(d);
    assert!((e1[1] - v1).abs() < 1e-15 && e1[0] > 0.0);
    let e2 = p.eval(2.0 * d - 1e-12);
    assert!((e2[0] - 0.06).abs() < 1e-12 && (e2[1] - v2).abs() < 1e-12 && e2[2].abs() < 1e-9);
    // Derivatives against central differences of the order below, everywhere.
    let hstep = 1e-5;
    for i in 1..720 {
        let th = i as f64 * TAU / 720.0 + 0.001;
        let (lo, hi) = (p.eval(th - hstep), p.eval(th + hstep));
        let e = p.eval(th);
        for k in 0..3 {
            let fd = (hi[k] - lo[k]) / (2.0 * hstep);
            let scale = 1.0 + e[k + 1].abs();
            assert!(
                (fd - e[k + 1]).abs() < 1e-5 * scale * 10f64.powi(k as i32),
                "{th} order {k}: {fd} vs {}",
                e[k + 1]
            );
        }
    }
}

#[test]
fn a_rest_to_rest_polynomial_refuses_a_moving_end() {
    let e = Program::new(
        &[
            seg(
                "polynomial_345",
                180.0,
                FREE,
                [Some(0.1), Some(0.3), None, None],
            ),
            seg("poly5", 180.0, FREE, at(0.0)),
        ],
        0,
        0.0,
    )
    .unwrap_err()
    .to_string();
    assert_eq!(
        e,
        "segment 1 (polynomial_345): the law cannot meet its end velocity = 0.3 (its own is 0) \
         (this law is rest to rest; for moving ends use poly5 or poly7)"
    );
}

#[test]
fn poly5_and_poly7_meet_their_end_conditions() {
    let (s1, v0, a0, v1, a1, j1) = (0.3, 0.2, -0.1, 0.05, 0.4, 1.5);
    for law in ["poly5", "poly7"] {
        let j = if law == "poly7" { Some(j1) } else { None };
        let p = Program::new(
            &[
                seg(
                    law,
                    200.0,
                    [Some(0.0), Some(v0), Some(a0), None],
                    [Some(s1), Some(v1), Some(a1), j],
                ),
                seg(
                    "poly7",
                    160.0,
                    FREE,
                    [Some(0.0), Some(v0), Some(a0), Some(0.0)],
                ),
            ],
            2,
            0.0,
        )
        .unwrap();
        let b = 200f64.to_radians();
        let e0 = p.eval(0.0);
        let e1 = p.spans()[0].at_end;
        for (got, want) in [
            (e0[0], 0.0),
            (e0[1], v0),
            (e0[2], a0),
            (e1[0], s1),
            (e1[1], v1),
            (e1[2], a1),
        ] {
            assert!((got - want).abs() < 1e-12, "{law}: {got} vs {want}");
        }
        if law == "poly7" {
            assert!((e1[3] - j1).abs() < 1e-10);
        }
        assert!((p.spans()[0].angle - b).abs() < 1e-15);
    }
    // A rest-to-rest poly5 is the 3-4-5 law.
    let a = Program::new(
        &[
            seg("poly5", 180.0, FREE, at(1.0)),
            seg("poly5", 180.0, FREE, at(0.0)),
        ],
        2,
        0.0,
    )
    .unwrap();
    let b = Program::new(
        &[
            seg("polynomial_345", 180.0, FREE, at(1.0)),
            seg("polynomial_345", 180.0, FREE, at(0.0)),
        ],
        2,
        0.0,
    )
    .unwrap();
    for i in 0..100 {
        let th = i as f64 * 0.0628;
        let (x, y) = (a.eval(th), b.eval(th));
        for k in 0..4 {
            assert!((x[k] - y[k]).abs() < 1e-12, "{th} {k}");
        }
    }
}

#[test]
fn published_characteristic_values() {
    // VDI 2143 / Norton table 3-2: modified sine Cv = 1.76, Ca = 5.53;
    // cycloidal Cv = 2, Ca = 2π, Cj = 4π².
    let p = Program::new(
        &[
            seg("modified_sine", 100.0, FREE, at(0.02)),
            seg("cycloidal", 260.0, FREE, at(0.0)),
        ],
        2,
        0.0,
    )
    .unwrap();
    let c = p.characteristics(0);
    assert!(
        (c.cv - 1.760).abs() < 5e-4 && (c.ca - 5.528).abs() < 5e-4,
        "{c:?}"
    );
    let c = p.characteristics(1);
    assert!(
        (c.cv - 2.0).abs() < 1e-12
            && (c.ca - TAU).abs() < 1e-12
            && (c.cj - TAU * TAU).abs() < 1e-10,
        "{c:?}"
    );
    assert!((c.stroke + 0.02).abs() < 1e-15);
}

#[test]
fn an_advancing_axis_repeats_with_its_advance() {
    let p = Program::new(
        &[seg(
            "constant_velocity",
            360.0,
            [Some(0.0), Some(0.1), None, None],
            FREE,
        )],
        3,
        0.1 * TAU,
    )
    .unwrap();
    let e = p.eval(TAU + 1.0);
    assert!((e[0] - 0.1 * (TAU + 1.0)).abs() < 1e-14 && e[1] == 0.1);
    assert!(Program::new(
        &[seg(
            "constant_velocity",
            360.0,
            [Some(0.0), Some(0.1), None, None],
            FREE
        )],
        0,
        0.0
    )
    .is_err());
}

#[test]
fn the_unit_law_is_the_segment() {
    let p = Program::new(
        &[
            seg(
                "cycloidal",
                90.0,
                [None, Some(0.01), None, None],
                [Some(0.03), Some(0.02), None, None],
            ),
            seg("poly5", 270.0, FREE, [Some(0.0), Some(0.01), None, None]),
        ],
        2,
        0.0,
    )
    .unwrap();
    for i in 0..2 {
        let sp = &p.spans()[i];
        let (s0, h, law) = p.unit_law(i);
        for x in [0.0, 0.25, 0.6, 1.0] {
            let th = sp.start + x * sp.angle;
            let e = p.eval(th.min(TAU - 1e-15));
            assert!((s0 + h * law.z(x, 0) - e[0]).abs() < 1e-13);
            assert!((h * law.z(x, 1) / sp.angle - e[1]).abs() < 1e-12);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// Random programs of moving and resting segments built with free values:
    /// every join is continuous to the acceleration (free values resolve so),
    /// or the program is refused naming a join.
    #[test]
    fn free_values_join_smoothly(
        laws in prop::collection::vec(0usize..6, 2..7),
        angles in prop::collection::vec(10.0f64..100.0, 7),
        ends in prop::collection::vec(-0.1f64..0.1, 7),
        v in -0.05f64..0.05,
    ) {
        let names = ["cycloidal", "modified_sine", "modified_trapezoid", "poly5", "poly7", "constant_velocity"];
        let n = laws.len();
        let total: f64 = angles[..n].iter().sum();
        let mut specs = Vec::new();
        for (i, &l) in laws.iter().enumerate() {
            let deg = angles[i] * 360.0 / total;
            let mut end = if names[l] == "constant_velocity" { FREE } else { at(ends[i]) };
            if i == n - 1 {
                end = [Some(0.0), Some(v), None, None];
            }
            let start = if i == 0 { [Some(0.0), Some(v), Some(0.0), Some(0.0)] } else { FREE };
            specs.push(seg(names[l], deg, start, end));
        }
        match Program::new(&specs, 2, 0.0) {
            Ok(p) => {
                for w in p.spans().windows(2) {
                    for k in 0..3 {
                        let d = (w[0].at_end[k] - w[1].at_start[k]).abs();
                        prop_assert!(d <= 1e-8 * (1.0 + w[0].at_end[k].abs()) * 1e3, "{k}: {d}");
                    }
                }
            }
            Err(e) => {
                let e = e.to_string();
                prop_assert!(e.contains("jumps") || e.contains("cannot meet"), "{}", e);
            }
        }
    }
}

#[test]
fn the_lane_path_is_the_pointwise_path_bit_for_bit() {
    let p = Program::new(
        &[
            seg(
                "cycloidal",
                90.0,
                [None, Some(0.01), None, None],
                [Some(0.03), Some(0.02), None, None],
            ),
            seg("constant_velocity", 30.0, FREE, FREE),
            seg("modified_trapezoid", 60.0, FREE, at(0.06)),
            seg(
                "poly7",
                180.0,
                FREE,
                [Some(0.0), Some(0.01), Some(0.0), Some(0.0)],
            ),
        ],
        2,
        0.0,
    )
    .unwrap();
    // A sorted grid (groups within one piece), a shuffled one (groups across
    // pieces), and angles outside one cycle.
    let n = 4099;
    let mut theta: Vec<f64> = (0..n).map(|i| i as f64 * TAU / n as f64).collect();
    theta.extend((0..n).map(|i| ((i * 7919) % n) as f64 * TAU / n as f64));
    theta.extend([-1.0, 7.0, 100.0, TAU, 0.0]);
    let mut out = vec![0.0; 4 * theta.len()];
    p.eval_into(&theta, Some(2), &mut out).unwrap();
    let m = theta.len();
    for (i, &t) in theta.iter().enumerate() {
        let e = p.eval(t);
        for k in 0..4 {
            assert_eq!(
                out[k * m + i].to_bits(),
                e[k].to_bits(),
                "θ = {t}, order {k}"
            );
        }
    }
}

#[test]
fn a_segment_that_comes_back_keeps_its_size_in_the_join_tolerance() {
    // One poly5 out and back over the whole cycle: its stroke is 0, its ends
    // move (v = 0.05): rounding at the wrap (~1e-18) is not a jump.
    let p = Program::new(
        &[seg(
            "poly5",
            360.0,
            [Some(0.0), Some(0.05), None, None],
            [Some(1e-18), Some(0.05), None, None],
        )],
        1,
        0.0,
    );
    assert!(p.is_ok(), "{p:?}");
    // A real jump still is one.
    let e = Program::new(
        &[seg(
            "poly5",
            360.0,
            [Some(0.0), Some(0.05), None, None],
            [Some(1e-3), Some(0.05), None, None],
        )],
        0,
        0.0,
    );
    assert!(e.unwrap_err().to_string().contains("the position jumps"));
}
