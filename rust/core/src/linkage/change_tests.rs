//! Change points: found where the closed forms put them, followed smoothly
//! (checked against each mechanism's closed-form motion and against central
//! differences of the positions across them), held where they cannot repeat.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use proptest::prelude::*;

use super::model::*;

/// Four-bar A(0,0)–B (crank r), B–C (coupler l2), C–D (rocker l3), D(d, 0), drawn
/// at crank angle `phi0` with C on side `sign` of B→D.
fn four_bar(r: f64, l2: f64, l3: f64, d: f64, sign: f64, phi0: f64) -> Program {
    let b = [r * phi0.cos(), r * phi0.sin()];
    let (dx, dy) = (d - b[0], -b[1]);
    let l = (dx * dx + dy * dy).sqrt();
    let x = (l2 * l2 - l3 * l3 + l * l) / (2.0 * l);
    let h = (l2 * l2 - x * x).max(0.0).sqrt();
    let (ex, ey) = (dx / l, dy / l);
    let c = [b[0] + x * ex - sign * h * ey, b[1] + x * ey + sign * h * ex];
    Program {
        n_points: 4,
        fixed: vec![(0, [0.0, 0.0]), (3, [d, 0.0])],
        steps: vec![
            Step::Driver {
                pivot: 0,
                tip: 1,
                radius: r,
            },
            Step::Circles {
                a: 1,
                b: 3,
                p: 2,
                ra: l2,
                rb: l3,
                sign,
            },
        ],
        drawn: Some((phi0, vec![[0.0, 0.0], b, c, [d, 0.0]])),
    }
}

fn all() -> Request {
    Request {
        points: vec![0, 1, 2, 3],
        analogs: true,
    }
}

fn at(s: &Solution, i: usize, k: usize) -> [f64; 2] {
    [s.xy[(i * 4 + k) * 2], s.xy[(i * 4 + k) * 2 + 1]]
}

/// The largest gap between the analogs of point `k` and central differences of
/// its positions at step `h`, over `angles` (each with its ± h neighbours),
/// relative to the largest analog.
fn analogs_against_differences(prog: &Program, angles: &[f64], k: usize, h: f64) -> f64 {
    let grid: Vec<f64> = angles.iter().flat_map(|&a| [a - h, a, a + h]).collect();
    let s = prog.solve(&grid, &all(), Some(1)).unwrap();
    let (mut worst, mut scale) = (0.0f64, 0.0f64);
    for i in 0..angles.len() {
        let (m, c, p) = (at(&s, 3 * i, k), at(&s, 3 * i + 1, k), at(&s, 3 * i + 2, k));
        for d in 0..2 {
            let v = s.vel[((3 * i + 1) * 4 + k) * 2 + d];
            let a = s.acc[((3 * i + 1) * 4 + k) * 2 + d];
            worst = worst.max((v - (p[d] - m[d]) / (2.0 * h)).abs());
            worst = worst.max((a - (p[d] - 2.0 * c[d] + m[d]) / (h * h)).abs());
            scale = scale.max(v.abs()).max(a.abs());
        }
    }
    worst / scale
}

