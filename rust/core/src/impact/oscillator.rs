//! Stop impact (seed 000, §1): the forced oscillator behind the Duhamel integral,
//! the first rebound after a force pulse, and a link hitting its stop as a
//! unilateral contact.
//!
//! **Forced oscillator.** m q̈ + 2ζω m q̇ + m ω² q = F(t), ω = `omega_n` [rad/s] > 0,
//! ζ = `zeta` ≥ 0 (any value: under-, critically and over-damped are all exact),
//! m = `mass` > 0; q and F in consistent units (m and N, or rad and N·m with m a
//! moment of inertia). F is piecewise linear between its samples (first-order
//! hold) and held at its last value after the last sample. A repeated time
//! (t[k+1] = t[k]) is a jump of the force at that instant: how a pulse table ends
//! a rectangular pulse. Over a step h = t[k+1] − t[k] the state x = (q, q̇) moves
//! exactly (Nigam–Jennings):
//!
//! ```text
//! x[k+1] = Φ(h) x[k] + Γ0(h) F[k] + Γ1(h) F[k+1]
//! Φ  = e^{−σh} [[C + σS, S], [−ω²S, C − σS]]
//! Γ1 = [I2/h, I1/h] / m,   Γ0 = [I1 − I2/h, e^{−σh} S − I1/h] / m
//! ```
//!
//! with σ = ζω, λ = ω² − σ² = ω²(1 − ζ)(1 + ζ), C = cos(√λ h), S = sin(√λ h)/√λ
//! (cosh and sinh/√−λ when λ < 0; 1 and h when λ = 0; a series when |λ|h² ≤ 1, so
//! that every coefficient is continuous across ζ = 1), and I1 = ∫₀ʰ g,
//! I2 = ∫₀ʰ (h − τ) g(τ) dτ the integrals of the unit impulse response
//! g(τ) = e^{−στ} S(τ) (by their Taylor series when (σ + √|λ|)·h ≤ 2, where the
//! closed forms would cancel). This is the Duhamel integral of seed 000 (eq. 2)
//! evaluated exactly for a piecewise-linear force: no quadrature error.
//!
//! **First rebound.** The first local extremum of q after t[0]: the first instant
//! t > t[0] at which q̇ = 0 after q̇ has been non-zero (if q̇(t[0]) = 0, after it
//! first moves). Generically q̇ changes sign there; a touch (q̇ = 0 without a sign
//! change, a non-generic case) counts too. It is found segment by segment: inside a
//! segment with a linear force, q̇ = c + e^{−σs}(…) with c = slope/(mω²), the zeros
//! of q̈ are in closed form and q̇ is monotone between them, so the first crossing
//! is bracketed and solved by safeguarded Newton steps to rounding; after the last
//! sample (constant force) it is in closed form. If q̇ never returns to zero (an
//! over-damped creep), the result is time = +∞ and q = F[last]/(mω²), the limit.
//!
//! **Contact oscillator.** A link of mass m at x meets its stop at x = 0: free for
//! x > 0 (restoring force −k_f (x + δ), preload δ ≥ 0: at rest the link presses on
//! the stop with k_f δ), in contact for x < 0 (−k_f (x + δ) − k_s x: stiffness
//! k_c = k_f + k_s about x_c = −k_f δ / k_c). Each regime has its own damping ratio
//! relative to its own stiffness (c = 2ζ√(k m)). Each regime is an unforced
//! oscillator about its equilibrium, so its motion is in closed form and each
//! crossing of x = 0 is bracketed between closed-form extrema and solved to
//! rounding: an exact event-driven history.

use std::f64::consts::{FRAC_PI_2, PI};

use rayon::prelude::*;

use crate::geom::sin_cos;
use crate::parallel::{pool, resolve_threads, ThreadsError};

/// Events a contact history follows by default before it reports chattering.
pub const MAX_EVENTS: usize = 10_000;

/// Errors of the impact domain.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DuhamelError {
    #[error("{field} must be {want}; got {value}")]
    Param {
        field: &'static str,
        value: f64,
        want: &'static str,
    },
    #[error("{field} must be {want}; got {value}")]
    Count {
        field: &'static str,
        value: i64,
        want: &'static str,
    },
    #[error("{field} must be a C-contiguous float64 array")]
    Layout { field: &'static str },
    #[error("{field}[{index}] must be finite; got {value}")]
    NotFinite {
        field: &'static str,
        index: usize,
        value: f64,
    },
    #[error(
        "{field} must be non-decreasing (a repeated time is a jump of the force); \
         got {field}[{index}] = {value} after {field}[{prev_index}] = {prev}"
    )]
    Decreasing {
        field: &'static str,
        index: usize,
        value: f64,
        prev_index: usize,
        prev: f64,
    },
    #[error(
        "{field}[{index}] - {field}[{prev_index}] = {value} - {prev} overflows; \
         times must differ by a finite amount"
    )]
    StepOverflow {
        field: &'static str,
        index: usize,
        value: f64,
        prev_index: usize,
        prev: f64,
    },
    #[error("{field} must have {want}; got {got}")]
    Length {
        field: &'static str,
        got: usize,
        want: String,
    },
    #[error(
        "a step h = {h} with omega_n = {omega_n} and zeta = {zeta} gives non-finite \
         coefficients; rescale time so that omega_n*h and zeta*omega_n*h stay below ~1e150"
    )]
    Range { h: f64, omega_n: f64, zeta: f64 },
    #[error(
        "the response overflows f64 (q or v is not finite at t = {time}); \
         forces or initial values are too large"
    )]
    Overflow { time: f64 },
    #[error("case {row}: {error}")]
    Case {
        row: usize,
        error: Box<DuhamelError>,
    },
    #[error(
        "the link chatters: more than max_events = {max_events} contact events before \
         t = {time}; raise max_events or sample a shorter time"
    )]
    TooManyEvents { max_events: usize, time: f64 },
    #[error(
        "the first-rebound search stopped advancing at t = {time} (q̇ stays within \
         rounding of zero); refine or rescale the pulse table"
    )]
    Stalled { time: f64 },
    #[error("{0}")]
    Threads(#[from] ThreadsError),
}

impl DuhamelError {
    fn case(row: usize) -> impl Fn(DuhamelError) -> DuhamelError {
        move |e| DuhamelError::Case {
            row,
            error: Box::new(e),
        }
    }
}

fn param(
    field: &'static str,
    value: f64,
    ok: bool,
    want: &'static str,
) -> Result<(), DuhamelError> {
    if ok && value.is_finite() {
        Ok(())
    } else {
        Err(DuhamelError::Param { field, value, want })
    }
}

/// The range of natural frequencies ω [rad/s] and damping rates ζω [1/s] the
/// closed forms hold in: ω², (ζω)², 1/ω² and the ramp's c = slope/(mω²) stay
/// finite with room to spare. Outside it the coefficients overflow or vanish and
/// the searches cannot advance; rescale time instead.
pub const MODE_RANGE: (f64, f64) = (1e-150, 1e150);

fn mode_range(field: &'static str, omega: f64, zeta: f64) -> Result<(), DuhamelError> {
    let (lo, hi) = MODE_RANGE;
    param(
        field,
        omega,
        (lo..=hi).contains(&omega),
        "within [1e-150, 1e150] rad/s (rescale time)",
    )?;
    let rate = zeta * omega;
    param(
        "zeta * omega",
        rate,
        rate <= hi,
        "<= 1e150 1/s (rescale time or lower the damping ratio)",
    )
}

fn finite(field: &'static str, value: f64) -> Result<(), DuhamelError> {
    param(field, value, true, "finite")
}

fn length(field: &'static str, got: usize, want: usize, what: &str) -> Result<(), DuhamelError> {
    if got == want {
        Ok(())
    } else {
        Err(DuhamelError::Length {
            field,
            got,
            want: format!("{want} entries ({what})"),
        })
    }
}

/// Every value finite (one vectorised pass; the index only on failure).
fn check_finite(field: &'static str, x: &[f64]) -> Result<(), DuhamelError> {
    // An OR of flags, unlike a float sum, is associative: LLVM vectorises it.
    if x.iter().fold(0u8, |a, v| a | u8::from(!v.is_finite())) == 0 {
        return Ok(());
    }
    let index = x.iter().position(|v| !v.is_finite()).unwrap_or(0);
    Err(DuhamelError::NotFinite {
        field,
        index,
        value: x[index],
    })
}

/// A time grid: at least one time, all finite, non-decreasing, finite steps.
fn check_times(field: &'static str, t: &[f64]) -> Result<(), DuhamelError> {
    if t.is_empty() {
        return Err(DuhamelError::Length {
            field,
            got: 0,
            want: "at least 1 entry".into(),
        });
    }
    check_finite(field, t)?;
    match t.windows(2).position(|w| !step_ok(w[1] - w[0])) {
        None => Ok(()),
        Some(i) => Err(time_error(field, t, i + 1)),
    }
}

#[inline(always)]
fn step_ok(h: f64) -> bool {
    h >= 0.0 && h.is_finite()
}

/// Why the step t[k] − t[k−1] is not a valid step.
#[cold]
fn time_error(field: &'static str, t: &[f64], k: usize) -> DuhamelError {
    for index in [k - 1, k] {
        if !t[index].is_finite() {
            return DuhamelError::NotFinite {
                field,
                index,
                value: t[index],
            };
        }
    }
    let (index, value, prev_index, prev) = (k, t[k], k - 1, t[k - 1]);
    if value < prev {
        DuhamelError::Decreasing {
            field,
            index,
            value,
            prev_index,
            prev,
        }
    } else {
        DuhamelError::StepOverflow {
            field,
            index,
            value,
            prev_index,
            prev,
        }
    }
}

/// The forced oscillator: ω = `omega_n` [rad/s], ζ = `zeta`, m = `mass`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Oscillator {
    pub omega_n: f64,
    pub zeta: f64,
    pub mass: f64,
}

impl Oscillator {
    /// A checked oscillator.
    pub fn new(omega_n: f64, zeta: f64, mass: f64) -> Result<Oscillator, DuhamelError> {
        let o = Oscillator {
            omega_n,
            zeta,
            mass,
        };
        o.validate()?;
        Ok(o)
    }

