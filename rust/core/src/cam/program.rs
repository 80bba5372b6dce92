//! The cam program: segments over one turn and the displacement s(θ).

use std::f64::consts::TAU;

use crate::input::InvalidInput;
use crate::motion::{Law, NAMES};

/// Tolerance on the segments' angles summing to one turn [rad].
pub const ANGLE_TOL: f64 = 1e-9 * TAU;

/// Relative tolerance on the displacement returning to its start.
pub const CLOSE_TOL: f64 = 1e-12;

/// Errors of the cam domain.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CamError {
    // Segments are counted from 1 in every message (`index` is the 0-based position).
    #[error("segment {} ({kind}): {field} = {} {why}", index + 1, crate::num_text::Num(*value))]
    BadSegment {
        index: usize,
        kind: &'static str,
        field: &'static str,
        value: f64,
        why: &'static str,
    },
    #[error("segment {} ({kind}): unknown motion law {name:?}; known laws: {known}", index + 1)]
    UnknownLaw {
        index: usize,
        kind: &'static str,
        name: String,
        known: String,
    },
    #[error("the segments' angles sum to {sum_deg}°, not 360°")]
    NotOneTurn { sum_deg: f64 },
    #[error("the displacement does not return to its start: rises − returns = {}", crate::num_text::Num(*net))]
    NotClosed { net: f64 },
    #[error("the program has no segment")]
    Empty,
    #[error("follower {field} = {} {why}", crate::num_text::Num(*value))]
    BadFollower {
        field: &'static str,
        value: f64,
        why: String,
    },
    #[error(transparent)]
    Input(#[from] InvalidInput),
}

crate::input::wraps_invalid_input!(CamError);

/// The kind of a segment.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    Rise,
    Dwell,
    Return,
}

impl Kind {
    /// The kind's name in messages and in Python.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Rise => "rise",
            Kind::Dwell => "dwell",
            Kind::Return => "return",
        }
    }
}

/// A segment as given: its kind, angle [rad], stroke [m or rad] and law name
/// (ignored for a dwell); `unit`, if given, is its law on the unit square
/// (s = s0 ± stroke·Z(x)) instead of the named rise: a segment of a motion
/// program (`motion::Program::unit_law`), whose ends may be in motion.
#[derive(Debug, Clone, PartialEq)]
pub struct SegmentSpec {
    pub kind: Kind,
    pub angle: f64,
    pub stroke: f64,
    pub law: String,
    pub unit: Option<Law>,
}

impl SegmentSpec {
    /// Its law on the unit square: `unit`, else the named rise.
    pub fn unit_law(&self) -> Result<Law, crate::motion::MotionError> {
        match &self.unit {
            Some(law) => Ok(law.clone()),
            None => Law::rise(&self.law),
        }
    }
}

#[derive(Debug, Clone)]
struct Seg {
    start: f64,
    angle: f64,
    s0: f64,
    /// Signed stroke: + for a rise, − for a return, 0 for a dwell.
    h: f64,
    law: Option<Law>,
    /// 1/angle and h/angle^n for n = 1, 2, 3: [`Program::eval_lanes_fast_then`]
    /// multiplies where [`Program::eval`] divides.
    inv_angle: f64,
    h_per: [f64; 3],
}

/// A validated cam program: s(θ) and its derivatives over one turn.
#[derive(Debug, Clone)]
pub struct Program {
    segs: Vec<Seg>,
    s_min: f64,
    s_max: f64,
}

/// What takes a lane group's [s, s′, s″, s‴] from
/// [`Program::eval_lanes_fast_then`] (a trait, not a closure: a closure kept
/// out of line would lose the caller's instruction set).
pub(super) trait LanesSink<const L: usize> {
    /// What the work on the lanes gives.
    type Out;
    /// The work on the lanes `sv` = [s, s′, s″, s‴].
    fn take(self, sv: [[f64; L]; 4]) -> Self::Out;
}

