//! The forced oscillator's exact recurrence (Nigam–Jennings, see the domain's
//! docs): one case, and batches of cases in lock step across SIMD lanes.

use std::f64::consts::{FRAC_PI_2, PI};

use rayon::prelude::*;

use crate::geom::sin_cos;
use crate::parallel::{pool, resolve_threads};
use crate::tile::{transpose_in, transpose_out, HALF, TILE};

use super::error::{
    check_finite, check_times, finite, length, mode_range, param, step_ok, time_error, ImpactError,
};
use super::lane_coef::LaneCoef;
use super::scan::scan;

/// The forced oscillator: ω = `omega_n` [rad/s], ζ = `zeta`, m = `mass`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Oscillator {
    pub omega_n: f64,
    pub zeta: f64,
    pub mass: f64,
}

impl Oscillator {
    /// A checked oscillator.
    pub fn new(omega_n: f64, zeta: f64, mass: f64) -> Result<Oscillator, ImpactError> {
        let o = Oscillator {
            omega_n,
            zeta,
            mass,
        };
        o.validate()?;
        Ok(o)
    }

    /// ω finite and > 0, ζ finite and ≥ 0, m finite and > 0.
    pub fn validate(&self) -> Result<(), ImpactError> {
        param(
            "omega_n",
            self.omega_n,
            self.omega_n > 0.0,
            "finite and > 0 [rad/s]",
        )?;
        param("zeta", self.zeta, self.zeta >= 0.0, "finite and >= 0")?;
        param("mass", self.mass, self.mass > 0.0, "finite and > 0")?;
        mode_range("omega_n", self.omega_n, self.zeta)
    }

    pub(super) fn mode(&self) -> Mode {
        Mode::new(self.omega_n, self.zeta)
    }
}

/// The unforced oscillator y'' + 2σy' + ω²y = 0 in the forms the kernels use.
#[derive(Debug, Clone, Copy)]
pub(super) struct Mode {
    pub(super) omega: f64,
    pub(super) zeta: f64,
    /// σ = ζω.
    pub(super) sigma: f64,
    /// ω².
    pub(super) w2: f64,
    /// λ = ω² − σ²: > 0 under-damped, < 0 over-damped.
    pub(super) lambda: f64,
    /// √|λ|: the damped frequency ωd (λ > 0) or κ (λ < 0).
    pub(super) k: f64,
    /// The slow decay rate σ − κ = ω²/(σ + κ) of an over-damped mode (else σ).
    pub(super) slow: f64,
    /// σ + √|λ|, a bound on |eigenvalue|: the scale of the Taylor series.
    pub(super) rate: f64,
    /// Clearly over-damped (κ ≥ σ/2, ζ ≥ 2/√3): the two real decay rates
    /// a = σ − κ and b = σ + κ are far apart, and the forms in e^{−aτ}, e^{−bτ}
    /// avoid the cancellation of σS against C that grows like ζ².
    pub(super) split: bool,
}

/// 1/(2n)! and 1/(2n+1)!, n = 0 … 11: the coefficients of [`cs_series`].
/// The factorials are exact in f64 up to 22! (their odd parts stay below 2⁵³),
/// so each reciprocal but the last is correctly rounded.
pub(super) const CS_COEF: ([f64; 12], [f64; 12]) = {
    let (mut c, mut s) = ([0.0; 12], [0.0; 12]);
    let mut fact = 1.0;
    let mut k = 0;
    while k < 24 {
        if k > 0 {
            fact *= k as f64;
        }
        if k % 2 == 0 {
            c[k / 2] = 1.0 / fact;
        } else {
            s[k / 2] = 1.0 / fact;
        }
        k += 1;
    }
    (c, s)
};

/// cos(√−u)-type and sin(√−u)/√−u-type series for |u| ≤ 1:
/// (Σ uⁿ/(2n)!, Σ uⁿ/(2n+1)!), n ≤ 11 (the first term left out is below
/// 1/24! ≈ 2⁻⁷⁹ of the sum). Horner's rule on the reciprocal factorials:
/// a multiply and an add a term, no division (the nested form
/// 1 + u/(1·2)(1 + u/(3·4)(1 + …)) took 22 divisions, half the cost of a
/// step's coefficients).
#[inline(always)]
pub(super) fn cs_series(u: f64) -> (f64, f64) {
    let (dc, ds) = CS_COEF;
    let (mut c, mut s) = (dc[11], ds[11]);
    for i in (0..11).rev() {
        c = c * u + dc[i];
        s = s * u + ds[i];
    }
    (c, s)
}

#[inline]
pub(super) fn sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

impl Mode {
    pub(super) fn new(omega: f64, zeta: f64) -> Mode {
        let sigma = zeta * omega;
        let w2 = omega * omega;
        // (1 − ζ)(1 + ζ) keeps λ's relative accuracy near ζ = 1.
        let lambda = w2 * ((1.0 - zeta) * (1.0 + zeta));
        let k = lambda.abs().sqrt();
        let slow = if lambda < 0.0 {
            w2 / (sigma + k)
        } else {
            sigma
        };
        Mode {
            omega,
            zeta,
            sigma,
            w2,
            lambda,
            k,
            slow,
            rate: sigma + k,
            split: lambda < 0.0 && k >= 0.5 * sigma,
        }
    }

