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

use std::sync::OnceLock;

use rayon::prelude::*;

/// Errors of the schedule domain (event graphs, cycle ratios, speed limits).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ScheduleError {
    #[error("n_events = {value} is invalid: it must be an integer between 0 and {max}")]
    BadEventCount { value: i64, max: usize },
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

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

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
}
