//! The closed-form (class II) steps over blocks of [`LANES`] crank angles in
//! explicit SIMD: `pulp` picks the instruction set at run time (AVX-512, AVX2 or
//! plain scalar code), and each step runs over the whole block before the next,
//! so the angles' independent square roots and divisions fill the vector units.
//!
//! Every closed-form step has a lane form: the crank, RRR (and coupler points),
//! RRP, PRP and RPR.
//!
//! Bit for bit [`Program::solve_one`] (tested on every instruction set): the same
//! formulas, operation for operation, no fused multiply-adds, IEEE division and
//! square root in every lane, sin/cos by [`sin_cos_simd`] (fdlibm's, bit for bit
//! [`crate::geom::sin_cos`]). A lane that cannot be assembled is masked, not
//! returned from; its values are computed and thrown away.

use pulp::{Simd, WithSimd};

use crate::geom::{sin_cos, sin_cos_simd};

use super::model::{Line, Program, Step};
use super::solve::{Out, FOLD_H2_REL, SINGULAR_REL};

/// Angles solved together.
pub(super) const LANES: usize = 32;

/// One coordinate of a point over a block of angles.
pub(super) type Lane = [f64; LANES];

/// A point (x, y) over a block.
type P2 = [Lane; 2];

const ZERO: P2 = [[0.0; LANES]; 2];

impl Program {
    /// Every step has a lane form: the crank and the closed-form class II groups
    /// (RRR and coupler points, RRP, PRP, RPR). Programs with class III groups
    /// are walked angle by angle ([`Program::solve_one`]).
    pub(super) fn has_lane_form(&self) -> bool {
        !self.steps.iter().any(|s| matches!(s, Step::Triad { .. }))
    }

    /// Per step: whether its analogs are needed for those of the points `sel`
    /// (a point's analogs read the analogs of the points its step reads). Every
    /// step's positions are always solved: the flags `ok` and `singular` are the
    /// whole mechanism's at each angle, whatever points are asked for.
    pub(super) fn analogs_needed(&self, sel: &[usize]) -> Vec<bool> {
        let mut need = vec![false; self.n_points];
        for &k in sel {
            need[k] = true;
        }
        let mut steps = vec![false; self.steps.len()];
        for (s, step) in self.steps.iter().enumerate().rev() {
            let (reads, writes) = step.reads_writes();
            if writes.iter().any(|&w| need[w]) {
                steps[s] = true;
                for r in reads {
                    need[r] = true;
                }
            }
        }
        steps
    }
}

/// Solve `angles` in blocks of [`LANES`] into `out` (rows of the points `sel`),
/// the analogs of step `s` when `an[s]` (none when `out` has no analogs). The
/// program must have [`Program::has_lane_form`].
pub(super) struct Blocks<'a, 'b, 'c> {
    pub(super) prog: &'a Program,
    pub(super) an: &'a [bool],
    pub(super) angles: &'a [f64],
    pub(super) sel: &'a [usize],
    pub(super) out: &'c mut Out<'b>,
}

