//! Position, velocity and acceleration analysis of planar linkages over crank-angle
//! grids, by Assur groups solved in order (seed 001).
//!
//! A linkage is compiled (in Python, from its topology) into a [`Program`]: fixed
//! points, a driver (crank) and a sequence of steps, each placing one point from
//! points already known. This module holds the class II step in closed form:
//!
//! * [`Step::Circles`] — point `p` at distance `ra` from known `a` and `rb` from
//!   known `b`, on the side `sign` of the line a→b. This is the RRR dyad (two
//!   binary links meeting at `p`) and also a further joint of a rigid body two of
//!   whose joints are known (a coupler point). With `d = |b − a|`,
//!   `x = (ra² − rb² + d²) / 2d`, `h² = ra² − x²`; `h² < 0` is the seed's R² < 0:
//!   the mechanism cannot be assembled at that angle.
//!
//! The analogs (derivatives with respect to the crank angle φ) come from the
//! differentiated loop equations, exactly: `(p − a)·(p' − a') = 0` and
//! `(p − b)·(p' − b') = 0` give a 2×2 system for `p'`, and differentiating once
//! more, `(p − a)·(p'' − a'') + |p' − a'|² = 0` and the same for b, give `p''` with
//! the same matrix. Its determinant `(p − a) × (p − b)` vanishes at a dead centre,
//! where the analogs are infinite: such angles are flagged `singular`.
//!
//! Files: `model` (the compiled program: points, steps, lines, errors), `solve`
//! (one program over an angle grid: class II in closed form, class III groups
//! by [`Triad`] along a path), `lanes` (the class II steps over blocks of angles
//! in explicit SIMD), `batch` (many geometries at once, into
//! caller-owned buffers) and `triad` (the class III group).

mod batch;
mod change;
#[cfg(test)]
mod change_tests;
#[cfg(test)]
mod lane_tests;
mod lanes;
mod model;
mod solve;
#[cfg(test)]
mod tests;
mod triad;

pub use batch::{solve_many, solve_many_into, Outputs};
pub use change::{ChangePoint, NEAR_H_REL};
pub use model::{Line, LinkageError, Program, Request, Solution, Step};
pub use triad::Triad;
