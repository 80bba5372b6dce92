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

use std::f64::consts::{FRAC_PI_2, TAU};

use rayon::prelude::*;

use crate::geom::sin_cos;
use crate::parallel::{pool, resolve_threads, ThreadsError};

/// Errors of the press domain.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PressError {
    #[error("{field} = {value} {why}")]
    BadDesign {
        field: &'static str,
        value: f64,
        why: String,
    },
    #[error("{field}[{index}] = {value} is not finite")]
    NotFinite {
        field: &'static str,
        index: usize,
        value: f64,
    },
    #[error("{0}")]
    BadSpec(String),
    #[error("{0}")]
    Threads(#[from] ThreadsError),
}

/// One gear-lever press: lengths [m], angle [rad].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Design {
    /// Pitch radius of the fixed internal guide gear R [m].
    pub big_r: f64,
    /// Pitch radius of the planet (generating) gear r [m].
    pub r: f64,
    /// Eccentricity of the rod's pin on the planet d [m] (0: a crank-slider).
    pub d: f64,
    /// Rod length L [m].
    pub l: f64,
    /// Setting angle of the guide gear φ0 [rad].
    pub phi0: f64,
    /// Offset of the slider's guide from the centre [m].
    pub offset: f64,
}

/// Largest gear ratio accepted (a typo such as R/r = 3000 is not a press).
pub const MAX_RATIO: f64 = 64.0;

impl Design {
    /// Check the design; returns the gear ratio i = R/r (a whole number ≥ 2: the
    /// drive repeats every crank turn only then).
    pub fn validate(&self) -> Result<f64, PressError> {
        let bad = |field, value, why: &str| {
            Err(PressError::BadDesign {
                field,
                value,
                why: why.to_string(),
            })
        };
        for (field, v) in [
            ("R", self.big_r),
            ("r", self.r),
            ("d", self.d),
            ("L", self.l),
            ("phi0", self.phi0),
            ("offset", self.offset),
        ] {
            if !v.is_finite() {
                return bad(field, v, "must be finite");
            }
        }
        if self.r <= 0.0 {
            return bad("r", self.r, "must be a positive radius [m]");
        }
        if self.big_r <= self.r {
            return bad(
                "R",
                self.big_r,
                &format!(
                    "must exceed r = {} (the planet rolls inside the guide gear)",
                    self.r
                ),
            );
        }
        let i = self.big_r / self.r;
        if (i - i.round()).abs() > 1e-9 * i || i.round() > MAX_RATIO {
            return Err(PressError::BadDesign {
                field: "R/r",
                value: i,
                why: format!(
                    "must be a whole number between 2 and {MAX_RATIO} (R = {}, r = {}): only then \
                     does the drive repeat every crank turn; the seed uses 3",
                    self.big_r, self.r
                ),
            });
        }
        if self.d < 0.0 {
            return bad(
                "d",
                self.d,
                "must be ≥ 0 [m] (0 gives a plain crank-slider)",
            );
        }
        if self.l <= 0.0 {
            return bad("L", self.l, "must be a positive rod length [m]");
        }
        Ok(i.round())
    }

    fn frame(&self) -> Frame {
        let i = (self.big_r / self.r).round();
        Frame {
            a: self.big_r - self.r,
            k: i - 1.0,
            beta0: i * (self.phi0 - FRAC_PI_2),
            d: self.d,
            l: self.l,
            e: self.offset,
        }
    }
}

/// A design in the form the kernels use.
#[derive(Debug, Clone, Copy)]
struct Frame {
    a: f64,
    k: f64,
    beta0: f64,
    d: f64,
    l: f64,
    e: f64,
}

/// Slider height and its θ-derivatives at one carrier angle.
#[derive(Debug, Clone, Copy)]
struct Kin {
    centre: [f64; 2],
    pin: [f64; 2],
    /// L² − (P_x − offset)²: > 0 where the rod reaches the guide.
    w2: f64,
    y: f64,
    dy: f64,
    ddy: f64,
    /// y''' where `order` ≥ 3, else 0.
    dddy: f64,
    /// y'''' where `order` ≥ 4, else 0.
    ddddy: f64,
}

impl Frame {
    /// Kinematics from cos/sin of θ and of β = −kθ + β0, with the derivatives
    /// of y up to `order` (2, 3 or 4).
    #[inline(always)]
    fn kin(&self, (ct, st): (f64, f64), (cb, sb): (f64, f64), order: u32) -> Kin {
        let (a, k, d) = (self.a, self.k, self.d);
        let (kd, k2d) = (k * d, k * k * d);
        let (cx, cy) = (a * ct, a * st);
        let (px, py) = (cx + d * cb, cy + d * sb);
        let (px1, py1) = (-a * st + kd * sb, a * ct - kd * cb);
        let (px2, py2) = (-a * ct - k2d * cb, -a * st - k2d * sb);
        let u = px - self.e;
        let w2 = self.l * self.l - u * u;
        let w = w2.sqrt();
        let iw = 1.0 / w;
        let g = u * px1 * iw;
        let h = px1 * px1 + u * px2;
        let (mut dddy, mut ddddy) = (0.0, 0.0);
        if order >= 3 {
            let k3d = k * k2d;
            let (px3, py3) = (a * st - k3d * sb, -a * ct + k3d * cb);
            let h1 = 3.0 * px1 * px2 + u * px3;
            dddy = py3 + h1 * iw + 3.0 * (g * h + g * g * g) * iw * iw;
            if order >= 4 {
                // From w·w''' + 3w'·w'' = −(u'² + u·u'')' by one more
                // derivative: w'''' = −((u'² + u·u'')'' + 4w'·w''' + 3w''²)/w,
                // with w' = −g, w'' = −(h + g²)/w, w''' = py3 − y'''.
                let k4d = k * k3d;
                let (px4, py4) = (a * ct + k4d * cb, a * st + k4d * sb);
                let h2 = 3.0 * px2 * px2 + 4.0 * px1 * px3 + u * px4;
                let (w1, w2d, w3) = (-g, -(h + g * g) * iw, py3 - dddy);
                ddddy = py4 + (h2 + 4.0 * w1 * w3 + 3.0 * w2d * w2d) * iw;
            }
        }
        Kin {
            centre: [cx, cy],
            pin: [px, py],
            w2,
            y: py - w,
            dy: py1 + g,
            ddy: py2 + (h + g * g) * iw,
            dddy,
            ddddy,
        }
    }