    pub(super) fn underdamped(&self) -> bool {
        self.lambda > 0.0 && self.k > 0.0
    }

    /// (e^{−στ}C(τ), e^{−στ}S(τ)) without overflow for large τ and continuous in ζ.
    #[inline]
    pub(super) fn ecs(&self, tau: f64) -> (f64, f64) {
        let u = -self.lambda * tau * tau;
        if u.abs() <= 1.0 {
            let e = (-self.sigma * tau).exp();
            let (c, s) = cs_series(u);
            (e * c, e * s * tau)
        } else if self.lambda > 0.0 {
            let e = (-self.sigma * tau).exp();
            let (s, c) = sin_cos(self.k * tau);
            (e * c, e * s / self.k)
        } else {
            // e^{−στ}cosh κτ = e^{−(σ−κ)τ}(1 + e^{−2κτ})/2, and sinh likewise.
            let ea = (-self.slow * tau).exp();
            let m = (-2.0 * self.k * tau).exp_m1();
            (ea * (1.0 + 0.5 * m), -ea * m / (2.0 * self.k))
        }
    }

    /// The transition (Φ00, Φ01, Φ11) over τ of the unforced motion
    /// (Φ10 = −ω²Φ01).
    #[inline]
    pub(super) fn phi(&self, tau: f64) -> (f64, f64, f64) {
        if self.split {
            let (a, b, k2) = (self.slow, self.rate, 2.0 * self.k);
            let (ea, eb) = ((-a * tau).exp(), (-b * tau).exp());
            let p01 = -ea * (-k2 * tau).exp_m1() / k2;
            return ((b * ea - a * eb) / k2, p01, (b * eb - a * ea) / k2);
        }
        let (ec, es) = self.ecs(tau);
        (ec + self.sigma * es, es, ec - self.sigma * es)
    }

    /// (y(τ), y'(τ)) of the unforced motion from y(0) = y0, y'(0) = y1.
    #[inline]
    pub(super) fn eval(&self, y0: f64, y1: f64, tau: f64) -> (f64, f64) {
        let (p00, p01, p11) = self.phi(tau);
        (p00 * y0 + p01 * y1, p11 * y1 - self.w2 * p01 * y0)
    }

    /// The first τ > 0 at which the unforced motion from y(0) = y0,
    /// y'(0) = y1 is zero, in closed form (an atan, or an atanh when over-damped);
    /// None if it never is. Its zeros are where C y0 + S (σ y0 + y1) = 0.
    pub(super) fn first_zero(&self, y0: f64, y1: f64) -> Option<f64> {
        let w = self.sigma * y0 + y1;
        if y0 == 0.0 {
            // y = e^{−στ} S w: zero again after half a damped period, if ever.
            return (w != 0.0 && self.underdamped()).then(|| PI / self.k);
        }
        if w == 0.0 {
            return self.underdamped().then(|| FRAC_PI_2 / self.k);
        }
        // S/C = r, with S/C = tan(ωd τ)/ωd, τ or tanh(κτ)/κ.
        let r = -y0 / w;
        let tau = if self.k == 0.0 {
            if r > 0.0 {
                r
            } else {
                return None;
            }
        } else if self.lambda > 0.0 {
            let x = (r * self.k).atan();
            if r > 0.0 {
                x / self.k
            } else {
                (PI + x) / self.k
            }
        } else {
            let x = r * self.k;
            if r > 0.0 && x < 1.0 {
                x.atanh() / self.k
            } else {
                return None;
            }
        };
        (tau.is_finite() && tau > 0.0).then_some(tau)
    }

    /// The first τ in (0, ∞) at which f(τ) = y(τ) − level, moving from the side
    /// `side` (±1; f(0) has that sign or is 0 with f leaving 0 that way), reaches
    /// zero: None if it never does. With `touch`, an extremum of f at zero (within
    /// rounding) counts; without, only a crossing does (f must pass beyond zero by
    /// more than rounding).
    ///
    /// y' vanishes at closed-form instants z1 < z2 < …, f is monotone between
    /// them, and the extrema y(z_i) alternate in sign with non-increasing
    /// magnitude; so if f has not reached zero by z2 it never will, and at most two
    /// pieces are examined (an over-damped mode has at most one z, after which f
    /// tends monotonically to −level).
    pub(super) fn crossing(
        &self,
        y0: f64,
        y1: f64,
        level: f64,
        side: f64,
        touch: bool,
    ) -> Option<f64> {
        if level == 0.0 {
            // Zeros of an unforced motion are simple: every one is a crossing.
            return self.first_zero(y0, y1);
        }
        let f = |tau: f64| {
            let (y, dy) = self.eval(y0, y1, tau);
            (y - level, dy)
        };
        // Rounding of f near an extremum: a few ulps of the motion's amplitude.
        let tol = 32.0 * f64::EPSILON * (y0.abs() + y1.abs() / self.omega + level.abs());
        // Zeros of y': y'(0) = y1, y''(0) = −2σy1 − ω²y0.
        let z1 = self.first_zero(y1, -2.0 * self.sigma * y1 - self.w2 * y0);
        let z2 = z1.filter(|_| self.underdamped()).map(|z| z + PI / self.k);
        let (mut ta, mut fa) = (0.0, y0 - level);
        for z in [z1, z2] {
            let Some(tb) = z else {
                // Monotone from ta on, towards −level.
                if side * (-level) >= 0.0 {
                    return None;
                }
                let mut d = (1.0 / self.slow.max(self.omega)).max(ta);
                // d doubles from ≥ 1e-150 s (ω ≤ 1e150) to overflow within ~1520
                // rounds; the cap only makes that bound explicit.
                for _ in 0..2100 {
                    let tb = ta + d;
                    let fb = f(tb).0;
                    if side * fb <= 0.0 {
                        return Some(if fb == 0.0 {
                            tb
                        } else {
                            solve(f, ta, tb, fa, fb)
                        });
                    }
                    (ta, fa) = (tb, fb);
                    d *= 2.0;
                    if !d.is_finite() {
                        return None;
                    }
                }
                return None;
            };
            // f has an extremum at tb.
            let fb = f(tb).0;
            let reach = side * fb;
            if reach < -tol {
                return Some(solve(f, ta, tb, fa, fb));
            }
            if reach <= tol && touch {
                return Some(tb);
            }
            (ta, fa) = (tb, fb);
        }
        None
    }

