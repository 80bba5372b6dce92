//! Followers and the exact geometry of the cam: pitch curve, profile (both flanks
//! of a groove), pressure angle, signed radii of curvature and undercut.

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

use rayon::prelude::*;

use super::program::{CamError, LanesSink, Program};
use crate::geom::{sin_cos_fma_lanes, sin_cos_lanes, sin_cos_near_lanes};
use crate::input::InvalidInput;
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

/// How [`Cam::geometry`] finishes a row.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Mode {
    /// Every column; the pressure angle by the inlined [`atan2_lanes`].
    Lanes,
    /// [`Mode::Lanes`] for a kernel compiled with FMA: fused multiply-adds,
    /// θ's sine and cosine by [`sin_cos_fma_lanes`] or, where the lane
    /// group lies within [`NEAR_RAD`](crate::geom::NEAR_RAD) of its
    /// [`Anchor`], rotated from the anchor's ([`sin_cos_near_lanes`]), the
    /// law's sinusoid once (`Program::eval_lanes_fast_then`), one reciprocal
    /// of the pitch speed, the pitch radius as −(|T|²/k)·|T| and the pressure
    /// angle by [`atan2_fast_lanes`] of the unscaled normal (neither waits
    /// for the square root); a translating roller by
    /// [`Cam::translating_fast`] (its zero terms dropped, the pressure angle
    /// by [`atan2_right_lanes`]). Within 1e-13 of each output's scale
    /// (curvature for the radii) of [`Mode::Platform`]'s (tested), about
    /// half the work of [`Mode::Lanes`]; the same bits on every instruction
    /// set, but an angle's bits depend on its anchor (the first angle of its
    /// run of [`ANCHOR_GROUPS`] groups), not on the angle alone.
    Fast,
    /// Every column; the pressure angle by the platform's `atan2`.
    Platform,
    /// The bound searches' inner loop: no cam-frame points (NaN) and, in the
    /// pressure angle's column, cos φ (what the loads need) instead of φ.
    Lean,
}

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

