//! The statistics at many speeds from the structure T = u·a + b, u = ω² (issue 37).
//!
//! At each sample θ_k every quantity the statistics read is linear in u:
//! T_k = u·a_k + b_k, d_k = T_k − T̄ = u·ã_k + b̃_k (ã, b̃ the parts less their
//! means) and the trapezoid energy E_k = Σ_{j<k} h(d_j + d_{j+1})/2 =
//! u·Ea_k + Eb_k. So, with O(N) work once and O(log N) per speed:
//!
//! - the mean is u·ā + b̄;
//! - the RMS: (1/2π)∮T² = T̄² + (1/2π)∮d², the second a quadratic in u whose
//!   three coefficients are the step sums h(d₀² + d₀d₁ + d₁²)/3 of the parts
//!   (centred, so no cancellation against T̄²);
//! - the peak and lowest torque are the upper and lower envelopes over k of the
//!   lines u ↦ u·a_k + b_k: the upper and lower convex hulls of the points
//!   (a_k, b_k), searched by the slope of each speed;
//! - the largest and smallest sampled energy likewise from the hulls of
//!   (Ea_k, Eb_k), k = 0..N (E_0 = 0);
//! - E's extrema inside a step (where d crosses 0; the kernel's exact ΔE for the
//!   piecewise-linear torque): step k holds a local maximum for the speeds where
//!   d_k(u) ≥ 0 > d_{k+1}(u) and a local minimum where d_k(u) < 0 ≤ d_{k+1}(u),
//!   each an interval of u. The speeds are taken in increasing order and each
//!   step's interval enters and leaves an active list: a speed evaluates only
//!   the crossings d has at it (a few per turn for a real torque).
//!
//! The cost is O(N log N + S log S + Σ crossings) against the sampled kernel's
//! O(N·S); the values are the sampled kernel's up to rounding (tested).

use std::f64::consts::TAU;

use rayon::prelude::*;

use super::N_STATS;

/// The upper convex hull of points (x, y), for max_k (u·x_k + y_k) at u ≥ 0.
#[derive(Debug, Clone)]
struct UpperHull {
    x: Vec<f64>,
    y: Vec<f64>,
}

impl UpperHull {
    /// The hull of the points (x_k, y_k).
    fn new(x: &[f64], y: &[f64]) -> UpperHull {
        let mut idx: Vec<usize> = (0..x.len()).collect();
        idx.sort_unstable_by(|&i, &j| x[i].total_cmp(&x[j]).then(y[i].total_cmp(&y[j])));
        let (mut hx, mut hy): (Vec<f64>, Vec<f64>) = (Vec::new(), Vec::new());
        for &i in &idx {
            let (px, py) = (x[i], y[i]);
            // Equal x: the later (higher y) replaces.
            if hx.last() == Some(&px) {
                hx.pop();
                hy.pop();
            }
            while hx.len() >= 2 {
                let m = hx.len();
                let (ax, ay, bx, by) = (hx[m - 2], hy[m - 2], hx[m - 1], hy[m - 1]);
                // b is not above the chord a → p: drop it.
                if (bx - ax) * (py - ay) - (by - ay) * (px - ax) >= 0.0 {
                    hx.pop();
                    hy.pop();
                } else {
                    break;
                }
            }
            hx.push(px);
            hy.push(py);
        }
        UpperHull { x: hx, y: hy }
    }

    /// The vertex maximising u·x + y: the first whose next edge does not
    /// gain, Δy + u·Δx ≤ 0 (the edges' slopes decrease).
    #[inline]
    fn argmax(&self, u: f64) -> usize {
        let (mut lo, mut hi) = (0, self.x.len() - 1);
        while lo < hi {
            let mid = (lo + hi) / 2;
            let gain = (self.y[mid + 1] - self.y[mid]) + u * (self.x[mid + 1] - self.x[mid]);
            if gain > 0.0 {
                lo = mid + 1;
            } else {
                hi = mid;
            }
        }
        lo
    }

    #[inline]
    fn max(&self, u: f64) -> f64 {
        let i = self.argmax(u);
        u * self.x[i] + self.y[i]
    }
}

/// max and min over k of u·x_k + y_k.
#[derive(Debug, Clone)]
struct Envelope {
    upper: UpperHull,
    /// The upper hull of (−x, −y): min = −max.
    lower: UpperHull,
}