#[test]
fn a_parallelogram_has_two_change_points_and_stays_a_parallelogram() {
    // AB = DC, BC = AD: the links line up at crank angles 0 and π.
    let prog = four_bar(0.3, 1.0, 0.3, 1.0, 1.0, FRAC_PI_2);
    let cps = prog.change_points().unwrap();
    assert_eq!(cps.len(), 2, "{cps:?}");
    let want = [PI, TAU];
    for (c, w) in cps.iter().zip(want) {
        assert_eq!(c.step, 1);
        assert!(c.followed);
        assert!((c.phi - w).abs() < 1e-9, "{} against {w}", c.phi);
    }
    // The parallelogram's closed form: C = B + (1, 0), C' = B', C'' = B''; within
    // a window (h under 1e-3 of BC) the analogs are NaN and the row singular.
    let angles: Vec<f64> = (0..720).map(|i| 0.25 + i as f64 * TAU / 720.0).collect();
    let s = prog.solve(&angles, &all(), Some(1)).unwrap();
    let mut flagged = 0;
    for (i, &phi) in angles.iter().enumerate() {
        let (b, c) = (at(&s, i, 1), at(&s, i, 2));
        assert!(
            (c[0] - b[0] - 1.0).abs() < 1e-12 && (c[1] - b[1]).abs() < 1e-12,
            "{i}: {b:?} {c:?}"
        );
        // C's height over the diagonal B–D: twice the triangle BCD's area, 0.3 |sin φ|,
        // over |BD|.
        let h = 0.3 * phi.sin().abs() / ((1.0 - b[0]).powi(2) + b[1] * b[1]).sqrt();
        assert!(h > 1.0001e-3 || s.singular[i], "{i} {cps:?}");
        if s.singular[i] {
            flagged += 1;
            assert!(h <= 1.01e-3, "{phi}");
            assert!(s.vel[(i * 4 + 2) * 2].is_nan());
            continue;
        }
        for d in 0..2 {
            let (vb, vc) = (s.vel[(i * 4 + 1) * 2 + d], s.vel[(i * 4 + 2) * 2 + d]);
            let (ab, ac) = (s.acc[(i * 4 + 1) * 2 + d], s.acc[(i * 4 + 2) * 2 + d]);
            // Outside the window the closed form's analogs hold to 1e-7 of their scale
            // (0.3; 3.5e-8 at h = 1.3e-3 of BC, this grid's nearest angle to 0).
            assert!(
                (vb - vc).abs() < 3e-9 && (ab - ac).abs() < 3e-8,
                "{i} {phi} {vb} {vc} {ab} {ac}"
            );
        }
    }
    // The grid's nearest angle to π is within its window (3.1e-3 < 4.3e-3 rad),
    // to 0 not (3.07e-3 > 2.3e-3).
    assert_eq!(flagged, 1);
    // h ≈ 0.3 |φ − φc| / |BD|, |BD| = 1.3 at π and 0.7 at 0: windows 1e-3 |BD| / 0.3
    // (to the curvature of h over the scan's 5° bracket).
    for (c, bd) in cps.iter().zip([1.3, 0.7]) {
        let w = 1e-3 * bd / 0.3;
        assert!((c.window - w).abs() < 1e-2 * w, "{} against {w}", c.window);
    }
}

#[test]
fn the_differences_agree_across_the_change_points() {
    // Angles just outside each change point's window, the differences' stencils
    // (± 1e-3 rad) on one side of it.
    let prog = four_bar(0.3, 1.0, 0.3, 1.0, -1.0, 2.0);
    let near: Vec<f64> = [PI, TAU]
        .iter()
        .flat_map(|&c| [c - 3e-2, c - 1.2e-2, c + 1.2e-2, c + 3e-2])
        .collect();
    let err = analogs_against_differences(&prog, &near, 2, 1e-3);
    assert!(err < 1e-5, "{err}");
}

#[test]
fn a_near_parallelogram_has_none_and_keeps_its_drawn_assembly() {
    // DC 3e-4 longer: the two assemblies no longer meet (h ≥ 4e-3 of BC).
    let prog = four_bar(0.3, 1.0, 0.3003, 1.0, 1.0, FRAC_PI_2);
    assert!(prog.change_points().unwrap().is_empty());
    let angles: Vec<f64> = (0..360).map(|i| i as f64 * TAU / 360.0 + 1e-3).collect();
    assert!(analogs_against_differences(&prog, &angles, 2, 1e-5) < 1e-4);
}

#[test]
fn one_change_point_a_turn_is_held() {
    // s + l = p + q with unequal pairs: 0.2 + 0.9 = 0.5 + 0.6, one change point a
    // turn (crank angle 0), where the smooth motion would need two turns to repeat.
    for sign in [1.0, -1.0] {
        let prog = four_bar(0.2, 0.9, 0.5, 0.6, sign, 1.0);
        let cps = prog.change_points().unwrap();
        assert_eq!(cps.len(), 1, "{cps:?}");
        assert!(!cps[0].followed);
        assert!(
            (cps[0].phi - TAU).abs() < 1e-9
                || cps[0].phi.abs() < 1e-9
                || (cps[0].phi - TAU).abs() < 1e-9
        );
        // Held: the drawn side everywhere, as the plain closed form.
        let angles: Vec<f64> = (0..90).map(|i| 0.01 + i as f64 * TAU / 90.0).collect();
        let s = prog.solve(&angles, &all(), Some(1)).unwrap();
        for i in 0..angles.len() {
            let (b, c) = (at(&s, i, 1), at(&s, i, 2));
            let side =
                (1.0 - b[0]) * 0.0 + ((0.6 - b[0]) * (c[1] - b[1]) - (0.0 - b[1]) * (c[0] - b[0]));
            assert!(side * sign >= -1e-12, "{i}");
        }
    }
}

