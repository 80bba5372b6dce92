//! Rotor transfer (seed 002): the guide of a workpiece from a transport rotor to
//! a process rotor — circle, smooth quintic transition, straight segment, the
//! mirror transition, circle — sampled, the workpiece's acceleration and jerk
//! along it for a speed law, and the scan of transition lengths that
//! `cyclomech.transfer.design_transfer` minimises the peak jerk over.
//!
//! **Quintic** ([`Quintic`]): y = a2·x² + … + a5·x⁵ in the frame of the point A
//! where the path leaves the circle; its derivatives by Horner's rule, curvature
//! κ = y''/(1 + y'²)^{3/2} and its rate dκ/ds, and the arc length
//! s(x) = ∫₀ˣ √(1 + y'²) dx: 16-point Gauss–Legendre on one piece per 0.05 rad
//! the tangent turns (exact to rounding), or, along a sampling grid, 4-point
//! Gauss–Legendre per interval summed — restarted from the 16-point value at the
//! start of every block of [`BLOCK`] points, so rounding does not accumulate
//! past a block and every block can run on its own thread (the Python layer
//! summed one running total: the two agree to rounding, 1e-13 relative).
//!
//! **Path** ([`sample_into`]): the pieces in travel order from a [`PathSpec`]
//! the Python layer works out once per path (the geometry, a few numbers);
//! arcs by a rotation from each block's start (one sine and cosine a block,
//! within 1e-16 of the direct ones). **Kinematics** ([`kinematics_into`]): for
//! a speed law v(s) (constant, or V_t → V_p by a quintic smoothstep between A
//! and C) the normal and tangential accelerations, their rates, |a|, the jerk
//! |da/dt| with the turning of the frame, and the time (trapezoid in 1/v,
//! summed per block as above). **Design** ([`peak_jerk`], [`longest`]): the
//! path's geometry in closed form for any pair of transition lengths, the peak
//! jerk of each candidate on m points of each transition and of the straight
//! (rayon over candidates), and the longest transitions the gap allows.
//!
//! Files: this door (errors, checks, the parallel helpers), `quintic`, `path`,
//! `design` and `tests`.

use rayon::prelude::*;

use crate::input::InvalidInput;
use crate::parallel::{pool, resolve_threads};

mod design;
mod path;
mod quintic;
#[cfg(test)]
mod tests;

pub use design::{geometry, longest, peak_jerk, Geometry};
pub use path::{
    kinematics_into, sample_into, PathSpec, SampleOut, SpeedLaw, KINEMATICS, N_KINEMATICS, N_SPEC,
};
pub use quintic::{coefficients, quintic, quintic_eval_into, Quintic, QuinticValue};

/// Points a block holds: the unit of work of a thread, and the span over which
/// the running sums (arc length, time) accumulate rounding.
pub const BLOCK: usize = 4096;

/// Errors of the rotor transfer kernels: the invalid inputs every domain shares,
/// and the transfer's own (an array's length, its layout).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TransferError {
    #[error(transparent)]
    Input(#[from] InvalidInput),
    #[error("{field} has {got} values; it needs {want}")]
    BadLength {
        field: &'static str,
        got: usize,
        want: &'static str,
    },
    #[error("{field} must be a C-contiguous array")]
    Layout { field: &'static str },
}

crate::input::wraps_invalid_input!(TransferError);

/// `f` on every task: inline on the calling thread when one thread is asked
/// for or there is one task (no hop to a pool thread, which on a loaded machine
/// can cost milliseconds), else on the pool of `threads`.
pub(crate) fn run_tasks<T, F>(tasks: Vec<T>, threads: usize, f: F) -> Result<(), TransferError>
where
    T: Send,
    F: Fn(T) + Sync + Send,
{
    let f = |t| {
        if !crate::cancel::requested() {
            f(t)
        }
    };
    if threads <= 1 || tasks.len() <= 1 {
        tasks.into_iter().for_each(f);
    } else {
        pool(threads)?.install(|| tasks.into_par_iter().for_each(f));
    }
    Ok(())
}

/// [`run_tasks`] collecting each task's result, in order.
pub(crate) fn map_tasks<T, R, F>(
    tasks: Vec<T>,
    threads: usize,
    f: F,
) -> Result<Vec<R>, TransferError>
where
    T: Send,
    R: Send,
    F: Fn(T) -> R + Sync + Send,
{
    if threads <= 1 || tasks.len() <= 1 {
        Ok(tasks.into_iter().map(f).collect())
    } else {
        Ok(pool(threads)?.install(|| tasks.into_par_iter().map(f).collect()))
    }
}

/// √(a² + b²) in a lane loop; where that over- or underflows, `hypot`.
#[inline(always)]
pub(crate) fn norms(a: &[f64], b: &[f64], out: &mut [f64]) {
    for ((o, &a), &b) in out.iter_mut().zip(a).zip(b) {
        *o = (a * a + b * b).sqrt();
    }
    for ((o, &a), &b) in out.iter_mut().zip(a).zip(b) {
        if !(o.is_finite() && (*o >= 1e-150 || *o == 0.0)) {
            *o = a.hypot(b);
        }
    }
}

/// out[i] = f(x[i]) in blocks of [`BLOCK`] on `n_threads`.
fn par_map<F>(x: &[f64], out: &mut [f64], n_threads: Option<i64>, f: F) -> Result<(), TransferError>
where
    F: Fn(f64) -> f64 + Sync + Send,
{
    let threads = resolve_threads(n_threads)?;
    let tasks: Vec<_> = out.chunks_mut(BLOCK).zip(x.chunks(BLOCK)).collect();
    run_tasks(tasks, threads, |(o, xs)| {
        for (o, &v) in o.iter_mut().zip(xs) {
            *o = f(v);
        }
    })
}
