//! The compiled linkage: its points, steps and lines, and the domain's error.

use super::triad::Triad;
use crate::geom::{cross, dot, sub, V2};

/// Errors of the linkage domain.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LinkageError {
    #[error("{field}[{position}] = {value} is not a finite number; {what}")]
    NonFinite {
        field: &'static str,
        position: usize,
        value: f64,
        what: &'static str,
    },
    #[error("step {step} of the program is invalid: {why}")]
    BadProgram { step: usize, why: String },
    #[error("the solution would need {bytes} bytes of memory, more than this machine can allocate; solve fewer angles, geometries or points at a time")]
    Memory { bytes: usize },
    #[error(transparent)]
    Input(#[from] crate::input::InvalidInput),
}

crate::input::wraps_invalid_input!(LinkageError);

/// The straight guide of a prismatic joint.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Line {
    /// Fixed to the frame: through `o` along `u` (any non-zero length).
    Fixed { o: V2, u: V2 },
    /// Along a moving link: through its joints `b` and `c`.
    Through { b: usize, c: usize },
}

/// A line at one pose: a point `o` on it, its direction `e` (not normalised), and
/// their first and second analogs.
pub(super) struct LineAt {
    pub(super) o: V2,
    pub(super) e: V2,
    pub(super) o1: V2,
    pub(super) e1: V2,
    pub(super) o2: V2,
    pub(super) e2: V2,
}

impl Line {
    pub(super) fn reads(&self) -> Vec<usize> {
        match *self {
            Line::Fixed { .. } => vec![],
            Line::Through { b, c } => vec![b, c],
        }
    }

    pub(super) fn dims(&self) -> Vec<f64> {
        match *self {
            Line::Fixed { o, u } => {
                let n = dot(u, u).sqrt();
                // o may be anywhere (0 included); only u must be a direction.
                vec![1.0 + o[0].abs() + o[1].abs(), n]
            }
            Line::Through { .. } => vec![],
        }
    }

    pub(super) fn at<const AN: bool>(&self, xy: &[V2], vel: &[V2], acc: &[V2]) -> LineAt {
        const Z: V2 = [0.0, 0.0];
        match *self {
            Line::Fixed { o, u } => LineAt {
                o,
                e: u,
                o1: Z,
                e1: Z,
                o2: Z,
                e2: Z,
            },
            Line::Through { b, c } => {
                let (o1, e1, o2, e2) = if AN {
                    (vel[b], sub(vel[c], vel[b]), acc[b], sub(acc[c], acc[b]))
                } else {
                    (Z, Z, Z, Z)
                };
                LineAt {
                    o: xy[b],
                    e: sub(xy[c], xy[b]),
                    o1,
                    e1,
                    o2,
                    e2,
                }
            }
        }
    }
}

impl LineAt {
    /// Normal row of `(p − o) × e = 0`: n·x = x × e.
    pub(super) fn normal(&self) -> V2 {
        [self.e[1], -self.e[0]]
    }

    /// Right-hand side of n·p' for the first analog.
    pub(super) fn rhs_v(&self, p: V2) -> f64 {
        dot(self.normal(), self.o1) - cross(sub(p, self.o), self.e1)
    }

    /// Right-hand side of n·p'' for the second analog, given p'.
    pub(super) fn rhs_a(&self, p: V2, v: V2) -> f64 {
        dot(self.normal(), self.o2)
            - 2.0 * cross(sub(v, self.o1), self.e1)
            - cross(sub(p, self.o), self.e2)
    }
}

/// One step of a compiled linkage.
#[derive(Debug, Clone, PartialEq)]
pub enum Step {
    /// A class III group: the ternary link `joints` held by binary links to `anchors`.
    Triad {
        anchors: [usize; 3],
        joints: [usize; 3],
        triad: Triad,
    },
    /// The crank: `tip = pivot + radius·(cos φ, sin φ)` for the absolute crank angle φ.
    Driver {
        pivot: usize,
        tip: usize,
        radius: f64,
    },
    /// RRR dyad (or a coupler point): `p` at distance `ra` from `a` and `rb` from
    /// `b`, on side `sign` (±1) of a→b.
    Circles {
        a: usize,
        b: usize,
        p: usize,
        ra: f64,
        rb: f64,
        sign: f64,
    },
    /// RRP dyad: `p` at distance `r` from `a` and on `line`; `sign` (±1) picks the
    /// intersection ahead of or behind the foot of `a` along the line's direction.
    Slide {
        a: usize,
        r: f64,
        line: Line,
        p: usize,
        sign: f64,
    },
    /// PRP dyad: `p` where two guides cross.
    Cross { l1: Line, l2: Line, p: usize },
    /// RPR dyad: the link b–c turns about known `b` and its line passes through
    /// known `s` (a block pinned at `s` slides on it): `c = b + sign·len·ŝ`, with ŝ
    /// the unit vector from b to s.
    Aim {
        b: usize,
        s: usize,
        c: usize,
        len: f64,
        sign: f64,
    },
}

impl Step {
    /// The points this step reads and the points it places.
    pub(super) fn reads_writes(&self) -> (Vec<usize>, Vec<usize>) {
        match *self {
            Step::Triad {
                anchors, joints, ..
            } => (anchors.to_vec(), joints.to_vec()),
            Step::Driver { pivot, tip, .. } => (vec![pivot], vec![tip]),
            Step::Circles { a, b, p, .. } => (vec![a, b], vec![p]),
            Step::Slide { a, line, p, .. } => {
                let mut reads = line.reads();
                reads.push(a);
                (reads, vec![p])
            }
            Step::Cross { l1, l2, p } => ([l1.reads(), l2.reads()].concat(), vec![p]),
            Step::Aim { b, s, c, .. } => (vec![b, s], vec![c]),
        }
    }
}

/// A compiled linkage: `n_points` points, the fixed ones with their coordinates,
/// then the steps in solving order (each step reads only points placed before it).
#[derive(Debug, Clone, PartialEq)]
pub struct Program {
    pub n_points: usize,
    pub fixed: Vec<(usize, [f64; 2])>,
    pub steps: Vec<Step>,
    /// The drawn pose (crank angle, every point): where a sweep through class III
    /// groups starts, so that it follows the drawn assembly.
    pub drawn: Option<(f64, Vec<[f64; 2]>)>,
}

/// Positions and analogs of the chosen points over an angle grid (and, for a
/// sweep, over geometries), row-major: `xy[(i * M + k) * 2 + c]` for angle row `i`
/// and chosen point `k` of `M`. `vel` and `acc` are empty when analogs were not
/// asked for.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    pub xy: Vec<f64>,
    pub vel: Vec<f64>,
    pub acc: Vec<f64>,
    /// The mechanism can be assembled at the angle.
    pub ok: Vec<bool>,
    /// A group is at (or within round-off of) a dead centre: analogs are NaN there.
    pub singular: Vec<bool>,
    /// The pose is not continuous with the one solved before it in the walk from
    /// the drawn pose: the followed branch of a class III group ended (at a fold,
    /// or where the mechanism stopped assembling) and the group was re-acquired
    /// here by the seed's bracketing (see [`Program::solve_path`]).
    pub branch: Vec<bool>,
}

/// What to compute: which points (indices) and whether the analogs.
#[derive(Debug, Clone, PartialEq)]
pub struct Request {
    pub points: Vec<usize>,
    pub analogs: bool,
}