#[test]
fn a_deltoid_is_followed_through_both() {
    // AB = BC, CD = DA: change points at 0 and π.
    let prog = four_bar(0.5, 0.5, 1.0, 1.0, 1.0, 1.0);
    let cps = prog.change_points().unwrap();
    assert_eq!(cps.len(), 2, "{cps:?}");
    assert!(cps.iter().all(|c| c.followed));
    let near: Vec<f64> = [PI, TAU]
        .iter()
        .flat_map(|&c| [c - 2e-2, c + 2e-2])
        .collect();
    let err = analogs_against_differences(&prog, &near, 2, 1e-3);
    assert!(err < 1e-5, "{err}");
}

#[test]
fn an_isosceles_slider_crank_slides_on_two_crank_radii() {
    // Crank r, rod r, the block on the line through the crank's pivot: the block's
    // two assemblies (x = 2r cos φ and x = 0) meet at φ = ±π/2.
    let r: f64 = 0.25;
    let phi0: f64 = 0.4;
    let b = [r * phi0.cos(), r * phi0.sin()];
    let prog = Program {
        n_points: 3,
        fixed: vec![(0, [0.0, 0.0])],
        steps: vec![
            Step::Driver {
                pivot: 0,
                tip: 1,
                radius: r,
            },
            Step::Slide {
                a: 1,
                r,
                line: Line::Fixed {
                    o: [0.0, 0.0],
                    u: [1.0, 0.0],
                },
                p: 2,
                sign: 1.0,
            },
        ],
        drawn: Some((phi0, vec![[0.0, 0.0], b, [2.0 * r * phi0.cos(), 0.0]])),
    };
    let cps = prog.change_points().unwrap();
    assert_eq!(cps.len(), 2, "{cps:?}");
    assert!(
        (cps[0].phi - FRAC_PI_2).abs() < 1e-9 && (cps[1].phi - 1.5 * PI).abs() < 1e-9,
        "{cps:?}"
    );
    let angles: Vec<f64> = (0..720).map(|i| i as f64 * TAU / 720.0 + 1e-3).collect();
    let req = Request {
        points: vec![2],
        analogs: true,
    };
    let s = prog.solve(&angles, &req, Some(1)).unwrap();
    for (i, &phi) in angles.iter().enumerate() {
        assert!((s.xy[2 * i] - 2.0 * r * phi.cos()).abs() < 1e-12, "{phi}");
        // Flagged only where its h = r|cos φ| is under 1e-3 of r.
        assert_eq!(s.singular[i], phi.cos().abs() <= 1e-3, "{phi}");
        if !s.singular[i] {
            assert!((s.vel[2 * i] + 2.0 * r * phi.sin()).abs() < 1e-9, "{phi}");
            assert!((s.acc[2 * i] + 2.0 * r * phi.cos()).abs() < 1e-8, "{phi}");
        }
    }
}

