//! Systems of difference constraints: the optimum of a cyclogram LP by
//! Bellman–Ford shortest paths (negative weights and cycles allowed).

use rayon::prelude::*;

use super::graph::{
    all_within, check_finite, check_memory, validate_arcs, Csr, CyclogramError, MAX_ABS_VALUE,
    MAX_SIZE, PARALLEL_MIN_WORK,
};

// ---------------------------------------------------------------------------
// Systems of difference constraints
// ---------------------------------------------------------------------------

/// Relative tolerance of one relaxation in [`max_difference`]: a distance is
/// lowered only when it improves by more than
/// `eps = DIFFERENCE_RTOL · (1 + max |w|) · n_nodes` (per weight row). Round-off of
/// a sum of up to `n_nodes` weights is far below this, so an exactly tight cycle
/// whose float sum comes out at ±1e-13 is feasible, not a negative cycle.
pub const DIFFERENCE_RTOL: f64 = 1e-12;

/// What a difference bound is, for error messages.
const BOUND_WHAT: &str = "difference bounds";

/// "No arc": the predecessor of a vertex that was never lowered (arc indices are
/// at most [`MAX_SIZE`] - 1 < `u32::MAX`).
const NO_ARC: u32 = u32::MAX;

/// Lower bound of the work of one row of a difference batch, in units of
/// (arcs + nodes), counted against [`PARALLEL_MIN_WORK`]: two Bellman–Ford runs,
/// each of at least one pass over the arcs and one over the nodes.
pub(super) const DIFFERENCE_PASSES: usize = 4;

/// The structure of a system of difference constraints, validated once per call.
pub(super) struct Differences {
    n: usize,
    src: Vec<u32>,
    source: usize,
    target: usize,
    /// The arcs in the order the relaxation passes take them: by the tail's rank in
    /// a depth-first topological order (back arcs of cycles ignored), so one pass
    /// settles every path along that order and each further pass one more back arc.
    /// In input order a chain given tail-first needed one pass per arc: quadratic.
    order: Vec<u32>,
    /// The tails and heads of the arcs in that order (`src[order[i]]`, `dst[order[i]]`):
    /// read in sequence by the passes.
    ord_src: Vec<u32>,
    ord_dst: Vec<u32>,
    /// The runs of `order` that share a tail: (tail, end of the run) in order.
    groups: Vec<(u32, u32)>,
}

/// Arc indices sorted (stably) by their tail's position in the reverse postorder
/// of an iterative depth-first search over all vertices: for a graph without
/// cycles a topological order, so Bellman–Ford over the arcs in this order settles
/// in one pass (plus one to see that nothing changes) whatever the input order.
fn arc_order(n: usize, src: &[u32], dst: &[u32]) -> Vec<u32> {
    let m = src.len();
    let out = Csr::build(n, |e| src[e] as usize, |e| dst[e], m);
    let mut rank = vec![0usize; n];
    let mut seen = vec![false; n];
    let mut next = n; // ranks are handed out from the back: reverse postorder
    let mut stack: Vec<(u32, usize)> = Vec::new();
    for root in 0..n {
        if seen[root] {
            continue;
        }
        seen[root] = true;
        stack.push((root as u32, out.ptr[root]));
        while let Some(top) = stack.last_mut() {
            let v = top.0 as usize;
            if top.1 < out.ptr[v + 1] {
                let w = out.other[top.1] as usize;
                top.1 += 1;
                if !seen[w] {
                    seen[w] = true;
                    stack.push((w as u32, out.ptr[w]));
                }
            } else {
                next -= 1;
                rank[v] = next;
                stack.pop();
            }
        }
    }
    let by_rank = Csr::build(n, |e| rank[src[e] as usize], |_| 0, m);
    by_rank.edge
}

/// Working memory of one thread: distances, predecessor arcs, cycle-search marks
/// (each V,) and the arcs of the last path found.
pub(super) struct DifferenceWork {
    pub(super) dist: Vec<f64>,
    pub(super) pred: Vec<u32>,
    pub(super) mark: Vec<u32>,
    pub(super) path: Vec<u32>,
    /// Passes over the arcs made by the last row (both runs): its cost, in passes.
    pub(super) passes: usize,
    /// After a row whose first run settled, if that run's distances π are a
    /// potential of the row's weights exactly (π[v] ≤ fl(π[u] + w[e]) on every
    /// arc): (max |π|, max |w|), for a caller's certificate; else None.
    pub(super) potential: Option<(f64, f64)>,
    /// The arcs of the last cycle of predecessors a first run stopped at (a cycle
    /// below `-eps` at that row's weights): a candidate for [`Differences::cycle_below`].
    pub(super) cycle: Vec<u32>,
    /// When each vertex's distance last fell, in steps of the run (V,).
    changed: Vec<usize>,
}