// fdlibm's atan (s_atan.c): atan(0.5), atan(1), atan(1.5), atan(∞) split hi + lo,
// and the odd minimax polynomial on |x| < 7/16, digits as published.
#[allow(clippy::excessive_precision)]
const ATAN_HI: [f64; 4] = [
    4.636_476_090_008_060_935_15e-01,
    FRAC_PI_4,
    9.827_937_232_473_290_540_82e-01,
    FRAC_PI_2,
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

/// `if m { a } else { b }` by bit masks: a blend in every lane, where an `if`
/// in a lane loop can compile to a branch per lane.
#[inline(always)]
fn pick(m: bool, a: f64, b: f64) -> f64 {
    let k = (m as u64).wrapping_neg();
    f64::from_bits((a.to_bits() & k) | (b.to_bits() & !k))
}

/// atan2(y, x) [rad] in (−π, π] for `L` lanes: fdlibm's atan (its reduction
/// to |w| < 7/16 written as one rational map whose constants each lane picks,
/// and its polynomial) and fdlibm's quadrant rule, without branches; lanes with a
/// zero, infinite or NaN argument or ratio take the platform's `atan2`. Within 2
/// ulp of the platform (tested); glibc's out-of-line atan2 was a seventh of the
/// kernel's time.
#[inline(always)]
fn atan2_lanes<const L: usize>(y: &[f64; L], x: &[f64; L]) -> [f64; L] {
    let mut out = [0.0; L];
    let mut special = false;
    for l in 0..L {
        let a = y[l].abs() / x[l].abs();
        special |= !(y[l] != 0.0 && x[l] != 0.0 && a.is_finite() && a > 0.0);
        // w = (p·a − q)/(r + s·a): a, (2a − 1)/(2 + a), (a − 1)/(a + 1),
        // (a − 1.5)/(1 + 1.5a), −1/a; then atan a = hi − ((w·P(w²) − lo) − w),
        // which for hi = lo = 0 is fdlibm's w − w·P(w²) exactly.
        let (b0, b1, b2, b3) = (a >= 0.4375, a >= 0.6875, a >= 1.1875, a >= 2.4375);
        let p = pick(b3, 0.0, pick(b0 & !b1, 2.0, 1.0));
        let q = pick(b3, 1.0, pick(b2, 1.5, pick(b0, 1.0, 0.0)));
        let r = pick(b3, 0.0, pick(b0 & !b1, 2.0, 1.0));
        let s = pick(b3, 1.0, pick(b2, 1.5, pick(b0, 1.0, 0.0)));
        let hi = pick(
            b3,
            ATAN_HI[3],
            pick(
                b2,
                ATAN_HI[2],
                pick(b1, ATAN_HI[1], pick(b0, ATAN_HI[0], 0.0)),
            ),
        );
        let lo = pick(
            b3,
            ATAN_LO[3],
            pick(
                b2,
                ATAN_LO[2],
                pick(b1, ATAN_LO[1], pick(b0, ATAN_LO[0], 0.0)),
            ),
        );
        let w = (p * a - q) / (r + s * a);
        let z = w * w;
        let v = z * z;
        let s1 = z * (AT[0] + v * (AT[2] + v * (AT[4] + v * (AT[6] + v * (AT[8] + v * AT[10])))));
        let s2 = v * (AT[1] + v * (AT[3] + v * (AT[5] + v * (AT[7] + v * AT[9]))));
        let t = hi - ((w * (s1 + s2) - lo) - w);
        let t = pick(x[l] > 0.0, t, PI - (t - PI_LO));
        out[l] = pick(y[l] > 0.0, t, -t);
    }
    if special {
        for l in 0..L {
            let a = y[l].abs() / x[l].abs();
            if !(y[l] != 0.0 && x[l] != 0.0 && a.is_finite() && a > 0.0) {
                out[l] = platform_atan2(y[l], x[l]);
            }
        }
    }
    out
}

/// π/2 − the f64 nearest π/2.
#[allow(clippy::excessive_precision)]
const PIO2_LO: f64 = 6.123_233_995_736_766_035_87e-17;

/// atan2(y, x) [rad] in (−π, π] for `L` lanes with one division and fused
/// multiply-adds, for a kernel compiled with FMA: with u = min(|x|, |y|) and
/// v = max(|x|, |y|), atan(u/v) ∈ [0, π/4] is fdlibm's odd polynomial of w =
/// u/v, or π/4 + that of w = (u − v)/(u + v) when u/v > √2 − 1 (either way
/// |w| ≤ √2 − 1, inside the polynomial's |w| < 7/16), then π/2 − · when
/// |y| > |x|, π − · when x < 0 and the sign of y, each constant split hi + lo
/// as fdlibm's. [`atan2_lanes`] divides twice (the ratio, then fdlibm's map of
/// it). Lanes with a zero, infinite, NaN or huge (> 1e300) argument take the
/// platform's `atan2`. Within 2 ulp of the platform (tested).
#[inline(always)]
fn atan2_fast_lanes<const L: usize>(y: &[f64; L], x: &[f64; L]) -> [f64; L] {
    const TAN_PI_8: f64 = std::f64::consts::SQRT_2 - 1.0;
    let mut out = [0.0; L];
    let mut special = false;
    for l in 0..L {
        let (ax, ay) = (x[l].abs(), y[l].abs());
        let (u, v) = (ax.min(ay), ax.max(ay));
        // (min and max drop a NaN: x + y keeps it.)
        special |= !((u > 0.0) & (v < 1e300) & !(x[l] + y[l]).is_nan());
        let big = u > TAN_PI_8 * v;
        let w = pick(big, u - v, u) / pick(big, u + v, v);
        let z = w * w;
        let zz = z * z;
        let even = zz
            .mul_add(AT[10], AT[8])
            .mul_add(zz, AT[6])
            .mul_add(zz, AT[4])
            .mul_add(zz, AT[2])
            .mul_add(zz, AT[0]);
        let odd = zz
            .mul_add(AT[9], AT[7])
            .mul_add(zz, AT[5])
            .mul_add(zz, AT[3])
            .mul_add(zz, AT[1]);
        let q = z.mul_add(odd, even);
        // atan u/v = hi − ((w·z·Q − lo) − w): fdlibm's form, hi = lo = 0 below
        // tan(π/8).
        let (hi, lo) = (pick(big, FRAC_PI_4, 0.0), pick(big, ATAN_LO[1], 0.0));
        let t = hi - ((w * z).mul_add(q, -lo) - w);
        let t = pick(ay > ax, (FRAC_PI_2 - t) + PIO2_LO, t);
        let t = pick(x[l] > 0.0, t, (PI - t) + PI_LO);
        out[l] = pick(y[l] > 0.0, t, -t);
    }
    if special {
        for l in 0..L {
            let (ax, ay) = (x[l].abs(), y[l].abs());
            if !((ax.min(ay) > 0.0) & (ax.max(ay) < 1e300) & !(x[l] + y[l]).is_nan()) {
                out[l] = platform_atan2(y[l], x[l]);
            }
        }
    }
    out
}

#[cold]
#[inline(never)]
fn platform_atan2(y: f64, x: f64) -> f64 {
    y.atan2(x)
}

// atan w = w − w·z·P(z), z = w², on |w| ≤ tan(π/8): P of degree 8, fitted by
// least squares on Chebyshev nodes in 40-digit arithmetic (its error 2.4e-16
// absolute at most on the interval, against fdlibm's degree 10 for |w| < 7/16).
#[allow(clippy::excessive_precision)]
const AT_SHORT: [f64; 9] = [
    0.333_333_333_331_451_5,
    -0.199_999_999_658_150_57,
    0.142_857_119_541_588_3,
    -0.111_110_290_702_336_69,
    0.090_892_171_020_029_1,
    -0.076_706_048_215_711_52,
    0.064_898_628_793_205_32,
    -0.049_766_422_130_405_4,
    0.024_714_823_887_357_16,
];

/// atan2(y, x) [rad] for x > 0 (the pressure angle of a translating roller,
/// whose x is the lift R + s > 0) for `L` lanes: [`atan2_fast_lanes`]
/// without the left half-plane, the sign of y copied onto atan(|y|/x), and
/// the shorter polynomial [`AT_SHORT`] on the same reduction (|w| ≤
/// tan(π/8)). Lanes with x not > 0, an infinite, NaN or huge (> 1e300)
/// argument take the platform's `atan2`. Within 2 ulp and 4e-16 of the
/// platform (tested), not bit for bit [`atan2_fast_lanes`].
#[inline(always)]
fn atan2_right_lanes<const L: usize>(y: &[f64; L], x: &[f64; L]) -> [f64; L] {
    const TAN_PI_8: f64 = std::f64::consts::SQRT_2 - 1.0;
    const SIGN: u64 = 1 << 63;
    let mut out = [0.0; L];
    let mut special = false;
    for l in 0..L {
        let ay = y[l].abs();
        let (u, v) = (x[l].min(ay), x[l].max(ay));
        special |= !((x[l] > 0.0) & (v < 1e300) & !y[l].is_nan());
        let big = u > TAN_PI_8 * v;
        let w = pick(big, u - v, u) / pick(big, u + v, v);
        let z = w * w;
        let zz = z * z;
        let a = &AT_SHORT;
        let even = zz
            .mul_add(a[8], a[6])
            .mul_add(zz, a[4])
            .mul_add(zz, a[2])
            .mul_add(zz, a[0]);
        let odd = zz.mul_add(a[7], a[5]).mul_add(zz, a[3]).mul_add(zz, a[1]);
        let q = z.mul_add(odd, even);
        let (hi, lo) = (pick(big, FRAC_PI_4, 0.0), pick(big, ATAN_LO[1], 0.0));
        let t = hi - ((w * z).mul_add(q, -lo) - w);
        // t ≥ 0 (+0 for y = ±0): y's sign bit is atan2's sign.
        let t = pick(ay > x[l], (FRAC_PI_2 - t) + PIO2_LO, t);
        out[l] = f64::from_bits(t.to_bits() | (y[l].to_bits() & SIGN));
    }
    if special {
        for l in 0..L {
            let v = x[l].max(y[l].abs());
            if !((x[l] > 0.0) & (v < 1e300) & !y[l].is_nan()) {
                out[l] = platform_atan2(y[l], x[l]);
            }
        }
    }
    out
}

/// One parallel chunk of [`Cam::solve_flags_into`]: its rows, angles, flags
/// and copy of the angles (empty where not asked for).
type Chunk<'a> = (&'a mut [f64], &'a [f64], &'a mut [bool], &'a mut [f64]);

/// Angles per lane group of [`Cam::solve_into`]: one AVX-512 register of f64.
const GROUP: usize = 8;

/// [`Cam::solve_into`]'s loop over one chunk, compiled once per instruction set
/// (`pulp` picks AVX-512, AVX2 or baseline at run time). Its output: whether
/// every angle was finite (a group holding a non-finite angle is left
/// unwritten).
struct Rows<'a> {
    cam: &'a Cam,
    theta: &'a [f64],
    out: &'a mut [f64],
    /// [`Mode::Fast`] (the processor has FMA), else [`Mode::Lanes`].
    fast: bool,
    /// The undercut flags of `theta` as booleans, written beside the rows
    /// while they are in registers (empty: not asked for).
    flags: &'a mut [bool],
    /// A copy of `theta` written group by group while it is in registers
    /// (empty: not asked for), where a later copy would read θ again.
    theta_copy: &'a mut [f64],
}

