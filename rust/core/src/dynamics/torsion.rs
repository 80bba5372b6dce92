//! The main shaft's torsion and the working members' dynamic errors (issue 34
//! item 3).
//!
//! **The chain.** The main shaft is a chain of torsional springs: the head
//! (the motor's end, with the flywheel, the rotor and the gears reduced to it)
//! and, along the shaft, one node per mechanism's take-off point. Node k
//! (k = 1…n) carries its mechanism's reduced inertia J_k(φ_k) on top of a
//! constant hub inertia H_k (the cam disc, crank, gear and shaft section there),
//! its reduced load torque Q_k(φ_k), and is joined to node k − 1 (node 0 the
//! head) by a segment of stiffness c_k and damping d_k. With θ_k = φ₀ − φ_k the
//! twist of node k behind the head and S_k = c_k·(θ_k − θ_{k−1}) +
//! d_k·(θ̇_k − θ̇_{k−1}) (θ₀ = 0) the torque the segment passes on:
//!
//! ```text
//! (J_k + H_k)·φ̈_k + ½·J_k′·φ̇_k² = S_k − S_{k+1} − Q_k(φ_k)        (S_{n+1} = 0)
//! J₀·φ̈₀ = M(φ̇₀) − S₁      (a motor at the head)   or   φ̇₀ = ω (a constant speed)
//! ```
//!
//! **The working member.** The mechanism's working member sits at Π(φ_k) (one
//! to three coordinates: a slider's or follower's travel, a point's x and y)
//! when its links are rigid; an elastic link or transmission of natural
//! frequency ω_n and damping ratio ζ (the member as one mass on it, each
//! coordinate alike) puts it at x = Π(φ_k) + u with
//!
//! ```text
//! ü + 2ζω_n·u̇ + ω_n²·u = −d²Π(φ_k)/dt² = −(Π″·φ̇_k² + Π′·φ̈_k)
//! ```
//!
//! (the member's reaction on the shaft is in J_k and Q_k already; its
//! vibration's is not: the member is light against the shaft's inertias).
//! **The dynamic error** is where the member is minus where the rigid machine
//! puts it at the same head angle, e = Π(φ₀ − θ_k) + u − Π(φ₀): the shaft's
//! lag and the link's vibration together.
//!
//! **The periodic steady state** is integrated in the head's angle φ₀ (so one
//! cycle is exactly 2π) by fixed-step RK4, whose step keeps the fastest rate of
//! the chain times the time step at `accuracy` (the Gershgorin bound of the
//! stiffness over the inertias, the damping's rate, the links' ω_n), cycle
//! after cycle from the static twist until the state at φ₀ = 0 repeats to
//! `tol` (relative to each variable's range over the cycle): the damping takes
//! the start's transient away. A lightly damped chain takes more cycles; one
//! that does not settle in `max_cycles` is reported so, not returned as if it
//! had.

use std::f64::consts::TAU;

use rayon::prelude::*;

use super::shaft::{bad, DriveError, Motor, Spline};
use crate::input::InvalidInput;
use crate::parallel::{pool, resolve_threads};

#[cfg(test)]
#[path = "torsion_tests.rs"]
mod tests;

/// A working member on a node: its rigid position Π and its derivatives in the
/// node's angle, each `components` rows of N samples (row-major), and its
/// link's natural frequency [rad/s] (infinite: a rigid link) and damping ratio.
#[derive(Debug, Clone, Copy)]
pub struct Member<'a> {
    pub pos: &'a [f64],
    pub d1: &'a [f64],
    pub d2: &'a [f64],
    pub components: usize,
    pub omega_n: f64,
    pub zeta: f64,
}

/// One take-off point along the shaft, in order from the head: its
/// mechanism's J [kg·m²], J′ [kg·m²/rad] and Q [N·m] at N uniform angles of
/// the main shaft (phased by the cyclogram), its hub inertia [kg·m²], the
/// stiffness [N·m/rad] and damping [N·m·s/rad] of the segment before it, and
/// its working member if any.
#[derive(Debug, Clone, Copy)]
pub struct Node<'a> {
    pub j: &'a [f64],
    pub dj: &'a [f64],
    pub q: &'a [f64],
    pub hub: f64,
    pub stiffness: f64,
    pub damping: f64,
    pub member: Option<Member<'a>>,
}

