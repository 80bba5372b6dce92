//! The single case's chunked scan: the recurrence of [`super::oscillator`] on a
//! uniform grid as eight blocks in vector lanes, stitched by the unforced
//! motion's transition in closed form (see [`scan`]).

use super::error::step_ok;
use super::oscillator::{Mode, Step};
use crate::tile::{transpose, TILE};

/// Blocks of the chunked scan, one vector lane each (one AVX-512 register,
/// two AVX2 ones).
pub(super) const SCAN: usize = 8;

/// Fewest steps per block for the scan: below, its two passes and the
/// coefficients' set-up cost more than the sequential loop saves.
pub(super) const SCAN_MIN_BLOCK: usize = 128;

/// The step coefficients near a reference step h̄ as c(h̄ + δ) = c0 + δ·c1, in
/// [`Step`]'s field order. δ is bounded by `tol` = 2⁻²⁷·min(h̄, 1/rate), so the
/// dropped δ²c''/2 is below 2⁻⁵⁴ of c (half an ulp); c1 is the central
/// difference over ±η, η = 2⁻¹⁷·min(h̄, 1/rate), whose own error (η² c‴/6,
/// and rounding ε·c/η) enters multiplied by δ: below 1e-18 of c.
pub(super) struct Drift {
    pub(super) hbar: f64,
    pub(super) tol: f64,
    pub(super) c0: [f64; 8],
    pub(super) c1: [f64; 8],
}

impl Drift {
    /// None if h̄ is no valid step or a coefficient is not finite.
    pub(super) fn new(mode: &Mode, hbar: f64, inv_m: f64) -> Option<Drift> {
        if !(step_ok(hbar) && hbar > 0.0) {
            return None;
        }
        let scale = hbar.min(1.0 / mode.rate);
        let eta = scale * 2f64.powi(-17);
        let (hp, hm) = (hbar + eta, hbar - eta);
        let all = |s: Step| [s.p00, s.p01, s.p10, s.p11, s.g0q, s.g0v, s.g1q, s.g1v];
        let s0 = Step::new(mode, hbar, inv_m);
        let (sp, sm) = (Step::new(mode, hp, inv_m), Step::new(mode, hm, inv_m));
        if !(s0.is_finite() && sp.is_finite() && sm.is_finite()) {
            return None;
        }
        let (a, b) = (all(sp), all(sm));
        let c1 = std::array::from_fn(|i| (a[i] - b[i]) / (hp - hm));
        c1.iter().all(|c: &f64| c.is_finite()).then(|| Drift {
            hbar,
            tol: scale * 2f64.powi(-27),
            c0: all(s0),
            c1,
        })
    }
}

/// One pass of the chunked scan over blocks of `m` steps: lane l runs steps
/// l·m + 1 ..= (l + 1)·m from its start state, with the coefficients of
/// [`Drift`], and writes q (and v if WITH_V) to the outputs' samples
/// l·m + 1 ..= (l + 1)·m.
pub(super) struct ScanPass<'a, const WITH_V: bool> {
    pub(super) t: &'a [f64],
    pub(super) force: &'a [f64],
    pub(super) m: usize,
    pub(super) drift: &'a Drift,
    pub(super) q0: [f64; SCAN],
    pub(super) v0: [f64; SCAN],
    pub(super) q_out: &'a mut [f64],
    pub(super) v_out: &'a mut [f64],
}

/// What a [`ScanPass`] leaves: each lane's final state, whether every step
/// stayed within the drift's bound, and the largest |h_k − h̄| it met. (A NaN
/// or infinite time is not counted there: it leaves its lane's state
/// non-finite, which the caller checks.)
pub(super) struct PassEnd {
    pub(super) q: [f64; SCAN],
    pub(super) v: [f64; SCAN],
    pub(super) ok: bool,
    pub(super) dmax: f64,
}

