//! The speed limit of a cyclogram whose extra bounds are proportional to the
//! speed, for many designs at once: the search of the Python layer's
//! `SpeedNetwork.speed_limits` (`python/cyclomech/cyclogram/_network.py`), step
//! for step and operation for operation, so that each design's limit is bit for
//! bit the Python search's (tested there against it).
//!
//! A design's network is the cyclogram's system of difference constraints
//! (see [`super::max_difference`]): fixed arcs (`base` weights) and, per
//! operation, a minimum-angle arc whose weight is `base - min`, where the minimum
//! angle at `n` rpm is `max(angle, 6·n·secs)` (the duration only where
//! `secs > 0`) raised by the extra bounds on that operation, bound `k` being
//! `t = max(n·per_rpm[k], 1e-9)` [deg], no angle at all (the row does not fit)
//! above 360°. A row fits when the shortest path from the limiting operation's
//! start to its end is finite (no negative cycle, the end reachable).
//!
//! The search, per design: not fitting at `floor` gives 0; otherwise the bracket
//! grows 4× from `start` up to `cap` (fitting at `cap`: inf); then the bracket
//! `[lo, hi]` is cut at the speeds `lo + i·(hi - lo)/65`, i = 1 … 64 (numpy's
//! `linspace(lo, hi, 66)[1:-1]`: a product then a sum, never fused), `lo` moving to
//! the last speed before the first that does not fit and `hi` to that one, until
//! `hi - lo <= rtol·hi`. The first non-fitting speed is found by trying them in
//! order and stopping there (the Python search tries all 64 and takes the first
//! False: the same speed, even where round-off makes fitting non-monotone),
//! found faster by a bisection and a certificate for the speeds below it (see
//! `Prepared::first_miss`).
//!
//! [`solve_proportional_into`] is `SpeedNetwork.solve` of every design at every
//! speed of a sweep on the same weights: the limiting angles, the chains' codes
//! and the bounds' minimum angles.

use rayon::prelude::*;

use super::difference::{DifferenceWork, Differences};
use super::graph::{CyclogramError, MAX_ABS_VALUE};
use crate::input::InvalidInput;
use crate::units::DEG_PER_S_PER_RPM;

/// Smallest angle a proportional bound gives [deg] (the Python `Proportional`).
pub const PROPORTIONAL_MIN_DEG: f64 = 1e-9;

/// Largest angle of a proportional bound [deg]: above, no phase angle of one
/// turn will do and the row does not fit.
pub const PROPORTIONAL_MAX_DEG: f64 = 360.0;

/// Speeds of one refinement step (numpy's `linspace(lo, hi, 66)` less its ends).
const GRID: usize = 64;

/// Relaxations a certificate may take, per (V + E): a potential of a network
/// far from infeasible is found in a few passes; near the edge (within the core's
/// tolerance) there may be none, and the speeds are tried one by one.
const CERTIFICATE_WORK: usize = 8;

/// The certificate's round-off bound, (|π| + V·max|w|) ≤ this·(1 + max |w| of the
/// constant arcs): 4.4e-16·that is half of DIFFERENCE_RTOL (1e-12) at most.
const CERTIFICATE_SCALE: f64 = 1000.0;

/// Certificates tried per refinement step (at the bisection's last fitting speed
/// and 2, 6, 14 … below it).
const CERTIFICATE_TRIES: usize = 4;

/// Refinement steps at most per design: rtol >= 1e-14 needs fewer than 20 (each
/// step shrinks the bracket 65×); the cap only stops a bracket that round-off
/// could no longer shrink (the Python search would loop there forever).
const MAX_REFINEMENTS: usize = 200;

/// The cyclogram's network with the operations' minimum-angle data and the extra
/// bounds' operations (all slices borrowed from the caller).
pub struct ProportionalNetwork<'a> {
    /// Nodes of the difference system.
    pub n_nodes: i64,
    /// Arc tails and heads (E,).
    pub src: &'a [i64],
    pub dst: &'a [i64],
    /// Each arc's constant weight [deg] (E,).
    pub base: &'a [f64],
    /// The limiting operation's start and end nodes.
    pub source: i64,
    pub target: i64,
    /// Added to the shortest path for the limiting angle [deg] (360·height).
    pub lim_shift: f64,
    /// The minimum-angle arc of each operation (O,).
    pub min_edge: &'a [i64],
    /// Each operation's minimum angle [deg] and minimum duration [s] (O,).
    pub angle: &'a [f64],
    pub secs: &'a [f64],
    /// The operation of each extra bound (K,).
    pub bound_op: &'a [i64],
}

/// The search's speeds [rpm] and its relative tolerance.
#[derive(Debug, Clone, Copy)]
pub struct SpeedSearch {
    /// The first speed tried.
    pub start: f64,
    /// The lowest speed tried: not fitting there gives 0.
    pub floor: f64,
    /// The highest speed tried: fitting there gives inf.
    pub cap: f64,
    /// The bracket's relative width at which the search stops.
    pub rtol: f64,
}

/// A validated network: the difference system and the per-operation data as
/// indices.
struct Prepared<'a> {
    sys: Differences,
    /// Nodes of the system (validated by `Differences::new`).
    n: usize,
    base: &'a [f64],
    lim_shift: f64,
    min_edge: Vec<usize>,
    angle: &'a [f64],
    secs: &'a [f64],
    bound_op: Vec<usize>,
    /// Arc heads, and the arcs out of each node (CSR: `out_arcs[out_ptr[u]..out_ptr[u + 1]]`).
    dst: Vec<u32>,
    out_ptr: Vec<usize>,
    out_arcs: Vec<u32>,
    /// Whether the limiting operation's end is reachable from its start at all.
    reachable: bool,
    /// max |w| over the arcs whose weight is the same at every speed, and over
    /// those and the minimum-angle arcs at their largest (base − angle).
    max_const: f64,
    max_static: f64,
    /// The operations whose minimum angle depends on the speed (a duration or an
    /// extra bound; all of them if two share an arc), in order; the others' weights
    /// are set once per scratch. And whether every weight set once is in range.
    dynamic: Vec<usize>,
    static_ok: bool,
}

