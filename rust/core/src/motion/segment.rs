//! Motion segments with boundary conditions (VDI 2143): each law turned into
//! pieces s(t) = Σ c_k t^k + A·sin(ω t + φ) over a segment's angle, in the
//! program's own units (t [rad of master] from the segment's start, s [m or rad]).
//!
//! A segment has a law, an angle β and its boundary values at each end: position
//! s, velocity v = ds/dθ, acceleration a = d²s/dθ², jerk j = d³s/dθ³ (per radian
//! of master). The laws:
//!
//! - `dwell`: s = s0 (v = a = j = 0);
//! - `constant_velocity`: s = s0 + V·t (V from a given start or end velocity, or
//!   from the end position);
//! - the six named laws F on the unit square (`cycloidal`, `harmonic`,
//!   `modified_sine`, `modified_trapezoid`, `polynomial_345`, `polynomial_4567`),
//!   rest to rest: s = s0 + h·F(t/β). The first four also join moving ends
//!   (VDI 2143's rest–velocity, velocity–rest, velocity–velocity): the law's shape
//!   carries the change of velocity and the rest of the stroke,
//!   s = s0 + V0·t + (V1 − V0)·β·H(t/β) + K·F(t/β), H(x) = ∫₀ˣ F,
//!   K = h − V0·β − (V1 − V0)·β·H(1), so s′ = V0 + (V1 − V0)·F + (K/β)·F′ takes V0
//!   and V1 at the ends and s″ there is the law's own (0 but for the harmonic).
//!   With V0 = V1 = V this is the law superposed on a straight line (the
//!   sine–straight-line combination for the cycloid). The two polynomials stay
//!   rest to rest (for moving ends use `poly5` or `poly7`);
//! - `poly5` / `poly7`: the polynomial of degree 5 (7) through position, velocity
//!   and acceleration (and jerk) at both ends;
//! - `polynomial`: the polynomial through exactly the given end values (degree =
//!   their count − 1);
//! - `spline`: the interpolating spline of degree 3 or 5 through a point table.
//!
//! **Free values** (None) are resolved once, by one rule: a free start value is
//! the previous segment's end value (position; and velocity, acceleration, jerk
//! where the law takes them), 0 for the first segment; a free end value is what
//! the next segment (the first, after the last) fixes at its start (given there,
//! or fixed by its law: a dwell starts at rest, a constant velocity at its
//! velocity), else 0. **Given values
//! are checked**: a law that cannot meet a value the user gave is an error naming
//! the segment, the end, the order, the value given and the law's own.

use std::f64::consts::FRAC_PI_2;

use nalgebra::{DMatrix, DVector};

use super::law::{Fast, Law, MotionError, Segment as Piece};
use super::SplineEnd;
use crate::num_text::Num;

/// Laws a motion segment can take.
pub const SEGMENT_LAWS: [&str; 12] = [
    "dwell",
    "constant_velocity",
    "cycloidal",
    "harmonic",
    "modified_sine",
    "modified_trapezoid",
    "polynomial_345",
    "polynomial_4567",
    "poly5",
    "poly7",
    "polynomial",
    "spline",
];

/// Named laws that also join moving ends (module docs).
const VELOCITY_LAWS: [&str; 4] = [
    "cycloidal",
    "harmonic",
    "modified_sine",
    "modified_trapezoid",
];

/// Names of the boundary orders in messages.
pub const ORDER_NAMES: [&str; 4] = ["position", "velocity", "acceleration", "jerk"];

/// Relative tolerance on a given boundary value and on a join.
pub const BOUNDARY_TOL: f64 = 1e-9;

/// A segment as given: its law, angle [rad] and boundary values at each end
/// ([s, v, a, j], per radian of master; None = free), and for a spline its
/// point table ((angle from the segment's start [rad], s), first at 0, last at
/// the angle) and degree.
#[derive(Debug, Clone, PartialEq)]
pub struct SegmentSpec {
    pub law: String,
    pub angle: f64,
    pub start: [Option<f64>; 4],
    pub end: [Option<f64>; 4],
    pub points: Vec<[f64; 2]>,
    pub degree: usize,
}

