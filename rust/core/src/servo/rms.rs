//! The RMS bound of a servo segment: the smallest phase angle at which the
//! motor's RMS torque over the whole cycle stays within its rated torque
//! (issue 33, item 3).
//!
//! The RMS couples the cycle, so the bound is exact for one segment whose
//! angle the cyclogram sets while the rest of the program keeps its shape: the
//! segment k at angle β (its unit law stretched, as in `bounds`), the next
//! dwell taking up the change (its angle D₀ + β₀ − β, holding the load at the
//! static torque T_h), every other segment fixed. At master speed ω the
//! energy of the motor's torque over the cycle is
//!
//!   E(β) = β·∫₀¹ T_m(u; ω²/β²)² du + (D₀ + β₀ − β)·T_h² + E_fixed(ω),
//!
//! with T_m the motor torque of `bounds` (the efficiency on the side of the
//! power flow) and E_fixed the fixed segments' ∫T_m² dθ, and RMS² = E/2π.
//! Both integrals are trapezoid sums over the samples given (their weights),
//! exact to O(h²).
//!
//! **The structure.** Each sample's motor torque is a line in x (x = ω²/β² for
//! the segment, ω² for the fixed part) whose coefficients switch once, where
//! the load torque T_L crosses zero (the efficiency's side of the power flow).
//! So a weighted sum of squared torques is a piecewise quadratic in x with one
//! break per such sample ([`SquareSum`]): built once per call (a sort of the
//! breaks and prefix sums), each evaluation is a binary search and three
//! multiply–adds instead of a pass over every sample. The speeds are
//! independent and run in parallel.
//!
//! **The rule**, as the other bounds': the smallest β ≤ β_max = β₀ + D₀ such
//! that the RMS holds at every β′ in [β, β_max] (a window of admissible angles
//! below a violation is ignored): the highest violation is found on a
//! geometric grid of [`RMS_GRID`] angles down from β_max and refined by
//! bisection to 1e-13 relative. NaN when even β_max fails (no angle the dwell
//! can give will do); 0 when none of the grid fails down to β_max·1e-9.

use rayon::prelude::*;

use super::bounds::{motor_torque, Drive};
use super::ServoError;
use crate::input::InvalidInput;
use crate::parallel::{pool, resolve_threads};

/// Angles of the grid [`rms_angle`] scans down from β_max.
pub const RMS_GRID: usize = 2048;

/// The bound segment and the rest of the program, for [`rms_angle`].
#[derive(Debug, Clone, Copy)]
pub struct RmsProgram<'a> {
    /// The segment's unit law Z′, Z″ at samples of u ∈ [0, 1], their trapezoid
    /// weights (summing to 1), and its stroke at the load shaft H [rad].
    pub dz: &'a [f64],
    pub ddz: &'a [f64],
    pub weights: &'a [f64],
    pub stroke: f64,
    /// The fixed segments' φ_L′ and φ_L″ per radian of master at samples, and
    /// their trapezoid weights [rad of master].
    pub fixed_v: &'a [f64],
    pub fixed_a: &'a [f64],
    pub fixed_w: &'a [f64],
    /// The segment's and the taking-up dwell's angles in the program [rad].
    pub angle: f64,
    pub dwell: f64,
}

impl RmsProgram<'_> {
    fn check(&self) -> Result<(), InvalidInput> {
        for (field, v) in [
            ("dz", self.dz),
            ("ddz", self.ddz),
            ("weights", self.weights),
            ("fixed_v", self.fixed_v),
            ("fixed_a", self.fixed_a),
            ("fixed_w", self.fixed_w),
        ] {
            InvalidInput::check_finite(field, v)?;
        }
        if self.ddz.len() != self.dz.len() || self.weights.len() != self.dz.len() {
            return Err(InvalidInput::bad_value(
                "weights",
                self.weights.len() as f64,
                "dz, ddz and weights must have one entry per sample",
            ));
        }
        if self.fixed_a.len() != self.fixed_v.len() || self.fixed_w.len() != self.fixed_v.len() {
            return Err(InvalidInput::bad_value(
                "fixed_w",
                self.fixed_w.len() as f64,
                "fixed_v, fixed_a and fixed_w must have one entry per sample",
            ));
        }
        for (field, v) in [("angle", self.angle), ("dwell", self.dwell)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(InvalidInput::bad_value(
                    field,
                    v,
                    "[rad] must be finite and > 0",
                ));
            }
        }
        if !self.stroke.is_finite() {
            return Err(InvalidInput::bad_value(
                "stroke",
                self.stroke,
                "[rad] must be finite",
            ));
        }
        Ok(())
    }
}

