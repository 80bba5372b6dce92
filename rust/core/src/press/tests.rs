use std::f64::consts::TAU;

use super::criteria::*;
use super::kinematics::EXACT;
use super::kinematics::*;
use super::walk::{SHORTCUTS, SKIP_WALK};
use proptest::prelude::*;
use std::f64::consts::PI;

fn press(d: f64, l: f64, phi0: f64) -> Design {
    Design {
        big_r: 0.09,
        r: 0.03,
        d,
        l,
        phi0,
        offset: 0.0,
    }
}

fn solve(design: &Design, alpha: &[f64]) -> (Vec<f64>, Vec<f64>, Vec<f64>, Vec<bool>) {
    let n = alpha.len();
    let (mut s, mut ds, mut dds) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let (mut c, mut p, mut sl) = (vec![0.0; 2 * n], vec![0.0; 2 * n], vec![0.0; 2 * n]);
    let mut ok = vec![false; n];
    solve_into(
        &[*design],
        alpha,
        Some(1),
        KinOut {
            s: &mut s,
            ds: &mut ds,
            dds: &mut dds,
            centre: &mut c,
            pin: &mut p,
            slider: &mut sl,
            ok: &mut ok,
        },
    )
    .unwrap();
    (s, ds, dds, ok)
}

#[test]
fn rod_scan_is_the_same_on_every_instruction_set() {
    // The rod loop and extreme search compiled for scalar code, AVX2 and
    // AVX-512 (those the processor has): the same values and indices.
    use pulp::Simd;
    let m: usize = 361;
    let col = |f: &dyn Fn(f64) -> f64| (0..m).map(|j| f(j as f64 * 0.0174)).collect::<Vec<f64>>();
    let u2 = col(&|x| 0.01 * (1.0 + x.sin()).powi(2));
    let upx1 = col(&|x| 0.02 * x.cos());
    let hh = col(&|x| 0.001 * (2.0 * x).sin());
    let mut py = col(&|x| 0.3 * (x * 0.5).cos());
    py[200..210].fill(-0.4); // a dip: the lowest point is in it
    let mut py1 = col(&|x| -0.15 * (x * 0.5).sin());
    let mut py2 = col(&|x| -0.075 * (x * 0.5).cos());
    // Equal lowest samples in three lanes and in the remainder: the first wins.
    py[202] = -0.5;
    let (mut u2, mut upx1, mut hh) = (u2, upx1, hh);
    for j in [203, 207, 360] {
        for v in [&mut u2, &mut upx1, &mut hh, &mut py, &mut py1, &mut py2] {
            v[j] = v[202];
        }
    }
    // In blocks of LANES samples, the last one padded with sample 0 (as
    // PinScan::fill does).
    let nb = m.div_ceil(LANES);
    let cols = [&u2, &upx1, &hh, &py, &py1, &py2];
    let pin: Vec<[[f64; LANES]; 6]> = (0..nb)
        .map(|b| {
            std::array::from_fn(|k| {
                std::array::from_fn(|l| {
                    let j = b * LANES + l;
                    cols[k][if j < m { j } else { 0 }]
                })
            })
        })
        .collect();
    let runs = on_each_isa!(|simd| {
        let mut rows = vec![vec![[0.0; LANES]; nb]; 3];
        let mut cands = [Vec::new(), Vec::new(), Vec::new()];
        let [y, dy, ddy] = &mut rows[..] else {
            unreachable!()
        };
        let ex = Simd::vectorize(
            simd,
            RodScan {
                l2: 0.09,
                m,
                pin: &pin,
                out: [y, dy, ddy],
                cands: &mut cands,
            },
        );
        let flat = |v: &Vec<[f64; LANES]>| v.as_flattened()[..m].to_vec();
        ([ex.lo, ex.hi, ex.acc], cands, flat(y), flat(dy), flat(ddy))
    });
    let (_, first) = &runs[0];
    let (y, ddy) = (&first.2, &first.4);
    let lowest = (0..m).fold(0, |b, j| if y[j] < y[b] { j } else { b });
    let highest = (0..m).fold(0, |b, j| if y[j] > y[b] { j } else { b });
    let steepest = (0..m).fold(0, |b, j| if ddy[j].abs() > ddy[b].abs() { j } else { b });
    assert_eq!(first.0, [lowest, highest, steepest], "the first extremes");
    assert_eq!(lowest, 202);
    // The candidates by brute force: local maxima of |y''| within 1 % of
    // the largest, local minima (maxima) of y within the band of the lowest
    // (highest).
    let a = |j: usize| ddy[j % m].abs();
    let yc = |j: usize| y[j % m];
    let peaks: Vec<usize> = (0..m)
        .filter(|&j| a(j) >= 0.99 * a(steepest) && a(j) >= a(j + m - 1) && a(j) >= a(j + 1))
        .collect();
    assert!(peaks.contains(&steepest));
    let (ylo, yhi) = (y[lowest], y[highest]);
    let h = TAU / m as f64;
    let band = 0.25 * a(steepest) * h * h
        + TIE * (yhi - ylo)
        + 8.0 * f64::EPSILON * (ylo.abs() + yhi.abs());
    let lows: Vec<usize> = (0..m)
        .filter(|&j| yc(j) <= ylo + band && yc(j) <= yc(j + m - 1) && yc(j) <= yc(j + 1))
        .collect();
    let highs: Vec<usize> = (0..m)
        .filter(|&j| yc(j) >= yhi - band && yc(j) >= yc(j + m - 1) && yc(j) >= yc(j + 1))
        .collect();
    // The equal lowest samples 202, 203 (a flat pair), 207 and 360.
    assert_eq!(lows, [202, 203, 207, 360]);
    assert_eq!(first.1, [peaks, lows, highs]);
    for (isa, run) in &runs {
        assert_eq!(run, first, "{isa}");
    }
}

