//! Follower loads along the cycle: the generalised force the cam must supply,
//! the normal contact force through the pressure angle, the Hertz line-contact
//! stress on the profile's local curvature, the cam shaft's torque and, for
//! spring closure, separation (jump).
//!
//! Along the follower's coordinate s (m, or rad for an oscillating arm), at a
//! constant cam speed ω [rad/s], the cam must supply the generalised force
//! Q = m s″ω² + k s + F0 + F_L (N, or N·m about the arm's pivot): inertia
//! (m the mass, or the arm's moment of inertia about its pivot), the spring
//! (rate k, preload F0 at s = 0) and the segment's external load F_L, the last
//! three acting toward the cam. The normal force on the roller is
//! N = Q/(l cos φ) (l = 1 for a translating follower, the arm length for an
//! oscillating one; φ the pressure angle), carried by the inner flank when
//! N ≥ 0 and by a groove's outer flank when N < 0; with spring closure N < 0
//! means the follower leaves the cam (jump). Friction is neglected. The shaft
//! torque is T = Q s′ (power balance T ω = Q ṡ).
//!
//! Hertz line contact (Johnson, *Contact Mechanics*, eq. 4.45): the peak
//! pressure σ_H = √(|N| κ / (π b c)), κ = 1/r_r + 1/ρ the relative curvature of
//! the roller (radius r_r) on the cam surface (ρ signed, + convex toward the
//! roller: ρ_p − r_r on the inner flank, −(ρ_p + r_r) on a groove's outer
//! flank; a flat face: κ = 1/(R_b + s + s″)), b the contact width and
//! c = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂. Where κ ≤ 0 (an undercut profile) σ_H is NaN.

use rayon::prelude::*;

use super::follower::{Cam, Follower, N_COLUMNS};
use super::program::CamError;
use crate::input::InvalidInput;
use crate::parallel::{pool, resolve_threads};

/// The columns of [`Cam::loads_into`]'s rows, in order.
pub const LOAD_COLUMNS: [&str; 5] = [
    "force",
    "normal_force",
    "contact_stress",
    "shaft_torque",
    "separated",
];

/// Values per cam angle in [`Cam::loads_into`].
pub const N_LOAD_COLUMNS: usize = LOAD_COLUMNS.len();

/// Angles per parallel chunk.
const CHUNK: usize = 4096;

/// The follower's loads (see the module's docs for the units and signs).
#[derive(Debug, Clone, PartialEq)]
pub struct Loads {
    /// Mass [kg], or the arm's moment of inertia about its pivot [kg·m²].
    pub mass: f64,
    /// Spring rate [N/m, or N·m/rad].
    pub spring_rate: f64,
    /// Spring force at s = 0 [N, or N·m].
    pub preload: f64,
    /// External load per segment, toward the cam [N, or N·m].
    pub segment_loads: Vec<f64>,
}

/// Hertz line contact: width [m], Young's moduli [Pa] and Poisson's ratios
/// of the follower (roller or face) and the cam.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    pub width: f64,
    pub follower_modulus: f64,
    pub follower_poisson: f64,
    pub cam_modulus: f64,
    pub cam_poisson: f64,
}

fn bad(field: &'static str, value: f64, why: &str) -> CamError {
    InvalidInput::bad_value(field, value, why.to_owned()).into()
}

impl Loads {
    /// Check the loads against a program of `n_segments` segments.
    pub fn validate(&self, n_segments: usize) -> Result<(), CamError> {
        if !(self.mass.is_finite() && self.mass >= 0.0) {
            return Err(bad("mass", self.mass, "must be finite and >= 0"));
        }
        if !(self.spring_rate.is_finite() && self.spring_rate >= 0.0) {
            return Err(bad(
                "spring_rate",
                self.spring_rate,
                "must be finite and >= 0",
            ));
        }
        if !self.preload.is_finite() {
            return Err(bad("preload", self.preload, "must be finite"));
        }
        if self.segment_loads.len() != n_segments {
            return Err(bad(
                "segment_loads",
                self.segment_loads.len() as f64,
                &format!("values given; the program has {n_segments} segments"),
            ));
        }
        if let Some((index, &value)) = self
            .segment_loads
            .iter()
            .enumerate()
            .find(|(_, v)| !v.is_finite())
        {
            return Err(InvalidInput::NotFinite {
                field: "segment_loads",
                index,
                value,
            }
            .into());
        }
        Ok(())
    }
}

