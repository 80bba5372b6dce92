//! What every cyclogram kernel shares: the domain's error, the checks of arcs
//! and values, the compressed adjacency and the topological order.

use crate::input::InvalidInput;

/// Errors of the cyclogram domain (event graphs, difference constraints, cycle ratios,
/// speed limits).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CyclogramError {
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
    #[error("{field}[{position}] = {} is invalid: {what}", crate::num_text::Num(*value))]
    OutOfDomain {
        field: &'static str,
        position: usize,
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
    Input(#[from] InvalidInput),
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

crate::input::wraps_invalid_input!(CyclogramError);

impl CyclogramError {
    /// A scalar outside its valid values, said the cyclogram's way:
    /// "`field` = `value` is invalid: `what`".
    pub fn bad_scalar(field: &'static str, value: f64, what: &str) -> Self {
        InvalidInput::bad_value(field, value, format!("is invalid: {what}")).into()
    }
}

/// Upper bound of the working memory per event and per arc of any schedule kernel
/// (index arrays, adjacency, times, Howard's policy state), in bytes.
const BYTES_PER_EVENT: usize = 96;
const BYTES_PER_ARC: usize = 48;

/// Refuse sizes whose working memory cannot be allocated, instead of letting the
/// allocator abort the process (an abort cannot be caught at the Python boundary).
pub(crate) fn check_memory(n: usize, m: usize, extra_bytes: usize) -> Result<(), CyclogramError> {
    let bytes = n
        .saturating_mul(BYTES_PER_EVENT)
        .saturating_add(m.saturating_mul(BYTES_PER_ARC))
        .saturating_add(extra_bytes);
    if crate::memory::can_allocate(bytes) {
        return Ok(());
    }
    Err(CyclogramError::TooLarge {
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
pub(super) const LANES: usize = 8;

/// Below this many arc evaluations (rows × arcs) a batch runs on the calling
/// thread: a pool hand-off costs more than the work.
pub(super) const PARALLEL_MIN_WORK: usize = 1 << 16;

/// Check `n_events`, the arc lists and return them as `u32`.
pub(crate) fn validate_arcs(
    n_events: i64,
    src: &[i64],
    dst: &[i64],
) -> Result<(usize, Vec<u32>, Vec<u32>), CyclogramError> {
    if n_events < 0 || n_events as u64 > MAX_SIZE as u64 {
        return Err(CyclogramError::BadEventCount {
            value: n_events,
            max: MAX_SIZE,
        });
    }
    let n = n_events as usize;
    check_memory(n, src.len(), 0)?;
    if src.len() != dst.len() {
        return Err(CyclogramError::LengthMismatch {
            src: src.len(),
            dst: dst.len(),
        });
    }
    if src.len() > MAX_SIZE {
        return Err(CyclogramError::WeightLength {
            field: "src",
            expected: MAX_SIZE,
            got: src.len(),
        });
    }
    // One branch-free pass for the range (it vectorises), a plain cast, and a
    // search for the culprit only when the range is wrong.
    let check = |field: &'static str, idx: &[i64]| -> Result<Vec<u32>, CyclogramError> {
        let (lo, hi) = idx
            .iter()
            .fold((0i64, -1i64), |(lo, hi), &v| (lo.min(v), hi.max(v)));
        if lo < 0 || (hi >= 0 && hi as u64 >= n as u64) {
            let (position, &value) = idx
                .iter()
                .enumerate()
                .find(|(_, &v)| v < 0 || v as u64 >= n as u64)
                .unwrap_or((0, &lo));
            return Err(CyclogramError::IndexOutOfRange {
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
) -> Result<(), CyclogramError> {
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
    Err(CyclogramError::NonFinite {
        field,
        location,
        value,
        what,
    })
}

/// Compressed adjacency: for vertex `k`, entries `ptr[k]..ptr[k + 1]`.
#[derive(Debug, Clone)]
pub(super) struct Csr {
    pub(super) ptr: Vec<usize>,
    pub(super) other: Vec<u32>,
    pub(super) edge: Vec<u32>,
}

impl Csr {
    /// Group arcs by `key[e]` (stable: arcs keep their input order within a group),
    /// recording `other[e]` and the arc index.
    pub(super) fn build(
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
    pub(super) fn range(&self, k: usize) -> std::ops::Range<usize> {
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
