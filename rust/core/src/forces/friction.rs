//! Friction in the joints and the guides (issue 34 item 5), solved with the
//! reactions at each crank angle and each steady crank speed.
//!
//! **Model.** A revolute joint of two members with Coulomb friction puts a
//! torque of magnitude μ·r·|R| on each member (r the pin radius, R the joint's
//! reaction), opposing their relative angular velocity ω_rel = θ̇_a − θ̇_b (the
//! frame's is 0, a slider's block turns with its guide), plus an optional
//! viscous c·ω_rel. A guide with Coulomb friction puts μ·|N| along the guide on
//! the block, opposing its sliding velocity relative to the guide (the guide's
//! carrier is pushed back at the point), plus an optional viscous c·v_rel.
//! Where a joint's pin carries a load or a point mass, the forces on its two
//! members differ: |R| is the larger of the two (the conservative choice).
//!
//! **Zero relative velocity.** Kinetic friction with sign(0) = 0: where a
//! joint's relative angular velocity analog is within 1e-12 rad/rad of 0, or a
//! guide's sliding analog within 1e-12 of the pose's largest point velocity
//! analog [m/rad] (a dwell, a reversal), its Coulomb friction is taken as zero.
//! The static friction there can be anything up to μ·|R| (or μ·|N|): the value at
//! that one angle is a limit of neither side.
//!
//! **Solving.** The friction loads are extra loads in the static part: the
//! system's matrix does not change. So at each angle the frictionless forces
//! (three parts) and each friction element's response to a load of unit size
//! (a torque of 1 N·m on a joint's two members, a force of 1 N along a guide)
//! are solved once, and the forces at any friction are the frictionless ones
//! plus each element's size times its response (the response is taken as the
//! change of the static part, so it carries a rounding of order 1e-16 of the
//! static forces). At each steady crank speed ω (ε = 0) the sizes are iterated
//! to a fixed point, R⁽ᵏ⁺¹⁾ = solve(ω² part 0 + part 2 + friction(R⁽ᵏ⁾)), from
//! the frictionless forces, until the friction magnitudes change by less than
//! 1e-12 of the largest: each step costs the F responses, not a solve. The
//! map's contraction factor is, near enough, μ·r over the links' lever arms (for
//! a slider, μ·tan of the pushing angle): where it is 1 or more, friction grows
//! as fast as the reactions that cause it, or faster: the rigid-body Coulomb
//! model then has no finite driving torque (the linkage jams) or no unique one
//! (where friction would help the motion, x = a − q|x| with q > 1 has two
//! roots), a *self-locking* pose. One flagged (status −1, its values NaN)
//! where the iteration has not converged in `MAX_ITER` steps or the friction
//! magnitudes have grown past 1e10 times the frictionless forces (a factor
//! within about 0.3 % below 1 also exhausts the steps: a pose that near
//! self-locking is flagged too).

use rayon::prelude::*;

use super::solve::{Row, CHUNK};
use super::{ForceError, Guide, Inputs, Model, Side};
use crate::geom::{cross, dot, sub};
use crate::parallel::{pool, resolve_threads};

/// Fixed-point steps per angle and speed before a pose is flagged self-locking
/// (a contraction factor q needs about 28 / −ln q steps to 1e-12: 10 000 up
/// to q ≈ 0.997).
const MAX_ITER: usize = 10_000;
/// Converged when the friction magnitudes change by less than this fraction of
/// the largest.
const TOL: f64 = 1e-12;
/// Self-locking when the friction magnitudes pass this multiple of the
/// frictionless forces' largest.
const BLOW_UP: f64 = 1e10;
/// Relative velocities within this many units of the crank's are zero.
const ZERO_SPEED: f64 = 1e-12;

/// Coulomb and viscous friction at the joint at `point`: μ·r (`mu_r`) [m] and
/// the viscous coefficient [N·m·s/rad].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PinFriction {
    pub point: usize,
    pub mu_r: f64,
    pub viscous: f64,
}

/// Coulomb and viscous friction on guide `guide`: μ and the viscous
/// coefficient [N·s/m].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GuideFriction {
    pub guide: usize,
    pub mu: f64,
    pub viscous: f64,
}

/// The friction of a linkage: its joints' and its guides'.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Friction {
    pub pins: Vec<PinFriction>,
    pub guides: Vec<GuideFriction>,
}

/// What turns against member `a` at a joint.
#[derive(Debug, Clone, Copy)]
enum Other {
    Frame,
    Body(usize),
    /// A slider's block, turning with its guide.
    Block(usize),
}

