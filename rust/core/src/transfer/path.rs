//! The composed path sampled in travel order ([`sample_into`]) and the
//! workpiece's kinematics along a sampled path for a speed law
//! ([`kinematics_into`]).

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

use super::quintic::{curvature, Quintic};
use super::{map_tasks, run_tasks, TransferError, BLOCK};
use crate::input::InvalidInput;
use crate::parallel::resolve_threads;

/// Numbers in a [`PathSpec`]'s flat form, in this order: transport centre (2),
/// process centre (2), R_t, R_p, lead [rad], the two quintics' a0 … a5 (6 + 6),
/// x2_t, x2_p, A (2), C (2), the local x axes at A and C (2 + 2), B_t (2), the
/// straight's direction u (2), its length, the five pieces' lengths, A's angle
/// about the transport centre φ_A, the headings of A's x axis, of the straight
/// and of C's x axis, and C's angle about the process centre φ_C — all in the
/// frame where the transport rotor turns counter-clockwise.
pub const N_SPEC: usize = 44;

/// A path as the Python layer builds it (see [`N_SPEC`] for the flat form).
#[derive(Debug, Clone, PartialEq)]
pub struct PathSpec {
    pub centre: [[f64; 2]; 2],
    pub radius: [f64; 2],
    pub lead: f64,
    pub quintic: [Quintic; 2],
    pub x2: [f64; 2],
    pub origin: [[f64; 2]; 2],
    pub t_a: [[f64; 2]; 2],
    pub end_t: [f64; 2],
    pub u: [f64; 2],
    pub straight: f64,
    pub lengths: [f64; 5],
    pub phi_a: f64,
    pub base_t: f64,
    pub head: f64,
    pub base_p: f64,
    pub phi_c: f64,
}

impl PathSpec {
    /// From the flat form, checked: N_SPEC finite numbers, positive radii and
    /// transition lengths, lengths not negative.
    pub fn from_flat(v: &[f64]) -> Result<Self, TransferError> {
        if v.len() != N_SPEC {
            return Err(TransferError::BadLength {
                field: "spec",
                got: v.len(),
                want: "44 numbers (see cyclomech_core::transfer::N_SPEC)",
            });
        }
        InvalidInput::check_finite("spec", v)?;
        let p = |i: usize| [v[i], v[i + 1]];
        let q = |i: usize| Quintic {
            c: [v[i], v[i + 1], v[i + 2], v[i + 3], v[i + 4], v[i + 5]],
        };
        let spec = PathSpec {
            centre: [p(0), p(2)],
            radius: [v[4], v[5]],
            lead: v[6],
            quintic: [q(7), q(13)],
            x2: [v[19], v[20]],
            origin: [p(21), p(23)],
            t_a: [p(25), p(27)],
            end_t: p(29),
            u: p(31),
            straight: v[33],
            lengths: [v[34], v[35], v[36], v[37], v[38]],
            phi_a: v[39],
            base_t: v[40],
            head: v[41],
            base_p: v[42],
            phi_c: v[43],
        };
        for (field, value) in [
            ("R_t", spec.radius[0]),
            ("R_p", spec.radius[1]),
            ("x2_t", spec.x2[0]),
            ("x2_p", spec.x2[1]),
        ] {
            if value <= 0.0 {
                return Err(InvalidInput::BadValue {
                    field,
                    value,
                    why: "must be > 0 m".into(),
                }
                .into());
            }
        }
        if spec.lead < 0.0 || spec.straight < 0.0 || spec.lengths.iter().any(|&l| l < 0.0) {
            return Err(InvalidInput::BadValue {
                field: "spec",
                value: spec.lead.min(spec.straight),
                why: "has a negative length (lead, straight or a piece)".into(),
            }
            .into());
        }
        Ok(spec)
    }
}

/// The sampled path's arrays, each `n` long (`points` 2·n, (x, y) pairs).
pub struct SampleOut<'a> {
    pub points: &'a mut [f64],
    pub s: &'a mut [f64],
    pub heading: &'a mut [f64],
    pub curvature: &'a mut [f64],
    pub rate: &'a mut [f64],
    pub piece: &'a mut [i8],
}

impl<'a> SampleOut<'a> {
    fn len(&self) -> usize {
        self.s.len()
    }

