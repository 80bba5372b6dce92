//! `cyclomech_core::cancel`: the flag's rules, and kernels of each loop kind
//! stopping at their chunks when it is raised.
//!
//! A test binary of its own: the flag is global, so it must not be raised while
//! other tests' kernels run (each file under `tests/` is its own process), and
//! the checks run in one test, in order.

use cyclomech_core::cam::residual_ratio_batch;
use cyclomech_core::cancel;
use cyclomech_core::cyclogram::{max_difference_batch, EventGraph};
use cyclomech_core::impact::{response_batch_into, Cases};
use cyclomech_core::motion::Law;
use cyclomech_core::shaft::stats_into;
use std::sync::atomic::Ordering::SeqCst;

/// Sentinel: an output entry no kernel writes here.
const UNSET: f64 = -12345.0;

/// Run `call` on a fresh output twice: armed with the signal raised before it
/// starts (every chunk must be skipped: the output stays unset, and `finish`
/// says to drop it), then unarmed (the output is whole: nothing unset).
fn stops(name: &str, len: usize, call: impl Fn(&mut [f64])) {
    let mut out = vec![UNSET; len];
    let armed = cancel::arm();
    cancel::flag().store(true, SeqCst);
    assert!(cancel::requested());
    call(&mut out);
    assert!(armed.finish(), "{name}: a cut call must be dropped");
    assert!(!cancel::requested() && !cancel::flag().load(SeqCst));
    let skipped = out.iter().filter(|&&v| v == UNSET).count();
    assert_eq!(
        skipped,
        len,
        "{name}: {} of {len} entries written after the signal",
        len - skipped
    );
    let mut out = vec![UNSET; len];
    call(&mut out);
    assert!(
        out.iter().all(|&v| v != UNSET),
        "{name}: the uncut call left entries unset"
    );
}

#[test]
fn the_flag_and_the_kernels_that_poll_it() {
    // Unarmed, a signal changes nothing; arming forgets a signal from before.
    cancel::flag().store(true, SeqCst);
    assert!(!cancel::requested());
    let armed = cancel::arm();
    assert!(!cancel::requested());
    assert!(!armed.finish());

    // A watched call (another thread) sees an armed call cut while it ran, and
    // only that.
    let quiet = cancel::watch();
    let during = cancel::watch();
    let armed = cancel::arm();
    cancel::flag().store(true, SeqCst);
    assert!(during.cut_short(), "the flag is up while armed");
    assert!(armed.finish());
    assert!(during.cut_short(), "the cut was counted");
    let after = cancel::watch();
    assert!(!after.cut_short());
    assert!(quiet.cut_short(), "taken before the cut: may have been cut");

    let n = 2_000;
    let tau: Vec<f64> = (0..n).map(|i| 1.0 + i as f64 * 0.01).collect();
    for threads in [1, 2] {
        stops(
            &format!("cam residual ratio, {threads} thread(s)"),
            n,
            |out| residual_ratio_batch("cycloidal", &tau, 0.1, Some(threads), out).unwrap(),
        );
    }
    let x: Vec<f64> = (0..100_000).map(|i| i as f64 / 100_000.0).collect();
    stops("motion law (chunks on 2 threads)", x.len(), |out| {
        Law::rise("cycloidal")
            .unwrap()
            .eval_into(&x, 2, Some(2), out)
            .unwrap()
    });
    let (a, b) = (vec![1.0; 360], vec![0.5; 360]);
    let omegas: Vec<f64> = (1..=2000).map(f64::from).collect();
    let stats = cyclomech_core::shaft::STATS.len();
    stops("shaft statistics", omegas.len() * stats, |out| {
        stats_into(&a, &b, &omegas, 0.02, out, Some(2)).unwrap()
    });

    // A chain of 200 events, 1024 weight vectors.
    let (src, dst): (Vec<i64>, Vec<i64>) = (0..199).map(|i| (i, i + 1)).unzip();
    let rows = 1024;
    let w: Vec<f64> = (0..rows * 199).map(|i| (i % 7) as f64).collect();
    let graph = EventGraph::new(200, &src, &dst).unwrap();
    for threads in [1, 2] {
        stops(
            &format!("batch longest path, {threads} thread(s)"),
            rows * 200,
            |out| {
                graph
                    .earliest_batch_into(&w, rows, 199, out, Some(threads))
                    .unwrap()
            },
        );
    }

    // 16 cases of 4096 steps, forced oscillator.
    let t: Vec<f64> = (0..4096).map(|i| i as f64 * 1e-4).collect();
    let cases = 16;
    let forces = vec![1.0; cases * t.len()];
    let (omega, zeta, mass) = (vec![300.0; cases], vec![0.05; cases], vec![1.0; cases]);
    let zero = vec![0.0; cases];
    for threads in [1, 2] {
        stops(
            &format!("Duhamel batch, {threads} thread(s)"),
            cases * t.len(),
            |out| {
                let c = Cases {
                    omega_n: &omega,
                    zeta: &zeta,
                    mass: &mass,
                    q0: &zero,
                    v0: &zero,
                };
                response_batch_into(&t, &forces, &c, Some(threads), out).unwrap()
            },
        );
    }

    // Difference constraints, row by row: a cut call leaves every row at 0.
    let armed = cancel::arm();
    cancel::flag().store(true, SeqCst);
    let (values, _) =
        max_difference_batch(200, &src, &dst, &w, (rows, 199), 0, 199, Some(2)).unwrap();
    assert!(armed.finish());
    assert!(
        values.iter().all(|&v| v == 0.0),
        "difference rows solved after the signal"
    );
    let (values, _) =
        max_difference_batch(200, &src, &dst, &w, (rows, 199), 0, 199, Some(2)).unwrap();
    assert!(values.iter().any(|&v| v != 0.0));
}
