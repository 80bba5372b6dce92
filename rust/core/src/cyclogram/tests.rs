use super::difference::*;
use super::event_graph::*;
use super::graph::*;
use crate::tile::transpose;
use proptest::prelude::*;

/// Issue 16 item 20: a chain of constraints given head-first took one
/// Bellman–Ford pass per arc (the machine's speed limit was quadratic in its
/// operations: 4000 operations 108 s). In depth-first order each run settles in
/// two passes whatever the input order; the value is the chain's sum (closed form).
#[test]
fn item20_a_chain_settles_in_two_passes_whatever_its_order() {
    let n = 2000usize;
    // x[i] - x[i+1] <= -1 (x[i+1] >= x[i] + 1): arcs i+1 -> i of weight -1, and
    // the span bound x[n-1] - x[0] <= 10 000 as the arc 0 -> n-1. Largest
    // x[0] - x[n-1] is -(n-1): the shortest path from n-1 to 0 along the chain.
    for reversed in [false, true] {
        let mut src: Vec<i64> = (0..n as i64 - 1).map(|i| i + 1).collect();
        let mut dst: Vec<i64> = (0..n as i64 - 1).collect();
        if reversed {
            src.reverse();
            dst.reverse();
        }
        src.push(0);
        dst.push(n as i64 - 1);
        let mut w = vec![-1.0; n - 1];
        w.push(10_000.0);
        let sys = Differences::new(n as i64, &src, &dst, n as i64 - 1, 0).unwrap();
        let mut work = DifferenceWork::new(n);
        let value = sys.solve_row(&w, &mut work);
        assert_eq!(value, -((n - 1) as f64));
        assert_eq!(work.path.len(), n - 1);
        // Two runs of (one settling pass + one that changes nothing), plus at
        // most one pass per back arc (the span arc closes the only cycle).
        assert!(
            work.passes <= 6,
            "{} passes (reversed = {reversed})",
            work.passes
        );
    }
}

