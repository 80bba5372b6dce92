//! The path's geometry in closed form for a pair of transition lengths
//! ([`geometry`]), the longest transitions a gap allows ([`longest`]) and the
//! peak jerk of many candidate lengths at once ([`peak_jerk`]).

use super::path::{parts, SpeedLaw};
use super::quintic::{coefficients, curvature, Quintic};
use super::{map_tasks, norms, TransferError};
use crate::input::InvalidInput;
use crate::parallel::resolve_threads;

/// The guide for transition lengths (x2_t, x2_p) between circles of radii
/// (R_t, R_p) whose centres are `d` apart, the transport centre at the origin
/// and the process one on the +x axis (counter-clockwise transport).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Geometry {
    /// Each smooth transition's line in its frame: y = k·x + b.
    pub k: [f64; 2],
    pub b: [f64; 2],
    /// The two shifted circles leave room for the common tangent.
    pub feasible: bool,
    /// Length of the straight segment [m] (−∞ when not feasible; negative when
    /// the transitions overlap).
    pub straight: f64,
}

#[inline(always)]
fn rot(v: [f64; 2], angle: f64) -> [f64; 2] {
    let (s, c) = (angle.sin(), angle.cos());
    [c * v[0] - s * v[1], s * v[0] + c * v[1]]
}

/// An overlap of the transitions up to this times the centre distance is
/// rounding, not an overlap: the straight counts as 0 m (`TransferPath` takes
/// the same rule). The straight is not monotone in x2 at the ulp: a candidate
/// one ulp shorter than the longest that fits had −1.6e-16 m, and its jerk was inf.
pub const STRAIGHT_RTOL: f64 = 1e-12;

/// The geometry, the operations in the Python layer's order: smooth lines
/// k = x2/(2R), b = −3·x2²/(20R), their distances from the centres, the
/// internal common tangent's direction u at ψ = asin(span/d), each transition's
/// frame turned by atan(k) from it, its end B on the line, the straight B_t→B_p
/// along u.
pub fn geometry(r: [f64; 2], d: f64, x2: [f64; 2]) -> Geometry {
    let mut k = [0.0; 2];
    let mut b = [0.0; 2];
    let mut dist = [0.0; 2];
    for i in 0..2 {
        k[i] = x2[i] / (2.0 * r[i]);
        b[i] = -3.0 * (x2[i] * x2[i]) / (20.0 * r[i]);
        dist[i] = (r[i] - b[i]) / (1.0 + k[i] * k[i]).sqrt();
    }
    let span = dist[0] + dist[1];
    let feasible = span <= d;
    let psi = (span / d).min(1.0).asin();
    let u = rot([1.0, 0.0], psi);
    let centres = [[0.0, 0.0], [d, 0.0]];
    let mut ends = [[0.0; 2]; 2];
    for i in 0..2 {
        let dir = if i == 0 { u } else { [-u[0], -u[1]] };
        let t = rot(dir, -k[i].atan());
        let left = [-t[1], t[0]];
        let origin = [
            centres[i][0] - r[i] * left[0],
            centres[i][1] - r[i] * left[1],
        ];
        let y_end = k[i] * x2[i] + b[i];
        ends[i] = [
            origin[0] + x2[i] * t[0] + y_end * left[0],
            origin[1] + x2[i] * t[1] + y_end * left[1],
        ];
    }
    let straight = (ends[1][0] - ends[0][0]) * u[0] + (ends[1][1] - ends[0][1]) * u[1];
    Geometry {
        k,
        b,
        feasible,
        straight: if feasible {
            straight
        } else {
            f64::NEG_INFINITY
        },
    }
}

fn check_rotors(r: [f64; 2], d: f64) -> Result<(), TransferError> {
    InvalidInput::check_finite("radii", &r)?;
    for (field, value) in [("R_t", r[0]), ("R_p", r[1])] {
        if value <= 0.0 {
            return Err(InvalidInput::BadValue {
                field,
                value,
                why: "must be > 0 m (a pitch radius)".into(),
            }
            .into());
        }
    }
    if !(d.is_finite() && d > r[0] + r[1]) {
        return Err(InvalidInput::BadValue {
            field: "distance",
            value: d,
            why: "must be finite and above R_t + R_p (the centres' distance)".into(),
        }
        .into());
    }
    Ok(())
}

