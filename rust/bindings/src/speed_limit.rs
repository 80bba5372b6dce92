//! Bindings of the cyclogram's kernels for designs with speed-proportional
//! bounds: the speed-limit search and the solve at many speeds
//! (`cyclomech.cyclogram.SpeedNetwork.speed_limits_proportional` and
//! `solve_proportional`).

use cyclomech_core::cyclogram::{self, CyclogramError, ProportionalNetwork, SolveOut, SpeedSearch};
use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;

use crate::convert::{self, LayoutError};
use crate::errors::{run, IntoPyErr};

/// What to do when a result does not fit in memory.
const HINT: &str = "sweep fewer designs or speeds per chunk";

/// (value (B,), code (B, E) int16, bound minima (B, K), run starts (B,) bool) of
/// `solve_proportional`.
type Solved<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray2<i16>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray1<bool>>,
);

/// The network's arrays, borrowed (shared by both functions).
#[allow(clippy::too_many_arguments)]
fn network<'a>(
    py: Python<'_>,
    n_nodes: i64,
    src: &'a PyReadonlyArray1<'_, i64>,
    dst: &'a PyReadonlyArray1<'_, i64>,
    base: &'a PyReadonlyArray1<'_, f64>,
    source: i64,
    target: i64,
    lim_shift: f64,
    min_edge: &'a PyReadonlyArray1<'_, i64>,
    angle: &'a PyReadonlyArray1<'_, f64>,
    secs: &'a PyReadonlyArray1<'_, f64>,
    bound_op: &'a PyReadonlyArray1<'_, i64>,
) -> PyResult<ProportionalNetwork<'a>> {
    Ok(ProportionalNetwork {
        n_nodes,
        src: CyclogramError::slice(py, "src", src)?,
        dst: CyclogramError::slice(py, "dst", dst)?,
        base: CyclogramError::slice(py, "base", base)?,
        source,
        target,
        lim_shift,
        min_edge: CyclogramError::slice(py, "min_edge", min_edge)?,
        angle: CyclogramError::slice(py, "angle", angle)?,
        secs: CyclogramError::slice(py, "secs", secs)?,
        bound_op: CyclogramError::slice(py, "bound_op", bound_op)?,
    })
}

/// The slopes (D, K) as a flat slice, K checked against the bounds.
fn slopes<'a>(
    py: Python<'_>,
    per_rpm: &'a PyReadonlyArray2<'_, f64>,
    k: usize,
) -> PyResult<(&'a [f64], usize)> {
    if per_rpm.shape()[1] != k {
        return Err(CyclogramError::WeightLength {
            field: "per_rpm",
            expected: k,
            got: per_rpm.shape()[1],
        }
        .into_pyerr(py));
    }
    Ok((
        CyclogramError::slice(py, "per_rpm", per_rpm)?,
        per_rpm.shape()[0],
    ))
}

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
    let net = network(
        py, n_nodes, &src, &dst, &base, source, target, lim_shift, &min_edge, &angle, &secs,
        &bound_op,
    )?;
    let (slopes, designs) = slopes(py, &per_rpm, bound_op.len())?;
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

/// Every design at every speed solved (`SpeedNetwork.solve_proportional`):
/// design d at `rpm[j]` is row d·S + j.
#[pyfunction]
#[pyo3(signature = (
    n_nodes, src, dst, base, source, target, lim_shift, min_edge, angle, secs, bound_op,
    per_rpm, rpm, *, n_threads=None
))]
#[allow(clippy::too_many_arguments)] // the network, the bounds and the speeds
pub fn solve_proportional<'py>(
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
    rpm: PyReadonlyArray1<'py, f64>,
    n_threads: Option<i64>,
) -> PyResult<Solved<'py>> {
    let net = network(
        py, n_nodes, &src, &dst, &base, source, target, lim_shift, &min_edge, &angle, &secs,
        &bound_op,
    )?;
    let (k, m) = (bound_op.len(), src.len());
    let (slopes, designs) = slopes(py, &per_rpm, k)?;
    let speeds = CyclogramError::slice(py, "rpm", &rpm)?;
    let b = designs.saturating_mul(speeds.len());
    let what = "solve_proportional's results";
    let value = convert::zeros::<f64, _>(py, &[b], what, HINT)?;
    let code = convert::zeros::<i16, _>(py, &[b, m], what, HINT)?;
    let mins = convert::zeros::<f64, _>(py, &[b, k], what, HINT)?;
    let starts = convert::zeros::<bool, _>(py, &[b], what, HINT)?;
    {
        let (mut vw, mut cw, mut mw) = (value.readwrite(), code.readwrite(), mins.readwrite());
        let mut sw = starts.readwrite();
        let out = SolveOut {
            value: convert::output(py, &mut vw)?,
            code: convert::output(py, &mut cw)?,
            bound_mins: convert::output(py, &mut mw)?,
            new_run: convert::output(py, &mut sw)?,
        };
        run(py, "solve_proportional", || {
            cyclogram::solve_proportional_into(&net, slopes, designs, speeds, n_threads, out)
        })?;
    }
    Ok((value, code, mins, starts))
}