/// What turns the head: a constant speed [rad/s], or a motor on the head's
/// constant inertia [kg·m²] starting from `omega` [rad/s] (the rigid steady
/// state's speed at φ = 0 is a good start).
#[derive(Debug, Clone, Copy)]
pub enum Head<'a> {
    Speed(f64),
    Motor {
        motor: &'a Motor,
        inertia: f64,
        omega: f64,
    },
}

/// Options of the steady state.
#[derive(Debug, Clone, Copy)]
pub struct TorsionOptions {
    /// The state at φ₀ = 0 repeats to this, relative to each variable's range.
    pub tol: f64,
    /// At most this many cycles.
    pub max_cycles: usize,
    /// The fastest rate times the time step (0.1: RK4's local error ~(0.1)⁵/120
    /// of the fastest mode; the peak errors move by ~1e-9 relative from 0.05).
    pub accuracy: f64,
}

impl Default for TorsionOptions {
    fn default() -> Self {
        TorsionOptions {
            tol: 1e-9,
            max_cycles: 5000,
            accuracy: 0.1,
        }
    }
}

/// The outcome: 0 periodic, 1 not settled in `max_cycles`, 2 the head stalled
/// or the integration blew up.
pub const TORSION_STATUS: [&str; 3] = ["periodic", "not settled", "stalled"];

/// The periodic steady state at the N head angles φ₀ = 2πi/N.
#[derive(Debug, Clone)]
pub struct Torsion {
    pub status: u8,
    pub cycles: usize,
    /// The last cycle's largest relative change of the state at φ₀ = 0.
    pub residual: f64,
    /// RK4 steps per cycle.
    pub steps: usize,
    /// The head's speed [rad/s] and the time from φ₀ = 0 [s].
    pub omega: Vec<f64>,
    pub time: Vec<f64>,
    /// θ_k [rad], row k − 1 (n × N).
    pub twist: Vec<f64>,
    /// S_k [N·m], the torque in the segment before node k (n × N).
    pub torque: Vec<f64>,
    /// e [the member's unit], the members' coordinates in node order (R × N).
    pub error: Vec<f64>,
    /// The largest |e| (the norm over a member's coordinates) over the N
    /// samples, per node (NaN without a member).
    pub peak: Vec<f64>,
}

struct Link {
    pos: Vec<Spline>,
    d1: Vec<Spline>,
    d2: Vec<Spline>,
    wn: f64,
    zeta: f64,
    rigid: bool,
    /// The index of its first u in the state.
    at: usize,
}

struct Seg {
    j: Spline,
    dj: Spline,
    q: Spline,
    c: f64,
    d: f64,
    link: Option<Link>,
    /// The mean of Q over the samples [N·m] (the start's static twist).
    q_mean: f64,
}

/// The chain, built once for every head that turns it (one speed or a sweep).
struct Model {
    segs: Vec<Seg>,
    dim: usize,
    samples: usize,
    /// The chain's own fastest rate [1/s] (a motor's head may add to it).
    rate: f64,
}

