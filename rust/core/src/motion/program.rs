//! A motion program: segments over one master cycle (2π), free values
//! resolved, given values and joins checked, evaluated over angle grids.
//!
//! Position at any master angle θ: s(θ) = s_cycle(θ mod 2π) + advance·⌊θ/2π⌋,
//! so that an axis that moves on by `advance` each cycle (a film feed, a
//! rotating knife) is one program, and a cam (advance 0) repeats.

use std::f64::consts::TAU;

use rayon::prelude::*;

use super::law::{extreme, Fast, Law, MotionError, Segment as Piece};
use super::segment::{
    bad, law_fixed_start, pieces, validate, SegmentSpec, BOUNDARY_TOL, ORDER_NAMES,
};
use crate::parallel::{pool, resolve_threads};
use lanes::LaneFill;

mod lanes;

/// One piece of [`Program::pieces`]: (segment, start [rad], end [rad],
/// coefficients, A, ω, φ).
pub type PieceRow = (usize, f64, f64, Vec<f64>, f64, f64, f64);

/// Tolerance on the segments' angles summing to one cycle [rad].
pub const CYCLE_TOL: f64 = 1e-9 * TAU;

/// One segment of a built program.
#[derive(Debug, Clone)]
pub struct Span {
    /// Its start angle on the cycle [rad].
    pub start: f64,
    /// Its angle [rad].
    pub angle: f64,
    /// [s, v, a, j] at its start and at its end (as built).
    pub at_start: [f64; 4],
    pub at_end: [f64; 4],
    /// Its pieces' indices in the program: first..last.
    pub first: usize,
    pub last: usize,
    /// Does its shape scale with its angle (rest to rest, no point table), so
    /// that the segment at another angle is the same law stretched?
    pub scalable: bool,
    /// Where it runs backwards (against its stroke although neither end
    /// moves so): the angle [rad] of the worst reversal, and its velocity.
    pub backwards: Option<(f64, f64)>,
}

/// A validated motion program over one master cycle.
#[derive(Debug, Clone)]
pub struct Program {
    specs: Vec<SegmentSpec>,
    spans: Vec<Span>,
    /// Every piece, in absolute angle on [0, 2π], and their start angles.
    fast: Vec<Fast>,
    starts: Vec<f64>,
    advance: f64,
}

/// The characteristic values of one segment (VDI 2143): with h its stroke and
/// β its angle, C_v = max|s′|·β/|h|, C_a = max|s″|·β²/|h|, C_j = max|s‴|·β³/|h|,
/// C_m = max|s′·s″|·β³/h² (the dynamic torque's); NaN where h = 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Characteristics {
    pub stroke: f64,
    pub peaks: [f64; 3],
    pub cv: f64,
    pub ca: f64,
    pub cj: f64,
    pub cm: f64,
}

impl Program {
    /// Build a program: every segment validated, free values resolved (the
    /// rule of the `segment` module), given values checked, the angles summing
    /// to 2π and every join (the last to the first across `advance`) continuous
    /// up to the derivative `continuity` (0 position … 3 jerk).
    pub fn new(
        specs: &[SegmentSpec],
        continuity: usize,
        advance: f64,
    ) -> Result<Program, MotionError> {
        if specs.is_empty() {
            return Err(MotionError::BadLaw {
                what: "a program needs at least one segment".to_string(),
            });
        }
        if !advance.is_finite() {
            return Err(crate::input::InvalidInput::bad_value(
                "advance",
                advance,
                "[m or rad] must be finite",
            )
            .into());
        }
        if continuity > 3 {
            return Err(MotionError::BadLaw {
                what: format!(
                    "continuity = {continuity} must be 0 (position), 1 (velocity), 2 (acceleration) or 3 (jerk)"
                ),
            });
        }
        for (i, s) in specs.iter().enumerate() {
            validate(i, s)?;
        }
        let total: f64 = specs.iter().map(|s| s.angle).sum();
        if (total - TAU).abs() > CYCLE_TOL {
            return Err(MotionError::BadLaw {
                what: format!(
                    "the segments' angles sum to {}°, not 360°",
                    crate::num_text::Num(total.to_degrees())
                ),
            });
        }
        let mut program = Program {
            specs: specs.to_vec(),
            spans: Vec::with_capacity(specs.len()),
            fast: Vec::new(),
            starts: Vec::new(),
            advance,
        };
        let mut prev_end = [0.0; 4];
        let mut start = 0.0;
        for (i, spec) in specs.iter().enumerate() {
            let s0: [f64; 4] = std::array::from_fn(|k| spec.start[k].unwrap_or(prev_end[k]));
            // After the last segment comes the first (the cycle repeats).
            let next = specs.get((i + 1) % specs.len());
            let mut s1 = spec.end;
            for (k, v) in s1.iter_mut().enumerate().skip(1) {
                if v.is_none() {
                    *v = next.and_then(|n| n.start[k].or(law_fixed_start(n)[k - 1]));
                }
            }
            let local = pieces(i, spec, s0, s1)?;
            program.push(i, start, local)?;
            // The start values it was built from, where met to rounding, are
            // its values (joins then compare exact numbers).
            let span = &mut program.spans[i];
            let scale = span.at_end[0]
                .abs()
                .max(span.at_start[0].abs())
                .max(s0[0].abs());
            for (k, (v, want)) in span.at_start.iter_mut().zip(s0).enumerate() {
                let tol = BOUNDARY_TOL * (scale / spec.angle.powi(k as i32)).max(want.abs());
                if (*v - want).abs() <= tol {
                    *v = want;
                }
            }
            prev_end = program.spans[i].at_end;
            start += spec.angle;
        }
        program.check_joins(continuity)?;
        Ok(program)
    }

