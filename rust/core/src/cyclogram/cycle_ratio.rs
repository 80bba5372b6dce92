//! Maximum cycle ratio (Howard's policy iteration) and the speed limit of a cyclic
//! schedule.
//!
//! A machine repeats its cycle: an operation may end in the next cycle (an arc of
//! height 1). With occurrence angles `p` and a cycle of `T` degrees, every arc
//! demands `p(y) + T·h(x, y) >= p(x) + w(x, y)`. Such a system is feasible exactly
//! when no cycle of the graph has `Σw > T·Σh`, so the shortest cycle the machine
//! can have is the **maximum cycle ratio** `ρ = max over cycles C of Σw(C) / Σh(C)`
//! (the arcs of height 0 must form a DAG, so `Σh > 0` on every cycle).
//!
//! Operations bound in seconds rather than degrees take `6·n·s` degrees at `n` rpm
//! (360° per revolution, n/60 revolutions per second), so `ρ(n)` is the maximum of
//! finitely many lines in `n`: convex, piecewise linear and non-decreasing. The
//! highest admissible speed solves `ρ(n) = T`; Newton's method on that convex
//! function, started to the right of the root, steps from one critical cycle to
//! the next and stops after finitely many cycles (Dinkelbach's scheme).
//!
//! Howard's algorithm follows Cochet-Terrasson, Cohen, Gaubert, McGettrick and
//! Quadrat (1998), "Numerical computation of spectral elements in max-plus
//! algebra", in the ratio form of Dasdan (2004), "Experimental analysis of the
//! fastest optimum cycle ratio and mean algorithms".

use crate::units::DEG_PER_S_PER_RPM;

use super::graph::{check_finite, topological_order, validate_arcs, CyclogramError};

/// Smallest non-zero height or duration: both end up as denominators (of the
/// cycle ratio, of the Newton step in speed), where a denormal would give inf.
pub const MIN_DIVISOR: f64 = 1e-12;

/// A cycle of the graph and its ratio Σw / Σh.
#[derive(Debug, Clone, PartialEq)]
pub struct CycleRatio {
    /// Σw / Σh over the cycle.
    pub ratio: f64,
    /// The arcs of the cycle, in order (each arc's head is the next arc's tail).
    pub arcs: Vec<usize>,
}

/// The highest speed at which a cyclic schedule fits in its cycle.
#[derive(Debug, Clone, PartialEq)]
pub enum SpeedLimit {
    /// No cycle of the graph contains an operation bound in seconds (or the graph
    /// has no cycle): the cyclogram fits at any speed.
    Unlimited,
    /// The highest speed (rpm) and the cycle that limits it; `cycle.ratio` is the
    /// cycle's length in degrees at that speed (= the cycle angle).
    Limited { rpm: f64, cycle: CycleRatio },
    /// Even at standstill the minimum angles alone do not fit in the cycle angle:
    /// the cycle with the largest ratio at zero speed.
    Infeasible { cycle: CycleRatio },
}

struct Graph<'a> {
    n: usize,
    src: &'a [u32],
    dst: &'a [u32],
    heights: &'a [f64],
    out_ptr: Vec<usize>,
    out_arc: Vec<u32>,
    /// Vertices that lie on or between cycles (others cannot be on a cycle).
    alive: Vec<bool>,
}

