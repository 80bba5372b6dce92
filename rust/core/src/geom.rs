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

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

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