    /// The first extremum of y of the wanted kind (max if `max`, else min) at
    /// τ > 0: (τ, y(τ)).
    pub(super) fn extremum(&self, y0: f64, y1: f64, max: bool) -> Option<(f64, f64)> {
        let z1 = self.first_zero(y1, -2.0 * self.sigma * y1 - self.w2 * y0)?;
        // At a zero of y', y'' = −ω² y: a maximum where y > 0.
        let y = self.eval(y0, y1, z1).0;
        if (y > 0.0) == max {
            return Some((z1, y));
        }
        if !self.underdamped() {
            return None;
        }
        let z2 = z1 + PI / self.k;
        Some((z2, self.eval(y0, y1, z2).0))
    }
}

/// The root of f in (lo, hi] where f(lo), f(hi) have opposite signs: Newton steps
/// from the secant point, bisection whenever a step leaves the bracket, to
/// rounding in τ. `f` returns (f, f').
fn solve(f: impl Fn(f64) -> (f64, f64), mut lo: f64, mut hi: f64, mut flo: f64, fhi: f64) -> f64 {
    let mut x = lo - flo * (hi - lo) / (fhi - flo);
    if !(x > lo && x < hi) {
        x = lo + 0.5 * (hi - lo);
    }
    for _ in 0..200 {
        let (fx, dfx) = f(x);
        if fx == 0.0 {
            return x;
        }
        if (fx > 0.0) == (flo > 0.0) {
            (lo, flo) = (x, fx);
        } else {
            hi = x;
        }
        if hi - lo <= 4.0 * f64::EPSILON * hi.abs() {
            return x;
        }
        let mut xn = x - fx / dfx;
        if !(xn > lo && xn < hi) {
            xn = lo + 0.5 * (hi - lo);
        }
        if (xn - x).abs() <= 2.0 * f64::EPSILON * x.abs() {
            return xn;
        }
        x = xn;
    }
    x
}

/// The exact transition over one step h, forces per unit of force (1/m folded in).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Step {
    pub(super) p00: f64,
    pub(super) p01: f64,
    pub(super) p10: f64,
    pub(super) p11: f64,
    pub(super) g0q: f64,
    pub(super) g0v: f64,
    pub(super) g1q: f64,
    pub(super) g1v: f64,
}

impl Step {
    const IDENTITY: Step = Step {
        p00: 1.0,
        p01: 0.0,
        p10: 0.0,
        p11: 1.0,
        g0q: 0.0,
        g0v: 0.0,
        g1q: 0.0,
        g1v: 0.0,
    };

    pub(super) fn new(mode: &Mode, h: f64, inv_m: f64) -> Step {
        if h == 0.0 {
            return Step::IDENTITY;
        }
        let (p00, p01, p11) = mode.phi(h);
        let (sig, w2) = (mode.sigma, mode.w2);
        let (i1, i1h, i2h) = if mode.rate * h <= 2.0 {
            integrals_series(mode, h)
        } else if mode.split {
            // I1 = h (φ1(ah) − φ1(bh))/(b − a), I2 = h² (φ2(ah) − φ2(bh))/(b − a).
            let (a, b, k2) = (mode.slow, mode.rate, 2.0 * mode.k);
            let i1 = h * (phi1(a * h) - phi1(b * h)) / k2;
            let i2h = h * (phi2(a * h) - phi2(b * h)) / k2;
            (i1, i1 / h, i2h)
        } else {
            let i1 = (1.0 - p00) / w2;
            let i2 = (h - p01 - 2.0 * sig * i1) / w2;
            (i1, i1 / h, i2 / h)
        };
        Step {
            p00,
            p01,
            p10: -w2 * p01,
            p11,
            g0q: (i1 - i2h) * inv_m,
            g0v: (p01 - i1h) * inv_m,
            g1q: i2h * inv_m,
            g1v: i1h * inv_m,
        }
    }

    pub(super) fn is_finite(&self) -> bool {
        [
            self.p00, self.p01, self.p10, self.p11, self.g0q, self.g0v, self.g1q, self.g1v,
        ]
        .iter()
        .all(|c| c.is_finite())
    }

