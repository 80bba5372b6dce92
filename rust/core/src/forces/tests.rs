//! Kinetostatics against closed forms and a dense solver (nalgebra's LU of the
//! whole system, no block order).

use proptest::prelude::*;

use super::solve::Pose;
use super::*;

const G: f64 = 9.81;

fn body(points: &[usize], mass: f64, com_uv: V2, inertia: f64) -> Body {
    Body {
        points: points.to_vec(),
        mass,
        com_uv,
        inertia,
    }
}

/// Solve one pose; values per part: [torque, guides…, reactions…].
fn one(model: &Model, xy: &[V2], vel: &[V2], acc: &[V2], force: Option<&[V2]>) -> Vec<f64> {
    let flat = |v: &[V2]| v.iter().flat_map(|p| *p).collect::<Vec<f64>>();
    let w = model.width(true);
    let mut values = vec![0.0; 3 * w];
    let mut conditioning = vec![0.0];
    let f = force.map(flat);
    let (x, v, a) = (flat(xy), flat(vel), flat(acc));
    let inputs = Inputs {
        xy: &x,
        vel: &v,
        acc: &a,
        force: f.as_deref(),
        torque: None,
    };
    solve_into(
        model,
        inputs,
        Outputs {
            values: &mut values,
            conditioning: &mut conditioning,
            reactions: true,
            analogs: None,
        },
        Some(1),
    )
    .unwrap();
    assert!(conditioning[0] > 1e-6, "{}", conditioning[0]);
    values
}

/// A crank O–A with a point mass at A: M = m g r cos φ holds it against gravity,
/// m r² ε accelerates it, and at constant speed no torque (the pull is radial).
#[test]
fn crank_pendulum_closed_form() {
    let (m, r, phi) = (2.0, 0.3, 0.7_f64);
    let spec = Spec {
        n_points: 2,
        bodies: vec![body(&[0, 1], m, [1.0, 0.0], 0.0)],
        ground: vec![0],
        point_mass: vec![0.0; 2],
        guides: vec![],
        driver: 0,
        gravity: [0.0, -G],
    };
    let model = Model::new(spec).unwrap();
    assert_eq!(model.block_sizes(), vec![1, 1, 1]);
    let (s, c) = phi.sin_cos();
    let xy = [[0.0, 0.0], [r * c, r * s]];
    let vel = [[0.0, 0.0], [-r * s, r * c]];
    let acc = [[0.0, 0.0], [-r * c, -r * s]];
    let v = one(&model, &xy, &vel, &acc, None);
    let w = v.len() / 3;
    assert!(v[0].abs() < 1e-12, "ω² part {}", v[0]);
    assert!((v[w] - m * r * r).abs() < 1e-12, "ε part {}", v[w]);
    assert!(
        (v[2 * w] - m * G * r * c).abs() < 1e-12,
        "static {}",
        v[2 * w]
    );
    // The bearing carries the weight (static) and the centripetal pull (ω²).
    let (fx, fy) = (v[2 * w + 1], v[2 * w + 2]);
    assert!(fx.abs() < 1e-12 && (fy + m * G).abs() < 1e-12, "{fx} {fy}");
    assert!((v[1] - m * r * c).abs() < 1e-12 && (v[2] - m * r * s).abs() < 1e-12);
}

/// Slider-crank positions and analogs in closed form: O = 0, A = 1, C = 2 on x.
fn slider_crank(r: f64, l: f64, phi: f64) -> ([V2; 3], [V2; 3], [V2; 3]) {
    let (s, c) = phi.sin_cos();
    let q = (l * l - r * r * s * s).sqrt();
    let x = r * c + q;
    // q' = −r² s c / q, q'' = −r²(c² − s²)/q − (r² s c)²/q³
    let q1 = -r * r * s * c / q;
    let q2 = -r * r * (c * c - s * s) / q - (r * r * s * c).powi(2) / q.powi(3);
    (
        [[0.0, 0.0], [r * c, r * s], [x, 0.0]],
        [[0.0, 0.0], [-r * s, r * c], [-r * s + q1, 0.0]],
        [[0.0, 0.0], [-r * c, -r * s], [-r * c + q2, 0.0]],
    )
}