impl pulp::WithSimd for Rows<'_> {
    type Output = bool;

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, simd: S) -> bool {
        let Rows {
            cam,
            theta,
            out,
            fast,
            flags,
            theta_copy,
        } = self;
        const BLOCK: usize = GROUP * N_COLUMNS;
        // A group's stretch of an optional output (empty: not asked for).
        fn part<T>(v: &mut [T], at: std::ops::Range<usize>) -> &mut [T] {
            if v.is_empty() {
                v
            } else {
                &mut v[at]
            }
        }
        let mut finite = true;
        let n_full = theta.len() / GROUP;
        let mut anchors = None;
        let (full, rest) = out.split_at_mut(n_full * BLOCK);
        let mut groups = theta.chunks_exact(GROUP);
        for (g, (tg, og)) in (&mut groups).zip(full.chunks_exact_mut(BLOCK)).enumerate() {
            let tg: &[f64; GROUP] = tg.try_into().unwrap_or(&[0.0; GROUP]);
            let Ok(og) = <&mut [f64; BLOCK]>::try_from(og) else {
                continue;
            };
            if fast && g % ANCHOR_GROUPS == 0 {
                anchors = anchors_at(theta, g);
            }
            let near = anchors.map(|a| a[g % ANCHOR_GROUPS]);
            let at = g * GROUP..(g + 1) * GROUP;
            let path = if fast { Path::Fast(near) } else { Path::Lanes };
            finite &= group_rows(
                simd,
                cam,
                path,
                tg,
                og,
                part(flags, at.clone()),
                part(theta_copy, at),
            );
        }
        // The tail (fewer than a group) padded to a whole group, so that every
        // angle of a solve takes the same arithmetic.
        let tail = groups.remainder();
        if !tail.is_empty() {
            let mut tg = [0.0; GROUP];
            tg[..tail.len()].copy_from_slice(tail);
            let mut block = [0.0; BLOCK];
            let at = n_full * GROUP..theta.len();
            let path = if fast { Path::Fast(None) } else { Path::Lanes };
            let ok = group_rows(
                simd,
                cam,
                path,
                &tg,
                &mut block,
                part(flags, at.clone()),
                part(theta_copy, at),
            );
            if ok {
                rest.copy_from_slice(&block[..rest.len()]);
            }
            finite &= ok;
        }
        finite
    }
}