impl WithSimd for Blocks<'_, '_, '_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, simd: S) {
        let Blocks {
            prog,
            an,
            angles,
            sel,
            out,
        } = self;
        // Registers of 1, 2, 4 or 8 doubles: a block is whole registers.
        assert!(LANES.is_multiple_of(S::F64_LANES) && an.len() == prog.steps.len());
        let p = prog.n_points;
        let (mut xy, mut vel, mut acc) = (vec![ZERO; p], vec![ZERO; p], vec![ZERO; p]);
        for &(k, q) in &prog.fixed {
            xy[k] = [[q[0]; LANES], [q[1]; LANES]];
        }
        let analogs = !out.vel.is_empty();
        for start in (0..angles.len()).step_by(LANES) {
            let n = LANES.min(angles.len() - start);
            // A short last block repeats its last angle in the unused lanes.
            let phi: Lane = std::array::from_fn(|l| angles[start + l.min(n - 1)]);
            let mut st = Block {
                simd,
                xy: &mut xy,
                vel: &mut vel,
                acc: &mut acc,
                ok: [1.0; LANES],
                singular: [0.0; LANES],
            };
            for (step, &an) in prog.steps.iter().zip(an) {
                let an = an && analogs;
                match *step {
                    Step::Driver { pivot, tip, radius } => st.driver(&phi, pivot, tip, radius, an),
                    Step::Circles {
                        a,
                        b,
                        p,
                        ra,
                        rb,
                        sign,
                    } => st.circles([a, b, p], ra, rb, sign, an),
                    Step::Slide {
                        a,
                        r,
                        line,
                        p,
                        sign,
                    } => st.slide(a, line, p, r, sign, an),
                    Step::Cross { l1, l2, p } => st.cross(l1, l2, p, an),
                    Step::Aim { b, s, c, len, sign } => st.aim([b, s, c], len, sign, an),
                    // has_lane_form() holds: a class III group would leave its
                    // points unsolved, so fail rather than guess.
                    Step::Triad { .. } => st.ok = [0.0; LANES],
                }
            }
            let (ok, singular) = (st.ok, st.singular);
            let m = sel.len();
            let rows = start * m..(start + n) * m;
            for (k, &j) in sel.iter().enumerate() {
                emit(simd, &ok, &xy[j], &mut out.xy[rows.clone()], m, k);
                if analogs {
                    emit(simd, &ok, &vel[j], &mut out.vel[rows.clone()], m, k);
                    emit(simd, &ok, &acc[j], &mut out.acc[rows.clone()], m, k);
                }
            }
            for l in 0..n {
                let good = ok[l] != 0.0;
                out.ok[start + l] = good;
                out.singular[start + l] = good && singular[l] != 0.0;
                out.branch[start + l] = false;
            }
        }
    }
}

/// Column `k` of the rows `dst` (`m` points a row, one row per lane of the
/// block) from the point `src` over the block, NaN where the lane is not `ok`.
#[inline(always)]
fn emit<S: Simd>(simd: S, ok: &Lane, src: &P2, dst: &mut [[f64; 2]], m: usize, k: usize) {
    let (one, nan) = (simd.splat_f64s(1.0), simd.splat_f64s(f64::NAN));
    let (mut x, mut y) = ([0.0; LANES], [0.0; LANES]);
    for i in 0..LANES / S::F64_LANES {
        let good = simd.equal_f64s(ld::<S>(ok, i), one);
        st::<S>(&mut x, i, simd.select_f64s(good, ld::<S>(&src[0], i), nan));
        st::<S>(&mut y, i, simd.select_f64s(good, ld::<S>(&src[1], i), nan));
    }
    assert!(k < m);
    for (l, row) in dst.chunks_exact_mut(m).enumerate().take(LANES) {
        row[k] = [x[l], y[l]];
    }
}

/// The state of one block while its steps run: points, analogs, and per lane
/// `ok` (1.0 while assembled, else 0.0) and `singular` (1.0 at a dead centre).
struct Block<'s, S: Simd> {
    simd: S,
    xy: &'s mut [P2],
    vel: &'s mut [P2],
    acc: &'s mut [P2],
    ok: Lane,
    singular: Lane,
}

/// [`sin_cos`] in the lanes beyond the SIMD reduction's range; out of line and
/// cold, so that the compiler does not evaluate it for every block.
#[cold]
#[inline(never)]
fn far_sin_cos(phi: &Lane, sn: &mut Lane, cs: &mut Lane) {
    for l in 0..LANES {
        if phi[l].abs() > 1e6 || phi[l].is_nan() {
            (sn[l], cs[l]) = sin_cos(phi[l]);
        }
    }
}

/// Register `i` of a lane.
#[inline(always)]
fn ld<S: Simd>(v: &Lane, i: usize) -> S::f64s {
    S::as_simd_f64s(v).0[i]
}

/// Store register `i` of a lane.
#[inline(always)]
fn st<S: Simd>(v: &mut Lane, i: usize, x: S::f64s) {
    S::as_mut_simd_f64s(v).0[i] = x;
}

