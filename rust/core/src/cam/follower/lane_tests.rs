//! The lane forms of the cam kernel (sin_cos, atan2, the rows) against the
//! scalar ones: bit for bit per instruction set, and [`Mode::Fast`] within a
//! tolerance of them (its bits alike on every instruction set).

use proptest::prelude::*;
use std::f64::consts::TAU;

use super::*;
use crate::cam::{Kind, SegmentSpec};
use crate::geom::{sin_cos, NEAR_RAD};

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
                    fast: false,
                    flags: &mut [],
                    theta_copy: &mut [],
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

/// The angles of the lane tests: sorted over a turn (groups in one segment),
/// a group across every segment end, unsorted and out-of-turn angles, and a
/// tail shorter than a group.
fn test_angles() -> Vec<f64> {
    let mut theta: Vec<f64> = (0..4003).map(|i| i as f64 * TAU / 4003.0).collect();
    for d in [0.0, 100.0, 150.0, 280.0, 360.0] {
        let e = f64::to_radians(d);
        theta.extend([e.next_down(), e, e.next_up(), e, e, e, e, e]);
    }
    theta.extend((0..41).map(|i| (i as f64 * 7.3).sin() * 40.0));
    theta.extend([2e6, -3e7, 1e6]);
    theta
}

/// The rows of `theta` through [`Rows`] on every instruction set, in
/// [`Mode::Fast`] (`fast`) or [`Mode::Lanes`].
fn rows_on_each_isa(cam: &Cam, theta: &[f64], fast: bool) -> Vec<(&'static str, Vec<f64>)> {
    use pulp::Simd;
    on_each_isa!(|simd| {
        let mut out = vec![0.0; theta.len() * N_COLUMNS];
        Simd::vectorize(
            simd,
            Rows {
                cam,
                theta,
                out: &mut out,
                fast,
                flags: &mut [],
                theta_copy: &mut [],
            },
        );
        out
    })
}

/// Largest allowed gap of [`Mode::Fast`] from `row_at`, in units of each
/// column's scale (its largest |value| over the test's angles); curvature for
/// the radii (they pass through infinity at an inflection of the pitch curve).
const FAST_TOL: f64 = 1e-13;

/// Checks the fast rows of `theta` against `row` (the platform path, the values
/// before issue 37's round 2) and their bits alike on every instruction set.
fn check_fast_rows(cam: &Cam, theta: &[f64]) -> Result<(), String> {
    let runs = rows_on_each_isa(cam, theta, true);
    let (_, first) = &runs[0];
    for (isa, out) in &runs {
        if let Some(i) = (0..out.len()).find(|&i| !same(out[i], first[i])) {
            return Err(format!(
                "{isa} differs from scalar at θ = {}",
                theta[i / N_COLUMNS]
            ));
        }
    }
    let rows: Vec<[f64; N_COLUMNS]> = theta
        .iter()
        .map(|&t| {
            let mut r = [0.0; N_COLUMNS];
            cam.row(t, &mut r);
            r
        })
        .collect();
    // Scales: |value| for the plain columns, curvature 1/ρ for the radii.
    let curv = |c: usize, v: f64| if c == 11 || c == 12 { 1.0 / v } else { v };
    let mut scale = [f64::MIN_POSITIVE; N_COLUMNS];
    for r in &rows {
        for c in 0..N_COLUMNS {
            let v = curv(c, r[c]);
            if v.is_finite() {
                scale[c] = scale[c].max(v.abs());
            }
        }
    }
    for (i, r) in rows.iter().enumerate() {
        for c in 0..N_COLUMNS {
            let (got, want) = (first[i * N_COLUMNS + c], r[c]);
            let (g, w) = (curv(c, got), curv(c, want));
            let close = same(g, w) || (g - w).abs() <= FAST_TOL * scale[c];
            // The undercut flag may flip only where its criterion is at its
            // threshold: ρ_pitch = r (profile radius 0) or an inflection.
            let edge = COLUMNS[c] == "undercut"
                && ((r[12] / r[11]).abs() <= 1e-9 || (1.0 / r[11]).abs() <= 1e-9 * scale[11]);
            if !(close || edge) {
                return Err(format!(
                    "θ = {}, {}: {got} vs {want} ({} of the scale {})",
                    theta[i],
                    COLUMNS[c],
                    (g - w).abs() / scale[c],
                    scale[c]
                ));
            }
        }
    }
    Ok(())
}