/// How [`group_rows`] computes a group: [`Mode::Lanes`], or [`Mode::Fast`]
/// with the group's anchor for θ's sine and cosine, if it has one.
#[derive(Clone, Copy)]
enum Path {
    Lanes,
    Fast(Option<Anchor>),
}

/// One group of [`Rows`]: the rows of the angles `tg` into `block` (8 × 14
/// values), their undercut flags into `flags` and `tg` into `theta_copy` (each
/// as many as it holds: none, or the group's angles); false, and nothing
/// written, if an angle is not finite. (A function, not a closure: a closure
/// kept out of line would lose the instruction set.)
#[inline(always)]
fn group_rows<S: pulp::Simd>(
    simd: S,
    cam: &Cam,
    path: Path,
    tg: &[f64; GROUP],
    block: &mut [f64; GROUP * N_COLUMNS],
    flags: &mut [bool],
    theta_copy: &mut [f64],
) -> bool {
    if !tg.iter().fold(true, |ok, t| ok & t.is_finite()) {
        return false;
    }
    if let Path::Fast(near) = path {
        cam.program.eval_lanes_fast_then(
            tg,
            FastGroup {
                simd,
                cam,
                theta: tg,
                block,
                flags,
                near,
            },
        );
    } else {
        let cols = cam.geometry(tg, cam.program.eval_lanes(tg), Mode::Lanes, None);
        finish_rows(simd, &cols, block, flags);
    }
    for (c, &t) in theta_copy.iter_mut().zip(tg) {
        *c = t;
    }
    true
}

/// A group's rows into its block and its undercut flags into `flags` (empty:
/// not asked for).
#[inline(always)]
fn finish_rows<S: pulp::Simd>(
    simd: S,
    cols: &[[f64; GROUP]; N_COLUMNS],
    block: &mut [f64; GROUP * N_COLUMNS],
    flags: &mut [bool],
) {
    store_rows(simd, cols, block);
    for (f, &u) in flags.iter_mut().zip(&cols[13]) {
        *f = u != 0.0;
    }
}

/// [`group_rows`] in [`Mode::Fast`] from the lanes [s, s′, s″, s‴]: the
/// sink of [`Program::eval_lanes_fast_then`], so that the geometry and the
/// stores are inlined into each of its branches.
struct FastGroup<'a, S> {
    simd: S,
    cam: &'a Cam,
    theta: &'a [f64; GROUP],
    block: &'a mut [f64; GROUP * N_COLUMNS],
    flags: &'a mut [bool],
    /// The group's anchor for θ's sine and cosine (see [`Anchor`]).
    near: Option<Anchor>,
}

/// An angle θ [rad] near a lane group's and its sine and cosine, from which
/// [`sin_cos_near_lanes`] rotates: the first angle of a group, taken eight
/// groups at a time in one register ([`ANCHOR_GROUPS`]).
#[derive(Clone, Copy)]
struct Anchor {
    theta: f64,
    sin: f64,
    cos: f64,
}

/// Lane groups sharing one register of anchors.
const ANCHOR_GROUPS: usize = 8;

/// The anchors of the lane groups `g`, …, `g` + [`ANCHOR_GROUPS`] − 1 of
/// `theta` (past its last whole group, that group's): each group's first
/// angle, their sines and cosines by one [`sin_cos_fma_lanes`] (the work of
/// one group's, shared by eight). `None` where an anchor is not within
/// 10⁶ rad (that kernel's range) or is NaN.
#[inline(always)]
fn anchors_at(theta: &[f64], g: usize) -> Option<[Anchor; ANCHOR_GROUPS]> {
    let last = (theta.len() / GROUP).checked_sub(1)?;
    let mut a = [0.0; ANCHOR_GROUPS];
    for (j, v) in a.iter_mut().enumerate() {
        *v = theta[(g + j).min(last) * GROUP];
    }
    if !a.iter().fold(true, |ok, v| ok & (v.abs() <= 1e6)) {
        return None;
    }
    let (sn, cs) = sin_cos_fma_lanes(&a);
    Some(std::array::from_fn(|j| Anchor {
        theta: a[j],
        sin: sn[j],
        cos: cs[j],
    }))
}

