//! The residual vibration of the built-in laws in closed form (issue 37).
//!
//! **One integral.** Started from rest, the end state of
//! x'' + 2ζτx' + τ²x = g(u) on [0, 1] is the Duhamel integral with the impulse
//! response h(u) = Im e^{λu}/ω_d, λ = −ζτ + iω_d, ω_d = τ√(1 − ζ²). With
//! G = ∫₀¹ e^{λ(1−s)} g(s) ds, x(1) = Im G/ω_d and x'(1) = Im(λG)/ω_d, so
//! (x'(1) + ζτx(1))/ω_d = Re G/ω_d and the free-vibration amplitude of the
//! module docs of `vibration` is simply
//!
//! ```text
//! R = |G| / ω_d,       G = −∫₀¹ e^{λ(1−s)} z''(s) ds     (g = −z'', unit stroke)
//! ```
//!
//! **Closed forms per piece.** Every built-in law is, piece by piece on
//! [x0, x0 + L], a polynomial plus one sine in t = s − x0 (`motion::Segment`),
//! so g is too. With μ = λL and E = e^{μ}:
//!
//! - a power t^k gives k!·L^{k+1}·φ_{k+1}(μ), the exponential integrators'
//!   φ functions φ_j(μ) = ∫₀¹ e^{(1−σ)μ} σ^{j−1}/(j−1)! dσ; for |μ| <
//!   [`SERIES_RADIUS`] φ_m by its Taylor series Σ μⁿ/(n+m)! and the lower ones
//!   by φ_j = μφ_{j+1} + 1/j! (stable downward), else φ_1 = (E − 1)/μ and
//!   φ_{j+1} = (φ_j − 1/j!)/μ (stable upward for |μ| ≥ 2 and the degrees here);
//! - B·sin(Ωt + φ) gives B·[E(λ sin φ + Ω cos φ) − (λ sin ψ + Ω cos ψ)]/(λ² + Ω²),
//!   ψ = ΩL + φ (one fraction: no cancellation at large τ, where R is small);
//!   near resonance (|λ ∓ iΩ|·L < 1, where both vanish) the same integral as
//!   B·L/(2i)·[e^{iψ}φ_1((λ − iΩ)L) − e^{−iψ}φ_1((λ + iΩ)L)], whose φ_1 is
//!   smooth through the resonance (ζ = 0, τ = Ω: the cycloidal rise's removable
//!   0/0 at τ = 2π);
//!
//! and the piece's integral is weighted by e^{λ(1 − x0 − L)}.
//!
//! **Small τ.** As τ → 0 G → −λ while the pieces' integrals stay O(1): their sum
//! would lose digits like 1/τ. Integrated by parts once (z'(0) = z'(1) = 0),
//! G = −λ∫₀¹ e^{λ(1−s)} z'(s) ds, whose integral tends to
//! z(1) − z(0) = 1 with no cancellation; it serves τ < 1 (|λ| = τ), the
//! z''-form τ ≥ 1. R → 1/√(1 − ζ²) as τ → 0 as it must.
//!
//! **In lanes.** [`ClosedResidual::fill`] serves the cycloidal and harmonic
//! rises by their own real forms ([`cycloidal`], [`lanes::harmonic`]) and the
//! other built-in laws by the same pieces
//! summed with per-law constants, in real arithmetic across SIMD lanes
//! ([`Lanes`], module `lanes`); [`ClosedResidual::general`] below is the
//! scalar path both fall back to (small τ, near a resonance, huge τ) and the
//! reference they are tested against.
//!
//! Accuracy (tested against the sampled Duhamel path of `vibration`, the
//! cycloidal law's textbook form and, in Python, independent numpy closed forms
//! and scipy's `solve_ivp`): within 1e-11 of R's envelope up to τ = 10⁴. The
//! pieces' sum keeps an absolute error of a few ulps of its largest term,
//! ~ε/τ² against an envelope of 1/τ² to 1/τ³ (the laws' first discontinuous
//! derivative), so the error relative to the envelope grows like ε·τ.

use std::f64::consts::FRAC_PI_2;

use nalgebra::Complex;

use crate::geom::sin_cos;
use crate::motion::{Law, MotionError};

#[path = "residual_lanes.rs"]
pub mod lanes;
pub use lanes::Lanes;

