//! Pure-Rust kernels of cyclomech.
//!
//! No Python types here: every kernel takes slices and returns owned vectors or a
//! typed error (one `thiserror` enum per domain, wrapping the mistakes every
//! domain shares, [`input::InvalidInput`]). The pyo3 layer in `rust/bindings`
//! only converts arrays and maps these errors to `cyclomech.CyclomechError`
//! subclasses. No kernel may panic on user input: inputs are validated up front.
//!
//! Domains, one folder each (the Python package of the same name calls it), each
//! with a `mod.rs` door that re-exports its public kernels and keeps its helpers
//! private to the domain:
//! * [`cam`] — disc cams: the program of rise, dwell and return segments, and the
//!   exact follower kinematics, pitch curve, profile, pressure angle, curvature
//!   and undercut.
//! * [`cyclogram`] — network cyclograms: topological order, earliest/latest event
//!   times, slack, critical arcs, batches of weight vectors; systems of difference
//!   constraints (the cyclogram LP); the maximum cycle ratio (Howard's policy
//!   iteration) and the highest main-shaft speed at which a cyclic schedule fits
//!   in its cycle.
//! * [`dynamics`] — machine dynamics: the main shaft's forward dynamics with a
//!   variable reduced inertia and a motor (periodic steady state by shooting,
//!   start-up from rest, batches of designs).
//! * [`impact`] — stops (seed 000): the exact forced-oscillator recurrence
//!   (Duhamel integral of a piecewise-linear force), the first rebound after a
//!   pulse, and the link on its stop as an exact event-driven unilateral contact.
//! * [`linkage`] — planar linkages over crank-angle grids by Assur groups:
//!   positions, velocity and acceleration analogs, assembly and dead-centre flags.
//! * [`motion`] — dimensionless motion laws (rise and half forms) and the
//!   two-period slider law of seed 003.
//! * [`press`] — the planetary gear-lever press drive: kinematics over α grids,
//!   working-stroke criteria, design grids in parallel, and the non-dominated
//!   filtering of its optimiser.
//! * [`servo`] — servo axes: the motor torque and speed of an electronic cam
//!   on the (virtual) main shaft through a gearbox, the checks of a motor
//!   (peak and RMS torque, speed, inertia ratio) and the sizing batch over
//!   motors × gear ratios × speeds.
//! * [`synthesis`] — mechanisms dimensioned from what they must do (issue 35).
//! * [`transfer`] — rotor transfer (seed 002): the quintic transition's values,
//!   curvature and arc length, the composed path sampled by arc length, the
//!   kinematics of a speed law and the design's candidate scan.
//!
//! Shared by every domain: [`input`] (the invalid inputs every domain refuses the
//! same way: a bad scalar, a non-finite entry, a bad thread count, an output
//! array that cannot be filled), [`parallel`] (the rayon thread pools behind
//! `n_threads=` and `CYCLOMECH_THREADS`), [`cancel`] (the Ctrl-C flag every
//! parallel loop polls at the start of a chunk), [`units`] (rpm to rad/s and deg/s) and
//! the crate-private `geom` (plane vectors and the sine and cosine every kernel
//! evaluates the same way) and `tile` (the 8 × 8 register transpose the batch
//! longest path, the Duhamel scan and the Duhamel batch share).

/// Tests only: `$body` run once per instruction set the processor has (plain
/// scalar code, AVX2 + FMA, AVX-512), with `$s` the `pulp::Simd` of each, as
/// (name, value) pairs. The kernels dispatched by `pulp::Arch` pick the best one
/// at run time; this checks the ones a machine would not pick too.
#[cfg(test)]
macro_rules! on_each_isa {
    (|$s:ident| $body:expr) => {{
        let mut all = Vec::new();
        {
            let $s = pulp::Scalar::new();
            all.push(("scalar", $body));
        }
        #[cfg(target_arch = "x86_64")]
        {
            if let Some($s) = pulp::x86::V3::try_new() {
                all.push(("avx2", $body));
            }
            if let Some($s) = pulp::x86::V4::try_new() {
                all.push(("avx512", $body));
            }
        }
        all
    }};
}

pub mod cam;
pub mod cancel;
pub mod cyclogram;
pub mod dynamics;
pub mod forces;
pub(crate) mod geom;
pub mod impact;
pub mod input;
pub mod linkage;
mod memory;
pub mod motion;
pub(crate) mod num_text;
pub mod parallel;
pub mod press;
pub mod servo;
pub mod shaft;
pub mod synthesis;
pub(crate) mod tile;
pub mod timing;
pub mod transfer;
pub mod units;
