//! The batched per-angle solve: each pose's system assembled straight into its
//! blocks, solved by its blocks in order, three right-hand sides at once; 8
//! angles at a time in SIMD lanes (each lane the one-angle path's operations,
//! bit for bit), the rest one by one; tasks of angles in parallel.

use rayon::prelude::*;

use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub};

use super::lanes::{solve_block_lanes, Lanes, LANES};
use super::{ForceError, Guide, Model, Sink, Spec};
use crate::geom::V2;
use crate::parallel::{pool, resolve_threads};

/// A pivot below this fraction of its block's largest entry is a dead centre.
const SINGULAR_REL: f64 = 1e-10;

/// Angles per parallel task.
pub(super) const CHUNK: usize = 256;

/// Where [`solve_into`] writes: `values` (3, N, W) — for each part (ω², ε,
/// static) and angle the driving torque [N·m], the G guide forces [N] and, when
/// `reactions`, the K reactions (x, y) [N] of [`Model::pairs`] (W = 1 + G + 2K;
/// 1 + G without them) — and `conditioning` (N,): the smallest ratio, over the
/// system's blocks, of a pivot to the block's largest entry (0 at a dead centre,
/// where the values are NaN; NaN where the inputs are not finite; near a fold it
/// falls only as the square root of the crank angle to it: see the module).
///
/// `analogs`, if given (N,): the largest |x'| of the points over twice their
/// largest |x''| [rad] (∞ where no point accelerates, NaN where an input is
/// not finite): the crank angle to a dead centre the Python layer flags poses
/// by (`forces._result._conditioning`), taken here while the analogs are read.
pub struct Outputs<'a> {
    pub values: &'a mut [f64],
    pub conditioning: &'a mut [f64],
    pub reactions: bool,
    pub analogs: Option<&'a mut [f64]>,
}

/// The number type of [`Pose`] and [`Model::assemble`]: one angle (`f64`) or
/// [`LANES`] angles at once ([`Lanes`]), the same IEEE operations either way.
pub(super) trait Num:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
{
    fn splat(v: f64) -> Self;
    fn sqrt(self) -> Self;
}

impl Num for f64 {
    #[inline(always)]
    fn splat(v: f64) -> f64 {
        v
    }
    #[inline(always)]
    fn sqrt(self) -> f64 {
        f64::sqrt(self)
    }
}

