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
        let mut r = self.0;
        for a in &mut r {
            *a = -*a;
        }
        Lanes(r)
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
        let mut r = self.0;
        for a in &mut r {
            *a = a.sqrt();
        }
        Lanes(r)
    }
}

/// One diagonal block `m` (k rows of `st` lanes-values: see `solve::Plan`) of
/// [`LANES`] angles solved in place: each lane's largest |entry| of the k×k
/// matrix, and [`lu_lanes`]'s smallest pivots and live lanes with a pivot
/// tolerance of `rel` times the largest entry. Blocks of up to 13 unknowns in
/// the lanes' plan (st = k + 3) run a copy for their size, where every loop's
/// length is a constant: the loops unroll, and each lanes operation stays one
/// vector instruction (with a length known only at run time, the compiler
/// vectorizes the loops over a row's entries instead, across the lanes' arrays,
/// into code slower than the plain lane by lane operations).
#[inline(always)]
pub(super) fn solve_block_lanes(
    m: &mut [Lanes],
    k: usize,
    st: usize,
    rel: f64,
) -> (Lanes, Lanes, [bool; LANES]) {
    #[inline(always)]
    fn sized(m: &mut [Lanes], k: usize, st: usize, rel: f64) -> (Lanes, Lanes, [bool; LANES]) {
        let m = &mut m[..k * st];
        let scale = block_abs_max_lanes(m, k, st);
        let (pivot, alive) = lu_lanes(m, k, st, Lanes::splat(rel) * scale);
        (scale, pivot, alive)
    }
    macro_rules! fixed {
        ($($k:literal),*) => {
            match k {
                $($k if st == $k + 3 => sized(m, $k, $k + 3, rel),)*
                _ => sized(m, k, st, rel),
            }
        };
    }
    fixed!(1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13)
}

/// `solve::block_abs_max` lane by lane (the largest |v| ignoring NaN, as there).
#[inline(always)]
fn block_abs_max_lanes(m: &[Lanes], k: usize, st: usize) -> Lanes {
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

/// Lane by lane `if a == b { x } else { y }` (a compare and a blend: each
/// lane's choice is an IEEE comparison of floats, which the compiler keeps in
/// vector registers, where a mask of integers it turns back into branches).
// Indexed: the same lane of four arrays.
#[allow(clippy::needless_range_loop)]
#[inline(always)]
fn if_eq(a: Lanes, b: Lanes, x: Lanes, y: Lanes) -> Lanes {
    let mut r = [0.0; LANES];
    for l in 0..LANES {
        r[l] = if a.0[l] == b.0[l] { x.0[l] } else { y.0[l] };
    }
    Lanes(r)
}

/// Lane by lane `if a > b { x } else { y }`.
// Indexed: the same lane of four arrays.
#[allow(clippy::needless_range_loop)]
#[inline(always)]
fn if_gt(a: Lanes, b: Lanes, x: Lanes, y: Lanes) -> Lanes {
    let mut r = [0.0; LANES];
    for l in 0..LANES {
        r[l] = if a.0[l] > b.0[l] { x.0[l] } else { y.0[l] };
    }
    Lanes(r)
}

/// Whether a == b in every lane.
#[inline(always)]
fn all_eq(a: Lanes, b: Lanes) -> bool {
    let mut all = true;
    for l in 0..LANES {
        all &= a.0[l] == b.0[l];
    }
    all
}

/// Whether a == b in some lane.
#[inline(always)]
fn any_eq(a: Lanes, b: Lanes) -> bool {
    let mut any = false;
    for l in 0..LANES {
        any |= a.0[l] == b.0[l];
    }
    any
}

/// |v| lane by lane.
#[inline(always)]
fn abs(v: Lanes) -> Lanes {
    let mut r = v.0;
    for a in &mut r {
        *a = a.abs();
    }
    Lanes(r)
}

/// `solve::lu_rows` on the augmented block `m` (k rows of `st` lanes-values, as in
/// `solve::Plan`) of [`LANES`] angles: each lane chooses its own pivot rows by the
/// same rule and is eliminated by the same operations, so each lane ends as
/// `solve::lu_rows` would leave it (in the entries read afterwards: the upper
/// triangle and the right-hand sides; `lu_rows` also updates the entries left
/// of the pivot column and the padding, which nothing reads, and these are
/// skipped here). Returns each lane's smallest |pivot| and whether it had no
/// pivot at most `tol` (nor one not finite); a lane without is left with
/// garbage, the others untouched by it. Branch-free per lane: the pivot search,
/// the row swap and the skip of a zero factor are float compares and blends.
#[inline(always)]
fn lu_lanes(m: &mut [Lanes], k: usize, st: usize, tol: Lanes) -> (Lanes, [bool; LANES]) {
    let mut smallest = Lanes::splat(f64::INFINITY);
    let mut alive = [true; LANES];
    // The columns an elimination step at column c reads and writes: c + 1..k
    // and the three right-hand sides.
    let rhs = st - 3;
    let zero = Lanes::splat(0.0);
    for c in 0..k {
        // Each lane's pivot row (as a float: its choice a float compare too).
        let mut best = abs(m[c * st + c]);
        let mut piv = Lanes::splat(c as f64);
        for r in c + 1..k {
            let y = abs(m[r * st + c]);
            piv = if_gt(y, best, Lanes::splat(r as f64), piv);
            best = if_gt(y, best, y, best);
        }
        for ((a, s), (&b, &t)) in alive
            .iter_mut()
            .zip(&mut smallest.0)
            .zip(best.0.iter().zip(&tol.0))
        {
            // As `b <= tol || b == 0.0 || !b.is_finite()`, with no branch.
            *a &= !((b <= t) | (b == 0.0) | !b.is_finite());
            *s = s.min(b);
        }
        // Each lane swaps row c with its own pivot row: row r's swap blends
        // the lanes that pivot on r.
        for r in c + 1..k {
            let rr = Lanes::splat(r as f64);
            if !any_eq(piv, rr) {
                continue;
            }
            let (top, bottom) = m.split_at_mut(r * st);
            let (a, b) = (&mut top[c * st..(c + 1) * st], &mut bottom[..st]);
            for j in c..k {
                let (u, v) = (a[j], b[j]);
                a[j] = if_eq(piv, rr, v, u);
                b[j] = if_eq(piv, rr, u, v);
            }
            for j in rhs..st {
                let (u, v) = (a[j], b[j]);
                a[j] = if_eq(piv, rr, v, u);
                b[j] = if_eq(piv, rr, u, v);
            }
        }
        let (top, bottom) = m.split_at_mut((c + 1) * st);
        let prow = &mut top[c * st..];
        let inv = Lanes::splat(1.0) / prow[c];
        prow[c] = inv;
        let prow = &top[c * st..];
        for row in bottom[..(k - c - 1) * st].chunks_exact_mut(st) {
            let f = row[c] * inv;
            // The scalar path skips a row whose factor is 0.
            if all_eq(f, zero) {
                continue;
            }
            for j in c + 1..k {
                let x = row[j];
                row[j] = if_eq(f, zero, x, x - f * prow[j]);
            }
            for j in rhs..st {
                let x = row[j];
                row[j] = if_eq(f, zero, x, x - f * prow[j]);
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
    (smallest, alive)
}
