//! Cams sized against the cyclogram (issue 35, item 7): the smallest base
//! radius R_b that meets the pressure-angle, undercut and Hertz-stress limits
//! at the cam's own phase angles and a speed, and the trade-off between the
//! base radius and the smallest phase angles.
//!
//! **What is searched, what is held.** The base radius always; optionally one
//! second dimension over a stated range: a translating roller's offset e, or
//! an oscillating roller's pivot distance a (its arm length l held: scaling a,
//! l and R_b together leaves every angle, so the pressure angle, unchanged,
//! and the arm length is usually set by the space around the cam). The roller
//! radius, the program (phase angles, strokes, laws), the loads and the
//! contact are held.
//!
//! **The criteria** are the cam module's own, at each segment's own angle
//! (every segment, dwells included: an offset or a spring's preload load a
//! dwell too): the pressure angle's ratio max|φ|/[α], the undercut ratio
//! (r_r/ρ_p on a roller's pitch curve, both flanks of a groove; −s″/(R_b + s)
//! for a flat face) and the Hertz stress's ratio σ_max/[σ_H] (+∞ on an undercut
//! profile), each a segment's worst value by the grid-and-Brent search of
//! `cam::search`. g(R_b) is the largest of them; ≤ 1 is admissible (up to
//! [`ADMIT`], 1 + 1e-9). A radius
//! at which the follower cannot be built (a roller larger than the base circle,
//! an arm that cannot reach the pitch circle) counts as violated ("geometry").
//!
//! **The rule.** The pressure angle of a translating roller falls
//! monotonically with R_b, but the stress need not (a larger radius flattens
//! the curvature and changes the pressure angle, so the normal force), and an
//! oscillating follower's geometry closes at both ends. So: g is scanned on
//! [`SCAN`] radii geometrically spaced over [R_min, R_max]; the answer is the
//! smallest scanned radius with g ≤ 1, refined downward to the crossing by
//! Brent's root (1e-13 relative) against the scanned radius below it (where g
//! is +∞ there, a geometric bisection first finds a finite violating point).
//! A feasible window narrower than one scan cell is not seen; an admissible
//! radius with a violation above it (a window, not an interval up to R_max) is
//! flagged (`gap_above`). If the smallest scanned radius is already
//! admissible, the answer is R_min and no criterion binds ("at_lower_bound":
//! the optimum is at the search's bound). If no scanned radius is admissible,
//! the status is "infeasible" and the row holds the scanned radius where g is
//! least, its ratios and the criterion that fails there.
//!
//! The second dimension: R_b*(p) at [`SECOND_GRID`] values of p evenly over the
//! range (in parallel), the least taken (ties, within 1e-12 relative, to the
//! smaller |p|), then Brent's minimiser on its two neighbouring cells (to
//! 1e-10 of the range). R_b*(p) is continuous where the binding criterion does
//! not change; the grid guards against its several local minima.

use rayon::prelude::*;

use crate::cam::{brent_max, brent_zero, Cam, CamError, Contact, Follower, Limits, Loads};
use crate::input::InvalidInput;
use crate::parallel::{pool, resolve_threads};

/// The criteria of a sizing, in the order of its ratios; "geometry" (the
/// follower cannot be built) is the binding index [`GEOMETRY`].
pub const SIZE_CRITERIA: [&str; 4] = ["pressure_angle", "undercut", "contact_stress", "geometry"];

/// The index of "geometry" in [`SIZE_CRITERIA`].
pub const GEOMETRY: usize = 3;

/// The statuses of a sizing, by index.
pub const SIZE_STATUS: [&str; 3] = ["ok", "at_lower_bound", "infeasible"];

/// The columns of [`Sizing::solve_into`]'s rows: the base radius [m], the
/// second dimension [m] (NaN if not searched), the status (index into
/// [`SIZE_STATUS`]), the binding criterion (index into [`SIZE_CRITERIA`], −1:
/// none), the three ratios at the answer and `gap_above` (0/1).
pub const SIZE_COLUMNS: [&str; 8] = [
    "base_radius",
    "second",
    "status",
    "binding",
    "pressure_angle",
    "undercut",
    "contact_stress",
    "gap_above",
];

