//! The fused evaluator of the two-period law: one pass over the angles with
//! explicit SIMD (`pulp`, AVX-512 / AVX2 + FMA picked at run time), no staging.
//!
//! Per register of angles (8 on AVX-512, 4 on AVX2): the period by one compare,
//! the law's argument u, every piece's polynomial and sine argument, the angle's
//! own piece picked by blends, one sine ([`sin_fma_simd`]: one reduction by π and
//! one odd polynomial), the range check (a running minimum, maximum and NaN
//! probe) and the store. The output scaling of each period is folded into its
//! pieces' coefficients once, so a value is P(t) + A·sin(ωt + φ) with fused
//! multiply-adds: a reassociation of the lane evaluator's off + sc·(p + a·sin),
//! within 20 ε of the order's scale of the pointwise evaluator and a few ε of
//! exact values (tested; BENCHMARKS.md, issue 20 session 3), the same bits on
//! every instruction set (tested). Used where the processor has FMA; elsewhere
//! the lane evaluator runs.

use pulp::Simd;

use super::law::Law;
use crate::geom::sin_fma_simd;

/// Largest |freq| + |phase| of a piece: its sine arguments stay within
/// [`sin_fma_simd`]'s range (|x| ≤ 10⁵) for t in [0, 1].
const ARG_MAX: f64 = 1e5;

/// Registers of angles per step of the loop (their chains overlap).
const U: usize = 4;

/// One piece of a [`Fused`] law, its period's output scaling folded in.
struct Piece {
    /// Of period II (α > α1)?
    second: bool,
    /// The end of the law's previous piece: the piece holds u > `after`, up
    /// to the next piece's `after` (None for a law's first piece).
    after: Option<f64>,
    x0: f64,
    /// off + sc·Σ c_k t^k as coefficients, lowest first (at least one).
    poly: Vec<f64>,
    /// sc·amp, and the sine's ω and φ.
    amp: f64,
    freq: f64,
    phase: f64,
}

/// A two-period law (or one law) prepared for one derivative order, for
/// [`FusedChunk`]: the same pieces, period split and scalings as the lane
/// evaluator's `Lanes`.
pub(super) struct Fused {
    pieces: Vec<Piece>,
    /// α ≤ split: period I.
    split: f64,
    /// u = max((α − c)·s, 0), per period.
    map: [(f64, f64); 2],
}

/// Does this processor run fused multiply-adds in hardware (so that the FMA
/// kernel is fast; `pulp`'s scalar fallback would call a software `fma`)?
fn has_fma() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        pulp::x86::V3::try_new().is_some()
    }
    #[cfg(target_arch = "aarch64")]
    {
        true
    }
    #[cfg(not(any(target_arch = "x86_64", target_arch = "aarch64")))]
    {
        false
    }
}

impl Fused {
    /// The law(s) at `order`: period I is laws[0] at u = (α − c1)·s1, value
    /// off1 + sc1·Z; period II (α > split) laws[1] likewise. None where the
    /// processor has no FMA or a piece's sine would leave [`sin_fma_simd`]'s
    /// range (the caller then uses the lane evaluator).
    pub(super) fn new(
        laws: [&Law; 2],
        order: usize,
        split: f64,
        map: [(f64, f64); 2],
        out: [(f64, f64); 2],
    ) -> Option<Fused> {
        Fused::build(laws, order, split, map, out).filter(|_| has_fma())
    }

    /// [`Fused::new`] whatever the processor (the tests run it on every
    /// instruction set, `pulp`'s scalar one included).
    pub(super) fn build(
        laws: [&Law; 2],
        order: usize,
        split: f64,
        map: [(f64, f64); 2],
        out: [(f64, f64); 2],
    ) -> Option<Fused> {
        let mut pieces = Vec::new();
        for (l, law) in laws.iter().enumerate() {
            let (off, sc) = out[l];
            for (k, f) in law.fast.iter().enumerate() {
                // t = u − x0 ≤ x1 − x0 ≤ 1 keeps |ωt + φ| ≤ ARG_MAX.
                if f.freq.abs() + f.phase[order].abs() > ARG_MAX || f.x1 - f.x0 > 1.0 {
                    return None;
                }
                let mut poly: Vec<f64> = f.poly[order].iter().map(|&c| sc * c).collect();
                if poly.is_empty() {
                    poly.push(0.0);
                }
                poly[0] = off + sc * f.poly[order].first().copied().unwrap_or(0.0);
                pieces.push(Piece {
                    second: l == 1,
                    after: (k > 0).then(|| law.fast[k - 1].x1),
                    x0: f.x0,
                    poly,
                    amp: sc * f.amp[order],
                    freq: f.freq,
                    phase: f.phase[order],
                });
            }
        }
        Some(Fused { pieces, split, map })
    }

    /// out[i] = the law at v[i] for a chunk, after checking in the same pass
    /// that every v lies in [0, `hi`]: false if one does not (the outputs are
    /// then not to be used).
    pub(super) fn eval(&self, v: &[f64], out: &mut [f64], hi: f64) -> bool {
        pulp::Arch::new().dispatch(FusedChunk {
            fused: self,
            v,
            out,
            hi,
        })
    }
}

/// [`Fused::eval`]'s loop, compiled once per instruction set.
pub(super) struct FusedChunk<'a> {
    pub(super) fused: &'a Fused,
    pub(super) v: &'a [f64],
    pub(super) out: &'a mut [f64],
    /// The values' upper bound (the lower is 0).
    pub(super) hi: f64,
}

