//! The planetary gear-lever drive: a design, its kinematics over α grids, and
//! the domain's error.

use std::f64::consts::{FRAC_PI_2, TAU};

use rayon::prelude::*;

use crate::geom::sin_cos;
use crate::input::InvalidInput;
use crate::parallel::{pool, resolve_threads};

use super::criteria::{bdc_of, wrap, DEFAULT_SAMPLES, TIE};

/// Errors of the press domain.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PressError {
    #[error(transparent)]
    Input(#[from] InvalidInput),
    #[error("{0}")]
    BadSpec(String),
}

crate::input::wraps_invalid_input!(PressError);

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
            Err(InvalidInput::bad_value(field, value, why.to_owned()).into())
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
            return Err(InvalidInput::BadValue {
                field: "R/r",
                value: i,
                why: format!(
                    "must be a whole number between 2 and {MAX_RATIO} (R = {}, r = {}): only then \
                     does the drive repeat every crank turn; the seed uses 3",
                    self.big_r, self.r
                )
                .into(),
            }
            .into());
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

    pub(super) fn frame(&self) -> Frame {
        let i = (self.big_r / self.r).round();
        let beta0 = i * (self.phi0 - FRAC_PI_2);
        Frame {
            a: self.big_r - self.r,
            k: i - 1.0,
            beta0,
            turn0: cos_sin(beta0),
            // A whole number from 1 to MAX_RATIO − 1 for a valid design.
            k_int: (i - 1.0).clamp(0.0, MAX_RATIO) as u32,
            d: self.d,
            l: self.l,
            e: self.offset,
        }
    }
}

/// A design in the form the kernels use.
#[derive(Debug, Clone, Copy)]
pub(super) struct Frame {
    pub(super) a: f64,
    pub(super) k: f64,
    pub(super) beta0: f64,
    /// (cos β0, sin β0).
    pub(super) turn0: (f64, f64),
    /// k as an integer (the gear ratio less one), for the powers of e^{iθ}.
    pub(super) k_int: u32,
    pub(super) d: f64,
    pub(super) l: f64,
    pub(super) e: f64,
}

/// Slider height and its θ-derivatives at one carrier angle.
#[derive(Debug, Clone, Copy)]
pub(super) struct Kin {
    pub(super) centre: [f64; 2],
    pub(super) pin: [f64; 2],
    /// L² − (P_x − offset)²: > 0 where the rod reaches the guide.
    pub(super) w2: f64,
    pub(super) y: f64,
    pub(super) dy: f64,
    pub(super) ddy: f64,
    /// y''' where `order` ≥ 3, else 0.
    pub(super) dddy: f64,
    /// y'''' where `order` ≥ 4, else 0.
    pub(super) ddddy: f64,
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
    pub(super) fn at(&self, theta: f64, order: u32) -> Kin {
        self.kin(cos_sin(theta), cos_sin(self.beta0 - self.k * theta), order)
    }

    /// [`at`](Self::at) with one sin/cos, of θ; those of β = β0 − kθ from
    /// them, as e^{iβ0}·(e^{−iθ})^k with k whole (binary powers): not the bits
    /// of sin/cos of the rounded β0 − kθ but as accurate (the power's phase
    /// error, ~k ulps, is that of rounding kθ). For the criteria's
    /// refinements; [`at`](Self::at) where [`exact`].
    #[inline]
    pub(super) fn at_pow(&self, theta: f64, order: u32) -> Kin {
        #[cfg(test)]
        EVALS.with(|c| c.set(c.get() + 1));
        if exact() {
            return self.at(theta, order);
        }
        let t = cos_sin(theta);
        self.kin(t, self.turn(t), order)
    }

    /// (cos β, sin β) for β = β0 − kθ from (cos θ, sin θ).
    #[inline(always)]
    fn turn(&self, (c, s): (f64, f64)) -> (f64, f64) {
        // (cos kθ, sin kθ) = (c + i·s)^k.
        let (mut pc, mut ps) = (1.0, 0.0);
        let (mut bc, mut bs) = (c, s);
        let mut n = self.k_int;
        while n > 0 {
            if n & 1 == 1 {
                (pc, ps) = (pc * bc - ps * bs, pc * bs + ps * bc);
            }
            n >>= 1;
            if n > 0 {
                (bc, bs) = (bc * bc - bs * bs, 2.0 * bc * bs);
            }
        }
        let (c0, s0) = self.turn0;
        (c0 * pc + s0 * ps, s0 * pc - c0 * ps)
    }
}

#[cfg(test)]
thread_local! {
    /// Tests only: true runs the reference arithmetic of the criteria — sin/cos
    /// of β = β0 − kθ itself in [`Frame::at`], and the rod scan's exact √ and
    /// division for √(L² − u²) and its reciprocal — against which the faster
    /// forms (the power of e^{iθ}, both from an estimate of the reciprocal
    /// square root and its correction) are tested.
    pub(super) static EXACT: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

#[cfg(test)]
thread_local! {
    /// Tests only: evaluations of the kinematics by the criteria's
    /// refinements ([`Frame::at_pow`]) on this thread, for the timing test's
    /// count per design.
    pub(super) static EVALS: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// Whether the criteria run their reference arithmetic (tests only, [`EXACT`]).
#[inline]
pub(super) fn exact() -> bool {
    #[cfg(test)]
    return EXACT.with(|c| c.get());
    #[cfg(not(test))]
    false
}

/// (cos x, sin x).
#[inline(always)]
pub(super) fn cos_sin(x: f64) -> (f64, f64) {
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
pub(super) struct Table {
    pub(super) ct: Vec<f64>,
    pub(super) st: Vec<f64>,
    pub(super) cb: Vec<f64>,
    pub(super) sb: Vec<f64>,
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

    pub(super) fn len(&self) -> usize {
        self.ct.len()
    }

    pub(super) fn theta(&self, j: usize) -> f64 {
        TAU * j as f64 / self.len() as f64
    }
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
/// [`solve_into`] takes it only for a design whose rod does not reach over the
/// whole turn; for the others it takes the BDC of their criteria, which agrees
/// with this one to rounding where BDC is an ordinary minimum (y'' > 0) and to
/// ~1e-5 rad where it is flat (y'' ≈ 0: θ_B is a root of a y' cubic there).
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
    let ratios = designs
        .iter()
        .map(|d| d.validate())
        .collect::<Result<Vec<f64>, _>>()?;
    InvalidInput::check_finite("alpha", alpha)?;
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
    // α counts from the BDC the design's criteria report (one computation,
    // so that S(α_p) = S_p to rounding even where a flat BDC leaves θ_B
    // uncertain by ~1e-5 rad); where the rod does not reach over the whole
    // turn (no criteria), from the lowest point of its assembled part.
    let frames: Vec<(Frame, Option<(f64, f64)>)> = designs
        .iter()
        .zip(&ratios)
        .map(|(d, &ratio)| {
            let b = bdc_of(d, ratio, DEFAULT_SAMPLES).or_else(|| bdc(d, 4 * DEFAULT_SAMPLES));
            (d.frame(), b)
        })
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
    let one = |(st, c)| {
        if !crate::cancel::requested() {
            one(st, c)
        }
    };
    if threads == 1 || chunks.len() <= 1 {
        chunks.into_iter().for_each(one);
    } else {
        pool(threads)?.install(|| chunks.into_par_iter().for_each(one));
    }
    Ok(())
}
