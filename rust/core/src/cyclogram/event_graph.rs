//! Longest-path event scheduling on a network cyclogram.
//!
//! A cyclogram within one machine cycle is a directed acyclic graph: events are
//! vertices, operations are arcs `x -> y` with a phase angle `w` (degrees of
//! main-shaft rotation, negative for overlapping operations). The earliest
//! occurrence angle of every event is
//!
//! ```text
//! p(y) = 0                                  if y has no incoming arcs,
//! p(y) = max over arcs (x, y) of p(x) + w   otherwise,
//! ```
//!
//! computed in one pass over a topological order. [`EventGraph`] analyses the
//! structure once (topological order, incoming and outgoing arc lists laid out by
//! topological position) and then evaluates any number of weight vectors against it.
//!
//! [`max_difference`] and [`max_difference_batch`] solve the other problem a
//! cyclogram poses once cycles are allowed: the largest `x[t] - x[s]` subject to
//! difference constraints `x[dst] - x[src] <= w`, i.e. the optimum of a cyclogram
//! LP, by Bellman–Ford shortest paths (negative weights and cycles allowed).

use std::sync::OnceLock;

use rayon::prelude::*;

/// Errors of the schedule domain (event graphs, cycle ratios, speed limits).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ScheduleError {
    #[error("n_events = {value} is invalid: it must be an integer between 0 and {max}")]
    BadEventCount { value: i64, max: usize },
    #[error("n_nodes = {value} is invalid: it must be an integer between 1 and {max}")]
    BadNodeCount { value: i64, max: usize },
    #[error(
        "{field}{location} = {value} is not a node index; valid indices are 0 to {} \
         (n_nodes = {n_nodes})", n_nodes.saturating_sub(1)
    )]
    NodeOutOfRange {
        field: &'static str,
        location: String,
        value: i64,
        n_nodes: usize,
    },
    #[error("src and dst must have the same length (one entry per arc); got {src} and {dst}")]
    LengthMismatch { src: usize, dst: usize },
    #[error(
        "{field}[{position}] = {value} is not an event index; valid indices are 0 to {} \
         (n_events = {n_events})", n_events.saturating_sub(1)
    )]
    IndexOutOfRange {
        field: &'static str,
        position: usize,
        value: i64,
        n_events: usize,
    },
    #[error("{field} must have {expected} entries per weight vector (one per arc); got {got}")]
    WeightLength {
        field: &'static str,
        expected: usize,
        got: usize,
    },
    #[error(
        "{field}{location} = {} is out of range: {what} must be finite, with magnitude at most 1e12",
        compact(*value)
    )]
    NonFinite {
        field: &'static str,
        location: String,
        value: f64,
        what: &'static str,
    },
    #[error("{field}[{position}] = {value} is invalid: {what}")]
    OutOfDomain {
        field: &'static str,
        position: usize,
        value: f64,
        what: &'static str,
    },
    #[error("{field} = {value} is invalid: {what}")]
    BadScalar {
        field: &'static str,
        value: f64,
        what: &'static str,
    },
    #[error(
        "the arcs contain a cycle through events {events:?}; the operations of one machine \
         cycle must form an acyclic graph"
    )]
    Cycle { events: Vec<usize> },
    #[error(
        "the arcs of height 0 contain a cycle through events {events:?}; a cycle of operations \
         must cross into the next machine cycle somewhere (give one of its arcs a height >= 1)"
    )]
    ZeroHeightCycle { events: Vec<usize> },
    #[error("policy iteration did not converge in {iterations} iterations")]
    NotConverged { iterations: usize },
    #[error(transparent)]
    Threads(#[from] crate::parallel::ThreadsError),
    #[error(
        "n_events = {n_events} with {n_arcs} arcs needs about {gib:.1} GiB of working memory, \
         more than can be allocated here"
    )]
    TooLarge {
        n_events: usize,
        n_arcs: usize,
        gib: f64,
    },
}

/// Upper bound of the working memory per event and per arc of any schedule kernel
/// (index arrays, adjacency, times, Howard's policy state), in bytes.
const BYTES_PER_EVENT: usize = 96;
const BYTES_PER_ARC: usize = 48;

/// Refuse sizes whose working memory cannot be allocated, instead of letting the
/// allocator abort the process (an abort cannot be caught at the Python boundary).
pub(crate) fn check_memory(n: usize, m: usize, extra_bytes: usize) -> Result<(), ScheduleError> {
    let bytes = n
        .saturating_mul(BYTES_PER_EVENT)
        .saturating_add(m.saturating_mul(BYTES_PER_ARC))
        .saturating_add(extra_bytes);
    let mut probe: Vec<u8> = Vec::new();
    probe
        .try_reserve_exact(bytes)
        .map_err(|_| ScheduleError::TooLarge {
            n_events: n,
            n_arcs: m,
            gib: bytes as f64 / (1u64 << 30) as f64,
        })
}

/// Largest number of events or arcs (indices are stored as `u32`).
pub const MAX_SIZE: usize = u32::MAX as usize - 1;

/// Weight vectors evaluated together in the batch kernel. One arc relaxation is a
/// short dependency chain (add, max, store, load): evaluating 8 rows per chain
/// hides its latency, and a block of E arcs × 8 lanes × 8 bytes stays in L2 for
/// the graph sizes batches are meant for.
const LANES: usize = 8;

/// Below this many arc evaluations (rows × arcs) a batch runs on the calling
/// thread: a pool hand-off costs more than the work.
const PARALLEL_MIN_WORK: usize = 1 << 16;

/// Check `n_events`, the arc lists and return them as `u32`.
pub(crate) fn validate_arcs(
    n_events: i64,
    src: &[i64],
    dst: &[i64],
) -> Result<(usize, Vec<u32>, Vec<u32>), ScheduleError> {
    if n_events < 0 || n_events as u64 > MAX_SIZE as u64 {
        return Err(ScheduleError::BadEventCount {
            value: n_events,
            max: MAX_SIZE,
        });
    }
    let n = n_events as usize;
    check_memory(n, src.len(), 0)?;
    if src.len() != dst.len() {
        return Err(ScheduleError::LengthMismatch {
            src: src.len(),
            dst: dst.len(),
        });
    }
    if src.len() > MAX_SIZE {
        return Err(ScheduleError::WeightLength {
            field: "src",
            expected: MAX_SIZE,
            got: src.len(),
        });
    }
    // One branch-free pass for the range (it vectorises), a plain cast, and a
    // search for the culprit only when the range is wrong.
    let check = |field: &'static str, idx: &[i64]| -> Result<Vec<u32>, ScheduleError> {
        let (lo, hi) = idx
            .iter()
            .fold((0i64, -1i64), |(lo, hi), &v| (lo.min(v), hi.max(v)));
        if lo < 0 || (hi >= 0 && hi as u64 >= n as u64) {
            let (position, &value) = idx
                .iter()
                .enumerate()
                .find(|(_, &v)| v < 0 || v as u64 >= n as u64)
                .unwrap_or((0, &lo));
            return Err(ScheduleError::IndexOutOfRange {
                field,
                position,
                value,
                n_events: n,
            });
        }
        Ok(idx.iter().map(|&v| v as u32).collect())
    };
    Ok((n, check("src", src)?, check("dst", dst)?))
}