    /// The first `k` points and the rest.
    fn split(self, k: usize) -> (SampleOut<'a>, SampleOut<'a>) {
        let (p0, p1) = self.points.split_at_mut(2 * k);
        let (s0, s1) = self.s.split_at_mut(k);
        let (h0, h1) = self.heading.split_at_mut(k);
        let (c0, c1) = self.curvature.split_at_mut(k);
        let (r0, r1) = self.rate.split_at_mut(k);
        let (i0, i1) = self.piece.split_at_mut(k);
        (
            SampleOut {
                points: p0,
                s: s0,
                heading: h0,
                curvature: c0,
                rate: r0,
                piece: i0,
            },
            SampleOut {
                points: p1,
                s: s1,
                heading: h1,
                curvature: c1,
                rate: r1,
                piece: i1,
            },
        )
    }
}

/// Points between exact sines and cosines on an arc (the rest by one rotation).
const ROTATE: usize = 64;

/// The path `spec` sampled with `counts[p]` points on piece p (arc_t,
/// transition_t, straight, transition_p, arc_p; each ≥ 2; each piece evenly in
/// its own parameter, the last one's end point included), mirrored in the x
/// axis when `ccw` is false (points' y, heading, curvature and its rate change
/// sign), into `out`. Blocks of [`BLOCK`] points run in parallel; the result
/// does not depend on the thread count.
pub fn sample_into(
    spec: &PathSpec,
    counts: &[usize; 5],
    ccw: bool,
    out: SampleOut<'_>,
    n_threads: Option<i64>,
) -> Result<(), TransferError> {
    let n: usize = counts.iter().sum();
    if counts.iter().any(|&c| c < 2) {
        return Err(InvalidInput::BadValue {
            field: "counts",
            value: counts.iter().copied().min().unwrap_or(0) as f64,
            why: "must give every piece ≥ 2 points".into(),
        }
        .into());
    }
    if out.len() != n || out.points.len() != 2 * n || out.heading.len() != n {
        return Err(TransferError::BadLength {
            field: "out",
            got: out.len(),
            want: "the sum of counts",
        });
    }
    let tops = [
        spec.x2[0] / counts[1] as f64 * (counts[1] - 1) as f64,
        spec.x2[1],
    ];
    let pieces = [
        spec.quintic[0].pieces(tops[0]),
        spec.quintic[1].pieces(tops[1]),
    ];
    // Blocks, in order: (piece, first index in the piece, its slice of out).
    let mut tasks = Vec::with_capacity(n / BLOCK + 10);
    let mut rest = out;
    for (p, &c) in counts.iter().enumerate() {
        let mut i = 0;
        while i < c {
            let k = BLOCK.min(c - i);
            let (head, tail) = rest.split(k);
            tasks.push((p, i, head));
            rest = tail;
            i += k;
        }
    }
    let threads = resolve_threads(n_threads)?;
    run_tasks(tasks, threads, |(p, i0, o)| {
        fill(spec, counts, &pieces, p, i0, ccw, o)
    })
}

/// Arc length at the start of each piece: the lengths summed in travel order.
fn starts(lengths: &[f64; 5]) -> [f64; 5] {
    let mut s = [0.0; 5];
    for p in 1..5 {
        s[p] = s[p - 1] + lengths[p - 1];
    }
    s
}

/// One block of piece `p`, from its point `i0`.
fn fill(
    spec: &PathSpec,
    counts: &[usize; 5],
    pieces: &[usize; 2],
    p: usize,
    i0: usize,
    ccw: bool,
    mut o: SampleOut<'_>,
) {
    let c = counts[p];
    let s0 = starts(&spec.lengths)[p];
    o.piece.fill(p as i8);
    match p {
        0 => {
            // Lead-in arc, counter-clockwise about the transport centre, to A.
            let lead = spec.lead;
            pulp::Arch::new().dispatch(Arc {
                centre: spec.centre[0],
                r: spec.radius[0],
                sign: 1.0,
                a: spec.phi_a - lead,
                b: lead,
                step: 1.0 / c as f64,
                last: None,
                i0,
                s0: 0.0,
                o: &mut o,
            });
        }
        1 | 3 => {
            let side = (p - 1) / 2;
            pulp::Arch::new().dispatch(QuinticBlock {
                spec,
                side,
                c,
                m: pieces[side],
                i0,
                s0,
                o: &mut o,
            });
        }
        2 => pulp::Arch::new().dispatch(Straight {
            spec,
            step: 1.0 / c as f64,
            i0,
            s0,
            o: &mut o,
        }),
        _ => {
            // Lead-out arc, clockwise about the process centre, from C; the
            // piece's last point is the path's end (u = 1 exactly).
            pulp::Arch::new().dispatch(Arc {
                centre: spec.centre[1],
                r: spec.radius[1],
                sign: -1.0,
                a: spec.phi_c,
                b: -spec.lead,
                step: 1.0 / (c - 1) as f64,
                last: Some(c - 1),
                i0,
                s0,
                o: &mut o,
            });
        }
    }
    if !ccw {
        for y in o.points.iter_mut().skip(1).step_by(2) {
            *y = -*y;
        }
        for v in o
            .heading
            .iter_mut()
            .chain(o.curvature.iter_mut())
            .chain(o.rate.iter_mut())
        {
            *v = -*v;
        }
    }
}