#[inline(always)]
fn gsub<T: Num>(a: [T; 2], b: [T; 2]) -> [T; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

#[inline(always)]
fn gdot<T: Num>(a: [T; 2], b: [T; 2]) -> T {
    a[0] * b[0] + a[1] * b[1]
}

#[inline(always)]
fn gcross<T: Num>(a: [T; 2], b: [T; 2]) -> T {
    a[0] * b[1] - a[1] * b[0]
}

/// x₀ + u·d + v·d⊥ with d = x₁ − x₀, d⊥ = (−d_y, d_x), x₀ = `x[j0]`, x₁ = `x[j1]`
/// (a body's centre of mass, or its analogs).
#[inline(always)]
fn body_point<T: Num>(x: &[[T; 2]], j0: usize, j1: usize, u: f64, v: f64) -> [T; 2] {
    let k = T::splat;
    let d = gsub(x[j1], x[j0]);
    [
        x[j0][0] + k(u) * d[0] - k(v) * d[1],
        x[j0][1] + k(u) * d[1] + k(v) * d[0],
    ]
}

/// The kinematic quantities of one pose (or of [`LANES`] poses), for
/// [`Model::assemble`].
pub(super) struct Pose<T = f64> {
    pub(super) xy: Vec<[T; 2]>,
    pub(super) vel: Vec<[T; 2]>,
    acc: Vec<[T; 2]>,
    com: Vec<[T; 2]>,
    pub(super) com_v: Vec<[T; 2]>,
    pub(super) com_a: Vec<[T; 2]>,
    pub(super) omega_v: Vec<T>,
    pub(super) omega_a: Vec<T>,
    pub(super) normal: Vec<[T; 2]>,
    force: Vec<[T; 2]>,
    torques: Vec<T>,
    /// Friction's loads (see `friction`), read only when `extra` is set: a
    /// force on each point [N] and a force and moment about the centre of mass
    /// on each body [N, N·m], all in the static part.
    pub(super) extra: bool,
    pub(super) extra_force: Vec<V2>,
    pub(super) extra_body: Vec<[f64; 3]>,
    /// Each point's load F_ext + m g − m a by part (see [`Pose::pin_load`]).
    loads: Vec<[[T; 2]; 3]>,
    /// max |x'| / (2 max |x''|) over the points (see [`Outputs::analogs`]).
    pub(super) analog_ratio: f64,
}

impl<T: Num> Pose<T> {
    /// A pose of zeros: only the pattern is read from it.
    fn zeroed(spec: &Spec) -> Pose<T> {
        let (p, b, g) = (spec.n_points, spec.bodies.len(), spec.guides.len());
        let z = T::splat(0.0);
        Pose {
            xy: vec![[z; 2]; p],
            vel: vec![[z; 2]; p],
            acc: vec![[z; 2]; p],
            com: vec![[z; 2]; b],
            com_v: vec![[z; 2]; b],
            com_a: vec![[z; 2]; b],
            omega_v: vec![z; b],
            omega_a: vec![z; b],
            normal: vec![[z; 2]; g],
            force: vec![[z; 2]; p],
            torques: vec![z; b],
            extra: false,
            extra_force: vec![[0.0; 2]; p],
            extra_body: vec![[0.0; 3]; b],
            loads: vec![[[z; 2]; 3]; p],
            analog_ratio: f64::NAN,
        }
    }

    /// The bodies' centres of mass and angular analogs, the guides' normals and
    /// the points' loads, from the points' positions and analogs.
    #[inline(always)]
    fn derive(&mut self, spec: &Spec) {
        let k = T::splat;
        for (i, body) in spec.bodies.iter().enumerate() {
            let (j0, j1) = (body.points[0], body.points[1]);
            let [u, v] = body.com_uv;
            self.com[i] = body_point(&self.xy, j0, j1, u, v);
            self.com_v[i] = body_point(&self.vel, j0, j1, u, v);
            self.com_a[i] = body_point(&self.acc, j0, j1, u, v);
            let d = gsub(self.xy[j1], self.xy[j0]);
            let d1 = gsub(self.vel[j1], self.vel[j0]);
            let d2 = gsub(self.acc[j1], self.acc[j0]);
            let n2 = gdot(d, d);
            let w = gcross(d, d1) / n2;
            self.omega_v[i] = w;
            self.omega_a[i] = gcross(d, d2) / n2 - k(2.0) * gdot(d, d1) * w / n2;
        }
        for (g, guide) in spec.guides.iter().enumerate() {
            let e = match *guide {
                Guide::Fixed { dir, .. } => [k(dir[0]), k(dir[1])],
                Guide::Link { b, c, .. } => gsub(self.xy[c], self.xy[b]),
            };
            let len = gdot(e, e).sqrt();
            self.normal[g] = [-e[1] / len, e[0] / len];
        }
        self.refresh_loads(spec);
    }

    /// Recompute the points' loads (after `fill`, or after a change of the
    /// `extra` loads).
    #[inline(always)]
    pub(super) fn refresh_loads(&mut self, spec: &Spec) {
        let k = T::splat;
        let g = spec.gravity;
        for p in 0..self.loads.len() {
            let m = spec.point_mass[p];
            let (v, a, mut f) = (self.vel[p], self.acc[p], self.force[p]);
            if self.extra {
                f = [
                    f[0] + k(self.extra_force[p][0]),
                    f[1] + k(self.extra_force[p][1]),
                ];
            }
            self.loads[p] = [
                [k(-m) * a[0], k(-m) * a[1]],
                [k(-m) * v[0], k(-m) * v[1]],
                [f[0] + k(m * g[0]), f[1] + k(m * g[1])],
            ];
        }
    }

    /// r − c of body `b`.
    #[inline(always)]
    pub(super) fn arm(&self, b: usize, x: [T; 2]) -> [T; 2] {
        gsub(x, self.com[b])
    }

    /// The external torque on body `b` [N·m].
    #[inline(always)]
    pub(super) fn torque(&self, b: usize) -> T {
        self.torques[b]
    }

    /// The known part of pin `p`'s equation, F_ext + m_p g − m_p a_p, by part
    /// (as of the last [`Pose::fill`] or [`Pose::refresh_loads`]).
    #[inline(always)]
    pub(super) fn pin_load(&self, _spec: &Spec, p: usize) -> [[T; 2]; 3] {
        self.loads[p]
    }
}

/// max |x'| / (2 max |x''|) of one angle's analogs (see [`Outputs::analogs`]),
/// given that they are finite.
#[inline(always)]
fn analog_ratio(vel: &[f64], acc: &[f64]) -> f64 {
    let big = |v: &[f64]| {
        v.chunks_exact(2)
            .fold(0.0f64, |m, p| m.max(p[0] * p[0] + p[1] * p[1]))
    };
    let (v2, a2) = (big(vel), big(acc));
    if a2 > 0.0 {
        v2.sqrt() / (2.0 * a2.sqrt())
    } else {
        f64::INFINITY
    }
}

impl Pose<f64> {
    /// A pose with placeholder values: only the pattern is read from it.
    pub(super) fn structural(spec: &Spec) -> Pose {
        Pose::zeroed(spec)
    }

    /// The pose at one angle; false where an input is not finite (the linkage
    /// not assembled there, or at a dead centre of its kinematics).
    pub(super) fn fill(&mut self, spec: &Spec, row: Row<'_>) -> bool {
        let pts = |s: &[f64], out: &mut Vec<V2>| {
            for (o, c) in out.iter_mut().zip(s.chunks_exact(2)) {
                *o = [c[0], c[1]];
            }
        };
        pts(row.xy, &mut self.xy);
        pts(row.vel, &mut self.vel);
        pts(row.acc, &mut self.acc);
        match row.force {
            Some(f) => pts(f, &mut self.force),
            None => self.force.fill([0.0; 2]),
        }
        match row.torque {
            Some(t) => self.torques.copy_from_slice(t),
            None => self.torques.fill(0.0),
        }
        if !row.finite() {
            self.analog_ratio = f64::NAN;
            return false;
        }
        self.analog_ratio = analog_ratio(row.vel, row.acc);
        self.derive(spec);
        true
    }
}

impl Pose<Lanes> {
    /// The poses at [`LANES`] consecutive angles, lane l from angle l of
    /// `rows`; for each lane whether its inputs are finite, and its analog
    /// ratio (as [`Pose::fill`]).
    #[inline(always)]
    fn fill_lanes(
        &mut self,
        spec: &Spec,
        rows: Rows<'_>,
        ok: &mut [bool; LANES],
        ratio: &mut [f64; LANES],
    ) {
        /// Value j of each of the [`LANES`] angles of `s` (angle after angle,
        /// `per` values each): a strided load into one vector, never a vector
        /// read of values stored one lane at a time.
        #[inline(always)]
        fn column(s: &[f64], per: usize, j: usize) -> Lanes {
            let mut v = [0.0; LANES];
            for (l, v) in v.iter_mut().enumerate() {
                *v = s[l * per + j];
            }
            Lanes(v)
        }
        /// The points' (x, y) of the [`LANES`] angles of `s` into `out`, as
        /// [`column`] (each angle's pairs a slice of `out`'s length, so that
        /// no load needs a bounds check).
        #[inline(always)]
        fn pts(out: &mut [[Lanes; 2]], s: &[f64]) {
            let n = out.len();
            let mut at: [&[[f64; 2]]; LANES] = [&[]; LANES];
            for (l, a) in at.iter_mut().enumerate() {
                *a = &s[2 * n * l..2 * n * (l + 1)].as_chunks::<2>().0[..n];
            }
            for (j, o) in out.iter_mut().enumerate() {
                let (mut x, mut y) = ([0.0; LANES], [0.0; LANES]);
                for l in 0..LANES {
                    let p = at[l][j];
                    x[l] = p[0];
                    y[l] = p[1];
                }
                *o = [Lanes(x), Lanes(y)];
            }
        }
        pts(&mut self.xy, rows.xy);
        pts(&mut self.vel, rows.vel);
        pts(&mut self.acc, rows.acc);
        if let Some(f) = rows.force {
            pts(&mut self.force, f);
        }
        if let Some(t) = rows.torque {
            let per = self.torques.len();
            let t = &t[..LANES * per];
            for (j, o) in self.torques.iter_mut().enumerate() {
                *o = column(t, per, j);
            }
        }
        // 0·x is ±0 where x is finite, NaN where not: a lane's sum is 0 where
        // all its inputs are finite ([`Row::finite`]).
        let (zero, mut z) = (Lanes::splat(0.0), Lanes::splat(0.0));
        let pairs = self
            .xy
            .iter()
            .chain(&self.vel)
            .chain(&self.acc)
            .chain(&self.force);
        for p in pairs {
            z += p[0] * zero;
            z += p[1] * zero;
        }
        for &t in &self.torques {
            z += t * zero;
        }
        // As [`analog_ratio`], lane by lane.
        let big = |v: &[[Lanes; 2]]| {
            let mut m = [0.0f64; LANES];
            for p in v {
                for (m, (x, y)) in m.iter_mut().zip(p[0].0.iter().zip(p[1].0)) {
                    *m = m.max(x * x + y * y);
                }
            }
            m
        };
        let (v2, a2) = (big(&self.vel), big(&self.acc));
        for l in 0..LANES {
            ok[l] = z.0[l] == 0.0;
            ratio[l] = if !ok[l] {
                f64::NAN
            } else if a2[l] > 0.0 {
                v2[l].sqrt() / (2.0 * a2[l].sqrt())
            } else {
                f64::INFINITY
            };
        }
        self.derive(spec);
    }
}

/// One parallel task: its chunk's index, its rows of the three parts and flags.
type Task<'a> = (
    usize,
    (
        (
            ((&'a mut [f64], &'a mut [f64]), &'a mut [f64]),
            &'a mut [f64],
        ),
        &'a mut [f64],
    ),
);

/// The inputs of [`LANES`] consecutive angles, angle after angle (as in
/// [`Inputs`]).
#[derive(Clone, Copy)]
struct Rows<'a> {
    xy: &'a [f64],
    vel: &'a [f64],
    acc: &'a [f64],
    force: Option<&'a [f64]>,
    torque: Option<&'a [f64]>,
}