    /// (q, v) after the step from (q, v) with forces f0 → f1, in fused
    /// multiply-adds (one rounding each):
    ///
    /// ```text
    /// fq = fma(g0q, f0, g1q·f1),   q' = fma(p00, q, fma(p01, v, fq))
    /// fv = fma(g0v, f0, g1v·f1),   v' = fma(p10, q, fma(p11, v, fv))
    /// ```
    ///
    /// The batch's lockstep lanes do exactly these operations in this order
    /// ([`Lockstep`]), and a fused multiply-add is correctly rounded whether
    /// the processor does it (`vfmadd`, `fmadd`) or libm's `fma` does, so every
    /// path gives the same bits. The state's chain is two fused operations a
    /// step (8 cycles on Zen 4, against 11 for the unfused multiply → add →
    /// add; the lockstep loop in cache stays ~0.5 ns a case-step, bound by
    /// its loads, but overlaps memory better). Compiled without hardware FMA (x86-64 before AVX2, outside a
    /// `pulp` dispatch) each `mul_add` is a call into libm: the hot loops run
    /// inside a dispatch ([`RunLoop`], [`Lockstep`]).
    #[inline(always)]
    pub(super) fn apply(&self, q: f64, v: f64, f0: f64, f1: f64) -> (f64, f64) {
        let fq = self.g0q.mul_add(f0, self.g1q * f1);
        let fv = self.g0v.mul_add(f0, self.g1v * f1);
        (
            self.p00.mul_add(q, self.p01.mul_add(v, fq)),
            self.p10.mul_add(q, self.p11.mul_add(v, fv)),
        )
    }
}

/// φ1(u) = (1 − e^{−u})/u, u > 0.
fn phi1(u: f64) -> f64 {
    -(-u).exp_m1() / u
}

/// φ2(u) = (u − 1 + e^{−u})/u², u > 0: by its series below 1/2 (where the closed
/// form cancels), Σ (−u)ⁿ/(n+2)!.
fn phi2(u: f64) -> f64 {
    if u < 0.5 {
        return phi2_series(u);
    }
    (u + (-u).exp_m1()) / (u * u)
}

fn phi2_series(u: f64) -> f64 {
    // 1/2 − u/6 + u²/24 − … = (1/2)(1 − (u/3)(1 − (u/4)(1 − …))).
    let mut s = 1.0;
    for n in (3..20).rev() {
        s = 1.0 - u / n as f64 * s;
    }
    0.5 * s
}

/// (I1, I1/h, I2/h) by their Taylor series, for (σ + √|λ|)·h ≤ 2. With
/// G_n = g⁽ⁿ⁾(0) hⁿ/n!: G_0 = 0, G_1 = h, G_{n+2} = −(2σh G_{n+1} + ω²h² G_n/(n+1))/(n+2),
/// I1/h = Σ G_n/(n+1), I2/h = h Σ G_n/((n+1)(n+2)).
/// 1/n and −1/n, so that the series multiply instead of dividing (three
/// divisions a term would dominate the cost of a step's coefficients).
pub(super) const INV: ([f64; 46], [f64; 46]) = {
    let (mut t, mut m) = ([0.0; 46], [0.0; 46]);
    let mut n = 1;
    while n < 46 {
        t[n] = 1.0 / n as f64;
        m[n] = -t[n];
        n += 1;
    }
    (t, m)
};

/// Terms of [`integrals_series`] at most (its n runs over 1..SERIES_END).
pub(super) const SERIES_END: usize = 42;

/// Where [`integrals_series`] stops: after the term at which its bound on
/// |G_n|/h falls below this.
pub(super) const SERIES_TOL: f64 = 1e-18;

fn integrals_series(mode: &Mode, h: f64) -> (f64, f64, f64) {
    let (inv, neg_inv) = INV;
    let (a, b) = (2.0 * mode.sigma * h, mode.w2 * h * h);
    let rh = mode.rate * h;
    let (mut gp, mut g) = (0.0, h); // G_{n−1}, G_n, n = 1
    let (mut s1, mut s2) = (h / 2.0, h / 6.0);
    // |G_n| ≤ h (rh)^{n−1}/(n−1)!.
    let mut bound = 1.0;
    for n in 1..SERIES_END {
        // −(…)/(n + 1) as (…)·(−1/(n + 1)): the same bits, one operation less
        // on the chain.
        let gn = (a * g + b * gp * inv[n]) * neg_inv[n + 1];
        (gp, g) = (g, gn);
        s1 += g * inv[n + 2];
        s2 += g * (inv[n + 2] * inv[n + 3]);
        bound *= rh * inv[n];
        if bound < SERIES_TOL {
            break;
        }
    }
    (s1 * h, s1, s2 * h)
}

/// Slots of the step table (a power of two).
const SLOTS: usize = 64;

/// Step coefficients for the step lengths a grid uses, in a small direct-mapped
/// table keyed by h's bits and compared exactly. np.linspace grids use some
/// twenty values a few ulps apart and change h at about every other step in no
/// regular pattern: a table lookup keeps the hot loop free of mispredicted
/// branches, and its loads stay off the q, v dependency chain.
struct Steps<'a> {
    pub(super) mode: &'a Mode,
    pub(super) inv_m: f64,
    pub(super) table: Box<[(f64, Step); SLOTS]>,
}

