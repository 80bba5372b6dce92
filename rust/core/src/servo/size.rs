//! The sizing batch: the checks of every motor × gear ratio at every master
//! speed, reduced to each candidate's smallest margin over the speeds, by the
//! structure of the module docs (one envelope of lines per speed, O(1) per
//! candidate).

use rayon::prelude::*;

use super::{positive_entries, Load, Motors, ServoError, N_CHECKS};
use crate::input::InvalidInput;
use crate::parallel::{pool, resolve_threads};

/// For every motor m and ratio r (row-major (M, R, [`N_CHECKS`])) the smallest
/// margin of each [`super::CHECKS`] over the master speeds `omegas` [rad/s] into
/// `margins`, and the index of the speed where it is smallest (the first on a
/// tie) into `worst`. A margin is 1 − used/available: the peak |T_m| over the
/// motor's peak torque, the RMS torque over its rated torque, the peak |ω_m|
/// over its maximum speed, the inertia ratio (J_L/i² + J_gearbox)/J_motor over
/// `inertia_limit`; ≥ 0 passes, < 0 fails. The gearbox's inertia
/// `gear_inertia` [kg·m²] is the same for every ratio.
#[allow(clippy::too_many_arguments)]
pub fn size_into(
    load: &Load<'_>,
    ratios: &[f64],
    gear_inertia: f64,
    motors: &Motors<'_>,
    omegas: &[f64],
    inertia_limit: f64,
    margins: &mut [f64],
    worst: &mut [i64],
    n_threads: Option<i64>,
) -> Result<(), ServoError> {
    load.check()?;
    positive_entries("ratio", ratios)?;
    let m = motors.check()?;
    positive_entries("omega", omegas)?;
    if !(gear_inertia.is_finite() && gear_inertia >= 0.0) {
        return Err(InvalidInput::bad_value(
            "gear_inertia",
            gear_inertia,
            "[kg·m²] must be finite and >= 0",
        )
        .into());
    }
    if !(inertia_limit.is_finite() && inertia_limit > 0.0) {
        return Err(InvalidInput::bad_value(
            "inertia_limit",
            inertia_limit,
            "must be finite and > 0",
        )
        .into());
    }
    let r = ratios.len();
    debug_assert_eq!(margins.len(), m * r * N_CHECKS);
    debug_assert_eq!(worst.len(), m * r * N_CHECKS);
    let batch = Batch::new(load, ratios, gear_inertia, motors, inertia_limit);
    let pool = pool(resolve_threads(n_threads)?)?;
    let best = pool.install(|| {
        omegas
            .par_iter()
            .enumerate()
            .fold(
                || Reduced::new(m * r),
                |mut acc, (s, &w)| {
                    if !crate::cancel::requested() {
                        batch.at_speed(w, s as i64, &mut acc);
                    }
                    acc
                },
            )
            .reduce(|| Reduced::new(m * r), Reduced::merge)
    });
    // Back from the order of J′ to the candidates' (m·R + r), the inertia ratio's
    // margin beside (it holds at every speed: the first speed is the worst).
    for (q, &c) in batch.by_jp.iter().enumerate() {
        for k in 0..N_CHECKS - 1 {
            margins[c * N_CHECKS + k] = best.margins[q * 3 + k];
            worst[c * N_CHECKS + k] = best.worst[q * 3 + k];
        }
        margins[c * N_CHECKS + 3] = batch.inertia_margin[c];
        worst[c * N_CHECKS + 3] = 0;
    }
    Ok(())
}

/// What every speed shares: the load, the candidates in ascending order of
/// J′ = (J_motor + J_gear)·i² with the factors that turn the envelope, the RMS
/// sum and the speed into margins, and the envelope's line order.
struct Batch<'a> {
    load: &'a Load<'a>,
    /// Candidates (m·R + r) by ascending J′.
    by_jp: Vec<usize>,
    /// In that order: J′, 1/(i·T_peak), 1/(i·T_rated·√N), i·max|φ_L′|/ω_max.
    jp: Vec<f64>,
    per_peak: Vec<f64>,
    per_rms: Vec<f64>,
    per_speed: Vec<f64>,
    /// The 2N lines ±(ã_k + J′·b̃_k) by ascending slope: (k, sign).
    lines: Vec<(usize, f64)>,
    /// Inertia ratio margin per candidate (m·R + r): no speed in it.
    inertia_margin: Vec<f64>,
}

