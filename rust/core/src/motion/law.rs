//! The motion laws: named rises and half laws, user polynomials, evaluated in
//! parallel chunks across SIMD lanes.

use std::f64::consts::{FRAC_PI_2, PI};

use rayon::prelude::*;

use crate::geom::{sin, sin_lanes};
use crate::input::InvalidInput;
use crate::parallel::{pool, resolve_threads};

/// Highest polynomial degree accepted for a user law.
pub const MAX_DEGREE: usize = 24;

/// Tolerance on the boundary conditions of a user law (Z(0) = 0, Z(1) = 1, …).
pub const LAW_TOL: f64 = 1e-9;

/// Errors of the motion domain.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MotionError {
    #[error("unknown motion law {name:?}; known laws: {known}")]
    UnknownLaw { name: String, known: String },
    #[error("{what}")]
    BadLaw { what: String },
    // Segments are counted from 1 in every message, as a designer counts the
    // segment tables of a file (`index` is the 0-based position).
    #[error("segment {} ({law}): {what}", index + 1)]
    BadSegment {
        index: usize,
        law: String,
        what: String,
    },
    #[error(
        "segment {} ({left_law}) → segment {} ({right_law}) at {}°: the {what} jumps from {} to {}",
        left + 1, right + 1,
        crate::num_text::Num(*at_deg), crate::num_text::Num(*from), crate::num_text::Num(*to)
    )]
    Join {
        left: usize,
        left_law: String,
        right: usize,
        right_law: String,
        at_deg: f64,
        what: &'static str,
        from: f64,
        to: f64,
    },
    #[error("{field}[{index}] = {} lies outside [{lo}, {hi}]{why}", crate::num_text::Num(*value))]
    OutOfRange {
        field: &'static str,
        index: usize,
        value: f64,
        lo: f64,
        hi: f64,
        why: &'static str,
    },
    #[error(transparent)]
    Input(#[from] InvalidInput),
}

crate::input::wraps_invalid_input!(MotionError);

/// One piece of a law: Z = Σ c_k t^k + amp·sin(freq·t + phase), t = x − x0.
#[derive(Debug, Clone, PartialEq)]
pub struct Segment {
    pub x0: f64,
    pub x1: f64,
    pub poly: Vec<f64>,
    pub amp: f64,
    pub freq: f64,
    pub phase: f64,
}

/// A segment prepared for evaluation: for each order 0..=3 the coefficients of
/// that derivative of the polynomial, and the sinusoid's amplitude and phase
/// (d^n/dt^n sin(ωt + φ) = ω^n sin(ωt + φ + nπ/2)), so that evaluating costs one
/// Horner pass and at most one sine.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Fast {
    pub(super) x0: f64,
    pub(super) x1: f64,
    pub(super) poly: [Vec<f64>; 4],
    pub(super) amp: [f64; 4],
    pub(super) freq: f64,
    pub(super) phase: [f64; 4],
}

impl Fast {
    pub(super) fn new(s: &Segment) -> Fast {
        let poly = std::array::from_fn(|order| {
            (order..s.poly.len())
                .map(|k| {
                    let falling: f64 = (0..order).map(|m| (k - m) as f64).product();
                    s.poly[k] * falling
                })
                .collect()
        });
        Fast {
            x0: s.x0,
            x1: s.x1,
            poly,
            amp: std::array::from_fn(|order| s.amp * s.freq.powi(order as i32)),
            freq: s.freq,
            phase: std::array::from_fn(|order| s.phase + order as f64 * FRAC_PI_2),
        }
    }

    #[inline(always)]
    pub(super) fn eval(&self, x: f64, order: usize) -> f64 {
        let t = x - self.x0;
        let c = &self.poly[order];
        let mut p = 0.0;
        for &ck in c.iter().rev() {
            p = p * t + ck;
        }
        let a = self.amp[order];
        if a != 0.0 {
            p += a * sin(self.freq * t + self.phase[order]);
        }
        p
    }
}

impl Fast {
    /// [`Fast::eval`] for orders 0..=3 at once: the same arithmetic per order
    /// (so the same values), `t` computed once.
    #[inline(always)]
    pub(super) fn eval_all(&self, x: f64) -> [f64; 4] {
        let t = x - self.x0;
        std::array::from_fn(|order| {
            let mut p = 0.0;
            for &ck in self.poly[order].iter().rev() {
                p = p * t + ck;
            }
            let a = self.amp[order];
            if a != 0.0 {
                p += a * sin(self.freq * t + self.phase[order]);
            }
            p
        })
    }
}

/// An acceleration piece used to build a law: a(t) = Σ p_k t^k + A·sin(ω t + φ).
struct AccelPiece {
    x1: f64,
    poly: Vec<f64>,
    amp: f64,
    freq: f64,
    phase: f64,
}