impl DifferenceWork {
    pub(super) fn new(n: usize) -> Self {
        DifferenceWork {
            dist: vec![0.0; n],
            pred: vec![NO_ARC; n],
            mark: vec![0; n],
            path: Vec::new(),
            passes: 0,
            potential: None,
            cycle: Vec::new(),
            changed: vec![0; n],
        }
    }
}

/// How a Bellman–Ford run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Relaxation {
    /// A full pass lowered no distance by more than `eps`.
    Settled,
    /// The predecessor arcs closed a cycle: its weights sum to less than `-eps`.
    NegativeCycle,
}

impl Differences {
    pub(super) fn new(
        n_nodes: i64,
        src: &[i64],
        dst: &[i64],
        source: i64,
        target: i64,
    ) -> Result<Self, CyclogramError> {
        if n_nodes < 1 || n_nodes as u64 > MAX_SIZE as u64 {
            return Err(CyclogramError::BadNodeCount {
                value: n_nodes,
                max: MAX_SIZE,
            });
        }
        // The arc checks are those of event graphs; only the wording differs.
        let (n, src, dst) = validate_arcs(n_nodes, src, dst).map_err(|e| match e {
            CyclogramError::IndexOutOfRange {
                field,
                position,
                value,
                n_events,
            } => CyclogramError::NodeOutOfRange {
                field,
                location: format!("[{position}]"),
                value,
                n_nodes: n_events,
            },
            other => other,
        })?;
        for (field, value) in [("source", source), ("target", target)] {
            if value < 0 || value as u64 >= n as u64 {
                return Err(CyclogramError::NodeOutOfRange {
                    field,
                    location: String::new(),
                    value,
                    n_nodes: n,
                });
            }
        }
        let order = arc_order(n, &src, &dst);
        let ord_src: Vec<u32> = order.iter().map(|&e| src[e as usize]).collect();
        let ord_dst = order.iter().map(|&e| dst[e as usize]).collect();
        let mut groups: Vec<(u32, u32)> = Vec::new();
        for (i, &u) in ord_src.iter().enumerate() {
            match groups.last_mut() {
                Some((tail, end)) if *tail == u => *end = i as u32 + 1,
                _ => groups.push((u, i as u32 + 1)),
            }
        }
        Ok(Differences {
            n,
            src,
            source: source as usize,
            target: target as usize,
            order,
            ord_src,
            ord_dst,
            groups,
        })
    }

    /// Bellman–Ford from `start`, or from a virtual vertex with a 0 arc to every
    /// vertex (`None`: every distance starts at 0, which finds a negative cycle
    /// anywhere in the graph). Passes over the arcs in [`arc_order`] until one
    /// changes nothing; a distance is replaced, with its predecessor, only on an
    /// improvement by more than `eps`.
    ///
    /// A cycle of predecessor arcs proves a cycle of weight < -eps (the arc that
    /// closed it improved its head by more than eps). Conversely, as long as the
    /// predecessors form a forest every distance is at least that of a simple
    /// path, so distances can drop by more than eps only finitely often: after
    /// pass n - 1 each is within (n - 1)·eps of that bound, so at most n(n - 1)
    /// more improvements can happen before a predecessor cycle must appear. The
    /// cap of n² + n + 1 passes is therefore never reached in practice.
    /// `check_cycles = false` skips the search for a cycle of predecessors, for a
    /// caller that has proved there is none to find (the run then settles).
    fn relax(
        &self,
        w: &[f64],
        eps: f64,
        start: Option<usize>,
        check_cycles: bool,
        work: &mut DifferenceWork,
    ) -> Relaxation {
        let DifferenceWork {
            dist,
            pred,
            mark,
            passes: done,
            changed: changed_at,
            ..
        } = work;
        match start {
            None => dist.fill(0.0),
            Some(s) => {
                dist.fill(f64::INFINITY);
                dist[s] = 0.0;
            }
        }
        pred.fill(NO_ARC);
        changed_at.fill(0);
        let passes = self.n.saturating_mul(self.n).saturating_add(self.n + 1);
        // A tail's arcs are relaxed at step t (one step per run of arcs sharing
        // a tail, counted from 1); the last time at t - G. If the tail's distance
        // has not fallen since, each of them gives the same sum as then, which
        // was not below the head's distance less eps then (or became it), and
        // the head's distance has only fallen: the arcs would change nothing and
        // are passed over. The same distances, predecessors and passes.
        let g = self.groups.len();
        let mut t = 0usize;
        for p in 0..passes {
            *done += 1;
            let mut changed = false;
            let mut begin = 0usize;
            for &(u, end) in &self.groups {
                t += 1;
                let (u, end) = (u as usize, end as usize);
                if p > 0 && changed_at[u] + g < t {
                    begin = end;
                    continue;
                }
                for (&e, &v) in self.order[begin..end].iter().zip(&self.ord_dst[begin..end]) {
                    // inf + w = inf is never below anything: unreached tails do nothing.
                    let v = v as usize;
                    let c = dist[u] + w[e as usize];
                    if c < dist[v] - eps {
                        dist[v] = c;
                        pred[v] = e;
                        changed_at[v] = t;
                        changed = true;
                    }
                }
                begin = end;
            }
            if !changed {
                return Relaxation::Settled;
            }
            if check_cycles && predecessor_cycle(&self.src, pred, mark).is_some() {
                return Relaxation::NegativeCycle;
            }
        }
        Relaxation::NegativeCycle
    }