impl<'a> Batch<'a> {
    fn new(
        load: &'a Load<'a>,
        ratios: &'a [f64],
        gear_inertia: f64,
        motors: &'a Motors<'a>,
        limit: f64,
    ) -> Self {
        let r = ratios.len();
        let m = motors.inertia.len();
        let jp_of = |c: usize| {
            let i = ratios[c % r];
            (motors.inertia[c / r] + gear_inertia) * i * i
        };
        let mut by_jp: Vec<usize> = (0..m * r).collect();
        by_jp.sort_by(|&a, &b| jp_of(a).total_cmp(&jp_of(b)));
        let max_vel = load.vel.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let root_n = (load.vel.len() as f64).sqrt();
        let (mut jp, mut per_peak, mut per_rms, mut per_speed) = (vec![], vec![], vec![], vec![]);
        for &c in &by_jp {
            let (mi, i) = (c / r, ratios[c % r]);
            jp.push(jp_of(c));
            per_peak.push(1.0 / (i * motors.peak_torque[mi]));
            per_rms.push(1.0 / (i * motors.rated_torque[mi] * root_n));
            per_speed.push(i * max_vel / motors.max_speed[mi]);
        }
        let inertia_margin = (0..m * r)
            .map(|c| {
                let i = ratios[c % r];
                let ratio = (load.inertia / (i * i) + gear_inertia) / motors.inertia[c / r];
                1.0 - ratio / limit
            })
            .collect();
        // The slope of line (k, ±) is ±φ_L″_k·ω²: ω² > 0 keeps the order of ±φ_L″_k.
        let mut lines: Vec<(usize, f64)> = (0..load.acc.len())
            .flat_map(|k| [(k, 1.0), (k, -1.0)])
            .collect();
        lines.sort_by(|a, b| (a.1 * load.acc[a.0]).total_cmp(&(b.1 * load.acc[b.0])));
        Batch {
            load,
            by_jp,
            jp,
            per_peak,
            per_rms,
            per_speed,
            lines,
            inertia_margin,
        }
    }

    /// Every candidate's margins of the peak torque, the RMS torque and the
    /// speed at the master speed `w` (index `s`), kept in `acc` where smaller.
    fn at_speed(&self, w: f64, s: i64, acc: &mut Reduced) {
        let load = self.load;
        let w2 = w * w;
        let (mut saa, mut sab, mut sbb) = (0.0, 0.0, 0.0);
        acc.a.clear();
        for k in 0..load.acc.len() {
            let a = load.reduced(k, w2);
            let b = load.acc[k] * w2;
            saa += a * a;
            sab += a * b;
            sbb += b * b;
            acc.a.push(a);
        }
        self.envelope(w2, &acc.a, &mut acc.hull);
        let hull = &acc.hull;
        let value = |(slope, c): (f64, f64), x: f64| c + slope * x;
        let mut p = 0;
        let rows = acc
            .margins
            .chunks_exact_mut(3)
            .zip(acc.worst.chunks_exact_mut(3));
        for (q, (m, at)) in rows.enumerate() {
            let x = self.jp[q];
            // The walk: the envelope's line on top moves right as J′ grows.
            while p + 1 < hull.len() && value(hull[p + 1], x) >= value(hull[p], x) {
                p += 1;
            }
            let sq = (saa + x * (2.0 * sab + x * sbb)).max(0.0);
            let new = [
                1.0 - value(hull[p], x) * self.per_peak[q],
                1.0 - sq.sqrt() * self.per_rms[q],
                1.0 - w * self.per_speed[q],
            ];
            for k in 0..3 {
                if new[k] < m[k] || at[k] < 0 {
                    m[k] = new[k];
                    at[k] = s;
                }
            }
        }
    }

    /// The upper envelope of the 2N lines ±(ã_k + J′·b̃_k) into `hull` as
    /// (slope, intercept), slopes ascending.
    fn envelope(&self, w2: f64, a: &[f64], hull: &mut Vec<(f64, f64)>) {
        hull.clear();
        for &(k, sign) in &self.lines {
            let (slope, c) = (sign * self.load.acc[k] * w2, sign * a[k]);
            if let Some(&(s2, c2)) = hull.last() {
                if s2 == slope {
                    if c2 >= c {
                        continue;
                    }
                    hull.pop();
                }
            }
            while hull.len() >= 2 {
                let (s1, c1) = hull[hull.len() - 2];
                let (s2, c2) = hull[hull.len() - 1];
                // The middle line is never on top if the new one reaches it where
                // the first one leaves it: (c3 − c2)(m2 − m1) + (m3 − m2)(c1 − c2) ≥ 0.
                if (c - c2) * (s2 - s1) + (slope - s2) * (c1 - c2) >= 0.0 {
                    hull.pop();
                } else {
                    break;
                }
            }
            hull.push((slope, c));
        }
    }
}

/// The smallest margins so far of the peak torque, RMS torque and speed checks
/// (candidates in the order of J′) and the speeds where they are, with the working
/// arrays of one thread (one per thread's share of the speeds, merged at the end).
struct Reduced {
    margins: Vec<f64>,
    worst: Vec<i64>,
    a: Vec<f64>,
    hull: Vec<(f64, f64)>,
}

impl Reduced {
    fn new(candidates: usize) -> Self {
        Reduced {
            margins: vec![f64::INFINITY; candidates * 3],
            worst: vec![-1; candidates * 3],
            a: Vec::new(),
            hull: Vec::new(),
        }
    }

    /// The smaller of two partial results, the earlier speed on a tie.
    fn merge(mut self, other: Reduced) -> Reduced {
        for i in 0..self.margins.len() {
            let (a, b) = (self.margins[i], other.margins[i]);
            let (wa, wb) = (self.worst[i], other.worst[i]);
            let later_tie = b == a && wb >= 0 && (wa < 0 || wb < wa);
            if wb >= 0 && (wa < 0 || b < a || later_tie) {
                self.margins[i] = b;
                self.worst[i] = wb;
            }
        }
        self
    }
}
