//! An 8 × 8 tile of f64 transposed in registers: explicit shuffles on AVX-512 and
//! AVX2, element by element elsewhere. Shared by the kernels that gather eight
//! lanes and store them by row: the cyclogram's batch longest path
//! (`cyclogram::event_graph`), the Duhamel scan (`impact::scan`) and the
//! Duhamel batch's lockstep loop (`impact::oscillator`, in half tiles of
//! 8 × 4: [`transpose_in`], [`transpose_out`]).

/// The tile's side: eight f64 lanes (one AVX-512 register).
pub(crate) const TILE: usize = 8;

/// Columns in a half tile: 8 rows × 4 columns, one AVX2 register a row.
pub(crate) const HALF: usize = 4;

/// The lane vectors of eight rows' next [`HALF`] values: `rows` (8 × 4)
/// transposed to 4 × 8, column c of the result holding row l's value c in
/// lane l. Eight shuffles on AVX-512 (each register holds rows k and k + 4,
/// which a 4 × 4 transpose per 256-bit half then turns into columns), two
/// 4 × 4 blocks on AVX2, element by element elsewhere.
#[inline(always)]
pub(crate) fn transpose_in<S: pulp::Simd>(
    simd: S,
    rows: &[[f64; HALF]; TILE],
) -> [[f64; TILE]; HALF] {
    #[cfg(target_arch = "x86_64")]
    {
        let any = &simd as &dyn std::any::Any;
        if let Some(&v4) = any.downcast_ref::<pulp::x86::V4>() {
            return half_v4(
                v4,
                pulp::cast([
                    [rows[0], rows[4]],
                    [rows[1], rows[5]],
                    [rows[2], rows[6]],
                    [rows[3], rows[7]],
                ]),
            );
        }
        if let Some(&v3) = any.downcast_ref::<pulp::x86::V3>() {
            use std::arch::x86_64::__m256d;
            let r: [__m256d; TILE] = pulp::cast(*rows);
            let lo = block(v3, r[0], r[1], r[2], r[3]);
            let hi = block(v3, r[4], r[5], r[6], r[7]);
            return pulp::cast([
                [lo[0], hi[0]],
                [lo[1], hi[1]],
                [lo[2], hi[2]],
                [lo[3], hi[3]],
            ]);
        }
    }
    let _ = simd;
    let mut out = [[0.0; TILE]; HALF];
    for (c, col) in out.iter_mut().enumerate() {
        for (l, x) in col.iter_mut().enumerate() {
            *x = rows[l][c];
        }
    }
    out
}

/// [`transpose_in`] undone: `cols` (4 × 8, lane l of column c is row l's value
/// c) as eight rows of [`HALF`] values.
#[inline(always)]
pub(crate) fn transpose_out<S: pulp::Simd>(
    simd: S,
    cols: &[[f64; TILE]; HALF],
) -> [[f64; HALF]; TILE] {
    #[cfg(target_arch = "x86_64")]
    {
        let any = &simd as &dyn std::any::Any;
        if let Some(&v4) = any.downcast_ref::<pulp::x86::V4>() {
            // Register k holds rows k and k + 4.
            let p: [[[f64; HALF]; 2]; HALF] = pulp::cast(half_v4(v4, *cols));
            return [
                p[0][0], p[1][0], p[2][0], p[3][0], p[0][1], p[1][1], p[2][1], p[3][1],
            ];
        }
        if let Some(&v3) = any.downcast_ref::<pulp::x86::V3>() {
            use std::arch::x86_64::__m256d;
            let c: [[__m256d; 2]; HALF] = pulp::cast(*cols);
            let lo = block(v3, c[0][0], c[1][0], c[2][0], c[3][0]);
            let hi = block(v3, c[0][1], c[1][1], c[2][1], c[3][1]);
            return pulp::cast([lo[0], lo[1], lo[2], lo[3], hi[0], hi[1], hi[2], hi[3]]);
        }
    }
    let _ = simd;
    let mut out = [[0.0; HALF]; TILE];
    for (l, row) in out.iter_mut().enumerate() {
        for (c, x) in row.iter_mut().enumerate() {
            *x = cols[c][l];
        }
    }
    out
}

/// Four AVX-512 registers, each two 4 × 4 blocks side by side (its 256-bit
/// halves), in 8 shuffles: register c of the result holds column c of the
/// first blocks in its low half and of the second in its high half. Both
/// [`transpose_in`] (registers = rows k | k + 4) and [`transpose_out`]
/// (registers = lane vectors, whose halves are lanes 0-3 | 4-7) are this.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn half_v4(simd: pulp::x86::V4, x: [[f64; TILE]; HALF]) -> [[f64; TILE]; HALF] {
    use std::arch::x86_64::{__m512d, __m512i};
    let a = simd.avx512f;
    let z: [__m512d; HALF] = x.map(pulp::cast);
    // Within each 128-bit pair: elements 0 of registers 0, 1 (resp. 2, 3), then 1.
    let t0 = a._mm512_unpacklo_pd(z[0], z[1]);
    let t1 = a._mm512_unpackhi_pd(z[0], z[1]);
    let t2 = a._mm512_unpacklo_pd(z[2], z[3]);
    let t3 = a._mm512_unpackhi_pd(z[2], z[3]);
    // Pairs 0 of t and t' (and pairs 2), or pairs 1 (and 3).
    let lo: __m512i = pulp::cast([0i64, 1, 8, 9, 4, 5, 12, 13]);
    let hi: __m512i = pulp::cast([2i64, 3, 10, 11, 6, 7, 14, 15]);
    [
        a._mm512_permutex2var_pd(t0, lo, t2),
        a._mm512_permutex2var_pd(t1, lo, t3),
        a._mm512_permutex2var_pd(t0, hi, t2),
        a._mm512_permutex2var_pd(t1, hi, t3),
    ]
    .map(pulp::cast)
}

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

/// A 4 × 4 block of f64 (four AVX2 registers) transposed in 8 shuffles. A
/// function, not a closure: the closure was not inlined.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn block(
    simd: pulp::x86::V3,
    x0: std::arch::x86_64::__m256d,
    x1: std::arch::x86_64::__m256d,
    x2: std::arch::x86_64::__m256d,
    x3: std::arch::x86_64::__m256d,
) -> [std::arch::x86_64::__m256d; 4] {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The half-tile transposes against their definition by index, on every
    /// instruction set the processor has, and each the other's inverse.
    #[test]
    fn half_tile_transposes_are_index_swaps() {
        let mut rows = [[0.0; HALF]; TILE];
        for (l, row) in rows.iter_mut().enumerate() {
            for (c, x) in row.iter_mut().enumerate() {
                *x = (10 * l + c) as f64 + 0.5;
            }
        }
        struct Both([[f64; HALF]; TILE]);
        impl pulp::WithSimd for Both {
            type Output = ([[f64; TILE]; HALF], [[f64; HALF]; TILE]);
            #[inline(always)]
            fn with_simd<S: pulp::Simd>(self, simd: S) -> Self::Output {
                let cols = transpose_in(simd, &self.0);
                (cols, transpose_out(simd, &cols))
            }
        }
        let runs = on_each_isa!(|simd| pulp::Simd::vectorize(simd, Both(rows)));
        for (isa, (cols, back)) in runs {
            for l in 0..TILE {
                for c in 0..HALF {
                    assert_eq!(cols[c][l], rows[l][c], "{isa}: row {l}, column {c}");
                }
            }
            assert_eq!(back, rows, "{isa}");
        }
    }
}
