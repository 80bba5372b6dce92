//! Issue 20, longest path at scale: the build's radix grouping and the weights'
//! partition made during it, against the plain one-scatter build.
//!
//! Every plan (radix shifts of 0 to a few bits, so that buckets hold one key,
//! a few, or every key, and the last bucket is short; the partition on or off)
//! must give the same layout, entry for entry, as the plan without radix
//! passes, and the same times bit for bit; the partition must be a
//! permutation onto `inc`'s slots.

use super::event_graph::*;
use super::graph::*;
use super::layout::{Layout, Partition, Plan, PARTITION_MIN_ARCS, RADIX_MIN_ARCS};
use proptest::prelude::*;

fn bits(x: &[f64]) -> Vec<u64> {
    x.iter().map(|v| v.to_bits()).collect()
}

const PLAIN: Plan = Plan {
    tail_shift: None,
    head_shift: None,
    partition: false,
};

fn build(n: usize, s: &[i64], d: &[i64], plan: Plan) -> Result<EventGraph, CyclogramError> {
    let (n, src, dst) = validate_arcs(n as i64, s, d)?;
    EventGraph::with_plan(n, src, dst, plan)
}

fn same_layout(a: &Layout, b: &Layout) -> Result<(), TestCaseError> {
    prop_assert_eq!(&a.order, &b.order);
    prop_assert_eq!(&a.pos, &b.pos);
    prop_assert_eq!(&a.inc.ptr, &b.inc.ptr);
    prop_assert_eq!(&a.inc.arcs, &b.inc.arcs);
    Ok(())
}

/// The partition's invariants: `bucket` is a permutation of the arcs, bucket `b`
/// occupies block `b`'s range of `inc`, and `local` sends every entry to its
/// arc's slot in `inc`.
fn check_partition(lay: &Layout, part: &Partition, m: usize) -> Result<(), TestCaseError> {
    let inc = &lay.inc;
    let mut slot = vec![usize::MAX; m];
    for (j, &[_, e]) in inc.arcs.iter().enumerate() {
        slot[e as usize] = j;
    }
    let mut seen = vec![false; m];
    prop_assert_eq!(*part.start.last().unwrap() as usize, lay.order.len());
    let mut widest = 0;
    for b in part.start.windows(2) {
        let (j0, j1) = (
            inc.ptr[b[0] as usize] as usize,
            inc.ptr[b[1] as usize] as usize,
        );
        widest = widest.max(j1 - j0);
        for (&i, &j) in part.bucket.iter().zip(&slot) {
            let i = i as usize;
            if (j0..j1).contains(&j) {
                prop_assert!((j0..j1).contains(&i));
                prop_assert!(!seen[i]);
                seen[i] = true;
                prop_assert_eq!(j0 + part.local[i] as usize, j);
            }
        }
    }
    prop_assert!(seen.iter().all(|&x| x));
    prop_assert_eq!(part.widest, widest);
    Ok(())
}

