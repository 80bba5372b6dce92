//! Bindings of the motion domain: dimensionless laws and the two-period law.

use cyclomech_core::motion::{Law, MotionError, PieceRow, Program, SegmentSpec, TwoPeriod};
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2};
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

/// One built segment for Python: (start, angle, at start, at end, scalable,
/// (angle, velocity) where it runs backwards).
type SpanRow = (f64, f64, [f64; 4], [f64; 4], bool, Option<(f64, f64)>);

/// A motion program over one master cycle (see `cyclomech.motion.Program`).
#[pyclass(module = "cyclomech._core", frozen)]
pub struct ProgramKernel {
    pub(crate) program: Program,
}

/// The (4, N) output of [`ProgramKernel::eval`], numpy's memory.
fn program_rows(py: Python<'_>, n: usize) -> PyResult<Bound<'_, PyArray2<f64>>> {
    convert::empty(
        py,
        &[4, n],
        "Program.evaluate",
        "evaluate fewer angles at a time",
    )
}

#[pymethods]
impl ProgramKernel {
    /// Segments as parallel lists: law names, angles [rad], start and end
    /// values (N × 4: s, v, a, j; NaN = free), point tables ((angle [rad], s)
    /// pairs; empty but for a spline) and spline degrees.
    #[new]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        laws: Vec<String>,
        angles: PyReadonlyArray1<'_, f64>,
        start: PyReadonlyArray2<'_, f64>,
        end: PyReadonlyArray2<'_, f64>,
        points: Vec<Vec<[f64; 2]>>,
        degrees: Vec<usize>,
        continuity: usize,
        advance: f64,
    ) -> PyResult<Self> {
        let angles = MotionError::slice(py, "angles", &angles)?;
        let (start, end) = (start.as_array(), end.as_array());
        let n = laws.len();
        let shape_ok = angles.len() == n
            && start.shape() == [n, 4]
            && end.shape() == [n, 4]
            && points.len() == n
            && degrees.len() == n;
        if !shape_ok {
            return Err(MotionError::BadLaw {
                what:
                    "laws, angles, start, end, points and degrees must have one entry per segment"
                        .into(),
            }
            .into_pyerr(py));
        }
        let free = |v: f64| (!v.is_nan()).then_some(v);
        let specs: Vec<SegmentSpec> = (0..n)
            .map(|i| SegmentSpec {
                law: laws[i].clone(),
                angle: angles[i],
                start: std::array::from_fn(|k| free(start[[i, k]])),
                end: std::array::from_fn(|k| free(end[[i, k]])),
                points: points[i].clone(),
                degree: degrees[i],
            })
            .collect();
        run(py, "Program", || Program::new(&specs, continuity, advance))
            .map(|program| ProgramKernel { program })
    }

    /// s + c·s″: the polydyne cam motion of this program (core docs), joins
    /// checked to `continuity`.
    fn plus_second_derivative(&self, py: Python<'_>, c: f64, continuity: usize) -> PyResult<Self> {
        run(py, "Program.plus_second_derivative", || {
            self.program.plus_second_derivative(c, continuity)
        })
        .map(|program| ProgramKernel { program })
    }

    /// [s, v, a, j] at master angles θ [rad]: a (4, N) array.
    #[pyo3(signature = (theta, *, n_threads=None))]
    fn eval<'py>(
        &self,
        py: Python<'py>,
        theta: PyReadonlyArray1<'py, f64>,
        n_threads: Option<i64>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let th = MotionError::slice(py, "theta", &theta)?;
        let out = program_rows(py, th.len())?;
        {
            let mut rw = out.readwrite();
            let slice = convert::output(py, &mut rw)?;
            run(py, "Program.evaluate", || {
                self.program.eval_into(th, n_threads, slice)
            })?;
        }
        Ok(out)
    }

    /// [`ProgramKernel::eval`] and a copy of θ (N), written in the same pass as
    /// the angles are read (`Program.evaluate` keeps one): (copy, rows). Two
    /// arrays, not one (5, N): each stays under the allocator's threshold for
    /// fresh pages at a million angles (32 MiB), so that repeated calls reuse
    /// memory as numpy's own arrays of that size do.
    #[pyo3(signature = (theta, *, n_threads=None))]
    #[allow(clippy::type_complexity)]
    fn eval_with_theta<'py>(
        &self,
        py: Python<'py>,
        theta: PyReadonlyArray1<'py, f64>,
        n_threads: Option<i64>,
    ) -> PyResult<(Bound<'py, PyArray1<f64>>, Bound<'py, PyArray2<f64>>)> {
        let th = MotionError::slice(py, "theta", &theta)?;
        let copy = convert::empty(
            py,
            &[th.len()],
            "Program.evaluate",
            "evaluate fewer angles at a time",
        )?;
        let out = program_rows(py, th.len())?;
        {
            let (mut rc, mut rw) = (copy.readwrite(), out.readwrite());
            let copy_slice = convert::output(py, &mut rc)?;
            let slice = convert::output(py, &mut rw)?;
            run(py, "Program.evaluate", || {
                self.program
                    .eval_with_theta_into(th, n_threads, copy_slice, slice)
            })?;
        }
        Ok((copy, out))
    }

    /// Per segment: (start [rad], angle [rad], [s, v, a, j] at its start and
    /// at its end, scalable).
    #[getter]
    fn spans(&self) -> Vec<SpanRow> {
        self.program
            .spans()
            .iter()
            .map(|s| {
                (
                    s.start,
                    s.angle,
                    s.at_start,
                    s.at_end,
                    s.scalable,
                    s.backwards,
                )
            })
            .collect()
    }

    /// Every piece: (segment, start [rad], end [rad], coefficients, A, ω, φ).
    #[getter]
    fn pieces(&self) -> Vec<PieceRow> {
        self.program.pieces()
    }

    /// Segment `i`'s (stroke, max |v|, max |a|, max |j|, C_v, C_a, C_j, C_m).
    fn characteristics(&self, i: usize) -> [f64; 8] {
        let c = self
            .program
            .characteristics(i.min(self.program.spans().len() - 1));
        [
            c.stroke, c.peaks[0], c.peaks[1], c.peaks[2], c.cv, c.ca, c.cj, c.cm,
        ]
    }
}