    /// Add segment `i` (its pieces in t from its start) at `start`, checking
    /// the values its spec gives at each end.
    fn push(
        &mut self,
        i: usize,
        start: f64,
        (local, scalable): (Vec<Piece>, bool),
    ) -> Result<(), MotionError> {
        let spec = &self.specs[i];
        let first = self.fast.len();
        for p in local {
            let abs = Piece {
                x0: start + p.x0,
                x1: start + p.x1,
                ..p
            };
            self.starts.push(abs.x0);
            self.fast.push(Fast::new(&abs));
        }
        let last = self.fast.len() - 1;
        let end = start + spec.angle;
        let mut at_start = self.fast[first].eval_all(start);
        let mut at_end = self.fast[last].eval_all(end);
        // The segment's scale of position: its stroke, its ends, and each
        // end derivative times β^k (a motion that returns to where it started).
        let scale = (0..4)
            .flat_map(|k| [at_start[k], at_end[k]].map(|v| v.abs() * spec.angle.powi(k as i32)))
            .fold((at_end[0] - at_start[0]).abs(), f64::max);
        // Rounding's crumbs at an end (a derivative of 1e-17 where the law
        // stops) are 0, so that the next segment starts truly at rest.
        for values in [&mut at_start, &mut at_end] {
            for (k, v) in values.iter_mut().enumerate().skip(1) {
                if v.abs() <= BOUNDARY_TOL * 1e-3 * scale / spec.angle.powi(k as i32) {
                    *v = 0.0;
                }
            }
        }
        for (which, given, law) in [
            ("start", &spec.start, &mut at_start),
            ("end", &spec.end, &mut at_end),
        ] {
            for k in 0..4 {
                let Some(g) = given[k] else { continue };
                let tol =
                    BOUNDARY_TOL * (scale / spec.angle.powi(k as i32)).max(g.abs()).max(1e-300);
                if (law[k] - g).abs() > tol {
                    // The law's own value, with rounding's crumbs shown as 0.
                    let own = if law[k].abs() <= tol { 0.0 } else { law[k] };
                    let hint = match spec.law.as_str() {
                        "polynomial_345" | "polynomial_4567" => {
                            " (this law is rest to rest; for moving ends use poly5 or poly7)"
                        }
                        "dwell" | "constant_velocity" => "",
                        _ if k >= 2 => " (for a given end acceleration or jerk use poly5 or poly7)",
                        _ => "",
                    };
                    return Err(bad(
                        i,
                        spec,
                        format!(
                            "the law cannot meet its {which} {} = {} (its own is {}){hint}",
                            ORDER_NAMES[k],
                            crate::num_text::Num(g),
                            crate::num_text::Num(own)
                        ),
                    ));
                }
                // Met to the tolerance: the value given is the value.
                law[k] = g;
            }
        }
        let h = at_end[0] - at_start[0];
        let sign = h.signum();
        // (A spline runs where its table goes: going back is the table's, and a
        // periodic table's stroke is 0 but for rounding.)
        let shaped = spec.law != "spline";
        let backwards =
            if shaped && h != 0.0 && sign * at_start[1] >= 0.0 && sign * at_end[1] >= 0.0 {
                let (x, worst) = extreme(&self.fast[first..=last], |p, x| -sign * p.eval(x, 1));
                let tol = BOUNDARY_TOL * h.abs() / spec.angle;
                (worst > tol).then_some((x, -sign * worst))
            } else {
                None
            };
        self.spans.push(Span {
            start,
            angle: spec.angle,
            at_start,
            at_end,
            first,
            last,
            scalable,
            backwards,
        });
        Ok(())
    }