#[test]
fn crank_slider_limit_is_the_closed_form() {
    let (a, l) = (0.06, 0.25);
    let design = press(0.0, l, 0.3);
    let alpha: Vec<f64> = (0..=72).map(|k| k as f64 * PI / 36.0).collect();
    let (s, ds, dds, ok) = solve(&design, &alpha);
    for (q, &al) in alpha.iter().enumerate() {
        let (sa, ca) = al.sin_cos();
        let root = (l * l - a * a * sa * sa).sqrt();
        let s0 = a * (1.0 - ca) + l - root;
        let ds0 = a * sa + a * a * sa * ca / root;
        let dds0 = a * ca
            + a * a * (ca * ca - sa * sa) / root
            + a.powi(4) * sa * sa * ca * ca / root.powi(3);
        assert!(ok[q]);
        assert!((s[q] - s0).abs() < 1e-14, "S at {al}: {} vs {s0}", s[q]);
        assert!((ds[q] - ds0).abs() < 1e-14, "S' at {al}");
        assert!((dds[q] - dds0).abs() < 1e-13, "S'' at {al}");
    }
}

#[test]
fn criteria_of_the_crank_slider() {
    // Crank-slider with ω = 1: α_p from S(α_p) = S_p in closed form.
    let (a, l) = (0.06, 0.25);
    let spec = Spec {
        stroke: Stroke::Fraction(0.1),
        omega: 1.0,
        samples: 360,
    };
    let (row, status) = criteria(&press(0.0, l, 0.0), &spec).unwrap();
    assert_eq!(status, Status::Ok);
    assert!((row[0] - 2.0 * a).abs() < 1e-14);
    let s_p = 0.1 * 2.0 * a;
    let s = |al: f64| a * (1.0 - al.cos()) + l - (l * l - (a * al.sin()).powi(2)).sqrt();
    let alpha_p = row[2];
    assert!((s(alpha_p) - s_p).abs() < 1e-15);
    assert!(alpha_p > 0.0 && alpha_p < PI);
    // Speed falls monotonically to BDC: the peak is at the start.
    assert!((row[5] - row[3]).abs() < 1e-15);
    // J_max of a crank-slider is at BDC: a(1 + a/L).
    assert!((row[6] - a * (1.0 + a / l)).abs() < 1e-13, "{}", row[6]);
}

