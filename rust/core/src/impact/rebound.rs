//! The first rebound after a force pulse: the first extremum of q, bracketed
//! segment by segment and solved to rounding.

use rayon::prelude::*;

use crate::parallel::{pool, resolve_threads};

use super::error::{check_finite, check_times, finite, length, ImpactError};
use super::oscillator::{sign, Cases, Mode, Oscillator, Step};

/// The first extremum of q after t[0]: its time [s] (+∞ if none) and signed q.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rebound {
    pub time: f64,
    pub q: f64,
}

/// The first rebound of one oscillator driven by the pulse table (t, force) from
/// q(t[0]) = q0, q̇(t[0]) = v0; the force is held at its last value after t[last].
pub fn first_rebound(
    t: &[f64],
    force: &[f64],
    osc: &Oscillator,
    q0: f64,
    v0: f64,
) -> Result<Rebound, ImpactError> {
    first_turn(t, force, osc, q0, v0, false)
}

/// [`first_rebound`], or with `maximum` the first local maximum of q (minima
/// passed over): the rebound of a link that first presses into its stop.
pub fn first_turn(
    t: &[f64],
    force: &[f64],
    osc: &Oscillator,
    q0: f64,
    v0: f64,
    maximum: bool,
) -> Result<Rebound, ImpactError> {
    osc.validate()?;
    finite("q0", q0)?;
    finite("v0", v0)?;
    check_times("t", t)?;
    length("force", force.len(), t.len(), "one per time")?;
    check_finite("force", force)?;
    rebound(t, force, &osc.mode(), 1.0 / osc.mass, q0, v0, maximum)
}

/// The direction q̇ leaves 0 in, from q̇ = v, q̈ = a and the force's quasi-static
/// velocity c (q̇ ≈ c ω² s²/2 when v = a = 0).
fn start_sign(v: f64, a: f64, c: f64) -> f64 {
    if v != 0.0 {
        sign(v)
    } else if a != 0.0 {
        sign(a)
    } else {
        sign(c)
    }
}

fn rebound(
    t: &[f64],
    force: &[f64],
    mode: &Mode,
    inv_m: f64,
    q0: f64,
    v0: f64,
    maximum: bool,
) -> Result<Rebound, ImpactError> {
    let (sig, w2) = (mode.sigma, mode.w2);
    let (mut q, mut v) = (q0, v0);
    // The sign q̇ has had since it became non-zero (0: not moving yet).
    let mut s = sign(v0);
    // Is a turn with q̇ of sign `s` before it the one wanted? (With `maximum`,
    // minima are passed over.)
    let wanted = |s: f64| !maximum || s > 0.0;
    let range = |h| ImpactError::Range {
        h,
        omega_n: mode.omega,
        zeta: mode.zeta,
    };
    for (tw, fw) in t.windows(2).zip(force.windows(2)) {
        let h = tw[1] - tw[0];
        if h == 0.0 {
            continue; // a jump of the force: the state is unchanged
        }
        let slope = (fw[1] - fw[0]) / h;
        // The segment from (t_a, f_a) to its end; t_a moves past passed-over minima.
        let (mut t_a, mut f_a) = (tw[0], fw[0]);
        let mut passed = 0;
        loop {
            let rest = tw[1] - t_a;
            let (p0, p1) = (f_a * inv_m, slope * inv_m);
            // q̇(τ) = c + y(τ), y unforced with y(0) = v − c, y'(0) = q̈(0).
            let c = p1 / w2;
            let a0 = p0 - 2.0 * sig * v - w2 * q;
            if s == 0.0 {
                s = start_sign(v, a0, c);
                if s == 0.0 {
                    // At rest under a constant force (q̇ = q̈ = 0, c = 0): exactly
                    // so to the segment's end; stepping would only add rounding noise.
                    break;
                }
            }
            // q̇ = c + y loses the digits of c: where those are most of the
            // dip of q̇ after a point of rest, that dip is searched on its own
            // (shallow_dip); where they are most of q̇'s own size over the
            // segment (a steep ramp over a short step), the closed form's zero is
            // rounding noise: bracket q̇ by exact steps instead.
            let h = rest.min(1.0 / mode.rate.max(mode.omega));
            let noise = 32.0 * f64::EPSILON * ((v - c).abs() + a0.abs() / mode.omega + c.abs());
            let size = v.abs() + a0.abs() * h + 0.5 * p1.abs() * h * h;
            let turn = if let Some(dip) = shallow_dip(mode, v, a0, p1, s, noise, rest) {
                dip
            } else if noise > 1e-6 * size {
                stepped_turn(mode, inv_m, (q, v), (f_a, slope), rest, s)
            } else {
                mode.crossing(v - c, a0, -c, s, true).filter(|&x| x <= rest)
            };
            if let Some(tau) = turn {
                let f_tau = f_a + slope * tau;
                let (qt, _) = Step::new(mode, tau, inv_m).apply(q, v, f_a, f_tau);
                if wanted(s) {
                    return Ok(Rebound {
                        time: t_a + tau,
                        q: qt,
                    });
                }
                // A minimum: go on from it, q̇ = 0 there, its new sign from q̈.
                // Between two minima lies a maximum, which is wanted, so a segment
                // passes over at most one minimum; a second one would be rounding
                // that stops time from advancing: an error, never a hang.
                passed += 1;
                if passed > MAX_PASSED || t_a + tau <= t_a {
                    return Err(ImpactError::Stalled { time: t_a });
                }
                (q, v, s) = (qt, 0.0, 0.0);
                (t_a, f_a) = (t_a + tau, f_tau);
                continue;
            }
            let st = Step::new(mode, rest, inv_m);
            if !st.is_finite() {
                return Err(range(rest));
            }
            (q, v) = st.apply(q, v, f_a, fw[1]);
            if s * v <= 0.0 {
                // The turn rounds onto the end of the segment.
                if wanted(s) {
                    return Ok(Rebound { time: tw[1], q });
                }
                s = 0.0;
            }
            break;
        }
    }
    // After the last sample: constant force, static deflection q_s, and q̇ is
    // itself an unforced motion, whose zeros are in closed form.
    let (mut t_last, f_last) = (t[t.len() - 1], force[force.len() - 1]);
    let q_s = f_last * inv_m / w2;
    let never = Rebound {
        time: f64::INFINITY,
        q: q_s,
    };
    for _ in 0..2 {
        let a0 = f_last * inv_m - 2.0 * sig * v - w2 * q;
        let before = if s == 0.0 { start_sign(v, a0, 0.0) } else { s };
        if before == 0.0 {
            return Ok(never);
        }
        let Some(tau) = mode.first_zero(v, a0) else {
            return Ok(never);
        };
        let qt = q_s + mode.eval(q - q_s, v, tau).0;
        if wanted(before) {
            return Ok(Rebound {
                time: t_last + tau,
                q: qt,
            });
        }
        // Passed over a minimum: the next turn is a maximum.
        (q, v, s, t_last) = (qt, 0.0, 0.0, t_last + tau);
    }
    Ok(never)
}

