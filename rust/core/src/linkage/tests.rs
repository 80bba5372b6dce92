use crate::geom::{dot, sub, V2};

use super::batch::*;
use super::model::*;
use super::solve::*;
use super::triad::Triad;
use proptest::prelude::*;

/// Crank-rocker A(0,0)–B (crank r), B–C (coupler l2), C–D (rocker l3), D(d, 0).
fn four_bar(r: f64, l2: f64, l3: f64, d: f64, sign: f64) -> Program {
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
        drawn: None,
    }
}

fn all(p: usize) -> Request {
    Request {
        points: (0..p).collect(),
        analogs: true,
    }
}

fn point(s: &Solution, i: usize, p: usize, k: usize) -> V2 {
    let base = (i * p + k) * 2;
    [s.xy[base], s.xy[base + 1]]
}

proptest! {
    #[test]
    fn lengths_hold_and_analogs_match_differences(
        r in 0.5f64..1.5, l2 in 3.0f64..4.0, l3 in 2.5f64..3.5, d in 3.0f64..4.0,
        sign in prop::sample::select(vec![1.0, -1.0]),
        phi in 0.0f64..std::f64::consts::TAU,
    ) {
        // Grashof crank-rocker: shortest link the crank, s + l <= p + q.
        let mut links = [r, l2, l3, d];
        links.sort_by(f64::total_cmp);
        prop_assume!(links[0] + links[3] < links[1] + links[2] - 1e-3);
        let prog = four_bar(r, l2, l3, d, sign);
        let h = 1e-5;
        let s = prog.solve(&[phi - h, phi, phi + h], &all(4), Some(1)).unwrap();
        prop_assert!(s.ok.iter().all(|&o| o));
        let (b, c, dd) = (point(&s, 1, 4, 1), point(&s, 1, 4, 2), point(&s, 1, 4, 3));
        let len = |u: V2, v: V2| dot(sub(u, v), sub(u, v)).sqrt();
        prop_assert!((len(b, c) - l2).abs() < 1e-12 * l2);
        prop_assert!((len(c, dd) - l3).abs() < 1e-12 * l3);
        for comp in 0..2 {
            let base = (4 + 2) * 2 + comp;
            let fd1 = (s.xy[(2 * 4 + 2) * 2 + comp] - s.xy[2 * 2 + comp]) / (2.0 * h);
            let fd2 = (s.xy[(2 * 4 + 2) * 2 + comp] - 2.0 * s.xy[base] + s.xy[2 * 2 + comp]) / (h * h);
            prop_assert!((s.vel[base] - fd1).abs() < 1e-6 * (1.0 + fd1.abs()));
            prop_assert!((s.acc[base] - fd2).abs() < 1e-3 * (1.0 + fd2.abs()));
        }
    }
}

/// Finite-difference check of the analogs of point `k` at angle `phi`.
fn check_analogs(prog: &Program, k: usize, phi: f64) {
    let h = 1e-5;
    let req = Request {
        points: vec![k],
        analogs: true,
    };
    let s = prog.solve(&[phi - h, phi, phi + h], &req, Some(1)).unwrap();
    assert!(s.ok.iter().all(|&o| o));
    for c in 0..2 {
        let fd1 = (s.xy[4 + c] - s.xy[c]) / (2.0 * h);
        let fd2 = (s.xy[4 + c] - 2.0 * s.xy[2 + c] + s.xy[c]) / (h * h);
        assert!(
            (s.vel[2 + c] - fd1).abs() < 1e-6 * (1.0 + fd1.abs()),
            "vel {} vs {fd1}",
            s.vel[2 + c]
        );
        assert!(
            (s.acc[2 + c] - fd2).abs() < 1e-3 * (1.0 + fd2.abs()),
            "acc {} vs {fd2}",
            s.acc[2 + c]
        );
    }
}

