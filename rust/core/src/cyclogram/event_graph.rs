//! Longest paths on a network analysed once: earliest and latest event times,
//! slack, critical arcs, for one weight vector or a batch.

use std::sync::OnceLock;

use rayon::prelude::*;

use super::graph::{
    check_finite, check_memory, topological_order, validate_arcs, CyclogramError, LANES,
    MAX_ABS_VALUE, PARALLEL_MIN_WORK,
};
use super::layout::{layout, outgoing, ByPosition, Layout, Partition, Plan};
use crate::input::InvalidInput;
use crate::tile::{transpose, TILE};

// The batch kernel's lanes are the shared tile's side.
const _: () = assert!(LANES == TILE);

/// The structure of an event network, analysed once and reused for any number of
/// weight vectors.
///
/// Inside, events are numbered by their topological position and the arcs are
/// stored by position ([`Layout`]): the forward pass reads the incoming arcs of
/// position 0, 1, 2, … and writes the times in that order, the backward pass the
/// outgoing arcs from the last position down. Every public result is by the
/// caller's event and arc numbering.
#[derive(Debug)]
pub struct EventGraph {
    n: usize,
    src: Vec<u32>,
    dst: Vec<u32>,
    lay: Layout,
    /// Outgoing arcs by their tail's position: only the backward pass needs
    /// them, built on first use.
    out: OnceLock<ByPosition>,
    /// The weights' two-pass permutation of a graph of at least
    /// [`PARTITION_MIN_ARCS`](super::layout::PARTITION_MIN_ARCS) arcs, a
    /// by-product of the build (`None` below).
    part: Option<Partition>,
}

/// A copy of a lazily built part, built or not.
fn copy_lazy<T: Clone>(c: &OnceLock<T>) -> OnceLock<T> {
    let o = OnceLock::new();
    if let Some(x) = c.get() {
        let _ = o.set(x.clone());
    }
    o
}