/// Points `i0 ..` of the straight segment, from B_t along u at
/// t = i·`step` of its length, arc length from `s0` (a lane loop under
/// `pulp`'s dispatch).
struct Straight<'s, 'a, 'b> {
    spec: &'s PathSpec,
    step: f64,
    i0: usize,
    s0: f64,
    o: &'a mut SampleOut<'b>,
}

impl pulp::WithSimd for Straight<'_, '_, '_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        let Straight {
            spec,
            step,
            i0,
            s0,
            o,
        } = self;
        let (e, u, len) = (spec.end_t, spec.u, spec.straight);
        for (j, (p, s)) in o.points.chunks_exact_mut(2).zip(o.s.iter_mut()).enumerate() {
            let t = (i0 + j) as f64 * step;
            let a = t * len;
            p[0] = e[0] + a * u[0];
            p[1] = e[1] + a * u[1];
            *s = s0 + t * len;
        }
        o.heading.fill(spec.head);
        o.curvature.fill(0.0);
        o.rate.fill(0.0);
    }
}

/// Points `i0 ..` of an arc of radius `r` about `centre` at the angles
/// φ = `a` + `b`·u (u = i·`step`, the piece's last point u = 1 when `last`),
/// heading φ ± π/2 and curvature ±1/r by `sign`, arc length `s0` + r·|b|·u:
/// the sine and cosine exact every [`ROTATE`] points, rotated by multiples of
/// b·step between (lane loops under `pulp`'s dispatch).
struct Arc<'a, 'b> {
    centre: [f64; 2],
    r: f64,
    sign: f64,
    a: f64,
    b: f64,
    step: f64,
    last: Option<usize>,
    i0: usize,
    s0: f64,
    o: &'a mut SampleOut<'b>,
}

impl pulp::WithSimd for Arc<'_, '_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        let Arc {
            centre,
            r,
            sign,
            a,
            b,
            step,
            last,
            i0,
            s0,
            o,
        } = self;
        let len = o.s.len();
        let mut u = [0.0; BLOCK];
        let u = &mut u[..len];
        for (j, u) in u.iter_mut().enumerate() {
            *u = (i0 + j) as f64 * step;
        }
        if let Some(l) = last {
            if (i0..i0 + len).contains(&l) {
                u[l - i0] = 1.0;
            }
        }
        let (kappa, turn, rl) = (sign / r, sign * FRAC_PI_2, r * b.abs());
        let dphi = b * step;
        let mut table = [(0.0, 1.0); ROTATE];
        for (j, t) in table.iter_mut().enumerate().take(len) {
            *t = (j as f64 * dphi).sin_cos();
        }
        let (ct, st): (Vec<f64>, Vec<f64>) = table.iter().map(|&(s, c)| (c, s)).unzip();
        for (start, pts) in (0..len)
            .step_by(ROTATE)
            .zip(o.points.chunks_mut(2 * ROTATE))
        {
            let (sa, ca) = (a + b * u[start]).sin_cos();
            for (k, p) in pts.chunks_exact_mut(2).enumerate() {
                p[0] = centre[0] + r * (ca * ct[k] - sa * st[k]);
                p[1] = centre[1] + r * (sa * ct[k] + ca * st[k]);
            }
        }
        for ((h, s), &u) in o.heading.iter_mut().zip(o.s.iter_mut()).zip(u.iter()) {
            *h = (a + b * u) + turn;
            *s = s0 + rl * u;
        }
        o.curvature.fill(kappa);
        o.rate.fill(0.0);
    }
}

