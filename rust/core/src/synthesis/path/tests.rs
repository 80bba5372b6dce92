//! The batch evaluator against what it claims, by independent means: the
//! closed-form ranges against dense sampling of the same functions written out
//! again, the untimed error against the dense curve, the timed one against
//! the points placed by circle intersection here.

use super::*;
use proptest::prelude::*;

fn spec(kind: Kind, targets: &[f64], timing: Option<&[f64]>) -> Spec<'static> {
    let targets: &'static [f64] = Box::leak(targets.to_vec().into_boxed_slice());
    let timing = timing.map(|t| &*Box::leak(t.to_vec().into_boxed_slice()));
    Spec {
        kind,
        targets,
        timing,
        samples: 90,
        refine: 40,
        full_turn: true,
        min_transmission: 0.0,
        max_ratio: f64::INFINITY,
        pivot_box: None,
    }
}

/// The four-bar's points placed here independently: C as the intersection of
/// the circles about B and D on the side `mode`, P from the coupler frame.
fn fourbar_p(row: &[f64], phi: f64) -> Option<([f64; 2], [f64; 2], [f64; 2])> {
    let [x0, y0, th, r1, r2, r3, r4, u, v, mode] = row[..10].try_into().unwrap();
    let d = [x0 + r1 * th.cos(), y0 + r1 * th.sin()];
    let b = [x0 + r2 * phi.cos(), y0 + r2 * phi.sin()];
    let (dx, dy) = (d[0] - b[0], d[1] - b[1]);
    let l = dx.hypot(dy);
    // Law of cosines for the angle at B between B→D and B→C.
    let cg = (r3 * r3 + l * l - r4 * r4) / (2.0 * r3 * l);
    if cg.abs() >= 1.0 {
        return None;
    }
    // σ = +1: C on the left of the ray D → B, so to the right of B → D.
    let g = -cg.acos() * mode.signum();
    let ang = dy.atan2(dx) + g;
    let c = [b[0] + r3 * ang.cos(), b[1] + r3 * ang.sin()];
    let p = [
        b[0] + u * ang.cos() - v * ang.sin(),
        b[1] + u * ang.sin() + v * ang.cos(),
    ];
    Some((b, c, p))
}

#[test]
fn timed_error_is_the_distance_at_the_given_angles() {
    let row = [0.1, -0.2, 0.3, 4.0, 1.0, 3.5, 2.5, 1.2, 0.7, 1.0, 0.4];
    let timing = [0.0, 0.5, 1.9, 3.0, 4.4];
    let targets: Vec<f64> = timing
        .iter()
        .flat_map(|t| {
            let (_, _, p) = fourbar_p(&row, 0.4 + t).unwrap();
            [p[0] + 0.01, p[1] - 0.02]
        })
        .collect();
    let s = spec(Kind::FourBar, &targets, Some(&timing));
    let mut out = [0.0; 6];
    let mut ang = [0.0; 5];
    evaluate_into(&s, &row, Some(1), &mut out, Some(&mut ang)).unwrap();
    let e = 0.01f64.hypot(0.02);
    assert!((out[1] - e).abs() < 1e-12, "{out:?}");
    assert!((out[2] - e).abs() < 1e-12);
    assert_eq!(out[0], out[1], "a Grashof crank-rocker is feasible");
    for (a, t) in ang.iter().zip(timing) {
        assert!((a - 0.4 - t).abs() < 1e-15);
    }
}

#[test]
fn untimed_error_matches_the_dense_curve() {
    let row = [0.0, 0.0, 0.0, 4.0, 1.0, 3.5, 2.5, 1.2, 0.7, -1.0];
    let targets = [1.0, 2.0, 3.0, 3.5, 0.5, -1.0, 2.2, 0.1];
    let s = spec(Kind::FourBar, &targets, None);
    let mut out = [0.0; 6];
    let mut ang = [0.0; 4];
    evaluate_into(&s, &row, Some(1), &mut out, Some(&mut ang)).unwrap();
    let dense: Vec<[f64; 2]> = (0..200_000)
        .filter_map(|k| fourbar_p(&row, k as f64 * std::f64::consts::TAU / 200_000.0))
        .map(|(_, _, p)| p)
        .collect();
    let mut sum = 0.0;
    for i in 0..4 {
        let t = [targets[2 * i], targets[2 * i + 1]];
        let best = dense
            .iter()
            .map(|p| (p[0] - t[0]).hypot(p[1] - t[1]))
            .fold(f64::INFINITY, f64::min);
        let (_, _, p) = fourbar_p(&row, ang[i]).unwrap();
        let at = (p[0] - t[0]).hypot(p[1] - t[1]);
        // The point found is on the curve, at the dense minimum (within the
        // dense grid's own resolution, second order at a minimum).
        assert!((at - best).abs() < 1e-7, "target {i}: {at} vs dense {best}");
        sum += at * at;
    }
    assert!((out[1] - (sum / 4.0).sqrt()).abs() < 1e-12);
}