/// One angle's inputs (flat (x, y) pairs).
#[derive(Clone, Copy)]
pub(super) struct Row<'a> {
    pub(super) xy: &'a [f64],
    pub(super) vel: &'a [f64],
    pub(super) acc: &'a [f64],
    pub(super) force: Option<&'a [f64]>,
    pub(super) torque: Option<&'a [f64]>,
}

impl Row<'_> {
    /// Whether every input of the angle is finite.
    #[inline(always)]
    fn finite(&self) -> bool {
        let f = |v: &[f64]| v.iter().all(|x| x.is_finite());
        f(self.xy)
            && f(self.vel)
            && f(self.acc)
            && self.force.is_none_or(f)
            && self.torque.is_none_or(f)
    }
}

/// Where one pose's system is assembled: straight into the diagonal blocks'
/// augmented matrices and their rows' coefficients of earlier blocks' unknowns
/// (the slots of [`Plan`]), nothing else stored or zeroed.
struct Packed<'a, T> {
    plan: &'a Plan,
    vals: &'a mut [T],
}

impl<T: Num> Sink<T> for Packed<'_, T> {
    #[inline(always)]
    fn a(&mut self, row: usize, col: usize, v: T) {
        self.vals[self.plan.slot[row * self.plan.n + col] as usize] += v;
    }
    #[inline(always)]
    fn rhs(&mut self, row: usize, part: usize, v: T) {
        self.vals[self.plan.rhs_slot[row] as usize + part] += v;
    }
}

