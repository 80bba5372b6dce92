//! Bindings of the kinetostatics: a linkage's force model, solved at the angles
//! of a linkage solution.

use cyclomech_core::forces::{
    solve_friction_into, solve_into, Body, ForceError, Friction, FrictionOutputs, Guide,
    GuideFriction, Inputs, Model, Outputs, PinFriction, Side, Spec,
};
use numpy::ndarray::{Ix1, Ix2, Ix3};
use numpy::{
    PyArray1, PyArray2, PyArray3, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2,
    PyReadonlyArrayDyn, PyUntypedArrayMethods,
};
use pyo3::prelude::*;

use crate::convert::{self, LayoutError};
use crate::errors::{run, IntoPyErr};

impl LayoutError for ForceError {
    fn layout(field: &'static str) -> Self {
        ForceError::BadModel(format!("{field} must be a C-contiguous array"))
    }
}

fn index(py: Python<'_>, what: &str, v: i64, n: usize) -> PyResult<usize> {
    usize::try_from(v).ok().filter(|&u| u < n).ok_or_else(|| {
        ForceError::BadModel(format!("{what} index {v} out of range 0..{n}")).into_pyerr(py)
    })
}

/// A linkage's force model (see `cyclomech.forces`): bodies by their joints
/// (`body_ptr` (B+1,) into `body_points`), masses (B,) [kg], centres of mass in
/// their frames (B, 2), inertias (B,) [kg·m²]; ground joints; a mass per point
/// (P,) [kg]; guides (`guide_idx` (G, 4): point, b, c, body, with b = −1 for a
/// guide of the frame along `guide_dir` (G, 2)); the crank's body; gravity (2,).
#[pyclass(module = "cyclomech._core", frozen)]
pub struct ForceModel {
    model: Model,
}

