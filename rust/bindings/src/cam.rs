//! Bindings of the cam domain: a validated cam and its exact geometry over angles.

use cyclomech_core::cam::{Cam, CamError, Follower, Kind, Program, SegmentSpec, N_COLUMNS};
use numpy::ndarray::Ix2;
use numpy::{PyArray2, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;

use crate::convert::{self, LayoutError};
use crate::errors::{run, IntoPyErr};

fn kind(py: Python<'_>, index: usize, name: &str) -> PyResult<Kind> {
    match name {
        "rise" => Ok(Kind::Rise),
        "dwell" => Ok(Kind::Dwell),
        "return" => Ok(Kind::Return),
        _ => Err(CamError::BadFollower {
            field: "kind",
            value: index as f64,
            why: format!("{name:?} must be rise, dwell or return"),
        }
        .into_pyerr(py)),
    }
}

/// A validated cam: program, follower and closure (see `cyclomech.cam`).
#[pyclass(module = "cyclomech._core", frozen)]
pub struct CamKernel {
    cam: Cam,
}

#[pymethods]
impl CamKernel {
    /// `follower` is "translating" (params base, roller, offset), "flat" (base)
    /// or "oscillating" (pivot distance, arm length, base, roller); angles in rad.
    #[new]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        kinds: Vec<String>,
        angles: Vec<f64>,
        strokes: Vec<f64>,
        laws: Vec<String>,
        follower: &str,
        params: Vec<f64>,
        groove: bool,
    ) -> PyResult<Self> {
        let n = kinds.len();
        if angles.len() != n || strokes.len() != n || laws.len() != n {
            return Err(CamError::BadFollower {
                field: "segments",
                value: n as f64,
                why: "kinds, angles, strokes and laws must have one entry per segment".into(),
            }
            .into_pyerr(py));
        }
        let mut specs = Vec::with_capacity(n);
        for i in 0..n {
            specs.push(SegmentSpec {
                kind: kind(py, i, &kinds[i])?,
                angle: angles[i],
                stroke: strokes[i],
                law: laws[i].clone(),
            });
        }
        let follower = match (follower, params.as_slice()) {
            ("translating", &[b, r, e]) => Follower::TranslatingRoller {
                base_radius: b,
                roller_radius: r,
                offset: e,
            },
            ("flat", &[b]) => Follower::FlatFaced { base_radius: b },
            ("oscillating", &[a, l, b, r]) => Follower::OscillatingRoller {
                pivot_distance: a,
                arm_length: l,
                base_radius: b,
                roller_radius: r,
            },
            _ => {
                return Err(CamError::BadFollower {
                    field: "follower",
                    value: params.len() as f64,
                    why: format!("{follower:?}: unknown kind or wrong parameter count"),
                }
                .into_pyerr(py))
            }
        };
        Program::new(&specs)
            .and_then(|p| Cam::new(p, follower, groove))
            .map(|cam| CamKernel { cam })
            .map_err(|e| e.into_pyerr(py))
    }

    /// Initial arm angle ψ0 [rad] of an oscillating follower, else None.
    #[getter]
    fn initial_arm_angle(&self) -> Option<f64> {
        self.cam.initial_arm_angle()
    }

    /// (N, 14) rows of s, s', s'', s''', pitch, profile, outer flank, pressure
    /// angle, radii of curvature and undercut (0/1) at cam angles `theta` [rad].
    #[pyo3(signature = (theta, *, n_threads=None))]
    fn solve<'py>(
        &self,
        py: Python<'py>,
        theta: PyReadonlyArray1<'py, f64>,
        n_threads: Option<i64>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let ts = CamError::slice(py, "theta", &theta)?;
        let out = convert::zeros::<f64, Ix2>(
            py,
            &[ts.len(), N_COLUMNS],
            "CamKernel.solve",
            "solve fewer cam angles at a time",
        )?;
        {
            let mut rw = out.readwrite();
            let slice = convert::output(py, &mut rw)?;
            run(py, "CamKernel.solve", || {
                self.cam.solve_into(ts, slice, n_threads)
            })?;
        }
        Ok(out)
    }
}
