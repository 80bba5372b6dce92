//! The smallest phase angle of each rise or return for each criterion: the
//! pressure angle, undercut, jump (spring closure) and the Hertz stress.
//!
//! A segment's criteria depend only on its own angle β (its start displacement,
//! stroke, law and load kept) and the speed, so each is a ratio g(β, ω) of the
//! worst value over the segment to its limit (≤ 1 is admissible), the worst
//! value found by [`super::search::max_unit`] (a grid and Brent's maximiser).
//! **The rule:** the bound is the smallest β with g ≤ 1 on all of [β, 2π]; it
//! is found by scanning β downward from 2π in geometric steps of 0.7 to the
//! first violation, then the crossing by Brent's root to 1e-13 relative. A
//! feasible window below a violation is ignored (conservative), and a violation
//! narrower than one step of the scan between two admissible steps is not
//! seen. NaN: no angle up to a whole turn will do (g(2π) > 1, or the criterion
//! cannot be met at all, e.g. a spring too weak to hold the follower at rest).
//! 0: the criterion does not bound the segment (a flat face's pressure angle, a
//! groove's jump, no stress limit) or not above 2π·1e-6. The Hertz stress is not
//! defined on an undercut profile, so below the undercut bound it counts as
//! violated; where it holds right above the undercut bound, its column is 0 (the
//! undercut binds).
//!
//! Closed forms where there are: the pressure angle and undercut do not depend
//! on the speed (one search per segment); jump is β_min = ω·√(max m(−h z″)/K)
//! with K = k s + F0 + F_L (s″ = h z″/β²), proportional to the speed.

use std::f64::consts::TAU;

use rayon::prelude::*;

use super::contact::{Contact, Loads};
use super::follower::{Cam, Follower, N_COLUMNS};
use super::program::CamError;
use super::search::{brent_max, brent_zero, max_unit, refine, GRID};

/// The curvature ratio (r_r/ρ_p, 1 at a cusp) above which the stress search
/// also looks at the curvature's peak: there the profile's radius ρ_p − r_r is
/// under the roller's and the relative curvature grows without bound.
pub(super) const NEAR_UNDERCUT: f64 = 0.5;

/// A trial angle whose worst value on the grid is below this fraction of its
/// limit is admissible without refining the maximum: a peak would have to stand
/// 25 % above the two grid samples around it (1/48 of the segment apart).
pub(super) const CUT: f64 = 0.8;
use crate::input::InvalidInput;
use crate::parallel::{pool, resolve_threads};

/// The criteria of [`Cam::min_angles_into`], in the order of its output.
pub const CRITERIA: [&str; 4] = ["pressure_angle", "undercut", "jump", "contact_stress"];

/// The scan's step ratio and its floor [rad].
pub(super) const STEP: f64 = 0.7;
pub(super) const FLOOR: f64 = TAU * 1e-6;

/// Limits of the criteria: the pressure angle [rad] and, optionally, the
/// Hertz stress [Pa].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    pub max_pressure_angle: f64,
    pub max_stress: Option<f64>,
}

/// The smallest β with g ≤ 1 on [β, 2π] (see the module's rule).
pub fn last_crossing(g: impl Fn(f64) -> f64) -> f64 {
    let mut hi = TAU;
    let mut ghi = g(hi);
    if ghi.is_nan() || ghi > 1.0 {
        return f64::NAN;
    }
    loop {
        let mut lo = hi * STEP;
        if lo < FLOOR {
            return 0.0;
        }
        let mut glo = g(lo);
        if glo <= 1.0 {
            (hi, ghi) = (lo, glo);
            continue;
        }
        // Violated at lo. Brent needs finite values: where g is +∞ or NaN at lo
        // (a locked follower, an undercut profile), bisect (geometrically) for a
        // finite violating point, moving hi down over admissible ones.
        let mut tries = 0;
        while !glo.is_finite() && tries < 200 {
            let mid = (lo * hi).sqrt();
            let gm = g(mid);
            if gm <= 1.0 {
                (hi, ghi) = (mid, gm);
            } else {
                (lo, glo) = (mid, gm);
            }
            tries += 1;
            if hi - lo <= 1e-15 * hi {
                return hi;
            }
        }
        return brent_zero(|b| g(b) - 1.0, lo, hi, glo - 1.0, ghi - 1.0, 0.0, 1e-13);
    }
}

