//! Interpolating splines through a point table: the spline law of a motion
//! program, and the user's own table of s(θ).
//!
//! The spline of odd degree k = 2m − 1 (cubic: m = 2, quintic: m = 3) with its
//! knots at the data points x_0 < … < x_{n−1} is, on each interval, the Hermite
//! polynomial of degree k fixed by the values y_i, y_{i+1} and the derivatives
//! of orders 1 … m − 1 at its two ends (the slope s′, and for the quintic the
//! curvature s″ too). Those derivatives are the unknowns, d = m − 1 of them per
//! knot; values and derivatives up to m − 1 are then continuous by construction,
//! and the equations ask that the derivatives of orders m … 2m − 2 (s″; s‴ and
//! s⁗) be continuous at every interior knot, with d end conditions at each end:
//!
//! * [`SplineEnd::Given`]: the derivatives 1 … m − 1 at the end (clamped);
//! * [`SplineEnd::Natural`]: the derivatives m … 2m − 2 vanish at the end (the
//!   variational natural spline: s″ = 0 for the cubic, s‴ = s⁗ = 0 for the
//!   quintic, which minimises ∫ (s^(m))² and reproduces polynomials of degree
//!   < m);
//! * [`SplineEnd::Periodic`] at both ends: the table spans one period (y_0 =
//!   y_{n−1}) and the derivatives 1 … 2m − 2 are periodic, so that a table over
//!   one machine cycle runs smoothly into the next.
//!
//! The space (piecewise polynomials of degree k, C^(k−1), knots at the data) and
//! the conditions are those of scipy's `CubicSpline(x, y, bc_type=…)` and
//! `make_interp_spline(x, y, k=5, bc_type=…)`, so the spline is the same
//! function (the quintic's `Natural` is scipy's `bc_type=([(3, 0.0), (4, 0.0)],
//! [(3, 0.0), (4, 0.0)])`; scipy 1.17's string "natural" sets s″ = 0 only, which
//! is one condition short for k = 5, and it refuses it).
//!
//! The unknowns form a banded system (bandwidth 2d − 1 either side), solved by
//! Gaussian elimination with partial pivoting in O(n) after scaling each
//! curvature by its knot's shorter interval and each row by its largest entry,
//! so that neighbouring intervals of very different lengths (ratios of 1e3 and
//! more) do not spoil the pivots. The periodic system is the same band plus two
//! corners; it is solved bordered: the first knot's derivatives are eliminated
//! through the band's solution for d + 1 right-hand sides and a d × d system.

use super::{MotionError, Segment};
use crate::input::InvalidInput;
use crate::num_text::Num;

/// The condition at one end of a [`spline`].
#[derive(Debug, Clone, PartialEq)]
pub enum SplineEnd {
    /// The derivatives of orders m … 2m − 2 vanish at the end: s″ = 0 for a
    /// cubic, s‴ = s⁗ = 0 for a quintic.
    Natural,
    /// The derivatives of orders 1 … m − 1 at the end, in the units of y per
    /// unit of x to that power: `[s′]` for a cubic, `[s′, s″]` for a quintic.
    Given(Vec<f64>),
    /// Both ends together (set it at both): the table covers one period, y_0 =
    /// y_{n−1}, and s′ … s^(k−1) are periodic.
    Periodic,
}

impl SplineEnd {
    fn name(&self) -> &'static str {
        match self {
            SplineEnd::Natural => "Natural",
            SplineEnd::Given(_) => "Given",
            SplineEnd::Periodic => "Periodic",
        }
    }
}

/// Relative tolerance on y_0 = y_{n−1} for a periodic spline (of max |y|): a
/// table sampled from a periodic function at 0 and at its period may differ by
/// rounding; the spline then takes y_0 at both ends.
pub const PERIODIC_TOL: f64 = 1e-12;

