//! Followers and the exact geometry of the cam: pitch curve, profile (both flanks
//! of a groove), pressure angle, signed radii of curvature and undercut.

use std::f64::consts::PI;

use rayon::prelude::*;

use super::program::{CamError, Program};
use crate::geom::{cross, dot, sin_cos, V2};
use crate::parallel::{pool, resolve_threads};

/// The columns of [`Cam::solve_into`]'s rows, in order.
pub const COLUMNS: [&str; 14] = [
    "s",
    "ds",
    "dds",
    "ddds",
    "pitch_x",
    "pitch_y",
    "profile_x",
    "profile_y",
    "outer_x",
    "outer_y",
    "pressure_angle",
    "pitch_radius_of_curvature",
    "profile_radius_of_curvature",
    "undercut",
];

/// Values per cam angle in [`Cam::solve_into`].
pub const N_COLUMNS: usize = COLUMNS.len();

/// Angles per parallel chunk.
const CHUNK: usize = 4096;

/// The follower of a cam [m].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Follower {
    /// Translating roller along +y, offset `offset` along +x (knife edge: roller 0).
    TranslatingRoller {
        base_radius: f64,
        roller_radius: f64,
        offset: f64,
    },
    /// Translating flat face perpendicular to its motion along +y.
    FlatFaced { base_radius: f64 },
    /// Roller on an arm of `arm_length` about a pivot at `pivot_distance`; the
    /// displacement is the arm's rotation [rad].
    OscillatingRoller {
        pivot_distance: f64,
        arm_length: f64,
        base_radius: f64,
        roller_radius: f64,
    },
}

/// A validated cam: its program, follower and closure.
#[derive(Debug, Clone)]
pub struct Cam {
    program: Program,
    follower: Follower,
    groove: bool,
    /// Translating: √(R_p² − e²); oscillating: the initial arm angle ψ0 [rad].
    start: f64,
}

fn positive(field: &'static str, value: f64) -> Result<(), CamError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(CamError::BadFollower {
            field,
            value,
            why: "must be finite and > 0".into(),
        })
    }
}

fn roller(base: f64, r: f64) -> Result<(), CamError> {
    positive("base_radius", base)?;
    if !(r.is_finite() && r >= 0.0 && r < base) {
        return Err(CamError::BadFollower {
            field: "roller_radius",
            value: r,
            why: format!("must be >= 0 and < base_radius = {base}"),
        });
    }
    Ok(())
}

/// J v: v turned by +90°.
#[inline]
fn perp(v: V2) -> V2 {
    [-v[1], v[0]]
}

impl Cam {
    /// Validate the follower against the program; `groove` is form closure.
    pub fn new(program: Program, follower: Follower, groove: bool) -> Result<Cam, CamError> {
        let start = match follower {
            Follower::TranslatingRoller {
                base_radius,
                roller_radius,
                offset,
            } => {
                roller(base_radius, roller_radius)?;
                let rp = base_radius + roller_radius;
                if !(offset.is_finite() && offset.abs() < rp) {
                    return Err(CamError::BadFollower {
                        field: "offset",
                        value: offset,
                        why: format!("must satisfy |offset| < base_radius + roller_radius = {rp}"),
                    });
                }
                (rp * rp - offset * offset).sqrt()
            }
            Follower::FlatFaced { base_radius } => {
                positive("base_radius", base_radius)?;
                if groove {
                    return Err(CamError::BadFollower {
                        field: "closure",
                        value: f64::NAN,
                        why: "a flat-faced follower needs spring closure, not a groove".into(),
                    });
                }
                base_radius
            }
            Follower::OscillatingRoller {
                pivot_distance: a,
                arm_length: l,
                base_radius,
                roller_radius,
            } => {
                positive("pivot_distance", a)?;
                positive("arm_length", l)?;
                roller(base_radius, roller_radius)?;
                let rp = base_radius + roller_radius;
                if !((a - l).abs() < rp && rp < a + l) {
                    return Err(CamError::BadFollower {
                        field: "pivot_distance",
                        value: a,
                        why: format!(
                            "with arm_length = {l}: the roller cannot reach the pitch base \
                             circle R_p = {rp} (needs |a − l| < R_p < a + l)"
                        ),
                    });
                }
                let psi0 = ((a * a + l * l - rp * rp) / (2.0 * a * l)).acos();
                let (lo, hi) = (psi0 + program.s_min(), psi0 + program.s_max());
                if !(lo > 0.0 && hi < PI) {
                    return Err(CamError::BadFollower {
                        field: "arm_length",
                        value: l,
                        why: format!(
                            "the arm angle runs over [{lo}, {hi}] rad from ψ0 = {psi0}: it \
                             must stay inside (0, π), off the line of centres"
                        ),
                    });
                }
                psi0
            }
        };
        if let Follower::TranslatingRoller { .. } = follower {
            if start + program.s_min() <= 0.0 {
                return Err(CamError::BadFollower {
                    field: "base_radius",
                    value: start,
                    why: "is too small: the follower would cross the cam centre".into(),
                });
            }
        }
        Ok(Cam {
            program,
            follower,
            groove,
            start,
        })
    }

    /// The program.
    pub fn program(&self) -> &Program {
        &self.program
    }

    /// The follower.
    pub fn follower(&self) -> Follower {
        self.follower
    }

    /// Whether the cam is grooved (form closure).
    pub fn groove(&self) -> bool {
        self.groove
    }

