//! Servo axes (issue 33, item 3): the motor torque and speed of an electronic cam
//! whose master is the machine's (virtual) main shaft, the checks of a motor and
//! gearbox against them, and the sizing batch over motors × gear ratios × speeds.
//!
//! **Conventions (SI).** The master turns at a constant ω [rad/s]; the program
//! gives the slave's load-shaft angle φ_L(θ) over one cycle θ ∈ [0, 2π), sampled
//! at N uniform angles θ_k = 2πk/N: `vel` = φ_L′ [rad/rad] and `acc` = φ_L″
//! [rad/rad²] (a linear axis is brought to its screw shaft first: φ_L = 2πx/lead).
//! Time is uniform in θ at constant ω, so every mean over the cycle (the RMS
//! torque, the regenerated energy) is a mean over the uniform samples, dwells
//! included. At the load shaft the ideal torque is T_L = J_L·φ_L″·ω² + T_ext
//! (T_ext > 0 resists positive motion). Brought through the drive (screw and
//! gearbox, efficiency η, ratio i = motor speed / load speed):
//!
//! * T_out = T_L/(i·η) when the motor drives the load (T_L·φ_L′ > 0), and also
//!   where the load stands (φ_L′ = 0: a holding torque is taken on the motoring
//!   side, the larger of the two: the conservative choice for a check);
//! * T_out = T_L·η/i when the load drives the motor (T_L·φ_L′ < 0: regeneration).
//!
//! The motor torque is T_m = J·i·φ_L″·ω² + T_out with J = J_motor + J_gearbox (the
//! gearbox's inertia is at the motor side), its speed ω_m = i·φ_L′·ω.
//!
//! **The structure the sizing uses.** With ã = T_L·(1/η or η) (the factor by the
//! sign of the power, which does not depend on i > 0) and b̃ = φ_L″·ω², the motor
//! torque is T_m = (ã + J′·b̃)/i with J′ = J·i². At one speed, ã and b̃ are fixed:
//! every motor and every ratio is a point J′ on the same family of lines, so the
//! peak |T_m| is the upper envelope of the 2N lines ±(ã_k + J′·b̃_k) (built once per
//! speed, queried at the sorted J′) and the RMS is √((Σã² + 2J′Σãb̃ + J′²Σb̃²)/N)/i.
//!
//! Files: this one (the door: the load, the motors, the errors), `duty` (one
//! motor and ratio, every sample: the reference), `size` (the batch), `bounds`
//! (a segment's smallest phase angle for the cyclogram) and `tests`.

use crate::input::InvalidInput;

mod bounds;
mod duty;
mod rms;
mod size;
#[cfg(test)]
mod tests;

pub use bounds::{
    law_samples, law_weights, min_angles_into, segment_samples, speed_limit, Drive, Shape,
    BOUND_CRITERIA, BOUND_SAMPLES, LIMIT_SAMPLES,
};
pub use duty::{duty_into, DUTY, N_DUTY};
pub use rms::{rms_angles_into, rms_speed_limit, RmsProgram, RMS_GRID};
pub use size::size_into;

/// The checks of a motor and drive, in the order of every margin array: the peak
/// torque against the motor's peak torque, the RMS torque against its rated
/// torque (thermal), the peak speed against its maximum speed, the inertia ratio
/// against the user's limit.
pub const CHECKS: [&str; 4] = ["peak_torque", "rms_torque", "speed", "inertia_ratio"];

/// Values per candidate in the margin arrays: one per [`CHECKS`] entry.
pub const N_CHECKS: usize = CHECKS.len();

/// Errors of the servo kernels: all of them the invalid inputs every domain shares.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ServoError {
    #[error(transparent)]
    Input(#[from] InvalidInput),
}

crate::input::wraps_invalid_input!(ServoError);