/// Values per speed in [`Sizing::solve_into`].
pub const N_SIZE_COLUMNS: usize = SIZE_COLUMNS.len();

/// Scanned radii over [R_min, R_max].
pub const SCAN: usize = 64;

/// Values of the second dimension over its range.
pub const SECOND_GRID: usize = 33;

/// A ratio up to this is admissible: a cam laid out at phase angles its own
/// bounds gave (the machine's LP) sits at ratio 1 to the bounds' 1e-13, which
/// the sizing's own evaluation must not read as a violation.
pub const ADMIT: f64 = 1.0 + 1e-9;

/// One sizing's answer (see [`SIZE_COLUMNS`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sized {
    pub base_radius: f64,
    pub second: f64,
    pub status: usize,
    pub binding: i64,
    pub ratios: [f64; 3],
    pub gap_above: bool,
}

impl Sized {
    fn row(&self) -> [f64; N_SIZE_COLUMNS] {
        [
            self.base_radius,
            self.second,
            self.status as f64,
            self.binding as f64,
            self.ratios[0],
            self.ratios[1],
            self.ratios[2],
            if self.gap_above { 1.0 } else { 0.0 },
        ]
    }
}

/// A sizing problem: the cam (its base radius is the search's variable, its
/// other dimensions held), the loads and contact, the limits and the search's
/// range.
#[derive(Debug, Clone)]
pub struct Sizing<'a> {
    pub cam: &'a Cam,
    pub loads: Option<&'a Loads>,
    pub contact: Option<&'a Contact>,
    pub limits: Limits,
    /// The base radii searched [m]: R_min > 0, R_max > R_min.
    pub min_radius: f64,
    pub max_radius: f64,
    /// The second dimension's range [m] (offset, or pivot distance), if searched.
    pub second: Option<(f64, f64)>,
}

fn bad(field: &'static str, value: f64, why: String) -> CamError {
    InvalidInput::BadValue {
        field,
        value,
        why: why.into(),
    }
    .into()
}

/// The cam with base radius `rb` and, if given, the second dimension `p`
/// (offset or pivot distance); `None` if the follower cannot be built.
pub fn resized(cam: &Cam, rb: f64, p: Option<f64>) -> Option<Cam> {
    let follower = match cam.follower() {
        Follower::TranslatingRoller {
            roller_radius,
            offset,
            ..
        } => Follower::TranslatingRoller {
            base_radius: rb,
            roller_radius,
            offset: p.unwrap_or(offset),
        },
        Follower::FlatFaced { .. } => Follower::FlatFaced { base_radius: rb },
        Follower::OscillatingRoller {
            pivot_distance,
            arm_length,
            roller_radius,
            ..
        } => Follower::OscillatingRoller {
            pivot_distance: p.unwrap_or(pivot_distance),
            arm_length,
            base_radius: rb,
            roller_radius,
        },
    };
    Cam::new(cam.program().clone(), follower, cam.groove()).ok()
}

