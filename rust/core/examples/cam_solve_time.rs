//! Times `Cam::solve_into` on 1e6 sorted cam angles into a reused block, one
//! thread: the kernel alone, without Python, the fresh pages or the copy of θ
//! (the Python bench, `benches/bench_cam.py`, measures the whole call).
//! The program and follower are the bench's: a translating offset roller on a
//! cycloidal rise 120°, dwell 60°, return 100°, dwell 80°.
//!
//! Run: `cargo run --release -p cyclomech-core --example cam_solve_time [calls]`.
//! Prints the median wall time of the calls and the process's CPU time per
//! call (user + system, from /proc/self/stat, so load-independent).

use std::time::Instant;

use cyclomech_core::cam::{Cam, Follower, Kind, Program, SegmentSpec, N_COLUMNS};
use cyclomech_core::timing::process_cpu_seconds;

const N: usize = 1_000_000;

fn main() {
    let calls: usize = std::env::args()
        .nth(1)
        .and_then(|v| v.parse().ok())
        .unwrap_or(40);
    let seg = |kind, deg: f64, stroke| SegmentSpec {
        kind,
        angle: deg.to_radians(),
        stroke,
        law: "cycloidal".into(),
        unit: None,
    };
    let program = Program::new(&[
        seg(Kind::Rise, 120.0, 0.025),
        seg(Kind::Dwell, 60.0, 0.0),
        seg(Kind::Return, 100.0, 0.025),
        seg(Kind::Dwell, 80.0, 0.0),
    ])
    .expect("the bench's program is valid");
    let follower = Follower::TranslatingRoller {
        base_radius: 0.05,
        roller_radius: 0.012,
        offset: 0.006,
    };
    let cam = Cam::new(program, follower, false).expect("the bench's cam is valid");
    let theta: Vec<f64> = (0..N)
        .map(|i| i as f64 * std::f64::consts::TAU / N as f64)
        .collect();
    let mut out = vec![0.0; N * N_COLUMNS];
    cam.solve_into(&theta, &mut out, Some(1))
        .expect("finite angles");
    let mut wall = Vec::with_capacity(calls);
    let cpu0 = process_cpu_seconds();
    for _ in 0..calls {
        let t0 = Instant::now();
        cam.solve_into(&theta, &mut out, Some(1))
            .expect("finite angles");
        wall.push(t0.elapsed().as_secs_f64());
    }
    let cpu = (process_cpu_seconds() - cpu0) / calls as f64;
    wall.sort_by(f64::total_cmp);
    let checksum: f64 = out.iter().step_by(97).filter(|v| v.is_finite()).sum();
    println!(
        "Cam::solve_into, {N} angles, 1 thread, {calls} calls: wall median {:.2} ms, \
         min {:.2} ms; CPU {:.2} ms a call (checksum {checksum:.6})",
        wall[calls / 2] * 1e3,
        wall[0] * 1e3,
        cpu * 1e3
    );
}
