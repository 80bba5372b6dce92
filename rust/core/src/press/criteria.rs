//! The working-stroke criteria of one design: dead centres, first contact, the
//! peaks of speed, jerk and torque over the working stroke.

use std::f64::consts::TAU;

use crate::geom::sin_cos;

use super::kinematics::{cos_sin, exact, Design, Frame, Kin, PressError, Table};
use super::walk::{shortcuts, skips_walk, Contact, Walk, WalkPoint, WalkPoints};

/// Carrier angles sampled per turn to find dead centres and extremes, unless the
/// caller gives its own count.
pub const DEFAULT_SAMPLES: usize = 360;

/// Dead centres whose heights differ by at most this fraction of the stroke tie
/// (mirror-symmetric designs have two equally low BDCs or two equally high TDCs,
/// equal but for rounding). Of tied BDCs the one at the smallest θ in [0, 2π) is
/// taken; of tied TDCs the first one reached going back from that BDC (so that a
/// working stroke of k_Sp = 1 runs from the nearest TDC).
pub const TIE: f64 = 1e-12;

/// Why a design has no criteria (or has them with a warning).
#[repr(u8)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    Ok = 0,
    /// The rod cannot reach the guide somewhere in the turn.
    NoReach = 1,
    /// The slider moves back up during the working stroke.
    Reverses = 2,
    /// The working stroke asked for exceeds the nominal stroke.
    LongStroke = 3,
    /// After the tool first meets the blank (coming down from TDC), the slider
    /// backs off above S_p and comes down again before BDC: the blank is hit
    /// twice (see [`RECONTACT`]). The criteria are those from the first contact.
    ReContacts = 4,
}

impl Status {
    /// Every status, indexed by its code.
    pub const ALL: [Status; 5] = [
        Status::Ok,
        Status::NoReach,
        Status::Reverses,
        Status::LongStroke,
        Status::ReContacts,
    ];

    /// What the status means, as `cyclomech.press.STATUS` shows it (the Python
    /// layer reads these texts from `cyclomech._core.PRESS_STATUS`).
    pub const fn text(self) -> &'static str {
        match self {
            Status::Ok => "ok",
            Status::NoReach => "the rod cannot reach the guide somewhere in the turn",
            Status::Reverses => "the slider moves back up during the working stroke",
            Status::LongStroke => "the working stroke exceeds the nominal stroke",
            Status::ReContacts => {
                "re-contacts: the slider meets the blank, backs off above it and comes \
                 down on it again before BDC"
            }
        }
    }
}

/// Columns of the criteria rows.
pub const CRITERIA: [&str; 14] = [
    "S_n",
    "S_p",
    "alpha_p",
    "V_np",
    "V_cp",
    "V_pmax",
    "J_max",
    "torque_arm",
    "k_Sp",
    "k_Vp",
    "k_Vmax",
    "k_M",
    "k_J",
    "theta_bdc",
];

/// The working stroke: a fraction k_Sp of the nominal stroke, or a length S_p [m].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Stroke {
    Fraction(f64),
    Length(f64),
}

/// What the criteria are computed for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spec {
    pub stroke: Stroke,
    /// Crank speed ω [rad/s] (constant).
    pub omega: f64,
    /// Carrier angles sampled per turn.
    pub samples: usize,
}

impl Spec {
    pub fn validate(&self) -> Result<(), PressError> {
        let (name, v, ok) = match self.stroke {
            Stroke::Fraction(k) => ("k_Sp", k, k > 0.0 && k <= 1.0),
            Stroke::Length(s) => ("working_stroke", s, s > 0.0),
        };
        if !(v.is_finite() && ok) {
            let want = if name == "k_Sp" {
                "a fraction of the nominal stroke in (0, 1]"
            } else {
                "a positive length [m]"
            };
            return Err(PressError::BadSpec(format!("{name} = {v} must be {want}")));
        }
        if !(self.omega.is_finite() && self.omega > 0.0) {
            return Err(PressError::BadSpec(format!(
                "omega = {} must be a positive crank speed [rad/s]",
                self.omega
            )));
        }
        if !(8..=1_000_000).contains(&self.samples) {
            return Err(PressError::BadSpec(format!(
                "samples = {} must be between 8 and 1000000 carrier angles per turn",
                self.samples
            )));
        }
        Ok(())
    }
}

/// Wrap an angle into [0, 2π).
#[inline]
pub(super) fn wrap(x: f64) -> f64 {
    let w = x.rem_euclid(TAU);
    if w >= TAU {
        0.0
    } else {
        w
    }
}

/// One pin path sampled over the turn: everything of the slider's kinematics
/// that does not depend on the rod length, so that a sweep computes it once per
/// (R, r, d, φ0, offset) and reuses it for every L.
#[derive(Default)]
pub(super) struct PinScan {
    /// Rows of the pin path in blocks of [`LANES`] samples, so that the rod scan
    /// reads whole registers: u², u·P_x', P_x'² + u·P_x'', P_y, P_y', P_y''
    /// (u = P_x − offset). The last block is padded with copies of sample 0.
    pin: Vec<[[f64; LANES]; 6]>,
    /// max |P_x − offset| over the turn, exact (sample maximum refined at a root
    /// of P_x'): the rod reaches the guide everywhere iff L exceeds it.
    u_max: f64,
    // Rows of one rod length (y, y', y''), in blocks like `pin`.
    pub(super) y: Vec<[f64; LANES]>,
    pub(super) dy: Vec<[f64; LANES]>,
    pub(super) ddy: Vec<[f64; LANES]>,
    /// Candidates of the |y''| peak, of BDC and of TDC for one rod length (see
    /// [`scan_rod`]).
    pub(super) cands: [Vec<usize>; 3],
}