#[test]
fn slider_crank_matches_its_closed_form() {
    // Crank A(0,0)–B (r), rod B–C (l), C on the guide y = e along +x.
    let (r, l, e) = (0.1, 0.35, 0.02);
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
                r: l,
                line: Line::Fixed {
                    o: [0.0, e],
                    u: [2.0, 0.0],
                },
                p: 2,
                sign: 1.0,
            },
        ],
        drawn: None,
    };
    let angles: Vec<f64> = (0..360).map(|i| (i as f64).to_radians()).collect();
    let s = prog.solve(&angles, &all(3), Some(1)).unwrap();
    for (i, &phi) in angles.iter().enumerate() {
        let (sn, cs) = phi.sin_cos();
        let root = (l * l - (r * sn - e).powi(2)).sqrt();
        let x = r * cs + root;
        let dx = -r * sn - (r * sn - e) * r * cs / root;
        let base = (i * 3 + 2) * 2;
        assert!((s.xy[base] - x).abs() < 1e-14 && (s.xy[base + 1] - e).abs() < 1e-15);
        assert!((s.vel[base] - dx).abs() < 1e-13 && s.vel[base + 1].abs() < 1e-15);
    }
    check_analogs(&prog, 2, 0.7);
    // The other assembly: C behind the crank.
    let mut back = prog.clone();
    if let Step::Slide { sign, .. } = &mut back.steps[1] {
        *sign = -1.0;
    }
    let s = back.solve(&[0.0], &all(3), Some(1)).unwrap();
    assert!((s.xy[4] - (r - (l * l - e * e).sqrt())).abs() < 1e-14);
}

#[test]
fn inverted_slider_crank_and_yoke_match_closed_forms() {
    // Crank A(0,0)–B (r); rocker O(0,−d)–C (len) whose line passes through B.
    let (r, d, len) = (0.1, 0.25, 0.5);
    let prog = Program {
        n_points: 4,
        fixed: vec![(0, [0.0, 0.0]), (2, [0.0, -d])],
        steps: vec![
            Step::Driver {
                pivot: 0,
                tip: 1,
                radius: r,
            },
            Step::Aim {
                b: 2,
                s: 1,
                c: 3,
                len,
                sign: 1.0,
            },
        ],
        drawn: None,
    };
    let phi = 1.1;
    let s = prog.solve(&[phi], &all(4), Some(1)).unwrap();
    let theta = (r * phi.sin() + d).atan2(r * phi.cos());
    assert!((s.xy[6] - len * theta.cos()).abs() < 1e-14);
    assert!((s.xy[7] - (-d + len * theta.sin())).abs() < 1e-14);
    check_analogs(&prog, 3, phi);
    // PRP: P on the x axis and on the line from the crank tip B to D(0, 2).
    let yoke = Program {
        n_points: 4,
        fixed: vec![(0, [0.0, 0.0]), (2, [0.0, 2.0])],
        steps: vec![
            Step::Driver {
                pivot: 0,
                tip: 1,
                radius: r,
            },
            Step::Cross {
                l1: Line::Fixed {
                    o: [5.0, 0.0],
                    u: [1.0, 0.0],
                },
                l2: Line::Through { b: 1, c: 2 },
                p: 3,
            },
        ],
        drawn: None,
    };
    let s = yoke.solve(&[phi], &all(4), Some(1)).unwrap();
    let x = 2.0 * r * phi.cos() / (2.0 - r * phi.sin());
    assert!((s.xy[6] - x).abs() < 1e-14 && s.xy[7].abs() < 1e-15);
    check_analogs(&yoke, 3, phi);
    // An RRP dyad on a moving guide: E at 0.3 from A on the rocker's line O–C.
    let mut moving = prog.clone();
    moving.n_points = 5;
    moving.steps.push(Step::Slide {
        a: 0,
        r: 0.3,
        line: Line::Through { b: 2, c: 3 },
        p: 4,
        sign: 1.0,
    });
    check_analogs(&moving, 4, phi);
}

#[test]
fn positions_only_parallel_and_many_agree_with_one_serial_solve() {
    let prog = four_bar(1.0, 3.5, 3.0, 3.5, 1.0);
    let angles: Vec<f64> = (0..5000).map(|i| i as f64 * 0.00127).collect();
    let serial = prog.solve(&angles, &all(4), Some(1)).unwrap();
    let parallel = prog.solve(&angles, &all(4), Some(2)).unwrap();
    assert_eq!(serial, parallel);
    let pick = Request {
        points: vec![2],
        analogs: false,
    };
    let only = prog.solve(&angles, &pick, Some(2)).unwrap();
    assert!(only.vel.is_empty() && only.acc.is_empty());
    for i in 0..angles.len() {
        assert_eq!(
            only.xy[2 * i..2 * i + 2],
            serial.xy[(4 * i + 2) * 2..(4 * i + 2) * 2 + 2]
        );
    }
    let geoms = [
        four_bar(1.0, 3.5, 3.0, 3.5, 1.0),
        four_bar(1.2, 3.4, 3.1, 3.5, -1.0),
    ];
    let many = solve_many(&geoms, &angles, &all(4), Some(2)).unwrap();
    let n = angles.len() * 4 * 2;
    for (g, prog) in geoms.iter().enumerate() {
        let one = prog.solve(&angles, &all(4), Some(1)).unwrap();
        assert_eq!(many.xy[g * n..(g + 1) * n], one.xy[..]);
        assert_eq!(many.acc[g * n..(g + 1) * n], one.acc[..]);
    }
}

