//! Three-position motion generation (issue 35, item 3): a four-bar whose coupler
//! takes three given poses, by the classical construction.
//!
//! **Construction.** A pose is (x, y, θ): the coupler frame's origin at (x, y),
//! its x axis at θ [rad]. A *circle point* (a moving pivot) is chosen in the
//! coupler frame as (u, v); in pose i it is at (x_i, y_i) + R(θ_i)·(u, v). Its
//! three positions lie on a circle whose centre — the circumcentre, where the
//! perpendicular bisectors meet — is the *centre point*, the ground pivot that
//! keeps a binary link of constant length on the circle point in all three
//! poses. Two circle points give two such dyads; together with the coupler they
//! are a four-bar through the three poses (Burmester; Erdman & Sandor,
//! *Mechanism Design*, §8; Norton, *Design of Machinery*, §5.8). The family of
//! solutions is parametrised by the two circle points (four free numbers).
//!
//! **Degenerate choices.** Three collinear positions of a circle point have no
//! circumcentre (the centre at infinity): that dyad must be a slider, not a
//! pivoted link ([`MotionError::Collinear`]). Two coinciding positions mean the
//! circle point is a displacement pole: every point of a line is a centre
//! ([`MotionError::Pole`]). Two circle points with the same centre leave no
//! ground link ([`MotionError::SameCentre`]).
//!
//! **Defects.** The first dyad (centre A0, circle point A) is the crank. The
//! crank angles θ_i of A − A0 at the three poses fix its motion: it turns
//! counter-clockwise from pose 1 through pose 2 to pose 3 when
//! (θ2 − θ1) mod 2π < (θ3 − θ1) mod 2π, else clockwise; the working range is that
//! arc. A *branch defect* is a pose reached on the other assembly (the branch
//! σ_i, the side of the ray B0 → A that B lies on, differs between poses): the
//! linkage cannot go from one pose to the next without being taken apart. An
//! *order defect* is a working arc the linkage cannot sweep on one branch (it
//! cannot be assembled somewhere between the poses): the crank would have to
//! turn back, meeting the poses out of order.
//!
//! **Four and five poses** ([`super::burmester`]): the dyads come from
//! Burmester's curves or points, and [`fourbar_of_dyads`] applies the same
//! rules to n poses. With more than three the crank can also meet the poses out
//! of order however it turns (its angles from pose 1, counted one way, do not
//! increase through poses 2, …, n): that is an order defect too.

use std::f64::consts::TAU;

use super::fourbar::{fourbar_transmission, Transmission};
use crate::input::InvalidInput;

/// Relative tolerance for three positions on a line (the cross product against
/// the product of the two chords' lengths) and for coinciding positions
/// (against the poses' size).
pub const COLLINEAR_TOL: f64 = 1e-10;

/// A pose (x [m], y [m], θ [rad]).
pub type Pose = [f64; 3];

/// Errors of motion generation: every one names the circle point (`which`: 1
/// for the crank's, 2 for the rocker's) and says what would be valid.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MotionError {
    #[error(transparent)]
    Input(#[from] InvalidInput),
    #[error(
        "circle point {which} (u, v) = ({u}, {v}) m takes three collinear positions: its \
         centre point is at infinity, so that dyad would be a slider on a straight guide, \
         not a pivoted link; choose another circle point"
    )]
    Collinear { which: usize, u: f64, v: f64 },
    #[error(
        "circle point {which} (u, v) = ({u}, {v}) m is in the same place in poses {i} and \
         {j} (it is their displacement pole): its centre is not fixed; choose another circle point"
    )]
    Pole {
        which: usize,
        u: f64,
        v: f64,
        i: usize,
        j: usize,
    },
    #[error(
        "the two circle points have the same centre point: no ground link; choose circle \
         points that are not on one dyad"
    )]
    SameCentre,
    #[error(
        "poses[{i}] and poses[{j}] are coincident (the same place and angle): {n} distinct \
         poses are needed"
    )]
    Coincident { i: usize, j: usize, n: usize },
    #[error(
        "{what} needs {want} poses; got {got} (motion generation takes 3, 4 or 5 poses: \
         three by circumcentres, four by Burmester's curves, five by Burmester's points)"
    )]
    PoseCount {
        what: &'static str,
        want: &'static str,
        got: usize,
    },
    #[error(
        "circle point {which} (u, v) = ({u}, {v}) m with centre ({cx}, {cy}) m is not a dyad of \
         these poses: its positions' distances from the centre differ by {spread:.3e} of the \
         radius (more than 1e-6); take dyads from burmester_curves or burmester_points"
    )]
    NotADyad {
        which: usize,
        u: f64,
        v: f64,
        cx: f64,
        cy: f64,
        spread: f64,
    },
}