/// One thread's scratch: weights (E,), minimum angles (O,) and the shortest-path
/// work space.
struct Scratch {
    w: Vec<f64>,
    mins: Vec<f64>,
    /// Which lower bound sets each minimum: 0 its angle, 1 its duration, 2 + k
    /// extra bound k (`SpeedNetwork.minimums`).
    which: Vec<u8>,
    work: DifferenceWork,
    /// The certificate's potential, queue and queue marks (V,).
    pi: Vec<f64>,
    queue: Vec<u32>,
    queued: Vec<bool>,
}

fn index(
    field: &'static str,
    values: &[i64],
    len: usize,
    what: &'static str,
) -> Result<Vec<usize>, CyclogramError> {
    values
        .iter()
        .enumerate()
        .map(|(i, &v)| {
            if v < 0 || v as u64 >= len as u64 {
                Err(CyclogramError::OutOfDomain {
                    field,
                    position: i,
                    value: v as f64,
                    what,
                })
            } else {
                Ok(v as usize)
            }
        })
        .collect()
}

fn scalar(
    field: &'static str,
    value: f64,
    ok: bool,
    what: &'static str,
) -> Result<(), CyclogramError> {
    if ok {
        Ok(())
    } else {
        Err(CyclogramError::bad_scalar(field, value, what))
    }
}

/// The arcs out of each node: (ptr (V + 1,), arcs), by a counting sort of the
/// (validated) tails.
fn outgoing(n: usize, src: &[i64]) -> (Vec<usize>, Vec<u32>) {
    let mut ptr = vec![0usize; n + 1];
    for &u in src {
        ptr[u as usize + 1] += 1;
    }
    for v in 0..n {
        ptr[v + 1] += ptr[v];
    }
    let mut fill = ptr.clone();
    let mut arcs = vec![0u32; src.len()];
    for (e, &u) in src.iter().enumerate() {
        arcs[fill[u as usize]] = e as u32;
        fill[u as usize] += 1;
    }
    (ptr, arcs)
}

/// Whether `target` is reachable from `source` along the arcs.
fn reaches(ptr: &[usize], arcs: &[u32], dst: &[i64], source: usize, target: usize) -> bool {
    let mut seen = vec![false; ptr.len() - 1];
    let mut stack = vec![source];
    seen[source] = true;
    while let Some(u) = stack.pop() {
        if u == target {
            return true;
        }
        for &e in &arcs[ptr[u]..ptr[u + 1]] {
            let v = dst[e as usize] as usize;
            if !seen[v] {
                seen[v] = true;
                stack.push(v);
            }
        }
    }
    false
}

impl<'a> Prepared<'a> {
    fn new(net: &ProportionalNetwork<'a>) -> Result<Self, CyclogramError> {
        let sys = Differences::new(net.n_nodes, net.src, net.dst, net.source, net.target)?;
        let m = net.src.len();
        if net.base.len() != m {
            return Err(CyclogramError::WeightLength {
                field: "base",
                expected: m,
                got: net.base.len(),
            });
        }
        let o = net.min_edge.len();
        for (field, got) in [("angle", net.angle.len()), ("secs", net.secs.len())] {
            if got != o {
                return Err(CyclogramError::WeightLength {
                    field,
                    expected: o,
                    got,
                });
            }
        }
        let min_edge = index(
            "min_edge",
            net.min_edge,
            m,
            "an arc index below the arc count",
        )?;
        let bound_op = index(
            "bound_op",
            net.bound_op,
            o,
            "an operation index below the count",
        )?;
        scalar(
            "lim_shift",
            net.lim_shift,
            net.lim_shift.is_finite(),
            "it must be finite",
        )?;
        let n = net.n_nodes as usize;
        let (out_ptr, out_arcs) = outgoing(n, net.src);
        let reachable = reaches(
            &out_ptr,
            &out_arcs,
            net.dst,
            net.source as usize,
            net.target as usize,
        );
        let mut is_min = vec![false; m];
        for &e in &min_edge {
            is_min[e] = true;
        }
        let max_const = (0..m)
            .filter(|&e| !is_min[e])
            .fold(0.0f64, |a, e| a.max(net.base[e].abs()));
        let max_static = min_edge
            .iter()
            .zip(net.angle)
            .fold(max_const, |a, (&e, &t)| a.max((net.base[e] - t).abs()));
        let mut dynamic_op: Vec<bool> = net.secs.iter().map(|&t| t > 0.0).collect();
        for &op in &bound_op {
            dynamic_op[op] = true;
        }
        let mut seen = vec![false; m];
        if min_edge
            .iter()
            .any(|&e| std::mem::replace(&mut seen[e], true))
        {
            dynamic_op.fill(true);
        }
        let dynamic: Vec<usize> = (0..o).filter(|&op| dynamic_op[op]).collect();
        let mut w = net.base.to_vec();
        for (op, &e) in min_edge.iter().enumerate() {
            if !dynamic_op[op] {
                w[e] = net.base[e] - net.angle[op];
            }
        }
        let static_ok = (0..m)
            .filter(|&e| !dynamic.iter().any(|&op| min_edge[op] == e))
            .all(|e| w[e].abs() <= MAX_ABS_VALUE);
        Ok(Prepared {
            max_const,
            max_static,
            dynamic,
            static_ok,
            dst: net.dst.iter().map(|&v| v as u32).collect(),
            out_ptr,
            out_arcs,
            reachable,
            sys,
            n,
            base: net.base,
            lim_shift: net.lim_shift,
            min_edge,
            angle: net.angle,
            secs: net.secs,
            bound_op,
        })
    }