impl Cam {
    /// The geometry row of segment `k` at fraction `x` for a trial angle `beta`.
    #[inline]
    fn trial_row(&self, k: usize, x: f64, beta: f64, geo: &mut [f64; N_COLUMNS]) {
        let start = self.program().segment(k).0;
        self.row_at(start + x * beta, self.program().trial(k, x, beta), geo);
    }

    /// The pressure angle's ratio max|φ|/[α] for segment `k` at angle `beta`.
    pub(crate) fn pressure_ratio(&self, k: usize, beta: f64, limit: f64) -> f64 {
        max_unit(|x| {
            let mut geo = [0.0; N_COLUMNS];
            self.trial_row(k, x, beta, &mut geo);
            geo[10].abs() / limit
        })
        .0
    }

    /// The undercut ratio at one point from its geometry row `geo` (≤ 1: no
    /// cusp): a roller's r_r/ρ_p on a convex pitch curve (either sign for a
    /// groove's two flanks; 0 for a knife edge); a flat face's −s″/(R_b + s).
    #[inline]
    pub(super) fn undercut_of(&self, geo: &[f64]) -> f64 {
        match self.follower() {
            Follower::FlatFaced { base_radius } => -geo[2] / (base_radius + geo[0]),
            Follower::TranslatingRoller { roller_radius, .. }
            | Follower::OscillatingRoller { roller_radius, .. } => {
                let kappa = if geo[11].is_infinite() {
                    0.0
                } else {
                    1.0 / geo[11]
                };
                roller_radius * if self.groove() { kappa.abs() } else { kappa }
            }
        }
    }

    /// The undercut ratio's worst value over segment `k` at angle `beta`.
    pub(crate) fn undercut_ratio(&self, k: usize, beta: f64) -> f64 {
        max_unit(|x| self.undercut_of(&self.lean_row(self.program().trial(k, x, beta)))).0
    }

    /// β_min/ω for jump [s]: √(max m(−h z″)/K) over segment `k` (∞ if the
    /// spring and loads do not hold the follower at rest somewhere on it).
    fn jump_coefficient(&self, k: usize, loads: &Loads) -> f64 {
        if self.groove() || loads.mass == 0.0 {
            return 0.0;
        }
        let load = loads.segment_loads[k];
        let (v, _) = max_unit(|x| {
            // β = 1: s″ = h z″.
            let [s, _, dds, _] = self.program().trial(k, x, 1.0);
            let hold = loads.spring_rate * s + loads.preload + load;
            if hold <= 0.0 {
                f64::INFINITY
            } else {
                (-loads.mass * dds / hold).max(0.0)
            }
        });
        v.sqrt()
    }

