//! The process's CPU time, for the ignored timing tests and the timing
//! examples (`forces_kernel_timing`, `examples/cam_solve_time.rs`): user +
//! system time, which the machine's load distorts less than the wall clock.

/// The process's user + system CPU time [s], from `/proc/self/stat` (Linux; 0
/// elsewhere, or if it cannot be read).
#[doc(hidden)]
pub fn process_cpu_seconds() -> f64 {
    let Ok(stat) = std::fs::read_to_string("/proc/self/stat") else {
        return 0.0;
    };
    // Fields after the command's closing parenthesis: utime and stime are the
    // 14th and 15th fields of the line, in clock ticks (100 per second).
    let rest = stat.rsplit(')').next().unwrap_or("");
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks = |i: usize| f.get(i).and_then(|v| v.parse::<f64>().ok()).unwrap_or(0.0);
    (ticks(11) + ticks(12)) / 100.0
}
