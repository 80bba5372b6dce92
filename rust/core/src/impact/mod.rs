//! Stop impact (seed 000, §1): the forced oscillator behind the Duhamel integral,
//! the first rebound after a force pulse, and a link hitting its stop as a
//! unilateral contact.
//!
//! **Forced oscillator.** m q̈ + 2ζω m q̇ + m ω² q = F(t), ω = `omega_n` [rad/s] > 0,
//! ζ = `zeta` ≥ 0 (any value: under-, critically and over-damped are all exact),
//! m = `mass` > 0; q and F in consistent units (m and N, or rad and N·m with m a
//! moment of inertia). F is piecewise linear between its samples (first-order
//! hold) and held at its last value after the last sample. A repeated time
//! (t[k+1] = t[k]) is a jump of the force at that instant: how a pulse table ends
//! a rectangular pulse. Over a step h = t[k+1] − t[k] the state x = (q, q̇) moves
//! exactly (Nigam–Jennings):
//!
//! ```text
//! x[k+1] = Φ(h) x[k] + Γ0(h) F[k] + Γ1(h) F[k+1]
//! Φ  = e^{−σh} [[C + σS, S], [−ω²S, C − σS]]
//! Γ1 = [I2/h, I1/h] / m,   Γ0 = [I1 − I2/h, e^{−σh} S − I1/h] / m
//! ```
//!
//! with σ = ζω, λ = ω² − σ² = ω²(1 − ζ)(1 + ζ), C = cos(√λ h), S = sin(√λ h)/√λ
//! (cosh and sinh/√−λ when λ < 0; 1 and h when λ = 0; a series when |λ|h² ≤ 1, so
//! that every coefficient is continuous across ζ = 1), and I1 = ∫₀ʰ g,
//! I2 = ∫₀ʰ (h − τ) g(τ) dτ the integrals of the unit impulse response
//! g(τ) = e^{−στ} S(τ) (by their Taylor series when (σ + √|λ|)·h ≤ 2, where the
//! closed forms would cancel). This is the Duhamel integral of seed 000 (eq. 2)
//! evaluated exactly for a piecewise-linear force: no quadrature error.
//!
//! **First rebound.** The first local extremum of q after t[0]: the first instant
//! t > t[0] at which q̇ = 0 after q̇ has been non-zero (if q̇(t[0]) = 0, after it
//! first moves). Generically q̇ changes sign there; a touch (q̇ = 0 without a sign
//! change, a non-generic case) counts too. It is found segment by segment: inside a
//! segment with a linear force, q̇ = c + e^{−σs}(…) with c = slope/(mω²), the zeros
//! of q̈ are in closed form and q̇ is monotone between them, so the first crossing
//! is bracketed and solved by safeguarded Newton steps to rounding. A dip of q̇
//! right after a point of rest (q̇ = 0 with q̈ and q⃛ of opposite signs: it turns
//! back near s = −2q̈/q⃛) too shallow for c + e^{…}'s digits is bisected instead on
//! q̇/s by its Taylor series. After the last sample (constant force) it is in
//! closed form. If q̇ never returns to zero (an
//! over-damped creep), the result is time = +∞ and q = F[last]/(mω²), the limit.
//!
//! **Contact oscillator.** A link of mass m at x meets its stop at x = 0: free for
//! x > 0 (restoring force −k_f (x + δ), preload δ ≥ 0: at rest the link presses on
//! the stop with k_f δ), in contact for x < 0 (−k_f (x + δ) − k_s x: stiffness
//! k_c = k_f + k_s about x_c = −k_f δ / k_c). Each regime has its own damping ratio
//! relative to its own stiffness (c = 2ζ√(k m)). Each regime is an unforced
//! oscillator about its equilibrium, so its motion is in closed form and each
//! crossing of x = 0 is bracketed between closed-form extrema and solved to
//! rounding: an exact event-driven history.
//!
//! Files: `oscillator` (the recurrence for one case and for batches),
//! `lane_coef` (a batch's lockstep group's step coefficients in vector lanes,
//! bit for bit the one case's), `scan`
//! (the one case's chunked lane-parallel scan on uniform grids),
//! `rebound` (the first rebound after a pulse), `contact` (the link on its stop),
//! `design_batch` (many designs of one stop built and solved at once, for
//! machine sweeps) and `error` (the domain's error and its input checks).

mod contact;
mod design_batch;
mod error;
mod lane_coef;
mod oscillator;
mod rebound;
mod scan;
#[cfg(test)]
mod tests;

pub use contact::{
    contact_rebound_batch_into, contact_response, contact_sample_into, Contact, ContactEnd,
    ContactHistory, MAX_EVENTS,
};
pub use design_batch::{
    contact_point, max_speed, min_phase, stop_designs_into, DesignOut, PulseShape, PulseStop,
    PulseTable, StopDesigns, SPEED_MARGIN,
};
pub use error::{ImpactError, MODE_RANGE};
pub use oscillator::{response_batch_into, response_into, Cases, Oscillator};
pub use rebound::{first_rebound, first_rebound_batch_into, first_turn, Rebound};