/// A dimensionless law Z(x) on [0, 1], with its peaks.
#[derive(Debug, Clone, PartialEq)]
pub struct Law {
    pub segments: Vec<Segment>,
    pub(super) fast: Vec<Fast>,
    /// max |Z'| on [0, 1] (Cv for a rise, Z'max for a half law).
    pub dz_max: f64,
    /// max |Z''| on [0, 1] (Ca for a rise, Z''max for a half law).
    pub ddz_max: f64,
}

/// Names of the built-in laws.
pub const NAMES: [&str; 6] = [
    "cycloidal",
    "harmonic",
    "polynomial_345",
    "polynomial_4567",
    "modified_sine",
    "modified_trapezoid",
];

impl Law {
    pub(crate) fn from_segments(segments: Vec<Segment>) -> Law {
        let fast = segments.iter().map(Fast::new).collect();
        let mut law = Law {
            segments,
            fast,
            dz_max: 0.0,
            ddz_max: 0.0,
        };
        law.dz_max = law.peak(1).1;
        law.ddz_max = law.peak(2).1;
        law
    }

    /// The full rise of a named law (Z' = 0 at both ends).
    pub fn rise(name: &str) -> Result<Law, MotionError> {
        let one = |poly: Vec<f64>, amp: f64, freq: f64, phase: f64| {
            vec![Segment {
                x0: 0.0,
                x1: 1.0,
                poly,
                amp,
                freq,
                phase,
            }]
        };
        let w = 4.0 * PI;
        let piece = |x1: f64, poly: Vec<f64>, amp: f64, freq: f64, phase: f64| AccelPiece {
            x1,
            poly,
            amp,
            freq,
            phase,
        };
        let segments = match name {
            "cycloidal" => one(vec![0.0, 1.0], -0.5 / PI, 2.0 * PI, 0.0),
            // (1 − cos πx)/2, with −cos written as a shifted sine.
            "harmonic" => one(vec![0.5], -0.5, PI, FRAC_PI_2),
            "polynomial_345" => one(vec![0.0, 0.0, 0.0, 10.0, -15.0, 6.0], 0.0, 0.0, 0.0),
            "polynomial_4567" => one(
                vec![0.0, 0.0, 0.0, 0.0, 35.0, -84.0, 70.0, -20.0],
                0.0,
                0.0,
                0.0,
            ),
            // Acceleration: sine ramp over 1/8, a sine of period 3/2 through the
            // middle 3/4, sine ramp back to zero over the last 1/8.
            "modified_sine" => integrate(&[
                piece(0.125, vec![], 1.0, w, 0.0),
                piece(0.875, vec![], 1.0, w / 3.0, FRAC_PI_2),
                piece(1.0, vec![], -1.0, w, FRAC_PI_2),
            ]),
            // Acceleration: sine ramps of 1/8 joined by constant plateaus of 1/4.
            "modified_trapezoid" => integrate(&[
                piece(0.125, vec![], 1.0, w, 0.0),
                piece(0.375, vec![1.0], 0.0, 0.0, 0.0),
                piece(0.625, vec![], 1.0, w, FRAC_PI_2),
                piece(0.875, vec![-1.0], 0.0, 0.0, 0.0),
                piece(1.0, vec![], -1.0, w, FRAC_PI_2),
            ]),
            _ => {
                return Err(MotionError::UnknownLaw {
                    name: name.to_string(),
                    known: NAMES.join(", "),
                })
            }
        };
        Ok(Law::from_segments(segments))
    }

    /// The half law of a named law: the first half of its rise on the unit square.
    pub fn half(name: &str) -> Result<Law, MotionError> {
        Ok(Law::rise(name)?.first_half())
    }

    /// Z_h(j) = 2·Z(j/2): the first half of this (symmetric) rise, rescaled.
    pub fn first_half(&self) -> Law {
        let mut segments = Vec::new();
        for s in &self.segments {
            if s.x0 >= 0.5 {
                break;
            }
            let poly = s
                .poly
                .iter()
                .enumerate()
                .map(|(k, &c)| 2.0 * c * 0.5f64.powi(k as i32))
                .collect();
            segments.push(Segment {
                x0: 2.0 * s.x0,
                x1: (2.0 * s.x1).min(1.0),
                poly,
                amp: 2.0 * s.amp,
                freq: 0.5 * s.freq,
                phase: s.phase,
            });
        }
        Law::from_segments(segments)
    }

