//! The other built-in laws' residual vibration in SIMD lanes (issue 37 row 1).
//!
//! **One sum per law.** Every built-in law's g = −z'' is, piece by piece on
//! [x0, x0 + L] with whole-eighth breakpoints, a polynomial plus one sine in
//! t = s − x0. Integrated exactly (by parts for the polynomial,
//! ∫₀ᴸ e^{λ(L−t)} p(t) dt = Σ_k [p⁽ᵏ⁾(0)·e^{λL} − p⁽ᵏ⁾(L)]·μ^{k+1}, μ = 1/λ; the
//! sine's one fraction of the parent module) and weighted by e^{λ(1 − x0 − L)},
//! the pieces sum to
//!
//! ```text
//! G = Σ_n Eⁿ·[Σ_j a_{n,j} μʲ] + Σ_Ω [λ·Σ_n q_{Ω,n} Eⁿ + Σ_n p_{Ω,n} Eⁿ] / (λ² + Ω²)
//! ```
//!
//! with E = e^{λh} (h the largest eighth dividing every breakpoint's distance
//! to 1: h = 1 for the one-piece laws, 1/8 for the modified sine and
//! trapezoid) and real constants a, p, q fixed by the law: computed once here,
//! so a τ costs one real exponential, one sine–cosine pair, the powers of E
//! and a few complex products — in real arithmetic, across [`LANES`] values of
//! τ at once, without branches (μ = (−ζ − i√(1 − ζ²))/τ since |λ| = τ;
//! λ² + Ω² = (λ − iΩ)(λ + iΩ) and its squared modulus
//! ((ζτ)² + (ω_d − Ω)²)((ζτ)² + (ω_d + Ω)²) without cancellation).
//!
//! **Where the lanes do not serve.** Three places lose digits in this sum,
//! and a lane there takes the parent module's exact scalar path instead
//! (overwritten after the block, so every τ's value depends on that τ alone):
//!
//! - small τ, where the pieces' terms (up to |a|/τʲ) cancel to G = O(τ):
//!   below [`Lanes::tau_min`], the smallest τ ≥ 1 where Σ|a|τ^{−j} ≤
//!   [`TERM_BOUND`] (1 for the sine laws; 1.95 for 3-4-5 and 4.03 for 4-5-6-7);
//! - near a resonance of a sine piece, |λ ∓ iΩ| < [`NEAR`], where its numerator
//!   and denominator both vanish (the absolute error there is
//!   ~ε·B/|λ − iΩ|);
//! - τ > [`TAU_MAX`] (the products of τ⁴ in the denominators stay far from
//!   overflow below it).
//!
//! Elsewhere the sum's absolute error is a few ulps of its largest term, as in
//! the parent module: within 1e-12 of R's envelope to τ = 10⁴ (tested against
//! the scalar pieces by proptest).

use super::cycloidal::exp_split;
use crate::geom::sin_cos_lanes;
use crate::motion::Law;

/// Values of τ per block.
pub const LANES: usize = 8;

/// Largest τ the lanes serve.
pub const TAU_MAX: f64 = 2e6;

/// Largest sum of the polynomial terms' bounds Σ|a|τ^{−j} the lanes accept.
pub const TERM_BOUND: f64 = 256.0;

/// Distance |λ ∓ iΩ| from a sine piece's resonance below which the scalar path
/// serves.
pub const NEAR: f64 = 0.25;

/// Powers of E: at most the eight eighths.
const POWERS: usize = 9;

/// The terms of one sine frequency Ω: Σ_n (q_n·λ + p_n)·Eⁿ / (λ² + Ω²).
#[derive(Debug, Clone, PartialEq)]
struct Sine {
    omega: f64,
    /// (n, p_n), p_n ≠ 0.
    p: Vec<(usize, f64)>,
    /// (n, q_n), q_n ≠ 0.
    q: Vec<(usize, f64)>,
}

/// One law's constants for the lanes (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Lanes {
    /// h = step/8.
    step: usize,
    /// poly[j − 1]: the (n, a_{n,j}) of μʲ, a ≠ 0.
    poly: Vec<Vec<(usize, f64)>>,
    sines: Vec<Sine>,
    /// Below this τ the scalar path serves.
    pub tau_min: f64,
}

