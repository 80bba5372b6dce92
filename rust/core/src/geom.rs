//! Plane vectors as `[f64; 2]` and the sine and cosine the kernels share.

/// A point or vector in the plane [m].
pub type V2 = [f64; 2];

/// a − b.
#[inline]
pub fn sub(a: V2, b: V2) -> V2 {
    [a[0] - b[0], a[1] - b[1]]
}

/// a · b.
#[inline]
pub fn dot(a: V2, b: V2) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// a × b (the z component).
#[inline]
pub fn cross(a: V2, b: V2) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// |a − b|.
#[inline]
pub fn dist(a: V2, b: V2) -> f64 {
    let d = sub(a, b);
    dot(d, d).sqrt()
}

// fdlibm's constants, digits as published. π/2 = PIO2_1 + PIO2_2 + PIO2_3, the
// first two with 33 significant bits, so k·PIO2_1 and k·PIO2_2 are exact for
// |k| < 2²⁰ (fdlibm's pio2_1, pio2_2, pio2_3).
#[allow(clippy::excessive_precision)]
const PIO2_1: f64 = 1.570_796_326_734_125_614_17;
#[allow(clippy::excessive_precision)]
const PIO2_2: f64 = 6.077_100_506_303_965_976_6e-11;
#[allow(clippy::excessive_precision)]
const PIO2_3: f64 = 2.022_266_248_711_166_455_8e-21;
#[allow(clippy::excessive_precision)]
const S: [f64; 6] = [
    -1.666_666_666_666_663_243_48e-1,
    8.333_333_333_322_489_461_24e-3,
    -1.984_126_982_985_794_931_34e-4,
    2.755_731_370_707_006_767_89e-6,
    -2.505_076_025_340_686_341_95e-8,
    1.589_690_995_211_550_102_21e-10,
];
#[allow(clippy::excessive_precision)]
const C: [f64; 6] = [
    4.166_666_666_666_660_190_37e-2,
    -1.388_888_888_887_410_957_49e-3,
    2.480_158_728_947_672_941_78e-5,
    -2.755_731_435_139_066_330_35e-7,
    2.087_572_321_298_174_827_90e-9,
    -1.135_964_755_778_819_482_65e-11,
];

/// x = k·π/2 + r with |r| ≤ π/4 (three-part Cody–Waite): (k mod 4, r), for
/// |x| ≤ 10⁶. Branch-free and without a float-to-integer conversion, so that
/// loops over it run several lanes per instruction.
#[inline(always)]
fn reduce(x: f64) -> (u64, f64) {
    // Round to nearest by the 1.5·2⁵² trick (f64::round is a libm call on baseline
    // x86-64); exact for |x·2/π| < 2⁵¹. The low bits of the shifted value are
    // k mod 4 (1.5·2⁵² has ulp 1).
    const ROUND: f64 = 6_755_399_441_055_744.0;
    let shifted = x * std::f64::consts::FRAC_2_PI + ROUND;
    let k = shifted - ROUND;
    let r = ((x - k * PIO2_1) - k * PIO2_2) - k * PIO2_3;
    (shifted.to_bits() & 3, r)
}

/// fdlibm's sine kernel on |r| ≤ π/4.
#[inline(always)]
fn kernel_sin(r: f64) -> f64 {
    let z = r * r;
    r + r * z * (S[0] + z * (S[1] + z * (S[2] + z * (S[3] + z * (S[4] + z * S[5])))))
}

/// fdlibm's cosine kernel on |r| ≤ π/4.
#[inline(always)]
fn kernel_cos(r: f64) -> f64 {
    let z = r * r;
    let p = z * z * (C[0] + z * (C[1] + z * (C[2] + z * (C[3] + z * (C[4] + z * C[5])))));
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    w + (((1.0 - w) - hz) + p)
}

