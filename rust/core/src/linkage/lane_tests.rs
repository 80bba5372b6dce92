//! The SIMD lane kernel (`lanes`) against the one-angle scalar kernel
//! (`Program::solve_one`), bit for bit, on every instruction set.

use pulp::Simd;

use super::batch::Buffers;
use super::lanes::Blocks;
use super::model::*;
use super::solve::State;
use proptest::prelude::*;

/// A crank-rocker A–B–C–D with a coupler point G (two circles from B and C), a
/// block E at `le` from B on the rocker's line D–C (RRP on a moving guide) and a
/// block F at `lf` from C on a fixed guide (RRP on the frame), a point P where a
/// frame guide crosses the coupler line B–C (PRP) and a link D–Q of length `le`
/// aimed through a block at B (RPR).
#[allow(clippy::too_many_arguments)]
fn program(r: f64, l2: f64, l3: f64, d: f64, sign: f64, le: f64, lf: f64, tilt: f64) -> Program {
    Program {
        n_points: 9,
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
            Step::Circles {
                a: 1,
                b: 2,
                p: 6,
                ra: 0.7 * l2,
                rb: 0.6 * l2,
                sign: -sign,
            },
            Step::Slide {
                a: 1,
                r: le,
                line: Line::Through { b: 3, c: 2 },
                p: 4,
                sign: 1.0,
            },
            Step::Slide {
                a: 2,
                r: lf,
                line: Line::Fixed {
                    o: [0.5, -1.0],
                    u: [1.0, tilt],
                },
                p: 5,
                sign: -1.0,
            },
            Step::Cross {
                l1: Line::Fixed {
                    o: [0.0, 2.0],
                    u: [1.0, tilt],
                },
                l2: Line::Through { b: 1, c: 2 },
                p: 7,
            },
            Step::Aim {
                b: 3,
                s: 1,
                c: 8,
                len: le,
                sign: 1.0,
            },
        ],
        drawn: None,
    }
}

/// The lane kernel's solution on each instruction set.
fn on_each(
    prog: &Program,
    angles: &[f64],
    sel: &[usize],
    analogs: bool,
) -> Vec<(&'static str, Solution)> {
    let an = if analogs {
        prog.analogs_needed(sel)
    } else {
        vec![false; prog.steps.len()]
    };
    let (n, m) = (angles.len(), sel.len());
    on_each_isa!(|simd| {
        let mut buf = Buffers::new(n, m, analogs).unwrap();
        let mut out = buf.outputs().view(n, m, analogs).unwrap();
        Simd::vectorize(
            simd,
            Blocks {
                prog,
                an: &an,
                angles,
                sel,
                out: &mut out,
            },
        );
        buf.finish()
    })
}

/// `got` equals the one-angle kernel's result at every angle: the same bits
/// where assembled, NaN where not, the same flags.
fn assert_same_as_one_angle(
    isa: &str,
    prog: &Program,
    angles: &[f64],
    sel: &[usize],
    analogs: bool,
    got: &Solution,
) -> Result<(), TestCaseError> {
    let mut st = State::new(prog.n_points);
    let m = sel.len();
    for (i, &phi) in angles.iter().enumerate() {
        let pose = prog.solve_one::<true>(phi, &mut st.xy, &mut st.vel, &mut st.acc, None);
        prop_assert_eq!(got.ok[i], pose.ok, "{} ok at {}", isa, phi);
        prop_assert_eq!(
            got.singular[i],
            pose.ok && pose.singular,
            "{} singular",
            isa
        );
        prop_assert!(!got.branch[i]);
        for (k, &j) in sel.iter().enumerate() {
            for c in 0..2 {
                let at = (i * m + k) * 2 + c;
                let same = |g: f64, w: f64| {
                    if pose.ok {
                        g.to_bits() == w.to_bits() || (g.is_nan() && w.is_nan())
                    } else {
                        g.is_nan()
                    }
                };
                prop_assert!(
                    same(got.xy[at], st.xy[j][c]),
                    "{} xy of {} at {}",
                    isa,
                    j,
                    phi
                );
                if analogs {
                    prop_assert!(same(got.vel[at], st.vel[j][c]), "{} vel {} {}", isa, j, phi);
                    prop_assert!(same(got.acc[at], st.acc[j][c]), "{} acc {} {}", isa, j, phi);
                }
            }
        }
    }
    Ok(())
}

