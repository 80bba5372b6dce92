//! `cyclomech._core`: the pyo3 extension module.
//!
//! Thin by design: convert arrays and errors, release the GIL, call `cyclomech-core`.
//! The public Python API (validation, coercion of lists to arrays, docs) lives in
//! `python/cyclomech`; the stubs in `python/cyclomech/_core.pyi` are the contract.

use pyo3::prelude::*;

mod cam;
mod cam_size;
mod cam_vibration;
mod convert;
mod cyclogram;
mod dynamics_shaft;
mod dynamics_shaking;
mod dynamics_torsion;
mod errors;
mod forces;
mod impact;
mod interrupt;
mod linkage;
mod motion;
mod press;
mod servo;
mod shaft;
mod speed_limit;
mod synthesis_dwell;
mod synthesis_fourbar;
mod synthesis_function;
mod synthesis_motion;
mod synthesis_path;
mod transfer;

#[pymodule]
mod _core {
    #[pymodule_export]
    use super::cam::CamKernel;
    #[pymodule_export]
    use super::cam_size::{cam_size, cam_size_tradeoff};
    #[pymodule_export]
    use super::cam_vibration::{cam_follower_response, cam_min_tau, cam_residual_ratio};
    #[pymodule_export]
    use super::cyclogram::{longest_path, max_cycle_ratio, max_difference, max_speed, EventGraph};
    #[pymodule_export]
    use super::dynamics_shaft::{dynamics_start_up, dynamics_steady, dynamics_steady_batch};
    #[pymodule_export]
    use super::dynamics_shaking::{shaking_batch, shaking_channels};
    #[pymodule_export]
    use super::dynamics_torsion::{dynamics_torsion, dynamics_torsion_sweep};
    #[pymodule_export]
    use super::forces::ForceModel;
    #[pymodule_export]
    use super::impact::stop_design_batch;
    #[pymodule_export]
    use super::impact::{
        contact_rebound_batch, contact_response, contact_sample, duhamel, duhamel_batch,
        first_rebound_batch,
    };
    #[pymodule_export]
    use super::linkage::LinkageProgram;
    #[pymodule_export]
    use super::motion::{MotionLaw, ProgramKernel, TwoPeriodKernel};
    #[pymodule_export]
    use super::press::{pareto_mask, press_check, press_criteria_names, press_solve, press_sweep};
    #[pymodule_export]
    use super::servo::{
        servo_duty, servo_min_angles, servo_rms_angles, servo_size, servo_speed_limit,
    };
    #[pymodule_export]
    use super::shaft::{shaft_stats, shaft_sum};
    #[pymodule_export]
    use super::speed_limit::{solve_proportional, speed_limits_proportional};
    #[pymodule_export]
    use super::synthesis_dwell::{dwell_batch, dwell_fields, fit_circle};
    #[pymodule_export]
    use super::synthesis_fourbar::{
        fourbar_grashof, fourbar_output_angle, fourbar_transmission, slider_crank_kind,
        slider_crank_position, slider_crank_transmission,
    };
    #[pymodule_export]
    use super::synthesis_function::{
        chebyshev_points, function_branches, function_error, function_fit, function_generated,
    };
    #[pymodule_export]
    use super::synthesis_motion::{
        burmester_curves, burmester_det, burmester_dyad, burmester_points, motion_fourbar,
        motion_fourbars,
    };
    #[pymodule_export]
    use super::synthesis_path::{path_columns, path_evaluate, path_points};
    #[pymodule_export]
    use super::threads;
    #[pymodule_export]
    use super::transfer::{
        transfer_kinematics, transfer_longest, transfer_peak_jerk, transfer_quintic,
        transfer_sample,
    };

    #[pymodule_init]
    fn init(m: &Bound<'_, PyModule>) -> PyResult<()> {
        m.add("__version__", env!("CARGO_PKG_VERSION"))?;
        // Constants the Python layer needs too: read from the core, not copied.
        m.add("MOTION_LAWS", PyTuple::new(m.py(), LAW_NAMES)?)?;
        m.add("SEGMENT_LAWS", PyTuple::new(m.py(), SEGMENT_LAWS)?)?;
        let status = Status::ALL.map(Status::text);
        m.add("PRESS_STATUS", PyTuple::new(m.py(), status)?)?;
        m.add("RAD_PER_S_PER_RPM", units::RAD_PER_S_PER_RPM)?;
        m.add("DEG_PER_S_PER_RPM", units::DEG_PER_S_PER_RPM)?;
        m.add("CAM_CRITERIA", PyTuple::new(m.py(), CAM_CRITERIA)?)?;
        m.add("CAM_LOAD_COLUMNS", PyTuple::new(m.py(), LOAD_COLUMNS)?)?;
        super::cam_size::constants(m)?;
        m.add("SHAFT_STATS", PyTuple::new(m.py(), SHAFT_STATS)?)?;
        m.add(
            "DYNAMICS_STEADY_COLUMNS",
            PyTuple::new(m.py(), STEADY_COLUMNS)?,
        )?;
        m.add(
            "DYNAMICS_STEADY_STATUS",
            PyTuple::new(m.py(), STEADY_STATUS)?,
        )?;
        m.add("TORSION_STATUS", PyTuple::new(m.py(), TORSION_STATUS)?)?;
        m.add("SHAKING_STATS", PyTuple::new(m.py(), SHAKING_STATS)?)?;
        m.add("SERVO_CHECKS", PyTuple::new(m.py(), SERVO_CHECKS)?)?;
        m.add("SERVO_DUTY", PyTuple::new(m.py(), SERVO_DUTY)?)?;
        m.add("SERVO_BOUNDS", PyTuple::new(m.py(), SERVO_BOUNDS)?)?;
        m.add("THREADS_ENV", parallel::THREADS_ENV)?;
        crate::interrupt::install(m.py());
        Ok(())
    }

    use super::*;
    use cyclomech_core::cam::{CRITERIA as CAM_CRITERIA, LOAD_COLUMNS};
    use cyclomech_core::dynamics::shaking::STATS as SHAKING_STATS;
    use cyclomech_core::dynamics::{STEADY_COLUMNS, STEADY_STATUS, TORSION_STATUS};
    use cyclomech_core::motion::{NAMES as LAW_NAMES, SEGMENT_LAWS};
    use cyclomech_core::press::Status;
    use cyclomech_core::servo::{
        BOUND_CRITERIA as SERVO_BOUNDS, CHECKS as SERVO_CHECKS, DUTY as SERVO_DUTY,
    };
    use cyclomech_core::shaft::STATS as SHAFT_STATS;
    use cyclomech_core::{parallel, units};
    use pyo3::types::PyTuple;
}

/// The thread count the kernels take for `n_threads` (None: `CYCLOMECH_THREADS`,
/// else every core), by the core's one rule; an `InputError` names what is wrong.
#[pyfunction]
#[pyo3(signature = (n_threads=None))]
fn threads(py: Python<'_>, n_threads: Option<i64>) -> PyResult<usize> {
    use errors::IntoPyErr;
    cyclomech_core::parallel::resolve_threads(n_threads).map_err(|e| e.into_pyerr(py))
}