    /// Shortest distance from source to target for one weight row (NaN if some
    /// cycle is negative, +inf if the target is unreachable); the arcs of one
    /// shortest path, source to target, are left in `work.path`.
    pub(super) fn solve_row(&self, w: &[f64], work: &mut DifferenceWork) -> f64 {
        self.solve_row_as(w, work, false)
    }

    /// [`Self::solve_row`], told with `feasible` whether the caller has proved that
    /// no cycle weighs less than `-eps` (a potential π with π[v] ≤ fl(π[u] + w[e])
    /// on every arc and small round-off: `speed_limit`'s certificate). Then no
    /// predecessor cycle can form (it needs a cycle below `-eps`) and both runs
    /// settle (see [`Self::relax`]): the first run, which only looks for such a
    /// cycle, is skipped and the second runs without looking for one. The same
    /// result bit for bit, at about half the work.
    pub(super) fn solve_row_as(&self, w: &[f64], work: &mut DifferenceWork, feasible: bool) -> f64 {
        match self.start_row(w, work, feasible) {
            Some(eps) => self.finish_row(w, eps, feasible, work),
            None => f64::NAN,
        }
    }

    /// The first part of [`Self::solve_row_as`]: the row's tolerance `eps`, and
    /// unless `feasible` the first run (None: it found a cycle below `-eps`, the
    /// row's value is NaN). Leaves `work.potential` set when that run settled on
    /// an exact potential.
    pub(super) fn start_row(
        &self,
        w: &[f64],
        work: &mut DifferenceWork,
        feasible: bool,
    ) -> Option<f64> {
        let scale = w.iter().fold(0.0f64, |a, &x| a.max(x.abs()));
        let eps = DIFFERENCE_RTOL * (1.0 + scale) * self.n as f64;
        work.path.clear();
        work.passes = 0;
        work.potential = None;
        if !feasible {
            if self.relax(w, eps, None, true, work) == Relaxation::NegativeCycle {
                self.keep_cycle(work);
                return None;
            }
            work.potential = self.potential(w, &work.dist).map(|pi| (pi, scale));
        }
        Some(eps)
    }

    /// The rest of [`Self::solve_row_as`] after [`Self::start_row`]: the run from
    /// the source, the path and the value.
    pub(super) fn finish_row(
        &self,
        w: &[f64],
        eps: f64,
        feasible: bool,
        work: &mut DifferenceWork,
    ) -> f64 {
        if self.relax(w, eps, Some(self.source), !feasible, work) == Relaxation::NegativeCycle {
            return f64::NAN;
        }
        if work.dist[self.target] == f64::INFINITY {
            return f64::INFINITY;
        }
        // A settled run leaves a predecessor tree rooted at the source (the source
        // itself can only be lowered through a negative cycle), so this walk ends
        // at the source within n - 1 arcs; the guard only keeps a bug from looping.
        let mut v = self.target;
        while v != self.source {
            let e = work.pred[v];
            if e == NO_ARC || work.path.len() >= self.n {
                work.path.clear();
                return f64::NAN;
            }
            work.path.push(e);
            v = self.src[e as usize] as usize;
        }
        work.path.reverse();
        // The value is the weight of the path reported, summed from the source, so
        // the two agree exactly; it is within (n - 1)·eps of the relaxed distance.
        work.path.iter().fold(0.0, |s, &e| s + w[e as usize])
    }
}

