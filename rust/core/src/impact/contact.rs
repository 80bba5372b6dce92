//! A link on its stop as an exact event-driven unilateral contact.

use rayon::prelude::*;

use crate::parallel::{pool, resolve_threads};

use super::error::{check_times, finite, length, mode_range, param, ImpactError};
use super::oscillator::Mode;
use super::rebound::REBOUND_TASK;

/// Events a contact history follows by default before it reports chattering.
pub const MAX_EVENTS: usize = 10_000;

/// A link and its stop: `mass` m, free stiffness k_f (`k_free`), stop stiffness
/// k_s (`k_stop`), preload δ (`preload`: the free spring's equilibrium lies δ
/// inside the stop), and the damping ratio of each regime relative to its own
/// stiffness (c = 2ζ√(k m); k_c = k_f + k_s in contact). Consistent units (SI:
/// kg, N/m, m; or a lever's inertia, N·m/rad and rad).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    pub mass: f64,
    pub k_free: f64,
    pub k_stop: f64,
    pub preload: f64,
    pub zeta_free: f64,
    pub zeta_contact: f64,
}

/// Why a contact history stops.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ContactEnd {
    /// The next event would come after `t_end`; the stop state is at `t_end`.
    TEnd,
    /// `max_rebounds` rebound maxima were found; the stop state is the last one.
    MaxRebounds,
    /// The contact never ends: the link settles in contact at x_c = −k_f δ/k_c
    /// (also a link at rest on the stop).
    RestInContact,
    /// The free flight never returns to the stop (δ = 0 with ζ_free ≥ 1): the
    /// link creeps towards x = 0 from above.
    RestFree,
    /// `max_events` crossings of x = 0 (chattering); the stop state is the last.
    MaxEvents,
}

impl ContactEnd {
    /// The name the Python layer reports.
    pub fn name(&self) -> &'static str {
        match self {
            ContactEnd::TEnd => "t_end",
            ContactEnd::MaxRebounds => "max_rebounds",
            ContactEnd::RestInContact => "rest_in_contact",
            ContactEnd::RestFree => "rest_free",
            ContactEnd::MaxEvents => "max_events",
        }
    }
}

/// The events of a contact history, in time order.
///
/// Contact i runs from `contact_start[i]` (arriving at `impact_velocity[i]` ≤ 0)
/// to `contact_end[i]` (leaving at `exit_velocity[i]` > 0), with
/// `contact_duration[i]` = end − start; its deepest point is `penetration[i]` ≤ 0
/// at `penetration_time[i]`. A link that starts in contact (x0 < 0, or x0 = 0
/// with v0 ≤ 0) has its first contact start at t = 0 with impact velocity v0.
/// Rebound j is the free flight after contact j: its top `rebound_height[j]` at
/// `rebound_time[j]` (the initial flight of a link that starts free is not a
/// rebound). The last contact may have no end (the arrays of ends are then one
/// shorter). `t_stop`, `x_stop`, `v_stop` is where the history stops (see
/// [`ContactEnd`]); at rest it is (+∞, the rest position, 0).
#[derive(Debug, Clone, PartialEq)]
pub struct ContactHistory {
    pub contact_start: Vec<f64>,
    pub impact_velocity: Vec<f64>,
    pub contact_end: Vec<f64>,
    pub exit_velocity: Vec<f64>,
    pub contact_duration: Vec<f64>,
    pub penetration_time: Vec<f64>,
    pub penetration: Vec<f64>,
    pub rebound_time: Vec<f64>,
    pub rebound_height: Vec<f64>,
    /// Crossings of x = 0 followed.
    pub n_events: usize,
    pub end: ContactEnd,
    pub t_stop: f64,
    pub x_stop: f64,
    pub v_stop: f64,
}

/// One regime: an unforced oscillator about its equilibrium `x_eq`.
struct Regime {
    mode: Mode,
    x_eq: f64,
    contact: bool,
}

impl Regime {
    /// Time until x crosses 0 (leaves the regime) from (x, v), if ever. A touch
    /// of x = 0 (x̄ = 0 with ẋ = 0) is no crossing.
    fn exit(&self, x: f64, v: f64) -> Option<f64> {
        let side = if self.contact { -1.0 } else { 1.0 };
        self.mode
            .crossing(x - self.x_eq, v, -self.x_eq, side, false)
    }

    /// (x, ẋ) a time τ after (x, v).
    fn at(&self, x: f64, v: f64, tau: f64) -> (f64, f64) {
        let (y, dy) = self.mode.eval(x - self.x_eq, v, tau);
        (self.x_eq + y, dy)
    }
}

