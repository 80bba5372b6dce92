//! Issue 20: the positional layout against the layout it replaced.
//!
//! `Old` is the previous `EventGraph` verbatim in its arithmetic: times by event,
//! incoming arcs grouped by their head's position (input order within a group)
//! holding tail *events*, outgoing arcs likewise for the backward pass. Every
//! public result of the new layout must equal it bit for bit, on random DAGs with
//! duplicate arcs, isolated events, tied paths and signed zeros.

use super::event_graph::*;
use super::graph::*;
use super::layout::Partition;
use proptest::prelude::*;

struct Old {
    n: usize,
    src: Vec<u32>,
    dst: Vec<u32>,
    order: Vec<u32>,
    inc: Csr,
    out: Csr,
}

impl Old {
    fn new(n: usize, s: &[i64], d: &[i64]) -> Result<Old, CyclogramError> {
        let (n, src, dst) = validate_arcs(n as i64, s, d)?;
        let order =
            topological_order(n, &src, &dst).map_err(|events| CyclogramError::Cycle { events })?;
        let mut pos = vec![0usize; n];
        for (k, &v) in order.iter().enumerate() {
            pos[v as usize] = k;
        }
        let m = src.len();
        let inc = Csr::build(n, |e| pos[dst[e] as usize], |e| src[e], m);
        let out = Csr::build(n, |e| pos[src[e] as usize], |e| dst[e], m);
        Ok(Old {
            n,
            src,
            dst,
            order,
            inc,
            out,
        })
    }

    fn forward(&self, w: &[f64]) -> Vec<f64> {
        let mut t = vec![0.0; self.n];
        for (k, &v) in self.order.iter().enumerate() {
            let r = self.inc.range(k);
            let mut best = if r.is_empty() { 0.0 } else { f64::NEG_INFINITY };
            for (&s, &e) in self.inc.other[r.clone()].iter().zip(&self.inc.edge[r]) {
                let c = t[s as usize] + w[e as usize];
                best = if c > best { c } else { best };
            }
            t[v as usize] = best;
        }
        t
    }

    fn backward(&self, w: &[f64], horizon: f64) -> Vec<f64> {
        let mut t = vec![0.0; self.n];
        for (k, &v) in self.order.iter().enumerate().rev() {
            let mut best = horizon;
            let r = self.out.range(k);
            for (&d, &e) in self.out.other[r.clone()].iter().zip(&self.out.edge[r]) {
                best = best.min(t[d as usize] - w[e as usize]);
            }
            t[v as usize] = best;
        }
        t
    }

    fn analyze(&self, w: &[f64], horizon: Option<f64>) -> Analysis {
        let early = self.forward(w);
        let horizon = horizon.unwrap_or_else(|| early.iter().copied().fold(0.0f64, f64::max));
        let late = self.backward(w, horizon);
        let scale = early
            .iter()
            .chain(w.iter())
            .fold(horizon.abs().max(1.0), |a, &b| a.max(b.abs()));
        let tolerance = 1e-9 * scale;
        let m = self.src.len();
        let (mut total, mut free, mut critical) = (vec![0.0; m], vec![0.0; m], vec![false; m]);
        for e in 0..m {
            let (x, y) = (self.src[e] as usize, self.dst[e] as usize);
            total[e] = late[y] - early[x] - w[e];
            free[e] = early[y] - early[x] - w[e];
            critical[e] = total[e].abs() <= tolerance;
        }
        Analysis {
            earliest: early,
            latest: late,
            total_slack: total,
            free_slack: free,
            critical,
            horizon,
            tolerance,
        }
    }
}

fn bits(x: &[f64]) -> Vec<u64> {
    x.iter().map(|v| v.to_bits()).collect()
}

/// A random DAG with duplicate arcs, isolated events and tie-prone weights:
/// small integers (many equal path lengths), ±0.0, and a few fractions.
fn tied_dag() -> impl Strategy<Value = (usize, Vec<i64>, Vec<i64>, Vec<f64>)> {
    (1usize..50).prop_flat_map(|n| {
        let perm = Just((0..n as i64).collect::<Vec<_>>()).prop_shuffle();
        let weight = prop_oneof![
            (-3i32..6).prop_map(f64::from),
            Just(0.0),
            Just(-0.0),
            -50.0f64..100.0,
        ];
        // Arcs among the first half of the ranks only, so that events are often
        // isolated; each arc drawn may be repeated (parallel arcs).
        let arcs = prop::collection::vec((0..n, 0..n, weight, 1usize..3), 0..150);
        (Just(n), perm, arcs).prop_map(|(n, perm, arcs)| {
            let (mut s, mut d, mut w) = (vec![], vec![], vec![]);
            for (a, b, x, copies) in arcs {
                let (lo, hi) = (a.min(b), a.max(b));
                if lo != hi && hi < n.div_ceil(2).max(2) {
                    for c in 0..copies {
                        s.push(perm[lo]);
                        d.push(perm[hi]);
                        w.push(if c == 0 { x } else { x - c as f64 + 1.0 });
                    }
                }
            }
            (n, s, d, w)
        })
    })
}