#[test]
fn the_scan_grid_and_the_parallel_blocks_give_the_same_rows() {
    // Many angles (solved in parallel blocks, each split by branch) against one
    // at a time.
    let prog = four_bar(0.3, 1.0, 0.3, 1.0, 1.0, FRAC_PI_2);
    let angles: Vec<f64> = (0..5000).map(|i| -7.0 + i as f64 * 0.003).collect();
    let many = prog.solve(&angles, &all(), Some(2)).unwrap();
    for (i, &phi) in angles.iter().enumerate().step_by(97) {
        let one = prog.solve(&[phi], &all(), Some(1)).unwrap();
        assert_eq!(&one.xy[..], &many.xy[i * 8..i * 8 + 8]);
        assert_eq!(&one.vel[..], &many.vel[i * 8..i * 8 + 8]);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    #[test]
    fn parallelograms_and_their_crossed_forms(
        r in 0.05f64..0.9, phi0 in 0.05f64..3.0, sign in prop::sample::select(vec![1.0, -1.0]),
        d in 0.5f64..2.0,
    ) {
        prop_assume!(r < 0.95 * d);
        // Drawn above the frame, sign +1 is the parallelogram, −1 the crossed form;
        // both meet at 0 and π, and either is followed smoothly through them.
        let prog = four_bar(r, d, r, d, sign, phi0);
        let cps = prog.change_points().unwrap();
        prop_assert_eq!(cps.len(), 2);
        prop_assert!((cps[0].phi - PI).abs() < 1e-8 && (cps[1].phi - TAU).abs() < 1e-8, "{:?}", cps);
        let w = cps[0].window.max(cps[1].window);
        let near: Vec<f64> = [PI, TAU].iter().flat_map(|&c| [c - 2.0 * w - 2e-3, c + 2.0 * w + 2e-3]).collect();
        prop_assert!(analogs_against_differences(&prog, &near, 2, 1e-3) < 1e-4);
        if sign > 0.0 {
            let s = prog.solve(&[phi0 + 3.5, phi0 + 5.0], &all(), Some(1)).unwrap();
            for i in 0..2 {
                let (b, c) = (at(&s, i, 1), at(&s, i, 2));
                prop_assert!((c[0] - b[0] - d).abs() < 1e-10 && (c[1] - b[1]).abs() < 1e-10);
            }
        }
    }
}

#[test]
#[ignore = "timing, run by hand"]
fn change_point_search_cost() {
    let prog = four_bar(0.3, 1.1, 0.5, 1.0, 1.0, FRAC_PI_2);
    let angles: Vec<f64> = (0..360).map(|i| i as f64 * TAU / 360.0).collect();
    let n = 20000;
    let t = std::time::Instant::now();
    for _ in 0..n {
        std::hint::black_box(prog.change_points().unwrap());
    }
    let cp = t.elapsed().as_secs_f64() / n as f64;
    let t = std::time::Instant::now();
    for _ in 0..n {
        std::hint::black_box(prog.solve(&angles, &all(), Some(1)).unwrap());
    }
    let sv = t.elapsed().as_secs_f64() / n as f64;
    println!(
        "change points {:.2} µs, solve 360 with analogs {:.2} µs",
        cp * 1e6,
        sv * 1e6
    );
}

#[test]
#[ignore = "measurement, run by hand"]
fn analog_error_near_a_change_point() {
    let prog = four_bar(0.3, 1.0, 0.3, 1.0, 1.0, FRAC_PI_2);
    for delta in [1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7] {
        let s = prog
            .solve(&[PI - delta, PI + delta], &all(), Some(1))
            .unwrap();
        let mut e = [0.0f64; 3];
        for i in 0..2 {
            for d in 0..2 {
                let k = |v: &Vec<f64>, p: usize| v[(i * 4 + p) * 2 + d];
                e[0] = e[0].max((k(&s.xy, 2) - k(&s.xy, 1) - if d == 0 { 1.0 } else { 0.0 }).abs());
                e[1] = e[1].max((k(&s.vel, 2) - k(&s.vel, 1)).abs() / 0.3);
                e[2] = e[2].max((k(&s.acc, 2) - k(&s.acc, 1)).abs() / 0.3);
            }
        }
        println!(
            "delta {delta:e}: position {:.1e} m, velocity {:.1e}, acceleration {:.1e} (relative)",
            e[0], e[1], e[2]
        );
    }
}

#[test]
fn a_coupler_point_is_not_searched() {
    // A point of the coupler B–C (anchors B and C, held at a fixed distance): no
    // change point whatever the four-bar, and the parallelogram's own are found.
    let mut prog = four_bar(0.3, 1.0, 0.3, 1.0, 1.0, FRAC_PI_2);
    prog.n_points = 5;
    prog.steps.push(Step::Circles {
        a: 1,
        b: 2,
        p: 4,
        ra: 0.5,
        rb: 0.7,
        sign: 1.0,
    });
    if let Some((_, pose)) = &mut prog.drawn {
        pose.push([0.4, 0.7]);
    }
    assert!(prog.held_pairs().contains(&(1, 2)));
    let cps = prog.change_points().unwrap();
    assert_eq!(cps.iter().map(|c| c.step).collect::<Vec<_>>(), vec![1, 1]);
}