impl Program {
    /// Validate the segments: angles > 0 summing to 2π, strokes ≥ 0 (> 0 for a
    /// rise or return, 0 for a dwell), known laws, and rises − returns = 0.
    pub fn new(specs: &[SegmentSpec]) -> Result<Program, CamError> {
        if specs.is_empty() {
            return Err(CamError::Empty);
        }
        let mut segs = Vec::with_capacity(specs.len());
        let (mut start, mut s0, mut s_min, mut s_max, mut scale) =
            (0.0, 0.0, 0.0f64, 0.0f64, 0.0f64);
        for (index, sp) in specs.iter().enumerate() {
            let kind = sp.kind.name();
            let bad = |field, value, why| CamError::BadSegment {
                index,
                kind,
                field,
                value,
                why,
            };
            if !(sp.angle.is_finite() && sp.angle > 0.0) {
                return Err(bad("angle", sp.angle, "must be finite and > 0"));
            }
            if !sp.stroke.is_finite() || sp.stroke < 0.0 {
                return Err(bad("stroke", sp.stroke, "must be finite and >= 0"));
            }
            let (h, law) = match sp.kind {
                Kind::Dwell if sp.stroke != 0.0 => {
                    return Err(bad("stroke", sp.stroke, "must be 0 for a dwell"))
                }
                Kind::Dwell => (0.0, None),
                _ if sp.stroke == 0.0 => {
                    return Err(bad("stroke", sp.stroke, "must be > 0 for a rise or return"))
                }
                k => {
                    let law = sp.unit_law().map_err(|_| CamError::UnknownLaw {
                        index,
                        kind,
                        name: sp.law.clone(),
                        known: NAMES.join(", "),
                    })?;
                    let sign = if k == Kind::Rise { 1.0 } else { -1.0 };
                    (sign * sp.stroke, Some(law))
                }
            };
            let b = sp.angle;
            segs.push(Seg {
                start,
                angle: b,
                s0,
                h,
                law,
                inv_angle: 1.0 / b,
                h_per: [h / b, h / (b * b), h / (b * b * b)],
            });
            // A program's segment may overshoot its ends (moving ends): its
            // law's own range; a named rise stays within them.
            if let Some(law) = segs
                .last()
                .and_then(|g: &Seg| g.law.as_ref())
                .filter(|_| sp.unit.is_some())
            {
                let (lo, hi) = law.z_range();
                for v in [s0 + h * lo, s0 + h * hi] {
                    s_max = s_max.max(v);
                    s_min = s_min.min(v);
                }
            }
            start += sp.angle;
            s0 += h;
            s_max = s_max.max(s0);
            s_min = s_min.min(s0);
            scale = scale.max(sp.stroke);
        }
        if (start - TAU).abs() > ANGLE_TOL {
            return Err(CamError::NotOneTurn {
                sum_deg: start.to_degrees(),
            });
        }
        if s0.abs() > CLOSE_TOL * scale {
            return Err(CamError::NotClosed { net: s0 });
        }
        Ok(Program { segs, s_min, s_max })
    }

    /// Lowest displacement over the turn [m or rad] (0 unless a return comes first).
    pub fn s_min(&self) -> f64 {
        self.s_min
    }

    /// Highest displacement over the turn [m or rad].
    pub fn s_max(&self) -> f64 {
        self.s_max
    }

