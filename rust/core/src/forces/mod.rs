//! Kinetostatics of planar linkages (issue 19): the reaction at every joint,
//! the normal force of every guide and the driving torque on the crank, at each
//! crank angle, from the positions and the velocity and acceleration analogs the
//! linkage solver gives.
//!
//! **Model.** Moving links are rigid bodies (mass m, centre of mass c, moment of
//! inertia J about c). A joint is a *pin* at a point, shared by the links that
//! meet there (and the frame, for a ground joint); a point may carry a lumped
//! mass (a slider block, a knife) and an external force. A slider adds a *guide*:
//! a block pinned at the point slides on a straight line of the frame or of a
//! link; the block is massless apart from the point's mass, so the guide pushes
//! the pin along its normal n̂ with a force N through the point (and the link
//! that carries the guide is pushed back by −N n̂ there). The crank carries the
//! driving torque M in the direction of increasing crank angle φ.
//!
//! **Equations at one angle.** With F_{p,b} the force pin p exerts on body b
//! (b the frame: the force on the frame's bearing), each moving body obeys
//! Newton–Euler about its centre of mass, ΣF = m a_c and Σ(r − c)×F + τ (+M on
//! the crank) = J α, and each pin ΣF_{p,b} = F_ext + m_p g − m_p a_p + ΣN n̂. One
//! force per pin is eliminated by the pin's equation (the frame's if the pin is a
//! ground joint), which leaves 3 equations per moving body (2 more per pin on no
//! body: the pin of two crossing guides) in as many unknowns for a linkage of one
//! degree of freedom. At a crank speed ω and angular acceleration ε the
//! accelerations are a = ω² x'' + ε x' (x' and x'' the analogs), so the system's
//! right-hand side, and its solution, is ω²·(part 0) + ε·(part 1) + (part 2, the
//! loads and gravity): one factorisation per angle, three right-hand sides, and
//! any speed afterwards by a weighted sum.
//!
//! **Solving.** The sparsity pattern is the same at every angle, so it is
//! analysed once: a perfect matching of equations to unknowns (none: the forces
//! are statically indeterminate, an error) and the strongly connected components
//! of the matched graph give a block-triangular order (the Dulmage–Mendelsohn
//! form). For a linkage built of Assur groups the blocks are the groups, from the
//! last placed to the crank: 6 unknowns for a dyad, 12 for a class III group, 3
//! for the crank. Each block is an LU with partial pivoting; a pivot below 1e-10
//! of the block's largest entry is a dead centre (the reactions are unbounded):
//! that angle's results are NaN and flagged singular (its conditioning 0). Each
//! angle's conditioning is the smallest pivot to its block's largest entry. It
//! is no measure of how near a dead centre a pose is: at a crank angle δ from a
//! fold it falls only as √δ (and it changes with the links' size) while the
//! analogs grow as δ^-3/2 and the torque as δ^-2; the Python layer flags poses
//! near a dead centre from the analogs (`Kinetostatics.near_dead_centre`).
//!
//! Files: this one (the model, its analysis and errors), `solve` (the batched
//! per-angle solve), `lanes` (8 angles at once in SIMD lanes) and `tests`.

mod friction;
mod lanes;
mod solve;
#[cfg(test)]
mod tests;

pub use friction::{solve_friction_into, Friction, FrictionOutputs, GuideFriction, PinFriction};
pub use solve::{solve_into, Inputs, Outputs};

use crate::geom::V2;

/// Errors of the kinetostatics.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ForceError {
    #[error("{0}")]
    BadModel(String),
    #[error(transparent)]
    Input(#[from] crate::input::InvalidInput),
}

crate::input::wraps_invalid_input!(ForceError);

/// A moving link: its joints (indices of points; the first two fix its frame),
/// its mass [kg], its centre of mass c = x₀ + u·d + v·d⊥ with d = x₁ − x₀ and
/// d⊥ = (−d_y, d_x) (`com_uv` = (u, v)), its moment of inertia about c [kg·m²].
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    pub points: Vec<usize>,
    pub mass: f64,
    pub com_uv: V2,
    pub inertia: f64,
}