/// Points `i0 ..` of transition `side` (0 forward from A, 1 backwards from B_p
/// to C) at the abscissas x_i = i·(±x2/c) + (0 or x2) in its frame (numpy's
/// `linspace`); arc length from the piece's start `s0`. On a grid too coarse
/// for 4-point steps (fewer than ten points per 16-point piece) every point's
/// length is its own 16-point quadrature. The loops are plain lane loops, run
/// under `pulp`'s dispatch so that they compile to the widest vectors the
/// processor has (the arithmetic is the same on every instruction set: no
/// fused multiply-adds are introduced).
struct QuinticBlock<'s, 'a, 'b> {
    spec: &'s PathSpec,
    side: usize,
    c: usize,
    m: usize,
    i0: usize,
    s0: f64,
    o: &'a mut SampleOut<'b>,
}

impl pulp::WithSimd for QuinticBlock<'_, '_, '_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        let QuinticBlock {
            spec,
            side,
            c,
            m,
            i0,
            s0,
            o,
        } = self;
        let q = spec.quintic[side];
        let x2 = spec.x2[side];
        let forward = side == 0;
        let (start, step) = if forward {
            (0.0, x2 / c as f64)
        } else {
            (x2, -x2 / c as f64)
        };
        let len = o.s.len();
        let mut xs = [0.0; BLOCK];
        let mut sl = [0.0; BLOCK];
        let xs = &mut xs[..len];
        let sl = &mut sl[..len];
        for (j, x) in xs.iter_mut().enumerate() {
            *x = (i0 + j) as f64 * step + start;
        }
        if 10 * m > c {
            for (s, &x) in sl.iter_mut().zip(xs.iter()) {
                *s = q.arc_from_zero(x, m);
            }
        } else {
            // 4-point steps between neighbours (lane loop), then their running
            // sum from the block's first point's 16-point length.
            for j in 1..len {
                sl[j] = q.arc_step(xs[j - 1], xs[j]);
            }
            let mut acc = q.arc_from_zero(xs[0], m);
            sl[0] = acc;
            for s in sl.iter_mut().skip(1) {
                acc += *s;
                *s = acc;
            }
        }
        let (org, t) = (spec.origin[side], spec.t_a[side]);
        let total = spec.lengths[1 + 2 * side];
        let (base, turn, sign) = if forward {
            (spec.base_t, 0.0, 1.0)
        } else {
            (spec.base_p, PI, -1.0)
        };
        let (pts, s, head, kap, rat) = (
            &mut o.points[..2 * len],
            &mut o.s[..len],
            &mut o.heading[..len],
            &mut o.curvature[..len],
            &mut o.rate[..len],
        );
        for j in 0..len {
            let xi = xs[j];
            let [y, d1, d2, d3] = q.all(xi);
            pts[2 * j] = org[0] + xi * t[0] + y * -t[1];
            pts[2 * j + 1] = org[1] + xi * t[1] + y * t[0];
            let (kappa, rate) = curvature(d1, d2, d3, (1.0 + d1 * d1).sqrt());
            head[j] = atan(d1) + base + turn;
            kap[j] = sign * kappa;
            rat[j] = rate;
            s[j] = if forward {
                s0 + sl[j]
            } else {
                s0 + (total - sl[j])
            };
        }
    }
}

/// atan(x) without a branch (Cephes' `atan`: range reduction at tan(3π/8) and
/// 0.66, a rational approximation; within an ulp or two of the library's), so
/// that lane loops vectorise.
#[inline(always)]
pub(super) fn atan(x: f64) -> f64 {
    const T3P8: f64 = 2.414_213_562_373_095;
    const MOREBITS: f64 = 6.123_233_995_736_766e-17;
    const P: [f64; 5] = [
        -8.750_608_600_031_904e-1,
        -1.615_753_718_733_365e1,
        -7.500_855_792_314_705e1,
        -1.228_866_684_490_136_2e2,
        -6.485_021_904_942_025e1,
    ];
    const Q: [f64; 5] = [
        2.485_846_490_142_306_4e1,
        1.650_270_098_316_988_6e2,
        4.328_810_604_912_903e2,
        4.853_903_996_359_137e2,
        1.945_506_571_482_614e2,
    ];
    let a = x.abs();
    let big = a > T3P8;
    let mid = !big && a > 0.66;
    // One division for the three ranges: −1/a, (a − 1)/(a + 1) or a/1.
    let (num, den) = if big {
        (-1.0, a)
    } else if mid {
        (a - 1.0, a + 1.0)
    } else {
        (a, 1.0)
    };
    let r = num / den;
    let (y0, more) = if big {
        (FRAC_PI_2, MOREBITS)
    } else if mid {
        (FRAC_PI_4, 0.5 * MOREBITS)
    } else {
        (0.0, 0.0)
    };
    let z = r * r;
    let p = (((P[0] * z + P[1]) * z + P[2]) * z + P[3]) * z + P[4];
    let qq = ((((z + Q[0]) * z + Q[1]) * z + Q[2]) * z + Q[3]) * z + Q[4];
    let w = r * (z * p / qq) + r + more;
    (y0 + w).copysign(x)
}