proptest! {
    #[test]
    fn positional_layout_is_the_old_one_bit_for_bit(
        (n, s, d, w) in tied_dag(),
        horizon in prop_oneof![Just(None), Just(Some(-0.0)), Just(Some(0.0)), (-10i32..300).prop_map(|h| Some(f64::from(h)))],
    ) {
        let old = Old::new(n, &s, &d).unwrap();
        let g = EventGraph::new(n as i64, &s, &d).unwrap();
        prop_assert_eq!(g.topological_order(), &old.order[..]);
        let want = old.forward(&w);
        prop_assert_eq!(bits(&g.earliest(&w).unwrap()), bits(&want));
        let h = horizon.unwrap_or(17.0);
        prop_assert_eq!(bits(&g.latest(&w, h).unwrap()), bits(&old.backward(&w, h)));
        let (a, b) = (g.analyze(&w, horizon).unwrap(), old.analyze(&w, horizon));
        prop_assert_eq!(bits(&a.earliest), bits(&b.earliest));
        prop_assert_eq!(bits(&a.latest), bits(&b.latest));
        prop_assert_eq!(bits(&a.total_slack), bits(&b.total_slack));
        prop_assert_eq!(bits(&a.free_slack), bits(&b.free_slack));
        prop_assert_eq!(&a.critical, &b.critical);
        prop_assert_eq!(a.horizon.to_bits(), b.horizon.to_bits());
        prop_assert_eq!(a.tolerance.to_bits(), b.tolerance.to_bits());
        // The batch kernel (explicit SIMD) gives each row the same times.
        let rows = 11;
        let m = w.len();
        let all: Vec<f64> = (0..rows)
            .flat_map(|r| w.iter().map(move |x| if r == 0 { *x } else { (x * r as f64).round() - 1.0 }))
            .collect();
        for threads in [1, 2] {
            let batch = g.earliest_batch(&all, rows, m, Some(threads)).unwrap();
            for r in 0..rows {
                prop_assert_eq!(bits(&batch[r * n..(r + 1) * n]), bits(&old.forward(&all[r * m..(r + 1) * m])));
            }
        }
        // The one-shot kernel (pushes along arcs in another order) agrees in value.
        let fused = longest_path(n as i64, &s, &d, &w).unwrap();
        prop_assert_eq!(bits(&fused), bits(&want));
    }

    /// The large-graph forward pass (weights permuted in two streaming passes
    /// through blocks of positions) is the plain pass bit for bit, whatever the
    /// block size: blocks of one event, of a few, or one block for everything.
    #[test]
    fn partitioned_forward_is_the_plain_pass_bit_for_bit(
        (n, s, d, w) in tied_dag(),
        block in prop_oneof![Just(1usize), 2usize..9, Just(1usize << 17)],
    ) {
        let g = EventGraph::new(n as i64, &s, &d).unwrap();
        let dst: Vec<u32> = d.iter().map(|&x| x as u32).collect();
        let part = Partition::new(g.layout(), &dst, block);
        let (mut t, mut tpos) = (vec![f64::NAN; n], vec![f64::NAN; n]);
        g.forward_through(&part, &w, &mut t, &mut tpos);
        prop_assert_eq!(bits(&t), bits(&Old::new(n, &s, &d).unwrap().forward(&w)));
    }

    /// Cycles are rejected by the new build with the old build's error (the same
    /// cycle named), whatever else the graph holds.
    #[test]
    fn cycles_are_rejected_with_the_old_error(
        (n, mut s, mut d, _w) in tied_dag(),
        cycle in prop::collection::vec(0usize..50, 1..6),
    ) {
        let cyc: Vec<i64> = cycle.iter().map(|&v| (v % n) as i64).collect();
        for i in 0..cyc.len() {
            s.push(cyc[i]);
            d.push(cyc[(i + 1) % cyc.len()]);
        }
        let old = Old::new(n, &s, &d).err();
        let new = EventGraph::new(n as i64, &s, &d).err();
        prop_assert!(old.is_some());
        prop_assert_eq!(new, old);
    }
}

/// The documented tie rule: every arc of every longest path is critical, on a
/// graph made of equal-length parallel routes and duplicate arcs.
#[test]
fn ties_mark_every_longest_route() {
    // 0 -> 1 -> 3 and 0 -> 2 -> 3 both 30; 0 -> 3 twice (30 and 10); 4 isolated.
    let (s, d) = ([0, 1, 0, 2, 0, 0], [1, 3, 2, 3, 3, 3]);
    let w = [10.0, 20.0, 20.0, 10.0, 30.0, 10.0];
    let g = EventGraph::new(5, &s, &d).unwrap();
    let a = g.analyze(&w, None).unwrap();
    assert_eq!(a.earliest, vec![0.0, 10.0, 20.0, 30.0, 0.0]);
    assert_eq!(a.critical, vec![true, true, true, true, true, false]);
    assert_eq!(a.total_slack[5], 20.0);
    let old = Old::new(5, &s, &d).unwrap().analyze(&w, None);
    assert_eq!(a, old);
}