/// A random DAG with parallel arcs, isolated events and tie-prone weights
/// (small integers, ±0.0, a few fractions).
fn dag() -> impl Strategy<Value = (usize, Vec<i64>, Vec<i64>, Vec<f64>)> {
    (1usize..70).prop_flat_map(|n| {
        let perm = Just((0..n as i64).collect::<Vec<_>>()).prop_shuffle();
        let weight = prop_oneof![
            (-3i32..6).prop_map(f64::from),
            Just(0.0),
            Just(-0.0),
            -50.0f64..100.0,
        ];
        let arcs = prop::collection::vec((0..n, 0..n, weight, 1usize..3), 0..250);
        (Just(n), perm, arcs).prop_map(|(n, perm, arcs)| {
            let (mut s, mut d, mut w) = (vec![], vec![], vec![]);
            for (a, b, x, copies) in arcs {
                let (lo, hi) = (a.min(b), a.max(b));
                if lo != hi && hi < (3 * n).div_ceil(4).max(2) {
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

fn shift() -> impl Strategy<Value = Option<u32>> {
    prop_oneof![Just(None), (0u32..4).prop_map(Some), Just(Some(12))]
}

proptest! {
    #[test]
    fn radix_build_is_the_plain_build(
        (n, s, d, w) in dag(),
        tail_shift in shift(),
        head_shift in shift(),
        partition in any::<bool>(),
    ) {
        let plan = Plan { tail_shift, head_shift, partition };
        let (a, b) = (build(n, &s, &d, plan).unwrap(), build(n, &s, &d, PLAIN).unwrap());
        same_layout(a.layout(), b.layout())?;
        prop_assert_eq!(a.partition().is_some(), partition && head_shift.is_some());
        if let Some(part) = a.partition() {
            check_partition(a.layout(), part, s.len())?;
        }
        // The single-row pass (through the partition when there is one), the
        // backward pass and the batch kernel: the plain build's bits.
        prop_assert_eq!(bits(&a.earliest(&w).unwrap()), bits(&b.earliest(&w).unwrap()));
        let (x, y) = (a.analyze(&w, None).unwrap(), b.analyze(&w, None).unwrap());
        prop_assert_eq!(bits(&x.latest), bits(&y.latest));
        prop_assert_eq!(&x.critical, &y.critical);
        let rows = 3;
        let all: Vec<f64> = (0..rows).flat_map(|r| w.iter().map(move |v| v - r as f64)).collect();
        let (p, q) = (
            a.earliest_batch(&all, rows, w.len(), Some(1)).unwrap(),
            b.earliest_batch(&all, rows, w.len(), Some(1)).unwrap(),
        );
        prop_assert_eq!(bits(&p), bits(&q));
    }

    /// Cycles: every plan rejects them with the plain build's error.
    #[test]
    fn radix_build_rejects_cycles_alike(
        (n, mut s, mut d, _w) in dag(),
        cycle in prop::collection::vec(0usize..70, 1..6),
        shift in shift(),
    ) {
        let cyc: Vec<i64> = cycle.iter().map(|&v| (v % n) as i64).collect();
        for i in 0..cyc.len() {
            s.push(cyc[i]);
            d.push(cyc[(i + 1) % cyc.len()]);
        }
        let plan = Plan { tail_shift: shift, head_shift: shift, partition: true };
        let (a, b) = (build(n, &s, &d, plan).err(), build(n, &s, &d, PLAIN).err());
        prop_assert!(b.is_some());
        prop_assert_eq!(a, b);
    }
}

/// The plan by size: one scatter below [`RADIX_MIN_ARCS`], radix passes from
/// it, the partition from [`PARTITION_MIN_ARCS`].
#[test]
fn plan_switches_at_its_thresholds() {
    for m in [
        RADIX_MIN_ARCS - 1,
        RADIX_MIN_ARCS,
        PARTITION_MIN_ARCS - 1,
        PARTITION_MIN_ARCS,
    ] {
        let p = Plan::for_size(m / 4, m);
        let radix = m >= RADIX_MIN_ARCS;
        assert_eq!(p.tail_shift.is_some(), radix, "{m}");
        assert_eq!(p.head_shift.is_some(), radix, "{m}");
        assert_eq!(p.partition, radix && m >= PARTITION_MIN_ARCS, "{m}");
    }
    // A million events: at most 64 buckets of 2^14 events.
    let p = Plan::for_size(1_000_000, 4_000_000);
    assert_eq!((p.tail_shift, p.head_shift), (Some(14), Some(14)));
}

/// A chain-and-fan DAG of `m` arcs on `n` events (every event but 0 has an arc
/// from the one before it, the rest are pseudo-random forward arcs), numbered
/// by a scrambling permutation: graphs just below and at the partition's
/// threshold, V not a multiple of the buckets, built by `new` (the size's own
/// plan) and plainly, give the same times bit for bit.
#[test]
fn sizes_around_the_partition_threshold_give_the_plain_times() {
    for (n, m) in [
        (300_007, PARTITION_MIN_ARCS - 1),
        (262_147, PARTITION_MIN_ARCS),
    ] {
        let scramble = |v: usize| ((v * 7919) % n) as i64; // 7919 is prime, n not a multiple
        let (mut s, mut d) = (Vec::with_capacity(m), Vec::with_capacity(m));
        let mut x = 12345u64;
        for e in 0..m {
            let (a, b) = if e + 1 < n {
                (e, e + 1)
            } else {
                x = x
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let a = (x >> 33) as usize % (n - 1);
                (a, a + 1 + (x >> 13) as usize % (n - 1 - a))
            };
            s.push(scramble(a));
            d.push(scramble(b));
        }
        let w: Vec<f64> = (0..m).map(|e| ((e * 37) % 101) as f64 - 20.0).collect();
        let g = EventGraph::new(n as i64, &s, &d).unwrap();
        assert_eq!(g.partition().is_some(), m >= PARTITION_MIN_ARCS);
        let plain = build(n, &s, &d, PLAIN).unwrap();
        assert_eq!(g.layout().inc.arcs, plain.layout().inc.arcs);
        assert_eq!(
            bits(&g.earliest(&w).unwrap()),
            bits(&plain.earliest(&w).unwrap())
        );
        let fused = longest_path(n as i64, &s, &d, &w).unwrap();
        assert_eq!(bits(&g.earliest(&w).unwrap()), bits(&fused));
    }
}