    /// A user polynomial Z = Σ c_k x^k, checked as a rise (Z(0) = 0, Z(1) = 1,
    /// Z'(0) = Z'(1) = 0) or as a half law (Z(0) = 0, Z(1) = 1, Z'(0) = 0, Z'
    /// largest at x = 1); in both forms Z' ≥ 0 (the law never runs backwards).
    pub fn polynomial(coeffs: &[f64], rise: bool) -> Result<Law, MotionError> {
        InvalidInput::check_finite("coeffs", coeffs)?;
        if coeffs.len() < 2 || coeffs.len() > MAX_DEGREE + 1 {
            return Err(MotionError::BadLaw {
                what: format!(
                    "coeffs must hold between 2 and {} coefficients c0, c1, … of Z = Σ c_k x^k; got {}",
                    MAX_DEGREE + 1,
                    coeffs.len()
                ),
            });
        }
        let law = Law::from_segments(vec![Segment {
            x0: 0.0,
            x1: 1.0,
            poly: coeffs.to_vec(),
            amp: 0.0,
            freq: 0.0,
            phase: 0.0,
        }]);
        let form = if rise { "rise" } else { "half law" };
        let check = |ok: bool, what: String| {
            if ok {
                Ok(())
            } else {
                Err(MotionError::BadLaw {
                    what: format!("this polynomial is not a {form}: {what}"),
                })
            }
        };
        let (z0, z1, v0, v1) = (law.z(0.0, 0), law.z(1.0, 0), law.z(0.0, 1), law.z(1.0, 1));
        check(z0.abs() <= LAW_TOL, format!("Z(0) = {z0} must be 0"))?;
        check(
            (z1 - 1.0).abs() <= LAW_TOL,
            format!("Z(1) = {z1} must be 1"),
        )?;
        check(v0.abs() <= LAW_TOL, format!("Z'(0) = {v0} must be 0"))?;
        if rise {
            check(v1.abs() <= LAW_TOL, format!("Z'(1) = {v1} must be 0"))?;
        } else {
            check(
                v1 >= law.dz_max - LAW_TOL * law.dz_max.max(1.0),
                format!(
                    "Z' must peak at x = 1 (Z'(1) = {v1}, but max Z' = {})",
                    law.dz_max
                ),
            )?;
        }
        let (at, lowest) = law.peak_signed(1, -1.0);
        check(
            lowest >= -LAW_TOL,
            format!("Z' = {lowest} < 0 at x = {at}: the law runs backwards"),
        )?;
        Ok(law)
    }

    /// Z^(order)(x), order 0..=3, for x in [0, 1].
    #[inline]
    pub fn z(&self, x: f64, order: usize) -> f64 {
        let s = &self.fast;
        let mut k = 0;
        while k + 1 < s.len() && x > s[k].x1 {
            k += 1;
        }
        s[k].eval(x, order.min(3))
    }

    /// [Z, Z′, Z″, Z‴](x) for x in [0, 1]: bit for bit `z(x, k)` for k = 0..=3,
    /// with one piece lookup for the four orders.
    ///
    /// ```
    /// # use cyclomech_core::motion::Law;
    /// let law = Law::rise("cycloidal").unwrap();
    /// let z = law.z_all(0.25);
    /// assert_eq!(z, [0, 1, 2, 3].map(|k| law.z(0.25, k)));
    /// ```
    #[inline]
    pub fn z_all(&self, x: f64) -> [f64; 4] {
        let s = &self.fast;
        let mut k = 0;
        while k + 1 < s.len() && x > s[k].x1 {
            k += 1;
        }
        s[k].eval_all(x)
    }

    /// The piece the first of `x` lies in, and whether every value of `x` lies
    /// in it as the lookup of `z` puts them: v in piece k iff x1(k − 1) < v ≤
    /// x1(k), open ends for the first and last pieces (NaN is in none).
    #[inline(always)]
    fn lanes_piece<const L: usize>(&self, x: &[f64; L]) -> (&Fast, bool) {
        let s = &self.fast;
        let mut k = 0;
        while k + 1 < s.len() && x[0] > s[k].x1 {
            k += 1;
        }
        let lo = if k == 0 {
            f64::NEG_INFINITY
        } else {
            s[k - 1].x1
        };
        let hi = if k + 1 == s.len() {
            f64::INFINITY
        } else {
            s[k].x1
        };
        (
            &s[k],
            x.iter().fold(true, |ok, &v| ok & (v > lo) & (v <= hi)),
        )
    }

    /// [`Law::z_all`] of each value of `x`, as the lanes' four rows: the path
    /// of lanes that straddle pieces.
    #[inline(always)]
    fn z_all_each<const L: usize>(&self, x: &[f64; L]) -> [[f64; L]; 4] {
        let mut out = [[0.0; L]; 4];
        for (l, &v) in x.iter().enumerate() {
            let z = self.z_all(v);
            for o in 0..4 {
                out[o][l] = z[o];
            }
        }
        out
    }

