//! Disc cams: the cam program (rise, dwell, return segments over one turn) and
//! the exact kinematics and geometry of its follower.
//!
//! Conventions: the cam turns counter-clockwise at positive ω; the cam angle θ
//! [rad] is measured from the start of the first segment. Results are in the cam
//! frame (x, y) [m], fixed to the cam, with the follower at θ = 0 on +y: a
//! translating follower moves along +y, offset `e` along +x; an oscillating
//! follower's pivot lies at (a, 0) and its arm angle ψ is measured from the line
//! pivot → cam centre, the roller centre at (a − l cos ψ, l sin ψ), ψ = ψ0 + s.
//! Every derivative comes from the laws' closed forms by the chain rule: no
//! finite differences.
//!
//! Files: `program` (segments, the displacement s(θ) and its derivatives),
//! `follower` (pitch curve, profile, pressure angle, curvature, undercut),
//! `contact` (forces, Hertz stress, shaft torque, jump), `bounds` (the smallest
//! phase angle per criterion), `search` (the bracketed searches they use),
//! `vibration` (follower dynamics: residual vibration, its bound, the steady
//! state) and `residual` (the built-in laws' residual vibration in closed form).

mod bounds;
mod contact;
mod follower;
mod program;
mod residual;
mod search;
mod stress;
#[cfg(test)]
mod tests;
mod vibration;

pub use bounds::{last_crossing, Limits, CRITERIA};
pub use contact::{Contact, Loads, LOAD_COLUMNS, N_LOAD_COLUMNS};
pub use follower::{Cam, Follower, COLUMNS, N_COLUMNS};
pub use program::{CamError, Kind, Program, SegmentSpec};
pub use residual::{ClosedResidual, MAX_CLOSED_DEGREE, SERIES_RADIUS};
pub(crate) use search::{brent_max, brent_zero};
pub use vibration::{
    free_amplitude, min_tau, min_tau_of, residual_ratio, residual_ratio_batch, steady_response,
    LawForce, SteadyState, VibrationError, GRID_PER_UNIT, RESONANCE_DET, SCAN_MAX, SCAN_STEP,
    SETTLE_WINDOW,
};