crate::input::wraps_invalid_input!(MotionError);

/// (u, v) of the coupler frame in pose p.
pub fn pose_point(p: Pose, uv: [f64; 2]) -> [f64; 2] {
    let (s, c) = p[2].sin_cos();
    [p[0] + c * uv[0] - s * uv[1], p[1] + s * uv[0] + c * uv[1]]
}

/// The circumcentre of three points, or the reason there is none.
fn circumcentre(
    q: [[f64; 2]; 3],
    which: usize,
    uv: [f64; 2],
    size: f64,
) -> Result<[f64; 2], MotionError> {
    let [p1, p2, p3] = q;
    let pairs = [(0, 1), (0, 2), (1, 2)];
    for (i, j) in pairs {
        let d = (q[i][0] - q[j][0]).hypot(q[i][1] - q[j][1]);
        if d <= COLLINEAR_TOL * size {
            return Err(MotionError::Pole {
                which,
                u: uv[0],
                v: uv[1],
                i: i + 1,
                j: j + 1,
            });
        }
    }
    let (bx, by) = (p2[0] - p1[0], p2[1] - p1[1]);
    let (cx, cy) = (p3[0] - p1[0], p3[1] - p1[1]);
    let cross = bx * cy - by * cx;
    if cross.abs() <= COLLINEAR_TOL * bx.hypot(by) * cx.hypot(cy) {
        return Err(MotionError::Collinear {
            which,
            u: uv[0],
            v: uv[1],
        });
    }
    // Relative to p1: |o|² = 2 o·b and |o|² = 2 o·c (o equidistant from 0, b, c).
    let (b2, c2) = (bx * bx + by * by, cx * cx + cy * cy);
    let ox = (cy * b2 - by * c2) / (2.0 * cross);
    let oy = (bx * c2 - cx * b2) / (2.0 * cross);
    Ok([p1[0] + ox, p1[1] + oy])
}

/// One dyad: its centre point (ground pivot) and the circle point's positions,
/// one per pose.
#[derive(Debug, Clone, PartialEq)]
pub struct Dyad {
    pub centre: [f64; 2],
    pub circle: Vec<[f64; 2]>,
}

/// Finite poses; their size (the largest |x|, |y|) for the relative tolerances.
pub(crate) fn check_poses(poses: &[Pose]) -> Result<f64, MotionError> {
    for (i, p) in poses.iter().enumerate() {
        for (k, &v) in p.iter().enumerate() {
            if !v.is_finite() {
                return Err(InvalidInput::NotFinite {
                    field: "poses",
                    index: 3 * i + k,
                    value: v,
                }
                .into());
            }
        }
    }
    let size = poses
        .iter()
        .fold(0.0f64, |m, p| m.max(p[0].abs()).max(p[1].abs()));
    Ok(size.max(1e-300))
}

/// The dyad of circle point `uv` (coupler frame, [m]) through three poses.
pub fn motion_dyad(poses: &[Pose; 3], uv: [f64; 2], which: usize) -> Result<Dyad, MotionError> {
    let size = check_poses(poses)?;
    InvalidInput::check_finite("circle_point", &uv)?;
    let circle = poses.map(|p| pose_point(p, uv));
    let size = size.max(uv[0].abs()).max(uv[1].abs());
    let centre = circumcentre(circle, which, uv, size)?;
    Ok(Dyad {
        centre,
        circle: circle.to_vec(),
    })
}