/// A slider's guide: the block pinned at `point` slides along a line of the
/// frame of direction `dir`, or along the line through joints `b` and `c` of
/// moving body `body`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Guide {
    Fixed {
        point: usize,
        dir: V2,
    },
    Link {
        point: usize,
        b: usize,
        c: usize,
        body: usize,
    },
}

impl Guide {
    fn point(&self) -> usize {
        match *self {
            Guide::Fixed { point, .. } | Guide::Link { point, .. } => point,
        }
    }
}

/// A linkage for kinetostatics: `n_points` points, its moving bodies, its ground
/// joints, a lumped mass per point [kg] (0 for none), its guides, the crank (the
/// index of the body that carries the driving torque) and gravity [m/s²].
#[derive(Debug, Clone, PartialEq)]
pub struct Spec {
    pub n_points: usize,
    pub bodies: Vec<Body>,
    pub ground: Vec<usize>,
    pub point_mass: Vec<f64>,
    pub guides: Vec<Guide>,
    pub driver: usize,
    pub gravity: V2,
}

/// Who a pin's force acts on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    Frame,
    Body(usize),
}

/// A pin: its point, the sides it joins (the frame first; the first side's force
/// is eliminated by the pin's equation), the first column of the other sides'
/// forces, its guides (indices), and its 2 rows when it joins no body.
#[derive(Debug, Clone, PartialEq)]
struct Pin {
    point: usize,
    sides: Vec<Side>,
    col: usize,
    guides: Vec<usize>,
    rows: Option<usize>,
}

/// One diagonal block of the block-triangular order: its rows and columns, and
/// for each row the columns of earlier blocks it reads.
#[derive(Debug, Clone, PartialEq)]
struct Block {
    rows: Vec<usize>,
    cols: Vec<usize>,
    deps: Vec<Vec<usize>>,
}

/// A [`Spec`] analysed for solving: its pins, unknowns and block order.
#[derive(Debug, Clone, PartialEq)]
pub struct Model {
    spec: Spec,
    pins: Vec<Pin>,
    /// Unknowns (= equations).
    n: usize,
    /// Column of the first guide force, and of the driving torque.
    guide_col: usize,
    torque_col: usize,
    blocks: Vec<Block>,
    /// Where each block's entries go at solving time.
    plan: solve::Plan,
    /// The same for the 8 angles at once of the lanes path.
    plan_lanes: solve::Plan,
}

impl Model {
    /// Analyse `spec`: check it, number its unknowns and order its blocks.
    pub fn new(spec: Spec) -> Result<Model, ForceError> {
        check(&spec)?;
        let np = spec.n_points;
        let mut on: Vec<Vec<Side>> = vec![Vec::new(); np];
        for &g in &spec.ground {
            on[g].push(Side::Frame);
        }
        for (b, body) in spec.bodies.iter().enumerate() {
            for &p in &body.points {
                on[p].push(Side::Body(b));
            }
        }
        let mut guided: Vec<Vec<usize>> = vec![Vec::new(); np];
        for (g, guide) in spec.guides.iter().enumerate() {
            guided[guide.point()].push(g);
        }
        let mut pins = Vec::new();
        let mut col = 0;
        let mut rows = 3 * spec.bodies.len();
        for p in 0..np {
            let sides = std::mem::take(&mut on[p]);
            let guides = std::mem::take(&mut guided[p]);
            if sides.is_empty() && guides.is_empty() {
                continue;
            }
            let extra = if sides.is_empty() {
                rows += 2;
                Some(rows - 2)
            } else {
                None
            };
            let k = sides.len().saturating_sub(1);
            pins.push(Pin {
                point: p,
                sides,
                col,
                guides,
                rows: extra,
            });
            col += 2 * k;
        }
        let guide_col = col;
        let torque_col = guide_col + spec.guides.len();
        let n = torque_col + 1;
        if n != rows {
            return Err(ForceError::BadModel(format!(
                "the linkage's forces are not statically determinate: {rows} equations \
                 (3 per moving link, 2 per pin on no link) in {n} unknowns (2 per joint \
                 between two parts, 1 per guide, the driving torque); a linkage of one \
                 degree of freedom driven by one crank has as many"
            )));
        }
        let mut model = Model {
            spec,
            pins,
            n,
            guide_col,
            torque_col,
            blocks: Vec::new(),
            plan: solve::Plan::new(0, &[]),
            plan_lanes: solve::Plan::new(0, &[]),
        };
        model.blocks = model.order()?;
        model.plan = solve::Plan::new(model.n, &model.blocks);
        model.plan_lanes = solve::Plan::lanes(model.n, &model.blocks);
        Ok(model)
    }

