//! Bindings of the rotor transfer: the quintic's values and arc length, the
//! composed path sampled, the kinematics along it, the candidate scan of the
//! design and the longest transitions a gap allows. Every kernel runs with the
//! GIL released (`errors::run`).

use cyclomech_core::transfer::{
    kinematics_into, longest, peak_jerk, quintic, quintic_eval_into, sample_into, PathSpec,
    QuinticValue, SampleOut, SpeedLaw, TransferError, N_KINEMATICS,
};
use numpy::ndarray::{Dimension, Ix1, Ix2};
use numpy::{
    Element, IntoPyArray, PyArray, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::convert::{self, LayoutError};
use crate::errors::{input_error, run, IntoPyErr};

impl LayoutError for TransferError {
    fn layout(field: &'static str) -> Self {
        TransferError::Layout { field }
    }
}

/// A new C-order array of `shape`, not zeroed: every kernel here writes every
/// element of its outputs (a zeroed array would be written twice, and calloc's
/// clearing of reused memory is a pass over the whole output).
fn empty<'py, T: Element, D: Dimension>(
    py: Python<'py>,
    shape: &[usize],
    what: &str,
) -> PyResult<Bound<'py, PyArray<T, D>>> {
    convert::empty(py, shape, what, "ask for fewer points at a time")
}

fn new_f64<'py, D: Dimension>(
    py: Python<'py>,
    shape: &[usize],
    what: &str,
) -> PyResult<Bound<'py, PyArray<f64, D>>> {
    empty::<f64, D>(py, shape, what)
}

/// The quintic with coefficients `coeffs` (a0 … a5) at every `x` [m]: `what`
/// one of "y", "dy", "ddy", "dddy", "curvature", "curvature_rate",
/// "arc_length" (from 0, 16-point Gauss–Legendre on pieces).
#[pyfunction]
#[pyo3(signature = (coeffs, x, what, *, n_threads=None))]
pub fn transfer_quintic<'py>(
    py: Python<'py>,
    coeffs: PyReadonlyArray1<'py, f64>,
    x: PyReadonlyArray1<'py, f64>,
    what: &str,
    n_threads: Option<i64>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let value = match what {
        "y" => QuinticValue::Derivative(0),
        "dy" => QuinticValue::Derivative(1),
        "ddy" => QuinticValue::Derivative(2),
        "dddy" => QuinticValue::Derivative(3),
        "curvature" => QuinticValue::Curvature,
        "curvature_rate" => QuinticValue::CurvatureRate,
        "arc_length" => QuinticValue::ArcLength,
        other => {
            return Err(input_error(
                py,
                format!(
                    "what = {other:?} must be one of y, dy, ddy, dddy, curvature, \
                     curvature_rate, arc_length"
                ),
            ))
        }
    };
    let c = TransferError::slice(py, "coeffs", &coeffs)?;
    let q = quintic(c).map_err(|e| e.into_pyerr(py))?;
    let xs = TransferError::slice(py, "x", &x)?;
    let out = new_f64::<Ix1>(py, &[xs.len()], "transfer_quintic")?;
    {
        let mut rw = out.readwrite();
        let o = convert::output(py, &mut rw)?;
        run(py, "transfer_quintic", || {
            quintic_eval_into(&q, xs, value, o, n_threads)
        })?;
    }
    Ok(out)
}

/// The six arrays a path sample is written into: points (n, 2), s, heading,
/// curvature, curvature_rate (n,) and piece (n,) int8.
type SampleArrays<'py> = (
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<i8>>,
);