/// The arithmetic of the scalar kernel on registers (no fused multiply-add).
#[derive(Clone, Copy)]
struct Ops<S: Simd>(S);

impl<S: Simd> Ops<S> {
    #[inline(always)]
    fn k(self, v: f64) -> S::f64s {
        self.0.splat_f64s(v)
    }
    #[inline(always)]
    fn add(self, a: S::f64s, b: S::f64s) -> S::f64s {
        self.0.add_f64s(a, b)
    }
    #[inline(always)]
    fn sub(self, a: S::f64s, b: S::f64s) -> S::f64s {
        self.0.sub_f64s(a, b)
    }
    #[inline(always)]
    fn mul(self, a: S::f64s, b: S::f64s) -> S::f64s {
        self.0.mul_f64s(a, b)
    }
    #[inline(always)]
    fn div(self, a: S::f64s, b: S::f64s) -> S::f64s {
        self.0.div_f64s(a, b)
    }
    /// a·b as [`crate::geom::dot`]: a0·b0 + a1·b1.
    #[inline(always)]
    fn dot(self, a: [S::f64s; 2], b: [S::f64s; 2]) -> S::f64s {
        self.add(self.mul(a[0], b[0]), self.mul(a[1], b[1]))
    }
    /// a × b as [`crate::geom::cross`]: a0·b1 − a1·b0.
    #[inline(always)]
    fn cross(self, a: [S::f64s; 2], b: [S::f64s; 2]) -> S::f64s {
        self.sub(self.mul(a[0], b[1]), self.mul(a[1], b[0]))
    }
    #[inline(always)]
    fn sub2(self, a: [S::f64s; 2], b: [S::f64s; 2]) -> [S::f64s; 2] {
        [self.sub(a[0], b[0]), self.sub(a[1], b[1])]
    }
    /// √(max(x, 0)) as the scalar kernel takes it: x where x > 0, else 0 (NaN
    /// included; such a lane has already failed).
    #[inline(always)]
    fn sqrt_pos(self, x: S::f64s) -> S::f64s {
        let z = self.k(0.0);
        self.0
            .sqrt_f64s(self.0.select_f64s(self.0.less_than_f64s(z, x), x, z))
    }
    /// `solve2` of the scalar kernel: `[n1ᵀ; n2ᵀ] x = (r1, r2)` by Cramer's rule.
    #[inline(always)]
    fn solve2(
        self,
        n1: [S::f64s; 2],
        n2: [S::f64s; 2],
        inv: S::f64s,
        r1: S::f64s,
        r2: S::f64s,
    ) -> [S::f64s; 2] {
        [
            self.mul(self.sub(self.mul(r1, n2[1]), self.mul(r2, n1[1])), inv),
            self.mul(self.sub(self.mul(n1[0], r2), self.mul(n2[0], r1)), inv),
        ]
    }
    /// `v` where `dead` is false, NaN where it is true.
    #[inline(always)]
    fn nan_where(self, dead: S::m64s, v: [S::f64s; 2]) -> [S::f64s; 2] {
        let nan = self.k(f64::NAN);
        [
            self.0.select_f64s(dead, nan, v[0]),
            self.0.select_f64s(dead, nan, v[1]),
        ]
    }
}

/// Register `i` of a point over the block.
#[inline(always)]
fn ld2<S: Simd>(v: &P2, i: usize) -> [S::f64s; 2] {
    [ld::<S>(&v[0], i), ld::<S>(&v[1], i)]
}

#[inline(always)]
fn st2<S: Simd>(v: &mut P2, i: usize, x: [S::f64s; 2]) {
    st::<S>(&mut v[0], i, x[0]);
    st::<S>(&mut v[1], i, x[1]);
}

