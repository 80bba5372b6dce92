//! The main shaft's forward dynamics (issue 34, items 1–2).
//!
//! **Equation of motion.** A machine of one degree of freedom, the main-shaft
//! angle φ, with the reduced moment of inertia J(φ) [kg·m²] (the mechanisms'
//! kinetic energy is ½·J(φ)·φ̇², plus the constant inertias), the reduced load
//! torque Q(φ) [N·m] (what the shaft must supply against loads, springs and
//! gravity) and a motor giving M(φ̇) on the shaft (through a gear of ratio i =
//! motor speed / shaft speed and efficiency η):
//!
//! J(φ)·φ̈ + ½·J′(φ)·φ̇² = M(φ̇) − Q(φ).
//!
//! J, J′ and Q are sampled at N points φ_k = 2πk/N (N even). J′ is given (the
//! kinetostatics' ω² part is ½·J′ exactly), not differentiated here.
//!
//! **Periodic steady state**, in φ with y = ω² (the energy form
//! d(½·J·y)/dφ = M(√y) − Q):
//!
//! y′ = (2·(M(√y) − Q) − J′·y)/J,   t′ = 1/√y,
//!
//! by a fixed-step classical Runge–Kutta of step h = 2·(2π/N): its nodes are the
//! even samples and its half steps the odd ones, so J, J′ and Q are used exactly
//! as sampled (no interpolation); the global error is O(h⁴). The odd samples of
//! y and t are the cubic Hermite interpolants of the nodes' values and slopes
//! (also O(h⁴)). Shooting on y(0): Newton on F(y₀) = y(2π; y₀) − y₀ with the
//! sensitivity z = ∂y/∂y₀ integrated alongside (z′ = (M′(ω)/ω − J′)/J·z) until
//! |F| ≤ tol·y₀. The first guess is the speed where the motor's torque equals
//! the mean load torque. A constant-torque motor has F′ ≡ 0 (every speed is
//! periodic once ∮(M − Q)dφ = 0, none otherwise): it is integrated once from the
//! given speed when the energy balances and reported as unbalanced when not.
//!
//! **Start-up**, in time from rest (φ = 0, ω = 0): the Dormand–Prince 5(4)
//! pair with error control, J, J′ and Q between samples by cubic Hermite
//! interpolation with fourth-order central-difference slopes (O(h⁴)), until the
//! speed stays within a tolerance of the steady state (its samples by the same
//! interpolation) for a whole turn; the settle time is the last crossing into
//! that band, on each step's continuous extension of order 4.
//!
//! Files: this one (the kernels) and `shaft_tests` (unit tests).

use std::f64::consts::TAU;

use rayon::prelude::*;

use crate::input::InvalidInput;
use crate::parallel::{pool, resolve_threads};

#[cfg(test)]
#[path = "shaft_tests.rs"]
mod tests;

/// The errors of the shaft's dynamics: all of them the caller's inputs.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DriveError {
    #[error(transparent)]
    Input(#[from] InvalidInput),
}

crate::input::wraps_invalid_input!(DriveError);

pub(crate) fn bad(field: &'static str, value: f64, why: impl Into<String>) -> DriveError {
    InvalidInput::bad_value(field, value, why.into()).into()
}

/// A motor's torque against its own speed [N·m, rad/s].
#[derive(Debug, Clone, PartialEq)]
pub enum Characteristic {
    /// The same torque at every speed.
    Constant { torque: f64 },
    /// M = stall·(1 − ω/no_load) (a DC or servo motor).
    Linear { stall: f64, no_load: f64 },
    /// Kloss: M = 2·M_k·s·s_k/(s² + s_k²), s = (ω_sync − ω)/ω_sync.
    Kloss {
        breakdown: f64,
        synchronous: f64,
        critical_slip: f64,
    },
    /// Linear between the (speed, torque) points, extended by the end segments.
    Table { speed: Vec<f64>, torque: Vec<f64> },
}

/// A motor on the main shaft: its characteristic, the gear ratio i (motor
/// speed / shaft speed) and the gear's efficiency η (the shaft gets i·η·M while
/// the motor drives, i·M/η while it brakes).
#[derive(Debug, Clone, PartialEq)]
pub struct Motor {
    pub characteristic: Characteristic,
    pub ratio: f64,
    pub efficiency: f64,
}

impl Characteristic {
    /// (M, dM/dω) at the motor speed `w` [rad/s].
    fn torque(&self, w: f64) -> (f64, f64) {
        match self {
            Characteristic::Constant { torque } => (*torque, 0.0),
            Characteristic::Linear { stall, no_load } => {
                (stall * (1.0 - w / no_load), -stall / no_load)
            }
            Characteristic::Kloss {
                breakdown,
                synchronous,
                critical_slip,
            } => {
                let s = (synchronous - w) / synchronous;
                let sk = *critical_slip;
                let d = s * s + sk * sk;
                let m = 2.0 * breakdown * s * sk / d;
                let dm_ds = 2.0 * breakdown * sk * (sk * sk - s * s) / (d * d);
                (m, -dm_ds / synchronous)
            }
            Characteristic::Table { speed, torque } => {
                let n = speed.len();
                // The segment holding w (the end segments beyond the table).
                let j = match speed.partition_point(|&v| v <= w) {
                    0 => 0,
                    p if p >= n => n - 2,
                    p => p - 1,
                };
                let slope = (torque[j + 1] - torque[j]) / (speed[j + 1] - speed[j]);
                (torque[j] + slope * (w - speed[j]), slope)
            }
        }
    }