proptest! {
    #[test]
    fn lanes_equal_one_angle_at_a_time_on_every_isa(
        r in 0.3f64..2.5, l2 in 1.5f64..4.0, l3 in 1.5f64..3.5, d in 2.5f64..4.0,
        sign in prop::sample::select(vec![1.0, -1.0]),
        le in 0.5f64..5.0, lf in 0.5f64..4.0, tilt in -0.5f64..0.5,
        phi0 in -10.0f64..10.0, step in 1e-3f64..0.3, n in 1usize..40,
        sel in prop::sample::subsequence((0usize..9).collect::<Vec<_>>(), 1..=9),
        analogs in any::<bool>(),
    ) {
        let prog = program(r, l2, l3, d, sign, le, lf, tilt);
        prog.validate().unwrap();
        let angles: Vec<f64> = (0..n).map(|i| phi0 + step * i as f64).collect();
        for (isa, got) in on_each(&prog, &angles, &sel, analogs) {
            assert_same_as_one_angle(isa, &prog, &angles, &sel, analogs, &got)?;
        }
    }
}

#[test]
fn lanes_at_dead_centres_far_angles_and_exact_quadrants() {
    // Crank 1, coupler and rocker 2, ground 3: at φ = π (and its multiples),
    // |BD| = 4 = l2 + l3 and C is on the line B–D (a dead centre, h² = 0 up to
    // round-off); angles on quadrant edges, signed zeros, and beyond the sine's
    // reduction range (|φ| > 1e6: the platform's sin/cos in those lanes).
    let prog = program(1.0, 2.0, 2.0, 3.0, 1.0, 2.0, 1.5, 0.1);
    let mut angles: Vec<f64> = (-8..=8)
        .map(|k| k as f64 * std::f64::consts::FRAC_PI_2)
        .collect();
    angles.extend([0.0, -0.0, 1e-300, 2e6, -3e7, 1e6, 1e6 + 1.0, 7.0e5]);
    for analogs in [true, false] {
        let sel: Vec<usize> = (0..9).collect();
        for (isa, got) in on_each(&prog, &angles, &sel, analogs) {
            assert_same_as_one_angle(isa, &prog, &angles, &sel, analogs, &got).unwrap();
            assert!(got.ok.iter().any(|&o| o), "{isa}");
        }
    }
}

#[test]
fn only_the_analogs_asked_for_are_computed_and_the_flags_stay_the_mechanisms() {
    let prog = program(1.0, 3.5, 3.0, 3.5, 1.0, 3.0, 1.5, 0.2);
    // G (6) reads B and C; E (4) reads B, D, C; F (5) reads C; P (7) reads B,
    // C; Q (8) reads D, B.
    let (t, f) = (true, false);
    assert_eq!(prog.analogs_needed(&[6]), vec![t, t, t, f, f, f, f]);
    assert_eq!(prog.analogs_needed(&[1]), vec![t, f, f, f, f, f, f]);
    assert_eq!(prog.analogs_needed(&[0, 3]), vec![f; 7]);
    assert_eq!(prog.analogs_needed(&[5, 4]), vec![t, t, f, t, t, f, f]);
    assert_eq!(prog.analogs_needed(&[8]), vec![t, f, f, f, f, f, t]);
    assert_eq!(prog.analogs_needed(&[7]), vec![t, t, f, f, f, t, f]);
    // A subset's rows are the full solve's columns, bit for bit, and its flags
    // the full solve's: F's guide cannot be reached at some angles, which fails
    // the whole pose even when only B is asked for.
    let angles: Vec<f64> = (0..3001).map(|i| i as f64 * 0.0021).collect();
    let full = prog.solve(
        &angles,
        &Request {
            points: (0..9).collect(),
            analogs: true,
        },
        Some(1),
    );
    let full = full.unwrap();
    for sel in [vec![1], vec![6, 2], vec![5], vec![3, 0], vec![8, 7]] {
        let req = Request {
            points: sel.clone(),
            analogs: true,
        };
        let s = prog.solve(&angles, &req, Some(2)).unwrap();
        assert_eq!(s.ok, full.ok);
        assert_eq!(s.singular, full.singular);
        let m = sel.len();
        for i in 0..angles.len() {
            for (k, &j) in sel.iter().enumerate() {
                for c in 0..2 {
                    let (a, b) = ((i * m + k) * 2 + c, (i * 9 + j) * 2 + c);
                    for (x, y) in [(&s.xy, &full.xy), (&s.vel, &full.vel), (&s.acc, &full.acc)] {
                        assert!(
                            x[a].to_bits() == y[b].to_bits() || (x[a].is_nan() && y[b].is_nan())
                        );
                    }
                }
            }
        }
    }
}