    /// Every join continuous up to the derivative `order` (module docs).
    fn check_joins(&self, order: usize) -> Result<(), MotionError> {
        let n = self.spans.len();
        // Per order, the program's scale: the largest extent/β^k of its segments,
        // the extent a segment's stroke or an end value times β^m (so that a
        // segment that comes back to where it started still has its size).
        let extent = |s: &Span| {
            (0..4)
                .flat_map(|m| {
                    [s.at_start[m], s.at_end[m]].map(|v| v.abs() * s.angle.powi(m as i32))
                })
                .fold((s.at_end[0] - s.at_start[0]).abs(), f64::max)
        };
        let scale: [f64; 4] = std::array::from_fn(|k| {
            self.spans
                .iter()
                .map(|s| extent(s) / s.angle.powi(k as i32))
                .fold(1e-300, f64::max)
        });
        for i in 0..n {
            let j = (i + 1) % n;
            let (left, right) = (&self.spans[i], &self.spans[j]);
            for k in 0..=order {
                let mut from = left.at_end[k];
                if j == 0 && k == 0 {
                    from -= self.advance;
                }
                let to = right.at_start[k];
                let tol = BOUNDARY_TOL * scale[k];
                if (from - to).abs() > tol {
                    // Rounding's crumbs shown as 0.
                    let snap = |x: f64| if x.abs() <= tol { 0.0 } else { x };
                    let (from, to) = (snap(from), snap(to));
                    return Err(MotionError::Join {
                        left: i,
                        left_law: self.specs[i].law.clone(),
                        right: j,
                        right_law: self.specs[j].law.clone(),
                        // Degrees to 1e-9 (the sum of radians is not exact).
                        at_deg: ((left.start + left.angle).to_degrees() * 1e9).round() / 1e9,
                        what: ORDER_NAMES[k],
                        from,
                        to,
                    });
                }
            }
        }
        Ok(())
    }

    /// s + c·s″ over the whole program: the cam motion whose spring-mass
    /// follower (m, k) follows this program exactly at master speed ω when
    /// c = m·ω²/k (the polydyne cam: m·ÿ + k·(y − s) = 0 is met by y = this
    /// program's s). Every piece stays a polynomial plus a sine (the sine's
    /// amplitude becomes A·(1 − c·ω_p²)); its joins are checked to the
    /// derivative `continuity`, which the shifted motion keeps only where this
    /// program is continuous two derivatives higher.
    pub fn plus_second_derivative(
        &self,
        c: f64,
        continuity: usize,
    ) -> Result<Program, MotionError> {
        if !c.is_finite() {
            return Err(
                crate::input::InvalidInput::bad_value("c", c, "[rad²] must be finite").into(),
            );
        }
        let mut out = Program {
            specs: self.specs.clone(),
            spans: Vec::with_capacity(self.spans.len()),
            fast: Vec::with_capacity(self.fast.len()),
            starts: self.starts.clone(),
            advance: self.advance,
        };
        for f in &self.fast {
            let mut poly = f.poly[0].clone();
            for (k, &d2) in f.poly[2].iter().enumerate() {
                poly[k] += c * d2;
            }
            out.fast.push(Fast::new(&Piece {
                x0: f.x0,
                x1: f.x1,
                poly,
                amp: f.amp[0] * (1.0 - c * f.freq * f.freq),
                freq: f.freq,
                phase: f.phase[0],
            }));
        }
        for span in &self.spans {
            let end = span.start + span.angle;
            out.spans.push(Span {
                at_start: out.fast[span.first].eval_all(span.start),
                at_end: out.fast[span.last].eval_all(end),
                scalable: false,
                backwards: None,
                ..span.clone()
            });
        }
        out.check_joins(continuity)?;
        Ok(out)
    }