/// What a law fixes at its start whatever its neighbours ([v, a, j]).
pub(super) fn law_fixed_start(spec: &SegmentSpec) -> [Option<f64>; 3] {
    match spec.law.as_str() {
        "dwell" => [Some(0.0); 3],
        "constant_velocity" => [spec.start[1].or(spec.end[1]), Some(0.0), Some(0.0)],
        "polynomial_345" | "polynomial_4567" => [Some(0.0), Some(0.0), None],
        "cycloidal" | "modified_sine" | "modified_trapezoid" => [None, Some(0.0), None],
        _ => [None; 3],
    }
}

/// The segment's error with its index and law.
pub(super) fn bad(index: usize, spec: &SegmentSpec, what: String) -> MotionError {
    MotionError::BadSegment {
        index,
        law: spec.law.clone(),
        what,
    }
}

/// Check a spec on its own: a known law, a finite angle > 0, finite given
/// values, a point table only for a spline.
pub(super) fn validate(index: usize, spec: &SegmentSpec) -> Result<(), MotionError> {
    if !SEGMENT_LAWS.contains(&spec.law.as_str()) {
        return Err(bad(
            index,
            spec,
            format!("unknown law; known laws: {}", SEGMENT_LAWS.join(", ")),
        ));
    }
    if !(spec.angle.is_finite() && spec.angle > 0.0) {
        return Err(bad(
            index,
            spec,
            format!("angle = {} [rad] must be finite and > 0", spec.angle),
        ));
    }
    for (end, values) in [("start", &spec.start), ("end", &spec.end)] {
        for (k, v) in values.iter().enumerate() {
            if let Some(v) = v.filter(|v| !v.is_finite()) {
                return Err(bad(
                    index,
                    spec,
                    format!("{end} {} = {v} must be finite or free", ORDER_NAMES[k]),
                ));
            }
        }
    }
    let spline = spec.law == "spline";
    if spline == spec.points.is_empty() {
        let what = if spline {
            "a spline needs its point table".to_string()
        } else {
            format!("points are for a spline, not a {} segment", spec.law)
        };
        return Err(bad(index, spec, what));
    }
    if spline && spec.degree != 3 && spec.degree != 5 {
        return Err(bad(
            index,
            spec,
            format!("degree = {} must be 3 or 5", spec.degree),
        ));
    }
    Ok(())
}

/// The pieces of segment `index` (t from its start), from its resolved start
/// values `s0` = [s, v, a, j] and end values `s1` (position resolved, others
/// as resolved by the program: given, the next segment's, or 0), and whether
/// its shape scales with its angle (rest to rest by a law that keeps its
/// shape: the same law stretched, as a cam's bound search assumes).
pub(super) fn pieces(
    index: usize,
    spec: &SegmentSpec,
    s0: [f64; 4],
    s1: [Option<f64>; 4],
) -> Result<(Vec<Piece>, bool), MotionError> {
    let beta = spec.angle;
    let need_end = || {
        s1[0].ok_or_else(|| {
            bad(
                index,
                spec,
                "its end position is required (end = (s, …))".to_string(),
            )
        })
    };
    let line = |c: Vec<f64>| {
        vec![Piece {
            x0: 0.0,
            x1: beta,
            poly: c,
            amp: 0.0,
            freq: 0.0,
            phase: 0.0,
        }]
    };
    match spec.law.as_str() {
        "dwell" => Ok((line(vec![s0[0]]), true)),
        "constant_velocity" => {
            // Given start v, given end v, the end position, else the
            // velocity it starts with (the previous segment's end).
            let v = match (spec.start[1], spec.end[1], spec.end[0]) {
                (Some(v), _, _) | (None, Some(v), _) => v,
                (None, None, Some(e)) => (e - s0[0]) / beta,
                (None, None, None) => s0[1],
            };
            Ok((line(vec![s0[0], v]), false))
        }
        "poly5" | "poly7" | "polynomial" => {
            let e = need_end()?;
            let mut conds = Vec::new();
            // s, v, a at each end for poly5; and j for poly7 and the general one.
            let orders = if spec.law == "poly5" { 3 } else { 4 };
            for k in 0..orders {
                let general = spec.law == "polynomial";
                let at0 = if general && k > 0 {
                    spec.start[k]
                } else {
                    Some(s0[k])
                };
                let at1 = if k == 0 {
                    Some(e)
                } else if general {
                    spec.end[k]
                } else {
                    Some(s1[k].unwrap_or(0.0))
                };
                conds.extend(at0.map(|v| (0.0, k, v)));
                conds.extend(at1.map(|v| (1.0, k, v)));
            }
            let rest = conds.iter().all(|&(_, k, v)| k == 0 || v == 0.0);
            let c = hermite(&conds, beta).map_err(|what| bad(index, spec, what))?;
            Ok((line(c), rest))
        }
        "spline" => Ok((spline_pieces(index, spec)?, false)),
        name => {
            let e = need_end()?;
            let rise = Law::rise(name)?;
            let moving = VELOCITY_LAWS.contains(&name);
            let (v0, v1) = if moving {
                (s0[1], s1[1].unwrap_or(0.0))
            } else {
                (0.0, 0.0)
            };
            let rest = v0 == 0.0 && v1 == 0.0;
            Ok((shaped(&rise, s0[0], e - s0[0], v0, v1, beta), rest))
        }
    }
}

