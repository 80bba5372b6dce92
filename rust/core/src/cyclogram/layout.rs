//! An event network laid out by topological position, built in linear time.
//!
//! Events are renumbered once by their position in a topological order, and the
//! arcs are stored grouped by the position of one end (incoming arcs by their
//! head for the forward pass, outgoing arcs by their tail for the backward
//! pass), each entry holding the other end's position and the arc index side by
//! side. A pass over positions then reads the arcs and writes the times as two
//! sequential streams; only the times of the other ends and the weights are read
//! out of order.
//!
//! The build is O(V + E) with no comparison sort and no hash map: one counting
//! pass for the degrees, one stable counting-sort scatter for the outgoing arcs,
//! Kahn's algorithm over them (a cycle is detected there, when the queue runs
//! dry before every event is placed), then the two positional layouts.

use super::graph::topological_order;

/// Arcs grouped by the topological position of one end: group `k` is
/// `arcs[ptr[k]..ptr[k + 1]]`, each entry `[other end's position, arc index]`,
/// arcs in input order within a group.
#[derive(Debug, Clone)]
pub(super) struct ByPosition {
    pub(super) ptr: Vec<u32>,
    pub(super) arcs: Vec<[u32; 2]>,
}

impl ByPosition {
    #[inline]
    pub(super) fn range(&self, k: usize) -> std::ops::Range<usize> {
        self.ptr[k] as usize..self.ptr[k + 1] as usize
    }
}

/// The topological layout of an event network.
#[derive(Debug, Clone)]
pub(super) struct Layout {
    /// `order[k]`: the event at topological position `k`.
    pub(super) order: Vec<u32>,
    /// `pos[v]`: the topological position of event `v`.
    pub(super) pos: Vec<u32>,
    /// Incoming arcs grouped by their head's position; `[tail position, arc]`.
    pub(super) inc: ByPosition,
    /// Outgoing arcs grouped by their tail's position; `[head position, arc]`.
    pub(super) out: ByPosition,
}

/// Prefix sums of `counts` (length n) as group offsets (length n + 1). The arcs
/// number at most `MAX_SIZE` < 2^32, so the sums fit in `u32`.
fn offsets(n: usize, count: impl Fn(usize) -> u32) -> Vec<u32> {
    let mut ptr = Vec::with_capacity(n + 1);
    let mut acc = 0u32;
    ptr.push(0);
    for k in 0..n {
        acc += count(k);
        ptr.push(acc);
    }
    ptr
}

/// Lay out `n` events and the arcs `src[e] -> dst[e]` (indices already checked)
/// by topological position, or return one cycle (events in arc order, starting at
/// the smallest, as [`topological_order`] reports it).
///
/// The topological order is Kahn's with a FIFO queue seeded with the events
/// without incoming arcs in increasing index and outgoing arcs taken in input
/// order: the order `EventGraph` has always reported.
pub(super) fn layout(n: usize, src: &[u32], dst: &[u32]) -> Result<Layout, Vec<usize>> {
    let m = src.len();
    // Degrees, one pass.
    let mut outdeg = vec![0u32; n];
    let mut indeg = vec![0u32; n];
    for (&a, &b) in src.iter().zip(dst) {
        outdeg[a as usize] += 1;
        indeg[b as usize] += 1;
    }
    // Outgoing arcs by tail event (stable counting sort): [head event, arc].
    let eptr = offsets(n, |v| outdeg[v]);
    let mut fill: Vec<u32> = eptr[..n].to_vec();
    let mut by_tail = vec![[0u32; 2]; m];
    for (e, (&a, &b)) in src.iter().zip(dst).enumerate() {
        let f = &mut fill[a as usize];
        by_tail[*f as usize] = [b, e as u32];
        *f += 1;
    }
    drop(fill);
    // Kahn's algorithm; `left` counts each event's unplaced predecessors.
    let mut left = indeg.clone();
    let mut order: Vec<u32> = Vec::with_capacity(n);
    order.extend((0..n as u32).filter(|&v| left[v as usize] == 0));
    let mut next = 0;
    while next < order.len() {
        let v = order[next] as usize;
        next += 1;
        for &[h, _] in &by_tail[eptr[v] as usize..eptr[v + 1] as usize] {
            let l = &mut left[h as usize];
            *l -= 1;
            if *l == 0 {
                order.push(h);
            }
        }
    }
    if order.len() < n {
        // Cold path: name one cycle the way every cyclogram kernel does.
        return Err(topological_order(n, src, dst).err().unwrap_or_default());
    }
    drop(left);
    let mut pos = vec![0u32; n];
    for (k, &v) in order.iter().enumerate() {
        pos[v as usize] = k as u32;
    }
    // Outgoing arcs by tail position: the groups of `by_tail` copied in
    // topological order (sequential writes), heads renumbered.
    let optr = offsets(n, |k| outdeg[order[k] as usize]);
    let mut out_arcs = Vec::with_capacity(m);
    for &v in &order {
        let v = v as usize;
        out_arcs.extend(
            by_tail[eptr[v] as usize..eptr[v + 1] as usize]
                .iter()
                .map(|&[h, e]| [pos[h as usize], e]),
        );
    }
    drop(by_tail);
    // Incoming arcs by head position (stable counting sort over the arcs in input
    // order): [tail position, arc].
    let iptr = offsets(n, |k| indeg[order[k] as usize]);
    let mut fill: Vec<u32> = iptr[..n].to_vec();
    let mut in_arcs = vec![[0u32; 2]; m];
    for (e, (&a, &b)) in src.iter().zip(dst).enumerate() {
        let f = &mut fill[pos[b as usize] as usize];
        in_arcs[*f as usize] = [pos[a as usize], e as u32];
        *f += 1;
    }
    Ok(Layout {
        order,
        pos,
        inc: ByPosition {
            ptr: iptr,
            arcs: in_arcs,
        },
        out: ByPosition {
            ptr: optr,
            arcs: out_arcs,
        },
    })
}
