//! Bindings of the linkage domain: a compiled program, solved over angle grids.

use cyclomech_core::linkage::{self, LinkageError, Step};
use cyclomech_core::triad::Triad;
use numpy::ndarray::{Array1, Array3};
use numpy::{IntoPyArray, PyArray1, PyArray3, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;

use crate::errors::{run, IntoPyErr};

fn bad(py: Python<'_>, why: String) -> PyErr {
    LinkageError::BadProgram { step: 0, why }.into_pyerr(py)
}

/// A linkage compiled into solving steps (see `cyclomech.Linkage`).
///
/// `kind[s]` is 0 for the driver (idx = pivot, tip; dims = radius), 1 for two
/// circles (idx = a, b, p; dims = ra, rb, sign) and 2 for a class III group
/// (idx = 3 anchors, 3 joints; dims = 3 arms, 3 sides, orientation). Rows of `idx`
/// have 6 entries and rows of `dims` 7; unused entries are ignored.
#[pyclass(module = "cyclomech._core", frozen)]
pub struct LinkageProgram {
    program: linkage::Program,
}

#[pymethods]
impl LinkageProgram {
    #[new]
    #[allow(clippy::too_many_arguments)] // the flat arrays of the compiled program
    fn new(
        py: Python<'_>,
        n_points: usize,
        fixed_idx: PyReadonlyArray1<'_, i64>,
        fixed_xy: PyReadonlyArray2<'_, f64>,
        kind: PyReadonlyArray1<'_, i64>,
        idx: PyReadonlyArray2<'_, i64>,
        dims: PyReadonlyArray2<'_, f64>,
        drawn_phi: f64,
        drawn_xy: PyReadonlyArray2<'_, f64>,
    ) -> PyResult<Self> {
        let (fi, fx) = (fixed_idx.as_array(), fixed_xy.as_array());
        let (kd, ix, dm) = (kind.as_array(), idx.as_array(), dims.as_array());
        let dx = drawn_xy.as_array();
        if fx.shape() != [fi.len(), 2]
            || ix.shape() != [kd.len(), 6]
            || dm.shape() != [kd.len(), 7]
            || dx.shape() != [n_points, 2]
        {
            return Err(bad(py, "array shapes do not match".into()));
        }
        let index = |v: i64| -> PyResult<usize> {
            usize::try_from(v)
                .ok()
                .filter(|&u| u < n_points)
                .ok_or_else(|| bad(py, format!("point index {v} out of range")))
        };
        let mut fixed = Vec::with_capacity(fi.len());
        for (k, &i) in fi.iter().enumerate() {
            fixed.push((index(i)?, [fx[[k, 0]], fx[[k, 1]]]));
        }
        let mut steps = Vec::with_capacity(kd.len());
        for (s, &k) in kd.iter().enumerate() {
            steps.push(match k {
                0 => Step::Driver {
                    pivot: index(ix[[s, 0]])?,
                    tip: index(ix[[s, 1]])?,
                    radius: dm[[s, 0]],
                },
                1 => Step::Circles {
                    a: index(ix[[s, 0]])?,
                    b: index(ix[[s, 1]])?,
                    p: index(ix[[s, 2]])?,
                    ra: dm[[s, 0]],
                    rb: dm[[s, 1]],
                    sign: dm[[s, 2]],
                },
                2 => Step::Triad {
                    anchors: [index(ix[[s, 0]])?, index(ix[[s, 1]])?, index(ix[[s, 2]])?],
                    joints: [index(ix[[s, 3]])?, index(ix[[s, 4]])?, index(ix[[s, 5]])?],
                    triad: Triad {
                        arms: [dm[[s, 0]], dm[[s, 1]], dm[[s, 2]]],
                        sides: [dm[[s, 3]], dm[[s, 4]], dm[[s, 5]]],
                        orientation: dm[[s, 6]],
                    },
                },
                other => return Err(bad(py, format!("unknown step kind {other}"))),
            });
        }
        let drawn = (0..n_points).map(|k| [dx[[k, 0]], dx[[k, 1]]]).collect();
        let program = linkage::Program {
            n_points,
            fixed,
            steps,
            drawn: Some((drawn_phi, drawn)),
        };
        run(py, "LinkageProgram", || program.validate())?;
        Ok(LinkageProgram { program })
    }

    #[getter]
    fn n_points(&self) -> usize {
        self.program.n_points
    }

    /// Solve over absolute crank angles [rad]: (xy, vel, acc) of shape (N, P, 2),
    /// ok (N,) and singular (N,).
    #[pyo3(signature = (angles, *, n_threads=None))]
    #[allow(clippy::type_complexity)]
    fn solve<'py>(
        &self,
        py: Python<'py>,
        angles: PyReadonlyArray1<'py, f64>,
        n_threads: Option<i64>,
    ) -> PyResult<(
        Bound<'py, PyArray3<f64>>,
        Bound<'py, PyArray3<f64>>,
        Bound<'py, PyArray3<f64>>,
        Bound<'py, PyArray1<bool>>,
        Bound<'py, PyArray1<bool>>,
    )> {
        let a = angles
            .as_slice()
            .map_err(|_| bad(py, "angles must be C-contiguous".into()))?;
        let (n, p) = (a.len(), self.program.n_points);
        let s = run(py, "Linkage.solve", || self.program.solve(a, n_threads))?;
        let shape = |v: Vec<f64>| {
            Array3::from_shape_vec((n, p, 2), v).map_err(|e| {
                pyo3::exceptions::PyRuntimeError::new_err(format!("internal error: {e}"))
            })
        };
        Ok((
            shape(s.xy)?.into_pyarray(py),
            shape(s.vel)?.into_pyarray(py),
            shape(s.acc)?.into_pyarray(py),
            Array1::from(s.ok).into_pyarray(py),
            Array1::from(s.singular).into_pyarray(py),
        ))
    }
}