impl<'a> Graph<'a> {
    fn new(n: usize, src: &'a [u32], dst: &'a [u32], heights: &'a [f64]) -> Self {
        let m = src.len();
        let mut out_ptr = vec![0usize; n + 1];
        for &s in src {
            out_ptr[s as usize + 1] += 1;
        }
        for k in 0..n {
            out_ptr[k + 1] += out_ptr[k];
        }
        let mut fill = out_ptr.clone();
        let mut out_arc = vec![0u32; m];
        for (e, &s) in src.iter().enumerate() {
            out_arc[fill[s as usize]] = e as u32;
            fill[s as usize] += 1;
        }
        // Peel vertices without outgoing or incoming arcs until none is left: what
        // remains is every vertex that can lie on a cycle, and each has an arc out.
        let mut outdeg: Vec<usize> = (0..n).map(|v| out_ptr[v + 1] - out_ptr[v]).collect();
        let mut indeg = vec![0usize; n];
        for &d in dst {
            indeg[d as usize] += 1;
        }
        let mut in_ptr = vec![0usize; n + 1];
        for &d in dst {
            in_ptr[d as usize + 1] += 1;
        }
        for k in 0..n {
            in_ptr[k + 1] += in_ptr[k];
        }
        let mut fill = in_ptr.clone();
        let mut in_arc = vec![0u32; m];
        for (e, &d) in dst.iter().enumerate() {
            in_arc[fill[d as usize]] = e as u32;
            fill[d as usize] += 1;
        }
        let mut alive = vec![true; n];
        let mut stack: Vec<usize> = (0..n)
            .filter(|&v| outdeg[v] == 0 || indeg[v] == 0)
            .collect();
        while let Some(v) = stack.pop() {
            if !alive[v] {
                continue;
            }
            alive[v] = false;
            for &e in &in_arc[in_ptr[v]..in_ptr[v + 1]] {
                let u = src[e as usize] as usize;
                outdeg[u] -= 1;
                if alive[u] && outdeg[u] == 0 {
                    stack.push(u);
                }
            }
            for &e in &out_arc[out_ptr[v]..out_ptr[v + 1]] {
                let u = dst[e as usize] as usize;
                indeg[u] -= 1;
                if alive[u] && indeg[u] == 0 {
                    stack.push(u);
                }
            }
        }
        Graph {
            n,
            src,
            dst,
            heights,
            out_ptr,
            out_arc,
            alive,
        }
    }

    fn out(&self, v: usize) -> impl Iterator<Item = usize> + '_ {
        self.out_arc[self.out_ptr[v]..self.out_ptr[v + 1]]
            .iter()
            .map(|&e| e as usize)
            .filter(|&e| self.alive[self.dst[e] as usize])
    }

    /// Howard's policy iteration for the maximum of Σw/Σh over cycles.
    fn howard(&self, w: &[f64]) -> Result<Option<CycleRatio>, CyclogramError> {
        let n = self.n;
        let live: Vec<usize> = (0..n).filter(|&v| self.alive[v]).collect();
        if live.is_empty() {
            return Ok(None);
        }
        // Tolerances scale with the largest path weight that can occur.
        let scale = 1.0 + w.iter().map(|x| x.abs()).sum::<f64>();
        let tol = 1e-12 * scale;
        // Initial policy: the heaviest arc out of each vertex.
        let mut policy = vec![usize::MAX; n];
        for &v in &live {
            policy[v] = self
                .out(v)
                .max_by(|&a, &b| w[a].total_cmp(&w[b]))
                .unwrap_or(usize::MAX);
        }
        let mut eta = vec![0.0f64; n];
        let mut x = vec![0.0f64; n];
        let mut root = vec![usize::MAX; n];
        let max_iter = 100 + 10 * self.src.len();
        for _ in 0..max_iter {
            self.evaluate(&live, &policy, w, &mut eta, &mut x, &mut root);
            // First improve the ratio: move to an arc that reaches a better cycle.
            let mut changed = false;
            for &v in &live {
                let mut best = eta[v] + tol;
                let mut pick = None;
                for e in self.out(v) {
                    let u = self.dst[e] as usize;
                    if eta[u] > best {
                        best = eta[u];
                        pick = Some(e);
                    }
                }
                if let Some(e) = pick {
                    policy[v] = e;
                    changed = true;
                }
            }
            if changed {
                continue;
            }
            // Then improve the bias among arcs that keep the ratio.
            for &v in &live {
                let mut best = x[v] + tol;
                let mut pick = None;
                for e in self.out(v) {
                    let u = self.dst[e] as usize;
                    if (eta[u] - eta[v]).abs() <= tol {
                        let val = w[e] - eta[v] * self.heights[e] + x[u];
                        if val > best {
                            best = val;
                            pick = Some(e);
                        }
                    }
                }
                if let Some(e) = pick {
                    policy[v] = e;
                    changed = true;
                }
            }
            if !changed {
                let best = live
                    .iter()
                    .copied()
                    .max_by(|&a, &b| eta[a].total_cmp(&eta[b]))
                    .unwrap_or(live[0]);
                let start = root[best];
                let mut arcs = vec![policy[start]];
                let mut v = self.dst[policy[start]] as usize;
                while v != start && arcs.len() <= n {
                    arcs.push(policy[v]);
                    v = self.dst[policy[v]] as usize;
                }
                let (sw, sh) = arcs
                    .iter()
                    .fold((0.0, 0.0), |(a, b), &e| (a + w[e], b + self.heights[e]));
                return Ok(Some(CycleRatio {
                    ratio: sw / sh,
                    arcs,
                }));
            }
        }
        Err(CyclogramError::NotConverged {
            iterations: max_iter,
        })
    }

    /// Ratio `eta` and bias `x` of every live vertex under `policy`; `root[v]` is a
    /// fixed vertex on the policy cycle that `v` reaches.
    fn evaluate(
        &self,
        live: &[usize],
        policy: &[usize],
        w: &[f64],
        eta: &mut [f64],
        x: &mut [f64],
        root: &mut [usize],
    ) {
        const NEW: u32 = u32::MAX;
        const DONE: u32 = u32::MAX - 1;
        let mut mark = vec![NEW; self.n];
        let mut path: Vec<usize> = Vec::new();
        for (walk_id, &start) in live.iter().enumerate() {
            if mark[start] != NEW {
                continue;
            }
            path.clear();
            let mut v = start;
            while mark[v] == NEW {
                mark[v] = walk_id as u32;
                path.push(v);
                v = self.dst[policy[v]] as usize;
            }
            // `v` is either on a cycle closed by this walk or already evaluated.
            let closes_here = mark[v] == walk_id as u32;
            if closes_here {
                let (mut sw, mut sh) = (0.0, 0.0);
                let mut u = v;
                loop {
                    let e = policy[u];
                    sw += w[e];
                    sh += self.heights[e];
                    u = self.dst[e] as usize;
                    if u == v {
                        break;
                    }
                }
                eta[v] = sw / sh;
                x[v] = 0.0;
                root[v] = v;
            }
            for &p in path.iter().rev() {
                if closes_here && p == v {
                    continue;
                }
                let e = policy[p];
                let s = self.dst[e] as usize;
                eta[p] = eta[s];
                x[p] = w[e] - eta[p] * self.heights[e] + x[s];
                root[p] = root[s];
            }
            for &p in &path {
                mark[p] = DONE;
            }
        }
    }
}