    /// The highest speed at which it can still drive [rad/s] (the top of the
    /// search for the equilibrium speed); None for a constant torque.
    fn top_speed(&self) -> Option<f64> {
        match self {
            Characteristic::Constant { .. } => None,
            Characteristic::Linear { no_load, .. } => Some(*no_load),
            Characteristic::Kloss { synchronous, .. } => Some(*synchronous),
            Characteristic::Table { speed, .. } => speed.last().copied(),
        }
    }
}

impl Motor {
    /// Check every parameter: a typed error naming the first bad one.
    pub fn check(&self) -> Result<(), DriveError> {
        if !(self.ratio.is_finite() && self.ratio > 0.0) {
            return Err(bad(
                "ratio",
                self.ratio,
                "must be finite and > 0 (motor speed / shaft speed)",
            ));
        }
        if !(self.efficiency.is_finite() && self.efficiency > 0.0 && self.efficiency <= 1.0) {
            return Err(bad("efficiency", self.efficiency, "must be in (0, 1]"));
        }
        match &self.characteristic {
            Characteristic::Constant { torque } => {
                if !torque.is_finite() {
                    return Err(bad("torque_nm", *torque, "[N·m] must be finite"));
                }
            }
            Characteristic::Linear { stall, no_load } => {
                if !(stall.is_finite() && *stall > 0.0) {
                    return Err(bad(
                        "stall_torque_nm",
                        *stall,
                        "[N·m] must be finite and > 0",
                    ));
                }
                if !(no_load.is_finite() && *no_load > 0.0) {
                    return Err(bad(
                        "no_load_speed",
                        *no_load,
                        "[rad/s] must be finite and > 0",
                    ));
                }
            }
            Characteristic::Kloss {
                breakdown,
                synchronous,
                critical_slip,
            } => {
                if !(breakdown.is_finite() && *breakdown > 0.0) {
                    return Err(bad(
                        "breakdown_torque_nm",
                        *breakdown,
                        "[N·m] must be finite and > 0",
                    ));
                }
                if !(synchronous.is_finite() && *synchronous > 0.0) {
                    return Err(bad(
                        "synchronous_speed",
                        *synchronous,
                        "[rad/s] must be finite and > 0",
                    ));
                }
                if !(critical_slip.is_finite() && *critical_slip > 0.0) {
                    return Err(bad(
                        "critical_slip",
                        *critical_slip,
                        "must be finite and > 0",
                    ));
                }
            }
            Characteristic::Table { speed, torque } => {
                if speed.len() < 2 || speed.len() != torque.len() {
                    return Err(bad(
                        "speed",
                        speed.len() as f64,
                        format!("points given; the table needs >= 2 (speed, torque) pairs, as many torques ({})", torque.len()),
                    ));
                }
                InvalidInput::check_finite("speed", speed)?;
                InvalidInput::check_finite("torque", torque)?;
                if let Some(k) = speed.windows(2).position(|w| w[1] <= w[0]) {
                    return Err(bad("speed", speed[k + 1], format!("(at index {}) must exceed the speed before it: the table's speeds increase strictly", k + 1)));
                }
            }
        }
        Ok(())
    }

    /// (shaft torque, its derivative in the shaft speed, motor torque) at the
    /// shaft speed `w` [rad/s].
    #[inline]
    pub(crate) fn on_shaft(&self, w: f64) -> (f64, f64, f64) {
        let (m, dm) = self.characteristic.torque(self.ratio * w);
        let g = if m >= 0.0 {
            self.ratio * self.efficiency
        } else {
            self.ratio / self.efficiency
        };
        (g * m, g * dm * self.ratio, m)
    }
}

/// The reduced machine on N samples over the turn (N even, ≥ 4): J [kg·m²],
/// J′ = dJ/dφ [kg·m²/rad] and Q [N·m], each at φ_k = 2πk/N.
#[derive(Debug, Clone, Copy)]
pub struct Curves<'a> {
    pub j: &'a [f64],
    pub dj: &'a [f64],
    pub q: &'a [f64],
}