impl<'a> Steps<'a> {
    pub(super) fn new(mode: &'a Mode, inv_m: f64) -> Steps<'a> {
        Steps {
            mode,
            inv_m,
            table: Box::new([(f64::NAN, Step::IDENTITY); SLOTS]),
        }
    }

    /// The first slot of h's pair of slots.
    #[inline(always)]
    pub(super) fn slot(h: f64) -> usize {
        // Fibonacci hashing of the bits (the top bits of the product), 2-way
        // associative so that two frequent steps sharing a set do not thrash.
        let set = (h.to_bits().wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 59) as usize;
        (2 * set) & (SLOTS - 2)
    }

    /// The coefficients of the step h = t[k] − t[k−1].
    #[inline(always)]
    pub(super) fn get(&mut self, h: f64, t: &[f64], k: usize) -> Result<Step, ImpactError> {
        let i = Self::slot(h);
        let (key, st) = self.table[i];
        if key == h {
            return Ok(st);
        }
        let (key, st) = self.table[i + 1];
        if key == h {
            return Ok(st);
        }
        self.fill(h, t, k)
    }

    /// A new h: check it (the only way a bad time can show up, so the grid is
    /// checked for free) and compute its coefficients.
    #[cold]
    #[inline(never)]
    pub(super) fn fill(&mut self, h: f64, t: &[f64], k: usize) -> Result<Step, ImpactError> {
        if !step_ok(h) {
            return Err(time_error("t", t, k));
        }
        let st = Step::new(self.mode, h, self.inv_m);
        if !st.is_finite() {
            return Err(ImpactError::Range {
                h,
                omega_n: self.mode.omega,
                zeta: self.mode.zeta,
            });
        }
        // The set's newest entry first, its previous one second.
        let i = Self::slot(h);
        self.table[i + 1] = self.table[i];
        self.table[i] = (h, st);
        Ok(st)
    }
}

/// The recurrence over a checked grid; q_out[0] = q0 (and v_out[0] = v0).
#[allow(clippy::too_many_arguments)] // grid, force, oscillator, start, outputs
pub(super) fn run(
    t: &[f64],
    force: &[f64],
    mode: &Mode,
    inv_m: f64,
    q0: f64,
    v0: f64,
    q_out: &mut [f64],
    v_out: Option<&mut [f64]>,
) -> Result<(), ImpactError> {
    let mut steps = Steps::new(mode, inv_m);
    let arch = pulp::Arch::new();
    match v_out {
        None => arch.dispatch(RunLoop::<false> {
            t,
            force,
            steps: &mut steps,
            q0,
            v0,
            q_out,
            v_out: &mut [],
        }),
        Some(v_out) => arch.dispatch(RunLoop::<true> {
            t,
            force,
            steps: &mut steps,
            q0,
            v0,
            q_out,
            v_out,
        }),
    }
}

/// [`run`] for one case: by the chunked scan where it applies (see [`scan`]),
/// else (or if the scan meets anything to report) by the sequential loop,
/// which words the error.
#[allow(clippy::too_many_arguments)] // as run
fn run_one(
    t: &[f64],
    force: &[f64],
    mode: &Mode,
    inv_m: f64,
    q0: f64,
    v0: f64,
    q_out: &mut [f64],
    mut v_out: Option<&mut [f64]>,
) -> Result<(), ImpactError> {
    let done = match v_out.as_deref_mut() {
        None => scan::<false>(t, force, mode, inv_m, (q0, v0), q_out, &mut []),
        Some(v) => scan::<true>(t, force, mode, inv_m, (q0, v0), q_out, v),
    };
    if done {
        return Ok(());
    }
    run(t, force, mode, inv_m, q0, v0, q_out, v_out)
}

/// The hot loop: plain indexing over slices cut to one length (no bounds checks,
/// q and v stay in registers); coefficients are computed once per distinct h.
/// Run through a `pulp` dispatch so that [`Step::apply`]'s fused multiply-adds
/// are the processor's (AVX2 + FMA, AVX-512) rather than calls into libm.
struct RunLoop<'a, 'b, const WITH_V: bool> {
    t: &'b [f64],
    force: &'b [f64],
    steps: &'b mut Steps<'a>,
    q0: f64,
    v0: f64,
    q_out: &'b mut [f64],
    v_out: &'b mut [f64],
}

impl<const WITH_V: bool> pulp::WithSimd for RunLoop<'_, '_, WITH_V> {
    type Output = Result<(), ImpactError>;

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> Self::Output {
        let RunLoop {
            t,
            force,
            steps,
            q0,
            v0,
            q_out,
            v_out,
        } = self;
        run_loop::<WITH_V>(t, force, steps, q0, v0, q_out, v_out)
    }
}

#[inline(always)]
fn run_loop<const WITH_V: bool>(
    t: &[f64],
    force: &[f64],
    steps: &mut Steps<'_>,
    q0: f64,
    v0: f64,
    q_out: &mut [f64],
    v_out: &mut [f64],
) -> Result<(), ImpactError> {
    let n = t.len();
    let (force, q_out) = (&force[..n], &mut q_out[..n]);
    if n == 1 {
        // No step uses the only force: check it here.
        check_finite("force", force)?;
    }
    let v_out = if WITH_V { &mut v_out[..n] } else { v_out };
    q_out[0] = q0;
    if WITH_V {
        v_out[0] = v0;
    }
    let (mut q, mut v) = (q0, v0);
    for k in 1..n {
        let st = steps.get(t[k] - t[k - 1], t, k)?;
        (q, v) = st.apply(q, v, force[k - 1], force[k]);
        q_out[k] = q;
        if WITH_V {
            v_out[k] = v;
        }
    }
    // A non-finite force always leaves a non-finite state (0·NaN = NaN), so the
    // forces need a look only then.
    if q.is_finite() && v.is_finite() {
        return Ok(());
    }
    check_finite("force", force)?;
    Err(ImpactError::Overflow { time: t[n - 1] })
}

/// Response q(t[k]) (and q̇(t[k]) if `v_out` is given) of one oscillator to the
/// piecewise-linear force `force` sampled at `t`, from q(t[0]) = q0,
/// q̇(t[0]) = v0. `t` non-decreasing (repeated times are force jumps), every array
/// of the same length ≥ 1.
pub fn response_into(
    t: &[f64],
    force: &[f64],
    osc: &Oscillator,
    q0: f64,
    v0: f64,
    q_out: &mut [f64],
    v_out: Option<&mut [f64]>,
) -> Result<(), ImpactError> {
    osc.validate()?;
    finite("q0", q0)?;
    finite("v0", v0)?;
    let n = t.len();
    if n == 0 {
        return check_times("t", t);
    }
    length("force", force.len(), n, "one per time")?;
    length("q_out", q_out.len(), n, "one per time")?;
    if let Some(v) = &v_out {
        length("v_out", v.len(), n, "one per time")?;
    }
    // Every step and force is checked inside the recurrence (see run_loop).
    finite("t[0]", t[0])?;
    run_one(t, force, &osc.mode(), 1.0 / osc.mass, q0, v0, q_out, v_out)
}

/// Per-case parameters of a batch: ω, ζ, m, q0, v0, each of length B.
#[derive(Debug, Clone, Copy)]
pub struct Cases<'a> {
    pub omega_n: &'a [f64],
    pub zeta: &'a [f64],
    pub mass: &'a [f64],
    pub q0: &'a [f64],
    pub v0: &'a [f64],
}