    /// Every piece as (segment index, start [rad], end [rad], polynomial
    /// coefficients c_k of s in t = θ − start [per rad^k], A, ω [per rad], φ):
    /// s = Σ c_k t^k + A·sin(ω t + φ) exactly (a drive's cam table rebuilt).
    pub fn pieces(&self) -> Vec<PieceRow> {
        let mut out = Vec::with_capacity(self.fast.len());
        for (i, span) in self.spans.iter().enumerate() {
            for f in &self.fast[span.first..=span.last] {
                out.push((
                    i,
                    f.x0,
                    f.x1,
                    f.poly[0].clone(),
                    f.amp[0],
                    f.freq,
                    f.phase[0],
                ));
            }
        }
        out
    }

    /// The segments as built.
    pub fn spans(&self) -> &[Span] {
        &self.spans
    }

    /// The segments as given.
    pub fn specs(&self) -> &[SegmentSpec] {
        &self.specs
    }

    /// Position gained per cycle [m or rad].
    pub fn advance(&self) -> f64 {
        self.advance
    }

    /// [s, v, a, j] at master angle θ [rad] (any real; module docs).
    #[inline]
    pub fn eval(&self, theta: f64) -> [f64; 4] {
        let (cycles, t) = if (0.0..TAU).contains(&theta) {
            (0.0, theta)
        } else {
            let c = (theta / TAU).floor();
            (c, (theta - c * TAU).clamp(0.0, TAU))
        };
        let k = self.starts.partition_point(|&x0| x0 <= t).max(1) - 1;
        let mut out = piece_all(&self.fast[k], t);
        if cycles != 0.0 {
            out[0] += cycles * self.advance;
        }
        out
    }

    /// [s, v, a, j] at every θ into the four rows of `out` (4 × N, row-major),
    /// on `n_threads` threads: bit for bit [`Program::eval`] at each θ, in SIMD
    /// lanes over the runs of a sorted grid that stay in one piece (the
    /// `lanes` module); a non-finite θ is an error naming the first.
    pub fn eval_into(
        &self,
        theta: &[f64],
        n_threads: Option<i64>,
        out: &mut [f64],
    ) -> Result<(), MotionError> {
        self.fill_rows(theta, n_threads, None, out)
    }

    /// [`Program::eval_into`] and a copy of θ into `copy` (N), written as the
    /// angles are read (cheaper than a separate copy, which reads them again).
    pub fn eval_with_theta_into(
        &self,
        theta: &[f64],
        n_threads: Option<i64>,
        copy: &mut [f64],
        out: &mut [f64],
    ) -> Result<(), MotionError> {
        let n = theta.len();
        if copy.len() != n {
            return Err(crate::input::InvalidInput::Output {
                field: "copy",
                want: format!("{n} values (the angles)"),
                got: format!("{} values", copy.len()),
            }
            .into());
        }
        self.fill_rows(theta, n_threads, Some(copy), out)
    }

    fn fill_rows(
        &self,
        theta: &[f64],
        n_threads: Option<i64>,
        mut copy: Option<&mut [f64]>,
        out: &mut [f64],
    ) -> Result<(), MotionError> {
        let n = theta.len();
        if out.len() != 4 * n {
            return Err(crate::input::InvalidInput::Output {
                field: "out",
                want: format!("4 × {n} values (s, v, a, j at each angle)"),
                got: format!("{} values", out.len()),
            }
            .into());
        }
        let threads = resolve_threads(n_threads)?;
        let (mut s, rest) = out.split_at_mut(n);
        let (mut v, rest) = rest.split_at_mut(n);
        let (mut a, mut j) = rest.split_at_mut(n);
        // Chunks of the rows, one job each; on one thread, one chunk.
        const CHUNK: usize = 8192;
        let size = if threads == 1 { n.max(1) } else { CHUNK };
        let mut jobs = Vec::with_capacity(n.div_ceil(size));
        for th in theta.chunks(size) {
            let m = th.len();
            jobs.push(LaneFill {
                program: self,
                th,
                out: [&mut s, &mut v, &mut a, &mut j].map(|r| split_off(r, m)),
                copy: copy.as_mut().map(|r| split_off(r, m)),
            });
        }
        // Each chunk says whether its angles were all finite (the lane loop
        // sees that for free); a non-finite angle is then found and named here.
        let fill = |job: LaneFill<'_>| pulp::Arch::new().dispatch(job);
        let finite = if jobs.len() <= 1 {
            jobs.into_iter().all(fill)
        } else {
            pool(threads)?.install(|| {
                jobs.into_par_iter()
                    .map(|job| crate::cancel::requested() || fill(job))
                    .reduce(|| true, |x, y| x & y)
            })
        };
        if !finite {
            crate::input::InvalidInput::check_finite("theta", theta)?;
        }
        Ok(())
    }