fn slider_spec(mc: f64, rod: (f64, f64)) -> Spec {
    Spec {
        n_points: 3,
        bodies: vec![
            body(&[0, 1], 0.0, [0.5, 0.0], 0.0),
            body(&[1, 2], rod.0, [0.5, 0.0], rod.1),
        ],
        ground: vec![0],
        point_mass: vec![0.0, 0.0, mc],
        guides: vec![Guide::Fixed {
            point: 2,
            dir: [1.0, 0.0],
        }],
        driver: 0,
        gravity: [0.0, 0.0],
    }
}

/// The textbook massless slider-crank under a piston force F (along −x, the gas
/// pressure on the piston of an engine): the gas turns the crank with the torque
/// T = F·r·sin(φ + β)/cos β (Uicker, Pennock & Shigley, *Theory of Machines and
/// Mechanisms*, the engine's force analysis), so the driving torque that holds
/// the crank is M = −T; the rod carries F/cos β and the guide F·tan β (β the
/// rod's angle, sin β = r sin φ / l).
#[test]
fn slider_crank_gas_force_closed_form() {
    let (r, l, f) = (0.1, 0.35, 1000.0);
    let model = Model::new(slider_spec(0.0, (0.0, 0.0))).unwrap();
    assert_eq!(model.block_sizes(), vec![3, 1, 1, 1]);
    for k in 1..36 {
        let phi = k as f64 * 10f64.to_radians();
        let (xy, vel, acc) = slider_crank(r, l, phi);
        let force = [[0.0, 0.0], [0.0, 0.0], [-f, 0.0]];
        let v = one(&model, &xy, &vel, &acc, Some(&force));
        let st = &v[2 * v.len() / 3..];
        let beta = (r * phi.sin() / l).asin();
        let m = -f * r * (phi + beta).sin() / beta.cos();
        assert!(
            (st[0] - m).abs() < 1e-9 * f * r,
            "φ {k}0°: {} vs {m}",
            st[0]
        );
        // The rod pushes the piston towards the frame's −y side for 0 < φ < π:
        // the guide pushes back along +y (its normal, (0, 1)).
        let n = f * beta.tan();
        assert!(
            (st[1] - n).abs() < 1e-9 * f,
            "φ {k}0°: guide {} vs {n}",
            st[1]
        );
        // Pairs: O(frame, crank), A(crank, rod), C(rod).
        let rod = (st[2 + 6], st[2 + 7]);
        assert!(((rod.0 * rod.0 + rod.1 * rod.1).sqrt() - f / beta.cos()).abs() < 1e-9 * f);
    }
}

/// Power balance with inertia: M ω = d(kinetic energy)/dt for a slider-crank
/// with a piston mass and a rod with mass and inertia, at ω = 1 (part 0): M =
/// Σ m a·v + J α Ω in analogs.
#[test]
fn slider_crank_inertia_power_balance() {
    let (r, l, mc, mr, jr) = (0.1, 0.35, 3.0, 2.0, 0.02);
    let model = Model::new(slider_spec(mc, (mr, jr))).unwrap();
    for k in 0..36 {
        let phi = 0.05 + k as f64 * 10f64.to_radians();
        let (xy, vel, acc) = slider_crank(r, l, phi);
        let v = one(&model, &xy, &vel, &acc, None);
        let mid = |x: &[V2; 3]| [(x[1][0] + x[2][0]) / 2.0, (x[1][1] + x[2][1]) / 2.0];
        let (cv, ca) = (mid(&vel), mid(&acc));
        let d = sub(xy[2], xy[1]);
        let (d1, d2) = (sub(vel[2], vel[1]), sub(acc[2], acc[1]));
        let w = cross(d, d1) / dot(d, d);
        let al = cross(d, d2) / dot(d, d) - 2.0 * dot(d, d1) * w / dot(d, d);
        let power = mc * acc[2][0] * vel[2][0] + mr * dot(ca, cv) + jr * al * w;
        assert!((v[0] - power).abs() < 1e-10, "{} vs {power}", v[0]);
    }
}