    /// The initial arm angle ψ0 [rad] of an oscillating follower (else `None`).
    pub fn initial_arm_angle(&self) -> Option<f64> {
        match self.follower {
            Follower::OscillatingRoller { .. } => Some(self.start),
            _ => None,
        }
    }

    /// One row of [`COLUMNS`] at cam angle θ [rad].
    #[inline]
    pub fn row(&self, theta: f64, out: &mut [f64]) {
        self.row_at(theta, self.program.eval(theta), out)
    }

    /// One row of [`COLUMNS`] at cam angle θ [rad] for the displacement and its
    /// derivatives `sv` = [s, s′, s″, s‴] (the program's at θ, or a bound
    /// search's trial segment).
    #[inline]
    pub fn row_at(&self, theta: f64, sv: [f64; 4], out: &mut [f64]) {
        let [s, ds, dds, ddds] = sv;
        // Fixed frame: roller centre (or flat-face trace point) C, C', C'', and
        // the unit direction v of the follower's motion (increasing s).
        let (c, c1, c2, v, rr) = match self.follower {
            Follower::TranslatingRoller {
                roller_radius,
                offset,
                ..
            } => (
                [offset, self.start + s],
                [0.0, ds],
                [0.0, dds],
                [0.0, 1.0],
                roller_radius,
            ),
            Follower::FlatFaced { .. } => (
                [0.0, self.start + s],
                [0.0, ds],
                [0.0, dds],
                [0.0, 1.0],
                0.0,
            ),
            Follower::OscillatingRoller {
                pivot_distance: a,
                arm_length: l,
                roller_radius,
                ..
            } => {
                let (sn, cs) = sin_cos(self.start + s);
                (
                    [a - l * cs, l * sn],
                    [l * ds * sn, l * ds * cs],
                    [l * (dds * sn + ds * ds * cs), l * (dds * cs - ds * ds * sn)],
                    [sn, cs],
                    roller_radius,
                )
            }
        };
        // Pitch point in the cam frame P = R(−θ) C: dP/dθ = R(−θ) T and
        // d²P/dθ² = R(−θ) A, with T = C' − J C and A = C'' − 2 J C' − C.
        let jc = perp(c);
        let jc1 = perp(c1);
        let t = [c1[0] - jc[0], c1[1] - jc[1]];
        let acc = [c2[0] - 2.0 * jc1[0] - c[0], c2[1] - 2.0 * jc1[1] - c[1]];
        let speed = dot(t, t).sqrt();
        let k = cross(t, acc);
        // The pitch point moves clockwise in the cam frame: convex is k < 0.
        let rho_p = if k == 0.0 {
            f64::INFINITY
        } else {
            -speed * speed * speed / k
        };
        let jt = perp(t);
        let n = [jt[0] / speed, jt[1] / speed];
        let (sn, cs) = sin_cos(theta);
        let to_cam = |p: V2| [p[0] * cs + p[1] * sn, -p[0] * sn + p[1] * cs];
        let pitch = to_cam(c);
        let nan = [f64::NAN, f64::NAN];
        let (profile, outer, phi, rho_q, undercut) = match self.follower {
            Follower::FlatFaced { .. } => {
                let rho = self.start + s + dds;
                let q = to_cam([ds, self.start + s]);
                (q, nan, 0.0, rho, rho < 0.0)
            }
            _ => {
                let q = to_cam([c[0] - rr * n[0], c[1] - rr * n[1]]);
                let o = if self.groove {
                    to_cam([c[0] + rr * n[0], c[1] + rr * n[1]])
                } else {
                    nan
                };
                let phi = cross(v, n).atan2(dot(v, n));
                let cusp_inner = rr > 0.0 && rho_p > 0.0 && rho_p < rr;
                let cusp_outer = self.groove && rr > 0.0 && rho_p < 0.0 && -rho_p < rr;
                (q, o, phi, rho_p - rr, cusp_inner || cusp_outer)
            }
        };
        let row = [
            s,
            ds,
            dds,
            ddds,
            pitch[0],
            pitch[1],
            profile[0],
            profile[1],
            outer[0],
            outer[1],
            phi,
            rho_p,
            rho_q,
            if undercut { 1.0 } else { 0.0 },
        ];
        out[..N_COLUMNS].copy_from_slice(&row);
    }

    /// Rows of [`COLUMNS`] for every cam angle [rad] into `out` (row-major,
    /// `theta.len() · N_COLUMNS` values), in parallel chunks.
    pub fn solve_into(
        &self,
        theta: &[f64],
        out: &mut [f64],
        n_threads: Option<i64>,
    ) -> Result<(), CamError> {
        if let Some((index, &value)) = theta.iter().enumerate().find(|(_, t)| !t.is_finite()) {
            return Err(CamError::NotFinite {
                field: "theta",
                index,
                value,
            });
        }
        debug_assert_eq!(out.len(), theta.len() * N_COLUMNS);
        let pool = pool(resolve_threads(n_threads)?)?;
        pool.install(|| {
            out.par_chunks_mut(CHUNK * N_COLUMNS)
                .zip(theta.par_chunks(CHUNK))
                .for_each(|(rows, ts)| {
                    for (row, &t) in rows.chunks_exact_mut(N_COLUMNS).zip(ts) {
                        self.row(t, row);
                    }
                })
        });
        Ok(())
    }
}