/// The interpolating spline of `degree` 3 (C²) or 5 (C⁴) through the points
/// (x_i, y_i), knots at the points, as one [`Segment`] per interval: Z = Σ c_k
/// t^k with t = x − x_i on [x_i, x_{i+1}] (no sinusoid). `x` increases
/// strictly; `start` and `end` are the end conditions (module docs). Points: at
/// least 2 (a quintic with both ends natural: at least 3, the least that fix a
/// quadratic, which is what it reproduces).
///
/// ```
/// # use cyclomech_core::motion::{spline, SplineEnd};
/// // A cubic through four points of y = x³ with its true end slopes is y = x³.
/// let x = [0.0, 0.5, 1.5, 2.0];
/// let y = x.map(|v: f64| v.powi(3));
/// let pieces = spline(&x, &y, 3, SplineEnd::Given(vec![0.0]), SplineEnd::Given(vec![12.0])).unwrap();
/// let p = &pieces[1]; // on [0.5, 1.5]: 0.125 + 0.75 t + 1.5 t² + t³
/// for (c, want) in p.poly.iter().zip([0.125, 0.75, 1.5, 1.0]) {
///     assert!((c - want).abs() < 1e-14);
/// }
/// ```
pub fn spline(
    x: &[f64],
    y: &[f64],
    degree: usize,
    start: SplineEnd,
    end: SplineEnd,
) -> Result<Vec<Segment>, MotionError> {
    let bad = |what: String| Err(MotionError::BadLaw { what });
    let d = match degree {
        3 => 1,
        5 => 2,
        _ => {
            return bad(format!(
                "degree must be 3 (a cubic spline, C2) or 5 (a quintic spline, C4); got {degree}"
            ))
        }
    };
    let kind = if d == 1 { "cubic" } else { "quintic" };
    if x.len() != y.len() {
        return bad(format!(
            "x and y must have the same length (one y per x); got {} and {}",
            x.len(),
            y.len()
        ));
    }
    let n = x.len();
    let least = if d == 2 && start == SplineEnd::Natural && end == SplineEnd::Natural {
        3
    } else {
        2
    };
    if n < least {
        let why = if least == 3 {
            " with both ends natural"
        } else {
            ""
        };
        return bad(format!(
            "a {kind} spline{why} needs at least {least} points; got {n}"
        ));
    }
    InvalidInput::check_finite("x", x)?;
    InvalidInput::check_finite("y", y)?;
    for i in 1..n {
        if x[i] <= x[i - 1] {
            return bad(format!(
                "x must increase strictly: x[{i}] = {} is not greater than x[{}] = {}",
                Num(x[i]),
                i - 1,
                Num(x[i - 1])
            ));
        }
        let h = x[i] - x[i - 1];
        if !h.is_finite() {
            return bad(format!(
                "x[{i}] − x[{}] = {} overflows: the table's span must be finite",
                i - 1,
                Num(h)
            ));
        }
    }
    let periodic = (start == SplineEnd::Periodic, end == SplineEnd::Periodic);
    if periodic.0 != periodic.1 {
        return bad(format!(
            "start and end must both be Periodic or neither; got start = {}, end = {}",
            start.name(),
            end.name()
        ));
    }
    for (field, e) in [("start", &start), ("end", &end)] {
        if let SplineEnd::Given(v) = e {
            if v.len() != d {
                let want = if d == 1 { "[s′]" } else { "[s′, s″]" };
                return bad(format!(
                    "{field}: a {kind} spline's given end takes {d} derivative{} {want}; got {}",
                    if d == 1 { "" } else { "s" },
                    v.len()
                ));
            }
            InvalidInput::check_finite(field, v)?;
        }
    }
    let h: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
    let mut y = y.to_vec();
    if periodic.0 {
        let scale = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let (a, b) = (y[0], y[n - 1]);
        if (a - b).abs() > PERIODIC_TOL * scale {
            return bad(format!(
                "a periodic spline needs y[0] = y[{}] (the table spans one period); got y[0] = {} and y[{}] = {}",
                n - 1,
                Num(a),
                n - 1,
                Num(b)
            ));
        }
        y[n - 1] = a;
    }
    let sys = System::new(d, &h, &y, periodic.0);
    let derivs = if periodic.0 {
        sys.solve_periodic()
    } else {
        sys.solve(&start, &end)
    };
    let segments = derivs.map(|u| sys.segments(x, &u));
    match segments {
        Some(s) if s.iter().all(|p| p.poly.iter().all(|c| c.is_finite())) => Ok(s),
        _ => bad(format!(
            "the {kind} spline through these {n} points overflows: its coefficients are not finite (intervals from {} to {} long)",
            Num(h.iter().copied().fold(f64::INFINITY, f64::min)),
            Num(h.iter().copied().fold(0.0, f64::max)),
        )),
    }
}

