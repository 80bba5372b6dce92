//! Bindings of the linkage domain: a compiled program, solved over angle grids,
//! one geometry or many.

use cyclomech_core::linkage::{self, Line, LinkageError, Outputs, Request, Step, Triad};
use numpy::ndarray::{ArrayView1, Axis};
use numpy::{
    PyArrayDyn, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArray3,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;

use crate::convert::{self, LayoutError};
use crate::errors::{run, IntoPyErr};

/// Columns of a compiled step's index and dimension rows.
const IDX: usize = 6;
const DIMS: usize = 8;

fn bad(py: Python<'_>, why: String) -> PyErr {
    LinkageError::BadProgram { step: 0, why }.into_pyerr(py)
}

/// One step from its kind, index row and dimension row (see `LinkageProgram`).
fn step(
    py: Python<'_>,
    kind: i64,
    ix: ArrayView1<'_, i64>,
    dm: ArrayView1<'_, f64>,
    n_points: usize,
) -> PyResult<Step> {
    let at = |c: usize| -> PyResult<usize> {
        let v = ix[c];
        usize::try_from(v)
            .ok()
            .filter(|&u| u < n_points)
            .ok_or_else(|| bad(py, format!("point index {v} out of range")))
    };
    // A guide: fixed (first index −1, direction from the dims) or along b–c.
    let line = |c: usize, d: usize| -> PyResult<Line> {
        Ok(if ix[c] < 0 {
            Line::Fixed {
                o: [dm[d], dm[d + 1]],
                u: [dm[d + 2], dm[d + 3]],
            }
        } else {
            Line::Through {
                b: at(c)?,
                c: at(c + 1)?,
            }
        })
    };
    Ok(match kind {
        0 => Step::Driver {
            pivot: at(0)?,
            tip: at(1)?,
            radius: dm[0],
        },
        1 => Step::Circles {
            a: at(0)?,
            b: at(1)?,
            p: at(2)?,
            ra: dm[0],
            rb: dm[1],
            sign: dm[2],
        },
        2 => Step::Triad {
            anchors: [at(0)?, at(1)?, at(2)?],
            joints: [at(3)?, at(4)?, at(5)?],
            triad: Triad {
                arms: [dm[0], dm[1], dm[2]],
                sides: [dm[3], dm[4], dm[5]],
                orientation: dm[6],
            },
        },
        3 => Step::Slide {
            a: at(0)?,
            p: at(1)?,
            line: line(2, 2)?,
            r: dm[0],
            sign: dm[1],
        },
        4 => Step::Cross {
            p: at(0)?,
            l1: line(1, 0)?,
            l2: line(3, 4)?,
        },
        5 => Step::Aim {
            b: at(0)?,
            s: at(1)?,
            c: at(2)?,
            len: dm[0],
            sign: dm[1],
        },
        other => return Err(bad(py, format!("unknown step kind {other}"))),
    })
}

/// A linkage compiled into solving steps (see `cyclomech.Linkage`).
///
/// Rows of `idx` have 6 entries and rows of `dims` 8; unused entries are ignored.
/// `kind[s]`: 0 driver (idx = pivot, tip; dims = radius); 1 two circles (idx = a,
/// b, p; dims = ra, rb, sign); 2 class III group (idx = 3 anchors, 3 joints; dims =
/// 3 arms, 3 sides, orientation); 3 circle and guide (idx = a, p, b, c; dims = r,
/// sign, ox, oy, ux, uy); 4 two guides (idx = p, b1, c1, b2, c2; dims = o1, u1, o2,
/// u2); 5 a link aimed through a block (idx = b, s, c; dims = len, sign). A guide
/// with b = −1 is fixed, through o along u; otherwise it runs along b–c.
#[pyclass(module = "cyclomech._core", frozen)]
pub struct LinkageProgram {
    program: linkage::Program,
    kind: Vec<i64>,
    idx: Vec<[i64; IDX]>,
}

type Arrays<'py> = (
    Bound<'py, PyArrayDyn<f64>>,
    Option<Bound<'py, PyArrayDyn<f64>>>,
    Option<Bound<'py, PyArrayDyn<f64>>>,
    Bound<'py, PyArrayDyn<bool>>,
    Bound<'py, PyArrayDyn<bool>>,
    Bound<'py, PyArrayDyn<bool>>,
);