/// The dyad of circle point `uv` (coupler frame, [m]) and centre point `centre`
/// ([m]) through n poses, checked: the positions' distances from the centre
/// agree to 1e-6 of the radius (else [`MotionError::NotADyad`]).
pub fn dyad_through(
    poses: &[Pose],
    uv: [f64; 2],
    centre: [f64; 2],
    which: usize,
) -> Result<Dyad, MotionError> {
    check_poses(poses)?;
    InvalidInput::check_finite("circle_point", &uv)?;
    InvalidInput::check_finite("centre_point", &centre)?;
    let circle: Vec<[f64; 2]> = poses.iter().map(|&p| pose_point(p, uv)).collect();
    let r: Vec<f64> = circle
        .iter()
        .map(|q| (q[0] - centre[0]).hypot(q[1] - centre[1]))
        .collect();
    let (lo, hi) = r
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
    let spread = (hi - lo) / hi.max(1e-300);
    if spread.is_nan() || spread > 1e-6 {
        return Err(MotionError::NotADyad {
            which,
            u: uv[0],
            v: uv[1],
            cx: centre[0],
            cy: centre[1],
            spread,
        });
    }
    Ok(Dyad { centre, circle })
}

/// A four-bar through n poses and its defects (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct MotionFourBar {
    /// The crank's dyad (centre A0, circle point A).
    pub crank: Dyad,
    /// The rocker's dyad (centre B0, circle point B).
    pub rocker: Dyad,
    /// Crank a = |A − A0|, coupler b = |B − A|, rocker c = |B − B0|, ground
    /// d = |B0 − A0| [m].
    pub lengths: [f64; 4],
    /// The crank's absolute angles at the poses [rad], in (−π, π].
    pub crank_angles: Vec<f64>,
    /// +1: the crank turns counter-clockwise through the poses; −1 clockwise.
    pub direction: f64,
    /// The crank meets the poses in their order turning one way (always so for
    /// three poses; module docs).
    pub in_order: bool,
    /// The branch σ at each pose (module docs; 0 for a folded pose).
    pub branches: Vec<f64>,
    /// The working arc as (lo, hi) crank angles [rad] from the ground line
    /// A0 → B0 (lo < hi).
    pub arc: (f64, f64),
    /// The transmission angle over the working arc.
    pub transmission: Transmission,
}

impl MotionFourBar {
    /// A pose reached on the other branch (or folded).
    pub fn branch_defect(&self) -> bool {
        let s = self.branches[0];
        s == 0.0 || self.branches.iter().any(|&b| b != s)
    }

    /// The crank meets the poses out of order, or the working arc cannot be
    /// swept on one branch.
    pub fn order_defect(&self) -> bool {
        !self.in_order || matches!(self.transmission, Transmission::Breaks { .. })
    }
}

/// The four-bar of circle points `uv1` (the crank's) and `uv2` (the rocker's),
/// both in the coupler frame [m], through three poses (module docs).
pub fn motion_fourbar(
    poses: &[Pose; 3],
    uv1: [f64; 2],
    uv2: [f64; 2],
) -> Result<MotionFourBar, MotionError> {
    let crank = motion_dyad(poses, uv1, 1)?;
    let rocker = motion_dyad(poses, uv2, 2)?;
    fourbar_of_dyads(poses, crank, rocker)
}

