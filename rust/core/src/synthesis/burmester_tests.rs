//! Tests of Burmester's curves and points against a known four-bar: its
//! coupler poses, drawn from its own closed-form position solution, have its
//! moving pivots on the circle-point curve and among Burmester's points.

use super::*;
use crate::synthesis::fourbar::fourbar_output_angle;
use crate::synthesis::motion::{dyad_through, fourbar_of_dyads};
use proptest::prelude::*;

/// Poses of the known four-bar a, b, c, d (A0 at the origin, B0 at (d, 0)) at
/// crank angles `th` on branch σ = 1: the pose point at `uv` of the frame at A
/// with x along A → B. Also A, B of the first pose.
fn poses_of(dims: [f64; 4], uv: [f64; 2], th: &[f64]) -> Option<(Vec<Pose>, [f64; 2], [f64; 2])> {
    let [a, b, c, d] = dims;
    let mut out = Vec::new();
    let mut first = None;
    for &t in th {
        let t4 = fourbar_output_angle(a, b, c, d, t, 1.0)?;
        let pa = [a * t.cos(), a * t.sin()];
        let pb = [d + c * t4.cos(), c * t4.sin()];
        let g = (pb[1] - pa[1]).atan2(pb[0] - pa[0]);
        let p = pose_point([pa[0], pa[1], g], uv);
        out.push([p[0], p[1], g]);
        first.get_or_insert((pa, pb));
    }
    let (pa, pb) = first?;
    Some((out, pa, pb))
}

/// World point `w` in pose p's coupler frame.
fn frame(p: Pose, w: [f64; 2]) -> [f64; 2] {
    let (s, c) = p[2].sin_cos();
    let (dx, dy) = (w[0] - p[0], w[1] - p[1]);
    [c * dx + s * dy, -s * dx + c * dy]
}

const DIMS: [f64; 4] = [1.0, 3.0, 3.5, 4.0];
const UV: [f64; 2] = [1.2, 0.8];

#[test]
fn a_known_four_bar_s_pivots_are_on_the_curves() {
    pivots_on_the_curves(DIMS, UV, &[0.3, 0.9, 1.6, 2.4]);
    // A rocker that barely turns: its dyad lies where the curve races through
    // a fold of the compatibility linkage (sampled through the fold, not in β).
    let deg = [0.0f64, 12.0, 24.0, 38.0].map(f64::to_radians);
    pivots_on_the_curves([0.5, 2.0, 2.0, 2.5], [0.0, 0.0], &deg);
}

fn pivots_on_the_curves(dims: [f64; 4], uv: [f64; 2], th: &[f64]) {
    let (poses, pa, pb) = poses_of(dims, uv, th).unwrap();
    let (ua, ub) = (frame(poses[0], pa), frame(poses[0], pb));
    let p4: [Pose; 4] = poses.clone().try_into().unwrap();
    // The cubic vanishes there (and not at an arbitrary point).
    assert!(circle_point_det(&p4, ua).unwrap().abs() < 1e-12);
    assert!(circle_point_det(&p4, ub).unwrap().abs() < 1e-12);
    assert!(circle_point_det(&p4, [0.3, -2.0]).unwrap().abs() > 1e-3);
    let curves = burmester_curves(&poses, 4096).unwrap();
    let near = |w: [f64; 2], f: &dyn Fn(&CurvePoint) -> [f64; 2]| {
        curves
            .branches
            .iter()
            .flatten()
            .map(|p| {
                let q = f(p);
                (q[0] - w[0]).hypot(q[1] - w[1])
            })
            .fold(f64::INFINITY, f64::min)
    };
    assert!(
        near(ua, &|p| p.circle) < 1e-2,
        "{}",
        near(ua, &|p| p.circle)
    );
    assert!(near(ub, &|p| p.circle) < 1e-2);
    assert!(near([0.0, 0.0], &|p| p.centre) < 1e-2);
    assert!(near([dims[3], 0.0], &|p| p.centre) < 1e-2);
    // Every sampled point is a dyad of the four poses.
    for p in curves.branches.iter().flatten() {
        let r: Vec<f64> = poses
            .iter()
            .map(|&q| {
                let w = pose_point(q, p.circle);
                (w[0] - p.centre[0]).hypot(w[1] - p.centre[1])
            })
            .collect();
        let rm = r[0];
        assert!(
            r.iter().all(|x| (x - rm).abs() <= 1e-9 * (1.0 + rm)),
            "{r:?}"
        );
    }
}

