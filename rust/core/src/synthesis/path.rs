//! Path generation (issue 35, item 2): a batch evaluator of candidate four-bars
//! and slider-cranks against target points a coupler point must pass.
//!
//! **Candidates.** One flat row of [`PARAMS`] (+1 with timing) values per
//! candidate, in the frame of the targets [m, rad]:
//! * four-bar: `x0, y0` the crank's ground pivot A; `theta0` the direction of
//!   the ground link A→D; `r1` |AD|, `r2` the crank |AB|, `r3` the coupler
//!   |BC|, `r4` the rocker |DC|; `u, v` the coupler point P in the coupler's
//!   frame (origin B, x along B→C, y a quarter turn to its left); `mode` the
//!   assembly mode σ of [`super::fourbar`] (≥ 0: +1, C on the left of the ray
//!   D → B; < 0: −1, on its right).
//! * slider-crank: `x0, y0` the crank pivot A; `theta0` the direction t of the
//!   slider's guide; `r1` the guide's offset e (the guide is the line through
//!   A + e·n along t, n = t turned a quarter left); `r2` the crank |AB|; `r3`
//!   the coupler |BC|; `r4` unused (any value); `u, v` as above; `mode` ≥ 0:
//!   C ahead of B's foot on the guide (along t), < 0: behind.
//! * with timing, a last column `phi1`: the absolute crank angle [rad] (from
//!   the frame's x axis) at the first target.
//!
//! The crank angle φ is absolute, as `Linkage.solve` takes it: B = A +
//! r2·(cos φ, sin φ).
//!
//! **Error.** With timing τ (the crank's turn from the first target to each
//! target, τ₀ = 0), target i is compared with P(phi1 + τᵢ). Without timing, the
//! error of a target is its distance to the coupler curve over the whole turn,
//! found by the rule: sample the curve at `samples` crank angles 2πk/M, take
//! the sample nearest the target, then `refine` golden-section steps on the
//! squared distance over the two sample intervals beside it. The distance found
//! is always a distance to a point of the curve (never below the true
//! distance); it is the true one when the samples resolve the curve, that is
//! when the nearest sample lies in the basin of the nearest point (checked
//! against dense sampling in the tests). The crank angle of each target's
//! nearest point is returned when asked, so the error can be re-checked by any
//! solver.
//!
//! **Working range and constraints.** The working range of the crank is the
//! whole turn without timing, or with `full_turn`; otherwise the interval of
//! crank angles the targets span, [phi1 + min τ, phi1 + max τ]. On it, in
//! closed form (the dyad's closing distance is a function of cos or sin of the
//! crank angle, extreme at the interval's ends or at a whole or half turn
//! inside it; the shared closed forms of [`super::fourbar`]):
//! * the candidate must assemble at every angle of the range, strictly (no
//!   fold: the dyad never stretched or folded flat), so the assembly mode it
//!   starts in is the one it keeps, without a branch change;
//! * the transmission angle μ (four-bar: between coupler and rocker; slider:
//!   between coupler and the guide's normal, 90° with the coupler along the
//!   guide) must stay in [μmin, 180° − μmin];
//! * longest over shortest link (four-bar: r1..r4; slider-crank: r2, r3) at
//!   most `max_ratio`;
//! * the ground pivots (A, and D for a four-bar) inside the box, when given.
//!
//! **Penalty, decided.** A candidate that violates a constraint gets the cost
//! [`PENALTY`]·(1 + v), v the sum of its violations each measured relative to
//! its own scale (so any feasible candidate ranks before any violated one, and
//! violated ones rank by how far they are from feasible); a feasible one gets
//! its RMS error. A row with a non-finite value or a length not above zero gets
//! the cost +∞ and NaN errors.

use rayon::prelude::*;

use std::f64::consts::PI;

use super::fourbar::{fourbar_transmission, slider_crank_transmission, Transmission};
use crate::geom::sin_cos;
use crate::input::InvalidInput;

/// Columns of a candidate row without timing (with timing, `phi1` follows).
pub const PARAMS: [&str; 10] = [
    "x0", "y0", "theta0", "r1", "r2", "r3", "r4", "u", "v", "mode",
];

/// The columns of the result of [`evaluate_into`], per candidate.
pub const COLUMNS: [&str; 6] = ["cost", "rms", "max", "violation", "mu_min", "mu_max"];

/// The cost floor of a violated candidate (module doc).
pub const PENALTY: f64 = 1e100;

/// Candidates per parallel chunk (a poll of the cancel flag each).
const CHUNK: usize = 256;

