//! Six-bar dwell linkages (issue 35, item 4): a four-bar's coupler point whose
//! curve holds a nearly circular arc while the crank turns the dwell angle,
//! driving a dyad whose joint sits at that arc's centre — so the output rocker
//! stands (nearly) still — and swings the output outside the dwell (a Stephenson
//! III six-bar; Norton, *Design of Machinery*, §3.9, "dwell mechanisms").
//!
//! **Four-bar.** As in [`super::fourbar`]: A at the origin, D at (d, 0), crank a,
//! coupler b, rocker c, coupler point P = (u, v) in the coupler's frame (u along
//! B → C, v to its left), branch σ. The dwell is the crank range
//! [θm − δ/2, θm + δ/2] around its middle θm.
//!
//! **Arc.** The coupler points at `n_dwell` equally spaced crank angles of the
//! dwell are fitted by a circle in the geometric least-squares sense,
//! min Σ (|P_i − E| − R)², started from the algebraic (Kåsa) fit — a linear
//! least squares on x² + y² + Dx + Ey + F = 0 — and refined by Gauss–Newton
//! steps ([`fit_circle`]). A fit over the whole arc, not the osculating circle at
//! its middle: the osculating circle is exact at one point and drifts away
//! towards the dwell's ends, where the fit spreads the error over the arc.
//!
//! **Dyad and output.** The output joint E is at the circle's centre E0 during
//! the dwell; the dyad PE has the circle's radius R; the output rocker FE
//! (pivot F, length e) turns about F. Its pivot is placed in closed form and
//! then corrected: E0 is one extreme of the output's swing; the other extreme
//! E1 is taken where the coupler point is farthest from E0 (P_far), the dyad
//! pulled straight towards it, E1 = E0 + (|P_far − E0| − R)·(P_far − E0)/|·|.
//! F lies on the perpendicular bisector of E0E1, where the chord E0E1 subtends
//! the angle q: e = h/(2 sin(q/2)), h = |E1 − E0|, on either side (`side`
//! ±1). The construction's E1 is not exactly the actual extreme, so q is
//! corrected by secant steps until the swing measured on the six-bar's own
//! position solution equals the wanted swing; both sides are tried and the
//! better kept.
//!
//! **Measures, from the position solution (not from the fit).** E is solved
//! from P and F (circle–circle, branch τ: the side of the ray F → P that E is
//! on, fixed by E0 at the dwell's middle); the output angle ψ = arg(E − F). The
//! *residual* is the output's peak-to-peak motion over the dwell range (max ψ −
//! min ψ there); the *swing* its peak-to-peak motion over the whole turn. Both
//! are sampled and their extremes refined by golden-section search between the
//! samples next to each sampled extreme (to ~1e-12 rad): a refined extreme is
//! the true one when the sampled extreme lies in its basin, which the grid's
//! spacing (fine against the curve's features) makes the case. The second loop's
//! transmission angle μ2 (between E → P and E → F) is sampled on the
//! whole-turn grid; the four-bar's is in closed form. The coupler points on these
//! fixed grids (and at θm) do not depend on the output's placement: they are
//! solved once per candidate ([`Grids`]) and shared by all its placements; only
//! the golden-section searches solve the four-bar at new angles.
//!
//! **Ranking rule.** A candidate *violates* by the sum of: the four-bar's worst
//! transmission angle below the limit, the second loop's below the limit,
//! |swing − wanted| beyond [`SWING_TOL`] (all [rad]), and the logarithm of the
//! six links' longest-over-shortest ratio over its limit where above it. It is
//! *rejected* ([`REJECTED`]) where the crank does not turn fully, no arc or
//! placement exists, or the dyad cannot be assembled somewhere in the turn. The
//! objective is residual + 1000·violation (degrees): feasible candidates rank
//! by their residual alone.

use std::f64::consts::{PI, TAU};

use rayon::prelude::*;

use super::fourbar::{coupler_point, fourbar_transmission, grashof, Transmission};
use crate::input::InvalidInput;

/// Gauss–Newton steps after the Kåsa fit (each roughly squares the error near
/// the optimum; they stop early once a step is below 1e-15 of the radius).
pub const GN_STEPS: usize = 20;
/// The swing counts as met within this many radians.
pub const SWING_TOL: f64 = 1e-9;
/// The objective of a candidate that cannot be evaluated (see the module docs).
pub const REJECTED: f64 = 1e9;
/// Fields per candidate in [`dwell_batch`]'s output, in this order.
pub const FIELDS: [&str; 18] = [
    "objective",
    "violation",
    "residual",
    "swing",
    "e0_x",
    "e0_y",
    "radius",
    "pivot_x",
    "pivot_y",
    "rocker",
    "branch",
    "arc_dev",
    "mu4_min",
    "mu4_max",
    "mu2_min",
    "mu2_max",
    "side",
    "ratio",
];
/// Parameters per candidate in [`dwell_batch`]'s input: a, b, c, d [m], u, v
/// [m], θm [rad].
pub const PARAMS: usize = 7;

