//! The walk back in time from the slider's bottom dead centre (BDC) over the
//! sampled pin path, to where it crosses S_p last (the first contact in time):
//! its points, the passes over stretches where nothing can happen (far above
//! S_p, and the approach from BDC while the slider still descends), and the
//! tests' switches that turn those passes off to check them against the
//! point-by-point walk. `criteria` runs it for every design.

use std::f64::consts::TAU;

use super::criteria::wrap;
use super::kinematics::Table;

#[cfg(test)]
thread_local! {
    /// Tests only: false runs the first pass of the walk point by point (no
    /// [`Walk::skip_above`]), the reference the skipping pass must equal.
    pub(super) static SKIP_WALK: std::cell::Cell<bool> = const { std::cell::Cell::new(true) };
}

/// Whether the walk's first pass passes over the stretches far above S_p.
#[inline]
pub(super) fn skips_walk() -> bool {
    #[cfg(test)]
    return SKIP_WALK.with(|c| c.get());
    #[cfg(not(test))]
    true
}

#[cfg(test)]
thread_local! {
    /// Tests only: false leaves out [`Walk::rest_above`] (the first pass then
    /// skips its way to TDC) and [`Walk::skip_below`] (main's walk), to time
    /// the two.
    pub(super) static SHORTCUTS: std::cell::Cell<bool> = const { std::cell::Cell::new(true) };
}

/// Whether the walk's first pass ends once the rest of the way to TDC is
/// known to be far above S_p, and passes over the approach from BDC to S_p
/// where nothing can happen.
#[inline]
pub(super) fn shortcuts() -> bool {
    #[cfg(test)]
    return SHORTCUTS.with(|c| c.get());
    #[cfg(not(test))]
    true
}

/// One point of the walk back from BDC: θ, S = y − y_B, y' and −y''.
#[derive(Debug, Clone, Copy)]
pub(super) struct WalkPoint {
    pub(super) th: f64,
    pub(super) s: f64,
    pub(super) dy: f64,
    pub(super) g: f64,
}

/// Where the walk back from BDC crosses S_p last (the first contact in time).
pub(super) struct Contact {
    /// The walk's step at the crossing's point above S_p.
    pub(super) step: usize,
    /// (θ, S) of the bottom of a dip between two samples above S_p, the
    /// crossing's other end; None: the next point of the walk.
    pub(super) dip: Option<(f64, f64)>,
    /// The highest S between the crossing and BDC (refined peaks included).
    pub(super) s_max: f64,
}

/// The sampled rows the walk reads.
pub(super) struct WalkPoints<'a> {
    pub(super) ys: &'a [f64],
    pub(super) dys: &'a [f64],
    pub(super) ddys: &'a [f64],
    pub(super) y_b: f64,
    pub(super) s_n: f64,
    pub(super) ddy_t: f64,
}

/// The walk back in time from BDC (θ decreasing) over the samples, with TDC
/// as a point of its own; it ends at TDC.
#[derive(Debug, Clone)]
pub(super) struct Walk {
    pub(super) j: usize,
    pub(super) m: usize,
    pub(super) h: f64,
    pub(super) theta_j: f64,
    pub(super) th_top: f64,
    pub(super) top_pending: bool,
}

