//! A lockstep group's step coefficients with its [`LOCK`] lanes side by side:
//! [`Step::new`]'s operations, in its order, on each lane's mode, so that every
//! lane holds [`Step::new`]'s bits (tested). Only the exponentials stay scalar
//! (libm's `exp`, once per lane); the rest (the series of C and S, the force
//! integrals' series, the closed forms) runs in vector lanes.
//!
//! The lanes go together where each takes one of the branches of the common
//! grids: C and S by their series (|λ|h² ≤ 1) or by sin/cos (under-damped),
//! the force integrals by their series ((σ + √|λ|)h ≤ 2) or by the closed form
//! from Φ. A lane's series stops after its own last term, as the scalar loop
//! does: the others' further terms are computed but not added to it. A group
//! with a split (clearly over-damped) or over-damped long-step lane, or h = 0,
//! goes lane by lane through [`Step::new`] itself.

use crate::geom::sin_cos_lanes;

use super::oscillator::{LaneStep, Mode, Step, CS_COEF, INV, LOCK, SERIES_END, SERIES_TOL};

/// One array a lane each.
type Lanes = [f64; LOCK];

/// The group's modes, a field per array, and 1/m.
struct Group {
    sigma: Lanes,
    lambda: Lanes,
    w2: Lanes,
    k: Lanes,
    rate: Lanes,
    inv_m: Lanes,
    /// Some lane is split (see [`Mode::split`]): the whole group goes lane by lane.
    split: bool,
}

impl Group {
    fn new(modes: &[Mode; LOCK], inv_m: &Lanes) -> Group {
        let field = |f: fn(&Mode) -> f64| std::array::from_fn(|l| f(&modes[l]));
        Group {
            sigma: field(|m| m.sigma),
            lambda: field(|m| m.lambda),
            w2: field(|m| m.w2),
            k: field(|m| m.k),
            rate: field(|m| m.rate),
            inv_m: *inv_m,
            split: modes.iter().any(|m| m.split),
        }
    }
}

/// All ones where `c` holds (a select mask).
#[inline(always)]
fn mask(c: bool) -> u64 {
    if c {
        u64::MAX
    } else {
        0
    }
}

/// `a` where the mask is set, else `b`, by bits (exact: no arithmetic).
#[inline(always)]
fn pick(m: u64, a: f64, b: f64) -> f64 {
    f64::from_bits((a.to_bits() & m) | (b.to_bits() & !m))
}

/// [`Step::new`] of every lane for one step h, or None where a lane would take
/// a branch done here only lane by lane (see the module's docs). The lanes'
/// loops are written for the vectoriser: no early exit inside, selects as bit
/// masks.
#[inline(always)]
fn lanes_step(g: &Group, h: f64) -> Option<LaneStep> {
    if h == 0.0 || g.split {
        return None;
    }
    // Mode::ecs: which lanes sum C and S by their series, which use sin/cos.
    let mut u = [0.0; LOCK];
    let mut by_cs = [0u64; LOCK];
    let mut ok = [0u64; LOCK];
    for l in 0..LOCK {
        u[l] = -g.lambda[l] * h * h;
        by_cs[l] = mask(u[l].abs() <= 1.0);
        ok[l] = by_cs[l] | mask(g.lambda[l] > 0.0);
    }
    if ok.contains(&0) {
        return None;
    }
    let series = by_cs.iter().any(|&x| x != 0);
    let trig = by_cs.contains(&0);
    let e: Lanes = std::array::from_fn(|l| (-g.sigma[l] * h).exp());
    let (mut ec, mut es) = ([0.0; LOCK], [0.0; LOCK]);
    if series {
        let (c, s) = cs_lanes(&u);
        for l in 0..LOCK {
            (ec[l], es[l]) = (e[l] * c[l], e[l] * s[l] * h);
        }
    }
    if trig {
        let kh: Lanes = std::array::from_fn(|l| g.k[l] * h);
        let (s, c) = sin_cos_lanes(&kh);
        for l in 0..LOCK {
            let (tc, ts) = (e[l] * c[l], e[l] * s[l] / g.k[l]);
            ec[l] = pick(by_cs[l], ec[l], tc);
            es[l] = pick(by_cs[l], es[l], ts);
        }
    }
    // Mode::phi, then Step::new's force integrals.
    let mut c = LaneStep([[0.0; LOCK]; 8]);
    let mut by_series = [0u64; LOCK];
    for l in 0..LOCK {
        let (p00, p01, p11) = (
            ec[l] + g.sigma[l] * es[l],
            es[l],
            ec[l] - g.sigma[l] * es[l],
        );
        c.0[0][l] = p00;
        c.0[1][l] = p01;
        c.0[2][l] = -g.w2[l] * p01;
        c.0[3][l] = p11;
        by_series[l] = mask(g.rate[l] * h <= 2.0);
    }
    let (mut i1, mut i1h, mut i2h) = integrals_lanes(g, h, by_series);
    if by_series.contains(&0) {
        for l in 0..LOCK {
            let (p00, p01, w2) = (c.0[0][l], c.0[1][l], g.w2[l]);
            let j1 = (1.0 - p00) / w2;
            let j2 = (h - p01 - 2.0 * g.sigma[l] * j1) / w2;
            i1[l] = pick(by_series[l], i1[l], j1);
            i1h[l] = pick(by_series[l], i1h[l], j1 / h);
            i2h[l] = pick(by_series[l], i2h[l], j2 / h);
        }
    }
    for l in 0..LOCK {
        let (p01, inv_m) = (c.0[1][l], g.inv_m[l]);
        c.0[4][l] = (i1[l] - i2h[l]) * inv_m;
        c.0[5][l] = (p01 - i1h[l]) * inv_m;
        c.0[6][l] = i2h[l] * inv_m;
        c.0[7][l] = i1h[l] * inv_m;
    }
    Some(c)
}

