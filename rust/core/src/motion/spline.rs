//! Interpolating splines through a point table: the spline law of a motion
//! program, and the user's own table of s(θ).
//!
//! The spline of odd degree k = 2m − 1 (cubic: m = 2, quintic: m = 3) with its
//! knots at the data points x_0 < … < x_{n−1} is a polynomial of degree k on
//! each interval, with derivatives up to k − 1 continuous at every interior
//! knot; it interpolates the n values, and d = m − 1 conditions at each end
//! fix it:
//!
//! * [`SplineEnd::Given`]: the derivatives 1 … m − 1 at the end (clamped);
//! * [`SplineEnd::Natural`]: the derivatives m … 2m − 2 vanish at the end (the
//!   variational natural spline: s″ = 0 for the cubic, s‴ = s⁗ = 0 for the
//!   quintic, which minimises ∫ (s^(m))² and reproduces polynomials of degree
//!   < m);
//! * [`SplineEnd::Periodic`] at both ends: the table spans one period (y_0 =
//!   y_{n−1}) and the derivatives 1 … k − 1 are periodic, so that a table over
//!   one machine cycle runs smoothly into the next.
//!
//! The space and the conditions are those of scipy's `CubicSpline(x, y,
//! bc_type=…)` and `make_interp_spline(x, y, k=5, bc_type=…)`, so the spline
//! is the same function (the quintic's `Natural` is scipy's `bc_type=([(3,
//! 0.0), (4, 0.0)], [(3, 0.0), (4, 0.0)])`; scipy 1.17's string "natural" sets
//! s″ = 0 only, one condition short for k = 5, and scipy refuses it).
//!
//! It is solved in the B-spline basis, much as scipy's `make_interp_spline`
//! does: the coefficients of the B-splines on the data knots from the n values
//! and the end conditions, a banded system (k sub- and super-diagonals) by
//! Gaussian elimination with partial pivoting, in O(n). The B-splines are
//! local and well conditioned whatever the spacing; a first version solved
//! for the knots' derivatives (Hermite form) and lost five digits of the
//! quintic where neighbouring intervals differ by 1e3, because there s⁗ over
//! the short interval lives only in the differences of the derivatives at its
//! ends. A given end is the end knot of multiplicity k + 1 and its derivative
//! rows (scipy's `_augknt`); a natural end is not (scipy's way loses up to six
//! digits next to a short end interval): the spline is continued over an
//! outer span by a polynomial of degree < m ([`Basis::end_rows`]). The
//! periodic spline identifies c_{j+n−1} = c_j on knots continued by the
//! period: a band plus two corners, solved bordered. Each piece's
//! coefficients are then the spline's derivatives at the start of its
//! interval over j!.
//!
//! Accuracy (`spline_tests.rs`, against an exact solve in 50 digits): 2e-16
//! to 6e-14 of each derivative's scale on even and uneven tables (interval
//! ratios to 2e3), every end kind; random tables with ratios to 1e3 hold
//! their properties to 1e-9. Beyond, the problem itself turns touchy and the
//! solve loses a little more: for a quintic with given ends through x = 0, 1,
//! 1.00012 (ratio 8e3), rounding the table to f64 moves the exact spline by
//! 1.4e-8 of its value at 0.5, and this solve is 1.1e-7 off it (scipy, on a
//! like table, 3e-9); a natural quintic near ratio 1e5 loses ~3e-7. Time: 1e5
//! points in tens of milliseconds.

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
    let k = degree;
    let basis = if periodic.0 {
        Basis::periodic(x, k)
    } else {
        let natural = (start == SplineEnd::Natural, end == SplineEnd::Natural);
        Basis::open(x, k, natural)
    };
    let coef = if periodic.0 {
        basis.solve_periodic(&y)
    } else {
        basis.solve(&y, &start, &end)
    };
    let segments = coef.map(|c| basis.segments(&c));
    match segments {
        Some(s) if s.iter().all(|p| p.poly.iter().all(|c| c.is_finite())) => Ok(s),
        _ => bad(format!(
            "the {kind} spline through these {n} points overflows: its coefficients are not finite (intervals from {} to {} long)",
            Num(h.iter().copied().fold(f64::INFINITY, f64::min)),
            Num(h.iter().copied().fold(0.0, f64::max)),
        )),
    }
}