impl Contact {
    /// m, k_f, k_s finite and > 0; δ, ζ_free, ζ_contact finite and ≥ 0.
    pub fn validate(&self) -> Result<(), ImpactError> {
        let pos = "finite and > 0";
        param("mass", self.mass, self.mass > 0.0, pos)?;
        param("k_free", self.k_free, self.k_free > 0.0, pos)?;
        param("k_stop", self.k_stop, self.k_stop > 0.0, pos)?;
        let nonneg = "finite and >= 0";
        param("preload", self.preload, self.preload >= 0.0, nonneg)?;
        param("zeta_free", self.zeta_free, self.zeta_free >= 0.0, nonneg)?;
        param(
            "zeta_contact",
            self.zeta_contact,
            self.zeta_contact >= 0.0,
            nonneg,
        )?;
        let free = (self.k_free / self.mass).sqrt();
        mode_range("sqrt(k_free / mass)", free, self.zeta_free)?;
        let contact = ((self.k_free + self.k_stop) / self.mass).sqrt();
        mode_range("sqrt((k_free + k_stop) / mass)", contact, self.zeta_contact)
    }

    fn regime(&self, contact: bool) -> Regime {
        if contact {
            let kc = self.k_free + self.k_stop;
            Regime {
                mode: Mode::new((kc / self.mass).sqrt(), self.zeta_contact),
                x_eq: -self.k_free * self.preload / kc,
                contact,
            }
        } else {
            Regime {
                mode: Mode::new((self.k_free / self.mass).sqrt(), self.zeta_free),
                x_eq: -self.preload,
                contact,
            }
        }
    }

    /// Contact or free at the start: in contact if x0 < 0, or on the stop
    /// (x0 = 0) and not leaving it.
    fn starts_in_contact(x0: f64, v0: f64) -> bool {
        x0 < 0.0 || (x0 == 0.0 && v0 <= 0.0)
    }

    fn check_start(&self, x0: f64, v0: f64, max_events: usize) -> Result<(), ImpactError> {
        self.validate()?;
        finite("x0", x0)?;
        finite("v0", v0)?;
        if max_events == 0 {
            return Err(ImpactError::Count {
                field: "max_events",
                value: 0,
                want: ">= 1",
            });
        }
        Ok(())
    }
}

/// The event history of a link released at x0 with velocity v0 at t = 0 (x0 = 0
/// with v0 < 0: arriving at the stop), up to `t_end` (> 0, may be +∞),
/// `max_rebounds` (≥ 1) rebound maxima or `max_events` (≥ 1) crossings, or until
/// it comes to rest.
pub fn contact_response(
    stop: &Contact,
    x0: f64,
    v0: f64,
    t_end: f64,
    max_rebounds: usize,
    max_events: usize,
) -> Result<ContactHistory, ImpactError> {
    stop.check_start(x0, v0, max_events)?;
    if t_end.is_nan() || t_end <= 0.0 {
        return Err(ImpactError::Param {
            field: "t_end",
            value: t_end,
            want: "> 0 (+inf for no limit)",
        });
    }
    if max_rebounds == 0 {
        return Err(ImpactError::Count {
            field: "max_rebounds",
            value: 0,
            want: ">= 1",
        });
    }
    let mut contact = Contact::starts_in_contact(x0, v0);
    let mut h = ContactHistory {
        contact_start: Vec::new(),
        impact_velocity: Vec::new(),
        contact_end: Vec::new(),
        exit_velocity: Vec::new(),
        contact_duration: Vec::new(),
        penetration_time: Vec::new(),
        penetration: Vec::new(),
        rebound_time: Vec::new(),
        rebound_height: Vec::new(),
        n_events: 0,
        end: ContactEnd::TEnd,
        t_stop: 0.0,
        x_stop: x0,
        v_stop: v0,
    };
    if contact {
        h.contact_start.push(0.0);
        h.impact_velocity.push(v0);
    }
    let (mut t, mut x, mut v) = (0.0, x0, v0);
    // Whether the current free flight follows a contact.
    let mut rebound = false;
    loop {
        let r = stop.regime(contact);
        let tmax = t_end - t;
        let exit = r.exit(x, v);
        let limit = exit.unwrap_or(f64::INFINITY).min(tmax);
        if contact || rebound {
            // The deepest point of a contact, the top of a rebound.
            let ext = r.mode.extremum(x - r.x_eq, v, !contact);
            if let Some((z, y)) = ext.filter(|&(z, _)| z <= limit) {
                let xe = r.x_eq + y;
                if contact {
                    h.penetration_time.push(t + z);
                    h.penetration.push(xe);
                } else {
                    h.rebound_time.push(t + z);
                    h.rebound_height.push(xe);
                    if h.rebound_height.len() >= max_rebounds {
                        (h.end, h.t_stop, h.x_stop, h.v_stop) =
                            (ContactEnd::MaxRebounds, t + z, xe, 0.0);
                        return Ok(h);
                    }
                }
            }
        }
        let tau = match exit {
            None => {
                h.end = if contact {
                    ContactEnd::RestInContact
                } else {
                    ContactEnd::RestFree
                };
                (h.t_stop, h.x_stop, h.v_stop) = (f64::INFINITY, r.x_eq, 0.0);
                return Ok(h);
            }
            Some(tau) if tau > tmax => {
                let (xs, vs) = r.at(x, v, tmax);
                (h.end, h.t_stop, h.x_stop, h.v_stop) = (ContactEnd::TEnd, t_end, xs, vs);
                return Ok(h);
            }
            Some(tau) => tau,
        };
        let vc = r.at(x, v, tau).1;
        (t, x, v) = (t + tau, 0.0, vc);
        h.n_events += 1;
        if !contact {
            h.contact_start.push(t);
            h.impact_velocity.push(v);
            contact = true;
        } else if v > 0.0 {
            let start = h.contact_start.last().copied().unwrap_or(0.0);
            h.contact_end.push(t);
            h.exit_velocity.push(v);
            h.contact_duration.push(t - start);
            contact = false;
            rebound = true;
        }
        if h.n_events >= max_events {
            (h.end, h.t_stop, h.x_stop, h.v_stop) = (ContactEnd::MaxEvents, t, x, v);
            return Ok(h);
        }
    }
}