impl PinScan {
    /// The rows of one rod length (L² = `l2`) over the `m` samples, their
    /// extremes and candidates ([`scan_rod`]).
    pub(super) fn rod(&mut self, l2: f64, m: usize) -> Extremes {
        let PinScan {
            pin,
            y,
            dy,
            ddy,
            cands,
            ..
        } = self;
        scan_rod(l2, m, pin, [y, dy, ddy], cands)
    }

    /// y, y', y'' of the last [`PinScan::rod`] over its `m` samples.
    pub(super) fn rows(&self, m: usize) -> (&[f64], &[f64], &[f64]) {
        (
            &self.y.as_flattened()[..m],
            &self.dy.as_flattened()[..m],
            &self.ddy.as_flattened()[..m],
        )
    }

    /// Sample the pin path of `f` (its rod length is not used).
    pub(super) fn fill(&mut self, f: &Frame, table: &Table) {
        let m = table.len();
        let (c0, s0) = cos_sin(f.beta0);
        let blocks = m.div_ceil(LANES);
        self.pin.resize(blocks, [[0.0; LANES]; 6]);
        for v in [&mut self.y, &mut self.dy, &mut self.ddy] {
            v.resize(blocks, [0.0; LANES]);
        }
        let (a, d, kd, k2d) = (f.a, f.d, f.k * f.d, f.k * f.k * f.d);
        let mut best = (0, -1.0);
        for q in 0..blocks * LANES {
            let j = if q < m { q } else { 0 };
            let (ct, st) = (table.ct[j], table.st[j]);
            let (tcb, tsb) = (table.cb[j], table.sb[j]);
            let (cb, sb) = (tcb * c0 - tsb * s0, tsb * c0 + tcb * s0);
            let u = a * ct + d * cb - f.e;
            let px1 = -a * st + kd * sb;
            let px2 = -a * ct - k2d * cb;
            let row = [
                u * u,
                u * px1,
                px1 * px1 + u * px2,
                a * st + d * sb,
                a * ct - kd * cb,
                -a * st - k2d * sb,
            ];
            for (col, v) in self.pin[q / LANES].iter_mut().zip(row) {
                col[q % LANES] = v;
            }
            if u * u > best.1 {
                best = (j, u * u);
            }
        }
        // Refine the largest |u| at a root of u' = P_x' (Newton with u'').
        let h = TAU / m as f64;
        let th = table.theta(best.0);
        let ux = |t: f64| {
            let (st, ct) = sin_cos(t);
            let (sb, cb) = sin_cos(f.beta0 - f.k * t);
            (a * ct + d * cb - f.e, -a * st + kd * sb, -a * ct - k2d * cb)
        };
        let dir = ux(th).0.signum();
        let g = |t: f64| {
            let (_, u1, u2) = ux(t);
            (dir * u1, dir * u2)
        };
        let (lo, hi) = (th - h, th + h);
        let (glo, ghi) = (g(lo).0, g(hi).0);
        self.u_max = best.1.sqrt();
        if glo > 0.0 && ghi < 0.0 {
            let newton = |t: f64| {
                let (v, d) = g(t);
                (v, d, 0.0)
            };
            let t = chebyshev(newton, lo, hi, glo, ghi, th, NEWTON_LAST);
            self.u_max = self.u_max.max(ux(t).0.abs());
        }
    }
}

/// A Newton step at most this large (relative to 1 + |x|) is taken as the last.
const NEWTON_LAST: f64 = 1e-9;

/// A Chebyshev step at most this large (relative to 1 + |x|) is taken as the
/// last: the method's error cubes, so the next one would be below rounding.
const STEP_LAST: f64 = 1e-7;

/// Root of f on [lo, hi] (f(lo), f(hi) of opposite signs) from `x0` by
/// Chebyshev's method (Newton's step plus its second-order term), kept inside
/// the bracket by bisection; `f` returns the value and the first two
/// derivatives. The second-order term is taken only where it corrects
/// Newton's step (is below half of it), so far from the root this is Newton,
/// and with a zero second derivative it is Newton's method throughout. A step
/// at most `last` (relative to 1 + |x|) is taken as the last: [`STEP_LAST`]
/// where the error cubes, [`NEWTON_LAST`] where it squares (Newton).
fn chebyshev(
    mut f: impl FnMut(f64) -> (f64, f64, f64),
    mut lo: f64,
    mut hi: f64,
    flo: f64,
    fhi: f64,
    x0: f64,
    last: f64,
) -> f64 {
    if flo == 0.0 {
        return lo;
    }
    if fhi == 0.0 {
        return hi;
    }
    // Orient so that f(lo) < 0.
    if flo > 0.0 {
        std::mem::swap(&mut lo, &mut hi);
    }
    let mut x = if (x0 - lo) * (x0 - hi) < 0.0 {
        x0
    } else {
        0.5 * (lo + hi)
    };
    for _ in 0..60 {
        let (v, d1, d2) = f(x);
        if v == 0.0 {
            return x;
        }
        if v < 0.0 {
            lo = x;
        } else {
            hi = x;
        }
        let r = 1.0 / d1;
        let newton = -v * r;
        let second = -0.5 * d2 * r * newton * newton;
        let step = if second.abs() < 0.5 * newton.abs() {
            newton + second
        } else {
            newton
        };
        let tiny = 4.0 * f64::EPSILON * (1.0 + x.abs());
        if step.abs() <= tiny {
            return x;
        }
        let next = x + step;
        let inside = (next - lo) * (next - hi) < 0.0;
        if inside && step.abs() <= last * (1.0 + x.abs()) {
            return next;
        }
        if !inside {
            // A root within rounding of an end of the bracket: that end (else
            // the bisections below would creep up on it).
            for end in [lo, hi] {
                if (next - end).abs() <= tiny {
                    return end;
                }
            }
        }
        let next = if inside { next } else { 0.5 * (lo + hi) };
        if (next - x).abs() <= 2.0 * f64::EPSILON * (1.0 + x.abs()) {
            return next;
        }
        x = next;
    }
    x
}

