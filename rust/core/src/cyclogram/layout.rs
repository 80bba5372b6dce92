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
//! pass for the in-degrees, a stable grouping of the arcs by tail event, Kahn's
//! algorithm over them (a cycle is detected there, when the queue runs dry
//! before every event is placed; in a large graph the events a few places ahead
//! in the queue are prefetched), then a stable grouping of the arcs, read in input order, by
//! their head's position. From [`RADIX_MIN_ARCS`] arcs each grouping is a radix
//! partition in two cache-sized passes (at most 256 sequential streams into
//! buckets of key ranges, then each bucket into its groups in L2) instead of one
//! scatter over the whole output, and from [`PARTITION_MIN_ARCS`] the second
//! one's two passes are kept as the weights' [`Partition`], so a large graph's
//! first solve costs no more than the next. The outgoing arcs by position
//! (backward pass only) are built on first use, by one more counting sort.
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

/// Arcs from which the build groups them in two cache-sized passes (a radix
/// partition) rather than one scatter over the whole output: 2^20 arcs are
/// 8 MiB of `[u32; 2]` entries, four times a core's L2 (below, the one scatter
/// stays in the L3 and measured as fast).
pub(super) const RADIX_MIN_ARCS: usize = 1 << 20;

/// Coarse buckets of a radix partition at most 2^6: the first pass writes two
/// sequential streams per bucket (keys and payloads), 128 in all, as many as L1
/// and the TLB keep; a bucket (~64 Ki arcs for E = 4V) is sorted in L2. The
/// buckets by head position are the weights' [`Partition`] blocks too, whose
/// first pass every solve repeats.
const RADIX_BITS: u32 = 6;

/// The shift of a radix partition of `n` keys into at most `2^bits` buckets:
/// keys `k >> shift` share a bucket.
fn radix_shift(n: usize, bits: u32) -> u32 {
    (usize::BITS - n.leading_zeros()).saturating_sub(bits)
}

/// A hint that `x[i]` will be read soon (a prefetch into every cache level):
/// no effect on any result, nothing outside x86-64 or past the slice's end.
#[derive(Clone, Copy)]
pub(super) struct Prefetch {
    #[cfg(target_arch = "x86_64")]
    sse: Option<pulp::core_arch::x86::Sse>,
}

impl Prefetch {
    pub(super) fn new() -> Prefetch {
        Prefetch {
            #[cfg(target_arch = "x86_64")]
            sse: pulp::core_arch::x86::Sse::try_new(),
        }
    }

    #[inline(always)]
    pub(super) fn at<T>(self, x: &[T], i: usize) {
        #[cfg(target_arch = "x86_64")]
        if let (Some(sse), Some(r)) = (self.sse, x.get(i)) {
            use std::arch::x86_64::_MM_HINT_T0;
            sse._mm_prefetch::<_MM_HINT_T0>((r as *const T).cast());
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = (x, i);
    }
}

/// The two factors of a radix partition's permutation, written when asked:
/// `bucket[e]`, where item `e` went in the first pass, and `local[i]`, the slot
/// (relative to its bucket's first) that entry `i` of the first pass went to.
struct Factors<'a> {
    bucket: &'a mut [u32],
    local: &'a mut [u32],
}

/// Scratch reused by the groupings of one build: the first radix pass's keys
/// and payloads, and a spent output. Reusing them spares fresh pages' faults (a
/// 4e6-arc build touches ~100 MB less); keys and payloads apart keep each
/// buffer of a 4e6-arc build under 32 MiB, which glibc's allocator recycles
/// from call to call instead of mapping (and faulting) afresh.
struct Scratch<T> {
    keys: Vec<u32>,
    tmp: Vec<T>,
    out: Vec<T>,
}

