//! Follower dynamics: the dynamic error of a motion law (issue 18, item 6).
//!
//! **Model.** The follower is a mass–spring–damper driven through its cam: the
//! cam imposes s(t) on one end of the follower's elastic link and the working
//! member y obeys ÿ + 2ζω_n(ẏ − ṡ) + ω_n²(y − s) = 0, so the dynamic error
//! x = y − s obeys
//!
//! ```text
//! ẍ + 2ζω_n ẋ + ω_n² x = −s̈(t)
//! ```
//!
//! (x in the stroke's unit, m or rad). ω_n [rad/s] is the natural frequency,
//! ζ ∈ [0, 1) the damping ratio (under-damped only: the residual amplitude below
//! is the envelope of a damped oscillation).
//!
//! **Residual vibration of one segment.** A rise or return of stroke h over a cam
//! angle β [rad] at cam speed ω [rad/s] lasts T = β/ω and s̈ = h z''(t/T)/T², z
//! the law's normalised rise. In dimensionless time u = t/T:
//!
//! ```text
//! x'' + 2ζτ x' + τ² x = −h z''(u),   τ = ω_n T
//! ```
//!
//! τ is the segment's duration in radians of the natural vibration. Started
//! from rest (x = x' = 0 at u = 0: the classic "dynamic error of the motion
//! law"), the free vibration after the segment has the amplitude A = h·R(τ, ζ):
//! R depends on the law, τ and ζ only. From the state (q, q') at u = 1,
//!
//! ```text
//! R = √(q² + ((q' + ζτq)/(τ√(1 − ζ²)))²)      (per unit stroke)
//! ```
//!
//! the amplitude of q(u) = R e^{−ζτ(u−1)} cos(ω_d (u − 1) − φ). As τ → 0 (a
//! follower far too soft) y stays put, x(1) → −1 and R → 1/√(1 − ζ²).
//!
//! For the built-in laws R is a closed form ([`ClosedResidual`], module
//! `residual`; issue 37). A law given as its pieces ([`LawForce::of`], a motion
//! program's segment) keeps the sampled path:
//! R comes from the exact piecewise-linear Duhamel kernel of the stops
//! ([`crate::impact::response_into`], mass 1, ω_n = τ) with the force −z''(u)
//! sampled on [0, 1] at [`GRID_PER_UNIT`] intervals per unit (the law's internal
//! breakpoints are nodes), so that the only error is the linear interpolation of
//! z'', O(h²) with an expansion in even powers of h. The end state is computed
//! on that grid and on its bisection and combined by Richardson extrapolation
//! ((4·fine − coarse)/3), which leaves O(h⁴τ²): measured against the cycloidal
//! closed form, 1.5e-9 of the envelope at τ = 200, 2e-8 at τ = 1e3 and ~4e-6 at
//! τ ≥ 1e4 (where R < 1e-10: physically nil; a limit that small is refused, see
//! [`SCAN_MAX`]).
//!
//! **Minimum τ (the bound rule).** For an amplitude limit R_max, τ* is the
//! smallest τ such that R(τ') ≤ R_max for EVERY τ' ≥ τ*. R is not monotone: it
//! has lobes of period ≈ 2π in τ and zeros (for the cycloidal rise
//! R = 8π²|sin(τ/2)|/(τ|4π² − τ²|), zero at τ = 2πk, k ≥ 2), so a feasible
//! window below a violating lobe is ignored: conservative, since a speed change
//! moves τ out of such a window. τ* is found by a scan of step [`SCAN_STEP`]
//! (≤ 2π/32) upward until R has stayed below R_max/4 for [`SETTLE_WINDOW`]
//! (R's envelope decays like 1/τ² or faster beyond it), each sampled local
//! maximum above 0.9 R_max refined by a golden-section search (a lobe whose
//! sampled top is just under the limit is not missed), then the last crossing
//! by a bracketed root (Illinois) to ~1e-13 relative. If R ≤ R_max everywhere,
//! τ* = 0. A machine turns τ* into a bound on the segment's cam angle:
//! β_min = τ*·ω/ω_n.
//!
//! **Steady state of a whole cam.** At a constant cam speed ω the error is
//! periodic with the turn. Written in cam angle θ = ωt the equation is
//! x'' + 2ζr x' + r² x = −s''(θ) with r = ω_n/ω; s'' is sampled on every segment
//! (segment boundaries are nodes, with a jump in s'' where the law has one: a
//! repeated angle), propagated exactly over one turn from rest (the end state d)
//! and the periodic start solves (I − Φ) x0 = d, Φ the unforced one-turn
//! transition in closed form. For ζ = 0 at resonance (r a whole number: the turn
//! lasts a whole number of natural periods) I − Φ is singular; a determinant
//! below [`RESONANCE_DET`] is refused as a resonance (the answer would lose more
//! than ~1e-6 of its digits). The residual amplitude after each segment is the
//! free-vibration amplitude of the state at its end (the residual vibration if a
//! dwell follows).