impl<const WITH_V: bool> pulp::WithSimd for ScanPass<'_, WITH_V> {
    type Output = PassEnd;

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> Self::Output {
        let ScanPass {
            t,
            force,
            m,
            drift,
            q0,
            v0,
            q_out,
            v_out,
        } = self;
        let ts: [&[f64]; SCAN] = std::array::from_fn(|l| &t[l * m..][..m + 1]);
        let fs: [&[f64]; SCAN] = std::array::from_fn(|l| &force[l * m..][..m + 1]);
        // Output rows of exactly m samples each (empty when not stored), as
        // arrays so that the lane stores need no bounds checks.
        let mut qs = scan_rows(q_out, m, true);
        let mut vs = scan_rows(v_out, m, WITH_V);
        let (c0, c1, hbar) = (drift.c0, drift.c1, drift.hbar);
        let (mut q, mut v) = (q0, v0);
        let mut tp: [f64; SCAN] = std::array::from_fn(|l| ts[l][0]);
        let mut f0: [f64; SCAN] = std::array::from_fn(|l| fs[l][0]);
        // Largest |d| so far, in one max a step (a NaN step makes the state
        // NaN, which the caller sees).
        let mut dmax = [0.0f64; SCAN];
        // Steps go in whole tiles of 8 × 8 (steps × lanes), stored transposed
        // into each lane's row as one vector; the rest one sample at a time.
        let tiles = m / TILE;
        let (mut bq, mut bv) = ([[0.0; SCAN]; TILE], [[0.0; SCAN]; TILE]);
        for tile in 0..tiles {
            for (s, (bqs, bvs)) in bq.iter_mut().zip(bv.iter_mut()).enumerate() {
                let j = tile * TILE + s + 1;
                let tn: [f64; SCAN] = std::array::from_fn(|l| ts[l][j]);
                let f1: [f64; SCAN] = std::array::from_fn(|l| fs[l][j]);
                lane_step(
                    &c0, &c1, hbar, &tn, &tp, &f0, &f1, &mut q, &mut v, &mut dmax,
                );
                *bqs = q;
                *bvs = v;
                tp = tn;
                f0 = f1;
            }
            let at = tile * TILE;
            let tq = transpose(_simd, &bq);
            for (row, x) in qs.iter_mut().zip(&tq) {
                row[at..at + TILE].copy_from_slice(x);
            }
            if WITH_V {
                let tv = transpose(_simd, &bv);
                for (row, x) in vs.iter_mut().zip(&tv) {
                    row[at..at + TILE].copy_from_slice(x);
                }
            }
        }
        for j in tiles * TILE + 1..=m {
            let tn: [f64; SCAN] = std::array::from_fn(|l| ts[l][j]);
            let f1: [f64; SCAN] = std::array::from_fn(|l| fs[l][j]);
            lane_step(
                &c0, &c1, hbar, &tn, &tp, &f0, &f1, &mut q, &mut v, &mut dmax,
            );
            for l in 0..SCAN {
                qs[l][j - 1] = q[l];
                if WITH_V {
                    vs[l][j - 1] = v[l];
                }
            }
            tp = tn;
            f0 = f1;
        }
        let dmax = dmax.iter().fold(0.0, |a, &b| if b > a { b } else { a });
        PassEnd {
            q,
            v,
            ok: dmax <= drift.tol,
            dmax,
        }
    }
}

// Steps per stored tile of the lane pass = lanes (square: the tile is transposed).
const _: () = assert!(TILE == SCAN);

/// One step of every lane: the step h = tn − tp = h̄ + d, coefficients
/// c0 + d·c1, forces f0 → f1; `dmax` keeps the largest |d|.
#[inline(always)]
#[allow(clippy::too_many_arguments)] // the step's coefficients, grid, forces, state
fn lane_step(
    c0: &[f64; 8],
    c1: &[f64; 8],
    hbar: f64,
    tn: &[f64; SCAN],
    tp: &[f64; SCAN],
    f0: &[f64; SCAN],
    f1: &[f64; SCAN],
    q: &mut [f64; SCAN],
    v: &mut [f64; SCAN],
    dmax: &mut [f64; SCAN],
) {
    for l in 0..SCAN {
        let d = (tn[l] - tp[l]) - hbar;
        let ad = d.abs();
        dmax[l] = if ad > dmax[l] { ad } else { dmax[l] };
        let c: [f64; 8] = std::array::from_fn(|i| d.mul_add(c1[i], c0[i]));
        let fq = c[4].mul_add(f0[l], c[6] * f1[l]);
        let fv = c[5].mul_add(f0[l], c[7] * f1[l]);
        let qn = c[0].mul_add(q[l], c[1].mul_add(v[l], fq));
        v[l] = c[2].mul_add(q[l], c[3].mul_add(v[l], fv));
        q[l] = qn;
    }
}

