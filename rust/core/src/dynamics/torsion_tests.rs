use super::*;
use crate::dynamics::shaft::Characteristic;
use proptest::prelude::*;

const N: usize = 720;

fn grid() -> Vec<f64> {
    (0..N).map(|i| TAU * i as f64 / N as f64).collect()
}

/// A node of constant inertia `j` loaded by q0 + q1·sin φ.
fn loaded(j: f64, q0: f64, q1: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let g = grid();
    (
        vec![j; N],
        vec![0.0; N],
        g.iter().map(|p| q0 + q1 * p.sin()).collect(),
    )
}

/// Two inertias, the head at constant speed: J·θ̈ + d·θ̇ + c·θ = Q(φ₀ − θ); with
/// the twist small, Q ≈ q0 + q1·sin ωt and θ = q0/c + q1/|c − Jω² + i·dω|·sin(ωt − ψ).
fn forced(c: f64, j: f64, d: f64, w: f64) {
    // Loads small against the stiffness: a twist of a few 1e-5 rad at most.
    let (q0, q1) = (2e-6 * c, 1e-6 * c);
    let (jj, dj, q) = loaded(0.0, q0, q1);
    let node = Node {
        j: &jj,
        dj: &dj,
        q: &q,
        hub: j,
        stiffness: c,
        damping: d,
        member: None,
    };
    let t = torsion(&[node], Head::Speed(w), &TorsionOptions::default()).unwrap();
    assert_eq!(t.status, 0, "cycles {} residual {}", t.cycles, t.residual);
    let (re, im) = (c - j * w * w, d * w);
    let amp = q1 / (re * re + im * im).sqrt();
    let lag = im.atan2(re);
    let g = grid();
    let scale = q0 / c + amp;
    for (i, p) in g.iter().enumerate() {
        let want = q0 / c + amp * (p - lag).sin();
        // The load read at φ₀ − θ: an error of order θ·q1·amp.
        assert!(
            (t.twist[i] - want).abs() < 1e-4 * scale,
            "at {p}: {} vs {want} (c {c}, j {j}, d {d}, w {w})",
            t.twist[i]
        );
        // S₁ = c·θ + d·θ̇
        let s = c * want + d * w * amp * (p - lag).cos();
        assert!(
            (t.torque[i] - s).abs() < 1e-4 * (q0 + c * amp),
            "torque at {p}"
        );
    }
}

#[test]
fn two_inertias_against_the_closed_form() {
    forced(1e4, 0.05, 2.0, 10.0);
    forced(1e5, 0.2, 10.0, 50.0);
    // Near resonance (√(c/J) = 447 rad/s at 440 rad/s): the amplitude is large.
    forced(1e4, 0.05, 1.0, 440.0);
}

#[test]
fn a_stiffer_shaft_lags_less() {
    let g = grid();
    let (jj, dj, q) = loaded(0.0, 0.0, 5.0);
    let pos: Vec<f64> = g.iter().map(|p| 0.01 * p.sin()).collect();
    let d1: Vec<f64> = g.iter().map(|p| 0.01 * p.cos()).collect();
    let d2: Vec<f64> = g.iter().map(|p| -0.01 * p.sin()).collect();
    let mut last = f64::INFINITY;
    for c in [1e3, 1e4, 1e5, 1e6] {
        let node = Node {
            j: &jj,
            dj: &dj,
            q: &q,
            hub: 0.01,
            stiffness: c,
            damping: 2.0 * 0.05 * (c * 0.01_f64).sqrt(),
            member: Some(Member {
                pos: &pos,
                d1: &d1,
                d2: &d2,
                components: 1,
                omega_n: f64::INFINITY,
                zeta: 0.0,
            }),
        };
        let t = torsion(&[node], Head::Speed(20.0), &TorsionOptions::default()).unwrap();
        assert_eq!(t.status, 0);
        // A rigid link: the error is the lag's, Π′·θ to first order, ~ 1/c.
        assert!(t.peak[0] < last / 5.0, "c {c}: {} after {last}", t.peak[0]);
        last = t.peak[0];
    }
    assert!(last < 1e-7);
}