/// Where each structural entry of the system goes, fixed once per model: each
/// block is a k×s row-major augmented matrix (its k columns, zero padding, the
/// three right-hand sides in the last three columns; s = 8 for k ≤ 5, 16 for
/// k ≤ 13, so the elimination runs on whole rows of fixed length), followed by
/// its rows' coefficients of earlier blocks' unknowns.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Plan {
    n: usize,
    /// Slot of entry (row, col) of the system (n × n), `u32::MAX` off the pattern.
    slot: Vec<u32>,
    /// Slot of each row's first right-hand side.
    rhs_slot: Vec<u32>,
    /// Slots in all.
    len: usize,
    blocks: Vec<PlanBlock>,
}

#[derive(Debug, Clone, PartialEq)]
struct PlanBlock {
    /// First slot of the augmented matrix, its size k and row stride s.
    base: usize,
    k: usize,
    s: usize,
    /// First slot of its dependency coefficients, row after row.
    dep_base: usize,
}

/// The row stride of a block of `k` columns (see [`Plan`]).
fn stride(k: usize) -> usize {
    match k {
        0..=5 => 8,
        6..=13 => 16,
        _ => (k + 3).div_ceil(4) * 4,
    }
}

impl Plan {
    /// The plan of the one-angle path (rows of fixed length: see [`Plan`]).
    pub(super) fn new(n: usize, blocks: &[super::Block]) -> Plan {
        Plan::with_stride(n, blocks, stride)
    }

    /// The plan of the [`LANES`] path: each entry is a vector of the lanes
    /// already, so the rows need no padding (stride k + 3) and the slots to
    /// zero before each assembly are half as many.
    pub(super) fn lanes(n: usize, blocks: &[super::Block]) -> Plan {
        Plan::with_stride(n, blocks, |k| k + 3)
    }

    fn with_stride(n: usize, blocks: &[super::Block], stride: impl Fn(usize) -> usize) -> Plan {
        let mut slot = vec![u32::MAX; n * n];
        let mut rhs_slot = vec![0u32; n];
        let mut next = 0usize;
        let mut out = Vec::with_capacity(blocks.len());
        for blk in blocks {
            let (k, s) = (blk.cols.len(), stride(blk.cols.len()));
            let base = next;
            for (i, &row) in blk.rows.iter().enumerate() {
                for (j, &col) in blk.cols.iter().enumerate() {
                    slot[row * n + col] = (base + i * s + j) as u32;
                }
                rhs_slot[row] = (base + i * s + s - 3) as u32;
            }
            next += k * s;
            let dep_base = next;
            for (i, &row) in blk.rows.iter().enumerate() {
                for &col in &blk.deps[i] {
                    slot[row * n + col] = next as u32;
                    next += 1;
                }
            }
            out.push(PlanBlock {
                base,
                k,
                s,
                dep_base,
            });
        }
        Plan {
            n,
            slot,
            rhs_slot,
            len: next,
            blocks: out,
        }
    }
}

/// Per-task buffers.
pub(super) struct Scratch {
    pub(super) pose: Pose,
    vals: Vec<f64>,
    x: Vec<f64>,
}

impl Model {
    pub(super) fn scratch(&self) -> Scratch {
        Scratch {
            pose: Pose::structural(&self.spec),
            vals: vec![0.0; self.plan.len],
            x: vec![0.0; self.n * 3],
        }
    }

    /// Values per angle and part in [`Outputs::values`], with or without the
    /// reactions.
    pub fn width(&self, reactions: bool) -> usize {
        1 + self.spec.guides.len() + if reactions { 2 * self.pairs().len() } else { 0 }
    }

    /// Solve one pose into `out` (its row of each part): its conditioning (see
    /// [`Outputs`]), 0 at a dead centre (`out` untouched).
    pub(super) fn solve_one(&self, s: &mut Scratch, out: [&mut [f64]; 3]) -> f64 {
        if s.pose.extra {
            s.pose.refresh_loads(&self.spec);
        }
        s.vals.fill(0.0);
        self.assemble(
            &s.pose,
            &mut Packed {
                plan: &self.plan,
                vals: &mut s.vals,
            },
        );
        let (vals, x) = (&mut s.vals, &mut s.x);
        let mut cond = f64::INFINITY;
        for (blk, pb) in self.blocks.iter().zip(&self.plan.blocks) {
            let (k, st) = (pb.k, pb.s);
            let (head, deps) = vals.split_at_mut(pb.dep_base);
            let m = &mut head[pb.base..pb.base + k * st];
            let mut d = 0;
            for (i, cols) in blk.deps.iter().enumerate() {
                let b = &mut m[i * st + st - 3..(i + 1) * st];
                let mut v = [b[0], b[1], b[2]];
                for &col in cols {
                    let c = deps[d];
                    d += 1;
                    let xs = &x[col * 3..col * 3 + 3];
                    v[0] -= c * xs[0];
                    v[1] -= c * xs[1];
                    v[2] -= c * xs[2];
                }
                b.copy_from_slice(&v);
            }
            let scale = block_abs_max(m, k, st);
            match lu_solve(m, k, st, SINGULAR_REL * scale) {
                Some(pivot) => cond = cond.min(pivot / scale),
                None => return 0.0,
            }
            for (j, &col) in blk.cols.iter().enumerate() {
                x[col * 3..col * 3 + 3].copy_from_slice(&m[j * st + st - 3..(j + 1) * st]);
            }
        }
        self.write(s, out);
        cond
    }

