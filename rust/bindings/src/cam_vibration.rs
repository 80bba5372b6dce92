//! Bindings of the cam's follower dynamics: the residual vibration of a motion
//! law, its bound τ*, and the periodic steady state of a whole cam.

use cyclomech_core::cam::{
    min_tau, min_tau_of, residual_ratio_batch, steady_response, CamError, LawForce, VibrationError,
};
use numpy::ndarray::Ix1;
use numpy::{IntoPyArray, PyArray1, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;

use crate::convert::{self, LayoutError};
use crate::errors::{run, IntoPyErr};
use crate::motion::ProgramKernel;

/// Each wrapped error keeps its own domain's mapping (errors.rs).
impl IntoPyErr for VibrationError {
    fn into_pyerr(self, py: Python<'_>) -> PyErr {
        match self {
            VibrationError::Law(e) => e.into_pyerr(py),
            VibrationError::Input(e) => e.into_pyerr(py),
            VibrationError::Cam(e) => e.into_pyerr(py),
        }
    }
}

/// R(τ_i, ζ), the residual amplitude per unit stroke after one segment of the
/// named law started from rest, for every τ_i [rad] (rayon, GIL released).
#[pyfunction]
#[pyo3(signature = (law, tau, zeta, *, n_threads=None))]
pub fn cam_residual_ratio<'py>(
    py: Python<'py>,
    law: &str,
    tau: PyReadonlyArray1<'py, f64>,
    zeta: f64,
    n_threads: Option<i64>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let ts = CamError::slice(py, "tau", &tau)?;
    let out = convert::zeros::<f64, Ix1>(
        py,
        &[ts.len()],
        "cam_residual_ratio",
        "pass fewer tau values at a time",
    )?;
    {
        let mut rw = out.readwrite();
        let slice = convert::output(py, &mut rw)?;
        run(py, "cam_residual_ratio", || {
            residual_ratio_batch(law, ts, zeta, n_threads, slice)
        })?;
    }
    Ok(out)
}

/// τ*: the smallest τ [rad] with R(τ') ≤ `ratio_limit` for every τ' ≥ τ*, for
/// the named `law`, or for segment `index` of a motion `program` (its law on
/// the unit square; a rest-to-rest one).
#[pyfunction]
#[pyo3(signature = (law, ratio_limit, zeta, program=None, index=0))]
pub fn cam_min_tau(
    py: Python<'_>,
    law: &str,
    ratio_limit: f64,
    zeta: f64,
    program: Option<PyRef<'_, ProgramKernel>>,
    index: usize,
) -> PyResult<f64> {
    match program {
        None => run(py, "cam_min_tau", || min_tau(law, ratio_limit, zeta)),
        Some(p) => {
            let index = index.min(p.program.spans().len() - 1);
            let force = LawForce::of(&p.program.unit_law(index).2);
            run(py, "cam_min_tau", || min_tau_of(&force, ratio_limit, zeta))
        }
    }
}

/// Three float64 arrays: the error, its rate and the per-segment residual.
type Triple<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
);

/// The periodic steady-state dynamic error of the cam given by its segments
/// (as `CamKernel` takes them: angles [rad]) at cam speed `omega` [rad/s],
/// natural frequency `omega_n` [rad/s], damping ratio `zeta`, at cam angles
/// `theta` [rad]: (x, ẋ [per s], residual amplitude after each segment).
#[pyfunction]
#[pyo3(signature = (kinds, angles, strokes, laws, omega, omega_n, zeta, theta, program=None))]
#[allow(clippy::too_many_arguments)]
pub fn cam_follower_response<'py>(
    py: Python<'py>,
    kinds: Vec<String>,
    angles: Vec<f64>,
    strokes: Vec<f64>,
    laws: Vec<String>,
    omega: f64,
    omega_n: f64,
    zeta: f64,
    theta: PyReadonlyArray1<'py, f64>,
    program: Option<PyRef<'py, ProgramKernel>>,
) -> PyResult<Triple<'py>> {
    let n = kinds.len();
    let bad = |field: &'static str, value: f64, why: String| {
        CamError::BadFollower { field, value, why }.into_pyerr(py)
    };
    if angles.len() != n || strokes.len() != n || laws.len() != n {
        return Err(bad(
            "segments",
            n as f64,
            "kinds, angles, strokes and laws must have one entry per segment".into(),
        ));
    }
    let specs = crate::cam::specs(py, &kinds, &angles, &strokes, &laws, program.as_deref())?;
    let ts = CamError::slice(py, "theta", &theta)?;
    let st = run(py, "cam_follower_response", || {
        steady_response(&specs, omega, omega_n, zeta, ts)
    })?;
    Ok((
        st.x.into_pyarray(py),
        st.rate.into_pyarray(py),
        st.residual.into_pyarray(py),
    ))
}