/// A dip of q̇ shallower than this many times the closed form's rounding of
/// q̇ (`noise` in [`rebound`]) is found by [`shallow_dip`]: the closed form's
/// turn time is off by about noise/(4·depth) relative (measured ~0.45·ε·c/depth,
/// about 1e-10 at the bound), and below ~1e-14·c it loses the dip entirely.
const DIP_TRUST: f64 = 1e8;

/// The turn of a dip of q̇ right after a point of rest, where the closed form
/// q̇ = c + y cannot see it: Some(the turn) if it is found here (Some(None): no
/// turn in this segment, q̇ still in the dip at its end), None to leave the
/// segment to the other searches.
///
/// From q̇ = v = 0 with q̈ = a0 and q⃛ = j = p1 − 2σ·a0 of opposite signs, q̇
/// leaves 0 with the sign of a0 and turns back through 0 near T = −2·a0/j,
/// having dipped by a0²/(2|j|). When that depth is below [`DIP_TRUST`] times
/// the closed form's rounding, the turn is found instead on g(τ) = q̇(τ)/τ by
/// its Taylor series (see [`dip_rate`]): every term carries its own digits (no
/// cancellation against the ramp's quasi-static velocity c) and dividing by τ
/// removes the trivial zero at τ = 0 and the underflow of q̇ itself (a dip
/// from q0 = 5e-207 is 1e-415 deep). The window [0, min(4T, rest)] is short
/// against the mode (rate·4T ≤ 1), where the series converges in a few terms.
fn shallow_dip(
    mode: &Mode,
    v: f64,
    a0: f64,
    p1: f64,
    s: f64,
    noise: f64,
    rest: f64,
) -> Option<Option<f64>> {
    let j = p1 - 2.0 * mode.sigma * a0;
    if v != 0.0 || a0 * j >= 0.0 || s != sign(a0) {
        return None;
    }
    let t_dip = -2.0 * a0 / j;
    // The depth a0²/(2|j|) = |a0|·T/4 < DIP_TRUST·noise, without squaring a0
    // (which underflows).
    let shallow = a0.abs() * (0.25 * t_dip) < DIP_TRUST * noise;
    let window = (4.0 * t_dip).min(rest);
    if !shallow || mode.rate.max(mode.omega) * window > 1.0 {
        return None;
    }
    let g = |tau: f64| dip_rate(mode, a0, j, tau);
    let g_end = g(window);
    if s * g_end > 0.0 {
        // Still in the dip at the window's end: the whole segment if the window
        // is the segment (no turn in it), else not a dip of this shape.
        return (window == rest).then_some(None);
    }
    // Bisect [lo, hi]: s·g > 0 at lo (g(0) = a0), ≤ 0 at hi.
    let (mut lo, mut hi) = (0.0, window);
    loop {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if s * g(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(Some(hi))
}

/// g(τ) = q̇(τ)/τ from q̇(0) = 0, q̈(0) = a0, q⃛(0) = j under a force linear in
/// τ: Σ_{n≥2} d_n τ^{n−2}/(n−1)! with d_2 = a0, d_3 = j and
/// d_{n+2} = −2σ d_{n+1} − ω² d_n, carried as D_n = d_n τ^{n−2} (bounded for
/// rate·τ ≤ 1). Terms fall like (rate·τ)ⁿ/n!: a few for the dips it is used on.
fn dip_rate(mode: &Mode, a0: f64, j: f64, tau: f64) -> f64 {
    let (b1, b2) = (2.0 * mode.sigma * tau, mode.w2 * tau * tau);
    let (mut dp, mut d) = (a0, j * tau); // D_n, D_{n+1}, n = 2
    let (mut g, mut inv_fact) = (a0, 1.0); // Σ, 1/(n−1)!
    for n in 2..40 {
        // Add D_{n+1}/n!.
        inv_fact /= n as f64;
        let term = d * inv_fact;
        g += term;
        if term.abs() <= 1e-18 * a0.abs() && n > 3 {
            break;
        }
        (dp, d) = (d, -b1 * d - b2 * dp);
    }
    g
}

/// Minima one segment may pass over before [`rebound`] reports that time has
/// stopped advancing (one is the most an exact motion can have).
const MAX_PASSED: usize = 4;

/// Samples of q̇ per segment in [`stepped_turn`]'s bracketing.
const TURN_SAMPLES: usize = 64;

/// The first τ in (0, rest] at which q̇ leaves the sign `s`, from (q, q̇) =
/// `state` under the force f_a + slope·τ, with q̇ evaluated by exact steps (no
/// cancellation against the ramp's particular velocity): sampled on a uniform
/// grid and bisected to rounding. Used only on segments short against the
/// mode's time constants, where q̇ is smooth on the grid's scale.
fn stepped_turn(
    mode: &Mode,
    inv_m: f64,
    state: (f64, f64),
    force: (f64, f64),
    rest: f64,
    s: f64,
) -> Option<f64> {
    let (q, v) = state;
    let (f_a, slope) = force;
    let vel = |tau: f64| {
        Step::new(mode, tau, inv_m)
            .apply(q, v, f_a, f_a + slope * tau)
            .1
    };
    let mut lo = 0.0;
    for j in 1..=TURN_SAMPLES {
        let hi = if j == TURN_SAMPLES {
            rest
        } else {
            rest * j as f64 / TURN_SAMPLES as f64
        };
        if s * vel(hi) > 0.0 {
            lo = hi;
            continue;
        }
        // Bisect [lo, hi]: s·q̇ > 0 at lo (or lo = 0), ≤ 0 at hi.
        let mut hi = hi;
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            if s * vel(mid) > 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        return Some(hi);
    }
    None
}

/// Cases per rayon task of the peak-only batch.
pub(super) const REBOUND_TASK: usize = 64;

/// First rebounds of B oscillators driven by B pulse tables (B, K) on one time
/// grid `t` (K,): `time_out` (B,) and `q_out` (B,); with `maximum`, the first
/// local maxima (see [`first_turn`]).
#[allow(clippy::too_many_arguments)] // the grid, the cases, the kind and the outputs
pub fn first_rebound_batch_into(
    t: &[f64],
    forces: &[f64],
    cases: &Cases<'_>,
    maximum: bool,
    n_threads: Option<i64>,
    time_out: &mut [f64],
    q_out: &mut [f64],
) -> Result<(), ImpactError> {
    check_times("t", t)?;
    let (b, k) = (cases.len()?, t.len());
    length("forces", forces.len(), b * k, "B*K: one row of K per case")?;
    length("time_out", time_out.len(), b, "one per case")?;
    length("q_out", q_out.len(), b, "one per case")?;
    let one = |i: usize, f: &[f64]| -> Result<Rebound, ImpactError> {
        let (mode, inv_m, q0, v0) = cases.case(i)?;
        check_finite("force", f)
            .and_then(|_| rebound(t, f, &mode, inv_m, q0, v0, maximum))
            .map_err(ImpactError::case(i))
    };
    let block = |j: usize, f: &[f64], to: &mut [f64], qo: &mut [f64]| {
        for (r, (fr, (tt, qq))) in f.chunks(k).zip(to.iter_mut().zip(qo)).enumerate() {
            if r % REBOUND_TASK == 0 && crate::cancel::requested() {
                return None;
            }
            let i = j * REBOUND_TASK + r;
            match one(i, fr) {
                Ok(reb) => (*tt, *qq) = (reb.time, reb.q),
                Err(e) => return Some((i, e)),
            }
        }
        None
    };
    let threads = resolve_threads(n_threads)?;
    let first_error = if threads == 1 || b <= REBOUND_TASK {
        block(0, forces, time_out, q_out)
    } else {
        pool(threads)?.install(|| {
            forces
                .par_chunks(REBOUND_TASK * k)
                .zip(time_out.par_chunks_mut(REBOUND_TASK))
                .zip(q_out.par_chunks_mut(REBOUND_TASK))
                .enumerate()
                .filter_map(|(j, ((f, to), qo))| block(j, f, to, qo))
                .min_by_key(|(i, _)| *i)
        })
    };
    match first_error {
        Some((_, e)) => Err(e),
        None => Ok(()),
    }
}