fn check_heights(
    n: usize,
    src: &[u32],
    dst: &[u32],
    heights: &[f64],
) -> Result<(), CyclogramError> {
    if heights.len() != src.len() {
        return Err(CyclogramError::WeightLength {
            field: "heights",
            expected: src.len(),
            got: heights.len(),
        });
    }
    check_finite(
        "heights",
        heights,
        0,
        "heights (machine cycles an arc crosses)",
    )?;
    if let Some((i, &h)) = heights
        .iter()
        .enumerate()
        .find(|(_, &h)| h < 0.0 || (h > 0.0 && h < MIN_DIVISOR))
    {
        return Err(CyclogramError::OutOfDomain {
            field: "heights",
            position: i,
            value: h,
            what: "heights count the machine cycles an arc crosses: 0, or at least 1e-12",
        });
    }
    let (zs, zd): (Vec<u32>, Vec<u32>) = (0..src.len())
        .filter(|&e| heights[e] == 0.0)
        .map(|e| (src[e], dst[e]))
        .unzip();
    topological_order(n, &zs, &zd).map_err(|events| CyclogramError::ZeroHeightCycle { events })?;
    Ok(())
}

fn check_weights(
    field: &'static str,
    m: usize,
    w: &[f64],
    what: &'static str,
) -> Result<(), CyclogramError> {
    if w.len() != m {
        return Err(CyclogramError::WeightLength {
            field,
            expected: m,
            got: w.len(),
        });
    }
    check_finite(field, w, 0, what)
}

/// Maximum over the cycles of the graph of Σweights / Σheights, with a cycle that
/// attains it; `None` when the graph has no cycle.
pub fn max_cycle_ratio(
    n_events: i64,
    src: &[i64],
    dst: &[i64],
    weights: &[f64],
    heights: &[f64],
) -> Result<Option<CycleRatio>, CyclogramError> {
    let (n, s, d) = validate_arcs(n_events, src, dst)?;
    check_weights("weights", s.len(), weights, "phase angles [deg]")?;
    check_heights(n, &s, &d, heights)?;
    Graph::new(n, &s, &d, heights).howard(weights)
}

