//! Bindings of path generation (issue 35, item 2): the batch evaluator of
//! candidate four-bars and slider-cranks, one call per population.

use cyclomech_core::input::InvalidInput;
use cyclomech_core::synthesis::path::{self, Kind, Spec, COLUMNS};
use numpy::{PyArray2, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;

use crate::convert;
use crate::errors::{input_error, run};

/// A C-contiguous input array's values, else an `InputError` naming it.
fn flat<'a, D: numpy::ndarray::Dimension>(
    py: Python<'_>,
    field: &str,
    a: &'a numpy::PyReadonlyArray<'_, f64, D>,
) -> PyResult<&'a [f64]> {
    a.as_slice()
        .map_err(|_| input_error(py, format!("{field} must be a C-contiguous float64 array")))
}

/// Evaluate candidates `params` (K, 10) or, with timing, (K, 11) against the
/// targets (N, 2): returns (K, 6) in the order of `path_columns()` and, when
/// `angles`, the crank angle [rad] of each target (K, N).
#[pyfunction]
#[pyo3(signature = (kind, params, targets, timing=None, *, samples=90, refine=40, full_turn=true, min_transmission=0.0, max_ratio=f64::INFINITY, pivot_box=None, angles=false, n_threads=None))]
#[allow(clippy::too_many_arguments)] // the targets, the rule and each constraint
#[allow(clippy::type_complexity)]
pub fn path_evaluate<'py>(
    py: Python<'py>,
    kind: &str,
    params: PyReadonlyArray2<'py, f64>,
    targets: PyReadonlyArray2<'py, f64>,
    timing: Option<PyReadonlyArray1<'py, f64>>,
    samples: usize,
    refine: usize,
    full_turn: bool,
    min_transmission: f64,
    max_ratio: f64,
    pivot_box: Option<[f64; 4]>,
    angles: bool,
    n_threads: Option<i64>,
) -> PyResult<(Bound<'py, PyArray2<f64>>, Option<Bound<'py, PyArray2<f64>>>)> {
    let kind = parse_kind(py, kind)?;
    let p = flat(py, "params", &params)?;
    let t = flat(py, "targets", &targets)?;
    let tm = match &timing {
        Some(a) => Some(flat(py, "timing", a)?),
        None => None,
    };
    let spec = Spec {
        kind,
        targets: t,
        timing: tm,
        samples,
        refine,
        full_turn,
        min_transmission,
        max_ratio,
        pivot_box,
    };
    let (k, w) = (params.shape()[0], params.shape()[1]);
    if w != spec.width() || targets.shape()[1] != 2 {
        return Err(input_error(
            py,
            format!(
                "params must have {} columns and targets 2; got {w} and {}",
                spec.width(),
                targets.shape()[1]
            ),
        ));
    }
    let n = targets.shape()[0];
    let nc = COLUMNS.len();
    convert::check(
        py,
        "path_evaluate's results",
        convert::nbytes(&[(&[k, nc], 8), (&[k, if angles { n } else { 0 }], 8)]),
        "evaluate the candidates in parts",
    )?;
    let mut out = vec![0.0; k * nc];
    let mut ang = if angles { Some(vec![0.0; k * n]) } else { None };
    run(
        py,
        "synthesis.path_evaluate",
        || -> Result<(), InvalidInput> {
            path::evaluate_into(&spec, p, n_threads, &mut out, ang.as_deref_mut())
        },
    )?;
    let out = convert::shaped(py, k, nc, out)?;
    let ang = match ang {
        Some(a) => Some(PyArray2::from_owned_array(
            py,
            convert::shaped(py, k, n, a)?,
        )),
        None => None,
    };
    Ok((PyArray2::from_owned_array(py, out), ang))
}

/// The names of `path_evaluate`'s result columns and of a candidate's columns,
/// and the cost floor of a violated candidate.
#[pyfunction]
pub fn path_columns() -> (Vec<&'static str>, Vec<&'static str>, f64) {
    (COLUMNS.to_vec(), path::PARAMS.to_vec(), path::PENALTY)
}

/// The coupler point of one candidate `row` at absolute crank angles [rad]:
/// (N, 2) [m], NaN where it does not close.
#[pyfunction]
pub fn path_points<'py>(
    py: Python<'py>,
    kind: &str,
    row: PyReadonlyArray1<'py, f64>,
    angles: PyReadonlyArray1<'py, f64>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let kind = parse_kind(py, kind)?;
    let r = flat(py, "row", &row)?;
    let a = flat(py, "angles", &angles)?;
    let n = a.len();
    let pts = run(py, "synthesis.path_points", || path::points(kind, r, a))?;
    Ok(PyArray2::from_owned_array(
        py,
        convert::shaped(py, n, 2, pts)?,
    ))
}

fn parse_kind(py: Python<'_>, kind: &str) -> PyResult<Kind> {
    match kind {
        "four_bar" => Ok(Kind::FourBar),
        "slider_crank" => Ok(Kind::SliderCrank),
        other => Err(input_error(
            py,
            format!("kind = {other:?} is not a mechanism path generation knows; use \"four_bar\" or \"slider_crank\""),
        )),
    }
}