type C = Complex<f64>;

/// Below this |μ| the φ functions come from their Taylor series.
pub const SERIES_RADIUS: f64 = 2.0;

/// Terms of the Taylor series of φ_m: 2^n/n! < 1e-17 beyond (with m ≥ 1).
const SERIES_TERMS: usize = 26;

/// Highest polynomial degree served in closed form (the built-in laws' z' has
/// degree ≤ 6); a law with higher pieces keeps the sampled path.
pub const MAX_CLOSED_DEGREE: usize = 8;

/// 1/k! for k = 0..SERIES_TERMS + MAX_CLOSED_DEGREE + 1.
const INV_FACT: [f64; SERIES_TERMS + MAX_CLOSED_DEGREE + 2] = {
    let mut t = [1.0; SERIES_TERMS + MAX_CLOSED_DEGREE + 2];
    let mut k = 1;
    while k < t.len() {
        t[k] = t[k - 1] / k as f64;
        k += 1;
    }
    t
};

/// e^{z}.
#[inline(always)]
fn cexp(z: C) -> C {
    let (s, c) = sin_cos(z.im);
    let m = z.re.exp();
    C::new(m * c, m * s)
}

/// φ_1..=φ_m of μ into `out[1..=m]` (`e` = e^μ).
#[inline(always)]
fn phis(mu: C, e: C, m: usize, out: &mut [C; MAX_CLOSED_DEGREE + 2]) {
    if mu.norm_sqr() < SERIES_RADIUS * SERIES_RADIUS {
        let mut acc = C::new(INV_FACT[SERIES_TERMS + m], 0.0);
        for n in (0..SERIES_TERMS).rev() {
            acc = acc * mu + INV_FACT[n + m];
        }
        out[m] = acc;
        for j in (1..m).rev() {
            out[j] = out[j + 1] * mu + INV_FACT[j];
        }
    } else {
        let inv = mu.inv();
        out[1] = (e - 1.0) * inv;
        for j in 1..m {
            out[j + 1] = (out[j] - INV_FACT[j]) * inv;
        }
    }
}

/// φ_1(w) = (e^w − 1)/w.
#[inline]
fn phi1(w: C) -> C {
    let mut out = [C::new(0.0, 0.0); MAX_CLOSED_DEGREE + 2];
    phis(w, cexp(w), 1, &mut out);
    out[1]
}

/// One piece of g on [x0, x0 + len]: Σ poly[k]·t^k + amp·sin(freq·t + phase).
#[derive(Debug, Clone, PartialEq)]
struct Piece {
    x0: f64,
    len: f64,
    /// poly[k]·k!·len^{k+1}: the weight of φ_{k+1}(λ·len).
    weights: Vec<f64>,
    amp: f64,
    freq: f64,
    /// (sin, cos) of the phase at the piece's start and end.
    start: (f64, f64),
    end: (f64, f64),
}

impl Piece {
    fn new(x0: f64, len: f64, poly: &[f64], amp: f64, freq: f64, phase: f64) -> Piece {
        let mut fact = 1.0;
        let weights = poly
            .iter()
            .enumerate()
            .map(|(k, &c)| {
                if k > 0 {
                    fact *= k as f64;
                }
                c * fact * len.powi(k as i32 + 1)
            })
            .collect();
        Piece {
            x0,
            len,
            weights,
            amp: if freq == 0.0 { 0.0 } else { amp },
            freq,
            start: phase.sin_cos(),
            end: (freq * len + phase).sin_cos(),
        }
    }