fn sparse(dense: &[f64; POWERS], step: usize) -> Vec<(usize, f64)> {
    dense
        .iter()
        .enumerate()
        .filter(|&(_, &v)| v != 0.0)
        .map(|(n, &v)| (n / step, v))
        .collect()
}

fn gcd(a: usize, b: usize) -> usize {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

impl Lanes {
    /// The constants of a rise whose breakpoints are whole eighths; None
    /// otherwise, or above the closed forms' degree.
    pub fn of(law: &Law) -> Option<Lanes> {
        let eighth = |x: f64| {
            let k = x * 8.0;
            (k == k.round() && (0.0..=8.0).contains(&k)).then_some(k as usize)
        };
        let mut poly: Vec<[f64; POWERS]> = Vec::new();
        let mut sines: Vec<(f64, [f64; POWERS], [f64; POWERS])> = Vec::new();
        for s in &law.segments {
            let len = s.x1 - s.x0;
            if len <= 0.0 {
                continue;
            }
            if s.poly.len() > super::MAX_CLOSED_DEGREE + 2 {
                return None;
            }
            let (nb, na) = (eighth(1.0 - s.x0)?, eighth(1.0 - s.x0 - len)?);
            // g = −z'' = Σ g_i tⁱ.
            let g: Vec<f64> = (2..s.poly.len())
                .map(|k| -((k * (k - 1)) as f64) * s.poly[k])
                .collect();
            for k in 0..g.len() {
                // g⁽ᵏ⁾(0) = k!·g_k and g⁽ᵏ⁾(L) = Σ_{i≥k} g_i·i!/(i − k)!·L^{i−k}.
                let falling = |i: usize| ((i - k + 1)..=i).map(|m| m as f64).product::<f64>();
                let d0 = g[k] * falling(k);
                let dl = (k..g.len())
                    .rev()
                    .fold(0.0, |acc, i| acc * len + g[i] * falling(i));
                if poly.len() <= k {
                    poly.resize(k + 1, [0.0; POWERS]);
                }
                poly[k][nb] += d0;
                poly[k][na] -= dl;
            }
            if s.freq != 0.0 && s.amp != 0.0 {
                let (b, om) = (s.amp * s.freq * s.freq, s.freq);
                let (s0, c0) = s.phase.sin_cos();
                let (s1, c1) = (om * len + s.phase).sin_cos();
                let i = match sines.iter().position(|t| t.0 == om) {
                    Some(i) => i,
                    None => {
                        sines.push((om, [0.0; POWERS], [0.0; POWERS]));
                        sines.len() - 1
                    }
                };
                let (_, p, q) = &mut sines[i];
                q[nb] += b * s0;
                p[nb] += b * om * c0;
                q[na] -= b * s1;
                p[na] -= b * om * c1;
            }
        }
        // The coarsest step that reaches every power in use.
        let used = poly
            .iter()
            .chain(sines.iter().flat_map(|(_, p, q)| [p, q]))
            .flat_map(|d| {
                d.iter()
                    .enumerate()
                    .filter(|(_, &v)| v != 0.0)
                    .map(|(n, _)| n)
            });
        let step = used.fold(8, gcd);
        let bounds: Vec<f64> = poly
            .iter()
            .map(|d| d.iter().map(|v| v.abs()).sum())
            .collect();
        let term_sum = |tau: f64| {
            bounds
                .iter()
                .enumerate()
                .map(|(k, b)| b / tau.powi(k as i32 + 1))
                .sum::<f64>()
        };
        let mut tau_min = 1.0;
        while term_sum(tau_min) > TERM_BOUND {
            tau_min *= 1.0625;
            if tau_min > 1e3 {
                return None;
            }
        }
        Some(Lanes {
            step,
            poly: poly.iter().map(|d| sparse(d, step)).collect(),
            sines: sines
                .iter()
                .map(|(om, p, q)| Sine {
                    omega: *om,
                    p: sparse(p, step),
                    q: sparse(q, step),
                })
                .collect(),
            tau_min,
        })
    }

    /// R for [`LANES`] values of τ without branches (`c` = √(1 − ζ²)), and
    /// which lanes the scalar path must redo (module docs).
    #[inline(always)]
    pub fn block<const L: usize>(&self, tau: &[f64; L], zeta: f64, c: f64) -> ([f64; L], bool) {
        let h = self.step as f64 / 8.0;
        let n_pow = 8 / self.step;
        let mut a = [0.0; L];
        let mut w = [0.0; L];
        let mut inv = [0.0; L];
        let mut bad = false;
        for l in 0..L {
            a[l] = zeta * tau[l];
            w[l] = c * tau[l];
            inv[l] = 1.0 / tau[l];
            bad |= !(tau[l] >= self.tau_min && tau[l] <= TAU_MAX);
        }
        // E = e^{λh} and its powers.
        let mut er = [[0.0; L]; POWERS];
        let mut ei = [[0.0; L]; POWERS];
        let mut wh = [0.0; L];
        for l in 0..L {
            wh[l] = w[l] * h;
            er[0][l] = 1.0;
        }
        let (sn, cs) = sin_cos_lanes(&wh);
        for l in 0..L {
            let (two_k, em1) = exp_split((-a[l] * h).max(-700.0));
            let m = two_k * (em1 + 1.0);
            er[1][l] = m * cs[l];
            ei[1][l] = m * sn[l];
        }
        for n in 2..=n_pow {
            for l in 0..L {
                let (pr, pi) = (er[n - 1][l], ei[n - 1][l]);
                er[n][l] = pr * er[1][l] - pi * ei[1][l];
                ei[n][l] = pr * ei[1][l] + pi * er[1][l];
            }
        }
        let mut gr = [0.0; L];
        let mut gi = [0.0; L];
        // Σ_j μʲ·S_j by Horner in μ, S_j = Σ_n a_{n,j} Eⁿ.
        if !self.poly.is_empty() {
            let (mut ar, mut ai) = ([0.0; L], [0.0; L]);
            for terms in self.poly.iter().rev() {
                for l in 0..L {
                    let (mr, mi) = (-zeta * inv[l], -c * inv[l]);
                    let (r, i) = (ar[l] * mr - ai[l] * mi, ar[l] * mi + ai[l] * mr);
                    ar[l] = r;
                    ai[l] = i;
                }
                for &(n, v) in terms {
                    for l in 0..L {
                        ar[l] += v * er[n][l];
                        ai[l] += v * ei[n][l];
                    }
                }
            }
            for l in 0..L {
                let (mr, mi) = (-zeta * inv[l], -c * inv[l]);
                gr[l] = ar[l] * mr - ai[l] * mi;
                gi[l] = ar[l] * mi + ai[l] * mr;
            }
        }
        for s in &self.sines {
            let (mut pr, mut pi, mut qr, mut qi) = ([0.0; L], [0.0; L], [0.0; L], [0.0; L]);
            for &(n, v) in &s.p {
                for l in 0..L {
                    pr[l] += v * er[n][l];
                    pi[l] += v * ei[n][l];
                }
            }
            for &(n, v) in &s.q {
                for l in 0..L {
                    qr[l] += v * er[n][l];
                    qi[l] += v * ei[n][l];
                }
            }
            for l in 0..L {
                let (al, wl) = (a[l], w[l]);
                // N = λQ + P, λ = −a + iω.
                let nr = -al * qr[l] - wl * qi[l] + pr[l];
                let ni = -al * qi[l] + wl * qr[l] + pi[l];
                let (dm, dp) = (wl - s.omega, wl + s.omega);
                let a2 = al * al;
                let near = a2 + dm * dm;
                bad |= near < NEAR * NEAR;
                // D = (λ − iΩ)(λ + iΩ); N/D = N·conj(D)/|D|².
                let (dr, di) = (a2 - dm * dp, -2.0 * al * wl);
                let inv_den = 1.0 / (near * (a2 + dp * dp));
                gr[l] += (nr * dr + ni * di) * inv_den;
                gi[l] += (ni * dr - nr * di) * inv_den;
            }
        }
        let mut out = [0.0; L];
        for l in 0..L {
            out[l] = (gr[l] * gr[l] + gi[l] * gi[l]).sqrt() / w[l];
        }
        (out, bad)
    }
}

/// Fills `out` with R(τ_i, ζ) in blocks of [`LANES`], the lanes the scalar
/// path must redo by `scalar`.
pub(crate) struct Blocks<'a, F: Fn(f64) -> f64> {
    pub(crate) lanes: &'a Lanes,
    pub(crate) tau: &'a [f64],
    pub(crate) out: &'a mut [f64],
    pub(crate) zeta: f64,
    pub(crate) scalar: F,
}

