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
                        batch.at_speed(w, &mut acc.scratch);
                        acc.keep(s as i64);
                    }
                    acc
                },
            )
            .reduce(|| Reduced::new(m * r), Reduced::merge)
    });
    margins.copy_from_slice(&best.margins);
    worst.copy_from_slice(&best.worst);
    Ok(())
}

/// What every speed shares: the load, the candidates' J′ = (J_motor + J_gear)·i²
/// in ascending order, the envelope's line order.
struct Batch<'a> {
    load: &'a Load<'a>,
    ratios: &'a [f64],
    motors: &'a Motors<'a>,
    /// J′ per candidate (m·R + r).
    jp: Vec<f64>,
    /// Candidates by ascending J′.
    by_jp: Vec<usize>,
    /// The 2N lines ±(ã_k + J′·b̃_k) by ascending slope: (k, sign).
    lines: Vec<(usize, f64)>,
    /// Inertia ratio margin per candidate (no speed in it).
    inertia_margin: Vec<f64>,
    /// max_k |φ_L′|.
    max_vel: f64,
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
        let mut jp = Vec::with_capacity(m * r);
        let mut inertia_margin = Vec::with_capacity(m * r);
        for &jm in motors.inertia {
            for &i in ratios {
                jp.push((jm + gear_inertia) * i * i);
                let ratio = (load.inertia / (i * i) + gear_inertia) / jm;
                inertia_margin.push(1.0 - ratio / limit);
            }
        }
        let mut by_jp: Vec<usize> = (0..m * r).collect();
        by_jp.sort_by(|&a, &b| jp[a].total_cmp(&jp[b]));
        // The slope of line (k, ±) is ±φ_L″_k·ω²: ω² > 0 keeps the order of ±φ_L″_k.
        let mut lines: Vec<(usize, f64)> = (0..load.acc.len())
            .flat_map(|k| [(k, 1.0), (k, -1.0)])
            .collect();
        lines.sort_by(|a, b| (a.1 * load.acc[a.0]).total_cmp(&(b.1 * load.acc[b.0])));
        let max_vel = load.vel.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        Batch {
            load,
            ratios,
            motors,
            jp,
            by_jp,
            lines,
            inertia_margin,
            max_vel,
        }
    }

    /// Every candidate's margins at the master speed `w` into `scratch.margins`.
    fn at_speed(&self, w: f64, scratch: &mut Scratch) {
        let load = self.load;
        let n = load.acc.len();
        let w2 = w * w;
        let (mut saa, mut sab, mut sbb) = (0.0, 0.0, 0.0);
        scratch.a.clear();
        for k in 0..n {
            let a = load.reduced(k, w2);
            let b = load.acc[k] * w2;
            saa += a * a;
            sab += a * b;
            sbb += b * b;
            scratch.a.push(a);
        }
        self.envelope(w2, scratch);
        let r = self.ratios.len();
        for (c, out) in scratch.margins.chunks_exact_mut(N_CHECKS).enumerate() {
            let (mi, ri) = (c / r, c % r);
            let i = self.ratios[ri];
            let jp = self.jp[c];
            let peak = scratch.peak[c] / i;
            let rms = ((saa + jp * (2.0 * sab + jp * sbb)).max(0.0) / n as f64).sqrt() / i;
            let speed = i * w * self.max_vel;
            out[0] = 1.0 - peak / self.motors.peak_torque[mi];
            out[1] = 1.0 - rms / self.motors.rated_torque[mi];
            out[2] = 1.0 - speed / self.motors.max_speed[mi];
            out[3] = self.inertia_margin[c];
        }
    }

    /// max_k |ã_k + J′·b̃_k| for every candidate's J′ into `scratch.peak`: the
    /// upper envelope of the 2N lines (slopes ascending), walked at ascending J′.
    fn envelope(&self, w2: f64, scratch: &mut Scratch) {
        let hull = &mut scratch.hull;
        hull.clear();
        for &(k, sign) in &self.lines {
            let (slope, c) = (sign * self.load.acc[k] * w2, sign * scratch.a[k]);
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
        let mut p = 0;
        let value = |(s, c): (f64, f64), x: f64| c + s * x;
        for &cand in &self.by_jp {
            let x = self.jp[cand];
            while p + 1 < hull.len() && value(hull[p + 1], x) >= value(hull[p], x) {
                p += 1;
            }
            scratch.peak[cand] = value(hull[p], x);
        }
    }
}

/// Working arrays of one thread.
struct Scratch {
    a: Vec<f64>,
    hull: Vec<(f64, f64)>,
    peak: Vec<f64>,
    margins: Vec<f64>,
}

/// The smallest margins so far and the speeds where they are (one per thread's
/// share of the speeds, merged at the end).
struct Reduced {
    margins: Vec<f64>,
    worst: Vec<i64>,
    scratch: Scratch,
}

impl Reduced {
    fn new(candidates: usize) -> Self {
        Reduced {
            margins: vec![f64::INFINITY; candidates * N_CHECKS],
            worst: vec![-1; candidates * N_CHECKS],
            scratch: Scratch {
                a: Vec::new(),
                hull: Vec::new(),
                peak: vec![0.0; candidates],
                margins: vec![0.0; candidates * N_CHECKS],
            },
        }
    }

    /// Keep the smaller of the margins so far and the scratch's (at speed index `s`).
    fn keep(&mut self, s: i64) {
        let new = &self.scratch.margins;
        for ((m, w), &v) in self.margins.iter_mut().zip(&mut self.worst).zip(new) {
            if v < *m || *w < 0 {
                *m = v;
                *w = s;
            }
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