impl Envelope {
    fn new(x: &[f64], y: &[f64]) -> Envelope {
        let (nx, ny): (Vec<f64>, Vec<f64>) = x.iter().zip(y).map(|(&a, &b)| (-a, -b)).unzip();
        Envelope {
            upper: UpperHull::new(x, y),
            lower: UpperHull::new(&nx, &ny),
        }
    }

    #[inline]
    fn max(&self, u: f64) -> f64 {
        self.upper.max(u)
    }

    #[inline]
    fn min(&self, u: f64) -> f64 {
        let i = self.lower.argmax(u);
        // −(u·(−x) + (−y)) = u·x + y: the same rounding as the samples'.
        u * -self.lower.x[i] + -self.lower.y[i]
    }
}

/// {u > 0 : p·u + q ≥ 0} (`strict`: > 0) as [lo, hi] (lo > hi if empty).
fn half_line(p: f64, q: f64, strict: bool) -> (f64, f64) {
    let ok = |v: f64| if strict { v > 0.0 } else { v >= 0.0 };
    if p == 0.0 {
        return if ok(q) {
            (0.0, f64::INFINITY)
        } else {
            (1.0, 0.0)
        };
    }
    let root = -q / p;
    if p > 0.0 {
        (root.max(0.0), f64::INFINITY)
    } else {
        (0.0, root)
    }
}

/// A step whose E has an interior extremum for u in [lo, hi].
#[derive(Debug, Clone, Copy)]
struct Crossing {
    lo: f64,
    hi: f64,
    step: usize,
}

/// The steps' crossing intervals, by increasing lo: local maxima (d_k ≥ 0 >
/// d_{k+1}) if `max`, else local minima (d_k < 0 ≤ d_{k+1}). The endpoints are
/// widened by a relative 1e-9 (the sign is checked again per speed, and E's
/// interior extremum tends to the sample's at an endpoint: nothing jumps).
fn crossings(da: &[f64], db: &[f64], max: bool) -> Vec<Crossing> {
    let n = da.len();
    let mut out = Vec::new();
    for k in 0..n {
        let j = (k + 1) % n;
        // max: d_k ≥ 0 and −d_{k+1} > 0; min: −d_k > 0 and d_{k+1} ≥ 0.
        let (s0, s1) = if max { (1.0, -1.0) } else { (-1.0, 1.0) };
        let (l0, h0) = half_line(s0 * da[k], s0 * db[k], !max);
        let (l1, h1) = half_line(s1 * da[j], s1 * db[j], max);
        let (lo, hi) = (l0.max(l1), h0.min(h1));
        if lo <= hi {
            out.push(Crossing {
                lo: lo * (1.0 - 1e-9),
                hi: hi * (1.0 + 1e-9),
                step: k,
            });
        }
    }
    out.sort_unstable_by(|p, q| p.lo.total_cmp(&q.lo));
    out
}

/// Everything the statistics need, computed once for a torque.
#[derive(Debug, Clone)]
pub(super) struct Prepared {
    h: f64,
    mean_a: f64,
    mean_b: f64,
    /// d's parts ã, b̃ per sample.
    da: Vec<f64>,
    db: Vec<f64>,
    /// E's parts per sample, E_0 = 0 .. E_N.
    ea: Vec<f64>,
    eb: Vec<f64>,
    /// (1/2π)∮d² = q2·u² + q1·u + q0.
    q: [f64; 3],
    torque: Envelope,
    energy: Envelope,
    maxima: Vec<Crossing>,
    minima: Vec<Crossing>,
}

impl Prepared {
    pub(super) fn new(a: &[f64], b: &[f64]) -> Prepared {
        let n = a.len();
        let h = TAU / n as f64;
        let mean_a = a.iter().sum::<f64>() / n as f64;
        let mean_b = b.iter().sum::<f64>() / n as f64;
        let da: Vec<f64> = a.iter().map(|v| v - mean_a).collect();
        let db: Vec<f64> = b.iter().map(|v| v - mean_b).collect();
        let (mut ea, mut eb) = (vec![0.0; n + 1], vec![0.0; n + 1]);
        let mut q = [0.0; 3];
        for k in 0..n {
            let j = (k + 1) % n;
            let (a0, a1, b0, b1) = (da[k], da[j], db[k], db[j]);
            ea[k + 1] = ea[k] + 0.5 * (a0 + a1) * h;
            eb[k + 1] = eb[k] + 0.5 * (b0 + b1) * h;
            q[2] += a0 * a0 + a0 * a1 + a1 * a1;
            q[1] += 2.0 * a0 * b0 + a0 * b1 + a1 * b0 + 2.0 * a1 * b1;
            q[0] += b0 * b0 + b0 * b1 + b1 * b1;
        }
        // h/3 per step, over 2π: 1/(3N).
        for c in &mut q {
            *c /= 3.0 * n as f64;
        }
        Prepared {
            h,
            mean_a,
            mean_b,
            torque: Envelope::new(a, b),
            energy: Envelope::new(&ea, &eb),
            maxima: crossings(&da, &db, true),
            minima: crossings(&da, &db, false),
            da,
            db,
            ea,
            eb,
            q,
        }
    }