impl Walk {
    pub(super) fn new(table: &Table, j_b: usize, th_b: f64, th_t: f64) -> Walk {
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
    pub(super) fn done(&self) -> bool {
        !self.top_pending
    }

    /// The next point back: TDC if it lies before the next sample.
    #[inline]
    pub(super) fn next(&mut self, p: &WalkPoints<'_>) -> Option<WalkPoint> {
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

    /// True if every sample the walk can still visit before TDC has S ≥ `far`:
    /// checked on the samples up to two beyond the estimate of TDC's place (a
    /// superset of those visited, as the walk's angles are the estimate's to
    /// far better than a step), in two vectorised passes over the rows and
    /// without the walk's dependent chain of angles. False if TDC is not
    /// ahead, or any of those samples is below `far` (or NaN).
    pub(super) fn rest_above(&self, p: &WalkPoints<'_>, far: f64) -> bool {
        if !self.top_pending {
            return false;
        }
        let ahead = (self.theta_j - self.th_top) / self.h;
        if ahead.is_nan() || ahead >= self.m as f64 {
            return false;
        }
        let n = if ahead < 0.0 {
            0
        } else {
            (ahead as usize + 2).min(self.m)
        };
        let y_b = p.y_b;
        let above = |ys: &[f64]| ys.iter().fold(true, |a, &y| a & (y - y_b >= far));
        // Samples j, j − 1, …, j − n + 1 on the turn.
        let j = self.j;
        if n <= j + 1 {
            above(&p.ys[j + 1 - n..=j])
        } else {
            above(&p.ys[..=j]) && above(&p.ys[self.m - (n - j - 1)..self.m])
        }
    }

    /// Passes over at most `limit` samples ahead while each has S < `s_p` and
    /// y' ≤ 0 (and TDC does not come first): how many, the highest S among
    /// them and the last one as a point (None if none), as
    /// [`skip_above`](Self::skip_above).
    #[inline]
    pub(super) fn skip_below(
        &mut self,
        p: &WalkPoints<'_>,
        s_p: f64,
        limit: usize,
    ) -> (usize, f64, Option<WalkPoint>) {
        // The walk's place and angle in locals (registers) through the loop,
        // not in `self` (stored and reloaded every step: the chain of angles
        // then waits on the store); the same steps, the same bits.
        let (mut j, mut th) = (self.j, self.theta_j);
        let (m, h, top, th_top) = (self.m, self.h, self.top_pending, self.th_top);
        let (ys, dys, y_b) = (p.ys, p.dys, p.y_b);
        let (mut k, mut high, mut last) = (0, f64::NEG_INFINITY, None);
        while k < limit && !(top && th_top >= th) {
            let s = ys[j] - y_b;
            // (False for NaN too.)
            if !(s < s_p && dys[j] <= 0.0) {
                break;
            }
            high = if s > high { s } else { high };
            last = Some((j, th));
            j = if j == 0 { m - 1 } else { j - 1 };
            th -= h;
            k += 1;
        }
        (self.j, self.theta_j) = (j, th);
        let last = last.map(|(j, th)| WalkPoint {
            th,
            s: p.ys[j] - p.y_b,
            dy: p.dys[j],
            g: -p.ddys[j],
        });
        (k, high, last)
    }

    /// Passes over at most `limit` samples ahead while each has S ≥ `far` (and
    /// TDC does not come first): how many, the highest S among them and the
    /// last one as a point (None if none). The samples and their angles are
    /// [`next`](Self::next)'s, step for step.
    #[inline]
    pub(super) fn skip_above(
        &mut self,
        p: &WalkPoints<'_>,
        far: f64,
        limit: usize,
    ) -> (usize, f64, Option<WalkPoint>) {
        // (Locals through the loop, as in `skip_below`.)
        let (mut j, mut th) = (self.j, self.theta_j);
        let (m, h, top, th_top) = (self.m, self.h, self.top_pending, self.th_top);
        let (ys, y_b) = (p.ys, p.y_b);
        let (mut k, mut high, mut last) = (0, f64::NEG_INFINITY, None);
        while k < limit && !(top && th_top >= th) {
            let s = ys[j] - y_b;
            if s < far || s.is_nan() {
                break;
            }
            high = high.max(s);
            last = Some((j, th));
            j = if j == 0 { m - 1 } else { j - 1 };
            th -= h;
            k += 1;
        }
        (self.j, self.theta_j) = (j, th);
        let last = last.map(|(j, th)| WalkPoint {
            th,
            s: p.ys[j] - p.y_b,
            dy: p.dys[j],
            g: -p.ddys[j],
        });
        (k, high, last)
    }
}