/// The highest main-shaft speed (rpm) at which arcs with minimum angles
/// `angle_deg` plus minimum durations `seconds` fit in a cycle of `cycle_deg`.
///
/// An arc's minimum phase angle at `n` rpm is `angle_deg + 6·n·seconds`.
pub fn max_speed(
    n_events: i64,
    src: &[i64],
    dst: &[i64],
    angle_deg: &[f64],
    seconds: &[f64],
    heights: &[f64],
    cycle_deg: f64,
) -> Result<SpeedLimit, CyclogramError> {
    let (n, s, d) = validate_arcs(n_events, src, dst)?;
    let m = s.len();
    check_weights("angle_deg", m, angle_deg, "minimum angles [deg]")?;
    check_weights("seconds", m, seconds, "minimum durations [s]")?;
    if let Some((i, &v)) = seconds
        .iter()
        .enumerate()
        .find(|(_, &v)| v < 0.0 || (v > 0.0 && v < MIN_DIVISOR))
    {
        return Err(CyclogramError::OutOfDomain {
            field: "seconds",
            position: i,
            value: v,
            what: "minimum durations must be 0 or at least 1e-12 seconds",
        });
    }
    if !(cycle_deg > 0.0 && cycle_deg <= super::graph::MAX_ABS_VALUE) {
        return Err(CyclogramError::bad_scalar(
            "cycle_deg",
            cycle_deg,
            "the cycle must be a finite positive number of degrees (360 for one revolution)",
        ));
    }
    check_heights(n, &s, &d, heights)?;
    let g = Graph::new(n, &s, &d, heights);
    let fits = |ratio: f64| ratio <= cycle_deg * (1.0 + 1e-12);

    let Some(at_rest) = g.howard(angle_deg)? else {
        return Ok(SpeedLimit::Unlimited);
    };
    if !fits(at_rest.ratio) {
        return Ok(SpeedLimit::Infeasible { cycle: at_rest });
    }
    // Degrees per rpm of each arc; the cycle with the largest of these per height
    // grows fastest with speed.
    let slope: Vec<f64> = seconds.iter().map(|&t| DEG_PER_S_PER_RPM * t).collect();
    let growth = match g.howard(&slope)? {
        Some(c) if c.ratio > 0.0 => c.ratio,
        _ => return Ok(SpeedLimit::Unlimited),
    };
    let weights_at = |rpm: f64| -> Vec<f64> {
        angle_deg
            .iter()
            .zip(&slope)
            .map(|(a, k)| a + rpm * k)
            .collect()
    };
    // ρ(n) <= ρ(0) + n·growth, so the schedule fits up to n_lo; find a speed to the
    // right of the root by doubling past it.
    let n_lo = ((cycle_deg - at_rest.ratio) / growth).max(0.0);
    let mut rpm = 2.0 * n_lo + 1.0;
    let mut current = g.howard(&weights_at(rpm))?;
    let mut doublings = 0;
    while current.as_ref().is_none_or(|c| fits(c.ratio)) {
        doublings += 1;
        if doublings > 200 {
            return Ok(SpeedLimit::Unlimited);
        }
        rpm *= 2.0;
        current = g.howard(&weights_at(rpm))?;
    }
    // Newton from the right on the convex ρ(n) = cycle_deg.
    for _ in 0..10_000 {
        let Some(c) = current else {
            return Ok(SpeedLimit::Unlimited);
        };
        let (sa, sk, sh) = c.arcs.iter().fold((0.0, 0.0, 0.0), |(a, k, h), &e| {
            (a + angle_deg[e], k + slope[e], h + heights[e])
        });
        if sk <= 0.0 {
            // A cycle without time-bound arcs above the cycle angle would already
            // have failed at rest; guard anyway instead of dividing by zero.
            return Ok(SpeedLimit::Infeasible { cycle: c });
        }
        let next = ((cycle_deg * sh - sa) / sk).max(0.0);
        let after = g.howard(&weights_at(next))?;
        let done = after.as_ref().is_none_or(|a| fits(a.ratio)) || next >= rpm;
        if done {
            let ratio = (sa + next * sk) / sh;
            return Ok(SpeedLimit::Limited {
                rpm: next,
                cycle: CycleRatio {
                    ratio,
                    arcs: c.arcs,
                },
            });
        }
        rpm = next;
        current = after;
    }
    Err(CyclogramError::NotConverged { iterations: 10_000 })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Brute force: enumerate simple cycles by DFS from each start (small graphs).
    fn brute_max_ratio(n: usize, s: &[i64], d: &[i64], w: &[f64], h: &[f64]) -> Option<f64> {
        let mut best: Option<f64> = None;
        #[allow(clippy::too_many_arguments)]
        fn dfs(
            start: usize,
            v: usize,
            s: &[i64],
            d: &[i64],
            w: &[f64],
            h: &[f64],
            on: &mut Vec<bool>,
            acc: (f64, f64),
            best: &mut Option<f64>,
        ) {
            for e in 0..s.len() {
                if s[e] as usize != v {
                    continue;
                }
                let u = d[e] as usize;
                let a = (acc.0 + w[e], acc.1 + h[e]);
                if u == start {
                    let r = a.0 / a.1;
                    *best = Some(best.map_or(r, |b: f64| b.max(r)));
                } else if u > start && !on[u] {
                    on[u] = true;
                    dfs(start, u, s, d, w, h, on, a, best);
                    on[u] = false;
                }
            }
        }
        for start in 0..n {
            let mut on = vec![false; n];
            on[start] = true;
            dfs(start, start, s, d, w, h, &mut on, (0.0, 0.0), &mut best);
        }
        best
    }

    /// Random graphs whose height-0 arcs go forward in index order (so they are
    /// acyclic) and whose backward arcs have height 1 or 2.
    fn cyclic() -> impl Strategy<Value = (usize, Vec<i64>, Vec<i64>, Vec<f64>, Vec<f64>)> {
        (2usize..8).prop_flat_map(|n| {
            prop::collection::vec((0..n, 0..n, -30.0f64..100.0, 1u8..3), 1..16).prop_map(
                move |arcs| {
                    let (mut s, mut d, mut w, mut h) = (vec![], vec![], vec![], vec![]);
                    for (a, b, x, k) in arcs {
                        s.push(a as i64);
                        d.push(b as i64);
                        w.push(x);
                        h.push(if a < b { 0.0 } else { k as f64 });
                    }
                    (n, s, d, w, h)
                },
            )
        })
    }

    proptest! {
        #[test]
        fn howard_matches_enumeration((n, s, d, w, h) in cyclic()) {
            let got = max_cycle_ratio(n as i64, &s, &d, &w, &h).unwrap();
            let want = brute_max_ratio(n, &s, &d, &w, &h);
            match (got, want) {
                (None, None) => {}
                (Some(c), Some(r)) => {
                    prop_assert!((c.ratio - r).abs() <= 1e-9 * (1.0 + r.abs()), "{} vs {r}", c.ratio);
                    // The reported arcs form a closed walk with that ratio.
                    for k in 0..c.arcs.len() {
                        let next = c.arcs[(k + 1) % c.arcs.len()];
                        prop_assert_eq!(d[c.arcs[k]], s[next]);
                    }
                    let sw: f64 = c.arcs.iter().map(|&e| w[e]).sum();
                    let sh: f64 = c.arcs.iter().map(|&e| h[e]).sum();
                    prop_assert!((sw / sh - r).abs() <= 1e-9 * (1.0 + r.abs()));
                }
                (g, w) => prop_assert!(false, "{g:?} vs {w:?}"),
            }
        }

        #[test]
        fn speed_limit_is_the_feasibility_edge(
            (n, s, d, a, h) in cyclic(),
            secs in prop::collection::vec(0.0f64..0.05, 16),
            cycle in 200.0f64..400.0,
        ) {
            let m = s.len();
            let a: Vec<f64> = a.iter().map(|x| x * 0.3).collect();
            let secs = &secs[..m];
            let ratio_at = |rpm: f64| {
                let w: Vec<f64> = (0..m).map(|e| a[e] + 6.0 * rpm * secs[e]).collect();
                brute_max_ratio(n, &s, &d, &w, &h)
            };
            match max_speed(n as i64, &s, &d, &a, secs, &h, cycle).unwrap() {
                SpeedLimit::Limited { rpm, cycle: c } => {
                    let at = ratio_at(rpm).unwrap();
                    prop_assert!((at - cycle).abs() <= 1e-7 * cycle, "rho({rpm}) = {at}");
                    prop_assert!((c.ratio - cycle).abs() <= 1e-7 * cycle);
                    prop_assert!(ratio_at(rpm * 1.001 + 1e-6).unwrap() > cycle);
                }
                SpeedLimit::Unlimited => {
                    prop_assert!(ratio_at(1e9).is_none_or(|r| r <= cycle * (1.0 + 1e-9)));
                }
                SpeedLimit::Infeasible { cycle: c } => {
                    prop_assert!(ratio_at(0.0).unwrap() > cycle);
                    prop_assert!(c.ratio > cycle);
                }
            }
        }
    }

    #[test]
    fn two_cycles_hand_computed() {
        // 0 -> 1 (100°) -> 0 (h 1, 200°): ratio 300. 1 -> 2 (0.1 s) -> 1 (h 1, 60°).
        let (s, d) = ([0i64, 1, 1, 2], [1i64, 0, 2, 1]);
        let a = [100.0, 200.0, 0.0, 60.0];
        let t = [0.0, 0.0, 0.1, 0.0];
        let h = [0.0, 1.0, 0.0, 1.0];
        let r = max_cycle_ratio(3, &s, &d, &a, &h).unwrap().unwrap();
        assert_eq!(r.ratio, 300.0);
        // The second cycle needs 60 + 0.6 n <= 360  =>  n <= 500 rpm.
        match max_speed(3, &s, &d, &a, &t, &h, 360.0).unwrap() {
            SpeedLimit::Limited { rpm, cycle } => {
                assert!((rpm - 500.0).abs() < 1e-9, "{rpm}");
                let mut arcs = cycle.arcs.clone();
                arcs.sort();
                assert_eq!(arcs, vec![2, 3]);
            }
            other => panic!("{other:?}"),
        }
        // With a 250° cycle the first loop (300°) does not fit at any speed.
        assert!(matches!(
            max_speed(3, &s, &d, &a, &t, &h, 250.0).unwrap(),
            SpeedLimit::Infeasible { .. }
        ));
    }

    #[test]
    fn values_that_would_overflow_are_errors() {
        // Finite but huge: sums would overflow to inf and ratios to NaN.
        let big = 1e308;
        assert!(max_cycle_ratio(2, &[0, 1], &[1, 0], &[big, big], &[0.0, 1.0]).is_err());
        assert!(max_cycle_ratio(2, &[0, 1], &[1, 0], &[1.0, 1.0], &[0.0, 1e-320]).is_err());
        assert!(max_speed(
            3,
            &[0, 1],
            &[1, 2],
            &[-big, big],
            &[1.0, 0.0],
            &[0.0, 0.0],
            360.0
        )
        .is_err());
        assert!(max_speed(2, &[0], &[1], &[1.0], &[1e-300], &[0.0], 360.0).is_err());
        assert!(max_speed(2, &[0], &[1], &[1.0], &[0.0], &[0.0], 1e300).is_err());
    }

    #[test]
    fn bad_heights_are_errors() {
        assert!(matches!(
            max_cycle_ratio(2, &[0, 1], &[1, 0], &[1.0, 1.0], &[0.0, 0.0]),
            Err(CyclogramError::ZeroHeightCycle { .. })
        ));
        assert!(matches!(
            max_cycle_ratio(2, &[0, 1], &[1, 0], &[1.0, 1.0], &[0.0, -1.0]),
            Err(CyclogramError::OutOfDomain {
                field: "heights",
                ..
            })
        ));
        assert!(matches!(
            max_cycle_ratio(2, &[0, 1], &[1, 0], &[1.0, 1.0], &[0.0, f64::NAN]),
            Err(CyclogramError::NonFinite {
                field: "heights",
                ..
            })
        ));
        assert!(max_speed(2, &[0], &[1], &[1.0], &[0.0], &[0.0], 0.0).is_err());
        assert!(max_speed(2, &[0], &[1], &[1.0], &[-1.0], &[0.0], 360.0).is_err());
        assert_eq!(
            max_speed(2, &[0], &[1], &[1.0], &[1.0], &[0.0], 360.0).unwrap(),
            SpeedLimit::Unlimited
        );
    }
}