/// A joint's friction, resolved against the model: member `a`, the other, and
/// the offsets in a values row of the forces on its sides (x, y).
#[derive(Debug, Clone)]
struct Joint {
    a: usize,
    other: Other,
    offsets: Vec<usize>,
    mu_r: f64,
    viscous: f64,
}

/// Where [`solve_friction_into`] writes, for N angles and S speeds: `values`
/// (N, S, W) the driving torque, guide forces and reactions as
/// [`super::Outputs`] (W = [`Model::width`] with reactions) at each speed with
/// friction; `losses` (N, S, F) the friction power of each joint and then each
/// guide [W] (≥ 0); `status` (N, S): the solves the fixed point took (≥ 1), 0
/// where the angle is not solved (an input not finite or a dead centre, see
/// `conditioning`), −1 where the pose is self-locking (values and losses NaN);
/// `conditioning` (N,) as [`super::Outputs`].
pub struct FrictionOutputs<'a> {
    pub values: &'a mut [f64],
    pub losses: &'a mut [f64],
    pub status: &'a mut [i64],
    pub conditioning: &'a mut [f64],
}

fn bad(why: String) -> ForceError {
    ForceError::BadModel(why)
}

impl Model {
    /// The joints of `friction`, checked.
    fn joints(&self, friction: &Friction) -> Result<Vec<Joint>, ForceError> {
        let mut offsets = Vec::new();
        let mut k = 1 + self.spec.guides.len();
        for pin in &self.pins {
            offsets.push(k);
            k += 2 * pin.sides.len();
        }
        let mut seen = vec![false; self.spec.n_points];
        let mut out = Vec::new();
        for f in &friction.pins {
            if !(f.mu_r.is_finite() && f.mu_r >= 0.0 && f.viscous.is_finite() && f.viscous >= 0.0) {
                return Err(bad(format!(
                    "the friction of joint {}: μ·r = {} [m] and viscous = {} [N·m·s/rad] must \
                     be finite and >= 0",
                    f.point, f.mu_r, f.viscous
                )));
            }
            let i = self
                .pins
                .iter()
                .position(|p| p.point == f.point)
                .ok_or_else(|| bad(format!("point {} is not a joint", f.point)))?;
            if std::mem::replace(&mut seen[f.point], true) {
                return Err(bad(format!("joint {} has friction twice", f.point)));
            }
            let pin = &self.pins[i];
            let (a, other) = match (pin.sides.as_slice(), pin.guides.as_slice()) {
                ([Side::Frame, Side::Body(b)], []) => (*b, Other::Frame),
                ([Side::Body(a), Side::Body(b)], []) => (*a, Other::Body(*b)),
                ([Side::Body(a)], [g]) => (*a, Other::Block(*g)),
                _ => {
                    return Err(bad(format!(
                        "joint {} joins {} parts and {} guides: friction is modelled at a \
                         joint of two members (two links, a link and the frame, a link and a \
                         slider's block)",
                        f.point,
                        pin.sides.len(),
                        pin.guides.len()
                    )))
                }
            };
            let offsets = (0..pin.sides.len()).map(|j| offsets[i] + 2 * j).collect();
            out.push(Joint {
                a,
                other,
                offsets,
                mu_r: f.mu_r,
                viscous: f.viscous,
            });
        }
        let mut seen = vec![false; self.spec.guides.len()];
        for g in &friction.guides {
            if g.guide >= seen.len() {
                return Err(bad(format!("guide {} is not a guide", g.guide)));
            }
            if std::mem::replace(&mut seen[g.guide], true) {
                return Err(bad(format!("guide {} has friction twice", g.guide)));
            }
            if !(g.mu.is_finite() && g.mu >= 0.0 && g.viscous.is_finite() && g.viscous >= 0.0) {
                return Err(bad(format!(
                    "the friction of guide {}: μ = {} and viscous = {} [N·s/m] must be finite \
                     and >= 0",
                    g.guide, g.mu, g.viscous
                )));
            }
        }
        Ok(out)
    }
}

/// The relative velocity analogs of one pose: each joint's ω_rel/ω [rad/rad],
/// each guide's sliding v_rel/ω [m/rad] and unit direction, exact zeros within
/// the rule of the module.
struct Relative {
    joint: Vec<f64>,
    slide: Vec<f64>,
    dir: Vec<[f64; 2]>,
}