    /// ω finite and > 0, ζ finite and ≥ 0, m finite and > 0.
    pub fn validate(&self) -> Result<(), DuhamelError> {
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

    fn mode(&self) -> Mode {
        Mode::new(self.omega_n, self.zeta)
    }
}

/// The unforced oscillator y'' + 2σy' + ω²y = 0 in the forms the kernels use.
#[derive(Debug, Clone, Copy)]
struct Mode {
    omega: f64,
    zeta: f64,
    /// σ = ζω.
    sigma: f64,
    /// ω².
    w2: f64,
    /// λ = ω² − σ²: > 0 under-damped, < 0 over-damped.
    lambda: f64,
    /// √|λ|: the damped frequency ωd (λ > 0) or κ (λ < 0).
    k: f64,
    /// The slow decay rate σ − κ = ω²/(σ + κ) of an over-damped mode (else σ).
    slow: f64,
    /// σ + √|λ|, a bound on |eigenvalue|: the scale of the Taylor series.
    rate: f64,
    /// Clearly over-damped (κ ≥ σ/2, ζ ≥ 2/√3): the two real decay rates
    /// a = σ − κ and b = σ + κ are far apart, and the forms in e^{−aτ}, e^{−bτ}
    /// avoid the cancellation of σS against C that grows like ζ².
    split: bool,
}

/// cos(√−u)-type and sin(√−u)/√−u-type series for |u| ≤ 1:
/// (Σ uⁿ/(2n)!, Σ uⁿ/(2n+1)!), to 1/24! (below rounding).
#[inline(always)]
fn cs_series(u: f64) -> (f64, f64) {
    // Nested form: 1 + u/(1·2)(1 + u/(3·4)(1 + …)).
    const DC: [f64; 11] = [
        2.0, 12.0, 30.0, 56.0, 90.0, 132.0, 182.0, 240.0, 306.0, 380.0, 462.0,
    ];
    const DS: [f64; 11] = [
        6.0, 20.0, 42.0, 72.0, 110.0, 156.0, 210.0, 272.0, 342.0, 420.0, 506.0,
    ];
    let (mut c, mut s) = (1.0, 1.0);
    for i in (0..11).rev() {
        c = 1.0 + u / DC[i] * c;
        s = 1.0 + u / DS[i] * s;
    }
    (c, s)
}

#[inline]
fn sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

impl Mode {
    fn new(omega: f64, zeta: f64) -> Mode {
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

    fn underdamped(&self) -> bool {
        self.lambda > 0.0 && self.k > 0.0
    }

    /// (e^{−στ}C(τ), e^{−στ}S(τ)) without overflow for large τ and continuous in ζ.
    #[inline]
    fn ecs(&self, tau: f64) -> (f64, f64) {
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
    fn phi(&self, tau: f64) -> (f64, f64, f64) {
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
    fn eval(&self, y0: f64, y1: f64, tau: f64) -> (f64, f64) {
        let (p00, p01, p11) = self.phi(tau);
        (p00 * y0 + p01 * y1, p11 * y1 - self.w2 * p01 * y0)
    }

    /// The first τ > 0 at which the unforced motion from y(0) = y0,
    /// y'(0) = y1 is zero, in closed form (an atan, or an atanh when over-damped);
    /// None if it never is. Its zeros are where C y0 + S (σ y0 + y1) = 0.
    fn first_zero(&self, y0: f64, y1: f64) -> Option<f64> {
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
    fn crossing(&self, y0: f64, y1: f64, level: f64, side: f64, touch: bool) -> Option<f64> {
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
    fn extremum(&self, y0: f64, y1: f64, max: bool) -> Option<(f64, f64)> {
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
struct Step {
    p00: f64,
    p01: f64,
    p10: f64,
    p11: f64,
    g0q: f64,
    g0v: f64,
    g1q: f64,
    g1v: f64,
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

    fn new(mode: &Mode, h: f64, inv_m: f64) -> Step {
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

    fn is_finite(&self) -> bool {
        [
            self.p00, self.p01, self.p10, self.p11, self.g0q, self.g0v, self.g1q, self.g1v,
        ]
        .iter()
        .all(|c| c.is_finite())
    }

    /// (q, v) after the step from (q, v) with forces f0 → f1.
    #[inline(always)]
    fn apply(&self, q: f64, v: f64, f0: f64, f1: f64) -> (f64, f64) {
        let fq = self.g0q * f0 + self.g1q * f1;
        let fv = self.g0v * f0 + self.g1v * f1;
        (
            self.p00 * q + (self.p01 * v + fq),
            self.p10 * q + (self.p11 * v + fv),
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
fn integrals_series(mode: &Mode, h: f64) -> (f64, f64, f64) {
    // 1/n, so that the loop multiplies instead of dividing (three divisions a
    // term would dominate the cost of a step's coefficients).
    const INV: [f64; 46] = {
        let mut t = [0.0; 46];
        let mut n = 1;
        while n < 46 {
            t[n] = 1.0 / n as f64;
            n += 1;
        }
        t
    };
    let (a, b) = (2.0 * mode.sigma * h, mode.w2 * h * h);
    let rh = mode.rate * h;
    let (mut gp, mut g) = (0.0, h); // G_{n−1}, G_n, n = 1
    let (mut s1, mut s2) = (h / 2.0, h / 6.0);
    // |G_n| ≤ h (rh)^{n−1}/(n−1)!.
    let mut bound = 1.0;
    for n in 1..42 {
        let gn = -(a * g + b * gp * INV[n]) * INV[n + 1];
        (gp, g) = (g, gn);
        s1 += g * INV[n + 2];
        s2 += g * (INV[n + 2] * INV[n + 3]);
        bound *= rh * INV[n];
        if bound < 1e-18 {
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
    mode: &'a Mode,
    inv_m: f64,
    table: Box<[(f64, Step); SLOTS]>,
}

impl<'a> Steps<'a> {
    fn new(mode: &'a Mode, inv_m: f64) -> Steps<'a> {
        Steps {
            mode,
            inv_m,
            table: Box::new([(f64::NAN, Step::IDENTITY); SLOTS]),
        }
    }

    /// The first slot of h's pair of slots.
    #[inline(always)]
    fn slot(h: f64) -> usize {
        // Fibonacci hashing of the bits (the top bits of the product), 2-way
        // associative so that two frequent steps sharing a set do not thrash.
        let set = (h.to_bits().wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 59) as usize;
        (2 * set) & (SLOTS - 2)
    }

    /// The coefficients of the step h = t[k] − t[k−1].
    #[inline(always)]
    fn get(&mut self, h: f64, t: &[f64], k: usize) -> Result<Step, DuhamelError> {
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
    fn fill(&mut self, h: f64, t: &[f64], k: usize) -> Result<Step, DuhamelError> {
        if !step_ok(h) {
            return Err(time_error("t", t, k));
        }
        let st = Step::new(self.mode, h, self.inv_m);
        if !st.is_finite() {
            return Err(DuhamelError::Range {
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
fn run(
    t: &[f64],
    force: &[f64],
    mode: &Mode,
    inv_m: f64,
    q0: f64,
    v0: f64,
    q_out: &mut [f64],
    v_out: Option<&mut [f64]>,
) -> Result<(), DuhamelError> {
    let mut steps = Steps::new(mode, inv_m);
    match v_out {
        None => run_loop::<false>(t, force, &mut steps, q0, v0, q_out, &mut []),
        Some(v_out) => run_loop::<true>(t, force, &mut steps, q0, v0, q_out, v_out),
    }
}

/// The hot loop: plain indexing over slices cut to one length (no bounds checks,
/// q and v stay in registers); coefficients are computed once per distinct h.
#[inline(never)]
fn run_loop<const WITH_V: bool>(
    t: &[f64],
    force: &[f64],
    steps: &mut Steps<'_>,
    q0: f64,
    v0: f64,
    q_out: &mut [f64],
    v_out: &mut [f64],
) -> Result<(), DuhamelError> {
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
    Err(DuhamelError::Overflow { time: t[n - 1] })
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
) -> Result<(), DuhamelError> {
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
    run(t, force, &osc.mode(), 1.0 / osc.mass, q0, v0, q_out, v_out)
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
    fn len(&self) -> Result<usize, DuhamelError> {
        let b = self.omega_n.len();
        let what = "one per case, like omega_n";
        length("zeta", self.zeta.len(), b, what)?;
        length("mass", self.mass.len(), b, what)?;
        length("q0", self.q0.len(), b, what)?;
        length("v0", self.v0.len(), b, what)?;
        Ok(b)
    }

    /// Case i checked: (mode, 1/m, q0, v0); errors name the case.
    fn case(&self, i: usize) -> Result<(Mode, f64, f64, f64), DuhamelError> {
        let osc = Oscillator {
            omega_n: self.omega_n[i],
            zeta: self.zeta[i],
            mass: self.mass[i],
        };
        osc.validate()
            .and_then(|_| finite("q0", self.q0[i]))
            .and_then(|_| finite("v0", self.v0[i]))
            .map_err(DuhamelError::case(i))?;
        Ok((osc.mode(), 1.0 / osc.mass, self.q0[i], self.v0[i]))
    }
}

/// Cases per rayon task of at least this many steps.
const TASK_STEPS: usize = 16_384;

/// Cases the batch advances in lockstep: two AVX2 registers of f64, so that
/// the two dependent FMAs of one step of each case's (q, v) overlap across
/// lanes instead of waiting on each other.
const LOCK: usize = 8;

/// Distinct step lengths above which a batch's grid is treated as ragged.
const MAX_DISTINCT: usize = 256;

/// A batch's shared grid: its distinct step lengths and, for each step
/// k = 1 … N−1, which of them it is (`which[k − 1]`). Each case's coefficients
/// are then worked out once per distinct h, outside the loop over steps.
struct GridSteps {
    hs: Vec<f64>,
    which: Vec<u32>,
}

impl GridSteps {
    /// None for a grid of more than [`MAX_DISTINCT`] step lengths (each case
    /// then goes through its own table, see [`Steps`]). `t` is checked already.
    fn new(t: &[f64]) -> Option<GridSteps> {
        let mut seen = std::collections::HashMap::new();
        let (mut hs, mut which) = (Vec::new(), Vec::with_capacity(t.len().saturating_sub(1)));
        for w in t.windows(2) {
            let h = w[1] - w[0];
            let fresh = hs.len() as u32;
            let i = *seen.entry(h.to_bits()).or_insert(fresh);
            if i == fresh {
                if hs.len() == MAX_DISTINCT {
                    return None;
                }
                hs.push(h);
            }
            which.push(i);
        }
        Some(GridSteps { hs, which })
    }
}

/// One distinct step's coefficients for the lanes of a lockstep group, in
/// [`Step`]'s field order.
type LaneStep = [[f64; LOCK]; 8];

/// A lockstep group: LOCK cases on one grid, each lane the exact arithmetic of
/// [`Step::apply`] (so the results equal the single-case ones bit for bit).
struct Lockstep<'a, 'b> {
    which: &'a [u32],
    coef: &'a [LaneStep],
    forces: &'a [f64],
    out: &'b mut [f64],
    q0: [f64; LOCK],
    v0: [f64; LOCK],
}

impl pulp::WithSimd for Lockstep<'_, '_> {
    /// The final (q, v) of each lane.
    type Output = ([f64; LOCK], [f64; LOCK]);

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> Self::Output {
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
        let mut outs: Vec<&mut [f64]> = out.chunks_exact_mut(n).collect();
        let (mut q, mut v) = (q0, v0);
        let mut f0: [f64; LOCK] = std::array::from_fn(|l| rows[l][0]);
        for (l, o) in outs.iter_mut().enumerate() {
            o[0] = q[l];
        }
        for (k, &w) in (1..n).zip(which) {
            let c = &coef[w as usize];
            let f1: [f64; LOCK] = std::array::from_fn(|l| rows[l][k]);
            for l in 0..LOCK {
                let fq = c[4][l] * f0[l] + c[6][l] * f1[l];
                let fv = c[5][l] * f0[l] + c[7][l] * f1[l];
                let qn = c[0][l] * q[l] + (c[1][l] * v[l] + fq);
                v[l] = c[2][l] * q[l] + (c[3][l] * v[l] + fv);
                q[l] = qn;
            }
            for (l, o) in outs.iter_mut().enumerate() {
                o[k] = q[l];
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
) -> Result<(), DuhamelError> {
    check_times("t", t)?;
    let (b, n) = (cases.len()?, t.len());
    length("forces", forces.len(), b * n, "B*N: one row of N per case")?;
    length("q_out", q_out.len(), b * n, "B*N")?;
    let one = |i: usize, f: &[f64], qo: &mut [f64]| -> Result<(), DuhamelError> {
        let (mode, inv_m, q0, v0) = cases.case(i)?;
        run(t, f, &mode, inv_m, q0, v0, qo, None).map_err(DuhamelError::case(i))
    };
    let grid = if n >= 2 { GridSteps::new(t) } else { None };
    // Rows first..first+rows of the batch: in lockstep if the grid allows and
    // every case of the group is sound, else one by one.
    let group = |first: usize, f: &[f64], qo: &mut [f64]| -> Result<(), DuhamelError> {
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
            .filter_map(|(g, (f, qo))| group(g * LOCK, f, qo).err().map(|e| (g, e)))
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
/// coefficients per lane, and each lane's (q0, v0); None if a case is invalid or
/// a coefficient not finite.
fn lane_steps(
    grid: &GridSteps,
    cases: &Cases<'_>,
    first: usize,
) -> Option<(Vec<LaneStep>, [f64; LOCK], [f64; LOCK])> {
    let mut coef = vec![[[0.0; LOCK]; 8]; grid.hs.len()];
    let (mut q0, mut v0) = ([0.0; LOCK], [0.0; LOCK]);
    for l in 0..LOCK {
        let (mode, inv_m, q, v) = cases.case(first + l).ok()?;
        (q0[l], v0[l]) = (q, v);
        for (c, &h) in coef.iter_mut().zip(&grid.hs) {
            let st = Step::new(&mode, h, inv_m);
            if !st.is_finite() {
                return None;
            }
            let all = [
                st.p00, st.p01, st.p10, st.p11, st.g0q, st.g0v, st.g1q, st.g1v,
            ];
            for (cj, x) in c.iter_mut().zip(all) {
                cj[l] = x;
            }
        }
    }
    Some((coef, q0, v0))
}

/// The first extremum of q after t[0]: its time [s] (+∞ if none) and signed q.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rebound {
    pub time: f64,
    pub q: f64,
}

/// The first rebound of one oscillator driven by the pulse table (t, force) from
/// q(t[0]) = q0, q̇(t[0]) = v0; the force is held at its last value after t[last].
pub fn first_rebound(
    t: &[f64],
    force: &[f64],
    osc: &Oscillator,
    q0: f64,
    v0: f64,
) -> Result<Rebound, DuhamelError> {
    first_turn(t, force, osc, q0, v0, false)
}

/// [`first_rebound`], or with `maximum` the first local maximum of q (minima
/// passed over): the rebound of a link that first presses into its stop.
pub fn first_turn(
    t: &[f64],
    force: &[f64],
    osc: &Oscillator,
    q0: f64,
    v0: f64,
    maximum: bool,
) -> Result<Rebound, DuhamelError> {
    osc.validate()?;
    finite("q0", q0)?;
    finite("v0", v0)?;
    check_times("t", t)?;
    length("force", force.len(), t.len(), "one per time")?;
    check_finite("force", force)?;
    rebound(t, force, &osc.mode(), 1.0 / osc.mass, q0, v0, maximum)
}

/// The direction q̇ leaves 0 in, from q̇ = v, q̈ = a and the force's quasi-static
/// velocity c (q̇ ≈ c ω² s²/2 when v = a = 0).
fn start_sign(v: f64, a: f64, c: f64) -> f64 {
    if v != 0.0 {
        sign(v)
    } else if a != 0.0 {
        sign(a)
    } else {
        sign(c)
    }
}

fn rebound(
    t: &[f64],
    force: &[f64],
    mode: &Mode,
    inv_m: f64,
    q0: f64,
    v0: f64,
    maximum: bool,
) -> Result<Rebound, DuhamelError> {
    let (sig, w2) = (mode.sigma, mode.w2);
    let (mut q, mut v) = (q0, v0);
    // The sign q̇ has had since it became non-zero (0: not moving yet).
    let mut s = sign(v0);
    // Is a turn with q̇ of sign `s` before it the one wanted? (With `maximum`,
    // minima are passed over.)
    let wanted = |s: f64| !maximum || s > 0.0;
    let range = |h| DuhamelError::Range {
        h,
        omega_n: mode.omega,
        zeta: mode.zeta,
    };
    for (tw, fw) in t.windows(2).zip(force.windows(2)) {
        let h = tw[1] - tw[0];
        if h == 0.0 {
            continue; // a jump of the force: the state is unchanged
        }
        let slope = (fw[1] - fw[0]) / h;
        // The segment from (t_a, f_a) to its end; t_a moves past passed-over minima.
        let (mut t_a, mut f_a) = (tw[0], fw[0]);
        let mut passed = 0;
        loop {
            let rest = tw[1] - t_a;
            let (p0, p1) = (f_a * inv_m, slope * inv_m);
            // q̇(τ) = c + y(τ), y unforced with y(0) = v − c, y'(0) = q̈(0).
            let c = p1 / w2;
            let a0 = p0 - 2.0 * sig * v - w2 * q;
            if s == 0.0 {
                s = start_sign(v, a0, c);
                if s == 0.0 {
                    // At rest under a constant force (q̇ = q̈ = 0, c = 0): exactly
                    // so to the segment's end; stepping would only add rounding noise.
                    break;
                }
            }
            // q̇ = c + y loses the digits of c: where those are most of q̇'s own
            // size over the segment (a steep ramp over a short step), the closed
            // form's zero is rounding noise; bracket q̇ by exact steps instead.
            let h = rest.min(1.0 / mode.rate.max(mode.omega));
            let noise = 32.0 * f64::EPSILON * ((v - c).abs() + a0.abs() / mode.omega + c.abs());
            let size = v.abs() + a0.abs() * h + 0.5 * p1.abs() * h * h;
            let turn = if noise > 1e-6 * size {
                stepped_turn(mode, inv_m, (q, v), (f_a, slope), rest, s)
            } else {
                mode.crossing(v - c, a0, -c, s, true).filter(|&x| x <= rest)
            };
            if let Some(tau) = turn {
                let f_tau = f_a + slope * tau;
                let (qt, _) = Step::new(mode, tau, inv_m).apply(q, v, f_a, f_tau);
                if wanted(s) {
                    return Ok(Rebound {
                        time: t_a + tau,
                        q: qt,
                    });
                }
                // A minimum: go on from it, q̇ = 0 there, its new sign from q̈.
                // Between two minima lies a maximum, which is wanted, so a segment
                // passes over at most one minimum; a second one would be rounding
                // that stops time from advancing: an error, never a hang.
                passed += 1;
                if passed > MAX_PASSED || t_a + tau <= t_a {
                    return Err(DuhamelError::Stalled { time: t_a });
                }
                (q, v, s) = (qt, 0.0, 0.0);
                (t_a, f_a) = (t_a + tau, f_tau);
                continue;
            }
            let st = Step::new(mode, rest, inv_m);
            if !st.is_finite() {
                return Err(range(rest));
            }
            (q, v) = st.apply(q, v, f_a, fw[1]);
            if s * v <= 0.0 {
                // The turn rounds onto the end of the segment.
                if wanted(s) {
                    return Ok(Rebound { time: tw[1], q });
                }
                s = 0.0;
            }
            break;
        }
    }
    // After the last sample: constant force, static deflection q_s, and q̇ is
    // itself an unforced motion, whose zeros are in closed form.
    let (mut t_last, f_last) = (t[t.len() - 1], force[force.len() - 1]);
    let q_s = f_last * inv_m / w2;
    let never = Rebound {
        time: f64::INFINITY,
        q: q_s,
    };
    for _ in 0..2 {
        let a0 = f_last * inv_m - 2.0 * sig * v - w2 * q;
        let before = if s == 0.0 { start_sign(v, a0, 0.0) } else { s };
        if before == 0.0 {
            return Ok(never);
        }
        let Some(tau) = mode.first_zero(v, a0) else {
            return Ok(never);
        };
        let qt = q_s + mode.eval(q - q_s, v, tau).0;
        if wanted(before) {
            return Ok(Rebound {
                time: t_last + tau,
                q: qt,
            });
        }
        // Passed over a minimum: the next turn is a maximum.
        (q, v, s, t_last) = (qt, 0.0, 0.0, t_last + tau);
    }
    Ok(never)
}

/// Minima one segment may pass over before [`rebound`] reports that time has
/// stopped advancing (one is the most an exact motion can have).
const MAX_PASSED: usize = 4;

/// Samples of q̇ per segment in [`stepped_turn`]'s bracketing.
const TURN_SAMPLES: usize = 64;

/// The first τ in (0, rest] at which q̇ leaves the sign `s`, from (q, q̇) =
/// `state` under the force f_a + slope·τ, with q̇ evaluated by exact steps (no
/// cancellation against the ramp's particular velocity): sampled on a uniform
/// grid and bisected to rounding. Used only on segments short against the
/// mode's time constants, where q̇ is smooth on the grid's scale.
fn stepped_turn(
    mode: &Mode,
    inv_m: f64,
    state: (f64, f64),
    force: (f64, f64),
    rest: f64,
    s: f64,
) -> Option<f64> {
    let (q, v) = state;
    let (f_a, slope) = force;
    let vel = |tau: f64| {
        Step::new(mode, tau, inv_m)
            .apply(q, v, f_a, f_a + slope * tau)
            .1
    };
    let mut lo = 0.0;
    for j in 1..=TURN_SAMPLES {
        let hi = if j == TURN_SAMPLES {
            rest
        } else {
            rest * j as f64 / TURN_SAMPLES as f64
        };
        if s * vel(hi) > 0.0 {
            lo = hi;
            continue;
        }
        // Bisect [lo, hi]: s·q̇ > 0 at lo (or lo = 0), ≤ 0 at hi.
        let mut hi = hi;
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            if s * vel(mid) > 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        return Some(hi);
    }
    None
}

/// Cases per rayon task of the peak-only batch.
const REBOUND_TASK: usize = 64;

/// First rebounds of B oscillators driven by B pulse tables (B, K) on one time
/// grid `t` (K,): `time_out` (B,) and `q_out` (B,); with `maximum`, the first
/// local maxima (see [`first_turn`]).
#[allow(clippy::too_many_arguments)] // the grid, the cases, the kind and the outputs
pub fn first_rebound_batch_into(
    t: &[f64],
    forces: &[f64],
    cases: &Cases<'_>,
    maximum: bool,
    n_threads: Option<i64>,
    time_out: &mut [f64],
    q_out: &mut [f64],
) -> Result<(), DuhamelError> {
    check_times("t", t)?;
    let (b, k) = (cases.len()?, t.len());
    length("forces", forces.len(), b * k, "B*K: one row of K per case")?;
    length("time_out", time_out.len(), b, "one per case")?;
    length("q_out", q_out.len(), b, "one per case")?;
    let one = |i: usize, f: &[f64]| -> Result<Rebound, DuhamelError> {
        let (mode, inv_m, q0, v0) = cases.case(i)?;
        check_finite("force", f)
            .and_then(|_| rebound(t, f, &mode, inv_m, q0, v0, maximum))
            .map_err(DuhamelError::case(i))
    };
    let block = |j: usize, f: &[f64], to: &mut [f64], qo: &mut [f64]| {
        for (r, (fr, (tt, qq))) in f.chunks(k).zip(to.iter_mut().zip(qo)).enumerate() {
            let i = j * REBOUND_TASK + r;
            match one(i, fr) {
                Ok(reb) => (*tt, *qq) = (reb.time, reb.q),
                Err(e) => return Some((i, e)),
            }
        }
        None
    };
    let threads = resolve_threads(n_threads)?;
    let first_error = if threads == 1 || b <= REBOUND_TASK {
        block(0, forces, time_out, q_out)
    } else {
        pool(threads)?.install(|| {
            forces
                .par_chunks(REBOUND_TASK * k)
                .zip(time_out.par_chunks_mut(REBOUND_TASK))
                .zip(q_out.par_chunks_mut(REBOUND_TASK))
                .enumerate()
                .filter_map(|(j, ((f, to), qo))| block(j, f, to, qo))
                .min_by_key(|(i, _)| *i)
        })
    };
    match first_error {
        Some((_, e)) => Err(e),
        None => Ok(()),
    }
}

/// A link and its stop: `mass` m, free stiffness k_f (`k_free`), stop stiffness
/// k_s (`k_stop`), preload δ (`preload`: the free spring's equilibrium lies δ
/// inside the stop), and the damping ratio of each regime relative to its own
/// stiffness (c = 2ζ√(k m); k_c = k_f + k_s in contact). Consistent units (SI:
/// kg, N/m, m; or a lever's inertia, N·m/rad and rad).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    pub mass: f64,
    pub k_free: f64,
    pub k_stop: f64,
    pub preload: f64,
    pub zeta_free: f64,
    pub zeta_contact: f64,
}

/// Why a contact history stops.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ContactEnd {
    /// The next event would come after `t_end`; the stop state is at `t_end`.
    TEnd,
    /// `max_rebounds` rebound maxima were found; the stop state is the last one.
    MaxRebounds,
    /// The contact never ends: the link settles in contact at x_c = −k_f δ/k_c
    /// (also a link at rest on the stop).
    RestInContact,
    /// The free flight never returns to the stop (δ = 0 with ζ_free ≥ 1): the
    /// link creeps towards x = 0 from above.
    RestFree,
    /// `max_events` crossings of x = 0 (chattering); the stop state is the last.
    MaxEvents,
}

impl ContactEnd {
    /// The name the Python layer reports.
    pub fn name(&self) -> &'static str {
        match self {
            ContactEnd::TEnd => "t_end",
            ContactEnd::MaxRebounds => "max_rebounds",
            ContactEnd::RestInContact => "rest_in_contact",
            ContactEnd::RestFree => "rest_free",
            ContactEnd::MaxEvents => "max_events",
        }
    }
}

/// The events of a contact history, in time order.
///
/// Contact i runs from `contact_start[i]` (arriving at `impact_velocity[i]` ≤ 0)
/// to `contact_end[i]` (leaving at `exit_velocity[i]` > 0), with
/// `contact_duration[i]` = end − start; its deepest point is `penetration[i]` ≤ 0
/// at `penetration_time[i]`. A link that starts in contact (x0 < 0, or x0 = 0
/// with v0 ≤ 0) has its first contact start at t = 0 with impact velocity v0.
/// Rebound j is the free flight after contact j: its top `rebound_height[j]` at
/// `rebound_time[j]` (the initial flight of a link that starts free is not a
/// rebound). The last contact may have no end (the arrays of ends are then one
/// shorter). `t_stop`, `x_stop`, `v_stop` is where the history stops (see
/// [`ContactEnd`]); at rest it is (+∞, the rest position, 0).
#[derive(Debug, Clone, PartialEq)]
pub struct ContactHistory {
    pub contact_start: Vec<f64>,
    pub impact_velocity: Vec<f64>,
    pub contact_end: Vec<f64>,
    pub exit_velocity: Vec<f64>,
    pub contact_duration: Vec<f64>,
    pub penetration_time: Vec<f64>,
    pub penetration: Vec<f64>,
    pub rebound_time: Vec<f64>,
    pub rebound_height: Vec<f64>,
    /// Crossings of x = 0 followed.
    pub n_events: usize,
    pub end: ContactEnd,
    pub t_stop: f64,
    pub x_stop: f64,
    pub v_stop: f64,
}

/// One regime: an unforced oscillator about its equilibrium `x_eq`.
struct Regime {
    mode: Mode,
    x_eq: f64,
    contact: bool,
}

impl Regime {
    /// Time until x crosses 0 (leaves the regime) from (x, v), if ever. A touch
    /// of x = 0 (x̄ = 0 with ẋ = 0) is no crossing.
    fn exit(&self, x: f64, v: f64) -> Option<f64> {
        let side = if self.contact { -1.0 } else { 1.0 };
        self.mode
            .crossing(x - self.x_eq, v, -self.x_eq, side, false)
    }

    /// (x, ẋ) a time τ after (x, v).
    fn at(&self, x: f64, v: f64, tau: f64) -> (f64, f64) {
        let (y, dy) = self.mode.eval(x - self.x_eq, v, tau);
        (self.x_eq + y, dy)
    }
}

impl Contact {
    /// m, k_f, k_s finite and > 0; δ, ζ_free, ζ_contact finite and ≥ 0.
    pub fn validate(&self) -> Result<(), DuhamelError> {
        let pos = "finite and > 0";
        param("mass", self.mass, self.mass > 0.0, pos)?;
        param("k_free", self.k_free, self.k_free > 0.0, pos)?;
        param("k_stop", self.k_stop, self.k_stop > 0.0, pos)?;
        let nonneg = "finite and >= 0";
        param("preload", self.preload, self.preload >= 0.0, nonneg)?;
        param("zeta_free", self.zeta_free, self.zeta_free >= 0.0, nonneg)?;
        param(
            "zeta_contact",
            self.zeta_contact,
            self.zeta_contact >= 0.0,
            nonneg,
        )?;
        let free = (self.k_free / self.mass).sqrt();
        mode_range("sqrt(k_free / mass)", free, self.zeta_free)?;
        let contact = ((self.k_free + self.k_stop) / self.mass).sqrt();
        mode_range("sqrt((k_free + k_stop) / mass)", contact, self.zeta_contact)
    }

    fn regime(&self, contact: bool) -> Regime {
        if contact {
            let kc = self.k_free + self.k_stop;
            Regime {
                mode: Mode::new((kc / self.mass).sqrt(), self.zeta_contact),
                x_eq: -self.k_free * self.preload / kc,
                contact,
            }
        } else {
            Regime {
                mode: Mode::new((self.k_free / self.mass).sqrt(), self.zeta_free),
                x_eq: -self.preload,
                contact,
            }
        }
    }

    /// Contact or free at the start: in contact if x0 < 0, or on the stop
    /// (x0 = 0) and not leaving it.
    fn starts_in_contact(x0: f64, v0: f64) -> bool {
        x0 < 0.0 || (x0 == 0.0 && v0 <= 0.0)
    }

    fn check_start(&self, x0: f64, v0: f64, max_events: usize) -> Result<(), DuhamelError> {
        self.validate()?;
        finite("x0", x0)?;
        finite("v0", v0)?;
        if max_events == 0 {
            return Err(DuhamelError::Count {
                field: "max_events",
                value: 0,
                want: ">= 1",
            });
        }
        Ok(())
    }
}

/// The event history of a link released at x0 with velocity v0 at t = 0 (x0 = 0
/// with v0 < 0: arriving at the stop), up to `t_end` (> 0, may be +∞),
/// `max_rebounds` (≥ 1) rebound maxima or `max_events` (≥ 1) crossings, or until
/// it comes to rest.
pub fn contact_response(
    stop: &Contact,
    x0: f64,
    v0: f64,
    t_end: f64,
    max_rebounds: usize,
    max_events: usize,
) -> Result<ContactHistory, DuhamelError> {
    stop.check_start(x0, v0, max_events)?;
    if t_end.is_nan() || t_end <= 0.0 {
        return Err(DuhamelError::Param {
            field: "t_end",
            value: t_end,
            want: "> 0 (+inf for no limit)",
        });
    }
    if max_rebounds == 0 {
        return Err(DuhamelError::Count {
            field: "max_rebounds",
            value: 0,
            want: ">= 1",
        });
    }
    let mut contact = Contact::starts_in_contact(x0, v0);
    let mut h = ContactHistory {
        contact_start: Vec::new(),
        impact_velocity: Vec::new(),
        contact_end: Vec::new(),
        exit_velocity: Vec::new(),
        contact_duration: Vec::new(),
        penetration_time: Vec::new(),
        penetration: Vec::new(),
        rebound_time: Vec::new(),
        rebound_height: Vec::new(),
        n_events: 0,
        end: ContactEnd::TEnd,
        t_stop: 0.0,
        x_stop: x0,
        v_stop: v0,
    };
    if contact {
        h.contact_start.push(0.0);
        h.impact_velocity.push(v0);
    }
    let (mut t, mut x, mut v) = (0.0, x0, v0);
    // Whether the current free flight follows a contact.
    let mut rebound = false;
    loop {
        let r = stop.regime(contact);
        let tmax = t_end - t;
        let exit = r.exit(x, v);
        let limit = exit.unwrap_or(f64::INFINITY).min(tmax);
        if contact || rebound {
            // The deepest point of a contact, the top of a rebound.
            let ext = r.mode.extremum(x - r.x_eq, v, !contact);
            if let Some((z, y)) = ext.filter(|&(z, _)| z <= limit) {
                let xe = r.x_eq + y;
                if contact {
                    h.penetration_time.push(t + z);
                    h.penetration.push(xe);
                } else {
                    h.rebound_time.push(t + z);
                    h.rebound_height.push(xe);
                    if h.rebound_height.len() >= max_rebounds {
                        (h.end, h.t_stop, h.x_stop, h.v_stop) =
                            (ContactEnd::MaxRebounds, t + z, xe, 0.0);
                        return Ok(h);
                    }
                }
            }
        }
        let tau = match exit {
            None => {
                h.end = if contact {
                    ContactEnd::RestInContact
                } else {
                    ContactEnd::RestFree
                };
                (h.t_stop, h.x_stop, h.v_stop) = (f64::INFINITY, r.x_eq, 0.0);
                return Ok(h);
            }
            Some(tau) if tau > tmax => {
                let (xs, vs) = r.at(x, v, tmax);
                (h.end, h.t_stop, h.x_stop, h.v_stop) = (ContactEnd::TEnd, t_end, xs, vs);
                return Ok(h);
            }
            Some(tau) => tau,
        };
        let vc = r.at(x, v, tau).1;
        (t, x, v) = (t + tau, 0.0, vc);
        h.n_events += 1;
        if !contact {
            h.contact_start.push(t);
            h.impact_velocity.push(v);
            contact = true;
        } else if v > 0.0 {
            let start = h.contact_start.last().copied().unwrap_or(0.0);
            h.contact_end.push(t);
            h.exit_velocity.push(v);
            h.contact_duration.push(t - start);
            contact = false;
            rebound = true;
        }
        if h.n_events >= max_events {
            (h.end, h.t_stop, h.x_stop, h.v_stop) = (ContactEnd::MaxEvents, t, x, v);
            return Ok(h);
        }
    }
}

/// First rebound heights [m] of one link on its stop for many impact states
/// (x0, v0) in parallel: the highest point of the first free flight after a
/// contact, 0 where the link never leaves the stop again.
pub fn contact_rebound_batch_into(
    stop: &Contact,
    x0: &[f64],
    v0: &[f64],
    n_threads: Option<i64>,
    out: &mut [f64],
) -> Result<(), DuhamelError> {
    length("v0", v0.len(), x0.len(), "one per x0")?;
    length("out", out.len(), x0.len(), "one per case")?;
    let one = |i: usize| -> Result<f64, DuhamelError> {
        let h = contact_response(stop, x0[i], v0[i], f64::INFINITY, 1, MAX_EVENTS)
            .map_err(DuhamelError::case(i))?;
        Ok(h.rebound_height.first().copied().unwrap_or(0.0))
    };
    let threads = resolve_threads(n_threads)?;
    if threads == 1 || x0.len() < 2 * REBOUND_TASK {
        for (i, o) in out.iter_mut().enumerate() {
            *o = one(i)?;
        }
        return Ok(());
    }
    let first_error = pool(threads)?.install(|| {
        out.par_chunks_mut(REBOUND_TASK)
            .enumerate()
            .filter_map(|(j, os)| {
                for (r, o) in os.iter_mut().enumerate() {
                    let i = j * REBOUND_TASK + r;
                    match one(i) {
                        Ok(v) => *o = v,
                        Err(e) => return Some((i, e)),
                    }
                }
                None
            })
            .min_by_key(|(i, _)| *i)
    });
    match first_error {
        Some((_, e)) => Err(e),
        None => Ok(()),
    }
}

/// x(t) and ẋ(t) of the same history at `times` (non-decreasing, ≥ 0), by the
/// same piecewise closed form; more than `max_events` crossings before the last
/// time is an error (the link chatters).
pub fn contact_sample_into(
    stop: &Contact,
    x0: f64,
    v0: f64,
    times: &[f64],
    max_events: usize,
    x_out: &mut [f64],
    v_out: &mut [f64],
) -> Result<(), DuhamelError> {
    stop.check_start(x0, v0, max_events)?;
    let n = times.len();
    length("x_out", x_out.len(), n, "one per time")?;
    length("v_out", v_out.len(), n, "one per time")?;
    if n == 0 {
        return Ok(());
    }
    check_times("times", times)?;
    param(
        "times[0]",
        times[0],
        times[0] >= 0.0,
        ">= 0 (the history starts at t = 0)",
    )?;
    let mut contact = Contact::starts_in_contact(x0, v0);
    let (mut t, mut x, mut v) = (0.0, x0, v0);
    let (mut i, mut events) = (0, 0);
    loop {
        let r = stop.regime(contact);
        let exit = r.exit(x, v);
        let t_next = exit.map_or(f64::INFINITY, |tau| t + tau);
        while i < n && times[i] <= t_next {
            (x_out[i], v_out[i]) = r.at(x, v, times[i] - t);
            i += 1;
        }
        let Some(tau) = exit.filter(|_| i < n) else {
            return Ok(());
        };
        if events >= max_events {
            return Err(DuhamelError::TooManyEvents {
                max_events,
                time: t,
            });
        }
        let vc = r.at(x, v, tau).1;
        (t, x, v) = (t_next, 0.0, vc);
        // Leave the contact only moving out (a touch stays), as in the history.
        if !contact || v > 0.0 {
            contact = !contact;
        }
        events += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 16 item 15: a ramp of 1e9 N/s over 1 ns (c = slope/(mω²) = 1e9
    /// against q̇ ~ 1e-10) hung with `maximum` and put the minimum inside the
    /// ramp without. By hand (Taylor): on the ramp q̇ ≈ −0.75τ + 5e8τ², still
    /// −2.5e-10 at 1 ns; then q̈ ≈ 1 − 0.75 = 0.25 brings it to 0 about 1 ns
    /// later: the minimum is at ≈ 2 ns, and over-damped (ζ = 10) q then creeps
    /// to q_s = 1 with no maximum.
    #[test]
    fn item15_steep_short_ramp_neither_hangs_nor_turns_inside_the_ramp() {
        let osc = Oscillator::new(1.0, 10.0, 1.0).unwrap();
        let (t, f) = ([0.0, 1e-9], [0.0, 1.0]);
        let max = first_turn(&t, &f, &osc, 0.75, 0.0, true).unwrap();
        assert_eq!(max.time, f64::INFINITY);
        assert!((max.q - 1.0).abs() < 1e-12);
        let min = first_turn(&t, &f, &osc, 0.75, 0.0, false).unwrap();
        assert!((1.9e-9..2.1e-9).contains(&min.time), "{min:?}");
    }

    /// Issue 16 item 15: k/m overflowing hung the crossing search; ω outside
    /// [1e-150, 1e150] rad/s is refused.
    #[test]
    fn item15_overflowing_k_over_m_is_refused() {
        let stop = Contact {
            mass: 1e-300,
            k_free: 1e300,
            k_stop: 1e300,
            preload: 0.1,
            zeta_free: 0.0,
            zeta_contact: 0.0,
        };
        let e = contact_response(&stop, 1.0, -1.0, f64::INFINITY, 3, 100).unwrap_err();
        assert!(matches!(
            e,
            DuhamelError::Param {
                field: "sqrt(k_free / mass)",
                ..
            }
        ));
    }
    use proptest::prelude::*;

    // ---------------------------------------------------------------------
    // Independent references: textbook closed forms, one per damping case.

    /// Free vibration from (q0, v0), written out per damping case.
    fn free(w: f64, z: f64, q0: f64, v0: f64, t: f64) -> (f64, f64) {
        if z < 1.0 {
            let (sg, wd) = (z * w, w * (1.0 - z * z).sqrt());
            let (a, b) = (q0, (v0 + sg * q0) / wd);
            let e = (-sg * t).exp();
            let (c, s) = ((wd * t).cos(), (wd * t).sin());
            let q = e * (a * c + b * s);
            let v = e * ((-sg * a + wd * b) * c + (-sg * b - wd * a) * s);
            (q, v)
        } else if z == 1.0 {
            let b = v0 + w * q0;
            let e = (-w * t).exp();
            (e * (q0 + b * t), e * (b - w * (q0 + b * t)))
        } else {
            let r = w * (z * z - 1.0).sqrt();
            let (r1, r2) = (-z * w + r, -z * w - r);
            let a = (v0 - r2 * q0) / (r1 - r2);
            let b = q0 - a;
            let (e1, e2) = ((r1 * t).exp(), (r2 * t).exp());
            (a * e1 + b * e2, a * r1 * e1 + b * r2 * e2)
        }
    }

    /// Response from rest to a step F0 applied at t = 0.
    fn step_ref(w: f64, z: f64, m: f64, f0: f64, t: f64) -> (f64, f64) {
        let qs = f0 / (m * w * w);
        let (q, v) = free(w, z, -qs, 0.0, t);
        (qs + q, v)
    }

    /// Response from rest to the ramp F = r·t.
    fn ramp_ref(w: f64, z: f64, m: f64, r: f64, t: f64) -> (f64, f64) {
        let k = m * w * w;
        let (qp, vp) = ((r / k) * (t - 2.0 * z / w), r / k);
        let (q, v) = free(w, z, 2.0 * z * r / (k * w), -r / k, t);
        (qp + q, vp + v)
    }

    fn respond(t: &[f64], f: &[f64], osc: &Oscillator, q0: f64, v0: f64) -> (Vec<f64>, Vec<f64>) {
        let (mut q, mut v) = (vec![0.0; t.len()], vec![0.0; t.len()]);
        response_into(t, f, osc, q0, v0, &mut q, Some(&mut v)).unwrap();
        (q, v)
    }

    /// max |a − b| over max |b|.
    fn rel_err(a: &[f64], b: &[f64]) -> f64 {
        let scale = b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        a.iter()
            .zip(b)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
            / scale
    }

    fn coarse(w: f64, periods: f64) -> Vec<f64> {
        // 10 steps per natural period.
        let h = 2.0 * PI / w / 10.0;
        (0..=(10.0 * periods) as usize)
            .map(|k| k as f64 * h)
            .collect()
    }

    /// Non-uniform, with repeated times and long and short steps.
    fn ragged(w: f64, t_end: f64) -> Vec<f64> {
        let mut t = vec![0.0];
        let mut k = 0usize;
        while *t.last().unwrap() < t_end {
            k += 1;
            let h = match k % 7 {
                0 => 0.0,
                1 => 1.7,
                2 => 0.013,
                3 => 0.61,
                4 => 2.9,
                5 => 0.2,
                _ => 0.0071,
            } / w;
            t.push(t.last().unwrap() + h);
        }
        t
    }

    const ZETAS: [f64; 4] = [0.0, 0.05, 1.0, 2.0];

    #[test]
    fn free_vibration_matches_closed_forms() {
        for &z in &ZETAS {
            for (w, m) in [(1.0, 1.0), (37.0, 0.2)] {
                let osc = Oscillator::new(w, z, m).unwrap();
                for t in [coarse(w, 6.0), ragged(w, 40.0 / w)] {
                    let (q0, v0) = (0.3, -1.7 * w);
                    let (q, v) = respond(&t, &vec![0.0; t.len()], &osc, q0, v0);
                    let rq: Vec<f64> = t.iter().map(|&x| free(w, z, q0, v0, x).0).collect();
                    let rv: Vec<f64> = t.iter().map(|&x| free(w, z, q0, v0, x).1).collect();
                    assert!(
                        rel_err(&q, &rq) < 1e-12,
                        "z {z} w {w}: q {}",
                        rel_err(&q, &rq)
                    );
                    assert!(
                        rel_err(&v, &rv) < 1e-12,
                        "z {z} w {w}: v {}",
                        rel_err(&v, &rv)
                    );
                }
            }
        }
    }

    #[test]
    fn step_and_ramp_match_closed_forms() {
        for &z in &ZETAS {
            let (w, m) = (12.0, 0.7);
            let osc = Oscillator::new(w, z, m).unwrap();
            for t in [coarse(w, 5.0), ragged(w, 30.0 / w)] {
                // The step starts at t[0]: a jump of the force at the start.
                let (q, v) = respond(&t, &vec![2.5; t.len()], &osc, 0.0, 0.0);
                let r: Vec<(f64, f64)> = t.iter().map(|&x| step_ref(w, z, m, 2.5, x)).collect();
                let (rq, rv): (Vec<f64>, Vec<f64>) = r.into_iter().unzip();
                assert!(rel_err(&q, &rq) < 1e-12, "step z {z}: {}", rel_err(&q, &rq));
                assert!(rel_err(&v, &rv) < 1e-12, "step z {z}: {}", rel_err(&v, &rv));
                // A ramp is linear on any grid: exact with first-order hold.
                let f: Vec<f64> = t.iter().map(|&x| -3.0 * x).collect();
                let (q, v) = respond(&t, &f, &osc, 0.0, 0.0);
                let r: Vec<(f64, f64)> = t.iter().map(|&x| ramp_ref(w, z, m, -3.0, x)).collect();
                let (rq, rv): (Vec<f64>, Vec<f64>) = r.into_iter().unzip();
                assert!(rel_err(&q, &rq) < 1e-12, "ramp z {z}: {}", rel_err(&q, &rq));
                assert!(rel_err(&v, &rv) < 1e-12, "ramp z {z}: {}", rel_err(&v, &rv));
            }
        }
    }

    #[test]
    fn start_time_shifts_the_response() {
        let osc = Oscillator::new(5.0, 0.1, 1.0).unwrap();
        let t: Vec<f64> = (0..60).map(|k| 1000.0 + 0.1 * k as f64).collect();
        let (q, _) = respond(&t, &vec![1.0; 60], &osc, 0.0, 0.0);
        let rq: Vec<f64> = t
            .iter()
            .map(|&x| step_ref(5.0, 0.1, 1.0, 1.0, x - 1000.0).0)
            .collect();
        assert!(rel_err(&q, &rq) < 1e-12);
    }

    #[test]
    fn repeated_time_is_a_jump() {
        let (w, z, m, f0) = (3.0, 0.2, 2.0, 4.0);
        let osc = Oscillator::new(w, z, m).unwrap();
        // Force 0 until 0.5, then F0: the jump at the repeated time.
        let t = [0.0, 0.5, 0.5, 0.9, 3.0];
        let (q, v) = respond(&t, &[0.0, 0.0, f0, f0, f0], &osc, 0.0, 0.0);
        assert_eq!(
            (q[1], v[1]),
            (q[2], v[2]),
            "a zero-length step keeps the state"
        );
        for k in 0..t.len() {
            let (rq, rv) = step_ref(w, z, m, f0, (t[k] - 0.5).max(0.0));
            assert!(
                (q[k] - rq).abs() < 1e-13 && (v[k] - rv).abs() < 1e-13,
                "{k}"
            );
        }
        // A rectangular pulse F0 on [0, τ): step(t) − step(t − τ).
        let tau = 0.4;
        let t = [0.0, tau, tau, 2.0, 5.0];
        let (q, _) = respond(&t, &[f0, f0, 0.0, 0.0, 0.0], &osc, 0.0, 0.0);
        for k in 0..t.len() {
            let mut r = step_ref(w, z, m, f0, t[k]).0;
            if t[k] >= tau {
                r -= step_ref(w, z, m, f0, t[k] - tau).0;
            }
            assert!((q[k] - r).abs() < 1e-13, "{k}: {} vs {r}", q[k]);
        }
    }

    #[test]
    fn continuous_across_critical_damping() {
        let (w, m) = (7.0, 1.3);
        let t = ragged(w, 25.0 / w);
        let f: Vec<f64> = t.iter().map(|&x| (2.0 - x).max(0.0)).collect();
        let at = |z: f64| respond(&t, &f, &Oscillator::new(w, z, m).unwrap(), 0.1, 0.4);
        let (q1, v1) = at(1.0);
        for z in [1.0 - 1e-9, 1.0 + 1e-9, 1.0 - 1e-7, 1.0 + 1e-7] {
            let (q, v) = at(z);
            let d = (z - 1.0f64).abs();
            assert!(rel_err(&q, &q1) < 10.0 * d, "z {z}: q {}", rel_err(&q, &q1));
            assert!(rel_err(&v, &v1) < 10.0 * d, "z {z}: v {}", rel_err(&v, &v1));
        }
        // Every coefficient, for steps from tiny to long.
        for h in [1e-6, 0.1, 1.0, 30.0] {
            let c = Step::new(&Mode::new(w, 1.0), h, 1.0);
            for z in [1.0 - 1e-9, 1.0 + 1e-9] {
                let d = Step::new(&Mode::new(w, z), h, 1.0);
                let (a, b) = (
                    [
                        c.p00,
                        c.p01 * w,
                        c.p10 / w,
                        c.p11,
                        c.g0q * w * w,
                        c.g0v * w,
                        c.g1q * w * w,
                        c.g1v * w,
                    ],
                    [
                        d.p00,
                        d.p01 * w,
                        d.p10 / w,
                        d.p11,
                        d.g0q * w * w,
                        d.g0v * w,
                        d.g1q * w * w,
                        d.g1v * w,
                    ],
                );
                let err = a
                    .iter()
                    .zip(&b)
                    .fold(0.0f64, |e, (x, y)| e.max((x - y).abs()));
                assert!(err < 1e-8, "h {h} z {z}: {err}");
            }
        }
    }

    #[test]
    fn large_damping_and_long_steps_stay_finite_and_exact() {
        // ζ = 50 and ω·h up to 1e4: no overflow, and the static deflection.
        for z in [0.0, 0.5, 1.0, 50.0] {
            let osc = Oscillator::new(100.0, z, 1.0).unwrap();
            let t = [0.0, 1e-5, 0.5, 100.0];
            let (q, v) = respond(&t, &[1.0, 1.0, 1.0, 1.0], &osc, 0.0, 0.0);
            assert!(q.iter().chain(&v).all(|x| x.is_finite()));
            if z > 0.0 {
                assert!((q[3] - 1e-4).abs() < 1e-15, "z {z}: {}", q[3]);
            }
        }
    }

    fn cases_of<'a>(
        w: &'a [f64],
        z: &'a [f64],
        m: &'a [f64],
        q0: &'a [f64],
        v0: &'a [f64],
    ) -> Cases<'a> {
        Cases {
            omega_n: w,
            zeta: z,
            mass: m,
            q0,
            v0,
        }
    }

    /// The batch, on one and two threads, equals each case run alone, bit for bit.
    fn batch_is_single(t: &[f64], forces: &[f64], cases: &Cases<'_>) {
        let (b, n) = (cases.omega_n.len(), t.len());
        for threads in [1, 2] {
            let mut out = vec![0.0; b * n];
            response_batch_into(t, forces, cases, Some(threads), &mut out).unwrap();
            for i in 0..b {
                let osc = Oscillator::new(cases.omega_n[i], cases.zeta[i], cases.mass[i]).unwrap();
                let row = &forces[i * n..(i + 1) * n];
                let (q, _) = respond(t, row, &osc, cases.q0[i], cases.v0[i]);
                assert_eq!(
                    &out[i * n..(i + 1) * n],
                    &q[..],
                    "case {i}, {threads} threads"
                );
            }
        }
    }

    #[test]
    fn batch_equals_single() {
        let t = ragged(5.0, 20.0);
        let n = t.len();
        let w = [5.0, 1.0, 30.0, 2.0, 9.0, 4.0, 0.3];
        let z = [0.0, 0.05, 1.0, 2.5, 0.7, 1.0 + 1e-9, 3.0];
        let m = [1.0, 2.0, 0.5, 1.0, 3.0, 1.0, 0.1];
        let q0 = [0.0, 0.1, -0.2, 0.0, 1.0, 0.0, 0.3];
        let v0 = [1.0, 0.0, 0.5, -2.0, 0.0, 0.1, 0.0];
        let forces: Vec<f64> = (0..w.len() * n)
            .map(|i| ((i * 7919) % 13) as f64 - 6.0)
            .collect();
        let cases = cases_of(&w, &z, &m, &q0, &v0);
        batch_is_single(&t, &forces, &cases);
        // First rebounds too.
        let k = 4;
        let tk = [0.0, 0.01, 0.03, 0.03];
        let pulses: Vec<f64> = (0..w.len())
            .flat_map(|i| [0.0, 3.0 + i as f64, 1.0, 0.0])
            .collect();
        for threads in [1, 2] {
            let (mut tt, mut qq) = (vec![0.0; w.len()], vec![0.0; w.len()]);
            first_rebound_batch_into(&tk, &pulses, &cases, false, Some(threads), &mut tt, &mut qq)
                .unwrap();
            for i in 0..w.len() {
                let osc = Oscillator::new(w[i], z[i], m[i]).unwrap();
                let r =
                    first_rebound(&tk, &pulses[i * k..(i + 1) * k], &osc, q0[i], v0[i]).unwrap();
                assert_eq!((tt[i], qq[i]), (r.time, r.q), "case {i}");
            }
        }
    }

    #[test]
    fn lockstep_batch_equals_single() {
        // A linspace-like grid (a few step lengths ulps apart) with a repeated
        // time (a force jump), and 2·LOCK + 3 cases: two lockstep groups and a
        // remainder, every damping regime in each group.
        let mut t: Vec<f64> = (0..400).map(|k| k as f64 * (0.02 / 399.0)).collect();
        t.insert(150, t[150]);
        let n = t.len();
        let grid = GridSteps::new(&t).unwrap();
        assert!(grid.hs.len() > 2 && grid.hs.contains(&0.0), "{:?}", grid.hs);
        let b = 2 * LOCK + 3;
        let w: Vec<f64> = (0..b).map(|i| 200.0 + 97.0 * i as f64).collect();
        let z: Vec<f64> = (0..b).map(|i| [0.0, 0.05, 1.0, 2.5, 0.7][i % 5]).collect();
        let m: Vec<f64> = (0..b).map(|i| 0.1 + 0.3 * i as f64).collect();
        let q0: Vec<f64> = (0..b).map(|i| 1e-3 * (i as f64 - 9.0)).collect();
        let v0: Vec<f64> = (0..b).map(|i| 0.1 * (i % 3) as f64).collect();
        let forces: Vec<f64> = (0..b * n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        let cases = cases_of(&w, &z, &m, &q0, &v0);
        batch_is_single(&t, &forces, &cases);
        // The lockstep loop compiled for each instruction set the processor has.
        {
            use pulp::Simd;
            let grid = GridSteps::new(&t).unwrap();
            let (coef, lane_q0, lane_v0) = lane_steps(&grid, &cases, 0).unwrap();
            let runs = on_each_isa!(|simd| {
                let mut out = vec![0.0; LOCK * n];
                Simd::vectorize(
                    simd,
                    Lockstep {
                        which: &grid.which,
                        coef: &coef,
                        forces: &forces[..LOCK * n],
                        out: &mut out,
                        q0: lane_q0,
                        v0: lane_v0,
                    },
                );
                out
            });
            for (isa, out) in runs {
                for i in 0..LOCK {
                    let osc = Oscillator::new(w[i], z[i], m[i]).unwrap();
                    let (q, _) = respond(&t, &forces[i * n..(i + 1) * n], &osc, q0[i], v0[i]);
                    assert_eq!(&out[i * n..(i + 1) * n], &q[..], "{isa}: case {i}");
                }
            }
        }
        // A bad force or case inside a lockstep group is reported by its row.
        for (row, col) in [(10, 7), (3, n - 1)] {
            let mut bad = forces.clone();
            bad[row * n + col] = f64::INFINITY;
            for threads in [1, 2] {
                let mut out = vec![0.0; b * n];
                let e = response_batch_into(&t, &bad, &cases, Some(threads), &mut out);
                assert_eq!(
                    e.unwrap_err().to_string(),
                    format!("case {row}: force[{col}] must be finite; got inf")
                );
            }
        }
        let mut zb = z.clone();
        zb[12] = f64::NAN;
        let e = response_batch_into(
            &t,
            &forces,
            &cases_of(&w, &zb, &m, &q0, &v0),
            Some(2),
            &mut vec![0.0; b * n],
        );
        assert_eq!(
            e.unwrap_err().to_string(),
            "case 12: zeta must be finite and >= 0; got NaN"
        );
        // A graded grid (every step its own length) goes case by case.
        let graded: Vec<f64> = (0..1000).map(|k| (k as f64).powf(1.5)).collect();
        assert!(GridSteps::new(&graded).is_none());
    }

    #[test]
    fn batch_errors_name_the_case() {
        let t = [0.0, 0.1, 0.2];
        let w = [1.0; 4];
        let m = [1.0; 4];
        let zero = [0.0; 4];
        let mut forces = vec![0.0; 12];
        forces[2 * 3 + 1] = f64::NAN;
        let cases = cases_of(&w, &zero, &m, &zero, &zero);
        for threads in [1, 2] {
            let mut out = vec![0.0; 12];
            let e = response_batch_into(&t, &forces, &cases, Some(threads), &mut out).unwrap_err();
            assert!(
                matches!(&e, DuhamelError::Case { row: 2, error } if matches!(**error, DuhamelError::NotFinite { field: "force", index: 1, .. })),
                "{e}"
            );
            assert_eq!(e.to_string(), "case 2: force[1] must be finite; got NaN");
            let (mut a, mut b) = (vec![0.0; 4], vec![0.0; 4]);
            let e =
                first_rebound_batch_into(&t, &forces, &cases, false, Some(threads), &mut a, &mut b)
                    .unwrap_err();
            assert!(matches!(e, DuhamelError::Case { row: 2, .. }), "{e}");
        }
        let z = [0.0, 0.0, 0.0, -0.1];
        let e = response_batch_into(
            &t,
            &[0.0; 12],
            &cases_of(&w, &z, &m, &zero, &zero),
            None,
            &mut [0.0; 12],
        )
        .unwrap_err();
        assert_eq!(
            e.to_string(),
            "case 3: zeta must be finite and >= 0; got -0.1"
        );
        let e = response_batch_into(
            &t,
            &[0.0; 12],
            &cases_of(&w, &zero[..3], &m, &zero, &zero),
            None,
            &mut [0.0; 12],
        )
        .unwrap_err();
        assert!(
            matches!(
                e,
                DuhamelError::Length {
                    field: "zeta",
                    got: 3,
                    ..
                }
            ),
            "{e}"
        );
        let e = response_batch_into(&t, &[0.0; 11], &cases, None, &mut [0.0; 12]).unwrap_err();
        assert!(
            matches!(
                e,
                DuhamelError::Length {
                    field: "forces",
                    ..
                }
            ),
            "{e}"
        );
        let e = response_batch_into(&[0.0, 0.2, 0.1], &[0.0; 12], &cases, None, &mut [0.0; 12])
            .unwrap_err();
        assert!(
            matches!(e, DuhamelError::Decreasing { index: 2, .. }),
            "{e}"
        );
        let e = response_batch_into(&t, &[0.0; 12], &cases, Some(0), &mut [0.0; 12]).unwrap_err();
        assert!(matches!(e, DuhamelError::Threads(_)), "{e}");
    }

    #[test]
    fn input_errors_are_typed_and_name_the_field() {
        let osc = Oscillator::new(2.0, 0.1, 1.0).unwrap();
        let mut q = [0.0; 3];
        let run = |t: &[f64], f: &[f64], o: &Oscillator, q0: f64, q: &mut [f64]| {
            response_into(t, f, o, q0, 0.0, q, None).unwrap_err()
        };
        let t = [0.0, 0.1, 0.2];
        let f = [0.0, 1.0, 0.0];
        let e = run(&[0.0, 0.2, 0.1], &f, &osc, 0.0, &mut q);
        assert_eq!(
            e.to_string(),
            "t must be non-decreasing (a repeated time is a jump of the force); got t[2] = 0.1 after t[1] = 0.2"
        );
        let e = run(&[0.0, f64::NAN, 0.1], &f, &osc, 0.0, &mut q);
        assert!(
            matches!(
                e,
                DuhamelError::NotFinite {
                    field: "t",
                    index: 1,
                    ..
                }
            ),
            "{e}"
        );
        let e = run(&[0.0, 0.1, f64::INFINITY], &f, &osc, 0.0, &mut q);
        assert!(
            matches!(
                e,
                DuhamelError::NotFinite {
                    field: "t",
                    index: 2,
                    ..
                }
            ),
            "{e}"
        );
        let e = run(&[f64::NAN], &[0.0], &osc, 0.0, &mut q[..1]);
        assert!(
            matches!(e, DuhamelError::Param { field: "t[0]", .. }),
            "{e}"
        );
        let e = run(&[-1e308, 1e308, 1e308], &f, &osc, 0.0, &mut q);
        assert!(
            matches!(e, DuhamelError::StepOverflow { index: 1, .. }),
            "{e}"
        );
        let e = run(&t, &[0.0, f64::NAN, 0.0], &osc, 0.0, &mut q);
        assert_eq!(e.to_string(), "force[1] must be finite; got NaN");
        let e = run(&[0.0], &[f64::NAN], &osc, 0.0, &mut q[..1]);
        assert!(
            matches!(
                e,
                DuhamelError::NotFinite {
                    field: "force",
                    index: 0,
                    ..
                }
            ),
            "{e}"
        );
        let e = run(&t, &[0.0, 0.0, f64::NEG_INFINITY], &osc, 0.0, &mut q);
        assert!(
            matches!(
                e,
                DuhamelError::NotFinite {
                    field: "force",
                    index: 2,
                    ..
                }
            ),
            "{e}"
        );
        let e = run(
            &t,
            &[0.0, 1e308, 1e308],
            &Oscillator::new(1e-3, 0.0, 1e-300).unwrap(),
            0.0,
            &mut q,
        );
        assert!(matches!(e, DuhamelError::Overflow { .. }), "{e}");
        let e = run(&t, &f[..2], &osc, 0.0, &mut q);
        assert!(
            matches!(
                e,
                DuhamelError::Length {
                    field: "force",
                    got: 2,
                    ..
                }
            ),
            "{e}"
        );
        let e = run(&t, &f, &osc, 0.0, &mut q[..2]);
        assert!(
            matches!(e, DuhamelError::Length { field: "q_out", .. }),
            "{e}"
        );
        let e = run(&[], &[], &osc, 0.0, &mut q[..0]);
        assert!(
            matches!(
                e,
                DuhamelError::Length {
                    field: "t",
                    got: 0,
                    ..
                }
            ),
            "{e}"
        );
        let e = run(&t, &f, &osc, f64::NAN, &mut q);
        assert!(matches!(e, DuhamelError::Param { field: "q0", .. }), "{e}");
        let e = response_into(&t, &f, &osc, 0.0, 0.0, &mut q, Some(&mut [0.0; 2])).unwrap_err();
        assert!(
            matches!(e, DuhamelError::Length { field: "v_out", .. }),
            "{e}"
        );
        for (w, z, m, field) in [
            (0.0, 0.1, 1.0, "omega_n"),
            (-1.0, 0.1, 1.0, "omega_n"),
            (f64::INFINITY, 0.1, 1.0, "omega_n"),
            (1.0, -0.1, 1.0, "zeta"),
            (1.0, f64::NAN, 1.0, "zeta"),
            (1.0, 0.1, 0.0, "mass"),
            (1.0, 0.1, -2.0, "mass"),
            (1.0, 0.1, f64::NAN, "mass"),
        ] {
            let e = Oscillator::new(w, z, m).unwrap_err();
            assert!(
                matches!(e, DuhamelError::Param { field: f, .. } if f == field),
                "{e}"
            );
            let o = Oscillator {
                omega_n: w,
                zeta: z,
                mass: m,
            };
            assert!(response_into(&t, &f, &o, 0.0, 0.0, &mut q, None).is_err());
            assert!(first_rebound(&t, &f, &o, 0.0, 0.0).is_err());
        }
        assert_eq!(
            Oscillator::new(1.0, -0.1, 1.0).unwrap_err().to_string(),
            "zeta must be finite and >= 0; got -0.1"
        );
        // first_rebound checks its table up front.
        assert!(matches!(
            first_rebound(&[0.0, 0.2, 0.1], &f, &osc, 0.0, 0.0),
            Err(DuhamelError::Decreasing { index: 2, .. })
        ));
        assert!(matches!(
            first_rebound(&t, &[0.0, f64::INFINITY, 0.0], &osc, 0.0, 0.0),
            Err(DuhamelError::NotFinite { index: 1, .. })
        ));
        assert!(matches!(
            first_rebound(&[], &[], &osc, 0.0, 0.0),
            Err(DuhamelError::Length { .. })
        ));
        assert!(matches!(
            first_rebound(&t, &f[..1], &osc, 0.0, 0.0),
            Err(DuhamelError::Length { .. })
        ));
        assert!(matches!(
            first_rebound(&t, &f, &osc, 0.0, f64::NAN),
            Err(DuhamelError::Param { field: "v0", .. })
        ));
    }

    // ---------------------------------------------------------------------
    // First rebound.

    #[test]
    fn first_maximum_passes_over_minima() {
        // Undamped free vibration from q = 0 moving down at 1: the first turn is
        // the minimum −1/ω at a quarter period, the first maximum +1/ω at three.
        let w = 5.0;
        let osc = Oscillator::new(w, 0.0, 1.0).unwrap();
        let r = first_turn(&[0.0], &[0.0], &osc, 0.0, -1.0, true).unwrap();
        assert!((r.time - 1.5 * PI / w).abs() < 1e-14 && (r.q - 1.0 / w).abs() < 1e-15);
        let r = first_turn(&[0.0], &[0.0], &osc, 0.0, -1.0, false).unwrap();
        assert!((r.time - 0.5 * PI / w).abs() < 1e-14 && (r.q + 1.0 / w).abs() < 1e-15);
        // A link pressed into its stop and thrown back by a rectangular pulse: the
        // minimum falls inside the pulse, the maximum after it; against a fine
        // history scan.
        let osc = Oscillator::new(2.0 * PI * 297.0, 0.05, 7.4e-3).unwrap();
        let (tau, v0) = (6.5e-4, 0.2);
        let force = 7.4e-3 * (1.0 + 5.0 / 9.0) * v0 / tau;
        let r = first_turn(&[0.0, tau, tau], &[force, force, 0.0], &osc, 0.0, -v0, true).unwrap();
        // The scan's grid holds τ twice, so that its force jumps there too.
        let (n1, n2) = (13_001, 187_001);
        let dt = (0.01 - tau) / (n2 - 1) as f64;
        let mut t: Vec<f64> = (0..n1).map(|i| tau * i as f64 / (n1 - 1) as f64).collect();
        t.extend((0..n2).map(|i| tau + dt * i as f64));
        let mut f = vec![force; n1];
        f.extend(vec![0.0; n2]);
        let n = t.len();
        let mut q = vec![0.0; n];
        response_into(&t, &f, &osc, 0.0, -v0, &mut q, None).unwrap();
        let i_min = (1..n).find(|&i| q[i] > q[i - 1]).unwrap();
        let i_max = (i_min..n).find(|&i| q[i] < q[i - 1]).unwrap() - 1;
        assert!(t[i_min] < tau && t[i_max] > tau);
        assert!(
            (r.time - t[i_max]).abs() < 2.0 * dt,
            "{} vs {}",
            r.time,
            t[i_max]
        );
        // The scan misses the top by at most (ω·dt)²/2 of it.
        assert!(
            r.q >= q[i_max] && r.q - q[i_max] < 1e-8 * r.q.abs(),
            "{} vs {}",
            r.q,
            q[i_max]
        );
    }

    #[test]
    fn first_rebound_closed_forms() {
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-13 * b.abs().max(1.0);
        // Free vibration released from q0: the far side after half a damped period.
        for z in [0.0f64, 0.05, 0.5] {
            let (w, q0) = (4.0, 0.3);
            let wd = w * (1.0 - z * z).sqrt();
            let osc = Oscillator::new(w, z, 1.0).unwrap();
            let r = first_rebound(&[0.0], &[0.0], &osc, q0, 0.0).unwrap();
            assert!(close(r.time, PI / wd), "z {z}: {}", r.time);
            assert!(close(r.q, -q0 * (-z * w * PI / wd).exp()), "z {z}: {}", r.q);
        }
        // A step from rest: the overshoot 1 + e^{−σπ/ωd} of the static deflection.
        for z in [0.0f64, 0.1] {
            let (w, m, f0) = (10.0, 2.0, 5.0);
            let wd = w * (1.0 - z * z).sqrt();
            let osc = Oscillator::new(w, z, m).unwrap();
            let r = first_rebound(&[0.0, 1.0], &[f0, f0], &osc, 0.0, 0.0).unwrap();
            assert!(close(r.time, PI / wd), "{}", r.time);
            let qs = f0 / (m * w * w);
            assert!(close(r.q, qs * (1.0 + (-z * w * PI / wd).exp())), "{}", r.q);
        }
        // An undamped ramp from rest: q̇ = c(1 − cos ωt) touches zero at 2π/ω.
        let (w, r) = (3.0, 2.0);
        let osc = Oscillator::new(w, 0.0, 1.0).unwrap();
        let tt = 10.0 * 2.0 * PI / w;
        let reb = first_rebound(&[0.0, tt], &[0.0, r * tt], &osc, 0.0, 0.0).unwrap();
        assert!((reb.time - 2.0 * PI / w).abs() < 1e-7, "{}", reb.time);
        assert!(close(reb.q, r / (w * w) * 2.0 * PI / w), "{}", reb.q);
        // No extremum ever: at rest, or an over-damped creep; q is the limit.
        let osc = Oscillator::new(2.0, 2.0, 1.0).unwrap();
        let r = first_rebound(&[0.0, 1.0], &[0.0, 0.0], &osc, 0.0, 0.0).unwrap();
        assert_eq!((r.time, r.q), (f64::INFINITY, 0.0));
        let r = first_rebound(&[0.0, 1.0], &[0.0, 0.0], &osc, 1.0, 0.0).unwrap();
        assert_eq!((r.time, r.q), (f64::INFINITY, 0.0));
        let r = first_rebound(&[0.0, 1.0], &[0.0, 8.0], &osc, 0.0, 0.0).unwrap();
        assert_eq!(r.time, f64::INFINITY);
        assert!(close(r.q, 2.0), "static deflection {}", r.q);
        // At rest under a preload until a pulse comes: the rest stays exact, and
        // the first extremum is that of the pulse's response.
        let osc = Oscillator::new(3.0, 0.0, 1.0).unwrap();
        let qs = 0.7 / 9.0;
        let r = first_rebound(&[0.0, 1.3, 1.3, 5.0], &[0.7, 0.7, 1.7, 1.7], &osc, qs, 0.0).unwrap();
        assert!(close(r.time, 1.3 + PI / 3.0), "{}", r.time);
        assert!(close(r.q, qs + 2.0 / 9.0), "{}", r.q);
        // An over-damped overshoot: critically damped from q0 = 1 with v0 = −5ω.
        for z in [1.0, 1.5] {
            let osc = Oscillator::new(2.0, z, 1.0).unwrap();
            let r = first_rebound(&[0.0], &[0.0], &osc, 1.0, -10.0).unwrap();
            let v = free(2.0, z, 1.0, -10.0, r.time).1;
            assert!(r.time.is_finite() && v.abs() < 1e-13, "z {z}: v {v}");
            assert!(close(r.q, free(2.0, z, 1.0, -10.0, r.time).0));
        }
    }

    #[test]
    fn first_rebound_continuous_across_critical_damping() {
        let f = [0.0, 5.0, 0.0, 0.0];
        let t = [0.0, 0.05, 0.1, 0.1];
        let at = |z: f64| {
            first_rebound(&t, &f, &Oscillator::new(6.0, z, 1.0).unwrap(), 1.0, -20.0).unwrap()
        };
        let r1 = at(1.0);
        assert!(r1.time.is_finite());
        for z in [1.0 - 1e-9, 1.0 + 1e-9] {
            let r = at(z);
            assert!(
                (r.time - r1.time).abs() < 1e-8 * r1.time,
                "{} vs {}",
                r.time,
                r1.time
            );
            assert!(
                (r.q - r1.q).abs() < 1e-8 * r1.q.abs(),
                "{} vs {}",
                r.q,
                r1.q
            );
        }
    }

    /// F(x) of a pulse table (held after its last sample; right limit at jumps).
    fn force_at(t: &[f64], f: &[f64], x: f64) -> f64 {
        if x >= t[t.len() - 1] {
            return f[f.len() - 1];
        }
        let j = t.partition_point(|&y| y <= x) - 1;
        let (t0, t1) = (t[j], t[j + 1]);
        if t1 == t0 {
            f[j + 1]
        } else {
            f[j] + (f[j + 1] - f[j]) * (x - t0) / (t1 - t0)
        }
    }

    /// (q, q̇) at x by the recurrence over the table cut at x (no segment scan).
    fn state_at(t: &[f64], f: &[f64], osc: &Oscillator, q0: f64, v0: f64, x: f64) -> (f64, f64) {
        let mut tt: Vec<f64> = t.iter().copied().filter(|&y| y < x).collect();
        let mut ff: Vec<f64> = f[..tt.len()].to_vec();
        tt.push(x);
        ff.push(force_at(t, f, x));
        let (q, v) = respond(&tt, &ff, osc, q0, v0);
        (q[q.len() - 1], v[v.len() - 1])
    }

    /// An independent search: the recurrence on a dense grid (each segment cut in
    /// 200, then 20,000 steps to t_max), returning the grid and the first cell
    /// [g[k−1], g[k]] where q̇ returns to zero or changes sign, if any.
    fn dense_scan(
        t: &[f64],
        f: &[f64],
        osc: &Oscillator,
        q0: f64,
        v0: f64,
        t_max: f64,
    ) -> (Vec<f64>, Option<usize>) {
        let t_last = t[t.len() - 1];
        let (mut g, mut gf) = (vec![t[0]], vec![f[0]]);
        for j in 1..t.len() {
            let (a, b) = (t[j - 1], t[j]);
            let pieces = if b > a { 200 } else { 1 };
            for p in 1..=pieces {
                let u = p as f64 / pieces as f64;
                g.push(if p == pieces { b } else { a + (b - a) * u });
                gf.push(if p == pieces {
                    f[j]
                } else {
                    f[j - 1] + (f[j] - f[j - 1]) * u
                });
            }
        }
        for p in 1..=20_000 {
            g.push(t_last + (t_max - t_last) * p as f64 / 20_000.0);
            gf.push(f[f.len() - 1]);
        }
        let (_, v) = respond(&g, &gf, osc, q0, v0);
        let mut s = sign(v0);
        for (k, &vk) in v.iter().enumerate().skip(1) {
            if s == 0.0 {
                s = sign(vk);
            } else if s * vk <= 0.0 {
                return (g, Some(k));
            }
        }
        (g, None)
    }

    /// Bisection and Newton steps on q̇(x) computed by [`state_at`].
    fn refine(
        t: &[f64],
        f: &[f64],
        osc: &Oscillator,
        q0: f64,
        v0: f64,
        mut lo: f64,
        mut hi: f64,
    ) -> f64 {
        let s = sign(state_at(t, f, osc, q0, v0, lo).1);
        let mut x = 0.5 * (lo + hi);
        for _ in 0..200 {
            let (q, v) = state_at(t, f, osc, q0, v0, x);
            if s * v > 0.0 {
                lo = x
            } else {
                hi = x
            }
            let a = force_at(t, f, x) / osc.mass
                - 2.0 * osc.zeta * osc.omega_n * v
                - osc.omega_n.powi(2) * q;
            let xn = x - v / a;
            let xn = if xn > lo && xn < hi {
                xn
            } else {
                0.5 * (lo + hi)
            };
            if (xn - x).abs() <= 1e-15 * x.abs() {
                return xn;
            }
            x = xn;
        }
        x
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(48))]
        #[test]
        fn first_rebound_matches_a_dense_scan(
            w in 1.0f64..20.0,
            z in prop_oneof![Just(0.0), 0.0f64..1.2, Just(1.0)],
            durations in prop::collection::vec(0.0f64..0.4, 2..5),
            heights in prop::collection::vec(-1.0f64..3.0, 5),
            q0 in prop_oneof![Just(0.0), -0.05f64..0.05],
            v0 in prop_oneof![Just(0.0), -1.0f64..1.0],
        ) {
            let osc = Oscillator::new(w, z, 0.5).unwrap();
            let mut t = vec![0.0];
            for d in &durations {
                t.push(t.last().unwrap() + d / w);
            }
            let mut f: Vec<f64> = heights[..t.len()].to_vec();
            *f.last_mut().unwrap() = 0.0; // a pulse: free vibration afterwards
            let r = first_rebound(&t, &f, &osc, q0, v0).unwrap();
            let t_max = t[t.len() - 1] + 40.0 / w;
            let (g, cell) = dense_scan(&t, &f, &osc, q0, v0, t_max);
            let Some(k) = cell else {
                prop_assert!(r.time > t_max, "kernel {} but the scan finds no extremum before {}", r.time, t_max);
                return Ok(());
            };
            // Not after the scan's first sign change.
            prop_assert!(r.time <= g[k] * (1.0 + 1e-12), "kernel {} after the scan's cell [{}, {}]", r.time, g[k - 1], g[k]);
            let (q, v) = state_at(&t, &f, &osc, q0, v0, r.time);
            let vscale = v0.abs().max(heights.iter().fold(0.0f64, |m, h| m.max(h.abs())) / (0.5 * w)).max(q0.abs() * w);
            prop_assert!(v.abs() <= 1e-9 * vscale, "q̇({}) = {} (scale {})", r.time, v, vscale);
            prop_assert!((r.q - q).abs() <= 1e-12 * (vscale / w).max(q.abs()), "q {} vs {}", r.q, q);
            if r.time >= g[k - 1] {
                // The same cell: the kernel's root and an independent refinement agree.
                let x = refine(&t, &f, &osc, q0, v0, g[k - 1], g[k]);
                prop_assert!((r.time - x).abs() <= 1e-10 * t_max, "time {} vs refined {}", r.time, x);
            } else {
                // An earlier extremum inside one scan cell (a short bump of q̇): q̇
                // has opposite signs just before and after it.
                let d = 1e-6 * (g[k] - g[k - 1]).min(r.time - t[0]);
                let (vb, va) = (state_at(&t, &f, &osc, q0, v0, r.time - d).1, state_at(&t, &f, &osc, q0, v0, r.time + d).1);
                prop_assert!(vb * va < 0.0, "no sign change around {}: {} then {}", r.time, vb, va);
            }
        }

        #[test]
        fn recurrence_matches_rk4(
            w in 0.5f64..20.0,
            z in 0.0f64..3.0,
            steps in prop::collection::vec(0.0f64..1.5, 1..6),
            forces in prop::collection::vec(-2.0f64..2.0, 7),
            q0 in -1.0f64..1.0,
            v0 in -1.0f64..1.0,
        ) {
            let m = 0.8;
            let osc = Oscillator::new(w, z, m).unwrap();
            let mut t = vec![0.25];
            for h in &steps {
                t.push(t.last().unwrap() + h / w);
            }
            let f = &forces[..t.len()];
            let (q, v) = respond(&t, f, &osc, q0, v0 * w);
            // RK4 with tiny steps on the piecewise-linear force: independent of Φ, Γ.
            let (mut x, mut y) = (q0, v0 * w);
            let acc = |x: f64, y: f64, p: f64| p / m - 2.0 * z * w * y - w * w * x;
            let scale = q.iter().chain(v.iter().map(|a| a / w).collect::<Vec<_>>().iter()).fold(1e-3f64, |s, a| s.max(a.abs()));
            for k in 1..t.len() {
                let h = t[k] - t[k - 1];
                let n = ((h * w * (1.0 + 2.0 * z)) / 2e-3).ceil().max(1.0) as usize;
                let dt = h / n as f64;
                let p = |s: f64| f[k - 1] + (f[k] - f[k - 1]) * s / h;
                for i in 0..n {
                    let s = i as f64 * dt;
                    let (k1x, k1v) = (y, acc(x, y, p(s)));
                    let (k2x, k2v) = (y + 0.5 * dt * k1v, acc(x + 0.5 * dt * k1x, y + 0.5 * dt * k1v, p(s + 0.5 * dt)));
                    let (k3x, k3v) = (y + 0.5 * dt * k2v, acc(x + 0.5 * dt * k2x, y + 0.5 * dt * k2v, p(s + 0.5 * dt)));
                    let (k4x, k4v) = (y + dt * k3v, acc(x + dt * k3x, y + dt * k3v, p(s + dt)));
                    x += dt / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
                    y += dt / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
                }
                if h > 0.0 {
                    prop_assert!((q[k] - x).abs() <= 1e-9 * scale, "q[{}] {} vs rk4 {}", k, q[k], x);
                    prop_assert!((v[k] - y).abs() <= 1e-9 * scale * w, "v[{}] {} vs rk4 {}", k, v[k], y);
                }
            }
        }

        #[test]
        fn constant_force_is_exact(
            w in 0.5f64..50.0,
            z in prop_oneof![0.0f64..0.99, Just(1.0), 1.01f64..3.0],
            steps in prop::collection::vec(0.0f64..3.0, 1..12),
            f0 in -5.0f64..5.0,
        ) {
            let osc = Oscillator::new(w, z, 1.5).unwrap();
            let mut t = vec![0.0];
            for h in &steps {
                t.push(t.last().unwrap() + h / w);
            }
            let (q, _) = respond(&t, &vec![f0; t.len()], &osc, 0.0, 0.0);
            let r: Vec<f64> = t.iter().map(|&x| step_ref(w, z, 1.5, f0, x).0).collect();
            let scale = (f0 / (1.5 * w * w)).abs().max(1e-300);
            for k in 0..t.len() {
                prop_assert!((q[k] - r[k]).abs() <= 1e-12 * scale, "{}: {} vs {}", k, q[k], r[k]);
            }
        }
    }

    // ---------------------------------------------------------------------
    // Contact oscillator.

    fn stop(m: f64, kf: f64, ks: f64, d: f64, zf: f64, zc: f64) -> Contact {
        Contact {
            mass: m,
            k_free: kf,
            k_stop: ks,
            preload: d,
            zeta_free: zf,
            zeta_contact: zc,
        }
    }

    #[test]
    fn undamped_contact_without_preload_conserves_energy() {
        let (m, kf, ks, v0) = (0.5, 200.0, 5000.0, -1.3);
        let c = stop(m, kf, ks, 0.0, 0.0, 0.0);
        let h = contact_response(&c, 0.0, v0, f64::INFINITY, 3, MAX_EVENTS).unwrap();
        let (wf, wc) = ((kf / m).sqrt(), ((kf + ks) / m).sqrt());
        let tc = PI / wc;
        assert_eq!(h.end, ContactEnd::MaxRebounds);
        assert_eq!(h.rebound_height.len(), 3);
        assert_eq!(h.contact_start.len(), 3);
        for i in 0..3 {
            let start = i as f64 * (tc + PI / wf);
            assert!((h.contact_start[i] - start).abs() < 1e-13, "start {i}");
            assert!((h.contact_duration[i] - tc).abs() < 1e-14, "duration {i}");
            assert!((h.exit_velocity[i] + v0).abs() < 1e-13, "exit {i}");
            assert!((h.impact_velocity[i] - v0).abs() < 1e-13, "impact {i}");
            assert!(
                (h.rebound_height[i] - v0.abs() / wf).abs() < 1e-14,
                "height {i}"
            );
            assert!((h.rebound_time[i] - (start + tc + 0.5 * PI / wf)).abs() < 1e-13);
            assert!((h.penetration[i] + v0.abs() / wc).abs() < 1e-14);
            assert!((h.penetration_time[i] - (start + 0.5 * tc)).abs() < 1e-13);
        }
        assert_eq!(
            (h.t_stop, h.x_stop, h.v_stop),
            (h.rebound_time[2], h.rebound_height[2], 0.0)
        );
        assert_eq!(h.n_events, 5);
    }

    #[test]
    fn undamped_contact_with_preload_follows_energy() {
        let (m, kf, ks, d, v0) = (0.02, 300.0, 9000.0, 2.5e-4, -0.4);
        let c = stop(m, kf, ks, d, 0.0, 0.0);
        let h = contact_response(&c, 0.0, v0, f64::INFINITY, 2, MAX_EVENTS).unwrap();
        // ½ m v0² = ½ k_f ((x + δ)² − δ²) at the top of the rebound.
        let top = (d * d + m * v0 * v0 / kf).sqrt() - d;
        let kc = kf + ks;
        let xc = -kf * d / kc;
        let amp = (xc * xc + m * v0 * v0 / kc).sqrt();
        let phi = (xc.abs() / amp).acos();
        let wc = (kc / m).sqrt();
        for i in 0..2 {
            assert!(
                (h.exit_velocity[i] + v0).abs() < 1e-13,
                "{}",
                h.exit_velocity[i]
            );
            assert!(
                (h.rebound_height[i] - top).abs() < 1e-15 + 1e-12 * top,
                "{} vs {top}",
                h.rebound_height[i]
            );
            assert!(
                (h.penetration[i] - (xc - amp)).abs() < 1e-15,
                "{}",
                h.penetration[i]
            );
            let dur = (2.0 * PI - 2.0 * phi) / wc;
            assert!(
                (h.contact_duration[i] - dur).abs() < 1e-13 * dur,
                "{} vs {dur}",
                h.contact_duration[i]
            );
        }
    }

    #[test]
    fn damped_contact_restitution_and_rest() {
        // δ = 0: each contact is half a damped period and scales the speed by
        // e = exp(−ζπ/√(1 − ζ²)).
        let (m, kf, ks, zc) = (1.0, 100.0, 1e4, 0.1);
        let c = stop(m, kf, ks, 0.0, 0.0, zc);
        let h = contact_response(&c, 0.0, -2.0, f64::INFINITY, 4, MAX_EVENTS).unwrap();
        let wd = ((kf + ks) / m).sqrt() * (1.0 - zc * zc).sqrt();
        let e = (-zc * PI / (1.0 - zc * zc).sqrt()).exp();
        for i in 0..4 {
            assert!((h.contact_duration[i] - PI / wd).abs() < 1e-13);
            let ratio = -h.exit_velocity[i] / h.impact_velocity[i];
            assert!((ratio - e).abs() < 1e-13, "{ratio} vs {e}");
        }
        // Over-damped contact: the link never leaves.
        let c = stop(m, kf, ks, 0.0, 0.0, 2.0);
        let h = contact_response(&c, 0.0, -2.0, f64::INFINITY, 4, MAX_EVENTS).unwrap();
        assert_eq!(h.end, ContactEnd::RestInContact);
        assert_eq!((h.t_stop, h.x_stop, h.n_events), (f64::INFINITY, 0.0, 0));
        assert!(h.contact_end.is_empty() && h.penetration.len() == 1);
        // Preload and damping: bounces die out and the link settles in contact.
        let (kf, d) = (100.0, 1e-3);
        let c = stop(m, kf, ks, d, 0.05, 0.05);
        let h = contact_response(&c, 0.0, -2.0, f64::INFINITY, 1000, MAX_EVENTS).unwrap();
        assert_eq!(h.end, ContactEnd::RestInContact);
        assert!(
            h.n_events > 2 && h.n_events.is_multiple_of(2),
            "{}",
            h.n_events
        );
        assert!((h.x_stop + kf * d / (kf + ks)).abs() < 1e-18);
        assert!(h.rebound_height.windows(2).all(|w| w[1] < w[0]));
        // A free flight that never returns: δ = 0 and an over-damped free spring.
        let c = stop(m, kf, ks, 0.0, 1.5, 0.0);
        let h = contact_response(&c, 0.0, -2.0, f64::INFINITY, 5, MAX_EVENTS).unwrap();
        assert_eq!(h.end, ContactEnd::RestFree);
        assert_eq!(
            (h.rebound_height.len(), h.contact_end.len(), h.n_events),
            (1, 1, 1)
        );
        assert_eq!((h.t_stop, h.x_stop), (f64::INFINITY, 0.0));
    }

    #[test]
    fn resting_on_the_stop_does_not_chatter() {
        // Released at rest on the stop with a preload and no contact damping:
        // the contact oscillation touches x = 0 without leaving.
        let c = stop(1.0, 50.0, 500.0, 1e-3, 0.0, 0.0);
        let h = contact_response(&c, 0.0, 0.0, f64::INFINITY, 3, 100).unwrap();
        assert_eq!((h.end, h.n_events), (ContactEnd::RestInContact, 0));
        assert_eq!(h.contact_start, vec![0.0]);
        // No preload: at rest exactly.
        let c = stop(1.0, 50.0, 500.0, 0.0, 0.0, 0.0);
        let h = contact_response(&c, 0.0, 0.0, f64::INFINITY, 3, 100).unwrap();
        assert_eq!(
            (h.end, h.n_events, h.x_stop),
            (ContactEnd::RestInContact, 0, 0.0)
        );
    }

    #[test]
    fn event_cap_and_t_end() {
        // δ = 0, light damping: bounces shrink geometrically at a constant rate,
        // forever: the cap ends the history and sampling past it is an error.
        let c = stop(1.0, 100.0, 1e4, 0.0, 0.01, 0.01);
        let h = contact_response(&c, 0.0, -1.0, f64::INFINITY, 1_000_000, 50).unwrap();
        assert_eq!((h.end, h.n_events), (ContactEnd::MaxEvents, 50));
        let times: Vec<f64> = (0..100).map(|k| k as f64).collect();
        let (mut x, mut v) = (vec![0.0; 100], vec![0.0; 100]);
        let e = contact_sample_into(&c, 0.0, -1.0, &times, 50, &mut x, &mut v).unwrap_err();
        assert!(
            matches!(e, DuhamelError::TooManyEvents { max_events: 50, .. }),
            "{e}"
        );
        // t_end: the stop state is the sampled state at t_end.
        let t_end = 0.123;
        let h = contact_response(&c, 0.0, -1.0, t_end, 100, MAX_EVENTS).unwrap();
        assert_eq!((h.end, h.t_stop), (ContactEnd::TEnd, t_end));
        let (mut x, mut v) = ([0.0], [0.0]);
        contact_sample_into(&c, 0.0, -1.0, &[t_end], MAX_EVENTS, &mut x, &mut v).unwrap();
        assert_eq!((h.x_stop, h.v_stop), (x[0], v[0]));
        assert!(h
            .contact_start
            .iter()
            .chain(&h.rebound_time)
            .all(|&s| s <= t_end));
    }

    #[test]
    fn samples_follow_the_events_and_an_rk4_reference() {
        let (m, kf, ks, d, zf, zc) = (0.1, 400.0, 2e4, 5e-4, 0.03, 0.08);
        let c = stop(m, kf, ks, d, zf, zc);
        let (x0, v0) = (0.0, -0.8);
        let h = contact_response(&c, x0, v0, f64::INFINITY, 50, MAX_EVENTS).unwrap();
        // At the events x = 0; at the tops ẋ = 0 and x is the height.
        let mut times: Vec<f64> = h
            .contact_start
            .iter()
            .chain(&h.contact_end)
            .chain(&h.rebound_time)
            .copied()
            .collect();
        times.sort_by(f64::total_cmp);
        let (mut x, mut v) = (vec![0.0; times.len()], vec![0.0; times.len()]);
        contact_sample_into(&c, x0, v0, &times, MAX_EVENTS, &mut x, &mut v).unwrap();
        for (k, &tk) in times.iter().enumerate() {
            if let Some(j) = h.rebound_time.iter().position(|&r| r == tk) {
                assert!(
                    (x[k] - h.rebound_height[j]).abs() < 1e-16 && v[k].abs() < 1e-12,
                    "top {j}"
                );
            } else {
                assert!(x[k].abs() < 1e-16, "event at {tk}: x {}", x[k]);
            }
        }
        // RK4 on the piecewise-smooth ODE, tiny steps, the regime frozen within a
        // step and each crossing located by bisection on the step's length (the
        // damping makes the acceleration jump there: without the location, RK4
        // would be first order).
        let t_end = 0.3;
        let n = 30_000;
        let dt = t_end / n as f64;
        let (cf, cc) = (
            2.0 * zf * (kf * m).sqrt(),
            2.0 * zc * ((kf + ks) * m).sqrt(),
        );
        let acc = |x: f64, v: f64, contact: bool| {
            if contact {
                (-kf * (x + d) - ks * x - cc * v) / m
            } else {
                (-kf * (x + d) - cf * v) / m
            }
        };
        let rk4 = |x: f64, v: f64, dt: f64, c: bool| {
            let (k1x, k1v) = (v, acc(x, v, c));
            let (k2x, k2v) = (
                v + 0.5 * dt * k1v,
                acc(x + 0.5 * dt * k1x, v + 0.5 * dt * k1v, c),
            );
            let (k3x, k3v) = (
                v + 0.5 * dt * k2v,
                acc(x + 0.5 * dt * k2x, v + 0.5 * dt * k2v, c),
            );
            let (k4x, k4v) = (v + dt * k3v, acc(x + dt * k3x, v + dt * k3v, c));
            (
                x + dt / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x),
                v + dt / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v),
            )
        };
        let (mut x, mut v, mut contact) = (x0, v0, true);
        let samples: Vec<f64> = (1..=30).map(|k| k as f64 * 0.01).collect();
        let (mut xs, mut vs) = (vec![0.0; 30], vec![0.0; 30]);
        contact_sample_into(&c, x0, v0, &samples, MAX_EVENTS, &mut xs, &mut vs).unwrap();
        let amp = v0.abs() / (kf / m).sqrt();
        for i in 1..=n {
            let (x1, v1) = rk4(x, v, dt, contact);
            if (x1 > 0.0) == contact {
                // Crossed x = 0 within the step: land on it, switch, finish the step.
                let (mut lo, mut hi) = (0.0, dt);
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    if (rk4(x, v, mid, contact).0 > 0.0) == contact {
                        hi = mid
                    } else {
                        lo = mid
                    }
                }
                let (_, vc) = rk4(x, v, hi, contact);
                contact = !contact;
                (x, v) = rk4(0.0, vc, dt - hi, contact);
            } else {
                (x, v) = (x1, v1);
            }
            if i % 1000 == 0 {
                let j = i / 1000 - 1;
                assert!(
                    (xs[j] - x).abs() < 1e-9 * amp,
                    "t {}: {} vs rk4 {x}",
                    samples[j],
                    xs[j]
                );
                assert!(
                    (vs[j] - v).abs() < 1e-9 * v0.abs(),
                    "t {}: {} vs rk4 {v}",
                    samples[j],
                    vs[j]
                );
            }
        }
    }

    #[test]
    fn contact_input_errors() {
        let ok = stop(1.0, 10.0, 100.0, 0.0, 0.0, 0.0);
        for (c, field) in [
            (Contact { mass: 0.0, ..ok }, "mass"),
            (Contact { k_free: 0.0, ..ok }, "k_free"),
            (Contact { k_free: -1.0, ..ok }, "k_free"),
            (Contact { k_stop: 0.0, ..ok }, "k_stop"),
            (
                Contact {
                    k_stop: f64::NAN,
                    ..ok
                },
                "k_stop",
            ),
            (
                Contact {
                    preload: -1e-3,
                    ..ok
                },
                "preload",
            ),
            (
                Contact {
                    preload: f64::INFINITY,
                    ..ok
                },
                "preload",
            ),
            (
                Contact {
                    zeta_free: -0.1,
                    ..ok
                },
                "zeta_free",
            ),
            (
                Contact {
                    zeta_contact: f64::NAN,
                    ..ok
                },
                "zeta_contact",
            ),
        ] {
            let e = contact_response(&c, 0.0, -1.0, 1.0, 3, 10).unwrap_err();
            assert!(
                matches!(e, DuhamelError::Param { field: f, .. } if f == field),
                "{e}"
            );
            let e =
                contact_sample_into(&c, 0.0, -1.0, &[0.0], 10, &mut [0.0], &mut [0.0]).unwrap_err();
            assert!(
                matches!(e, DuhamelError::Param { field: f, .. } if f == field),
                "{e}"
            );
        }
        assert_eq!(
            contact_response(
                &Contact {
                    preload: -1e-3,
                    ..ok
                },
                0.0,
                -1.0,
                1.0,
                3,
                10
            )
            .unwrap_err()
            .to_string(),
            "preload must be finite and >= 0; got -0.001"
        );
        let e = |r: Result<ContactHistory, DuhamelError>| r.unwrap_err();
        assert!(matches!(
            e(contact_response(&ok, f64::NAN, -1.0, 1.0, 3, 10)),
            DuhamelError::Param { field: "x0", .. }
        ));
        assert!(matches!(
            e(contact_response(&ok, 0.0, f64::INFINITY, 1.0, 3, 10)),
            DuhamelError::Param { field: "v0", .. }
        ));
        assert!(matches!(
            e(contact_response(&ok, 0.0, -1.0, 0.0, 3, 10)),
            DuhamelError::Param { field: "t_end", .. }
        ));
        assert!(matches!(
            e(contact_response(&ok, 0.0, -1.0, f64::NAN, 3, 10)),
            DuhamelError::Param { field: "t_end", .. }
        ));
        assert!(matches!(
            e(contact_response(&ok, 0.0, -1.0, 1.0, 0, 10)),
            DuhamelError::Count {
                field: "max_rebounds",
                ..
            }
        ));
        assert!(matches!(
            e(contact_response(&ok, 0.0, -1.0, 1.0, 3, 0)),
            DuhamelError::Count {
                field: "max_events",
                ..
            }
        ));
        let s = |t: &[f64], x: &mut [f64], v: &mut [f64]| {
            contact_sample_into(&ok, 0.0, -1.0, t, 10, x, v)
        };
        assert!(matches!(
            s(&[0.2, 0.1], &mut [0.0; 2], &mut [0.0; 2]),
            Err(DuhamelError::Decreasing {
                field: "times",
                index: 1,
                ..
            })
        ));
        assert!(matches!(
            s(&[-0.1, 0.1], &mut [0.0; 2], &mut [0.0; 2]),
            Err(DuhamelError::Param {
                field: "times[0]",
                ..
            })
        ));
        assert!(matches!(
            s(&[0.0, f64::NAN], &mut [0.0; 2], &mut [0.0; 2]),
            Err(DuhamelError::NotFinite {
                field: "times",
                index: 1,
                ..
            })
        ));
        assert!(matches!(
            s(&[0.0, 0.1], &mut [0.0; 1], &mut [0.0; 2]),
            Err(DuhamelError::Length { field: "x_out", .. })
        ));
        assert!(s(&[], &mut [], &mut []).is_ok());
    }

    // ---------------------------------------------------------------------
    // Speed (run with --ignored --nocapture in release).

    #[test]
    #[ignore]
    fn speed_report() {
        use std::time::Instant;
        let osc = Oscillator::new(30.0, 0.05, 2.0).unwrap();
        for (name, n) in [
            ("uniform", 10_000usize),
            ("linspace", 10_000),
            ("uniform", 10_000_000),
        ] {
            let t: Vec<f64> = if name == "uniform" {
                (0..n).map(|k| k as f64 * 0.0001220703125).collect()
            } else {
                (0..n).map(|k| 2.0 * (k as f64 / (n - 1) as f64)).collect()
            };
            let f: Vec<f64> = (0..n).map(|k| ((k % 1000) as f64).sin()).collect();
            let (mut q, mut v) = (vec![1.0; n], vec![1.0; n]);
            let reps = (40_000_000 / n).max(2);
            let t0 = Instant::now();
            for _ in 0..reps {
                response_into(&t, &f, &osc, 0.0, 1.0, &mut q, None).unwrap();
            }
            let a = (n * reps) as f64 / t0.elapsed().as_secs_f64();
            let t0 = Instant::now();
            for _ in 0..reps {
                response_into(&t, &f, &osc, 0.0, 1.0, &mut q, Some(&mut v)).unwrap();
            }
            let b = (n * reps) as f64 / t0.elapsed().as_secs_f64();
            println!("single, {name} N={n}: q {a:.3e} steps/s, q and v {b:.3e} steps/s");
        }
        // Batch: B cases × 10,000 steps, and the peak-only batch on a 3-point pulse.
        let (b, n) = (2000usize, 10_000usize);
        let t: Vec<f64> = (0..n).map(|k| k as f64 * 1e-5).collect();
        let forces: Vec<f64> = (0..b * n)
            .map(|i| if i % n < 200 { 1.0 } else { 0.0 })
            .collect();
        let w: Vec<f64> = (0..b).map(|i| 500.0 + i as f64).collect();
        let z: Vec<f64> = (0..b).map(|i| 0.01 * (i % 300) as f64).collect();
        let ones = vec![1.0; b];
        let zeros = vec![0.0; b];
        let cases = cases_of(&w, &z, &ones, &zeros, &zeros);
        let mut out = vec![0.0; b * n];
        let mut full = [0.0; 2];
        for threads in [1usize, 2] {
            response_batch_into(&t, &forces, &cases, Some(threads as i64), &mut out).unwrap();
            let t0 = Instant::now();
            response_batch_into(&t, &forces, &cases, Some(threads as i64), &mut out).unwrap();
            let dt = t0.elapsed().as_secs_f64();
            full[threads - 1] = dt / b as f64;
            println!(
                "batch full history, {threads} thread(s): {:.3e} case-steps/s ({:.2e} s per case)",
                (b * n) as f64 / dt,
                dt / b as f64
            );
        }
        let bb = 1_000_000;
        let tk = [0.0, 1e-3, 2e-3];
        let pulses: Vec<f64> = (0..bb)
            .flat_map(|i| [0.0, 1.0 + (i % 7) as f64, 0.0])
            .collect();
        let w: Vec<f64> = (0..bb).map(|i| 500.0 + (i % 1000) as f64).collect();
        let z: Vec<f64> = (0..bb).map(|i| 0.003 * (i % 1000) as f64).collect();
        let (ones, zeros) = (vec![1.0; bb], vec![0.0; bb]);
        let cases = cases_of(&w, &z, &ones, &zeros, &zeros);
        let (mut tt, mut qq) = (vec![0.0; bb], vec![0.0; bb]);
        for threads in [1usize, 2] {
            let t0 = Instant::now();
            first_rebound_batch_into(
                &tk,
                &pulses,
                &cases,
                false,
                Some(threads as i64),
                &mut tt,
                &mut qq,
            )
            .unwrap();
            let dt = t0.elapsed().as_secs_f64();
            println!(
                "batch peak-only (3-point pulse, ζ in [0, 3]), {threads} thread(s): {:.3e} cases/s, {:.0}x faster per case than the 10,000-step history",
                bb as f64 / dt,
                full[threads - 1] / (dt / bb as f64)
            );
        }
    }
}
