//! Unit tests of the shaft's dynamics (the Python tests check against
//! independent references: sympy's Lagrangian and scipy's `solve_ivp`).

use std::f64::consts::TAU;

use super::*;

fn grid(n: usize, f: impl Fn(f64) -> f64) -> Vec<f64> {
    (0..n).map(|k| f(TAU * k as f64 / n as f64)).collect()
}

fn opts() -> SteadyOptions {
    SteadyOptions {
        tol: 1e-12,
        max_iter: 50,
        omega_start: 10.0,
    }
}

#[test]
fn constant_inertia_and_torque_in_closed_form() {
    // J y/2 = J y0/2 + A (cos φ − 1) with Q = Q̄ + A sin φ and M = Q̄.
    let (n, jv, qm, amp) = (3600, 2.0, 5.0, 3.0);
    let j = vec![jv; n];
    let dj = vec![0.0; n];
    let q = grid(n, |p| qm + amp * p.sin());
    let c = Curves {
        j: &j,
        dj: &dj,
        q: &q,
    };
    let motor = Motor {
        characteristic: Characteristic::Constant { torque: qm },
        ratio: 1.0,
        efficiency: 1.0,
    };
    let s = steady_state(&c, 0.0, &motor, &opts(), true).unwrap();
    assert_eq!(s.status, Status::Periodic);
    for (k, w) in s.omega.iter().enumerate() {
        let p = TAU * k as f64 / n as f64;
        let exact = (100.0 + 2.0 * amp * (p.cos() - 1.0) / jv).sqrt();
        assert!((w - exact).abs() < 1e-11 * exact, "{k}: {w} vs {exact}");
    }
    // Off balance: no periodic speed, said so.
    let weak = Motor {
        characteristic: Characteristic::Constant { torque: qm * 0.9 },
        ..motor
    };
    let s = steady_state(&c, 0.0, &weak, &opts(), false).unwrap();
    assert_ne!(s.status, Status::Periodic);
    assert!(s.row[4].is_nan());
}

#[test]
fn a_linear_motor_settles_where_its_torque_meets_the_load() {
    let n = 360;
    let j = vec![1.0; n];
    let dj = vec![0.0; n];
    let q = vec![4.0; n];
    let c = Curves {
        j: &j,
        dj: &dj,
        q: &q,
    };
    let motor = Motor {
        characteristic: Characteristic::Linear {
            stall: 10.0,
            no_load: 100.0,
        },
        ratio: 2.0,
        efficiency: 0.8,
    };
    // 2·0.8·10·(1 − 2ω/100) = 4 → ω = 37.5 rad/s.
    let s = steady_state(&c, 0.5, &motor, &opts(), true).unwrap();
    assert_eq!(s.status, Status::Periodic);
    assert!(s.omega.iter().all(|w| (w - 37.5).abs() < 1e-9));
    // Too weak a motor: no equilibrium.
    let q = vec![40.0; n];
    let c = Curves {
        j: &j,
        dj: &dj,
        q: &q,
    };
    let s = steady_state(&c, 0.0, &motor, &opts(), false).unwrap();
    assert_eq!(s.status, Status::MotorTooWeak);
}

#[test]
fn kloss_is_zero_at_synchronous_speed_and_peaks_at_the_critical_slip() {
    let ch = Characteristic::Kloss {
        breakdown: 50.0,
        synchronous: 100.0,
        critical_slip: 0.2,
    };
    assert_eq!(ch.torque(100.0).0, 0.0);
    assert!((ch.torque(80.0).0 - 50.0).abs() < 1e-12);
    assert!(ch.torque(80.0).1.abs() < 1e-12);
    let (m1, _) = ch.torque(90.0 + 1e-6);
    let (m0, d) = ch.torque(90.0 - 1e-6);
    assert!(((m1 - m0) / 2e-6 - d).abs() < 1e-5 * d.abs());
}

#[test]
fn bad_input_is_an_error() {
    let j = vec![1.0; 8];
    let dj = vec![0.0; 8];
    let q = vec![0.0; 8];
    let c = Curves {
        j: &j,
        dj: &dj,
        q: &q,
    };
    let m = Motor {
        characteristic: Characteristic::Linear {
            stall: 1.0,
            no_load: 1.0,
        },
        ratio: 1.0,
        efficiency: 1.0,
    };
    assert!(steady_state(&c, -1.0, &m, &opts(), false).is_err());
    let neg = vec![-2.0; 8];
    let cn = Curves {
        j: &neg,
        dj: &dj,
        q: &q,
    };
    assert!(steady_state(&cn, 1.0, &m, &opts(), false).is_err());
    let odd = vec![1.0; 7];
    let co = Curves {
        j: &odd,
        dj: &odd,
        q: &odd,
    };
    assert!(steady_state(&co, 0.0, &m, &opts(), false).is_err());
    let bad_eff = Motor {
        efficiency: 1.5,
        ..m.clone()
    };
    assert!(steady_state(&c, 0.0, &bad_eff, &opts(), false).is_err());
    // A start-up's steady speeds must be > 0 (its band is relative to their time
    // mean): a zero or negative one is named, not a division by it.
    let start = StartUpOptions {
        rtol: 1e-9,
        settle: 1e-3,
        t_max: 10.0,
        max_steps: 1000,
    };
    let mut steady = vec![1.0; 8];
    assert!(start_up(&c, 0.0, &m, &steady, &start).is_ok());
    steady[3] = 0.0;
    let e = start_up(&c, 0.0, &m, &steady, &start).unwrap_err();
    assert!(e.to_string().contains("steady"), "{e}");
    let mut out = vec![0.0; 12];
    assert!(steady_batch(&c, &[0.0, 1.0], &[m], &opts(), &mut out, Some(1)).is_err());
}