impl<F: Fn(f64) -> f64> pulp::WithSimd for Blocks<'_, F> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        let c = ((1.0 - self.zeta) * (1.0 + self.zeta)).sqrt();
        let lanes = self.lanes;
        let mut tc = self.tau.chunks_exact(LANES);
        let mut oc = self.out.chunks_exact_mut(LANES);
        for (t, o) in (&mut tc).zip(&mut oc) {
            let t: &[f64; LANES] = t.try_into().expect("chunks of LANES");
            let (r, bad) = lanes.block(t, self.zeta, c);
            o.copy_from_slice(&r);
            if bad {
                for (oj, &tj) in o.iter_mut().zip(t) {
                    if lanes.needs_scalar(tj, self.zeta, c) {
                        *oj = (self.scalar)(tj);
                    }
                }
            }
        }
        // The tail padded to a block (so that a τ's value does not depend on
        // its place in the array).
        let (rest, ro) = (tc.remainder(), oc.into_remainder());
        if let Some(&last) = rest.last() {
            let mut t = [last; LANES];
            t[..rest.len()].copy_from_slice(rest);
            let (r, _) = lanes.block(&t, self.zeta, c);
            for ((oj, &tj), &rj) in ro.iter_mut().zip(rest).zip(&r) {
                *oj = if lanes.needs_scalar(tj, self.zeta, c) {
                    (self.scalar)(tj)
                } else {
                    rj
                };
            }
        }
    }
}