impl Differences {
    /// Nodes up to which [`Self::cycle_below`] decides: its round-off margin holds
    /// while n·2⁻⁵³ is far below `DIFFERENCE_RTOL` (see there).
    const CYCLE_TEST_MAX_NODES: usize = 1000;

    /// Whether the first run of a row with weights `w` cannot settle because the
    /// cycle `cycle` (arc indices, a candidate from an earlier row) weighs less
    /// than `-2·|C|·eps` here: then that run ends at a cycle of predecessors or at
    /// its cap, and the row's value is NaN whatever else it would do.
    ///
    /// Why: a settled first run leaves distances d (sums of at most n weights,
    /// |d| ≤ n·max|w|) with fl(d[u] + w[e]) ≥ fl(d[v] − eps) on every arc; summed
    /// around the cycle, W(C) ≥ −|C|·eps − |C|·(n + 2)·max|w|·2⁻⁵³. With n ≤
    /// [`Self::CYCLE_TEST_MAX_NODES`] the last term (and the round-off of W's own
    /// sum) is below 1e-12·|C|·(1 + max|w|)·n/4 ≤ |C|·eps/4, so W < −2·|C|·eps
    /// contradicts it. False says nothing.
    pub(super) fn cycle_below(&self, w: &[f64], cycle: &[u32]) -> bool {
        if cycle.is_empty() || self.n > Self::CYCLE_TEST_MAX_NODES {
            return false;
        }
        let scale = w.iter().fold(0.0f64, |a, &x| a.max(x.abs()));
        let eps = DIFFERENCE_RTOL * (1.0 + scale) * self.n as f64;
        let weight = cycle.iter().fold(0.0, |s, &e| s + w[e as usize]);
        weight < -2.0 * cycle.len() as f64 * eps
    }

    /// After a first run stopped at a cycle of predecessors: its arcs into
    /// `work.cycle` (left as it was when the run stopped at its cap instead).
    fn keep_cycle(&self, work: &mut DifferenceWork) {
        let Some(start) = predecessor_cycle(&self.src, &work.pred, &mut work.mark) else {
            return;
        };
        work.cycle.clear();
        let mut v = start;
        while let Some(&e) = work.pred.get(v) {
            if e == NO_ARC || work.cycle.len() > self.n {
                work.cycle.clear();
                return;
            }
            work.cycle.push(e);
            v = self.src[e as usize] as usize;
            if v == start {
                return;
            }
        }
    }

    /// max |π| if `pi` is a potential of `w` exactly (π[v] ≤ fl(π[u] + w[e]) on
    /// every arc), else None.
    fn potential(&self, w: &[f64], pi: &[f64]) -> Option<f64> {
        let ok = self
            .order
            .iter()
            .zip(&self.ord_src)
            .zip(&self.ord_dst)
            .all(|((&e, &u), &v)| pi[v as usize] <= pi[u as usize] + w[e as usize]);
        ok.then(|| pi.iter().fold(0.0f64, |a, &x| a.max(x.abs())))
    }
}

/// True if following predecessor arcs from some vertex leads back to a vertex of
/// the same walk. `mark` (V,) is scratch space.
/// Returns a vertex on such a cycle.
fn predecessor_cycle(src: &[u32], pred: &[u32], mark: &mut [u32]) -> Option<usize> {
    mark.fill(0);
    for start in 0..pred.len() {
        if mark[start] != 0 {
            continue;
        }
        // Vertex indices are below u32::MAX - 1, so the stamp is never 0.
        let stamp = start as u32 + 1;
        let mut v = start;
        loop {
            mark[v] = stamp;
            let e = pred[v];
            if e == NO_ARC {
                break;
            }
            v = src[e as usize] as usize;
            if mark[v] != 0 {
                if mark[v] == stamp {
                    return Some(v);
                }
                break;
            }
        }
    }
    None
}