#[test]
fn first_contact_of_a_slider_that_dips_and_backs_off() {
    // Issue 16 item 1: coming down from TDC this slider first reaches S_p at
    // α ≈ 126.2° (the dense reference of tests/test_issue16_press.py gives
    // 126.22449…°), dips 1.55 mm below it, backs off above it and crosses it
    // again at α ≈ 76.0° (the old α_p).
    let spec = Spec {
        stroke: Stroke::Fraction(0.1),
        omega: 1.0,
        samples: 360,
    };
    let (row, status) = criteria(&press(0.028, 0.46, 56f64.to_radians()), &spec).unwrap();
    assert_eq!(status, Status::ReContacts);
    assert!(
        (row[2].to_degrees() - 126.2245).abs() < 1e-3,
        "{}",
        row[2].to_degrees()
    );
    // A shorter rod without the dip: ok, and the same from fewer samples.
    let (row, status) = criteria(&press(0.029, 0.25, 56f64.to_radians()), &spec).unwrap();
    assert_eq!(status, Status::Ok);
    let coarse = Spec {
        samples: 24,
        ..spec
    };
    let (row24, _) = criteria(&press(0.029, 0.25, 56f64.to_radians()), &coarse).unwrap();
    assert!((row[2] - row24[2]).abs() < 1e-9);
}

proptest! {
    #[test]
    fn derivatives_match_differences(d in 0.0f64..0.06, phi0 in -PI..PI, al in 0.1f64..6.0) {
        let design = press(d, 0.4, phi0);
        let h = 1e-6;
        let (s, ds, dds, ok) = solve(&design, &[al - h, al, al + h]);
        prop_assume!(ok.iter().all(|&o| o));
        prop_assert!(((s[2] - s[0]) / (2.0 * h) - ds[1]).abs() < 1e-7);
        prop_assert!(((ds[2] - ds[0]) / (2.0 * h) - dds[1]).abs() < 1e-6);
        let f = design.frame();
        let th = 1.234 + al;
        let fd = (f.at(th + h, 2).ddy - f.at(th - h, 2).ddy) / (2.0 * h);
        prop_assert!((fd - f.at(th, 3).dddy).abs() < 1e-6);
        let fd = (f.at(th + h, 3).dddy - f.at(th - h, 3).dddy) / (2.0 * h);
        let k = f.at(th, 4);
        prop_assert!((fd - k.ddddy).abs() < 1e-5 * (1.0 + k.ddddy.abs()), "{fd} {}", k.ddddy);
        prop_assert_eq!(k.dddy, f.at(th, 3).dddy);
    }
}

/// `Status::ALL` is indexed by code (the Python layer builds `STATUS` from it), and
/// every status has its own text.
#[test]
fn statuses_are_indexed_by_code_with_distinct_texts() {
    for (code, status) in Status::ALL.iter().enumerate() {
        assert_eq!(*status as usize, code);
    }
    let mut texts: Vec<&str> = Status::ALL.iter().map(|s| s.text()).collect();
    assert_eq!(texts[0], "ok");
    texts.sort_unstable();
    texts.dedup();
    assert_eq!(texts.len(), Status::ALL.len());
}

/// Criteria rows and status of `design`, with the walk's first pass skipping the
/// stretches far above S_p or going point by point.
fn criteria_walked(design: &Design, spec: &Spec, skip: bool) -> (Vec<u64>, Status) {
    criteria_shortcut(design, spec, skip, true)
}

/// [`criteria_walked`], with the walk's shortcuts of issue 37 (the early end
/// at TDC and the pass over the approach to S_p, [`SHORTCUTS`]) or without
/// (main's skipping walk before them).
fn criteria_shortcut(
    design: &Design,
    spec: &Spec,
    skip: bool,
    shortcuts: bool,
) -> (Vec<u64>, Status) {
    SKIP_WALK.with(|c| c.set(skip));
    SHORTCUTS.with(|c| c.set(shortcuts));
    let r = criteria(design, spec);
    SKIP_WALK.with(|c| c.set(true));
    SHORTCUTS.with(|c| c.set(true));
    let (row, status) = r.unwrap();
    (row.iter().map(|x| x.to_bits()).collect(), status)
}