/// Σ wᵢ·T_m,ᵢ(x)² over samples, as a piecewise quadratic in x ≥ 0 (module
/// docs): sample i has acceleration `acc`ᵢ·x and velocity sign `moving`ᵢ, so
/// its motor torque is pᵢ·x + qᵢ with (pᵢ, qᵢ) switching once, at the x where
/// its load torque J_L·accᵢ·x + T_ext crosses zero. Equal to the sum of
/// [`motor_torque`]'s squares to rounding (tested against that sum).
#[derive(Debug, Clone)]
pub(super) struct SquareSum {
    /// The x > 0 where some sample switches side, ascending.
    breaks: Vec<f64>,
    /// (c₂, c₁, c₀) on [breaks[k−1], breaks[k]): one more than `breaks`.
    coef: Vec<[f64; 3]>,
}

impl SquareSum {
    pub(super) fn new(d: &Drive, acc: &[f64], moving: &[f64], weights: &[f64]) -> Self {
        let mut base = [0.0; 3];
        let mut events: Vec<(f64, [f64; 3])> = Vec::new();
        let t_ext = d.load_torque;
        for ((&a, &m), &w) in acc.iter().zip(moving).zip(weights) {
            let slope = d.load_inertia * a; // T_L = slope·x + T_ext
                                            // The weighted square of the motor torque's line on one side of the
                                            // power flow (`motor_torque`'s two branches).
            let square = |tl_sign: f64| -> [f64; 3] {
                let k = if tl_sign * m < 0.0 {
                    d.efficiency / d.ratio
                } else {
                    1.0 / (d.ratio * d.efficiency)
                };
                let (p, q) = (d.drive_inertia * d.ratio * a + k * slope, k * t_ext);
                [w * p * p, 2.0 * w * p * q, w * q * q]
            };
            let cross = -t_ext / slope;
            if cross > 0.0 && cross.is_finite() {
                // T_ext's sign below the crossing, the slope's above it.
                let (below, above) = (square(t_ext), square(slope));
                add(&mut base, below, 1.0);
                let mut step = above;
                add(&mut step, below, -1.0);
                events.push((cross, step));
            } else {
                // One side for every x > 0 (and at 0 the same, or T_L = 0).
                add(&mut base, square(slope + t_ext), 1.0);
            }
        }
        events.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut coef = Vec::with_capacity(events.len() + 1);
        coef.push(base);
        for (_, step) in &events {
            add(&mut base, *step, 1.0);
            coef.push(base);
        }
        Self {
            breaks: events.iter().map(|e| e.0).collect(),
            coef,
        }
    }

    /// The sum at `x` ≥ 0 (continuous across the breaks: there T_L = 0 and both
    /// sides give the same torque).
    pub(super) fn at(&self, x: f64) -> f64 {
        let [c2, c1, c0] = self.coef[self.breaks.partition_point(|&b| b <= x)];
        (c2 * x + c1) * x + c0
    }
}

fn add(sum: &mut [f64; 3], term: [f64; 3], sign: f64) {
    for (s, t) in sum.iter_mut().zip(term) {
        *s += sign * t;
    }
}

/// The smallest angle [rad] of the segment by the RMS torque at each master
/// speed `omegas` [rad/s] (module docs) into `out`, the motor's rated torque
/// `rated` [N·m]; the speeds in parallel on `n_threads` (None: the default).
pub fn rms_angles_into(
    p: &RmsProgram<'_>,
    drive: &Drive,
    rated: f64,
    omegas: &[f64],
    out: &mut [f64],
    n_threads: Option<i64>,
) -> Result<(), ServoError> {
    p.check()?;
    super::bounds::check_drive(drive)?;
    super::positive_entries("omega", omegas)?;
    if !(rated.is_finite() && rated > 0.0) {
        return Err(InvalidInput::bad_value("rated", rated, "[N·m] must be finite and > 0").into());
    }
    if out.len() != omegas.len() {
        return Err(InvalidInput::bad_value(
            "out",
            out.len() as f64,
            "must have one entry per speed",
        )
        .into());
    }
    let moving: Vec<f64> = p.dz.iter().map(|&z| p.stroke * z).collect();
    let acc: Vec<f64> = p.ddz.iter().map(|&z| p.stroke * z).collect();
    let rule = Rule {
        segment: SquareSum::new(drive, &acc, &moving, p.weights),
        fixed: SquareSum::new(drive, p.fixed_a, p.fixed_v, p.fixed_w),
        hold: motor_torque(drive, 0.0, 0.0),
        budget: rated * rated * std::f64::consts::TAU,
        angle: p.angle,
        dwell: p.dwell,
    };
    let pool = pool(resolve_threads(n_threads)?)?;
    pool.install(|| {
        out.par_iter_mut()
            .zip(omegas.par_iter())
            .with_min_len(64)
            .for_each(|(o, &w)| *o = rule.angle_at(w));
    });
    Ok(())
}

