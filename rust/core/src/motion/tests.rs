use super::fused::{Fused, FusedChunk};
use super::law::*;
use super::two_period::*;
use std::f64::consts::PI;

use proptest::prelude::*;

/// The fused two-period kernel against the pointwise evaluator: at most this
/// many ε of the order's scale (its largest |value| on the law) apart. Both
/// round: the widest gap, 16.5 ε, is the 4-5-6-7 half law's jerk, a degree-4
/// Horner with cancellation evaluated with and without FMA; against exact
/// values (tests/test_motion_fused.py, mpmath) each is within 14 ε.
const FUSED_ULPS: f64 = 20.0;

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * (1.0 + b.abs())
}

#[test]
fn published_peaks_of_the_rises() {
    // (name, Cv, Ca) from the cam-design literature (Norton, Cam Design and
    // Manufacturing Handbook, table 3-2; Rothbart).
    for (name, cv, ca) in [
        ("cycloidal", 2.0, 2.0 * PI),
        ("harmonic", PI / 2.0, PI * PI / 2.0),
        ("polynomial_345", 1.875, 10.0 / 3f64.sqrt()),
        ("polynomial_4567", 2.1875, 7.5132),
        ("modified_sine", 1.760, 5.528),
        ("modified_trapezoid", 2.000, 4.888),
    ] {
        let law = Law::rise(name).unwrap();
        // Published to four or five digits; the closed forms to rounding.
        let tol = if name.starts_with("modified") || name == "polynomial_4567" {
            5e-4
        } else {
            1e-12
        };
        assert!(close(law.dz_max, cv, tol), "{name}: Cv {}", law.dz_max);
        assert!(close(law.ddz_max, ca, tol), "{name}: Ca {}", law.ddz_max);
        assert!(law.z(0.0, 0).abs() < 1e-14 && close(law.z(1.0, 0), 1.0, 1e-14));
        assert!(law.z(0.0, 1).abs() < 1e-14 && law.z(1.0, 1).abs() < 1e-13);
    }
}

#[test]
fn half_cycloidal_is_the_seed_form() {
    let h = Law::half("cycloidal").unwrap();
    for j in [0.0, 0.1, 0.37, 0.5, 0.9, 1.0] {
        assert!(close(h.z(j, 0), j - (PI * j).sin() / PI, 1e-14));
        assert!(close(h.z(j, 1), 1.0 - (PI * j).cos(), 1e-14));
        assert!(close(h.z(j, 2), PI * (PI * j).sin(), 1e-14));
    }
    assert!(close(h.dz_max, 2.0, 1e-14) && close(h.ddz_max, PI, 1e-14));
}

#[test]
fn pieces_join_smoothly() {
    for name in ["modified_sine", "modified_trapezoid"] {
        let law = Law::rise(name).unwrap();
        for w in law.fast.windows(2) {
            let x = w[0].x1;
            for order in 0..3 {
                let (a, b) = (w[0].eval(x, order), w[1].eval(x, order));
                assert!(
                    close(a, b, 1e-12),
                    "{name} order {order} at {x}: {a} vs {b}"
                );
            }
        }
    }
}

#[test]
fn user_polynomials_are_checked() {
    assert!(Law::polynomial(&[0.0, 0.0, 0.0, 10.0, -15.0, 6.0], true).is_ok());
    assert!(Law::polynomial(&[0.0, 0.0, 1.0], true).is_err()); // Z'(1) = 2
    assert!(Law::polynomial(&[0.0, 0.0, 1.0], false).is_ok()); // Z = x², Z' peaks at 1
    assert!(Law::polynomial(&[0.0, 2.0, -1.0], false).is_err()); // Z'(0) = 2
    assert!(Law::polynomial(&[0.0, f64::NAN], true).is_err());
}

proptest! {
    #[test]
    fn derivatives_match_differences(x in 0.01f64..0.99, k in 0usize..6, half in any::<bool>()) {
        let law = if half { Law::half(NAMES[k]) } else { Law::rise(NAMES[k]) }.unwrap();
        let h = 1e-6;
        for order in 0..3 {
            let fd = (law.z(x + h, order) - law.z(x - h, order)) / (2.0 * h);
            let exact = law.z(x, order + 1);
            // Pieces switch at breakpoints: skip a stencil straddling one.
            let straddles = law.segments.iter().any(|s| (s.x1 - x).abs() < 2.0 * h);
            prop_assert!(straddles || (fd - exact).abs() <= 1e-5 * (1.0 + exact.abs()),
                "{} order {}: {} vs {}", NAMES[k], order + 1, fd, exact);
        }
    }
}