    /// The characteristic values of segment `i` (see [`Characteristics`]).
    pub fn characteristics(&self, i: usize) -> Characteristics {
        let span = &self.spans[i];
        let pieces = &self.fast[span.first..=span.last];
        let peak = |order: usize| {
            let hi = extreme(pieces, |p, x| p.eval(x, order)).1;
            let lo = extreme(pieces, |p, x| -p.eval(x, order)).1;
            hi.max(lo)
        };
        let peaks = [peak(1), peak(2), peak(3)];
        let cm = {
            let hi = extreme(pieces, |p, x| p.eval(x, 1) * p.eval(x, 2)).1;
            let lo = extreme(pieces, |p, x| -p.eval(x, 1) * p.eval(x, 2)).1;
            hi.max(lo)
        };
        let h = span.at_end[0] - span.at_start[0];
        let b = span.angle;
        let per = |value: f64, power: i32| {
            if h == 0.0 {
                f64::NAN
            } else {
                value * b.powi(power) / h.abs()
            }
        };
        Characteristics {
            stroke: h,
            peaks,
            cv: per(peaks[0], 1),
            ca: per(peaks[1], 2),
            cj: per(peaks[2], 3),
            cm: if h == 0.0 {
                f64::NAN
            } else {
                cm * b.powi(3) / (h * h)
            },
        }
    }

    /// Segment `i` as a law on the unit square with its start position and
    /// scale: s = s0 + scale·Z(x), x = (θ − start)/angle, where scale is its
    /// stroke (1 where the stroke is 0). The cam's program holds it so.
    pub fn unit_law(&self, i: usize) -> (f64, f64, Law) {
        let span = &self.spans[i];
        let s0 = span.at_start[0];
        let h = span.at_end[0] - s0;
        let scale = if h == 0.0 { 1.0 } else { h };
        let b = span.angle;
        let segments = (span.first..=span.last)
            .map(|k| {
                let f = &self.fast[k];
                // Back from t to x = t/β: c_k t^k = c_k β^k x^k.
                let mut m = 1.0;
                let poly = f.poly[0]
                    .iter()
                    .enumerate()
                    .map(|(i, &c)| {
                        let v = (c - if i == 0 { s0 } else { 0.0 }) * m / scale;
                        m *= b;
                        v
                    })
                    .collect();
                Piece {
                    x0: (f.x0 - span.start) / b,
                    x1: (f.x1 - span.start) / b,
                    poly,
                    amp: f.amp[0] / scale,
                    freq: f.freq * b,
                    phase: f.phase[0],
                }
            })
            .collect();
        (s0, scale, Law::from_segments(segments))
    }
}

/// The first `m` values of `rest`, which keeps the others.
fn split_off<'a>(rest: &mut &'a mut [f64], m: usize) -> &'a mut [f64] {
    let (head, tail) = std::mem::take(rest).split_at_mut(m);
    *rest = tail;
    head
}

/// [s, v, a, j] of one piece at x: the four Horner passes and one sine and
/// cosine (d^k/dt^k A·sin(ωt + φ) = A·ω^k·(sin, cos, −sin, −cos)), the
/// arithmetic of the lane loop (`program/lanes.rs`) value for value.
#[inline(always)]
fn piece_all(f: &Fast, x: f64) -> [f64; 4] {
    let t = x - f.x0;
    let mut out: [f64; 4] = std::array::from_fn(|order| {
        let mut p = 0.0;
        for &ck in f.poly[order].iter().rev() {
            p = p * t + ck;
        }
        p
    });
    if f.amp[0] != 0.0 {
        let (sn, cs) = crate::geom::sin_cos(f.freq * t + f.phase[0]);
        out[0] += f.amp[0] * sn;
        out[1] += f.amp[1] * cs;
        out[2] -= f.amp[2] * sn;
        out[3] -= f.amp[3] * cs;
    }
    out
}