/// Output arrays allocated by numpy (which backs large ones with huge pages), of
/// shape `lead + (M, 2)` for positions and analogs (None unless `analogs`) and
/// `lead` for the flags. Sized before anything is allocated: a grid whose results
/// cannot fit is an `InputError`, and so is numpy's failure to allocate (never a
/// panic).
fn allocate<'py>(
    py: Python<'py>,
    lead: &[usize],
    m: usize,
    analogs: bool,
) -> PyResult<Arrays<'py>> {
    let points: Vec<usize> = lead.iter().copied().chain([m, 2]).collect();
    let copies = if analogs { 3 } else { 1 };
    let f = std::mem::size_of::<f64>();
    let bytes = convert::nbytes(&[(&points, copies * f), (lead, 3)]);
    let shape = points
        .iter()
        .map(|d| d.to_string())
        .collect::<Vec<_>>()
        .join(" × ");
    let what = format!("the linkage's results ({copies} arrays of {shape} float64 and 3 flags)");
    let hint = "solve fewer angles, points or geometries at a time";
    convert::check(py, &what, bytes, hint)?;
    let big = || convert::empty(py, &points, &what, hint);
    let flag = || convert::empty(py, lead, &what, hint);
    let (vel, acc) = if analogs {
        (Some(big()?), Some(big()?))
    } else {
        (None, None)
    };
    Ok((big()?, vel, acc, flag()?, flag()?, flag()?))
}

/// Run `kernel` (GIL released) writing into the arrays of `out`. An array numpy
/// will not lend for writing (read-only, or overlapping another argument) is an
/// `InputError`.
fn fill<'py, F>(py: Python<'py>, name: &'static str, out: &Arrays<'py>, kernel: F) -> PyResult<()>
where
    F: FnOnce(Outputs<'_>) -> Result<(), LinkageError> + Send,
{
    let lend = |e: numpy::BorrowError| {
        bad(
            py,
            format!("out: an output array cannot be written in place ({e}); pass arrays that share no memory with each other or with the angles"),
        )
    };
    let mut xy = out.0.try_readwrite().map_err(lend)?;
    let mut vel = out
        .1
        .as_ref()
        .map(|a| a.try_readwrite())
        .transpose()
        .map_err(lend)?;
    let mut acc = out
        .2
        .as_ref()
        .map(|a| a.try_readwrite())
        .transpose()
        .map_err(lend)?;
    let mut ok = out.3.try_readwrite().map_err(lend)?;
    let mut singular = out.4.try_readwrite().map_err(lend)?;
    let mut branch = out.5.try_readwrite().map_err(lend)?;
    let (mut no_vel, mut no_acc): ([f64; 0], [f64; 0]) = ([], []);
    let outputs = Outputs {
        xy: convert::output(py, &mut xy)?,
        vel: match vel.as_mut() {
            Some(v) => convert::output(py, v)?,
            None => &mut no_vel,
        },
        acc: match acc.as_mut() {
            Some(v) => convert::output(py, v)?,
            None => &mut no_acc,
        },
        ok: convert::output(py, &mut ok)?,
        singular: convert::output(py, &mut singular)?,
        branch: convert::output(py, &mut branch)?,
    };
    run(py, name, || kernel(outputs))
}

/// The caller's `out` arrays (the Python layer has checked them; this is the
/// last line): shapes `lead + (M, 2)` and `lead`, C-contiguous, analogs given
/// exactly when computed.
fn reuse<'py>(
    py: Python<'py>,
    out: Arrays<'py>,
    lead: &[usize],
    m: usize,
    analogs: bool,
) -> PyResult<Arrays<'py>> {
    let points: Vec<usize> = lead.iter().copied().chain([m, 2]).collect();
    let fine = |shape: &[usize], want: &[usize], c: bool| shape == want && c;
    let big = [Some(&out.0), out.1.as_ref(), out.2.as_ref()];
    let floats = big.iter().enumerate().all(|(i, a)| match a {
        Some(a) => (i == 0 || analogs) && fine(a.shape(), &points, a.is_c_contiguous()),
        None => i > 0 && !analogs,
    });
    let flags = [&out.3, &out.4, &out.5]
        .iter()
        .all(|a| fine(a.shape(), lead, a.is_c_contiguous()));
    if !(floats && flags) {
        return Err(bad(
            py,
            format!(
                "out must be C-contiguous arrays: xy of shape {points:?}, vel and acc {} and the flags of shape {lead:?}",
                if analogs { "of that shape too" } else { "None" }
            ),
        ));
    }
    Ok(out)
}

