//! One program over an angle grid: class II steps in closed form across SIMD
//! lanes, class III groups followed along a path from the drawn pose.

use rayon::prelude::*;

use crate::geom::{cross, dot, sub, V2};

use super::batch::{check_angles, check_request, Buffers, Outputs};
use super::change::Branches;
use super::lanes::Blocks;
use super::model::{LinkageError, Program, Request, Solution, Step};

/// A group whose determinant is below this fraction of its dimensions' product is
/// at a dead centre.
pub(super) const SINGULAR_REL: f64 = 1e-9;
/// A two-circle (RRR) dyad is at its fold when its height² h² is within this
/// fraction of ra² of zero, the same round-off floor below which it does not
/// assemble: h ≤ 1e-6·ra, a crank angle of about 1e-12 rad from a toggle.
pub(super) const FOLD_H2_REL: f64 = 1e-12;

/// Angles per parallel task of a closed-form (class II) solve.
const BLOCK: usize = 1024;

/// How class III groups find their pose from the one before.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Seek {
    /// From the drawn pose: Newton from it, else the bracketed root nearest it
    /// (within a quarter of the group's size).
    Start,
    /// A continuation step: Newton from the predictor, kept only if it lands near
    /// the predictor (within half the predicted move, plus 1e-9 of the group's size).
    Follow,
    /// Re-acquisition after the followed branch has ended: the seed's bracketing,
    /// on the drawn assembly mode (bit t of the mask set where group t's Jacobian
    /// determinant is negative at the drawn pose), nearest the last pose.
    Acquire(u64),
}

/// The pose just solved (positions, velocity and acceleration analogs), the step
/// Δφ [rad] to the angle being solved, and how class III groups find their pose.
#[derive(Clone, Copy)]
pub(super) struct Prev<'a> {
    pub(super) xy: &'a [V2],
    pub(super) vel: &'a [V2],
    pub(super) acc: &'a [V2],
    pub(super) dphi: f64,
    pub(super) seek: Seek,
}

/// Largest crank-angle step along a path through class III groups [rad]: larger
/// gaps in the grid are walked in substeps so that Newton stays in its basin.
const MAX_PATH_STEP: f64 = std::f64::consts::PI / 180.0;

/// Smallest continuation step [rad]: a walk whose step is refused down to this
/// size has reached the end of its branch (a fold, or where the mechanism stops
/// assembling).
const MIN_PATH_STEP: f64 = 1e-9;

/// `theta` [rad] moved by whole turns into [φ0 − π, φ0 + π] around the drawn angle
/// φ0: the crank's position is 2π-periodic, and the walk goes the short way (in a
/// time bounded for any finite angle). Angles already within half a turn are kept
/// bit for bit. The reduction by the float 2π is exact (`%` is), and its offset from
/// the true 2π, |θ|·4e-17, is below the rounding of θ itself.
pub(super) fn short_way(theta: f64, phi0: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    let d = theta - phi0;
    if d.abs() <= PI {
        return theta;
    }
    let mut r = d % TAU;
    if r > PI {
        r -= TAU;
    } else if r < -PI {
        r += TAU;
    }
    phi0 + r
}

/// The outcome at one angle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Pose {
    pub(super) ok: bool,
    pub(super) singular: bool,
    /// One bit per class III group: its Jacobian's determinant is negative.
    pub(super) branch: u64,
}

impl Pose {
    const FAILED: Pose = Pose {
        ok: false,
        singular: false,
        branch: 0,
    };
}

/// Positions and analogs of every point at one angle.
#[derive(Clone)]
pub(super) struct State {
    pub(super) xy: Vec<V2>,
    pub(super) vel: Vec<V2>,
    pub(super) acc: Vec<V2>,
}

impl State {
    pub(super) fn new(p: usize) -> State {
        State {
            xy: vec![[0.0; 2]; p],
            vel: vec![[0.0; 2]; p],
            acc: vec![[0.0; 2]; p],
        }
    }
}

