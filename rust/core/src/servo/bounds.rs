//! The smallest phase angle of a servo segment: the cyclogram's bound (issue 33,
//! item 3).
//!
//! A rest-to-rest segment whose shape scales with its angle β (a named law or a
//! polynomial: `motion::Program::unit_law`) moves the load shaft by H [rad]
//! along H·Z(u), u = (θ − θ₀)/β, so that φ_L′ = H·Z′(u)/β and
//! φ_L″ = H·Z″(u)/β². With t = 1/β², at master speed ω each sample u gives the
//! motor torque as a function of t (module docs of `servo` for the drive):
//!
//!   T_m(u; t) = J·i·H·Z″·ω²·t + T_L(u; t)·(1/(i·η) or η/i),
//!   T_L(u; t) = J_L·H·Z″·ω²·t + T_ext,
//!
//! linear in t but for the efficiency's kink where T_L changes sign (the side
//! of the power flow: T_L·Z′·H ≥ 0 motoring or holding, else regenerating).
//!
//! **The bound rule**, as the cams': the smallest β such that the motor's peak
//! torque holds at every β′ ≥ β — the first t ≥ 0 at which some sample's
//! |T_m| exceeds the peak, found exactly on each linear piece (a window of
//! admissible angles below a violation is ignored). NaN when even a segment
//! lasting forever (t = 0: the static torque) exceeds the peak; 0 when no angle
//! does. The speed: the motor's peak speed i·|H|·max|Z′|·ω/β reaches its
//! maximum speed at β = i·|H|·max|Z′|·ω/ω_max. The RMS torque couples every
//! segment of the cycle: it is the duty's check on the timing, not a bound of
//! one segment.

use super::ServoError;
use crate::input::InvalidInput;
use crate::motion::Law;

/// Intervals per piece of a segment's law in [`law_samples`]: the peak torque's
/// error is quadratic in the spacing (below 1e-5 relative).
pub const BOUND_SAMPLES: usize = 1024;

/// Z′ and Z″ of a law on the unit square at [`BOUND_SAMPLES`] intervals per
/// piece, each piece's start taken just inside it (where Z″ may jump), for a
/// [`Shape`].
pub fn law_samples(law: &Law) -> (Vec<f64>, Vec<f64>) {
    let mut x = Vec::with_capacity(law.segments.len() * (BOUND_SAMPLES + 1));
    for s in &law.segments {
        let d = (s.x1 - s.x0) / BOUND_SAMPLES as f64;
        x.push(s.x0 + 1e-12 * (s.x1 - s.x0));
        x.extend((1..=BOUND_SAMPLES).map(|j| s.x0 + d * j as f64));
    }
    let dz = x.iter().map(|&u| law.z(u, 1)).collect();
    let ddz = x.iter().map(|&u| law.z(u, 2)).collect();
    (dz, ddz)
}

/// The trapezoid weights on u ∈ [0, 1] of [`law_samples`]' samples (summing
/// to 1): half an interval at each piece's ends, a whole one inside.
pub fn law_weights(law: &Law) -> Vec<f64> {
    let mut w = Vec::with_capacity(law.segments.len() * (BOUND_SAMPLES + 1));
    for s in &law.segments {
        trapezoid(&mut w, (s.x1 - s.x0) / BOUND_SAMPLES as f64, BOUND_SAMPLES);
    }
    w
}

/// `n` intervals of width `d`: n + 1 trapezoid weights.
fn trapezoid(w: &mut Vec<f64>, d: f64, n: usize) {
    w.push(0.5 * d);
    w.extend(std::iter::repeat_n(d, n - 1));
    w.push(0.5 * d);
}

/// The criteria of [`min_angles_into`]'s rows, in order.
pub const BOUND_CRITERIA: [&str; 2] = ["peak_torque", "speed"];

/// A drive for the bounds: the load at its shaft, the gearbox and the motor.
#[derive(Debug, Clone, Copy)]
pub struct Drive {
    /// J_L [kg·m²] and T_ext [N·m] at the load shaft.
    pub load_inertia: f64,
    pub load_torque: f64,
    /// η of screw and gearbox together, in (0, 1].
    pub efficiency: f64,
    /// i = motor speed / load speed (> 0).
    pub ratio: f64,
    /// J = J_motor + J_gearbox [kg·m²] at the motor shaft.
    pub drive_inertia: f64,
    /// The motor's peak torque [N·m] and maximum speed [rad/s] (> 0).
    pub peak_torque: f64,
    pub max_speed: f64,
}