/// The load side of an axis over one master cycle (module docs for the symbols).
#[derive(Debug, Clone, Copy)]
pub struct Load<'a> {
    /// φ_L′ at the N samples [rad of load shaft per rad of master].
    pub vel: &'a [f64],
    /// φ_L″ at the N samples [rad/rad²].
    pub acc: &'a [f64],
    /// J_L, the load's inertia at the load shaft [kg·m²], ≥ 0.
    pub inertia: f64,
    /// T_ext, the constant load torque at the load shaft [N·m] (> 0 resists
    /// positive motion).
    pub torque: f64,
    /// η, the efficiency of the whole drive (screw × gearbox), in (0, 1].
    pub efficiency: f64,
}

impl Load<'_> {
    /// The load refused by name if it cannot be used.
    fn check(&self) -> Result<(), InvalidInput> {
        if self.vel.len() < 2 || self.acc.len() != self.vel.len() {
            return Err(InvalidInput::bad_value(
                "samples",
                self.vel.len() as f64,
                format!(
                    "must be >= 2 angles over the cycle, the same for vel and acc (acc has {})",
                    self.acc.len()
                ),
            ));
        }
        InvalidInput::check_finite("vel", self.vel)?;
        InvalidInput::check_finite("acc", self.acc)?;
        at_least(
            "load_inertia",
            self.inertia,
            "[kg·m²] must be finite and >= 0",
        )?;
        if !self.torque.is_finite() {
            return Err(InvalidInput::bad_value(
                "load_torque",
                self.torque,
                "[N·m] must be finite",
            ));
        }
        let eta = self.efficiency;
        if !(eta.is_finite() && eta > 0.0 && eta <= 1.0) {
            return Err(InvalidInput::bad_value(
                "efficiency",
                eta,
                "must be in (0, 1]",
            ));
        }
        Ok(())
    }

    /// ã_k: the load torque T_L at sample k and speed² `w2`, times 1/η where the
    /// motor drives or holds the load, η where the load drives the motor.
    #[inline]
    fn reduced(&self, k: usize, w2: f64) -> f64 {
        let t = self.inertia * self.acc[k] * w2 + self.torque;
        if t * self.vel[k] < 0.0 {
            t * self.efficiency
        } else {
            t / self.efficiency
        }
    }
}

/// A catalogue of M motors, one entry per motor in each slice.
#[derive(Debug, Clone, Copy)]
pub struct Motors<'a> {
    /// Rotor inertia [kg·m²], > 0.
    pub inertia: &'a [f64],
    /// Peak torque [N·m], > 0.
    pub peak_torque: &'a [f64],
    /// Rated (continuous) torque [N·m], > 0.
    pub rated_torque: &'a [f64],
    /// Maximum speed [rad/s], > 0.
    pub max_speed: &'a [f64],
}

impl Motors<'_> {
    fn check(&self) -> Result<usize, InvalidInput> {
        let m = self.inertia.len();
        let columns = [
            ("motor_inertia", self.inertia),
            ("peak_torque", self.peak_torque),
            ("rated_torque", self.rated_torque),
            ("max_speed", self.max_speed),
        ];
        for (field, values) in columns {
            if values.len() != m {
                return Err(InvalidInput::bad_value(
                    field,
                    values.len() as f64,
                    format!("values given; need one per motor ({m})"),
                ));
            }
            positive_entries(field, values)?;
        }
        Ok(m)
    }
}

/// `value` finite and ≥ 0, else [`InvalidInput::BadValue`] with `why`.
fn at_least(field: &'static str, value: f64, why: &'static str) -> Result<(), InvalidInput> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(InvalidInput::bad_value(field, value, why))
    }
}

/// Every entry of `values` finite and > 0, else the first that is not, by index.
fn positive_entries(field: &'static str, values: &[f64]) -> Result<(), InvalidInput> {
    InvalidInput::check_finite(field, values)?;
    match values.iter().position(|v| *v <= 0.0) {
        None => Ok(()),
        Some(index) => Err(InvalidInput::bad_value(
            field,
            values[index],
            format!("(at index {index}) must be > 0"),
        )),
    }
}
