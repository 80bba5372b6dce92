//! The batched per-angle solve: one pose's system assembled densely, solved by
//! its blocks in order, three right-hand sides at once, angles in parallel.

use rayon::prelude::*;

use super::{ForceError, Guide, Model, Sink, Spec};
use crate::geom::{cross, dot, sub, V2};
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
pub struct Outputs<'a> {
    pub values: &'a mut [f64],
    pub conditioning: &'a mut [f64],
    pub reactions: bool,
}

/// The kinematic quantities of one pose, for [`Model::assemble`].
pub(super) struct Pose {
    pub(super) xy: Vec<V2>,
    pub(super) vel: Vec<V2>,
    acc: Vec<V2>,
    com: Vec<V2>,
    pub(super) com_v: Vec<V2>,
    pub(super) com_a: Vec<V2>,
    pub(super) omega_v: Vec<f64>,
    pub(super) omega_a: Vec<f64>,
    pub(super) normal: Vec<V2>,
    force: Vec<V2>,
    torques: Vec<f64>,
    /// Friction's loads (see `friction`), read only when `extra` is set: a
    /// force on each point [N] and a force and moment about the centre of mass
    /// on each body [N, N·m], all in the static part.
    pub(super) extra: bool,
    pub(super) extra_force: Vec<V2>,
    pub(super) extra_body: Vec<[f64; 3]>,
}

impl Pose {
    /// A pose with placeholder values: only the pattern is read from it.
    pub(super) fn structural(spec: &Spec) -> Pose {
        let (p, b, g) = (spec.n_points, spec.bodies.len(), spec.guides.len());
        Pose {
            xy: vec![[0.0; 2]; p],
            vel: vec![[0.0; 2]; p],
            acc: vec![[0.0; 2]; p],
            com: vec![[0.0; 2]; b],
            com_v: vec![[0.0; 2]; b],
            com_a: vec![[0.0; 2]; b],
            omega_v: vec![0.0; b],
            omega_a: vec![0.0; b],
            normal: vec![[0.0; 2]; g],
            force: vec![[0.0; 2]; p],
            torques: vec![0.0; b],
            extra: false,
            extra_force: vec![[0.0; 2]; p],
            extra_body: vec![[0.0; 3]; b],
        }
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
        let finite = |v: &[V2]| v.iter().all(|p| p[0].is_finite() && p[1].is_finite());
        let ok = finite(&self.xy) && finite(&self.vel) && finite(&self.acc);
        if !(ok && finite(&self.force) && self.torques.iter().all(|t| t.is_finite())) {
            return false;
        }
        for (i, body) in spec.bodies.iter().enumerate() {
            let (j0, j1) = (body.points[0], body.points[1]);
            let [u, v] = body.com_uv;
            let at = |x: &[V2]| {
                let d = sub(x[j1], x[j0]);
                [
                    x[j0][0] + u * d[0] - v * d[1],
                    x[j0][1] + u * d[1] + v * d[0],
                ]
            };
            self.com[i] = at(&self.xy);
            self.com_v[i] = at(&self.vel);
            self.com_a[i] = at(&self.acc);
            let d = sub(self.xy[j1], self.xy[j0]);
            let d1 = sub(self.vel[j1], self.vel[j0]);
            let d2 = sub(self.acc[j1], self.acc[j0]);
            let n2 = dot(d, d);
            let w = cross(d, d1) / n2;
            self.omega_v[i] = w;
            self.omega_a[i] = cross(d, d2) / n2 - 2.0 * dot(d, d1) * w / n2;
        }
        for (g, guide) in spec.guides.iter().enumerate() {
            let e = match *guide {
                Guide::Fixed { dir, .. } => dir,
                Guide::Link { b, c, .. } => sub(self.xy[c], self.xy[b]),
            };
            let len = dot(e, e).sqrt();
            self.normal[g] = [-e[1] / len, e[0] / len];
        }
        true
    }

    /// r − c of body `b`.
    pub(super) fn arm(&self, b: usize, x: V2) -> V2 {
        sub(x, self.com[b])
    }

    /// The external torque on body `b` [N·m].
    pub(super) fn torque(&self, b: usize) -> f64 {
        self.torques[b]
    }

    /// The known part of pin `p`'s equation, F_ext + m_p g − m_p a_p, by part.
    pub(super) fn pin_load(&self, spec: &Spec, p: usize) -> [V2; 3] {
        let m = spec.point_mass[p];
        let (v, a, mut f, g) = (self.vel[p], self.acc[p], self.force[p], spec.gravity);
        if self.extra {
            f = [f[0] + self.extra_force[p][0], f[1] + self.extra_force[p][1]];
        }
        [
            [-m * a[0], -m * a[1]],
            [-m * v[0], -m * v[1]],
            [f[0] + m * g[0], f[1] + m * g[1]],
        ]
    }
}