#[test]
fn arrays_take_the_pointwise_values() {
    // The lane-parallel path (arrays) against the pointwise one, value for
    // value, for every pair of laws, every order, on a grid through the
    // pieces' ends, the junction and both ends; also single laws.
    let polys = [Law::polynomial(&[0.0, 0.0, 1.5, -0.5], false).unwrap()];
    let laws: Vec<Law> = NAMES
        .iter()
        .map(|n| Law::half(n).unwrap())
        .chain(NAMES.iter().map(|n| Law::rise(n).unwrap()))
        .chain(polys)
        .collect();
    let x: Vec<f64> = (0..=1003).map(|i| i as f64 / 1003.0).collect();
    for law in &laws {
        for order in 0..=3 {
            let mut out = vec![0.0; x.len()];
            law.eval_into(&x, order, Some(1), &mut out).unwrap();
            for (&xi, &o) in x.iter().zip(&out) {
                assert_eq!(o, law.z(xi, order), "x = {xi}, order {order}");
            }
        }
    }
    for l1 in &laws[..NAMES.len()] {
        for l2 in &laws[..NAMES.len()] {
            let law = TwoPeriod {
                stroke1: 0.04,
                angle1: 1.1,
                stroke: 0.1,
                angle: PI,
                law1: l1.clone(),
                law2: l2.clone(),
            };
            let mut alpha: Vec<f64> = x.iter().map(|v| v * PI).collect();
            alpha.extend([1.1, 1.1 * (1.0 + 1e-16), 0.0, PI]);
            for order in 0..=3 {
                let mut out = vec![0.0; alpha.len()];
                law.eval_into(&alpha, order, Some(2), &mut out).unwrap();
                // The fused kernel (FMA, its own sine) reassociates: within
                // FUSED_ULPS of the order's scale of the pointwise values.
                let want: Vec<f64> = alpha.iter().map(|&a| law.at(a, order)).collect();
                let scale = want.iter().fold(0.0f64, |m, w| m.max(w.abs()));
                for ((&a, &o), &w) in alpha.iter().zip(&out).zip(&want) {
                    assert!(
                        (o - w).abs() <= FUSED_ULPS * f64::EPSILON * scale,
                        "α = {a}, order {order}: {o} vs {w} ({} ulp of {scale})",
                        (o - w).abs() / (f64::EPSILON * scale)
                    );
                }
            }
        }
    }
}

#[test]
fn every_instruction_set_gives_the_pointwise_values() {
    // The lane evaluator compiled for scalar code, AVX2 and AVX-512 (those
    // the processor has), not only the one the dispatch picks.
    use pulp::Simd;
    let names = [
        "cycloidal",
        "modified_sine",
        "modified_trapezoid",
        "polynomial_345",
    ];
    let alpha: Vec<f64> = (0..=997).map(|i| i as f64 * (PI / 997.0)).collect();
    for (n1, n2) in names.iter().zip(names.iter().rev()) {
        let law = TwoPeriod {
            stroke1: 0.04,
            angle1: 1.1,
            stroke: 0.1,
            angle: PI,
            law1: Law::half(n1).unwrap(),
            law2: Law::half(n2).unwrap(),
        };
        for order in 0..=3 {
            let lanes = law.lanes(order).unwrap();
            let runs = on_each_isa!(|simd| {
                let mut out = vec![0.0; alpha.len()];
                let inside = Simd::vectorize(
                    simd,
                    LaneChunk {
                        lanes: &lanes,
                        v: &alpha,
                        out: &mut out,
                        hi: PI,
                    },
                );
                // The fused range check: a NaN, a value past α2, one below 0.
                let outside =
                    [(300, f64::NAN), (700, PI * (1.0 + 1e-15)), (997, -0.1)].map(|(i, bad)| {
                        let mut a = alpha.clone();
                        a[i] = bad;
                        Simd::vectorize(
                            simd,
                            LaneChunk {
                                lanes: &lanes,
                                v: &a,
                                out: &mut vec![0.0; a.len()],
                                hi: PI,
                            },
                        )
                    });
                assert!(inside && outside == [false; 3]);
                out
            });
            assert!(runs.len() >= 2 || !cfg!(target_arch = "x86_64"));
            for (isa, out) in runs {
                for (&a, &o) in alpha.iter().zip(&out) {
                    assert_eq!(o, law.at(a, order), "{isa}: α = {a}, order {order}");
                }
            }
        }
    }
}