#[pymethods]
impl ForceModel {
    #[new]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        n_points: usize,
        body_ptr: PyReadonlyArray1<'_, i64>,
        body_points: PyReadonlyArray1<'_, i64>,
        body_mass: PyReadonlyArray1<'_, f64>,
        body_com: PyReadonlyArray2<'_, f64>,
        body_inertia: PyReadonlyArray1<'_, f64>,
        ground: PyReadonlyArray1<'_, i64>,
        point_mass: PyReadonlyArray1<'_, f64>,
        guide_idx: PyReadonlyArray2<'_, i64>,
        guide_dir: PyReadonlyArray2<'_, f64>,
        driver: i64,
        gravity: PyReadonlyArray1<'_, f64>,
    ) -> PyResult<Self> {
        let ptr = ForceError::slice(py, "body_ptr", &body_ptr)?;
        let pts = ForceError::slice(py, "body_points", &body_points)?;
        let mass = ForceError::slice(py, "body_mass", &body_mass)?;
        let com = ForceError::slice(py, "body_com", &body_com)?;
        let inertia = ForceError::slice(py, "body_inertia", &body_inertia)?;
        let nb = mass.len();
        if ptr.len() != nb + 1 || com.len() != 2 * nb || inertia.len() != nb {
            return Err(ForceError::BadModel(format!(
                "{nb} bodies need {} pointers, {} centre coordinates and {nb} inertias",
                nb + 1,
                2 * nb
            ))
            .into_pyerr(py));
        }
        let mut bodies = Vec::with_capacity(nb);
        for b in 0..nb {
            let (lo, hi) = (
                index(py, "body_ptr", ptr[b], pts.len() + 1)?,
                index(py, "body_ptr", ptr[b + 1], pts.len() + 1)?,
            );
            if hi < lo {
                return Err(
                    ForceError::BadModel("body_ptr must not decrease".into()).into_pyerr(py)
                );
            }
            let points = pts[lo..hi]
                .iter()
                .map(|&p| index(py, "point", p, n_points))
                .collect::<PyResult<Vec<usize>>>()?;
            bodies.push(Body {
                points,
                mass: mass[b],
                com_uv: [com[2 * b], com[2 * b + 1]],
                inertia: inertia[b],
            });
        }
        let ground = ForceError::slice(py, "ground", &ground)?
            .iter()
            .map(|&g| index(py, "ground", g, n_points))
            .collect::<PyResult<Vec<usize>>>()?;
        let gi = ForceError::slice(py, "guide_idx", &guide_idx)?;
        let gd = ForceError::slice(py, "guide_dir", &guide_dir)?;
        if gi.len() % 4 != 0 || gd.len() != gi.len() / 2 {
            return Err(
                ForceError::BadModel("guide_idx is (G, 4) and guide_dir (G, 2)".into())
                    .into_pyerr(py),
            );
        }
        let mut guides = Vec::new();
        for (row, dir) in gi.chunks_exact(4).zip(gd.chunks_exact(2)) {
            let point = index(py, "guide point", row[0], n_points)?;
            guides.push(if row[1] < 0 {
                Guide::Fixed {
                    point,
                    dir: [dir[0], dir[1]],
                }
            } else {
                Guide::Link {
                    point,
                    b: index(py, "guide joint", row[1], n_points)?,
                    c: index(py, "guide joint", row[2], n_points)?,
                    body: index(py, "guide body", row[3], nb)?,
                }
            });
        }
        let g = ForceError::slice(py, "gravity", &gravity)?;
        if g.len() != 2 {
            return Err(ForceError::BadModel("gravity is (gx, gy)".into()).into_pyerr(py));
        }
        let spec = Spec {
            n_points,
            bodies,
            ground,
            point_mass: ForceError::slice(py, "point_mass", &point_mass)?.to_vec(),
            guides,
            driver: index(py, "driver", driver, nb)?,
            gravity: [g[0], g[1]],
        };
        let model = Model::new(spec).map_err(|e| e.into_pyerr(py))?;
        Ok(ForceModel { model })
    }

    /// The (point, body) pairs of the reactions in output order; body −1 is the frame.
    fn pairs(&self) -> Vec<(usize, i64)> {
        self.model
            .pairs()
            .into_iter()
            .map(|(p, s)| {
                (
                    p,
                    match s {
                        Side::Frame => -1,
                        Side::Body(b) => b as i64,
                    },
                )
            })
            .collect()
    }

    /// The sizes of the block-triangular order's diagonal blocks.
    fn block_sizes(&self) -> Vec<usize> {
        self.model.block_sizes()
    }

    /// Values per angle and part: torque, guides and (with `reactions`) the
    /// reactions (x, y).
    fn width(&self, reactions: bool) -> usize {
        self.model.width(reactions)
    }

    /// (values (3, N, width), conditioning (N,): 0 at a dead centre, NaN where an input is not finite,
    /// analogs (N,): the points' largest |x'| over twice their largest |x''| [rad], ∞ where none
    /// accelerates, NaN where an input is not finite) at the N angles of `xy`, `vel`, `acc`
    /// (N, P, 2), with optional point forces (N, P, 2) [N] and link torques (N, B) [N·m].
    /// The values into `out` (a writeable C-contiguous float64 (3, N, width) array
    /// that overlaps no input) when given, which is returned.
    #[pyo3(signature = (xy, vel, acc, force=None, torque=None, *, reactions=true, n_threads=None, out=None))]
    #[allow(clippy::too_many_arguments, clippy::type_complexity)]
    fn solve<'py>(
        &self,
        py: Python<'py>,
        xy: PyReadonlyArrayDyn<'py, f64>,
        vel: PyReadonlyArrayDyn<'py, f64>,
        acc: PyReadonlyArrayDyn<'py, f64>,
        force: Option<PyReadonlyArrayDyn<'py, f64>>,
        torque: Option<PyReadonlyArrayDyn<'py, f64>>,
        reactions: bool,
        n_threads: Option<i64>,
        out: Option<Bound<'py, PyArray3<f64>>>,
    ) -> PyResult<(
        Bound<'py, PyArray3<f64>>,
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray1<f64>>,
    )> {
        let n = xy.shape().first().copied().unwrap_or(0);
        let inputs = Inputs {
            xy: ForceError::slice(py, "xy", &xy)?,
            vel: ForceError::slice(py, "vel", &vel)?,
            acc: ForceError::slice(py, "acc", &acc)?,
            force: force
                .as_ref()
                .map(|f| ForceError::slice(py, "force", f))
                .transpose()?,
            torque: torque
                .as_ref()
                .map(|t| ForceError::slice(py, "torque", t))
                .transpose()?,
        };
        let w = self.model.width(reactions);
        let bad = |got: String| {
            ForceError::BadModel(format!(
                "out must be a writeable C-contiguous float64 array of shape (3, {n}, {w}) \
                 that overlaps no input; got {got}"
            ))
            .into_pyerr(py)
        };
        let values = match out {
            Some(a) if a.shape() == [3, n, w] && a.is_c_contiguous() => a,
            Some(a) => return Err(bad(format!("an array of shape {:?}", a.shape()))),
            None => convert::zeros::<f64, Ix3>(
                py,
                &[3, n, w],
                "kinetostatics",
                "solve fewer angles at a time",
            )?,
        };
        let conditioning =
            convert::zeros::<f64, Ix1>(py, &[n], "kinetostatics", "solve fewer angles at a time")?;
        let analogs =
            convert::zeros::<f64, Ix1>(py, &[n], "kinetostatics", "solve fewer angles at a time")?;
        {
            let mut vw = values
                .try_readwrite()
                .map_err(|e| bad(format!("an array numpy will not lend for writing ({e})")))?;
            let mut sw = conditioning.readwrite();
            let mut aw = analogs.readwrite();
            let out = Outputs {
                values: convert::output(py, &mut vw)?,
                conditioning: convert::output(py, &mut sw)?,
                reactions,
                analogs: Some(convert::output(py, &mut aw)?),
            };
            let model = &self.model;
            run(py, "kinetostatics", || {
                solve_into(model, inputs, out, n_threads)
            })?;
        }
        Ok((values, conditioning, analogs))
    }

    /// With friction, at the N angles of `xy`, `vel`, `acc` (as `solve`) and the
    /// S steady crank speeds `omegas` [rad/s]: joints' friction at points
    /// `pin_points` (J,) with μ·r `pin_mu_r` [m] and viscous `pin_viscous`
    /// [N·m·s/rad], guides `guides` (H,) with `guide_mu` and viscous
    /// `guide_viscous` [N·s/m]. (values (N, S, width with reactions), losses
    /// (N, S, J + H) [W], status (N, S): solves taken, 0 not solved, −1
    /// self-locking; conditioning (N,)).
    #[pyo3(signature = (xy, vel, acc, force, torque, omegas, pin_points, pin_mu_r, pin_viscous, guides, guide_mu, guide_viscous, *, n_threads=None))]
    #[allow(clippy::too_many_arguments, clippy::type_complexity)]
    fn solve_friction<'py>(
        &self,
        py: Python<'py>,
        xy: PyReadonlyArrayDyn<'py, f64>,
        vel: PyReadonlyArrayDyn<'py, f64>,
        acc: PyReadonlyArrayDyn<'py, f64>,
        force: Option<PyReadonlyArrayDyn<'py, f64>>,
        torque: Option<PyReadonlyArrayDyn<'py, f64>>,
        omegas: PyReadonlyArray1<'py, f64>,
        pin_points: PyReadonlyArray1<'py, i64>,
        pin_mu_r: PyReadonlyArray1<'py, f64>,
        pin_viscous: PyReadonlyArray1<'py, f64>,
        guides: PyReadonlyArray1<'py, i64>,
        guide_mu: PyReadonlyArray1<'py, f64>,
        guide_viscous: PyReadonlyArray1<'py, f64>,
        n_threads: Option<i64>,
    ) -> PyResult<(
        Bound<'py, PyArray3<f64>>,
        Bound<'py, PyArray3<f64>>,
        Bound<'py, PyArray2<i64>>,
        Bound<'py, PyArray1<f64>>,
    )> {
        let n = xy.shape().first().copied().unwrap_or(0);
        let inputs = Inputs {
            xy: ForceError::slice(py, "xy", &xy)?,
            vel: ForceError::slice(py, "vel", &vel)?,
            acc: ForceError::slice(py, "acc", &acc)?,
            force: force
                .as_ref()
                .map(|f| ForceError::slice(py, "force", f))
                .transpose()?,
            torque: torque
                .as_ref()
                .map(|t| ForceError::slice(py, "torque", t))
                .transpose()?,
        };
        let omegas = ForceError::slice(py, "omegas", &omegas)?;
        let pp = ForceError::slice(py, "pin_points", &pin_points)?;
        let pm = ForceError::slice(py, "pin_mu_r", &pin_mu_r)?;
        let pv = ForceError::slice(py, "pin_viscous", &pin_viscous)?;
        let gg = ForceError::slice(py, "guides", &guides)?;
        let gm = ForceError::slice(py, "guide_mu", &guide_mu)?;
        let gv = ForceError::slice(py, "guide_viscous", &guide_viscous)?;
        if pm.len() != pp.len()
            || pv.len() != pp.len()
            || gm.len() != gg.len()
            || gv.len() != gg.len()
        {
            return Err(ForceError::BadModel(
                "pin_points, pin_mu_r, pin_viscous are (J,) and guides, guide_mu, guide_viscous (H,)"
                    .into(),
            )
            .into_pyerr(py));
        }
        let np = self.model.spec().n_points;
        let ng = self.model.spec().guides.len();
        let mut friction = Friction::default();
        for ((&p, &mu_r), &viscous) in pp.iter().zip(pm).zip(pv) {
            friction.pins.push(PinFriction {
                point: index(py, "pin point", p, np)?,
                mu_r,
                viscous,
            });
        }
        for ((&g, &mu), &viscous) in gg.iter().zip(gm).zip(gv) {
            friction.guides.push(GuideFriction {
                guide: index(py, "guide", g, ng)?,
                mu,
                viscous,
            });
        }
        let (ns, w, nf) = (omegas.len(), self.model.width(true), pp.len() + gg.len());
        let hint = "solve fewer angles or speeds at a time";
        let values = convert::zeros::<f64, Ix3>(py, &[n, ns, w], "friction", hint)?;
        let losses = convert::zeros::<f64, Ix3>(py, &[n, ns, nf], "friction", hint)?;
        let status = convert::zeros::<i64, Ix2>(py, &[n, ns], "friction", hint)?;
        let conditioning = convert::zeros::<f64, Ix1>(py, &[n], "friction", hint)?;
        {
            let mut vw = values.readwrite();
            let mut lw = losses.readwrite();
            let mut stw = status.readwrite();
            let mut cw = conditioning.readwrite();
            let out = FrictionOutputs {
                values: convert::output(py, &mut vw)?,
                losses: convert::output(py, &mut lw)?,
                status: convert::output(py, &mut stw)?,
                conditioning: convert::output(py, &mut cw)?,
            };
            let model = &self.model;
            let friction = &friction;
            run(py, "friction", || {
                solve_friction_into(model, inputs, friction, omegas, out, n_threads)
            })?;
        }
        Ok((values, losses, status, conditioning))
    }
}
