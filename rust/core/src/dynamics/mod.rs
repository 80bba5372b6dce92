//! Machine dynamics (issue 34): the main shaft's real motion under a motor, the
//! frame's shaking force and moment, and balancing.
//!
//! * [`shaft`] — the forward dynamics of a one-degree-of-freedom machine with
//!   a variable reduced inertia J(φ): the periodic steady state ω(φ) by shooting,
//!   the start-up from rest in time, and batches of designs (flywheels, motors)
//!   in parallel.
//! * [`shaking`] — the frame's shaking force and moment and the balancing of
//!   linkages by counterweights: a batch of counterweight designs.
//!
//! Files: this door and one file per subject.

pub mod shaft;
pub mod shaking;

pub use shaft::{
    start_up, steady_batch, steady_state, Characteristic, Curves, DriveError, Motor, StartUp,
    StartUpOptions, Status, Steady, SteadyOptions, STEADY_COLUMNS, STEADY_STATUS,
};
