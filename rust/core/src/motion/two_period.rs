//! The two-period slider law of seed 003: a half law then a mirrored half law.

use super::fused::Fused;
use super::law::{par_chunks, par_fill, Lanes, Law, MotionError};

/// A pair of constants for each period (I, II).
type PerPeriod = [(f64, f64); 2];

/// The two-period law: Π1 = `stroke1` at α1 = `angle1`, Π2 = `stroke` at
/// α2 = `angle`.
#[derive(Debug, Clone, PartialEq)]
pub struct TwoPeriod {
    pub law1: Law,
    pub law2: Law,
    pub stroke1: f64,
    pub angle1: f64,
    pub stroke: f64,
    pub angle: f64,
}

impl TwoPeriod {
    /// Π^(order)(α) for α in [0, α2], order 0..=3.
    pub fn at(&self, alpha: f64, order: usize) -> f64 {
        self.evaluator(order.min(3))(alpha)
    }

    /// [1/α1, 1/(α2 − α1), and the factors of Z1^(order), Z2^(order) in
    /// Π^(order)] (period II runs backwards in j, so its second derivative
    /// changes sign).
    fn scales(&self, order: usize) -> [f64; 4] {
        let (p1, a1, p2, a2) = (self.stroke1, self.angle1, self.stroke, self.angle);
        let (ia1, ispan) = (1.0 / a1, 1.0 / (a2 - a1));
        let s1 = p1 * ia1.powi(order as i32);
        let s2 = (p2 - p1) * ispan.powi(order as i32) * if order == 2 { -1.0 } else { 1.0 };
        [ia1, ispan, s1, s2]
    }

    /// Π^(order) as a function of α, with its constants worked out once (no
    /// divisions by α1 or α2 − α1 and no powers per value). Period II runs
    /// backwards in j = (α2 − α)/(α2 − α1), so d/dα = −d/dj/(α2 − α1): its
    /// second derivative changes sign.
    fn evaluator(&self, order: usize) -> impl Fn(f64) -> f64 + Sync + '_ {
        let (p1, a1, p2, a2) = (self.stroke1, self.angle1, self.stroke, self.angle);
        let [ia1, ispan, s1, s2] = self.scales(order);
        let (l1, l2) = (&self.law1, &self.law2);
        move |v: f64| {
            if v <= a1 {
                s1 * l1.z(v * ia1, order)
            } else {
                let z = l2.z(((a2 - v) * ispan).max(0.0), order);
                if order == 0 {
                    p2 - (p2 - p1) * z
                } else {
                    s2 * z
                }
            }
        }
    }

    /// The periods' maps and output scalings of [`TwoPeriod::evaluator`]:
    /// u = (α − c)·s and value = off + sc·Z, per period.
    fn periods(&self, order: usize) -> (PerPeriod, PerPeriod) {
        let (p1, p2, a2) = (self.stroke1, self.stroke, self.angle);
        let [ia1, ispan, s1, s2] = self.scales(order);
        // Period II: u = (α2 − α)/(α2 − α1) = (α − α2)·(−1/(α2 − α1)).
        let map = [(0.0, ia1), (a2, -ispan)];
        let second = if order == 0 {
            (p2, -(p2 - p1))
        } else {
            (0.0, s2)
        };
        (map, [(0.0, s1), second])
    }

    /// [`TwoPeriod::evaluator`] in the lane-parallel form.
    pub(super) fn lanes(&self, order: usize) -> Option<Lanes> {
        let (map, out) = self.periods(order);
        Lanes::new([&self.law1, &self.law2], order, self.angle1, map, out)
    }

    /// [`TwoPeriod::evaluator`] in the fused SIMD form, whatever the processor
    /// (None beyond its sine's range).
    #[cfg(test)]
    pub(super) fn fused_any_cpu(&self, order: usize) -> Option<Fused> {
        let (map, out) = self.periods(order);
        Fused::build([&self.law1, &self.law2], order, self.angle1, map, out)
    }

    /// [`TwoPeriod::evaluator`] in the fused SIMD form, where the processor has
    /// FMA.
    pub(super) fn fused(&self, order: usize) -> Option<Fused> {
        let (map, out) = self.periods(order);
        Fused::new([&self.law1, &self.law2], order, self.angle1, map, out)
    }

    /// Check 0 < Π1 < Π2 and 0 < α1 < α2 (all finite).
    pub fn validate(&self) -> Result<(), MotionError> {
        let (p1, a1, p2, a2) = (self.stroke1, self.angle1, self.stroke, self.angle);
        let finite = [p1, a1, p2, a2].iter().all(|v| v.is_finite());
        if finite && 0.0 < p1 && p1 < p2 && 0.0 < a1 && a1 < a2 {
            return Ok(());
        }
        Err(MotionError::BadLaw {
            what: format!(
                "a two-period law needs 0 < Π1 < Π2 and 0 < α1 < α2; got Π1 = {p1}, \
                 Π2 = {p2}, α1 = {a1}, α2 = {a2}"
            ),
        })
    }

    /// out = Π^(order)(α) for every α (checked to lie in [0, α2]).
    pub fn eval_into(
        &self,
        alpha: &[f64],
        order: usize,
        n_threads: Option<i64>,
        out: &mut [f64],
    ) -> Result<(), MotionError> {
        self.validate()?;
        let order = order.min(3);
        let why = " [rad] (the law runs from α = 0 to the full angle α2)";
        let range = ("alpha", self.angle, why);
        let hi = self.angle;
        if let Some(f) = self.fused(order) {
            return par_chunks(alpha, out, n_threads, range, |xs, os| f.eval(xs, os, hi));
        }
        match self.lanes(order) {
            Some(l) => par_chunks(alpha, out, n_threads, range, |xs, os| l.eval(xs, os, hi)),
            None => par_fill(alpha, out, n_threads, range, self.evaluator(order)),
        }
    }
}