impl Lanes {
    /// Whether τ needs the scalar path (module docs; the test [`Lanes::block`]
    /// makes lane by lane).
    #[inline]
    pub fn needs_scalar(&self, tau: f64, zeta: f64, c: f64) -> bool {
        let (a, w) = (zeta * tau, c * tau);
        !(tau >= self.tau_min && tau <= TAU_MAX)
            || self.sines.iter().any(|s| {
                let dm = w - s.omega;
                a * a + dm * dm < NEAR * NEAR
            })
    }

    /// R for one τ by the lanes' formula, bit for bit a lane's value (the same
    /// operations; tested), wherever [`Lanes::needs_scalar`] is false.
    pub fn one(&self, tau: f64, zeta: f64) -> f64 {
        let c = ((1.0 - zeta) * (1.0 + zeta)).sqrt();
        self.block(&[tau], zeta, c).0[0]
    }
}

/// The harmonic rise in real arithmetic, as [`super::cycloidal`]: its
/// g = −(π²/2)·cos πs gives G = −(π²/2)·λ(1 + e^{λ})/(λ² + π²), and with
/// e = e^{−ζτ}, |λ| = τ, |1 + e^{λ}|² = (1 − e)² + 4e·cos²(ω_d/2),
///
/// ```text
/// R = (π²/2c)·√[((1 − e)² + 4e cos²(ω_d/2)) / ((ζτ)² + (ω_d − π)²) / ((ζτ)² + (ω_d + π)²)]
/// ```
///
/// (c = √(1 − ζ²)), every factor free of cancellation at any τ: 1 − e =
/// −expm1(−ζτ), cos(ω_d/2) = sin((π − ω_d)/2) and ω_d − π with a two-part π, so
/// that the undamped resonance τ = π (0/0) keeps its limit; as τ → 0 R → 1/c
/// with no sum to cancel (the pieces' sum needs the scalar path there).
pub mod harmonic {
    use std::f64::consts::PI;

    use crate::cam::residual::cycloidal::expm1_neg;
    use crate::geom::{sin, sin_lanes};

    /// π − PI (the second part of π).
    const PI_LO: f64 = 1.224_646_799_147_353_2e-16;
    const HALF_PI2: f64 = 0.5 * PI * PI;

    /// Values per block of [`ratio_lanes`].
    pub const LANES: usize = 8;

    /// The argument whose sine is cos(ω_d/2).
    #[inline(always)]
    fn half_gap(wd: f64) -> f64 {
        0.5 * ((PI - wd) + PI_LO)
    }