/// The spline through the segment's point table (angles from its start, first
/// at 0, last at its angle), its end derivatives the values given at each end
/// (a quintic's velocity and acceleration together) or natural where free; a
/// segment over the whole cycle with free ends is periodic (about the line
/// through its first and last values, whose slope carries the advance).
fn spline_pieces(index: usize, spec: &SegmentSpec) -> Result<Vec<Piece>, MotionError> {
    let beta = spec.angle;
    let mut x: Vec<f64> = spec.points.iter().map(|p| p[0]).collect();
    let y: Vec<f64> = spec.points.iter().map(|p| p[1]).collect();
    let n = x.len();
    let tol = 1e-9 * beta;
    if x[0].abs() > tol || (x[n - 1] - beta).abs() > tol {
        return Err(bad(
            index,
            spec,
            format!(
                "its points must run from 0° to its angle {}°; they run from {}° to {}°",
                Num(beta.to_degrees()),
                Num(x[0].to_degrees()),
                Num(x[n - 1].to_degrees())
            ),
        ));
    }
    (x[0], x[n - 1]) = (0.0, beta);
    let end = |which: &str, given: &[Option<f64>; 4]| match (spec.degree, given[1], given[2]) {
        (3, None, _) | (5, None, None) => Ok(SplineEnd::Natural),
        (3, Some(v), _) => Ok(SplineEnd::Given(vec![v])),
        (_, Some(v), Some(a)) => Ok(SplineEnd::Given(vec![v, a])),
        _ => Err(bad(
            index,
            spec,
            format!(
                "a quintic spline's {which} takes its velocity and acceleration together, \
                 or neither (natural)"
            ),
        )),
    };
    let free = |g: &[Option<f64>; 4]| g[1].is_none() && g[2].is_none();
    let whole = (beta - std::f64::consts::TAU).abs() <= 1e-9 * std::f64::consts::TAU;
    let map = |e| match e {
        MotionError::BadLaw { what } => bad(index, spec, what),
        other => other,
    };
    if whole && free(&spec.start) && free(&spec.end) {
        // A table over the whole cycle with free ends runs into the next cycle:
        // periodic ends (s′ … s^(k−1) equal at both), about the straight line from
        // its first to its last value (a feed's advance per cycle: the slope adds
        // a constant velocity and nothing to the higher derivatives).
        let slope = (y[n - 1] - y[0]) / beta;
        let flat: Vec<f64> = x.iter().zip(&y).map(|(t, v)| v - slope * t).collect();
        let mut pieces = super::spline(
            &x,
            &flat,
            spec.degree,
            SplineEnd::Periodic,
            SplineEnd::Periodic,
        )
        .map_err(map)?;
        for p in &mut pieces {
            p.poly.resize(p.poly.len().max(2), 0.0);
            p.poly[0] += slope * p.x0;
            p.poly[1] += slope;
        }
        return Ok(pieces);
    }
    let (s0, s1) = (end("start", &spec.start)?, end("end", &spec.end)?);
    super::spline(&x, &y, spec.degree, s0, s1).map_err(map)
}