use std::f64::consts::TAU;

use rayon::prelude::*;

use super::program::{CamError, Kind, Program, SegmentSpec};
use super::residual::ClosedResidual;
use crate::impact::{response_into, ImpactError, Oscillator, MODE_RANGE};
use crate::input::InvalidInput;
use crate::motion::{Law, MotionError};
use crate::parallel::{pool, resolve_threads, ThreadsError};

/// Intervals per unit of the law's abscissa on the coarse grid (the fine grid
/// bisects each).
pub const GRID_PER_UNIT: usize = 1024;

/// Step of the scan for the minimum τ [rad of natural vibration] (2π/64).
pub const SCAN_STEP: f64 = TAU / 64.0;

/// The scan stops once R has stayed below a quarter of the limit for this long
/// in τ [rad] (8 lobes).
pub const SETTLE_WINDOW: f64 = 8.0 * TAU;

/// Largest τ the scan reaches [rad]; a limit still violated there is refused.
pub const SCAN_MAX: f64 = 1e4;

/// Smallest det(I − Φ) of the one-turn map accepted (below: resonance).
pub const RESONANCE_DET: f64 = 1e-9;

/// Errors of the follower dynamics: the wrapped domain errors keep their own
/// messages (and Python classes).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum VibrationError {
    #[error("{0}")]
    Law(#[from] MotionError),
    #[error("{0}")]
    Input(#[from] ImpactError),
    #[error("{0}")]
    Cam(#[from] CamError),
}

impl From<ThreadsError> for VibrationError {
    fn from(e: ThreadsError) -> Self {
        VibrationError::Cam(e.into())
    }
}

fn param(field: &'static str, value: f64, ok: bool, want: &'static str) -> Result<(), ImpactError> {
    if ok && value.is_finite() {
        Ok(())
    } else {
        Err(ImpactError::Param { field, value, want })
    }
}

/// τ finite and within the oscillator's range (see [`MODE_RANGE`]).
fn check_tau(tau: f64) -> Result<(), ImpactError> {
    let (lo, hi) = MODE_RANGE;
    param(
        "tau",
        tau,
        (lo..=hi).contains(&tau),
        "finite and within [1e-150, 1e150] [rad] (> 0)",
    )
}

fn check_zeta(zeta: f64) -> Result<(), ImpactError> {
    param(
        "zeta",
        zeta,
        (0.0..1.0).contains(&zeta),
        "finite and in [0, 1) (an under-damped follower)",
    )
}

/// √(q² + ((v + ζwq)/(w√(1 − ζ²)))²): the amplitude of the free vibration of
/// natural frequency w from the state (q, v).
#[inline]
pub fn free_amplitude(q: f64, v: f64, w: f64, zeta: f64) -> f64 {
    let wd = w * ((1.0 - zeta) * (1.0 + zeta)).sqrt();
    q.hypot((v + zeta * w * q) / wd)
}

/// Nodes of [0, 1] for a law: each of its pieces split into ⌈per_unit·length⌉
/// equal intervals (its breakpoints are nodes). Written x0 + k·h: the named
/// laws' pieces have dyadic ends and lengths, so h is a power of two and every
/// node and step is exact, and the kernel works out a single step's
/// coefficients (its cost per τ; ulp-different steps would each need theirs).
fn law_nodes(law: &Law, per_unit: usize) -> Vec<f64> {
    let mut xs = vec![0.0];
    for s in &law.segments {
        let m = ((per_unit as f64) * (s.x1 - s.x0)).ceil().max(1.0) as usize;
        let h = (s.x1 - s.x0) / m as f64;
        for k in 1..m {
            xs.push(s.x0 + k as f64 * h);
        }
        xs.push(s.x1);
    }
    xs
}

/// Every interval of `xs` bisected.
fn bisect(xs: &[f64]) -> Vec<f64> {
    let mut out = Vec::with_capacity(2 * xs.len());
    for w in xs.windows(2) {
        out.push(w[0]);
        if w[1] > w[0] {
            out.push(0.5 * (w[0] + w[1]));
        }
    }
    out.extend(xs.last());
    out
}

/// The unit-stroke force −z''(u) of a law on its coarse and fine grids.
#[derive(Debug, Clone)]
pub struct LawForce {
    grids: [(Vec<f64>, Vec<f64>); 2],
}

impl LawForce {
    /// The law's force on its grids; an unknown name is an error.
    pub fn new(law: &str) -> Result<LawForce, VibrationError> {
        Ok(LawForce::of(&Law::rise(law)?))
    }

    /// The force of any law on the unit square (a rest-to-rest one: the
    /// residual vibration is after a segment started from rest).
    pub fn of(law: &Law) -> LawForce {
        let coarse = law_nodes(law, GRID_PER_UNIT);
        let fine = bisect(&coarse);
        let force = |xs: &[f64]| xs.iter().map(|&x| -law.z(x, 2)).collect::<Vec<f64>>();
        let (fc, ff) = (force(&coarse), force(&fine));
        LawForce {
            grids: [(coarse, fc), (fine, ff)],
        }
    }

    /// The end state (q, q') at u = 1 from rest, Richardson-extrapolated.
    fn end_state(
        &self,
        tau: f64,
        zeta: f64,
        buf: &mut Vec<f64>,
    ) -> Result<(f64, f64), ImpactError> {
        let osc = Oscillator::new(tau, zeta, 1.0)?;
        let mut ends = [(0.0, 0.0); 2];
        for (end, (t, f)) in ends.iter_mut().zip(&self.grids) {
            let n = t.len();
            buf.resize(2 * n, 0.0);
            let (q, v) = buf.split_at_mut(n);
            response_into(t, f, &osc, 0.0, 0.0, q, Some(v))?;
            *end = (q[n - 1], v[n - 1]);
        }
        let [(qc, vc), (qf, vf)] = ends;
        Ok(((4.0 * qf - qc) / 3.0, (4.0 * vf - vc) / 3.0))
    }

    /// R(τ, ζ) for a checked τ > 0 and ζ ∈ [0, 1).
    fn ratio(&self, tau: f64, zeta: f64, buf: &mut Vec<f64>) -> Result<f64, ImpactError> {
        let (q, v) = self.end_state(tau, zeta, buf)?;
        Ok(free_amplitude(q, v, tau, zeta))
    }

    /// R(τ, ζ) with τ checked (finite, > 0) and ζ ∈ [0, 1).
    pub fn residual_ratio(&self, tau: f64, zeta: f64) -> Result<f64, VibrationError> {
        check_zeta(zeta)?;
        check_tau(tau)?;
        Ok(self.ratio(tau, zeta, &mut Vec::new())?)
    }
}

/// Residual amplitude per unit stroke R(τ, ζ) after one segment of the named
/// law started from rest (see the module docs).
pub fn residual_ratio(law: &str, tau: f64, zeta: f64) -> Result<f64, VibrationError> {
    check_zeta(zeta)?;
    let closed = ClosedResidual::new(law)?;
    check_tau(tau)?;
    Ok(closed.ratio(tau, zeta))
}

/// τ values per rayon task of the sampled path.
const CHUNK: usize = 16;

/// τ values per rayon task of the closed forms (4 to 13 ns each in lanes, ~100
/// on the scalar path).
const CLOSED_CHUNK: usize = 4096;

/// R(τ_i, ζ) for every τ_i into `out`, in parallel (closed forms: see
/// [`ClosedResidual`]); an error names the first bad entry.
pub fn residual_ratio_batch(
    law: &str,
    tau: &[f64],
    zeta: f64,
    n_threads: Option<i64>,
    out: &mut [f64],
) -> Result<(), VibrationError> {
    check_zeta(zeta)?;
    let closed = ClosedResidual::new(law)?;
    if out.len() != tau.len() {
        return Err(ImpactError::Length {
            field: "out",
            got: out.len(),
            want: format!("{} entries (one per tau)", tau.len()),
        }
        .into());
    }
    if let Some((row, e)) = tau
        .iter()
        .enumerate()
        .find_map(|(i, &t)| check_tau(t).err().map(|e| (i, e)))
    {
        return Err(ImpactError::Case {
            row,
            error: Box::new(e),
        }
        .into());
    }
    let fill = |o: &mut [f64], t: &[f64]| closed.fill(t, zeta, o);
    let threads = resolve_threads(n_threads)?;
    if tau.len() <= CLOSED_CHUNK {
        // One chunk: skipped, as every chunk of a long batch is, when the flag is up.
        if !crate::cancel::requested() {
            fill(out, tau);
        }
        return Ok(());
    }
    if threads == 1 {
        // In the calling thread (a one-thread pool's hand-off costs a wake-up,
        // a scheduler slice on a loaded machine), chunk by chunk as the pool's.
        for (o, t) in out.chunks_mut(CLOSED_CHUNK).zip(tau.chunks(CLOSED_CHUNK)) {
            if !crate::cancel::requested() {
                fill(o, t)
            }
        }
        return Ok(());
    }
    let pool = pool(threads)?;
    pool.install(|| {
        out.par_chunks_mut(CLOSED_CHUNK)
            .zip(tau.par_chunks(CLOSED_CHUNK))
            .for_each(|(o, t)| {
                if !crate::cancel::requested() {
                    fill(o, t)
                }
            })
    });
    Ok(())
}

/// Root of f on [lo, hi] (f(lo) > 0 ≥ f(hi) or the reverse) by the Illinois
/// variant of regula falsi, until the bracket is narrower than `xtol`: the
/// evaluated point nearest a sign change with the smallest |f|.
fn root(
    mut f: impl FnMut(f64) -> Result<f64, ImpactError>,
    mut lo: f64,
    mut hi: f64,
    flo: f64,
    fhi: f64,
    xtol: f64,
) -> Result<f64, ImpactError> {
    if fhi == 0.0 {
        return Ok(hi);
    }
    // (ga, gb): the Illinois-weighted values at lo, hi; (best, fbest): the true
    // value of smallest magnitude seen.
    let (mut ga, mut gb) = (flo, fhi);
    let (mut best, mut fbest) = if flo.abs() < fhi.abs() {
        (lo, flo)
    } else {
        (hi, fhi)
    };
    let mut side = 0i8;
    for _ in 0..300 {
        if (hi - lo).abs() <= xtol {
            break;
        }
        let mut x = (lo * gb - hi * ga) / (gb - ga);
        if !(x > lo.min(hi) && x < lo.max(hi)) {
            x = 0.5 * (lo + hi);
        }
        let fx = f(x)?;
        if fx.abs() < fbest.abs() {
            (best, fbest) = (x, fx);
        }
        if fx == 0.0 {
            return Ok(x);
        }
        if (fx > 0.0) == (gb > 0.0) {
            (hi, gb) = (x, fx);
            if side == 1 {
                ga *= 0.5;
            }
            side = 1;
        } else {
            (lo, ga) = (x, fx);
            if side == -1 {
                gb *= 0.5;
            }
            side = -1;
        }
    }
    Ok(best)
}

/// (x, f(x)) at the maximum of f on [a, b] (unimodal there) by golden section.
fn maximise(
    mut f: impl FnMut(f64) -> Result<f64, ImpactError>,
    mut a: f64,
    mut b: f64,
) -> Result<(f64, f64), ImpactError> {
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
    let (mut fc, mut fd) = (f(c)?, f(d)?);
    while (b - a) > 1e-11 * b.abs().max(1.0) {
        if fc >= fd {
            (b, d, fd) = (d, c, fc);
            c = b - g * (b - a);
            fc = f(c)?;
        } else {
            (a, c, fc) = (c, d, fd);
            d = a + g * (b - a);
            fd = f(d)?;
        }
    }
    Ok(if fc >= fd { (c, fc) } else { (d, fd) })
}

/// The smallest τ* ≥ 0 such that R(τ) ≤ `ratio_limit` for every τ ≥ τ* (the
/// bound rule; see the module docs), for the named law and damping ratio ζ.
pub fn min_tau(law: &str, ratio_limit: f64, zeta: f64) -> Result<f64, VibrationError> {
    let closed = ClosedResidual::new(law)?;
    min_tau_by(
        |t, _: &mut Vec<f64>| Ok(closed.ratio(t, zeta)),
        ratio_limit,
        zeta,
    )
}

/// [`min_tau`] for a law's force ([`LawForce::of`] any rest-to-rest law).
pub fn min_tau_of(force: &LawForce, ratio_limit: f64, zeta: f64) -> Result<f64, VibrationError> {
    check_zeta(zeta)?;
    min_tau_by(|t, buf| force.ratio(t, zeta, buf), ratio_limit, zeta)
}

/// [`min_tau`] with R(τ) given by `r` (a scratch buffer its second argument).
fn min_tau_by(
    r: impl Fn(f64, &mut Vec<f64>) -> Result<f64, ImpactError> + Sync,
    ratio_limit: f64,
    zeta: f64,
) -> Result<f64, VibrationError> {
    check_zeta(zeta)?;
    param(
        "ratio_limit",
        ratio_limit,
        ratio_limit > 0.0,
        "finite and > 0 (amplitude per unit stroke)",
    )?;
    // R(0+) = 1/√(1 − ζ²) (module docs).
    let r0 = 1.0 / ((1.0 - zeta) * (1.0 + zeta)).sqrt();
    let pool = pool(resolve_threads(None)?)?;
    let mut taus = vec![0.0];
    let mut rs = vec![r0];
    // The last violation: where R > limit, and the sample index after it.
    let mut violation: Option<(f64, usize)> = (r0 > ratio_limit).then_some((0.0, 0));
    let mut loud = if r0 > 0.25 * ratio_limit { 0.0 } else { -1.0 };
    let block = 4 * CHUNK * pool.current_num_threads();
    let mut checked = 1; // samples whose local-maximum test is done: 1..checked
    loop {
        if crate::cancel::requested() {
            return Ok(f64::NAN); // dropped by the caller (crate::cancel)
        }
        let j0 = taus.len();
        let new: Vec<f64> = (j0..j0 + block).map(|j| j as f64 * SCAN_STEP).collect();
        let vals: Result<Vec<f64>, ImpactError> = pool.install(|| {
            new.par_chunks(CHUNK)
                .map(|ts| {
                    let mut buf = Vec::new();
                    ts.iter()
                        .map(|&t| r(t, &mut buf))
                        .collect::<Result<Vec<_>, _>>()
                })
                .collect::<Result<Vec<_>, _>>()
                .map(|v| v.concat())
        });
        taus.extend(&new);
        rs.extend(vals?);
        // Samples 1..len−1 have both neighbours now.
        let mut buf = Vec::new();
        for j in checked..taus.len() - 1 {
            if rs[j] > 0.25 * ratio_limit {
                loud = taus[j];
            }
            if rs[j] > ratio_limit {
                violation = Some((taus[j], j + 1));
            } else if rs[j] > 0.9 * ratio_limit && rs[j] >= rs[j - 1] && rs[j] >= rs[j + 1] {
                let (tm, rm) = maximise(|t| r(t, &mut buf), taus[j - 1], taus[j + 1])?;
                if rm > ratio_limit {
                    violation = Some((tm, j + 1));
                }
            }
        }
        checked = taus.len() - 1;
        let last = taus[checked - 1];
        if last > loud + SETTLE_WINDOW {
            break;
        }
        if last > SCAN_MAX {
            return Err(CamError::from(InvalidInput::BadValue {
                field: "ratio_limit",
                value: ratio_limit,
                why: format!(
                    "is still exceeded at tau = {SCAN_MAX:e} (R = {:e}): too small a residual \
                     amplitude to reach",
                    rs[checked - 1]
                )
                .into(),
            })
            .into());
        }
    }
    let Some((tv, after)) = violation else {
        return Ok(0.0);
    };
    // R > limit at tv, ≤ limit at taus[after] (else that would be a later
    // violation) and, lobes being much wider than a step, one crossing between.
    let mut buf = Vec::new();
    let fv = if tv == 0.0 {
        r0 - ratio_limit
    } else {
        r(tv, &mut buf)? - ratio_limit
    };
    let hi = taus[after];
    Ok(root(
        |t| Ok(r(t, &mut buf)? - ratio_limit),
        tv,
        hi,
        fv,
        rs[after] - ratio_limit,
        1e-14 * hi,
    )?)
}

/// The periodic steady state of a whole cam at one speed.
#[derive(Debug, Clone, PartialEq)]
pub struct SteadyState {
    /// Dynamic error x [stroke unit] at each requested cam angle.
    pub x: Vec<f64>,
    /// Its rate ẋ [stroke unit / s].
    pub rate: Vec<f64>,
    /// Free-vibration amplitude [stroke unit] of the state at each segment's end.
    pub residual: Vec<f64>,
}

/// One segment as the grids need it.
struct Piece {
    start: f64,
    end: f64,
    angle: f64,
    h: f64,
    law: Option<Law>,
}

/// A grid over one turn: angles, forces −s''(θ), the node of each query and
/// the last node of each segment.
struct TurnGrid {
    t: Vec<f64>,
    f: Vec<f64>,
    query: Vec<usize>,
    ends: Vec<usize>,
}

/// The turn's grid: each law segment on its law's nodes (bisected if `fine`)
/// plus the queries `sorted` (angle, index) that fall in it.
fn turn_grid(pieces: &[Piece], sorted: &[(f64, usize)], fine: bool) -> TurnGrid {
    let nq = sorted.len();
    let mut g = TurnGrid {
        t: Vec::new(),
        f: Vec::new(),
        query: vec![0; nq],
        ends: Vec::with_capacity(pieces.len()),
    };
    let mut qi = 0;
    let last = pieces.len() - 1;
    for (i, p) in pieces.iter().enumerate() {
        let mut th: Vec<f64> = match &p.law {
            Some(law) => law_nodes(law, GRID_PER_UNIT)
                .iter()
                .map(|&x| {
                    if x >= 1.0 {
                        p.end
                    } else {
                        p.start + p.angle * x
                    }
                })
                .filter(|&t| t <= p.end)
                .collect(),
            None => vec![p.start, p.end],
        };
        if *th.last().unwrap_or(&p.start) < p.end {
            th.push(p.end);
        }
        let first_q = qi;
        while qi < nq && (sorted[qi].0 < p.end || (i == last && sorted[qi].0 <= p.end)) {
            th.push(sorted[qi].0);
            qi += 1;
        }
        th.sort_by(f64::total_cmp);
        th.dedup();
        if fine {
            th = bisect(&th);
        }
        let base = g.t.len();
        for &q in &sorted[first_q..qi] {
            let k = th.partition_point(|&t| t < q.0);
            g.query[q.1] = base + k;
        }
        for &t in &th {
            let f = match &p.law {
                Some(law) => {
                    let x = ((t - p.start) / p.angle).clamp(0.0, 1.0);
                    -p.h * law.z(x, 2) / (p.angle * p.angle)
                }
                None => 0.0,
            };
            g.t.push(t);
            g.f.push(f);
        }
        g.ends.push(g.t.len() - 1);
    }
    g
}

/// The periodic steady-state dynamic error of the cam `specs` at cam speed
/// `omega` [rad/s] with natural frequency `omega_n` [rad/s] and damping ratio
/// `zeta` at cam angles `theta` [rad]: values in [0, 2π] are used as they are
/// (2π is the end of the turn), others taken modulo 2π.
pub fn steady_response(
    specs: &[SegmentSpec],
    omega: f64,
    omega_n: f64,
    zeta: f64,
    theta: &[f64],
) -> Result<SteadyState, VibrationError> {
    Program::new(specs)?;
    param(
        "omega",
        omega,
        omega > 0.0,
        "finite and > 0 [rad/s] (cam speed)",
    )?;
    param("omega_n", omega_n, omega_n > 0.0, "finite and > 0 [rad/s]")?;
    check_zeta(zeta)?;
    InvalidInput::check_finite("theta", theta).map_err(CamError::from)?;
    let ratio = omega_n / omega;
    let osc = Oscillator::new(ratio, zeta, 1.0)?;
    let mut pieces = Vec::with_capacity(specs.len());
    let mut start = 0.0;
    for (i, sp) in specs.iter().enumerate() {
        let end = if i + 1 == specs.len() {
            TAU
        } else {
            start + sp.angle
        };
        let (h, law) = match sp.kind {
            Kind::Dwell => (0.0, None),
            k => {
                let sign = if k == Kind::Rise { 1.0 } else { -1.0 };
                (sign * sp.stroke, Some(sp.unit_law()?))
            }
        };
        pieces.push(Piece {
            start,
            end,
            angle: sp.angle,
            h,
            law,
        });
        start = end;
    }
    let mut sorted: Vec<(f64, usize)> = theta
        .iter()
        .map(|&t| {
            if (0.0..=TAU).contains(&t) {
                t
            } else {
                t.rem_euclid(TAU)
            }
        })
        .zip(0..)
        .collect();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    let grids = [
        turn_grid(&pieces, &sorted, false),
        turn_grid(&pieces, &sorted, true),
    ];
    let run = |g: &TurnGrid, q0: f64, v0: f64| -> Result<(Vec<f64>, Vec<f64>), ImpactError> {
        let n = g.t.len();
        let (mut q, mut v) = (vec![0.0; n], vec![0.0; n]);
        response_into(&g.t, &g.f, &osc, q0, v0, &mut q, Some(&mut v))?;
        Ok((q, v))
    };
    // The end of a turn from rest, Richardson-extrapolated.
    let mut d = [0.0; 2];
    let rest = [run(&grids[0], 0.0, 0.0)?, run(&grids[1], 0.0, 0.0)?];
    for (k, dk) in d.iter_mut().enumerate() {
        let c = if k == 0 { &rest[0].0 } else { &rest[0].1 };
        let f = if k == 0 { &rest[1].0 } else { &rest[1].1 };
        *dk = (4.0 * f[f.len() - 1] - c[c.len() - 1]) / 3.0;
    }
    // The unforced one-turn transition Φ, exact.
    let mut phi = [[0.0; 2]; 2];
    for (col, (q0, v0)) in [(1.0, 0.0), (0.0, 1.0)].into_iter().enumerate() {
        let (mut q, mut v) = ([0.0; 2], [0.0; 2]);
        response_into(&[0.0, TAU], &[0.0, 0.0], &osc, q0, v0, &mut q, Some(&mut v))?;
        phi[0][col] = q[1];
        phi[1][col] = v[1];
    }
    let (a, b, c, e) = (1.0 - phi[0][0], -phi[0][1], -phi[1][0], 1.0 - phi[1][1]);
    // b·c = Φ01·Φ10 = −r²Φ01² ≤ 0: scale-free in the dimensionless (q, q' / r).
    let det = a * e - b * c;
    if det.is_nan() || det <= RESONANCE_DET {
        let rpm = omega * 30.0 / std::f64::consts::PI;
        return Err(CamError::from(InvalidInput::BadValue {
            field: "speed",
            value: rpm,
            why: format!(
                "rpm puts the follower at resonance: one turn lasts omega_n/omega = {ratio} \
                 natural periods (a whole number) and zeta = {zeta} leaves no steady state \
                 (det(I - Phi) = {det:e}); add damping or change the speed"
            )
            .into(),
        })
        .into());
    }
    let x0 = (e * d[0] - b * d[1]) / det;
    let v0 = (a * d[1] - c * d[0]) / det;
    let per = [run(&grids[0], x0, v0)?, run(&grids[1], x0, v0)?];
    let rich = |which: usize, ic: usize, jf: usize| {
        let (c, f) = if which == 0 {
            (&per[0].0, &per[1].0)
        } else {
            (&per[0].1, &per[1].1)
        };
        (4.0 * f[jf] - c[ic]) / 3.0
    };
    let nq = theta.len();
    let (mut x, mut rate) = (vec![0.0; nq], vec![0.0; nq]);
    for i in 0..nq {
        let (ic, jf) = (grids[0].query[i], grids[1].query[i]);
        x[i] = rich(0, ic, jf);
        rate[i] = omega * rich(1, ic, jf);
    }
    let residual = (0..pieces.len())
        .map(|s| {
            let (ic, jf) = (grids[0].ends[s], grids[1].ends[s]);
            free_amplitude(rich(0, ic, jf), rich(1, ic, jf), ratio, zeta)
        })
        .collect();
    Ok(SteadyState { x, rate, residual })
}

#[cfg(test)]
#[path = "vibration_tests.rs"]
mod tests;