    #[inline(always)]
    fn combine(zt: f64, wd: f64, c: f64, m: f64, s: f64) -> f64 {
        let (one_minus_e, e) = (-m, 1.0 + m);
        let num = one_minus_e * one_minus_e + 4.0 * e * s * s;
        let dm = (wd - PI) - PI_LO;
        let dp = wd + PI;
        let z2 = zt * zt;
        HALF_PI2 * (num / (z2 + dm * dm) / (z2 + dp * dp)).sqrt() / c
    }

    /// R(τ, ζ) for one τ (`c` = √(1 − ζ²)).
    #[inline]
    pub fn ratio(tau: f64, zeta: f64, c: f64) -> f64 {
        let (zt, wd) = (zeta * tau, c * tau);
        combine(zt, wd, c, (-zt).exp_m1(), sin(half_gap(wd)))
    }

    /// R for [`LANES`] values of τ in (0, 2e6] at once, without branches.
    #[inline(always)]
    pub fn ratio_lanes(tau: &[f64; LANES], zeta: f64, c: f64) -> [f64; LANES] {
        let mut m = [0.0; LANES];
        let mut s = [0.0; LANES];
        let mut out = [0.0; LANES];
        for l in 0..LANES {
            m[l] = expm1_neg((-zeta * tau[l]).max(-700.0));
        }
        for l in 0..LANES {
            s[l] = sin_lanes(half_gap(c * tau[l]));
        }
        for l in 0..LANES {
            out[l] = combine(zeta * tau[l], c * tau[l], c, m[l], s[l]);
        }
        out
    }

    /// The harmonic rise's real form, for [`RealBlocks`](crate::cam::residual::RealBlocks).
    pub(crate) struct Form;