    /// [`Law::z_all`] for `L` values x in [0, 1] at once, as four lanes [Z, Z′,
    /// Z″, Z‴]: bit for bit `z_all` per value. Values in one piece (the common
    /// case for sorted x) run as loops across lanes without branches, so that a
    /// caller compiled for AVX2 or AVX-512 (through `pulp`, inlining this) runs
    /// several values per instruction; otherwise each value goes alone.
    ///
    /// ```
    /// # use cyclomech_core::motion::Law;
    /// let law = Law::rise("modified_sine").unwrap();
    /// let x = [0.1, 0.2, 0.5, 0.95];
    /// let z = law.z_all_lanes(&x);
    /// for (l, &v) in x.iter().enumerate() {
    ///     assert_eq!([z[0][l], z[1][l], z[2][l], z[3][l]], law.z_all(v));
    /// }
    /// ```
    #[inline(always)]
    pub fn z_all_lanes<const L: usize>(&self, x: &[f64; L]) -> [[f64; L]; 4] {
        let (f, one_piece) = self.lanes_piece(x);
        // The branch-free sine holds for |argument| ≤ 1e6; here |t| ≤ 1.
        let sine_ok = (0..4).all(|o| f.amp[o] == 0.0 || f.freq.abs() + f.phase[o].abs() <= 1e5);
        if !(one_piece && sine_ok) {
            return self.z_all_each(x);
        }
        // Plain loops, no closures: a closure the compiler keeps out of line
        // would lose the caller's instruction set.
        let mut t = [0.0; L];
        for l in 0..L {
            t[l] = x[l] - f.x0;
        }
        let mut out = [[0.0; L]; 4];
        for (order, p) in out.iter_mut().enumerate() {
            for &ck in f.poly[order].iter().rev() {
                for l in 0..L {
                    p[l] = p[l] * t[l] + ck;
                }
            }
            let (a, w, phase) = (f.amp[order], f.freq, f.phase[order]);
            if a != 0.0 {
                for l in 0..L {
                    p[l] += a * sin_lanes(w * t[l] + phase);
                }
            }
        }
        out
    }

    /// [Z, Z′, Z″, Z‴] for `L` values x in [0, 1] (as [`Law::z_all_lanes`]),
    /// with the piece's sinusoid taken once for the four orders and fused
    /// multiply-adds: sin(ωt + φ + nπ/2) is sin, cos, −sin, −cos of ωt + φ, from
    /// one [`sin_cos_fma_lanes`](crate::geom) (where `z_all_lanes` takes four
    /// sines of four rounded phases), and each Horner step is one `mul_add`.
    /// Within 1e-13 of each order's scale of `z_all` (tested; where a piece's
    /// polynomial and sinusoid cancel, both forms round at their terms' size),
    /// not bit for bit;
    /// for callers compiled with FMA (a kernel dispatched by `pulp` to AVX2 or
    /// AVX-512: elsewhere `mul_add` is a libm call). Values in one piece run
    /// across lanes without branches; otherwise each value goes alone through
    /// `z_all`.
    ///
    /// ```
    /// # use cyclomech_core::motion::Law;
    /// let law = Law::rise("cycloidal").unwrap();
    /// let x = [0.1, 0.2, 0.5, 0.95];
    /// let z = law.z_all_lanes_shared(&x);
    /// for (l, &v) in x.iter().enumerate() {
    ///     for (o, want) in law.z_all(v).into_iter().enumerate() {
    ///         assert!((z[o][l] - want).abs() <= 1e-13 * (1.0 + want.abs()));
    ///     }
    /// }
    /// ```
    #[inline(always)]
    pub fn z_all_lanes_shared<const L: usize>(&self, x: &[f64; L]) -> [[f64; L]; 4] {
        let (f, one_piece) = self.lanes_piece(x);
        // (NaN fails the comparisons.) Within [−1, 2], |t| ≤ 3 (a piece lies in
        // [0, 1]), so the branch-free sine's argument stays within 1e6.
        let in_range = x.iter().fold(true, |ok, v| ok & (-1.0..=2.0).contains(v));
        let wave = f.amp.iter().any(|&a| a != 0.0);
        let sine_ok = !wave || 3.0 * f.freq.abs() + f.phase[0].abs() <= 1e6;
        if !(one_piece && in_range && sine_ok) {
            return self.z_all_each(x);
        }
        let mut t = [0.0; L];
        for l in 0..L {
            t[l] = x[l] - f.x0;
        }
        let mut out = [[0.0f64; L]; 4];
        for (order, p) in out.iter_mut().enumerate() {
            for &ck in f.poly[order].iter().rev() {
                for l in 0..L {
                    p[l] = p[l].mul_add(t[l], ck);
                }
            }
        }
        if wave {
            let mut arg = [0.0; L];
            for l in 0..L {
                arg[l] = f.freq.mul_add(t[l], f.phase[0]);
            }
            let (sn, cs) = crate::geom::sin_cos_fma_lanes(&arg);
            let [a0, a1, a2, a3] = f.amp;
            for l in 0..L {
                out[0][l] = a0.mul_add(sn[l], out[0][l]);
                out[1][l] = a1.mul_add(cs[l], out[1][l]);
                out[2][l] = (-a2).mul_add(sn[l], out[2][l]);
                out[3][l] = (-a3).mul_add(cs[l], out[3][l]);
            }
        }
        out
    }