/// `num` points from `a` to `b` as numpy's `linspace` (the last exactly `b`).
fn linspace(a: f64, b: f64, num: usize) -> impl Iterator<Item = f64> {
    let step = (b - a) / (num - 1) as f64;
    (0..num).map(move |i| if i == num - 1 { b } else { i as f64 * step + a })
}

/// The longest transitions x2 = λ·`ratio` whose straight segment is not
/// negative, between circles `r` with centres `d` apart: λ on 257 geometric
/// points from 1e-9·d, then eight refinements on 65 even points of the last
/// bracket (as the Python layer). None when no candidate fits.
pub fn longest(r: [f64; 2], d: f64, ratio: [f64; 2]) -> Result<Option<[f64; 2]>, TransferError> {
    check_rotors(r, d)?;
    InvalidInput::check_finite("ratio", &ratio)?;
    if ratio.iter().any(|&v| v <= 0.0) {
        return Err(InvalidInput::BadValue {
            field: "ratio",
            value: ratio[0].min(ratio[1]),
            why: "must be > 0 (the transitions' proportions)".into(),
        }
        .into());
    }
    let fits = |lam: f64| geometry(r, d, [lam * ratio[0], lam * ratio[1]]).straight >= 0.0;
    let hi = 2.0 * (d.max(1e-300) * r[0].max(r[1])).sqrt() * 4.0;
    let (l0, l1) = ((1e-9 * d).log10(), hi.log10());
    let grid: Vec<f64> = linspace(l0, l1, 257)
        .enumerate()
        .map(|(i, e)| match i {
            0 => 1e-9 * d,
            256 => hi,
            _ => 10f64.powf(e),
        })
        .collect();
    let Some(last) = grid.iter().rposition(|&lam| fits(lam)) else {
        return Ok(None);
    };
    let (mut lo, mut hi) = (grid[last], grid[(last + 1).min(grid.len() - 1)]);
    for _ in 0..8 {
        let grid: Vec<f64> = linspace(lo, hi, 65).collect();
        if let Some(last) = grid.iter().rposition(|&lam| fits(lam)) {
            (lo, hi) = (grid[last], grid[(last + 1).min(grid.len() - 1)]);
        }
    }
    Ok(Some([lo * ratio[0], lo * ratio[1]]))
}

/// The peak jerk |da/dt| [m/s³] of each candidate transition length in `x2`
/// [m] (the same on both sides) between circles `r` with centres `d` apart,
/// for the speed law V_t = `speed[0]` → V_p = `speed[1]` between A and C, on
/// `m` even points of each transition (in x) and of the straight; arc lengths
/// by the trapezoid rule on those points (enough to place the speed law).
/// Infinite for a candidate whose transitions do not fit. Candidates run in
/// parallel on the pool of `n_threads`.
pub fn peak_jerk(
    r: [f64; 2],
    d: f64,
    x2: &[f64],
    speed: [f64; 2],
    m: usize,
    n_threads: Option<i64>,
) -> Result<Vec<f64>, TransferError> {
    check_rotors(r, d)?;
    InvalidInput::check_finite("x2", x2)?;
    if let Some(&bad) = x2.iter().find(|&&v| v <= 0.0) {
        return Err(InvalidInput::BadValue {
            field: "x2",
            value: bad,
            why: "must be > 0 m (a transition length)".into(),
        }
        .into());
    }
    SpeedLaw::new(speed[0], speed[1], 0.0, 1.0)?;
    if m < 2 {
        return Err(InvalidInput::BadValue {
            field: "n_points",
            value: m as f64,
            why: "must be ≥ 2".into(),
        }
        .into());
    }
    let threads = resolve_threads(n_threads)?;
    let one = |x: &f64| {
        pulp::Arch::new().dispatch(Candidate {
            r,
            d,
            x2: *x,
            speed,
            m,
        })
    };
    map_tasks(x2.iter().collect(), threads, one)
}

/// [`peak_jerk`] of one candidate: lane loops over each piece's points under
/// `pulp`'s dispatch (the widest vectors the processor has; the same
/// arithmetic on every instruction set).
pub(super) struct Candidate {
    pub(super) r: [f64; 2],
    pub(super) d: f64,
    pub(super) x2: f64,
    pub(super) speed: [f64; 2],
    pub(super) m: usize,
}