/// [`FusedChunk`] on one instruction set, α in [0, π].
fn run_fused<S: pulp::Simd>(simd: S, fused: &Fused, v: &[f64], out: &mut [f64]) -> bool {
    simd.vectorize(FusedChunk {
        fused,
        v,
        out,
        hi: PI,
    })
}

#[test]
fn the_fused_kernel_gives_the_same_bits_on_every_instruction_set() {
    // FusedChunk compiled for scalar code (software fma), AVX2 and AVX-512
    // (those the processor has): the same bits, whatever a value's place in the
    // chunk (the body's registers or the padded tail), and the range check's
    // verdict for a NaN, an infinity, a value past α2 and one below 0 in the body
    // and in the tail. On a processor with FMA, `eval_into` runs this kernel.
    let names = [
        "cycloidal",
        "modified_sine",
        "harmonic",
        "modified_trapezoid",
        "polynomial_4567",
    ];
    let mut alpha: Vec<f64> = (0..=997).map(|i| i as f64 * (PI / 997.0)).collect();
    alpha.extend([1.1, 1.1f64.next_up(), 1.1f64.next_down(), 0.0, -0.0, PI]);
    for (n1, n2) in names.iter().zip(names.iter().cycle().skip(1)) {
        let law = TwoPeriod {
            stroke1: 0.04,
            angle1: 1.1,
            stroke: 0.1,
            angle: PI,
            law1: Law::half(n1).unwrap(),
            law2: Law::half(n2).unwrap(),
        };
        for order in 0..=3 {
            let fused = law.fused_any_cpu(order).unwrap();
            let runs = on_each_isa!(|simd| {
                let mut out = vec![0.0; alpha.len()];
                assert!(run_fused(simd, &fused, &alpha, &mut out));
                // Each value alone (in the tail) and the last few lengths.
                for (i, &a) in alpha.iter().enumerate().step_by(7) {
                    let mut one = [0.0];
                    assert!(run_fused(simd, &fused, &[a], &mut one));
                    assert_eq!(one[0].to_bits(), out[i].to_bits(), "α = {a}");
                }
                for n in 990..alpha.len() {
                    let mut part = vec![0.0; n];
                    assert!(run_fused(simd, &fused, &alpha[..n], &mut part));
                    assert_eq!(part[..], out[..n]);
                }
                for at in [300, alpha.len() - 2] {
                    for bad in [f64::NAN, f64::INFINITY, PI.next_up(), -1e-300] {
                        let mut a = alpha.clone();
                        a[at] = bad;
                        assert!(
                            !run_fused(simd, &fused, &a, &mut vec![0.0; a.len()]),
                            "{bad} at {at}"
                        );
                    }
                }
                out
            });
            assert!(runs.len() >= 2 || !cfg!(target_arch = "x86_64"));
            let (_, first) = &runs[0];
            for (isa, out) in &runs {
                for (i, (&a, &b)) in out.iter().zip(first).enumerate() {
                    assert_eq!(
                        a.to_bits(),
                        b.to_bits(),
                        "{isa}: α = {}, order {order}",
                        alpha[i]
                    );
                }
            }
            if law.fused(order).is_some() {
                let mut out = vec![0.0; alpha.len()];
                law.eval_into(&alpha, order, Some(1), &mut out).unwrap();
                assert_eq!(&out, first);
            }
        }
    }
}

#[test]
fn arrays_out_of_range_are_refused_by_index() {
    let law = Law::half("cycloidal").unwrap();
    let mut x = vec![0.5; 40_000];
    x[30_001] = f64::NAN;
    let mut out = vec![0.0; x.len()];
    let err = law.eval_into(&x, 0, Some(2), &mut out).unwrap_err();
    assert!(err.to_string().contains("30001"), "{err}");
    x[30_001] = 1.5;
    let err = law.eval_into(&x, 0, Some(2), &mut out).unwrap_err();
    assert!(err.to_string().contains("30001"), "{err}");
}