    /// (min Z, max Z) over [0, 1].
    pub fn z_range(&self) -> (f64, f64) {
        (self.peak_signed(0, -1.0).1, self.peak_signed(0, 1.0).1)
    }

    /// (x, max |Z^(order)|) over [0, 1].
    fn peak(&self, order: usize) -> (f64, f64) {
        let (xa, a) = self.peak_signed(order, 1.0);
        let (xb, b) = self.peak_signed(order, -1.0);
        if a >= -b {
            (xa, a)
        } else {
            (xb, -b)
        }
    }

    /// (x, extreme of Z^(order)): its maximum for `sign` = 1, its minimum for −1
    /// (see [`extreme`]).
    fn peak_signed(&self, order: usize, sign: f64) -> (f64, f64) {
        let (x, v) = extreme(&self.fast, |s, x| sign * s.eval(x, order));
        (x, sign * v)
    }
}

/// Sampled local maxima of a piece refined by [`extreme`], the highest first: two
/// peaks that tie to a sample's resolution are both refined, and a dip narrower
/// than a sample gap shows as a local maximum of the samples next to it.
const REFINED_PEAKS: usize = 8;

/// (x, max f(piece, x)) over the pieces, each on its own [x0, x1]: 256 samples
/// on every piece, then golden-section refinement around each of its
/// [`REFINED_PEAKS`] highest sampled local maxima (a sample above its left
/// neighbour and not below its right one; the ends included), the best refined
/// value kept (exact to rounding: its error is quadratic in the abscissa's).
/// The rule where the samples cannot see: a peak that is not a local maximum of
/// the samples (two extrema of f within one gap of 1/256 of the piece, on a
/// rising or falling stretch) is missed. Refining only the best sample took the
/// wrong one of two near-tied peaks (1e-4 low) and missed a dip of Z' below 0
/// narrower than a gap (a law running backwards, −8e-5, accepted). `f` must be
/// smooth on each piece.
pub(super) fn extreme(pieces: &[Fast], f: impl Fn(&Fast, f64) -> f64) -> (f64, f64) {
    const SAMPLES: usize = 256;
    let mut best = (0.0, f64::NEG_INFINITY);
    let mut v = [0.0; SAMPLES + 1];
    let mut peaks: Vec<usize> = Vec::with_capacity(SAMPLES / 2 + 1);
    for s in pieces {
        let f = |x: f64| f(s, x);
        let h = (s.x1 - s.x0) / SAMPLES as f64;
        for (i, vi) in v.iter_mut().enumerate() {
            *vi = f(s.x0 + h * i as f64);
        }
        peaks.clear();
        peaks.extend(
            (0..=SAMPLES)
                .filter(|&i| (i == 0 || v[i] > v[i - 1]) && (i == SAMPLES || v[i] >= v[i + 1])),
        );
        if peaks.is_empty() {
            // NaN samples: the highest number, if any.
            peaks.extend(
                (0..=SAMPLES)
                    .filter(|&i| !v[i].is_nan())
                    .max_by(|&a, &b| v[a].total_cmp(&v[b])),
            );
        }
        peaks.sort_by(|&a, &b| v[b].total_cmp(&v[a]));
        for &at in peaks.iter().take(REFINED_PEAKS) {
            let top = v[at];
            let lo = s.x0 + h * at.saturating_sub(1) as f64;
            let hi = (s.x0 + h * (at + 1) as f64).min(s.x1);
            let (x, val) = golden_max(f, lo, hi);
            let (x, val) = if val >= top {
                (x, val)
            } else {
                (s.x0 + h * at as f64, top)
            };
            if val > best.1 {
                best = (x, val);
            }
        }
    }
    best
}

