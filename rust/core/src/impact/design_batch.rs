//! Many designs of one stop at once (issue 20): a machine sweep that varies a
//! cam stop's parameters (its preload, stiffness, lever, rebound limit …) builds
//! and solves every design here, rayon over designs, instead of one Python
//! `StopImpact` and a handful of kernel calls per design.
//!
//! Per design d (seed 000's pulse model, the one whose rebound is linear in the
//! impact speed; the contact model and the half-sine pulse stay on the
//! per-design path, see `cyclomech.machine`):
//!
//! * the contact point j* where the rise law Z(j*) = 1 − preload/stroke, by the
//!   same 16 rounds of 64-point grids as `StopImpact`, and Z'(j*);
//! * the unit-impulse pulse table of duration τ (decaying, rectangular or
//!   triangular), as `Pulse.<shape>(1, τ).scaled(1/impulse)`;
//! * the rebound per unit impact speed g (the rebound at 1 m/s: the model is
//!   linear, so the rebound at v is g·v, in both paths) and the largest
//!   admissible impact speed v* = a_max/g
//!   less a 1e-13 margin, stepped down by ulps while its rebound exceeds a_max,
//!   as `max_impact_speeds`;
//! * the phase angle per rpm k = (360/2π)·(2π/60)·stroke·Z'/v* [deg/rpm] and the
//!   smallest phase angle max(n·k, 1e-9°) at every speed n (NaN over 360°).
//!
//! Every step is the arithmetic of the Python path in the same order, so the
//! results are bit for bit those of one `StopImpact` per design (the Python
//! tests compare them on random grids).

use rayon::prelude::*;

use crate::motion::Law;
use crate::parallel::{pool, resolve_threads};
use crate::units::RAD_PER_S_PER_RPM;

use super::error::{length, ImpactError};
use super::oscillator::Oscillator;
use super::rebound::first_turn;

/// Relative margin of v* below a_max/g (`_SPEED_MARGIN` of the Python path).
pub const SPEED_MARGIN: f64 = 1e-13;

/// Smallest phase angle [deg] a bound returns (`Proportional.evaluate`).
const MIN_PHASE_DEG: f64 = 1e-9;

/// Rounds of the ulp step-down of v* (as `max_impact_speeds`).
const STEP_DOWN_ROUNDS: usize = 8;

/// Designs per rayon task.
const TASK: usize = 16;

/// The pulse shapes the batch takes (the piecewise-linear ones of 2 or 3 points).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PulseShape {
    Decaying,
    Rectangular,
    Triangular,
}

impl PulseShape {
    /// The shape of code 0 (decaying), 1 (rectangular) or 2 (triangular).
    pub fn from_code(code: i64) -> Result<PulseShape, ImpactError> {
        match code {
            0 => Ok(PulseShape::Decaying),
            1 => Ok(PulseShape::Rectangular),
            2 => Ok(PulseShape::Triangular),
            _ => Err(ImpactError::Count {
                field: "pulse",
                value: code,
                want: "0 (decaying), 1 (rectangular) or 2 (triangular)",
            }),
        }
    }

    /// The table (t [s], f [1/s]) of unit impulse lasting `tau` [s]: the values of
    /// `Pulse.<shape>(1.0, tau).scaled(1.0 / impulse)`, the impulse summed as
    /// numpy sums the trapezoids Δt·0.5·(f0 + f1).
    pub fn unit(self, tau: f64) -> PulseTable {
        let (t, f, n): ([f64; 3], [f64; 3], usize) = match self {
            PulseShape::Decaying => ([0.0, tau, 0.0], [1.0, 0.0, 0.0], 2),
            PulseShape::Rectangular => ([0.0, tau, tau], [1.0, 1.0, 0.0], 3),
            PulseShape::Triangular => ([0.0, 0.5 * tau, tau], [0.0, 1.0, 0.0], 3),
        };
        let mut impulse = (t[1] - t[0]) * 0.5 * (f[1] + f[0]);
        if n == 3 {
            impulse += (t[2] - t[1]) * 0.5 * (f[2] + f[1]);
        }
        let factor = 1.0 / impulse;
        let mut out = PulseTable { t, f, n };
        for v in out.f.iter_mut().take(n) {
            *v *= factor;
        }
        out
    }
}