/// A cycle a little below 0 but above -eps settles (the core's tolerance), yet has
/// no exact potential: its first run leaves no certificate (the speed kernels would
/// otherwise skip the first run at lower speeds on a false proof). A cycle far
/// below -eps stops the run at a cycle of predecessors, which is kept, and
/// `cycle_below` takes it for the row's verdict only below -2·|C|·eps.
#[test]
fn a_tolerated_cycle_leaves_no_certificate_and_the_cycle_test_keeps_its_margin() {
    let sys = Differences::new(2, &[0, 1], &[1, 0], 0, 1).unwrap();
    let mut work = DifferenceWork::new(2);
    // eps of these rows: DIFFERENCE_RTOL·(1 + max|w|)·n, max|w| ≈ 1.
    let eps = DIFFERENCE_RTOL * 2.0 * 2.0;
    let row = |d: f64| [1.0, -1.0 - d];
    let v = sys.solve_row(&row(0.0), &mut work);
    assert_eq!(v, 1.0);
    assert!(work.potential.is_some(), "an exact cycle has a potential");
    let v = sys.solve_row(&row(eps / 4.0), &mut work);
    assert_eq!(v, 1.0, "tolerated");
    assert_eq!(work.potential, None, "no exact potential: no certificate");
    assert!(!sys.cycle_below(&row(eps / 4.0), &[0, 1]));
    assert!(sys.solve_row(&row(10.0 * eps), &mut work).is_nan());
    let mut cycle = work.cycle.clone();
    cycle.sort_unstable();
    assert_eq!(cycle, [0, 1], "the cycle the run stopped at");
    assert!(sys.cycle_below(&row(10.0 * eps), &work.cycle));
    // -3·eps: the run finds the cycle, but the test (−4·eps for two arcs) says nothing.
    assert!(sys.solve_row(&row(3.0 * eps), &mut work).is_nan());
    assert!(!sys.cycle_below(&row(3.0 * eps), &work.cycle));
}

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
        let want = reference(n, &s, &d, &w);
        let fused = longest_path(n as i64, &s, &d, &w).unwrap();
        let prepared = EventGraph::new(n as i64, &s, &d).unwrap().earliest(&w).unwrap();
        for ((f, p), r) in fused.iter().zip(&prepared).zip(&want) {
            prop_assert!((f - r).abs() <= 1e-9 * (1.0 + r.abs()), "{f} vs {r}");
            prop_assert!((p - r).abs() <= 1e-9 * (1.0 + r.abs()), "{p} vs {r}");
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
            // Bit for bit (== would let -0.0 pass for 0.0).
            let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            prop_assert_eq!(bits(&batch[r * n..(r + 1) * n]), bits(&single));
        }
    }

    /// Issue 20: the batch kernel in explicit SIMD (scalar, AVX2 and AVX-512, those
    /// the processor has) gives every lane the single-row scalar pass's times bit
    /// for bit, non-finite and signed-zero weights included (the public API
    /// rejects the non-finite ones; the kernel's flag is what it rejects them by).
    #[test]
    fn block_kernel_is_the_single_row_pass_bit_for_bit(
        (n, s, d, w) in dag(),
        special in prop::collection::vec((0usize..LANES, 0usize..120, 0usize..9), 0..12),
        scale in prop::array::uniform8(-3.0f64..3.0),
        lanes in 1usize..=LANES,
    ) {
        use pulp::Simd;
        let g = EventGraph::new(n as i64, &s, &d).unwrap();
        let m = w.len();
        // Lane l: the weights scaled and shifted (ties and sign changes), then
        // some entries replaced by special values.
        let mut rows: Vec<Vec<f64>> = (0..LANES)
            .map(|l| w.iter().map(|x| (x * scale[l]).round() - l as f64).collect())
            .collect();
        // The last two: the largest accepted magnitude and the next float up.
        let values = [
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            0.0,
            -0.0,
            1e300,
            -1e300,
            MAX_ABS_VALUE,
            -MAX_ABS_VALUE.next_up(),
        ];
        for &(l, e, k) in &special {
            if m > 0 {
                rows[l][e % m] = values[k];
            }
        }
        let within = |r: &[f64]| r.iter().all(|x| x.abs() <= MAX_ABS_VALUE);
        let want_ok = rows.iter().all(|r| within(r));
        let want: Vec<Vec<u64>> = rows
            .iter()
            .map(|r| {
                let mut t = vec![0.0; n];
                g.forward(r, &mut t);
                t.iter().map(|x| x.to_bits()).collect()
            })
            .collect();
        let runs = on_each_isa!(|simd| {
            let mut wblk = vec![[0.0; LANES]; m];
            let mut t = vec![[0.0; LANES]; n];
            // The first `lanes` rows are written out (NaN until then).
            let mut out = vec![f64::NAN; lanes * n];
            let ok = Simd::vectorize(simd, Block {
                graph: &g,
                rows: std::array::from_fn(|l| &rows[l][..]),
                wblk: &mut wblk,
                t: &mut t,
                out: &mut out,
            });
            (ok, t, out)
        });
        for (isa, (ok, t, out)) in runs {
            prop_assert_eq!(ok, want_ok, "{}", isa);
            for (l, want) in want.iter().enumerate() {
                // `t` is by topological position.
                let got: Vec<u64> = g.positions().iter().map(|&p| t[p as usize][l].to_bits()).collect();
                prop_assert_eq!(&got, want, "{} lane {}", isa, l);
                if l < lanes {
                    let got: Vec<u64> = out[l * n..(l + 1) * n].iter().map(|x| x.to_bits()).collect();
                    prop_assert_eq!(&got, want, "{} out row {}", isa, l);
                }
            }
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
        CyclogramError::Cycle {
            events: vec![1, 2, 3]
        }
    );
    let err = EventGraph::new(2, &[1], &[1]).unwrap_err();
    assert_eq!(err, CyclogramError::Cycle { events: vec![1] });
    let err = longest_path(4, &[0, 1, 2, 3], &[1, 2, 3, 1], &[1.0; 4]).unwrap_err();
    assert_eq!(
        err,
        CyclogramError::Cycle {
            events: vec![1, 2, 3]
        }
    );
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    assert!(matches!(
        EventGraph::new(3, &[0, 5], &[1, 2]),
        Err(CyclogramError::IndexOutOfRange {
            field: "src",
            position: 1,
            value: 5,
            ..
        })
    ));
    assert!(matches!(
        EventGraph::new(3, &[0], &[-1]),
        Err(CyclogramError::IndexOutOfRange { field: "dst", .. })
    ));
    assert!(matches!(
        EventGraph::new(-1, &[], &[]),
        Err(CyclogramError::BadEventCount { .. })
    ));
    assert!(matches!(
        EventGraph::new(3, &[0, 1], &[1]),
        Err(CyclogramError::LengthMismatch { .. })
    ));
    let g = EventGraph::new(3, &[0, 1], &[1, 2]).unwrap();
    assert!(matches!(
        g.earliest(&[1.0]),
        Err(CyclogramError::WeightLength { .. })
    ));
    match g.earliest(&[1.0, f64::NAN]) {
        Err(CyclogramError::NonFinite { location, .. }) => assert_eq!(location, "[1]"),
        other => panic!("{other:?}"),
    }
    assert!(g.latest(&[1.0, 2.0], f64::INFINITY).is_err());
    // Finite but huge weights would overflow the sums: refused like NaN.
    assert!(g.earliest(&[1e308, 1e308]).is_err());
    assert!(longest_path(3, &[0, 1], &[1, 2], &[1e308, 1e308]).is_err());
    assert!(g
        .earliest_batch(&[1.0, 2.0, 1e308, 1.0], 2, 2, Some(1))
        .is_err());
    assert!(g.earliest_batch(&[1.0, 2.0, 3.0], 2, 2, None).is_err());
    assert!(g.earliest_batch(&[], 0, 5, None).is_err());
    assert!(matches!(
        EventGraph::new(4_000_000_000, &[], &[]),
        Err(CyclogramError::TooLarge { .. })
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

// -----------------------------------------------------------------------
// Difference constraints
// -----------------------------------------------------------------------

/// Independent reference: Floyd–Warshall distances between all pairs, or None
/// if some cycle is negative (a negative diagonal entry). Exact on the
/// integer-valued weights the tests draw.
fn floyd_warshall(n: usize, src: &[i64], dst: &[i64], w: &[f64]) -> Option<Vec<Vec<f64>>> {
    let mut d = vec![vec![f64::INFINITY; n]; n];
    for (i, row) in d.iter_mut().enumerate() {
        row[i] = 0.0;
    }
    for e in 0..src.len() {
        let (a, b) = (src[e] as usize, dst[e] as usize);
        d[a][b] = d[a][b].min(w[e]);
    }
    for k in 0..n {
        for i in 0..n {
            for j in 0..n {
                let c = d[i][k] + d[k][j];
                if c < d[i][j] {
                    d[i][j] = c;
                }
            }
        }
    }
    if (0..n).any(|i| d[i][i] < 0.0) {
        None
    } else {
        Some(d)
    }
}

/// A random graph (self-loops and parallel arcs allowed) with integer weights
/// in [-10, 30] times a power-of-two or 360 scale (sums stay exact), a source
/// and a target.
#[allow(clippy::type_complexity)]
fn difference_system() -> impl Strategy<Value = (usize, Vec<i64>, Vec<i64>, Vec<f64>, i64, i64)> {
    (1usize..9).prop_flat_map(|n| {
        let arcs = prop::collection::vec((0..n as i64, 0..n as i64, -10i32..30), 0..24);
        let scale = prop_oneof![Just(1.0), Just(0.25), Just(360.0)];
        (Just(n), arcs, scale, 0..n as i64, 0..n as i64).prop_map(|(n, arcs, scale, s, t)| {
            let src = arcs.iter().map(|a| a.0).collect();
            let dst = arcs.iter().map(|a| a.1).collect();
            let w = arcs.iter().map(|a| a.2 as f64 * scale).collect();
            (n, src, dst, w, s, t)
        })
    })
}

/// The marked arcs, followed from `s`, form one path that ends at `t` and uses
/// each of them once; returns its weight summed from `s`.
fn walk_marked(src: &[i64], dst: &[i64], w: &[f64], marks: &[bool], s: i64, t: i64) -> f64 {
    let mut left: Vec<usize> = (0..src.len()).filter(|&e| marks[e]).collect();
    let (mut v, mut sum, mut seen) = (s, 0.0, vec![s]);
    while let Some(k) = left.iter().position(|&e| src[e] == v) {
        let e = left.remove(k);
        sum += w[e];
        v = dst[e];
        assert!(!seen.contains(&v), "the marked arcs revisit node {v}");
        seen.push(v);
    }
    assert!(left.is_empty(), "marked arcs {left:?} are off the path");
    assert_eq!(v, t, "the marked path ends at {v}, not at the target {t}");
    sum
}

proptest! {
    #[test]
    fn max_difference_matches_floyd_warshall((n, s, d, w, a, b) in difference_system()) {
        let (value, marks) = max_difference(n as i64, &s, &d, &w, a, b).unwrap();
        prop_assert_eq!(marks.len(), w.len());
        match floyd_warshall(n, &s, &d, &w) {
            None => {
                prop_assert!(value.is_nan(), "{value} for an infeasible system");
                prop_assert!(!marks.contains(&true));
            }
            Some(dist) => {
                let want = dist[a as usize][b as usize];
                if want == f64::INFINITY {
                    prop_assert_eq!(value, f64::INFINITY);
                    prop_assert!(!marks.contains(&true));
                } else {
                    prop_assert!((value - want).abs() <= 1e-9 * (1.0 + want.abs()), "{value} vs {want}");
                    let sum = walk_marked(&s, &d, &w, &marks, a, b);
                    prop_assert_eq!(sum.to_bits(), value.to_bits());
                    if a == b {
                        prop_assert_eq!(value, 0.0);
                        prop_assert!(!marks.contains(&true));
                    }
                }
            }
        }
    }

    #[test]
    fn max_difference_batch_matches_single(
        (n, s, d, w, a, b) in difference_system(),
        rows in 0usize..12,
        threads in 1i64..3,
    ) {
        let m = w.len();
        // Row r shifts every weight by 3 - r: later rows gain negative cycles.
        let all: Vec<f64> = (0..rows)
            .flat_map(|r| w.iter().map(move |x| x + 3.0 - r as f64))
            .collect();
        let (values, marks) =
            max_difference_batch(n as i64, &s, &d, &all, (rows, m), a, b, Some(threads)).unwrap();
        prop_assert_eq!(values.len(), rows);
        prop_assert_eq!(marks.len(), rows * m);
        for r in 0..rows {
            let (v, mk) = max_difference(n as i64, &s, &d, &all[r * m..(r + 1) * m], a, b).unwrap();
            prop_assert_eq!(values[r].to_bits(), v.to_bits());
            prop_assert_eq!(&marks[r * m..(r + 1) * m], &mk[..]);
        }
    }
}

#[test]
fn max_difference_by_hand() {
    // x1 - x0 <= 4, x2 - x1 <= -1, x2 - x0 <= 5: max x2 - x0 = 3 via 0 -> 1 -> 2.
    let (s, d) = ([0, 1, 0], [1, 2, 2]);
    let (v, mk) = max_difference(3, &s, &d, &[4.0, -1.0, 5.0], 0, 2).unwrap();
    assert_eq!((v, mk), (3.0, vec![true, true, false]));
    // source == target: 0, nothing marked.
    let (v, mk) = max_difference(3, &s, &d, &[4.0, -1.0, 5.0], 1, 1).unwrap();
    assert_eq!((v, mk), (0.0, vec![false; 3]));
    // Unreachable target: unbounded.
    let (v, mk) = max_difference(3, &s, &d, &[4.0, -1.0, 5.0], 2, 0).unwrap();
    assert_eq!((v, mk), (f64::INFINITY, vec![false; 3]));
    // No arcs at all.
    assert_eq!(
        max_difference(1, &[], &[], &[], 0, 0).unwrap(),
        (0.0, vec![])
    );
    assert_eq!(
        max_difference(2, &[], &[], &[], 0, 1).unwrap(),
        (f64::INFINITY, vec![])
    );
}

#[test]
fn negative_cycle_anywhere_is_infeasible() {
    // 0 -> 1 is all the source sees; 2 <-> 3 is a negative cycle off to the side.
    let (s, d) = ([0, 2, 3], [1, 3, 2]);
    let (v, mk) = max_difference(4, &s, &d, &[1.0, 2.0, -3.0], 0, 1).unwrap();
    assert!(v.is_nan());
    assert_eq!(mk, vec![false; 3]);
    // The same with source == target, and a negative self-loop.
    assert!(max_difference(4, &s, &d, &[1.0, 2.0, -3.0], 0, 0)
        .unwrap()
        .0
        .is_nan());
    assert!(max_difference(2, &[0, 1], &[1, 1], &[1.0, -0.5], 0, 1)
        .unwrap()
        .0
        .is_nan());
    // A zero cycle is feasible.
    let (v, _) = max_difference(4, &s, &d, &[1.0, 2.0, -2.0], 0, 1).unwrap();
    assert_eq!(v, 1.0);
}

#[test]
fn tight_cycle_is_feasible_within_the_tolerance() {
    // A cyclogram cycle that closes exactly, up to the round-off of its angles.
    for (scale, slack) in [
        (1.0, -1e-13),
        (1.0, 1e-13),
        (360.0, -1e-13),
        (360.0, -5e-11),
    ] {
        let w = [120.0 / 360.0 * scale, 240.0 / 360.0 * scale, -scale + slack];
        let (v, mk) = max_difference(3, &[0, 1, 2], &[1, 2, 0], &w, 0, 2).unwrap();
        assert!((v - scale).abs() < 1e-9 * scale, "{scale} {slack}: {v}");
        assert_eq!(mk, vec![true, true, false]);
        let (v, _) = max_difference(3, &[0, 1, 2], &[1, 2, 0], &w, 2, 1).unwrap();
        assert!((v - (w[2] + w[0])).abs() < 1e-9 * scale);
    }
    // Well below -n·eps: infeasible.
    let w = [1.0, 2.0, -3.0 - 1e-6];
    assert!(max_difference(3, &[0, 1, 2], &[1, 2, 0], &w, 0, 2)
        .unwrap()
        .0
        .is_nan());
    let w = [1.0, 2.0, -3.0 - 4.0 * 3.0 * DIFFERENCE_RTOL * 4.0 * 3.0];
    assert!(max_difference(3, &[0, 1, 2], &[1, 2, 0], &w, 0, 2)
        .unwrap()
        .0
        .is_nan());
}

#[test]
fn long_negative_cycle_is_found() {
    // A ring of 200 nodes whose weights sum to -1 (found through predecessors
    // long before the pass cap), plus a chord 5 -> 150 of weight 150 (the
    // cycle it closes weighs 150 - 145 >= 0).
    let n = 200i64;
    let s: Vec<i64> = (0..n).chain([5]).collect();
    let d: Vec<i64> = (1..n).chain([0, 150]).collect();
    let mut w = vec![1.0; n as usize + 1];
    w[n as usize] = 150.0;
    w[n as usize - 1] = -(n as f64);
    assert!(max_difference(n, &s, &d, &w, 3, 7).unwrap().0.is_nan());
    // Ring of weight 0: feasible, and the chord is never the shorter way.
    w[n as usize - 1] = -(n as f64) + 1.0;
    let (v, mk) = max_difference(n, &s, &d, &w, 3, 7).unwrap();
    assert_eq!(v, 4.0);
    assert_eq!(mk.iter().filter(|&&b| b).count(), 4);
    assert_eq!(max_difference(n, &s, &d, &w, 3, 160).unwrap().0, 157.0);
    // Going round: 160 -> 199 -> 0 -> 7.
    assert_eq!(
        max_difference(n, &s, &d, &w, 160, 7).unwrap().0,
        39.0 - 199.0 + 7.0
    );
    // A cheaper chord closes a negative cycle: infeasible.
    w[n as usize] = 144.0;
    assert!(max_difference(n, &s, &d, &w, 3, 7).unwrap().0.is_nan());
}

#[test]
fn difference_batch_threads_agree_bit_for_bit() {
    // Large enough for the threaded path (rows · (arcs + nodes) · 4 > 2^16).
    let (n, m, rows) = (20usize, 60usize, 400usize);
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let s: Vec<i64> = (0..m).map(|_| (next() % n as u64) as i64).collect();
    let d: Vec<i64> = (0..m).map(|_| (next() % n as u64) as i64).collect();
    let w: Vec<f64> = (0..rows * m)
        .map(|_| (next() % 4001) as f64 / 100.0 - 5.0)
        .collect();
    assert!(rows * (m + n) * DIFFERENCE_PASSES >= PARALLEL_MIN_WORK);
    let one = max_difference_batch(n as i64, &s, &d, &w, (rows, m), 0, 7, Some(1)).unwrap();
    let two = max_difference_batch(n as i64, &s, &d, &w, (rows, m), 0, 7, Some(2)).unwrap();
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&one.0), bits(&two.0));
    assert_eq!(one.1, two.1);
    let kinds = |f: fn(&f64) -> bool| one.0.iter().filter(|v| f(v)).count();
    // The draw mixes feasible and infeasible rows.
    assert!(kinds(|v| v.is_nan()) > 0 && kinds(|v| v.is_finite()) > 0);
    for r in (0..rows).step_by(37) {
        let single = max_difference(n as i64, &s, &d, &w[r * m..(r + 1) * m], 0, 7).unwrap();
        assert_eq!(single.0.to_bits(), one.0[r].to_bits());
        assert_eq!(&single.1[..], &one.1[r * m..(r + 1) * m]);
    }
}

#[test]
fn difference_bad_input_is_an_error_not_a_panic() {
    let (s, d, w) = ([0i64, 1], [1i64, 2], [1.0, 2.0]);
    let msg = |r: Result<(f64, Vec<bool>), CyclogramError>| r.unwrap_err().to_string();
    assert_eq!(
        msg(max_difference(0, &[], &[], &[], 0, 0)),
        format!("n_nodes = 0 is invalid: it must be an integer between 1 and {MAX_SIZE}")
    );
    assert!(msg(max_difference(-3, &s, &d, &w, 0, 1)).starts_with("n_nodes = -3"));
    assert_eq!(
        msg(max_difference(3, &s, &[1, 3], &w, 0, 1)),
        "dst[1] = 3 is not a node index; valid indices are 0 to 2 (n_nodes = 3)"
    );
    assert!(msg(max_difference(3, &[-1, 0], &d, &w, 0, 1)).starts_with("src[0] = -1"));
    assert_eq!(
        msg(max_difference(3, &s, &d, &w, 3, 1)),
        "source = 3 is not a node index; valid indices are 0 to 2 (n_nodes = 3)"
    );
    assert!(msg(max_difference(3, &s, &d, &w, 0, -1)).starts_with("target = -1"));
    assert!(msg(max_difference(3, &s, &d[..1], &w, 0, 1)).contains("same length"));
    assert!(msg(max_difference(3, &s, &d, &w[..1], 0, 1)).contains("got 1"));
    assert!(msg(max_difference(3, &s, &d, &[1.0, f64::NAN], 0, 1)).starts_with("weights[1] = NaN"));
    assert!(
        msg(max_difference(3, &s, &d, &[f64::INFINITY, 1.0], 0, 1)).starts_with("weights[0] = inf")
    );
    assert!(msg(max_difference(3, &s, &d, &[1e300, 1.0], 0, 1)).starts_with("weights[0] = 1e300"));
    let batch = |w: &[f64], shape, threads| {
        max_difference_batch(3, &s, &d, w, shape, 0, 1, threads)
            .unwrap_err()
            .to_string()
    };
    let mut rows = vec![1.0; 6];
    rows[5] = f64::NEG_INFINITY;
    assert!(batch(&rows, (3, 2), None).starts_with("weights[2, 1] = -inf"));
    assert!(batch(&[f64::NAN, 1.0], (1, 2), None).starts_with("weights[0, 0] = NaN"));
    assert!(batch(&[1.0; 6], (2, 3), None).contains("got 3"));
    assert!(batch(&[], (0, 5), None).contains("got 5"));
    assert!(batch(&[1.0; 5], (2, 2), None).contains("weights"));
    assert!(batch(&[1.0; 4], (2, 2), Some(0)).contains("n_threads"));
    assert!(max_difference_batch(3, &s, &d, &[], (0, 2), 0, 5, None).is_err());
    assert_eq!(
        max_difference_batch(3, &s, &d, &[], (0, 2), 0, 2, Some(2)).unwrap(),
        (vec![], vec![])
    );
    assert_eq!(
        max_difference_batch(2, &[], &[], &[], (3, 0), 0, 1, Some(2)).unwrap(),
        (vec![f64::INFINITY; 3], vec![])
    );
}

#[test]
fn tile_transpose_is_exact_on_every_instruction_set() {
    // The batch kernel's 8 × 8 transposes (explicit shuffles on AVX2 and
    // AVX-512): distinct entries, including a NaN payload and -0.0, land where
    // the element-wise definition puts them, bit for bit.
    let mut tile: [[f64; LANES]; LANES] =
        std::array::from_fn(|i| std::array::from_fn(|j| (10 * i + j) as f64 + 0.5));
    tile[3][5] = f64::from_bits(0x7ff8_0000_dead_beef);
    tile[6][1] = -0.0;
    let runs = on_each_isa!(|simd| transpose(simd, &tile));
    for (isa, got) in runs {
        for i in 0..LANES {
            for j in 0..LANES {
                assert_eq!(
                    got[i][j].to_bits(),
                    tile[j][i].to_bits(),
                    "{isa} ({i}, {j})"
                );
            }
        }
    }
}