/// Stable grouping of `m` items by key: item `e` (key `k < n`, payload `x` from
/// `item(e)`) goes to the next free slot of group `k`, so within a group the
/// items keep their input order. Returns the group offsets (n + 1; `ptr` when
/// given, else counted) and the grouped payloads.
///
/// With `shift = None` one scatter over the whole output; with `Some(s)` two
/// passes: the items in input order into the buckets of keys `k >> s` (at most
/// 2^[`RADIX_BITS`] buckets), then each bucket into its groups (a
/// range of the output that fits in L2; the bucket's counts are taken there,
/// in cache). Both give the same output.
fn group<T: Copy + Default>(
    n: usize,
    m: usize,
    item: impl Fn(usize) -> (u32, T),
    shift: Option<u32>,
    ptr: Option<Vec<u32>>,
    factors: Option<Factors<'_>>,
    scratch: &mut Scratch<T>,
) -> (Vec<u32>, Vec<T>) {
    let mut out = std::mem::take(&mut scratch.out);
    if out.len() != m {
        out = vec![T::default(); m];
    }
    let Some(s) = shift else {
        let ptr = ptr.unwrap_or_else(|| {
            let mut count = vec![0u32; n];
            for e in 0..m {
                count[item(e).0 as usize] += 1;
            }
            offsets(n, |k| count[k])
        });
        let mut fill: Vec<u32> = ptr[..n].to_vec();
        for e in 0..m {
            let (k, x) = item(e);
            let f = &mut fill[k as usize];
            out[*f as usize] = x;
            *f += 1;
        }
        return (ptr, out);
    };
    let buckets = n.div_ceil(1 << s);
    // Each bucket's first item: from the groups' offsets, or counted.
    let first: Vec<u32> = match &ptr {
        Some(p) => (0..=buckets).map(|b| p[(b << s).min(n)]).collect(),
        None => {
            let mut count = vec![0u32; buckets];
            for e in 0..m {
                count[(item(e).0 >> s) as usize] += 1;
            }
            offsets(buckets, |b| count[b])
        }
    };
    let (keys, tmp) = (&mut scratch.keys, &mut scratch.tmp);
    if tmp.len() != m {
        (*keys, *tmp) = (vec![0u32; m], vec![T::default(); m]);
    }
    let mut fill: Vec<u32> = first[..buckets].to_vec();
    let mut factors = factors;
    for e in 0..m {
        let (k, x) = item(e);
        let f = &mut fill[(k >> s) as usize];
        (keys[*f as usize], tmp[*f as usize]) = (k, x);
        if let Some(fa) = factors.as_mut() {
            fa.bucket[e] = *f;
        }
        *f += 1;
    }
    let counted = ptr.is_none();
    let mut ptr = ptr.unwrap_or_else(|| vec![0u32; n + 1]);
    let mut fill = vec![0u32; 1 << s];
    for b in 0..buckets {
        let (k0, k1) = (b << s, ((b + 1) << s).min(n));
        let (i0, i1) = (first[b] as usize, first[b + 1] as usize);
        let (items, keys) = (&tmp[i0..i1], &keys[i0..i1]);
        let fill = &mut fill[..k1 - k0];
        if counted {
            // Offsets unknown: this bucket's counts, in cache.
            fill.fill(0);
            for &k in keys {
                fill[k as usize - k0] += 1;
            }
            let mut acc = i0 as u32;
            for (p, f) in ptr[k0..k1].iter_mut().zip(fill.iter_mut()) {
                let c = *f;
                (*p, *f) = (acc, acc);
                acc += c;
            }
        } else {
            fill.copy_from_slice(&ptr[k0..k1]);
        }
        for (i, (&k, &x)) in keys.iter().zip(items).enumerate() {
            let f = &mut fill[k as usize - k0];
            out[*f as usize] = x;
            if let Some(fa) = factors.as_mut() {
                fa.local[i0 + i] = *f - i0 as u32;
            }
            *f += 1;
        }
    }
    ptr[n] = m as u32;
    (ptr, out)
}

/// How [`layout`] groups the arcs (tests choose; [`Plan::for_size`] otherwise).
#[derive(Debug, Clone, Copy)]
pub(super) struct Plan {
    /// Radix shift of the grouping by tail event, or one scatter.
    pub(super) tail_shift: Option<u32>,
    /// Radix shift of the grouping by head position, or one scatter.
    pub(super) head_shift: Option<u32>,
    /// Whether to keep the weights' [`Partition`] (blocks of `1 << head_shift`
    /// positions); needs `head_shift`.
    pub(super) partition: bool,
}

impl Plan {
    /// The plan of a graph of `n` events and `m` arcs: radix grouping from
    /// [`RADIX_MIN_ARCS`], the weights' partition from [`PARTITION_MIN_ARCS`].
    pub(super) fn for_size(n: usize, m: usize) -> Plan {
        let radix = m >= RADIX_MIN_ARCS;
        Plan {
            tail_shift: radix.then(|| radix_shift(n, RADIX_BITS)),
            head_shift: radix.then(|| radix_shift(n, RADIX_BITS)),
            partition: radix && m >= PARTITION_MIN_ARCS,
        }
    }
}