    /// One angle's values from the solved unknowns: the torque, the guides and
    /// (if the rows have room) every pin's forces, the eliminated one from its
    /// pin's equation.
    fn write(&self, s: &Scratch, out: [&mut [f64]; 3]) {
        let (x, pose) = (&s.x, &s.pose);
        self.write_with(
            |i| x[i],
            |p| pose.pin_load(&self.spec, p),
            |g| pose.normal[g],
            out,
        );
    }

    /// [`Model::write`] given the unknowns `x` (unknown j's part i at 3j + i),
    /// the points' loads and the guides' normals; one angle or [`LANES`].
    #[inline(always)]
    fn write_with<T: Num>(
        &self,
        x: impl Fn(usize) -> T,
        load_of: impl Fn(usize) -> [[T; 2]; 3],
        normal: impl Fn(usize) -> [T; 2],
        out: [&mut [T]; 3],
    ) {
        let g_n = self.spec.guides.len();
        let [r0, r1, r2] = out;
        let mut rows = [r0, r1, r2];
        for (part, row) in rows.iter_mut().enumerate() {
            row[0] = x(self.torque_col * 3 + part);
            for g in 0..g_n {
                row[1 + g] = x((self.guide_col + g) * 3 + part);
            }
        }
        if rows[0].len() == 1 + g_n {
            return;
        }
        let mut k = 1 + g_n;
        for pin in &self.pins {
            if pin.sides.is_empty() {
                continue;
            }
            let load = load_of(pin.point);
            for (part, row) in rows.iter_mut().enumerate() {
                let mut first = load[part];
                for &g in &pin.guides {
                    let nn = normal(g);
                    let f = x((self.guide_col + g) * 3 + part);
                    first[0] += f * nn[0];
                    first[1] += f * nn[1];
                }
                for j in 0..pin.sides.len() - 1 {
                    let (cx, cy) = (pin.col + 2 * j, pin.col + 2 * j + 1);
                    first[0] = first[0] - x(cx * 3 + part);
                    first[1] = first[1] - x(cy * 3 + part);
                }
                row[k] = first[0];
                row[k + 1] = first[1];
                for j in 0..pin.sides.len() - 1 {
                    let (cx, cy) = (pin.col + 2 * j, pin.col + 2 * j + 1);
                    row[k + 2 + 2 * j] = x(cx * 3 + part);
                    row[k + 3 + 2 * j] = x(cy * 3 + part);
                }
            }
            k += 2 * pin.sides.len();
        }
    }

    pub(super) fn scratch_lanes(&self, reactions: bool) -> ScratchLanes {
        ScratchLanes {
            res: vec![Lanes::splat(0.0); 3 * self.width(reactions)],
            pose: Pose::zeroed(&self.spec),
            vals: vec![Lanes::splat(0.0); self.plan_lanes.len],
            x: vec![Lanes::splat(0.0); self.n * 3],
        }
    }

    /// [`Model::solve_one`] at [`LANES`] angles at once, lane l's inputs
    /// angle l of `rows` and outputs row l of each part's `out` (`LANES` rows of W
    /// values each): the same operations on each lane (each
    /// lane pivots on its own rows), so bit for bit the scalar path's values.
    /// Each lane's conditioning into `cond` (NaN where an input is not finite,
    /// 0 at a dead centre: that lane's values NaN) and analog ratio into
    /// `ratio`.
    #[inline(always)]
    fn solve_lanes(
        &self,
        s: &mut ScratchLanes,
        rows: Rows<'_>,
        out: [&mut [f64]; 3],
        cond: &mut [f64],
        ratio: &mut [f64],
    ) {
        let mut ok = [true; LANES];
        let mut ratios = [0.0; LANES];
        s.pose.fill_lanes(&self.spec, rows, &mut ok, &mut ratios);
        ratio.copy_from_slice(&ratios);
        s.vals.fill(Lanes::splat(0.0));
        self.assemble(
            &s.pose,
            &mut Packed {
                plan: &self.plan_lanes,
                vals: &mut s.vals,
            },
        );
        let (vals, x) = (&mut s.vals, &mut s.x);
        let mut conds = [f64::INFINITY; LANES];
        let mut live = [true; LANES];
        for (blk, pb) in self.blocks.iter().zip(&self.plan_lanes.blocks) {
            let (k, st) = (pb.k, pb.s);
            let (head, deps) = vals.split_at_mut(pb.dep_base);
            let m = &mut head[pb.base..pb.base + k * st];
            let mut d = 0;
            for (i, cols) in blk.deps.iter().enumerate() {
                let b = &mut m[i * st + st - 3..(i + 1) * st];
                let mut v = [b[0], b[1], b[2]];
                for &col in cols {
                    let c = deps[d];
                    d += 1;
                    let xs = &x[col * 3..col * 3 + 3];
                    v[0] = v[0] - c * xs[0];
                    v[1] = v[1] - c * xs[1];
                    v[2] = v[2] - c * xs[2];
                }
                b.copy_from_slice(&v);
            }
            let (scale, pivot, alive) = solve_block_lanes(m, k, st, SINGULAR_REL);
            for l in 0..LANES {
                live[l] &= alive[l];
                conds[l] = conds[l].min(pivot.0[l] / scale.0[l]);
            }
            for (j, &col) in blk.cols.iter().enumerate() {
                x[col * 3..col * 3 + 3].copy_from_slice(&m[j * st + st - 3..(j + 1) * st]);
            }
        }
        let [o0, o1, o2] = out;
        let w = o0.len() / LANES;
        {
            let (pose, res) = (&s.pose, &mut s.res);
            let (q0, rest) = res.split_at_mut(w);
            let (q1, q2) = rest.split_at_mut(w);
            self.write_with(
                |i| x[i],
                |p| pose.pin_load(&self.spec, p),
                |g| pose.normal[g],
                [q0, q1, q2],
            );
        }
        for (part, o) in [o0, o1, o2].into_iter().enumerate() {
            let res = &s.res[part * w..(part + 1) * w];
            for (l, row) in o.chunks_exact_mut(w).enumerate() {
                if ok[l] && live[l] {
                    for (v, r) in row.iter_mut().zip(res) {
                        *v = r.0[l];
                    }
                } else {
                    row.fill(f64::NAN);
                }
            }
        }
        for l in 0..LANES {
            cond[l] = if !ok[l] {
                f64::NAN
            } else if !live[l] {
                0.0
            } else {
                conds[l]
            };
        }
    }
}