/// Root in [a, b] of the cubic that has the values `f` = [f(a), f(b)] (of
/// opposite signs) and the slopes `df` at the ends (Hermite): Newton on the
/// cubic from the secant's root, each step kept only if it stays in [a, b].
fn hermite_root(a: f64, b: f64, [fa, fb]: [f64; 2], [da, db]: [f64; 2]) -> f64 {
    if fa == 0.0 {
        return a;
    }
    if fb == 0.0 {
        return b;
    }
    // p(s) = fa + m0·s + c2·s² + c3·s³ on s ∈ [0, 1], x = a + s·(b − a).
    let len = b - a;
    let (m0, m1) = (len * da, len * db);
    let c2 = 3.0 * (fb - fa) - 2.0 * m0 - m1;
    let c3 = 2.0 * (fa - fb) + m0 + m1;
    let mut s = fa / (fa - fb);
    for _ in 0..2 {
        let p = fa + s * (m0 + s * (c2 + s * c3));
        let dp = m0 + s * (2.0 * c2 + 3.0 * s * c3);
        let t = s - p / dp;
        if (0.0..=1.0).contains(&t) {
            s = t;
        }
    }
    a + s * len
}

/// Offset from the middle sample of the peak of the quartic through five
/// samples `f` spaced `h` apart (0 if it is farther than `h`): two Newton steps
/// on the quartic's slope from its parabola's peak (the quartic itself misses
/// the function's peak by more than what a third would change).
fn quartic_peak(f: [f64; 5], h: f64) -> f64 {
    let [f0, f1, f2, f3, f4] = f;
    // The quartic's derivatives at the middle sample times h, h², h³, h⁴ (the
    // five-point stencils); s = x/h.
    let d1 = (f0 - 8.0 * f1 + 8.0 * f3 - f4) / 12.0;
    let d2 = (-f0 + 16.0 * f1 - 30.0 * f2 + 16.0 * f3 - f4) / 12.0;
    let d3 = 0.5 * (-f0 + 2.0 * f1 - 2.0 * f3 + f4);
    let d4 = f0 - 4.0 * f1 + 6.0 * f2 - 4.0 * f3 + f4;
    let mut s = -d1 / d2;
    for _ in 0..2 {
        let p1 = d1 + s * (d2 + s * (0.5 * d3 + s * d4 / 6.0));
        let p2 = d2 + s * (d3 + 0.5 * s * d4);
        s -= p1 / p2;
    }
    if s.abs() <= 1.0 {
        s * h
    } else {
        0.0
    }
}

/// Lanes of the rod scan: samples computed side by side, each lane with its own
/// running extremes, merged at the end (one AVX-512 register of f64).
pub(super) const LANES: usize = 8;

/// The lowest and the highest sample of y and the largest |y''| (the first of
/// ties), found by [`scan_rod`].
pub(super) struct Extremes {
    pub(super) lo: usize,
    pub(super) hi: usize,
    pub(super) acc: usize,
}

/// y, y', y'' over the turn for one rod length (L² = `l2`) from the pin path's
/// rod-independent rows, the sample extremes found in the same pass; `m`
/// samples, in blocks of [`LANES`]. Then, in θ order, the candidates `cands`:
/// [0] every sampled local maximum of |y''| within 1 % of the largest; [1]
/// every sampled local minimum of y that may tie with the lowest (BDC) and [2]
/// every local maximum that may tie with the highest (TDC), see [`TIE`]. A
/// separate function so that the blocks are known not to alias and the loops
/// are vectorised.
#[inline(never)]
fn scan_rod(
    l2: f64,
    m: usize,
    pin: &[[[f64; LANES]; 6]],
    out: [&mut [[f64; LANES]]; 3],
    cands: &mut [Vec<usize>; 3],
) -> Extremes {
    #[cfg(target_arch = "x86_64")]
    if !exact() {
        if let Some(v4) = pulp::x86::V4::try_new() {
            use pulp::Simd;
            // 1/w = 1/√(L² − u²) from the processor's 14-bit estimate r₀ of
            // the reciprocal square root, corrected by the series of
            // (1 − e)^(−1/2) in e = 1 − x·r₀² (|e| ≤ 2⁻¹³) to its e³ term
            // (what is left, 35e⁴/128, is below 2⁻⁵³): within an ulp or two
            // of 1/√x, by FMA; and w = x·(1/w). A few multiply-adds in place
            // of a √ and a division (the divider's ~20 cycles a register on
            // this processor), and a shorter chain than two Newton steps.
            let (one, half) = (v4.splat_f64s(1.0), v4.splat_f64s(0.5));
            let (c2, c3) = (v4.splat_f64s(3.0 / 8.0), v4.splat_f64s(5.0 / 16.0));
            let root = move |x: pulp::f64x8| {
                let r0: pulp::f64x8 = pulp::cast(v4.avx512f._mm512_rsqrt14_pd(pulp::cast(x)));
                let e = v4.mul_add_f64s(v4.neg_f64s(x), v4.mul_f64s(r0, r0), one);
                let p = v4.mul_add_f64s(v4.mul_add_f64s(e, c3, c2), e, half);
                let r = v4.mul_add_f64s(v4.mul_f64s(r0, e), p, r0);
                (v4.mul_f64s(x, r), r)
            };
            return v4.vectorize(
                #[inline(always)]
                move || rod_loops(v4, root, l2, m, pin, out, cands),
            );
        }
    }
    pulp::Arch::new().dispatch(RodScan {
        l2,
        m,
        pin,
        out,
        cands,
    })
}