/// The link alone (a stiff shaft): ü + 2ζω_n·u̇ + ω_n²·u = −d²Π/dt² with
/// Π = A·sin φ, φ = ωt: u = A·ω²/|ω_n² − ω² + 2iζω_nω|·sin(ωt − ψ).
#[test]
fn the_link_against_the_closed_form() {
    let g = grid();
    let (jj, dj, q) = loaded(0.0, 0.0, 0.0);
    let a = 0.02;
    let pos: Vec<f64> = g.iter().map(|p| a * p.sin()).collect();
    let d1: Vec<f64> = g.iter().map(|p| a * p.cos()).collect();
    let d2: Vec<f64> = g.iter().map(|p| -a * p.sin()).collect();
    let (wn, zeta, w) = (300.0, 0.1, 60.0);
    let node = Node {
        j: &jj,
        dj: &dj,
        q: &q,
        hub: 0.1,
        stiffness: 1e6,
        damping: 50.0,
        member: Some(Member {
            pos: &pos,
            d1: &d1,
            d2: &d2,
            components: 1,
            omega_n: wn,
            zeta,
        }),
    };
    let t = torsion(&[node], Head::Speed(w), &TorsionOptions::default()).unwrap();
    assert_eq!(t.status, 0);
    let (re, im) = (wn * wn - w * w, 2.0 * zeta * wn * w);
    let amp = a * w * w / (re * re + im * im).sqrt();
    let lag = im.atan2(re);
    for (i, p) in g.iter().enumerate() {
        let want = amp * (p - lag).sin();
        assert!(
            (t.error[i] - want).abs() < 1e-6 * amp,
            "at {p}: {} vs {want}",
            t.error[i]
        );
    }
    assert!((t.peak[0] - amp).abs() < 1e-4 * amp);
}

/// A motor at the head of a stiff shaft: the head turns as the rigid machine
/// with the same inertia does (the steady state of `shaft`).
#[test]
fn a_motor_at_the_head_of_a_stiff_shaft() {
    let (jj, dj, q) = loaded(0.0, 4.0, 3.0);
    let motor = Motor {
        characteristic: Characteristic::Linear {
            stall: 10.0,
            no_load: 100.0,
        },
        ratio: 1.0,
        efficiency: 1.0,
    };
    let node = Node {
        j: &jj,
        dj: &dj,
        q: &q,
        hub: 0.05,
        stiffness: 1e6,
        damping: 2.0 * 0.2 * (1e6 * 0.05_f64).sqrt(),
        member: None,
    };
    let head = Head::Motor {
        motor: &motor,
        inertia: 0.2,
        omega: 60.0,
    };
    let t = torsion(&[node], head, &TorsionOptions::default()).unwrap();
    assert_eq!(t.status, 0, "{} cycles, residual {}", t.cycles, t.residual);
    let total = vec![0.25; N];
    let c = crate::dynamics::Curves {
        j: &total,
        dj: &dj,
        q: &q,
    };
    let opt = crate::dynamics::SteadyOptions {
        tol: 1e-12,
        max_iter: 50,
        omega_start: 60.0,
    };
    let s = crate::dynamics::steady_state(&c, 0.0, &motor, &opt, true).unwrap();
    for i in (0..N).step_by(2) {
        // shaft's RK4 on its own samples (step 2·2π/N): agree to its error.
        assert!(
            (t.omega[i] - s.omega[i]).abs() < 1e-5 * s.omega[i],
            "at sample {i}: {} vs {}",
            t.omega[i],
            s.omega[i]
        );
    }
}