/// Largest `x[target] - x[source]` over all real `x` with
/// `x[dst[e]] - x[src[e]] <= weights[e]` for every arc `e`: the shortest-path
/// distance from `source` to `target` (Bellman–Ford; weights may be negative).
///
/// Returns the value and, per arc, whether it lies on the shortest path found:
/// * NaN (no arc marked) if the system is infeasible, i.e. some cycle anywhere in
///   the graph has negative total weight — reachable from `source` or not;
/// * +inf (no arc marked) if it is feasible and `target` is unreachable from
///   `source`;
/// * otherwise the total weight of the marked path, summed from `source`
///   (0 with no arc marked if `source == target`).
///
/// Tolerance: a relaxation counts only when it improves a distance by more than
/// `eps = 1e-12 · (1 + max |w|) · n_nodes` ([`DIFFERENCE_RTOL`]). A cycle whose
/// weights sum to `-eps` or more is therefore feasible (an exactly tight cycle
/// with round-off of ±1e-13 is), one summing to less than `-n_nodes · eps` is
/// always infeasible, and in between either verdict is possible; the value is
/// within `(n_nodes - 1) · eps` of the exact distance.
pub fn max_difference(
    n_nodes: i64,
    src: &[i64],
    dst: &[i64],
    weights: &[f64],
    source: i64,
    target: i64,
) -> Result<(f64, Vec<bool>), CyclogramError> {
    let sys = Differences::new(n_nodes, src, dst, source, target)?;
    let m = sys.src.len();
    if weights.len() != m {
        return Err(CyclogramError::WeightLength {
            field: "weights",
            expected: m,
            got: weights.len(),
        });
    }
    check_finite("weights", weights, m, BOUND_WHAT)?;
    check_memory(0, 0, m)?;
    let mut work = DifferenceWork::new(sys.n);
    let value = sys.solve_row(weights, &mut work);
    let mut on_path = vec![false; m];
    for &e in &work.path {
        on_path[e as usize] = true;
    }
    Ok((value, on_path))
}

/// [`max_difference`] for `rows` weight rows of `row_len` entries, stored
/// row-major in `weights` (`shape = (rows, row_len)`, `row_len` = number of arcs).
/// Returns the values (rows,) and the path marks (rows × arcs, row-major); row `r`
/// is bit for bit what [`max_difference`] gives for that row, whatever the thread
/// count. The structure is validated once; rows run in parallel on the pool chosen
/// by `n_threads` (see [`crate::parallel`]).
#[allow(clippy::too_many_arguments)]
pub fn max_difference_batch(
    n_nodes: i64,
    src: &[i64],
    dst: &[i64],
    weights: &[f64],
    shape: (usize, usize),
    source: i64,
    target: i64,
    n_threads: Option<i64>,
) -> Result<(Vec<f64>, Vec<bool>), CyclogramError> {
    let sys = Differences::new(n_nodes, src, dst, source, target)?;
    let (rows, row_len) = shape;
    let (n, m) = (sys.n, sys.src.len());
    if row_len != m || rows.checked_mul(m) != Some(weights.len()) {
        return Err(CyclogramError::WeightLength {
            field: "weights",
            expected: m,
            got: if row_len != m {
                row_len
            } else {
                weights.len() / rows.max(1)
            },
        });
    }
    let threads = crate::parallel::resolve_threads(n_threads)?;
    if !all_within(weights) {
        // Name the row and the column, even for a batch of one row.
        let (i, &value) = weights
            .iter()
            .enumerate()
            .find(|(_, v)| v.is_nan() || v.abs() > MAX_ABS_VALUE)
            .unwrap_or((0, &f64::NAN));
        return Err(CyclogramError::NonFinite {
            field: "weights",
            location: format!("[{}, {}]", i / m.max(1), i % m.max(1)),
            value,
            what: BOUND_WHAT,
        });
    }
    check_memory(0, 0, rows.saturating_mul(m.saturating_add(8)))?;
    let mut values = vec![0.0; rows];
    let mut on_path = vec![false; rows * m];
    let solve = |work: &mut DifferenceWork, r: usize, value: &mut f64, marks: &mut [bool]| {
        if crate::cancel::requested() {
            return;
        }
        *value = sys.solve_row(&weights[r * m..(r + 1) * m], work);
        for &e in &work.path {
            marks[e as usize] = true;
        }
    };
    let work = rows.saturating_mul((m + n).saturating_mul(DIFFERENCE_PASSES));
    // Without arcs there are no row chunks to hand out (and nothing to relax).
    if threads == 1 || m == 0 || work < PARALLEL_MIN_WORK {
        let mut scratch = DifferenceWork::new(n);
        for (r, value) in values.iter_mut().enumerate() {
            solve(&mut scratch, r, value, &mut on_path[r * m..(r + 1) * m]);
        }
    } else {
        crate::parallel::pool(threads)?.install(|| {
            values
                .par_iter_mut()
                .zip(on_path.par_chunks_mut(m))
                .enumerate()
                .for_each_init(
                    || DifferenceWork::new(n),
                    |scratch, (r, (value, marks))| solve(scratch, r, value, marks),
                )
        });
    }
    Ok((values, on_path))
}