/// A pulse table of at most 3 points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PulseTable {
    pub t: [f64; 3],
    pub f: [f64; 3],
    pub n: usize,
}

/// One design's stop in the pulse model: the oscillator (free stiffness) and the
/// impact's table.
#[derive(Debug, Clone, Copy)]
pub struct PulseStop {
    pub osc: Oscillator,
    /// Mass times (1 + restitution): the impulse per m/s of impact speed [kg].
    pub impulse_per_speed: f64,
    pub table: PulseTable,
}

impl PulseStop {
    /// The stop of free `stiffness` [N/m], reduced `mass` [kg], `restitution`,
    /// damping ratio `zeta` and impact pulse `shape` of duration `contact_time` [s].
    pub fn new(
        shape: PulseShape,
        stiffness: f64,
        mass: f64,
        contact_time: f64,
        restitution: f64,
        zeta: f64,
    ) -> PulseStop {
        PulseStop {
            osc: Oscillator {
                omega_n: (stiffness / mass).sqrt(),
                zeta,
                mass,
            },
            impulse_per_speed: mass * (1.0 + restitution),
            table: shape.unit(contact_time),
        }
    }

    /// The first rebound per unit impact speed g [m per m/s]: the first maximum
    /// of q from q = 0, q̇ = −1 m/s under the pulse of impulse m·(1 + k)·1 m/s.
    /// The model is linear (the lever starts at q = 0 and the impulse is ∝ the
    /// speed), so the rebound at speed v is g·v: both paths take it so
    /// (`rebounds` of the Python layer), one solve per stop.
    pub fn rebound_per_speed(&self) -> Result<f64, ImpactError> {
        let n = self.table.n;
        let impulse = self.impulse_per_speed * 1.0;
        let mut force = [0.0; 3];
        for (o, &f) in force.iter_mut().zip(&self.table.f[..n]) {
            *o = impulse * f;
        }
        first_turn(&self.table.t[..n], &force[..n], &self.osc, 0.0, -1.0, true).map(|r| r.q)
    }
}

/// The largest impact speed [m/s] whose rebound g·v is at most `a_max` [m], g
/// the rebound per unit speed: a_max/g less the margin, stepped down while over
/// (inf when g ≤ 0), as `max_impact_speeds`.
pub fn max_speed(g: f64, a_max: f64) -> f64 {
    let mut v = if g > 0.0 {
        a_max / g * (1.0 - SPEED_MARGIN)
    } else {
        f64::INFINITY
    };
    for _ in 0..STEP_DOWN_ROUNDS {
        if !v.is_finite() || g * v <= a_max {
            break;
        }
        v = next_down(v) * (1.0 - 2.0 * f64::EPSILON);
    }
    v
}

/// The next double towards 0 (numpy's `nextafter(v, 0)` for finite v > 0).
fn next_down(v: f64) -> f64 {
    if v > 0.0 {
        f64::from_bits(v.to_bits() - 1)
    } else {
        v
    }
}

/// numpy's `spacing(h)` for finite h ≥ 0: the gap to the next double up.
fn spacing(h: f64) -> f64 {
    f64::from_bits(h.to_bits() + 1) - h
}

/// `np.linspace(lo, hi, 66)[1:-1]`: lo + i·step for i = 1..=64, step = (hi − lo)/65.
fn inner_grid(lo: f64, hi: f64) -> [f64; 64] {
    let div = 65.0;
    let delta = hi - lo;
    let step = delta / div;
    std::array::from_fn(|k| {
        let i = (k + 1) as f64;
        if step == 0.0 {
            i / div * delta + lo
        } else {
            i * step + lo
        }
    })
}

