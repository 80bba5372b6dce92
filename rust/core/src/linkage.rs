//! Position, velocity and acceleration analysis of planar linkages over crank-angle
//! grids, by Assur groups solved in order (seed 001).
//!
//! A linkage is compiled (in Python, from its topology) into a [`Program`]: fixed
//! points, a driver (crank) and a sequence of steps, each placing one point from
//! points already known. This module holds the class II step in closed form:
//!
//! * [`Step::Circles`] — point `p` at distance `ra` from known `a` and `rb` from
//!   known `b`, on the side `sign` of the line a→b. This is the RRR dyad (two
//!   binary links meeting at `p`) and also a further joint of a rigid body two of
//!   whose joints are known (a coupler point). With `d = |b − a|`,
//!   `x = (ra² − rb² + d²) / 2d`, `h² = ra² − x²`; `h² < 0` is the seed's R² < 0:
//!   the mechanism cannot be assembled at that angle.
//!
//! The analogs (derivatives with respect to the crank angle φ) come from the
//! differentiated loop equations, exactly: `(p − a)·(p' − a') = 0` and
//! `(p − b)·(p' − b') = 0` give a 2×2 system for `p'`, and differentiating once
//! more, `(p − a)·(p'' − a'') + |p' − a'|² = 0` and the same for b, give `p''` with
//! the same matrix. Its determinant `(p − a) × (p − b)` vanishes at a dead centre,
//! where the analogs are infinite: such angles are flagged `singular`.

use rayon::prelude::*;

use crate::geom::{cross, dot, sub, V2};
use crate::triad::Triad;

/// Errors of the linkage domain.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LinkageError {
    #[error("{field}[{position}] = {value} is not a finite number; {what}")]
    NonFinite {
        field: &'static str,
        position: usize,
        value: f64,
        what: &'static str,
    },
    #[error("step {step} of the program is invalid: {why}")]
    BadProgram { step: usize, why: String },
    #[error(transparent)]
    Threads(#[from] crate::parallel::ThreadsError),
}

/// One step of a compiled linkage.
#[derive(Debug, Clone, PartialEq)]
pub enum Step {
    /// A class III group: the ternary link `joints` held by binary links to `anchors`.
    Triad {
        anchors: [usize; 3],
        joints: [usize; 3],
        triad: Triad,
    },
    /// The crank: `tip = pivot + radius·(cos φ, sin φ)` for the absolute crank angle φ.
    Driver {
        pivot: usize,
        tip: usize,
        radius: f64,
    },
    /// `p` at distance `ra` from `a` and `rb` from `b`, on side `sign` (±1) of a→b.
    Circles {
        a: usize,
        b: usize,
        p: usize,
        ra: f64,
        rb: f64,
        sign: f64,
    },
}

/// A compiled linkage: `n_points` points, the fixed ones with their coordinates,
/// then the steps in solving order (each step reads only points placed before it).
#[derive(Debug, Clone, PartialEq)]
pub struct Program {
    pub n_points: usize,
    pub fixed: Vec<(usize, [f64; 2])>,
    pub steps: Vec<Step>,
    /// The drawn pose (crank angle, every point): where a sweep through class III
    /// groups starts, so that it follows the drawn assembly.
    pub drawn: Option<(f64, Vec<[f64; 2]>)>,
}

/// Positions and analogs over an angle grid, row-major: `xy[(i * P + k) * 2 + c]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    pub xy: Vec<f64>,
    pub vel: Vec<f64>,
    pub acc: Vec<f64>,
    /// The mechanism can be assembled at the angle.
    pub ok: Vec<bool>,
    /// A dyad is at (or within round-off of) a dead centre: analogs are NaN there.
    pub singular: Vec<bool>,
}

/// A dyad whose determinant is below this fraction of `ra·rb` is at a dead centre.
const SINGULAR_REL: f64 = 1e-9;

/// Below this many angles a solve runs on the calling thread.
const PARALLEL_MIN_ANGLES: usize = 2048;

/// The pose just solved: positions, velocity and acceleration analogs, and the
/// step Δφ to the angle being solved.
type Prev<'a> = (&'a [V2], &'a [V2], &'a [V2], f64);

/// Largest crank-angle step along a path through class III groups [rad]: larger
/// gaps in the grid are walked in substeps so that Newton stays in its basin.
const MAX_PATH_STEP: f64 = std::f64::consts::PI / 180.0;

/// One angle's slot in the outputs: (((((φ, xy), vel), acc), ok), singular).
type AngleRow<'a> = (
    (
        (((&'a f64, &'a mut [V2]), &'a mut [V2]), &'a mut [V2]),
        &'a mut bool,
    ),
    &'a mut bool,
);