/// Lay out `n` events and the arcs `src[e] -> dst[e]` (indices already checked)
/// by topological position, or return one cycle (events in arc order, starting at
/// the smallest, as [`topological_order`] reports it). With `plan.partition`,
/// also the weights' [`Partition`], a by-product of the grouping by head.
///
/// The topological order is Kahn's with a FIFO queue seeded with the events
/// without incoming arcs in increasing index and outgoing arcs taken in input
/// order: the order `EventGraph` has always reported.
pub(super) fn layout(
    n: usize,
    src: &[u32],
    dst: &[u32],
    plan: Plan,
) -> Result<(Layout, Option<Partition>), Vec<usize>> {
    let m = src.len();
    // In-degrees, one pass (the out-degrees are counted by the grouping).
    let mut indeg = vec![0u32; n];
    for &b in dst {
        indeg[b as usize] += 1;
    }
    // Outgoing arcs by tail event (stable): [head event, arc].
    let mut scratch = Scratch {
        keys: Vec::new(),
        tmp: Vec::new(),
        out: Vec::new(),
    };
    let (eptr, by_tail) = group(
        n,
        m,
        |e| (src[e], [dst[e], e as u32]),
        plan.tail_shift,
        None,
        None,
        &mut scratch,
    );
    // Kahn's algorithm; `left` counts each event's unplaced predecessors. The
    // events a few places ahead in the queue have their arcs and their heads'
    // counts prefetched (the queue is usually far ahead of the walk).
    let pf = plan.tail_shift.map(|_| Prefetch::new());
    let mut left = indeg.clone();
    let mut order: Vec<u32> = Vec::with_capacity(n);
    order.extend((0..n as u32).filter(|&v| left[v as usize] == 0));
    let mut next = 0;
    while next < order.len() {
        if let Some(pf) = pf {
            if let Some(&u) = order.get(next + 16) {
                pf.at(&eptr, u as usize);
            }
            if let Some(&u) = order.get(next + 8) {
                pf.at(&by_tail, eptr[u as usize] as usize);
            }
            if let Some(&u) = order.get(next + 4) {
                let u = u as usize;
                for &[h, _] in &by_tail[eptr[u] as usize..eptr[u + 1] as usize] {
                    pf.at(&left, h as usize);
                }
            }
        }
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
    drop((left, eptr));
    scratch.out = by_tail;
    let mut pos = vec![0u32; n];
    for (k, &v) in order.iter().enumerate() {
        pos[v as usize] = k as u32;
    }
    // Incoming arcs by head position, stable over the arcs in input order (so in
    // input order within a group), tails renumbered.
    let iptr = offsets(n, |k| indeg[order[k] as usize]);
    drop(indeg);
    let item = |e: usize| (pos[dst[e] as usize], [pos[src[e] as usize], e as u32]);
    let (iptr, in_arcs, part) = match plan.head_shift.filter(|_| plan.partition) {
        Some(s) => {
            let (mut bucket, mut local) = (vec![0u32; m], vec![0u32; m]);
            let factors = Factors {
                bucket: &mut bucket,
                local: &mut local,
            };
            let (iptr, arcs) = group(n, m, item, Some(s), Some(iptr), Some(factors), &mut scratch);
            let start: Vec<u32> = (0..n.div_ceil(1 << s).max(1))
                .map(|b| (b << s) as u32)
                .chain([n as u32])
                .collect();
            let widest = start
                .windows(2)
                .map(|w| (iptr[w[1] as usize] - iptr[w[0] as usize]) as usize)
                .max()
                .unwrap_or(0);
            let part = Partition {
                start,
                bucket,
                local,
                widest,
            };
            (iptr, arcs, Some(part))
        }
        None => {
            let (iptr, arcs) = group(n, m, item, plan.head_shift, Some(iptr), None, &mut scratch);
            (iptr, arcs, None)
        }
    };
    Ok((
        Layout {
            order,
            pos,
            inc: ByPosition {
                ptr: iptr,
                arcs: in_arcs,
            },
        },
        part,
    ))
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

/// A two-pass permutation of a weight vector into the order of [`Layout::inc`],
/// for graphs too large for the caches. The positions are cut into blocks (the
/// radix buckets of the build's grouping by head position: `1 << shift`
/// positions each, about 64 Ki arcs for E = 4V; `Partition::new` cuts blocks
/// of a given number of arcs for the tests). Pass 1 streams the weights in
/// input order into one bucket per block (at most 64 sequential write streams);
/// pass 2, block by block inside the forward pass, scatters a bucket
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

#[cfg(test)]
impl Partition {
    /// Blocks of at most `block_arcs` incoming arcs (unless one event alone has
    /// more): the tests' partitions of any block size.
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