/// (Φ00, Φ01, Φ11) of the unforced motion's transitions (Φ10 = −ω²Φ01).
type Phi = (f64, f64, f64);

/// The product of two transitions of one mode (they commute).
#[inline(always)]
fn compose(w2: f64, a: Phi, b: Phi) -> Phi {
    let c = w2 * a.1 * b.1;
    (a.0 * b.0 - c, a.0 * b.1 + a.1 * b.2, a.2 * b.2 - c)
}

/// The unforced motion's transitions Φ(j·h̄) over the offsets j = 0 … m of a
/// block, built as Φ(i·r·h̄)·Φ(s·h̄), j = i·r + s, s < r: the r `fine` ones
/// Φ(s·h̄) and the m/r + 1 `coarse` ones Φ(i·r·h̄) each a chain of products from
/// one closed-form transition, so that each is off by about (r + m/r)·ε ≈
/// 2√m·ε (r ≈ √m) where one chain of m products would be m·ε. The table
/// itself (three arrays of m + 1) is filled in [`Correct`], in vectors.
pub(super) struct Free {
    pub(super) r: usize,
    pub(super) f00: Vec<f64>,
    pub(super) f01: Vec<f64>,
    pub(super) f11: Vec<f64>,
    pub(super) coarse: Vec<Phi>,
}

impl Free {
    pub(super) fn new(mode: &Mode, hbar: f64, m: usize) -> Free {
        let r = ((m as f64).sqrt() as usize).max(1);
        let w2 = mode.w2;
        let chain = |step: Phi, len: usize| {
            let mut all = Vec::with_capacity(len);
            let mut x = (1.0, 0.0, 1.0);
            for _ in 0..len {
                all.push(x);
                x = compose(w2, step, x);
            }
            all
        };
        let fine = chain(mode.phi(hbar), r);
        Free {
            r,
            f00: fine.iter().map(|x| x.0).collect(),
            f01: fine.iter().map(|x| x.1).collect(),
            f11: fine.iter().map(|x| x.2).collect(),
            coarse: chain(mode.phi(r as f64 * hbar), m / r + 1),
        }
    }

    /// The table (Φ00, Φ01, Φ11)(j·h̄), j = 0 ..= m, in whole runs of the fine
    /// ones (inlined into [`Correct`]'s vector code).
    #[inline(always)]
    pub(super) fn table(&self, w2: f64, m: usize) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let (mut a, mut b, mut d) = (vec![0.0; m + 1], vec![0.0; m + 1], vec![0.0; m + 1]);
        let r = self.r;
        let (g00, g01, g11) = (&self.f00[..r], &self.f01[..r], &self.f11[..r]);
        for (i, &(c00, c01, c11)) in self.coarse.iter().enumerate() {
            let (lo, hi) = (i * r, ((i + 1) * r).min(m + 1));
            let w01 = w2 * c01;
            let rows = a[lo..hi]
                .iter_mut()
                .zip(&mut b[lo..hi])
                .zip(&mut d[lo..hi])
                .zip(g00.iter().zip(g01).zip(g11));
            for (((x00, x01), x11), ((&f00, &f01), &f11)) in rows {
                *x00 = c00 * f00 - w01 * f01;
                *x01 = c00 * f01 + c01 * f11;
                *x11 = c11 * f11 - w01 * f01;
            }
        }
        (a, b, d)
    }
}

/// The scan's second pass: each block l ≥ 1 ran from rest in the first, so its
/// samples get its start state's unforced motion added, Φ(τ)·s_l with
/// τ = t[l·m + j] − t[l·m]. Φ is tabulated at j·h̄ ([`Free`]) and shifted to τ
/// to first order: x(j·h̄ + Δ) = x(j·h̄) + Δ·x′(j·h̄), Δ = τ − j·h̄ (formed with
/// one rounding, |Δ|·rate ≤ 2⁻²⁶ checked by the caller, so the dropped
/// Δ²x″/2 is below 2⁻⁵³ of the state). Two multiply-adds a sample for q, two
/// for v, two for the shift, in contiguous vectors (no dependency chain).
pub(super) struct Correct<'a, const WITH_V: bool> {
    pub(super) t: &'a [f64],
    pub(super) m: usize,
    pub(super) free: &'a Free,
    pub(super) mode: &'a Mode,
    pub(super) hbar: f64,
    pub(super) sq: [f64; SCAN],
    pub(super) sv: [f64; SCAN],
    pub(super) q_out: &'a mut [f64],
    pub(super) v_out: &'a mut [f64],
}