impl Program {
    /// Check indices and dimensions once, before any angle is solved.
    pub fn validate(&self) -> Result<(), LinkageError> {
        let n = self.n_points;
        let bad = |step: usize, why: String| Err(LinkageError::BadProgram { step, why });
        let mut placed = vec![false; n];
        for &(k, xy) in &self.fixed {
            if k >= n || !(xy[0].is_finite() && xy[1].is_finite()) {
                return bad(0, format!("fixed point {k} is out of range or not finite"));
            }
            placed[k] = true;
        }
        for (s, step) in self.steps.iter().enumerate() {
            let (reads, writes, dims): (Vec<usize>, Vec<usize>, Vec<f64>) = match step {
                Step::Triad {
                    anchors,
                    joints,
                    triad,
                } => {
                    if self.drawn.is_none() {
                        return bad(s, "a class III group needs the drawn pose".into());
                    }
                    let dims = triad.arms.iter().chain(&triad.sides).copied().collect();
                    (anchors.to_vec(), joints.to_vec(), dims)
                }
                &Step::Driver { pivot, tip, radius } => (vec![pivot], vec![tip], vec![radius]),
                &Step::Circles {
                    a,
                    b,
                    p,
                    ra,
                    rb,
                    sign,
                } => {
                    if sign != 1.0 && sign != -1.0 {
                        return bad(s, format!("sign must be +1 or -1, got {sign}"));
                    }
                    (vec![a, b], vec![p], vec![ra, rb])
                }
            };
            if writes.iter().chain(&reads).any(|&r| r >= n) {
                return bad(s, "a point index is out of range".into());
            }
            if let Some(&r) = reads.iter().find(|&&r| !placed[r]) {
                return bad(s, format!("it reads point {r} before any step places it"));
            }
            if let Some(&w) = writes.iter().find(|&&w| placed[w]) {
                return bad(s, format!("point {w} is placed twice"));
            }
            if dims.iter().any(|d| !(d.is_finite() && *d > 0.0)) {
                return bad(
                    s,
                    format!("lengths must be finite and positive, got {dims:?}"),
                );
            }
            for &w in &writes {
                placed[w] = true;
            }
        }
        if let Some((phi, pose)) = &self.drawn {
            let finite = phi.is_finite() && pose.iter().flatten().all(|v| v.is_finite());
            if pose.len() != n || !finite {
                return bad(
                    0,
                    "the drawn pose must give finite coordinates for every point".into(),
                );
            }
        }
        if let Some(k) = placed.iter().position(|&p| !p) {
            return bad(self.steps.len(), format!("point {k} is never placed"));
        }
        Ok(())
    }