/// A circle: centre [m] and radius [m].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Circle {
    pub centre: [f64; 2],
    pub radius: f64,
}

/// Solves the 3 × 3 system m·x = r by Gaussian elimination with partial
/// pivoting; None where it is singular (a pivot below 1e-14 of the largest).
fn solve3(mut m: [[f64; 3]; 3], mut r: [f64; 3]) -> Option<[f64; 3]> {
    let big = m.iter().flatten().fold(0.0f64, |a, &v| a.max(v.abs()));
    for k in 0..3 {
        let p = (k..3).max_by(|&i, &j| m[i][k].abs().total_cmp(&m[j][k].abs()))?;
        let pivot = m[p][k].abs();
        if pivot.is_nan() || pivot <= 1e-14 * big {
            return None;
        }
        m.swap(k, p);
        r.swap(k, p);
        for i in k + 1..3 {
            let f = m[i][k] / m[k][k];
            let row_k = m[k];
            for (mij, mkj) in m[i].iter_mut().zip(row_k).skip(k) {
                *mij -= f * mkj;
            }
            r[i] -= f * r[k];
        }
    }
    let mut x = [0.0; 3];
    for k in (0..3).rev() {
        let s: f64 = (k + 1..3).map(|j| m[k][j] * x[j]).sum();
        x[k] = (r[k] - s) / m[k][k];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// The least-squares circle through `pts` (module docs): Kåsa's algebraic fit
/// refined by Gauss–Newton on the geometric distances. None for fewer than three
/// points, (nearly) collinear points, or a non-finite point.
pub fn fit_circle(pts: &[[f64; 2]]) -> Option<Circle> {
    let n = pts.len() as f64;
    if pts.len() < 3 || pts.iter().flatten().any(|v| !v.is_finite()) {
        return None;
    }
    // Centred coordinates: the normal equations' conditioning needs it.
    let mx = pts.iter().map(|p| p[0]).sum::<f64>() / n;
    let my = pts.iter().map(|p| p[1]).sum::<f64>() / n;
    let mut m = [[0.0; 3]; 3];
    let mut r = [0.0; 3];
    for p in pts {
        let (x, y) = (p[0] - mx, p[1] - my);
        let row = [x, y, 1.0];
        let z = -(x * x + y * y);
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] += row[i] * row[j];
            }
            r[i] += row[i] * z;
        }
    }
    let [dd, ee, ff] = solve3(m, r)?;
    let (mut cx, mut cy) = (-dd / 2.0, -ee / 2.0);
    let r2 = cx * cx + cy * cy - ff;
    if r2.is_nan() || r2 <= 0.0 {
        return None;
    }
    let mut rad = r2.sqrt();
    for _ in 0..GN_STEPS {
        let mut jtj = [[0.0; 3]; 3];
        let mut jtr = [0.0; 3];
        for p in pts {
            let (dx, dy) = (p[0] - mx - cx, p[1] - my - cy);
            let di = dx.hypot(dy);
            if di == 0.0 {
                return None;
            }
            // Residual di − R; its gradient in (cx, cy, R).
            let row = [-dx / di, -dy / di, -1.0];
            let res = di - rad;
            for i in 0..3 {
                for j in 0..3 {
                    jtj[i][j] += row[i] * row[j];
                }
                jtr[i] -= row[i] * res;
            }
        }
        let Some(step) = solve3(jtj, jtr) else { break };
        cx += step[0];
        cy += step[1];
        rad += step[2];
        if step.iter().map(|s| s.abs()).fold(0.0, f64::max) <= 1e-15 * rad.abs() {
            break;
        }
    }
    (rad.is_finite() && rad > 0.0).then_some(Circle {
        centre: [cx + mx, cy + my],
        radius: rad,
    })
}

/// A four-bar with a coupler point (module docs), and the dwell's middle θm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Design {
    pub a: f64,
    pub b: f64,
    pub c: f64,
    pub d: f64,
    pub u: f64,
    pub v: f64,
    pub sigma: f64,
    pub theta_mid: f64,
}

impl Design {
    /// From [a, b, c, d, u, v, θm] and the branch σ.
    pub fn from_params(p: &[f64], sigma: f64) -> Design {
        Design {
            a: p[0],
            b: p[1],
            c: p[2],
            d: p[3],
            u: p[4],
            v: p[5],
            sigma,
            theta_mid: p[6],
        }
    }

    /// The coupler point at crank angle θ [rad].
    pub fn point(&self, theta: f64) -> Option<[f64; 2]> {
        coupler_point(
            self.a, self.b, self.c, self.d, theta, self.sigma, self.u, self.v,
        )
    }
}