impl Relative {
    fn fill(
        &mut self,
        model: &Model,
        joints: &[Joint],
        friction: &Friction,
        pose: &super::solve::Pose,
    ) {
        let spec = &model.spec;
        let w = |o: Other| match o {
            Other::Frame => 0.0,
            Other::Body(b) => pose.omega_v[b],
            Other::Block(g) => match spec.guides[g] {
                Guide::Fixed { .. } => 0.0,
                Guide::Link { body, .. } => pose.omega_v[body],
            },
        };
        for (out, j) in self.joint.iter_mut().zip(joints) {
            let rel = pose.omega_v[j.a] - w(j.other);
            *out = if rel.abs() <= ZERO_SPEED { 0.0 } else { rel };
        }
        let scale = pose
            .vel
            .iter()
            .fold(0.0f64, |m, v| m.max(dot(*v, *v).sqrt()));
        for ((out, dir), g) in self
            .slide
            .iter_mut()
            .zip(&mut self.dir)
            .zip(&friction.guides)
        {
            let guide = spec.guides[g.guide];
            let (e, p, carrier) = match guide {
                Guide::Fixed { point, dir } => (dir, point, [0.0, 0.0]),
                Guide::Link { point, b, c, body } => {
                    let r = sub(pose.xy[point], pose.xy[b]);
                    let wv = pose.omega_v[body];
                    let v = [pose.vel[b][0] - wv * r[1], pose.vel[b][1] + wv * r[0]];
                    (sub(pose.xy[c], pose.xy[b]), point, v)
                }
            };
            let len = dot(e, e).sqrt();
            *dir = [e[0] / len, e[1] / len];
            let rel = dot(*dir, sub(pose.vel[p], carrier));
            *out = if rel.abs() <= ZERO_SPEED * scale {
                0.0
            } else {
                rel
            };
        }
    }
}