/// [`scan_rod`]'s loops, compiled once per instruction set (AVX-512 or AVX2 +
/// FMA where the processor has them, plain SSE2 otherwise) and picked at run
/// time.
pub(super) struct RodScan<'a, 'b> {
    pub(super) l2: f64,
    pub(super) m: usize,
    pub(super) pin: &'a [[[f64; LANES]; 6]],
    pub(super) out: [&'b mut [[f64; LANES]]; 3],
    pub(super) cands: &'b mut [Vec<usize>; 3],
}

impl pulp::WithSimd for RodScan<'_, '_> {
    type Output = Extremes;

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, simd: S) -> Extremes {
        let RodScan {
            l2,
            m,
            pin,
            out,
            cands,
        } = self;
        let one = simd.splat_f64s(1.0);
        let root = |x: S::f64s| {
            let w = simd.sqrt_f64s(x);
            (w, simd.div_f64s(one, w))
        };
        rod_loops(simd, root, l2, m, pin, out, cands)
    }
}

/// The loops of [`scan_rod`] on one instruction set, with `root` for
/// (√x, 1/√x) at x = L² − u² (the exact √ and division, or an estimate
/// corrected by a series).
#[inline(always)]
fn rod_loops<S: pulp::Simd>(
    simd: S,
    root: impl Fn(S::f64s) -> (S::f64s, S::f64s),
    l2: f64,
    m: usize,
    pin: &[[[f64; LANES]; 6]],
    out: [&mut [[f64; LANES]]; 3],
    cands: &mut [Vec<usize>; 3],
) -> Extremes {
    {
        let [y, dy, ddy] = out;
        // Per lane of a block, the running minimum of y (BDC) and maxima of y
        // (TDC) and |y''| (the acceleration peak); where each is first met is
        // found by the candidate pass below, which visits those samples anyway.
        let mut best = [
            [f64::INFINITY; LANES],
            [f64::NEG_INFINITY; LANES],
            [f64::NEG_INFINITY; LANES],
        ];
        let l2 = simd.splat_f64s(l2);
        let rows = y.iter_mut().zip(dy.iter_mut()).zip(ddy.iter_mut());
        for (p, ((yc, dyc), ddyc)) in pin.iter().zip(rows) {
            let [u2, upx1, hh, py, py1, py2] = p.each_ref().map(|c| S::as_simd_f64s(c).0);
            let (yv, dyv, ddyv) = (
                S::as_mut_simd_f64s(yc).0,
                S::as_mut_simd_f64s(dyc).0,
                S::as_mut_simd_f64s(ddyc).0,
            );
            let [b0, b1, b2] = best.each_mut().map(|b| S::as_mut_simd_f64s(b).0);
            for v in 0..b0.len() {
                let (w, iw) = root(simd.sub_f64s(l2, u2[v]));
                let g = simd.mul_f64s(upx1[v], iw);
                let yy = simd.sub_f64s(py[v], w);
                let hg = simd.add_f64s(hh[v], simd.mul_f64s(g, g));
                let dd = simd.add_f64s(py2[v], simd.mul_f64s(hg, iw));
                yv[v] = yy;
                dyv[v] = simd.add_f64s(py1[v], g);
                ddyv[v] = dd;
                // (A NaN key leaves the extreme as it is, as `<` would.)
                b0[v] = simd.min_f64s(yy, b0[v]);
                b1[v] = simd.max_f64s(yy, b1[v]);
                b2[v] = simd.max_f64s(simd.abs_f64s(dd), b2[v]);
            }
        }
        // Merge the lanes.
        let [b0, b1, b2] = best;
        let ylo = b0.iter().fold(f64::INFINITY, |a, &x| a.min(x));
        let [yhi, vacc] = [b1, b2].map(|b| b.iter().fold(f64::NEG_INFINITY, |a, &x| a.max(x)));
        // The first sample at each extreme (0 if none is: all NaN).
        let (mut lo, mut hi, mut acc) = (None, None, None);
        // Candidates: local maxima of |y''| within 1 % of the largest, and local
        // extremes of y within `band` of the lowest and the highest sample. A
        // true extreme is at most max|y''|·h²/8 beyond its nearest sample, so
        // one that ties with the lowest (highest) has a sample in the band (with
        // twice the sampled max|y''| for the sampling of |y''| itself).
        let h = TAU / m as f64;
        let band =
            0.25 * vacc * h * h + TIE * (yhi - ylo) + 8.0 * f64::EPSILON * (ylo.abs() + yhi.abs());
        let (thr, thr_lo, thr_hi) = (0.99 * vacc, ylo + band, yhi - band);
        let [peaks, lows, highs] = cands;
        for c in [&mut *peaks, &mut *lows, &mut *highs] {
            c.clear();
        }
        let (ys, ddys) = (&y.as_flattened()[..m], &ddy.as_flattened()[..m]);
        let prev = |q: usize| if q == 0 { m - 1 } else { q - 1 };
        let next = |q: usize| if q + 1 == m { 0 } else { q + 1 };
        // Per block, the lanes in each range as bit masks: on AVX-512 straight
        // from the three vector compares (a mask register is a byte), elsewhere
        // lane by lane. A block with no lane in any range (most) is passed over;
        // in the others only the set lanes of each mask are visited, in θ
        // order (most lanes of a hit block are in no range, or in one only).
        let [tv, tlo, thi] = [thr, thr_lo, thr_hi].map(|t| simd.splat_f64s(t));
        let byte_masks =
            core::mem::size_of::<S::m64s>() == 1 && core::mem::size_of::<S::f64s>() == 8 * LANES;
        for (c, (yb, ddyb)) in y.iter().zip(ddy.iter()).enumerate() {
            let base = c * LANES;
            let [mut m_acc, mut m_lo, mut m_hi] = if byte_masks {
                let (yv, ddyv) = (S::as_simd_f64s(yb).0[0], S::as_simd_f64s(ddyb).0[0]);
                [
                    simd.greater_than_or_equal_f64s(simd.abs_f64s(ddyv), tv),
                    simd.less_than_or_equal_f64s(yv, tlo),
                    simd.greater_than_or_equal_f64s(yv, thi),
                ]
                .map(|k| u32::from(pulp::bytemuck::cast::<S::m64s, u8>(k)))
            } else {
                let mut bits = [0u32; 3];
                for (l, (&yq, &dq)) in yb.iter().zip(ddyb).enumerate() {
                    bits[0] |= u32::from(dq.abs() >= thr) << l;
                    bits[1] |= u32::from(yq <= thr_lo) << l;
                    bits[2] |= u32::from(yq >= thr_hi) << l;
                }
                bits
            };
            if m_acc | m_lo | m_hi == 0 {
                continue;
            }
            // The last block's lanes past m are padding.
            if base + LANES > m {
                let valid = (1u32 << (m - base)) - 1;
                (m_acc, m_lo, m_hi) = (m_acc & valid, m_lo & valid, m_hi & valid);
            }
            while m_acc != 0 {
                let q = base + m_acc.trailing_zeros() as usize;
                m_acc &= m_acc - 1;
                let aq = ddys[q].abs();
                if acc.is_none() && aq == vacc {
                    acc = Some(q);
                }
                if aq >= ddys[prev(q)].abs() && aq >= ddys[next(q)].abs() {
                    peaks.push(q);
                }
            }
            while m_lo != 0 {
                let q = base + m_lo.trailing_zeros() as usize;
                m_lo &= m_lo - 1;
                let yq = ys[q];
                if lo.is_none() && yq == ylo {
                    lo = Some(q);
                }
                if yq <= ys[prev(q)] && yq <= ys[next(q)] {
                    lows.push(q);
                }
            }
            while m_hi != 0 {
                let q = base + m_hi.trailing_zeros() as usize;
                m_hi &= m_hi - 1;
                let yq = ys[q];
                if hi.is_none() && yq == yhi {
                    hi = Some(q);
                }
                if yq >= ys[prev(q)] && yq >= ys[next(q)] {
                    highs.push(q);
                }
            }
        }
        Extremes {
            lo: lo.unwrap_or(0),
            hi: hi.unwrap_or(0),
            acc: acc.unwrap_or(0),
        }
    }
}