impl<S: pulp::Simd> LanesSink<GROUP> for FastGroup<'_, S> {
    type Out = ();

    #[inline(always)]
    fn take(self, sv: [[f64; GROUP]; 4]) {
        let FastGroup {
            simd,
            cam,
            theta,
            block,
            flags,
            near,
        } = self;
        let cols = match cam.follower {
            Follower::TranslatingRoller {
                roller_radius,
                offset,
                ..
            } => cam.translating_fast(theta, sv, offset, roller_radius, near),
            _ => cam.geometry(theta, sv, Mode::Fast, near),
        };
        finish_rows(simd, &cols, block, flags);
    }
}

/// A group's 14 columns of 8 lanes stored as its 8 rows of 14 (`block`, 112
/// values): two 8 × 8 transposes in registers ([`crate::tile::transpose`]),
/// then each row as whole-register stores, where a row written value by value
/// from the columns compiled to 128-bit pieces and single stores.
#[inline(always)]
fn store_rows<S: pulp::Simd>(
    simd: S,
    cols: &[[f64; GROUP]; N_COLUMNS],
    block: &mut [f64; GROUP * N_COLUMNS],
) {
    let c = cols;
    // Columns 0–7, then 8–13 (the last two rows of the second tile unused).
    let first = [c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]];
    let second = [c[8], c[9], c[10], c[11], c[12], c[13], c[13], c[13]];
    let (first, second) = (
        crate::tile::transpose(simd, &first),
        crate::tile::transpose(simd, &second),
    );
    for l in 0..GROUP {
        let row = l * N_COLUMNS;
        block[row..row + 8].copy_from_slice(&first[l]);
        block[row + 8..row + N_COLUMNS].copy_from_slice(&second[l][..N_COLUMNS - 8]);
    }
}

/// Whether the processor has fused multiply-add instructions, so that
/// [`Mode::Fast`]'s `mul_add`s are single instructions (`pulp` compiles the
/// kernel for AVX2 + FMA or AVX-512 where it finds them); elsewhere they would
/// be libm calls, and the kernel keeps [`Mode::Lanes`].
fn fma_is_fast() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("fma") && std::arch::is_x86_feature_detected!("avx2")
    }
    #[cfg(target_arch = "aarch64")]
    {
        true
    }
    #[cfg(not(any(target_arch = "x86_64", target_arch = "aarch64")))]
    {
        false
    }
}