/// The sign of `x`, 0 at 0.
fn sgn(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// Element `e`'s load of unit size into the pose's extra loads: a joint's
/// torque of 1 N·m on member `a` and −1 N·m on the other; a guide's force of 1 N
/// along it on the block (and −1 N on the guide's carrier, at the point).
fn unit_load(
    model: &Model,
    joints: &[Joint],
    friction: &Friction,
    rel: &Relative,
    e: usize,
    pose: &mut super::solve::Pose,
) {
    let spec = &model.spec;
    pose.extra = true;
    pose.extra_force.fill([0.0; 2]);
    pose.extra_body.fill([0.0; 3]);
    if let Some(j) = joints.get(e) {
        pose.extra_body[j.a][2] += 1.0;
        let other = match j.other {
            Other::Frame => None,
            Other::Body(b) => Some(b),
            Other::Block(g) => match spec.guides[g] {
                Guide::Fixed { .. } => None,
                Guide::Link { body, .. } => Some(body),
            },
        };
        if let Some(b) = other {
            pose.extra_body[b][2] -= 1.0;
        }
        return;
    }
    let k = e - joints.len();
    let force = rel.dir[k];
    match spec.guides[friction.guides[k].guide] {
        Guide::Fixed { point, .. } => {
            pose.extra_force[point][0] += force[0];
            pose.extra_force[point][1] += force[1];
        }
        Guide::Link { point, body, .. } => {
            pose.extra_force[point][0] += force[0];
            pose.extra_force[point][1] += force[1];
            let arm = pose.arm(body, pose.xy[point]);
            let b = &mut pose.extra_body[body];
            b[0] -= force[0];
            b[1] -= force[1];
            b[2] -= cross(arm, force);
        }
    }
}

/// Each element's signed size at speed `omega` [rad/s] with Coulomb magnitudes
/// `mags` (joints' μ·r·|R| [N·m], then guides' μ·|N| [N]): against its relative
/// velocity, with the viscous part (the torque on a joint's member `a` [N·m],
/// the force along a guide on its block [N]); and its power loss [W] into `loss`.
fn signed_sizes(
    joints: &[Joint],
    friction: &Friction,
    rel: &Relative,
    omega: f64,
    mags: &[f64],
    sized: &mut [f64],
    loss: &mut [f64],
) {
    let viscous = joints
        .iter()
        .map(|j| j.viscous)
        .chain(friction.guides.iter().map(|g| g.viscous));
    let speeds = rel.joint.iter().chain(&rel.slide);
    for ((((f, l), &m), c), &v) in sized
        .iter_mut()
        .zip(loss)
        .zip(mags)
        .zip(viscous)
        .zip(speeds)
    {
        let v = omega * v;
        *f = -(m * sgn(v) + c * v);
        *l = -*f * v;
    }
}

/// The Coulomb magnitudes a values row implies: μ·r·|R| per joint (|R| the
/// larger force on its two members), μ·|N| per guide.
fn magnitudes(joints: &[Joint], friction: &Friction, row: &[f64], mags: &mut [f64]) {
    let nj = joints.len();
    for (m, j) in mags.iter_mut().zip(joints) {
        let r = j.offsets.iter().fold(0.0f64, |m, &o| {
            // √(x² + y²), not hypot: libm's hypot, guarding against an
            // overflow no force reaches, was the fixed point's main cost.
            m.max((row[o] * row[o] + row[o + 1] * row[o + 1]).sqrt())
        });
        *m = j.mu_r * r;
    }
    for (k, g) in friction.guides.iter().enumerate() {
        mags[nj + k] = g.mu * row[1 + g.guide].abs();
    }
}

/// One parallel task: its chunk's index, its values, losses, status and
/// conditioning.
type Task<'a> = (
    usize,
    (
        ((&'a mut [f64], &'a mut [f64]), &'a mut [i64]),
        &'a mut [f64],
    ),
);

/// Kinetostatics of `model` with `friction` at the N angles of `inputs` and each
/// crank speed of `omegas` [rad/s] (steady), into `out`.
pub fn solve_friction_into(
    model: &Model,
    inputs: Inputs<'_>,
    friction: &Friction,
    omegas: &[f64],
    out: FrictionOutputs<'_>,
    n_threads: Option<i64>,
) -> Result<(), ForceError> {
    let joints = model.joints(friction)?;
    if let Some(w) = omegas.iter().find(|w| !w.is_finite()) {
        return Err(bad(format!("crank speed {w} [rad/s] is not finite")));
    }
    let Inputs {
        xy,
        vel,
        acc,
        force,
        torque,
    } = inputs;
    let p2 = 2 * model.spec.n_points;
    let nb = model.spec.bodies.len();
    let n = out.conditioning.len();
    let ns = omegas.len();
    let w = model.width(true);
    let nf = joints.len() + friction.guides.len();
    let sizes = [
        ("xy", xy.len(), n * p2),
        ("vel", vel.len(), n * p2),
        ("acc", acc.len(), n * p2),
        ("force", force.map_or(n * p2, <[f64]>::len), n * p2),
        ("torque", torque.map_or(n * nb, <[f64]>::len), n * nb),
        ("values", out.values.len(), n * ns * w),
        ("losses", out.losses.len(), n * ns * nf),
        ("status", out.status.len(), n * ns),
    ];
    for (field, got, want) in sizes {
        if got != want {
            return Err(bad(format!(
                "{field} has {got} values; {n} angles and {ns} speeds need {want}"
            )));
        }
    }
    let threads = resolve_threads(n_threads)?;
    if n == 0 || ns == 0 {
        return Ok(());
    }
    let FrictionOutputs {
        values,
        losses,
        status,
        conditioning,
    } = out;
    let run = |(c, (((vals, loss), stat), conds)): Task<'_>| {
        if crate::cancel::requested() {
            return;
        }
        let mut s = model.scratch();
        let mut parts = vec![0.0; 3 * w];
        let mut unit = vec![0.0; 3 * w];
        let mut units = vec![0.0; nf * w];
        let mut prev = vec![0.0; nf];
        let mut next = vec![0.0; nf];
        let mut sized = vec![0.0; nf];
        let mut rel = Relative {
            joint: vec![0.0; joints.len()],
            slide: vec![0.0; friction.guides.len()],
            dir: vec![[0.0; 2]; friction.guides.len()],
        };
        let rows = vals
            .chunks_exact_mut(ns * w)
            .zip(stat.chunks_exact_mut(ns))
            .zip(conds.iter_mut());
        for (i, ((vrow, srow), cond)) in rows.enumerate() {
            let lrow = &mut loss[i * ns * nf..(i + 1) * ns * nf];
            let a = c * CHUNK + i;
            let row = Row {
                xy: &xy[a * p2..(a + 1) * p2],
                vel: &vel[a * p2..(a + 1) * p2],
                acc: &acc[a * p2..(a + 1) * p2],
                force: force.map(|f| &f[a * p2..(a + 1) * p2]),
                torque: torque.map(|t| &t[a * nb..(a + 1) * nb]),
            };
            s.pose.extra = false;
            *cond = if s.pose.fill(&model.spec, row) {
                let (p0, rest) = parts.split_at_mut(w);
                let (p1, p2_) = rest.split_at_mut(w);
                model.solve_one(&mut s, [p0, p1, p2_])
            } else {
                f64::NAN
            };
            if cond.is_nan() || *cond == 0.0 {
                vrow.fill(f64::NAN);
                lrow.fill(f64::NAN);
                srow.fill(0);
                continue;
            }
            rel.fill(model, &joints, friction, &s.pose);
            // The matrix is the same for every load: each element's response to
            // a load of unit size, once per angle (the static part's change),
            // and the forces at any friction are the frictionless ones plus
            // the elements' sizes times their responses.
            for (e, resp) in units.chunks_exact_mut(w).enumerate() {
                unit_load(model, &joints, friction, &rel, e, &mut s.pose);
                let (u0, rest) = unit.split_at_mut(w);
                let (u1, u2) = rest.split_at_mut(w);
                model.solve_one(&mut s, [u0, u1, u2]);
                for ((r, x), y) in resp.iter_mut().zip(&unit[2 * w..]).zip(&parts[2 * w..]) {
                    *r = x - y;
                }
            }
            s.pose.extra = false;
            for (k, &omega) in omegas.iter().enumerate() {
                let out = &mut vrow[k * w..(k + 1) * w];
                let lo = &mut lrow[k * nf..(k + 1) * nf];
                let w2 = omega * omega;
                prev.fill(0.0);
                let mut scale = f64::NAN;
                let mut state = -1;
                for it in 1..=MAX_ITER {
                    signed_sizes(&joints, friction, &rel, omega, &prev, &mut sized, lo);
                    for (o, (a0, a2)) in out.iter_mut().zip(parts[..w].iter().zip(&parts[2 * w..]))
                    {
                        *o = w2 * a0 + a2;
                    }
                    for (&f, resp) in sized.iter().zip(units.chunks_exact(w)) {
                        for (o, r) in out.iter_mut().zip(resp) {
                            *o += f * r;
                        }
                    }
                    magnitudes(&joints, friction, out, &mut next);
                    let big = next.iter().fold(0.0f64, |m, &x| m.max(x));
                    if it == 1 {
                        scale = out.iter().fold(0.0f64, |m, &x| m.max(x.abs()));
                    }
                    if !big.is_finite() || big > BLOW_UP * scale.max(f64::MIN_POSITIVE) {
                        break;
                    }
                    let change = next
                        .iter()
                        .zip(&prev)
                        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
                    if change <= TOL * big {
                        state = it as i64;
                        break;
                    }
                    prev.copy_from_slice(&next);
                }
                srow[k] = state;
                if state <= 0 {
                    out.fill(f64::NAN);
                    lo.fill(f64::NAN);
                }
            }
        }
    };
    // With no friction element the losses are empty: each task gets an empty
    // slice (chunks of an empty slice would be none to zip with).
    let loss_chunks: Vec<&mut [f64]> = if nf == 0 {
        (0..n.div_ceil(CHUNK)).map(|_| Default::default()).collect()
    } else {
        losses.chunks_mut(CHUNK * ns * nf).collect()
    };
    pool(threads)?.install(|| {
        values
            .par_chunks_mut(CHUNK * ns * w)
            .zip(loss_chunks.into_par_iter())
            .zip(status.par_chunks_mut(CHUNK * ns))
            .zip(conditioning.par_chunks_mut(CHUNK))
            .enumerate()
            .for_each(run)
    });
    Ok(())
}

