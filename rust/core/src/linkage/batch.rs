//! Many geometries at once, into caller-owned buffers, in parallel.

use rayon::prelude::*;

use super::model::{LinkageError, Program, Request, Solution};
use super::solve::Out;

/// Caller-owned output buffers, laid out as [`Solution`]'s fields: `rows · M · 2`
/// values for `xy` (and for `vel`, `acc` when analogs are asked for, else empty),
/// `rows` flags each.
pub struct Outputs<'a> {
    pub xy: &'a mut [f64],
    pub vel: &'a mut [f64],
    pub acc: &'a mut [f64],
    pub ok: &'a mut [bool],
    pub singular: &'a mut [bool],
    pub branch: &'a mut [bool],
}

impl<'a> Outputs<'a> {
    /// Checked sizes, viewed as (x, y) pairs in place: the kernel writes the final
    /// layout.
    pub(super) fn view(
        self,
        rows: usize,
        m: usize,
        analogs: bool,
    ) -> Result<Out<'a>, LinkageError> {
        let len = rows * m * 2;
        let an = if analogs { len } else { 0 };
        let sizes = [self.xy.len(), self.vel.len(), self.acc.len()];
        let flags = [self.ok.len(), self.singular.len(), self.branch.len()];
        if sizes != [len, an, an] || flags != [rows; 3] {
            return Err(LinkageError::BadProgram {
                step: 0,
                why: format!(
                    "output buffers of {sizes:?} values and {flags:?} flags for {rows} rows of {m} points"
                ),
            });
        }
        Ok(Out {
            xy: self.xy.as_chunks_mut::<2>().0,
            vel: self.vel.as_chunks_mut::<2>().0,
            acc: self.acc.as_chunks_mut::<2>().0,
            ok: self.ok,
            singular: self.singular,
            branch: self.branch,
        })
    }
}

/// Output buffers of `rows` rows of `m` points.
pub(super) struct Buffers {
    xy: Vec<f64>,
    vel: Vec<f64>,
    acc: Vec<f64>,
    ok: Vec<bool>,
    singular: Vec<bool>,
    branch: Vec<bool>,
}

impl Buffers {
    pub(super) fn new(rows: usize, m: usize, analogs: bool) -> Result<Buffers, LinkageError> {
        let len = rows
            .checked_mul(m * 2)
            .ok_or(LinkageError::Memory { bytes: usize::MAX })?;
        let an = if analogs { len } else { 0 };
        // Probe the whole size once, fallibly; then allocate zeroed memory, which
        // for large buffers is fresh pages touched first by the (parallel) kernel
        // rather than a serial memset here.
        let bytes = (len + 2 * an).saturating_mul(8).saturating_add(3 * rows);
        if !crate::memory::can_allocate(bytes) {
            return Err(LinkageError::Memory { bytes });
        }
        Ok(Buffers {
            xy: vec![0.0; len],
            vel: vec![0.0; an],
            acc: vec![0.0; an],
            ok: vec![false; rows],
            singular: vec![false; rows],
            branch: vec![false; rows],
        })
    }

    pub(super) fn outputs(&mut self) -> Outputs<'_> {
        Outputs {
            xy: &mut self.xy,
            vel: &mut self.vel,
            acc: &mut self.acc,
            ok: &mut self.ok,
            singular: &mut self.singular,
            branch: &mut self.branch,
        }
    }

    pub(super) fn finish(self) -> Solution {
        Solution {
            xy: self.xy,
            vel: self.vel,
            acc: self.acc,
            ok: self.ok,
            singular: self.singular,
            branch: self.branch,
        }
    }
}

pub(super) fn check_angles(angles: &[f64]) -> Result<(), LinkageError> {
    if let Some((i, &v)) = angles.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(LinkageError::NonFinite {
            field: "angles",
            position: i,
            value: v,
            what: "crank angles must be finite radians",
        });
    }
    Ok(())
}

pub(super) fn check_request(request: &Request, n_points: usize) -> Result<(), LinkageError> {
    if request.points.is_empty() || request.points.iter().any(|&k| k >= n_points) {
        return Err(LinkageError::BadProgram {
            step: 0,
            why: format!(
                "the points asked for, {:?}, must be a non-empty list of indices below {n_points}",
                request.points
            ),
        });
    }
    Ok(())
}

/// Solve many geometries of one linkage (programs with the same points) over one
/// angle grid, in parallel over the geometries: rows are geometry-major, row
/// `g * N + i` for geometry `g` and angle `i`. A geometry whose drawn pose does
/// not close (its class III groups cannot start) is `ok = false` throughout.
pub fn solve_many(
    programs: &[Program],
    angles: &[f64],
    request: &Request,
    n_threads: Option<i64>,
) -> Result<Solution, LinkageError> {
    let rows = programs.len().saturating_mul(angles.len());
    let mut buffers = Buffers::new(rows, request.points.len(), request.analogs)?;
    solve_many_into(programs, angles, request, n_threads, buffers.outputs())?;
    Ok(buffers.finish())
}

/// [`solve_many`] into caller-owned buffers laid out as its [`Solution`].
pub fn solve_many_into(
    programs: &[Program],
    angles: &[f64],
    request: &Request,
    n_threads: Option<i64>,
    outputs: Outputs<'_>,
) -> Result<(), LinkageError> {
    let Some(first) = programs.first() else {
        return Ok(());
    };
    for (g, prog) in programs.iter().enumerate() {
        if prog.n_points != first.n_points {
            return Err(LinkageError::BadProgram {
                step: 0,
                why: format!(
                    "geometry {g} has {} points, geometry 0 {}",
                    prog.n_points, first.n_points
                ),
            });
        }
        prog.validate().map_err(|e| match e {
            LinkageError::BadProgram { step, why } => LinkageError::BadProgram {
                step,
                why: format!("geometry {g}: {why}"),
            },
            other => other,
        })?;
    }
    check_request(request, first.n_points)?;
    check_angles(angles)?;
    let threads = crate::parallel::resolve_threads(n_threads)?;
    let (n, m) = (angles.len(), request.points.len());
    let rows = programs.len().saturating_mul(n);
    let mut slabs = Vec::with_capacity(programs.len());
    let mut rest = outputs.view(rows, m, request.analogs)?;
    for _ in 0..programs.len() {
        let (head, tail) = rest.split(n, m);
        slabs.push(head);
        rest = tail;
    }
    let one = |(prog, mut slab): (&Program, Out<'_>)| {
        if crate::cancel::requested() {
            return;
        }
        if prog
            .solve_serial(angles, &request.points, &mut slab)
            .is_err()
        {
            slab.fail_all();
        }
    };
    if threads == 1 {
        programs.iter().zip(slabs).for_each(one);
    } else {
        crate::parallel::pool(threads)?
            .install(|| programs.par_iter().zip(slabs.into_par_iter()).for_each(one));
    }
    Ok(())
}