/// Which mechanism the rows describe.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    FourBar,
    SliderCrank,
}

/// The targets, the rule and the constraints one batch is evaluated against.
#[derive(Debug, Clone)]
pub struct Spec<'a> {
    pub kind: Kind,
    /// Target points, flat (x, y) pairs [m].
    pub targets: &'a [f64],
    /// The crank's turn from the first target to each [rad] (τ₀ = 0); None: no timing.
    pub timing: Option<&'a [f64]>,
    /// Curve samples over the whole turn without timing (M).
    pub samples: usize,
    /// Golden-section steps refining each target's nearest sample.
    pub refine: usize,
    /// The crank must turn fully (always so without timing).
    pub full_turn: bool,
    /// Smallest transmission angle allowed [rad] (0: none).
    pub min_transmission: f64,
    /// Largest ratio longest/shortest link (+∞: none).
    pub max_ratio: f64,
    /// Ground pivots in [xmin, xmax, ymin, ymax], when given.
    pub pivot_box: Option<[f64; 4]>,
}

impl Spec<'_> {
    /// Values per candidate row.
    pub fn width(&self) -> usize {
        PARAMS.len() + usize::from(self.timing.is_some())
    }

    fn validate(&self) -> Result<(), InvalidInput> {
        InvalidInput::check_finite("targets", self.targets)?;
        if !self.targets.len().is_multiple_of(2) || self.targets.is_empty() {
            return Err(InvalidInput::bad_value(
                "targets",
                self.targets.len() as f64,
                "values must be (x, y) pairs, at least one",
            ));
        }
        if let Some(t) = self.timing {
            InvalidInput::check_finite("timing", t)?;
            if t.len() * 2 != self.targets.len() {
                return Err(InvalidInput::bad_value(
                    "timing",
                    t.len() as f64,
                    "angles must be one per target",
                ));
            }
        } else if self.samples < 3 {
            return Err(InvalidInput::bad_value(
                "samples",
                self.samples as f64,
                "must be at least 3",
            ));
        }
        if !(0.0..std::f64::consts::FRAC_PI_2).contains(&self.min_transmission) {
            return Err(InvalidInput::bad_value(
                "min_transmission",
                self.min_transmission,
                "[rad] must be in [0, π/2)",
            ));
        }
        if self.max_ratio.is_nan() || self.max_ratio < 1.0 {
            return Err(InvalidInput::bad_value(
                "max_ratio",
                self.max_ratio,
                "must be at least 1 (or +inf for none)",
            ));
        }
        if let Some(b) = self.pivot_box {
            InvalidInput::check_finite("pivot_box", &b)?;
            if !(b[0] <= b[1] && b[2] <= b[3]) {
                return Err(InvalidInput::bad_value(
                    "pivot_box",
                    b[1] - b[0],
                    "must be [xmin, xmax, ymin, ymax] with xmin ≤ xmax and ymin ≤ ymax",
                ));
            }
        }
        Ok(())
    }
}

/// One candidate, its fixed parts computed once.
#[derive(Debug, Clone, Copy)]
struct Cand {
    kind: Kind,
    a: [f64; 2],
    /// Four-bar: D; slider: the guide's point A + e·n.
    d: [f64; 2],
    /// The guide's direction t (slider) or A→D's (four-bar).
    t: [f64; 2],
    r1: f64,
    r2: f64,
    r3: f64,
    r4: f64,
    u: f64,
    v: f64,
    mode: f64,
}

impl Cand {
    /// None when a value is not finite or a length is not above zero.
    fn new(kind: Kind, row: &[f64]) -> Option<Cand> {
        if row.iter().any(|x| !x.is_finite()) {
            return None;
        }
        let [x0, y0, th, r1, r2, r3, r4, u, v, mode] = row[..10].try_into().ok()?;
        let (s, c) = sin_cos(th);
        let lengths_ok = match kind {
            Kind::FourBar => r1 > 0.0 && r2 > 0.0 && r3 > 0.0 && r4 > 0.0,
            Kind::SliderCrank => r2 > 0.0 && r3 > 0.0,
        };
        if !lengths_ok {
            return None;
        }
        let d = match kind {
            Kind::FourBar => [x0 + r1 * c, y0 + r1 * s],
            Kind::SliderCrank => [x0 - r1 * s, y0 + r1 * c],
        };
        Some(Cand {
            kind,
            a: [x0, y0],
            d,
            t: [c, s],
            r1,
            r2,
            r3,
            r4,
            u,
            v,
            mode: if mode >= 0.0 { 1.0 } else { -1.0 },
        })
    }

