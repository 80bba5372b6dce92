//! The Hertz stress bound of one segment at many speeds, fast and by the same
//! rule as every other bound (see `bounds`): the scan's trial angles
//! 2π·0.7^j are the same at every speed, and at a fixed angle the segment's
//! geometry does not depend on the speed, so each trial angle's grid of nodes
//! is worked out once and the scan at a speed is arithmetic: the generalised
//! force is Q = a ω² + b at each node and σ_H²/[σ_H]² = |Q|·c on the flank Q
//! loads. The crossing is then found in a tight bracket around the root of the
//! previous speed (speeds in increasing order), widened until it brackets, by
//! Brent's root on the exact worst value (grid and Brent's maximiser); without
//! such a guess, on the scan's bracket.

use std::f64::consts::TAU;

use super::bounds::{CUT, FLOOR, NEAR_UNDERCUT, STEP};
use super::contact::Loads;
use super::follower::Cam;
use super::search::{brent_zero, refine, GRID};

/// A node of a trial angle's grid: Q = `a`·ω² + `b`; σ²/[σ]² = Q·`c_in` (Q ≥ 0)
/// or −Q·`c_out` (Q < 0; 0 with spring closure: separated).
#[derive(Debug, Clone, Copy)]
struct Node {
    a: f64,
    b: f64,
    c_in: f64,
    c_out: f64,
}

/// The scan's trial angles [rad] with their nodes.
pub(super) struct ScanCache {
    beta: Vec<f64>,
    nodes: Vec<Vec<Node>>,
    /// The law's values at the grid's points (they do not depend on the angle).
    law: [[f64; 4]; GRID],
}

impl Cam {
    /// The nodes of segment `k` at trial angle `beta`: the grid's, and where the
    /// curvature ratio passes [`NEAR_UNDERCUT`] one more at its peak (the stress's
    /// narrow peak near an undercut); all NaN (violated at every speed) where
    /// the profile is undercut (see `stress_ratio`).
    fn stress_nodes(
        &self,
        k: usize,
        beta: f64,
        loads: &Loads,
        hertz: (f64, f64),
        limit: f64,
    ) -> Vec<Node> {
        let load = loads.segment_loads[k];
        let h = 1.0 / (GRID - 1) as f64;
        let scale = std::f64::consts::PI * hertz.0 * hertz.1 * limit * limit;
        let node = |x: f64| {
            let sv = self.program().trial(k, x, beta);
            let geo = self.lean_row(sv);
            let lc = self.lever_times(geo[10]);
            let c = |n: f64| {
                if lc > 0.0 {
                    self.curvature(&geo, n) / (scale * lc)
                } else {
                    f64::INFINITY
                }
            };
            let nd = Node {
                a: loads.mass * sv[2],
                b: loads.spring_rate * sv[0] + loads.preload + load,
                c_in: c(1.0),
                c_out: if self.groove() { c(-1.0) } else { 0.0 },
            };
            (nd, self.undercut_of(&geo))
        };
        let mut out = Vec::with_capacity(GRID + 1);
        let mut vu = [0.0f64; GRID];
        for (i, u) in vu.iter_mut().enumerate() {
            let (nd, v) = node(i as f64 * h);
            out.push(nd);
            *u = v;
        }
        if vu.iter().any(|v| v.is_nan() || *v >= NEAR_UNDERCUT) {
            let (worst, x) = refine(&|x| node(x).1, &vu, f64::NEG_INFINITY);
            if worst.is_nan() || worst >= 1.0 {
                let bad = Node {
                    a: 0.0,
                    b: 0.0,
                    c_in: f64::NAN,
                    c_out: f64::NAN,
                };
                return vec![bad];
            }
            out.push(node(x).0);
        }
        out
    }

    /// The scan's trial angles and their nodes for segment `k`.
    pub(super) fn stress_cache(
        &self,
        k: usize,
        loads: &Loads,
        hertz: (f64, f64),
        limit: f64,
    ) -> ScanCache {
        let mut beta = vec![TAU];
        while beta[beta.len() - 1] * STEP >= FLOOR {
            beta.push(beta[beta.len() - 1] * STEP);
        }
        let nodes = beta
            .iter()
            .map(|&b| self.stress_nodes(k, b, loads, hertz, limit))
            .collect();
        let h = 1.0 / (GRID - 1) as f64;
        let law = std::array::from_fn(|i| self.program().law_at(k, i as f64 * h));
        ScanCache { beta, nodes, law }
    }