impl<const WITH_V: bool> pulp::WithSimd for Correct<'_, WITH_V> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        let Correct {
            t,
            m,
            free,
            mode,
            hbar,
            sq,
            sv,
            q_out,
            v_out,
        } = self;
        let (w2, s2) = (mode.w2, 2.0 * mode.sigma);
        let (a, b, d) = free.table(w2, m);
        let (a, b, d) = (&a[1..], &b[1..], &d[1..]);
        for l in 1..SCAN {
            let tl = t[l * m];
            let ts = &t[l * m + 1..][..m];
            let qs = &mut q_out[l * m + 1..][..m];
            let (q0, v0) = (sq[l], sv[l]);
            let wq0 = -w2 * q0;
            if WITH_V {
                let vs = &mut v_out[l * m + 1..][..m];
                for k in 0..m {
                    let dt = (-((k + 1) as u32 as f64)).mul_add(hbar, ts[k] - tl);
                    let qc = a[k].mul_add(q0, b[k] * v0);
                    let vc = b[k].mul_add(wq0, d[k] * v0);
                    let ac = (-w2).mul_add(qc, -s2 * vc);
                    qs[k] += dt.mul_add(vc, qc);
                    vs[k] += dt.mul_add(ac, vc);
                }
            } else {
                for k in 0..m {
                    let dt = (-((k + 1) as u32 as f64)).mul_add(hbar, ts[k] - tl);
                    let qc = a[k].mul_add(q0, b[k] * v0);
                    let vc = b[k].mul_add(wq0, d[k] * v0);
                    qs[k] += dt.mul_add(vc, qc);
                }
            }
        }
    }
}

/// Does the processor fuse multiply-adds (so that the scan's `mul_add` is one
/// instruction, not a library call)? Without, the sequential loop is faster.
fn fused_multiply_add() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("fma") && std::arch::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        cfg!(target_arch = "aarch64")
    }
}

/// Output rows of exactly m samples each from sample 1 on (empty unless
/// `keep`), as an array so that the lane stores need no bounds checks.
fn scan_rows(out: &mut [f64], m: usize, keep: bool) -> [&mut [f64]; SCAN] {
    let mut it = out.get_mut(1..).unwrap_or_default().chunks_exact_mut(m);
    std::array::from_fn(|_| match it.next() {
        Some(r) if keep => r,
        _ => &mut [],
    })
}