/// Per-task buffers of [`Model::solve_lanes`].
pub(super) struct ScratchLanes {
    pose: Pose<Lanes>,
    vals: Vec<Lanes>,
    x: Vec<Lanes>,
    /// The values of the three parts, W each.
    res: Vec<Lanes>,
}

/// The largest |v| of the k×k matrix of an augmented block of row stride `st`.
#[inline(always)]
fn block_abs_max(m: &[f64], k: usize, st: usize) -> f64 {
    let mut acc = [0.0f64; 4];
    for row in m.chunks_exact(st) {
        for (i, x) in row[..k].iter().enumerate() {
            let y = x.abs();
            if y > acc[i & 3] {
                acc[i & 3] = y;
            }
        }
    }
    acc.iter().fold(0.0, |m, &x| if x > m { x } else { m })
}

/// Gaussian elimination with partial pivoting of the augmented k×`st` block `m`
/// (row-major; the k×k matrix, zero padding, three right-hand sides last), in
/// place: the solutions end in the right-hand sides' columns. Returns the
/// smallest |pivot|, or None if a pivot is at most `tol` (or not finite).
/// Sizes up to 13 run a copy specialised to their k and stride.
fn lu_solve(m: &mut [f64], k: usize, st: usize, tol: f64) -> Option<f64> {
    pulp::Arch::new().dispatch(Lu { m, k, st, tol })
}

/// [`lu_solve`]'s work, compiled for the widest vector unit the CPU has (no
/// fused multiply–add: the same operations as the scalar code, bit for bit).
struct Lu<'a> {
    m: &'a mut [f64],
    k: usize,
    st: usize,
    tol: f64,
}

impl pulp::WithSimd for Lu<'_> {
    type Output = Option<f64>;

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> Option<f64> {
        let Lu { m, k, st, tol } = self;
        lu_fixed(m, k, st, tol)
    }
}

#[inline(always)]
fn lu_fixed(m: &mut [f64], k: usize, st: usize, tol: f64) -> Option<f64> {
    macro_rules! fixed {
        ($($k:literal => $s:literal),*) => {
            match k {
                $($k => lu_aug::<$s>(m, $k, tol),)*
                _ => lu_any(m, k, st, tol),
            }
        };
    }
    fixed!(1 => 8, 2 => 8, 3 => 8, 4 => 8, 5 => 8, 6 => 16, 7 => 16, 8 => 16, 9 => 16,
           10 => 16, 11 => 16, 12 => 16, 13 => 16)
}

#[inline(always)]
fn lu_aug<const S: usize>(m: &mut [f64], k: usize, tol: f64) -> Option<f64> {
    let (rows, _) = m.as_chunks_mut::<S>();
    lu_rows(&mut rows[..k], tol)
}

#[inline(always)]
fn lu_any(m: &mut [f64], k: usize, st: usize, tol: f64) -> Option<f64> {
    let mut rows: Vec<Vec<f64>> = m.chunks_exact(st).map(<[f64]>::to_vec).collect();
    let r = lu_rows(&mut rows[..k], tol);
    for (dst, src) in m.chunks_exact_mut(st).zip(&rows) {
        dst.copy_from_slice(src);
    }
    r
}

