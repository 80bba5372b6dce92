//! Bindings of the press domain: gear-lever drive kinematics, criteria, sweeps.

use cyclomech_core::press::{self, Design, Grid, KinOut, PressError, Spec, Stroke, CRITERIA};
use numpy::ndarray::IxDyn;
use numpy::{
    PyArray1, PyArrayDyn, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyReadwriteArray1,
    PyReadwriteArray2, PyUntypedArrayMethods,
};
use pyo3::prelude::*;

use crate::convert::{self, LayoutError};
use crate::errors::{run, IntoPyErr};

fn bad(py: Python<'_>, why: String) -> PyErr {
    PressError::BadSpec(why).into_pyerr(py)
}

fn spec(
    py: Python<'_>,
    k_sp: Option<f64>,
    working_stroke: Option<f64>,
    omega: f64,
    samples: usize,
) -> PyResult<Spec> {
    let stroke = match (k_sp, working_stroke) {
        (Some(k), None) => Stroke::Fraction(k),
        (None, Some(s)) => Stroke::Length(s),
        _ => {
            return Err(bad(
                py,
                "give exactly one of k_Sp and working_stroke".into(),
            ))
        }
    };
    Ok(Spec {
        stroke,
        omega,
        samples,
    })
}

/// Check one design (R > r > 0 with R/r whole, d ≥ 0, L > 0, all finite);
/// returns the gear ratio.
#[pyfunction]
#[pyo3(signature = (big_r, r, d, l, phi0, offset))]
pub fn press_check(
    py: Python<'_>,
    big_r: f64,
    r: f64,
    d: f64,
    l: f64,
    phi0: f64,
    offset: f64,
) -> PyResult<f64> {
    Design {
        big_r,
        r,
        d,
        l,
        phi0,
        offset,
    }
    .validate()
    .map_err(|e| e.into_pyerr(py))
}

/// Names of the criteria columns, in order.
#[pyfunction]
pub fn press_criteria_names() -> Vec<&'static str> {
    CRITERIA.to_vec()
}

type Kinematics<'py> = (
    Bound<'py, PyArrayDyn<f64>>,
    Bound<'py, PyArrayDyn<f64>>,
    Bound<'py, PyArrayDyn<f64>>,
    Bound<'py, PyArrayDyn<f64>>,
    Bound<'py, PyArrayDyn<f64>>,
    Bound<'py, PyArrayDyn<f64>>,
    Bound<'py, PyArrayDyn<bool>>,
);

/// Kinematics of K designs (rows R, r, d, L, φ0, offset) over α (N,) counted
/// from each design's BDC: s, ds, dds (K, N); centre, pin, slider (K, N, 2); ok.
#[pyfunction]
#[pyo3(signature = (designs, alpha, *, n_threads=None))]
pub fn press_solve<'py>(
    py: Python<'py>,
    designs: PyReadonlyArray2<'py, f64>,
    alpha: PyReadonlyArray1<'py, f64>,
    n_threads: Option<i64>,
) -> PyResult<Kinematics<'py>> {
    let dv = designs.as_array();
    if dv.shape()[1] != 6 {
        return Err(bad(py, "designs must have shape (K, 6)".into()));
    }
    let list: Vec<Design> = dv
        .rows()
        .into_iter()
        .map(|r| Design {
            big_r: r[0],
            r: r[1],
            d: r[2],
            l: r[3],
            phi0: r[4],
            offset: r[5],
        })
        .collect();
    let a = PressError::slice(py, "alpha", &alpha)?;
    let (k, n) = (list.len(), a.len());
    let what = format!("the press's kinematics ({k} designs × {n} angles × 9 float64 and 1 flag)");
    let hint = "solve fewer designs or angles at a time";
    let f8 = std::mem::size_of::<f64>();
    convert::check(py, &what, convert::nbytes(&[(&[k, n], 9 * f8 + 1)]), hint)?;
    let f = |shape: &[usize]| convert::zeros::<f64, IxDyn>(py, shape, &what, hint);
    let out = (
        f(&[k, n])?,
        f(&[k, n])?,
        f(&[k, n])?,
        f(&[k, n, 2])?,
        f(&[k, n, 2])?,
        f(&[k, n, 2])?,
        convert::zeros::<bool, IxDyn>(py, &[k, n], &what, hint)?,
    );
    {
        let (mut s, mut ds, mut dds) = (out.0.readwrite(), out.1.readwrite(), out.2.readwrite());
        let (mut c, mut p, mut sl) = (out.3.readwrite(), out.4.readwrite(), out.5.readwrite());
        let mut ok = out.6.readwrite();
        let kin = KinOut {
            s: convert::output(py, &mut s)?,
            ds: convert::output(py, &mut ds)?,
            dds: convert::output(py, &mut dds)?,
            centre: convert::output(py, &mut c)?,
            pin: convert::output(py, &mut p)?,
            slider: convert::output(py, &mut sl)?,
            ok: convert::output(py, &mut ok)?,
        };
        run(py, "GearLeverPress.solve", || {
            press::solve_into(&list, a, n_threads, kin)
        })?;
    }
    Ok(out)
}