#[test]
fn bad_input_is_named() {
    let (jj, dj, q) = loaded(0.0, 0.0, 1.0);
    let node = Node {
        j: &jj,
        dj: &dj,
        q: &q,
        hub: 0.1,
        stiffness: -1.0,
        damping: 0.0,
        member: None,
    };
    let e = torsion(&[node], Head::Speed(10.0), &TorsionOptions::default()).unwrap_err();
    assert!(format!("{e}").contains("stiffness"), "{e}");
    let node = Node {
        stiffness: 1e4,
        hub: 0.0,
        ..node
    };
    let e = torsion(&[node], Head::Speed(10.0), &TorsionOptions::default()).unwrap_err();
    assert!(format!("{e}").contains("hub_inertia"), "{e}");
    let node = Node { hub: 0.1, ..node };
    let e = torsion(&[node], Head::Speed(-1.0), &TorsionOptions::default()).unwrap_err();
    assert!(format!("{e}").contains("speed"), "{e}");
    let e = torsion(&[], Head::Speed(1.0), &TorsionOptions::default()).unwrap_err();
    assert!(format!("{e}").contains("nodes"), "{e}");
}

#[test]
fn an_undamped_chain_is_not_settled() {
    let (jj, dj, q) = loaded(0.0, 0.0, 1.0);
    let node = Node {
        j: &jj,
        dj: &dj,
        q: &q,
        hub: 0.01,
        stiffness: 1e3,
        damping: 0.0,
        member: None,
    };
    let opt = TorsionOptions {
        max_cycles: 20,
        ..TorsionOptions::default()
    };
    let t = torsion(&[node], Head::Speed(10.0), &opt).unwrap();
    assert_eq!(t.status, 1);
    assert!(t.twist.iter().all(|v| v.is_nan()));
}

#[test]
fn the_sweep_is_the_single_call_at_each_speed() {
    let g = grid();
    let (jj, dj, q) = loaded(0.0, 1.0, 2.0);
    let pos: Vec<f64> = g.iter().flat_map(|_| [0.0]).collect();
    let p2: Vec<f64> = g.iter().map(|p| (2.0 * p).cos()).collect();
    let mut both = pos.clone();
    both.extend(&p2);
    let d1: Vec<f64> = g
        .iter()
        .map(|p| 0.0 * p)
        .chain(g.iter().map(|p| -2.0 * (2.0 * p).sin()))
        .collect();
    let d2: Vec<f64> = g
        .iter()
        .map(|p| 0.0 * p)
        .chain(g.iter().map(|p| -4.0 * (2.0 * p).cos()))
        .collect();
    let member = Member {
        pos: &both,
        d1: &d1,
        d2: &d2,
        components: 2,
        omega_n: 500.0,
        zeta: 0.05,
    };
    let node = Node {
        j: &jj,
        dj: &dj,
        q: &q,
        hub: 0.02,
        stiffness: 5e3,
        damping: 1.0,
        member: Some(member),
    };
    let speeds = [5.0, 20.0, 40.0];
    let mut out = vec![0.0; 3 * 5];
    torsion_sweep(
        &[node],
        &speeds,
        &TorsionOptions::default(),
        &mut out,
        Some(2),
    )
    .unwrap();
    for (s, &w) in speeds.iter().enumerate() {
        let t = torsion(&[node], Head::Speed(w), &TorsionOptions::default()).unwrap();
        assert_eq!(out[s * 5], 0.0);
        assert_eq!(out[s * 5 + 3], t.peak[0]);
        let top = t.twist.iter().fold(0.0_f64, |a, &v| a.max(v.abs()));
        assert_eq!(out[s * 5 + 4], top);
    }
    // faster, larger errors here (below every resonance)
    assert!(out[5 + 3] > out[3] && out[10 + 3] > out[5 + 3]);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]
    #[test]
    fn forced_response_holds_across_designs(
        c in 1e3f64..1e6,
        j in 0.01f64..1.0,
        zeta in 0.02f64..0.5,
        ratio in 0.05f64..3.0,
    ) {
        let wn = (c / j).sqrt();
        let w = (ratio * wn).min(200.0);
        prop_assume!(w > 1.0);
        forced(c, j, 2.0 * zeta * (c * j).sqrt(), w);
    }
}