impl Cases<'_> {
    /// B, after checking that the lengths agree.
    pub(super) fn len(&self) -> Result<usize, ImpactError> {
        let b = self.omega_n.len();
        let what = "one per case, like omega_n";
        length("zeta", self.zeta.len(), b, what)?;
        length("mass", self.mass.len(), b, what)?;
        length("q0", self.q0.len(), b, what)?;
        length("v0", self.v0.len(), b, what)?;
        Ok(b)
    }

    /// Case i checked: (mode, 1/m, q0, v0); errors name the case.
    pub(super) fn case(&self, i: usize) -> Result<(Mode, f64, f64, f64), ImpactError> {
        let osc = Oscillator {
            omega_n: self.omega_n[i],
            zeta: self.zeta[i],
            mass: self.mass[i],
        };
        osc.validate()
            .and_then(|_| finite("q0", self.q0[i]))
            .and_then(|_| finite("v0", self.v0[i]))
            .map_err(ImpactError::case(i))?;
        Ok((osc.mode(), 1.0 / osc.mass, self.q0[i], self.v0[i]))
    }
}

/// Cases per rayon task of at least this many steps.
const TASK_STEPS: usize = 16_384;

/// Cases the batch advances in lockstep: two AVX2 registers of f64, so that
/// the two dependent FMAs of one step of each case's (q, v) overlap across
/// lanes instead of waiting on each other.
pub(super) const LOCK: usize = 8;

// The lockstep loop transposes half tiles of LOCK lanes × HALF steps.
const _: () = assert!(LOCK == TILE);

/// Distinct step lengths above which a batch's grid is treated as ragged.
const MAX_DISTINCT: usize = 256;

/// A batch's shared grid: its distinct step lengths and, for each step
/// k = 1 … N−1, which of them it is (`which[k − 1]`). Each case's coefficients
/// are then worked out once per distinct h, outside the loop over steps.
pub(super) struct GridSteps {
    pub(super) hs: Vec<f64>,
    pub(super) which: Vec<u32>,
}

impl GridSteps {
    /// None for a grid of more than [`MAX_DISTINCT`] step lengths (each case
    /// then goes through its own table, see [`Steps`]). `t` is checked already.
    pub(super) fn new(t: &[f64]) -> Option<GridSteps> {
        // The step lengths seen, by their bits, in an open-addressed table at
        // most a quarter full (Fibonacci hashing, linear probing): a std
        // HashMap's SipHash cost ~0.1 ms a call on 10 000 steps.
        const BITS: u32 = 10;
        const SLOTS: usize = 1 << BITS;
        const _: () = assert!(SLOTS >= 4 * MAX_DISTINCT);
        let mut slots = vec![(0u64, u32::MAX); SLOTS];
        let (mut hs, mut which) = (Vec::new(), Vec::with_capacity(t.len().saturating_sub(1)));
        for w in t.windows(2) {
            let h = w[1] - w[0];
            let bits = h.to_bits();
            let mut s = (bits.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> (64 - BITS)) as usize;
            let i = loop {
                let (b, i) = slots[s];
                if i == u32::MAX {
                    if hs.len() == MAX_DISTINCT {
                        return None;
                    }
                    let fresh = hs.len() as u32;
                    slots[s] = (bits, fresh);
                    hs.push(h);
                    break fresh;
                }
                if b == bits {
                    break i;
                }
                s = (s + 1) % SLOTS;
            };
            which.push(i);
        }
        Some(GridSteps { hs, which })
    }
}