/// One segment's shape: Z′ and Z″ of its unit law at samples of u ∈ [0, 1],
/// max |Z′| (exact), and its stroke at the load shaft H [rad].
#[derive(Debug, Clone, Copy)]
pub struct Shape<'a> {
    pub dz: &'a [f64],
    pub ddz: &'a [f64],
    pub dz_max: f64,
    pub stroke: f64,
}

/// The smallest angles [rad] of one segment at each master speed `omegas`
/// [rad/s]: rows of ([`BOUND_CRITERIA`]) into `out` (speeds × 2).
pub fn min_angles_into(
    shape: &Shape<'_>,
    drive: &Drive,
    omegas: &[f64],
    out: &mut [f64],
) -> Result<(), ServoError> {
    check(shape, drive)?;
    super::positive_entries("omega", omegas)?;
    debug_assert_eq!(out.len(), 2 * omegas.len());
    for (row, &w) in out.chunks_mut(2).zip(omegas) {
        row[0] = torque_angle(shape, drive, w);
        row[1] = drive.ratio * shape.stroke.abs() * shape.dz_max * w / drive.max_speed;
    }
    Ok(())
}

/// Samples per segment in [`speed_limit`]'s callers: the intervals of a
/// fixed-shape segment's span at which its φ_L′ and φ_L″ are taken.
pub const LIMIT_SAMPLES: usize = 4096;

/// The highest master speeds [rad/s] a motion of fixed shape allows (a
/// segment whose angle the cyclogram does not set: moving ends, a constant
/// velocity, a point table): (peak torque, speed).
///
/// `dz`, `ddz` are the load shaft's φ_L′ and φ_L″ per radian of master at
/// samples of the motion. At master speed ω its accelerations are φ_L″·ω², so
/// with t = ω² the motor torque is the module's T_m(u; t) for a unit angle
/// (β = 1): the peak-torque limit is √t* with t* the first t ≥ 0 at which a
/// sample's |T_m| exceeds the peak, the same rule as the bound's (every
/// speed below the limit holds); 0 when the static torque alone exceeds it, inf
/// when no speed does. The speed limit is ω_max/(i·max|φ_L′|) (inf standing).
pub fn speed_limit(dz: &[f64], ddz: &[f64], drive: &Drive) -> Result<(f64, f64), ServoError> {
    if dz.len() != ddz.len() {
        return Err(InvalidInput::bad_value(
            "ddz",
            ddz.len() as f64,
            "must have one entry per dz sample",
        )
        .into());
    }
    let dz_max = dz.iter().fold(0.0_f64, |m, &x| m.max(x.abs()));
    let shape = Shape {
        dz,
        ddz,
        dz_max,
        stroke: 1.0,
    };
    check(&shape, drive)?;
    let beta = torque_angle(&shape, drive, 1.0);
    let torque = if beta.is_nan() {
        0.0
    } else if beta == 0.0 {
        f64::INFINITY
    } else {
        1.0 / beta
    };
    let speed = if dz_max == 0.0 {
        f64::INFINITY
    } else {
        drive.max_speed / (drive.ratio * dz_max)
    };
    Ok((torque, speed))
}

/// The load shaft's φ_L′ and φ_L″ per radian of master (the program's s′ and s″
/// times `shaft`, its radians per program unit) on a program's `segments` at
/// [`LIMIT_SAMPLES`] intervals per piece, each piece's ends taken just inside
/// it (where φ″ may jump), and their trapezoid weights [rad of master], for
/// [`speed_limit`] and the RMS bound. Unknown segment indices are skipped (the
/// caller names them).
pub fn segment_samples(
    program: &crate::motion::Program,
    segments: &[usize],
    shaft: f64,
) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let (mut v, mut a, mut w) = (Vec::new(), Vec::new(), Vec::new());
    for (k, x0, x1, ..) in program.pieces() {
        if !segments.contains(&k) {
            continue;
        }
        let d = (x1 - x0) / LIMIT_SAMPLES as f64;
        trapezoid(&mut w, d, LIMIT_SAMPLES);
        let at = std::iter::once(x0 + 1e-12 * (x1 - x0))
            .chain((1..LIMIT_SAMPLES).map(|j| x0 + d * j as f64))
            .chain(std::iter::once(x1 - 1e-12 * (x1 - x0)));
        for t in at {
            let e = program.eval(t);
            v.push(shaft * e[1]);
            a.push(shaft * e[2]);
        }
    }
    (v, a, w)
}