    /// Number of unknowns (and of equations).
    pub fn unknowns(&self) -> usize {
        self.n
    }

    /// The sizes of the diagonal blocks, in solving order.
    pub fn block_sizes(&self) -> Vec<usize> {
        self.blocks.iter().map(|b| b.cols.len()).collect()
    }

    /// The (point, side) pairs of the reactions, in output order: each pin's
    /// sides, the frame first.
    pub fn pairs(&self) -> Vec<(usize, Side)> {
        self.pins
            .iter()
            .flat_map(|p| p.sides.iter().map(move |&s| (p.point, s)))
            .collect()
    }

    pub fn spec(&self) -> &Spec {
        &self.spec
    }

    /// The block-triangular order of the structural pattern.
    fn order(&self) -> Result<Vec<Block>, ForceError> {
        let n = self.n;
        let mut pattern = Pattern {
            adj: vec![Vec::new(); n],
        };
        self.assemble(&solve::Pose::structural(&self.spec), &mut pattern);
        let adj: Vec<Vec<usize>> = pattern
            .adj
            .into_iter()
            .map(|mut v| {
                v.sort_unstable();
                v.dedup();
                v
            })
            .collect();
        let row_of = matching(&adj, n).ok_or_else(|| {
            ForceError::BadModel(
                "the linkage's forces are not statically determinate: its equations cannot \
                 be matched to its unknowns (a part of the linkage is over-constrained while \
                 another is free)"
                    .into(),
            )
        })?;
        // Graph on columns: j → k when the row matched to j reads column k.
        let graph: Vec<Vec<usize>> = (0..n)
            .map(|j| adj[row_of[j]].iter().copied().filter(|&k| k != j).collect())
            .collect();
        let comps = tarjan(&graph);
        let mut blocks = Vec::with_capacity(comps.len());
        let mut done = vec![false; n];
        for cols in comps {
            let rows: Vec<usize> = cols.iter().map(|&j| row_of[j]).collect();
            let deps = rows
                .iter()
                .map(|&r| {
                    adj[r]
                        .iter()
                        .copied()
                        .filter(|k| !cols.contains(k))
                        .inspect(|&k| debug_assert!(done[k]))
                        .collect()
                })
                .collect();
            for &j in &cols {
                done[j] = true;
            }
            blocks.push(Block { rows, cols, deps });
        }
        Ok(blocks)
    }