#[test]
fn five_poses_give_back_the_known_pivots() {
    let th = [0.3, 0.8, 1.4, 2.0, 2.7];
    let (poses, pa, pb) = poses_of(DIMS, UV, &th).unwrap();
    let (ua, ub) = (frame(poses[0], pa), frame(poses[0], pb));
    let pts = burmester_points(&poses).unwrap();
    assert!(pts.parity_ok);
    assert!(pts.points.len() >= 2 && pts.points.len().is_multiple_of(2));
    for (uv, c) in [(ua, [0.0, 0.0]), (ub, [DIMS[3], 0.0])] {
        let hit = pts.points.iter().any(|p| {
            (p.circle[0] - uv[0]).hypot(p.circle[1] - uv[1]) < 1e-7
                && (p.centre[0] - c[0]).hypot(p.centre[1] - c[1]) < 1e-7
        });
        assert!(hit, "{uv:?} not in {:?}", pts.points);
    }
    // The four-bar of the two is the known one, in order, on one branch.
    let a = dyad_through(&poses, ua, [0.0, 0.0], 1).unwrap();
    let b = dyad_through(&poses, ub, [DIMS[3], 0.0], 2).unwrap();
    let m = fourbar_of_dyads(&poses, a, b).unwrap();
    for (got, want) in m.lengths.iter().zip(DIMS) {
        assert!((got - want).abs() < 1e-12);
    }
    assert!(m.in_order && !m.branch_defect() && !m.order_defect());
    for (got, want) in m.crank_angles.iter().zip(th) {
        assert!((got - want).abs() < 1e-12);
    }
}

#[test]
fn bad_pose_sets_are_named() {
    let p = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.1],
        [2.0, 1.0, 0.3],
        [1.0, 0.0, 0.1],
    ];
    let e = burmester_curves(&p, 64).unwrap_err();
    assert!(
        matches!(e, MotionError::Coincident { i: 1, j: 3, n: 4 }),
        "{e}"
    );
    let e = burmester_points(&p).unwrap_err();
    assert!(e.to_string().contains("exactly 5"), "{e}");
    let e = burmester_curves(&[[f64::NAN, 0.0, 0.0]; 4], 64).unwrap_err();
    assert!(e.to_string().contains("not finite"), "{e}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]
    /// A random four-bar's moving pivots are among the Burmester points of five
    /// of its coupler poses; every point returned is a dyad of the five.
    #[test]
    fn any_four_bar_s_pivots_are_burmester_points(
        a in 0.5f64..2.0, b in 1.0f64..3.0, c in 1.0f64..3.0, d in 1.0f64..3.0,
        u in -1.0f64..1.0, v in -1.0f64..1.0, t0 in -3.0f64..3.0,
        steps in prop::array::uniform4(0.15f64..0.6),
    ) {
        let mut th = vec![t0];
        for s in steps { th.push(th[th.len() - 1] + s); }
        let Some((poses, pa, pb)) = poses_of([a, b, c, d], [u, v], &th) else { return Ok(()) };
        let (ua, ub) = (frame(poses[0], pa), frame(poses[0], pb));
        let pts = burmester_points(&poses).unwrap();
        let size = 1.0 + a + b + c + d;
        for (uv, cc) in [(ua, [0.0, 0.0]), (ub, [d, 0.0])] {
            let hit = pts.points.iter().any(|p| {
                (p.circle[0] - uv[0]).hypot(p.circle[1] - uv[1]) < 1e-7 * size
                    && (p.centre[0] - cc[0]).hypot(p.centre[1] - cc[1]) < 1e-7 * size
            });
            prop_assert!(hit, "{:?} not in {:?}", uv, pts.points);
        }
        prop_assert!(pts.points.len().is_multiple_of(2) && pts.points.len() <= 4);
        for p in &pts.points {
            for &q in &poses {
                let w = pose_point(q, p.circle);
                let r = (w[0] - p.centre[0]).hypot(w[1] - p.centre[1]);
                prop_assert!((r - p.radius).abs() <= 1e-9 * (1.0 + p.radius));
            }
        }
    }
}