    /// [s, s', s'', s'''] at cam angle θ [rad] (any real: taken modulo 2π);
    /// derivatives per radian of cam.
    #[inline]
    pub fn eval(&self, theta: f64) -> [f64; 4] {
        // θ in [0, 2π) is its own remainder (bit for bit): skip the division.
        let t = if (0.0..TAU).contains(&theta) {
            theta
        } else {
            theta.rem_euclid(TAU)
        };
        // Last segment starting at or before t (segments are few: linear scan).
        let mut k = 0;
        while k + 1 < self.segs.len() && self.segs[k + 1].start <= t {
            k += 1;
        }
        let g = &self.segs[k];
        match &g.law {
            None => [g.s0, 0.0, 0.0, 0.0],
            Some(law) => {
                let x = ((t - g.start) / g.angle).clamp(0.0, 1.0);
                let b = g.angle;
                // All four orders from one piece lookup.
                let [z0, z1, z2, z3] = law.z_all(x);
                [
                    g.s0 + g.h * z0,
                    g.h * z1 / b,
                    g.h * z2 / (b * b),
                    g.h * z3 / (b * b * b),
                ]
            }
        }
    }

    /// The segment every angle of `theta` lies in, if one holds them all as
    /// `eval`'s lookup puts them (t in segment k iff start(k) ≤ t < start(k +
    /// 1), within [0, 2π)); None for lanes that straddle segments, lie outside
    /// the turn or are NaN (one mask test across the lanes).
    #[inline(always)]
    fn lanes_segment<const L: usize>(&self, theta: &[f64; L]) -> Option<&Seg> {
        let segs = &self.segs;
        let mut k = 0;
        while k + 1 < segs.len() && segs[k + 1].start <= theta[0] {
            k += 1;
        }
        let g = &segs[k];
        let hi = segs.get(k + 1).map_or(TAU, |n| n.start.min(TAU));
        theta
            .iter()
            .fold(true, |ok, &v| ok & (v >= 0.0) & (v >= g.start) & (v < hi))
            .then_some(g)
    }

    /// [`Program::eval`] of each angle, as the lanes' four rows: the path of
    /// lanes that straddle segments.
    #[inline(always)]
    fn eval_each<const L: usize>(&self, theta: &[f64; L]) -> [[f64; L]; 4] {
        let mut out = [[0.0; L]; 4];
        for (l, &v) in theta.iter().enumerate() {
            let e = self.eval(v);
            for o in 0..4 {
                out[o][l] = e[o];
            }
        }
        out
    }

    /// [`Program::eval`] for `L` angles at once, as four lanes [s, s′, s″, s‴]
    /// (the same values, bit for bit): angles in [0, 2π) within one segment (the
    /// common case for sorted angles) run as loops across lanes without branches
    /// (see `Law::z_all_lanes`), others one by one.
    #[inline(always)]
    pub(super) fn eval_lanes<const L: usize>(&self, theta: &[f64; L]) -> [[f64; L]; 4] {
        let Some(g) = self.lanes_segment(theta) else {
            return self.eval_each(theta);
        };
        match &g.law {
            None => [[g.s0; L], [0.0; L], [0.0; L], [0.0; L]],
            Some(law) => {
                let b = g.angle;
                let mut x = [0.0; L];
                for l in 0..L {
                    x[l] = ((theta[l] - g.start) / b).clamp(0.0, 1.0);
                }
                let [z0, z1, z2, z3] = law.z_all_lanes(&x);
                let mut out = [[0.0; L]; 4];
                for l in 0..L {
                    out[0][l] = g.s0 + g.h * z0[l];
                    out[1][l] = g.h * z1[l] / b;
                    out[2][l] = g.h * z2[l] / (b * b);
                    out[3][l] = g.h * z3[l] / (b * b * b);
                }
                out
            }
        }
    }