use crate::geom::{cross, dot, sub};

/// The dense system of one pose, solved by nalgebra's LU of the whole matrix.
fn dense(model: &Model, pose: &Pose) -> Option<nalgebra::DMatrix<f64>> {
    struct D {
        a: nalgebra::DMatrix<f64>,
        r: nalgebra::DMatrix<f64>,
    }
    impl Sink for D {
        fn a(&mut self, row: usize, col: usize, v: f64) {
            self.a[(row, col)] += v;
        }
        fn rhs(&mut self, row: usize, part: usize, v: f64) {
            self.r[(row, part)] += v;
        }
    }
    let n = model.unknowns();
    let mut d = D {
        a: nalgebra::DMatrix::zeros(n, n),
        r: nalgebra::DMatrix::zeros(n, 3),
    };
    model.assemble(pose, &mut d);
    d.a.lu().solve(&d.r)
}

/// A four-bar A(0,0)–B–C–D(d,0) at crank angle φ, by circle intersection, with
/// analogs by the differentiated loop equations.
fn four_bar(a: f64, b: f64, c: f64, d: f64, phi: f64) -> Option<([V2; 4], [V2; 4], [V2; 4])> {
    let pb = [a * phi.cos(), a * phi.sin()];
    let pd = [d, 0.0];
    let e = sub(pd, pb);
    let dist = dot(e, e).sqrt();
    let x = (b * b - c * c + dist * dist) / (2.0 * dist);
    let h2 = b * b - x * x;
    if h2 <= 1e-6 * b * b {
        return None;
    }
    let h = h2.sqrt();
    let u = [e[0] / dist, e[1] / dist];
    let pc = [pb[0] + x * u[0] - h * u[1], pb[1] + x * u[1] + h * u[0]];
    let vb = [-pb[1], pb[0]];
    let ab = [-pb[0], -pb[1]];
    // (c − b)·(c' − b') = 0, (c − d)·c' = 0.
    let (r1, r2) = (sub(pc, pb), sub(pc, pd));
    let det = r1[0] * r2[1] - r1[1] * r2[0];
    let solve = |s1: f64, s2: f64| {
        [
            (s1 * r2[1] - s2 * r1[1]) / det,
            (r1[0] * s2 - r2[0] * s1) / det,
        ]
    };
    let vc = solve(dot(r1, vb), 0.0);
    let w1 = sub(vc, vb);
    let ac = solve(dot(r1, ab) - dot(w1, w1), -dot(vc, vc));
    let z = [0.0, 0.0];
    Some(([[0.0, 0.0], pb, pc, pd], [z, vb, vc, z], [z, ab, ac, z]))
}

proptest! {
    /// The block order gives the dense LU's solution (a different solver), for
    /// random four-bars, masses, inertias, gravity and a load on the coupler.
    #[test]
    fn block_solve_matches_dense_lu(
        b in 2.0f64..4.0, c in 2.0f64..4.0, d in 2.5f64..4.0, phi in 0.0f64..std::f64::consts::TAU,
        m in proptest::collection::vec(0.0f64..5.0, 3), j in proptest::collection::vec(0.0f64..1.0, 3),
        u in -0.5f64..1.5, v in -0.5f64..0.5, fx in -100.0f64..100.0, gy in -10.0f64..0.0,
    ) {
        let Some((xy, vel, acc)) = four_bar(1.0, b, c, d, phi) else { return Ok(()); };
        let spec = Spec {
            n_points: 4,
            bodies: vec![
                body(&[0, 1], m[0], [0.5, 0.1], j[0]),
                body(&[1, 2], m[1], [u, v], j[1]),
                body(&[3, 2], m[2], [0.4, -0.2], j[2]),
            ],
            ground: vec![0, 3],
            point_mass: vec![0.0, 0.5, 0.0, 0.0],
            guides: vec![],
            driver: 0,
            gravity: [0.3, gy],
        };
        let model = Model::new(spec).unwrap();
        prop_assert_eq!(model.block_sizes(), vec![6, 1, 1, 1]);
        let force = [[0.0, 0.0], [0.0, 0.0], [fx, 10.0], [0.0, 0.0]];
        let got = one(&model, &xy, &vel, &acc, Some(&force));
        let mut pose = Pose::structural(model.spec());
        let flat = |v: &[V2]| v.iter().flat_map(|p| *p).collect::<Vec<f64>>();
        let (fxy, fv, fa, ff) = (flat(&xy), flat(&vel), flat(&acc), flat(&force));
        prop_assert!(pose.fill(model.spec(), super::solve::tests_row(&fxy, &fv, &fa, &ff)));
        let x = dense(&model, &pose).expect("not singular");
        let w = got.len() / 3;
        for part in 0..3 {
            let t = x[(model.torque_col, part)];
            let scale = 1.0 + t.abs();
            prop_assert!((got[part * w] - t).abs() < 1e-9 * scale, "part {} {} vs {}", part, got[part * w], t);
        }
    }
}