/// The four-bar of two dyads through the same n ≥ 3 poses (the crank's first),
/// with its defects (module docs). With n poses the crank meets them in order
/// when its angles, counted from pose 1 the way it turns, increase through
/// poses 2, …, n: it is tried counter-clockwise, then clockwise; if neither,
/// `in_order` is false (an order defect) and the direction is that of the
/// shorter turn from pose 1 to pose 2, the arc running to the farthest pose.
pub fn fourbar_of_dyads(
    poses: &[Pose],
    crank: Dyad,
    rocker: Dyad,
) -> Result<MotionFourBar, MotionError> {
    let (a0, b0) = (crank.centre, rocker.centre);
    let dist = |p: [f64; 2], q: [f64; 2]| (p[0] - q[0]).hypot(p[1] - q[1]);
    let d = dist(a0, b0);
    let size = check_poses(poses)?
        .max(a0[0].abs().max(a0[1].abs()))
        .max(b0[0].abs().max(b0[1].abs()));
    if d <= COLLINEAR_TOL * size {
        return Err(MotionError::SameCentre);
    }
    let n = poses.len();
    let (a1, b1) = (crank.circle[0], rocker.circle[0]);
    let lengths = [dist(a1, a0), dist(b1, a1), dist(b1, b0), d];
    let ang = |p: [f64; 2], o: [f64; 2]| (p[1] - o[1]).atan2(p[0] - o[0]);
    let crank_angles: Vec<f64> = crank.circle.iter().map(|&p| ang(p, a0)).collect();
    let branches: Vec<f64> = (0..n)
        .map(|i| {
            let (u, w) = (crank.circle[i], rocker.circle[i]);
            let z = (u[0] - b0[0]) * (w[1] - b0[1]) - (u[1] - b0[1]) * (w[0] - b0[0]);
            if z > 0.0 {
                1.0
            } else if z < 0.0 {
                -1.0
            } else {
                0.0
            }
        })
        .collect();
    let t1 = crank_angles[0];
    let ccw: Vec<f64> = crank_angles[1..]
        .iter()
        .map(|t| (t - t1).rem_euclid(TAU))
        .collect();
    let cw: Vec<f64> = crank_angles[1..]
        .iter()
        .map(|t| (t1 - t).rem_euclid(TAU))
        .collect();
    let increasing = |v: &[f64]| v.windows(2).all(|w| w[0] < w[1]);
    let (direction, in_order) = if increasing(&ccw) {
        (1.0, true)
    } else if increasing(&cw) {
        (-1.0, true)
    } else if ccw[0] <= cw[0] {
        (1.0, false)
    } else {
        (-1.0, false)
    };
    let ground = ang(b0, a0);
    let rel1 = t1 - ground;
    let arc = if direction > 0.0 {
        (rel1, rel1 + ccw.iter().fold(0.0f64, |m, &x| m.max(x)))
    } else {
        (rel1 - cw.iter().fold(0.0f64, |m, &x| m.max(x)), rel1)
    };
    let [a, b, c, _] = lengths;
    let transmission = fourbar_transmission(a, b, c, d, arc.0, arc.1)?;
    Ok(MotionFourBar {
        crank,
        rocker,
        lengths,
        crank_angles,
        direction,
        in_order,
        branches,
        arc,
        transmission,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synthesis::fourbar::fourbar_output_angle;
    use proptest::prelude::*;

    /// Three coupler poses of the known four-bar a, b, c, d (A0 at the origin,
    /// B0 at (d, 0)) at crank angles `th`, the pose frame at A with x along A → B.
    fn poses_of(a: f64, b: f64, c: f64, d: f64, th: [f64; 3], sigma: f64) -> Option<[Pose; 3]> {
        let mut out = [[0.0; 3]; 3];
        for (k, &t) in th.iter().enumerate() {
            let t4 = fourbar_output_angle(a, b, c, d, t, sigma)?;
            let pa = [a * t.cos(), a * t.sin()];
            let pb = [d + c * t4.cos(), c * t4.sin()];
            out[k] = [pa[0], pa[1], (pb[1] - pa[1]).atan2(pb[0] - pa[0])];
        }
        Some(out)
    }

    #[test]
    fn recovers_the_ground_pivots_of_a_known_four_bar() {
        let (a, b, c, d) = (1.0, 3.0, 3.5, 4.0);
        let poses = poses_of(a, b, c, d, [0.4, 1.1, 2.0], 1.0).unwrap();
        // The moving pivots in the coupler frame: A at (0, 0), B at (b, 0).
        let m = motion_fourbar(&poses, [0.0, 0.0], [b, 0.0]).unwrap();
        for (got, want) in m.crank.centre.iter().zip([0.0, 0.0]) {
            assert!((got - want).abs() < 1e-12);
        }
        for (got, want) in m.rocker.centre.iter().zip([d, 0.0]) {
            assert!((got - want).abs() < 1e-12);
        }
        for (got, want) in m.lengths.iter().zip([a, b, c, d]) {
            assert!((got - want).abs() < 1e-12);
        }
        assert_eq!(m.direction, 1.0);
        assert!(!m.branch_defect() && !m.order_defect());
        assert!((m.arc.0 - 0.4).abs() < 1e-12 && (m.arc.1 - 2.0).abs() < 1e-12);
    }

    #[test]
    fn degenerate_choices_are_named() {
        // Pure translation along x: every circle point moves on a line.
        let poses = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.5, 0.0, 0.0]];
        let e = motion_dyad(&poses, [0.3, 0.2], 1).unwrap_err();
        assert!(matches!(e, MotionError::Collinear { which: 1, .. }));
        assert!(e.to_string().contains("slider"));
        // A rotation about the origin: the origin is the pole of every pair.
        let poses = [[0.0, 0.0, 0.0], [0.0, 0.0, 0.5], [1.0, 0.0, 1.0]];
        let e = motion_dyad(&poses, [0.0, 0.0], 2).unwrap_err();
        assert!(
            matches!(
                e,
                MotionError::Pole {
                    which: 2,
                    i: 1,
                    j: 2,
                    ..
                }
            ),
            "{e:?}"
        );
        assert!(motion_dyad(
            &[[f64::NAN, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            [0.0, 0.0],
            1
        )
        .is_err());
    }

    proptest! {
        /// Three coupler poses of a random four-bar, with its moving pivots as
        /// the circle points, give back its ground pivots and lengths.
        #[test]
        fn any_four_bar_is_recovered_from_three_poses(
            a in 0.3f64..3.0, b in 0.3f64..3.0, c in 0.3f64..3.0, d in 0.3f64..3.0,
            t0 in -3.0f64..3.0, s1 in 0.1f64..1.0, s2 in 0.1f64..1.0,
        ) {
            let th = [t0, t0 + s1, t0 + s1 + s2];
            let Some(poses) = poses_of(a, b, c, d, th, 1.0) else { return Ok(()) };
            match motion_fourbar(&poses, [0.0, 0.0], [b, 0.0]) {
                Ok(m) => {
                    let tol = 1e-7 * (1.0 + a + b + c + d);
                    prop_assert!(m.crank.centre[0].abs() < tol && m.crank.centre[1].abs() < tol);
                    prop_assert!((m.rocker.centre[0] - d).abs() < tol && m.rocker.centre[1].abs() < tol);
                    for (got, want) in m.lengths.iter().zip([a, b, c, d]) {
                        prop_assert!((got - want).abs() < tol);
                    }
                    // Drawn from one branch, in order: no branch defect; an order
                    // defect exactly where the crank cannot sweep the arc (checked by
                    // sampling the closed-form output angle, and at the break found).
                    prop_assert!(!m.branch_defect());
                    prop_assert_eq!(m.direction, 1.0);
                    let sweeps = (0..=2000).all(|i| {
                        let t = th[0] + (th[2] - th[0]) * i as f64 / 2000.0;
                        fourbar_output_angle(a, b, c, d, t, 1.0).is_some()
                    });
                    match m.transmission {
                        Transmission::Breaks { theta, .. } => {
                            prop_assert!(fourbar_output_angle(a, b, c, d, theta, 1.0).is_none());
                            prop_assert!(th[0] <= theta && theta <= th[2]);
                        }
                        Transmission::Range { .. } => prop_assert!(sweeps),
                    }
                }
                // Nearly collinear or coinciding positions are refused, never answered wrongly.
                Err(MotionError::Collinear { .. } | MotionError::Pole { .. }) => {}
                Err(e) => prop_assert!(false, "{e}"),
            }
        }
    }

    proptest! {
        /// Circumcentre against its definition: equidistant from the three positions.
        #[test]
        fn centre_is_equidistant(
            x in prop::array::uniform3(-2.0f64..2.0), y in prop::array::uniform3(-2.0f64..2.0),
            t in prop::array::uniform3(-3.0f64..3.0), u in -1.0f64..1.0, v in -1.0f64..1.0,
        ) {
            let poses = [[x[0], y[0], t[0]], [x[1], y[1], t[1]], [x[2], y[2], t[2]]];
            if let Ok(dy) = motion_dyad(&poses, [u, v], 1) {
                let r: Vec<f64> = dy.circle.iter()
                    .map(|p| (p[0] - dy.centre[0]).hypot(p[1] - dy.centre[1])).collect();
                // Nearly collinear positions put the centre far away, where
                // rounding grows with its distance: checked up to 10⁴ m.
                prop_assume!(r[0] < 1e4);
                prop_assert!((r[0] - r[1]).abs() < 1e-9 * (1.0 + r[0]));
                prop_assert!((r[0] - r[2]).abs() < 1e-9 * (1.0 + r[0]));
            }
        }
    }
}
