//! The lane forms of the cam kernel (sin_cos, atan2, the rows) against the
//! scalar ones: bit for bit, per instruction set.

use proptest::prelude::*;
use std::f64::consts::TAU;

use super::*;
use crate::cam::{Kind, SegmentSpec};
use crate::geom::sin_cos;

#[test]
fn sin_cos_lanes_is_geom_sin_cos_bit_for_bit() {
    let mut x: Vec<f64> = (0..=20_000).map(|i| (i as f64 - 10_000.0) * 1e-3).collect();
    for k in -8..=8 {
        let e = k as f64 * std::f64::consts::FRAC_PI_4;
        x.extend([e.next_down(), e, e.next_up()]);
    }
    x.extend([
        1e6,
        -1e6,
        1e6f64.next_up(),
        3e9,
        f64::INFINITY,
        f64::NAN,
        0.0,
        -0.0,
    ]);
    for g in x.chunks(8) {
        let mut v = [0.0; 8];
        v[..g.len()].copy_from_slice(g);
        let (sn, cs) = sin_cos_lanes(&v);
        for l in 0..8 {
            let (s0, c0) = sin_cos(v[l]);
            assert!(sn[l].to_bits() == s0.to_bits() || (sn[l].is_nan() && s0.is_nan()));
            assert!(cs[l].to_bits() == c0.to_bits() || (cs[l].is_nan() && c0.is_nan()));
        }
    }
}

fn cams() -> Vec<Cam> {
    let mut out = Vec::new();
    for law in ["cycloidal", "modified_trapezoid", "polynomial_345"] {
        let seg = |kind, deg: f64, stroke| SegmentSpec {
            kind,
            angle: deg.to_radians(),
            stroke,
            law: law.into(),
            unit: None,
        };
        let prog = |h: f64| {
            Program::new(&[
                seg(Kind::Rise, 100.0, h),
                seg(Kind::Dwell, 50.0, 0.0),
                seg(Kind::Return, 130.0, h),
                seg(Kind::Dwell, 80.0, 0.0),
            ])
            .unwrap()
        };
        let tr = Follower::TranslatingRoller {
            base_radius: 0.012,
            roller_radius: 0.009,
            offset: 0.002,
        };
        let osc = Follower::OscillatingRoller {
            pivot_distance: 0.1,
            arm_length: 0.08,
            base_radius: 0.04,
            roller_radius: 0.01,
        };
        let flat = Follower::FlatFaced { base_radius: 0.05 };
        out.push(Cam::new(prog(0.02), tr, true).unwrap());
        out.push(Cam::new(prog(0.02), tr, false).unwrap());
        out.push(Cam::new(prog(0.02), flat, false).unwrap());
        out.push(Cam::new(prog(0.3), osc, true).unwrap());
    }
    out
}

fn same(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

#[test]
fn every_instruction_set_gives_the_rows_of_row_at() {
    // Sorted angles (groups in one segment: the lane path), a group across
    // every segment end, unsorted and out-of-turn angles (one by one), and a
    // tail shorter than a group; compiled for baseline, AVX2 and AVX-512.
    let mut theta: Vec<f64> = (0..4003).map(|i| i as f64 * TAU / 4003.0).collect();
    for d in [0.0, 100.0, 150.0, 280.0, 360.0] {
        let e = f64::to_radians(d);
        theta.extend([e.next_down(), e, e.next_up(), e, e, e, e, e]);
    }
    theta.extend((0..41).map(|i| (i as f64 * 7.3).sin() * 40.0));
    theta.extend([2e6, -3e7, 1e6]);
    use pulp::Simd;
    for cam in cams() {
        let runs = on_each_isa!(|simd| {
            let mut out = vec![0.0; theta.len() * N_COLUMNS];
            Simd::vectorize(
                simd,
                Rows {
                    cam: &cam,
                    theta: &theta,
                    out: &mut out,
                },
            );
            out
        });
        assert!(runs.len() >= 2 || !cfg!(target_arch = "x86_64"));
        let mut row = [0.0; N_COLUMNS];
        for (i, &t) in theta.iter().enumerate() {
            cam.row(t, &mut row);
            for (isa, out) in &runs {
                for c in 0..N_COLUMNS {
                    let v = out[i * N_COLUMNS + c];
                    // The lanes' pressure angle is the inlined atan2's, row's the
                    // platform's: within 2 ulp; every other column bit for bit.
                    let near = COLUMNS[c] == "pressure_angle" && ulps(v, row[c]) <= 2.0;
                    assert!(
                        same(v, row[c]) || near,
                        "{isa}: θ = {t}, {}: {v} vs {}",
                        COLUMNS[c],
                        row[c]
                    );
                }
            }
        }
    }
}

#[test]
fn solve_into_reports_the_first_bad_angle() {
    let cam = cams().remove(0);
    let mut theta = vec![1.0; 3 * CHUNK];
    theta[2 * CHUNK + 5] = f64::NAN;
    theta[2 * CHUNK + 9] = f64::INFINITY;
    let mut out = vec![0.0; theta.len() * N_COLUMNS];
    let err = cam.solve_into(&theta, &mut out, Some(2)).unwrap_err();
    assert!(
        err.to_string()
            .contains(&format!("theta[{}]", 2 * CHUNK + 5)),
        "{err}"
    );
}

fn ulps(a: f64, b: f64) -> f64 {
    (a - b).abs() / (f64::EPSILON * b.abs().max(f64::MIN_POSITIVE))
}

proptest! {
    #[test]
    fn atan2_matches_the_platform(y in -1e3f64..1e3, x in -1e3f64..1e3, e in -300i32..300) {
        for (yy, xx) in [(y, x), (y * 2f64.powi(e), x), (y, x * 2f64.powi(e))] {
            let (a, b) = (super::atan2_lanes(&[yy], &[xx])[0], yy.atan2(xx));
            prop_assert!(ulps(a, b) <= 2.0, "atan2({yy}, {xx}) = {a} vs {b}");
        }
    }
}

#[test]
fn atan2_at_the_reduction_edges_and_special_values() {
    for a in [
        0.4375f64, 0.6875, 1.1875, 2.4375, 1.0, 0.5, 1.5, 1e-300, 1e300,
    ] {
        for t in [a.next_down(), a, a.next_up()] {
            for (y, x) in [(t, 1.0), (-t, 1.0), (t, -1.0), (-t, -1.0), (1.0, 1.0 / t)] {
                let (a, b) = (super::atan2_lanes(&[y], &[x])[0], y.atan2(x));
                assert!(ulps(a, b) <= 2.0, "atan2({y}, {x}) = {a} vs {b}");
            }
        }
    }
    let inf = f64::INFINITY;
    for (y, x) in [
        (0.0, 1.0),
        (-0.0, -1.0),
        (1.0, 0.0),
        (0.0, 0.0),
        (inf, 1.0),
        (1.0, -inf),
    ] {
        assert_eq!(
            super::atan2_lanes(&[y], &[x])[0].to_bits(),
            y.atan2(x).to_bits()
        );
    }
    assert!(super::atan2_lanes(&[f64::NAN], &[1.0])[0].is_nan());
}