    /// [`Program::eval_lanes`] for a kernel compiled with FMA (see
    /// [`Law::z_all_lanes_shared`]), handed to `sink`: the law's sinusoid
    /// once for the four orders, fused multiply-adds, and each division by
    /// the segment's angle a multiplication by a reciprocal taken once.
    /// Within 1e-13 of each order's scale of [`Program::eval`] (tested), not
    /// bit for bit. `sink` takes the lanes on the branch that computed them
    /// (a dwell, a law, or the angles one by one), so that the caller's work
    /// on them is inlined into each branch: where the branches joined and
    /// the lanes were returned, the compiler passed them through the stack
    /// and reading them back waited on the stores (a tenth of the cam
    /// kernel's samples in a profile, at the first use of s).
    #[inline(always)]
    pub(super) fn eval_lanes_fast_then<const L: usize, K: LanesSink<L>>(
        &self,
        theta: &[f64; L],
        sink: K,
    ) -> K::Out {
        let Some(g) = self.lanes_segment(theta) else {
            return sink.take(self.eval_each(theta));
        };
        match &g.law {
            None => sink.take([[g.s0; L], [0.0; L], [0.0; L], [0.0; L]]),
            Some(law) => {
                let mut x = [0.0; L];
                for l in 0..L {
                    x[l] = ((theta[l] - g.start) * g.inv_angle).clamp(0.0, 1.0);
                }
                let [z0, z1, z2, z3] = law.z_all_lanes_shared(&x);
                let [d1, d2, d3] = g.h_per;
                let mut out = [[0.0; L]; 4];
                for l in 0..L {
                    out[0][l] = g.h.mul_add(z0[l], g.s0);
                    out[1][l] = d1 * z1[l];
                    out[2][l] = d2 * z2[l];
                    out[3][l] = d3 * z3[l];
                }
                sink.take(out)
            }
        }
    }

    /// The number of segments.
    pub fn len(&self) -> usize {
        self.segs.len()
    }

    /// Whether the program has no segment (never: [`Program::new`] refuses that).
    pub fn is_empty(&self) -> bool {
        self.segs.is_empty()
    }

    /// The index of the segment holding cam angle θ [rad] (modulo 2π; a
    /// boundary belongs to the segment it starts).
    pub fn segment_at(&self, theta: f64) -> usize {
        let t = theta.rem_euclid(TAU);
        let mut k = 0;
        while k + 1 < self.segs.len() && self.segs[k + 1].start <= t {
            k += 1;
        }
        k
    }

    /// Segment `k`: (start angle [rad], angle [rad], displacement at its start,
    /// signed stroke: + rise, − return, 0 dwell).
    pub fn segment(&self, k: usize) -> (f64, f64, f64, f64) {
        let g = &self.segs[k];
        (g.start, g.angle, g.s0, g.h)
    }

    /// Segment `k`'s law at `x`: [z, z′, z″, z‴] (zeros for a dwell), the part
    /// of [`Program::trial`] that does not depend on the angle.
    #[inline]
    pub fn law_at(&self, k: usize, x: f64) -> [f64; 4] {
        match &self.segs[k].law {
            None => [0.0; 4],
            Some(law) => law.z_all(x),
        }
    }

    /// [`Program::trial`] from the law's values `z` = [`Program::law_at`].
    #[inline]
    pub fn trial_from(&self, k: usize, z: [f64; 4], beta: f64) -> [f64; 4] {
        let g = &self.segs[k];
        let [z0, z1, z2, z3] = z;
        [
            g.s0 + g.h * z0,
            g.h * z1 / beta,
            g.h * z2 / (beta * beta),
            g.h * z3 / (beta * beta * beta),
        ]
    }

    /// [s, s′, s″, s‴] of segment `k` at the fraction `x` ∈ [0, 1] of its
    /// angle, were its angle `beta` [rad] instead of its own (a bound search's
    /// trial: the segment's start displacement and stroke are kept).
    #[inline]
    pub fn trial(&self, k: usize, x: f64, beta: f64) -> [f64; 4] {
        let g = &self.segs[k];
        match &g.law {
            None => [g.s0, 0.0, 0.0, 0.0],
            Some(law) => {
                let [z, z1, z2, z3] = law.z_all(x);
                [
                    g.s0 + g.h * z,
                    g.h * z1 / beta,
                    g.h * z2 / (beta * beta),
                    g.h * z3 / (beta * beta * beta),
                ]
            }
        }
    }
}
