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

// fdlibm's atan (s_atan.c): atan(0.5), atan(1), atan(1.5), atan(∞) split hi + lo,
// and the odd minimax polynomial on |x| < 7/16, digits as published.
#[allow(clippy::excessive_precision)]
const ATAN_HI: [f64; 4] = [
    4.636_476_090_008_060_935_15e-01,
    7.853_981_633_974_482_789_99e-01,
    9.827_937_232_473_290_540_82e-01,
    1.570_796_326_794_896_558_00e+00,
];
#[allow(clippy::excessive_precision)]
const ATAN_LO: [f64; 4] = [
    2.269_877_745_296_168_709_24e-17,
    3.061_616_997_868_383_017_93e-17,
    1.390_331_103_123_099_845_16e-17,
    6.123_233_995_736_766_035_87e-17,
];
#[allow(clippy::excessive_precision)]
const AT: [f64; 11] = [
    3.333_333_333_333_293_180_27e-01,
    -1.999_999_999_987_648_324_76e-01,
    1.428_571_427_250_346_637_11e-01,
    -1.111_111_040_546_235_578_80e-01,
    9.090_887_133_436_506_561_96e-02,
    -7.691_876_205_044_829_994_95e-02,
    6.661_073_137_387_531_206_69e-02,
    -5.833_570_133_790_573_486_45e-02,
    4.976_877_994_615_932_360_17e-02,
    -3.653_157_274_421_691_552_70e-02,
    1.628_582_011_536_578_236_23e-02,
];
/// π − the f64 nearest π.
#[allow(clippy::excessive_precision)]
const PI_LO: f64 = 1.224_646_799_147_353_177_2e-16;

/// atan a for finite a ≥ 0: fdlibm's reduction to |w| < 7/16 and its
/// polynomial, inlined (within 1 ulp; glibc's out-of-line atan2 was a seventh
/// of the whole kernel's time).
#[inline(always)]
fn atan_nonneg(a: f64) -> f64 {
    let (id, w) = if a < 0.4375 {
        (usize::MAX, a)
    } else if a < 0.6875 {
        (0, (2.0 * a - 1.0) / (2.0 + a))
    } else if a < 1.1875 {
        (1, (a - 1.0) / (a + 1.0))
    } else if a < 2.4375 {
        (2, (a - 1.5) / (1.0 + 1.5 * a))
    } else {
        (3, -1.0 / a)
    };
    let z = w * w;
    let v = z * z;
    let s1 = z * (AT[0] + v * (AT[2] + v * (AT[4] + v * (AT[6] + v * (AT[8] + v * AT[10])))));
    let s2 = v * (AT[1] + v * (AT[3] + v * (AT[5] + v * (AT[7] + v * AT[9]))));
    if id == usize::MAX {
        w - w * (s1 + s2)
    } else {
        ATAN_HI[id] - ((w * (s1 + s2) - ATAN_LO[id]) - w)
    }
}

/// atan2(y, x) [rad] in (−π, π]: fdlibm's quadrant rule around [`atan_nonneg`];
/// zeros, infinities and NaN go to the platform's `atan2`. Within 2 ulp of it
/// (tested).
#[inline(always)]
fn atan2(y: f64, x: f64) -> f64 {
    let a = y.abs() / x.abs();
    if !(y != 0.0 && x != 0.0 && a.is_finite() && a > 0.0) {
        return platform_atan2(y, x);
    }
    let z = atan_nonneg(a);
    let z = if x > 0.0 { z } else { PI - (z - PI_LO) };
    if y > 0.0 {
        z
    } else {
        -z
    }
}

#[cold]
#[inline(never)]
fn platform_atan2(y: f64, x: f64) -> f64 {
    y.atan2(x)
}

#[cfg(test)]
mod atan2_tests {
    use proptest::prelude::*;

    fn ulps(a: f64, b: f64) -> f64 {
        (a - b).abs() / (f64::EPSILON * b.abs().max(f64::MIN_POSITIVE))
    }

    proptest! {
        #[test]
        fn atan2_matches_the_platform(y in -1e3f64..1e3, x in -1e3f64..1e3, e in -300i32..300) {
            for (yy, xx) in [(y, x), (y * 2f64.powi(e), x), (y, x * 2f64.powi(e))] {
                let (a, b) = (super::atan2(yy, xx), yy.atan2(xx));
                prop_assert!(ulps(a, b) <= 2.0, "atan2({yy}, {xx}) = {a} vs {b}");
            }
        }
    }

    #[test]
    fn atan2_at_the_reduction_edges_and_special_values() {
        for a in [0.4375f64, 0.6875, 1.1875, 2.4375, 1.0, 0.5, 1.5, 1e-300, 1e300] {
            for t in [a.next_down(), a, a.next_up()] {
                for (y, x) in [(t, 1.0), (-t, 1.0), (t, -1.0), (-t, -1.0), (1.0, 1.0 / t)] {
                    let (a, b) = (super::atan2(y, x), y.atan2(x));
                    assert!(ulps(a, b) <= 2.0, "atan2({y}, {x}) = {a} vs {b}");
                }
            }
        }
        let inf = f64::INFINITY;
        for (y, x) in [(0.0, 1.0), (-0.0, -1.0), (1.0, 0.0), (0.0, 0.0), (inf, 1.0), (1.0, -inf)] {
            assert_eq!(super::atan2(y, x).to_bits(), y.atan2(x).to_bits());
        }
        assert!(super::atan2(f64::NAN, 1.0).is_nan());
    }
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
        let [s, ds, dds, ddds] = self.program.eval(theta);
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
                let phi = atan2(cross(v, n), dot(v, n));
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
