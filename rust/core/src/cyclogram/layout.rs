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
//! dry before every event is placed), then the incoming arcs by position from
//! the outgoing ones read in order. The outgoing arcs by position (backward pass
//! only) are built on first use, by one more counting sort.
//!
//! Order within a group does not change a result: the forward pass takes the
//! maximum of candidates `t + w` that are never NaN (finite weights) and never
//! −0.0 (a time starts at +0.0 or −∞, and a sum is −0.0 only if both terms
//! are), so any order gives the same bits; the backward pass, where a horizon
//! of −0.0 could make the order matter, keeps the input order.

use super::graph::topological_order;

/// Arcs grouped by the topological position of one end: group `k` is
/// `arcs[ptr[k]..ptr[k + 1]]`, each entry `[other end's position, arc index]`.
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
    // Incoming arcs by head position (counting sort): `by_tail` read in order,
    // tails renumbered. Within a group the arcs are in order of their tail's
    // index, then input order.
    let iptr = offsets(n, |k| indeg[order[k] as usize]);
    let mut fill: Vec<u32> = iptr[..n].to_vec();
    let mut in_arcs = vec![[0u32; 2]; m];
    for (v, &p) in pos.iter().enumerate() {
        for &[h, e] in &by_tail[eptr[v] as usize..eptr[v + 1] as usize] {
            let f = &mut fill[pos[h as usize] as usize];
            in_arcs[*f as usize] = [p, e];
            *f += 1;
        }
    }
    Ok(Layout {
        order,
        pos,
        inc: ByPosition {
            ptr: iptr,
            arcs: in_arcs,
        },
    })
}

/// Outgoing arcs grouped by their tail's position (counting sort over the arcs
/// in input order): `[head position, arc]`, input order within a group.
pub(super) fn outgoing(n: usize, src: &[u32], dst: &[u32], pos: &[u32]) -> ByPosition {
    let mut count = vec![0u32; n];
    for &a in src {
        count[pos[a as usize] as usize] += 1;
    }
    let ptr = offsets(n, |k| count[k]);
    drop(count);
    let mut fill: Vec<u32> = ptr[..n].to_vec();
    let mut arcs = vec![[0u32; 2]; src.len()];
    for (e, (&a, &b)) in src.iter().zip(dst).enumerate() {
        let f = &mut fill[pos[a as usize] as usize];
        arcs[*f as usize] = [pos[b as usize], e as u32];
        *f += 1;
    }
    ByPosition { ptr, arcs }
}

/// Arcs at or above which the single-row forward pass reads the weights through
/// a [`Partition`]: 2^20 arcs are 8 MiB of weights, four times a core's L2, and
/// the gather by arc index turns into a cache and TLB miss per arc.
pub(super) const PARTITION_MIN_ARCS: usize = 1 << 20;

/// Incoming arcs per block of a [`Partition`] at most (1 MiB of weights, half a
/// core's L2), unless one event alone has more.
pub(super) const BLOCK_ARCS: usize = 1 << 17;

/// A two-pass permutation of a weight vector into the order of [`Layout::inc`],
/// for graphs too large for the caches. The positions are cut into blocks whose
/// incoming arcs number at most [`BLOCK_ARCS`]. Pass 1 streams the weights in
/// input order into one bucket per block (a few hundred sequential write streams
/// at most); pass 2, block by block inside the forward pass, scatters a bucket
/// into a block-sized buffer that stays in L2. Either pass reads and writes
/// memory in order except within a block.
#[derive(Debug, Clone)]
pub(super) struct Partition {
    /// Block `b` is positions `start[b]..start[b + 1]` (B + 1 entries).
    pub(super) start: Vec<u32>,
    /// Pass 1: where arc `e`'s weight goes in the bucketed buffer (E,). Bucket `b`
    /// occupies the same range as block `b`'s incoming arcs in `inc`, arcs in
    /// input order within it.
    pub(super) bucket: Vec<u32>,
    /// Pass 2: the slot in `inc`, relative to its block's first, of each entry of
    /// the bucketed buffer (E,).
    pub(super) local: Vec<u32>,
    /// The largest number of incoming arcs of a block.
    pub(super) widest: usize,
}

impl Partition {
    /// Blocks of at most `block_arcs` incoming arcs ([`BLOCK_ARCS`] outside tests).
    pub(super) fn new(lay: &Layout, dst: &[u32], block_arcs: usize) -> Partition {
        let (n, m) = (lay.order.len(), dst.len());
        let inc = &lay.inc;
        // Blocks: greedy cuts at event boundaries.
        let mut start = vec![0u32];
        let mut block_of = vec![0u32; n];
        let mut widest = 0;
        let mut k = 0;
        while k < n {
            let j0 = inc.ptr[k] as usize;
            let mut k1 = k + 1;
            while k1 < n && inc.ptr[k1 + 1] as usize - j0 <= block_arcs {
                k1 += 1;
            }
            widest = widest.max(inc.ptr[k1] as usize - j0);
            block_of[k..k1].fill(start.len() as u32 - 1);
            start.push(k1 as u32);
            k = k1;
        }
        // The slot of each arc in `inc`.
        let mut slot = vec![0u32; m];
        for (j, &[_, e]) in inc.arcs.iter().enumerate() {
            slot[e as usize] = j as u32;
        }
        let mut fill: Vec<u32> = start[..start.len() - 1]
            .iter()
            .map(|&k| inc.ptr[k as usize])
            .collect();
        let mut bucket = vec![0u32; m];
        let mut local = vec![0u32; m];
        for (e, (&d, &j)) in dst.iter().zip(&slot).enumerate() {
            let b = block_of[lay.pos[d as usize] as usize] as usize;
            let i = fill[b];
            fill[b] += 1;
            bucket[e] = i;
            local[i as usize] = j - inc.ptr[start[b] as usize];
        }
        Partition {
            start,
            bucket,
            local,
            widest,
        }
    }
}
