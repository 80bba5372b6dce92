//! Unit tests of the cam sizing (the Python tests check it against brentq on
//! the public criteria and a closed form in numpy).

use std::f64::consts::PI;

use proptest::prelude::*;

use super::*;
use crate::cam::{Kind, Program, SegmentSpec};

fn program(rise_deg: f64, stroke: f64) -> Program {
    let seg = |kind, deg: f64, stroke| SegmentSpec {
        kind,
        angle: deg.to_radians(),
        stroke,
        law: "cycloidal".into(),
        unit: None,
    };
    let rest = (360.0 - 2.0 * rise_deg) / 2.0;
    Program::new(&[
        seg(Kind::Rise, rise_deg, stroke),
        seg(Kind::Dwell, rest, 0.0),
        seg(Kind::Return, rise_deg, stroke),
        seg(Kind::Dwell, rest, 0.0),
    ])
    .unwrap()
}

fn translating(rb: f64, rr: f64, e: f64) -> Follower {
    Follower::TranslatingRoller {
        base_radius: rb,
        roller_radius: rr,
        offset: e,
    }
}

fn sizing(cam: &Cam, alpha_deg: f64) -> Sizing<'_> {
    Sizing {
        cam,
        loads: None,
        contact: None,
        limits: Limits {
            max_pressure_angle: alpha_deg.to_radians(),
            max_stress: None,
        },
        min_radius: 0.011,
        max_radius: 0.5,
        second: None,
    }
}

fn solve(s: &Sizing<'_>, omega: f64) -> Sized {
    let mut out = [0.0; N_SIZE_COLUMNS];
    s.solve_into(&[omega], &mut out, Some(1)).unwrap();
    Sized {
        base_radius: out[0],
        second: out[1],
        status: out[2] as usize,
        binding: out[3] as i64,
        ratios: [out[4], out[5], out[6]],
        gap_above: out[7] != 0.0,
    }
}

/// Cycloidal rise h over β, zero offset: tan α = s′/(s + R_p), so the pitch
/// radius R_p = max(s′/tan[α] − s) over the rise, on a dense grid.
#[test]
fn pressure_angle_closed_form() {
    let (h, beta, rr) = (0.02, 100f64.to_radians(), 0.01);
    let cam = Cam::new(program(100.0, h), translating(0.05, rr, 0.0), false).unwrap();
    let s = sizing(&cam, 30.0);
    let got = solve(&s, 10.0);
    let t = 30f64.to_radians().tan();
    let n = 200_000;
    let mut rp: f64 = 0.0;
    for i in 0..=n {
        let x = i as f64 / n as f64;
        let sv = h * (x - (2.0 * PI * x).sin() / (2.0 * PI));
        let dsv = h / beta * (1.0 - (2.0 * PI * x).cos());
        rp = rp.max(dsv / t - sv);
    }
    assert_eq!(got.status, 0);
    assert_eq!(got.binding, 0);
    assert!(
        ((got.base_radius + rr) - rp).abs() < 1e-7 * rp,
        "{got:?} vs {rp}"
    );
    assert!((got.ratios[0] - 1.0).abs() < 1e-9);
}

#[test]
fn bounds_and_infeasible() {
    let cam = Cam::new(program(100.0, 0.02), translating(0.05, 0.01, 0.0), false).unwrap();
    // A large limit: the smallest radius searched already holds.
    let mut s = sizing(&cam, 89.0);
    s.min_radius = 0.2;
    let got = solve(&s, 10.0);
    assert_eq!((got.status, got.binding), (1, -1));
    assert_eq!(got.base_radius, 0.2);
    // A tight limit with a small R_max: infeasible, the pressure angle failing,
    // its least ratio at R_max (it falls with the radius).
    let mut s = sizing(&cam, 5.0);
    s.max_radius = 0.05;
    let got = solve(&s, 10.0);
    assert_eq!((got.status, got.binding), (2, 0));
    assert_eq!(got.base_radius, 0.05);
    assert!(got.ratios[0] > 1.0);
    // Bad limits are errors, not answers.
    let mut s = sizing(&cam, 30.0);
    s.max_radius = 0.001;
    let mut out = [0.0; N_SIZE_COLUMNS];
    assert!(s.solve_into(&[1.0], &mut out, Some(1)).is_err());
}

#[test]
fn offset_search_beats_zero_offset() {
    // A rise alone bounding (the return slow): an offset toward the rise's
    // side lowers its pressure angle, so the best offset is > 0.
    let seg = |kind, deg: f64, stroke| SegmentSpec {
        kind,
        angle: f64::to_radians(deg),
        stroke,
        law: "cycloidal".into(),
        unit: None,
    };
    let p = Program::new(&[seg(Kind::Rise, 90.0, 0.02), seg(Kind::Return, 270.0, 0.02)]).unwrap();
    let cam = Cam::new(p, translating(0.05, 0.01, 0.0), false).unwrap();
    let s0 = sizing(&cam, 30.0);
    let zero = solve(&s0, 10.0);
    let s1 = Sizing {
        second: Some((-0.02, 0.02)),
        ..s0.clone()
    };
    let best = solve(&s1, 10.0);
    assert_eq!(best.status, 0);
    assert!(best.second > 0.0, "{best:?}");
    assert!(
        best.base_radius < zero.base_radius * 0.99,
        "{best:?} vs {zero:?}"
    );
    // No grid value does better than the refined answer.
    for i in 0..SECOND_GRID {
        let p = -0.02 + 0.04 * i as f64 / (SECOND_GRID - 1) as f64;
        let s = Sizing {
            second: None,
            ..s0.clone()
        };
        let c = resized(&cam, 0.05, Some(p)).unwrap();
        let si = Sizing { cam: &c, ..s };
        let r = solve(&si, 10.0);
        assert!(r.status != 0 || r.base_radius >= best.base_radius * (1.0 - 1e-9));
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]
    /// The answer meets the limits with equality on the binding one, and a
    /// radius 0.1 % smaller does not.
    #[test]
    fn answer_is_tight(
        rise in 40.0f64..160.0,
        stroke in 0.005f64..0.04,
        alpha in 15.0f64..40.0,
        rr in 0.002f64..0.01,
    ) {
        let cam = Cam::new(program(rise, stroke), translating(0.05, rr, 0.0), false).unwrap();
        let mut s = sizing(&cam, alpha);
        s.min_radius = rr * 1.01;
        let got = solve(&s, 10.0);
        prop_assume!(got.status == 0);
        let b = got.binding as usize;
        prop_assert!((got.ratios[b] - 1.0).abs() < 1e-8, "{:?}", got);
        let below = s.ratios(got.base_radius * 0.999, None, 10.0, None);
        prop_assert!(below.is_none_or(|r| r[b] > 1.0));
    }
}