/// Maximum of a unimodal f on [lo, hi] by golden sections.
fn golden_max(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> (f64, f64) {
    const G: f64 = 0.618_033_988_749_894_8;
    let mut x1 = hi - G * (hi - lo);
    let mut x2 = lo + G * (hi - lo);
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..80 {
        if f1 < f2 {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + G * (hi - lo);
            f2 = f(x2);
        } else {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - G * (hi - lo);
            f1 = f(x1);
        }
        if hi - lo <= 1e-15 * (1.0 + hi.abs()) {
            break;
        }
    }
    let (fl, fh) = (f(lo), f(hi));
    [(x1, f1), (x2, f2), (lo, fl), (hi, fh)]
        .into_iter()
        .fold(
            (lo, f64::NEG_INFINITY),
            |b, c| if c.1 > b.1 { c } else { b },
        )
}

/// A law from its acceleration pieces, integrated exactly from Z(0) = Z'(0) = 0
/// and scaled to Z(1) = 1.
fn integrate(pieces: &[AccelPiece]) -> Vec<Segment> {
    let mut segments: Vec<Segment> = Vec::with_capacity(pieces.len());
    let (mut z0, mut v0, mut x0) = (0.0, 0.0, 0.0);
    for p in pieces {
        // a = Σ p_k t^k + A sin(ωt + φ) integrates to
        // Z = z0 + (v0 + (A/ω) cos φ) t + (A/ω²) sin φ + Σ p_k t^(k+2)/((k+1)(k+2))
        //     − (A/ω²) sin(ωt + φ).
        let (a, w, phi) = (p.amp, p.freq, p.phase);
        let (c0, c1, amp) = if a == 0.0 {
            (z0, v0, 0.0)
        } else {
            (
                z0 + a / (w * w) * phi.sin(),
                v0 + a / w * phi.cos(),
                -a / (w * w),
            )
        };
        let mut poly = vec![c0, c1];
        for (k, &pk) in p.poly.iter().enumerate() {
            poly.push(pk / (((k + 1) * (k + 2)) as f64));
        }
        let seg = Segment {
            x0,
            x1: p.x1,
            poly,
            amp,
            freq: w,
            phase: phi,
        };
        let fast = Fast::new(&seg);
        z0 = fast.eval(p.x1, 0);
        v0 = fast.eval(p.x1, 1);
        x0 = p.x1;
        segments.push(seg);
    }
    let scale = 1.0 / z0;
    for s in &mut segments {
        for c in &mut s.poly {
            *c *= scale;
        }
        s.amp *= scale;
    }
    segments
}

/// Check that every x is finite and in [0, `hi`] (`why` ends the message).
fn check_range(
    field: &'static str,
    x: &[f64],
    hi: f64,
    why: &'static str,
) -> Result<(), MotionError> {
    for (i, &v) in x.iter().enumerate() {
        if !v.is_finite() {
            return Err(InvalidInput::NotFinite {
                field,
                index: i,
                value: v,
            }
            .into());
        }
        if !(0.0..=hi).contains(&v) {
            return Err(MotionError::OutOfRange {
                field,
                index: i,
                value: v,
                lo: 0.0,
                hi,
                why,
            });
        }
    }
    Ok(())
}

/// Elements per parallel task: below it one thread is faster.
const CHUNK: usize = 16_384;

/// Fill `out` from `x` chunk by chunk with `f(xs, os)` on `n_threads` threads;
/// `f` also checks (in the same pass, by chunk) that every x is finite and in
/// [0, `hi`] and returns false if one is not: the first offending value is
/// then reported by [`check_range`] (and `out` holds no result).
pub(super) fn par_chunks(
    x: &[f64],
    out: &mut [f64],
    n_threads: Option<i64>,
    (field, hi, why): (&'static str, f64, &'static str),
    f: impl Fn(&[f64], &mut [f64]) -> bool + Sync,
) -> Result<(), MotionError> {
    let threads = resolve_threads(n_threads)?;
    let one = |(xs, os): (&[f64], &mut [f64])| -> bool { f(xs, os) };
    let inside = if threads == 1 || x.len() <= CHUNK {
        one((x, out))
    } else {
        pool(threads)?.install(|| {
            x.par_chunks(CHUNK)
                .zip(out.par_chunks_mut(CHUNK))
                .map(|c| crate::cancel::requested() || one(c))
                .reduce(|| true, |a, b| a & b)
        })
    };
    if !inside {
        check_range(field, x, hi, why)?;
    }
    Ok(())
}

/// [`par_chunks`] with a pointwise `f`.
pub(super) fn par_fill(
    x: &[f64],
    out: &mut [f64],
    n_threads: Option<i64>,
    range: (&'static str, f64, &'static str),
    f: impl Fn(f64) -> f64 + Sync,
) -> Result<(), MotionError> {
    let hi = range.1;
    par_chunks(x, out, n_threads, range, |xs, os| {
        if !inside(xs, hi) {
            return false;
        }
        for (o, &v) in os.iter_mut().zip(xs) {
            *o = f(v);
        }
        true
    })
}

/// Largest |freq| + |phase| of a piece for [`Lanes`]: its sine arguments stay
/// within the branch-free sine's range.
const LANE_ARG_MAX: f64 = 1e5;

/// One piece of a [`Lanes`] evaluator: the prepared segment of one law.
struct LanePiece {
    /// Of the second law (α > α1)?
    second: bool,
    /// The piece holds `after` < u ≤ `upto`: from the end of the law's
    /// previous piece (−∞ for the first) to its own end (∞ for the last).
    after: f64,
    upto: f64,
    x0: f64,
    /// Polynomial coefficients of the order, lowest first.
    poly: Vec<f64>,
    amp: f64,
    freq: f64,
    phase: f64,
}

/// A law (or the two laws of a two-period law) prepared for one derivative order,
/// evaluated a block of values at a time with every loop branch-free, so that
/// the compiler runs several values per instruction (AVX2 where the processor has
/// it, picked at run time): every piece's polynomial is evaluated for every
/// value and the value's own piece selected, then one sine per value. The same
/// arithmetic as the pointwise path, so the same values.
pub(super) struct Lanes {
    pieces: Vec<LanePiece>,
    /// v ≤ split: the first law.
    split: f64,
    /// u = (v − c)·s, per law (first, second).
    map: [(f64, f64); 2],
    /// value = off + sc·Z, per law.
    out: [(f64, f64); 2],
    has_sine: bool,
}

impl Lanes {
    /// None when a piece's sine would leave the branch-free sine's range.
    pub(super) fn new(
        laws: [&Law; 2],
        order: usize,
        split: f64,
        map: [(f64, f64); 2],
        out: [(f64, f64); 2],
    ) -> Option<Lanes> {
        let mut pieces = Vec::new();
        let n_laws = if split.is_finite() { 2 } else { 1 };
        for (l, law) in laws.iter().take(n_laws).enumerate() {
            for (k, f) in law.fast.iter().enumerate() {
                if f.freq.abs() + f.phase[order].abs() > LANE_ARG_MAX {
                    return None;
                }
                pieces.push(LanePiece {
                    second: l == 1,
                    after: if k == 0 {
                        f64::NEG_INFINITY
                    } else {
                        law.fast[k - 1].x1
                    },
                    upto: if k + 1 == law.fast.len() {
                        f64::INFINITY
                    } else {
                        f.x1
                    },
                    x0: f.x0,
                    poly: f.poly[order].clone(),
                    amp: f.amp[order],
                    freq: f.freq,
                    phase: f.phase[order],
                });
            }
        }
        let has_sine = pieces.iter().any(|p| p.amp != 0.0);
        Some(Lanes {
            pieces,
            split,
            map,
            out,
            has_sine,
        })
    }

    /// out[i] = the law at v[i], for a chunk of values, after checking (in the
    /// same pass, block by block while the values are in cache) that every v
    /// lies in [0, `hi`]: false if one does not (the outputs are then not to
    /// be used).
    pub(super) fn eval(&self, v: &[f64], out: &mut [f64], hi: f64) -> bool {
        pulp::Arch::new().dispatch(LaneChunk {
            lanes: self,
            v,
            out,
            hi,
        })
    }
}

/// Every v in [0, hi] (NaN is not).
#[inline(always)]
fn inside(v: &[f64], hi: f64) -> bool {
    v.iter().fold(true, |ok, &x| ok & (x >= 0.0) & (x <= hi))
}

/// [`Lanes::eval`]'s loops, compiled once per instruction set.
pub(super) struct LaneChunk<'a> {
    pub(super) lanes: &'a Lanes,
    pub(super) v: &'a [f64],
    pub(super) out: &'a mut [f64],
    /// The values' upper bound (the lower is 0).
    pub(super) hi: f64,
}

