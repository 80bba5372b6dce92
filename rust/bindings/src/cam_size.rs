//! Bindings of the cam sizing (`cyclomech.synthesis.cam_size`).

use cyclomech_core::cam::{CamError, Limits, CRITERIA};
use cyclomech_core::synthesis::cam_size::{
    tradeoff_into, Sizing, N_SIZE_COLUMNS, SIZE_COLUMNS, SIZE_CRITERIA, SIZE_STATUS,
};
use numpy::ndarray::{Ix2, Ix4};
use numpy::{PyArray2, PyArray4, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::cam::{to_contact, to_loads, CamKernel};
use crate::convert::{self, LayoutError};
use crate::errors::run;

/// The sizing's names, read from the core: criteria, statuses and columns.
pub(crate) fn constants(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("CAM_SIZE_CRITERIA", PyTuple::new(m.py(), SIZE_CRITERIA)?)?;
    m.add("CAM_SIZE_STATUS", PyTuple::new(m.py(), SIZE_STATUS)?)?;
    m.add("CAM_SIZE_COLUMNS", PyTuple::new(m.py(), SIZE_COLUMNS)?)?;
    Ok(())
}

/// (S, 8) rows of the smallest base radius of `cam` at each cam speed `omegas`
/// [rad/s] (see `CAM_SIZE_COLUMNS`), radii searched over [min_radius,
/// max_radius] [m], the offset or pivot distance over `second` if given.
#[pyfunction]
#[pyo3(signature = (cam, omegas, max_pressure_angle, min_radius, max_radius, loads=None,
                    contact=None, max_stress=None, second=None, *, n_threads=None))]
#[allow(clippy::too_many_arguments)]
pub fn cam_size<'py>(
    py: Python<'py>,
    cam: PyRef<'py, CamKernel>,
    omegas: PyReadonlyArray1<'py, f64>,
    max_pressure_angle: f64,
    min_radius: f64,
    max_radius: f64,
    loads: Option<(f64, f64, f64, Vec<f64>)>,
    contact: Option<[f64; 5]>,
    max_stress: Option<f64>,
    second: Option<(f64, f64)>,
    n_threads: Option<i64>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let ws = CamError::slice(py, "omegas", &omegas)?;
    let loads = loads.map(to_loads);
    let contact = contact.map(to_contact);
    let sizing = Sizing {
        cam: &cam.cam,
        loads: loads.as_ref(),
        contact: contact.as_ref(),
        limits: Limits {
            max_pressure_angle,
            max_stress,
        },
        min_radius,
        max_radius,
        second,
    };
    let out = convert::zeros::<f64, Ix2>(
        py,
        &[ws.len(), N_SIZE_COLUMNS],
        "cam_size",
        "ask for fewer speeds at a time",
    )?;
    {
        let mut rw = out.readwrite();
        let slice = convert::output(py, &mut rw)?;
        run(py, "cam_size", || sizing.solve_into(ws, slice, n_threads))?;
    }
    Ok(out)
}

/// (R, S, K, 4) smallest phase angles [rad] of `segments` at `omegas` [rad/s]
/// for each base radius of `radii` [m] (NaN where the follower cannot be built).
#[pyfunction]
#[pyo3(signature = (cam, radii, segments, omegas, max_pressure_angle, loads=None, contact=None,
                    max_stress=None, *, n_threads=None))]
#[allow(clippy::too_many_arguments)]
pub fn cam_size_tradeoff<'py>(
    py: Python<'py>,
    cam: PyRef<'py, CamKernel>,
    radii: PyReadonlyArray1<'py, f64>,
    segments: Vec<usize>,
    omegas: PyReadonlyArray1<'py, f64>,
    max_pressure_angle: f64,
    loads: Option<(f64, f64, f64, Vec<f64>)>,
    contact: Option<[f64; 5]>,
    max_stress: Option<f64>,
    n_threads: Option<i64>,
) -> PyResult<Bound<'py, PyArray4<f64>>> {
    let rs = CamError::slice(py, "radii", &radii)?;
    let ws = CamError::slice(py, "omegas", &omegas)?;
    let loads = loads.map(to_loads);
    let contact = contact.map(to_contact);
    let limits = Limits {
        max_pressure_angle,
        max_stress,
    };
    let kernel = &cam.cam;
    let out = convert::zeros::<f64, Ix4>(
        py,
        &[rs.len(), ws.len(), segments.len(), CRITERIA.len()],
        "cam_size_tradeoff",
        "ask for fewer radii or speeds at a time",
    )?;
    {
        let mut rw = out.readwrite();
        let slice = convert::output(py, &mut rw)?;
        run(py, "cam_size_tradeoff", || {
            tradeoff_into(
                kernel,
                rs,
                &segments,
                ws,
                loads.as_ref(),
                contact.as_ref(),
                &limits,
                slice,
                n_threads,
            )
        })?;
    }
    Ok(out)
}