    /// Emit the system at one pose into `sink`: matrix entries and the three
    /// right-hand sides (ω², ε, static), in the order of the module's equations.
    /// Generic over the number type: one angle (`f64`) or several in the lanes
    /// of [`solve::Lanes`], by the same operations in the same order.
    #[inline(always)]
    fn assemble<T: solve::Num, S: Sink<T>>(&self, pose: &solve::Pose<T>, s: &mut S) {
        let spec = &self.spec;
        let k = T::splat;
        for (i, body) in spec.bodies.iter().enumerate() {
            let r = 3 * i;
            let (m, jz) = (body.mass, body.inertia);
            let (c1, c2) = (pose.com_v[i], pose.com_a[i]);
            s.rhs(r, 0, k(m) * c2[0]);
            s.rhs(r + 1, 0, k(m) * c2[1]);
            s.rhs(r + 2, 0, k(jz) * pose.omega_a[i]);
            s.rhs(r, 1, k(m) * c1[0]);
            s.rhs(r + 1, 1, k(m) * c1[1]);
            s.rhs(r + 2, 1, k(jz) * pose.omega_v[i]);
            s.rhs(r, 2, k(-m * spec.gravity[0]));
            s.rhs(r + 1, 2, k(-m * spec.gravity[1]));
            s.rhs(r + 2, 2, -pose.torque(i));
            if pose.extra {
                let [fx, fy, mz] = pose.extra_body[i];
                s.rhs(r, 2, k(-fx));
                s.rhs(r + 1, 2, k(-fy));
                s.rhs(r + 2, 2, k(-mz));
            }
        }
        s.a(3 * spec.driver + 2, self.torque_col, k(1.0));
        for pin in &self.pins {
            let p = pin.point;
            let x = pose.xy[p];
            let load = pose.pin_load(spec, p);
            let first = pin.sides.first().copied();
            for (kk, &side) in pin.sides.iter().enumerate().skip(1) {
                let (cx, cy) = (pin.col + 2 * (kk - 1), pin.col + 2 * (kk - 1) + 1);
                if let Side::Body(b) = side {
                    let d = pose.arm(b, x);
                    s.a(3 * b, cx, k(1.0));
                    s.a(3 * b + 1, cy, k(1.0));
                    s.a(3 * b + 2, cx, -d[1]);
                    s.a(3 * b + 2, cy, d[0]);
                }
                if let Some(Side::Body(e)) = first {
                    let d = pose.arm(e, x);
                    s.a(3 * e, cx, k(-1.0));
                    s.a(3 * e + 1, cy, k(-1.0));
                    s.a(3 * e + 2, cx, d[1]);
                    s.a(3 * e + 2, cy, -d[0]);
                }
            }
            match (first, pin.rows) {
                (Some(Side::Body(e)), _) => {
                    let d = pose.arm(e, x);
                    for (part, g) in load.iter().enumerate() {
                        s.rhs(3 * e, part, -g[0]);
                        s.rhs(3 * e + 1, part, -g[1]);
                        s.rhs(3 * e + 2, part, -(d[0] * g[1] - d[1] * g[0]));
                    }
                    for &g in &pin.guides {
                        let nn = pose.normal[g];
                        s.a(3 * e, self.guide_col + g, nn[0]);
                        s.a(3 * e + 1, self.guide_col + g, nn[1]);
                        s.a(3 * e + 2, self.guide_col + g, d[0] * nn[1] - d[1] * nn[0]);
                    }
                }
                (None, Some(r)) => {
                    for (part, g) in load.iter().enumerate() {
                        s.rhs(r, part, -g[0]);
                        s.rhs(r + 1, part, -g[1]);
                    }
                    for &g in &pin.guides {
                        let nn = pose.normal[g];
                        s.a(r, self.guide_col + g, nn[0]);
                        s.a(r + 1, self.guide_col + g, nn[1]);
                    }
                }
                _ => {}
            }
        }
        for (g, guide) in spec.guides.iter().enumerate() {
            if let Guide::Link { point, body, .. } = *guide {
                let d = pose.arm(body, pose.xy[point]);
                let nn = pose.normal[g];
                s.a(3 * body, self.guide_col + g, -nn[0]);
                s.a(3 * body + 1, self.guide_col + g, -nn[1]);
                s.a(
                    3 * body + 2,
                    self.guide_col + g,
                    -(d[0] * nn[1] - d[1] * nn[0]),
                );
            }
        }
    }
}

/// Where [`Model::assemble`] writes.
trait Sink<T = f64> {
    fn a(&mut self, row: usize, col: usize, v: T);
    fn rhs(&mut self, row: usize, part: usize, v: T);
}

/// The structural pattern: which columns each row reads.
struct Pattern {
    adj: Vec<Vec<usize>>,
}

impl Sink for Pattern {
    fn a(&mut self, row: usize, col: usize, _: f64) {
        self.adj[row].push(col);
    }
    fn rhs(&mut self, _: usize, _: usize, _: f64) {}
}

