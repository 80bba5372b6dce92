//! The planetary gear-lever press drive of seed 003: kinematics over crank-angle
//! grids and the working-stroke criteria, for one design or a grid of designs.
//!
//! Frame: origin at the centre O of the fixed internal guide gear (radius R), y up;
//! the slider runs on the vertical guide x = `offset` below O. The carrier (crank)
//! at angle θ carries the planet gear (radius r) whose centre is C = (R − r)·e^{iθ};
//! the planet rolls inside the guide gear, so it turns at −k = −(R − r)/r times the
//! carrier. The rod (length L) hangs on the planet at eccentricity d:
//! pin P = C + d·e^{iβ}, β = −k·θ + i·(φ0 − π/2) with i = R/r: φ0 is the angle the
//! guide gear is turned from the setting in which the pin lies on the carrier line,
//! outwards, when the carrier points straight down. The slider is at
//! y = P_y − √(L² − (P_x − offset)²).
//!
//! The carrier turns counterclockwise. As in the seed, α is the crank angle counted
//! from the slider's bottom dead centre (BDC) **against** the motion: θ = θ_B − α,
//! and S = Π(α) = y(θ_B − α) − y(θ_B) ≥ 0 is the slider's height above BDC, so
//! the working stroke is the approach to BDC, α from α_p down to 0. α_p is the
//! first contact: coming down from TDC, the first α where S = S_p; a slider
//! that then backs off above S_p and comes down again before BDC re-contacts
//! ([`Status::ReContacts`]).
//!
//! With d = 0 the drive is a plain crank-slider of crank radius R − r.
//!
//! Files: `kinematics` (the design, its kinematics over α grids, the domain's
//! error), `criteria` (the working-stroke criteria of one design), `sweep`
//! (criteria over a design grid, in parallel), `walk` (the walk back from BDC
//! to the first contact, which `criteria` runs) and `pareto` (non-dominated
//! filtering, for the optimiser).

mod criteria;
mod kinematics;
mod pareto;
mod sweep;
#[cfg(test)]
mod tests;
mod walk;

pub use criteria::{criteria, Spec, Status, Stroke, CRITERIA, DEFAULT_SAMPLES, RECONTACT, TIE};
pub use kinematics::{bdc, solve_into, Design, KinOut, PressError, MAX_RATIO};
pub use pareto::{pareto_mask, ParetoError};
pub use sweep::{sweep_into, Grid};