    /// The coupler point at absolute crank angle φ, None where the dyad does
    /// not close.
    #[inline]
    fn point(&self, phi: f64) -> Option<[f64; 2]> {
        let (s, c) = sin_cos(phi);
        let b = [self.a[0] + self.r2 * c, self.a[1] + self.r2 * s];
        // f: the unit vector B→C.
        let f = match self.kind {
            Kind::FourBar => {
                let bd = [self.d[0] - b[0], self.d[1] - b[1]];
                let dd = bd[0] * bd[0] + bd[1] * bd[1];
                if dd <= 0.0 {
                    return None;
                }
                let dist = dd.sqrt();
                let e = [bd[0] / dist, bd[1] / dist];
                let along = (self.r3 * self.r3 - self.r4 * self.r4 + dd) / (2.0 * dist);
                let h2 = self.r3 * self.r3 - along * along;
                if h2 < 0.0 {
                    return None;
                }
                // mode +1: C on the left of the ray D → B (fourbar.rs's σ).
                let h = -self.mode * h2.sqrt();
                [
                    (along * e[0] - h * e[1]) / self.r3,
                    (along * e[1] + h * e[0]) / self.r3,
                ]
            }
            Kind::SliderCrank => {
                let t = self.t;
                let n = [-t[1], t[0]];
                let w = [b[0] - self.d[0], b[1] - self.d[1]];
                let q = w[0] * n[0] + w[1] * n[1];
                let h2 = self.r3 * self.r3 - q * q;
                if h2 < 0.0 {
                    return None;
                }
                // C − B = (mode·√h2)·t − q·n.
                let h = self.mode * h2.sqrt();
                [
                    (h * t[0] - q * n[0]) / self.r3,
                    (h * t[1] - q * n[1]) / self.r3,
                ]
            }
        };
        Some([
            b[0] + self.u * f[0] - self.v * f[1],
            b[1] + self.u * f[1] + self.v * f[0],
        ])
    }

    /// The transmission angle's range [μlo, μhi] over absolute crank angles
    /// [lo, hi] by the shared closed forms of [`super::fourbar`] (whose crank
    /// angle is measured from the ground line), whether the dyad closes
    /// strictly over it (a fold, μ = 0 or π, is not closing: the branch could
    /// change there), and by how much it misses (|cos μ| − 1 at the worst
    /// angle, 0 when it closes). NaN angles where it does not close.
    fn range(&self, lo: f64, hi: f64) -> (f64, f64, f64, bool) {
        let th = self.t[1].atan2(self.t[0]);
        let t = match self.kind {
            Kind::FourBar => {
                fourbar_transmission(self.r2, self.r3, self.r4, self.r1, lo - th, hi - th)
            }
            Kind::SliderCrank => {
                slider_crank_transmission(self.r2, self.r3, self.r1, lo - th, hi - th)
            }
        };
        match t {
            Ok(Transmission::Range { mu_min, mu_max, .. }) => {
                let closes = mu_min > 0.0 && mu_max < PI;
                (mu_min, mu_max, 0.0, closes)
            }
            Ok(Transmission::Breaks { cos_mu, .. }) => {
                (f64::NAN, f64::NAN, cos_mu.abs() - 1.0, false)
            }
            // Lengths and range are checked before: unreachable, but a
            // candidate, not a panic.
            Err(_) => (f64::NAN, f64::NAN, 1.0, false),
        }
    }
}

/// Squared distance from p to the target t (None: not assembled → +∞).
#[inline]
fn dist2(p: Option<[f64; 2]>, t: &[f64]) -> f64 {
    match p {
        Some(p) => (p[0] - t[0]).powi(2) + (p[1] - t[1]).powi(2),
        None => f64::INFINITY,
    }
}