/// One parallel task: its chunk's index, its rows of the three parts and flags.
type Task<'a> = (
    usize,
    (
        ((&'a mut [f64], &'a mut [f64]), &'a mut [f64]),
        &'a mut [f64],
    ),
);

/// One angle's inputs (flat (x, y) pairs).
#[derive(Clone, Copy)]
pub(super) struct Row<'a> {
    pub(super) xy: &'a [f64],
    pub(super) vel: &'a [f64],
    pub(super) acc: &'a [f64],
    pub(super) force: Option<&'a [f64]>,
    pub(super) torque: Option<&'a [f64]>,
}

/// The dense system of one pose.
struct Dense {
    n: usize,
    a: Vec<f64>,
    r: Vec<f64>,
}

impl Sink for Dense {
    #[inline(always)]
    fn a(&mut self, row: usize, col: usize, v: f64) {
        self.a[row * self.n + col] += v;
    }
    #[inline(always)]
    fn rhs(&mut self, row: usize, part: usize, v: f64) {
        self.r[row * 3 + part] += v;
    }
}

/// Per-task buffers.
pub(super) struct Scratch {
    pub(super) pose: Pose,
    sys: Dense,
    x: Vec<f64>,
    m: Vec<f64>,
    b: Vec<f64>,
}

impl Model {
    pub(super) fn scratch(&self) -> Scratch {
        let n = self.n;
        let big = self.blocks.iter().map(|b| b.cols.len()).max().unwrap_or(0);
        Scratch {
            pose: Pose::structural(&self.spec),
            sys: Dense {
                n,
                a: vec![0.0; n * n],
                r: vec![0.0; n * 3],
            },
            x: vec![0.0; n * 3],
            m: vec![0.0; big * big],
            b: vec![0.0; big * 3],
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
        let n = self.n;
        s.sys.a.fill(0.0);
        s.sys.r.fill(0.0);
        self.assemble(&s.pose, &mut s.sys);
        let (a, r, x) = (&s.sys.a, &s.sys.r, &mut s.x);
        let mut cond = f64::INFINITY;
        for blk in &self.blocks {
            let k = blk.cols.len();
            let (m, b) = (&mut s.m[..k * k], &mut s.b[..k * 3]);
            for (i, &row) in blk.rows.iter().enumerate() {
                let from = &a[row * n..(row + 1) * n];
                for (dst, &col) in m[i * k..(i + 1) * k].iter_mut().zip(&blk.cols) {
                    *dst = from[col];
                }
                let mut v = [r[row * 3], r[row * 3 + 1], r[row * 3 + 2]];
                for &col in &blk.deps[i] {
                    let c = from[col];
                    let xs = &x[col * 3..col * 3 + 3];
                    v[0] -= c * xs[0];
                    v[1] -= c * xs[1];
                    v[2] -= c * xs[2];
                }
                b[i * 3..i * 3 + 3].copy_from_slice(&v);
            }
            let scale = abs_max(m);
            match lu_solve(m, b, k, SINGULAR_REL * scale) {
                Some(pivot) => cond = cond.min(pivot / scale),
                None => return 0.0,
            }
            for (j, &col) in blk.cols.iter().enumerate() {
                x[col * 3..col * 3 + 3].copy_from_slice(&b[j * 3..j * 3 + 3]);
            }
        }
        self.write(s, out);
        cond
    }

    /// One angle's values from the solved unknowns: the torque, the guides and
    /// (if the rows have room) every pin's forces, the eliminated one from its
    /// pin's equation.
    fn write(&self, s: &Scratch, out: [&mut [f64]; 3]) {
        let g_n = self.spec.guides.len();
        let x = &s.x;
        for (part, row) in out.into_iter().enumerate() {
            row[0] = x[self.torque_col * 3 + part];
            for g in 0..g_n {
                row[1 + g] = x[(self.guide_col + g) * 3 + part];
            }
            if row.len() == 1 + g_n {
                continue;
            }
            let mut k = 1 + g_n;
            for pin in &self.pins {
                if pin.sides.is_empty() {
                    continue;
                }
                let load = s.pose.pin_load(&self.spec, pin.point)[part];
                let mut first = load;
                for &g in &pin.guides {
                    let nn = s.pose.normal[g];
                    let f = x[(self.guide_col + g) * 3 + part];
                    first[0] += f * nn[0];
                    first[1] += f * nn[1];
                }
                for j in 0..pin.sides.len() - 1 {
                    let (cx, cy) = (pin.col + 2 * j, pin.col + 2 * j + 1);
                    first[0] -= x[cx * 3 + part];
                    first[1] -= x[cy * 3 + part];
                }
                row[k] = first[0];
                row[k + 1] = first[1];
                k += 2;
                for j in 0..pin.sides.len() - 1 {
                    let (cx, cy) = (pin.col + 2 * j, pin.col + 2 * j + 1);
                    row[k] = x[cx * 3 + part];
                    row[k + 1] = x[cy * 3 + part];
                    k += 2;
                }
            }
        }
    }
}

/// The largest |v| of finite `v`, in four independent lanes (no serial chain
/// of NaN-aware maxima).
fn abs_max(v: &[f64]) -> f64 {
    let mut acc = [0.0f64; 4];
    let mut chunks = v.chunks_exact(4);
    for c in &mut chunks {
        for (a, x) in acc.iter_mut().zip(c) {
            let y = x.abs();
            if y > *a {
                *a = y;
            }
        }
    }
    for x in chunks.remainder() {
        let y = x.abs();
        if y > acc[0] {
            acc[0] = y;
        }
    }
    acc.iter().fold(0.0, |m, &x| if x > m { x } else { m })
}

/// Gaussian elimination with partial pivoting of the k×k `m` (row-major) on the
/// three right-hand sides `b` (k×3), in place (the diagonal keeps the pivots'
/// reciprocals): the smallest |pivot|, or None if a pivot is at most `tol` (or
/// not finite).
fn lu_solve(m: &mut [f64], b: &mut [f64], k: usize, tol: f64) -> Option<f64> {
    let mut smallest = f64::INFINITY;
    for c in 0..k {
        let (mut piv, mut best) = (c, m[c * k + c].abs());
        for r in c + 1..k {
            let v = m[r * k + c].abs();
            if v > best {
                (piv, best) = (r, v);
            }
        }
        if best <= tol || best == 0.0 || !best.is_finite() {
            return None;
        }
        smallest = smallest.min(best);
        if piv != c {
            let (top, bottom) = m.split_at_mut(piv * k);
            top[c * k..(c + 1) * k].swap_with_slice(&mut bottom[..k]);
            let (top, bottom) = b.split_at_mut(piv * 3);
            top[c * 3..c * 3 + 3].swap_with_slice(&mut bottom[..3]);
        }
        let inv = 1.0 / m[c * k + c];
        m[c * k + c] = inv;
        let (top, bottom) = m.split_at_mut((c + 1) * k);
        let prow = &top[c * k + c + 1..(c + 1) * k];
        let (btop, bbottom) = b.split_at_mut((c + 1) * 3);
        let bp = [btop[c * 3], btop[c * 3 + 1], btop[c * 3 + 2]];
        for (row, br) in bottom.chunks_exact_mut(k).zip(bbottom.chunks_exact_mut(3)) {
            let f = row[c] * inv;
            if f == 0.0 {
                continue;
            }
            for (x, p) in row[c + 1..].iter_mut().zip(prow) {
                *x -= f * p;
            }
            br[0] -= f * bp[0];
            br[1] -= f * bp[1];
            br[2] -= f * bp[2];
        }
    }
    for c in (0..k).rev() {
        let row = &m[c * k..(c + 1) * k];
        let mut v = [b[c * 3], b[c * 3 + 1], b[c * 3 + 2]];
        for (t, &coef) in row.iter().enumerate().skip(c + 1) {
            v[0] -= coef * b[t * 3];
            v[1] -= coef * b[t * 3 + 1];
            v[2] -= coef * b[t * 3 + 2];
        }
        let inv = row[c];
        b[c * 3] = v[0] * inv;
        b[c * 3 + 1] = v[1] * inv;
        b[c * 3 + 2] = v[2] * inv;
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
    let (part0, rest) = out.values.split_at_mut(n * w);
    let (part1, part2) = rest.split_at_mut(n * w);
    let run = |(c, (((v0, v1), v2), conds)): Task<'_>| {
        if crate::cancel::requested() {
            return;
        }
        let mut s = model.scratch();
        let rows = v0
            .chunks_exact_mut(w)
            .zip(v1.chunks_exact_mut(w))
            .zip(v2.chunks_exact_mut(w))
            .zip(conds.iter_mut());
        for (i, (((r0, r1), r2), cond)) in rows.enumerate() {
            let a = c * CHUNK + i;
            let row = Row {
                xy: &xy[a * p2..(a + 1) * p2],
                vel: &vel[a * p2..(a + 1) * p2],
                acc: &acc[a * p2..(a + 1) * p2],
                force: force.map(|f| &f[a * p2..(a + 1) * p2]),
                torque: torque.map(|t| &t[a * nb..(a + 1) * nb]),
            };
            *cond = if s.pose.fill(&model.spec, row) {
                model.solve_one(&mut s, [&mut *r0, &mut *r1, &mut *r2])
            } else {
                f64::NAN
            };
            if cond.is_nan() || *cond == 0.0 {
                r0.fill(f64::NAN);
                r1.fill(f64::NAN);
                r2.fill(f64::NAN);
            }
        }
    };
    pool(threads)?.install(|| {
        part0
            .par_chunks_mut(CHUNK * w)
            .zip(part1.par_chunks_mut(CHUNK * w))
            .zip(part2.par_chunks_mut(CHUNK * w))
            .zip(out.conditioning.par_chunks_mut(CHUNK))
            .enumerate()
            .for_each(run)
    });
    Ok(())
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