/// The output rows of a run of angles: `M` chosen points per row.
pub(super) struct Out<'a> {
    pub(super) xy: &'a mut [V2],
    pub(super) vel: &'a mut [V2],
    pub(super) acc: &'a mut [V2],
    pub(super) ok: &'a mut [bool],
    pub(super) singular: &'a mut [bool],
    pub(super) branch: &'a mut [bool],
}

impl<'a> Out<'a> {
    /// Rows before `at` and from `at` on.
    pub(super) fn split(self, at: usize, m: usize) -> (Out<'a>, Out<'a>) {
        let cut = |v: &'a mut [V2]| -> (&'a mut [V2], &'a mut [V2]) {
            if v.is_empty() {
                (&mut [], &mut [])
            } else {
                v.split_at_mut(at * m)
            }
        };
        let (x0, x1) = self.xy.split_at_mut(at * m);
        let (v0, v1) = cut(self.vel);
        let (a0, a1) = cut(self.acc);
        let (o0, o1) = self.ok.split_at_mut(at);
        let (s0, s1) = self.singular.split_at_mut(at);
        let (b0, b1) = self.branch.split_at_mut(at);
        (
            Out {
                xy: x0,
                vel: v0,
                acc: a0,
                ok: o0,
                singular: s0,
                branch: b0,
            },
            Out {
                xy: x1,
                vel: v1,
                acc: a1,
                ok: o1,
                singular: s1,
                branch: b1,
            },
        )
    }

    /// Row `i` from `state` (chosen points `sel`), or NaN where the pose failed.
    #[inline(always)]
    fn write(&mut self, i: usize, sel: &[usize], state: &State, pose: Pose, branch: bool) {
        let m = sel.len();
        let row = i * m..(i + 1) * m;
        self.ok[i] = pose.ok;
        self.singular[i] = pose.ok && pose.singular;
        self.branch[i] = pose.ok && branch;
        let an = !self.vel.is_empty();
        if !pose.ok {
            self.xy[row.clone()].fill([f64::NAN; 2]);
            if an {
                self.vel[row.clone()].fill([f64::NAN; 2]);
                self.acc[row].fill([f64::NAN; 2]);
            }
            return;
        }
        for (k, &j) in sel.iter().enumerate() {
            self.xy[i * m + k] = state.xy[j];
        }
        if an {
            for (k, &j) in sel.iter().enumerate() {
                self.vel[i * m + k] = state.vel[j];
                self.acc[i * m + k] = state.acc[j];
            }
        }
    }

    pub(super) fn fail_all(&mut self) {
        for v in [&mut *self.xy, &mut *self.vel, &mut *self.acc] {
            v.fill([f64::NAN; 2]);
        }
        self.ok.fill(false);
        self.singular.fill(false);
        self.branch.fill(false);
    }
}

/// `[n1ᵀ; n2ᵀ] x = (r1, r2)` by Cramer's rule, given `inv = 1 / (n1 × n2)`
/// (one division serves the velocity and the acceleration analog).
#[inline]
fn solve2(n1: V2, n2: V2, inv: f64, r1: f64, r2: f64) -> V2 {
    [
        (r1 * n2[1] - r2 * n1[1]) * inv,
        (n1[0] * r2 - n2[0] * r1) * inv,
    ]
}