/// Evaluate one candidate: its [`COLUMNS`] into `out`, each target's crank
/// angle into `angles` (when given), with `curve` a scratch of M samples.
fn one(
    spec: &Spec<'_>,
    row: &[f64],
    out: &mut [f64],
    mut angles: Option<&mut [f64]>,
    curve: &mut Vec<Option<[f64; 2]>>,
) {
    let n = spec.targets.len() / 2;
    let tau = std::f64::consts::TAU;
    let Some(c) = Cand::new(spec.kind, row) else {
        out.copy_from_slice(&[
            f64::INFINITY,
            f64::NAN,
            f64::NAN,
            f64::NAN,
            f64::NAN,
            f64::NAN,
        ]);
        if let Some(a) = angles.as_deref_mut() {
            a.fill(f64::NAN);
        }
        return;
    };
    // The error.
    let (mut sum, mut worst) = (0.0, 0.0_f64);
    let (lo, hi);
    match spec.timing {
        Some(timing) => {
            let phi1 = row[PARAMS.len()];
            for i in 0..n {
                let phi = phi1 + timing[i];
                let e2 = dist2(c.point(phi), &spec.targets[2 * i..2 * i + 2]);
                sum += e2;
                worst = worst.max(e2);
                if let Some(a) = angles.as_deref_mut() {
                    a[i] = phi;
                }
            }
            let (tmin, tmax) = timing
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &t| {
                    (a.min(t), b.max(t))
                });
            if spec.full_turn {
                (lo, hi) = (0.0, tau);
            } else {
                (lo, hi) = (phi1 + tmin, phi1 + tmax);
            }
        }
        None => {
            let m = spec.samples;
            let step = tau / m as f64;
            curve.clear();
            curve.extend((0..m).map(|k| c.point(k as f64 * step)));
            for i in 0..n {
                let t = &spec.targets[2 * i..2 * i + 2];
                let (mut best, mut kbest) = (f64::INFINITY, 0);
                for (k, p) in curve.iter().enumerate() {
                    let e2 = dist2(*p, t);
                    if e2 < best {
                        (best, kbest) = (e2, k);
                    }
                }
                let mut phi = kbest as f64 * step;
                if best.is_finite() && spec.refine > 0 {
                    (phi, best) = golden(&c, t, phi - step, phi + step, spec.refine, phi, best);
                }
                sum += best;
                worst = worst.max(best);
                if let Some(a) = angles.as_deref_mut() {
                    a[i] = if best.is_finite() { phi } else { f64::NAN };
                }
            }
            (lo, hi) = (0.0, tau);
        }
    }
    let rms = (sum / n as f64).sqrt();
    let max = worst.sqrt();
    // The constraints.
    let (mu_lo, mu_hi, miss, closes) = c.range(lo, hi);
    let mut v = miss;
    let mut feasible = closes;
    let margin = mu_lo.min(std::f64::consts::PI - mu_hi);
    if margin < spec.min_transmission {
        v += spec.min_transmission - margin;
        feasible = false;
    }
    if spec.max_ratio.is_finite() {
        let ls: &[f64] = match c.kind {
            Kind::FourBar => &[c.r1, c.r2, c.r3, c.r4],
            Kind::SliderCrank => &[c.r2, c.r3],
        };
        let (smin, smax) = ls
            .iter()
            .fold((f64::INFINITY, 0.0_f64), |(a, b), &l| (a.min(l), b.max(l)));
        let ratio = smax / smin;
        if ratio > spec.max_ratio {
            v += (ratio - spec.max_ratio) / spec.max_ratio;
            feasible = false;
        }
    }
    if let Some(b) = spec.pivot_box {
        let size = (b[1] - b[0]).max(b[3] - b[2]).max(f64::MIN_POSITIVE);
        let outside = |p: [f64; 2]| {
            (b[0] - p[0]).max(0.0)
                + (p[0] - b[1]).max(0.0)
                + (b[2] - p[1]).max(0.0)
                + (p[1] - b[3]).max(0.0)
        };
        let mut o = outside(c.a);
        if c.kind == Kind::FourBar {
            o += outside(c.d);
        }
        if o > 0.0 {
            v += o / size;
            feasible = false;
        }
    }
    if !rms.is_finite() {
        // A target at an angle where the candidate does not close (possible
        // only where the range check failed already) or an overflow.
        feasible = false;
    }
    let cost = if feasible { rms } else { PENALTY * (1.0 + v) };
    out.copy_from_slice(&[cost, rms, max, if feasible { 0.0 } else { v }, mu_lo, mu_hi]);
}

/// Golden-section search of the squared distance from the curve to `t` over
/// crank angles [a, b], from the sample (φ0, e0): the best point seen.
fn golden(
    c: &Cand,
    t: &[f64],
    mut a: f64,
    mut b: f64,
    steps: usize,
    phi0: f64,
    e0: f64,
) -> (f64, f64) {
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut best_phi, mut best) = (phi0, e0);
    let mut x1 = b - g * (b - a);
    let mut x2 = a + g * (b - a);
    let mut f1 = dist2(c.point(x1), t);
    let mut f2 = dist2(c.point(x2), t);
    for _ in 0..steps {
        if f1 < f2 {
            b = x2;
            x2 = x1;
            f2 = f1;
            x1 = b - g * (b - a);
            f1 = dist2(c.point(x1), t);
        } else {
            a = x1;
            x1 = x2;
            f1 = f2;
            x2 = a + g * (b - a);
            f2 = dist2(c.point(x2), t);
        }
    }
    for (x, f) in [(x1, f1), (x2, f2)] {
        if f < best {
            (best_phi, best) = (x, f);
        }
    }
    (best_phi, best)
}

