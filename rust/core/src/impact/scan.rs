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
/// dropped δ²c''/2 is below 2⁻⁵⁴ of c (half an ulp); c1 = dc/dh from c0 by
/// the equation of motion itself ([`derivative`]: a few operations where a
/// central difference took two more steps' closed forms), whose rounding
/// (a few ε of the terms) enters multiplied by δ.
pub(super) struct Drift {
    pub(super) hbar: f64,
    pub(super) tol: f64,
    pub(super) c0: [f64; 8],
    pub(super) c1: [f64; 8],
}

impl Drift {
    /// None if h̄ is no valid step, the bound `tol` is below 2⁻⁵⁰⁰ or a
    /// coefficient is not finite.
    pub(super) fn new(mode: &Mode, hbar: f64, inv_m: f64) -> Option<Drift> {
        if !(step_ok(hbar) && hbar > 0.0) {
            return None;
        }
        let scale = hbar.min(1.0 / mode.rate);
        // tol ≥ 2⁻⁵⁰⁰ (so rate ≤ 2⁴⁷³): a |d| whose square underflows in the
        // lane pass's Σ d² (below 2⁻⁵³⁷) is within tol, and m·|d|·rate ≤ 2⁻³³
        // meets the first-order shift's 2⁻²⁶, so √(Σ d²) still decides both.
        if scale < 2f64.powi(-473) {
            return None;
        }
        let s0 = Step::new(mode, hbar, inv_m);
        if !s0.is_finite() {
            return None;
        }
        let c1 = derivative(&s0, mode, hbar, inv_m);
        c1.iter().all(|c: &f64| c.is_finite()).then(|| Drift {
            hbar,
            tol: scale * 2f64.powi(-27),
            c0: [
                s0.p00, s0.p01, s0.p10, s0.p11, s0.g0q, s0.g0v, s0.g1q, s0.g1v,
            ],
            c1,
        })
    }
}