/// The single case's recurrence as a chunked scan, true if it ran (false:
/// nothing to be relied on was written, run the sequential loop). The N − 1
/// steps split into [`SCAN`] blocks of m steps (the r < SCAN left over run
/// last, sequentially); the recurrence x_{k+1} = A_k x_k + b_k is linear, so
///
/// 1. each block runs from rest (the first from (q0, v0)) in its own vector
///    lane, writing its samples and keeping its end state e_l;
/// 2. the blocks' start states are stitched in order: s_0 = (q0, v0),
///    s_{l+1} = Φ(t_end − t_start) s_l + e_l, Φ the unforced motion's
///    transition over the block in closed form (the product of the steps' A_k
///    up to rounding: the system is time-invariant);
/// 3. each later block's samples get the unforced motion from its start state
///    added ([`Correct`]: no recurrence, contiguous vectors).
///
/// The lane pass breaks the chain of two dependent FMAs per step that bounds
/// the sequential loop. Each sample is the sequential recurrence's from rest
/// plus an exact free motion, from a start state that differs from the
/// sequential one only by rounding, with coefficients that differ from their
/// exact c(h_k) only by rounding (see [`Drift`] and [`Free`]), so the results
/// differ from the sequential loop's by rounding (tested: 1e-12 of the peak,
/// and against closed forms). Taken for N − 1 ≥ SCAN·[`SCAN_MIN_BLOCK`] steps
/// within 2⁻²⁷ of the first (a uniform grid up to its rounding), finite forces
/// and a finite result; anything else (repeated times, a ragged grid, a bad
/// value) goes the sequential way. A grid whose steps drift so far that a
/// block's time offsets could leave j·h̄ by more than 2⁻²⁶/rate (never a
/// rounded uniform grid) runs its blocks a second time from their start states
/// instead of step 3.
pub(super) fn scan<const WITH_V: bool>(
    t: &[f64],
    force: &[f64],
    mode: &Mode,
    inv_m: f64,
    (q0, v0): (f64, f64),
    q_out: &mut [f64],
    v_out: &mut [f64],
) -> bool {
    let n = t.len();
    let m = n.saturating_sub(1) / SCAN;
    // m < 2³¹: the second pass counts offsets in u32 (whole vectors).
    if !(SCAN_MIN_BLOCK..1 << 31).contains(&m) || force.len() != n || q_out.len() != n {
        return false;
    }
    if WITH_V && v_out.len() != n {
        return false;
    }
    if !fused_multiply_add() {
        return false;
    }
    let Some(drift) = Drift::new(mode, t[1] - t[0], inv_m) else {
        return false;
    };
    let arch = pulp::Arch::new();
    let mut first_q0 = [0.0; SCAN];
    let mut first_v0 = [0.0; SCAN];
    (first_q0[0], first_v0[0]) = (q0, v0);
    let end = arch.dispatch(ScanPass::<WITH_V> {
        t,
        force,
        m,
        drift: &drift,
        q0: first_q0,
        v0: first_v0,
        q_out,
        v_out,
    });
    if !end.ok {
        return false;
    }
    let (mut sq, mut sv) = ([0.0; SCAN], [0.0; SCAN]);
    let (mut q, mut v) = (q0, v0);
    for l in 0..SCAN {
        (sq[l], sv[l]) = (q, v);
        // Block 0 started from (q0, v0) already.
        (q, v) = if l == 0 {
            (end.q[0], end.v[0])
        } else {
            let (hq, hv) = mode.eval(q, v, t[(l + 1) * m] - t[l * m]);
            (hq + end.q[l], hv + end.v[l])
        };
    }
    // A non-finite force leaves a non-finite state in its block (the
    // stitching carries it on); the tail's are checked below.
    let finite = |x: &f64| x.is_finite();
    if !(end.q.iter().chain(&end.v).chain(&sq).chain(&sv).all(finite)
        && q.is_finite()
        && v.is_finite())
    {
        return false;
    }
    q_out[0] = q0;
    if WITH_V {
        v_out[0] = v0;
    }
    // |Δ| ≤ m·max|h_k − h̄| within a block.
    if m as f64 * end.dmax * mode.rate <= 2f64.powi(-26) {
        let free = Free::new(mode, drift.hbar, m);
        arch.dispatch(Correct::<WITH_V> {
            t,
            m,
            free: &free,
            mode,
            hbar: drift.hbar,
            sq,
            sv,
            q_out,
            v_out,
        });
    } else {
        arch.dispatch(ScanPass::<WITH_V> {
            t,
            force,
            m,
            drift: &drift,
            q0: sq,
            v0: sv,
            q_out,
            v_out,
        });
    }
    // The steps left over, sequentially from the last block's end.
    for k in SCAN * m + 1..n {
        let d = (t[k] - t[k - 1]) - drift.hbar;
        let within = d.abs() <= drift.tol;
        if !within {
            return false;
        }
        let c: [f64; 8] = std::array::from_fn(|i| d.mul_add(drift.c1[i], drift.c0[i]));
        let st = Step {
            p00: c[0],
            p01: c[1],
            p10: c[2],
            p11: c[3],
            g0q: c[4],
            g0v: c[5],
            g1q: c[6],
            g1v: c[7],
        };
        (q, v) = st.apply(q, v, force[k - 1], force[k]);
        q_out[k] = q;
        if WITH_V {
            v_out[k] = v;
        }
    }
    q.is_finite() && v.is_finite()
}

#[cfg(test)]
use super::oscillator::{run, Oscillator};

#[cfg(test)]
#[path = "scan_tests.rs"]
mod scan_tests;