/// sin x and cos x, inlined: fdlibm's kernels (|r| ≤ π/4 minimax polynomials)
/// after a three-part Cody–Waite reduction by π/2, exact in k·(π/2) for
/// |x| ≤ 10⁶; larger or non-finite x go to the platform's `sin_cos`. Within 1 ulp
/// of 1 of the platform's values (tested), and several times faster than the
/// out-of-line libm call in the hot loop of a crank-angle grid.
#[inline(always)]
pub fn sin_cos(x: f64) -> (f64, f64) {
    if x.abs() > 1e6 || x.is_nan() {
        return platform_sin_cos(x);
    }
    let (q, r) = reduce(x);
    let (s, c) = (kernel_sin(r), kernel_cos(r));
    match q {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

/// sin x alone, inlined: the reduction of [`sin_cos`] and only the one kernel
/// the quadrant needs (the same values as `sin_cos(x).0`).
#[inline(always)]
pub fn sin(x: f64) -> f64 {
    if x.abs() > 1e6 || x.is_nan() {
        return platform_sin_cos(x).0;
    }
    let (q, r) = reduce(x);
    let v = if q & 1 == 0 {
        kernel_sin(r)
    } else {
        kernel_cos(r)
    };
    if q & 2 == 0 {
        v
    } else {
        -v
    }
}

/// [`sin`] without branches, for |x| ≤ 10⁶ and finite x only (the caller
/// guarantees it), so that a loop over many x runs several lanes per
/// instruction: the same reduction and kernels, both kernels evaluated and the
/// quadrant's picked by bit masks. Bit for bit the values of [`sin`].
#[inline(always)]
pub fn sin_lanes(x: f64) -> f64 {
    let (q, r) = reduce(x);
    let odd = (q & 1).wrapping_neg();
    let v = (kernel_sin(r).to_bits() & !odd) | (kernel_cos(r).to_bits() & odd);
    f64::from_bits(v ^ ((q & 2) << 62))
}

/// Out of line and cold, so that the compiler does not evaluate it on every call
/// of [`sin_cos`] (a plain `x.sin_cos()` there is speculated and selected).
#[cold]
#[inline(never)]
fn platform_sin_cos(x: f64) -> (f64, f64) {
    x.sin_cos()
}

/// [`sin_cos`] for `L` lanes, bit for bit (tested), without branches: the
/// same Cody–Waite reduction and fdlibm kernels, both kernels evaluated and each
/// result's picked and signed by the quadrant's bits; lanes with |x| > 10⁶ or
/// NaN take the platform's `sin_cos`, as [`sin_cos`] does.
#[inline(always)]
pub(crate) fn sin_cos_lanes<const L: usize>(x: &[f64; L]) -> ([f64; L], [f64; L]) {
    const ROUND: f64 = 6_755_399_441_055_744.0;
    let (mut sn, mut cs) = ([0.0; L], [0.0; L]);
    let mut wide = false;
    for l in 0..L {
        let v = x[l];
        wide |= (v.abs() > 1e6) | v.is_nan();
        let shifted = v * std::f64::consts::FRAC_2_PI + ROUND;
        let k = shifted - ROUND;
        let r = ((v - k * PIO2_1) - k * PIO2_2) - k * PIO2_3;
        let q = shifted.to_bits() & 3;
        let z = r * r;
        let ks = r + r * z * (S[0] + z * (S[1] + z * (S[2] + z * (S[3] + z * (S[4] + z * S[5])))));
        let p = z * z * (C[0] + z * (C[1] + z * (C[2] + z * (C[3] + z * (C[4] + z * C[5])))));
        let hz = 0.5 * z;
        let w = 1.0 - hz;
        let kc = w + (((1.0 - w) - hz) + p);
        // q = 0: (s, c); 1: (c, −s); 2: (−s, −c); 3: (−c, s).
        let odd = (q & 1).wrapping_neg();
        let (bs, bc) = (ks.to_bits(), kc.to_bits());
        sn[l] = f64::from_bits(((bs & !odd) | (bc & odd)) ^ ((q & 2) << 62));
        cs[l] = f64::from_bits(((bc & !odd) | (bs & odd)) ^ (((q + 1) & 2) << 62));
    }
    if wide {
        for l in 0..L {
            if x[l].abs() > 1e6 || x[l].is_nan() {
                (sn[l], cs[l]) = platform_sin_cos(x[l]);
            }
        }
    }
    (sn, cs)
}

/// sin x and cos x for `L` lanes of finite |x| ≤ 10⁶ (the caller guarantees
/// it: larger or non-finite x give meaningless values, no panic), with fused
/// multiply-adds: the reduction and fdlibm kernels of [`sin_cos`], each
/// multiply-then-add one `mul_add`, so about half the instructions of
/// [`sin_cos_lanes`] where the caller is compiled with FMA (through `pulp`'s
/// AVX2 or AVX-512 dispatch; elsewhere `mul_add` is a libm call, correct but
/// slow: the caller takes this only where the processor has FMA). Every
/// operation is a plain IEEE one or a fused multiply-add, so every instruction
/// set gives the same bits (tested). Within 1 ulp of 1 of [`sin_cos`] (tested:
/// the same kernels, rounded once per step instead of twice).
#[inline(always)]
pub(crate) fn sin_cos_fma_lanes<const L: usize>(x: &[f64; L]) -> ([f64; L], [f64; L]) {
    const ROUND: f64 = 6_755_399_441_055_744.0;
    let (mut sn, mut cs) = ([0.0; L], [0.0; L]);
    for l in 0..L {
        let v = x[l];
        let shifted = v.mul_add(std::f64::consts::FRAC_2_PI, ROUND);
        let k = shifted - ROUND;
        // k·PIO2_1 and k·PIO2_2 are exact (33-bit parts): fused or not alike.
        let r = (-k).mul_add(PIO2_3, (-k).mul_add(PIO2_2, (-k).mul_add(PIO2_1, v)));
        let q = shifted.to_bits() & 3;
        let z = r * r;
        let ps = z
            .mul_add(S[5], S[4])
            .mul_add(z, S[3])
            .mul_add(z, S[2])
            .mul_add(z, S[1])
            .mul_add(z, S[0]);
        let ks = (r * z).mul_add(ps, r);
        let pc = z
            .mul_add(C[5], C[4])
            .mul_add(z, C[3])
            .mul_add(z, C[2])
            .mul_add(z, C[1])
            .mul_add(z, C[0]);
        let p = (z * z) * pc;
        // fdlibm's cos r = w + (((1 − w) − z/2) + p), w = 1 − z/2: the low part
        // of 1 − z/2 kept.
        let hz = 0.5 * z;
        let w = 1.0 - hz;
        let kc = w + (((1.0 - w) - hz) + p);
        // q = 0: (s, c); 1: (c, −s); 2: (−s, −c); 3: (−c, s).
        let odd = (q & 1).wrapping_neg();
        let (bs, bc) = (ks.to_bits(), kc.to_bits());
        sn[l] = f64::from_bits(((bs & !odd) | (bc & odd)) ^ ((q & 2) << 62));
        cs[l] = f64::from_bits(((bc & !odd) | (bs & odd)) ^ (((q + 1) & 2) << 62));
    }
    (sn, cs)
}

/// Largest |x − a| [rad] for which [`sin_cos_near_lanes`] rotates from the
/// anchor a: its Taylor polynomials' first dropped terms, d⁹/9! and d⁸/8!,
/// are below 1e-19 there.
pub(crate) const NEAR_RAD: f64 = 1.0 / 64.0;

/// sin x and cos x for `L` lanes near an anchor a [rad] whose sine `sa` and
/// cosine `ca` are given (from [`sin_cos_fma_lanes`]): with d = x − a (exact
/// where x and a are within a factor 2 of each other, else rounded once,
/// 2⁻⁵⁴·|d| at most), sin d and cos d − 1 by their Taylor polynomials to d⁷
/// and d⁶ (truncation below 1e-19 for |d| ≤ [`NEAR_RAD`]), then the rotation
/// sin x = sa + (sa·(cos d − 1) + ca·sin d), cos x = ca + (ca·(cos d − 1) −
/// sa·sin d) by fused multiply-adds. About two fifths of the operations of
/// [`sin_cos_fma_lanes`]; within 4 ε of [`sin_cos`] absolutely when sa and
/// ca are [`sin_cos_fma_lanes`]'s (tested); `None` if some lane lies
/// farther than [`NEAR_RAD`] from a (or is NaN). Plain IEEE operations and
/// fused multiply-adds only: the same bits on every instruction set.
#[inline(always)]
pub(crate) fn sin_cos_near_lanes<const L: usize>(
    x: &[f64; L],
    a: f64,
    sa: f64,
    ca: f64,
) -> Option<([f64; L], [f64; L])> {
    let mut d = [0.0; L];
    let mut near = true;
    for l in 0..L {
        d[l] = x[l] - a;
        near &= d[l].abs() <= NEAR_RAD;
    }
    if !near {
        return None;
    }
    let (mut sn, mut cs) = ([0.0; L], [0.0; L]);
    for l in 0..L {
        let z = d[l] * d[l];
        // sin d = d + d·z·(−1/6 + z/120 − z²/5040); cos d − 1 = z·(−1/2 + z/24 − z²/720).
        let ps = z.mul_add(-1.0 / 5040.0, 1.0 / 120.0).mul_add(z, -1.0 / 6.0);
        let sd = (d[l] * z).mul_add(ps, d[l]);
        let cm = z * z.mul_add(-1.0 / 720.0, 1.0 / 24.0).mul_add(z, -0.5);
        sn[l] = ca.mul_add(sd, sa.mul_add(cm, sa));
        cs[l] = (-sa).mul_add(sd, ca.mul_add(cm, ca));
    }
    Some((sn, cs))
}

/// [`sin_cos`] on one SIMD register of angles, bit for bit (tested on every
/// instruction set): the same Cody–Waite reduction and fdlibm kernels, in the
/// same operation order and without fused multiply-adds, both kernels evaluated
/// and each result picked and signed by the quadrant's bits. Lanes with
/// |x| > 10⁶ or NaN are the caller's to redo with [`sin_cos`] (the platform's
/// `sin_cos` there); their values here are meaningless.
#[inline(always)]
pub(crate) fn sin_cos_simd<S: pulp::Simd>(simd: S, x: S::f64s) -> (S::f64s, S::f64s) {
    // Plain calls only: a closure would not inherit the caller's target
    // features, and each operation would become a function call.
    const ROUND: f64 = 6_755_399_441_055_744.0;
    let shifted = simd.add_f64s(
        simd.mul_f64s(x, simd.splat_f64s(std::f64::consts::FRAC_2_PI)),
        simd.splat_f64s(ROUND),
    );
    let kq = simd.sub_f64s(shifted, simd.splat_f64s(ROUND));
    let mut r = simd.sub_f64s(x, simd.mul_f64s(kq, simd.splat_f64s(PIO2_1)));
    r = simd.sub_f64s(r, simd.mul_f64s(kq, simd.splat_f64s(PIO2_2)));
    r = simd.sub_f64s(r, simd.mul_f64s(kq, simd.splat_f64s(PIO2_3)));
    let bits = simd.transmute_u64s_f64s(shifted);
    let (one, two) = (simd.splat_u64s(1), simd.splat_u64s(2));
    // q = 0: (s, c); 1: (c, −s); 2: (−s, −c); 3: (−c, s).
    let odd = simd.equal_u64s(simd.and_u64s(bits, one), one);
    let neg_s = simd.equal_u64s(simd.and_u64s(bits, two), two);
    let neg_c = simd.xor_m64s(odd, neg_s);
    let z = simd.mul_f64s(r, r);
    let ks = simd.add_f64s(r, simd.mul_f64s(simd.mul_f64s(r, z), horner(simd, z, &S)));
    let p = simd.mul_f64s(simd.mul_f64s(z, z), horner(simd, z, &C));
    let hz = simd.mul_f64s(simd.splat_f64s(0.5), z);
    let w = simd.sub_f64s(simd.splat_f64s(1.0), hz);
    let tail = simd.sub_f64s(simd.sub_f64s(simd.splat_f64s(1.0), w), hz);
    let kc = simd.add_f64s(w, simd.add_f64s(tail, p));
    let sign = simd.splat_f64s(-0.0);
    let sn = simd.select_f64s(odd, kc, ks);
    let cs = simd.select_f64s(odd, ks, kc);
    (
        simd.select_f64s(neg_s, simd.xor_f64s(sn, sign), sn),
        simd.select_f64s(neg_c, simd.xor_f64s(cs, sign), cs),
    )
}

/// c0 + z·(c1 + z·(c2 + z·(c3 + z·(c4 + z·c5)))), as the scalar kernels nest it.
#[inline(always)]
fn horner<S: pulp::Simd>(simd: S, z: S::f64s, c: &[f64; 6]) -> S::f64s {
    let mut acc = simd.mul_f64s(z, simd.splat_f64s(c[5]));
    for &ci in c[1..5].iter().rev() {
        acc = simd.mul_f64s(z, simd.add_f64s(simd.splat_f64s(ci), acc));
    }
    simd.add_f64s(simd.splat_f64s(c[0]), acc)
}

// sin r on |r| ≤ π/2 as r + r·z·P(z), z = r²: the minimax polynomial for the
// relative error (Remez exchange in 50-digit arithmetic, then rounded to
// double; 2.8e-19 before rounding), lowest degree first.
#[allow(clippy::excessive_precision)]
const SIN_HALF: [f64; 8] = [
    -1.666_666_666_666_666_557e-1,
    8.333_333_333_333_194_307e-3,
    -1.984_126_984_120_921_929e-4,
    2.755_731_921_113_729_089e-6,
    -2.505_210_687_280_364_427e-8,
    1.605_893_970_596_474_994e-10,
    -7.642_991_491_042_832_293e-13,
    2.721_174_980_538_557_326e-15,
];

/// sin x for finite |x| ≤ 10⁵ on one SIMD register, with fused multiply-adds:
/// x = kπ + r (k the nearest integer to x/π, three-part Cody–Waite with fdlibm's
/// parts of π/2 doubled, so kπ's first two parts are exact for |k| < 2²⁰),
/// |r| ≤ π/2, then sin x = (−1)^k·(r + r·r²·P(r²)) with one odd minimax
/// polynomial (no quadrant kernels to pick between: about half the operations
/// of [`sin_cos_simd`]'s sine). Within 2 ulps of the platform's `sin` and within
/// ε absolutely (tested on dense grids and by proptest; 2 ulps is reached just
/// below |sin x| = 1, where r·r²·P(r²) ≈ −0.5 carries its roundings, against
/// fdlibm's 1 ulp), less 2e-31·|x| near multiples of π where sin x is tiny (the
/// three-part π, as [`sin_cos`]'s). Every operation is a plain IEEE one or a
/// fused multiply-add, so each instruction set (`pulp::Scalar` through `fma`)
/// gives the same bits (tested); the caller picks it only where the processor
/// has FMA (a software `fma` would be slow). Larger or non-finite x give
/// meaningless values (no panic): the caller checks its range.
#[inline(always)]
pub(crate) fn sin_fma_simd<S: pulp::Simd>(simd: S, x: S::f64s) -> S::f64s {
    const ROUND: f64 = 6_755_399_441_055_744.0;
    // Plain calls only: a closure would not inherit the caller's target features.
    let shifted = simd.mul_add_f64s(
        x,
        simd.splat_f64s(std::f64::consts::FRAC_1_PI),
        simd.splat_f64s(ROUND),
    );
    let k = simd.sub_f64s(shifted, simd.splat_f64s(ROUND));
    let mut r = simd.negate_mul_add_f64s(k, simd.splat_f64s(2.0 * PIO2_1), x);
    r = simd.negate_mul_add_f64s(k, simd.splat_f64s(2.0 * PIO2_2), r);
    r = simd.negate_mul_add_f64s(k, simd.splat_f64s(2.0 * PIO2_3), r);
    let z = simd.mul_f64s(r, r);
    let mut p = simd.splat_f64s(SIN_HALF[7]);
    for &c in SIN_HALF[..7].iter().rev() {
        p = simd.mul_add_f64s(p, z, simd.splat_f64s(c));
    }
    let s = simd.mul_add_f64s(simd.mul_f64s(r, z), p, r);
    // k odd (the low bit of the shifted value, whose ulp is 1): −sin r.
    let one = simd.splat_u64s(1);
    let odd = simd.equal_u64s(simd.and_u64s(simd.transmute_u64s_f64s(shifted), one), one);
    // (`neg_f64s` is not `inline(always)`: it could become a call.)
    simd.select_f64s(odd, simd.xor_f64s(s, simd.splat_f64s(-0.0)), s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::f64::consts::PI;

    proptest! {
        #[test]
        fn sin_cos_matches_the_platform(x in -1e6f64..1e6, small in -10.0f64..10.0) {
            for v in [x, small, small * 1e-9] {
                let (s, c) = sin_cos(v);
                let (s0, c0) = v.sin_cos();
                prop_assert!((s - s0).abs() <= f64::EPSILON, "sin({v}) = {s} vs {s0}");
                prop_assert!((c - c0).abs() <= f64::EPSILON, "cos({v}) = {c} vs {c0}");
                prop_assert_eq!(sin(v).to_bits(), s.to_bits());
                prop_assert_eq!(sin_lanes(v).to_bits(), s.to_bits());
            }
        }
    }

    /// [`sin_cos_simd`] over eight angles.
    struct Lanes([f64; 8]);

    impl pulp::WithSimd for Lanes {
        type Output = ([f64; 8], [f64; 8]);

        #[inline(always)]
        fn with_simd<S: pulp::Simd>(self, simd: S) -> Self::Output {
            let (mut sn, mut cs) = ([0.0; 8], [0.0; 8]);
            let xv = S::as_simd_f64s(&self.0).0;
            let (sv, cv) = (
                S::as_mut_simd_f64s(&mut sn).0,
                S::as_mut_simd_f64s(&mut cs).0,
            );
            for i in 0..xv.len() {
                (sv[i], cv[i]) = sin_cos_simd(simd, xv[i]);
            }
            (sn, cs)
        }
    }

    proptest! {
        #[test]
        fn sin_cos_simd_is_sin_cos_bit_for_bit_on_every_isa(
            xs in prop::array::uniform8(-1e6f64..1e6), small in -10.0f64..10.0,
        ) {
            let mut all = xs.to_vec();
            all.extend([small, -small, small * 1e-9, 0.0, -0.0]);
            all.extend((-8..=8).map(|k| k as f64 * std::f64::consts::FRAC_PI_2));
            for chunk in all.chunks(8) {
                let mut x = [0.0; 8];
                x[..chunk.len()].copy_from_slice(chunk);
                let got = on_each_isa!(|s| pulp::Simd::vectorize(s, Lanes(x)));
                for (isa, (sn, cs)) in got {
                    for l in 0..8 {
                        let (s0, c0) = sin_cos(x[l]);
                        prop_assert_eq!(sn[l].to_bits(), s0.to_bits(), "{} sin({})", isa, x[l]);
                        prop_assert_eq!(cs[l].to_bits(), c0.to_bits(), "{} cos({})", isa, x[l]);
                    }
                }
            }
        }
    }

    /// [`sin_fma_simd`] over a slice, on one instruction set.
    struct FmaSine<'a>(&'a [f64]);

    impl pulp::WithSimd for FmaSine<'_> {
        type Output = Vec<f64>;

        #[inline(always)]
        fn with_simd<S: pulp::Simd>(self, simd: S) -> Vec<f64> {
            let lanes = std::mem::size_of::<S::f64s>() / 8;
            let mut x = self.0.to_vec();
            x.resize(self.0.len().div_ceil(lanes) * lanes, 0.0);
            let mut out = vec![0.0; x.len()];
            let (xv, ov) = (S::as_simd_f64s(&x).0, S::as_mut_simd_f64s(&mut out).0);
            for (o, &v) in ov.iter_mut().zip(xv) {
                *o = sin_fma_simd(simd, v);
            }
            out.truncate(self.0.len());
            out
        }
    }

    /// |s − sin x| in ulps of the platform's sin x, less 2e-31·|x| (the
    /// three-part π of the reduction, as fdlibm's, is short of π by 1.7e-31: near
    /// a multiple kπ, where sin x is tiny, that is the error, as in [`sin_cos`]).
    fn ulps(s: f64, x: f64) -> f64 {
        let want = x.sin();
        let w = want.abs().max(f64::MIN_POSITIVE);
        ((s - want).abs() - 2e-31 * x.abs()).max(0.0) / (w.next_up() - w)
    }

    /// The largest error, in ulps of the platform's sin, of [`sin_fma_simd`] over
    /// `x`, after checking every instruction set gives the same bits.
    fn fma_sine_error(x: &[f64]) -> f64 {
        let runs = on_each_isa!(|s| pulp::Simd::vectorize(s, FmaSine(x)));
        let (_, first) = &runs[0];
        for (isa, got) in &runs {
            for (i, (a, b)) in got.iter().zip(first).enumerate() {
                assert_eq!(a.to_bits(), b.to_bits(), "{isa}: sin({})", x[i]);
            }
        }
        x.iter()
            .zip(first)
            .fold(0.0, |m, (&v, &s)| m.max(ulps(s, v)))
    }

    #[test]
    fn fma_sine_is_within_two_ulp_on_dense_grids() {
        // The two-period law's arguments (ωt + φ, up to 2.5π for the cycloidal
        // jerk), both signs around zero, every multiple of π/2 to ±8π and an ulp
        // either side, then a wide grid.
        let mut x: Vec<f64> = (0..=400_000)
            .map(|i| i as f64 * (2.5 * PI / 400_000.0))
            .collect();
        x.extend((1..=20_000).flat_map(|i| {
            let v = i as f64 * 1e-4;
            [v, -v, v * 1e-9, -v * 1e-12]
        }));
        for k in -16..=16 {
            let v = k as f64 * std::f64::consts::FRAC_PI_2;
            x.extend([v, v.next_up(), v.next_down(), v + 1e-9, v - 1e-9]);
        }
        x.extend((0..=200_000).map(|i| -1e5 + i as f64));
        x.extend([0.0, -0.0, 1e5, -1e5, f64::MIN_POSITIVE, 5e-324]);
        let worst = fma_sine_error(&x);
        assert!(worst <= 2.0, "{worst} ulp");
        // Absolutely: within ε of the platform's sin.
        let got = pulp::Arch::new().dispatch(FmaSine(&x));
        for (&v, &s) in x.iter().zip(&got) {
            assert!(
                (s - v.sin()).abs() <= f64::EPSILON,
                "sin({v}) = {s} vs {}",
                v.sin()
            );
        }
    }

    proptest! {
        #[test]
        fn fma_sine_is_within_two_ulp_anywhere_in_range(
            xs in prop::array::uniform8(-1e5f64..1e5),
            small in prop::array::uniform8(-4.0f64..4.0),
        ) {
            let mut x = xs.to_vec();
            x.extend(small);
            x.extend(small.map(|v| v * 1e-7));
            let worst = fma_sine_error(&x);
            prop_assert!(worst <= 2.0, "{} ulp", worst);
        }
    }

    /// [`sin_cos_fma_lanes`] over a slice, on one instruction set.
    struct FmaSinCos<'a>(&'a [f64]);

    impl pulp::WithSimd for FmaSinCos<'_> {
        type Output = Vec<(f64, f64)>;

        #[inline(always)]
        fn with_simd<S: pulp::Simd>(self, _simd: S) -> Self::Output {
            let mut out = Vec::with_capacity(self.0.len());
            for g in self.0.chunks(8) {
                let mut x = [0.0; 8];
                x[..g.len()].copy_from_slice(g);
                let (sn, cs) = sin_cos_fma_lanes(&x);
                out.extend((0..g.len()).map(|l| (sn[l], cs[l])));
            }
            out
        }
    }

    /// The largest |Δ| of [`sin_cos_fma_lanes`] from [`sin_cos`] and from the
    /// platform's, after checking every instruction set gives the same bits.
    fn fma_sin_cos_gap(x: &[f64]) -> f64 {
        let runs = on_each_isa!(|s| pulp::Simd::vectorize(s, FmaSinCos(x)));
        let (_, first) = &runs[0];
        for (isa, got) in &runs {
            for (i, (a, b)) in got.iter().zip(first).enumerate() {
                assert!(
                    a.0.to_bits() == b.0.to_bits() && a.1.to_bits() == b.1.to_bits(),
                    "{isa}: sin_cos({})",
                    x[i]
                );
            }
        }
        x.iter().zip(first).fold(0.0, |m, (&v, &(s, c))| {
            let ((s0, c0), (s1, c1)) = (sin_cos(v), v.sin_cos());
            m.max((s - s0).abs().max((c - c0).abs()))
                .max((s - s1).abs().max((c - c1).abs()))
        })
    }

    #[test]
    fn fma_sin_cos_is_within_an_ulp_of_one_on_dense_grids() {
        // A turn densely (the cam angles), every multiple of π/4 to ±8π and an
        // ulp either side, tiny angles of both signs, then up to ±1e6.
        let mut x: Vec<f64> = (0..=400_000)
            .map(|i| i as f64 * (2.0 * PI / 400_000.0))
            .collect();
        for k in -32..=32 {
            let v = k as f64 * std::f64::consts::FRAC_PI_4;
            x.extend([v, v.next_up(), v.next_down(), v + 1e-9, v - 1e-9]);
        }
        x.extend((1..=2000).flat_map(|i| [i as f64 * 1e-9, -(i as f64) * 1e-12]));
        x.extend((0..=20_000).map(|i| -1e6 + i as f64 * 100.0));
        x.extend([0.0, -0.0, 1e6, -1e6, f64::MIN_POSITIVE, 5e-324]);
        let gap = fma_sin_cos_gap(&x);
        assert!(gap <= f64::EPSILON, "{gap}");
    }

    proptest! {
        #[test]
        fn fma_sin_cos_is_within_an_ulp_of_one_anywhere_in_range(
            xs in prop::array::uniform8(-1e6f64..1e6), small in prop::array::uniform8(-7.0f64..7.0),
        ) {
            let mut x = xs.to_vec();
            x.extend(small);
            x.extend(small.map(|v| v * 1e-8));
            let gap = fma_sin_cos_gap(&x);
            prop_assert!(gap <= f64::EPSILON, "{}", gap);
        }
    }

    #[test]
    fn sin_cos_at_quadrant_edges_and_beyond_the_reduction() {
        for k in -8..=8 {
            for dx in [-1e-12, 0.0, 1e-12] {
                let v = k as f64 * std::f64::consts::FRAC_PI_2 + dx;
                let ((s, c), (s0, c0)) = (sin_cos(v), v.sin_cos());
                assert!((s - s0).abs() <= f64::EPSILON && (c - c0).abs() <= f64::EPSILON);
            }
        }
        for v in [2e6, -3e9, f64::INFINITY, f64::NAN] {
            let ((s, c), (s0, c0)) = (sin_cos(v), v.sin_cos());
            assert!(s.to_bits() == s0.to_bits() && c.to_bits() == c0.to_bits());
        }
    }
}