/// √x where x > 0, else 0: a tangent position's round-off below zero (the lane
/// kernels take the same rule, bit for bit).
#[inline(always)]
fn sqrt_pos(x: f64) -> f64 {
    if x > 0.0 {
        x.sqrt()
    } else {
        0.0
    }
}

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
        let sign_ok = |s: f64| s == 1.0 || s == -1.0;
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
                    if !sign_ok(sign) {
                        return bad(s, format!("sign must be +1 or -1, got {sign}"));
                    }
                    (vec![a, b], vec![p], vec![ra, rb])
                }
                &Step::Slide {
                    a,
                    r,
                    line,
                    p,
                    sign,
                } => {
                    if !sign_ok(sign) {
                        return bad(s, format!("sign must be +1 or -1, got {sign}"));
                    }
                    let mut reads = line.reads();
                    reads.push(a);
                    let mut dims = line.dims();
                    dims.push(r);
                    (reads, vec![p], dims)
                }
                &Step::Cross { l1, l2, p } => {
                    let reads = [l1.reads(), l2.reads()].concat();
                    (reads, vec![p], [l1.dims(), l2.dims()].concat())
                }
                &Step::Aim {
                    b,
                    s: pin,
                    c,
                    len,
                    sign,
                } => {
                    if !sign_ok(sign) {
                        return bad(s, format!("sign must be +1 or -1, got {sign}"));
                    }
                    (vec![b, pin], vec![c], vec![len])
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

    pub(super) fn has_triads(&self) -> bool {
        self.steps.iter().any(|s| matches!(s, Step::Triad { .. }))
    }

    /// Solve one angle into `xy` and, when `AN`, `vel` and `acc` (each P×2).
    /// `prev` = (positions, velocity and acceleration analogs, Δφ) of the pose just
    /// solved, from which class III groups predict their next position (they need
    /// `AN`: the analogs are the predictor).
    #[inline(always)]
    pub(super) fn solve_one<const AN: bool>(
        &self,
        phi: f64,
        xy: &mut [V2],
        vel: &mut [V2],
        acc: &mut [V2],
        prev: Option<Prev<'_>>,
    ) -> Pose {
        const NAN2: V2 = [f64::NAN; 2];
        for &(k, p) in &self.fixed {
            xy[k] = p;
            if AN {
                vel[k] = [0.0, 0.0];
                acc[k] = [0.0, 0.0];
            }
        }
        let mut singular = false;
        let mut branch = 0u64;
        let mut n_triads = 0;
        for step in &self.steps {
            match *step {
                Step::Triad {
                    anchors,
                    joints,
                    ref triad,
                } => {
                    let Some(Prev {
                        xy: px,
                        vel: pv,
                        acc: pa,
                        dphi,
                        seek,
                    }) = prev
                    else {
                        return Pose::FAILED;
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
                    let last = joints.map(|j| px[j]);
                    let found = match seek {
                        Seek::Start => triad.solve(&k, predicted, 0.25 * triad.size()),
                        Seek::Follow => {
                            let moved = (0..3)
                                .map(|i| {
                                    dot(sub(predicted[i], last[i]), sub(predicted[i], last[i]))
                                })
                                .fold(0.0, f64::max)
                                .sqrt();
                            triad.follow(&k, predicted, 0.5 * moved + 1e-9 * triad.size())
                        }
                        Seek::Acquire(signs) => {
                            let negative = n_triads < 64 && signs >> n_triads & 1 == 1;
                            triad.acquire(&k, &last, if negative { -1.0 } else { 1.0 })
                        }
                    };
                    let Some(found) = found else {
                        return Pose::FAILED;
                    };
                    for (i, &j) in joints.iter().enumerate() {
                        xy[j] = found[i];
                    }
                    let (kv, ka) = (anchors.map(|i| vel[i]), anchors.map(|i| acc[i]));
                    let (det_sign, analogs) = triad.analogs(&k, &kv, &ka, &found);
                    if det_sign < 0.0 && n_triads < 64 {
                        branch |= 1 << n_triads;
                    }
                    n_triads += 1;
                    match analogs {
                        Some((v, a)) => {
                            for (i, &j) in joints.iter().enumerate() {
                                vel[j] = v[i];
                                acc[j] = a[i];
                            }
                        }
                        None => {
                            singular = true;
                            for &j in &joints {
                                vel[j] = NAN2;
                                acc[j] = NAN2;
                            }
                        }
                    }
                }
                Step::Driver { pivot, tip, radius } => {
                    let (s, c) = crate::geom::sin_cos(phi);
                    let o = xy[pivot];
                    xy[tip] = [o[0] + radius * c, o[1] + radius * s];
                    if AN {
                        // The pivot is fixed; d/dφ of (cos, sin) is (−sin, cos).
                        vel[tip] = [-radius * s, radius * c];
                        acc[tip] = [-radius * c, -radius * s];
                    }
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
                        return Pose::FAILED;
                    }
                    let inv = 1.0 / l;
                    let x = (ra * ra - rb * rb + dd) * (0.5 * inv);
                    let h2 = ra * ra - x * x;
                    // Round-off can make a tangent position slightly negative;
                    // NaN (from an overflowed distance) does not assemble either.
                    if h2.is_nan() || h2 < -1e-12 * ra * ra {
                        return Pose::FAILED;
                    }
                    let h = sqrt_pos(h2);
                    let (ex, ey) = (d[0] * inv, d[1] * inv);
                    let q = [
                        pa[0] + x * ex - sign * h * ey,
                        pa[1] + x * ey + sign * h * ex,
                    ];
                    xy[p] = q;
                    let (u, w) = (sub(q, pa), sub(q, pb));
                    let det = cross(u, w);
                    // At a fold (the two links in line) h² is round-off, and h its
                    // square root: ~1e-8 of the links, a determinant far above the
                    // 1e-9 tolerance and analogs of 1e22 (issue 31, item 2). An h²
                    // within the round-off floor is the fold itself: singular.
                    if det.abs() <= SINGULAR_REL * ra * rb || h2.abs() <= FOLD_H2_REL * ra * ra {
                        singular = true;
                        if AN {
                            vel[p] = NAN2;
                            acc[p] = NAN2;
                        }
                        continue;
                    }
                    if AN {
                        let inv = 1.0 / det;
                        let v = solve2(u, w, inv, dot(u, vel[a]), dot(w, vel[b]));
                        let (va, vb) = (sub(v, vel[a]), sub(v, vel[b]));
                        let r1 = dot(u, acc[a]) - dot(va, va);
                        vel[p] = v;
                        acc[p] = solve2(u, w, inv, r1, dot(w, acc[b]) - dot(vb, vb));
                    }
                }
                Step::Slide {
                    a,
                    r,
                    line,
                    p,
                    sign,
                } => {
                    let ln = line.at::<AN>(xy, vel, acc);
                    let el = dot(ln.e, ln.e).sqrt();
                    if el == 0.0 {
                        return Pose::FAILED;
                    }
                    let e = [ln.e[0] / el, ln.e[1] / el];
                    let ao = sub(xy[a], ln.o);
                    let (t0, off) = (dot(ao, e), cross(e, ao));
                    let q2 = r * r - off * off;
                    if q2.is_nan() || q2 < -1e-12 * r * r {
                        return Pose::FAILED;
                    }
                    let t = t0 + sign * sqrt_pos(q2);
                    let q = [ln.o[0] + t * e[0], ln.o[1] + t * e[1]];
                    xy[p] = q;
                    let (u, n) = (sub(q, xy[a]), ln.normal());
                    let det = cross(u, n);
                    if det.abs() <= SINGULAR_REL * r * el {
                        singular = true;
                        if AN {
                            vel[p] = NAN2;
                            acc[p] = NAN2;
                        }
                        continue;
                    }
                    if AN {
                        let inv = 1.0 / det;
                        let v = solve2(u, n, inv, dot(u, vel[a]), ln.rhs_v(q));
                        let va = sub(v, vel[a]);
                        let r1 = dot(u, acc[a]) - dot(va, va);
                        vel[p] = v;
                        acc[p] = solve2(u, n, inv, r1, ln.rhs_a(q, v));
                    }
                }
                Step::Cross { l1, l2, p } => {
                    let (g1, g2) = (l1.at::<AN>(xy, vel, acc), l2.at::<AN>(xy, vel, acc));
                    let (n1, n2) = (g1.normal(), g2.normal());
                    let det = cross(n1, n2);
                    let scale = dot(n1, n1).sqrt() * dot(n2, n2).sqrt();
                    // Parallel guides: no crossing (or a whole line of them).
                    if det.abs() <= SINGULAR_REL * scale || det.is_nan() {
                        return Pose::FAILED;
                    }
                    // n_i·q = n_i·o_i.
                    let inv = 1.0 / det;
                    let q = solve2(n1, n2, inv, dot(n1, g1.o), dot(n2, g2.o));
                    xy[p] = q;
                    if AN {
                        let v = solve2(n1, n2, inv, g1.rhs_v(q), g2.rhs_v(q));
                        vel[p] = v;
                        acc[p] = solve2(n1, n2, inv, g1.rhs_a(q, v), g2.rhs_a(q, v));
                    }
                }
                Step::Aim { b, s, c, len, sign } => {
                    let w = sub(xy[s], xy[b]);
                    let l2 = dot(w, w);
                    let l = l2.sqrt();
                    // The block at the link's pivot: the link's direction is free.
                    if l <= SINGULAR_REL * len {
                        return Pose::FAILED;
                    }
                    let (e, en) = ([w[0] / l, w[1] / l], [-w[1] / l, w[0] / l]);
                    let k = sign * len;
                    xy[c] = [xy[b][0] + k * e[0], xy[b][1] + k * e[1]];
                    if AN {
                        // θ' = w × w'/|w|², θ'' = w × w''/|w|² − 2 (w·w')(w × w')/|w|⁴.
                        let (w1, w2) = (sub(vel[s], vel[b]), sub(acc[s], acc[b]));
                        let t1 = cross(w, w1) / l2;
                        let t2 = cross(w, w2) / l2 - 2.0 * dot(w, w1) * cross(w, w1) / (l2 * l2);
                        vel[c] = [vel[b][0] + k * t1 * en[0], vel[b][1] + k * t1 * en[1]];
                        acc[c] = [
                            acc[b][0] + k * (t2 * en[0] - t1 * t1 * e[0]),
                            acc[b][1] + k * (t2 * en[1] - t1 * t1 * e[1]),
                        ];
                    }
                }
            }
        }
        Pose {
            ok: true,
            singular,
            branch,
        }
    }

    /// Class III groups have no closed form: the grid is walked from the drawn pose
    /// outwards, both ways (upwards through the angles above the drawn one, then
    /// downwards through those below), each pose predicted from the one before.
    ///
    /// * Angles are first moved by whole turns into [φ0 − π, φ0 + π] around the drawn
    ///   angle φ0 ([`short_way`]): θ and θ + 2πn are one crank position, solved the
    ///   short way from the drawing, in a time bounded for any finite angle.
    /// * A step is accepted only if Newton from the predictor lands near it and no
    ///   group's Jacobian determinant changed sign; otherwise it is halved. Gaps
    ///   wider than [`MAX_PATH_STEP`] are walked in substeps.
    /// * When the step is refused down to [`MIN_PATH_STEP`], the followed branch
    ///   has ended (a fold, or the mechanism stops assembling). From then on each
    ///   angle of the walk is re-acquired by the seed's bracketing, on the drawn
    ///   assembly mode (the sign of each group's determinant at the drawn pose)
    ///   nearest the last pose; the first angle re-acquired is flagged `branch`
    ///   (its pose is not continuous with the one before), angles where nothing
    ///   assembles are `ok = false`, and the walk follows on from the re-acquired pose.
    fn solve_path(
        &self,
        br: &Branches,
        angles: &[f64],
        sel: &[usize],
        out: &mut Out<'_>,
    ) -> Result<(), LinkageError> {
        let p = self.n_points;
        let Some((drawn_phi, drawn)) = &self.drawn else {
            return Err(LinkageError::BadProgram {
                step: 0,
                why: "a class III group needs the drawn pose".into(),
            });
        };
        let phi0 = *drawn_phi;
        let reduced: Vec<f64> = angles.iter().map(|&a| short_way(a, phi0)).collect();
        let mut order: Vec<usize> = (0..angles.len()).collect();
        order.sort_by(|&a, &b| reduced[a].total_cmp(&reduced[b]));
        let split = order.partition_point(|&i| reduced[i] < phi0);
        let (below, above) = order.split_at(split);
        let zeros = vec![[0.0; 2]; p];
        // The drawn pose, closed and with its analogs, starts every walk.
        let mut first = State::new(p);
        let start = self.solve_one::<true>(
            phi0,
            &mut first.xy,
            &mut first.vel,
            &mut first.acc,
            Some(Prev {
                xy: drawn,
                vel: &zeros,
                acc: &zeros,
                dphi: 0.0,
                seek: Seek::Start,
            }),
        );
        if !start.ok {
            return Err(LinkageError::BadProgram {
                step: 0,
                why: "the drawn pose does not close: check the points and lengths".into(),
            });
        }
        let mut scratch = State::new(p);
        for walk in [above.to_vec(), below.iter().rev().copied().collect()] {
            let mut state = first.clone();
            let (mut at, mut last) = (phi0, start);
            let mut ended = false;
            let mut h = MAX_PATH_STEP;
            for (k, i) in walk.into_iter().enumerate() {
                if k % 256 == 0 && crate::cancel::requested() {
                    return Ok(());
                }
                let target = reduced[i];
                // An angle equal to the current one is the pose already solved.
                let mut pose = last;
                let mut changed = false;
                while !ended && at != target {
                    let next = if (target - at).abs() <= h {
                        target
                    } else {
                        at + h.copysign(target - at)
                    };
                    let prev = Prev {
                        xy: &state.xy,
                        vel: &state.vel,
                        acc: &state.acc,
                        dphi: next - at,
                        seek: Seek::Follow,
                    };
                    let got = br.at(self, next).solve_one::<true>(
                        next,
                        &mut scratch.xy,
                        &mut scratch.vel,
                        &mut scratch.acc,
                        Some(prev),
                    );
                    if got.ok && got.branch == last.branch {
                        std::mem::swap(&mut state, &mut scratch);
                        (at, last, pose) = (next, got, got);
                        h = (2.0 * h).min(MAX_PATH_STEP);
                    } else {
                        h *= 0.5;
                        ended = h < MIN_PATH_STEP;
                    }
                }
                if ended {
                    let prev = Prev {
                        xy: &state.xy,
                        vel: &state.vel,
                        acc: &state.acc,
                        dphi: 0.0,
                        seek: Seek::Acquire(start.branch),
                    };
                    let got = br.at(self, target).solve_one::<true>(
                        target,
                        &mut scratch.xy,
                        &mut scratch.vel,
                        &mut scratch.acc,
                        Some(prev),
                    );
                    if got.ok {
                        std::mem::swap(&mut state, &mut scratch);
                        (at, last, pose) = (target, got, got);
                        (ended, changed, h) = (false, true, MAX_PATH_STEP);
                    } else {
                        pose = Pose::FAILED;
                    }
                }
                out.write(i, sel, &state, pose, changed);
            }
        }
        Ok(())
    }

    /// Closed-form groups only: every angle on its own, in blocks of
    /// [`super::lanes::LANES`] angles in SIMD when every step has a lane form (see
    /// [`super::lanes`]; the same bits), else one angle at a time. Only the
    /// analogs the chosen points need are computed.
    pub(super) fn solve_rows(&self, angles: &[f64], sel: &[usize], out: &mut Out<'_>) {
        let analogs = !out.vel.is_empty();
        if self.has_lane_form() {
            let an = if analogs {
                self.analogs_needed(sel)
            } else {
                vec![false; self.steps.len()]
            };
            pulp::Arch::new().dispatch(Blocks {
                prog: self,
                an: &an,
                angles,
                sel,
                out,
            });
            return;
        }
        let mut state = State::new(self.n_points);
        for (i, &phi) in angles.iter().enumerate() {
            let pose = if analogs {
                self.solve_one::<true>(phi, &mut state.xy, &mut state.vel, &mut state.acc, None)
            } else {
                self.solve_one::<false>(phi, &mut state.xy, &mut [], &mut [], None)
            };
            out.write(i, sel, &state, pose, false);
        }
    }

    /// Solve one run of angles single-threaded, through the change points of its
    /// class II groups (see [`super::change`]).
    pub(super) fn solve_serial(
        &self,
        angles: &[f64],
        sel: &[usize],
        out: &mut Out<'_>,
    ) -> Result<(), LinkageError> {
        let br = self.branches()?;
        self.solve_serial_with(&br, angles, sel, out)
    }

    /// [`Program::solve_serial`] with its change points already found.
    pub(super) fn solve_serial_with(
        &self,
        br: &Branches,
        angles: &[f64],
        sel: &[usize],
        out: &mut Out<'_>,
    ) -> Result<(), LinkageError> {
        self.solve_unflagged(br, angles, sel, out)?;
        br.flag(angles, sel.len(), out);
        Ok(())
    }

    /// [`Program::solve_serial_with`] without the change points' windows flagged
    /// (the search for them reads every row's analogs).
    pub(super) fn solve_unflagged(
        &self,
        br: &Branches,
        angles: &[f64],
        sel: &[usize],
        out: &mut Out<'_>,
    ) -> Result<(), LinkageError> {
        if self.has_triads() {
            self.solve_path(br, angles, sel, out)
        } else if br.is_trivial() {
            self.solve_rows(angles, sel, out);
            Ok(())
        } else {
            br.solve_rows(angles, sel, out);
            Ok(())
        }
    }

    /// Solve every angle of the grid (radians, absolute crank angle): the points
    /// and analogs of `request`, in parallel over the angles where no class III
    /// group makes the grid a path.
    pub fn solve(
        &self,
        angles: &[f64],
        request: &Request,
        n_threads: Option<i64>,
    ) -> Result<Solution, LinkageError> {
        let mut buffers = Buffers::new(angles.len(), request.points.len(), request.analogs)?;
        self.solve_into(angles, request, n_threads, buffers.outputs())?;
        Ok(buffers.finish())
    }

    /// [`Program::solve`] into caller-owned buffers (e.g. numpy arrays), laid out
    /// as [`Solution`]'s; every element is written.
    pub fn solve_into(
        &self,
        angles: &[f64],
        request: &Request,
        n_threads: Option<i64>,
        outputs: Outputs<'_>,
    ) -> Result<(), LinkageError> {
        self.validate()?;
        check_request(request, self.n_points)?;
        check_angles(angles)?;
        let threads = crate::parallel::resolve_threads(n_threads)?;
        let sel = &request.points;
        let mut out = outputs.view(angles.len(), sel.len(), request.analogs)?;
        let br = self.branches()?;
        if self.has_triads() || angles.len() < 2 * BLOCK {
            self.solve_serial_with(&br, angles, sel, &mut out)?;
        } else {
            let mut blocks = Vec::with_capacity(angles.len().div_ceil(BLOCK));
            let mut rest = out;
            for start in (0..angles.len()).step_by(BLOCK) {
                let take = BLOCK.min(angles.len() - start);
                let (head, tail) = rest.split(take, sel.len());
                blocks.push((start, head));
                rest = tail;
            }
            // One thread walks the same blocks in order: the rows are independent,
            // so the bits are the same, and Ctrl-C is seen between blocks.
            let one = |(start, mut block): (usize, Out<'_>)| {
                if crate::cancel::requested() {
                    return;
                }
                let run = &angles[start..start + block.ok.len()];
                if br.is_trivial() {
                    self.solve_rows(run, sel, &mut block);
                } else {
                    br.solve_rows(run, sel, &mut block);
                }
                br.flag(run, sel.len(), &mut block);
            };
            if threads == 1 {
                blocks.into_iter().for_each(one);
            } else {
                crate::parallel::pool(threads)?.install(|| blocks.into_par_iter().for_each(one));
            }
        }
        Ok(())
    }
}