fn check(spec: &Spec) -> Result<(), ForceError> {
    let np = spec.n_points;
    let bad = |why: String| Err(ForceError::BadModel(why));
    if spec.point_mass.len() != np {
        return bad(format!(
            "{} point masses for {np} points",
            spec.point_mass.len()
        ));
    }
    for (i, &m) in spec.point_mass.iter().enumerate() {
        if !(m.is_finite() && m >= 0.0) {
            return bad(format!(
                "the mass of point {i} is {m}; it must be finite and >= 0 [kg]"
            ));
        }
    }
    if spec.bodies.is_empty() || spec.driver >= spec.bodies.len() {
        return bad(format!(
            "the crank is body {} of {}",
            spec.driver,
            spec.bodies.len()
        ));
    }
    if !(spec.gravity[0].is_finite() && spec.gravity[1].is_finite()) {
        return bad(format!("gravity {:?} must be finite [m/s²]", spec.gravity));
    }
    for (i, b) in spec.bodies.iter().enumerate() {
        if b.points.len() < 2 || b.points.iter().any(|&p| p >= np) {
            return bad(format!(
                "body {i} has joints {:?}; it needs at least two of the {np} points",
                b.points
            ));
        }
        if b.points[0] == b.points[1] {
            return bad(format!("body {i}'s first two joints are one point"));
        }
        if !(b.mass.is_finite() && b.mass >= 0.0 && b.inertia.is_finite() && b.inertia >= 0.0) {
            return bad(format!(
                "body {i}: mass {} [kg] and inertia {} [kg·m²] must be finite and >= 0",
                b.mass, b.inertia
            ));
        }
        if !(b.com_uv[0].is_finite() && b.com_uv[1].is_finite()) {
            return bad(format!(
                "body {i}: centre of mass {:?} not finite",
                b.com_uv
            ));
        }
    }
    if spec.ground.iter().any(|&g| g >= np) {
        return bad(format!("a ground joint is out of the {np} points"));
    }
    for (i, g) in spec.guides.iter().enumerate() {
        let ok = match *g {
            Guide::Fixed { point, dir } => {
                point < np && dir[0].is_finite() && dir[1].is_finite() && dir != [0.0, 0.0]
            }
            Guide::Link { point, b, c, body } => {
                point < np
                    && b < np
                    && c < np
                    && b != c
                    && body < spec.bodies.len()
                    && spec.bodies[body].points.contains(&b)
                    && spec.bodies[body].points.contains(&c)
            }
        };
        if !ok {
            return bad(format!("guide {i} ({g:?}) is not a guide of this linkage"));
        }
    }
    Ok(())
}

/// A perfect matching of rows to columns (Kuhn's augmenting paths): the row
/// matched to each column, or None if there is none.
fn matching(adj: &[Vec<usize>], n: usize) -> Option<Vec<usize>> {
    let mut row_of = vec![usize::MAX; n];
    fn augment(r: usize, adj: &[Vec<usize>], seen: &mut [bool], row_of: &mut [usize]) -> bool {
        for &c in &adj[r] {
            if !seen[c] {
                seen[c] = true;
                if row_of[c] == usize::MAX || augment(row_of[c], adj, seen, row_of) {
                    row_of[c] = r;
                    return true;
                }
            }
        }
        false
    }
    for r in 0..adj.len() {
        let mut seen = vec![false; n];
        if !augment(r, adj, &mut seen, &mut row_of) {
            return None;
        }
    }
    row_of.iter().all(|&r| r != usize::MAX).then_some(row_of)
}

/// Strongly connected components (Tarjan), each emitted after every component it
/// reaches: the order in which the blocks can be solved.
fn tarjan(graph: &[Vec<usize>]) -> Vec<Vec<usize>> {
    struct T<'a> {
        g: &'a [Vec<usize>],
        index: Vec<usize>,
        low: Vec<usize>,
        on: Vec<bool>,
        stack: Vec<usize>,
        next: usize,
        out: Vec<Vec<usize>>,
    }
    fn visit(t: &mut T<'_>, v: usize) {
        t.index[v] = t.next;
        t.low[v] = t.next;
        t.next += 1;
        t.stack.push(v);
        t.on[v] = true;
        for i in 0..t.g[v].len() {
            let w = t.g[v][i];
            if t.index[w] == usize::MAX {
                visit(t, w);
                t.low[v] = t.low[v].min(t.low[w]);
            } else if t.on[w] {
                t.low[v] = t.low[v].min(t.index[w]);
            }
        }
        if t.low[v] == t.index[v] {
            let mut comp = Vec::new();
            loop {
                let w = t.stack.pop().expect("Tarjan's stack holds v");
                t.on[w] = false;
                comp.push(w);
                if w == v {
                    break;
                }
            }
            comp.sort_unstable();
            t.out.push(comp);
        }
    }
    let n = graph.len();
    let mut t = T {
        g: graph,
        index: vec![usize::MAX; n],
        low: vec![0; n],
        on: vec![false; n],
        stack: Vec::new(),
        next: 0,
        out: Vec::new(),
    };
    for v in 0..n {
        if t.index[v] == usize::MAX {
            visit(&mut t, v);
        }
    }
    t.out
}