/// Where the rise law meets the stop: (j*, Z'(j*)) with Z(j*) = `target`, by the
/// 64-point grids of `StopImpact` (16 rounds or down to adjacent doubles).
pub fn contact_point(law: &Law, target: f64) -> (f64, f64) {
    let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
    let mut z = [0.0; 64];
    for _ in 0..16 {
        let grid = inner_grid(lo, hi);
        // One thread: the law's lanes give the same values at any thread count.
        law.eval_into(&grid, 0, Some(1), &mut z)
            .expect("the grid lies in [0, 1]");
        // The first value not below the target (NaN counts as not below).
        let below = |v: f64| v.partial_cmp(&target) == Some(std::cmp::Ordering::Less);
        let k = z.iter().position(|&v| !below(v)).unwrap_or(64);
        if k > 0 {
            lo = grid[k - 1];
        }
        if k < 64 {
            hi = grid[k];
        }
        if hi - lo <= 2.0 * spacing(hi) {
            break;
        }
    }
    let j = 0.5 * (lo + hi);
    let mut dz = [0.0];
    law.eval_into(&[j], 1, Some(1), &mut dz)
        .expect("j lies in [0, 1]");
    (j, dz[0])
}

/// The stop designs of a batch, one value per design (D,), already checked by
/// the caller as `StopImpact` checks them: stroke > preload ≥ 0 [m], mass [kg],
/// free stiffness [N/m] and contact time [s] > 0, restitution in [0, 1], ζ ≥ 0,
/// a_max > 0 [m].
#[derive(Debug, Clone, Copy)]
pub struct StopDesigns<'a> {
    pub stroke: &'a [f64],
    pub preload: &'a [f64],
    pub mass: &'a [f64],
    pub stiffness: &'a [f64],
    pub contact_time: &'a [f64],
    pub restitution: &'a [f64],
    pub zeta: &'a [f64],
    pub a_max: &'a [f64],
}

impl StopDesigns<'_> {
    /// D, after checking that the lengths agree.
    pub fn len(&self) -> Result<usize, ImpactError> {
        let d = self.stroke.len();
        let what = "one per design, like stroke";
        length("preload", self.preload.len(), d, what)?;
        length("mass", self.mass.len(), d, what)?;
        length("stiffness", self.stiffness.len(), d, what)?;
        length("contact_time", self.contact_time.len(), d, what)?;
        length("restitution", self.restitution.len(), d, what)?;
        length("zeta", self.zeta.len(), d, what)?;
        length("a_max", self.a_max.len(), d, what)?;
        Ok(d)
    }

    /// Whether there are no designs.
    pub fn is_empty(&self) -> bool {
        self.stroke.is_empty()
    }

    /// Design i's stop.
    pub fn stop(&self, shape: PulseShape, i: usize) -> PulseStop {
        PulseStop::new(
            shape,
            self.stiffness[i],
            self.mass[i],
            self.contact_time[i],
            self.restitution[i],
            self.zeta[i],
        )
    }
}

/// What the batch gives per design (D,) and per design and speed (D, S).
#[derive(Debug)]
pub struct DesignOut<'a> {
    /// j* [-]: where the lever meets the stop.
    pub j_contact: &'a mut [f64],
    /// Z'(j*) [-].
    pub dz_contact: &'a mut [f64],
    /// v* [m/s]: the largest admissible impact speed.
    pub v_star: &'a mut [f64],
    /// (360/60)·stroke·Z' [deg·m/s per rpm]: the phase angle per rpm at 1 m/s.
    pub per_rpm_unit: &'a mut [f64],
    /// k = `per_rpm_unit`/v* [deg/rpm]: the smallest phase angle per rpm.
    pub per_rpm: &'a mut [f64],
    /// (D, S) smallest phase angles [deg] at the speeds.
    pub min_phase_deg: &'a mut [f64],
    /// g [m per m/s]: the first rebound per unit impact speed (the rebound at
    /// speed v is g·v).
    pub rebound_per_speed: &'a mut [f64],
}

/// The smallest phase angle [deg] n·k, at least 1e-9°, NaN over 360°.
pub fn min_phase(rpm: f64, per_rpm: f64) -> f64 {
    let t = rpm * per_rpm;
    let t = if t.is_nan() { t } else { t.max(MIN_PHASE_DEG) };
    if t <= 360.0 {
        t
    } else {
        f64::NAN
    }
}