/// A number as a person would write it: 1.5, -20, 1e+308, NaN.
fn compact(v: f64) -> String {
    if v.is_finite() && v != 0.0 && !(1e-4..1e9).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// Largest magnitude accepted for any weight, angle, duration or height: far
/// beyond any machine (1e12 degrees), and small enough that sums over billions of
/// arcs stay finite — a finite 1e308 would otherwise overflow to inf or NaN.
pub const MAX_ABS_VALUE: f64 = 1e12;

/// True if every value is finite with magnitude at most [`MAX_ABS_VALUE`].
/// Branch-free over blocks of 8 so that it vectorises (NaN fails the compare).
#[inline]
pub(crate) fn all_within(values: &[f64]) -> bool {
    let mut ok = [true; 8];
    let chunks = values.chunks_exact(8);
    let tail = chunks.remainder();
    for c in chunks {
        for i in 0..8 {
            ok[i] &= c[i].abs() <= MAX_ABS_VALUE;
        }
    }
    ok.iter().all(|&b| b) && tail.iter().all(|x| x.abs() <= MAX_ABS_VALUE)
}

/// Check that every value is finite and within [`MAX_ABS_VALUE`]; name the first
/// one that is not.
pub(crate) fn check_finite(
    field: &'static str,
    values: &[f64],
    row_len: usize,
    what: &'static str,
) -> Result<(), ScheduleError> {
    if all_within(values) {
        return Ok(());
    }
    let (i, &value) = values
        .iter()
        .enumerate()
        .find(|(_, v)| v.is_nan() || v.abs() > MAX_ABS_VALUE)
        .unwrap_or((0, &f64::NAN));
    let location = if row_len > 0 && values.len() > row_len {
        format!("[{}, {}]", i / row_len, i % row_len)
    } else {
        format!("[{i}]")
    };
    Err(ScheduleError::NonFinite {
        field,
        location,
        value,
        what,
    })
}

/// Compressed adjacency: for vertex `k`, entries `ptr[k]..ptr[k + 1]`.
#[derive(Debug, Clone)]
struct Csr {
    ptr: Vec<usize>,
    other: Vec<u32>,
    edge: Vec<u32>,
}

impl Csr {
    /// Group arcs by `key[e]` (stable: arcs keep their input order within a group),
    /// recording `other[e]` and the arc index.
    fn build(
        n: usize,
        key: impl Fn(usize) -> usize,
        other: impl Fn(usize) -> u32,
        m: usize,
    ) -> Csr {
        let mut ptr = vec![0usize; n + 1];
        for e in 0..m {
            ptr[key(e) + 1] += 1;
        }
        for k in 0..n {
            ptr[k + 1] += ptr[k];
        }
        let mut fill = ptr.clone();
        let mut o = vec![0u32; m];
        let mut ed = vec![0u32; m];
        for e in 0..m {
            let k = key(e);
            o[fill[k]] = other(e);
            ed[fill[k]] = e as u32;
            fill[k] += 1;
        }
        Csr {
            ptr,
            other: o,
            edge: ed,
        }
    }

    #[inline]
    fn range(&self, k: usize) -> std::ops::Range<usize> {
        self.ptr[k]..self.ptr[k + 1]
    }
}

/// Topological order of `n` vertices, or one cycle (events in arc order).
pub(crate) fn topological_order(
    n: usize,
    src: &[u32],
    dst: &[u32],
) -> Result<Vec<u32>, Vec<usize>> {
    let m = src.len();
    let out = Csr::build(n, |e| src[e] as usize, |e| dst[e], m);
    let mut indeg = vec![0u32; n];
    for &d in dst {
        indeg[d as usize] += 1;
    }
    let mut order: Vec<u32> = (0..n as u32).filter(|&v| indeg[v as usize] == 0).collect();
    let mut head = 0;
    while head < order.len() {
        let v = order[head] as usize;
        head += 1;
        for j in out.range(v) {
            let u = out.other[j] as usize;
            indeg[u] -= 1;
            if indeg[u] == 0 {
                order.push(u as u32);
            }
        }
    }
    if order.len() == n {
        return Ok(order);
    }
    // Every vertex left has a predecessor that is also left: walk backwards along
    // such predecessors until a vertex repeats; the repeat closes a cycle.
    let inc = Csr::build(n, |e| dst[e] as usize, |e| src[e], m);
    let start = (0..n).find(|&v| indeg[v] > 0).unwrap_or(0);
    let mut seen_at = vec![usize::MAX; n];
    let mut walk: Vec<usize> = Vec::new();
    let mut v = start;
    while seen_at[v] == usize::MAX {
        seen_at[v] = walk.len();
        walk.push(v);
        v = inc
            .range(v)
            .map(|j| inc.other[j] as usize)
            .find(|&u| indeg[u] > 0)
            .unwrap_or(v);
    }
    let mut cycle = walk[seen_at[v]..].to_vec();
    cycle.reverse(); // the walk went against the arcs
                     // Start the report at the smallest event so that it is reproducible.
    if let Some(i) = cycle
        .iter()
        .enumerate()
        .min_by_key(|(_, &e)| e)
        .map(|(i, _)| i)
    {
        cycle.rotate_left(i);
    }
    Err(cycle)
}

/// The structure of an event network, analysed once and reused for any number of
/// weight vectors.
#[derive(Debug)]
pub struct EventGraph {
    n: usize,
    src: Vec<u32>,
    dst: Vec<u32>,
    /// `order[k]`: the event at topological position `k`.
    order: Vec<u32>,
    /// Incoming arcs grouped by the topological position of their head, in that
    /// order, so the forward pass reads them sequentially; `other` = tail event.
    inc: Csr,
    /// `slot[e]`: where arc `e` sits in `inc` (the inverse of `inc.edge`).
    slot: Vec<u32>,
    /// Outgoing arcs grouped by the topological position of their tail; `other` =
    /// head event. Only the backward pass needs them: built on first use.
    out: OnceLock<Csr>,
}

impl Clone for EventGraph {
    fn clone(&self) -> Self {
        let out = OnceLock::new();
        if let Some(o) = self.out.get() {
            let _ = out.set(o.clone());
        }
        EventGraph {
            n: self.n,
            src: self.src.clone(),
            dst: self.dst.clone(),
            order: self.order.clone(),
            inc: self.inc.clone(),
            slot: self.slot.clone(),
            out,
        }
    }
}

/// Earliest and latest event times, slack and critical arcs of one weight vector.
#[derive(Debug, Clone, PartialEq)]
pub struct Analysis {
    /// Earliest occurrence angle of each event (V,).
    pub earliest: Vec<f64>,
    /// Latest occurrence angle of each event that keeps every event at or before the horizon (V,).
    pub latest: Vec<f64>,
    /// Total slack of each arc: latest(y) - earliest(x) - w (E,).
    pub total_slack: Vec<f64>,
    /// Free slack of each arc: earliest(y) - earliest(x) - w (E,).
    pub free_slack: Vec<f64>,
    /// Arcs with zero total slack (within `tolerance`), every tie included (E,).
    pub critical: Vec<bool>,
    /// The horizon the latest times were computed for.
    pub horizon: f64,
    /// Absolute tolerance used to call a slack zero.
    pub tolerance: f64,
}

impl EventGraph {
    /// Analyse the structure: validate indices, find a topological order (or report
    /// a cycle) and lay the incoming arcs out by topological position.
    pub fn new(n_events: i64, src: &[i64], dst: &[i64]) -> Result<Self, ScheduleError> {
        let (n, src, dst) = validate_arcs(n_events, src, dst)?;
        let order =
            topological_order(n, &src, &dst).map_err(|events| ScheduleError::Cycle { events })?;
        let mut pos = vec![0u32; n];
        for (k, &v) in order.iter().enumerate() {
            pos[v as usize] = k as u32;
        }
        let inc = Csr::build(n, |e| pos[dst[e] as usize] as usize, |e| src[e], src.len());
        let mut slot = vec![0u32; src.len()];
        for (j, &e) in inc.edge.iter().enumerate() {
            slot[e as usize] = j as u32;
        }
        Ok(EventGraph {
            n,
            src,
            dst,
            order,
            inc,
            slot,
            out: OnceLock::new(),
        })
    }

    fn out(&self) -> &Csr {
        self.out.get_or_init(|| {
            let mut pos = vec![0u32; self.n];
            for (k, &v) in self.order.iter().enumerate() {
                pos[v as usize] = k as u32;
            }
            Csr::build(
                self.n,
                |e| pos[self.src[e] as usize] as usize,
                |e| self.dst[e],
                self.src.len(),
            )
        })
    }

    /// Number of events (vertices).
    pub fn n_events(&self) -> usize {
        self.n
    }

    /// Number of operations (arcs).
    pub fn n_arcs(&self) -> usize {
        self.src.len()
    }

    /// Tail event of each arc.
    pub fn src(&self) -> &[u32] {
        &self.src
    }

    /// Head event of each arc.
    pub fn dst(&self) -> &[u32] {
        &self.dst
    }

    /// Events in a topological order.
    pub fn topological_order(&self) -> &[u32] {
        &self.order
    }

    fn check_weights(&self, weights: &[f64], rows: usize) -> Result<(), ScheduleError> {
        let m = self.n_arcs();
        if weights.len() != rows * m {
            return Err(ScheduleError::WeightLength {
                field: "weights",
                expected: m,
                got: if rows == 0 {
                    weights.len()
                } else {
                    weights.len() / rows.max(1)
                },
            });
        }
        check_finite("weights", weights, m, "phase angles [deg]")
    }

    /// Earliest times, by event, into `t` (V,).
    fn forward(&self, w: &[f64], t: &mut [f64]) {
        for (k, &v) in self.order.iter().enumerate() {
            let r = self.inc.range(k);
            let mut best = if r.is_empty() { 0.0 } else { f64::NEG_INFINITY };
            for (&s, &e) in self.inc.other[r.clone()].iter().zip(&self.inc.edge[r]) {
                // Finite inputs, no NaN: compare-and-select, not the NaN-aware max.
                let c = t[s as usize] + w[e as usize];
                best = if c > best { c } else { best };
            }
            t[v as usize] = best;
        }
    }

    /// Latest times, by event, for a horizon into `t` (V,).
    fn backward(&self, w: &[f64], horizon: f64, t: &mut [f64]) {
        let out = self.out();
        for (k, &v) in self.order.iter().enumerate().rev() {
            // Every event, not only the sinks, must occur by the horizon: with negative
            // (overlapping) arcs an inner event can be the last one.
            let mut best = horizon;
            let r = out.range(k);
            for (&d, &e) in out.other[r.clone()].iter().zip(&out.edge[r]) {
                best = best.min(t[d as usize] - w[e as usize]);
            }
            t[v as usize] = best;
        }
    }

    /// Earliest occurrence angle of every event for one weight vector (E,) -> (V,).
    pub fn earliest(&self, weights: &[f64]) -> Result<Vec<f64>, ScheduleError> {
        self.check_weights(weights, 1)?;
        let mut t = vec![0.0; self.n];
        self.forward(weights, &mut t);
        Ok(t)
    }

    /// Latest occurrence angle of every event such that every event occurs at or
    /// before `horizon` and every arc keeps its phase angle.
    pub fn latest(&self, weights: &[f64], horizon: f64) -> Result<Vec<f64>, ScheduleError> {
        self.check_weights(weights, 1)?;
        if !horizon.is_finite() {
            return Err(ScheduleError::BadScalar {
                field: "horizon",
                value: horizon,
                what: "the horizon must be a finite angle in degrees",
            });
        }
        let mut t = vec![0.0; self.n];
        self.backward(weights, horizon, &mut t);
        Ok(t)
    }

    /// Earliest times for 8 rows at once: `wblk[j]` holds the weights of the arc at
    /// `inc` position `j` for each lane; times by event into `t`.
    fn forward_block(&self, wblk: &[[f64; LANES]], t: &mut [[f64; LANES]]) {
        for (k, &v) in self.order.iter().enumerate() {
            let r = self.inc.range(k);
            let mut best = if r.is_empty() {
                [0.0; LANES]
            } else {
                [f64::NEG_INFINITY; LANES]
            };
            for (&s, w) in self.inc.other[r.clone()].iter().zip(&wblk[r]) {
                let ts = &t[s as usize];
                for l in 0..LANES {
                    // Inputs are finite, so no NaN: a plain compare-and-select.
                    let c = ts[l] + w[l];
                    best[l] = if c > best[l] { c } else { best[l] };
                }
            }
            t[v as usize] = best;
        }
    }

    /// One block of up to 8 rows starting at row `r0` into `out` (lanes × V).
    /// Returns false if a weight of the block is not finite (nothing is reported
    /// from here; the caller locates it).
    fn batch_block(
        &self,
        weights: &[f64],
        r0: usize,
        out: &mut [f64],
        wblk: &mut [[f64; LANES]],
        t: &mut [[f64; LANES]],
    ) -> bool {
        let (n, m) = (self.n, self.n_arcs());
        let lanes = out.len() / n;
        let rows: Vec<&[f64]> = (0..lanes)
            .map(|l| &weights[(r0 + l) * m..(r0 + l + 1) * m])
            .collect();
        // Gather: the rows are read in order, each arc's 8 lanes written once at
        // its position in the forward pass; the finite check rides along.
        let mut ok = [true; LANES];
        for (e, &j) in self.slot.iter().enumerate() {
            let dst = &mut wblk[j as usize];
            for l in 0..lanes {
                let x = rows[l][e];
                dst[l] = x;
                ok[l] &= x.abs() <= MAX_ABS_VALUE;
            }
        }
        if !ok.iter().all(|&b| b) {
            return false;
        }
        self.forward_block(wblk, t);
        for l in 0..lanes {
            for (o, tv) in out[l * n..(l + 1) * n].iter_mut().zip(t.iter()) {
                *o = tv[l];
            }
        }
        true
    }

    /// Earliest times for `rows` weight vectors of `row_len` entries stored
    /// row-major in `weights` (rows × E) -> (rows × V), row-major. Blocks of 8 rows
    /// run in parallel on the pool chosen by `n_threads`.
    pub fn earliest_batch(
        &self,
        weights: &[f64],
        rows: usize,
        row_len: usize,
        n_threads: Option<i64>,
    ) -> Result<Vec<f64>, ScheduleError> {
        let (n, m) = (self.n, self.n_arcs());
        if row_len != m {
            return Err(ScheduleError::WeightLength {
                field: "weights",
                expected: m,
                got: row_len,
            });
        }
        if weights.len() != rows * m {
            return Err(ScheduleError::WeightLength {
                field: "weights",
                expected: m,
                got: weights.len() / rows.max(1),
            });
        }
        let threads = crate::parallel::resolve_threads(n_threads)?;
        check_memory(0, 0, rows.saturating_mul(n).saturating_mul(8))?;
        let mut out = vec![0.0; rows * n];
        if n == 0 || rows == 0 {
            return check_finite("weights", weights, m, "phase angles [deg]").map(|_| out);
        }
        let buffers = || (vec![[0.0f64; LANES]; m], vec![[0.0f64; LANES]; n]);
        let all_ok = if threads == 1 || rows * m < PARALLEL_MIN_WORK {
            let (mut wblk, mut t) = buffers();
            out.chunks_mut(LANES * n)
                .enumerate()
                .map(|(b, chunk)| self.batch_block(weights, b * LANES, chunk, &mut wblk, &mut t))
                .fold(true, |a, b| a & b)
        } else {
            crate::parallel::pool(threads)?.install(|| {
                out.par_chunks_mut(LANES * n)
                    .enumerate()
                    .map_init(buffers, |(wblk, t), (b, chunk)| {
                        self.batch_block(weights, b * LANES, chunk, wblk, t)
                    })
                    .reduce(|| true, |a, b| a & b)
            })
        };
        if !all_ok {
            check_finite("weights", weights, m, "phase angles [deg]")?;
        }
        Ok(out)
    }

    /// Earliest and latest times, total and free slack, and the critical arcs of
    /// one weight vector. `horizon = None` takes the latest earliest time (the
    /// schedule's own end), so the critical arcs are those of the longest path.
    pub fn analyze(
        &self,
        weights: &[f64],
        horizon: Option<f64>,
    ) -> Result<Analysis, ScheduleError> {
        self.check_weights(weights, 1)?;
        let mut early = vec![0.0; self.n];
        self.forward(weights, &mut early);
        let horizon = match horizon {
            Some(h) if !h.is_finite() => {
                return Err(ScheduleError::BadScalar {
                    field: "horizon",
                    value: h,
                    what: "the horizon must be a finite angle in degrees",
                })
            }
            Some(h) => h,
            None => early.iter().copied().fold(0.0f64, f64::max),
        };
        let mut late = vec![0.0; self.n];
        self.backward(weights, horizon, &mut late);
        // Slack is a difference of sums of up to V weights: call it zero within a
        // few ulps of the largest magnitude involved.
        let scale = early
            .iter()
            .chain(weights.iter())
            .fold(horizon.abs().max(1.0), |a, &b| a.max(b.abs()));
        let tolerance = 1e-9 * scale;
        let m = self.n_arcs();
        let mut total = vec![0.0; m];
        let mut free = vec![0.0; m];
        let mut critical = vec![false; m];
        for e in 0..m {
            let (x, y) = (self.src[e] as usize, self.dst[e] as usize);
            total[e] = late[y] - early[x] - weights[e];
            free[e] = early[y] - early[x] - weights[e];
            critical[e] = total[e].abs() <= tolerance;
        }
        Ok(Analysis {
            earliest: early,
            latest: late,
            total_slack: total,
            free_slack: free,
            critical,
            horizon,
            tolerance,
        })
    }
}

/// One-shot longest path: earliest times computed during Kahn's topological sort,
/// with one adjacency structure and no stored order (an event's time is final
/// when its last incoming arc has been relaxed).
///
/// Each arc's weight is copied into the adjacency while it is built (reading the
/// weights in order), so the relaxation streams through (head, weight) pairs
/// instead of fetching every weight at a random position.
pub fn longest_path(
    n_events: i64,
    src: &[i64],
    dst: &[i64],
    weights: &[f64],
) -> Result<Vec<f64>, ScheduleError> {
    let (n, s, d) = validate_arcs(n_events, src, dst)?;
    let m = s.len();
    if weights.len() != m {
        return Err(ScheduleError::WeightLength {
            field: "weights",
            expected: m,
            got: weights.len(),
        });
    }
    check_finite("weights", weights, m, "phase angles [deg]")?;
    // Out-degrees (as CSR offsets) and in-degrees in one pass.
    let mut ptr = vec![0usize; n + 1];
    let mut indeg = vec![0u32; n];
    for (&a, &b) in s.iter().zip(&d) {
        ptr[a as usize + 1] += 1;
        indeg[b as usize] += 1;
    }
    for k in 0..n {
        ptr[k + 1] += ptr[k];
    }
    let mut fill = ptr.clone();
    let mut head = vec![0u32; m];
    let mut wt = vec![0.0f64; m];
    for ((&a, &b), &w) in s.iter().zip(&d).zip(weights) {
        let slot = &mut fill[a as usize];
        head[*slot] = b;
        wt[*slot] = w;
        *slot += 1;
    }
    drop(fill);
    let mut t: Vec<f64> = indeg
        .iter()
        .map(|&k| if k == 0 { 0.0 } else { f64::NEG_INFINITY })
        .collect();
    let mut queue: Vec<u32> = (0..n as u32).filter(|&v| indeg[v as usize] == 0).collect();
    queue.reserve(n - queue.len());
    let mut next = 0;
    while next < queue.len() {
        let v = queue[next] as usize;
        next += 1;
        let tv = t[v];
        let r = ptr[v]..ptr[v + 1];
        for (&u, &w) in head[r.clone()].iter().zip(&wt[r]) {
            let u = u as usize;
            let (c, old) = (tv + w, t[u]);
            // Finite inputs, no NaN: an unconditional select (maxsd), not a branch
            // on a value that was just fetched from a random address.
            t[u] = if c > old { c } else { old };
            indeg[u] -= 1;
            if indeg[u] == 0 {
                queue.push(u as u32);
            }
        }
    }
    if queue.len() < n {
        // Cold path: let the topological sort name one cycle.
        return Err(match topological_order(n, &s, &d) {
            Err(events) => ScheduleError::Cycle { events },
            Ok(_) => ScheduleError::Cycle { events: vec![] },
        });
    }
    Ok(t)
}

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
const DIFFERENCE_PASSES: usize = 4;

/// The structure of a system of difference constraints, validated once per call.
struct Differences {
    n: usize,
    src: Vec<u32>,
    dst: Vec<u32>,
    source: usize,
    target: usize,
    /// The arcs in the order the relaxation passes take them: by the tail's rank in
    /// a depth-first topological order (back arcs of cycles ignored), so one pass
    /// settles every path along that order and each further pass one more back arc.
    /// In input order a chain given tail-first needed one pass per arc: quadratic.
    order: Vec<u32>,
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
struct DifferenceWork {
    dist: Vec<f64>,
    pred: Vec<u32>,
    mark: Vec<u32>,
    path: Vec<u32>,
    /// Passes over the arcs made by the last row (both runs): its cost, in passes.
    passes: usize,
}

impl DifferenceWork {
    fn new(n: usize) -> Self {
        DifferenceWork {
            dist: vec![0.0; n],
            pred: vec![NO_ARC; n],
            mark: vec![0; n],
            path: Vec::new(),
            passes: 0,
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
    fn new(
        n_nodes: i64,
        src: &[i64],
        dst: &[i64],
        source: i64,
        target: i64,
    ) -> Result<Self, ScheduleError> {
        if n_nodes < 1 || n_nodes as u64 > MAX_SIZE as u64 {
            return Err(ScheduleError::BadNodeCount {
                value: n_nodes,
                max: MAX_SIZE,
            });
        }
        // The arc checks are those of event graphs; only the wording differs.
        let (n, src, dst) = validate_arcs(n_nodes, src, dst).map_err(|e| match e {
            ScheduleError::IndexOutOfRange {
                field,
                position,
                value,
                n_events,
            } => ScheduleError::NodeOutOfRange {
                field,
                location: format!("[{position}]"),
                value,
                n_nodes: n_events,
            },
            other => other,
        })?;
        for (field, value) in [("source", source), ("target", target)] {
            if value < 0 || value as u64 >= n as u64 {
                return Err(ScheduleError::NodeOutOfRange {
                    field,
                    location: String::new(),
                    value,
                    n_nodes: n,
                });
            }
        }
        let order = arc_order(n, &src, &dst);
        Ok(Differences {
            n,
            src,
            dst,
            source: source as usize,
            target: target as usize,
            order,
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
    fn relax(
        &self,
        w: &[f64],
        eps: f64,
        start: Option<usize>,
        work: &mut DifferenceWork,
    ) -> Relaxation {
        let DifferenceWork {
            dist,
            pred,
            mark,
            passes: done,
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
        let passes = self.n.saturating_mul(self.n).saturating_add(self.n + 1);
        for _ in 0..passes {
            *done += 1;
            let mut changed = false;
            for &e in &self.order {
                let (u, v) = (self.src[e as usize] as usize, self.dst[e as usize] as usize);
                // inf + w = inf is never below anything: unreached tails do nothing.
                let c = dist[u] + w[e as usize];
                if c < dist[v] - eps {
                    dist[v] = c;
                    pred[v] = e;
                    changed = true;
                }
            }
            if !changed {
                return Relaxation::Settled;
            }
            if predecessor_cycle(&self.src, pred, mark) {
                return Relaxation::NegativeCycle;
            }
        }
        Relaxation::NegativeCycle
    }

    /// Shortest distance from source to target for one weight row (NaN if some
    /// cycle is negative, +inf if the target is unreachable); the arcs of one
    /// shortest path, source to target, are left in `work.path`.
    fn solve_row(&self, w: &[f64], work: &mut DifferenceWork) -> f64 {
        let scale = w.iter().fold(0.0f64, |a, &x| a.max(x.abs()));
        let eps = DIFFERENCE_RTOL * (1.0 + scale) * self.n as f64;
        work.path.clear();
        work.passes = 0;
        if self.relax(w, eps, None, work) == Relaxation::NegativeCycle
            || self.relax(w, eps, Some(self.source), work) == Relaxation::NegativeCycle
        {
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

/// True if following predecessor arcs from some vertex leads back to a vertex of
/// the same walk. `mark` (V,) is scratch space.
fn predecessor_cycle(src: &[u32], pred: &[u32], mark: &mut [u32]) -> bool {
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
                    return true;
                }
                break;
            }
        }
    }
    false
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
) -> Result<(f64, Vec<bool>), ScheduleError> {
    let sys = Differences::new(n_nodes, src, dst, source, target)?;
    let m = sys.src.len();
    if weights.len() != m {
        return Err(ScheduleError::WeightLength {
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
) -> Result<(Vec<f64>, Vec<bool>), ScheduleError> {
    let sys = Differences::new(n_nodes, src, dst, source, target)?;
    let (rows, row_len) = shape;
    let (n, m) = (sys.n, sys.src.len());
    if row_len != m || rows.checked_mul(m) != Some(weights.len()) {
        return Err(ScheduleError::WeightLength {
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
        return Err(ScheduleError::NonFinite {
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

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Issue 16 item 20: a chain of constraints given head-first took one
    /// Bellman–Ford pass per arc (the machine's speed limit was quadratic in its
    /// operations: 4000 operations 108 s). In depth-first order each run settles in
    /// two passes whatever the input order; the value is the chain's sum (closed form).
    #[test]
    fn item20_a_chain_settles_in_two_passes_whatever_its_order() {
        let n = 2000usize;
        // x[i] - x[i+1] <= -1 (x[i+1] >= x[i] + 1): arcs i+1 -> i of weight -1, and
        // the span bound x[n-1] - x[0] <= 10 000 as the arc 0 -> n-1. Largest
        // x[0] - x[n-1] is -(n-1): the shortest path from n-1 to 0 along the chain.
        for reversed in [false, true] {
            let mut src: Vec<i64> = (0..n as i64 - 1).map(|i| i + 1).collect();
            let mut dst: Vec<i64> = (0..n as i64 - 1).collect();
            if reversed {
                src.reverse();
                dst.reverse();
            }
            src.push(0);
            dst.push(n as i64 - 1);
            let mut w = vec![-1.0; n - 1];
            w.push(10_000.0);
            let sys = Differences::new(n as i64, &src, &dst, n as i64 - 1, 0).unwrap();
            let mut work = DifferenceWork::new(n);
            let value = sys.solve_row(&w, &mut work);
            assert_eq!(value, -((n - 1) as f64));
            assert_eq!(work.path.len(), n - 1);
            // Two runs of (one settling pass + one that changes nothing), plus at
            // most one pass per back arc (the span arc closes the only cycle).
            assert!(
                work.passes <= 6,
                "{} passes (reversed = {reversed})",
                work.passes
            );
        }
    }

    /// Independent reference: relax every arc V times (Bellman–Ford style).
    fn reference(n: usize, src: &[i64], dst: &[i64], w: &[f64]) -> Vec<f64> {
        let mut has_in = vec![false; n];
        for &d in dst {
            has_in[d as usize] = true;
        }
        let mut t: Vec<f64> = has_in
            .iter()
            .map(|&h| if h { f64::NEG_INFINITY } else { 0.0 })
            .collect();
        for _ in 0..n {
            for e in 0..src.len() {
                let c = t[src[e] as usize] + w[e];
                if c > t[dst[e] as usize] {
                    t[dst[e] as usize] = c;
                }
            }
        }
        t
    }

    /// A random DAG: arcs go from a lower to a higher rank of a random permutation.
    fn dag() -> impl Strategy<Value = (usize, Vec<i64>, Vec<i64>, Vec<f64>)> {
        (1usize..40).prop_flat_map(|n| {
            let perm = Just((0..n as i64).collect::<Vec<_>>()).prop_shuffle();
            let arcs = prop::collection::vec((0..n, 0..n, -50.0f64..100.0), 0..120);
            (Just(n), perm, arcs).prop_map(|(n, perm, arcs)| {
                let (mut s, mut d, mut w) = (vec![], vec![], vec![]);
                for (a, b, x) in arcs {
                    if a != b {
                        let (lo, hi) = (a.min(b), a.max(b));
                        s.push(perm[lo]);
                        d.push(perm[hi]);
                        w.push(x);
                    }
                }
                (n, s, d, w)
            })
        })
    }

    proptest! {
        #[test]
        fn earliest_matches_reference((n, s, d, w) in dag()) {
            let want = reference(n, &s, &d, &w);
            let fused = longest_path(n as i64, &s, &d, &w).unwrap();
            let prepared = EventGraph::new(n as i64, &s, &d).unwrap().earliest(&w).unwrap();
            for ((f, p), r) in fused.iter().zip(&prepared).zip(&want) {
                prop_assert!((f - r).abs() <= 1e-9 * (1.0 + r.abs()), "{f} vs {r}");
                prop_assert!((p - r).abs() <= 1e-9 * (1.0 + r.abs()), "{p} vs {r}");
            }
        }

        #[test]
        fn batch_matches_single((n, s, d, w) in dag(), rows in 1usize..20, threads in 1i64..3) {
            let g = EventGraph::new(n as i64, &s, &d).unwrap();
            let m = w.len();
            let all: Vec<f64> = (0..rows).flat_map(|r| w.iter().map(move |x| x * (1.0 + r as f64 * 0.1) - r as f64)).collect();
            let batch = g.earliest_batch(&all, rows, m, Some(threads)).unwrap();
            for r in 0..rows {
                let single = g.earliest(&all[r * m..(r + 1) * m]).unwrap();
                prop_assert_eq!(&batch[r * n..(r + 1) * n], &single[..]);
            }
        }

        #[test]
        fn slack_is_consistent((n, s, d, w) in dag()) {
            let g = EventGraph::new(n as i64, &s, &d).unwrap();
            let a = g.analyze(&w, None).unwrap();
            for e in 0..w.len() {
                prop_assert!(a.total_slack[e] >= -a.tolerance);
                prop_assert!(a.free_slack[e] >= -a.tolerance);
                prop_assert!(a.free_slack[e] <= a.total_slack[e] + a.tolerance);
            }
            for v in 0..n {
                prop_assert!(a.latest[v] >= a.earliest[v] - a.tolerance);
            }
            // The event that ends the schedule is reached by a chain of critical arcs.
            if !w.is_empty() {
                let end = (0..n).max_by(|&i, &j| a.earliest[i].total_cmp(&a.earliest[j])).unwrap();
                let reached = (0..w.len()).any(|e| a.critical[e] && d[e] as usize == end);
                let is_source = !d.iter().any(|&x| x as usize == end);
                prop_assert!(reached || is_source);
            }
        }
    }

    #[test]
    fn cycle_is_named() {
        // 0 -> 1 -> 2 -> 3 -> 1
        let err = EventGraph::new(4, &[0, 1, 2, 3], &[1, 2, 3, 1]).unwrap_err();
        assert_eq!(
            err,
            ScheduleError::Cycle {
                events: vec![1, 2, 3]
            }
        );
        let err = EventGraph::new(2, &[1], &[1]).unwrap_err();
        assert_eq!(err, ScheduleError::Cycle { events: vec![1] });
        let err = longest_path(4, &[0, 1, 2, 3], &[1, 2, 3, 1], &[1.0; 4]).unwrap_err();
        assert_eq!(
            err,
            ScheduleError::Cycle {
                events: vec![1, 2, 3]
            }
        );
    }

    #[test]
    fn bad_input_is_an_error_not_a_panic() {
        assert!(matches!(
            EventGraph::new(3, &[0, 5], &[1, 2]),
            Err(ScheduleError::IndexOutOfRange {
                field: "src",
                position: 1,
                value: 5,
                ..
            })
        ));
        assert!(matches!(
            EventGraph::new(3, &[0], &[-1]),
            Err(ScheduleError::IndexOutOfRange { field: "dst", .. })
        ));
        assert!(matches!(
            EventGraph::new(-1, &[], &[]),
            Err(ScheduleError::BadEventCount { .. })
        ));
        assert!(matches!(
            EventGraph::new(3, &[0, 1], &[1]),
            Err(ScheduleError::LengthMismatch { .. })
        ));
        let g = EventGraph::new(3, &[0, 1], &[1, 2]).unwrap();
        assert!(matches!(
            g.earliest(&[1.0]),
            Err(ScheduleError::WeightLength { .. })
        ));
        match g.earliest(&[1.0, f64::NAN]) {
            Err(ScheduleError::NonFinite { location, .. }) => assert_eq!(location, "[1]"),
            other => panic!("{other:?}"),
        }
        assert!(g.latest(&[1.0, 2.0], f64::INFINITY).is_err());
        // Finite but huge weights would overflow the sums: refused like NaN.
        assert!(g.earliest(&[1e308, 1e308]).is_err());
        assert!(longest_path(3, &[0, 1], &[1, 2], &[1e308, 1e308]).is_err());
        assert!(g
            .earliest_batch(&[1.0, 2.0, 1e308, 1.0], 2, 2, Some(1))
            .is_err());
        assert!(g.earliest_batch(&[1.0, 2.0, 3.0], 2, 2, None).is_err());
        assert!(g.earliest_batch(&[], 0, 5, None).is_err());
        assert!(matches!(
            EventGraph::new(4_000_000_000, &[], &[]),
            Err(ScheduleError::TooLarge { .. })
        ));
    }

    #[test]
    fn empty_graph() {
        let g = EventGraph::new(0, &[], &[]).unwrap();
        assert!(g.earliest(&[]).unwrap().is_empty());
        assert!(g.earliest_batch(&[], 5, 0, Some(1)).unwrap().is_empty());
        let a = g.analyze(&[], None).unwrap();
        assert_eq!(a.horizon, 0.0);
    }

    #[test]
    fn hand_example_with_overlap() {
        // 0 -(30)-> 1 -(50)-> 3 ; 0 -(100)-> 2 -(-20)-> 3   => p = [0, 30, 100, 80]
        let g = EventGraph::new(4, &[0, 1, 0, 2], &[1, 3, 2, 3]).unwrap();
        let a = g.analyze(&[30.0, 50.0, 100.0, -20.0], None).unwrap();
        assert_eq!(a.earliest, vec![0.0, 30.0, 100.0, 80.0]);
        assert_eq!(a.horizon, 100.0);
        // Event 2 ends the schedule though it is no sink (its arc to 3 is negative):
        // the horizon caps it, so 0 -> 2 is the critical arc.
        assert_eq!(a.latest, vec![0.0, 50.0, 100.0, 100.0]);
        assert_eq!(a.critical, vec![false, false, true, false]);
        assert_eq!(a.total_slack, vec![20.0, 20.0, 0.0, 20.0]);
        assert_eq!(a.free_slack, vec![0.0, 0.0, 0.0, 0.0]);
    }

    // -----------------------------------------------------------------------
    // Difference constraints
    // -----------------------------------------------------------------------

    /// Independent reference: Floyd–Warshall distances between all pairs, or None
    /// if some cycle is negative (a negative diagonal entry). Exact on the
    /// integer-valued weights the tests draw.
    fn floyd_warshall(n: usize, src: &[i64], dst: &[i64], w: &[f64]) -> Option<Vec<Vec<f64>>> {
        let mut d = vec![vec![f64::INFINITY; n]; n];
        for (i, row) in d.iter_mut().enumerate() {
            row[i] = 0.0;
        }
        for e in 0..src.len() {
            let (a, b) = (src[e] as usize, dst[e] as usize);
            d[a][b] = d[a][b].min(w[e]);
        }
        for k in 0..n {
            for i in 0..n {
                for j in 0..n {
                    let c = d[i][k] + d[k][j];
                    if c < d[i][j] {
                        d[i][j] = c;
                    }
                }
            }
        }
        if (0..n).any(|i| d[i][i] < 0.0) {
            None
        } else {
            Some(d)
        }
    }

    /// A random graph (self-loops and parallel arcs allowed) with integer weights
    /// in [-10, 30] times a power-of-two or 360 scale (sums stay exact), a source
    /// and a target.
    #[allow(clippy::type_complexity)]
    fn difference_system() -> impl Strategy<Value = (usize, Vec<i64>, Vec<i64>, Vec<f64>, i64, i64)>
    {
        (1usize..9).prop_flat_map(|n| {
            let arcs = prop::collection::vec((0..n as i64, 0..n as i64, -10i32..30), 0..24);
            let scale = prop_oneof![Just(1.0), Just(0.25), Just(360.0)];
            (Just(n), arcs, scale, 0..n as i64, 0..n as i64).prop_map(|(n, arcs, scale, s, t)| {
                let src = arcs.iter().map(|a| a.0).collect();
                let dst = arcs.iter().map(|a| a.1).collect();
                let w = arcs.iter().map(|a| a.2 as f64 * scale).collect();
                (n, src, dst, w, s, t)
            })
        })
    }

    /// The marked arcs, followed from `s`, form one path that ends at `t` and uses
    /// each of them once; returns its weight summed from `s`.
    fn walk_marked(src: &[i64], dst: &[i64], w: &[f64], marks: &[bool], s: i64, t: i64) -> f64 {
        let mut left: Vec<usize> = (0..src.len()).filter(|&e| marks[e]).collect();
        let (mut v, mut sum, mut seen) = (s, 0.0, vec![s]);
        while let Some(k) = left.iter().position(|&e| src[e] == v) {
            let e = left.remove(k);
            sum += w[e];
            v = dst[e];
            assert!(!seen.contains(&v), "the marked arcs revisit node {v}");
            seen.push(v);
        }
        assert!(left.is_empty(), "marked arcs {left:?} are off the path");
        assert_eq!(v, t, "the marked path ends at {v}, not at the target {t}");
        sum
    }

    proptest! {
        #[test]
        fn max_difference_matches_floyd_warshall((n, s, d, w, a, b) in difference_system()) {
            let (value, marks) = max_difference(n as i64, &s, &d, &w, a, b).unwrap();
            prop_assert_eq!(marks.len(), w.len());
            match floyd_warshall(n, &s, &d, &w) {
                None => {
                    prop_assert!(value.is_nan(), "{value} for an infeasible system");
                    prop_assert!(!marks.contains(&true));
                }
                Some(dist) => {
                    let want = dist[a as usize][b as usize];
                    if want == f64::INFINITY {
                        prop_assert_eq!(value, f64::INFINITY);
                        prop_assert!(!marks.contains(&true));
                    } else {
                        prop_assert!((value - want).abs() <= 1e-9 * (1.0 + want.abs()), "{value} vs {want}");
                        let sum = walk_marked(&s, &d, &w, &marks, a, b);
                        prop_assert_eq!(sum.to_bits(), value.to_bits());
                        if a == b {
                            prop_assert_eq!(value, 0.0);
                            prop_assert!(!marks.contains(&true));
                        }
                    }
                }
            }
        }

        #[test]
        fn max_difference_batch_matches_single(
            (n, s, d, w, a, b) in difference_system(),
            rows in 0usize..12,
            threads in 1i64..3,
        ) {
            let m = w.len();
            // Row r shifts every weight by 3 - r: later rows gain negative cycles.
            let all: Vec<f64> = (0..rows)
                .flat_map(|r| w.iter().map(move |x| x + 3.0 - r as f64))
                .collect();
            let (values, marks) =
                max_difference_batch(n as i64, &s, &d, &all, (rows, m), a, b, Some(threads)).unwrap();
            prop_assert_eq!(values.len(), rows);
            prop_assert_eq!(marks.len(), rows * m);
            for r in 0..rows {
                let (v, mk) = max_difference(n as i64, &s, &d, &all[r * m..(r + 1) * m], a, b).unwrap();
                prop_assert_eq!(values[r].to_bits(), v.to_bits());
                prop_assert_eq!(&marks[r * m..(r + 1) * m], &mk[..]);
            }
        }
    }

    #[test]
    fn max_difference_by_hand() {
        // x1 - x0 <= 4, x2 - x1 <= -1, x2 - x0 <= 5: max x2 - x0 = 3 via 0 -> 1 -> 2.
        let (s, d) = ([0, 1, 0], [1, 2, 2]);
        let (v, mk) = max_difference(3, &s, &d, &[4.0, -1.0, 5.0], 0, 2).unwrap();
        assert_eq!((v, mk), (3.0, vec![true, true, false]));
        // source == target: 0, nothing marked.
        let (v, mk) = max_difference(3, &s, &d, &[4.0, -1.0, 5.0], 1, 1).unwrap();
        assert_eq!((v, mk), (0.0, vec![false; 3]));
        // Unreachable target: unbounded.
        let (v, mk) = max_difference(3, &s, &d, &[4.0, -1.0, 5.0], 2, 0).unwrap();
        assert_eq!((v, mk), (f64::INFINITY, vec![false; 3]));
        // No arcs at all.
        assert_eq!(
            max_difference(1, &[], &[], &[], 0, 0).unwrap(),
            (0.0, vec![])
        );
        assert_eq!(
            max_difference(2, &[], &[], &[], 0, 1).unwrap(),
            (f64::INFINITY, vec![])
        );
    }

    #[test]
    fn negative_cycle_anywhere_is_infeasible() {
        // 0 -> 1 is all the source sees; 2 <-> 3 is a negative cycle off to the side.
        let (s, d) = ([0, 2, 3], [1, 3, 2]);
        let (v, mk) = max_difference(4, &s, &d, &[1.0, 2.0, -3.0], 0, 1).unwrap();
        assert!(v.is_nan());
        assert_eq!(mk, vec![false; 3]);
        // The same with source == target, and a negative self-loop.
        assert!(max_difference(4, &s, &d, &[1.0, 2.0, -3.0], 0, 0)
            .unwrap()
            .0
            .is_nan());
        assert!(max_difference(2, &[0, 1], &[1, 1], &[1.0, -0.5], 0, 1)
            .unwrap()
            .0
            .is_nan());
        // A zero cycle is feasible.
        let (v, _) = max_difference(4, &s, &d, &[1.0, 2.0, -2.0], 0, 1).unwrap();
        assert_eq!(v, 1.0);
    }

    #[test]
    fn tight_cycle_is_feasible_within_the_tolerance() {
        // A cyclogram cycle that closes exactly, up to the round-off of its angles.
        for (scale, slack) in [
            (1.0, -1e-13),
            (1.0, 1e-13),
            (360.0, -1e-13),
            (360.0, -5e-11),
        ] {
            let w = [120.0 / 360.0 * scale, 240.0 / 360.0 * scale, -scale + slack];
            let (v, mk) = max_difference(3, &[0, 1, 2], &[1, 2, 0], &w, 0, 2).unwrap();
            assert!((v - scale).abs() < 1e-9 * scale, "{scale} {slack}: {v}");
            assert_eq!(mk, vec![true, true, false]);
            let (v, _) = max_difference(3, &[0, 1, 2], &[1, 2, 0], &w, 2, 1).unwrap();
            assert!((v - (w[2] + w[0])).abs() < 1e-9 * scale);
        }
        // Well below -n·eps: infeasible.
        let w = [1.0, 2.0, -3.0 - 1e-6];
        assert!(max_difference(3, &[0, 1, 2], &[1, 2, 0], &w, 0, 2)
            .unwrap()
            .0
            .is_nan());
        let w = [1.0, 2.0, -3.0 - 4.0 * 3.0 * DIFFERENCE_RTOL * 4.0 * 3.0];
        assert!(max_difference(3, &[0, 1, 2], &[1, 2, 0], &w, 0, 2)
            .unwrap()
            .0
            .is_nan());
    }

    #[test]
    fn long_negative_cycle_is_found() {
        // A ring of 200 nodes whose weights sum to -1 (found through predecessors
        // long before the pass cap), plus a chord 5 -> 150 of weight 150 (the
        // cycle it closes weighs 150 - 145 >= 0).
        let n = 200i64;
        let s: Vec<i64> = (0..n).chain([5]).collect();
        let d: Vec<i64> = (1..n).chain([0, 150]).collect();
        let mut w = vec![1.0; n as usize + 1];
        w[n as usize] = 150.0;
        w[n as usize - 1] = -(n as f64);
        assert!(max_difference(n, &s, &d, &w, 3, 7).unwrap().0.is_nan());
        // Ring of weight 0: feasible, and the chord is never the shorter way.
        w[n as usize - 1] = -(n as f64) + 1.0;
        let (v, mk) = max_difference(n, &s, &d, &w, 3, 7).unwrap();
        assert_eq!(v, 4.0);
        assert_eq!(mk.iter().filter(|&&b| b).count(), 4);
        assert_eq!(max_difference(n, &s, &d, &w, 3, 160).unwrap().0, 157.0);
        // Going round: 160 -> 199 -> 0 -> 7.
        assert_eq!(
            max_difference(n, &s, &d, &w, 160, 7).unwrap().0,
            39.0 - 199.0 + 7.0
        );
        // A cheaper chord closes a negative cycle: infeasible.
        w[n as usize] = 144.0;
        assert!(max_difference(n, &s, &d, &w, 3, 7).unwrap().0.is_nan());
    }

    #[test]
    fn difference_batch_threads_agree_bit_for_bit() {
        // Large enough for the threaded path (rows · (arcs + nodes) · 4 > 2^16).
        let (n, m, rows) = (20usize, 60usize, 400usize);
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let s: Vec<i64> = (0..m).map(|_| (next() % n as u64) as i64).collect();
        let d: Vec<i64> = (0..m).map(|_| (next() % n as u64) as i64).collect();
        let w: Vec<f64> = (0..rows * m)
            .map(|_| (next() % 4001) as f64 / 100.0 - 5.0)
            .collect();
        assert!(rows * (m + n) * DIFFERENCE_PASSES >= PARALLEL_MIN_WORK);
        let one = max_difference_batch(n as i64, &s, &d, &w, (rows, m), 0, 7, Some(1)).unwrap();
        let two = max_difference_batch(n as i64, &s, &d, &w, (rows, m), 0, 7, Some(2)).unwrap();
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&one.0), bits(&two.0));
        assert_eq!(one.1, two.1);
        let kinds = |f: fn(&f64) -> bool| one.0.iter().filter(|v| f(v)).count();
        // The draw mixes feasible and infeasible rows.
        assert!(kinds(|v| v.is_nan()) > 0 && kinds(|v| v.is_finite()) > 0);
        for r in (0..rows).step_by(37) {
            let single = max_difference(n as i64, &s, &d, &w[r * m..(r + 1) * m], 0, 7).unwrap();
            assert_eq!(single.0.to_bits(), one.0[r].to_bits());
            assert_eq!(&single.1[..], &one.1[r * m..(r + 1) * m]);
        }
    }

    #[test]
    fn difference_bad_input_is_an_error_not_a_panic() {
        let (s, d, w) = ([0i64, 1], [1i64, 2], [1.0, 2.0]);
        let msg = |r: Result<(f64, Vec<bool>), ScheduleError>| r.unwrap_err().to_string();
        assert_eq!(
            msg(max_difference(0, &[], &[], &[], 0, 0)),
            format!("n_nodes = 0 is invalid: it must be an integer between 1 and {MAX_SIZE}")
        );
        assert!(msg(max_difference(-3, &s, &d, &w, 0, 1)).starts_with("n_nodes = -3"));
        assert_eq!(
            msg(max_difference(3, &s, &[1, 3], &w, 0, 1)),
            "dst[1] = 3 is not a node index; valid indices are 0 to 2 (n_nodes = 3)"
        );
        assert!(msg(max_difference(3, &[-1, 0], &d, &w, 0, 1)).starts_with("src[0] = -1"));
        assert_eq!(
            msg(max_difference(3, &s, &d, &w, 3, 1)),
            "source = 3 is not a node index; valid indices are 0 to 2 (n_nodes = 3)"
        );
        assert!(msg(max_difference(3, &s, &d, &w, 0, -1)).starts_with("target = -1"));
        assert!(msg(max_difference(3, &s, &d[..1], &w, 0, 1)).contains("same length"));
        assert!(msg(max_difference(3, &s, &d, &w[..1], 0, 1)).contains("got 1"));
        assert!(
            msg(max_difference(3, &s, &d, &[1.0, f64::NAN], 0, 1)).starts_with("weights[1] = NaN")
        );
        assert!(msg(max_difference(3, &s, &d, &[f64::INFINITY, 1.0], 0, 1))
            .starts_with("weights[0] = inf"));
        assert!(
            msg(max_difference(3, &s, &d, &[1e300, 1.0], 0, 1)).starts_with("weights[0] = 1e300")
        );
        let batch = |w: &[f64], shape, threads| {
            max_difference_batch(3, &s, &d, w, shape, 0, 1, threads)
                .unwrap_err()
                .to_string()
        };
        let mut rows = vec![1.0; 6];
        rows[5] = f64::NEG_INFINITY;
        assert!(batch(&rows, (3, 2), None).starts_with("weights[2, 1] = -inf"));
        assert!(batch(&[f64::NAN, 1.0], (1, 2), None).starts_with("weights[0, 0] = NaN"));
        assert!(batch(&[1.0; 6], (2, 3), None).contains("got 3"));
        assert!(batch(&[], (0, 5), None).contains("got 5"));
        assert!(batch(&[1.0; 5], (2, 2), None).contains("weights"));
        assert!(batch(&[1.0; 4], (2, 2), Some(0)).contains("n_threads"));
        assert!(max_difference_batch(3, &s, &d, &[], (0, 2), 0, 5, None).is_err());
        assert_eq!(
            max_difference_batch(3, &s, &d, &[], (0, 2), 0, 2, Some(2)).unwrap(),
            (vec![], vec![])
        );
        assert_eq!(
            max_difference_batch(2, &[], &[], &[], (3, 0), 0, 1, Some(2)).unwrap(),
            (vec![f64::INFINITY; 3], vec![])
        );
    }
}
