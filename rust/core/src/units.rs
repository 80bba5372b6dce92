//! Shaft speeds between rpm, rad/s and deg/s: the one copy of the two factors
//! (the Python layer reads them from `cyclomech._core`).

use std::f64::consts::PI;

/// Angular speed [rad/s] of a shaft turning at 1 rpm: 2π/60.
pub const RAD_PER_S_PER_RPM: f64 = 2.0 * PI / 60.0;

/// Angular speed [deg/s] of a shaft turning at 1 rpm: 360° · 1/60 s⁻¹.
pub const DEG_PER_S_PER_RPM: f64 = 6.0;