    /// The stress ratio σ_max/[σ_H] over segment `k` at angle `beta`, speed
    /// `omega`. An undercut profile anywhere on the segment carries no Hertz
    /// contact: +∞ (so the stress bound is never below the undercut bound). Near
    /// an undercut the stress stands in a narrow peak where the profile's radius
    /// is smallest, which a grid can step over: where the curvature ratio passes
    /// [`NEAR_UNDERCUT`], its peak is found (grid and Brent) and the stress is
    /// also maximised on the two cells around it. `grid`: the law's values at
    /// the grid's points ([`Program::law_at`]), if the caller keeps them.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn stress_ratio(
        &self,
        k: usize,
        beta: f64,
        omega: f64,
        loads: &Loads,
        hertz: (f64, f64),
        limit: f64,
        grid: Option<&[[f64; 4]; GRID]>,
    ) -> f64 {
        let load = loads.segment_loads[k];
        let at = |x: f64| self.lean_row(self.program().trial(k, x, beta));
        let stress = |geo: &[f64; N_COLUMNS]| {
            let lc = self.lever_times(geo[10]);
            self.load_row_lc(geo, lc, omega, loads, load, Some(hertz))[2] / limit
        };
        let f = |x: f64| stress(&at(x));
        let u = |x: f64| self.undercut_of(&at(x));
        let h = 1.0 / (GRID - 1) as f64;
        let (mut vs, mut vu) = ([0.0; GRID], [0.0; GRID]);
        for i in 0..GRID {
            let z = match grid {
                Some(z) => z[i],
                None => self.program().law_at(k, i as f64 * h),
            };
            let geo = self.lean_row(self.program().trial_from(k, z, beta));
            vs[i] = stress(&geo);
            vu[i] = self.undercut_of(&geo);
        }
        let near = vu.iter().any(|v| v.is_nan() || *v >= NEAR_UNDERCUT);
        let peak = if near {
            let (worst, x) = refine(&u, &vu, f64::NEG_INFINITY);
            if worst.is_nan() || worst >= 1.0 {
                return f64::INFINITY;
            }
            Some(x)
        } else {
            None
        };
        let (main, _) = refine(&f, &vs, CUT);
        match peak {
            Some(x) if main.is_finite() => {
                let (lo, hi) = ((x - h).max(0.0), (x + h).min(1.0));
                let (_, local) = brent_max(&f, lo, hi, 1e-10);
                let v = main.max(local).max(f(x));
                if v.is_nan() {
                    f64::INFINITY
                } else {
                    v
                }
            }
            _ => main,
        }
    }

    /// The speed [rad/s] at which a spring-closed follower first leaves the cam,
    /// and the cam angle [rad] where (∞ and NaN for a groove or a massless
    /// follower; 0 where the spring and loads do not hold it at rest).
    pub fn jump_speed(&self, loads: &Loads) -> Result<(f64, f64), CamError> {
        loads.validate(self.program().len())?;
        let mut best = (f64::INFINITY, f64::NAN);
        if self.groove() || loads.mass == 0.0 {
            return Ok(best);
        }
        for k in 0..self.program().len() {
            let (start, beta, _, _) = self.program().segment(k);
            let load = loads.segment_loads[k];
            let (v, x) = max_unit(|x| {
                let [s, _, dds, _] = self.program().trial(k, x, beta);
                let hold = loads.spring_rate * s + loads.preload + load;
                if hold <= 0.0 {
                    f64::INFINITY
                } else {
                    (-loads.mass * dds / hold).max(0.0)
                }
            });
            let w = if v > 0.0 {
                1.0 / v.sqrt()
            } else {
                f64::INFINITY
            };
            if w < best.0 {
                best = (w, start + x * beta);
            }
        }
        Ok(best)
    }

    /// The smallest phase angle [rad] of each of `segments` (indices of rises
    /// or returns) for each of [`CRITERIA`] at each cam speed `omegas` [rad/s]
    /// into `out` (row-major (speeds, segments, criteria)); see the module's
    /// rule, NaN and 0. Jump needs `loads`; the stress needs `loads`,
    /// `contact` and `limits.max_stress`.
    #[allow(clippy::too_many_arguments)]
    pub fn min_angles_into(
        &self,
        segments: &[usize],
        omegas: &[f64],
        loads: Option<&Loads>,
        contact: Option<&Contact>,
        limits: &Limits,
        out: &mut [f64],
        n_threads: Option<i64>,
    ) -> Result<(), CamError> {
        let n = self.program().len();
        for &k in segments {
            if k >= n {
                return Err(InvalidInput::BadValue {
                    field: "segments",
                    value: k as f64,
                    why: format!("is not a segment index (the program has {n} segments)").into(),
                }
                .into());
            }
            if self.program().segment(k).3 == 0.0 {
                return Err(InvalidInput::BadValue {
                    field: "segments",
                    value: k as f64,
                    why: "is a dwell: only a rise or return has a phase-angle bound".into(),
                }
                .into());
            }
        }
        if let Some((index, &value)) = omegas
            .iter()
            .enumerate()
            .find(|(_, w)| !(w.is_finite() && **w >= 0.0))
        {
            return Err(InvalidInput::BadValue {
                field: "omega",
                value,
                why: format!("(at index {index}) [rad/s] must be finite and >= 0").into(),
            }
            .into());
        }
        let a = limits.max_pressure_angle;
        if !(a > 0.0 && a < std::f64::consts::FRAC_PI_2) {
            return Err(InvalidInput::BadValue {
                field: "max_pressure_angle",
                value: a,
                why: "[rad] must be in (0, π/2)".into(),
            }
            .into());
        }
        if let Some(l) = loads {
            l.validate(n)?;
        }
        let stress = match (limits.max_stress, loads, contact) {
            (None, _, _) => None,
            (Some(m), _, _) if !(m.is_finite() && m > 0.0) => {
                return Err(InvalidInput::BadValue {
                    field: "max_stress",
                    value: m,
                    why: "[Pa] must be finite and > 0".into(),
                }
                .into())
            }
            (Some(m), Some(l), Some(c)) => Some((m, l, (c.width, self.hertz_compliance(c)?))),
            (Some(m), _, _) => {
                return Err(InvalidInput::BadValue {
                    field: "max_stress",
                    value: m,
                    why: "needs the follower's loads and the contact's data".into(),
                }
                .into())
            }
        };
        let (ns, nk, nc) = (omegas.len(), segments.len(), CRITERIA.len());
        debug_assert_eq!(out.len(), ns * nk * nc);
        let pool = pool(resolve_threads(n_threads)?)?;
        pool.install(|| {
            // Per segment, the speed-free criteria and the jump coefficient.
            let fixed: Vec<[f64; 3]> = segments
                .par_iter()
                .map(|&k| {
                    let flat = matches!(self.follower(), Follower::FlatFaced { .. });
                    let p = if flat {
                        0.0
                    } else {
                        last_crossing(|b| self.pressure_ratio(k, b, a))
                    };
                    let u = last_crossing(|b| self.undercut_ratio(k, b));
                    let j = loads.map_or(0.0, |l| self.jump_coefficient(k, l));
                    [p, u, j]
                })
                .collect();
            // The stress: per segment, its scan cache, then the speeds in chunks.
            let mut sb = vec![0.0; ns * nk];
            if let Some((m, l, h)) = stress {
                const SPEEDS: usize = 64;
                let caches: Vec<_> = segments
                    .par_iter()
                    .map(|&k| self.stress_cache(k, l, h, m))
                    .collect();
                sb.par_chunks_mut(ns).enumerate().for_each(|(ki, col)| {
                    let k = segments[ki];
                    col.par_chunks_mut(SPEEDS)
                        .zip(omegas.par_chunks(SPEEDS))
                        .for_each(|(o, w)| {
                            if !crate::cancel::requested() {
                                self.stress_bounds(k, &caches[ki], w, l, h, m, o)
                            }
                        });
                });
            }
            out.par_chunks_mut(nc).enumerate().for_each(|(i, row)| {
                let (si, ki) = (i / nk, i % nk);
                let w = omegas[si];
                let [p, u, j] = fixed[ki];
                let jb = if j.is_infinite() {
                    f64::NAN
                } else {
                    let b = j * w;
                    if b <= TAU {
                        b
                    } else {
                        f64::NAN
                    }
                };
                // The stress is not defined on an undercut profile: below the
                // undercut bound it counts as violated. Where it holds right above
                // that bound it does not bound the segment itself: 0.
                let mut st = sb[ki * ns + si];
                if u > 0.0 && st <= u * (1.0 + 1e-9) {
                    st = 0.0;
                }
                row.copy_from_slice(&[p, u, jb, st]);
            });
        });
        Ok(())
    }
}