    /// ∫₀^L e^{λ(L−t)} g(t) dt (`inv_lam` = 1/λ, `e` = e^{λL}).
    #[inline(always)]
    fn integral(&self, lam: C, inv_lam: C, e: C) -> C {
        let l = self.len;
        let mut sum = C::new(0.0, 0.0);
        let m = self.weights.len();
        if m > 0 {
            let mut ph = [C::new(0.0, 0.0); MAX_CLOSED_DEGREE + 2];
            phis(lam * l, e, m, &mut ph);
            for (k, &w) in self.weights.iter().enumerate() {
                sum += ph[k + 1] * w;
            }
        }
        if self.amp != 0.0 {
            let om = self.freq;
            let (s0, c0) = self.start;
            let (s1, c1) = self.end;
            let near = (lam - C::new(0.0, om))
                .norm_sqr()
                .min((lam + C::new(0.0, om)).norm_sqr())
                * l
                * l
                < 1.0;
            sum += if near {
                let wm = (lam - C::new(0.0, om)) * l;
                let wp = (lam + C::new(0.0, om)) * l;
                let d = C::new(c1, s1) * phi1(wm) - C::new(c1, -s1) * phi1(wp);
                // d/(2i) = (Im d, −Re d)/2.
                C::new(d.im, -d.re) * (0.5 * self.amp * l)
            } else if lam.norm_sqr() >= 1.0 {
                // Numerator and denominator divided by λ (no overflow at huge τ).
                let r = om * inv_lam;
                let num = e * (r * c0 + s0) - (r * c1 + s1);
                num / (lam + r * om) * self.amp
            } else {
                let num = e * (lam * s0 + om * c0) - (lam * s1 + om * c1);
                num / (lam * lam + om * om) * self.amp
            };
        }
        sum
    }
}

/// Eighths of the unit: every built-in law's breakpoints are multiples of 1/8.
const EIGHTHS: usize = 8;

/// ∫₀¹ e^{λ(1−s)} g(s) ds for a piecewise g.
#[derive(Debug, Clone, PartialEq)]
struct Integrand {
    pieces: Vec<Piece>,
    /// Per piece, (len, 1 − x0 − len) in eighths when every piece's are whole
    /// eighths: then e^{λ/8} and its powers serve every exponential (one
    /// complex exponential per τ instead of two per piece).
    eighths: Option<Vec<(usize, usize)>>,
}

impl Integrand {
    fn new(pieces: Vec<Piece>) -> Integrand {
        let whole = |x: f64| {
            let k = x * EIGHTHS as f64;
            (k == k.round() && (0.0..=EIGHTHS as f64).contains(&k)).then_some(k as usize)
        };
        let eighths = pieces
            .iter()
            .map(|p| Some((whole(p.len)?, whole(1.0 - p.x0 - p.len)?)))
            .collect();
        Integrand { pieces, eighths }
    }

    #[inline(always)]
    fn weighted(&self, lam: C, inv_lam: C) -> C {
        let mut g = C::new(0.0, 0.0);
        if let Some(eighths) = &self.eighths {
            let mut pow = [C::new(1.0, 0.0); EIGHTHS + 1];
            pow[1] = cexp(lam / EIGHTHS as f64);
            for k in 2..=EIGHTHS {
                pow[k] = pow[k - 1] * pow[1];
            }
            for (p, &(len, after)) in self.pieces.iter().zip(eighths) {
                g += pow[after] * p.integral(lam, inv_lam, pow[len]);
            }
            return g;
        }
        for p in &self.pieces {
            let e = cexp(lam * p.len);
            let i = p.integral(lam, inv_lam, e);
            let after = 1.0 - p.x0 - p.len;
            g += if after > 0.0 {
                cexp(lam * after) * i
            } else {
                i
            };
        }
        g
    }
}

/// The residual vibration R(τ, ζ) of one law in closed form (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct ClosedResidual {
    /// The cycloidal rise: its own real form ([`cycloidal`]).
    cycloidal: bool,
    /// The harmonic rise: its own real form ([`lanes::harmonic`]).
    harmonic: bool,
    /// g = −z'' (τ ≥ 1).
    accel: Integrand,
    /// g = z' (τ < 1).
    vel: Integrand,
    /// The pieces' sum in SIMD lanes (`residual_lanes`), where the law allows.
    lanes: Option<Lanes>,
}

impl ClosedResidual {
    /// The closed form of the named law's rise; an unknown name is an error.
    pub fn new(law: &str) -> Result<ClosedResidual, MotionError> {
        let mut c = ClosedResidual::of(&Law::rise(law)?).expect("built-in laws have low degrees");
        c.cycloidal = law == "cycloidal";
        c.harmonic = law == "harmonic";
        Ok(c)
    }