impl Contact {
    /// Check the data and return the compliance c = Σ (1 − ν²)/E [1/Pa].
    pub fn compliance(&self) -> Result<f64, CamError> {
        if !(self.width.is_finite() && self.width > 0.0) {
            return Err(bad("width", self.width, "[m] must be finite and > 0"));
        }
        let mut c = 0.0;
        for (fe, e, fn_, nu) in [
            (
                "follower_modulus",
                self.follower_modulus,
                "follower_poisson",
                self.follower_poisson,
            ),
            (
                "cam_modulus",
                self.cam_modulus,
                "cam_poisson",
                self.cam_poisson,
            ),
        ] {
            if !(e.is_finite() && e > 0.0) {
                return Err(bad(fe, e, "[Pa] must be finite and > 0"));
            }
            if !(nu.is_finite() && nu > -1.0 && nu < 0.5) {
                return Err(bad(
                    fn_,
                    nu,
                    "must be in (-1, 0.5), an isotropic solid's range",
                ));
            }
            c += (1.0 - nu * nu) / e;
        }
        Ok(c)
    }
}

impl Cam {
    /// The lever of the normal force: the arm length of an oscillating follower, else 1.
    fn lever(&self) -> f64 {
        match self.follower() {
            Follower::OscillatingRoller { arm_length, .. } => arm_length,
            _ => 1.0,
        }
    }

    /// l cos φ: the lever of the normal force about the follower's motion
    /// (l = 1 for a translating follower), at pressure angle `phi` [rad].
    #[inline]
    pub(super) fn lever_cos(&self, phi: f64) -> f64 {
        self.lever() * phi.cos()
    }

    /// l cos φ from a lean row's cos φ.
    #[inline]
    pub(super) fn lever_times(&self, cos_phi: f64) -> f64 {
        self.lever() * cos_phi
    }

    /// Check that the follower can carry a Hertz stress (a roller of radius
    /// > 0, or a flat face); the compliance of `contact`.
    pub fn hertz_compliance(&self, contact: &Contact) -> Result<f64, CamError> {
        let r = match self.follower() {
            Follower::TranslatingRoller { roller_radius, .. }
            | Follower::OscillatingRoller { roller_radius, .. } => roller_radius,
            Follower::FlatFaced { .. } => f64::INFINITY,
        };
        if r == 0.0 {
            return Err(bad(
                "roller_radius",
                r,
                "is a knife edge: the Hertz stress needs a roller radius > 0 (or a flat face)",
            ));
        }
        contact.compliance()
    }

    /// The relative curvature κ [1/m] of the contact on the flank the force
    /// `n` (signed) loads, from a geometry row (NaN where undercut).
    #[inline]
    pub(super) fn curvature(&self, geo: &[f64], n: f64) -> f64 {
        let inv = |r: f64| if r.is_infinite() { 0.0 } else { 1.0 / r };
        let k = match self.follower() {
            Follower::FlatFaced { .. } => inv(geo[12]),
            Follower::TranslatingRoller { roller_radius, .. }
            | Follower::OscillatingRoller { roller_radius, .. } => {
                let cam = if n >= 0.0 {
                    inv(geo[12])
                } else {
                    -inv(geo[11] + roller_radius)
                };
                1.0 / roller_radius + cam
            }
        };
        if k < 0.0 {
            f64::NAN
        } else {
            k
        }
    }