#[test]
fn two_period_is_continuous_at_the_junction() {
    let (l1, l2) = (
        Law::half("cycloidal").unwrap(),
        Law::half("modified_sine").unwrap(),
    );
    // Π1 from continuity (9) for f_A = 1.5.
    let (p2, a2, f) = (0.1, PI, 1.5);
    let n1 = l1.dz_max / l2.dz_max;
    let law = TwoPeriod {
        stroke1: p2 / (1.0 + n1 * f),
        angle1: a2 / (1.0 + f),
        stroke: p2,
        angle: a2,
        law1: l1,
        law2: l2,
    };
    let a1 = law.angle1;
    for order in 0..3 {
        let (lo, hi) = (
            law.at(a1 * (1.0 - 1e-12), order),
            law.at(a1 * (1.0 + 1e-12), order),
        );
        assert!(close(lo, hi, 1e-9), "order {order}: {lo} vs {hi}");
    }
    assert!(close(law.at(a2, 0), p2, 1e-15) && law.at(0.0, 0).abs() < 1e-15);
}

#[test]
fn all_orders_at_once_are_the_single_orders_bit_for_bit() {
    // z_all shares the piece lookup; its values must be z(x, k)'s exactly, for
    // every named rise and half law and a user polynomial, on a grid through
    // every piece end (and one ulp either side of it) and both ends of [0, 1].
    let laws: Vec<Law> = NAMES
        .iter()
        .flat_map(|n| [Law::rise(n).unwrap(), Law::half(n).unwrap()])
        .chain([Law::polynomial(&[0.0, 0.0, 1.5, -0.5], false).unwrap()])
        .collect();
    for law in &laws {
        let mut x: Vec<f64> = (0..=4001).map(|i| i as f64 / 4001.0).collect();
        for s in &law.segments {
            for e in [s.x0, s.x1] {
                x.extend([e, e.next_down().max(0.0), e.next_up().min(1.0)]);
            }
        }
        for xi in x {
            let all = law.z_all(xi);
            for (k, &v) in all.iter().enumerate() {
                assert_eq!(v.to_bits(), law.z(xi, k).to_bits(), "x = {xi}, order {k}");
            }
        }
    }
}

proptest! {
    #[test]
    fn all_orders_match_single_orders_anywhere(x in 0.0f64..=1.0, k in 0usize..6, half in any::<bool>()) {
        let law = if half { Law::half(NAMES[k]) } else { Law::rise(NAMES[k]) }.unwrap();
        let all = law.z_all(x);
        for (order, &v) in all.iter().enumerate() {
            prop_assert_eq!(v.to_bits(), law.z(x, order).to_bits());
        }
    }
}

#[test]
fn lanes_of_all_orders_are_z_all_bit_for_bit() {
    // Groups inside one piece (the branch-free path) and groups straddling piece
    // ends (one by one), for every law: each lane must be z_all's value.
    let laws: Vec<Law> = NAMES
        .iter()
        .flat_map(|n| [Law::rise(n).unwrap(), Law::half(n).unwrap()])
        .chain([Law::polynomial(&[0.0, 0.0, 1.5, -0.5], false).unwrap()])
        .collect();
    let x: Vec<f64> = (0..=8001).map(|i| i as f64 / 8001.0).collect();
    for law in &laws {
        for start in 0..8 {
            for g in x[start..].chunks_exact(8) {
                let g: [f64; 8] = g.try_into().unwrap();
                let z = law.z_all_lanes(&g);
                for (l, &v) in g.iter().enumerate() {
                    let want = law.z_all(v);
                    for o in 0..4 {
                        assert_eq!(z[o][l].to_bits(), want[o].to_bits(), "x = {v}, order {o}");
                    }
                }
            }
        }
    }
}

/// z_all_lanes_shared against z_all: at most this much of each order's scale
/// (its largest |value|) apart. A piece adds a polynomial and a sinusoid that
/// partly cancel (the modified laws), so both round at the size of their terms,
/// up to ~50 ε of the sum's scale (measured); the cam kernel's outputs must stay
/// within 1e-12 of their scales.
const SHARED_TOL: f64 = 1e-13;