    fn scratch(&self) -> Scratch {
        // The operations that are not dynamic keep their angle (and its weight).
        let mut w = self.base.to_vec();
        for (&e, &a) in self.min_edge.iter().zip(self.angle) {
            w[e] = self.base[e] - a;
        }
        Scratch {
            w,
            mins: self.angle.to_vec(),
            which: vec![0; self.min_edge.len()],
            work: DifferenceWork::new(self.n),
            pi: vec![0.0; self.n],
            queue: Vec::with_capacity(8 * self.n),
            queued: vec![false; self.n],
        }
    }

    /// Whether the last row's first run left a certificate ([`Self::certified`]'s:
    /// an exact potential with the same round-off bound) for every lower speed.
    fn left_certificate(&self, work: &DifferenceWork) -> bool {
        matches!(work.potential, Some((pi, max_w)) if self.small_round_off(pi, max_w))
    }

    /// The certificates' round-off bound, for a potential of largest magnitude
    /// `max_pi` of weights of largest magnitude `max_w` (the static ones at their
    /// largest counted too): a cycle's weight is off by at most V ulps of
    /// (|π| + V·max|w|) here and in the core's own sums; it must stay far below the
    /// core's eps ≥ DIFFERENCE_RTOL·V·(1 + the constant arcs' max |w|).
    fn small_round_off(&self, max_pi: f64, max_w: f64) -> bool {
        max_pi + self.n as f64 * max_w.max(self.max_static)
            <= CERTIFICATE_SCALE * (1.0 + self.max_const)
    }

    /// The weights at `rpm` into `s.w` (`SpeedNetwork.solve`'s: the minimum
    /// angles, the extra bounds in order, base − minimum on each minimum-angle
    /// arc) and whether every bound has an angle (≤ 360°). An error where the
    /// Python search's shortest-path call would raise (a weight out of range).
    fn weights(&self, rpm: f64, per_rpm: &[f64], s: &mut Scratch) -> Result<bool, CyclogramError> {
        // minimum_angles: where(secs > 0, 6·n·secs, -inf), the larger of it and the
        // angle; only the dynamic operations' (the others' are their angles, set
        // by `scratch` and never changed).
        for &e in &self.dynamic {
            let dur = if self.secs[e] > 0.0 {
                DEG_PER_S_PER_RPM * rpm * self.secs[e]
            } else {
                f64::NEG_INFINITY
            };
            let by_time = dur > self.angle[e];
            s.mins[e] = if by_time { dur } else { self.angle[e] };
            s.which[e] = u8::from(by_time);
        }
        // The extra bounds in order, each raising its operation's minimum.
        let mut bound_ok = true;
        for (k, (&op, &c)) in self.bound_op.iter().zip(per_rpm).enumerate() {
            let x = rpm * c;
            // np.maximum propagates NaN; NaN or over 360°: no angle will do.
            let t = if x.is_nan() {
                f64::NAN
            } else if x > PROPORTIONAL_MIN_DEG {
                x
            } else {
                PROPORTIONAL_MIN_DEG
            };
            if t <= PROPORTIONAL_MAX_DEG {
                if t > s.mins[op] {
                    s.mins[op] = t;
                    s.which[op] = 2 + k as u8;
                }
            } else {
                bound_ok = false;
            }
        }
        let mut dynamic_ok = true;
        for &o in &self.dynamic {
            let e = self.min_edge[o];
            s.w[e] = self.base[e] - s.mins[o];
            dynamic_ok &= s.w[e].abs() <= MAX_ABS_VALUE; // NaN fails too
        }
        if !(self.static_ok && dynamic_ok) {
            // Out of range somewhere: the first such column, as one pass over all finds it.
            if let Some((col, &value)) =
                s.w.iter()
                    .enumerate()
                    .find(|(_, v)| v.is_nan() || v.abs() > MAX_ABS_VALUE)
            {
                return Err(CyclogramError::NonFinite {
                    field: "weights",
                    location: format!("[{col}] (at {rpm} rpm)"),
                    value,
                    what: "difference bounds",
                });
            }
        }
        Ok(bound_ok)
    }

    /// Whether the cyclogram fits at `rpm` with the bounds' slopes `per_rpm`
    /// (K,): `SpeedNetwork.solve(...)[1]` for one row, by the same shortest-path
    /// core (`Differences::solve_row`) on the same weights.
    ///
    /// When the first run settles on a certificate (`left_certificate`), the
    /// second cannot meet a cycle below `-eps` and settles too, so the value is
    /// finite exactly when the end is reachable at all: that run is skipped.
    fn fits(&self, rpm: f64, per_rpm: &[f64], s: &mut Scratch) -> Result<bool, CyclogramError> {
        if !self.weights(rpm, per_rpm, s)? || self.sys.cycle_below(&s.w, &s.work.cycle) {
            return Ok(false);
        }
        let Some(eps) = self.sys.start_row(&s.w, &mut s.work, false) else {
            return Ok(false);
        };
        if self.left_certificate(&s.work) {
            return Ok(self.reachable);
        }
        let value = self.sys.finish_row(&s.w, eps, false, &mut s.work);
        Ok((value + self.lim_shift).is_finite())
    }

