//! Binding of the cyclogram's speed-limit search with speed-proportional bounds
//! (`cyclomech.cyclogram.SpeedNetwork.speed_limits_proportional`).

use cyclomech_core::cyclogram::{self, CyclogramError, ProportionalNetwork, SpeedSearch};
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;

use crate::convert::LayoutError;
use crate::errors::{run, IntoPyErr};

/// Each design's speed limit [rpm] (D,) on a cyclogram's difference network
/// whose extra bounds are proportional to the speed: `per_rpm` (D, K) the
/// bounds' slopes [deg/rpm] (see `cyclogram::speed_limits_proportional`).
#[pyfunction]
#[pyo3(signature = (
    n_nodes, src, dst, base, source, target, lim_shift, min_edge, angle, secs, bound_op,
    per_rpm, start, floor, cap, rtol, *, n_threads=None
))]
#[allow(clippy::too_many_arguments)] // the network, the bounds and the search
pub fn speed_limits_proportional<'py>(
    py: Python<'py>,
    n_nodes: i64,
    src: PyReadonlyArray1<'py, i64>,
    dst: PyReadonlyArray1<'py, i64>,
    base: PyReadonlyArray1<'py, f64>,
    source: i64,
    target: i64,
    lim_shift: f64,
    min_edge: PyReadonlyArray1<'py, i64>,
    angle: PyReadonlyArray1<'py, f64>,
    secs: PyReadonlyArray1<'py, f64>,
    bound_op: PyReadonlyArray1<'py, i64>,
    per_rpm: PyReadonlyArray2<'py, f64>,
    start: f64,
    floor: f64,
    cap: f64,
    rtol: f64,
    n_threads: Option<i64>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let k = bound_op.len();
    if per_rpm.shape()[1] != k {
        return Err(CyclogramError::WeightLength {
            field: "per_rpm",
            expected: k,
            got: per_rpm.shape()[1],
        }
        .into_pyerr(py));
    }
    let designs = per_rpm.shape()[0];
    let net = ProportionalNetwork {
        n_nodes,
        src: CyclogramError::slice(py, "src", &src)?,
        dst: CyclogramError::slice(py, "dst", &dst)?,
        base: CyclogramError::slice(py, "base", &base)?,
        source,
        target,
        lim_shift,
        min_edge: CyclogramError::slice(py, "min_edge", &min_edge)?,
        angle: CyclogramError::slice(py, "angle", &angle)?,
        secs: CyclogramError::slice(py, "secs", &secs)?,
        bound_op: CyclogramError::slice(py, "bound_op", &bound_op)?,
    };
    let slopes = CyclogramError::slice(py, "per_rpm", &per_rpm)?;
    let search = SpeedSearch {
        start,
        floor,
        cap,
        rtol,
    };
    let out = run(py, "speed_limits_proportional", || {
        cyclogram::speed_limits_proportional(&net, slopes, designs, search, n_threads)
    })?;
    Ok(out.into_pyarray(py))
}