    #[inline]
    fn at(&self, theta: f64, order: u32) -> Kin {
        self.kin(cos_sin(theta), cos_sin(self.beta0 - self.k * theta), order)
    }
}

/// (cos x, sin x).
#[inline(always)]
fn cos_sin(x: f64) -> (f64, f64) {
    let (s, c) = sin_cos(x);
    (c, s)
}

/// Root of f on [lo, hi] where f(lo), f(hi) differ in sign (Illinois variant of
/// regula falsi: superlinear, and never leaves the bracket), to within `xtol`
/// in x: successive estimates closer than that end the search.
fn root(
    mut f: impl FnMut(f64) -> f64,
    mut lo: f64,
    mut hi: f64,
    mut flo: f64,
    mut fhi: f64,
    xtol: f64,
) -> f64 {
    if flo == 0.0 {
        return lo;
    }
    if fhi == 0.0 {
        return hi;
    }
    let mut side = 0i8;
    let mut last = f64::NAN;
    for _ in 0..100 {
        let x = (lo * fhi - hi * flo) / (fhi - flo);
        if !(x > lo.min(hi) && x < lo.max(hi)) || (x - last).abs() <= xtol {
            return if x.is_finite() { x } else { 0.5 * (lo + hi) };
        }
        last = x;
        let fx = f(x);
        if fx == 0.0 {
            return x;
        }
        if (fx > 0.0) == (fhi > 0.0) {
            hi = x;
            fhi = fx;
            if side == 1 {
                flo *= 0.5;
            }
            side = 1;
        } else {
            lo = x;
            flo = fx;
            if side == -1 {
                fhi *= 0.5;
            }
            side = -1;
        }
    }
    0.5 * (lo + hi)
}

/// Samples of the carrier angle for the grid scans: θ_j = 2πj/M, with cos/sin of
/// θ_j and of −kθ_j, shared by every design of one gear ratio.
pub struct Table {
    ct: Vec<f64>,
    st: Vec<f64>,
    cb: Vec<f64>,
    sb: Vec<f64>,
}

impl Table {
    pub fn new(ratio: f64, m: usize) -> Table {
        let k = ratio - 1.0;
        let mut t = Table {
            ct: Vec::with_capacity(m),
            st: Vec::with_capacity(m),
            cb: Vec::with_capacity(m),
            sb: Vec::with_capacity(m),
        };
        for j in 0..m {
            let th = TAU * j as f64 / m as f64;
            let (s, c) = sin_cos(th);
            let (sb, cb) = sin_cos(-k * th);
            t.ct.push(c);
            t.st.push(s);
            t.cb.push(cb);
            t.sb.push(sb);
        }
        t
    }

    fn len(&self) -> usize {
        self.ct.len()
    }

    fn theta(&self, j: usize) -> f64 {
        TAU * j as f64 / self.len() as f64
    }
}

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