/// A linkage with a redundant link is refused, not solved.
#[test]
fn indeterminate_is_an_error() {
    let spec = Spec {
        n_points: 2,
        bodies: vec![body(&[0, 1], 1.0, [0.5, 0.0], 0.0)],
        ground: vec![0, 1],
        point_mass: vec![0.0; 2],
        guides: vec![],
        driver: 0,
        gravity: [0.0, 0.0],
    };
    let e = Model::new(spec).unwrap_err();
    assert!(e.to_string().contains("statically determinate"), "{e}");
}

/// At a dead centre of the dyad the angle is flagged singular and NaN.
#[test]
fn dead_centre_is_singular() {
    // Four-bar 1, 2, 2, 3: at φ = 0, B = (1, 0), D = (3, 0), C on B–D's line? No:
    // |BD| = 2 < 4. Use a slider-crank at φ = 90° with l = r: the rod is vertical.
    let (r, l) = (0.1, 0.1);
    let model = Model::new(slider_spec(1.0, (0.0, 0.0))).unwrap();
    let phi = std::f64::consts::FRAC_PI_2;
    let xy = [[0.0, 0.0], [r * phi.cos(), r], [0.0, 0.0]];
    let _ = l;
    let z = [[0.0, 0.0]; 3];
    let flat = |v: &[V2]| v.iter().flat_map(|p| *p).collect::<Vec<f64>>();
    let mut values = vec![0.0; 3 * model.width(true)];
    let mut conditioning = vec![0.0];
    let (x, zz) = (flat(&xy), flat(&z));
    let inputs = Inputs {
        xy: &x,
        vel: &zz,
        acc: &zz,
        force: None,
        torque: None,
    };
    solve_into(
        &model,
        inputs,
        Outputs {
            values: &mut values,
            conditioning: &mut conditioning,
            reactions: true,
            analogs: None,
        },
        Some(1),
    )
    .unwrap();
    assert_eq!(conditioning[0], 0.0);
    assert!(values.iter().all(|v| v.is_nan()));
}

/// `solve_into` (angles in SIMD lanes, the rest one by one) and the
/// one-angle-at-a-time path, on the same inputs: equal bit for bit (NaN where
/// the other is NaN).
/// Returns the conditioning.
fn lanes_match_scalar(
    model: &Model,
    xy: &[f64],
    vel: &[f64],
    acc: &[f64],
    force: &[f64],
    torque: &[f64],
) -> Vec<f64> {
    let n = torque.len() / model.spec().bodies.len();
    let mut out = Vec::new();
    for reactions in [true, false] {
        let inputs = Inputs {
            xy,
            vel,
            acc,
            force: Some(force),
            torque: Some(torque),
        };
        let w = model.width(reactions);
        let mut values = vec![0.0; 3 * n * w];
        let (mut conds, mut ratios) = (vec![0.0; n], vec![0.0; n]);
        solve_into(
            model,
            inputs,
            Outputs {
                values: &mut values,
                conditioning: &mut conds,
                reactions,
                analogs: Some(&mut ratios),
            },
            Some(1),
        )
        .unwrap();
        let (rv, rc, rr) = solve::tests_scalar(model, inputs, reactions);
        let same = |a: &[f64], b: &[f64], what: &str| {
            for (i, (x, y)) in a.iter().zip(b).enumerate() {
                assert!(
                    x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan()),
                    "{what}[{i}]: lanes {x:e}, scalar {y:e}"
                );
            }
        };
        same(&values, &rv, "values");
        same(&conds, &rc, "conditioning");
        same(&ratios, &rr, "analog ratio");
        out = conds;
    }
    out
}