    impl crate::cam::residual::RealForm for Form {
        #[inline(always)]
        fn one(tau: f64, zeta: f64, c: f64) -> f64 {
            ratio(tau, zeta, c)
        }
        #[inline(always)]
        fn lanes(tau: &[f64; LANES], zeta: f64, c: f64) -> [f64; LANES] {
            ratio_lanes(tau, zeta, c)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cam::ClosedResidual;
    use proptest::prelude::*;

    /// The five laws the lanes serve (the cycloidal rise has its own real form).
    const LAWS: [&str; 5] = [
        "harmonic",
        "polynomial_345",
        "polynomial_4567",
        "modified_sine",
        "modified_trapezoid",
    ];

    /// R's envelope, as in the vibration tests: the small-τ value, then 100/τ².
    fn envelope(tau: f64, zeta: f64) -> f64 {
        (1.0 / ((1.0 - zeta) * (1.0 + zeta)).sqrt()).min(100.0 / (tau * tau))
    }

    fn closed(law: &str) -> ClosedResidual {
        ClosedResidual::new(law).unwrap()
    }

    #[test]
    fn every_other_law_has_lanes_with_a_modest_tau_min() {
        for law in LAWS {
            let l = Lanes::of(&Law::rise(law).unwrap()).unwrap();
            // The sines' terms are bounded; the polynomials' fall like 1/τʲ.
            assert!(l.tau_min >= 1.0 && l.tau_min < 6.0, "{law}: {}", l.tau_min);
            assert_eq!(l.step, if law.starts_with("modified") { 1 } else { 8 });
        }
        // A breakpoint off the eighths keeps the scalar path.
        let odd = Law::from_segments(vec![crate::motion::Segment {
            x0: 0.0,
            x1: 0.3,
            poly: vec![0.0, 0.0, 1.0],
            amp: 0.0,
            freq: 0.0,
            phase: 0.0,
        }]);
        assert!(Lanes::of(&odd).is_none());
    }

    /// The lanes against the scalar pieces (φ functions, the parent module's
    /// independent formulation) on a dense grid, resonances included.
    #[test]
    fn lanes_match_the_scalar_pieces_densely() {
        let mut taus: Vec<f64> = (0..20_000)
            .map(|i| 0.01 * (1e6f64).powf(i as f64 / 19_999.0))
            .collect();
        for om in [PI, 4.0 * PI / 3.0, 4.0 * PI] {
            for d in [-0.3, -0.25, -1e-3, 0.0, 1e-9, 0.2, 0.26] {
                taus.push(om + d);
            }
        }
        for law in LAWS {
            let c = closed(law);
            for zeta in [0.0, 1e-3, 0.05, 0.3, 0.9, 0.999] {
                let mut out = vec![0.0; taus.len()];
                c.fill(&taus, zeta, &mut out);
                let mut worst: f64 = 0.0;
                for (&t, &o) in taus.iter().zip(&out) {
                    let want = c.general(t, zeta);
                    worst = worst.max((o - want).abs() / envelope(t, zeta));
                }
                assert!(worst < 1e-12, "{law} zeta {zeta}: {worst:e}");
            }
        }
    }

    #[test]
    fn a_value_does_not_depend_on_its_place() {
        let taus: Vec<f64> = (0..203).map(|i| 0.3 + 0.37 * i as f64).collect();
        for law in LAWS {
            let c = closed(law);
            let mut all = vec![0.0; taus.len()];
            c.fill(&taus, 0.02, &mut all);
            for start in [1, 3, 7] {
                let mut part = vec![0.0; taus.len() - start];
                c.fill(&taus[start..], 0.02, &mut part);
                assert_eq!(&all[start..], &part[..], "{law} {start}");
            }
        }
    }

    /// The harmonic rise's real form against the scalar pieces (its own
    /// derivation against the φ functions' sum) and through its resonance.
    #[test]
    fn harmonic_real_form_equals_the_general_pieces() {
        let c = closed("harmonic");
        for zeta in [0.0, 0.05, 0.5, 0.99] {
            for i in 0..2000 {
                let tau = 1e-4 * (1e8f64).powf(i as f64 / 1999.0);
                let (a, b) = (c.ratio(tau, zeta), c.general(tau, zeta));
                assert!(
                    (a - b).abs() <= 1e-12 * envelope(tau, zeta),
                    "{tau} {zeta}: {a} {b}"
                );
            }
        }
        // Undamped at τ = π (ω_d = π − δ): (π²/2)·2|sin(δ/2)|/(|δ|·2π) → π/4.
        assert!((c.ratio(PI, 0.0) - PI / 4.0).abs() < 1e-14);
        for d in [1e-12, 1e-9, 1e-6] {
            for t in [PI * (1.0 + d), PI * (1.0 - d)] {
                assert!((c.ratio(t, 0.0) - PI / 4.0).abs() < 4.0 * d + 1e-14, "{t}");
            }
        }
    }

    proptest! {
        #[test]
        fn harmonic_lanes_match_one_by_one(t in proptest::collection::vec(1e-6f64..2e6, harmonic::LANES), zeta in 0.0f64..0.999) {
            let t: [f64; harmonic::LANES] = t.try_into().unwrap();
            let c = ((1.0 - zeta) * (1.0 + zeta)).sqrt();
            let r = harmonic::ratio_lanes(&t, zeta, c);
            for l in 0..harmonic::LANES {
                let one = harmonic::ratio(t[l], zeta, c);
                prop_assert!((r[l] - one).abs() <= 1e-14 * one, "{} {}", r[l], one);
            }
        }

        #[test]
        fn lanes_equal_one_by_one(law in 0usize..5, t in proptest::collection::vec(1.0f64..2e4, LANES), zeta in 0.0f64..0.999) {
            let c = closed(LAWS[law]);
            let lanes = c.lanes().unwrap();
            let t: [f64; LANES] = t.try_into().unwrap();
            let cz = ((1.0 - zeta) * (1.0 + zeta)).sqrt();
            let (r, bad) = lanes.block(&t, zeta, cz);
            prop_assert_eq!(bad, t.iter().any(|&v| lanes.needs_scalar(v, zeta, cz)));
            for l in 0..LANES {
                prop_assert_eq!(r[l], lanes.one(t[l], zeta));
            }
        }

        #[test]
        fn lanes_match_the_scalar_pieces(law in 0usize..5, lt in 0.0f64..4.0, zeta in 0.0f64..0.999) {
            let c = closed(LAWS[law]);
            let lanes = c.lanes().unwrap();
            let tau = 10f64.powf(lt);
            let cz = ((1.0 - zeta) * (1.0 + zeta)).sqrt();
            prop_assume!(!lanes.needs_scalar(tau, zeta, cz));
            let (got, want) = (lanes.one(tau, zeta), c.general(tau, zeta));
            prop_assert!((got - want).abs() <= 1e-12 * envelope(tau, zeta), "{} {} {}: {} {}", LAWS[law], tau, zeta, got, want);
        }
    }

    use std::f64::consts::PI;
}