/// What is asked of the six-bar.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spec {
    /// The dwell's crank angle δ [rad], in (0, 2π).
    pub span: f64,
    /// The output's wanted swing [rad], in (0, π).
    pub swing: f64,
    /// The least transmission angle allowed in both loops [rad], in [0, π/2].
    pub min_mu: f64,
    /// The largest ratio allowed of the six links' longest to shortest
    /// (a, b, c, d, the dyad R and the output rocker e), ≥ 1.
    pub max_ratio: f64,
    /// Crank angles sampled over the dwell (≥ 3).
    pub n_dwell: usize,
    /// Crank angles sampled over the whole turn (≥ 8).
    pub n_turn: usize,
}

impl Spec {
    /// Checks the fields, naming the bad one.
    pub fn check(&self) -> Result<(), InvalidInput> {
        if !(self.span > 0.0 && self.span < TAU) {
            return Err(InvalidInput::bad_value(
                "span",
                self.span,
                "[rad] must be in (0, 2π)",
            ));
        }
        if !(self.swing > 0.0 && self.swing < PI) {
            return Err(InvalidInput::bad_value(
                "swing",
                self.swing,
                "[rad] must be in (0, π)",
            ));
        }
        if !(0.0..=PI / 2.0).contains(&self.min_mu) {
            return Err(InvalidInput::bad_value(
                "min_mu",
                self.min_mu,
                "[rad] must be in [0, π/2]",
            ));
        }
        if self.max_ratio.is_nan() || self.max_ratio < 1.0 {
            return Err(InvalidInput::bad_value(
                "max_ratio",
                self.max_ratio,
                "must be ≥ 1 (longest over shortest link)",
            ));
        }
        if self.n_dwell < 3 || self.n_turn < 8 {
            return Err(InvalidInput::bad_value(
                "n_dwell",
                self.n_dwell as f64,
                "needs n_dwell ≥ 3 and n_turn ≥ 8",
            ));
        }
        Ok(())
    }
}

/// The output dyad: E0 and R of the arc, the rocker's pivot F [m] and length
/// e [m], the dyad's branch τ = ±1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Output {
    pub circle: Circle,
    pub pivot: [f64; 2],
    pub rocker: f64,
    pub branch: f64,
}

impl Output {
    /// The output joint E [m] for the coupler point P, or None where the dyad
    /// cannot be assembled.
    pub fn joint(&self, p: [f64; 2]) -> Option<[f64; 2]> {
        let (fx, fy) = (p[0] - self.pivot[0], p[1] - self.pivot[1]);
        let f = fx.hypot(fy);
        let (r, e) = (self.circle.radius, self.rocker);
        if f == 0.0 {
            return None;
        }
        let cos_g = (e * e + f * f - r * r) / (2.0 * e * f);
        if !(-1.0..=1.0).contains(&cos_g) {
            return None;
        }
        let ang = fy.atan2(fx) + self.branch * cos_g.acos();
        Some([self.pivot[0] + e * ang.cos(), self.pivot[1] + e * ang.sin()])
    }

    /// cos μ2 of the second loop for the coupler point P (μ2 between E → P and
    /// E → F, by the cosine rule).
    pub fn cos_mu2(&self, p: [f64; 2]) -> f64 {
        let f2 = (p[0] - self.pivot[0]).powi(2) + (p[1] - self.pivot[1]).powi(2);
        let (r, e) = (self.circle.radius, self.rocker);
        (r * r + e * e - f2) / (2.0 * r * e)
    }
}

/// The output angle ψ(θ) − ψ(θm) [rad] wrapped into (−π, π], or None where the
/// six-bar does not assemble.
pub fn output_angle(design: &Design, out: &Output, theta: f64, psi_mid: f64) -> Option<f64> {
    output_angle_at(out, design.point(theta)?, psi_mid)
}

/// [`output_angle`] for the coupler point P [m] at the crank angle.
fn output_angle_at(out: &Output, p: [f64; 2], psi_mid: f64) -> Option<f64> {
    let e = out.joint(p)?;
    let psi = (e[1] - out.pivot[1]).atan2(e[0] - out.pivot[0]) - psi_mid;
    Some(psi - TAU * ((psi + PI) / TAU).ceil() + TAU)
}

/// The coupler points at the crank angles lo + step·i, i = 0..=n, step =
/// (hi − lo)/n (None where the four-bar does not assemble): a sampling grid of
/// [`peak_to_peak`], solved once per candidate since it does not change with the
/// output's placement.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    lo: f64,
    step: f64,
    points: Vec<Option<[f64; 2]>>,
}

impl Grid {
    fn new(design: &Design, lo: f64, hi: f64, n: usize) -> Grid {
        let step = (hi - lo) / n as f64;
        let points = (0..=n)
            .map(|i| design.point(lo + step * i as f64))
            .collect();
        Grid { lo, step, points }
    }