    /// E's interior extremum in step k at u, if d changes sign there as `max`
    /// asks (the sampled kernel's formula).
    #[inline]
    fn interior(&self, k: usize, u: f64, max: bool) -> Option<f64> {
        let j = (k + 1) % self.da.len();
        let d0 = u * self.da[k] + self.db[k];
        let d1 = u * self.da[j] + self.db[j];
        let sign = if max {
            d0 >= 0.0 && d1 < 0.0
        } else {
            d0 < 0.0 && d1 >= 0.0
        };
        sign.then(|| {
            let e = u * self.ea[k] + self.eb[k];
            let f = d0 / (d0 - d1);
            e + 0.5 * d0 * f * self.h
        })
    }

    /// The statistics at the speeds `w` [rad/s] taken in the order `order`
    /// (increasing ω), each row written through `put(index, row)`.
    pub(super) fn run(&self, w: &[f64], order: &[usize], delta: f64) -> Vec<[f64; N_STATS]> {
        let mut rows = Vec::with_capacity(order.len());
        // Active crossings: (hi, step); the next to enter at `next_*`.
        let (mut act_max, mut act_min): (Vec<Crossing>, Vec<Crossing>) = (Vec::new(), Vec::new());
        let (mut next_max, mut next_min) = (0, 0);
        for &i in order {
            let wi = w[i];
            let u = wi * wi;
            let mean = u * self.mean_a + self.mean_b;
            let var = ((self.q[2] * u + self.q[1]) * u + self.q[0]).max(0.0);
            let rms = (mean * mean + var).sqrt();
            let mut e_max = self.energy.max(u);
            let mut e_min = self.energy.min(u);
            for (active, next, list, max) in [
                (&mut act_max, &mut next_max, &self.maxima, true),
                (&mut act_min, &mut next_min, &self.minima, false),
            ] {
                while *next < list.len() && list[*next].lo <= u {
                    active.push(list[*next]);
                    *next += 1;
                }
                active.retain(|c| c.hi >= u);
                for c in active.iter() {
                    if let Some(ex) = self.interior(c.step, u, max) {
                        if max {
                            e_max = e_max.max(ex);
                        } else {
                            e_min = e_min.min(ex);
                        }
                    }
                }
            }
            let de = e_max - e_min;
            rows.push([
                mean,
                self.torque.max(u),
                self.torque.min(u),
                rms,
                de,
                de / (u * delta),
                mean * wi,
            ]);
        }
        rows
    }
}

/// The statistics of T = ω²a + b at the speeds `omegas` into `out` (row-major
/// (S, N_STATS)); the inputs checked by the caller.
pub(super) fn stats_envelope(
    a: &[f64],
    b: &[f64],
    omegas: &[f64],
    delta: f64,
    out: &mut [f64],
    threads: usize,
) {
    let prep = Prepared::new(a, b);
    let mut order: Vec<usize> = (0..omegas.len()).collect();
    order.sort_unstable_by(|&i, &j| omegas[i].total_cmp(&omegas[j]));
    // Blocks of increasing speed, one sweep each (each block starts its active
    // lists from scratch: the crossings entered before it that still hold).
    let blocks = if omegas.len() < 4096 {
        1
    } else {
        threads.max(1)
    };
    let size = order.len().div_ceil(blocks).max(1);
    let parts: Vec<Vec<[f64; N_STATS]>> = order
        .par_chunks(size)
        .map(|ix| prep.run(omegas, ix, delta))
        .collect();
    for (ix, rows) in order.chunks(size).zip(parts) {
        for (&i, row) in ix.iter().zip(rows) {
            out[i * N_STATS..(i + 1) * N_STATS].copy_from_slice(&row);
        }
    }
}