fn request(py: Python<'_>, points: PyReadonlyArray1<'_, i64>, analogs: bool) -> PyResult<Request> {
    let points = points
        .as_array()
        .iter()
        .map(|&k| usize::try_from(k).map_err(|_| bad(py, format!("point index {k} out of range"))))
        .collect::<PyResult<Vec<usize>>>()?;
    Ok(Request { points, analogs })
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
            || ix.shape() != [kd.len(), IDX]
            || dm.shape() != [kd.len(), DIMS]
            || dx.shape() != [n_points, 2]
        {
            return Err(bad(py, "array shapes do not match".into()));
        }
        let mut fixed = Vec::with_capacity(fi.len());
        for (k, &i) in fi.iter().enumerate() {
            let i = usize::try_from(i)
                .ok()
                .filter(|&u| u < n_points)
                .ok_or_else(|| bad(py, format!("fixed point index {i} out of range")))?;
            fixed.push((i, [fx[[k, 0]], fx[[k, 1]]]));
        }
        let steps = kd
            .iter()
            .enumerate()
            .map(|(s, &k)| step(py, k, ix.row(s), dm.row(s), n_points))
            .collect::<PyResult<Vec<Step>>>()?;
        let drawn = (0..n_points).map(|k| [dx[[k, 0]], dx[[k, 1]]]).collect();
        let program = linkage::Program {
            n_points,
            fixed,
            steps,
            drawn: Some((drawn_phi, drawn)),
        };
        run(py, "LinkageProgram", || program.validate())?;
        let idx = ix
            .rows()
            .into_iter()
            .map(|r| std::array::from_fn(|c| r[c]))
            .collect();
        Ok(LinkageProgram {
            program,
            kind: kd.to_vec(),
            idx,
        })
    }

    #[getter]
    fn n_points(&self) -> usize {
        self.program.n_points
    }

    /// The change points of its class II groups over one turn from the drawn angle:
    /// a list of (step, crank angle [rad], followed, window [rad]).
    fn change_points(&self, py: Python<'_>) -> PyResult<Vec<(usize, f64, bool, f64)>> {
        let found = run(py, "Linkage.change_points", || self.program.change_points())?;
        Ok(found
            .into_iter()
            .map(|c| (c.step, c.phi, c.followed, c.window))
            .collect())
    }

    /// Solve over absolute crank angles [rad]: (xy, vel, acc) of shape (N, M, 2)
    /// for the M chosen `points` (vel and acc None unless `analogs`), and the flags
    /// ok, singular and branch, each (N,).
    /// `out`, if given, is six arrays of those shapes (vel and acc None unless
    /// `analogs`) written in place and returned.
    #[pyo3(signature = (angles, points, *, analogs=true, n_threads=None, out=None))]
    fn solve<'py>(
        &self,
        py: Python<'py>,
        angles: PyReadonlyArray1<'py, f64>,
        points: PyReadonlyArray1<'py, i64>,
        analogs: bool,
        n_threads: Option<i64>,
        out: Option<Arrays<'py>>,
    ) -> PyResult<Arrays<'py>> {
        let a = LinkageError::slice(py, "angles", &angles)?;
        let req = request(py, points, analogs)?;
        let (lead, m) = ([a.len()], req.points.len());
        let out = match out {
            Some(o) => reuse(py, o, &lead, m, analogs)?,
            None => allocate(py, &lead, m, analogs)?,
        };
        fill(py, "Linkage.solve", &out, |o| {
            self.program.solve_into(a, &req, n_threads, o)
        })?;
        Ok(out)
    }

    /// Solve K geometries of this program, `dims` (K, S, 8) replacing its
    /// dimensions row by row, over one angle grid, in parallel over the
    /// geometries: arrays of shape (K, N, M, 2) and flags (K, N).
    /// `out` as in [`LinkageProgram::solve`].
    #[pyo3(signature = (dims, angles, points, *, analogs=true, n_threads=None, out=None))]
    #[allow(clippy::too_many_arguments)] // the solve's arguments and its outputs
    fn solve_many<'py>(
        &self,
        py: Python<'py>,
        dims: PyReadonlyArray3<'py, f64>,
        angles: PyReadonlyArray1<'py, f64>,
        points: PyReadonlyArray1<'py, i64>,
        analogs: bool,
        n_threads: Option<i64>,
        out: Option<Arrays<'py>>,
    ) -> PyResult<Arrays<'py>> {
        let dm = dims.as_array();
        let (k, s) = (dm.shape()[0], self.kind.len());
        if dm.shape()[1..] != [s, DIMS] {
            return Err(bad(py, format!("dims must have shape (K, {s}, {DIMS})")));
        }
        let n = self.program.n_points;
        let mut programs = Vec::with_capacity(k);
        for g in 0..k {
            let mut steps = Vec::with_capacity(s);
            for (r, &kind) in self.kind.iter().enumerate() {
                let ix = ArrayView1::from(&self.idx[r][..]);
                let row = dm.index_axis(Axis(0), g);
                steps.push(step(py, kind, ix, row.row(r), n)?);
            }
            programs.push(linkage::Program {
                steps,
                ..self.program.clone()
            });
        }
        let a = LinkageError::slice(py, "angles", &angles)?;
        let req = request(py, points, analogs)?;
        let (lead, m) = ([k, a.len()], req.points.len());
        let out = match out {
            Some(o) => reuse(py, o, &lead, m, analogs)?,
            None => allocate(py, &lead, m, analogs)?,
        };
        fill(py, "linkage.sweep", &out, |o| {
            linkage::solve_many_into(&programs, a, &req, n_threads, o)
        })?;
        Ok(out)
    }
}