/// The segment's and the fixed part's energies and the budget, for
/// [`rms_angles_into`].
struct Rule {
    segment: SquareSum,
    fixed: SquareSum,
    hold: f64,
    budget: f64,
    angle: f64,
    dwell: f64,
}

impl Rule {
    /// ∫ T_m² dθ over the cycle [N²·m²·rad] with the segment at angle `beta`
    /// and master speed `w` [rad/s], the fixed part's `fixed`.
    fn energy(&self, w: f64, beta: f64, fixed: f64) -> f64 {
        beta * self.segment.at(w * w / (beta * beta))
            + (self.dwell + self.angle - beta) * self.hold * self.hold
            + fixed
    }

    /// The rule of the module docs at one speed.
    fn angle_at(&self, w: f64) -> f64 {
        let fixed = self.fixed.at(w * w);
        let top = self.angle + self.dwell;
        let fails = |beta: f64| self.energy(w, beta, fixed) > self.budget;
        if fails(top) {
            return f64::NAN;
        }
        // Down a geometric grid from the top to the highest failing angle.
        let ratio = (1e-9_f64).powf(1.0 / RMS_GRID as f64);
        let (mut hi, mut lo) = (top, f64::NAN);
        let mut beta = top;
        for _ in 0..RMS_GRID {
            let next = beta * ratio;
            if fails(next) {
                lo = next;
                hi = beta;
                break;
            }
            beta = next;
        }
        if lo.is_nan() {
            return 0.0;
        }
        // Bisection between a failing lo and a passing hi.
        while hi - lo > 1e-13 * hi {
            let mid = 0.5 * (lo + hi);
            if fails(mid) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        hi
    }
}

/// The highest master speed [rad/s] at which the RMS torque of a motion of
/// fixed shape (`v`, `a`: φ_L′ and φ_L″ per radian of master at samples,
/// `weights` their trapezoid weights over the whole cycle [rad]) stays within
/// `rated` [N·m], below `cap` [rad/s]: the first speed at which it exceeds
/// (every lower speed holds), found on a geometric grid of [`RMS_GRID`] speeds
/// up from cap·1e-9 and refined by bisection to 1e-13 relative; 0 when the
/// static torque's RMS alone exceeds it, inf when no speed up to `cap` does.
pub fn rms_speed_limit(
    v: &[f64],
    a: &[f64],
    weights: &[f64],
    drive: &Drive,
    rated: f64,
    cap: f64,
) -> Result<f64, ServoError> {
    for (field, x) in [("v", v), ("a", a), ("weights", weights)] {
        InvalidInput::check_finite(field, x)?;
    }
    if a.len() != v.len() || weights.len() != v.len() {
        return Err(InvalidInput::bad_value(
            "weights",
            weights.len() as f64,
            "v, a and weights must have one entry per sample",
        )
        .into());
    }
    super::bounds::check_drive(drive)?;
    for (field, x) in [("rated", rated), ("cap", cap)] {
        if !(x.is_finite() && x > 0.0) {
            return Err(InvalidInput::bad_value(field, x, "must be finite and > 0").into());
        }
    }
    let budget = rated * rated * std::f64::consts::TAU;
    let energy = SquareSum::new(drive, a, v, weights);
    let fails = |w: f64| energy.at(w * w) > budget;
    if fails(0.0) {
        return Ok(0.0);
    }
    let ratio = (1e9_f64).powf(1.0 / RMS_GRID as f64);
    let (mut lo, mut hi) = (0.0, f64::NAN);
    let mut w = cap * 1e-9;
    for _ in 0..=RMS_GRID {
        if fails(w) {
            hi = w;
            break;
        }
        lo = w;
        w = (w * ratio).min(cap);
        if lo == cap {
            break;
        }
    }
    if hi.is_nan() {
        return Ok(f64::INFINITY);
    }
    while hi - lo > 1e-13 * hi {
        let mid = 0.5 * (lo + hi);
        if fails(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Ok(lo)
}