impl Clone for EventGraph {
    fn clone(&self) -> Self {
        EventGraph {
            n: self.n,
            src: self.src.clone(),
            dst: self.dst.clone(),
            lay: self.lay.clone(),
            out: copy_lazy(&self.out),
            part: self.part.clone(),
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
    /// a cycle) and lay the arcs out by topological position, in O(V + E).
    pub fn new(n_events: i64, src: &[i64], dst: &[i64]) -> Result<Self, CyclogramError> {
        let (n, src, dst) = validate_arcs(n_events, src, dst)?;
        let plan = Plan::for_size(n, src.len());
        Self::with_plan(n, src, dst, plan)
    }

    /// [`new`](Self::new) from checked arcs with the build's grouping chosen
    /// (tests force the radix passes and the partition on small graphs).
    pub(super) fn with_plan(
        n: usize,
        src: Vec<u32>,
        dst: Vec<u32>,
        plan: Plan,
    ) -> Result<Self, CyclogramError> {
        let (lay, part) =
            layout(n, &src, &dst, plan).map_err(|events| CyclogramError::Cycle { events })?;
        Ok(EventGraph {
            n,
            src,
            dst,
            lay,
            out: OnceLock::new(),
            part,
        })
    }

    fn out(&self) -> &ByPosition {
        self.out
            .get_or_init(|| outgoing(self.n, &self.src, &self.dst, &self.lay.pos))
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
        &self.lay.order
    }

    /// The positional layout (tests).
    #[cfg(test)]
    pub(super) fn layout(&self) -> &Layout {
        &self.lay
    }

    /// The weights' partition, if the build made one (tests).
    #[cfg(test)]
    pub(super) fn partition(&self) -> Option<&Partition> {
        self.part.as_ref()
    }

    /// Topological position of each event (the inverse of
    /// [`topological_order`](Self::topological_order)).
    pub fn positions(&self) -> &[u32] {
        &self.lay.pos
    }

    fn check_weights(&self, weights: &[f64], rows: usize) -> Result<(), CyclogramError> {
        let m = self.n_arcs();
        if weights.len() != rows * m {
            return Err(CyclogramError::WeightLength {
                field: "weights",
                expected: m,
                got: if rows == 0 {
                    weights.len()
                } else {
                    weights.len() / rows.max(1)
                },
            });
        }
        check_finite("weights", weights, m, "phase angles [deg]")?;
        if self.part.is_none() {
            return Ok(());
        }
        // A large graph's pass: a bucketed copy of the weights and the times'
        // scratch, refused here rather than aborting the process in the allocator.
        check_memory(0, 0, (8 * m).saturating_add(24 * self.n))
    }

    /// Earliest times into `t` by event (V,), with `tpos` (V,) as scratch: the
    /// times by topological position, which the pass reads back.
    pub(super) fn forward_into(&self, w: &[f64], t: &mut [f64], tpos: &mut [f64]) {
        if let Some(part) = &self.part {
            return self.forward_through(part, w, t, tpos);
        }
        let inc = &self.lay.inc;
        for k in 0..self.n {
            let r = inc.range(k);
            let mut best = if r.is_empty() { 0.0 } else { f64::NEG_INFINITY };
            for &[s, e] in &inc.arcs[r] {
                // Finite inputs, no NaN: compare-and-select, not the NaN-aware max.
                let c = tpos[s as usize] + w[e as usize];
                best = if c > best { c } else { best };
            }
            tpos[k] = best;
        }
        self.by_event(tpos, t);
    }

    /// The forward pass with the weights permuted through `part`.
    pub(super) fn forward_through(
        &self,
        part: &Partition,
        w: &[f64],
        t: &mut [f64],
        tpos: &mut [f64],
    ) {
        let inc = &self.lay.inc;
        let mut bucketed = vec![0.0; w.len()];
        for (&x, &i) in w.iter().zip(&part.bucket) {
            bucketed[i as usize] = x;
        }
        let mut local = vec![0.0; part.widest];
        for b in part.start.windows(2) {
            let (k0, k1) = (b[0] as usize, b[1] as usize);
            let (j0, j1) = (inc.ptr[k0] as usize, inc.ptr[k1] as usize);
            for (&x, &q) in bucketed[j0..j1].iter().zip(&part.local[j0..j1]) {
                local[q as usize] = x;
            }
            for k in k0..k1 {
                let r = inc.range(k);
                let mut best = if r.is_empty() { 0.0 } else { f64::NEG_INFINITY };
                let lw = &local[r.start - j0..r.end - j0];
                for (&[s, _], &x) in inc.arcs[r].iter().zip(lw) {
                    let c = tpos[s as usize] + x;
                    best = if c > best { c } else { best };
                }
                tpos[k] = best;
            }
        }
        self.by_event(tpos, t);
    }

    /// Times by position -> by event, in one pass of its own: reading at random
    /// (independent loads the processor overlaps) and writing in order costs a
    /// fraction of a store miss per event inside the dependent pass.
    fn by_event(&self, tpos: &[f64], t: &mut [f64]) {
        for (x, &p) in t.iter_mut().zip(&self.lay.pos) {
            *x = tpos[p as usize];
        }
    }

    /// Earliest times, by event, into `t` (V,).
    pub(super) fn forward(&self, w: &[f64], t: &mut [f64]) {
        let mut tpos = vec![0.0; self.n];
        self.forward_into(w, t, &mut tpos);
    }

    /// Latest times, by event, for a horizon into `t` (V,).
    fn backward(&self, w: &[f64], horizon: f64, t: &mut [f64]) {
        let out = self.out();
        let mut tpos = vec![0.0; self.n];
        for k in (0..self.n).rev() {
            // Every event, not only the sinks, must occur by the horizon: with negative
            // (overlapping) arcs an inner event can be the last one.
            let mut best = horizon;
            for &[d, e] in &out.arcs[out.range(k)] {
                best = best.min(tpos[d as usize] - w[e as usize]);
            }
            tpos[k] = best;
        }
        self.by_event(&tpos, t);
    }

    /// Earliest occurrence angle of every event for one weight vector (E,) -> (V,).
    pub fn earliest(&self, weights: &[f64]) -> Result<Vec<f64>, CyclogramError> {
        self.check_weights(weights, 1)?;
        let mut t = vec![0.0; self.n];
        self.forward(weights, &mut t);
        Ok(t)
    }

    /// Latest occurrence angle of every event such that every event occurs at or
    /// before `horizon` and every arc keeps its phase angle.
    pub fn latest(&self, weights: &[f64], horizon: f64) -> Result<Vec<f64>, CyclogramError> {
        self.check_weights(weights, 1)?;
        if !horizon.is_finite() {
            return Err(CyclogramError::bad_scalar(
                "horizon",
                horizon,
                "the horizon must be a finite angle in degrees",
            ));
        }
        let mut t = vec![0.0; self.n];
        self.backward(weights, horizon, &mut t);
        Ok(t)
    }

    /// One block of up to [`LANES`] rows starting at row `r0` into `out` (lanes × V).
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
        // A short last block repeats its last row in the spare lanes (computed,
        // never written out), so every block runs the full-width kernel.
        let rows: [&[f64]; LANES] = std::array::from_fn(|l| {
            let r = r0 + l.min(lanes - 1);
            &weights[r * m..(r + 1) * m]
        });
        pulp::Arch::new().dispatch(Block {
            graph: self,
            rows,
            wblk,
            t,
            out,
        })
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
    ) -> Result<Vec<f64>, CyclogramError> {
        // The weights are checked by earliest_batch_into; the output must fit first.
        check_memory(0, 0, rows.saturating_mul(self.n).saturating_mul(8))?;
        let mut out = vec![0.0; rows * self.n];
        self.earliest_batch_into(weights, rows, row_len, &mut out, n_threads)?;
        Ok(out)
    }

    /// [`earliest_batch`](Self::earliest_batch) into the caller's `out` (rows × V,
    /// row-major), which is only written: a reused buffer skips the fresh pages'
    /// faults and zeroing.
    pub fn earliest_batch_into(
        &self,
        weights: &[f64],
        rows: usize,
        row_len: usize,
        out: &mut [f64],
        n_threads: Option<i64>,
    ) -> Result<(), CyclogramError> {
        let (n, m) = (self.n, self.n_arcs());
        if row_len != m {
            return Err(CyclogramError::WeightLength {
                field: "weights",
                expected: m,
                got: row_len,
            });
        }
        if weights.len() != rows * m {
            return Err(CyclogramError::WeightLength {
                field: "weights",
                expected: m,
                got: weights.len() / rows.max(1),
            });
        }
        if out.len() != rows * n {
            return Err(InvalidInput::Output {
                field: "out",
                want: format!("{rows} × {n} = {} times (rows × events)", rows * n),
                got: format!("{} values", out.len()),
            }
            .into());
        }
        let threads = crate::parallel::resolve_threads(n_threads)?;
        if n == 0 || rows == 0 {
            return check_finite("weights", weights, m, "phase angles [deg]");
        }
        let buffers = || (vec![[0.0f64; LANES]; m], vec![[0.0f64; LANES]; n]);
        let all_ok = if threads == 1 || rows * m < PARALLEL_MIN_WORK {
            let (mut wblk, mut t) = buffers();
            out.chunks_mut(LANES * n)
                .enumerate()
                .map(|(b, chunk)| {
                    crate::cancel::requested()
                        || self.batch_block(weights, b * LANES, chunk, &mut wblk, &mut t)
                })
                .fold(true, |a, b| a & b)
        } else {
            crate::parallel::pool(threads)?.install(|| {
                out.par_chunks_mut(LANES * n)
                    .enumerate()
                    .map_init(buffers, |(wblk, t), (b, chunk)| {
                        crate::cancel::requested()
                            || self.batch_block(weights, b * LANES, chunk, wblk, t)
                    })
                    .reduce(|| true, |a, b| a & b)
            })
        };
        if !all_ok {
            check_finite("weights", weights, m, "phase angles [deg]")?;
        }
        Ok(())
    }

    /// Earliest and latest times, total and free slack, and the critical arcs of
    /// one weight vector. `horizon = None` takes the latest earliest time (the
    /// schedule's own end), so the critical arcs are those of the longest path.
    pub fn analyze(
        &self,
        weights: &[f64],
        horizon: Option<f64>,
    ) -> Result<Analysis, CyclogramError> {
        self.check_weights(weights, 1)?;
        let mut early = vec![0.0; self.n];
        self.forward(weights, &mut early);
        let horizon = match horizon {
            Some(h) if !h.is_finite() => {
                return Err(CyclogramError::bad_scalar(
                    "horizon",
                    h,
                    "the horizon must be a finite angle in degrees",
                ))
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

/// The batch kernel for one block of [`LANES`] weight vectors, compiled once per
/// instruction set (AVX-512, AVX2 + FMA, or plain SSE2) and picked at run time.
/// Three passes:
/// 1. gather: the rows, read in 8 × 8 tiles (8 rows × 8 consecutive arcs) and
///    transposed in registers, go into `wblk` (each arc's lanes side by side, by
///    arc index: written in order, where scattering them to their positions in
///    the forward pass cost a store miss per arc); the finite check rides along;
/// 2. forward: the earliest times of all lanes into `t` (by topological
///    position), reading `wblk` through the arc indices of `inc` (loads off the
///    dependency chain, which the processor overlaps);
/// 3. scatter: `t`, gathered by event 8 rows at a time and transposed in 8 × 8
///    tiles again, into `out` (lanes × V, by event).
///
/// Lane by lane the arithmetic is [`EventGraph`]'s single-row `forward`: an
/// event's time starts at 0 (no incoming arc) or −∞, and each incoming arc in
/// `inc` order replaces it by `t[src] + w` when that is greater (compare and
/// select, so a NaN sum never wins and a tie keeps the earlier arc). Nothing is
/// reassociated, so every instruction set gives the single-row results bit for
/// bit. Returns whether every weight of the block is at most [`MAX_ABS_VALUE`]
/// in magnitude (NaN fails); the times are computed either way.
pub(super) struct Block<'a, 'b> {
    pub(super) graph: &'a EventGraph,
    /// The block's weight vectors, E entries each, by arc index (a short block
    /// repeats its last row).
    pub(super) rows: [&'a [f64]; LANES],
    /// Scratch (E,): the block's weights by arc index, lanes side by side.
    pub(super) wblk: &'b mut [[f64; LANES]],
    /// Scratch (V,): earliest times by topological position, one lane per row.
    pub(super) t: &'b mut [[f64; LANES]],
    /// Output (lanes × V), row-major: the first `out.len() / V` lanes' times.
    pub(super) out: &'b mut [f64],
}

impl pulp::WithSimd for Block<'_, '_> {
    type Output = bool;

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, simd: S) -> bool {
        let Block {
            graph: g,
            rows,
            wblk,
            t,
            out,
        } = self;
        let (n, m) = (g.n, g.src.len());
        let (inc, pos) = (&g.lay.inc, &g.lay.pos);
        assert!(wblk.len() == m && t.len() == n && rows.iter().all(|r| r.len() == m));
        // |x| <= MAX_ABS_VALUE as |x| < the next float up (false for NaN): pulp's
        // AVX2 `<=` is a call to baseline code, its `<` one instruction.
        let (limit, zero) = (
            simd.splat_f64s(MAX_ABS_VALUE.next_up()),
            simd.splat_f64s(0.0),
        );
        // 1.0 in a lane while every weight it has seen is within the limit.
        let mut ok = [1.0f64; LANES];
        let mut check = |x: &[f64; LANES]| {
            let (okv, xv) = (S::as_mut_simd_f64s(&mut ok).0, S::as_simd_f64s(x).0);
            for i in 0..okv.len() {
                let fine = simd.less_than_f64s(simd.abs_f64s(xv[i]), limit);
                okv[i] = simd.select_f64s(fine, okv[i], zero);
            }
        };
        let full = m - m % LANES;
        for (c, dst) in wblk[..full].chunks_exact_mut(LANES).enumerate() {
            let e = c * LANES;
            let mut tile = [[0.0; LANES]; LANES];
            for (x, r) in tile.iter_mut().zip(rows) {
                x.copy_from_slice(&r[e..e + LANES]);
            }
            tile.iter().for_each(&mut check);
            let dst: &mut [[f64; LANES]; LANES] = dst.try_into().unwrap();
            *dst = transpose(simd, &tile);
        }
        for (e, dst) in wblk.iter_mut().enumerate().skip(full) {
            for (x, r) in dst.iter_mut().zip(rows) {
                *x = r[e];
            }
            check(dst);
        }
        for k in 0..n {
            let r = inc.range(k);
            let mut best = if r.is_empty() {
                [0.0; LANES]
            } else {
                [f64::NEG_INFINITY; LANES]
            };
            {
                let bv = S::as_mut_simd_f64s(&mut best).0;
                for &[s, e] in &inc.arcs[r] {
                    let (ts, ws) = (
                        S::as_simd_f64s(&t[s as usize]).0,
                        S::as_simd_f64s(&wblk[e as usize]).0,
                    );
                    for i in 0..bv.len() {
                        let c = simd.add_f64s(ts[i], ws[i]);
                        bv[i] = simd.select_f64s(simd.less_than_f64s(bv[i], c), c, bv[i]);
                    }
                }
            }
            t[k] = best;
        }
        let lanes = out.len() / n.max(1);
        let mut outs: Vec<&mut [f64]> = out.chunks_exact_mut(n).take(lanes).collect();
        let tiles = n - n % LANES;
        // `t` is by topological position: each tile gathers the rows of 8
        // consecutive events (the graphs batches are for keep `t` in cache).
        for (c, pc) in pos[..tiles].chunks_exact(LANES).enumerate() {
            let mut tile = [[0.0; LANES]; LANES];
            for (x, &p) in tile.iter_mut().zip(pc) {
                *x = t[p as usize];
            }
            for (o, x) in outs.iter_mut().zip(transpose(simd, &tile)) {
                o[c * LANES..(c + 1) * LANES].copy_from_slice(&x);
            }
        }
        for (l, o) in outs.iter_mut().enumerate() {
            for (o, &p) in o[tiles..].iter_mut().zip(&pos[tiles..]) {
                *o = t[p as usize][l];
            }
        }
        ok.iter().all(|&x| x == 1.0)
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
) -> Result<Vec<f64>, CyclogramError> {
    let (n, s, d) = validate_arcs(n_events, src, dst)?;
    let m = s.len();
    if weights.len() != m {
        return Err(CyclogramError::WeightLength {
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
            Err(events) => CyclogramError::Cycle { events },
            Ok(_) => CyclogramError::Cycle { events: vec![] },
        });
    }
    Ok(t)
}