/// One distinct step's coefficients for the lanes of a lockstep group, in
/// [`Step`]'s field order. Aligned to 64 bytes so that each coefficient's
/// lanes are one cache line: the loop loads eight of them a step, and a load
/// across two lines costs two (8–11 % of the loop, in cache).
#[derive(Debug, Clone, Copy)]
#[repr(C, align(64))]
pub(super) struct LaneStep(pub(super) [[f64; LOCK]; 8]);

/// A lockstep group: LOCK cases on one grid, each lane the exact arithmetic of
/// [`Step::apply`] (so the results equal the single-case ones bit for bit).
pub(super) struct Lockstep<'a, 'b> {
    pub(super) which: &'a [u32],
    pub(super) coef: &'a [LaneStep],
    pub(super) forces: &'a [f64],
    pub(super) out: &'b mut [f64],
    pub(super) q0: [f64; LOCK],
    pub(super) v0: [f64; LOCK],
}

impl pulp::WithSimd for Lockstep<'_, '_> {
    /// The final (q, v) of each lane.
    type Output = ([f64; LOCK], [f64; LOCK]);

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, simd: S) -> Self::Output {
        let Lockstep {
            which,
            coef,
            forces,
            out,
            q0,
            v0,
        } = self;
        let n = which.len() + 1;
        let rows: [&[f64]; LOCK] = std::array::from_fn(|l| &forces[l * n..(l + 1) * n]);
        // The rows' outputs as an array, not a Vec: the loops over them below
        // unroll, and each tile's eight rows go from registers to memory (with a
        // Vec, the transposed tile went through the stack and a counted loop).
        let mut chunks = out.chunks_exact_mut(n);
        let outs: [&mut [f64]; LOCK] = std::array::from_fn(|_| chunks.next().unwrap_or_default());
        let (mut q, mut v) = (q0, v0);
        let mut f0: [f64; LOCK] = std::array::from_fn(|l| rows[l][0]);
        for l in 0..LOCK {
            outs[l][0] = q[l];
        }
        // One step of every lane: Step::apply's operations in its order (the
        // same fused multiply-adds), so the lanes equal the single-case loop.
        #[inline(always)]
        fn step(
            LaneStep(c): &LaneStep,
            q: &mut [f64; LOCK],
            v: &mut [f64; LOCK],
            f0: &[f64; LOCK],
            f1: &[f64; LOCK],
        ) {
            for l in 0..LOCK {
                let fq = c[4][l].mul_add(f0[l], c[6][l] * f1[l]);
                let fv = c[5][l].mul_add(f0[l], c[7][l] * f1[l]);
                let qn = c[0][l].mul_add(q[l], c[1][l].mul_add(v[l], fq));
                v[l] = c[2][l].mul_add(q[l], c[3][l].mul_add(v[l], fv));
                q[l] = qn;
            }
        }
        // Steps in half tiles of HALF columns: each row's HALF forces read, and
        // its HALF results written, as whole registers, the half tile
        // transposed in registers between rows and lanes. (Column by column,
        // the eight rows' loads and stores went one element at a time, at
        // eight addresses 80 KB apart: the loop's cost, not the arithmetic.)
        // Half tiles rather than 8 × 8 ones: the loop's registers (forces,
        // results, state) then fit in the 32 of AVX-512 and the row stores
        // cross a cache line less often; ~15 % faster. No `array::from_fn` in
        // the loop (see `tile::transpose_v3`).
        // Forces of columns c0..c0 + HALF, transposed to lanes. A function, not
        // a closure (see `tile::transpose_v3`).
        #[inline(always)]
        fn lanes<S: pulp::Simd>(simd: S, rows: &[&[f64]; LOCK], c0: usize) -> [[f64; LOCK]; HALF] {
            let mut fin = [[0.0; HALF]; LOCK];
            for l in 0..LOCK {
                fin[l] = rows[l][c0..c0 + HALF].try_into().unwrap();
            }
            transpose_in(simd, &fin)
        }
        let tiles = (n - 1) / HALF;
        // Each half tile's forces are read one half tile ahead, so that their
        // loads and shuffles are not queued behind the steps that need them
        // (3–5 % out of cache).
        let mut ahead = [[0.0; LOCK]; HALF];
        if tiles > 0 {
            ahead = lanes(simd, &rows, 1);
        }
        for j in 0..tiles {
            let c0 = 1 + j * HALF;
            // One bounds check for the half tile's step indices.
            let w: &[u32; HALF] = which[c0 - 1..c0 - 1 + HALF].try_into().unwrap();
            let ft = ahead;
            if j + 1 < tiles {
                ahead = lanes(simd, &rows, c0 + HALF);
            }
            let mut qt = [[0.0; LOCK]; HALF];
            for i in 0..HALF {
                step(&coef[w[i] as usize], &mut q, &mut v, &f0, &ft[i]);
                qt[i] = q;
                f0 = ft[i];
            }
            let qo = transpose_out(simd, &qt);
            for l in 0..LOCK {
                outs[l][c0..c0 + HALF].copy_from_slice(&qo[l]);
            }
        }
        for k in 1 + tiles * HALF..n {
            let f1: [f64; LOCK] = std::array::from_fn(|l| rows[l][k]);
            step(&coef[which[k - 1] as usize], &mut q, &mut v, &f0, &f1);
            for l in 0..LOCK {
                outs[l][k] = q[l];
            }
            f0 = f1;
        }
        (q, v)
    }
}