proptest! {
    /// Four-bars of random size, masses and loads at 19 random crank angles
    /// (two groups of lanes and a tail of three), one angle with a NaN input
    /// and one folded flat (a dead centre of the dyad): the lanes give the
    /// scalar path's values bit for bit, flags included.
    #[test]
    fn lanes_are_the_scalar_path_bit_for_bit(
        b in 2.0f64..4.0, c in 2.0f64..4.0, d in 2.5f64..4.0,
        phis in proptest::collection::vec(0.0f64..std::f64::consts::TAU, 19),
        m in proptest::collection::vec(0.0f64..5.0, 3), j in proptest::collection::vec(0.0f64..1.0, 3),
        u in -0.5f64..1.5, v in -0.5f64..0.5, loads in proptest::collection::vec(-50.0f64..50.0, 19),
        nan_at in 0usize..19, flat_at in 0usize..19,
    ) {
        let spec = Spec {
            n_points: 4,
            bodies: vec![
                body(&[0, 1], m[0], [0.5, 0.1], j[0]),
                body(&[1, 2], m[1], [u, v], j[1]),
                body(&[3, 2], m[2], [0.4, -0.2], j[2]),
            ],
            ground: vec![0, 3],
            point_mass: vec![0.0, 0.5, 0.0, 0.0],
            guides: vec![],
            driver: 0,
            gravity: [0.3, -9.81],
        };
        let model = Model::new(spec).unwrap();
        let (mut xy, mut vel, mut acc, mut force, mut torque) = (vec![], vec![], vec![], vec![], vec![]);
        for (i, &phi) in phis.iter().enumerate() {
            let (p, pv, pa) = four_bar(1.0, b, c, d, phi)
                .or_else(|| four_bar(1.0, 3.0, 3.0, 3.0, phi))
                .expect("the 1-3-3-3 four-bar assembles everywhere");
            let mut p = p;
            if i == flat_at {
                // C on the line B–D: the dyad's two links in line.
                let bd = sub(p[3], p[1]);
                p[2] = [p[1][0] + 0.5 * bd[0], p[1][1] + 0.5 * bd[1]];
            }
            xy.extend(p.iter().flatten());
            vel.extend(pv.iter().flatten());
            acc.extend(pa.iter().flatten());
            force.extend([0.0, 0.0, 0.0, 0.0, loads[i], 10.0, 0.0, 0.0]);
            torque.extend([0.0, 0.5 * loads[i], -loads[i]]);
        }
        acc[nan_at * 8 + 5] = f64::NAN;
        let cond = lanes_match_scalar(&model, &xy, &vel, &acc, &force, &torque);
        prop_assert!(cond[nan_at].is_nan());
        prop_assert!(flat_at == nan_at || cond[flat_at] == 0.0, "folded: {}", cond[flat_at]);
        prop_assert!(cond.iter().enumerate().all(|(i, &c)| i == nan_at || i == flat_at || c > 0.0));
    }

    /// The same for slider-cranks (a guide of the frame), the slider at
    /// random angles and once exactly at the dead centre l = r, φ = 90°.
    #[test]
    fn slider_lanes_are_the_scalar_path_bit_for_bit(
        l in 0.2f64..0.6, mc in 0.0f64..5.0, mr in 0.0f64..3.0, jr in 0.0f64..0.1,
        phis in proptest::collection::vec(0.0f64..std::f64::consts::TAU, 17),
        dead_at in 0usize..17,
    ) {
        let model = Model::new(Spec { gravity: [0.0, -9.81], ..slider_spec(mc, (mr, jr)) }).unwrap();
        let (mut xy, mut vel, mut acc, mut force, mut torque) = (vec![], vec![], vec![], vec![], vec![]);
        for (i, &phi) in phis.iter().enumerate() {
            let (p, pv, pa) = if i == dead_at {
                let z = [[0.0, 0.0]; 3];
                ([[0.0, 0.0], [0.0, 0.1], [0.0, 0.0]], z, z)
            } else {
                slider_crank(0.1, l, phi)
            };
            xy.extend(p.iter().flatten());
            vel.extend(pv.iter().flatten());
            acc.extend(pa.iter().flatten());
            force.extend([0.0, 0.0, 0.0, 0.0, -100.0 * phi, 0.0]);
            torque.extend([phi, 0.0]);
        }
        let cond = lanes_match_scalar(&model, &xy, &vel, &acc, &force, &torque);
        prop_assert_eq!(cond[dead_at], 0.0);
    }
}