    /// The closed form of a rise (z'(0) = z'(1) = 0, taken as exact: the
    /// built-in laws' are, up to the rounding of their phases) whose pieces
    /// have degree ≤ [`MAX_CLOSED_DEGREE`] + 1; None above (the sampled path
    /// serves it).
    pub fn of(law: &Law) -> Option<ClosedResidual> {
        let mut accel = Vec::new();
        let mut vel = Vec::new();
        for s in &law.segments {
            if s.poly.len() > MAX_CLOSED_DEGREE + 2 {
                return None;
            }
            let len = s.x1 - s.x0;
            if len <= 0.0 {
                continue;
            }
            // z = Σ c_k t^k + A sin(Ωt + φ): z' and −z''.
            let d1: Vec<f64> = (1..s.poly.len()).map(|k| k as f64 * s.poly[k]).collect();
            let d2: Vec<f64> = (2..s.poly.len())
                .map(|k| -((k * (k - 1)) as f64) * s.poly[k])
                .collect();
            let (a, w, ph) = (s.amp, s.freq, s.phase);
            vel.push(Piece::new(s.x0, len, &d1, a * w, w, ph + FRAC_PI_2));
            accel.push(Piece::new(s.x0, len, &d2, a * w * w, w, ph));
        }
        Some(ClosedResidual {
            cycloidal: false,
            harmonic: false,
            accel: Integrand::new(accel),
            vel: Integrand::new(vel),
            lanes: Lanes::of(law),
        })
    }

    /// R(τ, ζ) for τ > 0 and ζ ∈ [0, 1) (the caller checks them).
    #[inline]
    pub fn ratio(&self, tau: f64, zeta: f64) -> f64 {
        if self.cycloidal {
            return cycloidal::ratio(tau, zeta, ((1.0 - zeta) * (1.0 + zeta)).sqrt());
        }
        if self.harmonic {
            return lanes::harmonic::ratio(tau, zeta, ((1.0 - zeta) * (1.0 + zeta)).sqrt());
        }
        // The lanes' formula where it serves, so that one τ and a batch agree
        // bit for bit.
        if let Some(l) = &self.lanes {
            if !l.needs_scalar(tau, zeta, ((1.0 - zeta) * (1.0 + zeta)).sqrt()) {
                return l.one(tau, zeta);
            }
        }
        self.general(tau, zeta)
    }

    /// R(τ, ζ) by the pieces' closed forms (any law [`ClosedResidual::of`] took).
    #[inline]
    pub fn general(&self, tau: f64, zeta: f64) -> f64 {
        let wd = tau * ((1.0 - zeta) * (1.0 + zeta)).sqrt();
        let lam = C::new(-zeta * tau, wd);
        let inv_lam = lam.inv();
        let g = if tau >= 1.0 {
            self.accel.weighted(lam, inv_lam)
        } else {
            -lam * self.vel.weighted(lam, inv_lam)
        };
        // |G| ≤ O(1) and ≥ ~ε/τ² here: its square neither overflows nor
        // underflows for τ ≤ 1e150 (`hypot` would cost a third of the time).
        (g.re * g.re + g.im * g.im).sqrt() / wd
    }

    /// The lanes' constants, if the law has them.
    pub fn lanes(&self) -> Option<&Lanes> {
        self.lanes.as_ref()
    }

    /// R(τ_i, ζ) for every τ_i into `out` (checked τ > 0, ζ ∈ [0, 1)): the
    /// cycloidal rise in its real form, the other laws in the pieces' sum
    /// ([`Lanes`]), both in SIMD lanes.
    pub fn fill(&self, tau: &[f64], zeta: f64, out: &mut [f64]) {
        if self.cycloidal {
            let form = std::marker::PhantomData::<cycloidal::Form>;
            pulp::Arch::new().dispatch(RealBlocks {
                tau,
                out,
                zeta,
                form,
            });
        } else if self.harmonic {
            let form = std::marker::PhantomData::<lanes::harmonic::Form>;
            pulp::Arch::new().dispatch(RealBlocks {
                tau,
                out,
                zeta,
                form,
            });
        } else if let Some(lanes) = &self.lanes {
            pulp::Arch::new().dispatch(lanes::Blocks {
                lanes,
                tau,
                out,
                zeta,
                scalar: |t| self.general(t, zeta),
            });
        } else {
            for (o, &t) in out.iter_mut().zip(tau) {
                *o = self.general(t, zeta);
            }
        }
    }
}

