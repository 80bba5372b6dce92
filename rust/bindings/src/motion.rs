//! Bindings of the motion domain: dimensionless laws and the two-period law.

use cyclomech_core::motion::{Law, MotionError, TwoPeriod};
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;

use crate::convert::{self, LayoutError};
use crate::errors::{run, IntoPyErr};

/// A derivative order from Python (any int) as 0..=3, or a typed error (a
/// negative int would otherwise be pyo3's OverflowError).
fn order_arg(py: Python<'_>, order: i64) -> PyResult<usize> {
    usize::try_from(order)
        .ok()
        .filter(|&o| o <= 3)
        .ok_or_else(|| {
            MotionError::BadLaw {
                what: format!("order must be 0, 1, 2 or 3 (the derivative); got {order}"),
            }
            .into_pyerr(py)
        })
}

/// Evaluate `f` into a new float64 array of the length of `x`, GIL released.
fn evaluate<'py, F>(
    py: Python<'py>,
    kernel: &'static str,
    x: &[f64],
    f: F,
) -> PyResult<Bound<'py, PyArray1<f64>>>
where
    F: FnOnce(&mut [f64]) -> Result<(), MotionError> + Send,
{
    let out = convert::zeros(py, &[x.len()], kernel, "evaluate fewer points at a time")?;
    {
        let mut rw = out.readwrite();
        let slice = convert::output(py, &mut rw)?;
        run(py, kernel, || f(slice))?;
    }
    Ok(out)
}

/// A dimensionless law Z(x) on the unit square (see `cyclomech.motion`).
#[pyclass(module = "cyclomech._core", frozen)]
pub struct MotionLaw {
    law: Law,
}

#[pymethods]
impl MotionLaw {
    /// A named law: its full rise, or its half law.
    #[staticmethod]
    fn named(py: Python<'_>, name: &str, rise: bool) -> PyResult<Self> {
        let law = if rise {
            Law::rise(name)
        } else {
            Law::half(name)
        };
        law.map(|law| MotionLaw { law })
            .map_err(|e| e.into_pyerr(py))
    }

    /// A user polynomial Z = Σ c_k x^k, checked as a rise or a half law.
    #[staticmethod]
    fn polynomial(py: Python<'_>, coeffs: PyReadonlyArray1<'_, f64>, rise: bool) -> PyResult<Self> {
        let c = MotionError::slice(py, "coeffs", &coeffs)?;
        Law::polynomial(c, rise)
            .map(|law| MotionLaw { law })
            .map_err(|e| e.into_pyerr(py))
    }

    #[getter]
    fn dz_max(&self) -> f64 {
        self.law.dz_max
    }

    #[getter]
    fn ddz_max(&self) -> f64 {
        self.law.ddz_max
    }

    /// Breakpoints of the law's pieces on [0, 1].
    #[getter]
    fn breaks(&self) -> Vec<f64> {
        let mut b: Vec<f64> = self.law.segments.iter().map(|s| s.x0).collect();
        b.push(1.0);
        b
    }

    /// Z^(order)(x) for order 0..=3 (x in [0, 1]).
    #[pyo3(signature = (x, order, *, n_threads=None))]
    fn eval<'py>(
        &self,
        py: Python<'py>,
        x: PyReadonlyArray1<'py, f64>,
        order: i64,
        n_threads: Option<i64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let order = order_arg(py, order)?;
        let xs = MotionError::slice(py, "x", &x)?;
        evaluate(py, "MotionLaw.eval", xs, |out| {
            self.law.eval_into(xs, order, n_threads, out)
        })
    }
}

/// The two-period slider law of seed 003 (see `cyclomech.motion.two_period`).
#[pyclass(module = "cyclomech._core", frozen)]
pub struct TwoPeriodKernel {
    law: TwoPeriod,
}

#[pymethods]
impl TwoPeriodKernel {
    #[new]
    fn new(
        law1: &MotionLaw,
        law2: &MotionLaw,
        stroke1: f64,
        angle1: f64,
        stroke: f64,
        angle: f64,
    ) -> Self {
        TwoPeriodKernel {
            law: TwoPeriod {
                law1: law1.law.clone(),
                law2: law2.law.clone(),
                stroke1,
                angle1,
                stroke,
                angle,
            },
        }
    }

    /// Π^(order)(α) for order 0..=3 (α in [0, α2]); into `out` (a writeable
    /// C-contiguous float64 array of α's length that overlaps no input,
    /// checked by the Python layer) and returned, if it is given.
    #[pyo3(signature = (alpha, order, *, n_threads=None, out=None))]
    fn eval<'py>(
        &self,
        py: Python<'py>,
        alpha: PyReadonlyArray1<'py, f64>,
        order: i64,
        n_threads: Option<i64>,
        out: Option<Bound<'py, PyArray1<f64>>>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let order = order_arg(py, order)?;
        let a = MotionError::slice(py, "alpha", &alpha)?;
        let Some(out) = out else {
            return evaluate(py, "TwoPeriodLaw.eval", a, |out| {
                self.law.eval_into(a, order, n_threads, out)
            });
        };
        {
            let bad = |what: String| {
                MotionError::BadLaw {
                    what: format!(
                        "out must be a writeable C-contiguous float64 array of {} values \
                         that overlaps no input; got {what}",
                        a.len()
                    ),
                }
                .into_pyerr(py)
            };
            let mut rw = out
                .try_readwrite()
                .map_err(|e| bad(format!("an array numpy will not lend for writing ({e})")))?;
            let slice = convert::output(py, &mut rw)?;
            if slice.len() != a.len() {
                return Err(bad(format!("{} values", slice.len())));
            }
            run(py, "TwoPeriodLaw.eval", || {
                self.law.eval_into(a, order, n_threads, slice)
            })?;
        }
        Ok(out)
    }
}
