//! The planar four-bar and the offset slider-crank by their lengths: the checks
//! every synthesis result is held to (issue 35, item 5).
//!
//! **Four-bar conventions.** Ground pivot A at the origin, ground pivot D at
//! (d, 0); crank AB of length a (the input, angle θ from AD, counter-clockwise),
//! coupler BC of length b, rocker DC of length c (the output, angle θ4 from the
//! x axis at D). The transmission angle μ ∈ [0, π] is the angle BCD between
//! coupler and rocker; by the cosine rule on the diagonal BD,
//! BD² = a² + d² − 2ad·cos θ = b² + c² − 2bc·cos μ, so
//!
//! cos μ = (b² + c² − a² − d² + 2ad·cos θ) / (2bc),
//!
//! affine (increasing) in cos θ. Over a crank range [θlo, θhi] its extremes are
//! therefore at the range's ends and at θ = 0 (mod 2π, largest cos μ) and θ = π
//! (mod 2π, smallest) where those lie inside: a closed form, no sampling. The
//! linkage assembles at θ iff |cos μ| ≤ 1; the worst (acute) transmission angle
//! is min(μ_min, π − μ_max).
//!
//! **Assembly mode.** θ4 = arg(B − D) + σ·γ with γ = ∠BDC ∈ [0, π] from the
//! cosine rule in triangle BDC and σ = ±1: σ = +1 puts C on the left of the ray
//! D → B (counter-clockwise from DB seen at D), σ = −1 on its right. Along a crank
//! motion that keeps |cos μ| < 1, γ stays inside (0, π) and σ does not change: σ
//! is the branch.
//!
//! **Offset slider-crank.** Crank pivot at the origin, crank r at angle θ from the
//! slide direction (+x), rod l, the slider's pin on the line y = e (the offset).
//! The pin is at x = r·cos θ + σ·√(l² − (e − r·sin θ)²), σ = +1 for the slider on
//! the +x side of the crank pin. The transmission angle is the angle between the
//! rod and the normal of the slide, cos μ = (r·sin θ − e)/l (μ = 90° when the rod
//! is parallel to the slide), affine in sin θ: extremes at the ends and at
//! θ = π/2, 3π/2 where inside. It assembles iff |cos μ| ≤ 1.
//!
//! **Grashof.** With s, l the shortest and longest lengths and p, q the others:
//! s + l < p + q is a Grashof linkage, whose shortest link turns fully relative
//! to every other; s + l = p + q (to a relative [`CHANGE_POINT_TOL`]) is a change
//! point (links fold flat once a turn: the branch is ambiguous there); s + l > p + q
//! is a non-Grashof triple-rocker, no link turning fully. The crank (a) turns
//! fully relative to the ground iff the linkage is Grashof or change point and
//! min(a, d) = s; the output (c) likewise with min(c, d).

use std::f64::consts::{PI, TAU};

use crate::input::InvalidInput;

/// Relative tolerance on s + l = p + q for a change point: Grashof sums within
/// this fraction of the perimeter are called a change point (the float sum of
/// lengths given to 16 digits cannot say more).
pub const CHANGE_POINT_TOL: f64 = 1e-12;

/// A four-bar's Grashof type (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Grashof {
    /// Grashof, the crank a shortest: the crank turns fully, the output rocks.
    CrankRocker,
    /// Grashof, the output c shortest: the output turns fully, the input rocks.
    RockerCrank,
    /// Grashof, the ground d shortest: both crank and output turn fully.
    DoubleCrank,
    /// Grashof, the coupler b shortest: the coupler turns fully, a and c rock.
    DoubleRocker,
    /// s + l = p + q: the linkage folds flat once a turn (branch ambiguous there).
    ChangePoint,
    /// Non-Grashof: no link turns fully.
    TripleRocker,
}

impl Grashof {
    /// The names the Python layer shows, in the order of the variants.
    pub const NAMES: [&'static str; 6] = [
        "crank-rocker",
        "rocker-crank",
        "double-crank",
        "double-rocker",
        "change point",
        "triple-rocker",
    ];

    /// Its name (one of [`Grashof::NAMES`]).
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }
}

/// The Grashof type and which of crank and output turn fully relative to the
/// ground.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GrashofInfo {
    pub kind: Grashof,
    /// The crank a turns fully relative to the ground.
    pub crank_turns: bool,
    /// The output c turns fully relative to the ground.
    pub output_turns: bool,
}