#[cfg(test)]
mod tests {
    //! The kernel alone: a journal against μ·r·|R|, no friction equal to
    //! [`super::super::solve_into`], bad friction refused, an angle not
    //! assembled left unsolved.
    use super::*;
    use crate::forces::{solve_into, Body, Outputs, Spec};

    /// A crank O–A (0.3 m) with 2 kg at A, driven at angle `phi`.
    fn crank() -> (Model, [f64; 4], [f64; 4], [f64; 4]) {
        let spec = Spec {
            n_points: 2,
            bodies: vec![Body {
                points: vec![0, 1],
                mass: 0.0,
                com_uv: [0.5, 0.0],
                inertia: 0.0,
            }],
            ground: vec![0],
            point_mass: vec![0.0, 2.0],
            guides: vec![],
            driver: 0,
            gravity: [0.0, -9.81],
        };
        let phi = 0.7_f64;
        let (c, s) = (phi.cos(), phi.sin());
        let r = 0.3;
        (
            Model::new(spec).unwrap(),
            [0.0, 0.0, r * c, r * s],
            [0.0, 0.0, -r * s, r * c],
            [0.0, 0.0, -r * c, -r * s],
        )
    }

    fn run(
        model: &Model,
        friction: &Friction,
        omegas: &[f64],
        xy: &[f64],
    ) -> (Vec<f64>, Vec<f64>, Vec<i64>) {
        let (_, _, vel, acc) = crank();
        let w = model.width(true);
        let nf = friction.pins.len() + friction.guides.len();
        let (mut values, mut losses) = (vec![0.0; omegas.len() * w], vec![0.0; omegas.len() * nf]);
        let (mut status, mut cond) = (vec![0; omegas.len()], vec![0.0]);
        let inputs = Inputs {
            xy,
            vel: &vel,
            acc: &acc,
            force: None,
            torque: None,
        };
        let out = FrictionOutputs {
            values: &mut values,
            losses: &mut losses,
            status: &mut status,
            conditioning: &mut cond,
        };
        solve_friction_into(model, inputs, friction, omegas, out, Some(1)).unwrap();
        (values, losses, status)
    }

