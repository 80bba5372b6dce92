//! [`LANES`] crank angles at once: the number type of the SIMD lanes and the
//! block elimination lane by lane (see `solve`: each lane's values are the
//! one-angle path's, bit for bit).

use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub};

use super::solve::Num;

/// Angles solved at once, one per SIMD lane.
pub(super) const LANES: usize = 8;

/// [`LANES`] values, one per angle: every operation lane by lane (compiled to
/// vector instructions; no fused multiply–add, so each lane is bit for bit the
/// scalar code's value).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Lanes(pub(super) [f64; LANES]);

macro_rules! lane_op {
    ($tr:ident, $f:ident, $op:tt) => {
        impl $tr for Lanes {
            type Output = Lanes;
            #[inline(always)]
            fn $f(self, o: Lanes) -> Lanes {
                let mut r = [0.0; LANES];
                for ((r, a), b) in r.iter_mut().zip(self.0).zip(o.0) {
                    *r = a $op b;
                }
                Lanes(r)
            }
        }
    };
}
lane_op!(Add, add, +);
lane_op!(Sub, sub, -);
lane_op!(Mul, mul, *);
lane_op!(Div, div, /);

impl Neg for Lanes {
    type Output = Lanes;
    #[inline(always)]
    fn neg(self) -> Lanes {
        Lanes(self.0.map(|a| -a))
    }
}

impl AddAssign for Lanes {
    #[inline(always)]
    fn add_assign(&mut self, o: Lanes) {
        for (a, b) in self.0.iter_mut().zip(o.0) {
            *a += b;
        }
    }
}

impl Num for Lanes {
    #[inline(always)]
    fn splat(v: f64) -> Lanes {
        Lanes([v; LANES])
    }
    #[inline(always)]
    fn sqrt(self) -> Lanes {
        Lanes(self.0.map(f64::sqrt))
    }
}

/// `solve::block_abs_max` lane by lane (the largest |v| ignoring NaN, as there).
#[inline(always)]
pub(super) fn block_abs_max_lanes(m: &[Lanes], k: usize, st: usize) -> Lanes {
    let mut acc = [0.0f64; LANES];
    for row in m.chunks_exact(st) {
        for x in &row[..k] {
            for (a, v) in acc.iter_mut().zip(x.0) {
                let y = v.abs();
                if y > *a {
                    *a = y;
                }
            }
        }
    }
    Lanes(acc)
}

/// `solve::lu_rows` on the augmented block `m` (k rows of `st` lanes-values, as in
/// `solve::Plan`) of [`LANES`] angles: each lane chooses its own pivot rows by the
/// same rule and is eliminated by the same operations, so each lane ends as
/// `solve::lu_rows` would leave it. Returns each lane's smallest |pivot| and
/// whether it had no pivot at most `tol` (nor one not finite); a lane without
/// is left with garbage, the others untouched by it.
#[inline(always)]
pub(super) fn lu_lanes(m: &mut [Lanes], k: usize, st: usize, tol: Lanes) -> (Lanes, [bool; LANES]) {
    let mut smallest = [f64::INFINITY; LANES];
    let mut alive = [true; LANES];
    for c in 0..k {
        let mut best = m[c * st + c].0.map(f64::abs);
        let mut piv = [c; LANES];
        for r in c + 1..k {
            let v = m[r * st + c].0;
            for l in 0..LANES {
                let y = v[l].abs();
                if y > best[l] {
                    best[l] = y;
                    piv[l] = r;
                }
            }
        }
        for l in 0..LANES {
            let b = best[l];
            if b <= tol.0[l] || b == 0.0 || !b.is_finite() {
                alive[l] = false;
            }
            smallest[l] = smallest[l].min(b);
        }
        // Each lane swaps row c with its own pivot row: row r's swap blends
        // the lanes that pivot on r.
        for r in c + 1..k {
            let swap = piv.map(|p| p == r);
            if !swap.contains(&true) {
                continue;
            }
            let (top, bottom) = m.split_at_mut(r * st);
            for (a, b) in top[c * st..(c + 1) * st].iter_mut().zip(&mut bottom[..st]) {
                for ((x, y), &sw) in a.0.iter_mut().zip(b.0.iter_mut()).zip(&swap) {
                    let (u, v) = (*x, *y);
                    *x = if sw { v } else { u };
                    *y = if sw { u } else { v };
                }
            }
        }
        let (top, bottom) = m.split_at_mut((c + 1) * st);
        let prow = &mut top[c * st..];
        let inv = Lanes::splat(1.0) / prow[c];
        prow[c] = inv;
        let prow = &top[c * st..];
        for row in bottom[..(k - c - 1) * st].chunks_exact_mut(st) {
            let f = row[c] * inv;
            if f.0.iter().all(|&v| v == 0.0) {
                continue;
            }
            for (x, p) in row.iter_mut().zip(prow) {
                for l in 0..LANES {
                    // The scalar path skips a row whose factor is 0.
                    let u = x.0[l] - f.0[l] * p.0[l];
                    x.0[l] = if f.0[l] == 0.0 { x.0[l] } else { u };
                }
            }
        }
    }
    for c in (0..k).rev() {
        let (top, bottom) = m.split_at_mut((c + 1) * st);
        let row = &mut top[c * st..];
        let mut v = [row[st - 3], row[st - 2], row[st - 1]];
        for (t, b) in bottom[..(k - c - 1) * st].chunks_exact(st).enumerate() {
            let coef = row[c + 1 + t];
            v[0] = v[0] - coef * b[st - 3];
            v[1] = v[1] - coef * b[st - 2];
            v[2] = v[2] - coef * b[st - 1];
        }
        let inv = row[c];
        row[st - 3] = v[0] * inv;
        row[st - 2] = v[1] * inv;
        row[st - 1] = v[2] * inv;
    }
    (Lanes(smallest), alive)
}