/// Every design of `designs` built and solved: contact points, largest
/// admissible impact speeds, phase angles per rpm and the smallest phase angles
/// at the speeds `rpm` (S,) [rpm], rayon over designs. Errors name the design.
pub fn stop_designs_into(
    law: &Law,
    shape: PulseShape,
    designs: &StopDesigns<'_>,
    rpm: &[f64],
    n_threads: Option<i64>,
    out: DesignOut<'_>,
) -> Result<(), ImpactError> {
    let d = designs.len()?;
    let s = rpm.len();
    length("j_contact", out.j_contact.len(), d, "one per design")?;
    length("dz_contact", out.dz_contact.len(), d, "one per design")?;
    length("v_star", out.v_star.len(), d, "one per design")?;
    length("per_rpm_unit", out.per_rpm_unit.len(), d, "one per design")?;
    length("per_rpm", out.per_rpm.len(), d, "one per design")?;
    length(
        "rebound_per_speed",
        out.rebound_per_speed.len(),
        d,
        "one per design",
    )?;
    length(
        "min_phase_deg",
        out.min_phase_deg.len(),
        d * s,
        "D*S: one row per design",
    )?;
    let one = |i: usize| -> Result<[f64; 6], ImpactError> {
        let (stroke, preload) = (designs.stroke[i], designs.preload[i]);
        let (j, dz) = contact_point(law, 1.0 - preload / stroke);
        let g = designs
            .stop(shape, i)
            .rebound_per_speed()
            .map_err(ImpactError::case(i))?;
        let v = max_speed(g, designs.a_max[i]);
        let unit = RAD_PER_S_PER_RPM * stroke * dz * (180.0 / std::f64::consts::PI);
        Ok([j, dz, v, unit, unit / v, g])
    };
    let block =
        |j0: usize, rows: &mut [[f64; 6]], mins: &mut [f64]| -> Option<(usize, ImpactError)> {
            for (r, row) in rows.iter_mut().enumerate() {
                if r % TASK == 0 && crate::cancel::requested() {
                    return None;
                }
                let i = j0 * TASK + r;
                match one(i) {
                    Ok(v) => *row = v,
                    Err(e) => return Some((i, e)),
                }
                if s > 0 {
                    for (m, &n) in mins[r * s..(r + 1) * s].iter_mut().zip(rpm) {
                        *m = min_phase(n, row[4]);
                    }
                }
            }
            None
        };
    let mut rows = vec![[0.0; 6]; d];
    let threads = resolve_threads(n_threads)?;
    let first_error = if threads == 1 || d <= TASK {
        block(0, &mut rows, out.min_phase_deg)
    } else {
        // Rows of min_phase_deg per task: TASK designs of S speeds (S may be 0).
        let per = (TASK * s).max(1);
        let mut mins: Vec<&mut [f64]> = if s > 0 {
            out.min_phase_deg.chunks_mut(per).collect()
        } else {
            (0..d.div_ceil(TASK))
                .map(|_| <&mut [f64]>::default())
                .collect()
        };
        pool(threads)?.install(|| {
            rows.par_chunks_mut(TASK)
                .zip(mins.par_iter_mut())
                .enumerate()
                .filter_map(|(j, (r, m))| block(j, r, m))
                .min_by_key(|(i, _)| *i)
        })
    };
    if let Some((_, e)) = first_error {
        return Err(e);
    }
    for (i, row) in rows.iter().enumerate() {
        out.j_contact[i] = row[0];
        out.dz_contact[i] = row[1];
        out.v_star[i] = row[2];
        out.per_rpm_unit[i] = row[3];
        out.per_rpm[i] = row[4];
        out.rebound_per_speed[i] = row[5];
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn lifter(preload: f64) -> (Law, [f64; 8]) {
        // stroke, preload, mass, stiffness, contact time, restitution, zeta, a_max
        let law = Law::rise("modified_sine").unwrap();
        (
            law,
            [
                9.4e-3,
                preload,
                7.4e-3,
                25620.0,
                6.5e-4,
                5.0 / 9.0,
                0.05,
                1e-4,
            ],
        )
    }

    #[test]
    fn unit_pulses_have_unit_impulse() {
        for shape in [
            PulseShape::Decaying,
            PulseShape::Rectangular,
            PulseShape::Triangular,
        ] {
            let p = shape.unit(1e-3);
            let mut area = 0.0;
            for k in 1..p.n {
                area += (p.t[k] - p.t[k - 1]) * 0.5 * (p.f[k] + p.f[k - 1]);
            }
            assert!((area - 1.0).abs() < 1e-12, "{shape:?}: {area}");
        }
        assert!(PulseShape::from_code(3).is_err());
    }

    #[test]
    fn contact_point_solves_the_law() {
        let law = Law::rise("cycloidal").unwrap();
        for target in [0.1, 0.5, 0.9, 0.97] {
            let (j, dz) = contact_point(&law, target);
            assert!((law.z(j, 0) - target).abs() < 1e-14, "{target}");
            assert_eq!(dz, law.z(j, 1));
        }
    }

    #[test]
    fn the_admissible_speed_meets_a_max() {
        let (_, p) = lifter(2.5e-4);
        let stop = PulseStop::new(PulseShape::Decaying, p[3], p[2], p[4], p[5], p[6]);
        let g = stop.rebound_per_speed().unwrap();
        let v = max_speed(g, p[7]);
        let at = g * v;
        assert!(at <= p[7] && at > p[7] * (1.0 - 1e-12), "{at}");
        // The pulse model is linear in the impact speed: the rebound solved at
        // 2 m/s and 0.37 m/s (not scaled) is g times the speed.
        for speed in [2.0, 0.37] {
            let n = stop.table.n;
            let force: Vec<f64> = stop.table.f[..n]
                .iter()
                .map(|f| stop.impulse_per_speed * speed * f)
                .collect();
            let q = first_turn(&stop.table.t[..n], &force, &stop.osc, 0.0, -speed, true)
                .unwrap()
                .q;
            assert!((q / (g * speed) - 1.0).abs() < 1e-14, "{speed}: {q}");
        }
        assert_eq!(max_speed(0.0, 1e-4), f64::INFINITY);
    }

    #[test]
    fn min_phase_floor_and_cap() {
        assert_eq!(min_phase(100.0, 0.0), 1e-9);
        assert!(min_phase(100.0, 4.0).is_nan());
        assert!(min_phase(100.0, f64::INFINITY).is_nan());
        assert_eq!(min_phase(100.0, 0.5), 50.0);
    }

    fn run(preloads: &[f64], rpm: &[f64], threads: i64) -> Vec<Vec<f64>> {
        let (law, p) = lifter(0.0);
        let d = preloads.len();
        let col = |k: usize| vec![p[k]; d];
        let (stroke, mass, stiff, tau, rest, zeta, amax) =
            (col(0), col(2), col(3), col(4), col(5), col(6), col(7));
        let designs = StopDesigns {
            stroke: &stroke,
            preload: preloads,
            mass: &mass,
            stiffness: &stiff,
            contact_time: &tau,
            restitution: &rest,
            zeta: &zeta,
            a_max: &amax,
        };
        let mut o: Vec<Vec<f64>> = vec![vec![0.0; d]; 6];
        let mut mins = vec![0.0; d * rpm.len()];
        let [a, b, c, e, f, g] = &mut o[..] else {
            unreachable!()
        };
        stop_designs_into(
            &law,
            PulseShape::Decaying,
            &designs,
            rpm,
            Some(threads),
            DesignOut {
                j_contact: a,
                dz_contact: b,
                v_star: c,
                per_rpm_unit: e,
                per_rpm: f,
                min_phase_deg: &mut mins,
                rebound_per_speed: g,
            },
        )
        .unwrap();
        o.push(mins);
        o
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(24))]
        /// Threads do not change a bit; each design is the design alone; the
        /// smallest phase angle's impact speed is v* (the rebound there is a_max).
        #[test]
        fn designs_are_independent(
            preloads in prop::collection::vec(1e-5f64..5e-3, 1..40),
            rpm in prop::collection::vec(50.0f64..900.0, 0..5),
        ) {
            let one = run(&preloads, &rpm, 1);
            let two = run(&preloads, &rpm, 2);
            prop_assert_eq!(&one, &two);
            let s = rpm.len();
            for (i, &p) in preloads.iter().enumerate() {
                let alone = run(&[p], &rpm, 1);
                for k in 0..6 {
                    prop_assert_eq!(alone[k][0].to_bits(), one[k][i].to_bits());
                }
                prop_assert_eq!(&alone[6][..], &one[6][i * s..(i + 1) * s]);
            }
        }
    }
}