    /// A proof that the cyclogram fits at `rpm` and at every lower speed, without
    /// the shortest-path core: a potential π with π[v] ≤ fl(π[u] + w[e]) on every
    /// arc (label-correcting shortest paths from a virtual source, strict
    /// improvements only, at most `CERTIFICATE_WORK`·(V + E) relaxations).
    ///
    /// Why it decides `fits` exactly: every weight only falls as the speed grows
    /// (the minimum angles only grow, in floating point too: products, maxima and
    /// differences are monotone), so π satisfies the arcs at every lower speed;
    /// then each cycle weighs at least −V·(a few ulps of the distances), far above
    /// −eps (`DIFFERENCE_RTOL`·(1 + max|w|)·V), so the core's Bellman–Ford runs
    /// settle without a predecessor cycle (which needs a cycle below −eps), the
    /// target is reached when it is reachable at all (checked once), and the
    /// bounds that have an angle here have one below. False says nothing.
    fn certified(
        &self,
        rpm: f64,
        per_rpm: &[f64],
        s: &mut Scratch,
    ) -> Result<bool, CyclogramError> {
        if !self.reachable || !self.weights(rpm, per_rpm, s)? {
            return Ok(false);
        }
        let n = self.n;
        let Scratch {
            w,
            pi,
            queue,
            queued,
            ..
        } = s;
        pi.fill(0.0);
        queue.clear();
        queue.extend(0..n as u32);
        queued.fill(true);
        let mut head = 0usize;
        let mut budget = CERTIFICATE_WORK * (n + w.len());
        while head < queue.len() {
            let u = queue[head] as usize;
            head += 1;
            queued[u] = false;
            for &e in &self.out_arcs[self.out_ptr[u]..self.out_ptr[u + 1]] {
                if budget == 0 {
                    return Ok(false);
                }
                budget -= 1;
                let v = self.dst[e as usize] as usize;
                let c = pi[u] + w[e as usize];
                if c < pi[v] {
                    pi[v] = c;
                    if !queued[v] {
                        queued[v] = true;
                        queue.push(v as u32);
                    }
                }
            }
            if head > 4 * n {
                // Keep the queue short: drop what was taken.
                queue.drain(..head);
                head = 0;
            }
        }
        let max_pi = pi.iter().fold(0.0f64, |a, &x| a.max(x.abs()));
        let max_w = w.iter().fold(0.0f64, |a, &x| a.max(x.abs()));
        Ok(self.small_round_off(max_pi, max_w))
    }

    /// The first of the 64 grid speeds `at(0..64)` that does not fit (64 if all
    /// do): what trying each in order gives. A bisection finds a speed that fits
    /// followed by one that does not; below it, a certificate
    /// ([`Self::certified`]) at that speed or a few lower ones proves a run of
    /// speeds fits, and the speeds between are tried in order (in the last
    /// refinements, where the bracket is within the core's tolerance, that is
    /// most of them).
    fn first_miss(
        &self,
        at: &dyn Fn(usize) -> f64,
        per_rpm: &[f64],
        s: &mut Scratch,
    ) -> Result<usize, CyclogramError> {
        // known[i]: 0 not tried, 1 fits, 2 does not.
        let mut known = [0u8; GRID];
        let (mut fit, mut miss) = (-1isize, GRID as isize);
        // Every speed up to `proven` fits: a fitting speed whose check left a
        // certificate, or one of the certificates tried below.
        let mut proven = -1isize;
        while miss - fit > 1 {
            let mid = (fit + miss) / 2;
            if self.fits(at(mid as usize), per_rpm, s)? {
                known[mid as usize] = 1;
                fit = mid;
                if self.left_certificate(&s.work) {
                    proven = mid;
                }
            } else {
                known[mid as usize] = 2;
                miss = mid;
            }
        }
        let (mut p, mut gap) = (fit, 2isize);
        for _ in 0..CERTIFICATE_TRIES {
            if p < 1 || p <= proven {
                break;
            }
            if self.certified(at(p as usize), per_rpm, s)? {
                proven = p;
                break;
            }
            p -= gap;
            gap *= 2;
        }
        for i in (proven + 1).max(0)..fit {
            let i = i as usize;
            let ok = match known[i] {
                1 => true,
                2 => false,
                _ => self.fits(at(i), per_rpm, s)?,
            };
            if !ok {
                return Ok(i);
            }
        }
        Ok(miss as usize)
    }

    /// One design's speed limit [rpm] (see the module's docs).
    fn search(
        &self,
        per_rpm: &[f64],
        sp: SpeedSearch,
        s: &mut Scratch,
    ) -> Result<f64, CyclogramError> {
        if !self.fits(sp.floor, per_rpm, s)? {
            return Ok(0.0);
        }
        let (mut lo, mut hi) = (sp.floor, sp.start);
        while self.fits(hi, per_rpm, s)? {
            if hi >= sp.cap {
                return Ok(f64::INFINITY);
            }
            lo = hi;
            hi = (4.0 * hi).min(sp.cap);
        }
        for _ in 0..MAX_REFINEMENTS {
            if hi - lo <= sp.rtol * hi {
                return Ok(lo);
            }
            let step = (hi - lo) / (GRID + 1) as f64;
            let at = |i: usize| (i + 1) as f64 * step + lo;
            let k = self.first_miss(&at, per_rpm, s)?;
            let (new_lo, new_hi) = (
                if k > 0 { at(k - 1) } else { lo },
                if k < GRID { at(k) } else { hi },
            );
            lo = new_lo;
            hi = new_hi;
        }
        Ok(lo)
    }
}