    /// One row of [`LOAD_COLUMNS`] from a geometry row `geo` (of
    /// [`super::COLUMNS`]) at speed `omega` [rad/s] with the segment's load
    /// `load`; `hertz` = (width, compliance) when the stress is wanted.
    ///
    /// Where the follower has left the cam (spring closure, N < 0) there is no
    /// contact and so no stress: σ_H is NaN there, with the `separated` column
    /// saying why (a number would read as a stress a designer could compare with
    /// [σ_H]). The bounds use [`Cam::load_row_lc`], where such an angle counts as
    /// stress 0: no contact cannot exceed the limit (separation is its own check).
    #[inline]
    pub(super) fn load_row(
        &self,
        geo: &[f64],
        omega: f64,
        loads: &Loads,
        load: f64,
        hertz: Option<(f64, f64)>,
    ) -> [f64; N_LOAD_COLUMNS] {
        let lc = self.lever_cos(geo[10]);
        let mut row = self.load_row_lc(geo, lc, omega, loads, load, hertz);
        if row[4] != 0.0 {
            row[2] = f64::NAN; // separated: no contact, no stress
        }
        row
    }

    /// [`Cam::load_row`] given l cos φ `lc` (a lean row's cos φ times the lever).
    #[inline]
    pub(super) fn load_row_lc(
        &self,
        geo: &[f64],
        lc: f64,
        omega: f64,
        loads: &Loads,
        load: f64,
        hertz: Option<(f64, f64)>,
    ) -> [f64; N_LOAD_COLUMNS] {
        let (s, ds, dds) = (geo[0], geo[1], geo[2]);
        let q = loads.mass * dds * omega * omega + loads.spring_rate * s + loads.preload + load;
        let n = if lc > 0.0 {
            q / lc
        } else {
            f64::INFINITY.copysign(q)
        };
        let separated = !self.groove() && n < 0.0;
        let sigma = match hertz {
            None => f64::NAN,
            Some(_) if separated => 0.0,
            Some((width, c)) => {
                let k = self.curvature(geo, n);
                (n.abs() * k / (std::f64::consts::PI * width * c)).sqrt()
            }
        };
        [q, n, sigma, q * ds, if separated { 1.0 } else { 0.0 }]
    }

    /// Rows of [`LOAD_COLUMNS`] at every cam angle `theta` [rad] and cam speed
    /// `omega` [rad/s] into `out` (row-major, `theta.len() · N_LOAD_COLUMNS`);
    /// the stress column is NaN without `contact`.
    pub fn loads_into(
        &self,
        theta: &[f64],
        omega: f64,
        loads: &Loads,
        contact: Option<&Contact>,
        out: &mut [f64],
        n_threads: Option<i64>,
    ) -> Result<(), CamError> {
        if !omega.is_finite() {
            return Err(bad("omega", omega, "[rad/s] must be finite"));
        }
        loads.validate(self.program().len())?;
        let hertz = match contact {
            Some(c) => Some((c.width, self.hertz_compliance(c)?)),
            None => None,
        };
        if let Some((index, &value)) = theta.iter().enumerate().find(|(_, t)| !t.is_finite()) {
            return Err(InvalidInput::NotFinite {
                field: "theta",
                index,
                value,
            }
            .into());
        }
        debug_assert_eq!(out.len(), theta.len() * N_LOAD_COLUMNS);
        let pool = pool(resolve_threads(n_threads)?)?;
        pool.install(|| {
            out.par_chunks_mut(CHUNK * N_LOAD_COLUMNS)
                .zip(theta.par_chunks(CHUNK))
                .for_each(|(rows, ts)| {
                    if crate::cancel::requested() {
                        return;
                    }
                    let mut geo = [0.0; N_COLUMNS];
                    for (row, &t) in rows.chunks_exact_mut(N_LOAD_COLUMNS).zip(ts) {
                        self.row(t, &mut geo);
                        let load = loads.segment_loads[self.program().segment_at(t)];
                        row.copy_from_slice(&self.load_row(&geo, omega, loads, load, hertz));
                    }
                })
        });
        Ok(())
    }
}