#[test]
fn fast_rows_are_row_at_within_a_tolerance_of_scale_on_every_instruction_set() {
    // The test angles, then a grid dense enough that every group lies near
    // its anchor (θ's sine and cosine rotated from it; asserted below).
    let dense: Vec<f64> = (0..30_000).map(|i| i as f64 * TAU / 30_000.0).collect();
    assert!((ANCHOR_GROUPS * GROUP) as f64 * TAU / 30_000.0 < NEAR_RAD);
    for cam in cams() {
        check_fast_rows(&cam, &test_angles()).unwrap();
        check_fast_rows(&cam, &dense).unwrap();
    }
}

/// The kernel's anchors for `theta` as one chunk: each whole group's.
fn anchors_of(theta: &[f64]) -> Vec<Option<Anchor>> {
    let mut out = Vec::new();
    let mut anchors = None;
    for g in 0..theta.len() / GROUP {
        if g % ANCHOR_GROUPS == 0 {
            anchors = anchors_at(theta, g);
        }
        out.push(anchors.map(|a| a[g % ANCHOR_GROUPS]));
    }
    out
}

#[test]
fn rotated_sin_cos_on_a_million_angles_is_within_4_eps_of_sin_cos() {
    // The bench's grid over a turn, as the kernel anchors it (chunks of
    // CHUNK angles), and a grid around 1e5 rad: every group rotated from its
    // anchor; each sine and cosine within 4ε of geom::sin_cos (fdlibm's
    // kernels, within an ulp of the platform).
    let turn: Vec<f64> = (0..1_000_000).map(|i| i as f64 * TAU / 1e6).collect();
    let far: Vec<f64> = (0..100_000).map(|i| 1e5 + i as f64 * 1e-4).collect();
    let mut worst = 0.0f64;
    for theta in [turn, far] {
        for chunk in theta.chunks(CHUNK) {
            for (tg, near) in chunk.chunks_exact(GROUP).zip(anchors_of(chunk)) {
                let tg: &[f64; GROUP] = tg.try_into().unwrap();
                let a = near.expect("an anchor for every group");
                let (sn, cs) = sin_cos_near_lanes(tg, a.theta, a.sin, a.cos)
                    .expect("every group near its anchor");
                for l in 0..GROUP {
                    let (s0, c0) = sin_cos(tg[l]);
                    worst = worst.max((sn[l] - s0).abs()).max((cs[l] - c0).abs());
                }
            }
        }
    }
    eprintln!("rotated sin_cos: worst {:.2} ε", worst / f64::EPSILON);
    assert!(worst <= 4.0 * f64::EPSILON, "worst {worst:e}");
}

#[test]
fn rotated_sin_cos_declines_far_or_nan_lanes_and_anchors_refuse_wide_angles() {
    let a = 0.3f64;
    let (sa, ca) = a.sin_cos();
    let mut x = [a; 8];
    x[5] = a + NEAR_RAD;
    assert!(sin_cos_near_lanes(&x, a, sa, ca).is_some());
    x[5] = (a + NEAR_RAD).next_up();
    assert!(sin_cos_near_lanes(&x, a, sa, ca).is_none());
    x[5] = a - 2.0 * NEAR_RAD;
    assert!(sin_cos_near_lanes(&x, a, sa, ca).is_none());
    x[5] = f64::NAN;
    assert!(sin_cos_near_lanes(&x, a, sa, ca).is_none());
    // An anchor beyond 1e6 rad (the fused kernel's range) or NaN: none for
    // the eight groups; fewer than a group: none.
    let mut theta = vec![1.0; 8 * GROUP];
    assert!(anchors_at(&theta, 0).is_some());
    theta[7 * GROUP] = 2e6;
    assert!(anchors_at(&theta, 0).is_none());
    theta[7 * GROUP] = f64::NAN;
    assert!(anchors_at(&theta, 0).is_none());
    assert!(anchors_at(&theta[..GROUP - 1], 0).is_none());
}