/// A law's residual vibration in real arithmetic (the cycloidal and the
/// harmonic rise): one τ, and [`cycloidal::LANES`] values of τ ≤ 2e6 at once.
pub(crate) trait RealForm {
    fn one(tau: f64, zeta: f64, c: f64) -> f64;
    fn lanes(tau: &[f64; cycloidal::LANES], zeta: f64, c: f64) -> [f64; cycloidal::LANES];
}

/// Fills `out` with R(τ_i, ζ) by a [`RealForm`]: blocks of lanes where every τ
/// is ≤ 2e6, one by one elsewhere and in the tail (the same value either way).
pub(crate) struct RealBlocks<'a, F: RealForm> {
    pub(crate) tau: &'a [f64],
    pub(crate) out: &'a mut [f64],
    pub(crate) zeta: f64,
    pub(crate) form: std::marker::PhantomData<F>,
}

impl<F: RealForm> pulp::WithSimd for RealBlocks<'_, F> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        use cycloidal::LANES;
        let c = ((1.0 - self.zeta) * (1.0 + self.zeta)).sqrt();
        let mut tc = self.tau.chunks_exact(LANES);
        let mut oc = self.out.chunks_exact_mut(LANES);
        for (t, o) in (&mut tc).zip(&mut oc) {
            let t: &[f64; LANES] = t.try_into().expect("chunks of LANES");
            if t.iter().fold(true, |ok, &v| ok & (v <= 2e6)) {
                o.copy_from_slice(&F::lanes(t, self.zeta, c));
            } else {
                for (oj, &tj) in o.iter_mut().zip(t) {
                    *oj = F::one(tj, self.zeta, c);
                }
            }
        }
        for (oj, &tj) in oc.into_remainder().iter_mut().zip(tc.remainder()) {
            *oj = F::one(tj, self.zeta, c);
        }
    }
}

/// The cycloidal rise in real arithmetic: with e = e^{−ζτ},
/// |e^{λ} − 1|² = (1 − e)² + 4e·sin²(ω_d/2) and
/// λ² + 4π² = (λ − 2πi)(λ + 2πi), so
///
/// ```text
/// R = 4π²·√[((1 − e)² + 4e sin²(ω_d/2)) / ((ζτ)² + (ω_d − 2π)²) / ((ζτ)² + (ω_d + 2π)²)] / ω_d
/// ```
///
/// (the general form's G = −4π²(e^{λ} − 1)/(λ² + 4π²) for g = −2π sin 2πs),
/// every factor free of cancellation: 1 − e = −expm1(−ζτ), and ω_d − 2π with a
/// two-part 2π so that the undamped resonance τ = 2π (0/0) keeps R = 1/2.
pub mod cycloidal {
    use std::f64::consts::{PI, TAU};

    use crate::geom::{sin, sin_lanes};

    /// 2π − TAU (the second part of 2π).
    const TAU_LO: f64 = 2.449_293_598_294_706_4e-16;
    const FOUR_PI2: f64 = 4.0 * PI * PI;

    /// Values per block of [`ratio_lanes`].
    pub const LANES: usize = 8;

    #[inline(always)]
    fn combine(zt: f64, wd: f64, m: f64, s: f64) -> f64 {
        let (one_minus_e, e) = (-m, 1.0 + m);
        let num = one_minus_e * one_minus_e + 4.0 * e * s * s;
        let dm = (wd - TAU) - TAU_LO;
        let dp = wd + TAU;
        let z2 = zt * zt;
        FOUR_PI2 * (num / (z2 + dm * dm) / (z2 + dp * dp)).sqrt() / wd
    }

    /// R(τ, ζ) for one τ (`c` = √(1 − ζ²)).
    #[inline]
    pub fn ratio(tau: f64, zeta: f64, c: f64) -> f64 {
        let (zt, wd) = (zeta * tau, c * tau);
        combine(zt, wd, (-zt).exp_m1(), sin(0.5 * wd))
    }

    // fdlibm's two-part ln 2 (the high part's trailing bits zero: k·LN2_HI is
    // exact for |k| < 2¹¹).
    #[allow(clippy::excessive_precision)]
    const LN2_HI: f64 = 6.931_471_803_691_238_164_90e-1;
    #[allow(clippy::excessive_precision)]
    const LN2_LO: f64 = 1.908_214_929_270_587_700_02e-10;