    #[test]
    fn journal_closed_form_and_no_friction() {
        let (model, xy, vel, acc) = crank();
        let (mu_r, c) = (0.002, 0.01);
        let friction = Friction {
            pins: vec![PinFriction {
                point: 0,
                mu_r,
                viscous: c,
            }],
            guides: vec![],
        };
        let omegas = [5.0, 50.0];
        let (values, losses, status) = run(&model, &friction, &omegas, &xy);
        let w = model.width(true);
        let (m, g, phi, r) = (2.0, 9.81, 0.7_f64, 0.3);
        for (k, &om) in omegas.iter().enumerate() {
            // The bearing carries m g down and m ω² r outwards.
            let load = [
                m * om * om * r * phi.cos(),
                m * om * om * r * phi.sin() - m * g,
            ];
            let big_r = load[0].hypot(load[1]);
            let torque = m * g * r * phi.cos() + mu_r * big_r + c * om;
            assert!(
                (values[k * w] - torque).abs() < 1e-12 * torque.abs(),
                "{}",
                values[k * w]
            );
            assert!((losses[k] - (mu_r * big_r + c * om) * om).abs() < 1e-12 * losses[k]);
            assert!(status[k] >= 1);
        }
        // No friction: today's solve, exactly.
        let (values, losses, status) = run(&model, &Friction::default(), &omegas, &xy);
        let mut parts = vec![0.0; 3 * w];
        let mut cond = vec![0.0];
        let inputs = Inputs {
            xy: &xy,
            vel: &vel,
            acc: &acc,
            force: None,
            torque: None,
        };
        let out = Outputs {
            values: &mut parts,
            conditioning: &mut cond,
            reactions: true,
            analogs: None,
        };
        solve_into(&model, inputs, out, Some(1)).unwrap();
        for (k, &om) in omegas.iter().enumerate() {
            for j in 0..w {
                assert_eq!(values[k * w + j], om * om * parts[j] + parts[2 * w + j]);
            }
        }
        assert!(losses.is_empty() && status == [1, 1]);
    }

    #[test]
    fn bad_friction_is_refused_and_nan_left_unsolved() {
        let (model, mut xy, _, _) = crank();
        for (mu_r, viscous, point) in [(-1.0, 0.0, 0), (0.1, f64::NAN, 0), (0.1, 0.0, 1)] {
            let friction = Friction {
                pins: vec![PinFriction {
                    point,
                    mu_r,
                    viscous,
                }],
                guides: vec![],
            };
            let inputs = Inputs {
                xy: &xy,
                vel: &xy,
                acc: &xy,
                force: None,
                torque: None,
            };
            let (mut v, mut l, mut s, mut c) = (vec![0.0; 5], vec![0.0; 1], vec![0; 1], vec![0.0]);
            let out = FrictionOutputs {
                values: &mut v,
                losses: &mut l,
                status: &mut s,
                conditioning: &mut c,
            };
            assert!(solve_friction_into(&model, inputs, &friction, &[1.0], out, Some(1)).is_err());
        }
        xy[2] = f64::NAN;
        let friction = Friction {
            pins: vec![PinFriction {
                point: 0,
                mu_r: 0.01,
                viscous: 0.0,
            }],
            guides: vec![],
        };
        let (values, losses, status) = run(&model, &friction, &[1.0], &xy);
        assert!(values.iter().all(|v| v.is_nan()) && losses[0].is_nan() && status == [0]);
    }
}