/// The workpiece's speed along the path: `v_t` before `start` [m], `v_p` after
/// `start + span`, between them v_t + (v_p − v_t)·h(u), u = (s − start)/span,
/// h the quintic smoothstep u³(10 − 15u + 6u²) (dv/ds and d²v/ds² zero at
/// both ends).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpeedLaw {
    pub v_t: f64,
    pub v_p: f64,
    pub start: f64,
    pub span: f64,
}

impl SpeedLaw {
    /// Checked: finite, speeds > 0, span > 0.
    pub fn new(v_t: f64, v_p: f64, start: f64, span: f64) -> Result<Self, TransferError> {
        InvalidInput::check_finite("law", &[v_t, v_p, start, span])?;
        for (field, value) in [("v_t", v_t), ("v_p", v_p), ("span", span)] {
            if value <= 0.0 {
                return Err(InvalidInput::BadValue {
                    field,
                    value,
                    why: "must be > 0".into(),
                }
                .into());
            }
        }
        Ok(SpeedLaw {
            v_t,
            v_p,
            start,
            span,
        })
    }

    /// (v, dv/ds, d²v/ds²) at s.
    #[inline(always)]
    pub fn at(&self, s: f64) -> (f64, f64, f64) {
        let (start, span) = (self.start, self.span);
        let u = ((s - start) / span).clamp(0.0, 1.0);
        let inside = s > start && s < start + span;
        let h = u * u * u * (10.0 - 15.0 * u + 6.0 * u * u);
        let w = 1.0 - u;
        let (dh, ddh) = if inside {
            (
                30.0 * u * u * (w * w) / span,
                60.0 * u * w * (1.0 - 2.0 * u) / (span * span),
            )
        } else {
            (0.0, 0.0)
        };
        let dv = self.v_p - self.v_t;
        (self.v_t + dv * h, dv * dh, dv * ddh)
    }
}

/// Rows of [`kinematics_into`]'s output, in order.
pub const KINEMATICS: [&str; 8] = [
    "time",
    "speed",
    "normal",
    "tangential",
    "total",
    "normal_rate",
    "tangential_rate",
    "jerk",
];

/// Rows of [`kinematics_into`]'s output.
pub const N_KINEMATICS: usize = KINEMATICS.len();

/// (a_n, a_t, da_n/dt, da_t/dt) at speed v (dv, ddv its s-derivatives) on a
/// curve of curvature κ with rate dκ/ds; d/dt = v·d/ds. The jerk da/dt adds
/// the turning of the frame (dT/dt = v·κ·N, dN/dt = −v·κ·T): its components
/// are da_t/dt − a_n·v·κ along T and da_n/dt + a_t·v·κ along N.
#[inline(always)]
pub(super) fn parts(v: f64, dv: f64, ddv: f64, kappa: f64, rate: f64) -> [f64; 4] {
    let a_n = v * v * kappa;
    let a_t = v * dv;
    let an_rate = v * (2.0 * v * dv * kappa + v * v * rate);
    let at_rate = v * (dv * dv + v * ddv);
    [a_n, a_t, an_rate, at_rate]
}