/// Columns of the criteria rows.
pub const CRITERIA: [&str; 14] = [
    "S_n",
    "S_p",
    "alpha_p",
    "V_np",
    "V_cp",
    "V_pmax",
    "J_max",
    "torque",
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
fn wrap(x: f64) -> f64 {
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
pub struct PinScan {
    /// Rows of the pin path in blocks of [`LANES`] samples, so that the rod scan
    /// reads whole registers: u², u·P_x', P_x'² + u·P_x'', P_y, P_y', P_y''
    /// (u = P_x − offset). The last block is padded with copies of sample 0.
    pin: Vec<[[f64; LANES]; 6]>,
    /// max |P_x − offset| over the turn, exact (sample maximum refined at a root
    /// of P_x'): the rod reaches the guide everywhere iff L exceeds it.
    u_max: f64,
    // Rows of one rod length (y, y', y''), in blocks like `pin`.
    y: Vec<[f64; LANES]>,
    dy: Vec<[f64; LANES]>,
    ddy: Vec<[f64; LANES]>,
    /// Candidates of the |y''| peak, of BDC and of TDC for one rod length (see
    /// [`scan_rod`]).
    cands: [Vec<usize>; 3],
}

impl PinScan {
    /// Sample the pin path of `f` (its rod length is not used).
    fn fill(&mut self, f: &Frame, table: &Table) {
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
const LANES: usize = 8;

/// The lowest and the highest sample of y and the largest |y''| (the first of
/// ties), found by [`scan_rod`].
struct Extremes {
    lo: usize,
    hi: usize,
    acc: usize,
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
struct RodScan<'a, 'b> {
    l2: f64,
    m: usize,
    pin: &'a [[[f64; LANES]; 6]],
    out: [&'b mut [[f64; LANES]]; 3],
    cands: &'b mut [Vec<usize>; 3],
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
        let [y, dy, ddy] = out;
        // Per lane of a block, the running minima of the keys y (BDC), −y (TDC)
        // and −|y''| (the acceleration peak), and the index (an f64, a lane of
        // the same register type) where the lane first met each.
        let mut best = [[f64::INFINITY; LANES]; 3];
        let mut best_at = [[0.0f64; LANES]; 3];
        let mut at: [f64; LANES] = std::array::from_fn(|l| l as f64);
        let (l2, one) = (simd.splat_f64s(l2), simd.splat_f64s(1.0));
        let step = simd.splat_f64s(LANES as f64);
        let rows = y.iter_mut().zip(dy.iter_mut()).zip(ddy.iter_mut());
        for (p, ((yc, dyc), ddyc)) in pin.iter().zip(rows) {
            let [u2, upx1, hh, py, py1, py2] = p.each_ref().map(|c| S::as_simd_f64s(c).0);
            let (yv, dyv, ddyv) = (
                S::as_mut_simd_f64s(yc).0,
                S::as_mut_simd_f64s(dyc).0,
                S::as_mut_simd_f64s(ddyc).0,
            );
            let [b0, b1, b2] = best.each_mut().map(|b| S::as_mut_simd_f64s(b).0);
            let [a0, a1, a2] = best_at.each_mut().map(|b| S::as_mut_simd_f64s(b).0);
            let atv = S::as_mut_simd_f64s(&mut at).0;
            for v in 0..atv.len() {
                let w = simd.sqrt_f64s(simd.sub_f64s(l2, u2[v]));
                let iw = simd.div_f64s(one, w);
                let g = simd.mul_f64s(upx1[v], iw);
                let yy = simd.sub_f64s(py[v], w);
                let hg = simd.add_f64s(hh[v], simd.mul_f64s(g, g));
                let dd = simd.add_f64s(py2[v], simd.mul_f64s(hg, iw));
                yv[v] = yy;
                dyv[v] = simd.add_f64s(py1[v], g);
                ddyv[v] = dd;
                let keys = [yy, simd.neg_f64s(yy), simd.neg_f64s(simd.abs_f64s(dd))];
                let trackers = [
                    (&mut *b0, &mut *a0),
                    (&mut *b1, &mut *a1),
                    (&mut *b2, &mut *a2),
                ];
                for (k, (bk, ak)) in keys.into_iter().zip(trackers) {
                    let lt = simd.less_than_f64s(k, bk[v]);
                    bk[v] = simd.select_f64s(lt, k, bk[v]);
                    ak[v] = simd.select_f64s(lt, atv[v], ak[v]);
                }
                atv[v] = simd.add_f64s(atv[v], step);
            }
        }
        // Merge the lanes: the smallest key, the first index of ties.
        let [(vlo, lo), (vhi, hi), (vacc, acc)] = std::array::from_fn(|k| {
            let (mut v, mut i) = (f64::INFINITY, 0.0);
            for l in 0..LANES {
                let (b, a) = (best[k][l], best_at[k][l]);
                if b < v || (b == v && a < i) {
                    (v, i) = (b, a);
                }
            }
            (v, i as usize)
        });
        // Candidates: local maxima of |y''| within 1 % of the largest, and local
        // extremes of y within `band` of the lowest and the highest sample. A
        // true extreme is at most max|y''|·h²/8 beyond its nearest sample, so
        // one that ties with the lowest (highest) has a sample in the band (with
        // twice the sampled max|y''| for the sampling of |y''| itself).
        let (ylo, yhi) = (vlo, -vhi);
        let h = TAU / m as f64;
        let band =
            0.25 * -vacc * h * h + TIE * (yhi - ylo) + 8.0 * f64::EPSILON * (ylo.abs() + yhi.abs());
        let (thr, thr_lo, thr_hi) = (0.99 * -vacc, ylo + band, yhi - band);
        let [peaks, lows, highs] = cands;
        for c in [&mut *peaks, &mut *lows, &mut *highs] {
            c.clear();
        }
        let (ys, ddys) = (&y.as_flattened()[..m], &ddy.as_flattened()[..m]);
        let prev = |q: usize| if q == 0 { m - 1 } else { q - 1 };
        let next = |q: usize| if q + 1 == m { 0 } else { q + 1 };
        // A block with no sample in any of the three ranges is passed over in
        // one test.
        let [tv, tlo, thi] = [thr, thr_lo, thr_hi].map(|t| simd.splat_f64s(t));
        let high = |yv: S::f64s, ddyv: S::f64s| {
            let acc = simd.greater_than_or_equal_f64s(simd.abs_f64s(ddyv), tv);
            let low = simd.less_than_or_equal_f64s(yv, tlo);
            let top = simd.greater_than_or_equal_f64s(yv, thi);
            simd.or_m64s(acc, simd.or_m64s(low, top))
        };
        for (c, (yb, ddyb)) in y.iter().zip(ddy.iter()).enumerate() {
            let (yv, ddyv) = (S::as_simd_f64s(yb).0, S::as_simd_f64s(ddyb).0);
            let hit = (1..yv.len()).fold(high(yv[0], ddyv[0]), |a, v| {
                simd.or_m64s(a, high(yv[v], ddyv[v]))
            });
            if simd.first_true_m64s(hit) == S::F64_LANES {
                continue;
            }
            for q in c * LANES..(c * LANES + LANES).min(m) {
                let (yq, aq) = (ys[q], ddys[q].abs());
                let (is_acc, is_lo, is_hi) = (aq >= thr, yq <= thr_lo, yq >= thr_hi);
                if !(is_acc || is_lo || is_hi) {
                    continue;
                }
                let (qp, qn) = (prev(q), next(q));
                if is_acc && aq >= ddys[qp].abs() && aq >= ddys[qn].abs() {
                    peaks.push(q);
                }
                if is_lo && yq <= ys[qp] && yq <= ys[qn] {
                    lows.push(q);
                }
                if is_hi && yq >= ys[qp] && yq >= ys[qn] {
                    highs.push(q);
                }
            }
        }
        Extremes { lo, hi, acc }
    }
}

/// A rise of the slider above S_p after the tool first met the blank counts as
/// a re-contact (status [`Status::ReContacts`]) when it exceeds this fraction
/// of the nominal stroke; a smaller one is a touch within rounding, and a
/// slider that moves back up without leaving the blank is
/// [`Status::Reverses`].
pub const RECONTACT: f64 = 1e-9;

/// One point of the walk back from BDC: θ, S = y − y_B, y' and −y''.
#[derive(Debug, Clone, Copy)]
struct WalkPoint {
    th: f64,
    s: f64,
    dy: f64,
    g: f64,
}

/// Where the walk back from BDC crosses S_p last (the first contact in time).
struct Contact {
    /// The walk's step at the crossing's point above S_p.
    step: usize,
    /// (θ, S) of the bottom of a dip between two samples above S_p, the
    /// crossing's other end; None: the next point of the walk.
    dip: Option<(f64, f64)>,
    /// The highest S between the crossing and BDC (refined peaks included).
    s_max: f64,
}

/// The sampled rows the walk reads.
struct WalkPoints<'a> {
    ys: &'a [f64],
    dys: &'a [f64],
    ddys: &'a [f64],
    y_b: f64,
    s_n: f64,
    ddy_t: f64,
}

/// The walk back in time from BDC (θ decreasing) over the samples, with TDC
/// as a point of its own; it ends at TDC.
#[derive(Debug, Clone)]
struct Walk {
    j: usize,
    m: usize,
    h: f64,
    theta_j: f64,
    th_top: f64,
    top_pending: bool,
}

impl Walk {
    fn new(table: &Table, j_b: usize, th_b: f64, th_t: f64) -> Walk {
        let m = table.len();
        let mut j = j_b;
        if table.theta(j) >= th_b {
            j = if j == 0 { m - 1 } else { j - 1 };
        }
        let th_top = th_b - wrap(th_b - th_t);
        Walk {
            j,
            m,
            h: TAU / m as f64,
            theta_j: th_b - wrap(th_b - table.theta(j)),
            th_top,
            top_pending: th_top < th_b,
        }
    }

    /// True once TDC has been passed.
    fn done(&self) -> bool {
        !self.top_pending
    }

    /// The next point back: TDC if it lies before the next sample.
    #[inline]
    fn next(&mut self, p: &WalkPoints<'_>) -> Option<WalkPoint> {
        if self.top_pending && self.th_top >= self.theta_j {
            self.top_pending = false;
            return Some(WalkPoint {
                th: self.th_top,
                s: p.s_n,
                dy: 0.0,
                g: -p.ddy_t,
            });
        }
        let j = self.j;
        let pt = WalkPoint {
            th: self.theta_j,
            s: p.ys[j] - p.y_b,
            dy: p.dys[j],
            g: -p.ddys[j],
        };
        self.j = if j == 0 { self.m - 1 } else { j - 1 };
        self.theta_j -= self.h;
        Some(pt)
    }
}

/// Criteria of the design `f` (its rod length included) on its sampled pin path
/// `scan`, into `row` (see [`CRITERIA`]); returns its status.
fn criteria_with(
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
    let at = |x: f64, order: u32| f.at(x, order);
    // One branch-free pass over the turn (vectorised): height, slope, curvature.
    let Extremes {
        lo: j_lo,
        hi: j_hi,
        acc: j_acc,
    } = {
        let PinScan {
            pin,
            y,
            dy,
            ddy,
            cands,
            ..
        } = &mut *scan;
        scan_rod(l2, m, pin, [y, dy, ddy], cands)
    };
    let (ys, dys, ddys) = (
        &scan.y.as_flattened()[..m],
        &scan.dy.as_flattened()[..m],
        &scan.ddy.as_flattened()[..m],
    );
    let h = TAU / m as f64;
    // Neighbours on the turn (a compare, not a division: `prev` is on the
    // walk's chain of dependent steps).
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
    let [acc_peaks, lows, highs] = &scan.cands;
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
        for step in 0..=m + 1 {
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
        (nx_th, nx_s, nx_dy, nx_g) = (th, s, dy, g);
    }
    if th_p.is_nan() {
        // Unreachable: pass 2 walks the points of pass 1.
        return Status::LongStroke;
    }
    let (best_v, status) = (
        -dy_min,
        if s_max > s_p + rc_tol {
            Status::ReContacts
        } else if -dy_max < -1e-12 * s_n {
            Status::Reverses
        } else {
            Status::Ok
        },
    );
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
    // Speed peaks inside the working stroke: roots of y'' by Chebyshev steps
    // from the secant of the bracket's ends; Π' there by Taylor from the last
    // evaluation.
    let mut v_max = v_np.max(best_v);
    for &(lo, hi, glo, ghi) in &peaks[..n_peaks] {
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
            v_max = v_max.max(-dy);
        }
    }
    // Acceleration peak over the turn: every sampled local maximum of |y''| within
    // 1 % of the largest, refined at a root of y'''. One evaluation each, at the
    // peak of the quartic through the five samples around it (off by ~h⁴·y⁽⁷⁾/
    // (30·y'''')); the peak of the Taylor parabola there is the value, unless
    // that is more than a last step away, when a bracketed search follows.
    let acc = ddys[j_acc].abs();
    let mut a_max = acc;
    for &q in acc_peaks {
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

/// The axes of a design grid, designs in C order (R, r, d, L, φ0).
pub struct Grid<'a> {
    pub big_r: &'a [f64],
    pub r: &'a [f64],
    pub d: &'a [f64],
    pub l: &'a [f64],
    pub phi0: &'a [f64],
    pub offset: f64,
}

impl Grid<'_> {
    pub fn len(&self) -> usize {
        self.big_r.len() * self.r.len() * self.d.len() * self.l.len() * self.phi0.len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn design(&self, flat: usize) -> Design {
        let (np, nl, nd, nr) = (self.phi0.len(), self.l.len(), self.d.len(), self.r.len());
        let ip = flat % np;
        let il = (flat / np) % nl;
        let id = (flat / (np * nl)) % nd;
        let ir = (flat / (np * nl * nd)) % nr;
        let ib = flat / (np * nl * nd * nr);
        Design {
            big_r: self.big_r[ib],
            r: self.r[ir],
            d: self.d[id],
            l: self.l[il],
            phi0: self.phi0[ip],
            offset: self.offset,
        }
    }
}

/// Criteria over the full Cartesian grid: `rows` (designs × 14) and `status`
/// (designs), in parallel. Each pin path (R, r, d, φ0) is sampled once and
/// reused for every rod length L.
pub fn sweep_into(
    grid: &Grid<'_>,
    spec: &Spec,
    n_threads: Option<i64>,
    rows: &mut [f64],
    status: &mut [u8],
) -> Result<(), PressError> {
    spec.validate()?;
    let n = grid.len();
    let nc = CRITERIA.len();
    if rows.len() != n * nc || status.len() != n {
        return Err(PressError::BadSpec(
            "output sizes do not match the grid".into(),
        ));
    }
    if n == 0 {
        return Ok(());
    }
    // Validate every axis value (each with the first values of the other axes),
    // and build one table per gear ratio.
    let base = grid.design(0);
    // One table per gear ratio, and for every (R, r) pair (in grid order, one per
    // block of d values) the index of its table.
    let mut tables: Vec<(f64, Table)> = Vec::new();
    let mut table_at: Vec<usize> = Vec::with_capacity(grid.big_r.len() * grid.r.len());
    for &big_r in grid.big_r {
        for &r in grid.r {
            let ratio = Design { big_r, r, ..base }.validate()?;
            let k = match tables.iter().position(|(q, _)| *q == ratio) {
                Some(k) => k,
                None => {
                    tables.push((ratio, Table::new(ratio, spec.samples)));
                    tables.len() - 1
                }
            };
            table_at.push(k);
        }
    }
    for &d in grid.d {
        Design { d, ..base }.validate()?;
    }
    for &l in grid.l {
        Design { l, ..base }.validate()?;
    }
    for &phi0 in grid.phi0 {
        Design { phi0, ..base }.validate()?;
    }
    let (nl, np) = (grid.l.len(), grid.phi0.len());
    let block = nl * np;
    // Rows of one pin path (block b = (R, r, d), φ0 index p) for every L.
    let group = |b: usize, p: usize, scan: &mut PinScan| -> (Vec<f64>, Vec<u8>) {
        let design = grid.design(b * block + p);
        // Block b is (R, r, d) in C order: its (R, r) pair is b / len(d).
        let table = &tables[table_at[b / grid.d.len()]].1;
        let mut f = design.frame();
        scan.fill(&f, table);
        let mut out = vec![0.0; nl * nc];
        let mut st = vec![0u8; nl];
        for (il, (row, s)) in out.chunks_mut(nc).zip(st.iter_mut()).enumerate() {
            f.l = grid.l[il];
            *s = criteria_with(&f, table, spec, scan, row) as u8;
        }
        (out, st)
    };
    let place = |rb: &mut [f64], sb: &mut [u8], p: usize, (out, st): (Vec<f64>, Vec<u8>)| {
        for il in 0..nl {
            let q = il * np + p;
            rb[q * nc..(q + 1) * nc].copy_from_slice(&out[il * nc..(il + 1) * nc]);
            sb[q] = st[il];
        }
    };
    let threads = resolve_threads(n_threads)?;
    let blocks = rows
        .chunks_mut(block * nc)
        .zip(status.chunks_mut(block))
        .enumerate();
    if threads == 1 {
        let mut scan = PinScan::default();
        for (b, (rb, sb)) in blocks {
            for p in 0..np {
                let res = group(b, p, &mut scan);
                place(rb, sb, p, res);
            }
        }
    } else {
        let blocks: Vec<_> = blocks.collect();
        pool(threads)?.install(|| {
            blocks.into_par_iter().for_each(|(b, (rb, sb))| {
                let res: Vec<_> = (0..np)
                    .into_par_iter()
                    .map_init(PinScan::default, |scan, p| group(b, p, scan))
                    .collect();
                for (p, r) in res.into_iter().enumerate() {
                    place(rb, sb, p, r);
                }
            })
        });
    }
    Ok(())
}

/// Kinematics outputs for K designs × N angles, caller-owned: `s`, `ds`, `dds`
/// (K·N), `centre`, `pin`, `slider` (K·N·2), `ok` (K·N).
pub struct KinOut<'a> {
    pub s: &'a mut [f64],
    pub ds: &'a mut [f64],
    pub dds: &'a mut [f64],
    pub centre: &'a mut [f64],
    pub pin: &'a mut [f64],
    pub slider: &'a mut [f64],
    pub ok: &'a mut [bool],
}

/// The BDC of a design: (θ_B, y_B), the lowest slider position over the turn
/// (over its assembled part if the rod cannot reach everywhere; None if nowhere).
/// Of BDCs that tie (see [`TIE`]), the one at the smallest θ in [0, 2π).
pub fn bdc(design: &Design, samples: usize) -> Option<(f64, f64)> {
    let f = design.frame();
    let h = TAU / samples as f64;
    // y over the turn, +∞ where the rod does not reach (never a minimum).
    let mut ys = Vec::with_capacity(samples);
    let (mut lo, mut hi, mut acc) = (f64::INFINITY, f64::NEG_INFINITY, 0.0f64);
    for j in 0..samples {
        let k = f.at(h * j as f64, 2);
        if k.w2 > 0.0 {
            ys.push(k.y);
            (lo, hi, acc) = (lo.min(k.y), hi.max(k.y), acc.max(k.ddy.abs()));
        } else {
            ys.push(f64::INFINITY);
        }
    }
    if lo == f64::INFINITY {
        return None;
    }
    // Every sampled local minimum that may tie with the lowest (as in
    // `scan_rod`), refined at a root of y' where its neighbours bracket one.
    let band = 0.25 * acc * h * h + TIE * (hi - lo) + 8.0 * f64::EPSILON * (lo.abs() + hi.abs());
    let n = samples;
    let refine = |j: usize| -> (f64, f64) {
        let (th, y) = (h * j as f64, ys[j]);
        let (lo, hi) = (th - h, th + h);
        let (klo, khi) = (f.at(lo, 2), f.at(hi, 2));
        if klo.w2 > 0.0 && khi.w2 > 0.0 && klo.dy < 0.0 && khi.dy > 0.0 {
            let t = root(|x| f.at(x, 2).dy, lo, hi, klo.dy, khi.dy, 0.0);
            let yt = f.at(t, 2).y;
            if yt <= y {
                return (wrap(t), yt);
            }
        }
        (wrap(th), y)
    };
    let found: Vec<(f64, f64)> = (0..n)
        .filter(|&j| {
            let y = ys[j];
            y <= lo + band && y <= ys[(j + n - 1) % n] && y <= ys[(j + 1) % n]
        })
        .map(refine)
        .collect();
    let y_min = found.iter().fold(f64::INFINITY, |a, c| a.min(c.1));
    found
        .into_iter()
        .filter(|c| c.1 <= y_min + TIE * (hi - lo))
        .min_by(|a, b| a.0.total_cmp(&b.0))
}

/// One chunk of the outputs of [`solve_into`].
type KinChunk<'a> = (
    &'a mut [f64],
    &'a mut [f64],
    &'a mut [f64],
    &'a mut [f64],
    &'a mut [f64],
    &'a mut [f64],
    &'a mut [bool],
);

/// Solve K designs over one grid of α [rad] (counted from each design's BDC
/// against the motion), in parallel. Where the rod cannot reach the guide, `ok`
/// is false and the outputs NaN.
pub fn solve_into(
    designs: &[Design],
    alpha: &[f64],
    n_threads: Option<i64>,
    out: KinOut<'_>,
) -> Result<(), PressError> {
    for d in designs {
        d.validate()?;
    }
    if let Some((i, &v)) = alpha.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(PressError::NotFinite {
            field: "alpha",
            index: i,
            value: v,
        });
    }
    let (k, n) = (designs.len(), alpha.len());
    if out.s.len() != k * n
        || out.ds.len() != k * n
        || out.dds.len() != k * n
        || out.centre.len() != 2 * k * n
        || out.pin.len() != 2 * k * n
        || out.slider.len() != 2 * k * n
        || out.ok.len() != k * n
    {
        return Err(PressError::BadSpec("output sizes do not match".into()));
    }
    let threads = resolve_threads(n_threads)?;
    let frames: Vec<(Frame, Option<(f64, f64)>)> = designs
        .iter()
        .map(|d| (d.frame(), bdc(d, 4 * DEFAULT_SAMPLES)))
        .collect();
    const CHUNK: usize = 8192;
    let one = |start: usize, (s, ds, dds, centre, pin, slider, ok): KinChunk<'_>| {
        for q in 0..s.len() {
            let flat = start + q;
            let (f, b) = &frames[flat / n];
            let a = alpha[flat % n];
            let kin = b.map(|(th_b, y_b)| (f.at(th_b - a, 2), y_b));
            match kin {
                Some((kin, y_b)) if kin.w2 > 0.0 => {
                    s[q] = kin.y - y_b;
                    ds[q] = -kin.dy;
                    dds[q] = kin.ddy;
                    ok[q] = true;
                    slider[2 * q] = f.e;
                    slider[2 * q + 1] = kin.y;
                    centre[2 * q..2 * q + 2].copy_from_slice(&kin.centre);
                    pin[2 * q..2 * q + 2].copy_from_slice(&kin.pin);
                }
                _ => {
                    s[q] = f64::NAN;
                    ds[q] = f64::NAN;
                    dds[q] = f64::NAN;
                    ok[q] = false;
                    slider[2 * q..2 * q + 2].fill(f64::NAN);
                    match b {
                        // The crank still turns: centre and pin are known.
                        Some((th_b, _)) => {
                            let kin = f.at(th_b - a, 2);
                            centre[2 * q..2 * q + 2].copy_from_slice(&kin.centre);
                            pin[2 * q..2 * q + 2].copy_from_slice(&kin.pin);
                        }
                        None => {
                            centre[2 * q..2 * q + 2].fill(f64::NAN);
                            pin[2 * q..2 * q + 2].fill(f64::NAN);
                        }
                    }
                }
            }
        }
    };
    let KinOut {
        s,
        ds,
        dds,
        centre,
        pin,
        slider,
        ok,
    } = out;
    let chunks: Vec<_> = s
        .chunks_mut(CHUNK)
        .zip(ds.chunks_mut(CHUNK))
        .zip(dds.chunks_mut(CHUNK))
        .zip(centre.chunks_mut(2 * CHUNK))
        .zip(pin.chunks_mut(2 * CHUNK))
        .zip(slider.chunks_mut(2 * CHUNK))
        .zip(ok.chunks_mut(CHUNK))
        .enumerate()
        .map(|(c, ((((((a, b), cc), d), e), g), h))| (c * CHUNK, (a, b, cc, d, e, g, h)))
        .collect();
    if threads == 1 || chunks.len() <= 1 {
        chunks.into_iter().for_each(|(st, c)| one(st, c));
    } else {
        pool(threads)?.install(|| chunks.into_par_iter().for_each(|(st, c)| one(st, c)));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::f64::consts::PI;

    fn press(d: f64, l: f64, phi0: f64) -> Design {
        Design {
            big_r: 0.09,
            r: 0.03,
            d,
            l,
            phi0,
            offset: 0.0,
        }
    }

    fn solve(design: &Design, alpha: &[f64]) -> (Vec<f64>, Vec<f64>, Vec<f64>, Vec<bool>) {
        let n = alpha.len();
        let (mut s, mut ds, mut dds) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let (mut c, mut p, mut sl) = (vec![0.0; 2 * n], vec![0.0; 2 * n], vec![0.0; 2 * n]);
        let mut ok = vec![false; n];
        solve_into(
            &[*design],
            alpha,
            Some(1),
            KinOut {
                s: &mut s,
                ds: &mut ds,
                dds: &mut dds,
                centre: &mut c,
                pin: &mut p,
                slider: &mut sl,
                ok: &mut ok,
            },
        )
        .unwrap();
        (s, ds, dds, ok)
    }

    #[test]
    fn rod_scan_is_the_same_on_every_instruction_set() {
        // The rod loop and extreme search compiled for scalar code, AVX2 and
        // AVX-512 (those the processor has): the same values and indices.
        use pulp::Simd;
        let m: usize = 361;
        let col =
            |f: &dyn Fn(f64) -> f64| (0..m).map(|j| f(j as f64 * 0.0174)).collect::<Vec<f64>>();
        let u2 = col(&|x| 0.01 * (1.0 + x.sin()).powi(2));
        let upx1 = col(&|x| 0.02 * x.cos());
        let hh = col(&|x| 0.001 * (2.0 * x).sin());
        let mut py = col(&|x| 0.3 * (x * 0.5).cos());
        py[200..210].fill(-0.4); // a dip: the lowest point is in it
        let mut py1 = col(&|x| -0.15 * (x * 0.5).sin());
        let mut py2 = col(&|x| -0.075 * (x * 0.5).cos());
        // Equal lowest samples in three lanes and in the remainder: the first wins.
        py[202] = -0.5;
        let (mut u2, mut upx1, mut hh) = (u2, upx1, hh);
        for j in [203, 207, 360] {
            for v in [&mut u2, &mut upx1, &mut hh, &mut py, &mut py1, &mut py2] {
                v[j] = v[202];
            }
        }
        // In blocks of LANES samples, the last one padded with sample 0 (as
        // PinScan::fill does).
        let nb = m.div_ceil(LANES);
        let cols = [&u2, &upx1, &hh, &py, &py1, &py2];
        let pin: Vec<[[f64; LANES]; 6]> = (0..nb)
            .map(|b| {
                std::array::from_fn(|k| {
                    std::array::from_fn(|l| {
                        let j = b * LANES + l;
                        cols[k][if j < m { j } else { 0 }]
                    })
                })
            })
            .collect();
        let runs = on_each_isa!(|simd| {
            let mut rows = vec![vec![[0.0; LANES]; nb]; 3];
            let mut cands = [Vec::new(), Vec::new(), Vec::new()];
            let [y, dy, ddy] = &mut rows[..] else {
                unreachable!()
            };
            let ex = Simd::vectorize(
                simd,
                RodScan {
                    l2: 0.09,
                    m,
                    pin: &pin,
                    out: [y, dy, ddy],
                    cands: &mut cands,
                },
            );
            let flat = |v: &Vec<[f64; LANES]>| v.as_flattened()[..m].to_vec();
            ([ex.lo, ex.hi, ex.acc], cands, flat(y), flat(dy), flat(ddy))
        });
        let (_, first) = &runs[0];
        let (y, ddy) = (&first.2, &first.4);
        let lowest = (0..m).fold(0, |b, j| if y[j] < y[b] { j } else { b });
        let highest = (0..m).fold(0, |b, j| if y[j] > y[b] { j } else { b });
        let steepest = (0..m).fold(0, |b, j| if ddy[j].abs() > ddy[b].abs() { j } else { b });
        assert_eq!(first.0, [lowest, highest, steepest], "the first extremes");
        assert_eq!(lowest, 202);
        // The candidates by brute force: local maxima of |y''| within 1 % of
        // the largest, local minima (maxima) of y within the band of the lowest
        // (highest).
        let a = |j: usize| ddy[j % m].abs();
        let yc = |j: usize| y[j % m];
        let peaks: Vec<usize> = (0..m)
            .filter(|&j| a(j) >= 0.99 * a(steepest) && a(j) >= a(j + m - 1) && a(j) >= a(j + 1))
            .collect();
        assert!(peaks.contains(&steepest));
        let (ylo, yhi) = (y[lowest], y[highest]);
        let h = TAU / m as f64;
        let band = 0.25 * a(steepest) * h * h
            + TIE * (yhi - ylo)
            + 8.0 * f64::EPSILON * (ylo.abs() + yhi.abs());
        let lows: Vec<usize> = (0..m)
            .filter(|&j| yc(j) <= ylo + band && yc(j) <= yc(j + m - 1) && yc(j) <= yc(j + 1))
            .collect();
        let highs: Vec<usize> = (0..m)
            .filter(|&j| yc(j) >= yhi - band && yc(j) >= yc(j + m - 1) && yc(j) >= yc(j + 1))
            .collect();
        // The equal lowest samples 202, 203 (a flat pair), 207 and 360.
        assert_eq!(lows, [202, 203, 207, 360]);
        assert_eq!(first.1, [peaks, lows, highs]);
        for (isa, run) in &runs {
            assert_eq!(run, first, "{isa}");
        }
    }

    #[test]
    fn crank_slider_limit_is_the_closed_form() {
        let (a, l) = (0.06, 0.25);
        let design = press(0.0, l, 0.3);
        let alpha: Vec<f64> = (0..=72).map(|k| k as f64 * PI / 36.0).collect();
        let (s, ds, dds, ok) = solve(&design, &alpha);
        for (q, &al) in alpha.iter().enumerate() {
            let (sa, ca) = al.sin_cos();
            let root = (l * l - a * a * sa * sa).sqrt();
            let s0 = a * (1.0 - ca) + l - root;
            let ds0 = a * sa + a * a * sa * ca / root;
            let dds0 = a * ca
                + a * a * (ca * ca - sa * sa) / root
                + a.powi(4) * sa * sa * ca * ca / root.powi(3);
            assert!(ok[q]);
            assert!((s[q] - s0).abs() < 1e-14, "S at {al}: {} vs {s0}", s[q]);
            assert!((ds[q] - ds0).abs() < 1e-14, "S' at {al}");
            assert!((dds[q] - dds0).abs() < 1e-13, "S'' at {al}");
        }
    }

    #[test]
    fn criteria_of_the_crank_slider() {
        // Crank-slider with ω = 1: α_p from S(α_p) = S_p in closed form.
        let (a, l) = (0.06, 0.25);
        let spec = Spec {
            stroke: Stroke::Fraction(0.1),
            omega: 1.0,
            samples: 360,
        };
        let (row, status) = criteria(&press(0.0, l, 0.0), &spec).unwrap();
        assert_eq!(status, Status::Ok);
        assert!((row[0] - 2.0 * a).abs() < 1e-14);
        let s_p = 0.1 * 2.0 * a;
        let s = |al: f64| a * (1.0 - al.cos()) + l - (l * l - (a * al.sin()).powi(2)).sqrt();
        let alpha_p = row[2];
        assert!((s(alpha_p) - s_p).abs() < 1e-15);
        assert!(alpha_p > 0.0 && alpha_p < PI);
        // Speed falls monotonically to BDC: the peak is at the start.
        assert!((row[5] - row[3]).abs() < 1e-15);
        // J_max of a crank-slider is at BDC: a(1 + a/L).
        assert!((row[6] - a * (1.0 + a / l)).abs() < 1e-13, "{}", row[6]);
    }

    #[test]
    fn first_contact_of_a_slider_that_dips_and_backs_off() {
        // Issue 16 item 1: coming down from TDC this slider first reaches S_p at
        // α ≈ 126.2° (the dense reference of tests/test_issue16_press.py gives
        // 126.22449…°), dips 1.55 mm below it, backs off above it and crosses it
        // again at α ≈ 76.0° (the old α_p).
        let spec = Spec {
            stroke: Stroke::Fraction(0.1),
            omega: 1.0,
            samples: 360,
        };
        let (row, status) = criteria(&press(0.028, 0.46, 56f64.to_radians()), &spec).unwrap();
        assert_eq!(status, Status::ReContacts);
        assert!(
            (row[2].to_degrees() - 126.2245).abs() < 1e-3,
            "{}",
            row[2].to_degrees()
        );
        // A shorter rod without the dip: ok, and the same from fewer samples.
        let (row, status) = criteria(&press(0.029, 0.25, 56f64.to_radians()), &spec).unwrap();
        assert_eq!(status, Status::Ok);
        let coarse = Spec {
            samples: 24,
            ..spec
        };
        let (row24, _) = criteria(&press(0.029, 0.25, 56f64.to_radians()), &coarse).unwrap();
        assert!((row[2] - row24[2]).abs() < 1e-9);
    }

    proptest! {
        #[test]
        fn derivatives_match_differences(d in 0.0f64..0.06, phi0 in -PI..PI, al in 0.1f64..6.0) {
            let design = press(d, 0.4, phi0);
            let h = 1e-6;
            let (s, ds, dds, ok) = solve(&design, &[al - h, al, al + h]);
            prop_assume!(ok.iter().all(|&o| o));
            prop_assert!(((s[2] - s[0]) / (2.0 * h) - ds[1]).abs() < 1e-7);
            prop_assert!(((ds[2] - ds[0]) / (2.0 * h) - dds[1]).abs() < 1e-6);
            let f = design.frame();
            let th = 1.234 + al;
            let fd = (f.at(th + h, 2).ddy - f.at(th - h, 2).ddy) / (2.0 * h);
            prop_assert!((fd - f.at(th, 3).dddy).abs() < 1e-6);
            let fd = (f.at(th + h, 3).dddy - f.at(th - h, 3).dddy) / (2.0 * h);
            let k = f.at(th, 4);
            prop_assert!((fd - k.ddddy).abs() < 1e-5 * (1.0 + k.ddddy.abs()), "{fd} {}", k.ddddy);
            prop_assert_eq!(k.dddy, f.at(th, 3).dddy);
        }
    }
}