/// The motor torque [N·m] at the load shaft's acceleration `acc` [rad/s²]
/// with its velocity's sign that of `moving` (module docs: the efficiency on the
/// side of the power flow, a load at rest held on the motoring side).
pub(super) fn motor_torque(d: &Drive, acc: f64, moving: f64) -> f64 {
    let tl = d.load_inertia * acc + d.load_torque;
    let out = if tl * moving < 0.0 {
        tl * d.efficiency / d.ratio
    } else {
        tl / (d.ratio * d.efficiency)
    };
    d.drive_inertia * d.ratio * acc + out
}

fn check(shape: &Shape<'_>, d: &Drive) -> Result<(), InvalidInput> {
    InvalidInput::check_finite("dz", shape.dz)?;
    InvalidInput::check_finite("ddz", shape.ddz)?;
    if !shape.stroke.is_finite() || !shape.dz_max.is_finite() {
        return Err(InvalidInput::bad_value(
            "stroke",
            shape.stroke,
            "must be finite (and the max |Z′| too)",
        ));
    }
    check_drive(d)
}

/// The drive's numbers in their ranges.
pub(super) fn check_drive(d: &Drive) -> Result<(), InvalidInput> {
    let positive = [
        ("ratio", d.ratio, "must be finite and > 0"),
        ("peak_torque", d.peak_torque, "[N·m] must be finite and > 0"),
        ("max_speed", d.max_speed, "[rad/s] must be finite and > 0"),
    ];
    for (field, v, why) in positive {
        if !(v.is_finite() && v > 0.0) {
            return Err(InvalidInput::bad_value(field, v, why));
        }
    }
    for (field, v) in [
        ("load_inertia", d.load_inertia),
        ("drive_inertia", d.drive_inertia),
    ] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(InvalidInput::bad_value(
                field,
                v,
                "[kg·m²] must be finite and >= 0",
            ));
        }
    }
    if !d.load_torque.is_finite() {
        return Err(InvalidInput::bad_value(
            "load_torque",
            d.load_torque,
            "[N·m] must be finite",
        ));
    }
    if !(d.efficiency > 0.0 && d.efficiency <= 1.0) {
        return Err(InvalidInput::bad_value(
            "efficiency",
            d.efficiency,
            "must be in (0, 1]",
        ));
    }
    Ok(())
}

/// The peak-torque bound at master speed `w` (module docs): 1/√t* with t* the
/// first t ≥ 0 where a sample's |T_m| exceeds the peak.
fn torque_angle(shape: &Shape<'_>, d: &Drive, w: f64) -> f64 {
    let w2 = w * w;
    let (i, eta, limit) = (d.ratio, d.efficiency, d.peak_torque);
    let mut first = f64::INFINITY;
    for (&z1, &z2) in shape.dz.iter().zip(shape.ddz) {
        let acc = shape.stroke * z2 * w2; // φ_L″ per t
        let moving = shape.stroke * z1; // the sign of φ_L′
        let (p, q) = (d.load_inertia * acc, d.load_torque); // T_L = p·t + q
        let inertia = d.drive_inertia * i * acc;
        let tm = |t: f64| {
            let tl = p * t + q;
            let out = if tl * moving < 0.0 {
                tl * eta / i
            } else {
                tl / (i * eta)
            };
            inertia * t + out
        };
        // The pieces of t ≥ 0 between the kink (T_L = 0) and infinity.
        let kink = if p != 0.0 { -q / p } else { f64::NAN };
        let mut edges = vec![0.0];
        if kink > 0.0 && kink.is_finite() {
            edges.push(kink);
        }
        edges.push(f64::INFINITY);
        for piece in edges.windows(2) {
            let (a, b) = (piece[0], piece[1]);
            if a >= first {
                break;
            }
            let fa = tm(a);
            if fa.abs() > limit {
                first = first.min(a);
                break;
            }
            // The slope on this piece, from a point inside it.
            let probe = if b.is_finite() {
                0.5 * (a + b)
            } else {
                a + 1.0
            };
            let slope = (tm(probe) - fa) / (probe - a);
            let cross = if slope > 0.0 {
                a + (limit - fa) / slope
            } else if slope < 0.0 {
                a + (-limit - fa) / slope
            } else {
                f64::INFINITY
            };
            if cross < b {
                first = first.min(cross);
                break;
            }
        }
    }
    if first == 0.0 {
        f64::NAN // the static torque alone exceeds the peak: no angle will do
    } else if first.is_infinite() {
        0.0
    } else {
        1.0 / first.sqrt()
    }
}
