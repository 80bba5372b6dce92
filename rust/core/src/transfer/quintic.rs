//! The seed's quintic transition y(x) = a2·x² + … + a5·x⁵: its derivatives,
//! curvature and curvature rate, and its arc length (16-point Gauss–Legendre on
//! pieces from 0, 4-point Gauss–Legendre per interval along a grid).

use super::TransferError;
use crate::input::InvalidInput;

/// 16-point Gauss–Legendre nodes on [0, 1] (numpy's `leggauss(16)`, mapped).
pub(super) const NODES16: [f64; 16] = [
    0.005299532504175031,
    0.0277124884633837,
    0.06718439880608412,
    0.1222977958224985,
    0.19106187779867811,
    0.2709916111713863,
    0.35919822461037054,
    0.4524937450811813,
    0.5475062549188188,
    0.6408017753896295,
    0.7290083888286136,
    0.8089381222013219,
    0.8777022041775016,
    0.9328156011939159,
    0.9722875115366163,
    0.994700467495825,
];

/// Their weights on [0, 1].
pub(super) const WEIGHTS16: [f64; 16] = [
    0.013576229705877088,
    0.031126761969323728,
    0.0475792558412463,
    0.062314485627767036,
    0.07479799440828835,
    0.08457825969750132,
    0.09130170752246182,
    0.09472530522753432,
    0.09472530522753432,
    0.09130170752246182,
    0.08457825969750132,
    0.07479799440828835,
    0.062314485627767036,
    0.0475792558412463,
    0.031126761969323728,
    0.013576229705877088,
];

/// 4-point Gauss–Legendre nodes on [0, 1].
pub(super) const NODES4: [f64; 4] = [
    0.06943184420297371,
    0.33000947820757187,
    0.6699905217924281,
    0.9305681557970262,
];

/// Their weights on [0, 1].
pub(super) const WEIGHTS4: [f64; 4] = [
    0.17392742256872679,
    0.3260725774312732,
    0.3260725774312732,
    0.17392742256872679,
];

/// Most pieces of [0, x] in the 16-point arc length (as the Python layer).
const MAX_PIECES: usize = 512;

/// One quintic: coefficients a0 … a5 (a0 = a1 = 0 for the seed's transitions).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quintic {
    pub c: [f64; 6],
}

/// a2 … a5 of the transition from the circle of radius `r` (A at the origin, x
/// along its tangent, centre at (0, r)) to the line y = k·x + b at x = `x2`: the
/// conditions at B solved in closed form (inverse rows (10, −4, 1/2),
/// (−15, 7, −1), (6, −3, 1/2) of the 3×3 system), as the Python layer writes it.
pub fn coefficients(r: f64, k: f64, b: f64, x2: f64) -> [f64; 6] {
    let a2 = 0.5 / r;
    let r0 = k * x2 + b - a2 * (x2 * x2);
    let r1 = (k - 2.0 * a2 * x2) * x2;
    let r2 = -2.0 * a2 * (x2 * x2);
    let u = 10.0 * r0 - 4.0 * r1 + 0.5 * r2;
    let v = -15.0 * r0 + 7.0 * r1 - r2;
    let w = 6.0 * r0 - 3.0 * r1 + 0.5 * r2;
    [0.0, 0.0, a2, u / x2.powi(3), v / x2.powi(4), w / x2.powi(5)]
}

/// (κ, dκ/ds) of a graph from y', y'', y''': κ = y''/(1 + y'²)^{3/2},
/// dκ/ds = (y'''·(1 + y'²) − 3·y'·y''²)/(1 + y'²)³. `f` is √(1 + y'²) when the
/// caller has it (g^{3/2} = g·f, within an ulp of numpy's `g**1.5`).
#[inline(always)]
pub(super) fn curvature(d1: f64, d2: f64, d3: f64, f: f64) -> (f64, f64) {
    let g = 1.0 + d1 * d1;
    let kappa = d2 / (g * f);
    let rate = (d3 * g - 3.0 * d1 * d2 * d2) / (g * g * g);
    (kappa, rate)
}

impl Quintic {
    /// The order-th derivative (0 ≤ order ≤ 3) at x by Horner's rule, in the
    /// order the Python layer evaluates it: the coefficients of the derivative
    /// from the top down.
    #[inline(always)]
    pub fn d(&self, x: f64, order: usize) -> f64 {
        let c = &self.c;
        match order {
            0 => ((((c[5] * x + c[4]) * x + c[3]) * x + c[2]) * x + c[1]) * x + c[0],
            1 => (((5.0 * c[5] * x + 4.0 * c[4]) * x + 3.0 * c[3]) * x + 2.0 * c[2]) * x + c[1],
            2 => ((20.0 * c[5] * x + 12.0 * c[4]) * x + 6.0 * c[3]) * x + 2.0 * c[2],
            _ => (60.0 * c[5] * x + 24.0 * c[4]) * x + 6.0 * c[3],
        }
    }