/// Each of `designs` designs' speed limit [rpm] (D,): the highest speed at which the
/// network fits with the extra bounds' slopes `per_rpm` (D·K, row-major, K =
/// `net.bound_op.len()`; bound k of design d at n rpm is `n·per_rpm[d·K + k]`
/// degrees); 0 if it does not fit at `search.floor`, inf if it fits at
/// `search.cap`. Bit for bit the Python `SpeedNetwork.speed_limits` with
/// proportional bounds (see the module's docs), whatever the thread count: rayon
/// over designs on the pool chosen by `n_threads`.
pub fn speed_limits_proportional(
    net: &ProportionalNetwork<'_>,
    per_rpm: &[f64],
    designs: usize,
    search: SpeedSearch,
    n_threads: Option<i64>,
) -> Result<Vec<f64>, CyclogramError> {
    let prep = Prepared::new(net)?;
    let k = prep.bound_op.len();
    let threads = crate::parallel::resolve_threads(n_threads)?;
    let sp = search;
    scalar(
        "floor",
        sp.floor,
        sp.floor.is_finite() && sp.floor > 0.0,
        "it must be a positive speed",
    )?;
    scalar(
        "start",
        sp.start,
        sp.start.is_finite() && sp.start >= sp.floor,
        "it must be finite and at least the floor",
    )?;
    scalar(
        "cap",
        sp.cap,
        sp.cap.is_finite() && sp.cap >= sp.start,
        "it must be finite and at least start",
    )?;
    scalar(
        "rtol",
        sp.rtol,
        (1e-14..=0.5).contains(&sp.rtol),
        "it must be a relative tolerance in [1e-14, 0.5]",
    )?;
    if Some(per_rpm.len()) != designs.checked_mul(k) {
        return Err(CyclogramError::WeightLength {
            field: "per_rpm",
            expected: designs.saturating_mul(k),
            got: per_rpm.len(),
        });
    }
    let row = |d: usize| &per_rpm[d * k..(d + 1) * k];
    let mut out = vec![0.0; designs];
    if threads == 1 || designs < 2 {
        let mut s = prep.scratch();
        for (d, o) in out.iter_mut().enumerate() {
            if d % 64 == 0 && crate::cancel::requested() {
                break;
            }
            *o = prep.search(row(d), sp, &mut s)?;
        }
    } else {
        crate::parallel::pool(threads)?.install(|| {
            out.par_iter_mut().enumerate().try_for_each_init(
                || prep.scratch(),
                |s, (d, o)| -> Result<(), CyclogramError> {
                    if !crate::cancel::requested() {
                        *o = prep.search(row(d), sp, s)?;
                    }
                    Ok(())
                },
            )
        })?;
    }
    Ok(out)
}

/// One task of [`solve_proportional_into`]: its index, its rows' values, codes and
/// bound minima.
type TaskItem<'a> = (usize, (&'a mut [f64], (&'a mut [i16], &'a mut [f64])));

/// What [`solve_proportional_into`] gives per row (B = D·S rows, design-major).
#[derive(Debug)]
pub struct SolveOut<'a> {
    /// The limiting operation's optimal angle [deg] (B,), NaN where it does not fit.
    pub value: &'a mut [f64],
    /// Per row and arc (B, E): 0 off the shortest path (or the row does not
    /// fit), 1 on it; a minimum-angle arc on it: 1 + which bound sets it (1 its
    /// angle, 2 its duration, 3 + k extra bound k). `SpeedNetwork._labels`' codes.
    pub code: &'a mut [i16],
    /// The minimum angle [deg] of each extra bound's operation (B, K).
    pub bound_mins: &'a mut [f64],
    /// Per row (B,): whether its codes differ from the previous row's (true for
    /// row 0): the starts of the runs of equal chains, which the caller names
    /// once each (neighbouring speeds mostly share a chain).
    pub new_run: &'a mut [bool],
}

