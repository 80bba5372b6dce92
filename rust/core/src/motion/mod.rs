//! Dimensionless motion laws on the unit square and the two-period slider law.
//!
//! A law is Z(x) on 0 ≤ x ≤ 1, piecewise: on each segment [x0, x1],
//! Z = Σ c_k t^k + A·sin(ω t + φ) with t = x − x0, so that Z, Z', Z'', Z''' are
//! exact everywhere. Named laws (cycloidal, harmonic, 3-4-5, 4-5-6-7, modified
//! sine, modified trapezoid) are built as full rises (Z' = 0 at both ends); the
//! modified laws by integrating their acceleration pieces exactly and scaling to
//! Z(1) = 1, so that their peaks (Cv, Ca) follow from the shape rather than from
//! printed decimals. The **half law** of a symmetric rise is its first half
//! rescaled to the unit square: Z_h(j) = 2·Z(j/2), so Z_h' peaks at j = 1.
//!
//! The two-period law of seed 003 joins a half law over 0 ≤ α ≤ α1 (period I,
//! Π = Π1·Z1(α/α1)) and a mirrored half law over α1 ≤ α ≤ α2 (period II,
//! Π = Π2 − (Π2 − Π1)·Z2((α2 − α)/(α2 − α1))).
//!
//! A **motion program** (VDI 2143) is a list of segments over one master cycle,
//! each a law between boundary values (position, velocity, acceleration, jerk)
//! that may be in motion: `segment` turns each law into pieces, `program`
//! resolves free values, checks given ones and the joins, and evaluates.
//!
//! Files: `law` (the laws, named and polynomial, evaluated in SIMD lanes),
//! `two_period` (the two-period slider law), `fused` (its one-pass FMA kernel
//! for arrays of angles, where the processor has FMA), and `spline` (cubic
//! and quintic interpolating splines through a point table, as pieces).

mod fused;
mod law;
mod program;
#[cfg(test)]
mod program_tests;
mod segment;
mod spline;
#[cfg(test)]
mod spline_tests;
#[cfg(test)]
mod tests;
mod two_period;

pub use law::{Law, MotionError, Segment, LAW_TOL, MAX_DEGREE, NAMES};
pub use program::{Characteristics, PieceRow, Program, Span, CYCLE_TOL};
pub use segment::{SegmentSpec, BOUNDARY_TOL, ORDER_NAMES, SEGMENT_LAWS};
pub use spline::{spline, SplineEnd, PERIODIC_TOL};
pub use two_period::TwoPeriod;