#[test]
fn violations_rank_after_every_feasible_candidate() {
    // A triple rocker (non-Grashof): the crank cannot turn fully.
    let bad = [0.0, 0.0, 0.0, 2.0, 1.8, 1.0, 1.5, 0.5, 0.5, 1.0];
    let good = [0.0, 0.0, 0.0, 4.0, 1.0, 3.5, 2.5, 1.2, 0.7, 1.0];
    let targets = [100.0, 100.0, -50.0, 30.0, 0.0, 1.0];
    let s = spec(Kind::FourBar, &targets, None);
    let rows: Vec<f64> = bad.iter().chain(good.iter()).copied().collect();
    let mut out = [0.0; 12];
    evaluate_into(&s, &rows, Some(2), &mut out, None).unwrap();
    assert!(out[3] > 0.0 && out[0] >= PENALTY);
    assert_eq!(out[9], 0.0);
    assert!(out[6] < out[0]);
    // Non-positive lengths and NaN: +∞.
    let rows = [0.0, 0.0, 0.0, 4.0, -1.0, 3.5, 2.5, 1.2, 0.7, 1.0];
    let mut out = [0.0; 6];
    evaluate_into(&s, &rows, Some(1), &mut out, None).unwrap();
    assert_eq!(out[0], f64::INFINITY);
}

#[test]
fn bad_specs_are_refused() {
    let targets = [0.0, 1.0, 2.0];
    let s = spec(Kind::FourBar, &targets, None);
    let mut out = [0.0; 6];
    assert!(evaluate_into(&s, &[0.0; 10], None, &mut out, None).is_err());
    let s = spec(Kind::FourBar, &[0.0, 1.0, f64::NAN, 2.0], None);
    assert!(evaluate_into(&s, &[0.0; 10], None, &mut out, None).is_err());
    let s = spec(Kind::FourBar, &[0.0, 1.0, 1.0, 2.0], Some(&[0.0]));
    assert!(evaluate_into(&s, &[0.0; 11], None, &mut out, None).is_err());
    let s = spec(Kind::FourBar, &[0.0, 1.0, 1.0, 2.0], None);
    assert!(evaluate_into(&s, &[0.0; 11], None, &mut out, None).is_err());
}

proptest! {
    /// The closed-form range (closure and transmission-angle extremes) over a
    /// crank interval against the same quantities sampled from the points
    /// placed by `fourbar_p`.
    #[test]
    fn fourbar_range_matches_sampling(
        r1 in 0.5f64..3.0, r2 in 0.2f64..3.0, r3 in 0.5f64..3.0, r4 in 0.5f64..3.0,
        th in -3.0f64..3.0, lo in -4.0f64..4.0, w in 0.0f64..6.5,
    ) {
        let row = [0.3, -0.1, th, r1, r2, r3, r4, 0.2, 0.1, 1.0];
        let c = Cand::new(Kind::FourBar, &row).unwrap();
        let (mlo, mhi, _, closes) = c.range(lo, lo + w);
        let mut all = true;
        let (mut slo, mut shi) = (f64::INFINITY, f64::NEG_INFINITY);
        for k in 0..=4000 {
            let phi = lo + w * k as f64 / 4000.0;
            match fourbar_p(&row, phi) {
                Some((b, cc, _)) => {
                    let d = [row[0] + r1 * th.cos(), row[1] + r1 * th.sin()];
                    let (e1, e2) = ([b[0] - cc[0], b[1] - cc[1]], [d[0] - cc[0], d[1] - cc[1]]);
                    let mu = ((e1[0] * e2[0] + e1[1] * e2[1]) / (r3 * r4)).clamp(-1.0, 1.0).acos();
                    slo = slo.min(mu);
                    shi = shi.max(mu);
                }
                None => all = false,
            }
        }
        if !all {
            prop_assert!(!closes);
        }
        if closes {
            prop_assert!(all);
            prop_assert!(mlo <= slo + 1e-9 && mhi >= shi - 1e-9, "{mlo} {mhi} vs {slo} {shi}");
            prop_assert!(slo - mlo < 1e-3 && mhi - shi < 1e-3);
        }
    }
}