impl Curves<'_> {
    /// Check the shapes, finiteness and J + `extra` > 0 everywhere.
    fn check(&self, extra: f64) -> Result<usize, DriveError> {
        let n = self.j.len();
        if n < 4 || !n.is_multiple_of(2) || self.dj.len() != n || self.q.len() != n {
            return Err(bad(
                "samples",
                n as f64,
                format!(
                    "must be even and >= 4, the same for J, dJ and Q (they have {}, {}, {})",
                    n,
                    self.dj.len(),
                    self.q.len()
                ),
            ));
        }
        InvalidInput::check_finite("inertia", self.j)?;
        InvalidInput::check_finite("d_inertia", self.dj)?;
        InvalidInput::check_finite("load_torque", self.q)?;
        if !(extra.is_finite() && extra >= 0.0) {
            return Err(bad("flywheel", extra, "[kg·m²] must be finite and >= 0"));
        }
        if let Some(k) = self
            .j
            .iter()
            .position(|&v| (v + extra).is_nan() || v + extra <= 0.0)
        {
            return Err(bad(
                "inertia",
                self.j[k] + extra,
                format!("[kg·m²] (with the constant inertias, at sample {k}) must be > 0: the machine needs some inertia"),
            ));
        }
        Ok(n)
    }
}

/// The steady state's outcome.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    /// A periodic solution to the tolerance.
    Periodic = 0,
    /// The motor's torque stays below the mean load torque at every speed.
    MotorTooWeak = 1,
    /// ω² reaches 0 within the cycle: the machine stalls.
    Stalls = 2,
    /// Newton did not reach the tolerance in the iterations allowed.
    NotConverged = 3,
    /// A constant torque that does not balance the mean load: the machine
    /// speeds up or slows down for ever.
    Unbalanced = 4,
}

/// [`Status`]'s words, by code.
pub const STEADY_STATUS: [&str; 5] = [
    "periodic",
    "the motor's torque is below the mean load torque at every speed",
    "the machine stalls: the speed reaches 0 within the cycle",
    "the shooting did not converge",
    "a constant torque that does not balance the mean load torque: no periodic speed",
];

/// The columns of [`steady_batch`]'s rows, in order.
pub const STEADY_COLUMNS: [&str; 12] = [
    "status",
    "iterations",
    "residual",
    "omega_start",
    "omega_mean",
    "omega_min",
    "omega_max",
    "delta",
    "period",
    "peak_motor_torque",
    "lowest_motor_torque",
    "rms_motor_torque",
];

/// Options of the steady state.
#[derive(Debug, Clone, Copy)]
pub struct SteadyOptions {
    /// Newton stops at |y(2π) − y(0)| ≤ tol·y(0) (relative, in ω²).
    pub tol: f64,
    pub max_iter: usize,
    /// The shaft speed [rad/s] a constant-torque motor runs at φ = 0 (its
    /// steady states form a family); ignored for the other motors.
    pub omega_start: f64,
}

/// One design's periodic steady state.
#[derive(Debug, Clone)]
pub struct Steady {
    pub status: Status,
    pub iterations: usize,
    /// |y(2π) − y(0)|/y(0) of the last shot.
    pub residual: f64,
    /// ω at the N samples [rad/s] (empty unless asked for, or not periodic).
    pub omega: Vec<f64>,
    /// t at the N samples from φ = 0 [s] (idem).
    pub time: Vec<f64>,
    /// The motor's torque at the N samples [N·m] (idem).
    pub motor_torque: Vec<f64>,
    /// [`STEADY_COLUMNS`] (NaN where not periodic).
    pub row: [f64; 12],
}

/// One RK4 pass over the cycle from y0; Err(()) when ω² reaches 0.
/// Returns (y at the even nodes and the end, t likewise, z at the end, slopes y′ at the nodes).
struct Pass {
    y: Vec<f64>,
    t: Vec<f64>,
    dy: Vec<f64>,
    z: f64,
}

/// The right-hand sides (y′, t′, z′) at sample `k`; `inv` is 1/(J + constant).
#[inline]
fn rhs(c: &Curves<'_>, inv: &[f64], motor: &Motor, k: usize, y: f64, z: f64) -> Option<[f64; 3]> {
    if y.is_nan() || y <= 0.0 {
        return None;
    }
    let w = y.sqrt();
    let iw = 1.0 / w;
    let (m, dm, _) = motor.on_shaft(w);
    let (ij, dj) = (inv[k], c.dj[k]);
    Some([
        (2.0 * (m - c.q[k]) - dj * y) * ij,
        iw,
        (dm * iw - dj) * ij * z,
    ])
}