/// A rise of the slider above S_p after the tool first met the blank counts as
/// a re-contact (status [`Status::ReContacts`]) when it exceeds this fraction
/// of the nominal stroke; a smaller one is a touch within rounding, and a
/// slider that moves back up without leaving the blank is
/// [`Status::Reverses`].
pub const RECONTACT: f64 = 1e-9;

/// A dead centre: (θ, y, y'' there, the sample it was found from).
pub(super) type DeadCentre = (f64, f64, f64, usize);

/// BDC and TDC of the design `f` from its rows for one rod length
/// (`scan.rod` done; `j_lo`, `j_hi` its lowest and highest sample), with the
/// tie rule of [`TIE`]. The one computation of a design's BDC: the criteria
/// count α from it and so does [`super::kinematics::solve_into`] (through
/// [`bdc_of`]), bit for bit for the same sample count.
pub(super) fn dead_centres(
    f: &Frame,
    table: &Table,
    scan: &PinScan,
    j_lo: usize,
    j_hi: usize,
) -> (DeadCentre, DeadCentre) {
    let m = table.len();
    let at = |x: f64, order: u32| f.at_pow(x, order);
    let (ys, dys, ddys) = scan.rows(m);
    let h = TAU / m as f64;
    let prev = |j: usize| if j == 0 { m - 1 } else { j - 1 };
    let next = |j: usize| if j + 1 == m { 0 } else { j + 1 };
    // Dead centres: roots of y' between the neighbours of the sample extremes,
    // started from the root of the cubic that matches the samples' y', y'' on
    // the sample interval holding it (off by ~h⁴·y⁽⁵⁾/(384·y'')), then
    // Chebyshev steps on y'. Each returns (θ, y, y'') there, y and y'' carried
    // from the last evaluation by Taylor.
    let dead = |j: usize| -> (f64, f64, f64) {
        let th = table.theta(j);
        let (jl, jr) = (prev(j), next(j));
        let (glo, ghi) = (dys[jl], dys[jr]);
        if glo * ghi < 0.0 {
            let x0 = if (dys[j] < 0.0) == (glo < 0.0) {
                hermite_root(th, th + h, [dys[j], ghi], [ddys[j], ddys[jr]])
            } else {
                hermite_root(th - h, th, [glo, dys[j]], [ddys[jl], ddys[j]])
            };
            let mut last = None;
            let g = |x: f64| {
                let k = at(x, 3);
                last = Some((x, k));
                (k.dy, k.ddy, k.dddy)
            };
            let t = chebyshev(g, th - h, th + h, glo, ghi, x0, STEP_LAST);
            match last {
                Some((x, k)) => {
                    let e = t - x;
                    let y = k.y + e * (k.dy + e * (0.5 * k.ddy + e * k.dddy / 6.0));
                    (t, y, k.ddy + e * k.dddy)
                }
                None => (t, ys[j], ddys[j]),
            }
        } else {
            (th, ys[j], ddys[j])
        }
    };
    // Each candidate refined (its sample kept if that is beyond the root).
    let [_, lows, highs] = &scan.cands;
    let low = |q: usize| {
        let (t, y, ddy) = dead(q);
        (t, y.min(ys[q]), ddy, q)
    };
    let high = |q: usize| {
        let (t, y, ddy) = dead(q);
        (t, y.max(ys[q]), ddy, q)
    };
    // Usually one candidate each (the sample extreme); more only near a tie
    // (see [`TIE`]).
    let (b, t) = if lows.len() <= 1 && highs.len() <= 1 {
        (low(j_lo), high(j_hi))
    } else {
        let lows: Vec<_> = lows.iter().map(|&q| low(q)).collect();
        let highs: Vec<_> = highs.iter().map(|&q| high(q)).collect();
        let y_min = lows.iter().fold(f64::INFINITY, |a, c| a.min(c.1));
        let y_max = highs.iter().fold(f64::NEG_INFINITY, |a, c| a.max(c.1));
        let tol = TIE * (y_max - y_min);
        let b = lows
            .iter()
            .filter(|c| c.1 <= y_min + tol)
            .min_by(|p, q| wrap(p.0).total_cmp(&wrap(q.0)))
            .copied()
            .unwrap_or_else(|| low(j_lo));
        let t = highs
            .iter()
            .filter(|c| c.1 >= y_max - tol)
            .min_by(|p, q| wrap(b.0 - p.0).total_cmp(&wrap(b.0 - q.0)))
            .copied()
            .unwrap_or_else(|| high(j_hi));
        (b, t)
    };
    (b, t)
}

