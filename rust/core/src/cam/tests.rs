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
    };
    assert!(matches!(
        Program::new(std::slice::from_ref(&seg)),
        Err(CamError::UnknownLaw { .. })
    ));
    let ok = SegmentSpec {
        law: "cycloidal".into(),
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