/// Criteria over the Cartesian grid of designs (C order R, r, d, L, φ0), written
/// into `rows` (n, 14), in the order of `press_criteria_names()`, and `status`
/// (n,) uint8: the caller allocates the whole sweep's output once and passes a
/// chunk's slice, so that nothing is copied afterwards.
#[pyfunction]
#[pyo3(signature = (big_r, r, d, l, phi0, rows, status, *, offset, k_sp, working_stroke, omega, samples, n_threads=None))]
#[allow(clippy::too_many_arguments)] // the grid's axes, the outputs and the criteria's settings
pub fn press_sweep<'py>(
    py: Python<'py>,
    big_r: PyReadonlyArray1<'py, f64>,
    r: PyReadonlyArray1<'py, f64>,
    d: PyReadonlyArray1<'py, f64>,
    l: PyReadonlyArray1<'py, f64>,
    phi0: PyReadonlyArray1<'py, f64>,
    mut rows: PyReadwriteArray2<'py, f64>,
    mut status: PyReadwriteArray1<'py, u8>,
    offset: f64,
    k_sp: Option<f64>,
    working_stroke: Option<f64>,
    omega: f64,
    samples: usize,
    n_threads: Option<i64>,
) -> PyResult<()> {
    let grid = Grid {
        big_r: PressError::slice(py, "R", &big_r)?,
        r: PressError::slice(py, "r", &r)?,
        d: PressError::slice(py, "d", &d)?,
        l: PressError::slice(py, "L", &l)?,
        phi0: PressError::slice(py, "phi0", &phi0)?,
        offset,
    };
    let spec = spec(py, k_sp, working_stroke, omega, samples)?;
    // The grid's size is a product of the axes' lengths: refuse one that
    // overflows before anything sizes a buffer by it.
    let axes = [grid.big_r, grid.r, grid.d, grid.l, grid.phi0];
    if axes
        .iter()
        .try_fold(1usize, |n, a| n.checked_mul(a.len()))
        .and_then(|n| n.checked_mul(CRITERIA.len() * std::mem::size_of::<f64>()))
        .is_none()
    {
        let lens: Vec<usize> = axes.iter().map(|a| a.len()).collect();
        return Err(bad(
            py,
            format!("the grid of {lens:?} designs is too large to index; sweep it in parts"),
        ));
    }
    let n = grid.len();
    let want = [n, CRITERIA.len()];
    if rows.shape() != want || status.shape() != [n] {
        return Err(bad(
            py,
            format!(
                "rows must have shape {want:?} and status ({n},) for {n} designs; got {:?} and {:?}",
                rows.shape(),
                status.shape()
            ),
        ));
    }
    let rs = PressError::slice_mut(py, "rows", &mut rows)?;
    let ss = PressError::slice_mut(py, "status", &mut status)?;
    run(py, "press.sweep", || {
        press::sweep_into(&grid, &spec, n_threads, rs, ss)
    })
}

/// True for the rows of `points` (n, m) that no other row dominates (lower is
/// better in every column).
#[pyfunction]
pub fn pareto_mask<'py>(
    py: Python<'py>,
    points: PyReadonlyArray2<'py, f64>,
) -> PyResult<Bound<'py, PyArray1<bool>>> {
    let m = points.shape()[1];
    let flat = PressError::slice(py, "points", &points)?;
    let mask = run(py, "pareto_mask", || press::pareto_mask(flat, m))?;
    Ok(PyArray1::from_vec(py, mask))
}