    /// The smallest angle [rad] of segment `k` for the stress at each speed of
    /// `omegas` [rad/s], into `out` (same order).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn stress_bounds(
        &self,
        k: usize,
        cache: &ScanCache,
        omegas: &[f64],
        loads: &Loads,
        hertz: (f64, f64),
        limit: f64,
        out: &mut [f64],
    ) {
        let mut order: Vec<usize> = (0..omegas.len()).collect();
        order.sort_by(|&i, &j| omegas[i].total_cmp(&omegas[j]));
        let exact =
            |b: f64, w: f64| self.stress_ratio(k, b, w, loads, hertz, limit, Some(&cache.law));
        // The last two roots (speed, angle): the next guess is their line's.
        let mut last: Option<f64> = None;
        let mut prev: Option<(f64, f64)> = None;
        let mut prev2: Option<(f64, f64)> = None;
        for i in order {
            let w = omegas[i];
            let w2 = w * w;
            // The scan: the first trial angle (from 2π down) that is violated.
            let mut hit = None;
            for (j, nodes) in cache.nodes.iter().enumerate() {
                let mut g: f64 = 0.0;
                for nd in nodes {
                    let q = nd.a * w2 + nd.b;
                    let r = if q >= 0.0 { q * nd.c_in } else { -q * nd.c_out };
                    if r.is_nan() {
                        g = f64::INFINITY;
                        break;
                    }
                    g = g.max(r);
                }
                let g = g.sqrt();
                let violated = g > 1.0
                    || (g >= CUT && {
                        let e = exact(cache.beta[j], w);
                        e.is_nan() || e > 1.0
                    });
                if violated {
                    hit = Some(j);
                    break;
                }
            }
            let root = match hit {
                None => 0.0,
                Some(0) => f64::NAN,
                Some(j) => {
                    let (lo, hi) = (cache.beta[j], cache.beta[j - 1]);
                    let guess = match (prev2, prev) {
                        (Some((w0, b0)), Some((w1, b1))) if w1 > w0 => {
                            Some(b1 + (b1 - b0) * (w - w1) / (w1 - w0))
                        }
                        _ => last,
                    };
                    let step = match (guess, last) {
                        (Some(g), Some(l)) => (1e-3 * (g - l).abs() / l).max(1e-9),
                        _ => 1e-7,
                    };
                    self.bracketed(lo, hi, guess, step, |b| exact(b, w))
                }
            };
            out[i] = root;
            if root.is_finite() && root > 0.0 {
                last = Some(root);
                (prev2, prev) = (prev, Some((w, root)));
            }
        }
    }

    /// The crossing of `f` = 1 in [lo, hi] (violated at lo, admissible at hi):
    /// around `guess` first, in a bracket of relative half-width `step` widened
    /// eightfold until it brackets.
    fn bracketed(
        &self,
        lo: f64,
        hi: f64,
        guess: Option<f64>,
        step: f64,
        f: impl Fn(f64) -> f64,
    ) -> f64 {
        let g = |b: f64| {
            let v = f(b);
            if v.is_nan() {
                f64::INFINITY
            } else {
                v - 1.0
            }
        };
        let solve = |a: f64, b: f64, fa: f64, fb: f64| {
            if fa.is_finite() {
                brent_zero(g, a, b, fa, fb, 0.0, 1e-13)
            } else {
                // Brent needs finite values: bisect geometrically to a finite one.
                let (mut a, mut b, mut fa, mut fb) = (a, b, fa, fb);
                for _ in 0..200 {
                    if fa.is_finite() || b - a <= 1e-15 * b {
                        break;
                    }
                    let m = (a * b).sqrt();
                    let fm = g(m);
                    if fm <= 0.0 {
                        (b, fb) = (m, fm);
                    } else {
                        (a, fa) = (m, fm);
                    }
                }
                if fa.is_finite() {
                    brent_zero(g, a, b, fa, fb, 0.0, 1e-13)
                } else {
                    b
                }
            }
        };
        if let Some(x) = guess.filter(|x| *x > lo && *x < hi) {
            let fx = g(x);
            let mut d = step;
            if fx > 0.0 {
                // Violated at the guess: the crossing is above it.
                let (mut a, mut fa) = (x, fx);
                loop {
                    let b = (x * (1.0 + d)).min(hi);
                    let fb = g(b);
                    if fb <= 0.0 {
                        return solve(a, b, fa, fb);
                    }
                    if b >= hi {
                        break;
                    }
                    (a, fa) = (b, fb);
                    d *= 8.0;
                }
            } else {
                let (mut b, mut fb) = (x, fx);
                loop {
                    let a = (x * (1.0 - d)).max(lo);
                    let fa = g(a);
                    if fa > 0.0 {
                        return solve(a, b, fa, fb);
                    }
                    if a <= lo {
                        break;
                    }
                    (b, fb) = (a, fa);
                    d = (d * 8.0).min(0.5);
                }
            }
        }
        let (flo, fhi) = (g(lo), g(hi));
        if fhi > 0.0 {
            // The scan took hi as admissible from its grid; its exact value says
            // otherwise (a peak between nodes): the general rule decides.
            return super::bounds::last_crossing(&f);
        }
        solve(lo, hi, flo, fhi)
    }
}