/// The composed path of `spec` (see `cyclomech_core::transfer::N_SPEC`) with
/// `counts` points on its five pieces: (points (n, 2), s, heading, curvature,
/// curvature_rate, piece (int8)). `out`, if given, is those six arrays (C-contiguous,
/// of those shapes; the Python layer checks them), written in place and returned.
#[pyfunction]
#[pyo3(signature = (spec, counts, ccw, *, n_threads=None, out=None))]
pub fn transfer_sample<'py>(
    py: Python<'py>,
    spec: PyReadonlyArray1<'py, f64>,
    counts: PyReadonlyArray1<'py, i64>,
    ccw: bool,
    n_threads: Option<i64>,
    out: Option<SampleArrays<'py>>,
) -> PyResult<Bound<'py, PyTuple>> {
    let spec = PathSpec::from_flat(TransferError::slice(py, "spec", &spec)?)
        .map_err(|e| e.into_pyerr(py))?;
    let c = TransferError::slice(py, "counts", &counts)?;
    if c.len() != 5 || c.iter().any(|&v| v < 2) {
        return Err(input_error(
            py,
            format!("counts = {c:?} must be five counts ≥ 2 (one per piece)"),
        ));
    }
    let counts = [0, 1, 2, 3, 4].map(|i| c[i] as usize);
    let n: usize = counts.iter().sum();
    let (points, s, heading, curvature, rate, piece) = match out {
        Some(arrays) => {
            let (p, s) = (&arrays.0, &arrays.1);
            let shapes = [s.len(), arrays.2.len(), arrays.3.len(), arrays.4.len()];
            if p.shape() != [n, 2] || shapes.iter().any(|&l| l != n) || arrays.5.len() != n {
                return Err(input_error(
                    py,
                    format!(
                        "out holds arrays of {} points; this sample has {n}",
                        s.len()
                    ),
                ));
            }
            arrays
        }
        None => {
            convert::check(
                py,
                &format!("transfer_sample({n})"),
                convert::nbytes(&[(&[n, 6], 8), (&[n], 1)]),
                "sample fewer points",
            )?;
            let points = new_f64::<Ix2>(py, &[n, 2], "transfer_sample")?;
            let arrays = [0, 1, 2, 3].map(|_| new_f64::<Ix1>(py, &[n], "transfer_sample"));
            let [s, heading, curvature, rate] = arrays;
            // Every element is written (each block fills its piece index).
            let piece = empty::<i8, Ix1>(py, &[n], "transfer_sample")?;
            (points, s?, heading?, curvature?, rate?, piece)
        }
    };
    {
        let (mut p, mut s_, mut h, mut k, mut r, mut i) = (
            points.readwrite(),
            s.readwrite(),
            heading.readwrite(),
            curvature.readwrite(),
            rate.readwrite(),
            piece.readwrite(),
        );
        let out = SampleOut {
            points: convert::output(py, &mut p)?,
            s: convert::output(py, &mut s_)?,
            heading: convert::output(py, &mut h)?,
            curvature: convert::output(py, &mut k)?,
            rate: convert::output(py, &mut r)?,
            piece: convert::output(py, &mut i)?,
        };
        run(py, "transfer_sample", || {
            sample_into(&spec, &counts, ccw, out, n_threads)
        })?;
    }
    PyTuple::new(
        py,
        [
            points.into_any(),
            s.into_any(),
            heading.into_any(),
            curvature.into_any(),
            rate.into_any(),
            piece.into_any(),
        ],
    )
}

/// (8, n) kinematics along a sampled path (arc length `s`, `curvature`,
/// `curvature_rate`) for the speed law (v_t, v_p, start, span): rows time,
/// speed, normal, tangential, total, normal_rate, tangential_rate, jerk.
#[pyfunction]
#[pyo3(signature = (s, curvature, curvature_rate, law, *, n_threads=None))]
pub fn transfer_kinematics<'py>(
    py: Python<'py>,
    s: PyReadonlyArray1<'py, f64>,
    curvature: PyReadonlyArray1<'py, f64>,
    curvature_rate: PyReadonlyArray1<'py, f64>,
    law: (f64, f64, f64, f64),
    n_threads: Option<i64>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let law = SpeedLaw::new(law.0, law.1, law.2, law.3).map_err(|e| e.into_pyerr(py))?;
    let s = TransferError::slice(py, "s", &s)?;
    let k = TransferError::slice(py, "curvature", &curvature)?;
    let r = TransferError::slice(py, "curvature_rate", &curvature_rate)?;
    let out = new_f64::<Ix2>(py, &[N_KINEMATICS, s.len()], "transfer_kinematics")?;
    {
        let mut rw = out.readwrite();
        let o = convert::output(py, &mut rw)?;
        run(py, "transfer_kinematics", || {
            kinematics_into(s, k, r, &law, o, n_threads)
        })?;
    }
    Ok(out)
}

/// Peak jerk [m/s³] of each candidate transition length `x2` [m] (both sides)
/// between circles `radii` (R_t, R_p) with centres `distance` apart, for the
/// speeds (V_t, V_p), on `n_points` points a piece.
#[pyfunction]
#[pyo3(signature = (radii, distance, x2, speed, n_points, *, n_threads=None))]
pub fn transfer_peak_jerk<'py>(
    py: Python<'py>,
    radii: (f64, f64),
    distance: f64,
    x2: PyReadonlyArray1<'py, f64>,
    speed: (f64, f64),
    n_points: usize,
    n_threads: Option<i64>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let x = TransferError::slice(py, "x2", &x2)?;
    let out = run(py, "transfer_peak_jerk", || {
        peak_jerk(
            [radii.0, radii.1],
            distance,
            x,
            [speed.0, speed.1],
            n_points,
            n_threads,
        )
    })?;
    Ok(out.into_pyarray(py))
}

/// The longest transitions (x2_t, x2_p) = λ·`ratio` [m] that fit between
/// circles `radii` with centres `distance` apart; None if none fits.
#[pyfunction]
pub fn transfer_longest(
    py: Python<'_>,
    radii: (f64, f64),
    distance: f64,
    ratio: (f64, f64),
) -> PyResult<Option<(f64, f64)>> {
    let got = run(py, "transfer_longest", || {
        longest([radii.0, radii.1], distance, [ratio.0, ratio.1])
    })?;
    Ok(got.map(|[a, b]| (a, b)))
}