    /// The number of intervals n.
    fn n(&self) -> usize {
        self.points.len() - 1
    }
}

/// The coupler points a candidate's measures use at fixed crank angles (module
/// docs), whatever the output's placement: at θm, on the dwell's and the turn's
/// sampling grids, and on the second loop's transmission-angle grid.
#[derive(Debug, Clone, PartialEq)]
pub struct Grids {
    mid: Option<[f64; 2]>,
    dwell: Grid,
    turn: Grid,
    mu2: Vec<Option<[f64; 2]>>,
}

impl Grids {
    /// The four-bar solved on the grids of [`measure`] for `spec`.
    pub fn new(design: &Design, spec: &Spec) -> Grids {
        let tm = design.theta_mid;
        let (lo, hi) = (tm - spec.span / 2.0, tm + spec.span / 2.0);
        // One step beyond each end of the turn: ψ is periodic, and an extreme just
        // across the seam (θm ± π) must have samples on both sides for its refinement.
        let st = TAU / spec.n_turn as f64;
        Grids {
            mid: design.point(tm),
            dwell: Grid::new(design, lo, hi, 4 * spec.n_dwell),
            turn: Grid::new(design, tm - PI - st, tm + PI + st, spec.n_turn + 2),
            mu2: (0..spec.n_turn)
                .map(|i| design.point(tm + TAU * i as f64 / spec.n_turn as f64))
                .collect(),
        }
    }
}

/// The largest of f on [lo, hi] by golden-section search (f unimodal there).
fn golden_max(f: &dyn Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let (mut x1, mut x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..80 {
        if f1 < f2 {
            lo = x1;
            (x1, f1) = (x2, f2);
            x2 = lo + g * (hi - lo);
            f2 = f(x2);
        } else {
            hi = x2;
            (x2, f2) = (x1, f1);
            x1 = hi - g * (hi - lo);
            f1 = f(x1);
        }
        if hi - lo <= 1e-13 {
            break;
        }
    }
    f1.max(f2)
}

/// Peak-to-peak of `psi` over the grid's range, sampled at its n + 1 angles
/// (`psi_at` of its coupler points) and refined (module docs); None where it does
/// not assemble at a sample.
fn peak_to_peak(
    psi: &dyn Fn(f64) -> Option<f64>,
    psi_at: &dyn Fn([f64; 2]) -> Option<f64>,
    grid: &Grid,
) -> Option<f64> {
    let (lo, step, n) = (grid.lo, grid.step, grid.n());
    let vals: Vec<f64> = grid
        .points
        .iter()
        .map(|p| psi_at((*p)?))
        .collect::<Option<_>>()?;
    let arg = |better: &dyn Fn(f64, f64) -> bool| {
        (1..=n).fold(0, |k, i| if better(vals[i], vals[k]) { i } else { k })
    };
    let (imax, imin) = (arg(&|x, y| x > y), arg(&|x, y| x < y));
    // Outside the assembly range the search sees ∓∞ and stays inside.
    let around = |i: usize| {
        (
            lo + step * i.saturating_sub(1) as f64,
            lo + step * (i + 1).min(n) as f64,
        )
    };
    let up = |t: f64| psi(t).unwrap_or(f64::NEG_INFINITY);
    let down = |t: f64| psi(t).map_or(f64::NEG_INFINITY, |v| -v);
    let (a, b) = around(imax);
    let top = golden_max(&up, a, b).max(vals[imax]);
    let (a, b) = around(imin);
    let bottom = -golden_max(&down, a, b).max(-vals[imin]);
    Some(top - bottom)
}

/// The six-bar's measures (module docs), angles [rad].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Measures {
    pub residual: f64,
    pub swing: f64,
    pub mu2_min: f64,
    pub mu2_max: f64,
}

/// Residual, swing and the second loop's transmission angles of the six-bar
/// (module docs), or None where it does not assemble over the whole turn.
pub fn measure(design: &Design, out: &Output, spec: &Spec) -> Option<Measures> {
    measure_on(design, out, &Grids::new(design, spec))
}

/// [`measure`] with the design's coupler points on the grids solved beforehand
/// ([`Grids::new`] for this design and spec).
pub fn measure_on(design: &Design, out: &Output, grids: &Grids) -> Option<Measures> {
    let e_mid = out.joint(grids.mid?)?;
    let psi_mid = (e_mid[1] - out.pivot[1]).atan2(e_mid[0] - out.pivot[0]);
    let psi = |t: f64| output_angle(design, out, t, psi_mid);
    let psi_at = |p: [f64; 2]| output_angle_at(out, p, psi_mid);
    let residual = peak_to_peak(&psi, &psi_at, &grids.dwell)?;
    let swing = peak_to_peak(&psi, &psi_at, &grids.turn)?;
    let (mut cmin, mut cmax) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in &grids.mu2 {
        let c = out.cos_mu2((*p)?);
        cmin = cmin.min(c);
        cmax = cmax.max(c);
    }
    Some(Measures {
        residual,
        swing,
        mu2_min: cmax.clamp(-1.0, 1.0).acos(),
        mu2_max: cmin.clamp(-1.0, 1.0).acos(),
    })
}

