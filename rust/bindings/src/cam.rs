//! Bindings of the cam domain: a validated cam and its exact geometry over angles.

use cyclomech_core::cam::{
    Cam, CamError, Contact, Follower, Kind, Limits, Loads, Program, SegmentSpec, CRITERIA,
    N_COLUMNS, N_LOAD_COLUMNS,
};
use numpy::ndarray::{Ix2, Ix3};
use numpy::{
    PyArray1, PyArray2, PyArray3, PyArrayMethods, PyReadonlyArray1, PyUntypedArrayMethods,
};
use pyo3::prelude::*;

use crate::convert::{self, LayoutError};
use crate::errors::{run, IntoPyErr};
use crate::motion::ProgramKernel;
use cyclomech_core::input::InvalidInput;

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

/// The cam's segment specs from parallel lists; with a motion `program`,
/// each moving segment's law is the program's own on the unit square.
pub(crate) fn specs(
    py: Python<'_>,
    kinds: &[String],
    angles: &[f64],
    strokes: &[f64],
    laws: &[String],
    program: Option<&ProgramKernel>,
) -> PyResult<Vec<SegmentSpec>> {
    let mut specs = Vec::with_capacity(kinds.len());
    for i in 0..kinds.len() {
        let kind = kind(py, i, &kinds[i])?;
        let unit = match program {
            Some(p) if kind != Kind::Dwell && i < p.program.spans().len() => {
                Some(p.program.unit_law(i).2)
            }
            _ => None,
        };
        specs.push(SegmentSpec {
            kind,
            angle: angles[i],
            stroke: strokes[i],
            law: laws[i].clone(),
            unit,
        });
    }
    Ok(specs)
}

/// A validated cam: program, follower and closure (see `cyclomech.cam`).
#[pyclass(module = "cyclomech._core", frozen)]
pub struct CamKernel {
    pub(crate) cam: Cam,
}