/// [`lu_solve`] on rows that hold the matrix's columns first and the three
/// right-hand sides last. Each row update runs over the whole row, a fixed
/// length (the entries up to the pivot column are never read again: they hold
/// garbage), each entry right of it updated as by an update of those alone.
#[inline(always)]
fn lu_rows<R: AsMut<[f64]> + AsRef<[f64]>>(rows: &mut [R], tol: f64) -> Option<f64> {
    let k = rows.len();
    let mut smallest = f64::INFINITY;
    for c in 0..k {
        let (mut piv, mut best) = (c, rows[c].as_ref()[c].abs());
        for (r, row) in rows.iter().enumerate().skip(c + 1) {
            let v = row.as_ref()[c].abs();
            if v > best {
                (piv, best) = (r, v);
            }
        }
        if best <= tol || best == 0.0 || !best.is_finite() {
            return None;
        }
        smallest = smallest.min(best);
        if piv != c {
            rows.swap(c, piv);
        }
        let (top, bottom) = rows.split_at_mut(c + 1);
        let prow = top[c].as_mut();
        let inv = 1.0 / prow[c];
        prow[c] = inv;
        let prow = top[c].as_ref();
        for row in bottom.iter_mut() {
            let row = row.as_mut();
            let f = row[c] * inv;
            if f == 0.0 {
                continue;
            }
            for (x, p) in row.iter_mut().zip(prow) {
                *x -= f * p;
            }
        }
    }
    let st = rows[0].as_ref().len();
    for c in (0..k).rev() {
        let (top, bottom) = rows.split_at_mut(c + 1);
        let row = top[c].as_mut();
        let mut v = [row[st - 3], row[st - 2], row[st - 1]];
        for (t, b) in bottom.iter().enumerate() {
            let b = b.as_ref();
            let coef = row[c + 1 + t];
            v[0] -= coef * b[st - 3];
            v[1] -= coef * b[st - 2];
            v[2] -= coef * b[st - 1];
        }
        let inv = row[c];
        row[st - 3] = v[0] * inv;
        row[st - 2] = v[1] * inv;
        row[st - 1] = v[2] * inv;
    }
    Some(smallest)
}

/// The inputs at N angles: `xy`, `vel`, `acc` (N, P, 2) the points' positions
/// [m] and analogs [m/rad, m/rad²], optional external point forces `force`
/// (N, P, 2) [N] and link torques `torque` (N, B) [N·m].
#[derive(Clone, Copy)]
pub struct Inputs<'a> {
    pub xy: &'a [f64],
    pub vel: &'a [f64],
    pub acc: &'a [f64],
    pub force: Option<&'a [f64]>,
    pub torque: Option<&'a [f64]>,
}

/// Kinetostatics of `model` at the N angles of `inputs`, into `out`.
pub fn solve_into(
    model: &Model,
    inputs: Inputs<'_>,
    out: Outputs<'_>,
    n_threads: Option<i64>,
) -> Result<(), ForceError> {
    let Inputs {
        xy,
        vel,
        acc,
        force,
        torque,
    } = inputs;
    let p2 = 2 * model.spec.n_points;
    let nb = model.spec.bodies.len();
    let n = out.conditioning.len();
    let w = model.width(out.reactions);
    let sizes = [
        ("xy", xy.len(), n * p2),
        ("vel", vel.len(), n * p2),
        ("acc", acc.len(), n * p2),
        ("force", force.map_or(n * p2, <[f64]>::len), n * p2),
        ("torque", torque.map_or(n * nb, <[f64]>::len), n * nb),
        ("values", out.values.len(), 3 * n * w),
    ];
    for (field, got, want) in sizes {
        if got != want {
            return Err(ForceError::BadModel(format!(
                "{field} has {got} values; {n} angles need {want}"
            )));
        }
    }
    let threads = resolve_threads(n_threads)?;
    if n == 0 {
        return Ok(());
    }
    if out.analogs.as_ref().is_some_and(|a| a.len() != n) {
        return Err(ForceError::BadModel(format!(
            "analogs has {} values; {n} angles need {n}",
            out.analogs.as_ref().map_or(0, |a| a.len())
        )));
    }
    let (part0, rest) = out.values.split_at_mut(n * w);
    let (part1, part2) = rest.split_at_mut(n * w);
    let mut spare = Vec::new();
    let analogs: &mut [f64] = match out.analogs {
        Some(a) => a,
        None => {
            spare.resize(n, 0.0);
            &mut spare
        }
    };
    let run = |(c, ((((v0, v1), v2), conds), ratios)): Task<'_>| {
        if crate::cancel::requested() {
            return;
        }
        let inputs = Inputs {
            xy,
            vel,
            acc,
            force,
            torque,
        };
        pulp::Arch::new().dispatch(Chunk {
            model,
            inputs,
            first: c * CHUNK,
            values: [v0, v1, v2],
            conds,
            ratios,
        });
    };
    pool(threads)?.install(|| {
        part0
            .par_chunks_mut(CHUNK * w)
            .zip(part1.par_chunks_mut(CHUNK * w))
            .zip(part2.par_chunks_mut(CHUNK * w))
            .zip(out.conditioning.par_chunks_mut(CHUNK))
            .zip(analogs.par_chunks_mut(CHUNK))
            .enumerate()
            .for_each(run)
    });
    Ok(())
}