    /// Solve one angle into `xy`, `vel`, `acc` (each P×2); returns (ok, singular).
    /// `prev` = (positions, velocity and acceleration analogs, Δφ) of the pose just
    /// solved, from which class III groups predict their next position.
    fn solve_one(
        &self,
        phi: f64,
        xy: &mut [V2],
        vel: &mut [V2],
        acc: &mut [V2],
        prev: Option<Prev<'_>>,
    ) -> (bool, bool) {
        for &(k, p) in &self.fixed {
            xy[k] = p;
            vel[k] = [0.0, 0.0];
            acc[k] = [0.0, 0.0];
        }
        let mut singular = false;
        for step in &self.steps {
            if let Step::Triad {
                anchors,
                joints,
                triad,
            } = step
            {
                let Some((px, pv, pa, dphi)) = prev else {
                    return (false, singular);
                };
                let k = anchors.map(|i| xy[i]);
                // Second-order predictor; a NaN analog (a singular pose) is dropped.
                let predicted = joints.map(|j| {
                    let step = |c: usize| {
                        let d = pv[j][c] * dphi + 0.5 * pa[j][c] * dphi * dphi;
                        px[j][c] + if d.is_finite() { d } else { 0.0 }
                    };
                    [step(0), step(1)]
                });
                let Some(found) = triad.solve(&k, predicted, 0.25 * triad.size()) else {
                    return (false, singular);
                };
                for (i, &j) in joints.iter().enumerate() {
                    xy[j] = found[i];
                }
                let (kv, ka) = (anchors.map(|i| vel[i]), anchors.map(|i| acc[i]));
                match triad.analogs(&k, &kv, &ka, &found) {
                    Some((v, a)) => {
                        for (i, &j) in joints.iter().enumerate() {
                            vel[j] = v[i];
                            acc[j] = a[i];
                        }
                    }
                    None => {
                        singular = true;
                        for &j in joints {
                            vel[j] = [f64::NAN; 2];
                            acc[j] = [f64::NAN; 2];
                        }
                    }
                }
                continue;
            }
            match *step {
                Step::Triad { .. } => {}
                Step::Driver { pivot, tip, radius } => {
                    let (s, c) = phi.sin_cos();
                    let o = xy[pivot];
                    xy[tip] = [o[0] + radius * c, o[1] + radius * s];
                    // The pivot is fixed; d/dφ of (cos, sin) is (−sin, cos).
                    vel[tip] = [-radius * s, radius * c];
                    acc[tip] = [-radius * c, -radius * s];
                }
                Step::Circles {
                    a,
                    b,
                    p,
                    ra,
                    rb,
                    sign,
                } => {
                    let (pa, pb) = (xy[a], xy[b]);
                    let d = sub(pb, pa);
                    let dd = dot(d, d);
                    let l = dd.sqrt();
                    if l == 0.0 {
                        return (false, singular);
                    }
                    let x = (ra * ra - rb * rb + dd) / (2.0 * l);
                    let h2 = ra * ra - x * x;
                    // Round-off can make a tangent position slightly negative.
                    let tol = 1e-12 * ra * ra;
                    if h2 < -tol {
                        return (false, singular);
                    }
                    let h = h2.max(0.0).sqrt();
                    let (ex, ey) = (d[0] / l, d[1] / l);
                    let q = [
                        pa[0] + x * ex - sign * h * ey,
                        pa[1] + x * ey + sign * h * ex,
                    ];
                    xy[p] = q;
                    let (u, w) = (sub(q, pa), sub(q, pb));
                    let det = cross(u, w);
                    if det.abs() <= SINGULAR_REL * ra * rb {
                        singular = true;
                        vel[p] = [f64::NAN, f64::NAN];
                        acc[p] = [f64::NAN, f64::NAN];
                        continue;
                    }
                    // [uᵀ; wᵀ] v = r  by Cramer's rule.
                    let solve = |r0: f64, r1: f64| -> V2 {
                        [(r0 * w[1] - r1 * u[1]) / det, (u[0] * r1 - w[0] * r0) / det]
                    };
                    let v = solve(dot(u, vel[a]), dot(w, vel[b]));
                    let (va, vb) = (sub(v, vel[a]), sub(v, vel[b]));
                    let ac = solve(dot(u, acc[a]) - dot(va, va), dot(w, acc[b]) - dot(vb, vb));
                    vel[p] = v;
                    acc[p] = ac;
                }
            }
        }
        (true, singular)
    }

    /// Class III groups have no closed form: the grid is walked from the drawn pose
    /// outwards, both ways (upwards through the angles above the drawn one, then
    /// downwards through those below), each pose predicted from the one before and
    /// gaps wider than [`MAX_PATH_STEP`] walked in substeps. An angle that cannot be
    /// reached continuously is `ok = false`; the walk goes on from the last pose.
    fn solve_path(
        &self,
        angles: &[f64],
        xy: &mut [V2],
        vel: &mut [V2],
        acc: &mut [V2],
        ok: &mut [bool],
        singular: &mut [bool],
    ) -> Result<(), LinkageError> {
        let p = self.n_points;
        let Some((drawn_phi, drawn)) = &self.drawn else {
            return Err(LinkageError::BadProgram {
                step: 0,
                why: "a class III group needs the drawn pose".into(),
            });
        };
        let mut order: Vec<usize> = (0..angles.len()).collect();
        order.sort_by(|&a, &b| angles[a].total_cmp(&angles[b]));
        let split = order.partition_point(|&i| angles[i] < *drawn_phi);
        let (below, above) = order.split_at(split);
        let zeros = vec![[0.0; 2]; p];
        let mut scratch = (zeros.clone(), zeros.clone(), zeros.clone());
        for walk in [above.to_vec(), below.iter().rev().copied().collect()] {
            // The drawn pose, closed and with its analogs, starts every walk.
            let mut state = (zeros.clone(), zeros.clone(), zeros.clone());
            let (good, _) = self.solve_one(
                *drawn_phi,
                &mut state.0,
                &mut state.1,
                &mut state.2,
                Some((drawn, &zeros, &zeros, 0.0)),
            );
            if !good {
                return Err(LinkageError::BadProgram {
                    step: 0,
                    why: "the drawn pose does not close: check the points and lengths".into(),
                });
            }
            let mut at = *drawn_phi;
            // Once a substep from the current pose fails, every angle beyond it in
            // this walk would retry the same step from the same pose: it is not
            // reachable continuously, and is marked so without solving again.
            let mut blocked: Option<f64> = None;
            for i in walk {
                let target = angles[i];
                let beyond = |b: f64| (target - b) * (b - at) >= 0.0;
                let (mut good, mut sing) = (blocked.is_none_or(|b| !beyond(b)), false);
                while good && at != target {
                    let next = if (target - at).abs() <= MAX_PATH_STEP {
                        target
                    } else {
                        at + MAX_PATH_STEP.copysign(target - at)
                    };
                    let prev = Some((&state.0[..], &state.1[..], &state.2[..], next - at));
                    let (g, s) =
                        self.solve_one(next, &mut scratch.0, &mut scratch.1, &mut scratch.2, prev);
                    good = g;
                    if g {
                        std::mem::swap(&mut state, &mut scratch);
                        at = next;
                        sing = s;
                    } else {
                        blocked = Some(next);
                    }
                }
                ok[i] = good;
                singular[i] = good && sing;
                let row = i * p..(i + 1) * p;
                if good {
                    xy[row.clone()].copy_from_slice(&state.0);
                    vel[row.clone()].copy_from_slice(&state.1);
                    acc[row].copy_from_slice(&state.2);
                } else {
                    xy[row.clone()].fill([f64::NAN; 2]);
                    vel[row.clone()].fill([f64::NAN; 2]);
                    acc[row].fill([f64::NAN; 2]);
                }
            }
        }
        Ok(())
    }