/// dc/dh of the step coefficients `s` at h, exactly from ẋ = A·x + b·u(τ),
/// A = [[0, 1], [−ω², −2σ]], b = (0, 1/m), u linear from f0 to f1 over the
/// step: P = e^{Ah} gives P′ = A·P; with J0 = ∫₀ʰ e^{A(h−τ)}b dτ and
/// J1 = ∫₀ʰ e^{A(h−τ)}b·τ dτ, g1 = J1/h and g0 = J0 − g1, so (Leibniz)
/// g1′ = b + A·g1 − g1/h and g0′ = A·g0 + g1/h. In [`Step`]'s field order.
fn derivative(s: &Step, mode: &Mode, h: f64, inv_m: f64) -> [f64; 8] {
    let (w2, s2) = (mode.w2, 2.0 * mode.sigma);
    // A·(x, y) = (y, −ω²x − 2σy).
    let a = |x: f64, y: f64| (y, (-w2).mul_add(x, -s2 * y));
    let (p00, p10) = a(s.p00, s.p10);
    let (p01, p11) = a(s.p01, s.p11);
    let (a0q, a0v) = a(s.g0q, s.g0v);
    let (a1q, a1v) = a(s.g1q, s.g1v);
    let (r1q, r1v) = (s.g1q / h, s.g1v / h);
    [
        p00,
        p01,
        p10,
        p11,
        a0q + r1q,
        a0v + r1v,
        a1q - r1q,
        inv_m + a1v - r1v,
    ]
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
/// surely stayed within the drift's bound, and a bound on the largest
/// |d| = |h_k − h̄| it met: √(Σ d²) over a lane's steps (one FMA a step where
/// the largest |d| took two operations), at most √m times too large, so `ok`
/// false is not yet a step out of bounds (see [`largest_drift`]). (A NaN or
/// infinite time makes the bound NaN and leaves its lane's state non-finite,
/// which the caller checks.)
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
        // Σ d² so far, one FMA a step (a NaN step makes the state NaN, which
        // the caller sees).
        let mut dd = [0.0f64; SCAN];
        // Steps go in whole tiles of 8 × 8 (steps × lanes), stored transposed
        // into each lane's row as one vector; the rest one sample at a time.
        let tiles = m / TILE;
        let (mut bq, mut bv) = ([[0.0; SCAN]; TILE], [[0.0; SCAN]; TILE]);
        for tile in 0..tiles {
            for (s, (bqs, bvs)) in bq.iter_mut().zip(bv.iter_mut()).enumerate() {
                let j = tile * TILE + s + 1;
                let tn: [f64; SCAN] = std::array::from_fn(|l| ts[l][j]);
                let f1: [f64; SCAN] = std::array::from_fn(|l| fs[l][j]);
                lane_step(&c0, &c1, hbar, &tn, &tp, &f0, &f1, &mut q, &mut v, &mut dd);
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
            lane_step(&c0, &c1, hbar, &tn, &tp, &f0, &f1, &mut q, &mut v, &mut dd);
            for l in 0..SCAN {
                qs[l][j - 1] = q[l];
                if WITH_V {
                    vs[l][j - 1] = v[l];
                }
            }
            tp = tn;
            f0 = f1;
        }
        let dmax = dd.iter().fold(0.0, |a: f64, &b| a.max(b)).sqrt();
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
/// c0 + d·c1, forces f0 → f1; `dd` sums d².
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
    dd: &mut [f64; SCAN],
) {
    for l in 0..SCAN {
        let d = (tn[l] - tp[l]) - hbar;
        dd[l] = d.mul_add(d, dd[l]);
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

/// The unforced motion's transitions Φ((k + 1)·h̄) over a block's samples
/// k = 0 … m − 1, as Φ(i·r·h̄)·Φ((s + 1)·h̄), k = i·r + s, s < r: the r `fine`
/// ones and the ⌈m/r⌉ `coarse` ones each a chain of products from one
/// closed-form transition, so that each is off by about (r + m/r)·ε ≈ 2√m·ε
/// (r ≈ √m) where one chain of m products would be m·ε. r is a multiple of 8,
/// so that [`Correct`]'s runs of r samples are whole vectors; no table of m
/// entries is built (each run applies its coarse transition to the start
/// state first, then the fine ones).
pub(super) struct Free {
    pub(super) r: usize,
    pub(super) f00: Vec<f64>,
    pub(super) f01: Vec<f64>,
    pub(super) f11: Vec<f64>,
    /// −(s + 1) as a float: minus the sample's offset in steps is this less
    /// i·r, exactly.
    pub(super) nk: Vec<f64>,
    pub(super) coarse: Vec<Phi>,
}

impl Free {
    pub(super) fn new(mode: &Mode, hbar: f64, m: usize) -> Free {
        let r = ((((m as f64).sqrt() / 8.0).round() as usize) * 8).clamp(8, m.max(8));
        let nc = m.div_ceil(r);
        let w2 = mode.w2;
        let (step, big) = (mode.phi(hbar), mode.phi(r as f64 * hbar));
        let mut free = Free {
            r,
            f00: Vec::with_capacity(r),
            f01: Vec::with_capacity(r),
            f11: Vec::with_capacity(r),
            nk: (1..=r).map(|s| -(s as f64)).collect(),
            coarse: Vec::with_capacity(nc),
        };
        // The two chains side by side (independent products: twice the
        // throughput of one chain after the other).
        let (mut x, mut y) = (step, (1.0, 0.0, 1.0));
        for i in 0..r.max(nc) {
            if i < r {
                free.f00.push(x.0);
                free.f01.push(x.1);
                free.f11.push(x.2);
                x = compose(w2, step, x);
            }
            if i < nc {
                free.coarse.push(y);
                y = compose(w2, big, y);
            }
        }
        free
    }

    /// The free motion Φ((k + 1)·h̄ + dt)·(q0, v0) at sample k of a block, to
    /// first order in dt, in the operations (and so the roundings) of
    /// [`Correct`]'s vector loop: the stitching uses it for the block's last
    /// sample, so that the next block starts from what was written there.
    #[inline]
    pub(super) fn eval(&self, mode: &Mode, k: usize, dt: f64, (q0, v0): (f64, f64)) -> (f64, f64) {
        let (w2, s2) = (mode.w2, 2.0 * mode.sigma);
        let (i, s) = (k / self.r, k % self.r);
        let (y0, y1) = self.coarse_state(w2, i, q0, v0);
        let wy0 = -w2 * y0;
        let (f00, f01, f11) = (self.f00[s], self.f01[s], self.f11[s]);
        let qc = f00.mul_add(y0, f01 * y1);
        let vc = f01.mul_add(wy0, f11 * y1);
        let ac = (-w2).mul_add(qc, -s2 * vc);
        (dt.mul_add(vc, qc), dt.mul_add(ac, vc))
    }

    /// Φ(i·r·h̄)·(q0, v0).
    #[inline(always)]
    fn coarse_state(&self, w2: f64, i: usize, q0: f64, v0: f64) -> (f64, f64) {
        let (c00, c01, c11) = self.coarse[i];
        (c00.mul_add(q0, c01 * v0), c11.mul_add(v0, -w2 * c01 * q0))
    }
}

/// The scan's second pass: each block l ≥ 1 ran from rest in the first, so its
/// samples get its start state's unforced motion added, Φ(τ)·s_l with
/// τ = t[l·m + 1 + k] − t[l·m]. Φ is taken at (k + 1)·h̄ ([`Free`]) and
/// shifted to τ to first order: x((k + 1)·h̄ + Δ) = x((k + 1)·h̄) + Δ·x′, Δ =
/// τ − (k + 1)·h̄ (formed with one rounding, |Δ|·rate ≤ 2⁻²⁶ checked by the
/// caller, so the dropped Δ²x″/2 is below 2⁻⁵³ of the state). In runs of r
/// samples that share one coarse transition: per sample (q only) two
/// multiply-adds for Φ·s into the sample, two for x′, three for Δ and the
/// shift, in contiguous vectors (no dependency chain, no table of m entries).
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
    fn with_simd<S: pulp::Simd>(self, simd: S) {
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
        let (w2, s2, r) = (mode.w2, 2.0 * mode.sigma, free.r);
        // Last block first, each from its end: the lane pass has just left
        // the blocks' ends in the cache.
        for l in (1..SCAN).rev() {
            let tl = t[l * m];
            let ts = &t[l * m + 1..][..m];
            let qs = &mut q_out[l * m + 1..][..m];
            let vs: &mut [f64] = if WITH_V {
                &mut v_out[l * m + 1..][..m]
            } else {
                &mut []
            };
            for i in (0..m.div_ceil(r)).rev() {
                let (lo, hi) = (i * r, ((i + 1) * r).min(m));
                let (y0, y1) = free.coarse_state(w2, i, sq[l], sv[l]);
                let c = Shift {
                    y0,
                    y1,
                    wy0: -w2 * y0,
                    w2,
                    s2,
                    hbar,
                    tl,
                    o: lo as f64,
                };
                let vsi: &mut [f64] = if WITH_V { &mut vs[lo..hi] } else { &mut [] };
                c.run::<S, WITH_V>(simd, free, &ts[lo..hi], &mut qs[lo..hi], vsi);
            }
        }
    }
}

/// One run's constants in [`Correct`]: the coarse transition's state
/// (y0, y1), −ω²·y0, ω², 2σ, h̄, the block's start time and the run's first
/// offset i·r.
struct Shift {
    y0: f64,
    y1: f64,
    wy0: f64,
    w2: f64,
    s2: f64,
    hbar: f64,
    tl: f64,
    o: f64,
}

impl Shift {
    /// The samples `q` (and `v` if WITH_V) of one run, at times `t`, plus the
    /// free motion: whole vectors, then the rest one by one (the same
    /// operations, each a fused multiply-add or one rounding).
    #[inline(always)]
    fn run<S: pulp::Simd, const WITH_V: bool>(
        &self,
        simd: S,
        free: &Free,
        t: &[f64],
        q: &mut [f64],
        v: &mut [f64],
    ) {
        let len = t.len();
        let (f00, f01, f11, nk) = (
            &free.f00[..len],
            &free.f01[..len],
            &free.f11[..len],
            &free.nk[..len],
        );
        let (t_v, t_r) = S::as_simd_f64s(t);
        let (a_v, a_r) = S::as_simd_f64s(f00);
        let (b_v, b_r) = S::as_simd_f64s(f01);
        let (d_v, d_r) = S::as_simd_f64s(f11);
        let (k_v, k_r) = S::as_simd_f64s(nk);
        let (q_v, q_r) = S::as_mut_simd_f64s(q);
        let (v_v, v_r) = S::as_mut_simd_f64s(v);
        let sp = |x: f64| simd.splat_f64s(x);
        let (y0, y1, wy0, o, hbar, tl) = (
            sp(self.y0),
            sp(self.y1),
            sp(self.wy0),
            sp(self.o),
            sp(self.hbar),
            sp(self.tl),
        );
        let (nw2, ns2) = (sp(-self.w2), sp(-self.s2));
        let fma = |a, b, c| simd.mul_add_e_f64s(a, b, c);
        for j in (0..t_v.len()).rev() {
            let dt = fma(simd.sub_f64s(k_v[j], o), hbar, simd.sub_f64s(t_v[j], tl));
            let qc = fma(a_v[j], y0, simd.mul_f64s(b_v[j], y1));
            let vc = fma(b_v[j], wy0, simd.mul_f64s(d_v[j], y1));
            q_v[j] = simd.add_f64s(q_v[j], fma(dt, vc, qc));
            if WITH_V {
                let ac = fma(nw2, qc, simd.mul_f64s(ns2, vc));
                v_v[j] = simd.add_f64s(v_v[j], fma(dt, ac, vc));
            }
        }
        for j in 0..t_r.len() {
            let dt = (k_r[j] - self.o).mul_add(self.hbar, t_r[j] - self.tl);
            let qc = a_r[j].mul_add(self.y0, b_r[j] * self.y1);
            let vc = b_r[j].mul_add(self.wy0, d_r[j] * self.y1);
            q_r[j] += dt.mul_add(vc, qc);
            if WITH_V {
                let ac = (-self.w2).mul_add(qc, -self.s2 * vc);
                v_r[j] += dt.mul_add(ac, vc);
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

/// The largest |(t[k] − t[k−1]) − h̄| over the grid (a NaN step is not
/// counted: it leaves a non-finite state, which the caller checks).
fn largest_drift(t: &[f64], hbar: f64) -> f64 {
    t.windows(2).fold(0.0, |a, w| {
        let d = ((w[1] - w[0]) - hbar).abs();
        if d > a {
            d
        } else {
            a
        }
    })
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
    // m < 2³¹: a bound on the block (the free-motion pass counts its offsets
    // in floats, exact to 2⁵³).
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
    // |Δ| ≤ m·max|h_k − h̄| within a block: the first-order shift holds.
    let shift_ok = |dmax: f64| m as f64 * dmax * mode.rate <= 2f64.powi(-26);
    let mut dmax = end.dmax;
    if !(end.ok && shift_ok(dmax)) {
        // The bound decides nothing: the steps' own largest |d|.
        dmax = largest_drift(&t[..=SCAN * m], drift.hbar);
        if dmax > drift.tol {
            return false;
        }
    }
    let free = shift_ok(dmax).then(|| Free::new(mode, drift.hbar, m));
    let (mut sq, mut sv) = ([0.0; SCAN], [0.0; SCAN]);
    let (mut q, mut v) = (q0, v0);
    for l in 0..SCAN {
        (sq[l], sv[l]) = (q, v);
        // Block 0 started from (q0, v0) already.
        if l == 0 {
            (q, v) = (end.q[0], end.v[0]);
            continue;
        }
        let tau = t[(l + 1) * m] - t[l * m];
        let (hq, hv) = match &free {
            // As the free-motion pass adds it to the block's last sample.
            Some(free) => {
                let dt = (-(m as f64)).mul_add(drift.hbar, tau);
                free.eval(mode, m - 1, dt, (q, v))
            }
            None => mode.eval(q, v, tau),
        };
        (q, v) = (hq + end.q[l], hv + end.v[l]);
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
    if let Some(free) = &free {
        arch.dispatch(Correct::<WITH_V> {
            t,
            m,
            free,
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