fn pass(c: &Curves<'_>, inv: &[f64], motor: &Motor, y0: f64, keep: bool) -> Option<Pass> {
    let n = c.j.len();
    let h = 2.0 * TAU / n as f64;
    let steps = n / 2;
    let cap = if keep { steps + 1 } else { 0 };
    let (mut ys, mut ts, mut dys) = (
        Vec::with_capacity(cap),
        Vec::with_capacity(cap),
        Vec::with_capacity(cap),
    );
    let (mut y, mut t, mut z) = (y0, 0.0, 1.0);
    for s in 0..steps {
        let (k0, k1, k2) = (2 * s, 2 * s + 1, (2 * s + 2) % n);
        let a = rhs(c, inv, motor, k0, y, z)?;
        if keep {
            ys.push(y);
            ts.push(t);
            dys.push(a[0]);
        }
        let b = rhs(c, inv, motor, k1, y + 0.5 * h * a[0], z + 0.5 * h * a[2])?;
        let d = rhs(c, inv, motor, k1, y + 0.5 * h * b[0], z + 0.5 * h * b[2])?;
        let e = rhs(c, inv, motor, k2, y + h * d[0], z + h * d[2])?;
        y += h / 6.0 * (a[0] + 2.0 * b[0] + 2.0 * d[0] + e[0]);
        t += h / 6.0 * (a[1] + 2.0 * b[1] + 2.0 * d[1] + e[1]);
        z += h / 6.0 * (a[2] + 2.0 * b[2] + 2.0 * d[2] + e[2]);
    }
    let end = rhs(c, inv, motor, 0, y, z)?;
    ys.push(y);
    ts.push(t);
    dys.push(end[0]);
    Some(Pass {
        y: ys,
        t: ts,
        dy: dys,
        z,
    })
}

/// The shaft speed [rad/s] where the motor's shaft torque equals `load` on the
/// falling (stable) side of its characteristic; None if it never reaches it.
fn equilibrium(motor: &Motor, load: f64) -> Option<f64> {
    let top = motor.characteristic.top_speed()? / motor.ratio;
    let f = |w: f64| motor.on_shaft(w).0 - load;
    // From the top speed down: the first speed where the torque reaches the load.
    let samples = 400;
    let mut hi = top;
    let mut f_hi = f(hi);
    if f_hi >= 0.0 {
        // A table that still drives at its last speed: search beyond it.
        let mut w = top;
        for _ in 0..60 {
            w *= 2.0;
            if f(w) < 0.0 {
                return bisect(&f, top, w);
            }
        }
        return None;
    }
    for i in (0..samples).rev() {
        let lo = top * i as f64 / samples as f64;
        let f_lo = f(lo);
        if f_lo >= 0.0 {
            return bisect(&f, lo, hi);
        }
        hi = lo;
        f_hi = f_lo;
    }
    let _ = f_hi;
    None
}