/// The kernel alone on the bench's size (1e5 crank angles of a loaded
/// four-bar, reactions on, one thread, a reused output): CPU time a call,
/// several rounds, and a checksum of the output bits (equal before and after
/// a change that must keep the values bit for bit). Run:
/// `cargo test --release -p cyclomech-core --lib forces_kernel_timing -- --ignored --nocapture`
#[test]
#[ignore = "timing, not a check"]
fn forces_kernel_timing() {
    let spec = Spec {
        n_points: 4,
        bodies: vec![
            body(&[0, 1], 1.0, [0.5, 0.1], 0.1),
            body(&[1, 2], 2.0, [0.4, 0.05], 0.3),
            body(&[3, 2], 1.5, [0.4, -0.2], 0.2),
        ],
        ground: vec![0, 3],
        point_mass: vec![0.0, 0.5, 0.0, 0.0],
        guides: vec![],
        driver: 0,
        gravity: [0.0, -9.81],
    };
    let model = Model::new(spec).unwrap();
    let n = 100_000;
    let (mut xy, mut vel, mut acc, mut force, mut torque) =
        (vec![], vec![], vec![], vec![], vec![]);
    for i in 0..n {
        let phi = i as f64 * std::f64::consts::TAU / n as f64;
        let (p, pv, pa) = four_bar(1.0, 3.0, 3.0, 3.0, phi).unwrap();
        xy.extend(p.iter().flatten());
        vel.extend(pv.iter().flatten());
        acc.extend(pa.iter().flatten());
        force.extend([0.0, 0.0, 0.0, 0.0, phi.sin() * 20.0, 10.0, 0.0, 0.0]);
        torque.extend([0.0, 0.5, -1.0]);
    }
    for reactions in [true, false] {
        let w = model.width(reactions);
        let mut values = vec![0.0; 3 * n * w];
        let (mut conds, mut ratios) = (vec![0.0; n], vec![0.0; n]);
        let mut call = || {
            solve_into(
                &model,
                Inputs {
                    xy: &xy,
                    vel: &vel,
                    acc: &acc,
                    force: Some(&force),
                    torque: Some(&torque),
                },
                Outputs {
                    values: &mut values,
                    conditioning: &mut conds,
                    reactions,
                    analogs: Some(&mut ratios),
                },
                Some(1),
            )
            .unwrap();
        };
        call();
        let mut per = Vec::new();
        for _ in 0..7 {
            let t = crate::timing::process_cpu_seconds();
            for _ in 0..20 {
                call();
            }
            per.push((crate::timing::process_cpu_seconds() - t) / 20.0 * 1e3);
        }
        per.sort_by(f64::total_cmp);
        let sum = values
            .iter()
            .chain(&conds)
            .chain(&ratios)
            .fold(0u64, |h, v| h.rotate_left(5) ^ v.to_bits());
        println!(
            "reactions {reactions}: CPU ms a call min {:.2} median {:.2} max {:.2}; checksum {sum:016x}",
            per[0], per[3], per[6]
        );
    }
}