proptest! {
    #[test]
    fn rotated_sin_cos_anywhere_near_an_anchor(
        a in -1e6f64..1e6, d in prop::array::uniform8(-NEAR_RAD..=NEAR_RAD),
    ) {
        let x: [f64; 8] = std::array::from_fn(|l| a + d[l]);
        let (sa, ca) = crate::geom::sin_cos_fma_lanes(&[a]);
        let (sn, cs) = sin_cos_near_lanes(&x, a, sa[0], ca[0]).unwrap_or_default();
        // (a + d rounds: its lanes may lie a rounding beyond NEAR_RAD.)
        for l in 0..8 {
            if (x[l] - a).abs() <= NEAR_RAD {
                let (s0, c0) = sin_cos(x[l]);
                prop_assert!((sn[l] - s0).abs() <= 4.0 * f64::EPSILON, "sin {}", x[l]);
                prop_assert!((cs[l] - c0).abs() <= 4.0 * f64::EPSILON, "cos {}", x[l]);
            }
        }
    }
}

/// Within 2 ulp of `b`, or 6e-16 absolutely (the shorter arctangent's
/// polynomial is 2.4e-16 from atan at most).
fn near_atan(a: f64, b: f64) -> bool {
    ulps(a, b) <= 2.0 || (a - b).abs() <= 6e-16
}

proptest! {
    #[test]
    fn right_atan2_matches_the_platform(y in -1e3f64..1e3, x in 1e-3f64..1e3, e in -300i32..300) {
        for (yy, xx) in [(y, x), (y * 2f64.powi(e), x), (y, x * 2f64.powi(e)), (x, y.abs())] {
            let (a, b) = (super::atan2_right_lanes(&[yy], &[xx])[0], yy.atan2(xx));
            prop_assert!(near_atan(a, b), "atan2({yy}, {xx}) = {a} vs {b}");
        }
    }
}

#[test]
fn right_atan2_on_a_dense_grid_at_its_reduction_edges_and_special_values() {
    // Dense ratios over [0, 4] and their reciprocals (both branches of the
    // reduction), then the edges tan(π/8) and 1 to the ulp.
    let mut worst = 0.0f64;
    for i in 0..=400_000 {
        let r = i as f64 * 1e-5;
        for (y, x) in [(r, 1.0), (-r, 1.0), (1.0, r.max(1e-9)), (-1.0, r.max(1e-9))] {
            let (a, b) = (super::atan2_right_lanes(&[y], &[x])[0], y.atan2(x));
            assert!(near_atan(a, b), "atan2({y}, {x}) = {a} vs {b}");
            worst = worst.max((a - b).abs());
        }
    }
    eprintln!("right atan2: worst {worst:.2e} on the dense grid");
    assert!(worst <= 6e-16, "{worst:e}");
    let t8 = std::f64::consts::SQRT_2 - 1.0;
    for r in [t8, 1.0, 1e-300, 1e300, 1e-10, 1e10] {
        for t in [r.next_down(), r, r.next_up()] {
            for (y, x) in [(t, 1.0), (-t, 1.0), (1.0, t), (-1.0, t)] {
                let (a, b) = (super::atan2_right_lanes(&[y], &[x])[0], y.atan2(x));
                assert!(near_atan(a, b), "atan2({y}, {x}) = {a} vs {b}");
            }
        }
    }
    // Zeros keep their sign; x ≤ 0, infinities and huge values are the
    // platform's; NaN stays NaN.
    let inf = f64::INFINITY;
    for (y, x) in [
        (0.0, 1.0),
        (-0.0, 1.0),
        (0.0, -1.0),
        (1.0, 0.0),
        (1.0, -0.0),
        (-1.0, -2.0),
        (0.0, 0.0),
        (inf, 1.0),
        (1.0, inf),
        (1e308, 1e308),
        (-1e301, 1.0),
    ] {
        assert_eq!(
            super::atan2_right_lanes(&[y], &[x])[0].to_bits(),
            y.atan2(x).to_bits(),
            "atan2({y}, {x})"
        );
    }
    assert!(super::atan2_right_lanes(&[f64::NAN], &[1.0])[0].is_nan());
    assert!(super::atan2_right_lanes(&[1.0], &[f64::NAN])[0].is_nan());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]
    #[test]
    fn fast_rows_anywhere(
        start in 0.0f64..TAU, step in 1e-6f64..0.05, n in 1usize..40, shuffle in any::<bool>(),
        which in 0usize..12,
    ) {
        // Runs of evenly spaced angles from anywhere (the lane path where a
        // group stays in a segment), or the same angles reversed.
        let mut theta: Vec<f64> = (0..n).map(|i| start + i as f64 * step).collect();
        if shuffle {
            theta.reverse();
        }
        let cam = cams().swap_remove(which);
        prop_assert!(check_fast_rows(&cam, &theta).is_ok(), "{:?}", check_fast_rows(&cam, &theta));
    }
}