/// Responses of B oscillators to B forces (B, N) row-major on one grid `t` (N,):
/// q_out (B, N). Errors name the case (row) and, for forces, the column; with
/// several bad cases, the lowest row's error.
///
/// Cases run LOCK at a time in lockstep (one vector lane each) where the grid
/// has at most [`MAX_DISTINCT`] step lengths; the rest, and any group with a
/// bad case, go one by one, which also words the error.
pub fn response_batch_into(
    t: &[f64],
    forces: &[f64],
    cases: &Cases<'_>,
    n_threads: Option<i64>,
    q_out: &mut [f64],
) -> Result<(), ImpactError> {
    check_times("t", t)?;
    let (b, n) = (cases.len()?, t.len());
    length("forces", forces.len(), b * n, "B*N: one row of N per case")?;
    length("q_out", q_out.len(), b * n, "B*N")?;
    let one = |i: usize, f: &[f64], qo: &mut [f64]| -> Result<(), ImpactError> {
        let (mode, inv_m, q0, v0) = cases.case(i)?;
        run(t, f, &mode, inv_m, q0, v0, qo, None).map_err(ImpactError::case(i))
    };
    let grid = if n >= 2 { GridSteps::new(t) } else { None };
    // Rows first..first+rows of the batch: in lockstep if the grid allows and
    // every case of the group is sound, else one by one.
    let group = |first: usize, f: &[f64], qo: &mut [f64]| -> Result<(), ImpactError> {
        let rows = f.len() / n.max(1);
        let sound = match &grid {
            Some(g) if rows == LOCK => lockstep(g, cases, first, f, qo),
            _ => false,
        };
        if sound {
            return Ok(());
        }
        for (j, (fr, qr)) in f.chunks(n).zip(qo.chunks_mut(n)).enumerate() {
            one(first + j, fr, qr)?;
        }
        Ok(())
    };
    if n == 0 || b == 0 {
        return Ok(());
    }
    let threads = resolve_threads(n_threads)?;
    let span = LOCK * n;
    if threads == 1 || b <= LOCK {
        for (g, (f, qo)) in forces.chunks(span).zip(q_out.chunks_mut(span)).enumerate() {
            if crate::cancel::requested() {
                return Ok(());
            }
            group(g * LOCK, f, qo)?;
        }
        return Ok(());
    }
    let first_error = pool(threads)?.install(|| {
        forces
            .par_chunks(span)
            .zip(q_out.par_chunks_mut(span))
            .enumerate()
            .with_min_len(TASK_STEPS.div_ceil(span))
            .filter_map(|(g, (f, qo))| {
                if crate::cancel::requested() {
                    return None;
                }
                group(g * LOCK, f, qo).err().map(|e| (g, e))
            })
            .min_by_key(|(g, _)| *g)
    });
    match first_error {
        Some((_, e)) => Err(e),
        None => Ok(()),
    }
}

/// Rows first..first+LOCK in lockstep; false (output to be redone) if a case
/// is invalid, a coefficient not finite, or a final state not finite (a bad
/// force), so that the one-by-one path reports it.
fn lockstep(grid: &GridSteps, cases: &Cases<'_>, first: usize, f: &[f64], qo: &mut [f64]) -> bool {
    let Some((coef, q0, v0)) = lane_steps(grid, cases, first) else {
        return false;
    };
    let (q, v) = pulp::Arch::new().dispatch(Lockstep {
        which: &grid.which,
        coef: &coef,
        forces: f,
        out: qo,
        q0,
        v0,
    });
    q.iter().chain(&v).all(|x| x.is_finite())
}

/// The lockstep inputs of cases first..first+LOCK: each distinct step's
/// coefficients per lane (bit for bit [`Step::new`]'s, see [`LaneCoef`]), and
/// each lane's (q0, v0); None if a case is invalid or a coefficient not finite.
pub(super) fn lane_steps(
    grid: &GridSteps,
    cases: &Cases<'_>,
    first: usize,
) -> Option<(Vec<LaneStep>, [f64; LOCK], [f64; LOCK])> {
    let (mut q0, mut v0, mut inv_m) = ([0.0; LOCK], [0.0; LOCK], [0.0; LOCK]);
    let mut modes = [Mode::new(1.0, 0.0); LOCK];
    for l in 0..LOCK {
        (modes[l], inv_m[l], q0[l], v0[l]) = cases.case(first + l).ok()?;
    }
    let mut coef = vec![LaneStep([[0.0; LOCK]; 8]); grid.hs.len()];
    let finite = pulp::Arch::new().dispatch(LaneCoef {
        modes: &modes,
        inv_m: &inv_m,
        hs: &grid.hs,
        coef: &mut coef,
    });
    finite.then_some((coef, q0, v0))
}