#[test]
fn blocks_of_angles_equal_one_angle_at_a_time() {
    // A crank-rocker with a coupler point E, over angles where it assembles
    // and where it does not (non-Grashof), and a grid that is not a multiple
    // of the block: the block path must give the one-angle path's bits.
    for (r, l2, l3, d) in [(1.0, 3.5, 3.0, 3.5), (2.0, 2.0, 2.0, 3.0)] {
        let mut prog = four_bar(r, l2, l3, d, 1.0);
        prog.n_points = 5;
        prog.steps.push(Step::Circles {
            a: 1,
            b: 2,
            p: 4,
            ra: 0.8 * l2,
            rb: 0.5 * l2,
            sign: -1.0,
        });
        let angles: Vec<f64> = (0..1003).map(|i| i as f64 * 0.00627).collect();
        for analogs in [true, false] {
            let req = Request {
                points: vec![4, 2, 0],
                analogs,
            };
            let s = prog.solve(&angles, &req, Some(1)).unwrap();
            let mut st = State::new(5);
            for (i, &phi) in angles.iter().enumerate() {
                let pose = prog.solve_one::<true>(phi, &mut st.xy, &mut st.vel, &mut st.acc, None);
                assert_eq!(s.ok[i], pose.ok);
                assert_eq!(s.singular[i], pose.ok && pose.singular);
                for (k, &j) in req.points.iter().enumerate() {
                    for c in 0..2 {
                        let at = (i * 3 + k) * 2 + c;
                        let same = |got: f64, want: f64| {
                            if pose.ok {
                                got.to_bits() == want.to_bits()
                            } else {
                                got.is_nan()
                            }
                        };
                        assert!(same(s.xy[at], st.xy[j][c]), "xy at {i}");
                        if analogs {
                            assert!(same(s.vel[at], st.vel[j][c]) && same(s.acc[at], st.acc[j][c]));
                        }
                    }
                }
            }
            assert!(s.ok.iter().any(|&o| o));
        }
    }
}

proptest! {
    #[test]
    fn short_way_keeps_the_crank_position(
        theta in prop::num::f64::NORMAL.prop_filter("finite", |v| v.abs() < 1e12),
        phi0 in -10.0f64..10.0,
    ) {
        let r = short_way(theta, phi0);
        prop_assert!((r - phi0).abs() <= std::f64::consts::PI * (1.0 + 1e-15));
        if (theta - phi0).abs() <= std::f64::consts::PI {
            prop_assert_eq!(r.to_bits(), theta.to_bits());
        }
        // The platform's own reduction of θ is the reference: the float 2π is
        // off the true one by |θ|·4e-17, below θ's rounding.
        let tol = 1e-15 * (1.0 + theta.abs()) * 4.0 + 1e-14;
        prop_assert!((r.sin() - theta.sin()).abs() <= tol, "{} {}", r, theta);
        prop_assert!((r.cos() - theta.cos()).abs() <= tol, "{} {}", r, theta);
    }
}

/// Issue 16 item 2's Stephenson six-bar: A(0,0), B(1,0), D(4,0), C on |BC| = 3.5
/// and |DC| = 2.6, E(2, 3.5), F(1.15, 5.6), G(1, 5.6); the group B–C–E held by
/// AB, DC and EF, the crank G–F.
fn stephenson() -> Program {
    let (b, d) = ([1.0, 0.0], [4.0, 0.0]);
    let l = 3.0f64;
    let x = (3.5f64 * 3.5 - 2.6 * 2.6 + l * l) / (2.0 * l);
    let c = [b[0] + x, (3.5f64 * 3.5 - x * x).sqrt()];
    let pts = vec![[0.0, 0.0], b, d, c, [2.0, 3.5], [1.15, 5.6], [1.0, 5.6]];
    let (k, j) = ([pts[0], pts[2], pts[5]], [pts[1], pts[3], pts[4]]);
    Program {
        n_points: 7,
        fixed: vec![(0, pts[0]), (2, pts[2]), (6, pts[6])],
        steps: vec![
            Step::Driver {
                pivot: 6,
                tip: 5,
                radius: 0.15,
            },
            Step::Triad {
                anchors: [0, 2, 5],
                joints: [1, 3, 4],
                triad: Triad::from_pose(k, j),
            },
        ],
        drawn: Some((0.0, pts)),
    }
}