/// `SpeedNetwork.solve` of every design at every speed: design d (of
/// `designs`, bounds' slopes `per_rpm` (D·K,)) at `rpm[j]` is row d·S + j. The
/// same weights and shortest-path core as the Python call, so the same values,
/// paths and codes; rayon over rows on the pool chosen by `n_threads`.
pub fn solve_proportional_into(
    net: &ProportionalNetwork<'_>,
    per_rpm: &[f64],
    designs: usize,
    rpm: &[f64],
    n_threads: Option<i64>,
    out: SolveOut<'_>,
) -> Result<(), CyclogramError> {
    let prep = Prepared::new(net)?;
    let (k, m, s) = (prep.bound_op.len(), net.src.len(), rpm.len());
    let threads = crate::parallel::resolve_threads(n_threads)?;
    if Some(per_rpm.len()) != designs.checked_mul(k) {
        return Err(CyclogramError::WeightLength {
            field: "per_rpm",
            expected: designs.saturating_mul(k),
            got: per_rpm.len(),
        });
    }
    let b = designs.saturating_mul(s);
    for (field, got, want) in [
        ("value", out.value.len(), b),
        ("code", out.code.len(), b.saturating_mul(m)),
        ("bound_mins", out.bound_mins.len(), b.saturating_mul(k)),
        ("new_run", out.new_run.len(), b),
    ] {
        if got != want {
            return Err(InvalidInput::Output {
                field: "out",
                want: format!("{field} of {want} entries"),
                got: got.to_string(),
            }
            .into());
        }
    }
    // Each design's rows are solved from its highest speed down: the first row
    // whose first run settles on an exact potential certifies every lower speed
    // (the weights only grow as the speed falls, see `Prepared::certified`), and
    // there `solve_row_as` skips that run. `cover`: the speed of that row (-inf: none yet).
    let row = |sc: &mut Scratch,
               r: usize,
               cover: &mut f64,
               value: &mut f64,
               code: &mut [i16],
               mins: &mut [f64]|
     -> Result<(), CyclogramError> {
        let (d, x) = (r / s, rpm[r % s]);
        let per = &per_rpm[d * k..(d + 1) * k];
        let bound_ok = prep.weights(x, per, sc)?;
        for (o, &op) in mins.iter_mut().zip(&prep.bound_op) {
            *o = sc.mins[op];
        }
        code.fill(0);
        *value = f64::NAN;
        if !bound_ok {
            return Ok(());
        }
        // Only positive speeds: below 0 a bound n·per_rpm < 0 is not monotone.
        let certified = x > 0.0 && x <= *cover;
        if !certified && prep.sys.cycle_below(&sc.w, &sc.work.cycle) {
            return Ok(()); // NaN: an earlier row's negative cycle is one here too
        }
        let v = prep.sys.solve_row_as(&sc.w, &mut sc.work, certified);
        if x > 0.0 && !certified && prep.left_certificate(&sc.work) {
            *cover = x;
        }
        if !v.is_finite() || !(v + prep.lim_shift).is_finite() {
            return Ok(());
        }
        *value = v + prep.lim_shift;
        for &e in &sc.work.path {
            code[e as usize] = 1;
        }
        for (o, &e) in prep.min_edge.iter().enumerate() {
            if code[e] > 0 {
                code[e] = 1 + i16::from(sc.which[o]);
            }
        }
        Ok(())
    };
    if b == 0 {
        return Ok(());
    }
    let SolveOut {
        value,
        code,
        bound_mins,
        new_run,
    } = out;
    // Without arcs or bounds the rows are empty: pad them so the chunks hold.
    let mut no_code = vec![0i16; if m == 0 { b } else { 0 }];
    let mut no_mins = vec![0.0f64; if k == 0 { b } else { 0 }];
    let code: &mut [i16] = if m == 0 { &mut no_code } else { code };
    let bound_mins: &mut [f64] = if k == 0 { &mut no_mins } else { bound_mins };
    let (mc, kc) = (m.max(1), k.max(1));
    // The speeds from the highest down (ties in row order), for a whole design.
    let mut desc: Vec<usize> = (0..s).collect();
    desc.sort_by(|&i, &j| rpm[j].total_cmp(&rpm[i]));
    // (Any order gives the same rows; from the top down only saves work.)
    let ascending = rpm.windows(2).all(|p| p[0] <= p[1]);
    // A task: `rows` consecutive rows; each design's part of it from the top speed.
    let rows = s.clamp(64, 4096);
    let task = |sc: &mut Scratch, (t, (v, (c, bm))): TaskItem<'_>| -> Result<(), CyclogramError> {
        if crate::cancel::requested() {
            return Ok(());
        }
        let r0 = t * rows;
        let mut order: Vec<usize> = Vec::new();
        let mut start = r0;
        while start < r0 + v.len() {
            let d = start / s;
            let end = ((d + 1) * s).min(r0 + v.len());
            order.clear();
            if end - start == s {
                order.extend(desc.iter().map(|&j| d * s + j));
            } else if ascending {
                order.extend((start..end).rev());
            } else {
                order.extend(start..end);
                order.sort_unstable_by(|&a, &b| rpm[b % s].total_cmp(&rpm[a % s]));
            }
            let mut cover = f64::NEG_INFINITY;
            for &r in &order {
                let i = r - r0;
                let (ci, bi) = (&mut c[i * mc..i * mc + m], &mut bm[i * kc..i * kc + k]);
                if let Err(e) = row(sc, r, &mut cover, &mut v[i], ci, bi) {
                    // Report the task's first bad row in row order, as a loop would.
                    for r in r0..r0 + v.len() {
                        prep.weights(rpm[r % s], &per_rpm[(r / s) * k..(r / s + 1) * k], sc)?;
                    }
                    return Err(e);
                }
            }
            start = end;
        }
        Ok(())
    };
    if threads == 1 || b < 64 {
        let mut sc = prep.scratch();
        for item in value
            .chunks_mut(rows)
            .zip(
                code.chunks_mut(rows * mc)
                    .zip(bound_mins.chunks_mut(rows * kc)),
            )
            .enumerate()
        {
            task(&mut sc, item)?;
        }
    } else {
        crate::parallel::pool(threads)?.install(|| {
            value
                .par_chunks_mut(rows)
                .zip(
                    code.par_chunks_mut(rows * mc)
                        .zip(bound_mins.par_chunks_mut(rows * kc)),
                )
                .enumerate()
                .try_for_each_init(|| prep.scratch(), task)
        })?;
    }
    // Row r starts a run unless its codes are row r - 1's (m = 0: one run).
    let code: &[i16] = code;
    let starts = |(r, x): (usize, &mut bool)| {
        *x = r == 0 || (m > 0 && code[r * m..(r + 1) * m] != code[(r - 1) * m..r * m]);
    };
    if threads == 1 || b < 4096 {
        new_run.iter_mut().enumerate().for_each(starts);
    } else {
        crate::parallel::pool(threads)?.install(|| {
            new_run
                .par_iter_mut()
                .enumerate()
                .with_min_len(4096)
                .for_each(starts)
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// a→b (min 100°, duration 0.05 s), b→c (60°, limiting), as the Python
    /// `SpeedNetwork` builds it: events a, b, c = 0, 1, 2, z = 3, F = 4.
    fn chain() -> (Vec<i64>, Vec<i64>, Vec<f64>) {
        let mut src = vec![1, 2];
        let mut dst = vec![0, 1];
        let mut base = vec![0.0, 0.0];
        for v in 0..3 {
            src.extend([v, 4]);
            dst.extend([3, v]);
            base.extend([0.0, 0.0]);
        }
        src.push(3);
        dst.push(4);
        base.push(360.0);
        (src, dst, base)
    }

    /// The `chain` network with the operations' angles and durations and one
    /// extra bound on a→b.
    fn chain_net<'a>(
        (src, dst, base): &'a (Vec<i64>, Vec<i64>, Vec<f64>),
        angle: &'a [f64; 2],
        secs: &'a [f64; 2],
    ) -> ProportionalNetwork<'a> {
        ProportionalNetwork {
            n_nodes: 5,
            src,
            dst,
            base,
            source: 1,
            target: 2,
            lim_shift: 0.0,
            min_edge: &[0, 1],
            angle,
            secs,
            bound_op: &[0],
        }
    }

    fn limits(per_rpm: &[f64], secs: f64, threads: i64) -> Vec<f64> {
        let (chain, secs) = (chain(), [secs, 0.0]);
        let net = chain_net(&chain, &[100.0, 60.0], &secs);
        let sp = SpeedSearch {
            start: 100.0,
            floor: 1e-6,
            cap: 1e6,
            rtol: 1e-10,
        };
        speed_limits_proportional(&net, per_rpm, per_rpm.len(), sp, Some(threads)).unwrap()
    }

    #[test]
    fn closed_forms() {
        // 6·n·0.05 = 300 at 1000 rpm; a bound n·0.5 = 300 at 600 rpm; 0.001 never binds.
        let got = limits(&[0.001, 0.5, 400.0], 0.05, 1);
        assert!((got[0] - 1000.0).abs() <= 1e-10 * 1000.0 * 2.0, "{got:?}");
        assert!(got[0] <= 1000.0);
        assert!((got[1] - 600.0).abs() <= 1e-10 * 600.0 * 2.0, "{got:?}");
        // 400·1e-6 = 4e-4 deg fits at the floor; 300/400 = 0.75 rpm.
        assert!((got[2] - 0.75).abs() <= 1e-10, "{got:?}");
        assert_eq!(limits(&[0.001, 0.5, 400.0], 0.05, 2), got);
    }

    #[test]
    fn ends_of_the_range() {
        // No duration and a tiny slope: fits at the cap; a slope that passes 360°
        // at the floor: fits nowhere.
        let got = limits(&[1e-9, 1e9], 0.0, 1);
        assert_eq!(got, vec![f64::INFINITY, 0.0]);
    }

    #[test]
    fn bad_inputs_are_errors() {
        let (src, dst, base) = chain();
        let mut net = ProportionalNetwork {
            n_nodes: 5,
            src: &src,
            dst: &dst,
            base: &base,
            source: 1,
            target: 2,
            lim_shift: 0.0,
            min_edge: &[0, 99],
            angle: &[100.0, 60.0],
            secs: &[0.0, 0.0],
            bound_op: &[0],
        };
        let sp = SpeedSearch {
            start: 100.0,
            floor: 1e-6,
            cap: 1e6,
            rtol: 1e-10,
        };
        let e = speed_limits_proportional(&net, &[0.1], 1, sp, Some(1)).unwrap_err();
        assert!(e.to_string().contains("min_edge[1] = 99"), "{e}");
        net.min_edge = &[0, 1];
        let bad = SpeedSearch { rtol: 0.0, ..sp };
        let e = speed_limits_proportional(&net, &[0.1], 1, bad, Some(1)).unwrap_err();
        assert!(e.to_string().contains("rtol"), "{e}");
        let e = speed_limits_proportional(&net, &[0.1, 0.2, 0.3], 3, sp, Some(0)).unwrap_err();
        assert!(e.to_string().contains("n_threads"), "{e}");
    }

    /// A weight out of range is an error naming its column and the first row in
    /// row order that has it (the rows are solved from the top speed down): a
    /// static one (an angle) at the first row, a dynamic one (a duration at a huge
    /// speed) at the first speed that makes it.
    #[test]
    fn weight_errors_name_the_first_bad_row() {
        let chain = chain();
        let solve = |angle: [f64; 2], secs: [f64; 2], speeds: &[f64]| {
            let net = chain_net(&chain, &angle, &secs);
            let b = speeds.len();
            let (mut value, mut code) = (vec![0.0; b], vec![0i16; b * net.src.len()]);
            let (mut mins, mut new_run) = (vec![0.0; b], vec![false; b]);
            let out = SolveOut {
                value: &mut value,
                code: &mut code,
                bound_mins: &mut mins,
                new_run: &mut new_run,
            };
            solve_proportional_into(&net, &[0.1], 1, speeds, Some(1), out)
                .unwrap_err()
                .to_string()
        };
        let e = solve([100.0, 2e12], [0.0, 0.0], &[100.0, 300.0]);
        assert!(e.contains("[1] (at 100 rpm)"), "{e}");
        let e = solve([100.0, 60.0], [1e4, 0.0], &[10.0, 1e9, 2e9]);
        assert!(e.contains("[0] (at 1000000000 rpm)"), "{e}");
    }

    use proptest::prelude::*;

    /// `fits` by the plain core alone: the weights and both runs, no certificate
    /// and no earlier row's cycle (fresh scratch).
    fn plain_fits(prep: &Prepared<'_>, rpm: f64, per: &[f64]) -> bool {
        let mut s = prep.scratch();
        prep.weights(rpm, per, &mut s).unwrap()
            && (prep.sys.solve_row(&s.w, &mut s.work) + prep.lim_shift).is_finite()
    }

    /// A speed for the row tests: negative, zero, a repeated one, or 1e-6…3000 rpm.
    fn speed() -> impl Strategy<Value = f64> {
        prop_oneof![-100.0f64..0.0, Just(0.0), Just(250.0), 1e-6f64..3000.0]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(200))]

        /// `fits` (which skips the second run under a certificate and the whole
        /// row under an earlier row's negative cycle) is the plain core's verdict,
        /// whatever speeds the scratch saw before.
        #[test]
        fn fits_is_the_plain_core(
            a0 in 0.0f64..200.0, a1 in 0.0f64..200.0,
            s0 in prop_oneof![Just(0.0), 1e-4f64..0.05],
            per in prop_oneof![Just(0.0), 1e-4f64..2.0, -1.0f64..0.0],
            speeds in prop::collection::vec(speed(), 1..40),
        ) {
            let chain = chain();
            let (angle, secs) = ([a0, a1], [s0, 0.0]);
            let net = chain_net(&chain, &angle, &secs);
            let prep = Prepared::new(&net).unwrap();
            let mut s = prep.scratch();
            for &x in &speeds {
                prop_assert_eq!(prep.fits(x, &[per], &mut s).unwrap(), plain_fits(&prep, x, &[per]));
            }
        }

        /// Every row of `solve_proportional_into` (each design's rows from its top
        /// speed down, the first run skipped below a certificate, a row NaN by an
        /// earlier row's cycle, tasks cut inside designs) is what the plain core
        /// gives that row alone: value, path and codes; and the run starts.
        #[test]
        fn rows_are_the_plain_core_rows(
            a0 in 0.0f64..200.0, a1 in 0.0f64..200.0,
            s0 in prop_oneof![Just(0.0), 1e-4f64..0.05],
            pers in prop::collection::vec(prop_oneof![Just(0.0), 1e-4f64..2.0, -1.0f64..0.0], 1..5),
            mut speeds in prop::collection::vec(speed(), 1..150),
            ascending in any::<bool>(),
            threads in 1i64..3,
        ) {
            if ascending {
                speeds.sort_by(f64::total_cmp);
            }
            let chain = chain();
            let (angle, secs) = ([a0, a1], [s0, 0.0]);
            let net = chain_net(&chain, &angle, &secs);
            let (d, n, m) = (pers.len(), speeds.len(), net.src.len());
            let b = d * n;
            let (mut value, mut code) = (vec![0.0; b], vec![0i16; b * m]);
            let (mut mins, mut new_run) = (vec![0.0; b], vec![false; b]);
            let out = SolveOut {
                value: &mut value, code: &mut code, bound_mins: &mut mins, new_run: &mut new_run,
            };
            solve_proportional_into(&net, &pers, d, &speeds, Some(threads), out).unwrap();
            let prep = Prepared::new(&net).unwrap();
            for r in 0..b {
                let mut s = prep.scratch();
                let ok = prep.weights(speeds[r % n], &pers[r / n..r / n + 1], &mut s).unwrap();
                prop_assert_eq!(mins[r].to_bits(), s.mins[0].to_bits());
                let v = if ok { prep.sys.solve_row(&s.w, &mut s.work) } else { f64::NAN };
                let row = &code[r * m..(r + 1) * m];
                if v.is_finite() {
                    prop_assert_eq!(value[r].to_bits(), v.to_bits(), "row {}", r);
                    let mut want = vec![0i16; m];
                    for &e in &s.work.path {
                        want[e as usize] = 1;
                    }
                    for (o, &e) in [0usize, 1].iter().enumerate() {
                        if want[e] > 0 {
                            want[e] = 1 + i16::from(s.which[o]);
                        }
                    }
                    prop_assert_eq!(row, &want[..], "row {}", r);
                } else {
                    prop_assert!(value[r].is_nan(), "row {}: {} for {}", r, value[r], v);
                    prop_assert!(row.iter().all(|&c| c == 0));
                }
                let starts = r == 0 || row != &code[(r - 1) * m..r * m];
                prop_assert_eq!(new_run[r], starts, "row {}", r);
            }
        }

        /// The bisection with certificates finds the first grid speed that does
        /// not fit, as trying all 64 in order does; and a certificate is never
        /// wrong at its speed or below.
        #[test]
        fn first_miss_is_the_first_in_order(
            a0 in 0.0f64..200.0, a1 in 0.0f64..200.0,
            s0 in prop_oneof![Just(0.0), 1e-4f64..0.05],
            per in prop_oneof![Just(0.0), 1e-4f64..2.0],
            lo in 1e-6f64..900.0, width in prop_oneof![1e-9f64..1e-6, 1e-3f64..1e3],
        ) {
            let chain = chain();
            let (angle, secs) = ([a0, a1], [s0, 0.0]);
            let net = chain_net(&chain, &angle, &secs);
            let prep = Prepared::new(&net).unwrap();
            let mut s = prep.scratch();
            let step = width / 65.0;
            let at = |i: usize| (i + 1) as f64 * step + lo;
            let plain = (0..GRID)
                .find(|&i| !plain_fits(&prep, at(i), &[per]))
                .unwrap_or(GRID);
            prop_assert_eq!(prep.first_miss(&at, &[per], &mut s).unwrap(), plain);
            for i in (0..GRID).step_by(7) {
                if prep.certified(at(i), &[per], &mut s).unwrap() {
                    for j in 0..=i {
                        prop_assert!(prep.fits(at(j), &[per], &mut s).unwrap());
                    }
                }
            }
        }
    }
}