/// The fitted arc over the dwell and its largest radial deviation [m].
pub fn dwell_arc(design: &Design, spec: &Spec) -> Option<(Circle, f64)> {
    let n = spec.n_dwell;
    let lo = design.theta_mid - spec.span / 2.0;
    let pts: Vec<[f64; 2]> = (0..n)
        .map(|i| design.point(lo + spec.span * i as f64 / (n - 1) as f64))
        .collect::<Option<_>>()?;
    let circle = fit_circle(&pts)?;
    let dev = pts
        .iter()
        .map(|p| ((p[0] - circle.centre[0]).hypot(p[1] - circle.centre[1]) - circle.radius).abs())
        .fold(0.0, f64::max);
    Some((circle, dev))
}

/// The rocker of the construction for the chord angle q on `side` (module docs).
fn construct(circle: Circle, far: [f64; 2], q: f64, side: f64) -> Option<Output> {
    let e0 = circle.centre;
    let (dx, dy) = (far[0] - e0[0], far[1] - e0[1]);
    let dist = dx.hypot(dy);
    let h = dist - circle.radius;
    if h.is_nan() || h <= 1e-9 * dist {
        return None;
    }
    let (ux, uy) = (dx / dist, dy / dist);
    let mid = [e0[0] + ux * h / 2.0, e0[1] + uy * h / 2.0];
    let off = side * h / 2.0 / (q / 2.0).tan();
    let pivot = [mid[0] - uy * off, mid[1] + ux * off];
    let rocker = h / 2.0 / (q / 2.0).sin();
    Some(Output {
        circle,
        pivot,
        rocker,
        branch: 1.0,
    })
}

/// The output on `side` with its swing corrected to the wanted one by secant
/// steps on q (module docs), with its measures.
fn place_side(
    design: &Design,
    spec: &Spec,
    grids: &Grids,
    circle: Circle,
    far: [f64; 2],
    side: f64,
) -> Option<(Output, Measures)> {
    let p_mid = grids.mid?;
    let eval = |q: f64| -> Option<(Output, Measures)> {
        let mut out = construct(circle, far, q, side)?;
        // τ: the side of the ray F → P_mid that E0 is on.
        let (fx, fy) = (p_mid[0] - out.pivot[0], p_mid[1] - out.pivot[1]);
        let (gx, gy) = (
            circle.centre[0] - out.pivot[0],
            circle.centre[1] - out.pivot[1],
        );
        out.branch = if fx * gy - fy * gx >= 0.0 { 1.0 } else { -1.0 };
        let m = measure_on(design, &out, grids)?;
        Some((out, m))
    };
    let clamp = |q: f64| q.clamp(1e-3, PI - 1e-3);
    let (mut q0, mut q1) = (spec.swing, clamp(spec.swing * 1.05));
    let mut best = eval(q0)?;
    let mut g0 = best.1.swing - spec.swing;
    for _ in 0..30 {
        if g0.abs() <= SWING_TOL * 0.01 {
            break;
        }
        let Some(next) = eval(q1) else { break };
        let g1 = next.1.swing - spec.swing;
        if g1.abs() < g0.abs() {
            best = next;
        }
        if g1 == g0 {
            break;
        }
        let q2 = clamp(q1 - g1 * (q1 - q0) / (g1 - g0));
        (q0, g0, q1) = (q1, g1, q2);
    }
    Some(best)
}

/// One evaluated six-bar (module docs), angles [rad].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sixbar {
    pub output: Output,
    pub measures: Measures,
    pub arc_dev: f64,
    pub mu4_min: f64,
    pub mu4_max: f64,
    pub side: f64,
    /// The six links' longest over shortest.
    pub ratio: f64,
    /// The constraints' violation [rad] (module docs), 0 where all hold.
    pub violation: f64,
}

impl Sixbar {
    /// The objective [deg]: residual + 1000·violation.
    pub fn objective(&self) -> f64 {
        (self.measures.residual + 1000.0 * self.violation).to_degrees()
    }
}

