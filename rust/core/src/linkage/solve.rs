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

use super::triad::Triad;
use crate::geom::{cross, dot, sub, V2};

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
    #[error("the solution would need {bytes} bytes of memory, more than this machine can allocate; solve fewer angles, geometries or points at a time")]
    Memory { bytes: usize },
    #[error(transparent)]
    Threads(#[from] crate::parallel::ThreadsError),
}

/// The straight guide of a prismatic joint.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Line {
    /// Fixed to the frame: through `o` along `u` (any non-zero length).
    Fixed { o: V2, u: V2 },
    /// Along a moving link: through its joints `b` and `c`.
    Through { b: usize, c: usize },
}

/// A line at one pose: a point `o` on it, its direction `e` (not normalised), and
/// their first and second analogs.
struct LineAt {
    o: V2,
    e: V2,
    o1: V2,
    e1: V2,
    o2: V2,
    e2: V2,
}

impl Line {
    fn reads(&self) -> Vec<usize> {
        match *self {
            Line::Fixed { .. } => vec![],
            Line::Through { b, c } => vec![b, c],
        }
    }

    fn dims(&self) -> Vec<f64> {
        match *self {
            Line::Fixed { o, u } => {
                let n = dot(u, u).sqrt();
                // o may be anywhere (0 included); only u must be a direction.
                vec![1.0 + o[0].abs() + o[1].abs(), n]
            }
            Line::Through { .. } => vec![],
        }
    }

    fn at<const AN: bool>(&self, xy: &[V2], vel: &[V2], acc: &[V2]) -> LineAt {
        const Z: V2 = [0.0, 0.0];
        match *self {
            Line::Fixed { o, u } => LineAt {
                o,
                e: u,
                o1: Z,
                e1: Z,
                o2: Z,
                e2: Z,
            },
            Line::Through { b, c } => {
                let (o1, e1, o2, e2) = if AN {
                    (vel[b], sub(vel[c], vel[b]), acc[b], sub(acc[c], acc[b]))
                } else {
                    (Z, Z, Z, Z)
                };
                LineAt {
                    o: xy[b],
                    e: sub(xy[c], xy[b]),
                    o1,
                    e1,
                    o2,
                    e2,
                }
            }
        }
    }
}

impl LineAt {
    /// Normal row of `(p − o) × e = 0`: n·x = x × e.
    fn normal(&self) -> V2 {
        [self.e[1], -self.e[0]]
    }

    /// Right-hand side of n·p' for the first analog.
    fn rhs_v(&self, p: V2) -> f64 {
        dot(self.normal(), self.o1) - cross(sub(p, self.o), self.e1)
    }