/// The root of `f` in [lo, hi] with f(lo) ≥ 0 > f(hi), by bisection.
fn bisect(f: &impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> Option<f64> {
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if f(mid) >= 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(0.5 * (lo + hi))
}

fn nan_row(status: Status, iterations: usize, residual: f64) -> [f64; 12] {
    let mut row = [f64::NAN; 12];
    row[0] = status as i32 as f64;
    row[1] = iterations as f64;
    row[2] = residual;
    row
}

/// The periodic steady state of one design: the machine `c` with the constant
/// inertia `extra` [kg·m²] (flywheel, motor and gears reduced to the shaft)
/// driven by `motor`; with `curves`, ω, t and the motor torque at every sample.
pub fn steady_state(
    c: &Curves<'_>,
    extra: f64,
    motor: &Motor,
    opt: &SteadyOptions,
    curves: bool,
) -> Result<Steady, DriveError> {
    let n = c.check(extra)?;
    motor.check()?;
    if !(opt.tol.is_finite() && opt.tol > 0.0 && opt.tol < 1.0) {
        return Err(bad("tol", opt.tol, "must be in (0, 1)"));
    }
    if opt.max_iter < 1 {
        return Err(bad("max_iter", opt.max_iter as f64, "must be >= 1"));
    }
    Ok(solve(c, n, extra, motor, opt, curves))
}

fn solve(
    c: &Curves<'_>,
    n: usize,
    extra: f64,
    motor: &Motor,
    opt: &SteadyOptions,
    curves: bool,
) -> Steady {
    let fail = |status, it, res| Steady {
        status,
        iterations: it,
        residual: res,
        omega: Vec::new(),
        time: Vec::new(),
        motor_torque: Vec::new(),
        row: nan_row(status, it, res),
    };
    let q_mean = c.q.iter().sum::<f64>() / n as f64;
    // 1/J once per design: each shot then multiplies (4 evaluations a step).
    let inv: Vec<f64> = c.j.iter().map(|j| 1.0 / (j + extra)).collect();
    let mut iterations = 0;
    let mut residual = f64::NAN;
    let found: Option<(f64, Pass)>;
    if let Characteristic::Constant { .. } = motor.characteristic {
        let w0 = opt.omega_start;
        if !(w0.is_finite() && w0 > 0.0) {
            return fail(Status::NotConverged, 0, f64::NAN);
        }
        let y0 = w0 * w0;
        iterations = 1;
        let Some(p) = pass(c, &inv, motor, y0, true) else {
            return fail(Status::Stalls, 1, f64::NAN);
        };
        residual = (p.y[p.y.len() - 1] - y0).abs() / y0;
        if residual > opt.tol {
            return fail(Status::Unbalanced, 1, residual);
        }
        found = Some((y0, p));
    } else {
        let Some(we) = equilibrium(motor, q_mean) else {
            return fail(Status::MotorTooWeak, 0, f64::NAN);
        };
        let mut y0 = (we * we).max(1e-300);
        let mut ok = None;
        let mut stalled = 0;
        while iterations < opt.max_iter {
            iterations += 1;
            let Some(p) = pass(c, &inv, motor, y0, true) else {
                // Too slow to carry the machine through its peak: try faster.
                stalled += 1;
                if stalled > 40 {
                    return fail(Status::Stalls, iterations, f64::NAN);
                }
                y0 *= 1.5;
                continue;
            };
            let f = p.y[p.y.len() - 1] - y0;
            residual = f.abs() / y0;
            if residual <= opt.tol {
                ok = Some((y0, p));
                break;
            }
            let d = p.z - 1.0;
            let mut next = if d.abs() > 1e-300 {
                y0 - f / d
            } else {
                f64::NAN
            };
            if !next.is_finite() {
                break;
            }
            // Keep Newton in (y0/4, 4·y0): ω² stays positive and a bad step is damped.
            next = next.clamp(0.25 * y0, 4.0 * y0);
            y0 = next;
        }
        let Some(v) = ok else {
            return fail(
                if stalled > 0 && residual.is_nan() {
                    Status::Stalls
                } else {
                    Status::NotConverged
                },
                iterations,
                residual,
            );
        };
        found = Some(v);
    }
    let (_, p) = found.expect("set above");
    // The odd samples by cubic Hermite: the midpoint of a step of 2Δφ.
    let h = 2.0 * TAU / n as f64;
    let mut y = vec![0.0; n];
    let mut t = vec![0.0; n];
    for s in 0..n / 2 {
        y[2 * s] = p.y[s];
        t[2 * s] = p.t[s];
        y[2 * s + 1] = 0.5 * (p.y[s] + p.y[s + 1]) + h / 8.0 * (p.dy[s] - p.dy[s + 1]);
        let (d0, d1) = (1.0 / p.y[s].sqrt(), 1.0 / p.y[s + 1].sqrt());
        t[2 * s + 1] = 0.5 * (p.t[s] + p.t[s + 1]) + h / 8.0 * (d0 - d1);
    }
    if y.iter().any(|&v| v.is_nan() || v <= 0.0) {
        return fail(Status::Stalls, iterations, residual);
    }
    let period = p.t[p.t.len() - 1];
    let omega: Vec<f64> = y.iter().map(|v| v.sqrt()).collect();
    let mt: Vec<f64> = omega.iter().map(|&w| motor.on_shaft(w).2).collect();
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for &w in &omega {
        lo = lo.min(w);
        hi = hi.max(w);
    }
    let mean = TAU / period;
    // RMS over time: dt = dφ/ω (the rectangle rule, spectrally exact on a periodic grid).
    let dphi = TAU / n as f64;
    let m2: f64 = mt.iter().zip(&omega).map(|(m, w)| m * m / w).sum::<f64>() * dphi;
    let (mut mlo, mut mhi) = (f64::INFINITY, f64::NEG_INFINITY);
    for &m in &mt {
        mlo = mlo.min(m);
        mhi = mhi.max(m);
    }
    let row = [
        Status::Periodic as i32 as f64,
        iterations as f64,
        residual,
        omega[0],
        mean,
        lo,
        hi,
        (hi - lo) / mean,
        period,
        mhi,
        mlo,
        (m2 / period).sqrt(),
    ];
    let keep = curves;
    Steady {
        status: Status::Periodic,
        iterations,
        residual,
        omega: if keep { omega } else { Vec::new() },
        time: if keep { t } else { Vec::new() },
        motor_torque: if keep { mt } else { Vec::new() },
        row,
    }
}

/// The steady state of D designs in parallel: design d adds `extra[d]` [kg·m²]
/// to J and is driven by `motors[d]`; rows of [`STEADY_COLUMNS`] into `out`
/// (row-major (D, 12)).
pub fn steady_batch(
    c: &Curves<'_>,
    extra: &[f64],
    motors: &[Motor],
    opt: &SteadyOptions,
    out: &mut [f64],
    n_threads: Option<i64>,
) -> Result<(), DriveError> {
    if extra.len() != motors.len() {
        return Err(bad(
            "flywheel",
            extra.len() as f64,
            format!("values given; need one per motor ({})", motors.len()),
        ));
    }
    let low = extra.iter().copied().fold(f64::INFINITY, f64::min);
    let n = c.check(if extra.is_empty() { 0.0 } else { low })?;
    if let Some((i, &v)) = extra
        .iter()
        .enumerate()
        .find(|(_, v)| !(v.is_finite() && **v >= 0.0))
    {
        return Err(bad(
            "flywheel",
            v,
            format!("(design {i}) [kg·m²] must be finite and >= 0"),
        ));
    }
    for m in motors {
        m.check()?;
    }
    if !(opt.tol.is_finite() && opt.tol > 0.0 && opt.tol < 1.0) {
        return Err(bad("tol", opt.tol, "must be in (0, 1)"));
    }
    let cols = STEADY_COLUMNS.len();
    debug_assert_eq!(out.len(), motors.len() * cols);
    let pool = pool(resolve_threads(n_threads)?)?;
    pool.install(|| {
        out.par_chunks_mut(cols)
            .zip(extra.par_iter().zip(motors.par_iter()))
            .for_each(|(row, (&e, m))| {
                if !crate::cancel::requested() {
                    row.copy_from_slice(&solve(c, n, e, m, opt, false).row);
                }
            });
    });
    Ok(())
}

// ---------------------------------------------------------------- start-up

/// Options of the start-up.
#[derive(Debug, Clone, Copy)]
pub struct StartUpOptions {
    /// Relative tolerance of Dormand–Prince's error control.
    pub rtol: f64,
    /// Stop when |ω − ω_ss(φ)| ≤ settle·ω̄_ss for a whole turn (ω̄_ss = 2π/T,
    /// the time mean).
    pub settle: f64,
    /// Stop at this time at the latest [s].
    pub t_max: f64,
    /// Stop after this many accepted steps at the latest.
    pub max_steps: usize,
}

/// The start-up from rest.
#[derive(Debug, Clone)]
pub struct StartUp {
    /// 0: reached the steady state; 1: time or step limit; 2: cannot start
    /// (the speed turns negative).
    pub status: u8,
    pub t: Vec<f64>,
    pub phi: Vec<f64>,
    pub omega: Vec<f64>,
    pub motor_torque: Vec<f64>,
    /// When the speed entered the steady band for good [s] (NaN if it did not):
    /// the last crossing back into the band, found on the steps' continuous
    /// extensions (see [`Dense`], [`last_exit`]), not at a step's end.
    pub settle_time: f64,
}

/// Dormand–Prince 5(4)'s continuous extension of order 4 (Shampine 1986; the
/// `P` of scipy's `RK45` and of Hairer's `dopri5`): y(t0 + s·h) = y0 +
/// h·Σ_j q_j·s^(j+1), q = Kᵀ·P, from the step's seven stages. One order above a
/// cubic Hermite interpolant of the ends (whose O(h⁴) error in between blurred the
/// band's edge by ~1e-7 of ω̄ on a rippled start-up). `at(s)`, s ∈ [0, 1].
struct Dense {
    h: f64,
    y0: [f64; 2],
    y1: [f64; 2],
    q: [[f64; 4]; 2],
}

const DENSE_P: [[f64; 4]; 7] = [
    [
        1.0,
        -8048581381.0 / 2820520608.0,
        8663915743.0 / 2820520608.0,
        -12715105075.0 / 11282082432.0,
    ],
    [0.0; 4],
    [
        0.0,
        131558114200.0 / 32700410799.0,
        -68118460800.0 / 10900136933.0,
        87487479700.0 / 32700410799.0,
    ],
    [
        0.0,
        -1754552775.0 / 470086768.0,
        14199869525.0 / 1410260304.0,
        -10690763975.0 / 1880347072.0,
    ],
    [
        0.0,
        127303824393.0 / 49829197408.0,
        -318862633887.0 / 49829197408.0,
        701980252875.0 / 199316789632.0,
    ],
    [
        0.0,
        -282668133.0 / 205662961.0,
        2019193451.0 / 616988883.0,
        -1453857185.0 / 822651844.0,
    ],
    [
        0.0,
        40617522.0 / 29380423.0,
        -110615467.0 / 29380423.0,
        69997945.0 / 29380423.0,
    ],
];

impl Dense {
    fn new(h: f64, y0: [f64; 2], y1: [f64; 2], k: &[[f64; 2]; 7]) -> Dense {
        let mut q = [[0.0; 4]; 2];
        for (c, qc) in q.iter_mut().enumerate() {
            for (j, qj) in qc.iter_mut().enumerate() {
                *qj = k.iter().zip(&DENSE_P).map(|(ki, p)| ki[c] * p[j]).sum();
            }
        }
        Dense { h, y0, y1, q }
    }

    /// (φ, ω) at fraction `s` of the step.
    fn at(&self, s: f64) -> (f64, f64) {
        if s == 1.0 {
            return (self.y1[0], self.y1[1]);
        }
        let c = |i: usize| {
            let q = &self.q[i];
            self.y0[i] + self.h * s * (q[0] + s * (q[1] + s * (q[2] + s * q[3])))
        };
        (c(0), c(1))
    }
}

/// Samples a start-up step is checked at for an excursion out of the settle band
/// (its ends and 7 points between: an excursion between two steps' ends is
/// found where it spans an eighth of a step).
const BAND_SAMPLES: usize = 8;

/// The last fraction s ∈ (0, 1] of a step at which `outside(s)` holds, where
/// the speed was outside the band: 1 if it is at the step's end, else the
/// crossing back into the band after the last sample outside, by bisection to
/// 2⁻⁴⁰ of the step; None if no sample, its start included, is outside.
fn last_exit(outside: &impl Fn(f64) -> bool) -> Option<f64> {
    if outside(1.0) {
        return Some(1.0);
    }
    let m = BAND_SAMPLES;
    let (lo, hi) = (0..m)
        .rev()
        .map(|j| (j as f64 / m as f64, (j + 1) as f64 / m as f64))
        .find(|&(a, _)| outside(a))?;
    let (mut a, mut b) = (lo, hi);
    for _ in 0..37 {
        let mid = 0.5 * (a + b);
        if outside(mid) {
            a = mid;
        } else {
            b = mid;
        }
    }
    Some(0.5 * (a + b))
}

/// Where an angle falls among a spline's samples: the sample before it, the one
/// after (wrapping), and the Hermite weights of their values and slopes.
pub(crate) struct Cell {
    k: usize,
    k1: usize,
    w: [f64; 4],
}

/// Periodic cubic Hermite interpolation of a sampled curve, slopes by fourth-order
/// central differences.
pub(crate) struct Spline {
    v: Vec<f64>,
    d: Vec<f64>,
    h: f64,
}

impl Spline {
    pub(crate) fn new(v: &[f64]) -> Self {
        let n = v.len();
        let h = TAU / n as f64;
        let d = (0..n)
            .map(|k| {
                let at = |o: isize| v[((k as isize + o).rem_euclid(n as isize)) as usize];
                (at(-2) - 8.0 * at(-1) + 8.0 * at(1) - at(2)) / (12.0 * h)
            })
            .collect();
        Spline {
            v: v.to_vec(),
            d,
            h,
        }
    }

    /// The cell of `phi` [rad] (any turn) and its Hermite weights; one cell
    /// serves every spline on the same samples.
    #[inline]
    pub(crate) fn locate(&self, phi: f64) -> Cell {
        let n = self.v.len();
        let nf = n as f64;
        let mut s = phi / self.h;
        // Most angles are within a turn of the grid: a compare is cheaper than a
        // remainder.
        if s < 0.0 {
            s += nf;
        } else if s >= nf {
            s -= nf;
        }
        if !(0.0..nf).contains(&s) {
            s = s.rem_euclid(nf);
        }
        let k = (s.floor() as usize).min(n - 1);
        let u = s - k as f64;
        let (u2, u3) = (u * u, u * u * u);
        Cell {
            k,
            k1: if k + 1 == n { 0 } else { k + 1 },
            w: [
                2.0 * u3 - 3.0 * u2 + 1.0,
                (u3 - 2.0 * u2 + u) * self.h,
                -2.0 * u3 + 3.0 * u2,
                (u3 - u2) * self.h,
            ],
        }
    }

    /// The value in the cell `c` (of [`Spline::locate`] on a spline of as many samples).
    #[inline]
    pub(crate) fn at_cell(&self, c: &Cell) -> f64 {
        c.w[0] * self.v[c.k] + c.w[1] * self.d[c.k] + c.w[2] * self.v[c.k1] + c.w[3] * self.d[c.k1]
    }

    #[inline]
    pub(crate) fn at(&self, phi: f64) -> f64 {
        self.at_cell(&self.locate(phi))
    }
}

/// The start-up from rest (φ = 0, ω = 0) of the machine `c` with the constant
/// inertia `extra`, driven by `motor`; `steady` is its steady ω at the N samples
/// (from [`steady_state`]), the target the start-up settles on.
pub fn start_up(
    c: &Curves<'_>,
    extra: f64,
    motor: &Motor,
    steady: &[f64],
    opt: &StartUpOptions,
) -> Result<StartUp, DriveError> {
    let n = c.check(extra)?;
    motor.check()?;
    if steady.len() != n {
        return Err(bad(
            "steady",
            steady.len() as f64,
            format!("values given; need one per sample ({n})"),
        ));
    }
    InvalidInput::check_finite("steady", steady)?;
    if let Some(&w) = steady.iter().find(|&&w| w <= 0.0) {
        return Err(bad("steady", w, "[rad/s]: a steady speed must be > 0"));
    }
    if !(opt.rtol.is_finite() && opt.rtol >= 1e-14 && opt.rtol < 1.0) {
        return Err(bad("rtol", opt.rtol, "must be in [1e-14, 1)"));
    }
    if !(opt.settle.is_finite() && opt.settle > 0.0) {
        return Err(bad("settle", opt.settle, "must be finite and > 0"));
    }
    if !(opt.t_max.is_finite() && opt.t_max > 0.0) {
        return Err(bad("t_max", opt.t_max, "[s] must be finite and > 0"));
    }
    let jj: Vec<f64> = c.j.iter().map(|v| v + extra).collect();
    let (sj, sdj, sq) = (Spline::new(&jj), Spline::new(c.dj), Spline::new(c.q));
    // The steady state's time-mean speed 2π/T (T = ∮dφ/ω, the rectangle rule:
    // spectrally exact on the periodic grid), the ω̄ its result reports: the band
    // and the speed's absolute tolerance are relative to it. (The mean of the
    // samples over the angle is larger by about δ²/8 — 1.2 % at δ = 0.32.)
    let w_ref = n as f64 / steady.iter().map(|w| 1.0 / w).sum::<f64>();
    let f = |phi: f64, w: f64| -> [f64; 2] {
        let m = motor.on_shaft(w).0;
        [w, (m - sq.at(phi) - 0.5 * sdj.at(phi) * w * w) / sj.at(phi)]
    };
    // ω_ss between its samples as J, J′ and Q: periodic cubic Hermite, O(h⁴) (a
    // straight line between samples was off by ~h²·ω″/8, 1e-7 of ω̄ at 3600
    // samples and δ = 0.3: the band's edge blurred by that much).
    let sw = Spline::new(steady);
    let lookup = |phi: f64| -> f64 { sw.at(phi) };
    // Dormand–Prince 5(4).
    const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
    const A: [[f64; 6]; 7] = [
        [0.0; 6],
        [0.2, 0.0, 0.0, 0.0, 0.0, 0.0],
        [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
        [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
        [
            19372.0 / 6561.0,
            -25360.0 / 2187.0,
            64448.0 / 6561.0,
            -212.0 / 729.0,
            0.0,
            0.0,
        ],
        [
            9017.0 / 3168.0,
            -355.0 / 33.0,
            46732.0 / 5247.0,
            49.0 / 176.0,
            -5103.0 / 18656.0,
            0.0,
        ],
        [
            35.0 / 384.0,
            0.0,
            500.0 / 1113.0,
            125.0 / 192.0,
            -2187.0 / 6784.0,
            11.0 / 84.0,
        ],
    ];
    const E: [f64; 7] = [
        71.0 / 57600.0,
        0.0,
        -71.0 / 16695.0,
        71.0 / 1920.0,
        -17253.0 / 339200.0,
        22.0 / 525.0,
        -1.0 / 40.0,
    ];
    let _ = C;
    let atol = [opt.rtol, opt.rtol * w_ref.max(1e-9)];
    let (mut t, mut y) = (0.0, [0.0f64, 0.0f64]);
    let mut out = StartUp {
        status: 1,
        t: vec![0.0],
        phi: vec![0.0],
        omega: vec![0.0],
        motor_torque: vec![motor.on_shaft(0.0).2],
        settle_time: f64::NAN,
    };
    // A first step from the start's acceleration: a small fraction of the time to gain ω_ref.
    let a0 = f(0.0, 0.0)[1];
    let mut h = if a0 > 0.0 { 1e-3 * w_ref / a0 } else { 1e-6 };
    h = h.clamp(1e-12, opt.t_max);
    let mut k = [[0.0f64; 2]; 7];
    k[0] = f(y[0], y[1]);
    let mut last_out = 0.0; // the last time the speed was outside the band
    let mut phi_out = 0.0;
    let band = opt.settle * w_ref;
    let mut steps = 0usize;
    while t < opt.t_max && steps < opt.max_steps {
        if crate::cancel::requested() {
            break;
        }
        h = h.min(opt.t_max - t);
        for s in 1..7 {
            let mut yy = y;
            for (i, ki) in k.iter().enumerate().take(s) {
                yy[0] += h * A[s][i] * ki[0];
                yy[1] += h * A[s][i] * ki[1];
            }
            k[s] = f(yy[0], yy[1]);
        }
        let mut ynew = y;
        for (i, ki) in k.iter().enumerate().take(6) {
            ynew[0] += h * A[6][i] * ki[0];
            ynew[1] += h * A[6][i] * ki[1];
        }
        let mut err: f64 = 0.0;
        for c in 0..2 {
            let e: f64 = k.iter().zip(E).map(|(ki, e)| e * ki[c]).sum::<f64>() * h;
            let sc = atol[c] + opt.rtol * y[c].abs().max(ynew[c].abs());
            err = err.max((e / sc).abs());
        }
        if !err.is_finite() {
            h *= 0.1;
            if h < 1e-300 {
                break;
            }
            continue;
        }
        if err <= 1.0 {
            let step = Dense::new(h, y, ynew, &k);
            let t0 = t;
            t += h;
            y = ynew;
            k[0] = k[6]; // first same as last
            steps += 1;
            out.t.push(t);
            out.phi.push(y[0]);
            out.omega.push(y[1]);
            out.motor_torque.push(motor.on_shaft(y[1]).2);
            if y[1] < -1e-9 * w_ref {
                out.status = 2;
                return Ok(out);
            }
            let outside = |s: f64| {
                let (phi, w) = step.at(s);
                (w - lookup(phi)).abs() > band
            };
            if let Some(s) = last_exit(&outside) {
                // The speed was outside the band in this step: from where it last
                // came back in, it must stay in for a whole turn.
                last_out = t0 + s * h;
                phi_out = if s == 1.0 { y[0] } else { step.at(s).0 };
            }
            if !outside(1.0) && y[0] - phi_out >= TAU && last_out > 0.0 {
                out.status = 0;
                out.settle_time = last_out;
                return Ok(out);
            }
        }
        let fac = if err == 0.0 {
            5.0
        } else {
            (0.9 * err.powf(-0.2)).clamp(0.2, 5.0)
        };
        h *= if err <= 1.0 { fac } else { fac.min(1.0) };
    }
    Ok(out)
}