/// The six-bar of a four-bar design for `spec` (module docs), or None where it
/// is rejected (the crank does not turn fully, no arc, no placement, or the
/// dyad does not assemble over the turn).
pub fn evaluate(design: &Design, spec: &Spec) -> Option<Sixbar> {
    let g = grashof(design.a, design.b, design.c, design.d).ok()?;
    if !(g.crank_turns && design.u.is_finite() && design.v.is_finite()) {
        return None;
    }
    let Ok(Transmission::Range { mu_min, mu_max, .. }) =
        fourbar_transmission(design.a, design.b, design.c, design.d, 0.0, TAU)
    else {
        return None;
    };
    let (circle, arc_dev) = dwell_arc(design, spec)?;
    let far = (0..spec.n_turn)
        .filter_map(|i| design.point(TAU * i as f64 / spec.n_turn as f64))
        .max_by(|p, q| {
            let d = |p: &[f64; 2]| (p[0] - circle.centre[0]).hypot(p[1] - circle.centre[1]);
            d(p).total_cmp(&d(q))
        })?;
    let mu4 = mu_min.min(PI - mu_max);
    let (d4_lo, d4_hi) = [design.b, design.c, design.d]
        .into_iter()
        .fold((design.a, design.a), |(lo, hi), v| (lo.min(v), hi.max(v)));
    // The six links' longest over shortest (the output's e and R from the placement).
    let ratio = |o: &Output| {
        let (lo, hi) = [o.circle.radius, o.rocker]
            .into_iter()
            .fold((d4_lo, d4_hi), |(lo, hi), v| (lo.min(v), hi.max(v)));
        hi / lo
    };
    let violation = |o: &Output, m: &Measures| {
        let mu2 = m.mu2_min.min(PI - m.mu2_max);
        let miss = (m.swing - spec.swing).abs();
        (spec.min_mu - mu4).max(0.0)
            + (spec.min_mu - mu2).max(0.0)
            + (ratio(o) / spec.max_ratio).ln().max(0.0)
            + if miss > SWING_TOL { miss } else { 0.0 }
    };
    // Solved once here: the same for every placement of the output.
    let grids = Grids::new(design, spec);
    [1.0, -1.0]
        .into_iter()
        .filter_map(|side| {
            let (output, measures) = place_side(design, spec, &grids, circle, far, side)?;
            Some(Sixbar {
                output,
                measures,
                arc_dev,
                mu4_min: mu_min,
                mu4_max: mu_max,
                side,
                ratio: ratio(&output),
                violation: violation(&output, &measures),
            })
        })
        .min_by(|x, y| x.objective().total_cmp(&y.objective()))
}

/// The fields of one candidate ([`FIELDS`]): NaN but the objective
/// ([`REJECTED`]) where it is rejected.
pub fn fields(s: Option<&Sixbar>) -> [f64; FIELDS.len()] {
    let Some(s) = s else {
        let mut f = [f64::NAN; FIELDS.len()];
        f[0] = REJECTED;
        return f;
    };
    let o = &s.output;
    [
        s.objective(),
        s.violation,
        s.measures.residual,
        s.measures.swing,
        o.circle.centre[0],
        o.circle.centre[1],
        o.circle.radius,
        o.pivot[0],
        o.pivot[1],
        o.rocker,
        o.branch,
        s.arc_dev,
        s.mu4_min,
        s.mu4_max,
        s.measures.mu2_min,
        s.measures.mu2_max,
        s.side,
        s.ratio,
    ]
}