/// The kinematics of the speed law `law` along a sampled path (arc length `s`
/// [m], non-decreasing; `kappa` [1/m] and its rate `rate` [1/m²]) into `out`
/// ([`N_KINEMATICS`] rows of n, see [`KINEMATICS`]): the time from the start
/// (trapezoid in 1/v over each interval, summed per block of [`BLOCK`]
/// points and the blocks' totals in order), speed, normal v²κ and tangential
/// v·dv/ds accelerations, |a|, their rates and the jerk |da/dt|.
pub fn kinematics_into(
    s: &[f64],
    kappa: &[f64],
    rate: &[f64],
    law: &SpeedLaw,
    out: &mut [f64],
    n_threads: Option<i64>,
) -> Result<(), TransferError> {
    let n = s.len();
    if kappa.len() != n || rate.len() != n {
        return Err(TransferError::BadLength {
            field: "curvature",
            got: kappa.len().min(rate.len()),
            want: "as many as s (curvature and curvature_rate)",
        });
    }
    if out.len() != N_KINEMATICS * n {
        return Err(TransferError::BadLength {
            field: "out",
            got: out.len(),
            want: "8 rows of len(s)",
        });
    }
    InvalidInput::check_finite("s", s)?;
    InvalidInput::check_finite("curvature", kappa)?;
    InvalidInput::check_finite("curvature_rate", rate)?;
    let threads = resolve_threads(n_threads)?;
    // The time at each block's first point: the blocks' sums of dt, in order.
    let totals = map_tasks((0..n.div_ceil(BLOCK)).collect(), threads, |b| {
        let (lo, hi) = (b * BLOCK, ((b + 1) * BLOCK + 1).min(n));
        let v: Vec<f64> = s[lo..hi].iter().map(|&s| law.at(s).0).collect();
        let mut acc = 0.0;
        for j in 1..v.len() {
            acc += (s[lo + j] - s[lo + j - 1]) / (0.5 * (v[j] + v[j - 1]));
        }
        acc
    })?;
    let mut offsets = Vec::with_capacity(totals.len());
    let mut t = 0.0;
    for total in totals {
        offsets.push(t);
        t += total;
    }
    let mut rows: Vec<&mut [f64]> = out.chunks_mut(n.max(1)).collect();
    let mut blocks: Vec<Vec<&mut [f64]>> = Vec::with_capacity(offsets.len());
    for _ in 0..offsets.len() {
        blocks.push(Vec::with_capacity(N_KINEMATICS));
    }
    for row in rows.iter_mut() {
        for (b, chunk) in std::mem::take(row).chunks_mut(BLOCK).enumerate() {
            blocks[b].push(chunk);
        }
    }
    let tasks: Vec<_> = blocks.into_iter().zip(offsets).enumerate().collect();
    run_tasks(tasks, threads, |(b, (rows, t0))| {
        let (lo, hi) = (b * BLOCK, (b * BLOCK + rows[0].len()));
        pulp::Arch::new().dispatch(Motion {
            s: &s[lo..hi],
            kappa: &kappa[lo..hi],
            rate: &rate[lo..hi],
            law,
            t0,
            rows,
        })
    })
}

/// One block of [`kinematics_into`] in lane loops under `pulp`'s dispatch.
struct Motion<'a, 'b> {
    s: &'a [f64],
    kappa: &'a [f64],
    rate: &'a [f64],
    law: &'a SpeedLaw,
    t0: f64,
    rows: Vec<&'b mut [f64]>,
}

impl pulp::WithSimd for Motion<'_, '_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        let Motion {
            s,
            kappa,
            rate,
            law,
            t0,
            mut rows,
        } = self;
        let len = s.len();
        let mut dvs = [0.0; BLOCK];
        let mut ddvs = [0.0; BLOCK];
        let (dvs, ddvs) = (&mut dvs[..len], &mut ddvs[..len]);
        let [time, speed, normal, tangential, total, normal_rate, tangential_rate, jerk] =
            &mut rows[..]
        else {
            return;
        };
        for j in 0..len {
            (speed[j], dvs[j], ddvs[j]) = law.at(s[j]);
        }
        for j in 0..len {
            let [a_n, a_t, an_rate, at_rate] = parts(speed[j], dvs[j], ddvs[j], kappa[j], rate[j]);
            let (v, k) = (speed[j], kappa[j]);
            normal[j] = a_n;
            tangential[j] = a_t;
            normal_rate[j] = an_rate;
            tangential_rate[j] = at_rate;
            // The jerk's components, kept in the scratch rows until its norm.
            dvs[j] = at_rate - a_n * v * k;
            ddvs[j] = an_rate + a_t * v * k;
        }
        super::norms(normal, tangential, total);
        super::norms(dvs, ddvs, jerk);
        time[0] = t0;
        for j in 1..len {
            time[j] = (s[j] - s[j - 1]) / (0.5 * (speed[j] + speed[j - 1]));
        }
        for j in 1..len {
            time[j] += time[j - 1];
        }
    }
}