    /// Solve every angle of the grid (radians, absolute crank angle).
    pub fn solve(&self, angles: &[f64], n_threads: Option<i64>) -> Result<Solution, LinkageError> {
        self.validate()?;
        if let Some((i, &v)) = angles.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(LinkageError::NonFinite {
                field: "angles",
                position: i,
                value: v,
                what: "crank angles must be finite radians",
            });
        }
        let threads = crate::parallel::resolve_threads(n_threads)?;
        let (n, p) = (angles.len(), self.n_points);
        let mut xy_flat = vec![0.0; n * p * 2];
        let mut vel_flat = vec![0.0; n * p * 2];
        let mut acc_flat = vec![0.0; n * p * 2];
        // Viewed as (x, y) pairs in place: the kernel writes the final layout.
        let xy = xy_flat.as_chunks_mut::<2>().0;
        let vel = vel_flat.as_chunks_mut::<2>().0;
        let acc = acc_flat.as_chunks_mut::<2>().0;
        let mut ok = vec![false; n];
        let mut singular = vec![false; n];
        let one = |(((((phi, xy), vel), acc), ok), sing): AngleRow<'_>| {
            let (good, s) = self.solve_one(*phi, xy, vel, acc, None);
            *ok = good;
            *sing = s && good;
            if !good {
                for row in [xy, vel, acc] {
                    row.fill([f64::NAN; 2]);
                }
            }
        };
        let chunk = p.max(1);
        if self.steps.iter().any(|s| matches!(s, Step::Triad { .. })) {
            self.solve_path(angles, xy, vel, acc, &mut ok, &mut singular)?;
        } else if threads == 1 || n < PARALLEL_MIN_ANGLES {
            angles
                .iter()
                .zip(xy.chunks_mut(chunk))
                .zip(vel.chunks_mut(chunk))
                .zip(acc.chunks_mut(chunk))
                .zip(ok.iter_mut())
                .zip(singular.iter_mut())
                .for_each(one);
        } else {
            crate::parallel::pool(threads)?.install(|| {
                angles
                    .par_iter()
                    .zip(xy.par_chunks_mut(chunk))
                    .zip(vel.par_chunks_mut(chunk))
                    .zip(acc.par_chunks_mut(chunk))
                    .zip(ok.par_iter_mut())
                    .zip(singular.par_iter_mut())
                    .for_each(one)
            });
        }
        Ok(Solution {
            xy: xy_flat,
            vel: vel_flat,
            acc: acc_flat,
            ok,
            singular,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
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
            let s = prog.solve(&[phi - h, phi, phi + h], Some(1)).unwrap();
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

    #[test]
    fn unassemblable_angles_are_flagged() {
        // Non-Grashof: the crank (2) cannot turn fully; with l2 = l3 = 2, d = 3 the
        // position B = (-2, 0) is 5 away from D, beyond l2 + l3 = 4.
        let prog = four_bar(2.0, 2.0, 2.0, 3.0, 1.0);
        let s = prog.solve(&[0.0, std::f64::consts::PI], Some(1)).unwrap();
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
        assert!(prog.solve(&[f64::NAN], None).is_err());
        prog.n_points = 5;
        assert!(prog.validate().is_err());
    }
}