    /// e^x − 1 for −700 ≤ x ≤ 0 without branches (the caller clamps): x =
    /// k·ln 2 + r, |r| ≤ ln2/2, e^x − 1 = 2^k·expm1(r) + (2^k − 1), expm1(r)
    /// by its Taylor series to r¹³/13! (the remainder < 4e-18·|r|): within a
    /// few ulps of `exp_m1` (tested), and no cancellation at k = 0.
    #[inline(always)]
    pub(crate) fn expm1_neg(x: f64) -> f64 {
        let (two_k, em1) = exp_split(x);
        two_k * em1 + (two_k - 1.0)
    }

    /// (2^k, expm1(r)) with e^x = 2^k·(1 + expm1(r)) for −700 ≤ x ≤ 0 (the
    /// reduction of [`expm1_neg`], without branches).
    #[inline(always)]
    pub(crate) fn exp_split(x: f64) -> (f64, f64) {
        const ROUND: f64 = 6_755_399_441_055_744.0;
        let shifted = x * std::f64::consts::LOG2_E + ROUND;
        let k = shifted - ROUND;
        let r = (x - k * LN2_HI) - k * LN2_LO;
        // p = Σ_{n=1..13} r^{n−1}/n!, from 1/13! down.
        let mut p = super::INV_FACT[13];
        for n in (2..=12).rev() {
            p = p * r + super::INV_FACT[n];
        }
        let em1 = r * (p * r + 1.0);
        // 2^k from k's bits in the shifted value (its ulp is 1).
        let kb = shifted.to_bits().wrapping_sub(ROUND.to_bits());
        let two_k = f64::from_bits(kb.wrapping_add(1023) << 52);
        (two_k, em1)
    }

    /// R for [`LANES`] values of τ in (0, 2e6] at once, without branches (so a
    /// caller compiled for AVX2 or AVX-512 runs several per instruction).
    #[inline(always)]
    pub fn ratio_lanes(tau: &[f64; LANES], zeta: f64, c: f64) -> [f64; LANES] {
        // Stage by stage across the lanes (each loop one vector operation chain).
        let mut m = [0.0; LANES];
        let mut s = [0.0; LANES];
        let mut out = [0.0; LANES];
        for l in 0..LANES {
            m[l] = expm1_neg((-zeta * tau[l]).max(-700.0));
        }
        for l in 0..LANES {
            s[l] = sin_lanes(0.5 * c * tau[l]);
        }
        for l in 0..LANES {
            out[l] = combine(zeta * tau[l], c * tau[l], m[l], s[l]);
        }
        out
    }

    /// The cycloidal rise's real form, for [`RealBlocks`].
    pub(crate) struct Form;

    impl super::RealForm for Form {
        #[inline(always)]
        fn one(tau: f64, zeta: f64, c: f64) -> f64 {
            ratio(tau, zeta, c)
        }
        #[inline(always)]
        fn lanes(tau: &[f64; LANES], zeta: f64, c: f64) -> [f64; LANES] {
            ratio_lanes(tau, zeta, c)
        }
    }

    #[cfg(test)]
    mod tests {
        use super::*;
        use proptest::prelude::*;

        proptest! {
            #[test]
            fn expm1_matches_the_platform(x in -700.0f64..0.0, small in -1e-3f64..0.0) {
                for v in [x, small, small * 1e-12] {
                    let (got, want) = (expm1_neg(v), v.exp_m1());
                    prop_assert!((got - want).abs() <= 4.0 * f64::EPSILON * want.abs(), "{} {} {}", v, got, want);
                }
            }

            #[test]
            fn lanes_match_one_by_one(t in proptest::collection::vec(1e-6f64..2e6, LANES), zeta in 0.0f64..0.999) {
                let t: [f64; LANES] = t.try_into().unwrap();
                let c = ((1.0 - zeta) * (1.0 + zeta)).sqrt();
                let r = ratio_lanes(&t, zeta, c);
                for l in 0..LANES {
                    let one = ratio(t[l], zeta, c);
                    prop_assert!((r[l] - one).abs() <= 1e-14 * one, "{} {}", r[l], one);
                }
            }
        }
    }
}