/// Evaluate the candidates `params` (rows of [`Spec::width`]) against `spec`:
/// [`COLUMNS`] per candidate into `out` (K × 6), and each target's crank angle
/// [rad] into `angles` (K × N) when given. In parallel over candidates on
/// `n_threads` threads; a call cut short by Ctrl-C leaves `out` partly written
/// (`crate::cancel`).
pub fn evaluate_into(
    spec: &Spec<'_>,
    params: &[f64],
    n_threads: Option<i64>,
    out: &mut [f64],
    angles: Option<&mut [f64]>,
) -> Result<(), InvalidInput> {
    spec.validate()?;
    let w = spec.width();
    let n = spec.targets.len() / 2;
    if !params.len().is_multiple_of(w) {
        return Err(InvalidInput::bad_value(
            "params",
            params.len() as f64,
            format!("values must be rows of {w} (the candidate's columns)"),
        ));
    }
    let k = params.len() / w;
    let nc = COLUMNS.len();
    if out.len() != k * nc {
        return Err(InvalidInput::Output {
            field: "out",
            want: format!("{k} × {nc} values"),
            got: format!("{}", out.len()),
        });
    }
    if let Some(a) = angles.as_deref() {
        if a.len() != k * n {
            return Err(InvalidInput::Output {
                field: "angles",
                want: format!("{k} × {n} values"),
                got: format!("{}", a.len()),
            });
        }
    }
    if k == 0 {
        return Ok(());
    }
    let threads = crate::parallel::resolve_threads(n_threads)?;
    let m = if spec.timing.is_some() {
        0
    } else {
        spec.samples
    };
    let chunk = |(p, o, a): (&[f64], &mut [f64], Option<&mut [f64]>)| {
        if crate::cancel::requested() {
            return;
        }
        let mut curve = Vec::with_capacity(m);
        let rows = p.len() / w;
        let mut a = a;
        for r in 0..rows {
            let ang = a.as_deref_mut().map(|a| &mut a[r * n..(r + 1) * n]);
            one(
                spec,
                &p[r * w..(r + 1) * w],
                &mut o[r * nc..(r + 1) * nc],
                ang,
                &mut curve,
            );
        }
    };
    let prows = params.chunks(CHUNK * w);
    let orows = out.chunks_mut(CHUNK * nc);
    match angles {
        Some(a) => {
            let arows = a.chunks_mut(CHUNK * n.max(1));
            let work: Vec<_> = prows
                .zip(orows)
                .zip(arows)
                .map(|((p, o), a)| (p, o, Some(a)))
                .collect();
            run(threads, work, chunk)?;
        }
        None => {
            let work: Vec<_> = prows.zip(orows).map(|(p, o)| (p, o, None)).collect();
            run(threads, work, chunk)?;
        }
    }
    Ok(())
}

/// The coupler point [m] of one candidate `row` (its first 10 columns) at each
/// absolute crank angle of `angles` [rad], flat (x, y) pairs; NaN where the
/// candidate does not close. The points the errors of [`evaluate_into`] are
/// measured from, for a caller to report or to check against another solver.
pub fn points(kind: Kind, row: &[f64], angles: &[f64]) -> Result<Vec<f64>, InvalidInput> {
    if row.len() < PARAMS.len() {
        return Err(InvalidInput::bad_value(
            "row",
            row.len() as f64,
            "values are too few: a candidate has 10 columns",
        ));
    }
    InvalidInput::check_finite("row", row)?;
    InvalidInput::check_finite("angles", angles)?;
    let c = Cand::new(kind, row)
        .ok_or_else(|| InvalidInput::bad_value("row", f64::NAN, "must have lengths above zero"))?;
    Ok(angles
        .iter()
        .flat_map(|&phi| c.point(phi).unwrap_or([f64::NAN, f64::NAN]))
        .collect())
}

/// Run the chunks on `threads` threads (serially for one).
fn run<T: Send, F: Fn(T) + Sync + Send>(
    threads: usize,
    work: Vec<T>,
    f: F,
) -> Result<(), InvalidInput> {
    if threads == 1 {
        work.into_iter().for_each(f);
    } else {
        crate::parallel::pool(threads)?.install(|| work.into_par_iter().for_each(f));
    }
    Ok(())
}

#[cfg(test)]
mod tests;
