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
    #[error("{field}{location} = {value} is not a finite number; {what}")]
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

/// Weight vectors evaluated together in the batch kernel: one block of this many
/// rows is laid out lane-by-lane so the inner max runs as SIMD, and a block of
/// `E` arcs × 8 lanes × 8 bytes stays in cache for the graphs this is meant for.
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
    let check = |field: &'static str, idx: &[i64]| -> Result<Vec<u32>, ScheduleError> {
        idx.iter()
            .enumerate()
            .map(|(position, &value)| {
                if value < 0 || value as u64 >= n as u64 {
                    Err(ScheduleError::IndexOutOfRange {
                        field,
                        position,
                        value,
                        n_events: n,
                    })
                } else {
                    Ok(value as u32)
                }
            })
            .collect()
    };
    Ok((n, check("src", src)?, check("dst", dst)?))
}

/// Check that every value is finite; name the first one that is not.
pub(crate) fn check_finite(
    field: &'static str,
    values: &[f64],
    row_len: usize,
    what: &'static str,
) -> Result<(), ScheduleError> {
    if values.iter().all(|v| v.is_finite()) {
        return Ok(());
    }
    let (i, &value) = values
        .iter()
        .enumerate()
        .find(|(_, v)| !v.is_finite())
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
#[derive(Debug, Clone)]
pub struct EventGraph {
    n: usize,
    src: Vec<u32>,
    dst: Vec<u32>,
    /// `order[k]`: the event at topological position `k`.
    order: Vec<u32>,
    /// `pos[v]`: the topological position of event `v`.
    pos: Vec<u32>,
    /// Incoming arcs by topological position of their head; `other` = position of the tail.
    inc: Csr,
    /// Outgoing arcs by topological position of their tail; `other` = position of the head.
    out: Csr,
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
    /// a cycle) and lay the arcs out by topological position.
    pub fn new(n_events: i64, src: &[i64], dst: &[i64]) -> Result<Self, ScheduleError> {
        let (n, src, dst) = validate_arcs(n_events, src, dst)?;
        let order =
            topological_order(n, &src, &dst).map_err(|events| ScheduleError::Cycle { events })?;
        let mut pos = vec![0u32; n];
        for (k, &v) in order.iter().enumerate() {
            pos[v as usize] = k as u32;
        }
        let m = src.len();
        let inc = Csr::build(
            n,
            |e| pos[dst[e] as usize] as usize,
            |e| pos[src[e] as usize],
            m,
        );
        let out = Csr::build(
            n,
            |e| pos[src[e] as usize] as usize,
            |e| pos[dst[e] as usize],
            m,
        );
        Ok(EventGraph {
            n,
            src,
            dst,
            order,
            pos,
            inc,
            out,
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
        check_finite("weights", weights, m, "phase angles must be finite degrees")
    }

    /// Earliest times by topological position.
    fn forward(&self, w: &[f64], t: &mut [f64]) {
        for k in 0..self.n {
            let r = self.inc.range(k);
            let mut best = if r.is_empty() { 0.0 } else { f64::NEG_INFINITY };
            for (&s, &e) in self.inc.other[r.clone()].iter().zip(&self.inc.edge[r]) {
                let c = t[s as usize] + w[e as usize];
                if c > best {
                    best = c;
                }
            }
            t[k] = best;
        }
    }

    /// Latest times by topological position for a horizon.
    fn backward(&self, w: &[f64], horizon: f64, t: &mut [f64]) {
        for k in (0..self.n).rev() {
            let r = self.out.range(k);
            // Every event, not only the sinks, must occur by the horizon: with negative
            // (overlapping) arcs an inner event can be the last one.
            let mut best = horizon;
            for (&d, &e) in self.out.other[r.clone()].iter().zip(&self.out.edge[r]) {
                let c = t[d as usize] - w[e as usize];
                if c < best {
                    best = c;
                }
            }
            t[k] = best;
        }
    }

    fn to_event_order(&self, by_pos: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.n];
        for (k, &v) in self.order.iter().enumerate() {
            out[v as usize] = by_pos[k];
        }
        out
    }

    /// Earliest occurrence angle of every event for one weight vector (E,) -> (V,).
    pub fn earliest(&self, weights: &[f64]) -> Result<Vec<f64>, ScheduleError> {
        self.check_weights(weights, 1)?;
        let mut t = vec![0.0; self.n];
        self.forward(weights, &mut t);
        Ok(self.to_event_order(&t))
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
        Ok(self.to_event_order(&t))
    }

    /// Earliest times for `rows` weight vectors stored row-major in `weights`
    /// (rows × E) -> (rows × V), row-major. Blocks of [`LANES`] rows run in
    /// parallel on the pool chosen by `n_threads`.
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
        self.check_weights(weights, rows)?;
        let threads = crate::parallel::resolve_threads(n_threads)?;
        check_memory(0, 0, rows.saturating_mul(n).saturating_mul(8))?;
        let mut out = vec![0.0; rows * n];
        if n == 0 || rows == 0 {
            return Ok(out);
        }
        let block = |(b, chunk): (usize, &mut [f64])| {
            let r0 = b * LANES;
            let lanes = chunk.len() / n;
            // Weights of this block in incoming-arc order, lane-interleaved.
            let mut wblk = vec![[0.0f64; LANES]; m];
            for l in 0..lanes {
                let row = &weights[(r0 + l) * m..(r0 + l + 1) * m];
                for (slot, &e) in wblk.iter_mut().zip(&self.inc.edge) {
                    slot[l] = row[e as usize];
                }
            }
            let mut t = vec![[0.0f64; LANES]; n];
            for k in 0..n {
                let r = self.inc.range(k);
                let mut best = if r.is_empty() {
                    [0.0; LANES]
                } else {
                    [f64::NEG_INFINITY; LANES]
                };
                for j in r {
                    let s = t[self.inc.other[j] as usize];
                    let wj = wblk[j];
                    for l in 0..LANES {
                        best[l] = best[l].max(s[l] + wj[l]);
                    }
                }
                t[k] = best;
            }
            for (k, &v) in self.order.iter().enumerate() {
                for l in 0..lanes {
                    chunk[l * n + v as usize] = t[k][l];
                }
            }
        };
        if threads == 1 || rows * m < PARALLEL_MIN_WORK {
            out.chunks_mut(LANES * n).enumerate().for_each(block);
        } else {
            crate::parallel::pool(threads)?
                .install(|| out.par_chunks_mut(LANES * n).enumerate().for_each(block));
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
            let ps = self.pos[self.src[e] as usize] as usize;
            let pd = self.pos[self.dst[e] as usize] as usize;
            total[e] = late[pd] - early[ps] - weights[e];
            free[e] = early[pd] - early[ps] - weights[e];
            critical[e] = total[e].abs() <= tolerance;
        }
        Ok(Analysis {
            earliest: self.to_event_order(&early),
            latest: self.to_event_order(&late),
            total_slack: total,
            free_slack: free,
            critical,
            horizon,
            tolerance,
        })
    }
}

/// One-shot longest path: analyse the structure and evaluate one weight vector.
pub fn longest_path(
    n_events: i64,
    src: &[i64],
    dst: &[i64],
    weights: &[f64],
) -> Result<Vec<f64>, ScheduleError> {
    EventGraph::new(n_events, src, dst)?.earliest(weights)
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
            let got = longest_path(n as i64, &s, &d, &w).unwrap();
            let want = reference(n, &s, &d, &w);
            for (g, r) in got.iter().zip(&want) {
                prop_assert!((g - r).abs() <= 1e-9 * (1.0 + r.abs()), "{g} vs {r}");
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