#[test]
fn shared_sinusoid_lanes_are_z_all_within_a_tolerance_of_scale() {
    // z_all_lanes_shared (the cam kernel's: one sine and cosine for the four
    // orders, FMA) against the pointwise z_all, for every law, on groups inside
    // one piece and straddling piece ends: within SHARED_TOL of each order's
    // scale (its largest |value| on the grid).
    let laws: Vec<Law> = NAMES
        .iter()
        .flat_map(|n| [Law::rise(n).unwrap(), Law::half(n).unwrap()])
        .chain([Law::polynomial(&[0.0, 0.0, 1.5, -0.5], false).unwrap()])
        .collect();
    let x: Vec<f64> = (0..=8001).map(|i| i as f64 / 8001.0).collect();
    for law in &laws {
        let want: Vec<[f64; 4]> = x.iter().map(|&v| law.z_all(v)).collect();
        let scale: [f64; 4] = std::array::from_fn(|o| {
            want.iter()
                .fold(f64::MIN_POSITIVE, |m, w| m.max(w[o].abs()))
        });
        for start in 0..8 {
            for (i, g) in x[start..].chunks_exact(8).enumerate() {
                let g: [f64; 8] = g.try_into().unwrap();
                let z = law.z_all_lanes_shared(&g);
                for (l, &v) in g.iter().enumerate() {
                    let w = want[start + 8 * i + l];
                    for o in 0..4 {
                        let gap = (z[o][l] - w[o]).abs() / scale[o];
                        assert!(gap <= SHARED_TOL, "x = {v}, order {o}: {gap} of the scale");
                    }
                }
            }
        }
    }
}

proptest! {
    #[test]
    fn shared_sinusoid_lanes_anywhere_in_the_unit_interval(
        x in prop::array::uniform8(0.0f64..=1.0), k in 0usize..6, half in any::<bool>(),
    ) {
        // Unsorted x (one by one where they straddle a piece end), against the
        // law's published peak velocity and acceleration as scales of orders 1, 2.
        let law = if half { Law::half(NAMES[k]) } else { Law::rise(NAMES[k]) }.unwrap();
        let z = law.z_all_lanes_shared(&x);
        for (l, &v) in x.iter().enumerate() {
            let w = law.z_all(v);
            let scale = [1.0, law.dz_max, law.ddz_max, 1.0];
            for o in 0..3 {
                prop_assert!(
                    (z[o][l] - w[o]).abs() <= SHARED_TOL * scale[o],
                    "x = {}, order {}: {} vs {}", v, o, z[o][l], w[o]
                );
            }
            // The jerk's scale is not published: relative to 1 + |jerk|.
            prop_assert!((z[3][l] - w[3]).abs() <= 1e-12 * (1.0 + w[3].abs()));
        }
    }
}

/// Timing of the two-period law on the benchmark's 1e6 angles, one thread
/// (ignored: `cargo test --release -p cyclomech-core two_period_timing --
/// --ignored --nocapture`).
#[test]
#[ignore]
fn two_period_timing() {
    for second in ["cycloidal", "modified_sine"] {
        let (law1, law2) = (Law::half("cycloidal").unwrap(), Law::half(second).unwrap());
        // asymmetry 2: α1 = α2/3 … as the benchmark's two_period(0.2, π, …, asymmetry=2).
        let tp = TwoPeriod {
            law1,
            law2,
            stroke1: 0.2 / 3.0,
            angle1: PI / 3.0,
            stroke: 0.2,
            angle: PI,
        };
        for n in [1_000_000, 50_000] {
            let alpha: Vec<f64> = (0..n).map(|i| PI * i as f64 / (n - 1) as f64).collect();
            let mut out = vec![0.0; n];
            let best = (0..200)
                .map(|_| {
                    let s = std::time::Instant::now();
                    tp.eval_into(&alpha, 0, Some(1), &mut out).unwrap();
                    s.elapsed().as_secs_f64()
                })
                .fold(f64::INFINITY, f64::min);
            eprintln!(
                "cycloidal + {second}, {n} angles: {:.3} ns per angle (reused output)",
                best * 1e9 / n as f64
            );
        }
    }
}