impl pulp::WithSimd for LaneChunk<'_> {
    /// Every value in [0, hi]?
    type Output = bool;

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> bool {
        let LaneChunk { lanes, v, out, hi } = self;
        let mut stage = Stage::default();
        let mut ok = true;
        for (vb, ob) in v.chunks(BLOCK).zip(out.chunks_mut(BLOCK)) {
            ok &= inside(vb, hi);
            let m = vb.len();
            let whole = m - m % GROUP;
            for (g, vg) in vb[..whole].chunks_exact(GROUP).enumerate() {
                let vg: &[f64; GROUP] = vg.try_into().unwrap_or(&[0.0; GROUP]);
                lane_group(lanes, vg, &mut stage, g * GROUP);
            }
            if whole < m {
                let mut vg = [0.0; GROUP];
                vg[..m - whole].copy_from_slice(&vb[whole..]);
                lane_group(lanes, &vg, &mut stage, whole);
            }
            stage.finish(lanes.has_sine, &mut ob[..m]);
        }
        ok
    }
}

/// Values per group: one AVX2 register of f64.
const GROUP: usize = 4;

/// Values staged between [`lane_group`]'s pass and the sine's.
const BLOCK: usize = 256;

/// A block's values after the piece pass: the law is off + sc·(p + amp·sin(arg)).
/// The sine then runs as its own short loop, whose iterations the processor
/// overlaps (inside the piece pass, each group's sine waited on its polynomial).
struct Stage {
    p: [f64; BLOCK],
    amp: [f64; BLOCK],
    arg: [f64; BLOCK],
    off: [f64; BLOCK],
    sc: [f64; BLOCK],
}