/// The designs of the walk's proptests: designs that reach the guide or not,
/// dip and back off (re-contacts) or reverse, working strokes from near zero to
/// the whole stroke (k_Sp = 1 ends at TDC) and as lengths, coarse and fine
/// sampling, gear ratios 2–4 (invalid ones are left to `prop_assume!`).
fn walk_cases() -> impl Strategy<Value = (Design, Spec)> {
    (
        2usize..5,
        0.0f64..0.06,
        0.05f64..0.6,
        -PI..PI,
        prop_oneof![
            (1e-3f64..1.0).prop_map(Stroke::Fraction),
            Just(Stroke::Fraction(1.0)),
            (1e-4f64..0.2).prop_map(Stroke::Length),
        ],
        prop_oneof![Just(360usize), 8usize..100, 500usize..2000],
    )
        .prop_map(|(ratio, d, l, phi0, stroke, samples)| {
            let design = Design {
                big_r: 0.03 * ratio as f64,
                r: 0.03,
                d,
                l,
                phi0,
                offset: 0.0,
            };
            (
                design,
                Spec {
                    stroke,
                    omega: 3.0,
                    samples,
                },
            )
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]
    /// The first pass that skips the stretches far above S_p finds the same
    /// contact, the same re-contacts and so the same criteria, bit for bit, as
    /// the pass that visits every point: over designs that reach the guide or
    /// not, dip and back off (re-contacts) or reverse, working strokes from
    /// near zero to the whole stroke (k_Sp = 1 ends at TDC) and as lengths,
    /// coarse and fine sampling, gear ratios 2–4.
    #[test]
    fn skipping_the_far_stretches_changes_nothing(
        (design, spec) in walk_cases(),
    ) {
        prop_assume!(design.validate().is_ok());
        let skipped = criteria_walked(&design, &spec, true);
        let visited = criteria_walked(&design, &spec, false);
        // Without the shortcuts (the early end once the rest up to TDC is far
        // above S_p, the pass over the approach from BDC to S_p).
        let long_way = criteria_shortcut(&design, &spec, true, false);
        prop_assert_eq!(&skipped, &visited);
        prop_assert_eq!(&skipped, &long_way);
    }
}

#[test]
fn skipping_keeps_the_dip_and_back_off() {
    // The re-contacting slider of issue 16 (a dip below S_p after the first
    // contact): the same row and status either way.
    let spec = Spec {
        stroke: Stroke::Fraction(0.1),
        omega: 1.0,
        samples: 360,
    };
    for (d, l) in [(0.028, 0.46), (0.029, 0.25), (0.0, 0.3), (0.059, 0.5)] {
        let design = press(d, l, 56f64.to_radians());
        let skipped = criteria_walked(&design, &spec, true);
        assert_eq!(
            skipped,
            criteria_walked(&design, &spec, false),
            "d = {d}, L = {l}"
        );
        assert_eq!(
            skipped,
            criteria_shortcut(&design, &spec, true, false),
            "d = {d}, L = {l}, without the shortcuts"
        );
    }
    let (_, status) = criteria_walked(&press(0.028, 0.46, 56f64.to_radians()), &spec, true);
    assert_eq!(status, Status::ReContacts);
}

/// Criteria of `design` with the reference arithmetic ([`EXACT`]: sin/cos of
/// β itself, the exact √ and division in the rod scan) or the fast one.
fn criteria_exact(design: &Design, spec: &Spec, exact: bool) -> (Vec<f64>, Status) {
    EXACT.with(|c| c.set(exact));
    let r = criteria(design, spec);
    EXACT.with(|c| c.set(false));
    r.unwrap()
}

/// Where a row of the fast arithmetic differs from the reference's: the
/// largest difference of a column over its scale — the larger of the two
/// values, or the column's own scale where the value itself can be ~0:
/// heights by S_n, speeds by V_pmax, the speed ratio k_Vp by k_Vmax, angles
/// by one radian (θ_BDC on the circle) — and that column.
fn row_deviation(fast: &[f64], exact: &[f64]) -> (f64, usize) {
    let scale = |row: &[f64], c: usize| -> f64 {
        match c {
            0 | 1 => row[0].abs(),
            3..=5 => row[5].abs(),
            9 => row[10].abs(),
            2 | 13 => 1.0,
            _ => 0.0,
        }
    };
    let mut worst = (0.0f64, 0);
    for c in 0..CRITERIA.len() {
        let (a, b) = (fast[c], exact[c]);
        if a.is_nan() && b.is_nan() {
            continue;
        }
        let mut diff = (a - b).abs();
        if c == 13 {
            diff = diff.min(TAU - diff);
        }
        let unit = a
            .abs()
            .max(b.abs())
            .max(scale(fast, c))
            .max(scale(exact, c));
        let dev = if diff == 0.0 { 0.0 } else { diff / unit };
        // (NaN against a number counts as infinitely far.)
        let dev = if dev.is_nan() { f64::INFINITY } else { dev };
        if dev > worst.0 {
            worst = (dev, c);
        }
    }
    worst
}

#[test]
fn fast_turn_is_sin_cos_of_beta() {
    // Frame::at_pow's (cos β, sin β) as e^{iβ0}·(e^{−iθ})^k against sin/cos of
    // β = β0 − kθ (Frame::at), every gear ratio, angles over several turns.
    for ratio in 2..=64 {
        let design = Design {
            big_r: 0.01 * ratio as f64,
            r: 0.01,
            d: 0.007,
            l: 2.0,
            phi0: 0.37,
            offset: 0.001,
        };
        design.validate().unwrap();
        let f = design.frame();
        // The derivatives' scale: the pin's excursion times the power of k
        // each brings (k⁴·d for y'''').
        let k = f.k;
        let unit = f.a + f.d * k.powi(4) + 1.0;
        for q in 0..200 {
            let th = -7.0 + 0.137 * q as f64;
            let (a, b) = (f.at(th, 4), f.at_pow(th, 4));
            for (x, y, what) in [
                (a.y, b.y, "y"),
                (a.dy, b.dy, "dy"),
                (a.ddy, b.ddy, "ddy"),
                (a.dddy, b.dddy, "dddy"),
                (a.ddddy, b.ddddy, "ddddy"),
            ] {
                assert!(
                    (x - y).abs() <= 1e-13 * unit * (1.0 + k),
                    "ratio {ratio}, θ = {th}, {what}: {x} vs {y}"
                );
            }
        }
    }
}

#[test]
fn fast_reciprocal_keeps_the_rod_scan() {
    // The rod scan with w and 1/w from an estimate of 1/√ and its correction
    // against the exact √ and division: y, y' and y'' within a few ulps of
    // their terms, the same extremes and candidates.
    for (d, l) in [(0.021, 0.31), (0.03, 0.2), (0.0, 0.07), (0.05, 0.12)] {
        let f = press(d, l, 0.7).frame();
        let table = Table::new(3.0, 361);
        let m = table.len();
        let run = |exact: bool| {
            EXACT.with(|c| c.set(exact));
            let mut scan = PinScan::default();
            scan.fill(&f, &table);
            let ex = scan.rod(f.l * f.l, m);
            EXACT.with(|c| c.set(false));
            let flat = |v: &Vec<[f64; LANES]>| v.as_flattened()[..m].to_vec();
            (
                [ex.lo, ex.hi, ex.acc],
                scan.cands.clone(),
                flat(&scan.y),
                flat(&scan.dy),
                flat(&scan.ddy),
            )
        };
        let (fast, exact) = (run(false), run(true));
        assert_eq!(fast.0, exact.0, "d = {d}, L = {l}");
        assert_eq!(fast.1, exact.1, "d = {d}, L = {l}");
        let unit = |v: &[f64]| v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        for (a, b) in [
            (&fast.2, &exact.2),
            (&fast.3, &exact.3),
            (&fast.4, &exact.4),
        ] {
            let tol = 8.0 * f64::EPSILON * unit(b);
            for j in 0..m {
                assert!(
                    (a[j] - b[j]).abs() <= tol,
                    "d = {d}, L = {l}, sample {j}: {} vs {}",
                    a[j],
                    b[j]
                );
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]
    /// The fast arithmetic (one sin/cos per refinement evaluation, w and 1/w
    /// from an estimate of 1/√ in the rod scan) against the reference ([`EXACT`]): the
    /// same status, and every column within 1e-12 of its scale
    /// ([`row_deviation`]), over the designs of the walk's proptest.
    #[test]
    fn fast_arithmetic_is_the_exact_within_1e12(
        (design, spec) in walk_cases(),
    ) {
        prop_assume!(design.validate().is_ok());
        let (fast, st_fast) = criteria_exact(&design, &spec, false);
        let (exact, st_exact) = criteria_exact(&design, &spec, true);
        prop_assert_eq!(st_fast, st_exact);
        let (dev, col) = row_deviation(&fast, &exact);
        prop_assert!(dev <= 1e-12, "{} off by {:e}: {:?} vs {:?}", CRITERIA[col], dev, fast, exact);
    }
}

/// The grid of issue 37 (d, L, φ0) as `benches/bench_press.py` sweeps it, with
/// `n` values of d and of L (100 there) and 20 of φ0.
fn bench_grid(n: usize) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let lin = |a: f64, b: f64, n: usize, end: bool| -> Vec<f64> {
        let div = if end { (n - 1) as f64 } else { n as f64 };
        (0..n).map(|i| a + (b - a) * i as f64 / div).collect()
    };
    (
        lin(0.0, 0.04, n, true),
        lin(0.3, 0.5, n, true),
        lin(0.0, 2.0 * PI / 3.0, 20, false),
    )
}

/// Sweep of the grid `axes` (d, L, φ0) with the fast or the reference
/// arithmetic: rows and statuses.
fn sweep_exact(axes: &(Vec<f64>, Vec<f64>, Vec<f64>), exact: bool) -> (Vec<f64>, Vec<u8>) {
    let grid = super::sweep::Grid {
        big_r: &[0.09],
        r: &[0.03],
        d: &axes.0,
        l: &axes.1,
        phi0: &axes.2,
        offset: 0.0,
    };
    let spec = Spec {
        stroke: Stroke::Fraction(0.1),
        omega: 4.0,
        samples: 360,
    };
    let n = grid.len();
    let (mut rows, mut status) = (vec![0.0; n * CRITERIA.len()], vec![0u8; n]);
    EXACT.with(|c| c.set(exact));
    let r = super::sweep::sweep_into(&grid, &spec, Some(1), &mut rows, &mut status);
    EXACT.with(|c| c.set(false));
    r.unwrap();
    (rows, status)
}

/// Fast against reference arithmetic over a sweep: how many statuses differ,
/// the largest deviation of a row ([`row_deviation`]) and its column.
fn sweep_deviation(axes: &(Vec<f64>, Vec<f64>, Vec<f64>)) -> (usize, f64, &'static str) {
    let (fast, st_fast) = sweep_exact(axes, false);
    let (exact, st_exact) = sweep_exact(axes, true);
    let flips = st_fast
        .iter()
        .zip(&st_exact)
        .filter(|(a, b)| a != b)
        .count();
    let nc = CRITERIA.len();
    let mut worst = (0.0, CRITERIA[0]);
    for (a, b) in fast.chunks(nc).zip(exact.chunks(nc)) {
        let (dev, col) = row_deviation(a, b);
        if dev > worst.0 {
            worst = (dev, CRITERIA[col]);
        }
    }
    (flips, worst.0, worst.1)
}

#[test]
fn fast_arithmetic_keeps_the_bench_grid() {
    // A 12 × 12 × 20 cut of the bench grid (the whole grid in the timing
    // test): the same statuses, every row within 1e-12 of the reference's.
    let (flips, dev, col) = sweep_deviation(&bench_grid(12));
    assert_eq!(flips, 0);
    assert!(dev <= 1e-12, "{col} off by {dev:e}");
}

/// Time of the sweep over issue 37's 100 × 100 × 20 grid (d, L, φ0) on one
/// thread, best of a few rounds, and a checksum of the rows' bits (to compare
/// builds): `cargo test --release -p cyclomech-core press_sweep_timing --
/// --ignored --nocapture`. Not a test of speed (no assertion on time).
#[test]
#[ignore]
fn press_sweep_timing() {
    let axes = bench_grid(100);
    // The fast arithmetic against the reference on the whole grid first.
    let (flips, dev, col) = sweep_deviation(&axes);
    println!(
        "fast vs exact arithmetic: {flips} statuses differ, largest deviation {dev:e} ({col})"
    );
    assert_eq!(flips, 0);
    assert!(dev <= 1e-12);
    let (d, l, phi0) = axes;
    let grid = super::sweep::Grid {
        big_r: &[0.09],
        r: &[0.03],
        d: &d,
        l: &l,
        phi0: &phi0,
        offset: 0.0,
    };
    let spec = Spec {
        stroke: Stroke::Fraction(0.1),
        omega: 4.0,
        samples: 360,
    };
    let n = grid.len();
    let mut rows = vec![0.0; n * CRITERIA.len()];
    let mut status = vec![0u8; n];
    // Evaluations of the kinematics a design by the refinements (BDC, TDC, α_p,
    // the acceleration peak, now and then a speed peak): each refinement's
    // start is meant to be good enough for one evaluation (round 5 counted
    // 4.15 a design on this grid), so more than five means a start got worse.
    super::kinematics::EVALS.with(|c| c.set(0));
    super::sweep::sweep_into(&grid, &spec, Some(1), &mut rows, &mut status).unwrap();
    let evals = super::kinematics::EVALS.with(|c| c.get()) as f64 / n as f64;
    println!("evaluations of the kinematics by the refinements: {evals:.3} a design");
    assert!(evals <= 5.0, "{evals} evaluations a design");
    // This thread's time on a CPU [s] (Linux; the wall clock elsewhere): on a
    // shared machine the wall clock also counts the other processes' turns.
    let cpu = || {
        std::fs::read_to_string("/proc/thread-self/schedstat")
            .ok()
            .and_then(|s| s.split_whitespace().next()?.parse::<f64>().ok())
            .map(|ns| ns * 1e-9)
    };
    // Interleaved rounds of the kernel as it is (fast arithmetic, the walk's
    // shortcuts), with the exact arithmetic of round 2 ([`EXACT`]), and with
    // neither (main's walk before round 2): best wall and CPU time of each,
    // and a checksum of each's rows.
    let configs = [
        ("fast arithmetic + shortcuts", false, true),
        ("exact arithmetic + shortcuts (round 2)", true, true),
        ("exact arithmetic, reference walk", true, false),
    ];
    let mut best = [[f64::INFINITY; 2]; 3];
    let mut sums = [0u64; 3];
    for _ in 0..5 {
        for (k, &(_, exact, shortcuts)) in configs.iter().enumerate() {
            SHORTCUTS.with(|c| c.set(shortcuts));
            EXACT.with(|c| c.set(exact));
            let (t, c) = (std::time::Instant::now(), cpu());
            super::sweep::sweep_into(&grid, &spec, Some(1), &mut rows, &mut status).unwrap();
            best[k][0] = best[k][0].min(t.elapsed().as_secs_f64());
            if let (Some(a), Some(b)) = (c, cpu()) {
                best[k][1] = best[k][1].min(b - a);
            }
            sums[k] = rows
                .iter()
                .chain(
                    status
                        .iter()
                        .map(|&s| &[0.0, 1.0, 2.0, 3.0, 4.0][s as usize]),
                )
                .fold(0u64, |a, x| a.rotate_left(5) ^ x.to_bits());
        }
    }
    SHORTCUTS.with(|c| c.set(true));
    EXACT.with(|c| c.set(false));
    for (k, (name, ..)) in configs.iter().enumerate() {
        println!(
            "press sweep 100x100x20, {name}: best {:.3} us/design (CPU {:.3}), checksum {:016x}",
            best[k][0] / n as f64 * 1e6,
            best[k][1] / n as f64 * 1e6,
            sums[k]
        );
    }
}