#[test]
fn a_class_iii_walk_never_jumps_silently_at_a_fold() {
    let prog = stephenson();
    let angles: Vec<f64> = (0..=25000)
        .map(|i| (i as f64 * 0.01).to_radians())
        .collect();
    let s = prog.solve(&angles, &all(7), Some(1)).unwrap();
    assert!(s.ok.iter().all(|&o| o));
    let mut jumps = 0;
    for i in 0..angles.len() - 1 {
        let moved = (0..7)
            .map(|k| {
                let (p, q) = (point(&s, i, 7, k), point(&s, i + 1, 7, k));
                dot(sub(p, q), sub(p, q)).sqrt()
            })
            .fold(0.0, f64::max);
        if moved > 0.05 {
            jumps += 1;
            assert!(s.branch[i] || s.branch[i + 1], "silent jump at step {i}");
        }
    }
    assert!(jumps >= 1);
    // Every flagged pose (a re-acquired one) closes the group.
    for i in (0..angles.len()).filter(|&i| s.branch[i]) {
        let k = [point(&s, i, 7, 0), point(&s, i, 7, 2), point(&s, i, 7, 5)];
        let j = [point(&s, i, 7, 1), point(&s, i, 7, 3), point(&s, i, 7, 4)];
        let Step::Triad { triad, .. } = &prog.steps[1] else {
            unreachable!()
        };
        assert!(triad.closure_error(&k, &j) < 1e-12 * triad.size());
    }
}

/// The six-bar's group anchors (A, D and the crank tip F) at crank angle `deg` [°].
fn stephenson_anchors(deg: f64) -> [V2; 3] {
    let phi = deg.to_radians();
    [
        [0.0, 0.0],
        [4.0, 0.0],
        [1.0 + 0.15 * phi.cos(), 5.6 + 0.15 * phi.sin()],
    ]
}

/// The test's own continuation of the drawn branch: Newton from a secant predictor
/// at each angle of `degs` (from the drawn 0°, monotonic, 0.01° apart), `None` from
/// the first angle where no root stays within 0.01 m of the predictor on the drawn
/// determinant sign (the branch has ended).
fn continued(triad: &Triad, degs: &[f64]) -> Vec<Option<[V2; 3]>> {
    let drawn = stephenson();
    let pts = &drawn.drawn.as_ref().unwrap().1;
    let mut pose = [pts[1], pts[3], pts[4]];
    let mut back: Option<[V2; 3]> = None;
    let sign = triad.det_sign(&stephenson_anchors(0.0), &pose);
    let mut out = Vec::new();
    let mut alive = true;
    for &deg in degs {
        if alive {
            let k = stephenson_anchors(deg);
            let pred = match back {
                Some(b) => std::array::from_fn(|i| {
                    [2.0 * pose[i][0] - b[i][0], 2.0 * pose[i][1] - b[i][1]]
                }),
                None => pose,
            };
            let near =
                |j: &[V2; 3]| (0..3).all(|i| dot(sub(j[i], pred[i]), sub(j[i], pred[i])) < 1e-4);
            match triad.newton(&k, pred) {
                Some(j) if near(&j) && triad.det_sign(&k, &j) == sign => {
                    back = Some(pose);
                    pose = j;
                }
                _ => alive = false,
            }
        }
        out.push(alive.then_some(pose));
    }
    out
}