impl Default for Stage {
    fn default() -> Stage {
        Stage {
            p: [0.0; BLOCK],
            amp: [0.0; BLOCK],
            arg: [0.0; BLOCK],
            off: [0.0; BLOCK],
            sc: [0.0; BLOCK],
        }
    }
}

impl Stage {
    /// out[i] = the law at the block's value i.
    #[inline(always)]
    fn finish(&self, has_sine: bool, out: &mut [f64]) {
        let m = out.len().min(BLOCK);
        let (p, amp, arg) = (&self.p[..m], &self.amp[..m], &self.arg[..m]);
        let (off, sc, out) = (&self.off[..m], &self.sc[..m], &mut out[..m]);
        if has_sine {
            for i in 0..m {
                out[i] = off[i] + sc[i] * (p[i] + amp[i] * sin_lanes(arg[i]));
            }
        } else {
            for i in 0..m {
                out[i] = off[i] + sc[i] * p[i];
            }
        }
    }
}

/// `if m { a } else { b }` by bit masks: a blend in every lane, where an `if`
/// in a lane loop can compile to a branch per lane.
#[inline(always)]
fn pick(m: bool, a: f64, b: f64) -> f64 {
    let k = (m as u64).wrapping_neg();
    f64::from_bits((a.to_bits() & k) | (b.to_bits() & !k))
}

/// The piece pass of one group of [`LaneChunk`], into `stage` at `at`: the lane
/// loops have a fixed length, so each group's arrays live in vector registers and
/// every `if` is a blend.
#[inline(always)]
fn lane_group(lanes: &Lanes, v: &[f64; GROUP], stage: &mut Stage, at: usize) {
    let split = lanes.split;
    let [(c1, s1), (c2, s2)] = lanes.map;
    let second: [bool; GROUP] = std::array::from_fn(|l| v[l] > split);
    let u: [f64; GROUP] = std::array::from_fn(|l| {
        let x = if second[l] {
            (v[l] - c2) * s2
        } else {
            (v[l] - c1) * s1
        };
        if x > 0.0 {
            x
        } else {
            0.0
        }
    });
    let (mut p, mut t) = ([0.0; GROUP], [0.0; GROUP]);
    let (mut amp, mut freq, mut phase) = ([0.0; GROUP], [0.0; GROUP], [0.0; GROUP]);
    for piece in &lanes.pieces {
        let tk: [f64; GROUP] = std::array::from_fn(|l| u[l] - piece.x0);
        let mut q = [piece.poly.last().copied().unwrap_or(0.0); GROUP];
        for &c in piece.poly.iter().rev().skip(1) {
            for l in 0..GROUP {
                q[l] = q[l] * tk[l] + c;
            }
        }
        for l in 0..GROUP {
            let mine = (second[l] == piece.second) & (u[l] > piece.after) & (u[l] <= piece.upto);
            p[l] = pick(mine, q[l], p[l]);
            t[l] = pick(mine, tk[l], t[l]);
            amp[l] = pick(mine, piece.amp, amp[l]);
            freq[l] = pick(mine, piece.freq, freq[l]);
            phase[l] = pick(mine, piece.phase, phase[l]);
        }
    }
    let [(o1, k1), (o2, k2)] = lanes.out;
    let slot = at..at + GROUP;
    stage.p[slot.clone()].copy_from_slice(&p);
    stage.amp[slot.clone()].copy_from_slice(&amp);
    let arg: [f64; GROUP] = std::array::from_fn(|l| freq[l] * t[l] + phase[l]);
    stage.arg[slot.clone()].copy_from_slice(&arg);
    let off: [f64; GROUP] = std::array::from_fn(|l| pick(second[l], o2, o1));
    stage.off[slot.clone()].copy_from_slice(&off);
    let sc: [f64; GROUP] = std::array::from_fn(|l| pick(second[l], k2, k1));
    stage.sc[slot].copy_from_slice(&sc);
}

impl Law {
    /// out = Z^(order)(x) for every x (checked to lie in [0, 1]).
    pub fn eval_into(
        &self,
        x: &[f64],
        order: usize,
        n_threads: Option<i64>,
        out: &mut [f64],
    ) -> Result<(), MotionError> {
        let order = order.min(3);
        let range = ("x", 1.0, " (a law is defined on the unit square)");
        // One law: u = (x − 0)·1, value = 0 + 1·Z.
        let identity = [(0.0, 1.0); 2];
        match Lanes::new([self, self], order, f64::INFINITY, identity, identity) {
            Some(l) => par_chunks(x, out, n_threads, range, |xs, os| l.eval(xs, os, 1.0)),
            None => par_fill(x, out, n_threads, range, |v| self.z(v, order)),
        }
    }
}