/// The largest value, NaN if any is.
#[inline(always)]
fn peak(values: &[f64]) -> f64 {
    let mut lanes = [f64::NEG_INFINITY; 8];
    let mut nan = false;
    let mut chunks = values.chunks_exact(8);
    for c in &mut chunks {
        for l in 0..8 {
            lanes[l] = lanes[l].max(c[l]);
            nan |= c[l].is_nan();
        }
    }
    for &v in chunks.remainder() {
        lanes[0] = lanes[0].max(v);
        nan |= v.is_nan();
    }
    if nan {
        f64::NAN
    } else {
        lanes.iter().fold(f64::NEG_INFINITY, |a, &b| a.max(b))
    }
}

impl pulp::WithSimd for Candidate {
    type Output = f64;

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> f64 {
        let Candidate { r, d, x2, speed, m } = self;
        let g = geometry(r, d, [x2, x2]);
        if !(g.feasible && g.straight >= -STRAIGHT_RTOL * d) {
            return f64::INFINITY;
        }
        let straight = g.straight.max(0.0);
        let step = 1.0 / (m - 1) as f64;
        let u: Vec<f64> = (0..m)
            .map(|j| if j == m - 1 { 1.0 } else { j as f64 * step })
            .collect();
        // Per side: κ, dκ/ds and the trapezoid arc length on x = x2·u.
        let mut kappa = [vec![0.0; m], vec![0.0; m]];
        let mut rate = [vec![0.0; m], vec![0.0; m]];
        let mut s_loc = [vec![0.0; m], vec![0.0; m]];
        let mut f = vec![0.0; m];
        let mut xs = vec![0.0; m];
        for side in 0..2 {
            let q = Quintic {
                c: coefficients(r[side], g.k[side], g.b[side], x2),
            };
            for (x, &u) in xs.iter_mut().zip(&u) {
                *x = x2 * u;
            }
            for j in 0..m {
                let [_, d1, d2, d3] = q.all(xs[j]);
                f[j] = (1.0 + d1 * d1).sqrt();
                (kappa[side][j], rate[side][j]) = curvature(d1, d2, d3, f[j]);
            }
            let s = &mut s_loc[side];
            for j in 1..m {
                s[j] = 0.5 * (f[j] + f[j - 1]) * (xs[j] - xs[j - 1]);
            }
            for j in 1..m {
                s[j] += s[j - 1];
            }
        }
        let lengths = [s_loc[0][m - 1], s_loc[1][m - 1]];
        let span = lengths[0] + lengths[1] + straight;
        let law = SpeedLaw {
            v_t: speed[0],
            v_p: speed[1],
            start: 0.0,
            span,
        };
        // The jerk's two components at each point of a piece, then its norm.
        let (mut ja, mut jb, mut jerk) = (vec![0.0; m], vec![0.0; m], vec![0.0; m]);
        let mut top = f64::NEG_INFINITY;
        let mut nan = false;
        let (mut sp, mut kp, mut dkp) = (vec![0.0; m], vec![0.0; m], vec![0.0; m]);
        for piece in 0..3 {
            match piece {
                0 => {
                    sp.copy_from_slice(&s_loc[0]);
                    kp.copy_from_slice(&kappa[0]);
                    dkp.copy_from_slice(&rate[0]);
                }
                1 => {
                    for (s, &u) in sp.iter_mut().zip(&u) {
                        *s = lengths[0] + straight * u;
                    }
                    kp.fill(0.0);
                    dkp.fill(0.0);
                }
                _ => {
                    // The process transition travelled backwards: s from its
                    // far end, κ negated.
                    for j in 0..m {
                        sp[j] = (span - lengths[1]) + (lengths[1] - s_loc[1][j]);
                        kp[j] = -kappa[1][j];
                    }
                    dkp.copy_from_slice(&rate[1]);
                }
            }
            for j in 0..m {
                let (k, dk) = (kp[j], dkp[j]);
                let (v, dv, ddv) = law.at(sp[j]);
                let [a_n, a_t, an_rate, at_rate] = parts(v, dv, ddv, k, dk);
                ja[j] = at_rate - a_n * v * k;
                jb[j] = an_rate + a_t * v * k;
            }
            norms(&ja, &jb, &mut jerk);
            let p = peak(&jerk);
            nan |= p.is_nan();
            top = top.max(p);
        }
        if nan {
            f64::NAN
        } else {
            top
        }
    }
}