#[pymethods]
impl CamKernel {
    /// `follower` is "translating" (params base, roller, offset), "flat" (base)
    /// or "oscillating" (pivot distance, arm length, base, roller); angles in rad.
    #[new]
    #[pyo3(signature = (kinds, angles, strokes, laws, follower, params, groove, program=None))]
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
        program: Option<PyRef<'_, ProgramKernel>>,
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
        let specs = specs(py, &kinds, &angles, &strokes, &laws, program.as_deref())?;
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
    /// Into `out` (a writeable C-contiguous float64 (N, 14) array that overlaps
    /// `theta` nowhere) when given, which is returned. With `undercut` (a
    /// writeable contiguous bool array of N), the undercut column is also
    /// written there as booleans, in the same pass; with `theta_copy` (a
    /// writeable contiguous float64 array of N), a copy of `theta`.
    #[pyo3(signature = (theta, *, n_threads=None, out=None, undercut=None, theta_copy=None))]
    fn solve<'py>(
        &self,
        py: Python<'py>,
        theta: PyReadonlyArray1<'py, f64>,
        n_threads: Option<i64>,
        out: Option<Bound<'py, PyArray2<f64>>>,
        undercut: Option<Bound<'py, PyArray1<bool>>>,
        theta_copy: Option<Bound<'py, PyArray1<f64>>>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let ts = CamError::slice(py, "theta", &theta)?;
        let want = [ts.len(), N_COLUMNS];
        let bad = |got: String| {
            CamError::from(InvalidInput::Output {
                field: "out",
                want: format!(
                    "a writeable C-contiguous float64 array of shape ({}, {N_COLUMNS}) \
                     that overlaps no input",
                    ts.len()
                ),
                got,
            })
            .into_pyerr(py)
        };
        let out = match out {
            Some(a) if a.shape() == want && a.is_c_contiguous() => a,
            Some(a) => return Err(bad(format!("an array of shape {:?}", a.shape()))),
            None => convert::zeros::<f64, Ix2>(
                py,
                &want,
                "CamKernel.solve",
                "solve fewer cam angles at a time",
            )?,
        };
        let bad_flags = |got: String| {
            CamError::from(InvalidInput::Output {
                field: "undercut",
                want: format!(
                    "a writeable contiguous bool array of shape ({},) that overlaps no input",
                    ts.len()
                ),
                got,
            })
            .into_pyerr(py)
        };
        if let Some(u) = &undercut {
            if u.shape() != [ts.len()] || !u.is_c_contiguous() {
                return Err(bad_flags(format!("an array of shape {:?}", u.shape())));
            }
        }
        let bad_copy = |got: String| {
            CamError::from(InvalidInput::Output {
                field: "theta_copy",
                want: format!(
                    "a writeable contiguous float64 array of shape ({},) that overlaps no input",
                    ts.len()
                ),
                got,
            })
            .into_pyerr(py)
        };
        if let Some(c) = &theta_copy {
            if c.shape() != [ts.len()] || !c.is_c_contiguous() {
                return Err(bad_copy(format!("an array of shape {:?}", c.shape())));
            }
        }
        {
            let mut rw = out
                .try_readwrite()
                .map_err(|e| bad(format!("an array numpy will not lend for writing ({e})")))?;
            let slice = convert::output(py, &mut rw)?;
            let mut flags_rw = undercut
                .as_ref()
                .map(|u| u.try_readwrite())
                .transpose()
                .map_err(|e| {
                    bad_flags(format!("an array numpy will not lend for writing ({e})"))
                })?;
            let flags: &mut [bool] = match flags_rw.as_mut() {
                Some(f) => convert::output(py, f)?,
                None => &mut [],
            };
            let mut copy_rw = theta_copy
                .as_ref()
                .map(|c| c.try_readwrite())
                .transpose()
                .map_err(|e| bad_copy(format!("an array numpy will not lend for writing ({e})")))?;
            let copy: &mut [f64] = match copy_rw.as_mut() {
                Some(c) => convert::output(py, c)?,
                None => &mut [],
            };
            run(py, "CamKernel.solve", || {
                self.cam.solve_flags_into(ts, slice, flags, copy, n_threads)
            })?;
        }
        Ok(out)
    }
    /// (N, 5) rows of the generalised force Q, normal force N (signed: − on a
    /// groove's outer flank or, with a spring, separation), Hertz stress [Pa]
    /// (NaN without `contact`), shaft torque [N·m] and separated (0/1) at cam
    /// angles `theta` [rad] and cam speed `omega` [rad/s]. `loads` = (mass,
    /// spring rate, preload, per-segment loads); `contact` = (width, E and ν of
    /// the follower, E and ν of the cam).
    #[pyo3(signature = (theta, omega, loads, contact=None, *, n_threads=None))]
    fn loads<'py>(
        &self,
        py: Python<'py>,
        theta: PyReadonlyArray1<'py, f64>,
        omega: f64,
        loads: (f64, f64, f64, Vec<f64>),
        contact: Option<[f64; 5]>,
        n_threads: Option<i64>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let ts = CamError::slice(py, "theta", &theta)?;
        let loads = to_loads(loads);
        let contact = contact.map(to_contact);
        let out = convert::zeros::<f64, Ix2>(
            py,
            &[ts.len(), N_LOAD_COLUMNS],
            "CamKernel.loads",
            "solve fewer cam angles at a time",
        )?;
        {
            let mut rw = out.readwrite();
            let slice = convert::output(py, &mut rw)?;
            run(py, "CamKernel.loads", || {
                self.cam
                    .loads_into(ts, omega, &loads, contact.as_ref(), slice, n_threads)
            })?;
        }
        Ok(out)
    }

    /// (ω [rad/s], θ [rad]) at which a spring-closed follower first leaves the cam.
    fn jump_speed(&self, py: Python<'_>, loads: (f64, f64, f64, Vec<f64>)) -> PyResult<(f64, f64)> {
        let loads = to_loads(loads);
        run(py, "CamKernel.jump_speed", || self.cam.jump_speed(&loads))
    }

    /// (S, K, 4) smallest phase angles [rad] of `segments` at cam speeds
    /// `omegas` [rad/s] for the pressure angle, undercut, jump and Hertz stress
    /// (NaN: no angle up to a turn; 0: no bound).
    #[pyo3(signature = (segments, omegas, max_pressure_angle, loads=None, contact=None,
                        max_stress=None, *, n_threads=None))]
    #[allow(clippy::too_many_arguments)]
    fn min_angles<'py>(
        &self,
        py: Python<'py>,
        segments: Vec<usize>,
        omegas: PyReadonlyArray1<'py, f64>,
        max_pressure_angle: f64,
        loads: Option<(f64, f64, f64, Vec<f64>)>,
        contact: Option<[f64; 5]>,
        max_stress: Option<f64>,
        n_threads: Option<i64>,
    ) -> PyResult<Bound<'py, PyArray3<f64>>> {
        let ws = CamError::slice(py, "omegas", &omegas)?;
        let loads = loads.map(to_loads);
        let contact = contact.map(to_contact);
        let limits = Limits {
            max_pressure_angle,
            max_stress,
        };
        let out = convert::zeros::<f64, Ix3>(
            py,
            &[ws.len(), segments.len(), CRITERIA.len()],
            "CamKernel.min_angles",
            "ask for fewer speeds at a time",
        )?;
        {
            let mut rw = out.readwrite();
            let slice = convert::output(py, &mut rw)?;
            run(py, "CamKernel.min_angles", || {
                self.cam.min_angles_into(
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
}

pub(crate) fn to_loads(
    (mass, spring_rate, preload, segment_loads): (f64, f64, f64, Vec<f64>),
) -> Loads {
    Loads {
        mass,
        spring_rate,
        preload,
        segment_loads,
    }
}

pub(crate) fn to_contact([width, fe, fnu, ce, cnu]: [f64; 5]) -> Contact {
    Contact {
        width,
        follower_modulus: fe,
        follower_poisson: fnu,
        cam_modulus: ce,
        cam_poisson: cnu,
    }
}