impl<S: Simd> Block<'_, S> {
    /// Lane mask update: `ok` stays 1.0 where `fine`, becomes 0.0 elsewhere.
    #[inline(always)]
    fn keep(&mut self, i: usize, fine: S::m64s) {
        let s = self.simd;
        let ok = s.select_f64s(fine, ld::<S>(&self.ok, i), s.splat_f64s(0.0));
        st::<S>(&mut self.ok, i, ok);
    }

    #[inline(always)]
    fn mark_singular(&mut self, i: usize, dead: S::m64s) {
        let s = self.simd;
        let v = s.select_f64s(dead, s.splat_f64s(1.0), ld::<S>(&self.singular, i));
        st::<S>(&mut self.singular, i, v);
    }

    /// `tip = pivot + radius·(cos φ, sin φ)`; analogs `radius·(−sin, cos)` and
    /// `radius·(−cos, −sin)`.
    #[inline(always)]
    fn driver(&mut self, phi: &Lane, pivot: usize, tip: usize, radius: f64, an: bool) {
        let (simd, o) = (Ops(self.simd), self.xy[pivot]);
        let (mut sn, mut cs) = ([0.0; LANES], [0.0; LANES]);
        for i in 0..LANES / S::F64_LANES {
            let (s, c) = sin_cos_simd(self.simd, ld::<S>(phi, i));
            st::<S>(&mut sn, i, s);
            st::<S>(&mut cs, i, c);
        }
        // Beyond the reduction's range (|φ| > 1e6): the platform's, as sin_cos.
        if phi.iter().any(|v| v.abs() > 1e6 || v.is_nan()) {
            far_sin_cos(phi, &mut sn, &mut cs);
        }
        let (r, nr) = (simd.k(radius), simd.k(-radius));
        for i in 0..LANES / S::F64_LANES {
            let (s, c) = (ld::<S>(&sn, i), ld::<S>(&cs, i));
            let o = ld2::<S>(&o, i);
            st2::<S>(
                &mut self.xy[tip],
                i,
                [
                    simd.add(o[0], simd.mul(r, c)),
                    simd.add(o[1], simd.mul(r, s)),
                ],
            );
            if an {
                st2::<S>(&mut self.vel[tip], i, [simd.mul(nr, s), simd.mul(r, c)]);
                st2::<S>(&mut self.acc[tip], i, [simd.mul(nr, c), simd.mul(nr, s)]);
            }
        }
    }

    /// [`Step::Circles`]: `p` at `ra` from `a` and `rb` from `b`, on side `sign`.
    #[inline(always)]
    fn circles(&mut self, [a, b, p]: [usize; 3], ra: f64, rb: f64, sign: f64, an: bool) {
        let (s, o) = (self.simd, Ops(self.simd));
        // The scalar kernel's constants, bit for bit.
        let (c0, ra2) = (o.k(ra * ra - rb * rb), o.k(ra * ra));
        let floor = o.k(-1e-12 * ra * ra);
        let tol = o.k(SINGULAR_REL * ra * rb);
        let fold = o.k(FOLD_H2_REL * ra * ra);
        let (one, half, sg, zero) = (o.k(1.0), o.k(0.5), o.k(sign), o.k(0.0));
        let (mut q, mut v, mut ac) = (ZERO, ZERO, ZERO);
        for i in 0..LANES / S::F64_LANES {
            let (pa, pb) = (ld2::<S>(&self.xy[a], i), ld2::<S>(&self.xy[b], i));
            let d = o.sub2(pb, pa);
            let dd = o.dot(d, d);
            let len = s.sqrt_f64s(dd);
            let inv = o.div(one, len);
            let x = o.mul(o.add(c0, dd), o.mul(half, inv));
            let h2 = o.sub(ra2, o.mul(x, x));
            let fine = s.and_m64s(
                s.not_m64s(s.equal_f64s(len, zero)),
                s.greater_than_or_equal_f64s(h2, floor),
            );
            self.keep(i, fine);
            let h = o.sqrt_pos(h2);
            let (ex, ey) = (o.mul(d[0], inv), o.mul(d[1], inv));
            let sh = o.mul(sg, h);
            let qq = [
                o.sub(o.add(pa[0], o.mul(x, ex)), o.mul(sh, ey)),
                o.add(o.add(pa[1], o.mul(x, ey)), o.mul(sh, ex)),
            ];
            st2::<S>(&mut q, i, qq);
            let (u, w) = (o.sub2(qq, pa), o.sub2(qq, pb));
            let det = o.cross(u, w);
            let dead = s.or_m64s(
                s.less_than_or_equal_f64s(s.abs_f64s(det), tol),
                s.less_than_or_equal_f64s(s.abs_f64s(h2), fold),
            );
            self.mark_singular(i, dead);
            if an {
                let (va, vb) = (ld2::<S>(&self.vel[a], i), ld2::<S>(&self.vel[b], i));
                let (aa, ab) = (ld2::<S>(&self.acc[a], i), ld2::<S>(&self.acc[b], i));
                let inv = o.div(one, det);
                let vv = o.solve2(u, w, inv, o.dot(u, va), o.dot(w, vb));
                let (ra_, rb_) = (o.sub2(vv, va), o.sub2(vv, vb));
                let r1 = o.sub(o.dot(u, aa), o.dot(ra_, ra_));
                let r2 = o.sub(o.dot(w, ab), o.dot(rb_, rb_));
                let a2 = o.solve2(u, w, inv, r1, r2);
                st2::<S>(&mut v, i, o.nan_where(dead, vv));
                st2::<S>(&mut ac, i, o.nan_where(dead, a2));
            }
        }
        self.xy[p] = q;
        if an {
            self.vel[p] = v;
            self.acc[p] = ac;
        }
    }

    /// A guide over the block: a point on it, its direction (not normalised),
    /// and their first and second analogs (zero for a guide fixed to the frame),
    /// as `Line::at`.
    #[inline(always)]
    fn line(&self, line: Line, an: bool) -> [P2; 6] {
        match line {
            Line::Fixed { o: p0, u } => [
                [[p0[0]; LANES], [p0[1]; LANES]],
                [[u[0]; LANES], [u[1]; LANES]],
                ZERO,
                ZERO,
                ZERO,
                ZERO,
            ],
            Line::Through { b, c } => {
                let sub = |x: &P2, y: &P2| -> P2 {
                    [
                        std::array::from_fn(|l| x[0][l] - y[0][l]),
                        std::array::from_fn(|l| x[1][l] - y[1][l]),
                    ]
                };
                let (xy, vel, acc) = (&*self.xy, &*self.vel, &*self.acc);
                if an {
                    [
                        xy[b],
                        sub(&xy[c], &xy[b]),
                        vel[b],
                        sub(&vel[c], &vel[b]),
                        acc[b],
                        sub(&acc[c], &acc[b]),
                    ]
                } else {
                    [xy[b], sub(&xy[c], &xy[b]), ZERO, ZERO, ZERO, ZERO]
                }
            }
        }
    }

    /// [`Step::Cross`]: `p` where two guides cross; a lane where they are parallel
    /// (or NaN) is not assembled.
    #[inline(always)]
    fn cross(&mut self, l1: Line, l2: Line, p: usize, an: bool) {
        let (s, o) = (self.simd, Ops(self.simd));
        let g1 = self.line(l1, an);
        let g2 = self.line(l2, an);
        let (rel, two, one) = (o.k(SINGULAR_REL), o.k(2.0), o.k(1.0));
        let neg = o.k(-0.0);
        let (mut q, mut v, mut ac) = (ZERO, ZERO, ZERO);
        for i in 0..LANES / S::F64_LANES {
            let (o1, e1) = (ld2::<S>(&g1[0], i), ld2::<S>(&g1[1], i));
            let (o2, e2) = (ld2::<S>(&g2[0], i), ld2::<S>(&g2[1], i));
            let n1 = [e1[1], s.xor_f64s(e1[0], neg)];
            let n2 = [e2[1], s.xor_f64s(e2[0], neg)];
            let det = o.cross(n1, n2);
            let scale = o.mul(s.sqrt_f64s(o.dot(n1, n1)), s.sqrt_f64s(o.dot(n2, n2)));
            let parallel = s.less_than_or_equal_f64s(s.abs_f64s(det), o.mul(rel, scale));
            let nan = s.not_m64s(s.equal_f64s(det, det));
            self.keep(i, s.not_m64s(s.or_m64s(parallel, nan)));
            let inv = o.div(one, det);
            let qq = o.solve2(n1, n2, inv, o.dot(n1, o1), o.dot(n2, o2));
            st2::<S>(&mut q, i, qq);
            if an {
                let (o11, e11) = (ld2::<S>(&g1[2], i), ld2::<S>(&g1[3], i));
                let (o12, e12) = (ld2::<S>(&g1[4], i), ld2::<S>(&g1[5], i));
                let (o21, e21) = (ld2::<S>(&g2[2], i), ld2::<S>(&g2[3], i));
                let (o22, e22) = (ld2::<S>(&g2[4], i), ld2::<S>(&g2[5], i));
                let (p1, p2) = (o.sub2(qq, o1), o.sub2(qq, o2));
                let rv1 = o.sub(o.dot(n1, o11), o.cross(p1, e11));
                let rv2 = o.sub(o.dot(n2, o21), o.cross(p2, e21));
                let vv = o.solve2(n1, n2, inv, rv1, rv2);
                let ra1 = o.sub(
                    o.sub(o.dot(n1, o12), o.mul(two, o.cross(o.sub2(vv, o11), e11))),
                    o.cross(p1, e12),
                );
                let ra2 = o.sub(
                    o.sub(o.dot(n2, o22), o.mul(two, o.cross(o.sub2(vv, o21), e21))),
                    o.cross(p2, e22),
                );
                st2::<S>(&mut v, i, vv);
                st2::<S>(&mut ac, i, o.solve2(n1, n2, inv, ra1, ra2));
            }
        }
        self.xy[p] = q;
        if an {
            self.vel[p] = v;
            self.acc[p] = ac;
        }
    }

    /// [`Step::Aim`]: `c = b + sign·len·ŝ`, ŝ the unit vector from `b` to the
    /// block `s`; a lane with the block on the pivot is not assembled.
    #[inline(always)]
    fn aim(&mut self, [b, sp, c]: [usize; 3], len: f64, sign: f64, an: bool) {
        let (s, o) = (self.simd, Ops(self.simd));
        let (tol, k, two) = (o.k(SINGULAR_REL * len), o.k(sign * len), o.k(2.0));
        let neg = o.k(-0.0);
        let (mut q, mut v, mut ac) = (ZERO, ZERO, ZERO);
        for i in 0..LANES / S::F64_LANES {
            let pb = ld2::<S>(&self.xy[b], i);
            let w = o.sub2(ld2::<S>(&self.xy[sp], i), pb);
            let l2 = o.dot(w, w);
            let l = s.sqrt_f64s(l2);
            self.keep(i, s.not_m64s(s.less_than_or_equal_f64s(l, tol)));
            let e = [o.div(w[0], l), o.div(w[1], l)];
            let en = [o.div(s.xor_f64s(w[1], neg), l), o.div(w[0], l)];
            st2::<S>(
                &mut q,
                i,
                [o.add(pb[0], o.mul(k, e[0])), o.add(pb[1], o.mul(k, e[1]))],
            );
            if an {
                let (vb, ab) = (ld2::<S>(&self.vel[b], i), ld2::<S>(&self.acc[b], i));
                let w1 = o.sub2(ld2::<S>(&self.vel[sp], i), vb);
                let w2 = o.sub2(ld2::<S>(&self.acc[sp], i), ab);
                let c1 = o.cross(w, w1);
                let t1 = o.div(c1, l2);
                let t2 = o.sub(
                    o.div(o.cross(w, w2), l2),
                    o.div(o.mul(o.mul(two, o.dot(w, w1)), c1), o.mul(l2, l2)),
                );
                let kt1 = o.mul(k, t1);
                st2::<S>(
                    &mut v,
                    i,
                    [
                        o.add(vb[0], o.mul(kt1, en[0])),
                        o.add(vb[1], o.mul(kt1, en[1])),
                    ],
                );
                let tt = o.mul(t1, t1);
                st2::<S>(
                    &mut ac,
                    i,
                    [
                        o.add(ab[0], o.mul(k, o.sub(o.mul(t2, en[0]), o.mul(tt, e[0])))),
                        o.add(ab[1], o.mul(k, o.sub(o.mul(t2, en[1]), o.mul(tt, e[1])))),
                    ],
                );
            }
        }
        self.xy[c] = q;
        if an {
            self.vel[c] = v;
            self.acc[c] = ac;
        }
    }

    /// [`Step::Slide`]: `p` at `r` from `a` on `line`, on side `sign` of the foot
    /// of `a` along the line's direction.
    #[inline(always)]
    fn slide(&mut self, a: usize, line: Line, p: usize, r: f64, sign: f64, an: bool) {
        let (s, o) = (self.simd, Ops(self.simd));
        let [lo, le, lo1, le1, lo2, le2] = self.line(line, an);
        let (pa, va, aa) = (self.xy[a], self.vel[a], self.acc[a]);
        let floor = o.k(-1e-12 * r * r);
        let (r2, rel, sg, zero, one, two) = (
            o.k(r * r),
            o.k(SINGULAR_REL * r),
            o.k(sign),
            o.k(0.0),
            o.k(1.0),
            o.k(2.0),
        );
        let (mut q, mut v, mut ac) = (ZERO, ZERO, ZERO);
        for i in 0..LANES / S::F64_LANES {
            let (lo, le) = (ld2::<S>(&lo, i), ld2::<S>(&le, i));
            let el = s.sqrt_f64s(o.dot(le, le));
            let e = [o.div(le[0], el), o.div(le[1], el)];
            let pa = ld2::<S>(&pa, i);
            let ao = o.sub2(pa, lo);
            let (t0, off) = (o.dot(ao, e), o.cross(e, ao));
            let q2 = o.sub(r2, o.mul(off, off));
            let fine = s.and_m64s(
                s.not_m64s(s.equal_f64s(el, zero)),
                s.greater_than_or_equal_f64s(q2, floor),
            );
            self.keep(i, fine);
            let t = o.add(t0, o.mul(sg, o.sqrt_pos(q2)));
            let qq = [o.add(lo[0], o.mul(t, e[0])), o.add(lo[1], o.mul(t, e[1]))];
            st2::<S>(&mut q, i, qq);
            // The guide's normal, n·x = x × e (e not normalised).
            let nrm = [le[1], s.xor_f64s(le[0], o.k(-0.0))];
            let u = o.sub2(qq, pa);
            let det = o.cross(u, nrm);
            let dead = s.less_than_or_equal_f64s(s.abs_f64s(det), o.mul(rel, el));
            self.mark_singular(i, dead);
            if an {
                let (va, aa) = (ld2::<S>(&va, i), ld2::<S>(&aa, i));
                let (o1, e1) = (ld2::<S>(&lo1, i), ld2::<S>(&le1, i));
                let (o2, e2) = (ld2::<S>(&lo2, i), ld2::<S>(&le2, i));
                let inv = o.div(one, det);
                let po = o.sub2(qq, lo);
                // LineAt::rhs_v and rhs_a.
                let rhs_v = o.sub(o.dot(nrm, o1), o.cross(po, e1));
                let vv = o.solve2(u, nrm, inv, o.dot(u, va), rhs_v);
                let dv = o.sub2(vv, va);
                let r1 = o.sub(o.dot(u, aa), o.dot(dv, dv));
                let rhs_a = o.sub(
                    o.sub(o.dot(nrm, o2), o.mul(two, o.cross(o.sub2(vv, o1), e1))),
                    o.cross(po, e2),
                );
                let a2 = o.solve2(u, nrm, inv, r1, rhs_a);
                st2::<S>(&mut v, i, o.nan_where(dead, vv));
                st2::<S>(&mut ac, i, o.nan_where(dead, a2));
            }
        }
        self.xy[p] = q;
        if an {
            self.vel[p] = v;
            self.acc[p] = ac;
        }
    }
}