    /// Right-hand side of n·p'' for the second analog, given p'.
    fn rhs_a(&self, p: V2, v: V2) -> f64 {
        dot(self.normal(), self.o2)
            - 2.0 * cross(sub(v, self.o1), self.e1)
            - cross(sub(p, self.o), self.e2)
    }
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
    /// RRR dyad (or a coupler point): `p` at distance `ra` from `a` and `rb` from
    /// `b`, on side `sign` (±1) of a→b.
    Circles {
        a: usize,
        b: usize,
        p: usize,
        ra: f64,
        rb: f64,
        sign: f64,
    },
    /// RRP dyad: `p` at distance `r` from `a` and on `line`; `sign` (±1) picks the
    /// intersection ahead of or behind the foot of `a` along the line's direction.
    Slide {
        a: usize,
        r: f64,
        line: Line,
        p: usize,
        sign: f64,
    },
    /// PRP dyad: `p` where two guides cross.
    Cross { l1: Line, l2: Line, p: usize },
    /// RPR dyad: the link b–c turns about known `b` and its line passes through
    /// known `s` (a block pinned at `s` slides on it): `c = b + sign·len·ŝ`, with ŝ
    /// the unit vector from b to s.
    Aim {
        b: usize,
        s: usize,
        c: usize,
        len: f64,
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

/// Positions and analogs of the chosen points over an angle grid (and, for a
/// sweep, over geometries), row-major: `xy[(i * M + k) * 2 + c]` for angle row `i`
/// and chosen point `k` of `M`. `vel` and `acc` are empty when analogs were not
/// asked for.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    pub xy: Vec<f64>,
    pub vel: Vec<f64>,
    pub acc: Vec<f64>,
    /// The mechanism can be assembled at the angle.
    pub ok: Vec<bool>,
    /// A group is at (or within round-off of) a dead centre: analogs are NaN there.
    pub singular: Vec<bool>,
    /// The pose is not continuous with the one solved before it in the walk from
    /// the drawn pose: the followed branch of a class III group ended (at a fold,
    /// or where the mechanism stopped assembling) and the group was re-acquired
    /// here by the seed's bracketing (see [`Program::solve_path`]).
    pub branch: Vec<bool>,
}

/// What to compute: which points (indices) and whether the analogs.
#[derive(Debug, Clone, PartialEq)]
pub struct Request {
    pub points: Vec<usize>,
    pub analogs: bool,
}

/// A group whose determinant is below this fraction of its dimensions' product is
/// at a dead centre.
const SINGULAR_REL: f64 = 1e-9;

/// Angles solved together by [`Program::solve_lanes`].
const LANES: usize = 8;

/// One coordinate of a point over a block of angles.
type Lane = [f64; LANES];

/// Angles per parallel task of a closed-form (class II) solve.
const BLOCK: usize = 1024;

/// How class III groups find their pose from the one before.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Seek {
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
struct Prev<'a> {
    xy: &'a [V2],
    vel: &'a [V2],
    acc: &'a [V2],
    dphi: f64,
    seek: Seek,
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
fn short_way(theta: f64, phi0: f64) -> f64 {
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
struct Pose {
    ok: bool,
    singular: bool,
    /// One bit per class III group: its Jacobian's determinant is negative.
    branch: u64,
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
struct State {
    xy: Vec<V2>,
    vel: Vec<V2>,
    acc: Vec<V2>,
}

impl State {
    fn new(p: usize) -> State {
        State {
            xy: vec![[0.0; 2]; p],
            vel: vec![[0.0; 2]; p],
            acc: vec![[0.0; 2]; p],
        }
    }
}

/// The output rows of a run of angles: `M` chosen points per row.
struct Out<'a> {
    xy: &'a mut [V2],
    vel: &'a mut [V2],
    acc: &'a mut [V2],
    ok: &'a mut [bool],
    singular: &'a mut [bool],
    branch: &'a mut [bool],
}

impl<'a> Out<'a> {
    /// Rows before `at` and from `at` on.
    fn split(self, at: usize, m: usize) -> (Out<'a>, Out<'a>) {
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

    /// Row `i` from lane `l` of a block's state (chosen points `sel`).
    #[inline(always)]
    #[allow(clippy::type_complexity)]
    fn write_lane(
        &mut self,
        i: usize,
        sel: &[usize],
        (xy, vel, acc): (&[[Lane; 2]], &[[Lane; 2]], &[[Lane; 2]]),
        l: usize,
        pose: Pose,
    ) {
        let m = sel.len();
        self.ok[i] = pose.ok;
        self.singular[i] = pose.ok && pose.singular;
        self.branch[i] = false;
        let an = !self.vel.is_empty();
        let pick = |v: &[[Lane; 2]], j: usize| -> V2 {
            if pose.ok {
                [v[j][0][l], v[j][1][l]]
            } else {
                [f64::NAN; 2]
            }
        };
        for (k, &j) in sel.iter().enumerate() {
            self.xy[i * m + k] = pick(xy, j);
            if an {
                self.vel[i * m + k] = pick(vel, j);
                self.acc[i * m + k] = pick(acc, j);
            }
        }
    }

    fn fail_all(&mut self) {
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

    fn has_triads(&self) -> bool {
        self.steps.iter().any(|s| matches!(s, Step::Triad { .. }))
    }

    /// Solve one angle into `xy` and, when `AN`, `vel` and `acc` (each P×2).
    /// `prev` = (positions, velocity and acceleration analogs, Δφ) of the pose just
    /// solved, from which class III groups predict their next position (they need
    /// `AN`: the analogs are the predictor).
    #[inline(always)]
    fn solve_one<const AN: bool>(
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
                    // Round-off can make a tangent position slightly negative.
                    if h2 < -1e-12 * ra * ra {
                        return Pose::FAILED;
                    }
                    let h = h2.max(0.0).sqrt();
                    let (ex, ey) = (d[0] * inv, d[1] * inv);
                    let q = [
                        pa[0] + x * ex - sign * h * ey,
                        pa[1] + x * ey + sign * h * ex,
                    ];
                    xy[p] = q;
                    let (u, w) = (sub(q, pa), sub(q, pb));
                    let det = cross(u, w);
                    if det.abs() <= SINGULAR_REL * ra * rb {
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
                    if q2 < -1e-12 * r * r {
                        return Pose::FAILED;
                    }
                    let t = t0 + sign * q2.max(0.0).sqrt();
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
            for i in walk {
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
                    let got = self.solve_one::<true>(
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
                    let got = self.solve_one::<true>(
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

    /// Closed-form groups only: every angle on its own (in blocks of [`LANES`]
    /// angles when the program is cranks and two-circle steps only).
    fn solve_rows(&self, angles: &[f64], sel: &[usize], out: &mut Out<'_>) {
        if self
            .steps
            .iter()
            .all(|s| matches!(s, Step::Driver { .. } | Step::Circles { .. }))
        {
            return if out.vel.is_empty() {
                self.solve_lanes::<false>(angles, sel, out)
            } else {
                self.solve_lanes::<true>(angles, sel, out)
            };
        }
        let mut state = State::new(self.n_points);
        for (i, &phi) in angles.iter().enumerate() {
            let pose = if out.vel.is_empty() {
                self.solve_one::<false>(phi, &mut state.xy, &mut [], &mut [], None)
            } else {
                self.solve_one::<true>(phi, &mut state.xy, &mut state.vel, &mut state.acc, None)
            };
            out.write(i, sel, &state, pose, false);
        }
    }

    /// [`Program::solve_rows`] for cranks and two-circle steps, [`LANES`] angles at
    /// a time: every step runs over the block before the next, so the angles'
    /// independent square roots and divisions overlap (one angle at a time they
    /// form a dependent chain). The same formulas, operation for operation, as
    /// [`Program::solve_one`]; a lane that cannot be assembled is masked, not
    /// returned from.
    fn solve_lanes<const AN: bool>(&self, angles: &[f64], sel: &[usize], out: &mut Out<'_>) {
        let p = self.n_points;
        let zero = [[0.0; LANES]; 2];
        let (mut xy, mut vel, mut acc) = (vec![zero; p], vec![zero; p], vec![zero; p]);
        for &(k, q) in &self.fixed {
            xy[k] = [[q[0]; LANES], [q[1]; LANES]];
        }
        for start in (0..angles.len()).step_by(LANES) {
            let n = LANES.min(angles.len() - start);
            // A short last block repeats its last angle in the unused lanes.
            let phi: Lane = std::array::from_fn(|l| angles[start + l.min(n - 1)]);
            let mut ok = [true; LANES];
            let mut singular = [false; LANES];
            for step in &self.steps {
                match *step {
                    Step::Driver { pivot, tip, radius } => {
                        let o = xy[pivot];
                        for l in 0..LANES {
                            let (s, c) = crate::geom::sin_cos(phi[l]);
                            xy[tip][0][l] = o[0][l] + radius * c;
                            xy[tip][1][l] = o[1][l] + radius * s;
                            if AN {
                                vel[tip][0][l] = -radius * s;
                                vel[tip][1][l] = radius * c;
                                acc[tip][0][l] = -radius * c;
                                acc[tip][1][l] = -radius * s;
                            }
                        }
                    }
                    Step::Circles {
                        a,
                        b,
                        p: pt,
                        ra,
                        rb,
                        sign,
                    } => {
                        let (pa, pb) = (xy[a], xy[b]);
                        let mut q = zero;
                        let (mut v, mut ac) = (zero, zero);
                        for l in 0..LANES {
                            let d = [pb[0][l] - pa[0][l], pb[1][l] - pa[1][l]];
                            let dd = d[0] * d[0] + d[1] * d[1];
                            let len = dd.sqrt();
                            let inv = 1.0 / len;
                            let x = (ra * ra - rb * rb + dd) * (0.5 * inv);
                            let h2 = ra * ra - x * x;
                            ok[l] &= len != 0.0 && h2 >= -1e-12 * ra * ra;
                            let h = h2.max(0.0).sqrt();
                            let (ex, ey) = (d[0] * inv, d[1] * inv);
                            let qq = [
                                pa[0][l] + x * ex - sign * h * ey,
                                pa[1][l] + x * ey + sign * h * ex,
                            ];
                            q[0][l] = qq[0];
                            q[1][l] = qq[1];
                            let u = [qq[0] - pa[0][l], qq[1] - pa[1][l]];
                            let w = [qq[0] - pb[0][l], qq[1] - pb[1][l]];
                            let det = cross(u, w);
                            let dead = det.abs() <= SINGULAR_REL * ra * rb;
                            singular[l] |= dead;
                            if AN {
                                let va_ = [vel[a][0][l], vel[a][1][l]];
                                let vb_ = [vel[b][0][l], vel[b][1][l]];
                                let aa_ = [acc[a][0][l], acc[a][1][l]];
                                let ab_ = [acc[b][0][l], acc[b][1][l]];
                                let inv = 1.0 / det;
                                let vv = solve2(u, w, inv, dot(u, va_), dot(w, vb_));
                                let (ra_, rb_) = (sub(vv, va_), sub(vv, vb_));
                                let r1 = dot(u, aa_) - dot(ra_, ra_);
                                let aa = solve2(u, w, inv, r1, dot(w, ab_) - dot(rb_, rb_));
                                let nan = f64::NAN;
                                for c in 0..2 {
                                    v[c][l] = if dead { nan } else { vv[c] };
                                    ac[c][l] = if dead { nan } else { aa[c] };
                                }
                            }
                        }
                        xy[pt] = q;
                        if AN {
                            vel[pt] = v;
                            acc[pt] = ac;
                        }
                    }
                    // solve_rows sends only cranks and two-circle steps here; any
                    // other step would leave its point unsolved: fail, don't guess.
                    _ => ok = [false; LANES],
                }
            }
            for l in 0..n {
                let i = start + l;
                let pose = Pose {
                    ok: ok[l],
                    singular: singular[l],
                    branch: 0,
                };
                out.write_lane(i, sel, (&xy, &vel, &acc), l, pose);
            }
        }
    }

    /// Solve one run of angles single-threaded.
    fn solve_serial(
        &self,
        angles: &[f64],
        sel: &[usize],
        out: &mut Out<'_>,
    ) -> Result<(), LinkageError> {
        if self.has_triads() {
            self.solve_path(angles, sel, out)
        } else {
            self.solve_rows(angles, sel, out);
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
        if self.has_triads() || threads == 1 || angles.len() < 2 * BLOCK {
            self.solve_serial(angles, sel, &mut out)?;
        } else {
            let mut blocks = Vec::with_capacity(angles.len().div_ceil(BLOCK));
            let mut rest = out;
            for start in (0..angles.len()).step_by(BLOCK) {
                let take = BLOCK.min(angles.len() - start);
                let (head, tail) = rest.split(take, sel.len());
                blocks.push((start, head));
                rest = tail;
            }
            crate::parallel::pool(threads)?.install(|| {
                blocks.into_par_iter().for_each(|(start, mut block)| {
                    let run = &angles[start..start + block.ok.len()];
                    self.solve_rows(run, sel, &mut block);
                })
            });
        }
        Ok(())
    }
}

/// Caller-owned output buffers, laid out as [`Solution`]'s fields: `rows · M · 2`
/// values for `xy` (and for `vel`, `acc` when analogs are asked for, else empty),
/// `rows` flags each.
pub struct Outputs<'a> {
    pub xy: &'a mut [f64],
    pub vel: &'a mut [f64],
    pub acc: &'a mut [f64],
    pub ok: &'a mut [bool],
    pub singular: &'a mut [bool],
    pub branch: &'a mut [bool],
}

impl<'a> Outputs<'a> {
    /// Checked sizes, viewed as (x, y) pairs in place: the kernel writes the final
    /// layout.
    fn view(self, rows: usize, m: usize, analogs: bool) -> Result<Out<'a>, LinkageError> {
        let len = rows * m * 2;
        let an = if analogs { len } else { 0 };
        let sizes = [self.xy.len(), self.vel.len(), self.acc.len()];
        let flags = [self.ok.len(), self.singular.len(), self.branch.len()];
        if sizes != [len, an, an] || flags != [rows; 3] {
            return Err(LinkageError::BadProgram {
                step: 0,
                why: format!(
                    "output buffers of {sizes:?} values and {flags:?} flags for {rows} rows of {m} points"
                ),
            });
        }
        Ok(Out {
            xy: self.xy.as_chunks_mut::<2>().0,
            vel: self.vel.as_chunks_mut::<2>().0,
            acc: self.acc.as_chunks_mut::<2>().0,
            ok: self.ok,
            singular: self.singular,
            branch: self.branch,
        })
    }
}

/// Output buffers of `rows` rows of `m` points.
struct Buffers {
    xy: Vec<f64>,
    vel: Vec<f64>,
    acc: Vec<f64>,
    ok: Vec<bool>,
    singular: Vec<bool>,
    branch: Vec<bool>,
}

impl Buffers {
    fn new(rows: usize, m: usize, analogs: bool) -> Result<Buffers, LinkageError> {
        let len = rows
            .checked_mul(m * 2)
            .ok_or(LinkageError::Memory { bytes: usize::MAX })?;
        let an = if analogs { len } else { 0 };
        // Probe the whole size once, fallibly; then allocate zeroed memory, which
        // for large buffers is fresh pages touched first by the (parallel) kernel
        // rather than a serial memset here.
        let bytes = (len + 2 * an).saturating_mul(8).saturating_add(3 * rows);
        let mut probe: Vec<u8> = Vec::new();
        probe
            .try_reserve_exact(bytes)
            .map_err(|_| LinkageError::Memory { bytes })?;
        drop(probe);
        Ok(Buffers {
            xy: vec![0.0; len],
            vel: vec![0.0; an],
            acc: vec![0.0; an],
            ok: vec![false; rows],
            singular: vec![false; rows],
            branch: vec![false; rows],
        })
    }

    fn outputs(&mut self) -> Outputs<'_> {
        Outputs {
            xy: &mut self.xy,
            vel: &mut self.vel,
            acc: &mut self.acc,
            ok: &mut self.ok,
            singular: &mut self.singular,
            branch: &mut self.branch,
        }
    }

    fn finish(self) -> Solution {
        Solution {
            xy: self.xy,
            vel: self.vel,
            acc: self.acc,
            ok: self.ok,
            singular: self.singular,
            branch: self.branch,
        }
    }
}

fn check_angles(angles: &[f64]) -> Result<(), LinkageError> {
    if let Some((i, &v)) = angles.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(LinkageError::NonFinite {
            field: "angles",
            position: i,
            value: v,
            what: "crank angles must be finite radians",
        });
    }
    Ok(())
}

fn check_request(request: &Request, n_points: usize) -> Result<(), LinkageError> {
    if request.points.is_empty() || request.points.iter().any(|&k| k >= n_points) {
        return Err(LinkageError::BadProgram {
            step: 0,
            why: format!(
                "the points asked for, {:?}, must be a non-empty list of indices below {n_points}",
                request.points
            ),
        });
    }
    Ok(())
}

/// Solve many geometries of one linkage (programs with the same points) over one
/// angle grid, in parallel over the geometries: rows are geometry-major, row
/// `g * N + i` for geometry `g` and angle `i`. A geometry whose drawn pose does
/// not close (its class III groups cannot start) is `ok = false` throughout.
pub fn solve_many(
    programs: &[Program],
    angles: &[f64],
    request: &Request,
    n_threads: Option<i64>,
) -> Result<Solution, LinkageError> {
    let rows = programs.len().saturating_mul(angles.len());
    let mut buffers = Buffers::new(rows, request.points.len(), request.analogs)?;
    solve_many_into(programs, angles, request, n_threads, buffers.outputs())?;
    Ok(buffers.finish())
}

/// [`solve_many`] into caller-owned buffers laid out as its [`Solution`].
pub fn solve_many_into(
    programs: &[Program],
    angles: &[f64],
    request: &Request,
    n_threads: Option<i64>,
    outputs: Outputs<'_>,
) -> Result<(), LinkageError> {
    let Some(first) = programs.first() else {
        return Ok(());
    };
    for (g, prog) in programs.iter().enumerate() {
        if prog.n_points != first.n_points {
            return Err(LinkageError::BadProgram {
                step: 0,
                why: format!(
                    "geometry {g} has {} points, geometry 0 {}",
                    prog.n_points, first.n_points
                ),
            });
        }
        prog.validate().map_err(|e| match e {
            LinkageError::BadProgram { step, why } => LinkageError::BadProgram {
                step,
                why: format!("geometry {g}: {why}"),
            },
            other => other,
        })?;
    }
    check_request(request, first.n_points)?;
    check_angles(angles)?;
    let threads = crate::parallel::resolve_threads(n_threads)?;
    let (n, m) = (angles.len(), request.points.len());
    let rows = programs.len().saturating_mul(n);
    let mut slabs = Vec::with_capacity(programs.len());
    let mut rest = outputs.view(rows, m, request.analogs)?;
    for _ in 0..programs.len() {
        let (head, tail) = rest.split(n, m);
        slabs.push(head);
        rest = tail;
    }
    let one = |(prog, mut slab): (&Program, Out<'_>)| {
        if prog
            .solve_serial(angles, &request.points, &mut slab)
            .is_err()
        {
            slab.fail_all();
        }
    };
    if threads == 1 {
        programs.iter().zip(slabs).for_each(one);
    } else {
        crate::parallel::pool(threads)?
            .install(|| programs.par_iter().zip(slabs.into_par_iter()).for_each(one));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linkage::triad::Triad;
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
                    let pose =
                        prog.solve_one::<true>(phi, &mut st.xy, &mut st.vel, &mut st.acc, None);
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
                                assert!(
                                    same(s.vel[at], st.vel[j][c]) && same(s.acc[at], st.acc[j][c])
                                );
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
}