impl Sizing<'_> {
    /// Check the problem; the Hertz (width, compliance) if the stress is a criterion.
    fn validate(&self) -> Result<Option<(f64, f64)>, CamError> {
        let a = self.limits.max_pressure_angle;
        if !(a > 0.0 && a < std::f64::consts::FRAC_PI_2) {
            return Err(bad(
                "max_pressure_angle",
                a,
                "[rad] must be in (0, π/2)".into(),
            ));
        }
        let (lo, hi) = (self.min_radius, self.max_radius);
        if !(lo.is_finite() && lo > 0.0) {
            return Err(bad(
                "min_base_radius",
                lo,
                "[m] must be finite and > 0".into(),
            ));
        }
        if !(hi.is_finite() && hi > lo) {
            return Err(bad(
                "max_base_radius",
                hi,
                format!("[m] must be finite and > min_base_radius = {lo}"),
            ));
        }
        if let Some((p0, p1)) = self.second {
            let field = match self.cam.follower() {
                Follower::TranslatingRoller { .. } => "offset",
                Follower::OscillatingRoller { .. } => "pivot_distance",
                Follower::FlatFaced { .. } => {
                    return Err(bad(
                        "second",
                        p0,
                        "a flat-faced follower has no offset or pivot to search".into(),
                    ))
                }
            };
            if !(p0.is_finite() && p1.is_finite() && p1 > p0) {
                return Err(bad(
                    field,
                    p0,
                    format!("the range [{p0}, {p1}] [m] must be finite with low < high"),
                ));
            }
        }
        let n = self.cam.program().len();
        if let Some(l) = self.loads {
            l.validate(n)?;
        }
        match (self.limits.max_stress, self.loads, self.contact) {
            (None, _, _) => Ok(None),
            (Some(m), _, _) if !(m.is_finite() && m > 0.0) => {
                Err(bad("max_stress", m, "[Pa] must be finite and > 0".into()))
            }
            (Some(_), Some(_), Some(c)) => Ok(Some((c.width, self.cam.hertz_compliance(c)?))),
            (Some(m), _, _) => Err(bad(
                "max_stress",
                m,
                "needs the follower's loads and the contact's data".into(),
            )),
        }
    }

    /// Each criterion's worst ratio over the whole cam with base radius `rb`
    /// (and second dimension `p`) at speed `omega` [rad/s]; `None`: the
    /// follower cannot be built.
    pub fn ratios(
        &self,
        rb: f64,
        p: Option<f64>,
        omega: f64,
        hertz: Option<(f64, f64)>,
    ) -> Option<[f64; 3]> {
        let cam = resized(self.cam, rb, p)?;
        let flat = matches!(cam.follower(), Follower::FlatFaced { .. });
        let mut r = [0.0f64; 3];
        for k in 0..cam.program().len() {
            let beta = cam.program().segment(k).1;
            if !flat {
                r[0] = r[0].max(cam.pressure_ratio(k, beta, self.limits.max_pressure_angle));
            }
            r[1] = r[1].max(cam.undercut_ratio(k, beta));
            if let (Some(m), Some(l), Some(h)) = (self.limits.max_stress, self.loads, hertz) {
                let s = cam.stress_ratio(k, beta, omega, l, h, m, None);
                r[2] = r[2].max(if s.is_nan() { f64::INFINITY } else { s });
            }
        }
        Some(r)
    }

    /// g: the largest ratio (+∞ where the follower cannot be built).
    fn worst(&self, rb: f64, p: Option<f64>, omega: f64, hertz: Option<(f64, f64)>) -> f64 {
        self.ratios(rb, p, omega, hertz)
            .map_or(f64::INFINITY, |r| r.iter().fold(0.0f64, |a, &b| a.max(b)))
    }

    /// The answer's fields at radius `rb` (binding: the largest ratio).
    fn answer(
        &self,
        rb: f64,
        p: Option<f64>,
        omega: f64,
        hertz: Option<(f64, f64)>,
        status: usize,
    ) -> Sized {
        let (ratios, binding) = match self.ratios(rb, p, omega, hertz) {
            None => ([f64::INFINITY; 3], GEOMETRY as i64),
            Some(r) => {
                let mut b = 0;
                for i in 1..3 {
                    if r[i] > r[b] {
                        b = i;
                    }
                }
                (r, b as i64)
            }
        };
        Sized {
            base_radius: rb,
            second: p.unwrap_or(f64::NAN),
            status,
            binding: if status == 1 { -1 } else { binding },
            ratios,
            gap_above: false,
        }
    }

    /// The smallest admissible base radius at `p` and `omega` (see the rule).
    fn smallest(&self, p: Option<f64>, omega: f64, hertz: Option<(f64, f64)>) -> Sized {
        let (lo, hi) = (self.min_radius, self.max_radius);
        let q = (hi / lo).powf(1.0 / (SCAN - 1) as f64);
        let radii: Vec<f64> = (0..SCAN)
            .map(|i| {
                if i == SCAN - 1 {
                    hi
                } else {
                    lo * q.powi(i as i32)
                }
            })
            .collect();
        let g: Vec<f64> = radii
            .par_iter()
            .map(|&r| self.worst(r, p, omega, hertz))
            .collect();
        let Some(j) = g.iter().position(|&v| v <= ADMIT) else {
            // Infeasible: the scanned radius where g is least.
            let mut b = SCAN - 1;
            for i in 0..SCAN {
                if g[i] < g[b] {
                    b = i;
                }
            }
            return self.answer(radii[b], p, omega, hertz, 2);
        };
        let gap_above = g[j..].iter().any(|&v| v > ADMIT || v.is_nan());
        if j == 0 {
            return Sized {
                gap_above,
                ..self.answer(lo, p, omega, hertz, 1)
            };
        }
        let f = |r: f64| self.worst(r, p, omega, hertz);
        let (mut a, mut ga, mut b, mut gb) = (radii[j - 1], g[j - 1], radii[j], g[j]);
        let mut tries = 0;
        while !ga.is_finite() && tries < 200 {
            let mid = (a * b).sqrt();
            let gm = f(mid);
            if gm <= ADMIT {
                (b, gb) = (mid, gm);
            } else {
                (a, ga) = (mid, gm);
            }
            tries += 1;
        }
        // Admissible within ADMIT but above 1 at b: b itself is the crossing.
        let rb = if !ga.is_finite() || gb > 1.0 || b - a <= 1e-15 * b {
            b
        } else {
            brent_zero(|r| f(r) - 1.0, a, b, ga - 1.0, gb - 1.0, 0.0, 1e-13)
        };
        Sized {
            gap_above,
            ..self.answer(rb, p, omega, hertz, 0)
        }
    }

    /// The sizing at one speed, with the second dimension searched if asked.
    fn at_speed(&self, omega: f64, hertz: Option<(f64, f64)>) -> Sized {
        let Some((p0, p1)) = self.second else {
            return self.smallest(None, omega, hertz);
        };
        let h = (p1 - p0) / (SECOND_GRID - 1) as f64;
        let ps: Vec<f64> = (0..SECOND_GRID).map(|i| p0 + i as f64 * h).collect();
        let rows: Vec<Sized> = ps
            .par_iter()
            .map(|&p| self.smallest(Some(p), omega, hertz))
            .collect();
        // The key to minimise: feasible rows by radius; infeasible ones after
        // every feasible one, by their worst ratio.
        let key = |s: &Sized| {
            if s.status == 2 {
                let w = s.ratios.iter().fold(0.0f64, |a, &b| a.max(b));
                (1, w)
            } else {
                (0, s.base_radius)
            }
        };
        let mut order: Vec<usize> = (0..SECOND_GRID).collect();
        order.sort_by(|&x, &y| ps[x].abs().total_cmp(&ps[y].abs()));
        let mut best = order[0];
        for &i in &order[1..] {
            let (ki, kb) = (key(&rows[i]), key(&rows[best]));
            if ki.0 < kb.0 || (ki.0 == kb.0 && ki.1 < kb.1 * (1.0 - 1e-12)) {
                best = i;
            }
        }
        if rows[best].status != 0 {
            return rows[best];
        }
        // Brent's minimiser of R_b*(p) on the best grid value's two cells.
        let (a, b) = (
            ps[best.saturating_sub(1)],
            ps[(best + 1).min(SECOND_GRID - 1)],
        );
        let penalty = -10.0 * self.max_radius;
        let neg = |p: f64| {
            let s = self.smallest(Some(p), omega, hertz);
            if s.status == 0 {
                -s.base_radius
            } else if s.status == 1 {
                -self.min_radius
            } else {
                penalty
            }
        };
        let (x, _) = brent_max(&neg, a, b, 1e-10 * (p1 - p0));
        let refined = self.smallest(Some(x), omega, hertz);
        if refined.status == 0 && refined.base_radius < rows[best].base_radius {
            refined
        } else {
            rows[best]
        }
    }

    /// The sizing at each cam speed `omegas` [rad/s] into `out` (row-major,
    /// `omegas.len() · N_SIZE_COLUMNS`, see [`SIZE_COLUMNS`]); speeds in parallel.
    pub fn solve_into(
        &self,
        omegas: &[f64],
        out: &mut [f64],
        n_threads: Option<i64>,
    ) -> Result<(), CamError> {
        let hertz = self.validate()?;
        check_speeds(omegas)?;
        debug_assert_eq!(out.len(), omegas.len() * N_SIZE_COLUMNS);
        let pool = pool(resolve_threads(n_threads)?)?;
        pool.install(|| {
            out.par_chunks_mut(N_SIZE_COLUMNS)
                .zip(omegas.par_iter())
                .for_each(|(row, &w)| {
                    if !crate::cancel::requested() {
                        row.copy_from_slice(&self.at_speed(w, hertz).row());
                    }
                })
        });
        Ok(())
    }
}