/// K such that the derivative of order `order` at an end of an interval of
/// length h is Σ_j K_j·D_j / h^(order − j), over D = [Δy, derivatives 1 … d at
/// the start, derivatives 1 … d at the end] (j the derivative's order, 0 for
/// Δy): CUBIC for s″ (order 2), QUINTIC for s‴ and s⁗ (orders 3, 4), each
/// [at the start, at the end]. From the Hermite forms: for the quintic, with
/// Δ = y1 − y0, a5 h⁵ = 6Δ − 3h(p0 + p1) + h²(q1 − q0)/2 and its kin.
const CUBIC: [[[f64; 5]; 2]; 1] = [[[6.0, -4.0, -2.0, 0.0, 0.0], [-6.0, 2.0, 4.0, 0.0, 0.0]]];
const QUINTIC: [[[f64; 5]; 2]; 2] = [
    [
        [60.0, -36.0, -9.0, -24.0, 3.0],
        [60.0, -24.0, -3.0, -36.0, 9.0],
    ],
    [
        [-360.0, 192.0, 36.0, 168.0, -24.0],
        [360.0, -168.0, -24.0, -192.0, 36.0],
    ],
];

/// The spline's equations before the end conditions: interval lengths, values,
/// and each knot's scale H_i (its shorter neighbouring interval), by which its
/// derivative of order j is carried as D_j·H_i^(j − 1).
struct System<'a> {
    d: usize,
    h: &'a [f64],
    y: &'a [f64],
    scale: Vec<f64>,
}

/// One scaled equation: coefficients on (knot, derivative order 1 … d) and its
/// right-hand side.
struct Row {
    terms: Vec<(usize, usize, f64)>,
    rhs: f64,
}

impl Row {
    /// The same equation divided by its largest coefficient.
    fn normalised(mut self) -> Row {
        let big = self.terms.iter().fold(0.0f64, |m, t| m.max(t.2.abs()));
        if big > 0.0 && big.is_finite() {
            for t in &mut self.terms {
                t.2 /= big;
            }
            self.rhs /= big;
        }
        self
    }
}