/// One parallel task of [`solve_into`]: the angles from `first` on, as many
/// as `conds` has, into their rows of each part's `values`; [`LANES`] angles
/// at a time in SIMD lanes, the rest one by one. Compiled for the widest
/// vector unit the CPU has.
struct Chunk<'a, 'b> {
    model: &'a Model,
    inputs: Inputs<'a>,
    first: usize,
    values: [&'b mut [f64]; 3],
    conds: &'b mut [f64],
    ratios: &'b mut [f64],
}

impl pulp::WithSimd for Chunk<'_, '_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        let Chunk {
            model,
            inputs,
            first,
            values: [v0, v1, v2],
            conds,
            ratios,
        } = self;
        let p2 = 2 * model.spec.n_points;
        let nb = model.spec.bodies.len();
        let count = conds.len();
        let w = v0.len() / count.max(1);
        let row = |a: usize| Row {
            xy: &inputs.xy[a * p2..(a + 1) * p2],
            vel: &inputs.vel[a * p2..(a + 1) * p2],
            acc: &inputs.acc[a * p2..(a + 1) * p2],
            force: inputs.force.map(|f| &f[a * p2..(a + 1) * p2]),
            torque: inputs.torque.map(|t| &t[a * nb..(a + 1) * nb]),
        };
        let lanes = count / LANES * LANES;
        let (l0, t0) = v0.split_at_mut(lanes * w);
        let (l1, t1) = v1.split_at_mut(lanes * w);
        let (l2, t2) = v2.split_at_mut(lanes * w);
        let (lc, tc) = conds.split_at_mut(lanes);
        let (lr, tr) = ratios.split_at_mut(lanes);
        if lanes > 0 {
            let mut s = model.scratch_lanes(w > model.width(false));
            let groups = l0
                .chunks_exact_mut(LANES * w)
                .zip(l1.chunks_exact_mut(LANES * w))
                .zip(l2.chunks_exact_mut(LANES * w))
                .zip(lc.chunks_exact_mut(LANES))
                .zip(lr.chunks_exact_mut(LANES));
            for (i, ((((g0, g1), g2), cond), ratio)) in groups.enumerate() {
                let a = first + i * LANES;
                let (b, e) = (a * p2, (a + LANES) * p2);
                let rows = Rows {
                    xy: &inputs.xy[b..e],
                    vel: &inputs.vel[b..e],
                    acc: &inputs.acc[b..e],
                    force: inputs.force.map(|f| &f[b..e]),
                    torque: inputs.torque.map(|t| &t[a * nb..(a + LANES) * nb]),
                };
                model.solve_lanes(&mut s, rows, [g0, g1, g2], cond, ratio);
            }
        }
        let mut s = model.scratch();
        let rows = t0
            .chunks_exact_mut(w)
            .zip(t1.chunks_exact_mut(w))
            .zip(t2.chunks_exact_mut(w))
            .zip(tc.iter_mut())
            .zip(tr.iter_mut());
        for (i, ((((r0, r1), r2), cond), ratio)) in rows.enumerate() {
            *cond = if s.pose.fill(&model.spec, row(first + lanes + i)) {
                model.solve_one(&mut s, [&mut *r0, &mut *r1, &mut *r2])
            } else {
                f64::NAN
            };
            *ratio = s.pose.analog_ratio;
            if cond.is_nan() || *cond == 0.0 {
                r0.fill(f64::NAN);
                r1.fill(f64::NAN);
                r2.fill(f64::NAN);
            }
        }
    }
}

/// One angle's inputs for the tests (no link torques).
#[cfg(test)]
pub(super) fn tests_row<'a>(
    xy: &'a [f64],
    vel: &'a [f64],
    acc: &'a [f64],
    force: &'a [f64],
) -> Row<'a> {
    Row {
        xy,
        vel,
        acc,
        force: Some(force),
        torque: None,
    }
}

/// The one-angle-at-a-time path over all N angles (the kernel before the
/// lanes), for the tests: values, conditioning and analog ratios as
/// [`solve_into`]'s.
#[cfg(test)]
pub(super) fn tests_scalar(
    model: &Model,
    inputs: Inputs<'_>,
    reactions: bool,
) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let p2 = 2 * model.spec.n_points;
    let nb = model.spec.bodies.len();
    let n = inputs.xy.len() / p2;
    let w = model.width(reactions);
    let mut values = vec![0.0; 3 * n * w];
    let (mut conds, mut ratios) = (vec![0.0; n], vec![0.0; n]);
    let mut s = model.scratch();
    let (v0, rest) = values.split_at_mut(n * w);
    let (v1, v2) = rest.split_at_mut(n * w);
    for a in 0..n {
        let row = Row {
            xy: &inputs.xy[a * p2..(a + 1) * p2],
            vel: &inputs.vel[a * p2..(a + 1) * p2],
            acc: &inputs.acc[a * p2..(a + 1) * p2],
            force: inputs.force.map(|f| &f[a * p2..(a + 1) * p2]),
            torque: inputs.torque.map(|t| &t[a * nb..(a + 1) * nb]),
        };
        let (r0, r1, r2) = (
            &mut v0[a * w..(a + 1) * w],
            &mut v1[a * w..(a + 1) * w],
            &mut v2[a * w..(a + 1) * w],
        );
        conds[a] = if s.pose.fill(&model.spec, row) {
            model.solve_one(&mut s, [&mut *r0, &mut *r1, &mut *r2])
        } else {
            f64::NAN
        };
        ratios[a] = s.pose.analog_ratio;
        if conds[a].is_nan() || conds[a] == 0.0 {
            r0.fill(f64::NAN);
            r1.fill(f64::NAN);
            r2.fill(f64::NAN);
        }
    }
    (values, conds, ratios)
}