/// The BDC (θ_B, y_B) of a design whose rod reaches the guide over the whole
/// turn, as its criteria on `samples` angles a turn find it ([`dead_centres`]);
/// None if the rod does not reach everywhere. `ratio` is the design's gear
/// ratio ([`Design::validate`]).
pub(super) fn bdc_of(design: &Design, ratio: f64, samples: usize) -> Option<(f64, f64)> {
    let f = design.frame();
    let table = Table::new(ratio, samples);
    let mut scan = PinScan::default();
    scan.fill(&f, &table);
    if scan.u_max >= f.l {
        return None;
    }
    let Extremes { lo, hi, .. } = scan.rod(f.l * f.l, samples);
    let ((th_b, y_b, ..), _) = dead_centres(&f, &table, &scan, lo, hi);
    Some((wrap(th_b), y_b))
}

/// Criteria of the design `f` (its rod length included) on its sampled pin path
/// `scan`, into `row` (see [`CRITERIA`]); returns its status.
pub(super) fn criteria_with(
    f: &Frame,
    table: &Table,
    spec: &Spec,
    scan: &mut PinScan,
    row: &mut [f64],
) -> Status {
    row.fill(f64::NAN);
    let m = table.len();
    if scan.u_max >= f.l {
        return Status::NoReach;
    }
    let l2 = f.l * f.l;
    let at = |x: f64, order: u32| f.at_pow(x, order);
    // One branch-free pass over the turn (vectorised): height, slope, curvature.
    let Extremes {
        lo: j_lo,
        hi: j_hi,
        acc: j_acc,
    } = scan.rod(l2, m);
    let (ys, dys, ddys) = scan.rows(m);
    let h = TAU / m as f64;
    // Neighbours on the turn (a compare, not a division: `prev` is on the
    // walk's chain of dependent steps).
    let prev = |j: usize| if j == 0 { m - 1 } else { j - 1 };
    let next = |j: usize| if j + 1 == m { 0 } else { j + 1 };
    let (b, t) = dead_centres(f, table, scan, j_lo, j_hi);
    let ((th_b, y_b, ddy_b, j_b), (th_t, y_t, ddy_t, _)) = (b, t);
    let s_n = y_t - y_b;
    let s_p = match spec.stroke {
        Stroke::Fraction(k) => k * s_n,
        Stroke::Length(s) => s,
    };
    row[0] = s_n;
    row[13] = wrap(th_b);
    if s_p > s_n {
        row[1] = s_p;
        return Status::LongStroke;
    }
    // The working stroke starts where the tool first meets the blank: coming
    // down from TDC, the first θ where S = S_p. Walking back in time from BDC (θ
    // decreasing, α increasing) to TDC, that is the last crossing met; crossings
    // nearer BDC mean the slider dipped below S_p and backed off above it before
    // coming down again (re-contact). Pass 1 finds the crossing, pass 2 walks to
    // it for the speeds. TDC joins the walk as a point of its own (it is rarely a
    // sample), so that k_Sp = 1 ends there.
    let walk = Walk::new(table, j_b, th_b, th_t);
    let pts = WalkPoints {
        ys,
        dys,
        ddys,
        y_b,
        s_n,
        ddy_t,
    };
    // A true extreme of S lies at most max|y''|·h²/8 beyond its nearest
    // sample: only samples within `band` of S_p can hide a crossing.
    let band = 0.25 * ddys[j_acc].abs() * h * h;
    let rc_tol = RECONTACT * s_n;
    // S at the extreme of y between two walk points where y' changes sign.
    let extreme = |lo: f64, hi: f64, dlo: f64, dhi: f64| -> (f64, f64) {
        let g = |x: f64| {
            let k = at(x, 3);
            (k.dy, k.ddy, k.dddy)
        };
        let x0 = lo + (hi - lo) * dlo / (dlo - dhi);
        let t = chebyshev(g, lo, hi, dlo, dhi, x0, STEP_LAST);
        (t, at(t, 2).y - y_b)
    };
    // Pass 1: the step of the walk at the start of the last crossing, the
    // bracket's other end if it is a dip between two samples above S_p
    // ((θ, S) of the dip's bottom), and the highest S over the points (and
    // refined peaks) between that crossing and BDC.
    let mut contact: Option<Contact> = None;
    {
        let mut w = walk.clone();
        let mut nx = WalkPoint {
            th: th_b,
            s: 0.0,
            dy: 0.0,
            g: -ddy_b,
        };
        let mut s_max = 0.0f64;
        // A step whose point and the one before it are both at least `far`
        // (S_p + band) has nothing to find: no crossing, no dip that can reach
        // S_p, no peak below it. Such stretches (after the working stroke's
        // start, most of the walk to TDC) are passed over sample by sample
        // keeping only the highest S ([`Walk::skip_above`]).
        let far = if skips_walk() {
            s_p + band
        } else {
            f64::INFINITY
        };
        let mut step = 0;
        // Whether the rest of the walk has been checked with [`Walk::rest_above`]
        // (once: it fails only where the slider dips again before TDC).
        let mut rest_checked = !shortcuts();
        let below = skips_walk() && shortcuts();
        while step <= m + 1 {
            if below && nx.s < s_p {
                // Points below S_p where the slider descends (y' ≤ 0) are
                // neither a crossing nor a peak: passed over, keeping only
                // the highest S.
                let (k, high, last) = w.skip_below(&pts, s_p, m + 2 - step);
                if let Some(last) = last {
                    s_max = s_max.max(high);
                    nx = last;
                    step += k;
                    continue;
                }
            }
            if nx.s >= far {
                if !rest_checked {
                    rest_checked = true;
                    if w.rest_above(&pts, far) {
                        // Nothing left to find: the walk would pass over every
                        // sample up to TDC and end there (TDC itself is no
                        // crossing, as the point before it is above S_p).
                        break;
                    }
                }
                let (k, high, last) = w.skip_above(&pts, far, m + 2 - step);
                if let Some(last) = last {
                    s_max = s_max.max(high);
                    nx = last;
                    step += k;
                    continue;
                }
            }
            let Some(cur) = w.next(&pts) else {
                break;
            };
            if cur.s >= s_p {
                if nx.s < s_p {
                    contact = Some(Contact {
                        step,
                        dip: None,
                        s_max,
                    });
                } else if cur.dy < 0.0 && nx.dy > 0.0 && cur.s.min(nx.s) < s_p + band {
                    // A dip between two samples above S_p: below S_p at its bottom?
                    let (t, s) = extreme(cur.th, nx.th, cur.dy, nx.dy);
                    if s < s_p {
                        contact = Some(Contact {
                            step,
                            dip: Some((t, s)),
                            s_max,
                        });
                    }
                }
            } else if nx.s < s_p
                && cur.dy > 0.0
                && nx.dy < 0.0
                && cur.s.max(nx.s) > s_p - band
                && s_max <= s_p + rc_tol
            {
                // A peak between two samples below S_p: above S_p at its top?
                s_max = s_max.max(extreme(cur.th, nx.th, cur.dy, nx.dy).1);
            }
            s_max = s_max.max(cur.s);
            nx = cur;
            if w.done() {
                break;
            }
            step += 1;
        }
    }
    let Some(Contact {
        step: stop,
        dip,
        s_max,
    }) = contact
    else {
        // Unreachable when S_p ≤ S_n (the walk meets TDC), kept as a guard.
        return Status::LongStroke;
    };
    // Pass 2: walk to that crossing, watching Π' = −y' and bracketing each of
    // its local maxima: dΠ'/dθ = −y'' turns from + to − between two points.
    let mut w = walk;
    // The point after the current one in θ: (θ, S, y', −y'').
    let (mut nx_th, mut nx_s, mut nx_dy, mut nx_g) = (th_b, 0.0, 0.0, -ddy_b);
    // Brackets (θ_lo, θ_hi, y''(θ_lo), y''(θ_hi)) of the speed peaks.
    let mut peaks: [(f64, f64, f64, f64); 8] = [(0.0, 0.0, 0.0, 0.0); 8];
    let mut n_peaks = 0;
    // Brackets of the local maxima of y' (the slowest descent, or a rise: −y''
    // turns from − to +), refined only if no sample has the slider rising: a
    // reversal near a cusp of the planet point (d ≈ r) can lie between samples.
    let mut lulls: [(f64, f64, f64, f64); 8] = [(0.0, 0.0, 0.0, 0.0); 8];
    let mut n_lulls = 0;
    // The extremes of y' over the points passed (Π' = −y').
    let (mut dy_min, mut dy_max) = (f64::INFINITY, f64::NEG_INFINITY);
    let mut th_p = f64::NAN;
    let mut kp: Option<(f64, Kin)> = None;
    for step in 0..=stop {
        let Some(WalkPoint { th, s, dy, g }) = w.next(&pts) else {
            break;
        };
        if step == stop {
            // S = S_p between this point and the next (or the dip's bottom):
            // from the root of the cubic through their S and S' = y',
            // Chebyshev steps on S − S_p.
            let (hi, s_hi, dy_hi) = match dip {
                Some((t, s)) => (t, s, 0.0),
                None => (nx_th, nx_s, nx_dy),
            };
            let g = |x: f64| {
                let k = at(x, 3);
                kp = Some((x, k));
                (k.y - y_b - s_p, k.dy, k.ddy)
            };
            let guess = hermite_root(th, hi, [s - s_p, s_hi - s_p], [dy, dy_hi]);
            th_p = chebyshev(g, th, hi, s - s_p, s_hi - s_p, guess, STEP_LAST);
            break;
        }
        dy_min = if dy < dy_min { dy } else { dy_min };
        dy_max = if dy > dy_max { dy } else { dy_max };
        if g > 0.0 && nx_g < 0.0 && n_peaks < peaks.len() {
            peaks[n_peaks] = (th, nx_th, -g, -nx_g);
            n_peaks += 1;
        }
        if g < 0.0 && nx_g > 0.0 && n_lulls < lulls.len() {
            lulls[n_lulls] = (th, nx_th, -g, -nx_g);
            n_lulls += 1;
        }
        (nx_th, nx_s, nx_dy, nx_g) = (th, s, dy, g);
    }
    if th_p.is_nan() {
        // Unreachable: pass 2 walks the points of pass 1.
        return Status::LongStroke;
    }
    let best_v = -dy_min;
    let alpha_p = th_b - th_p;
    // y', y'' at the start of the working stroke, by Taylor from the last
    // evaluation of its search.
    let (dy_p, ddy_p) = match kp {
        Some((x, k)) => {
            let e = th_p - x;
            (k.dy + e * (k.ddy + 0.5 * e * k.dddy), k.ddy + e * k.dddy)
        }
        None => {
            let k = at(th_p, 2);
            (k.dy, k.ddy)
        }
    };
    let v_np = -dy_p;
    // The last stretch, from the start of the working stroke to the first point.
    if -ddy_p > 0.0 && nx_g < 0.0 && n_peaks < peaks.len() {
        peaks[n_peaks] = (th_p, nx_th, ddy_p, -nx_g);
        n_peaks += 1;
    }
    if -ddy_p < 0.0 && nx_g > 0.0 && n_lulls < lulls.len() {
        lulls[n_lulls] = (th_p, nx_th, ddy_p, -nx_g);
        n_lulls += 1;
    }
    // The slider rises during the working stroke when y' > 1e-12 of the stroke
    // per radian at a sample or at a local maximum of y' between two samples.
    let rising = 1e-12 * s_n;
    let n_lulls = if dy_max > rising { 0 } else { n_lulls };
    // Speed peaks (and the lulls) inside the working stroke: roots of y'' by
    // Chebyshev steps from the secant of the bracket's ends; Π' there by Taylor
    // from the last evaluation.
    let mut v_max = v_np.max(best_v);
    for (k, &(lo, hi, glo, ghi)) in peaks[..n_peaks].iter().chain(&lulls[..n_lulls]).enumerate() {
        if glo * ghi < 0.0 {
            let mut last = None;
            let g = |x: f64| {
                let k = at(x, 4);
                last = Some((x, k));
                (k.ddy, k.dddy, k.ddddy)
            };
            let t = chebyshev(
                g,
                lo,
                hi,
                glo,
                ghi,
                lo + (hi - lo) * glo / (glo - ghi),
                STEP_LAST,
            );
            let dy = match last {
                Some((x, k)) => {
                    let e = t - x;
                    k.dy + e * (k.ddy + e * (0.5 * k.dddy + e * k.ddddy / 6.0))
                }
                None => at(t, 2).dy,
            };
            if k < n_peaks {
                v_max = v_max.max(-dy);
            } else {
                dy_max = dy_max.max(dy);
            }
        }
    }
    let status = if s_max > s_p + rc_tol {
        Status::ReContacts
    } else if dy_max > rising {
        Status::Reverses
    } else {
        Status::Ok
    };
    // Acceleration peak over the turn: every sampled local maximum of |y''| within
    // 1 % of the largest, refined at a root of y'''. One evaluation each, at the
    // peak of the quartic through the five samples around it (off by ~h⁴·y⁽⁷⁾/
    // (30·y'''')); the peak of the Taylor parabola there is the value, unless
    // that is more than a last step away, when a bracketed search follows.
    let acc = ddys[j_acc].abs();
    let mut a_max = acc;
    for &q in &scan.cands[0] {
        let th_a = table.theta(q);
        let sgn = ddys[q].signum();
        let (q1, q2) = (prev(q), next(q));
        let five = [prev(q1), q1, q, q2, next(q2)].map(|i| sgn * ddys[i]);
        let t0 = th_a + quartic_peak(five, h);
        let k = at(t0, 4);
        let (v1, v2) = (sgn * k.dddy, sgn * k.ddddy);
        let e = -v1 / v2;
        if v2 < 0.0 && (t0 + e - th_a).abs() < h && e.abs() <= STEP_LAST * (1.0 + t0.abs()) {
            a_max = a_max.max((k.ddy + 0.5 * e * k.dddy).abs());
            continue;
        }
        let (lo, hi) = (th_a - h, th_a + h);
        let (glo, ghi) = (sgn * at(lo, 3).dddy, sgn * at(hi, 3).dddy);
        if glo > 0.0 && ghi < 0.0 {
            let mut last = None;
            let g = |x: f64| {
                let k = at(x, 4);
                last = Some((x, k));
                (sgn * k.dddy, sgn * k.ddddy, 0.0)
            };
            let t = chebyshev(g, lo, hi, glo, ghi, th_a, STEP_LAST);
            let ddy = match last {
                Some((x, k)) => k.ddy + (t - x) * k.dddy,
                None => at(t, 2).ddy,
            };
            a_max = a_max.max(ddy.abs());
        }
    }
    let w = spec.omega;
    let v_cp = s_p / alpha_p;
    row[1] = s_p;
    row[2] = alpha_p;
    row[3] = v_np * w;
    row[4] = v_cp * w;
    row[5] = v_max * w;
    row[6] = a_max * w * w;
    row[7] = v_max;
    row[8] = s_p / s_n;
    row[9] = v_np / v_cp;
    row[10] = v_max / v_cp;
    row[11] = v_max / (0.5 * s_n);
    row[12] = a_max / (0.5 * s_n);
    status
}

/// Criteria of one design.
pub fn criteria(design: &Design, spec: &Spec) -> Result<(Vec<f64>, Status), PressError> {
    let ratio = design.validate()?;
    spec.validate()?;
    let table = Table::new(ratio, spec.samples);
    let mut row = vec![0.0; CRITERIA.len()];
    let f = design.frame();
    let mut scan = PinScan::default();
    scan.fill(&f, &table);
    let status = criteria_with(&f, &table, spec, &mut scan, &mut row);
    Ok((row, status))
}