/// Evaluates the candidates `params` (rows of [`PARAMS`]: a, b, c, d, u, v
/// [m], θm [rad]) on branch σ in parallel on `pool`: rows of [`FIELDS`].
pub fn dwell_batch(
    params: &[f64],
    sigma: f64,
    spec: &Spec,
    pool: &rayon::ThreadPool,
) -> Result<Vec<f64>, InvalidInput> {
    spec.check()?;
    InvalidInput::check_finite("params", params)?;
    if !params.len().is_multiple_of(PARAMS) {
        return Err(InvalidInput::bad_value(
            "params",
            params.len() as f64,
            "must hold rows of 7 numbers (a, b, c, d, u, v, theta_mid)",
        ));
    }
    if sigma != 1.0 && sigma != -1.0 {
        return Err(InvalidInput::bad_value("sigma", sigma, "must be +1 or -1"));
    }
    let rows: Vec<[f64; FIELDS.len()]> = pool.install(|| {
        params
            .par_chunks(PARAMS)
            .map(|p| {
                if crate::cancel::requested() {
                    return fields(None);
                }
                fields(evaluate(&Design::from_params(p, sigma), spec).as_ref())
            })
            .collect()
    });
    Ok(rows.into_iter().flatten().collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn on_circle(cx: f64, cy: f64, r: f64, lo: f64, hi: f64, n: usize) -> Vec<[f64; 2]> {
        (0..n)
            .map(|i| {
                let t = lo + (hi - lo) * i as f64 / (n - 1) as f64;
                [cx + r * t.cos(), cy + r * t.sin()]
            })
            .collect()
    }

    #[test]
    fn fit_recovers_an_exact_circle() {
        let c = fit_circle(&on_circle(3.0, -2.0, 0.75, 0.3, 1.1, 9)).unwrap();
        assert!((c.centre[0] - 3.0).abs() < 1e-12 && (c.centre[1] + 2.0).abs() < 1e-12);
        assert!((c.radius - 0.75).abs() < 1e-12);
        assert!(fit_circle(&[[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]).is_none());
        assert!(fit_circle(&[[0.0, 0.0], [1.0, 1.0]]).is_none());
    }

    #[test]
    fn gauss_newton_beats_kasa_on_noisy_points() {
        // Radial errors alternating ±1 % on a short arc: the geometric fit's sum
        // of squared distances is the least, so no larger than a circle through
        // the true centre and radius.
        let mut pts = on_circle(0.0, 0.0, 1.0, 0.0, 0.8, 21);
        for (i, p) in pts.iter_mut().enumerate() {
            let s = if i % 2 == 0 { 1.01 } else { 0.99 };
            *p = [p[0] * s, p[1] * s];
        }
        let c = fit_circle(&pts).unwrap();
        let ss = |cx: f64, cy: f64, r: f64| -> f64 {
            pts.iter()
                .map(|p| ((p[0] - cx).hypot(p[1] - cy) - r).powi(2))
                .sum()
        };
        assert!(ss(c.centre[0], c.centre[1], c.radius) <= ss(0.0, 0.0, 1.0) + 1e-15);
    }

    fn spec() -> Spec {
        Spec {
            span: 60f64.to_radians(),
            swing: 40f64.to_radians(),
            min_mu: 0.0,
            max_ratio: f64::INFINITY,
            n_dwell: 25,
            n_turn: 360,
        }
    }

    #[test]
    fn spec_checks_name_the_field() {
        let bad = Spec {
            span: 0.0,
            ..spec()
        };
        assert!(format!("{:?}", bad.check().unwrap_err()).contains("span"));
        let bad = Spec {
            swing: PI,
            ..spec()
        };
        assert!(format!("{:?}", bad.check().unwrap_err()).contains("swing"));
    }

    #[test]
    fn a_dwell_linkage_meets_its_swing_and_its_residual_bounds_dense_sampling() {
        let design = Design {
            a: 0.3,
            b: 1.0,
            c: 1.0,
            d: 1.0,
            u: 0.5,
            v: 0.9,
            sigma: 1.0,
            theta_mid: 4.0,
        };
        let s = evaluate(&design, &spec()).expect("a crank-rocker with an arc");
        assert!((s.measures.swing - spec().swing).abs() <= SWING_TOL);
        // Dense sampling of the output (independent of the refinement) stays
        // inside the refined peak-to-peaks and comes within its step's error.
        let e = s.output.joint(design.point(4.0).unwrap()).unwrap();
        let psi_mid = (e[1] - s.output.pivot[1]).atan2(e[0] - s.output.pivot[0]);
        let dense = |lo: f64, hi: f64| {
            let v: Vec<f64> = (0..=100_000)
                .map(|i| {
                    let t = lo + (hi - lo) * i as f64 / 100_000.0;
                    output_angle(&design, &s.output, t, psi_mid).unwrap()
                })
                .collect();
            let mx = v.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
            let mn = v.iter().cloned().fold(f64::INFINITY, f64::min);
            mx - mn
        };
        let half = spec().span / 2.0;
        let r = dense(4.0 - half, 4.0 + half);
        assert!(r <= s.measures.residual + 1e-12 && r >= s.measures.residual - 1e-8);
        let w = dense(4.0 - PI, 4.0 + PI);
        assert!(w <= s.measures.swing + 1e-12 && w >= s.measures.swing - 1e-8);
    }

    /// The measures as the kernel took them before [`Grids`]: the four-bar solved
    /// again at every grid angle of every placement.
    fn measure_resolving(design: &Design, out: &Output, spec: &Spec) -> Option<Measures> {
        let p2p = |psi: &dyn Fn(f64) -> Option<f64>, lo: f64, hi: f64, n: usize| {
            let step = (hi - lo) / n as f64;
            let vals: Vec<f64> = (0..=n)
                .map(|i| psi(lo + step * i as f64))
                .collect::<Option<_>>()?;
            let arg = |better: &dyn Fn(f64, f64) -> bool| {
                (1..=n).fold(0, |k, i| if better(vals[i], vals[k]) { i } else { k })
            };
            let (imax, imin) = (arg(&|x, y| x > y), arg(&|x, y| x < y));
            let around = |i: usize| {
                (
                    lo + step * i.saturating_sub(1) as f64,
                    lo + step * (i + 1).min(n) as f64,
                )
            };
            let up = |t: f64| psi(t).unwrap_or(f64::NEG_INFINITY);
            let down = |t: f64| psi(t).map_or(f64::NEG_INFINITY, |v| -v);
            let (a, b) = around(imax);
            let top = golden_max(&up, a, b).max(vals[imax]);
            let (a, b) = around(imin);
            let bottom = -golden_max(&down, a, b).max(-vals[imin]);
            Some(top - bottom)
        };
        let tm = design.theta_mid;
        let e_mid = out.joint(design.point(tm)?)?;
        let psi_mid = (e_mid[1] - out.pivot[1]).atan2(e_mid[0] - out.pivot[0]);
        let psi = |t: f64| output_angle(design, out, t, psi_mid);
        let residual = p2p(
            &psi,
            tm - spec.span / 2.0,
            tm + spec.span / 2.0,
            4 * spec.n_dwell,
        )?;
        let st = TAU / spec.n_turn as f64;
        let swing = p2p(&psi, tm - PI - st, tm + PI + st, spec.n_turn + 2)?;
        let (mut cmin, mut cmax) = (f64::INFINITY, f64::NEG_INFINITY);
        for i in 0..spec.n_turn {
            let c = out.cos_mu2(design.point(tm + TAU * i as f64 / spec.n_turn as f64)?);
            cmin = cmin.min(c);
            cmax = cmax.max(c);
        }
        Some(Measures {
            residual,
            swing,
            mu2_min: cmax.clamp(-1.0, 1.0).acos(),
            mu2_max: cmin.clamp(-1.0, 1.0).acos(),
        })
    }

    proptest! {
        #[test]
        fn grids_solved_once_measure_bit_for_bit_as_solved_again(
            a in 0.15f64..0.4, b in 0.8f64..1.6, c in 0.8f64..1.6,
            u in -0.5f64..1.5, v in -1.0f64..1.0, tm in 0.0f64..TAU,
            sigma in prop::sample::select(vec![1.0, -1.0]),
            dq in -0.3f64..0.3, n_dwell in 3usize..30, n_turn in 8usize..400,
        ) {
            let design = Design { a, b, c, d: 1.0, u, v, sigma, theta_mid: tm };
            let sp = Spec { n_dwell, n_turn, ..spec() };
            let Some(s) = evaluate(&design, &sp) else { return Ok(()) };
            let bits = |m: Option<Measures>| {
                m.map(|m| [m.residual, m.swing, m.mu2_min, m.mu2_max].map(f64::to_bits))
            };
            // The placement the search kept, and another (a rocker dq longer or shorter).
            let again = measure_resolving(&design, &s.output, &sp);
            prop_assert_eq!(bits(Some(s.measures)), bits(again));
            let other = Output { rocker: s.output.rocker * (1.0 + dq), ..s.output };
            let cached = measure_on(&design, &other, &Grids::new(&design, &sp));
            prop_assert_eq!(bits(cached), bits(measure_resolving(&design, &other, &sp)));
        }

        #[test]
        fn fit_is_exact_on_random_circles(
            cx in -5.0f64..5.0, cy in -5.0f64..5.0, r in 0.05f64..3.0,
            lo in -3.0f64..3.0, span in 0.2f64..6.0, n in 3usize..40,
        ) {
            let c = fit_circle(&on_circle(cx, cy, r, lo, lo + span, n)).unwrap();
            let tol = 1e-7 * (1.0 + cx.abs() + cy.abs() + r) / span.min(1.0).powi(2);
            prop_assert!((c.centre[0] - cx).abs() < tol, "{:?}", c);
            prop_assert!((c.centre[1] - cy).abs() < tol, "{:?}", c);
            prop_assert!((c.radius - r).abs() < tol, "{:?}", c);
        }

        #[test]
        fn residual_bounds_the_sampled_dwell_motion(
            a in 0.15f64..0.4, b in 0.8f64..1.6, c in 0.8f64..1.6,
            u in -0.5f64..1.5, v in -1.0f64..1.0, tm in 0.0f64..TAU,
        ) {
            let design = Design { a, b, c, d: 1.0, u, v, sigma: 1.0, theta_mid: tm };
            let sp = spec();
            prop_assume!(grashof(a, b, c, 1.0).unwrap().crank_turns);
            let Some(s) = evaluate(&design, &sp) else { return Ok(()) };
            let e = s.output.joint(design.point(tm).unwrap()).unwrap();
            let psi_mid = (e[1] - s.output.pivot[1]).atan2(e[0] - s.output.pivot[0]);
            let half = sp.span / 2.0;
            let v: Vec<f64> = (0..=2000)
                .map(|i| output_angle(&design, &s.output, tm - half + sp.span * i as f64 / 2000.0, psi_mid).unwrap())
                .collect();
            let mx = v.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
            let mn = v.iter().cloned().fold(f64::INFINITY, f64::min);
            prop_assert!(mx - mn <= s.measures.residual + 1e-10, "{} > {}", mx - mn, s.measures.residual);
            // The arc's fit and the residual: an output standing still needs the
            // coupler point on the arc, so a residual of zero means no deviation.
            prop_assert!(s.arc_dev >= 0.0 && s.measures.residual >= 0.0);
        }
    }
}