/// First rebound heights [m] of one link on its stop for many impact states
/// (x0, v0) in parallel: the highest point of the first free flight after a
/// contact, 0 where the link never leaves the stop again.
pub fn contact_rebound_batch_into(
    stop: &Contact,
    x0: &[f64],
    v0: &[f64],
    n_threads: Option<i64>,
    out: &mut [f64],
) -> Result<(), ImpactError> {
    length("v0", v0.len(), x0.len(), "one per x0")?;
    length("out", out.len(), x0.len(), "one per case")?;
    let one = |i: usize| -> Result<f64, ImpactError> {
        let h = contact_response(stop, x0[i], v0[i], f64::INFINITY, 1, MAX_EVENTS)
            .map_err(ImpactError::case(i))?;
        Ok(h.rebound_height.first().copied().unwrap_or(0.0))
    };
    let threads = resolve_threads(n_threads)?;
    if threads == 1 || x0.len() < 2 * REBOUND_TASK {
        for (i, o) in out.iter_mut().enumerate() {
            if i % REBOUND_TASK == 0 && crate::cancel::requested() {
                return Ok(());
            }
            *o = one(i)?;
        }
        return Ok(());
    }
    let first_error = pool(threads)?.install(|| {
        out.par_chunks_mut(REBOUND_TASK)
            .enumerate()
            .filter_map(|(j, os)| {
                if crate::cancel::requested() {
                    return None;
                }
                for (r, o) in os.iter_mut().enumerate() {
                    let i = j * REBOUND_TASK + r;
                    match one(i) {
                        Ok(v) => *o = v,
                        Err(e) => return Some((i, e)),
                    }
                }
                None
            })
            .min_by_key(|(i, _)| *i)
    });
    match first_error {
        Some((_, e)) => Err(e),
        None => Ok(()),
    }
}

/// x(t) and ẋ(t) of the same history at `times` (non-decreasing, ≥ 0), by the
/// same piecewise closed form; more than `max_events` crossings before the last
/// time is an error (the link chatters).
pub fn contact_sample_into(
    stop: &Contact,
    x0: f64,
    v0: f64,
    times: &[f64],
    max_events: usize,
    x_out: &mut [f64],
    v_out: &mut [f64],
) -> Result<(), ImpactError> {
    stop.check_start(x0, v0, max_events)?;
    let n = times.len();
    length("x_out", x_out.len(), n, "one per time")?;
    length("v_out", v_out.len(), n, "one per time")?;
    if n == 0 {
        return Ok(());
    }
    check_times("times", times)?;
    param(
        "times[0]",
        times[0],
        times[0] >= 0.0,
        ">= 0 (the history starts at t = 0)",
    )?;
    let mut contact = Contact::starts_in_contact(x0, v0);
    let (mut t, mut x, mut v) = (0.0, x0, v0);
    let (mut i, mut events) = (0, 0);
    loop {
        let r = stop.regime(contact);
        let exit = r.exit(x, v);
        let t_next = exit.map_or(f64::INFINITY, |tau| t + tau);
        while i < n && times[i] <= t_next {
            (x_out[i], v_out[i]) = r.at(x, v, times[i] - t);
            i += 1;
        }
        let Some(tau) = exit.filter(|_| i < n) else {
            return Ok(());
        };
        if events >= max_events {
            return Err(ImpactError::TooManyEvents {
                max_events,
                time: t,
            });
        }
        let vc = r.at(x, v, tau).1;
        (t, x, v) = (t_next, 0.0, vc);
        // Leave the contact only moving out (a touch stays), as in the history.
        if !contact || v > 0.0 {
            contact = !contact;
        }
        events += 1;
    }
}