/// Check the nodes: a typed error naming the first bad field.
fn check(nodes: &[Node<'_>]) -> Result<usize, DriveError> {
    if nodes.is_empty() {
        return Err(bad(
            "nodes",
            0.0,
            "the shaft needs at least one take-off point",
        ));
    }
    let n = nodes[0].j.len();
    for node in nodes {
        if n < 4 || node.j.len() != n || node.dj.len() != n || node.q.len() != n {
            return Err(bad(
                "samples",
                node.j.len() as f64,
                format!(
                    "must be >= 4 and the same for every node's J, dJ and Q (the first has {n})"
                ),
            ));
        }
        InvalidInput::check_finite("inertia", node.j)?;
        InvalidInput::check_finite("d_inertia", node.dj)?;
        InvalidInput::check_finite("load_torque", node.q)?;
        if !(node.hub.is_finite() && node.hub > 0.0) {
            return Err(bad(
                "hub_inertia",
                node.hub,
                "[kg·m²] must be finite and > 0",
            ));
        }
        if let Some(k) = node.j.iter().position(|&v| v + node.hub <= 0.0) {
            return Err(bad(
                "inertia",
                node.j[k] + node.hub,
                format!("[kg·m²] (with the hub, at sample {k}) must be > 0"),
            ));
        }
        if !(node.stiffness.is_finite() && node.stiffness > 0.0) {
            return Err(bad(
                "stiffness",
                node.stiffness,
                "[N·m/rad] must be finite and > 0",
            ));
        }
        if !(node.damping.is_finite() && node.damping >= 0.0) {
            return Err(bad(
                "damping",
                node.damping,
                "[N·m·s/rad] must be finite and >= 0",
            ));
        }
        if let Some(m) = node.member {
            let r = m.components * n;
            if m.components == 0 || m.components > 3 {
                return Err(bad("components", m.components as f64, "must be 1, 2 or 3"));
            }
            if m.pos.len() != r || m.d1.len() != r || m.d2.len() != r {
                return Err(bad(
                    "member",
                    m.pos.len() as f64,
                    format!("values given; need components × samples = {r} for Π, Π′ and Π″"),
                ));
            }
            InvalidInput::check_finite("member_position", m.pos)?;
            InvalidInput::check_finite("member_d1", m.d1)?;
            InvalidInput::check_finite("member_d2", m.d2)?;
            if m.omega_n.is_nan() || m.omega_n <= 0.0 {
                return Err(bad(
                    "link_omega_n",
                    m.omega_n,
                    "[rad/s] must be > 0 (inf: a rigid link)",
                ));
            }
            if !(m.zeta.is_finite() && m.zeta >= 0.0) {
                return Err(bad("link_zeta", m.zeta, "must be finite and >= 0"));
            }
        }
    }
    Ok(n)
}

fn check_options(opt: &TorsionOptions) -> Result<(), DriveError> {
    if !(opt.tol.is_finite() && opt.tol > 0.0 && opt.tol < 1.0) {
        return Err(bad("tol", opt.tol, "must be in (0, 1)"));
    }
    if opt.max_cycles == 0 {
        return Err(bad("max_cycles", 0.0, "must be >= 1"));
    }
    if !(opt.accuracy.is_finite() && opt.accuracy > 0.0 && opt.accuracy <= 0.5) {
        return Err(bad("accuracy", opt.accuracy, "must be in (0, 0.5]"));
    }
    Ok(())
}

fn check_head(head: &Head<'_>) -> Result<(), DriveError> {
    match head {
        Head::Speed(w) => {
            if !(w.is_finite() && *w > 0.0) {
                return Err(bad("speed", *w, "[rad/s] must be finite and > 0"));
            }
        }
        Head::Motor {
            motor,
            inertia,
            omega,
        } => {
            motor.check()?;
            if !(inertia.is_finite() && *inertia > 0.0) {
                return Err(bad(
                    "head_inertia",
                    *inertia,
                    "[kg·m²] (flywheel, rotor and gears at the head) must be finite and > 0",
                ));
            }
            if !(omega.is_finite() && *omega > 0.0) {
                return Err(bad("omega_start", *omega, "[rad/s] must be finite and > 0"));
            }
        }
    }
    Ok(())
}

impl Model {
    fn new(nodes: &[Node<'_>]) -> Model {
        let samples = nodes[0].j.len();
        let mut dim = 2 + 2 * nodes.len();
        let mut segs = Vec::with_capacity(nodes.len());
        for node in nodes {
            let jj: Vec<f64> = node.j.iter().map(|v| v + node.hub).collect();
            let link = node.member.map(|m| {
                let rows =
                    |v: &[f64]| -> Vec<Spline> { v.chunks(samples).map(Spline::new).collect() };
                let l = Link {
                    pos: rows(m.pos),
                    d1: rows(m.d1),
                    d2: rows(m.d2),
                    wn: m.omega_n,
                    zeta: m.zeta,
                    rigid: m.omega_n.is_infinite(),
                    at: dim,
                };
                dim += 2 * m.components;
                l
            });
            segs.push(Seg {
                j: Spline::new(&jj),
                dj: Spline::new(node.dj),
                q: Spline::new(node.q),
                c: node.stiffness,
                d: node.damping,
                link,
                q_mean: node.q.iter().sum::<f64>() / samples as f64,
            });
        }
        let lows: Vec<f64> = nodes
            .iter()
            .map(|nd| nd.j.iter().fold(f64::INFINITY, |a, &v| a.min(v)) + nd.hub)
            .collect();
        let mut model = Model {
            segs,
            dim,
            samples,
            rate: 0.0,
        };
        model.rate = model.chain_rate(&lows);
        model
    }

    /// The chain's fastest rate [1/s] from each node's least inertia `lows`: the
    /// Gershgorin bound of the stiffnesses over the inertias, the damping's rate
    /// and the links'.
    fn chain_rate(&self, lows: &[f64]) -> f64 {
        let mut r2: f64 = 0.0;
        let mut rd: f64 = 0.0;
        for (k, s) in self.segs.iter().enumerate() {
            let (c_next, d_next) = self.segs.get(k + 1).map_or((0.0, 0.0), |n| (n.c, n.d));
            r2 = r2.max(2.0 * (s.c + c_next) / lows[k]);
            rd = rd.max(2.0 * (s.d + d_next) / lows[k]);
            if let Some(l) = &s.link {
                if !l.rigid {
                    r2 = r2.max(l.wn * l.wn);
                    rd = rd.max(2.0 * l.zeta * l.wn);
                }
            }
        }
        r2.sqrt().max(rd)
    }

    /// The fastest rate [1/s] with `head`: a motor's head inertia on the first
    /// segment may be the lightest node.
    fn rate(&self, head: &Head<'_>) -> f64 {
        match head {
            Head::Speed(_) => self.rate,
            Head::Motor { inertia, .. } => {
                let (c, d) = (self.segs[0].c, self.segs[0].d);
                self.rate
                    .max((2.0 * c / inertia).sqrt())
                    .max(2.0 * d / inertia)
            }
        }
    }

    /// dz/dφ₀ at head angle `phi`; None where the head stops or the state is
    /// not finite. `torque` gets S_k.
    fn rhs(
        &self,
        head: &Head<'_>,
        phi: f64,
        z: &[f64],
        dz: &mut [f64],
        torque: &mut [f64],
    ) -> Option<()> {
        let w0 = z[1];
        if !(w0.is_finite() && w0 > 0.0) {
            return None;
        }
        let n = self.segs.len();
        let (mut th_prev, mut dth_prev) = (0.0, 0.0);
        for (k, s) in self.segs.iter().enumerate() {
            let (th, dth) = (z[2 + 2 * k], z[3 + 2 * k]);
            torque[k] = s.c * (th - th_prev) + s.d * (dth - dth_prev);
            th_prev = th;
            dth_prev = dth;
        }
        let eps0 = match *head {
            Head::Speed(_) => 0.0,
            Head::Motor { motor, inertia, .. } => (motor.on_shaft(w0).0 - torque[0]) / inertia,
        };
        let iw = 1.0 / w0;
        dz[0] = iw;
        dz[1] = eps0 * iw;
        for (k, s) in self.segs.iter().enumerate() {
            let (th, dth) = (z[2 + 2 * k], z[3 + 2 * k]);
            let (pk, wk) = (phi - th, w0 - dth);
            let cell = s.j.locate(pk); // every curve of the node shares its samples
            let next = if k + 1 < n { torque[k + 1] } else { 0.0 };
            let acc = (torque[k] - next - 0.5 * s.dj.at_cell(&cell) * wk * wk - s.q.at_cell(&cell))
                / s.j.at_cell(&cell);
            dz[2 + 2 * k] = dth * iw;
            dz[3 + 2 * k] = (eps0 - acc) * iw;
            if let Some(l) = &s.link {
                for c in 0..l.pos.len() {
                    let (u, du) = (z[l.at + 2 * c], z[l.at + 2 * c + 1]);
                    let ddu = if l.rigid {
                        0.0
                    } else {
                        let yy = l.d2[c].at_cell(&cell) * wk * wk + l.d1[c].at_cell(&cell) * acc;
                        -yy - 2.0 * l.zeta * l.wn * du - l.wn * l.wn * u
                    };
                    dz[l.at + 2 * c] = du * iw;
                    dz[l.at + 2 * c + 1] = ddu * iw;
                }
            }
        }
        if dz.iter().all(|v| v.is_finite()) {
            Some(())
        } else {
            None
        }
    }

    /// The start: the head's speed, each node at its static twist under the
    /// mean loads, the links at rest.
    fn start(&self, w0: f64) -> Vec<f64> {
        let mut z = vec![0.0; self.dim];
        z[1] = w0;
        let n = self.segs.len();
        let mut th = 0.0;
        for k in 0..n {
            let passed: f64 = self.segs[k..].iter().map(|s| s.q_mean).sum();
            th += passed / self.segs[k].c;
            z[2 + 2 * k] = th;
        }
        z
    }
}

/// Scratch space and the samples of one cycle.
struct Run {
    k: [Vec<f64>; 4],
    tmp: Vec<f64>,
    torque: Vec<f64>,
    /// Per sample: t, ω₀, then θ_k, then S_k, then the members' u.
    rec: Vec<f64>,
    lo: Vec<f64>,
    hi: Vec<f64>,
}

/// The steady state of the chain `nodes` turned by `head`.
pub fn torsion(
    nodes: &[Node<'_>],
    head: Head<'_>,
    opt: &TorsionOptions,
) -> Result<Torsion, DriveError> {
    check(nodes)?;
    check_head(&head)?;
    check_options(opt)?;
    solve(&Model::new(nodes), nodes, head, opt)
}

/// The steady state of the built chain `model` (of `nodes`, checked) under `head`.
fn solve(
    model: &Model,
    nodes: &[Node<'_>],
    head: Head<'_>,
    opt: &TorsionOptions,
) -> Result<Torsion, DriveError> {
    let n = model.samples;
    let w_top = match head {
        Head::Speed(w) => w,
        Head::Motor { omega, .. } => 1.5 * omega,
    };
    // Head angle per step: the time step accuracy/rate at the top speed.
    let per_sample = TAU / n as f64;
    let h_max = opt.accuracy / model.rate(&head) * w_top;
    let sub = (per_sample / h_max).ceil().max(1.0);
    if sub * n as f64 > 2e8 {
        return Err(bad(
            "stiffness",
            sub * n as f64,
            "RK4 steps a cycle would be needed: the shaft's or a link's natural frequency is \
             too high for the speed (check the units of the stiffness and the inertias)",
        ));
    }
    Ok(integrate(model, nodes, &head, sub as usize, opt))
}

fn integrate(
    model: &Model,
    nodes: &[Node<'_>],
    head: &Head<'_>,
    sub: usize,
    opt: &TorsionOptions,
) -> Torsion {
    let n = model.samples;
    let nn = model.segs.len();
    let rows: usize = nodes
        .iter()
        .map(|x| x.member.map_or(0, |m| m.components))
        .sum();
    let width = 2 + 2 * nn + rows;
    let w0 = match *head {
        Head::Speed(w) => w,
        Head::Motor { omega, .. } => omega,
    };
    let dim = model.dim;
    let mut run = Run {
        k: [
            vec![0.0; dim],
            vec![0.0; dim],
            vec![0.0; dim],
            vec![0.0; dim],
        ],
        tmp: vec![0.0; dim],
        torque: vec![0.0; nn],
        rec: vec![0.0; n * width],
        lo: vec![0.0; dim],
        hi: vec![0.0; dim],
    };
    let h = TAU / (n * sub) as f64;
    let mut z = model.start(w0);
    let (mut status, mut cycles, mut residual) = (1u8, 0usize, f64::INFINITY);
    while cycles < opt.max_cycles {
        if crate::cancel::requested() {
            break;
        }
        cycles += 1;
        let z_start = z.clone();
        z[0] = 0.0;
        run.lo.copy_from_slice(&z);
        run.hi.copy_from_slice(&z);
        if cycle(model, head, &mut z, h, sub, &mut run, width).is_none() {
            status = 2;
            break;
        }
        residual = change(&z_start, &z, &run.lo, &run.hi);
        if residual <= opt.tol {
            status = 0;
            break;
        }
    }
    finish(model, nodes, status, cycles, residual, n * sub, &run, width)
}

/// out = z + a·k, element by element.
#[inline]
fn axpy(out: &mut [f64], z: &[f64], a: f64, k: &[f64]) {
    for ((o, &zi), &ki) in out.iter_mut().zip(z).zip(k) {
        *o = zi + a * ki;
    }
}

/// One cycle of RK4 from `z`, recording each sample's state.
fn cycle(
    model: &Model,
    head: &Head<'_>,
    z: &mut [f64],
    h: f64,
    sub: usize,
    run: &mut Run,
    width: usize,
) -> Option<()> {
    let n = model.samples;
    let nn = model.segs.len();
    for i in 0..n {
        // Record the sample: the segment torques from the state.
        let phi_i = TAU * i as f64 / n as f64;
        model.rhs(head, phi_i, z, &mut run.k[0], &mut run.torque)?;
        let r = &mut run.rec[i * width..(i + 1) * width];
        r[0] = z[0];
        r[1] = z[1];
        for k in 0..nn {
            r[2 + k] = z[2 + 2 * k];
            r[2 + nn + k] = run.torque[k];
        }
        let mut at = 2 + 2 * nn;
        for s in &model.segs {
            if let Some(l) = &s.link {
                for c in 0..l.pos.len() {
                    r[at] = z[l.at + 2 * c];
                    at += 1;
                }
            }
        }
        for j in 0..sub {
            let phi = phi_i + h * j as f64;
            if j > 0 {
                model.rhs(head, phi, z, &mut run.k[0], &mut run.torque)?;
            }
            axpy(&mut run.tmp, z, 0.5 * h, &run.k[0]);
            let (k0, rest) = run.k.split_at_mut(1);
            model.rhs(head, phi + 0.5 * h, &run.tmp, &mut rest[0], &mut run.torque)?;
            axpy(&mut run.tmp, z, 0.5 * h, &rest[0]);
            model.rhs(head, phi + 0.5 * h, &run.tmp, &mut rest[1], &mut run.torque)?;
            axpy(&mut run.tmp, z, h, &rest[1]);
            model.rhs(head, phi + h, &run.tmp, &mut rest[2], &mut run.torque)?;
            let (a, b, c, e) = (&k0[0], &rest[0], &rest[1], &rest[2]);
            for (d, zd) in z.iter_mut().enumerate() {
                *zd += h / 6.0 * (a[d] + 2.0 * b[d] + 2.0 * c[d] + e[d]);
                run.lo[d] = run.lo[d].min(*zd);
                run.hi[d] = run.hi[d].max(*zd);
            }
        }
    }
    if z.iter().all(|v| v.is_finite()) {
        Some(())
    } else {
        None
    }
}

/// The largest change of the state (but t) over the cycle, relative to the
/// variable's range over it, or to its size where its range is nil.
fn change(a: &[f64], b: &[f64], lo: &[f64], hi: &[f64]) -> f64 {
    (1..a.len())
        .map(|d| {
            let delta = (b[d] - a[d]).abs();
            let scale = (hi[d] - lo[d]).max(1e-12 * hi[d].abs().max(lo[d].abs()));
            if delta == 0.0 {
                0.0
            } else if scale > 0.0 {
                delta / scale
            } else {
                f64::INFINITY
            }
        })
        .fold(0.0, f64::max)
}

#[allow(clippy::too_many_arguments)]
fn finish(
    model: &Model,
    nodes: &[Node<'_>],
    status: u8,
    cycles: usize,
    residual: f64,
    steps: usize,
    run: &Run,
    width: usize,
) -> Torsion {
    let n = model.samples;
    let nn = model.segs.len();
    let rows = width - 2 - 2 * nn;
    let mut out = Torsion {
        status,
        cycles,
        residual,
        steps,
        omega: vec![f64::NAN; n],
        time: vec![f64::NAN; n],
        twist: vec![f64::NAN; nn * n],
        torque: vec![f64::NAN; nn * n],
        error: vec![f64::NAN; rows * n],
        peak: vec![f64::NAN; nn],
    };
    if status != 0 {
        return out;
    }
    for i in 0..n {
        let r = &run.rec[i * width..(i + 1) * width];
        out.time[i] = r[0];
        out.omega[i] = r[1];
        for k in 0..nn {
            out.twist[k * n + i] = r[2 + k];
            out.torque[k * n + i] = r[2 + nn + k];
        }
    }
    let mut row = 0;
    for (k, (s, node)) in model.segs.iter().zip(nodes).enumerate() {
        let (Some(l), Some(m)) = (&s.link, node.member) else {
            continue;
        };
        let mut peak: f64 = 0.0;
        for i in 0..n {
            let phi = TAU * i as f64 / n as f64;
            let th = out.twist[k * n + i];
            let mut sq = 0.0;
            for c in 0..m.components {
                let u = run.rec[i * width + 2 + 2 * nn + row + c];
                // Π at the node's own angle minus the rigid machine's, plus the link.
                let e = l.pos[c].at(phi - th) - m.pos[c * n + i] + u;
                out.error[(row + c) * n + i] = e;
                sq += e * e;
            }
            peak = peak.max(sq.sqrt());
        }
        out.peak[k] = peak;
        row += m.components;
    }
    out
}

/// The columns of [`torsion_sweep`]'s rows, then one peak error per node and
/// one largest twist [rad] per node.
pub const SWEEP_COLUMNS: [&str; 3] = ["status", "cycles", "residual"];

/// The steady state at each constant head speed of `speeds` [rad/s] in
/// parallel: rows of [`SWEEP_COLUMNS`], then n peak errors, then n largest
/// |twists|, into `out` (row-major (S, 3 + 2n)); NaN where not periodic.
pub fn torsion_sweep(
    nodes: &[Node<'_>],
    speeds: &[f64],
    opt: &TorsionOptions,
    out: &mut [f64],
    n_threads: Option<i64>,
) -> Result<(), DriveError> {
    check(nodes)?;
    check_options(opt)?;
    for &w in speeds {
        check_head(&Head::Speed(w))?;
    }
    let nn = nodes.len();
    let width = 3 + 2 * nn;
    if out.len() != speeds.len() * width {
        return Err(bad(
            "out",
            out.len() as f64,
            format!("values; need {}", speeds.len() * width),
        ));
    }
    let mut failed: Option<DriveError> = None;
    let model = Model::new(nodes); // once: the splines and the chain's rate
    let pool = pool(resolve_threads(n_threads)?)?;
    let results: Vec<Result<(), DriveError>> = pool.install(|| {
        out.par_chunks_mut(width)
            .zip(speeds.par_iter())
            .map(|(row, &w)| {
                row.fill(f64::NAN);
                if crate::cancel::requested() {
                    return Ok(());
                }
                let t = solve(&model, nodes, Head::Speed(w), opt)?;
                row[0] = t.status as f64;
                row[1] = t.cycles as f64;
                row[2] = t.residual;
                if t.status == 0 {
                    for k in 0..nn {
                        row[3 + k] = t.peak[k];
                        let tw = &t.twist[k * t.omega.len()..(k + 1) * t.omega.len()];
                        row[3 + nn + k] = tw.iter().fold(0.0, |a, &v| a.max(v.abs()));
                    }
                }
                Ok(())
            })
            .collect()
    });
    for r in results {
        if let Err(e) = r {
            failed.get_or_insert(e);
        }
    }
    failed.map_or(Ok(()), Err)
}