    /// y' at x: [`Quintic::d`] of order 1 with its coefficients precomputed.
    #[inline(always)]
    pub(super) fn slope(&self) -> impl Fn(f64) -> f64 + Copy {
        let c = self.c;
        let (b5, b4, b3, b2, b1) = (5.0 * c[5], 4.0 * c[4], 3.0 * c[3], 2.0 * c[2], c[1]);
        move |x: f64| (((b5 * x + b4) * x + b3) * x + b2) * x + b1
    }

    /// (y, y', y'', y''') at x.
    #[inline(always)]
    pub(super) fn all(&self, x: f64) -> [f64; 4] {
        [self.d(x, 0), self.d(x, 1), self.d(x, 2), self.d(x, 3)]
    }

    /// Pieces of [0, upto] for the 16-point arc length: one per 0.05 rad that
    /// the tangent turns, measured on 65 even points (at most 512).
    pub fn pieces(&self, upto: f64) -> usize {
        if upto <= 0.0 {
            return 1;
        }
        let slope = self.slope();
        let step = upto / 64.0;
        let mut turn = 0.0;
        let mut last = slope(0.0).atan();
        for i in 1..=64 {
            let x = if i == 64 { upto } else { i as f64 * step };
            let a = slope(x).atan();
            turn += (a - last).abs();
            last = a;
        }
        let m = (turn / 0.05).ceil();
        if m.is_nan() || m < 1.0 {
            1
        } else {
            (m as usize).min(MAX_PIECES)
        }
    }

    /// s(x) = ∫₀ˣ √(1 + y'²) dx by 16-point Gauss–Legendre on `m` equal pieces
    /// of [0, x] (x may be negative: then s < 0).
    pub fn arc_from_zero(&self, x: f64, m: usize) -> f64 {
        let slope = self.slope();
        let mf = m as f64;
        let mut acc = 0.0;
        for j in 0..m {
            let mut part = 0.0;
            for (xi, w) in NODES16.iter().zip(WEIGHTS16.iter()) {
                let d = slope(x * ((j as f64 + xi) / mf));
                part += w * (1.0 + d * d).sqrt();
            }
            acc += part;
        }
        x * acc / mf
    }

    /// ∫ √(1 + y'²) dx over [lo, hi] by 4-point Gauss–Legendre.
    #[inline(always)]
    pub(super) fn arc_step(&self, lo: f64, hi: f64) -> f64 {
        let slope = self.slope();
        let h = hi - lo;
        let mut acc = 0.0;
        for (xi, w) in NODES4.iter().zip(WEIGHTS4.iter()) {
            let d = slope(lo + h * xi);
            acc += (1.0 + d * d).sqrt() * w;
        }
        h * acc
    }
}

/// What [`quintic_eval_into`] writes for each x.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum QuinticValue {
    /// The order-th derivative, 0 ≤ order ≤ 3.
    Derivative(usize),
    /// κ = y''/(1 + y'²)^{3/2}.
    Curvature,
    /// dκ/ds.
    CurvatureRate,
    /// s(x) from 0, 16-point Gauss–Legendre on as many pieces as the tangent
    /// turns by 0.05 rad over [0, max |x|].
    ArcLength,
}

/// Check the coefficients of a quintic (six finite numbers).
pub fn quintic(c: &[f64]) -> Result<Quintic, TransferError> {
    if c.len() != 6 {
        return Err(TransferError::BadLength {
            field: "coeffs",
            got: c.len(),
            want: "6 (a0 … a5)",
        });
    }
    InvalidInput::check_finite("coeffs", c)?;
    Ok(Quintic {
        c: [c[0], c[1], c[2], c[3], c[4], c[5]],
    })
}

/// `what` of the quintic `q` at every x into `out` (same length), in parallel.
pub fn quintic_eval_into(
    q: &Quintic,
    x: &[f64],
    what: QuinticValue,
    out: &mut [f64],
    n_threads: Option<i64>,
) -> Result<(), TransferError> {
    InvalidInput::check_finite("x", x)?;
    if out.len() != x.len() {
        return Err(TransferError::BadLength {
            field: "out",
            got: out.len(),
            want: "as many as x",
        });
    }
    let m = match what {
        QuinticValue::ArcLength => q.pieces(x.iter().fold(0.0, |a: f64, v| a.max(v.abs()))),
        _ => 1,
    };
    let q = *q;
    let f = move |v: f64| match what {
        QuinticValue::Derivative(order) => q.d(v, order.min(3)),
        QuinticValue::Curvature => {
            let d1 = q.d(v, 1);
            curvature(d1, q.d(v, 2), 0.0, (1.0 + d1 * d1).sqrt()).0
        }
        QuinticValue::CurvatureRate => {
            let d1 = q.d(v, 1);
            curvature(d1, q.d(v, 2), q.d(v, 3), (1.0 + d1 * d1).sqrt()).1
        }
        QuinticValue::ArcLength => q.arc_from_zero(v, m),
    };
    super::par_map(x, out, n_threads, f)
}