impl System<'_> {
    /// `periodic`: knots 0 and n − 1 are one knot, with one scale.
    fn new<'a>(d: usize, h: &'a [f64], y: &'a [f64], periodic: bool) -> System<'a> {
        let n = y.len();
        let mut scale: Vec<f64> = (0..n)
            .map(|i| {
                let left = if i > 0 { h[i - 1] } else { f64::INFINITY };
                let right = if i + 1 < n { h[i] } else { f64::INFINITY };
                left.min(right)
            })
            .collect();
        if periodic {
            let s = scale[0].min(scale[n - 1]);
            scale[0] = s;
            scale[n - 1] = s;
        }
        System { d, h, y, scale }
    }

    /// Add to `row` the derivative of order d + 1 + `a` at the start (`at_end`
    /// false) or end of interval `k` (from knot `k` to knot `k + 1`, knot
    /// indices taken modulo `wrap`), times `sign`, scaled by H_i^order with H_i
    /// the row's knot scale: every term is then a ratio of lengths to a power
    /// (no overflow for tiny or huge intervals).
    fn add_end(&self, row: &mut Row, k: usize, a: usize, at_end: bool, sign: f64, wrap: usize) {
        let d = self.d;
        let order = (d + 1 + a) as i32;
        let table = if d == 1 { &CUBIC[a] } else { &QUINTIC[a] };
        let coef = &table[at_end as usize];
        let hk = self.h[k];
        let knot = if at_end { k + 1 } else { k };
        let hi = self.scale[knot % wrap];
        let r = hi / hk;
        // Δy term: K·Δ/h^order·H^order = K·r^order·Δ.
        let dy = self.y[k + 1] - self.y[k];
        row.rhs -= sign * coef[0] * r.powi(order) * dy;
        for (end, knot) in [(0, k), (1, k + 1)] {
            let knot = knot % wrap;
            for j in 1..=d {
                // K·D_j/h^(order − j)·H^order with D_j = D̃_j/H_knot^(j − 1).
                let c = coef[end * d + j] * r.powi(order - j as i32) * hi.powi(j as i32)
                    / self.scale[knot].powi(j as i32 - 1);
                row.terms.push((knot, j, sign * c));
            }
        }
    }

    /// The continuity row of order d + 1 + a at interior knot i (between
    /// intervals i − 1 and i, modulo `wrap`): left end minus right start = 0.
    fn continuity(&self, i: usize, a: usize, left: usize, wrap: usize) -> Row {
        let mut row = Row {
            terms: Vec::with_capacity(4 * self.d),
            rhs: 0.0,
        };
        self.add_end(&mut row, left, a, true, 1.0, wrap);
        self.add_end(&mut row, i, a, false, -1.0, wrap);
        row.normalised()
    }

    /// The d rows of one end's condition at `knot` (0 or n − 1).
    fn end_rows(&self, e: &SplineEnd, knot: usize) -> Vec<Row> {
        let n = self.y.len();
        (0..self.d)
            .map(|a| match e {
                SplineEnd::Given(v) => Row {
                    terms: vec![(knot, a + 1, 1.0)],
                    rhs: v[a] * self.scale[knot].powi(a as i32),
                },
                _ => {
                    // Natural: the derivative of order d + 1 + a vanishes.
                    let mut row = Row {
                        terms: Vec::with_capacity(2 * self.d),
                        rhs: 0.0,
                    };
                    let (k, at_end) = if knot == 0 { (0, false) } else { (n - 2, true) };
                    self.add_end(&mut row, k, a, at_end, 1.0, n);
                    row.normalised()
                }
            })
            .collect()
    }

    /// The scaled derivatives (row-major: knot, order) of the spline with the
    /// given ends; None if the system is singular.
    fn solve(&self, start: &SplineEnd, end: &SplineEnd) -> Option<Vec<f64>> {
        let (n, d) = (self.y.len(), self.d);
        let mut band = Banded::new(n * d, 2 * d - 1, 2 * d - 1);
        let mut rhs = vec![0.0; n * d];
        for i in 0..n {
            let rows = if i == 0 {
                self.end_rows(start, 0)
            } else if i + 1 == n {
                self.end_rows(end, n - 1)
            } else {
                (0..d).map(|a| self.continuity(i, a, i - 1, n)).collect()
            };
            for (a, row) in rows.into_iter().enumerate() {
                let r = i * d + a;
                for (knot, j, c) in row.terms {
                    band.add(r, knot * d + j - 1, c);
                }
                rhs[r] = row.rhs;
            }
        }
        band.factor()?;
        band.solve(&mut rhs);
        Some(rhs)
    }

    /// [`System::solve`] for a periodic spline: knot n − 1 is knot 0; the
    /// unknowns of knots 1 … n − 2 form a band (the clamped system, given knot
    /// 0's derivatives v), bordered by knot 0's: with A u + B v = f (rows of
    /// knots 1 … n − 2) and C u + D v = g (knot 0's rows), v solves
    /// (D − C A⁻¹B) v = g − C A⁻¹f.
    fn solve_periodic(&self) -> Option<Vec<f64>> {
        let (n, d) = (self.y.len(), self.d);
        let m = n - 1; // distinct knots
        let inner = (m - 1) * d;
        let mut band = Banded::new(inner, 2 * d - 1, 2 * d - 1);
        let mut b = vec![vec![0.0; inner]; d]; // B by columns
        let mut c = vec![vec![0.0; inner]; d]; // C by rows
        let mut dd = Banded::new(d, d - 1, d - 1);
        let (mut f, mut g) = (vec![0.0; inner], vec![0.0; d]);
        for i in 0..m {
            let left = if i == 0 { m - 1 } else { i - 1 };
            for a in 0..d {
                let row = self.continuity(i, a, left, m);
                for (knot, j, v) in row.terms {
                    match (i, knot) {
                        (0, 0) => dd.add(a, j - 1, v),
                        (0, k) => c[a][(k - 1) * d + j - 1] += v,
                        (i, 0) => b[j - 1][(i - 1) * d + a] += v,
                        (i, k) => band.add((i - 1) * d + a, (k - 1) * d + j - 1, v),
                    }
                }
                if i == 0 {
                    g[a] = row.rhs;
                } else {
                    f[(i - 1) * d + a] = row.rhs;
                }
            }
        }
        if inner > 0 {
            band.factor()?;
            band.solve(&mut f);
            for col in &mut b {
                band.solve(col);
            }
        }
        // S = D − C·X with X = A⁻¹B; g − C·w with w = A⁻¹f.
        for a in 0..d {
            for (j, col) in b.iter().enumerate() {
                dd.add(a, j, -dot(&c[a], col));
            }
            g[a] -= dot(&c[a], &f);
        }
        dd.factor()?;
        dd.solve(&mut g);
        let mut u = vec![0.0; n * d];
        u[..d].copy_from_slice(&g);
        for (k, uk) in u[d..d + inner].iter_mut().enumerate() {
            *uk = f[k] - b.iter().zip(&g).map(|(col, v)| col[k] * v).sum::<f64>();
        }
        // Knot n − 1 is knot 0.
        u.copy_within(..d, m * d);
        Some(u)
    }

    /// The pieces from the scaled derivatives `u` at the knots.
    fn segments(&self, x: &[f64], u: &[f64]) -> Vec<Segment> {
        let d = self.d;
        let deriv =
            |knot: usize, j: usize| u[knot * d + j - 1] / self.scale[knot].powi(j as i32 - 1);
        (0..x.len() - 1)
            .map(|i| {
                let h = self.h[i];
                let (y0, y1) = (self.y[i], self.y[i + 1]);
                let (p0, p1) = (deriv(i, 1), deriv(i + 1, 1));
                let poly = if d == 1 {
                    let delta = (y1 - y0) / h;
                    vec![
                        y0,
                        p0,
                        (3.0 * delta - 2.0 * p0 - p1) / h,
                        (p0 + p1 - 2.0 * delta) / (h * h),
                    ]
                } else {
                    let (q0, q1) = (deriv(i, 2), deriv(i + 1, 2));
                    // The remainders of y, s′, s″ at t = h after the known
                    // terms, made dimensionless-by-h: a_k h^k solve a 3 × 3
                    // system whose inverse is these integers.
                    let r0 = y1 - y0 - h * (p0 + 0.5 * h * q0);
                    let r1 = h * (p1 - p0 - h * q0);
                    let r2 = h * h * (q1 - q0);
                    let a3 = 10.0 * r0 - 4.0 * r1 + 0.5 * r2;
                    let a4 = -15.0 * r0 + 7.0 * r1 - r2;
                    let a5 = 6.0 * r0 - 3.0 * r1 + 0.5 * r2;
                    vec![
                        y0,
                        p0,
                        0.5 * q0,
                        a3 / h.powi(3),
                        a4 / h.powi(4),
                        a5 / h.powi(5),
                    ]
                };
                Segment {
                    x0: x[i],
                    x1: x[i + 1],
                    poly,
                    amp: 0.0,
                    freq: 0.0,
                    phase: 0.0,
                }
            })
            .collect()
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// A banded matrix (kl sub- and ku super-diagonals) and its LU factors with
/// partial pivoting, as LAPACK's `gbtrf`/`gbtrs` keep them: row r stores the
/// columns r − kl … r + kl + ku (the extra kl for the pivots' fill-in); after
/// [`Banded::factor`] the upper part holds U and the lower part the multipliers
/// of each step, applied in order with the row swaps by [`Banded::solve`].
struct Banded {
    n: usize,
    kl: usize,
    ku: usize,
    width: usize,
    a: Vec<f64>,
    pivot: Vec<usize>,
}

impl Banded {
    fn new(n: usize, kl: usize, ku: usize) -> Banded {
        let width = 2 * kl + ku + 1;
        Banded {
            n,
            kl,
            ku,
            width,
            a: vec![0.0; n * width],
            pivot: vec![0; n],
        }
    }

    #[inline]
    fn at(&self, r: usize, c: usize) -> usize {
        r * self.width + c + self.kl - r
    }

    fn add(&mut self, r: usize, c: usize, v: f64) {
        let k = self.at(r, c);
        self.a[k] += v;
    }

    /// Factor in place; None if a pivot column is all zero (singular).
    fn factor(&mut self) -> Option<()> {
        let (n, kl, ku) = (self.n, self.kl, self.ku);
        for j in 0..n {
            let last = (j + kl).min(n - 1);
            let mut p = j;
            for r in j + 1..=last {
                if self.a[self.at(r, j)].abs() > self.a[self.at(p, j)].abs() {
                    p = r;
                }
            }
            let piv = self.a[self.at(p, j)];
            if piv == 0.0 || !piv.is_finite() {
                return None;
            }
            self.pivot[j] = p;
            let cols = (j + kl + ku).min(n - 1);
            if p != j {
                for c in j..=cols {
                    let (x, y) = (self.at(j, c), self.at(p, c));
                    self.a.swap(x, y);
                }
            }
            for r in j + 1..=last {
                let k = self.at(r, j);
                let l = self.a[k] / piv;
                self.a[k] = l;
                if l != 0.0 {
                    for c in j + 1..=cols {
                        let (x, y) = (self.at(r, c), self.at(j, c));
                        self.a[x] -= l * self.a[y];
                    }
                }
            }
        }
        Some(())
    }

    /// b ← A⁻¹ b with the factors.
    fn solve(&self, b: &mut [f64]) {
        let (n, kl, ku) = (self.n, self.kl, self.ku);
        for j in 0..n {
            b.swap(j, self.pivot[j]);
            for r in j + 1..=(j + kl).min(n - 1) {
                b[r] -= self.a[self.at(r, j)] * b[j];
            }
        }
        for j in (0..n).rev() {
            let hi = (j + kl + ku).min(n - 1);
            let mut s = b[j];
            for (c, bc) in b.iter().enumerate().take(hi + 1).skip(j + 1) {
                s -= self.a[self.at(j, c)] * bc;
            }
            b[j] = s / self.a[self.at(j, j)];
        }
    }
}