#[test]
fn the_flags_are_the_undercut_column_and_the_copy_the_angles() {
    // Cams with and without undercut, a length that leaves a tail, two threads
    // and one (the calling thread's path).
    let theta: Vec<f64> = (0..3 * CHUNK + 5).map(|i| i as f64 * 1e-3).collect();
    for cam in cams() {
        for threads in [1, 2] {
            let mut out = vec![0.0; theta.len() * N_COLUMNS];
            let mut flags = vec![false; theta.len()];
            let mut copy = vec![f64::NAN; theta.len()];
            cam.solve_flags_into(&theta, &mut out, &mut flags, &mut copy, Some(threads))
                .unwrap();
            let mut plain = vec![0.0; theta.len() * N_COLUMNS];
            cam.solve_into(&theta, &mut plain, Some(3 - threads))
                .unwrap();
            assert!(out.iter().zip(&plain).all(|(a, b)| same(*a, *b)));
            assert!(copy.iter().zip(&theta).all(|(a, b)| same(*a, *b)));
            for (i, &f) in flags.iter().enumerate() {
                assert_eq!(f, out[i * N_COLUMNS + 13] != 0.0, "θ = {}", theta[i]);
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
    // The good angles' rows are still written (the check is each lane
    // group's): those of the one angle alone.
    let mut one = [0.0; N_COLUMNS];
    cam.solve_into(&[1.0], &mut one, Some(1)).unwrap();
    let bad_group = (2 * CHUNK + 5) / GROUP;
    for threads in [1, 2] {
        let mut out = vec![f64::NAN; theta.len() * N_COLUMNS];
        let err = cam.solve_into(&theta, &mut out, Some(threads)).unwrap_err();
        assert!(
            err.to_string()
                .contains(&format!("theta[{}]", 2 * CHUNK + 5)),
            "{err}"
        );
        for (i, row) in out.chunks_exact(N_COLUMNS).enumerate() {
            if i / GROUP != bad_group && i / GROUP != bad_group + 1 {
                assert!(row.iter().zip(&one).all(|(a, b)| same(*a, *b)), "row {i}");
            }
        }
    }
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

proptest! {
    #[test]
    fn fast_atan2_matches_the_platform(y in -1e3f64..1e3, x in -1e3f64..1e3, e in -300i32..300) {
        for (yy, xx) in [(y, x), (y * 2f64.powi(e), x), (y, x * 2f64.powi(e)), (x, y)] {
            let (a, b) = (super::atan2_fast_lanes(&[yy], &[xx])[0], yy.atan2(xx));
            prop_assert!(ulps(a, b) <= 2.0, "atan2({yy}, {xx}) = {a} vs {b}");
        }
    }
}

#[test]
fn fast_atan2_at_its_reduction_edges_and_special_values() {
    let t8 = std::f64::consts::SQRT_2 - 1.0;
    for a in [t8, 1.0, 0.5, 2.0, 1e-300, 1e300, 1e-10, 1e10] {
        for t in [a.next_down(), a, a.next_up()] {
            for (y, x) in [
                (t, 1.0),
                (-t, 1.0),
                (t, -1.0),
                (-t, -1.0),
                (1.0, t),
                (-1.0, -t),
            ] {
                let (a, b) = (super::atan2_fast_lanes(&[y], &[x])[0], y.atan2(x));
                assert!(ulps(a, b) <= 2.0, "atan2({y}, {x}) = {a} vs {b}");
            }
        }
    }
    let inf = f64::INFINITY;
    for (y, x) in [
        (0.0, 1.0),
        (-0.0, -1.0),
        (0.0, -1.0),
        (1.0, 0.0),
        (-1.0, -0.0),
        (0.0, 0.0),
        (inf, 1.0),
        (1.0, -inf),
        (1e308, 1e308),
    ] {
        assert_eq!(
            super::atan2_fast_lanes(&[y], &[x])[0].to_bits(),
            y.atan2(x).to_bits(),
            "atan2({y}, {x})"
        );
    }
    assert!(super::atan2_fast_lanes(&[f64::NAN], &[1.0])[0].is_nan());
    assert!(super::atan2_fast_lanes(&[1.0], &[f64::NAN])[0].is_nan());
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
