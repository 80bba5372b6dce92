//! Machine dynamics (issue 34): the main shaft's real motion under a motor, the
//! frame's shaking force and moment, and balancing.
//!
//! * [`shaft`] — the forward dynamics of a one-degree-of-freedom machine with
//!   a variable reduced inertia J(φ): the periodic steady state ω(φ) by shooting,
//!   the start-up from rest in time, and batches of designs (flywheels, motors)
//!   in parallel.
//! * [`shaking`] — the frame's shaking force and moment and the balancing of
//!   linkages by counterweights: a batch of counterweight designs.
//! * [`torsion`] — the main shaft as a chain of torsional springs with each
//!   mechanism's J(φ) on its take-off node, and each working member on an
//!   elastic link: the dynamic errors over the cycle, one speed or a sweep.
//!
//! Files: this door and one file per subject.

pub mod shaft;
pub mod shaking;
pub mod torsion;

pub use shaft::{
    start_up, steady_batch, steady_state, Characteristic, Curves, DriveError, Motor, StartUp,
    StartUpOptions, Status, Steady, SteadyOptions, STEADY_COLUMNS, STEADY_STATUS,
};
pub use torsion::{
    torsion, torsion_sweep, Head, Member, Node, Torsion, TorsionOptions, SWEEP_COLUMNS,
    TORSION_STATUS,
};