#[cfg(test)]
mod lane_tests;

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
        // The roller's centre, or the flat face, must stay on its side of the cam
        // centre (a face at R_b + s ≤ 0 has its profile's base circle nowhere).
        if let Follower::TranslatingRoller { .. } | Follower::FlatFaced { .. } = follower {
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
        let cols = self.geometry(&[theta], sv.map(|v| [v]), Mode::Platform, None);
        for (o, c) in out[..N_COLUMNS].iter_mut().zip(cols) {
            *o = c[0];
        }
    }

    /// A row of [`COLUMNS`] for `sv` = [s, s′, s″, s‴] without the cam-frame
    /// points (NaN there) and with cos φ in the pressure angle's column: what
    /// the loads, the Hertz stress and the undercut need, for the bound
    /// searches' inner loop (no sine, cosine or arctangent of an angle).
    #[inline]
    pub(super) fn lean_row(&self, sv: [f64; 4]) -> [f64; N_COLUMNS] {
        self.geometry(&[0.0], sv.map(|v| [v]), Mode::Lean, None)
            .map(|c| c[0])
    }

    /// The rows of `L` cam angles θ [rad] for their [s, s′, s″, s‴] lanes `sv`,
    /// column by column: every step a loop across lanes without branches, so
    /// that [`Cam::solve_into`] (compiled per instruction set) runs several
    /// angles per instruction. [`Cam::row_at`] is its one-lane case with
    /// `platform_atan2`: the same values but for the pressure angle, which the
    /// lanes take from the inlined [`atan2_lanes`] (within 2 ulp) and `row_at`
    /// from the platform's `atan2` (correctly rounded, so monotone: the bound
    /// searches built on `row_at` converge to the same float whatever their
    /// starting bracket, as before).
    #[inline(always)]
    fn geometry<const L: usize>(
        &self,
        theta: &[f64; L],
        sv: [[f64; L]; 4],
        mode: Mode,
        near: Option<Anchor>,
    ) -> [[f64; L]; N_COLUMNS] {
        // `each!(i => e)`: the lanes [e(0), …, e(L − 1)] by a plain loop (a
        // closure the compiler kept out of line would lose the instruction set).
        macro_rules! each {
            ($i:ident => $e:expr) => {{
                let mut a = [0.0; L];
                for $i in 0..L {
                    a[$i] = $e;
                }
                a
            }};
        }
        let [s, ds, dds, ddds] = sv;
        let st = self.start;
        let fast = mode == Mode::Fast;
        // `fma!(a, b, c)`: a·b + c, fused in the fast mode (one rounding), else
        // as written (two: bit for bit the values `row_at` has always had).
        macro_rules! fma {
            ($a:expr, $b:expr, $c:expr) => {
                if fast {
                    f64::mul_add($a, $b, $c)
                } else {
                    $a * $b + $c
                }
            };
        }
        // θ's (and an arm's) sine and cosine: the fused kernels in the fast
        // mode where every lane is within their range, else fdlibm's.
        // (A macro, not a closure: a closure kept out of line would lose the
        // instruction set.)
        macro_rules! sincos {
            ($a:expr) => {{
                let a: &[f64; L] = $a;
                if fast && a.iter().fold(true, |ok, v| ok & (v.abs() <= 1e6)) {
                    sin_cos_fma_lanes(a)
                } else {
                    sin_cos_lanes(a)
                }
            }};
        }
        let (zero, one) = ([0.0; L], [1.0; L]);
        // Fixed frame: roller centre (or flat-face trace point) C, C', C'', and
        // the unit direction v of the follower's motion (increasing s).
        let lift = each!(i => st + s[i]);
        let (c, c1, c2, v, rr) = match self.follower {
            Follower::TranslatingRoller {
                roller_radius,
                offset,
                ..
            } => (
                [[offset; L], lift],
                [zero, ds],
                [zero, dds],
                [zero, one],
                roller_radius,
            ),
            Follower::FlatFaced { .. } => ([zero, lift], [zero, ds], [zero, dds], [zero, one], 0.0),
            Follower::OscillatingRoller {
                pivot_distance: a,
                arm_length: l,
                roller_radius,
                ..
            } => {
                let (sn, cs) = sincos!(&lift);
                let dd = each!(i => ds[i] * ds[i]);
                (
                    [each!(i => a - l * cs[i]), each!(i => l * sn[i])],
                    [each!(i => l * ds[i] * sn[i]), each!(i => l * ds[i] * cs[i])],
                    [
                        each!(i => l * (dds[i] * sn[i] + dd[i] * cs[i])),
                        each!(i => l * (dds[i] * cs[i] - dd[i] * sn[i])),
                    ],
                    [sn, cs],
                    roller_radius,
                )
            }
        };
        // Pitch point in the cam frame P = R(−θ) C: dP/dθ = R(−θ) T and
        // d²P/dθ² = R(−θ) A, with T = C' − J C and A = C'' − 2 J C' − C
        // (J v = v turned by +90°: J (x, y) = (−y, x)).
        let t = [
            each!(i => c1[0][i] - -c[1][i]),
            each!(i => c1[1][i] - c[0][i]),
        ];
        let acc = [
            each!(i => c2[0][i] - 2.0 * -c1[1][i] - c[0][i]),
            each!(i => c2[1][i] - 2.0 * c1[0][i] - c[1][i]),
        ];
        let speed2 = each!(i => fma!(t[0][i], t[0][i], t[1][i] * t[1][i]));
        let speed = each!(i => speed2[i].sqrt());
        let k = each!(i => fma!(t[0][i], acc[1][i], -(t[1][i] * acc[0][i])));
        // The pitch point moves clockwise in the cam frame: convex is k < 0.
        // (The fast mode divides |T|² by k while the square root runs, where
        // |T|³/k waits for it.)
        let rho_p = if fast {
            each!(i => pick(k[i] == 0.0, f64::INFINITY, -(speed2[i] / k[i]) * speed[i]))
        } else {
            each!(i => pick(
                k[i] == 0.0,
                f64::INFINITY,
                -speed[i] * speed[i] * speed[i] / k[i]
            ))
        };
        // The unit normal: one reciprocal of the speed in the fast mode.
        let n = if fast {
            let inv = each!(i => 1.0 / speed[i]);
            [each!(i => -t[1][i] * inv[i]), each!(i => t[0][i] * inv[i])]
        } else {
            [
                each!(i => -t[1][i] / speed[i]),
                each!(i => t[0][i] / speed[i]),
            ]
        };
        let lean = mode == Mode::Lean;
        // θ's: in the fast mode rotated from the group's anchor where it is
        // near (see [`Anchor`]).
        let rotated = near
            .filter(|_| fast)
            .and_then(|a| sin_cos_near_lanes(theta, a.theta, a.sin, a.cos));
        let (sn, cs) = if lean {
            ([f64::NAN; L], [f64::NAN; L])
        } else if let Some(v) = rotated {
            v
        } else {
            sincos!(theta)
        };
        // P in the cam frame: R(−θ) p (NaN when lean).
        macro_rules! to_cam {
            ($p:expr) => {{
                let p: [[f64; L]; 2] = $p;
                [
                    each!(i => fma!(p[0][i], cs[i], p[1][i] * sn[i])),
                    each!(i => fma!(-p[0][i], sn[i], p[1][i] * cs[i])),
                ]
            }};
        }
        let pitch = to_cam!(c);
        let nan = [[f64::NAN; L]; 2];
        let (profile, outer, phi, rho_q, undercut) = match self.follower {
            Follower::FlatFaced { .. } => {
                let rho = each!(i => lift[i] + dds[i]);
                let q = to_cam!([ds, lift]);
                let phi = if lean { one } else { zero };
                (q, nan, phi, rho, each!(i => pick(rho[i] < 0.0, 1.0, 0.0)))
            }
            _ => {
                let q = to_cam!([
                    each!(i => c[0][i] - rr * n[0][i]),
                    each!(i => c[1][i] - rr * n[1][i])
                ]);
                let o = if self.groove {
                    to_cam!([
                        each!(i => c[0][i] + rr * n[0][i]),
                        each!(i => c[1][i] + rr * n[1][i])
                    ])
                } else {
                    nan
                };
                // φ = atan2(v × n, v · n); the fast mode takes the normal
                // unscaled, J T = |T| n (the same angle, one rounding fewer,
                // and not waiting for the square root and the reciprocal).
                let m = if fast {
                    [each!(i => -t[1][i]), t[0]]
                } else {
                    n
                };
                let cr = each!(i => v[0][i] * m[1][i] - v[1][i] * m[0][i]);
                let dt = each!(i => v[0][i] * m[0][i] + v[1][i] * m[1][i]);
                let phi = match mode {
                    Mode::Platform => each!(i => cr[i].atan2(dt[i])),
                    Mode::Lanes => atan2_lanes(&cr, &dt),
                    Mode::Fast => atan2_fast_lanes(&cr, &dt),
                    Mode::Lean => dt,
                };
                let groove = self.groove;
                let cusp = each!(i => {
                    let inner = (rr > 0.0) & (rho_p[i] > 0.0) & (rho_p[i] < rr);
                    let outer = groove & (rr > 0.0) & (rho_p[i] < 0.0) & (-rho_p[i] < rr);
                    pick(inner | outer, 1.0, 0.0)
                });
                (q, o, phi, each!(i => rho_p[i] - rr), cusp)
            }
        };
        [
            s, ds, dds, ddds, pitch[0], pitch[1], profile[0], profile[1], outer[0], outer[1], phi,
            rho_p, rho_q, undercut,
        ]
    }

    /// [`Cam::geometry`] in [`Mode::Fast`] for a translating roller (offset
    /// `e`, roller radius `rr` [m]), without the terms that are 0 for it (0·x,
    /// 0 − x, which IEEE rules keep in the general form): C = (e, R + s), so
    /// T = (R + s, s′ − e), A = (2s′ − e, s″ − R − s), and the pressure angle
    /// atan2(s′ − e, R + s) by [`atan2_right_lanes`] (R + s > 0). Every other
    /// column is the general form's, bit for bit; the pressure angle within
    /// 2 ulp and 4e-16 of it.
    #[inline(always)]
    fn translating_fast<const L: usize>(
        &self,
        theta: &[f64; L],
        sv: [[f64; L]; 4],
        e: f64,
        rr: f64,
        near: Option<Anchor>,
    ) -> [[f64; L]; N_COLUMNS] {
        macro_rules! each {
            ($i:ident => $e:expr) => {{
                let mut a = [0.0; L];
                for $i in 0..L {
                    a[$i] = $e;
                }
                a
            }};
        }
        let [s, ds, dds, ddds] = sv;
        let st = self.start;
        let lift = each!(i => st + s[i]);
        let t = [lift, each!(i => ds[i] - e)];
        let acc = [each!(i => 2.0 * ds[i] - e), each!(i => dds[i] - lift[i])];
        let speed2 = each!(i => t[0][i].mul_add(t[0][i], t[1][i] * t[1][i]));
        let speed = each!(i => speed2[i].sqrt());
        let k = each!(i => t[0][i].mul_add(acc[1][i], -(t[1][i] * acc[0][i])));
        let rho_p = each!(i => pick(k[i] == 0.0, f64::INFINITY, -(speed2[i] / k[i]) * speed[i]));
        let inv = each!(i => 1.0 / speed[i]);
        let n = [each!(i => -t[1][i] * inv[i]), each!(i => t[0][i] * inv[i])];
        let rotated = near.and_then(|a| sin_cos_near_lanes(theta, a.theta, a.sin, a.cos));
        let (sn, cs) = match rotated {
            Some(v) => v,
            None if theta.iter().fold(true, |ok, v| ok & (v.abs() <= 1e6)) => {
                sin_cos_fma_lanes(theta)
            }
            None => sin_cos_lanes(theta),
        };
        macro_rules! to_cam {
            ($x:expr, $y:expr) => {{
                let (x, y): ([f64; L], [f64; L]) = ($x, $y);
                [
                    each!(i => x[i].mul_add(cs[i], y[i] * sn[i])),
                    each!(i => (-x[i]).mul_add(sn[i], y[i] * cs[i])),
                ]
            }};
        }
        let pitch = to_cam!([e; L], lift);
        let profile = to_cam!(
            each!(i => e - rr * n[0][i]),
            each!(i => lift[i] - rr * n[1][i])
        );
        let outer = if self.groove {
            to_cam!(
                each!(i => e + rr * n[0][i]),
                each!(i => lift[i] + rr * n[1][i])
            )
        } else {
            [[f64::NAN; L]; 2]
        };
        let phi = atan2_right_lanes(&t[1], &lift);
        let groove = self.groove;
        let cusp = each!(i => {
            let inner = (rr > 0.0) & (rho_p[i] > 0.0) & (rho_p[i] < rr);
            let outer = groove & (rr > 0.0) & (rho_p[i] < 0.0) & (-rho_p[i] < rr);
            pick(inner | outer, 1.0, 0.0)
        });
        let rho_q = each!(i => rho_p[i] - rr);
        [
            s, ds, dds, ddds, pitch[0], pitch[1], profile[0], profile[1], outer[0], outer[1], phi,
            rho_p, rho_q, cusp,
        ]
    }

    /// Rows of [`COLUMNS`] for every cam angle [rad] into `out` (row-major,
    /// `theta.len() · N_COLUMNS` values), in parallel chunks.
    pub fn solve_into(
        &self,
        theta: &[f64],
        out: &mut [f64],
        n_threads: Option<i64>,
    ) -> Result<(), CamError> {
        self.solve_flags_into(theta, out, &mut [], &mut [], n_threads)
    }

    /// [`Cam::solve_into`], and the undercut column as booleans into
    /// `undercut` and a copy of `theta` into `theta_copy` (`theta.len()` of
    /// each, or empty for none): written while the group's rows and angles are
    /// in registers, where a later pass would read the whole (N, 14) block (in
    /// Python, `rows[:, 13] != 0`: a third of the kernel's time for 1e6 angles)
    /// or θ again. The finite check is the group's, in the same pass; a group
    /// with a non-finite angle is left unwritten, and the first such angle
    /// reported.
    pub fn solve_flags_into(
        &self,
        theta: &[f64],
        out: &mut [f64],
        undercut: &mut [bool],
        theta_copy: &mut [f64],
        n_threads: Option<i64>,
    ) -> Result<(), CamError> {
        debug_assert_eq!(out.len(), theta.len() * N_COLUMNS);
        debug_assert!(undercut.is_empty() || undercut.len() == theta.len());
        debug_assert!(theta_copy.is_empty() || theta_copy.len() == theta.len());
        let pool = pool(resolve_threads(n_threads)?)?;
        let fast = fma_is_fast();
        // Each chunk's rows, angles, flags and copy (empty where not asked for).
        let (with_flags, with_copy) = (!undercut.is_empty(), !theta_copy.is_empty());
        let mut flags = undercut.chunks_mut(CHUNK);
        let mut copies = theta_copy.chunks_mut(CHUNK);
        let chunks: Vec<Chunk> = out
            .chunks_mut(CHUNK * N_COLUMNS)
            .zip(theta.chunks(CHUNK))
            .map(|(rows, ts)| {
                let f = if with_flags { flags.next() } else { None };
                let c = if with_copy { copies.next() } else { None };
                (rows, ts, f.unwrap_or_default(), c.unwrap_or_default())
            })
            .collect();
        let one = |(rows, ts, flags, theta_copy): Chunk| {
            crate::cancel::requested()
                || pulp::Arch::new().dispatch(Rows {
                    cam: self,
                    theta: ts,
                    out: rows,
                    fast,
                    flags,
                    theta_copy,
                })
        };
        // One thread: the chunks in the calling thread (no hand-over to the
        // pool's worker and back).
        if pool.current_num_threads() == 1 {
            let finite = chunks.into_iter().fold(true, |ok, c| ok & one(c));
            return self.finite_or_error(theta, finite);
        }
        let finite = pool.install(|| {
            chunks
                .into_par_iter()
                .map(one)
                .reduce(|| true, |a, b| a & b)
        });
        self.finite_or_error(theta, finite)
    }

    /// Ok if `finite`, else the first non-finite angle of `theta` as the error.
    fn finite_or_error(&self, theta: &[f64], finite: bool) -> Result<(), CamError> {
        if !finite {
            if let Some((index, &value)) = theta.iter().enumerate().find(|(_, t)| !t.is_finite()) {
                return Err(InvalidInput::NotFinite {
                    field: "theta",
                    index,
                    value,
                }
                .into());
            }
        }
        Ok(())
    }
}