/// Highest degree of a spline here, and the size of its arrays of B-splines.
const K_MAX: usize = 5;

/// A row of a spline's system: its first column, its k + 1 entries from
/// there, and its right-hand side.
type Row = (usize, [f64; K_MAX + 1], f64);

/// [`Basis::triangle`]'s B-splines of every degree and knot differences.
struct Triangle {
    ndu: [[f64; K_MAX + 1]; K_MAX + 1],
    inv: [[f64; K_MAX + 1]; K_MAX + 1],
}

/// The B-spline basis of degree k on knots `t` over the data x_0 … x_{n−1}:
/// x_i = t[k + i], so interval i (x_i ≤ x < x_{i+1}) is knot span k + i, where
/// B_i … B_{i+k} are the nonzero ones.
struct Basis<'a> {
    x: &'a [f64],
    k: usize,
    t: Vec<f64>,
    /// x_i = t[off + i]: k, or k + 1 after a natural end's outer span.
    off: usize,
}

impl<'a> Basis<'a> {
    /// The data as simple knots, and at each end either the end knot of
    /// multiplicity k + 1 (scipy's `_augknt`: a given end) or, for a natural
    /// end (`natural`: start, end), an outer span of the mean interval's
    /// length with k more simple knots beyond it, on which the spline is asked
    /// to be a polynomial of degree < m ([`Basis::end_rows`]).
    fn open(x: &'a [f64], k: usize, natural: (bool, bool)) -> Basis<'a> {
        let n = x.len();
        let step = (x[n - 1] - x[0]) / (n - 1) as f64;
        let mut t: Vec<f64> = if natural.0 {
            (0..=k).map(|j| x[0] - (k + 1 - j) as f64 * step).collect()
        } else {
            vec![x[0]; k]
        };
        let off = t.len();
        t.extend_from_slice(x);
        if natural.1 {
            t.extend((1..=k + 1).map(|j| x[n - 1] + j as f64 * step));
        } else {
            t.extend(std::iter::repeat_n(x[n - 1], k));
        }
        Basis { x, k, t, off }
    }

    /// The data as knots, continued by the period's intervals on both sides
    /// (scipy's `_periodic_knots` for odd k): B_j and B_{j+n−1} are then one
    /// function shifted by the period, and the periodic spline is Σ c_j B_j
    /// with c_{j+n−1} = c_j.
    fn periodic(x: &'a [f64], k: usize) -> Basis<'a> {
        let n = x.len();
        let m = n - 1;
        let dx: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
        let mut t = vec![0.0; n + 2 * k];
        t[k..k + n].copy_from_slice(x);
        for i in 0..k {
            t[k - i - 1] = t[k - i] - dx[m - 1 - i % m];
            t[k + n + i] = t[k + n + i - 1] + dx[i % m];
        }
        Basis { x, k, t, off: k }
    }

    /// The knot span of interval i and the point x_i or x_{i+1} in it: the
    /// span's B-splines are polynomials, so at its right end they give the
    /// limits from the left (the last data point lies in the last interval).
    fn span(&self, i: usize) -> usize {
        self.off + i.min(self.x.len() - 2)
    }

    /// The triangle of The NURBS Book's algorithm A2.2 at u, t[span] ≤ u ≤
    /// t[span + 1]: above the diagonal ndu[r][q] = B_{span−q+r} of degree q
    /// (r ≤ q ≤ k), below it the knot differences across the span, and their
    /// reciprocals in `inv` (each divided once; all positive).
    #[inline(always)]
    fn triangle(&self, span: usize, u: f64) -> Triangle {
        let (p, t) = (self.k, &self.t);
        let mut ndu = [[0.0; K_MAX + 1]; K_MAX + 1];
        let mut inv = [[0.0; K_MAX + 1]; K_MAX + 1];
        let (mut left, mut right) = ([0.0; K_MAX + 1], [0.0; K_MAX + 1]);
        ndu[0][0] = 1.0;
        for j in 1..=p {
            left[j] = u - t[span + 1 - j];
            right[j] = t[span + j] - u;
            let mut saved = 0.0;
            for r in 0..j {
                ndu[j][r] = right[r + 1] + left[j - r];
                inv[j][r] = 1.0 / ndu[j][r];
                let temp = ndu[r][j - 1] * inv[j][r];
                ndu[r][j] = saved + right[r + 1] * temp;
                saved = left[j - r] * temp;
            }
            ndu[j][j] = saved;
        }
        Triangle { ndu, inv }
    }

    /// B_{span−k+l}(u) for l = 0 … k.
    fn values(&self, span: usize, u: f64) -> [f64; K_MAX + 1] {
        let tr = self.triangle(span, u);
        std::array::from_fn(|l| if l <= self.k { tr.ndu[l][self.k] } else { 0.0 })
    }

    /// ders[j][l] = the j-th derivative of B_{span−k+l} at u, j ≤ `nd`, l ≤ k,
    /// for t[span] ≤ u ≤ t[span + 1] (The NURBS Book, algorithm A2.3).
    fn ders(&self, span: usize, u: f64, nd: usize) -> [[f64; K_MAX + 1]; K_MAX + 1] {
        let p = self.k;
        let Triangle { ndu, inv } = self.triangle(span, u);
        let mut ders = [[0.0; K_MAX + 1]; K_MAX + 1];
        for (l, row) in ndu.iter().enumerate().take(p + 1) {
            ders[0][l] = row[p];
        }
        let (p_i, nd_i) = (p as isize, nd.min(p) as isize);
        let mut a = [[0.0; K_MAX + 1]; 2];
        for r in 0..=p_i {
            let (mut s1, mut s2) = (0, 1);
            a[0][0] = 1.0;
            for kk in 1..=nd_i {
                let mut d = 0.0;
                let (rk, pk) = (r - kk, p_i - kk);
                let (pk1, pku) = ((pk + 1) as usize, pk as usize);
                if r >= kk {
                    a[s2][0] = a[s1][0] * inv[pk1][rk as usize];
                    d = a[s2][0] * ndu[rk as usize][pku];
                }
                let j1 = if rk >= -1 { 1 } else { -rk };
                let j2 = if r - 1 <= pk { kk - 1 } else { p_i - r };
                for j in j1..=j2 {
                    let (ju, rkj) = (j as usize, (rk + j) as usize);
                    a[s2][ju] = (a[s1][ju] - a[s1][ju - 1]) * inv[pk1][rkj];
                    d += a[s2][ju] * ndu[rkj][pku];
                }
                if r <= pk {
                    let (ku, ru) = (kk as usize, r as usize);
                    a[s2][ku] = -a[s1][ku - 1] * inv[pk1][ru];
                    d += a[s2][ku] * ndu[ru][pku];
                }
                ders[kk as usize][r as usize] = d;
                std::mem::swap(&mut s1, &mut s2);
            }
        }
        // The derivatives of order j carry p!/(p − j)!.
        let mut f = p as f64;
        for (j, row) in ders.iter_mut().enumerate().take(nd.min(p) + 1).skip(1) {
            for v in row.iter_mut().take(p + 1) {
                *v *= f;
            }
            f *= (p - j) as f64;
        }
        ders
    }

    /// The rows of one end's conditions at x_0 (`first`) or x_{n−1}, as (first
    /// column, the k + 1 entries, right-hand side), each divided by its
    /// largest entry (derivative rows grow as h^(−order); the pivots compare
    /// rows): a given end's d derivatives at the end, or a natural end's d + 1
    /// conditions that the spline be a polynomial of degree < m on the outer
    /// span (its derivatives of orders m … k vanish there).
    ///
    /// That is the natural end: a spline C^(k−1) at x_0 that is of degree < m
    /// beyond it has s^(m) … s^(2m−2) = 0 at x_0, and the natural spline
    /// continued by its Taylor polynomial of degree m − 1 is such a spline.
    /// Asked at x_0 itself instead, on the end knot of multiplicity k + 1 as
    /// scipy does, the rows of s‴ and s⁗ are nearly parallel when the end
    /// interval is short (both ruled by the two B-splines living mostly
    /// inside it): a natural quintic through (0, 0), (1, c), (1.00106, ·)
    /// lost 2e-6 of its value (scipy 8e-6), and next to an interval 1e3 times
    /// longer 1.8e-11; on the outer span every knot difference is at least
    /// its length.
    fn end_rows(&self, e: &SplineEnd, first: bool) -> Vec<Row> {
        let (k, n) = (self.k, self.x.len());
        let d = (k - 1) / 2;
        let normalised = |span: usize, mut row: [f64; K_MAX + 1], rhs: f64| {
            let big = row.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for v in &mut row {
                *v /= big;
            }
            (span - k, row, rhs / big)
        };
        match e {
            SplineEnd::Given(v) => {
                let (span, u) = if first {
                    (self.span(0), self.x[0])
                } else {
                    (self.span(n - 2), self.x[n - 1])
                };
                let ders = self.ders(span, u, d);
                (0..d)
                    .map(|a| normalised(span, ders[a + 1], v[a]))
                    .collect()
            }
            _ => {
                let span = if first {
                    self.off - 1
                } else {
                    self.off + n - 1
                };
                let u = 0.5 * (self.t[span] + self.t[span + 1]);
                let ders = self.ders(span, u, k);
                (d + 1..=k)
                    .map(|o| normalised(span, ders[o], 0.0))
                    .collect()
            }
        }
    }

    /// The B-spline coefficients of the spline with these ends: d rows of the
    /// start's conditions, the n values, d rows of the end's (scipy's order),
    /// a band of k sub- and k super-diagonals.
    fn solve(&self, y: &[f64], start: &SplineEnd, end: &SplineEnd) -> Option<Vec<f64>> {
        let (k, n) = (self.k, self.x.len());
        let size = self.t.len() - k - 1;
        let mut band = Banded::new(size, k, k);
        let mut rhs = Vec::with_capacity(size);
        let mut put = |(col, entries, b): Row| {
            let r = rhs.len();
            for (l, &v) in entries.iter().enumerate().take(k + 1) {
                if v != 0.0 {
                    band.add(r, col + l, v);
                }
            }
            rhs.push(b);
        };
        self.end_rows(start, true).into_iter().for_each(&mut put);
        for (i, &yi) in y.iter().enumerate() {
            let span = self.span(i.min(n - 2));
            put((span - k, self.values(span, self.x[i]), yi));
        }
        self.end_rows(end, false).into_iter().for_each(&mut put);
        band.factor()?;
        band.solve(&mut rhs);
        Some(rhs)
    }

    /// [`Basis::solve`] for the periodic spline: m = n − 1 coefficients, one
    /// value row per distinct point x_0 … x_{m−1}, each B_{i+l} (l < k: B_{i+k}
    /// vanishes at x_i) in column (i + l − d) mod m, d = (k − 1)/2, so that the
    /// band is centred (kl = ku = d, its diagonal the middle B-spline, largest)
    /// and the wrapped entries fall in the corners. Bordered solve: with the
    /// last b = k − 1 columns and rows as the border, A u + B v = f, C u + D v
    /// = g and v from (D − C A⁻¹B) v = g − C A⁻¹f. A is a block of consecutive
    /// rows and columns of a collocation matrix, totally positive with a
    /// positive diagonal, so nonsingular (Schoenberg–Whitney).
    fn solve_periodic(&self, y: &[f64]) -> Option<Vec<f64>> {
        let (k, n) = (self.k, self.x.len());
        let (m, d) = (n - 1, (k - 1) / 2);
        let inner = m.saturating_sub(k - 1);
        let border = m - inner;
        let mut band = Banded::new(inner, d, d);
        let mut b = vec![vec![0.0; inner]; border]; // B by columns
        let mut c = vec![vec![0.0; inner]; border]; // C by rows
        let mut dd = Banded::new(border, border - 1, border - 1);
        let (mut f, mut g) = (vec![0.0; inner], vec![0.0; border]);
        for (i, &yi) in y.iter().enumerate().take(m) {
            let values = self.values(self.span(i), self.x[i]);
            for (l, &v) in values.iter().enumerate().take(k) {
                let col = (i + l + m - d % m) % m;
                match (i < inner, col < inner) {
                    (true, true) => band.add(i, col, v),
                    (true, false) => b[col - inner][i] += v,
                    (false, true) => c[i - inner][col] += v,
                    (false, false) => dd.add(i - inner, col - inner, v),
                }
            }
            if i < inner {
                f[i] = yi;
            } else {
                g[i - inner] = yi;
            }
        }
        if inner > 0 {
            band.factor()?;
            band.solve(&mut f);
            for col in &mut b {
                band.solve(col);
            }
        }
        for a in 0..border {
            for (j, col) in b.iter().enumerate() {
                dd.add(a, j, -dot(&c[a], col));
            }
            g[a] -= dot(&c[a], &f);
        }
        dd.factor()?;
        dd.solve(&mut g);
        // Column q holds c_{(q + d) mod m}; then c_{j+m} = c_j for all n + k − 1.
        let mut shifted = vec![0.0; m];
        for q in 0..m {
            let v = if q < inner {
                f[q] - b.iter().zip(&g).map(|(col, v)| col[q] * v).sum::<f64>()
            } else {
                g[q - inner]
            };
            shifted[(q + d) % m] = v;
        }
        Some((0..n + k - 1).map(|j| shifted[j % m]).collect())
    }

    /// The pieces: on interval i, the derivatives 0 … k at x_i over j! are the
    /// coefficients in t = x − x_i. The j-th derivative of Σ c_l B_l is Σ
    /// d^(j)_l B_l of degree k − j, with d^(j)_l = (k − j + 1)(d^(j−1)_l −
    /// d^(j−1)_{l−1}) / (t_{l+k−j+1} − t_l) (de Boor): the knot differences and
    /// the B-splines of every degree are in the span's triangle, so a piece
    /// costs one triangle and ~k² products.
    fn segments(&self, c: &[f64]) -> Vec<Segment> {
        let (k, x) = (self.k, self.x);
        (0..x.len() - 1)
            .map(|i| {
                let span = self.span(i);
                let Triangle { ndu, inv } = self.triangle(span, x[i]);
                // d[l] for l = j … k, the span's coefficients differenced j times.
                let mut d = [0.0; K_MAX + 1];
                d[..=k].copy_from_slice(&c[span - k..=span]);
                let mut poly = Vec::with_capacity(k + 1);
                let mut factorial = 1.0;
                for j in 0..=k {
                    if j > 0 {
                        factorial *= j as f64;
                        let scale = (k - j + 1) as f64;
                        for l in (j..=k).rev() {
                            // t_{l+k−j+1} − t_l across the span: ndu[k − j + 1][l − j].
                            d[l] = scale * (d[l] - d[l - 1]) * inv[k - j + 1][l - j];
                        }
                    }
                    // Degree k − j: B_{span−(k−j)+r} = ndu[r][k − j], coefficient d[r + j].
                    let q = k - j;
                    let s: f64 = (0..=q).map(|r| d[r + j] * ndu[r][q]).sum();
                    poly.push(s / factorial);
                }
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
        let (n, kl, ku, w) = (self.n, self.kl, self.ku, self.width);
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
            // Columns j … j + m of row j sit at kl …, of row r at j + kl − r ….
            let m = (j + kl + ku).min(n - 1) - j;
            if p != j {
                let (top, bottom) = self.a.split_at_mut(p * w);
                let row_j = &mut top[j * w + kl..j * w + kl + m + 1];
                let at_p = j + kl - p;
                row_j.swap_with_slice(&mut bottom[at_p..at_p + m + 1]);
            }
            for r in j + 1..=last {
                let (top, bottom) = self.a.split_at_mut(r * w);
                let row_j = &top[j * w + kl + 1..j * w + kl + 1 + m];
                let at_r = j + kl - r;
                let l = bottom[at_r] / piv;
                bottom[at_r] = l;
                if l != 0.0 {
                    for (x, y) in bottom[at_r + 1..at_r + 1 + m].iter_mut().zip(row_j) {
                        *x -= l * y;
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
        let w = self.width;
        for j in (0..n).rev() {
            let m = (j + kl + ku).min(n - 1) - j;
            let row = &self.a[j * w + kl..j * w + kl + 1 + m];
            let s = row[1..]
                .iter()
                .zip(&b[j + 1..=j + m])
                .fold(b[j], |s, (a, x)| s - a * x);
            b[j] = s / row[0];
        }
    }
}