/// [`super::oscillator::cs_series`] in lanes: Horner's rule, the same
/// coefficients and order.
#[inline(always)]
fn cs_lanes(u: &Lanes) -> (Lanes, Lanes) {
    let (dc, ds) = CS_COEF;
    let (mut c, mut s) = ([dc[11]; LOCK], [ds[11]; LOCK]);
    for i in (0..11).rev() {
        for l in 0..LOCK {
            c[l] = c[l] * u[l] + dc[i];
            s[l] = s[l] * u[l] + ds[i];
        }
    }
    (c, s)
}

/// [`super::oscillator::integrals_series`] in lanes: (I1, I1/h, I2/h) of the
/// lanes whose mask `keep` is set, each summing exactly the terms its scalar
/// loop sums (after the term at which its own bound falls below the
/// tolerance, a lane adds nothing more; the loop ends when every lane has
/// stopped).
#[inline(always)]
fn integrals_lanes(g: &Group, h: f64, mut keep: [u64; LOCK]) -> (Lanes, Lanes, Lanes) {
    let (inv, neg_inv) = INV;
    let a: Lanes = std::array::from_fn(|l| 2.0 * g.sigma[l] * h);
    let b: Lanes = std::array::from_fn(|l| g.w2[l] * h * h);
    let rh: Lanes = std::array::from_fn(|l| g.rate[l] * h);
    let (mut gp, mut gn) = ([0.0; LOCK], [h; LOCK]);
    let (mut s1, mut s2) = ([h / 2.0; LOCK], [h / 6.0; LOCK]);
    let mut bound = [1.0; LOCK];
    for n in 1..SERIES_END {
        if keep.iter().all(|&x| x == 0) {
            break;
        }
        let (i2, i23) = (inv[n + 2], inv[n + 2] * inv[n + 3]);
        for l in 0..LOCK {
            let next = (a[l] * gn[l] + b[l] * gp[l] * inv[n]) * neg_inv[n + 1];
            gp[l] = gn[l];
            gn[l] = next;
            s1[l] = pick(keep[l], s1[l] + next * i2, s1[l]);
            s2[l] = pick(keep[l], s2[l] + next * i23, s2[l]);
            bound[l] *= rh[l] * inv[n];
            keep[l] &= !mask(bound[l] < SERIES_TOL);
        }
    }
    (
        std::array::from_fn(|l| s1[l] * h),
        s1,
        std::array::from_fn(|l| s2[l] * h),
    )
}

/// Fills `coef` (one [`LaneStep`] per step length of `hs`) for the group's
/// lanes; false if a coefficient is not finite. Dispatched through `pulp` so
/// that the lanes' operations are vector instructions.
pub(super) struct LaneCoef<'a> {
    pub(super) modes: &'a [Mode; LOCK],
    pub(super) inv_m: &'a Lanes,
    pub(super) hs: &'a [f64],
    pub(super) coef: &'a mut [LaneStep],
}

impl pulp::WithSimd for LaneCoef<'_> {
    type Output = bool;

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> bool {
        let LaneCoef {
            modes,
            inv_m,
            hs,
            coef,
        } = self;
        let group = Group::new(modes, inv_m);
        for (c, &h) in coef.iter_mut().zip(hs) {
            *c = match lanes_step(&group, h) {
                Some(c) => c,
                None => one_by_one(modes, inv_m, h),
            };
            if !c.0.iter().flatten().all(|x| x.is_finite()) {
                return false;
            }
        }
        true
    }
}

/// [`Step::new`] lane by lane.
#[inline(never)]
fn one_by_one(modes: &[Mode; LOCK], inv_m: &Lanes, h: f64) -> LaneStep {
    let mut c = LaneStep([[0.0; LOCK]; 8]);
    for l in 0..LOCK {
        let st = Step::new(&modes[l], h, inv_m[l]);
        let all = [
            st.p00, st.p01, st.p10, st.p11, st.g0q, st.g0v, st.g1q, st.g1v,
        ];
        for (cj, x) in c.0.iter_mut().zip(all) {
            cj[l] = x;
        }
    }
    c
}

/// For tests: whether the lanes went together for h (else lane by lane).
#[cfg(test)]
pub(super) fn together(modes: &[Mode; LOCK], h: f64) -> bool {
    lanes_step(&Group::new(modes, &[1.0; LOCK]), h).is_some()
}