fn check_speeds(omegas: &[f64]) -> Result<(), CamError> {
    if let Some((index, &value)) = omegas
        .iter()
        .enumerate()
        .find(|(_, w)| !(w.is_finite() && **w >= 0.0))
    {
        return Err(bad(
            "omega",
            value,
            format!("(at index {index}) [rad/s] must be finite and >= 0"),
        ));
    }
    Ok(())
}

/// The trade-off base radius ↔ smallest phase angle: for each base radius of
/// `radii` [m] (the cam's other dimensions held), [`Cam::min_angles_into`]'s
/// angles of `segments` at `omegas` into `out` (row-major (radii, speeds,
/// segments, criteria)); NaN rows where the follower cannot be built at that
/// radius (the arguments are then checked only at the radii where it can).
/// Radii in parallel.
#[allow(clippy::too_many_arguments)]
pub fn tradeoff_into(
    cam: &Cam,
    radii: &[f64],
    segments: &[usize],
    omegas: &[f64],
    loads: Option<&Loads>,
    contact: Option<&Contact>,
    limits: &Limits,
    out: &mut [f64],
    n_threads: Option<i64>,
) -> Result<(), CamError> {
    // The cam's own call at each radius validates the segments, limits, loads
    // and contact (the same at every radius: the first error is returned).
    check_speeds(omegas)?;
    if let Some((index, &value)) = radii
        .iter()
        .enumerate()
        .find(|(_, r)| !(r.is_finite() && **r > 0.0))
    {
        return Err(bad(
            "radii",
            value,
            format!("(at index {index}) [m] must be finite and > 0"),
        ));
    }
    let per = omegas.len() * segments.len() * crate::cam::CRITERIA.len();
    debug_assert_eq!(out.len(), radii.len() * per);
    if per == 0 {
        return Ok(());
    }
    let threads = resolve_threads(n_threads)?;
    let pool = pool(threads)?;
    // Inside this pool the cam's own call installs on the same (cached) pool,
    // which runs inline: one level of work stealing over radii and segments.
    pool.install(|| {
        out.par_chunks_mut(per)
            .zip(radii.par_iter())
            .try_for_each(|(o, &r)| match resized(cam, r, None) {
                None => {
                    o.fill(f64::NAN);
                    Ok(())
                }
                Some(c) => c.min_angles_into(
                    segments,
                    omegas,
                    loads,
                    contact,
                    limits,
                    o,
                    Some(threads as i64),
                ),
            })
    })
}

#[cfg(test)]
#[path = "cam_size_tests.rs"]
mod tests;