#[test]
fn the_six_bar_walk_flags_only_where_its_branch_folds() {
    // Issue 31 item 1 read the flag at 230.82° as a regular branch dropped. The
    // walk reaches 230.83° the short way, down from 360°, and the drawn branch
    // has a fold there (at 230.823°); the smooth pose of the issue is the same
    // circuit reached upwards from 0°, where the walk lands when it re-acquires.
    let prog = stephenson();
    let Step::Triad { triad, .. } = &prog.steps[1] else {
        unreachable!()
    };
    let degs: Vec<f64> = (0..=30000).map(|i| i as f64 * 0.01).collect();
    let angles: Vec<f64> = degs.iter().map(|d| d.to_radians()).collect();
    let s = prog.solve(&angles, &all(7), Some(1)).unwrap();
    assert!(s.ok.iter().all(|&o| o));
    let flags: Vec<usize> = (0..degs.len()).filter(|&i| s.branch[i]).collect();
    assert_eq!(flags, vec![23082], "flagged at {flags:?}");
    let walked = |i: usize| [point(&s, i, 7, 1), point(&s, i, 7, 3), point(&s, i, 7, 4)];
    let gap = |a: [V2; 3], b: [V2; 3]| {
        (0..3)
            .map(|i| dot(sub(a[i], b[i]), sub(a[i], b[i])).sqrt())
            .fold(0.0, f64::max)
    };
    // Upwards from 0° the branch is regular through the near-fold at 9.5° and
    // beyond 230.83°: the walk's up half (to 180°) and its re-acquired poses (from
    // 230.82° down to 180°) both lie on it.
    let up = continued(triad, &degs[..=23083]);
    for i in 0..=23082 {
        let j = up[i].unwrap_or_else(|| panic!("no upward branch at {}°", degs[i]));
        assert!(
            gap(j, walked(i)) < 1e-9,
            "{}°: {}",
            degs[i],
            gap(j, walked(i))
        );
    }
    // Downwards from 360° the walk agrees with the branch down to 230.83°, where it
    // ends: at 230.82° no root continues it (by Newton from the secant predictor),
    // and the seed's bracketing finds none near its last pose just below the fold.
    // −n·0.01° is 360° − n·0.01°, the grid's index 36000 − n; 230.83° is n = 12917.
    let down_degs: Vec<f64> = (0..=12918).map(|n| -(n as f64) * 0.01).collect();
    let down = continued(triad, &down_degs);
    for (n, j) in down.iter().enumerate().take(12918) {
        let i = 36000 - n;
        if i <= 30000 {
            let j = j.unwrap_or_else(|| panic!("no downward branch at {}°", degs[i]));
            assert!(
                gap(j, walked(i)) < 1e-9,
                "{}°: {}",
                degs[i],
                gap(j, walked(i))
            );
        }
    }
    assert!(down[12917].is_some() && down[12918].is_none());
    let last = down[12917].unwrap();
    let below = triad.bracket_all(&stephenson_anchors(230.825));
    assert!(
        below.iter().all(|r| gap(*r, last) > 0.05),
        "a root continues the branch"
    );
    // The flagged pose is 0.6 m from the one before it in the walk's order: the
    // upward branch, regular there (the walk re-acquired it, it did not invent it).
    assert!(gap(walked(23082), walked(23083)) > 0.6);
    assert!(gap(up[23083].unwrap(), walked(23083)) > 0.6);
}

#[test]
fn unassemblable_angles_are_flagged() {
    // Non-Grashof: the crank (2) cannot turn fully; with l2 = l3 = 2, d = 3 the
    // position B = (-2, 0) is 5 away from D, beyond l2 + l3 = 4.
    let prog = four_bar(2.0, 2.0, 2.0, 3.0, 1.0);
    let s = prog
        .solve(&[0.0, std::f64::consts::PI], &all(4), Some(1))
        .unwrap();
    assert_eq!(s.ok, vec![true, false]);
    assert!(s.xy[8..].iter().all(|v| v.is_nan()));
}

#[test]
fn bad_programs_are_errors() {
    let mut prog = four_bar(1.0, 3.0, 3.0, 3.0, 1.0);
    prog.steps.swap(0, 1);
    assert!(matches!(
        prog.validate(),
        Err(LinkageError::BadProgram { step: 0, .. })
    ));
    let mut prog = four_bar(1.0, 3.0, 3.0, 3.0, 0.5);
    assert!(prog.validate().is_err());
    prog = four_bar(-1.0, 3.0, 3.0, 3.0, 1.0);
    assert!(prog.validate().is_err());
    prog = four_bar(1.0, 3.0, 3.0, 3.0, 1.0);
    assert!(prog.solve(&[f64::NAN], &all(4), None).is_err());
    assert!(prog
        .solve(
            &[0.0],
            &Request {
                points: vec![4],
                analogs: true
            },
            None
        )
        .is_err());
    prog.n_points = 5;
    assert!(prog.validate().is_err());
}