impl pulp::WithSimd for FusedChunk<'_> {
    /// Every value in [0, hi]?
    type Output = bool;

    #[inline(always)]
    fn with_simd<S: Simd>(self, simd: S) -> bool {
        let FusedChunk { fused, v, out, hi } = self;
        let n = v.len().min(out.len());
        let (v, out) = (&v[..n], &mut out[..n]);
        let lanes = std::mem::size_of::<S::f64s>() / std::mem::size_of::<f64>();
        let step = U * lanes;
        let whole = n - n % step;
        // The range check: the smallest and largest value, and v·0 summed (NaN
        // for a NaN or an infinity).
        let zero = simd.splat_f64s(0.0);
        let (mut lo, mut top, mut probe) = (zero, zero, zero);
        for (vb, ob) in v[..whole]
            .chunks_exact(step)
            .zip(out[..whole].chunks_exact_mut(step))
        {
            let xs = S::as_simd_f64s(vb).0;
            let mut x = [zero; U];
            for i in 0..U {
                x[i] = xs[i];
                lo = simd.min_f64s(lo, x[i]);
                top = simd.max_f64s(top, x[i]);
                probe = simd.mul_add_f64s(x[i], zero, probe);
            }
            let y = step_values(simd, fused, &x);
            let os = S::as_mut_simd_f64s(ob).0;
            os[..U].copy_from_slice(&y);
        }
        let mut ok = true;
        if whole < n {
            // The last values, padded with zeros (inside every range); a
            // register holds at most 8 f64 (AVX-512).
            let mut pad = [0.0; 8 * U];
            let rest = n - whole;
            pad[..rest].copy_from_slice(&v[whole..]);
            ok = v[whole..]
                .iter()
                .fold(true, |ok, &x| ok & (x >= 0.0) & (x <= hi));
            let xs = S::as_simd_f64s(&pad[..step]).0;
            let mut x = [zero; U];
            x.copy_from_slice(&xs[..U]);
            let y = step_values(simd, fused, &x);
            let mut got = [0.0; 8 * U];
            S::as_mut_simd_f64s(&mut got[..step]).0[..U].copy_from_slice(&y);
            out[whole..].copy_from_slice(&got[..rest]);
        }
        if whole > 0 {
            ok &= simd.reduce_min_f64s(lo) >= 0.0
                && simd.reduce_max_f64s(top) <= hi
                && simd.reduce_sum_f64s(probe) == 0.0;
        }
        ok
    }
}

/// The law at `U` registers of angles: the period and u, every piece's
/// polynomial (Horner, fused) and sine argument blended into the angle's own
/// piece, then one sine and P + A·sin.
#[inline(always)]
fn step_values<S: Simd>(simd: S, f: &Fused, x: &[S::f64s; U]) -> [S::f64s; U] {
    let zero = simd.splat_f64s(0.0);
    let split = simd.splat_f64s(f.split);
    let [(c1, s1), (c2, s2)] = f.map;
    let (c1, s1, c2, s2) = (
        simd.splat_f64s(c1),
        simd.splat_f64s(s1),
        simd.splat_f64s(c2),
        simd.splat_f64s(s2),
    );
    // Plain loops over the registers, no closures: a closure the compiler keeps
    // out of line would lose the caller's instruction set.
    let mut second = [simd.less_than_f64s(zero, zero); U];
    let mut u = [zero; U];
    for i in 0..U {
        second[i] = simd.greater_than_f64s(x[i], split);
        let c = simd.select_f64s(second[i], c2, c1);
        let s = simd.select_f64s(second[i], s2, s1);
        // max(·, 0) returns its second operand for a NaN or −0: u = +0 there.
        u[i] = simd.max_f64s(simd.mul_f64s(simd.sub_f64s(x[i], c), s), zero);
    }
    let (mut p, mut arg, mut amp) = ([zero; U], [zero; U], [zero; U]);
    for (k, piece) in f.pieces.iter().enumerate() {
        let x0 = simd.splat_f64s(piece.x0);
        let (w, phase, a) = (
            simd.splat_f64s(piece.freq),
            simd.splat_f64s(piece.phase),
            simd.splat_f64s(piece.amp),
        );
        let top = piece.poly.len() - 1;
        let after = piece.after.map(|b| simd.splat_f64s(b));
        for i in 0..U {
            let t = if piece.x0 == 0.0 {
                u[i]
            } else {
                simd.sub_f64s(u[i], x0)
            };
            let mut q = simd.splat_f64s(piece.poly[top]);
            for &c in piece.poly[..top].iter().rev() {
                q = simd.mul_add_f64s(q, t, simd.splat_f64s(c));
            }
            let g = simd.mul_add_f64s(w, t, phase);
            if k == 0 {
                // Law 1's first piece: everything starts here.
                (p[i], arg[i], amp[i]) = (q, g, a);
                continue;
            }
            // Pieces come in order (law 1's, then law 2's, each by x), so a
            // later piece that holds the value overrides an earlier one.
            let law = if piece.second {
                second[i]
            } else {
                simd.less_than_or_equal_f64s(x[i], split)
            };
            let mine = match after {
                Some(b) => simd.and_m64s(law, simd.greater_than_f64s(u[i], b)),
                None => law,
            };
            p[i] = simd.select_f64s(mine, q, p[i]);
            arg[i] = simd.select_f64s(mine, g, arg[i]);
            amp[i] = simd.select_f64s(mine, a, amp[i]);
        }
    }
    let mut y = [zero; U];
    for i in 0..U {
        y[i] = simd.mul_add_f64s(amp[i], sin_fma_simd(simd, arg[i]), p[i]);
    }
    y
}
