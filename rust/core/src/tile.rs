//! An 8 × 8 tile of f64 transposed in registers: explicit shuffles on AVX-512 and
//! AVX2, element by element elsewhere. Shared by the kernels that gather eight
//! lanes and store them by row: the cyclogram's batch longest path
//! (`cyclogram::event_graph`), the Duhamel scan (`impact::scan`) and the
//! Duhamel batch's lockstep loop (`impact::oscillator`).

/// The tile's side: eight f64 lanes (one AVX-512 register).
pub(crate) const TILE: usize = 8;

/// `tile` (8 × 8) transposed, in explicit shuffles on AVX-512 and AVX2 (written
/// element by element, LLVM assembles it from 128-bit pieces and single
/// stores). The instruction set is known when the kernel is compiled for it, so
/// the type test below is resolved then.
#[inline(always)]
pub(crate) fn transpose<S: pulp::Simd>(simd: S, tile: &[[f64; TILE]; TILE]) -> [[f64; TILE]; TILE] {
    #[cfg(target_arch = "x86_64")]
    {
        let any = &simd as &dyn std::any::Any;
        if let Some(&v4) = any.downcast_ref::<pulp::x86::V4>() {
            return transpose_v4(v4, tile);
        }
        if let Some(&v3) = any.downcast_ref::<pulp::x86::V3>() {
            return transpose_v3(v3, tile);
        }
    }
    let _ = simd;
    std::array::from_fn(|i| std::array::from_fn(|j| tile[j][i]))
}

/// [`transpose`] in 24 AVX-512 shuffles: 2 × 2, 4 × 4 then 8 × 8 blocks.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn transpose_v4(simd: pulp::x86::V4, tile: &[[f64; TILE]; TILE]) -> [[f64; TILE]; TILE] {
    use std::arch::x86_64::{__m512d, __m512i};
    let a = simd.avx512f;
    let r: [__m512d; 8] = tile.map(pulp::cast);
    // t[2i] = rows 2i, 2i+1 interleaved at even columns, t[2i+1] at odd ones.
    let t: [__m512d; 8] = std::array::from_fn(|k| {
        let (x, y) = (r[k & !1], r[k | 1]);
        if k % 2 == 0 {
            a._mm512_unpacklo_pd(x, y)
        } else {
            a._mm512_unpackhi_pd(x, y)
        }
    });
    // u[k], k < 4: column k (then k + 4) of rows 0-3; u[k + 4]: of rows 4-7.
    let lo: __m512i = pulp::cast([0i64, 1, 8, 9, 4, 5, 12, 13]);
    let hi: __m512i = pulp::cast([2i64, 3, 10, 11, 6, 7, 14, 15]);
    let u: [__m512d; 8] = std::array::from_fn(|k| {
        let base = (k / 4) * 4 + (k % 2);
        let idx = if k % 4 < 2 { lo } else { hi };
        a._mm512_permutex2var_pd(t[base], idx, t[base + 2])
    });
    let out: [__m512d; 8] = std::array::from_fn(|k| {
        if k < 4 {
            a._mm512_shuffle_f64x2::<0x44>(u[k], u[k + 4])
        } else {
            a._mm512_shuffle_f64x2::<0xEE>(u[k - 4], u[k])
        }
    });
    out.map(pulp::cast)
}

/// [`transpose`] in AVX2: four 4 × 4 blocks, 8 shuffles each. (No
/// `array::from_fn` here or in the kernel's loops: its closures were not
/// inlined into the AVX2 instance and ran as calls to baseline code.)
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn transpose_v3(simd: pulp::x86::V3, tile: &[[f64; TILE]; TILE]) -> [[f64; TILE]; TILE] {
    use std::arch::x86_64::__m256d;
    // q[i][h]: columns 4h..4h+4 of row i.
    let q: [[__m256d; 2]; TILE] = pulp::cast(*tile);
    // A function, not a closure: the closure was not inlined.
    #[inline(always)]
    fn block(
        simd: pulp::x86::V3,
        x0: __m256d,
        x1: __m256d,
        x2: __m256d,
        x3: __m256d,
    ) -> [__m256d; 4] {
        let a = simd.avx;
        let t0 = a._mm256_unpacklo_pd(x0, x1);
        let t1 = a._mm256_unpackhi_pd(x0, x1);
        let t2 = a._mm256_unpacklo_pd(x2, x3);
        let t3 = a._mm256_unpackhi_pd(x2, x3);
        [
            a._mm256_permute2f128_pd::<0x20>(t0, t2),
            a._mm256_permute2f128_pd::<0x20>(t1, t3),
            a._mm256_permute2f128_pd::<0x31>(t0, t2),
            a._mm256_permute2f128_pd::<0x31>(t1, t3),
        ]
    }
    // bhv: columns 4h.., rows 4v.. transposed: halves v of output rows 4h..4h+4.
    let b00 = block(simd, q[0][0], q[1][0], q[2][0], q[3][0]);
    let b01 = block(simd, q[4][0], q[5][0], q[6][0], q[7][0]);
    let b10 = block(simd, q[0][1], q[1][1], q[2][1], q[3][1]);
    let b11 = block(simd, q[4][1], q[5][1], q[6][1], q[7][1]);
    let out: [[__m256d; 2]; TILE] = [
        [b00[0], b01[0]],
        [b00[1], b01[1]],
        [b00[2], b01[2]],
        [b00[3], b01[3]],
        [b10[0], b11[0]],
        [b10[1], b11[1]],
        [b10[2], b11[2]],
        [b10[3], b11[3]],
    ];
    pulp::cast(out)
}