fn check_lengths(named: &[(&'static str, f64)]) -> Result<(), InvalidInput> {
    for &(field, v) in named {
        if !(v.is_finite() && v > 0.0) {
            return Err(InvalidInput::bad_value(
                field,
                v,
                "[m] must be a finite length > 0",
            ));
        }
    }
    Ok(())
}

/// The Grashof type of the four-bar a (crank), b (coupler), c (output), d (ground)
/// [m] (module docs), or an error naming a length that is not finite and > 0.
pub fn grashof(a: f64, b: f64, c: f64, d: f64) -> Result<GrashofInfo, InvalidInput> {
    check_lengths(&[("a", a), ("b", b), ("c", c), ("d", d)])?;
    let mut all = [a, b, c, d];
    all.sort_by(f64::total_cmp);
    let (s, p, q, l) = (all[0], all[1], all[2], all[3]);
    let excess = (s + l) - (p + q);
    let perimeter = a + b + c + d;
    let kind = if excess.abs() <= CHANGE_POINT_TOL * perimeter {
        Grashof::ChangePoint
    } else if excess > 0.0 {
        Grashof::TripleRocker
    } else if d == s {
        Grashof::DoubleCrank
    } else if a == s {
        Grashof::CrankRocker
    } else if c == s {
        Grashof::RockerCrank
    } else {
        Grashof::DoubleRocker
    };
    let grashof = kind != Grashof::TripleRocker;
    Ok(GrashofInfo {
        kind,
        crank_turns: grashof && a.min(d) == s,
        output_turns: grashof && c.min(d) == s,
    })
}

/// The extremes of a transmission angle over a crank range, or where the
/// linkage cannot be assembled.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Transmission {
    /// It assembles over the whole range: μ ∈ [mu_min, mu_max] [rad], reached at
    /// crank angles theta_at_min and theta_at_max [rad] (inside the range).
    Range {
        mu_min: f64,
        mu_max: f64,
        theta_at_min: f64,
        theta_at_max: f64,
    },
    /// It cannot be assembled at crank angle `theta` [rad] of the range (the
    /// one where |cos μ| is largest), where cos μ would be `cos_mu` (|·| > 1).
    Breaks { theta: f64, cos_mu: f64 },
}

impl Transmission {
    /// The worst (acute) transmission angle min(μ_min, π − μ_max) [rad], or None
    /// where it does not assemble.
    pub fn worst(&self) -> Option<f64> {
        match *self {
            Transmission::Range { mu_min, mu_max, .. } => Some(mu_min.min(PI - mu_max)),
            Transmission::Breaks { .. } => None,
        }
    }
}

fn check_range(lo: f64, hi: f64) -> Result<(), InvalidInput> {
    if !lo.is_finite() {
        return Err(InvalidInput::bad_value(
            "theta_lo",
            lo,
            "[rad] must be finite",
        ));
    }
    if !(hi.is_finite() && hi >= lo) {
        return Err(InvalidInput::bad_value(
            "theta_hi",
            hi,
            format!("[rad] must be finite and ≥ theta_lo = {lo}"),
        ));
    }
    Ok(())
}

/// The crank angles where an affine function of cos(θ − shift) can have its
/// extremes over [lo, hi]: the ends, and θ = shift + kπ inside (the extremes of
/// the cosine).
fn candidates(lo: f64, hi: f64, shift: f64) -> Vec<f64> {
    let mut out = vec![lo, hi];
    // First k with shift + kπ ≥ lo; a full turn holds at most three such angles.
    let mut k = ((lo - shift) / PI).ceil();
    while shift + k * PI <= hi && out.len() < 6 {
        out.push(shift + k * PI);
        k += 1.0;
    }
    out
}

/// Extremes of `cos_mu(θ)` over the candidate angles, turned into a
/// [`Transmission`] (μ decreasing in cos μ).
fn extremes(cands: &[f64], cos_mu: impl Fn(f64) -> f64) -> Transmission {
    let (mut lo_t, mut lo_c) = (cands[0], cos_mu(cands[0]));
    let (mut hi_t, mut hi_c) = (lo_t, lo_c);
    for &t in &cands[1..] {
        let cm = cos_mu(t);
        if cm < lo_c {
            (lo_t, lo_c) = (t, cm);
        }
        if cm > hi_c {
            (hi_t, hi_c) = (t, cm);
        }
    }
    if hi_c > 1.0 || lo_c < -1.0 {
        let (theta, cos_mu) = if hi_c - 1.0 >= -1.0 - lo_c {
            (hi_t, hi_c)
        } else {
            (lo_t, lo_c)
        };
        return Transmission::Breaks { theta, cos_mu };
    }
    Transmission::Range {
        mu_min: hi_c.acos(),
        mu_max: lo_c.acos(),
        theta_at_min: hi_t,
        theta_at_max: lo_t,
    }
}

/// cos μ of the four-bar at crank angle θ [rad] (module docs).
pub fn fourbar_cos_mu(a: f64, b: f64, c: f64, d: f64, theta: f64) -> f64 {
    (b * b + c * c - a * a - d * d + 2.0 * a * d * theta.cos()) / (2.0 * b * c)
}

/// The four-bar's transmission angle's extremes over the crank range
/// [lo, hi] [rad] in closed form (module docs).
pub fn fourbar_transmission(
    a: f64,
    b: f64,
    c: f64,
    d: f64,
    lo: f64,
    hi: f64,
) -> Result<Transmission, InvalidInput> {
    check_lengths(&[("a", a), ("b", b), ("c", c), ("d", d)])?;
    check_range(lo, hi)?;
    let cands = candidates(lo, hi, 0.0);
    Ok(extremes(&cands, |t| fourbar_cos_mu(a, b, c, d, t)))
}

/// The output angle θ4 [rad] (from +x at D, in (−π, π]) at crank angle θ [rad]
/// on branch σ = ±1 (module docs), or None where it does not assemble.
pub fn fourbar_output_angle(a: f64, b: f64, c: f64, d: f64, theta: f64, sigma: f64) -> Option<f64> {
    let (bx, by) = (a * theta.cos() - d, a * theta.sin());
    let f2 = bx * bx + by * by;
    let f = f2.sqrt();
    if f == 0.0 {
        return None;
    }
    let cos_g = (c * c + f2 - b * b) / (2.0 * c * f);
    if !(-1.0..=1.0).contains(&cos_g) {
        return None;
    }
    let theta4 = by.atan2(bx) + sigma.signum() * cos_g.acos();
    // Back into (−π, π].
    Some(theta4 - TAU * ((theta4 + PI) / TAU).ceil() + TAU)
}

/// The coupler point P [m] at crank angle θ [rad] on branch σ = ±1, or None
/// where it does not assemble. P is (u, v) [m] in the coupler's frame: u along
/// B → C, v to its left (the Python layer's `coupler_point`); A at the origin,
/// D at (d, 0).
#[allow(clippy::too_many_arguments)]
pub fn coupler_point(
    a: f64,
    b: f64,
    c: f64,
    d: f64,
    theta: f64,
    sigma: f64,
    u: f64,
    v: f64,
) -> Option<[f64; 2]> {
    let t4 = fourbar_output_angle(a, b, c, d, theta, sigma)?;
    let (bx, by) = (a * theta.cos(), a * theta.sin());
    let (cx, cy) = (d + c * t4.cos(), c * t4.sin());
    // |BC| = b on an assembled pose: the unit vector along the coupler.
    let (ex, ey) = ((cx - bx) / b, (cy - by) / b);
    Some([bx + u * ex - v * ey, by + u * ey + v * ex])
}

/// The branch σ = ±1 of a four-bar drawn with crank pin B and rocker pin C (D at
/// (d, 0)): the side of the ray D → B that C is on (module docs); 0 when C is on
/// the line DB (a folded pose, the branch undefined).
pub fn fourbar_branch(d: f64, b_pin: [f64; 2], c_pin: [f64; 2]) -> f64 {
    let (ux, uy) = (b_pin[0] - d, b_pin[1]);
    let (vx, vy) = (c_pin[0] - d, c_pin[1]);
    let z = ux * vy - uy * vx;
    if z > 0.0 {
        1.0
    } else if z < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// Whether the offset slider-crank's crank turns fully.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SliderCrankKind {
    /// r + |e| < l: the crank turns fully.
    Crank,
    /// r + |e| = l (to [`CHANGE_POINT_TOL`]): rod and slide line up once a turn.
    ChangePoint,
    /// r + |e| > l: the crank only rocks.
    Rocker,
}

impl SliderCrankKind {
    /// The names the Python layer shows, in the order of the variants.
    pub const NAMES: [&'static str; 3] = ["crank-slider", "change point", "rocker-slider"];

    /// Its name (one of [`SliderCrankKind::NAMES`]).
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }
}

/// The offset slider-crank's kind: crank r [m] and rod l [m] > 0, offset e [m]
/// of either sign.
pub fn slider_crank_kind(r: f64, l: f64, e: f64) -> Result<SliderCrankKind, InvalidInput> {
    check_lengths(&[("r", r), ("l", l)])?;
    if !e.is_finite() {
        return Err(InvalidInput::bad_value("e", e, "[m] must be finite"));
    }
    let excess = r + e.abs() - l;
    Ok(if excess.abs() <= CHANGE_POINT_TOL * (r + l + e.abs()) {
        SliderCrankKind::ChangePoint
    } else if excess < 0.0 {
        SliderCrankKind::Crank
    } else {
        SliderCrankKind::Rocker
    })
}

/// cos μ of the slider-crank at crank angle θ [rad] (module docs).
pub fn slider_crank_cos_mu(r: f64, l: f64, e: f64, theta: f64) -> f64 {
    (r * theta.sin() - e) / l
}

/// The slider-crank's transmission angle's extremes over [lo, hi] [rad] in
/// closed form (module docs).
pub fn slider_crank_transmission(
    r: f64,
    l: f64,
    e: f64,
    lo: f64,
    hi: f64,
) -> Result<Transmission, InvalidInput> {
    slider_crank_kind(r, l, e)?;
    check_range(lo, hi)?;
    // sin θ = cos(θ − π/2): its extremes at π/2 + kπ.
    let cands = candidates(lo, hi, PI / 2.0);
    Ok(extremes(&cands, |t| slider_crank_cos_mu(r, l, e, t)))
}

/// The slider's pin position x [m] at crank angle θ [rad] on branch σ = ±1
/// (module docs), or None where it does not assemble.
pub fn slider_crank_position(r: f64, l: f64, e: f64, theta: f64, sigma: f64) -> Option<f64> {
    let h = e - r * theta.sin();
    let w = l * l - h * h;
    if w < 0.0 {
        return None;
    }
    Some(r * theta.cos() + sigma.signum() * w.sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Dense sampling's extremes of cos μ over [lo, hi] (the independent check).
    fn sampled(lo: f64, hi: f64, f: impl Fn(f64) -> f64) -> (f64, f64) {
        let n = 20_000;
        (0..=n)
            .map(|i| f(lo + (hi - lo) * i as f64 / n as f64))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(m, x), v| {
                (m.min(v), x.max(v))
            })
    }

    #[test]
    fn grashof_types() {
        let g = |a, b, c, d| grashof(a, b, c, d).unwrap();
        assert_eq!(g(1.0, 3.0, 3.5, 4.0).kind, Grashof::CrankRocker);
        assert!(g(1.0, 3.0, 3.5, 4.0).crank_turns);
        assert!(!g(1.0, 3.0, 3.5, 4.0).output_turns);
        assert_eq!(g(3.0, 3.5, 4.0, 1.0).kind, Grashof::DoubleCrank);
        assert!(g(3.0, 3.5, 4.0, 1.0).output_turns);
        assert_eq!(g(3.0, 1.0, 3.5, 4.0).kind, Grashof::DoubleRocker);
        assert_eq!(g(3.0, 3.5, 1.0, 4.0).kind, Grashof::RockerCrank);
        assert_eq!(g(2.0, 4.0, 2.0, 4.0).kind, Grashof::ChangePoint); // parallelogram
        assert!(g(2.0, 4.0, 2.0, 4.0).crank_turns);
        let t = g(3.0, 3.0, 3.0, 4.0);
        assert_eq!(t.kind, Grashof::TripleRocker);
        assert!(!t.crank_turns && !t.output_turns);
        assert_eq!(Grashof::TripleRocker.name(), "triple-rocker");
        assert!(grashof(0.0, 1.0, 1.0, 1.0).is_err());
        assert!(grashof(1.0, f64::NAN, 1.0, 1.0).is_err());
    }

    #[test]
    fn transmission_matches_sampling_on_a_crank_rocker() {
        let (a, b, c, d) = (1.0, 3.0, 3.5, 4.0);
        let Transmission::Range { mu_min, mu_max, .. } =
            fourbar_transmission(a, b, c, d, 0.0, TAU).unwrap()
        else {
            panic!("a crank-rocker assembles over a full turn")
        };
        // Closed form by hand: θ = 0 gives BD = 3, θ = π gives BD = 5.
        let at = |bd: f64| ((b * b + c * c - bd * bd) / (2.0 * b * c)).acos();
        assert!((mu_min - at(3.0)).abs() < 1e-15);
        assert!((mu_max - at(5.0)).abs() < 1e-15);
    }

    #[test]
    fn breaks_where_it_cannot_assemble() {
        // Triple-rocker over a full turn: it must break somewhere.
        match fourbar_transmission(3.0, 3.0, 3.0, 4.0, 0.0, TAU).unwrap() {
            Transmission::Breaks { cos_mu, .. } => assert!(cos_mu.abs() > 1.0),
            r => panic!("expected a break, got {r:?}"),
        }
        assert!(fourbar_output_angle(3.0, 3.0, 3.0, 4.0, PI, 1.0).is_none());
        assert!(fourbar_transmission(1.0, 1.0, 1.0, 1.0, 1.0, 0.0).is_err());
    }

    #[test]
    fn output_angle_closes_the_loop_on_both_branches() {
        let (a, b, c, d) = (1.0, 3.0, 3.5, 4.0);
        for sigma in [1.0, -1.0] {
            for i in 0..64 {
                let th = i as f64 * TAU / 64.0;
                let t4 = fourbar_output_angle(a, b, c, d, th, sigma).unwrap();
                let bp = [a * th.cos(), a * th.sin()];
                let cp = [d + c * t4.cos(), c * t4.sin()];
                let bc = ((cp[0] - bp[0]).powi(2) + (cp[1] - bp[1]).powi(2)).sqrt();
                assert!((bc - b).abs() < 1e-12, "{bc}");
                assert_eq!(fourbar_branch(d, bp, cp), sigma);
            }
        }
    }

    #[test]
    fn coupler_point_is_rigid_with_the_coupler() {
        let (a, b, c, d, u, v) = (1.0, 3.0, 3.5, 4.0, 1.2, 0.7);
        for i in 0..32 {
            let th = i as f64 * TAU / 32.0;
            let p = coupler_point(a, b, c, d, th, 1.0, u, v).unwrap();
            let t4 = fourbar_output_angle(a, b, c, d, th, 1.0).unwrap();
            let bp = [a * th.cos(), a * th.sin()];
            let cp = [d + c * t4.cos(), c * t4.sin()];
            // Distances to B and C are those of (u, v) to (0, 0) and (b, 0).
            let pb = (p[0] - bp[0]).hypot(p[1] - bp[1]);
            let pc = (p[0] - cp[0]).hypot(p[1] - cp[1]);
            assert!((pb - u.hypot(v)).abs() < 1e-12);
            assert!((pc - (u - b).hypot(v)).abs() < 1e-12);
            // v > 0: P on the left of B → C.
            assert!(fourbar_branch_side(bp, cp, p) > 0.0);
        }
        assert!(coupler_point(3.0, 3.0, 3.0, 4.0, PI, 1.0, 0.0, 0.0).is_none());
    }

    fn fourbar_branch_side(p: [f64; 2], q: [f64; 2], r: [f64; 2]) -> f64 {
        (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])
    }

    #[test]
    fn slider_crank_kinds_and_position() {
        assert_eq!(
            slider_crank_kind(1.0, 3.0, 0.5).unwrap(),
            SliderCrankKind::Crank
        );
        assert_eq!(
            slider_crank_kind(1.0, 1.5, -0.5).unwrap(),
            SliderCrankKind::ChangePoint
        );
        assert_eq!(
            slider_crank_kind(1.0, 1.2, 0.5).unwrap(),
            SliderCrankKind::Rocker
        );
        assert!(slider_crank_kind(1.0, 1.2, f64::INFINITY).is_err());
        // Centred: x = r cos θ + √(l² − r² sin² θ); at θ = π/2 it is √(l² − r²).
        let x = slider_crank_position(0.1, 0.35, 0.0, PI / 2.0, 1.0).unwrap();
        assert!((x - (0.35f64 * 0.35 - 0.01).sqrt()).abs() < 1e-15);
        assert!(slider_crank_position(1.0, 1.2, 0.5, -PI / 2.0, 1.0).is_none());
    }

    proptest! {
        #[test]
        fn fourbar_extremes_equal_dense_sampling(
            a in 0.2f64..5.0, b in 0.2f64..5.0, c in 0.2f64..5.0, d in 0.2f64..5.0,
            lo in -7.0f64..7.0, span in 0.0f64..8.0,
        ) {
            let hi = lo + span;
            let (smin, smax) = sampled(lo, hi, |t| fourbar_cos_mu(a, b, c, d, t));
            match fourbar_transmission(a, b, c, d, lo, hi).unwrap() {
                Transmission::Range { mu_min, mu_max, theta_at_min, theta_at_max } => {
                    prop_assert!(smax <= 1.0 + 1e-12 && smin >= -1.0 - 1e-12);
                    // The closed form bounds every sample and is reached at its angles.
                    prop_assert!(mu_min.cos() >= smax - 1e-12);
                    prop_assert!(mu_max.cos() <= smin + 1e-12);
                    prop_assert!((fourbar_cos_mu(a, b, c, d, theta_at_min) - mu_min.cos()).abs() < 1e-12);
                    prop_assert!((fourbar_cos_mu(a, b, c, d, theta_at_max) - mu_max.cos()).abs() < 1e-12);
                    // Sampling at 20 001 points comes within the step's second-order error.
                    let step = span / 20_000.0;
                    let slack = a * d / (b * c) * step * step + 1e-12;
                    prop_assert!(mu_min.cos() - smax <= slack);
                    prop_assert!(smin - mu_max.cos() <= slack);
                    prop_assert!((lo..=hi).contains(&theta_at_min) && (lo..=hi).contains(&theta_at_max));
                    // The output angle exists everywhere inside.
                    for i in 0..=16 {
                        let t = lo + span * i as f64 / 16.0;
                        prop_assert!(fourbar_output_angle(a, b, c, d, t, 1.0).is_some()
                            || fourbar_cos_mu(a, b, c, d, t).abs() > 1.0 - 1e-9);
                    }
                }
                Transmission::Breaks { theta, cos_mu } => {
                    prop_assert!(cos_mu.abs() > 1.0);
                    prop_assert!((lo..=hi).contains(&theta));
                    prop_assert!(smax > 1.0 - 1e-9 || smin < -1.0 + 1e-9);
                }
            }
        }

        #[test]
        fn slider_crank_extremes_equal_dense_sampling(
            r in 0.1f64..2.0, l in 0.1f64..4.0, e in -1.0f64..1.0,
            lo in -7.0f64..7.0, span in 0.0f64..8.0,
        ) {
            let hi = lo + span;
            let (smin, smax) = sampled(lo, hi, |t| slider_crank_cos_mu(r, l, e, t));
            match slider_crank_transmission(r, l, e, lo, hi).unwrap() {
                Transmission::Range { mu_min, mu_max, .. } => {
                    prop_assert!(mu_min.cos() >= smax - 1e-12);
                    prop_assert!(mu_max.cos() <= smin + 1e-12);
                    let step = span / 20_000.0;
                    let slack = r / l * step * step + 1e-12;
                    prop_assert!(mu_min.cos() - smax <= slack && smin - mu_max.cos() <= slack);
                }
                Transmission::Breaks { cos_mu, .. } => {
                    prop_assert!(cos_mu.abs() > 1.0);
                    prop_assert!(smax > 1.0 - 1e-9 || smin < -1.0 + 1e-9);
                }
            }
        }

        #[test]
        fn grashof_crank_turns_iff_it_assembles_over_a_full_turn(
            a in 0.2f64..5.0, b in 0.2f64..5.0, c in 0.2f64..5.0, d in 0.2f64..5.0,
        ) {
            let g = grashof(a, b, c, d).unwrap();
            prop_assume!(g.kind != Grashof::ChangePoint);
            let full = matches!(
                fourbar_transmission(a, b, c, d, 0.0, TAU).unwrap(),
                Transmission::Range { .. }
            );
            prop_assert_eq!(g.crank_turns, full, "{:?}", g);
        }
    }
}