/// s = s0 + V0·t + (V1 − V0)·β·H(t/β) + K·F(t/β) (module docs) as pieces in t.
fn shaped(law: &Law, s0: f64, h: f64, v0: f64, v1: f64, beta: f64) -> Vec<Piece> {
    // H = ∫F piece by piece: ∫ Σ c_k u^k + A sin(ωu + φ) du from the piece's
    // start = H(x0) + Σ c_k u^(k+1)/(k+1) + (A/ω) cos φ + (A/ω) sin(ωu + φ − π/2).
    let mut h_at = 0.0;
    let mut h_pieces = Vec::with_capacity(law.segments.len());
    for p in &law.segments {
        let mut poly = vec![h_at];
        poly.extend(p.poly.iter().enumerate().map(|(k, c)| c / (k + 1) as f64));
        let (amp, phase) = if p.amp == 0.0 {
            (0.0, 0.0)
        } else {
            poly[0] += p.amp / p.freq * p.phase.cos();
            (p.amp / p.freq, p.phase - FRAC_PI_2)
        };
        let piece = Piece {
            x0: p.x0,
            x1: p.x1,
            poly,
            amp,
            freq: p.freq,
            phase,
        };
        h_at = Fast::new(&piece).eval(p.x1, 0);
        h_pieces.push(piece);
    }
    let dv = (v1 - v0) * beta;
    let k = h - v0 * beta - dv * h_at;
    law.segments
        .iter()
        .zip(&h_pieces)
        .map(|(f, hp)| {
            // In u = x − x0 (unit square): the sum of the three shapes.
            let n = f.poly.len().max(hp.poly.len()).max(2);
            let mut poly: Vec<f64> = (0..n)
                .map(|i| {
                    k * f.poly.get(i).copied().unwrap_or(0.0)
                        + dv * hp.poly.get(i).copied().unwrap_or(0.0)
                })
                .collect();
            poly[0] += s0 + v0 * beta * f.x0;
            poly[1] += v0 * beta;
            // Two sines of one frequency are one: a1 e^{iφ1} + a2 e^{iφ2} = R e^{iψ}.
            let (re, im) = (
                k * f.amp * f.phase.cos() + dv * hp.amp * hp.phase.cos(),
                k * f.amp * f.phase.sin() + dv * hp.amp * hp.phase.sin(),
            );
            let amp = re.hypot(im);
            let phase = if amp == 0.0 { 0.0 } else { im.atan2(re) };
            // t = β·u: c_k u^k = (c_k / β^k) t^k, sin(ω u + ψ) = sin((ω/β) t + ψ).
            let mut scale = 1.0;
            for c in &mut poly {
                *c /= scale;
                scale *= beta;
            }
            Piece {
                x0: f.x0 * beta,
                x1: f.x1 * beta,
                poly,
                amp,
                freq: if amp == 0.0 { 0.0 } else { f.freq / beta },
                phase,
            }
        })
        .collect()
}

/// The polynomial in t ∈ [0, β] meeting every condition (u, order, value) with
/// u ∈ {0, 1} the end (value per radian^order), of degree = conditions − 1;
/// solved in u = t/β (well scaled) and returned in t.
fn hermite(conds: &[(f64, usize, f64)], beta: f64) -> Result<Vec<f64>, String> {
    let n = conds.len();
    if n < 2 {
        return Err("a polynomial needs at least its two end positions".to_string());
    }
    let mut m = DMatrix::<f64>::zeros(n, n);
    let mut b = DVector::<f64>::zeros(n);
    for (row, &(u, order, value)) in conds.iter().enumerate() {
        for col in order..n {
            // d^order/du^order u^col = col!/(col − order)! u^(col − order).
            let falling: f64 = (0..order).map(|i| (col - i) as f64).product();
            m[(row, col)] = falling * u.powi((col - order) as i32);
        }
        b[row] = value * beta.powi(order as i32);
    }
    let c = m
        .lu()
        .solve(&b)
        .ok_or_else(|| "its end conditions do not determine a polynomial".to_string())?;
    let mut scale = 1.0;
    Ok(c.iter()
        .map(|&ck| {
            let v = ck / scale;
            scale *= beta;
            v
        })
        .collect())
}
