//! Unit tests of the cam kernels (the Python tests check against independent
//! references).

use std::f64::consts::{PI, TAU};

use super::*;

fn program() -> Program {
    let seg = |kind, deg: f64, stroke| SegmentSpec {
        kind,
        angle: deg.to_radians(),
        stroke,
        law: "cycloidal".into(),
        unit: None,
    };
    Program::new(&[
        seg(Kind::Rise, 120.0, 0.02),
        seg(Kind::Dwell, 60.0, 0.0),
        seg(Kind::Return, 120.0, 0.02),
        seg(Kind::Dwell, 60.0, 0.0),
    ])
    .unwrap()
}

#[test]
fn dwell_is_an_arc() {
    let f = Follower::TranslatingRoller {
        base_radius: 0.05,
        roller_radius: 0.01,
        offset: 0.0,
    };
    let cam = Cam::new(program(), f, false).unwrap();
    let mut row = [0.0; N_COLUMNS];
    cam.row(150f64.to_radians(), &mut row);
    assert!((row[0] - 0.02).abs() < 1e-15);
    assert!((row[11] - 0.08).abs() < 1e-12);
    assert!((row[12] - 0.07).abs() < 1e-12);
    assert!(row[10].abs() < 1e-15);
}

#[test]
fn bad_inputs_are_errors() {
    let seg = SegmentSpec {
        kind: Kind::Rise,
        angle: PI,
        stroke: 0.01,
        law: "nope".into(),
        unit: None,
    };
    assert!(matches!(
        Program::new(std::slice::from_ref(&seg)),
        Err(CamError::UnknownLaw { .. })
    ));
    let ok = SegmentSpec {
        law: "cycloidal".into(),
        unit: None,
        ..seg
    };
    assert!(matches!(
        Program::new(&[
            ok.clone(),
            SegmentSpec {
                kind: Kind::Dwell,
                stroke: 0.0,
                ..ok.clone()
            }
        ]),
        Err(CamError::NotClosed { .. })
    ));
    assert!(matches!(
        Program::new(std::slice::from_ref(&ok)),
        Err(CamError::NotOneTurn { .. })
    ));
    let f = Follower::TranslatingRoller {
        base_radius: 0.01,
        roller_radius: 0.02,
        offset: 0.0,
    };
    assert!(Cam::new(program(), f, false).is_err());
    let cam = Cam::new(program(), Follower::FlatFaced { base_radius: 0.05 }, false).unwrap();
    let mut out = vec![0.0; N_COLUMNS];
    assert!(cam.solve_into(&[f64::NAN], &mut out, Some(1)).is_err());
    assert!(cam.solve_into(&[TAU], &mut out, Some(1)).is_ok());
}

#[test]
fn brent_root_and_maximum_of_known_functions() {
    use super::search::{brent_max, brent_zero, max_unit};
    // cos x = x at the Dottie number.
    let f = |x: f64| x.cos() - x;
    let r = brent_zero(f, 0.0, 1.0, f(0.0), f(1.0), 0.0, 1e-15);
    assert!((r - 0.739_085_133_215_160_6).abs() < 1e-15);
    // sin on [0, π]: the maximum 1 at π/2.
    let (x, v) = brent_max(&|x: f64| x.sin(), 0.0, PI, 1e-12);
    assert!((x - PI / 2.0).abs() < 1e-7 && (v - 1.0).abs() < 1e-15);
    // A peak between two grid points of max_unit (width 0.015, under the grid's
    // 1/48, at x = 0.3071): refined to its top, not a grid point's value. (A
    // peak much narrower than the grid is not seen: why the stress also looks
    // at the curvature's peak.)
    let peak = |x: f64| (-((x - 0.3071) / 0.015).powi(2)).exp() + 0.2 * x;
    let (v, x) = max_unit(peak);
    assert!((x - 0.3071).abs() < 1e-3, "{x}");
    assert!(v > 1.0 + 0.2 * 0.3 && v < 1.0 + 0.2 * 0.31, "{v}");
    // A NaN anywhere counts as violated (+∞).
    assert_eq!(
        max_unit(|x: f64| if x > 0.5 { f64::NAN } else { x }).0,
        f64::INFINITY
    );
    let _ = TAU;
}

proptest::proptest! {
    #[test]
    fn brent_zero_finds_a_bracketed_root(r in 0.01f64..0.99, p in 1.0f64..5.0) {
        use super::search::brent_zero;
        // A monotone function with its root at r.
        let f = |x: f64| x.powf(p) - r.powf(p);
        let x = brent_zero(f, 0.0, 1.0, f(0.0), f(1.0), 0.0, 1e-14);
        proptest::prop_assert!((x - r).abs() <= 1e-12, "{x} vs {r}");
    }
}
