//! [`Program::eval_into`]'s loop over one chunk of angles, compiled once per
//! instruction set (`pulp`).
//!
//! A sorted grid is long runs of angles in one piece of one cycle, so the loop
//! finds the piece and cycle of a block's first angle once and then runs blocks
//! of one SIMD register (8 angles with AVX-512, 4 with AVX2) through that piece
//! while every lane of a block lies in it: a few compares per block (and one
//! division off the first cycle), no lookup, the piece's coefficients held in
//! registers, the four orders stored straight into the four output rows (and
//! the angles into their copy, where asked). Each piece shape (number of
//! coefficients, with or without its sine term) has its own loop, unrolled at
//! compile time. A block with an angle outside the piece (the run's end, an
//! unsorted grid, another cycle, NaN) is evaluated one angle at a time by
//! [`Program::eval`], and the next block looks its piece up again.
//!
//! Why so: profiled at 1e6 sorted angles, the former loop (groups of 8 with a
//! binary search each, an [[f64; 8]; 4] built and copied into the rows) was
//! compute-bound at 3.6 ms; this one runs as fast as a program of one dwell
//! (stores only), i.e. at the speed the core writes 32 MB, with the rows'
//! stores aligned to the register (a 64-byte store across two cache lines cost
//! a fifth of the time).
//!
//! Bit for bit [`Program::eval`] in every lane (tested on each instruction set):
//! the same operations in the same order, without fused multiply-adds, the sine
//! and cosine by [`sin_cos_simd`] (fdlibm's kernels, bit for bit the scalar
//! [`crate::geom::sin_cos`]), the cycle as eval finds it (⌊θ/2π⌋, then θ − c·2π
//! clamped to [0, 2π], and c·advance added to s). Horner's first step,
//! 0·t + c, is c + 0 here (the same value, −0 included, since t ≥ 0 inside a
//! piece).

use std::f64::consts::TAU;

use super::super::law::Fast;
use super::Program;
use crate::geom::sin_cos_simd;

/// Widest argument [rad] of a piece's sine that [`sin_cos_simd`] reduces
/// exactly (it is exact to 10⁶; a margin for the rounding of ω·t + φ).
const SINE_RANGE: f64 = 5e5;

/// One chunk of angles and its output rows: s, v, a, j, and a copy of the
/// angles where `copy` is given.
pub(super) struct LaneFill<'a> {
    pub(super) program: &'a Program,
    pub(super) th: &'a [f64],
    pub(super) out: [&'a mut [f64]; 4],
    pub(super) copy: Option<&'a mut [f64]>,
}

impl pulp::WithSimd for LaneFill<'_> {
    /// Were all the angles finite? (Non-finite ones are the caller's error.)
    type Output = bool;

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, simd: S) -> bool {
        let LaneFill {
            program,
            th,
            out: [s, v, a, j],
            copy,
        } = self;
        match copy {
            Some(c) => fill::<S, true>(simd, program, th, [c, s, v, a, j]),
            None => fill::<S, false>(simd, program, th, [&mut [], s, v, a, j]),
        }
    }
}

/// [`LaneFill`] into `rows` = [copy of θ (empty unless COPY), s, v, a, j].
#[inline(always)]
fn fill<S: pulp::Simd, const COPY: bool>(
    simd: S,
    program: &Program,
    th: &[f64],
    rows: [&mut [f64]; 5],
) -> bool {
    let [c, s, v, a, j] = rows;
    let w = S::F64_LANES;
    // Up to the first angle whose s lands on a register-aligned address, one
    // by one: aligned stores do not straddle cache lines (the rows share that
    // alignment when N is a multiple of the lanes).
    let bytes = w * std::mem::size_of::<f64>();
    let head = ((bytes - s.as_ptr() as usize % bytes) % bytes / 8).min(th.len());
    let mut finite = true;
    // Angle i one by one into the rows (`at` its index in them).
    let mut one = |x: f64, at: usize, rows: [&mut [f64]; 5]| {
        finite &= x.is_finite();
        let value = program.eval(x);
        let [c, s, v, a, j] = rows;
        if COPY {
            c[at] = x;
        }
        s[at] = value[0];
        v[at] = value[1];
        a[at] = value[2];
        j[at] = value[3];
    };
    for (i, &x) in th[..head].iter().enumerate() {
        one(x, i, [&mut *c, &mut *s, &mut *v, &mut *a, &mut *j]);
    }
    let th = &th[head..];
    let c: &mut [f64] = if COPY { &mut c[head..] } else { c };
    let (thv, th_tail) = S::as_simd_f64s(th);
    let (cv, c_tail) = S::as_mut_simd_f64s(c);
    let (sv, s_tail) = S::as_mut_simd_f64s(&mut s[head..]);
    let (vv, v_tail) = S::as_mut_simd_f64s(&mut v[head..]);
    let (av, a_tail) = S::as_mut_simd_f64s(&mut a[head..]);
    let (jv, j_tail) = S::as_mut_simd_f64s(&mut j[head..]);
    let mut b = 0;
    while b < thv.len() {
        let done = match program.locate(th[b * w]) {
            Some(at) => run::<S, COPY>(
                simd,
                program,
                at,
                &thv[b..],
                [
                    if COPY { &mut cv[b..] } else { &mut [] },
                    &mut sv[b..],
                    &mut vv[b..],
                    &mut av[b..],
                    &mut jv[b..],
                ],
            ),
            None => 0,
        };
        if done > 0 {
            b += done;
            continue;
        }
        // One by one: this block leaves its first angle's piece.
        let mut e = [[0.0; 16]; 5];
        for l in 0..w {
            let x = th[b * w + l];
            let [c, s, v, a, j] = &mut e;
            one(x, l, [c, s, v, a, j]);
        }
        if COPY {
            cv[b] = thv[b];
        }
        sv[b] = simd.partial_load_f64s(&e[1][..w]);
        vv[b] = simd.partial_load_f64s(&e[2][..w]);
        av[b] = simd.partial_load_f64s(&e[3][..w]);
        jv[b] = simd.partial_load_f64s(&e[4][..w]);
        b += 1;
    }
    for (i, &x) in th_tail.iter().enumerate() {
        one(
            x,
            i,
            [
                &mut *c_tail,
                &mut *s_tail,
                &mut *v_tail,
                &mut *a_tail,
                &mut *j_tail,
            ],
        );
    }
    finite
}

impl Program {
    /// The piece and the cycle of an angle, as [`Program::eval`] finds them:
    /// (piece, c) with c = ⌊θ/2π⌋ (0 for θ in [0, 2π)); None for a
    /// non-finite θ.
    #[inline(always)]
    fn locate(&self, theta: f64) -> Option<(usize, f64)> {
        if !theta.is_finite() {
            return None;
        }
        let (c, t) = if (0.0..TAU).contains(&theta) {
            (0.0, theta)
        } else {
            let c = (theta / TAU).floor();
            (c, (theta - c * TAU).clamp(0.0, TAU))
        };
        Some((self.starts.partition_point(|&x0| x0 <= t).max(1) - 1, c))
    }
}

/// Where a run's lanes must lie: cycle `c` (as [`Program::eval`] finds it
/// from θ) and, on that cycle, piece [lo, hi).
#[derive(Clone, Copy)]
struct Window {
    lo: f64,
    hi: f64,
    c: f64,
}

impl Window {
    /// The angles of block `x` on the cycle, t = θ − c·2π clamped to [0, 2π]
    /// as [`Program::eval`] computes it (θ itself for c = 0), if every lane
    /// lies in this window (NaN does not).
    #[inline(always)]
    fn on_cycle<S: pulp::Simd>(self, simd: S, x: S::f64s) -> Option<S::f64s> {
        let tau = simd.splat_f64s(TAU);
        let t = if self.c == 0.0 {
            x
        } else {
            // ⌊θ/2π⌋ = c exactly where c ≤ θ/2π < c + 1 (the same quotient),
            // and θ outside [0, 2π) (which eval takes as it is).
            let q = simd.div_f64s(x, tau);
            let this = simd.and_m64s(
                simd.greater_than_or_equal_f64s(q, simd.splat_f64s(self.c)),
                simd.less_than_f64s(q, simd.splat_f64s(self.c + 1.0)),
            );
            let outside = simd.or_m64s(
                simd.less_than_f64s(x, simd.splat_f64s(0.0)),
                simd.greater_than_or_equal_f64s(x, tau),
            );
            if !every(simd, simd.and_m64s(this, outside)) {
                return None;
            }
            let t = simd.sub_f64s(x, simd.splat_f64s(self.c * TAU));
            let zero = simd.splat_f64s(0.0);
            let t = simd.select_f64s(simd.less_than_f64s(t, zero), zero, t);
            simd.select_f64s(simd.greater_than_f64s(t, tau), tau, t)
        };
        let inside = simd.and_m64s(
            simd.greater_than_or_equal_f64s(t, simd.splat_f64s(self.lo)),
            simd.less_than_f64s(t, simd.splat_f64s(self.hi)),
        );
        every(simd, inside).then_some(t)
    }
}

/// Every lane of `m` true. (A plain function: a closure would not inherit the
/// caller's target features.)
#[inline(always)]
fn every<S: pulp::Simd>(simd: S, m: S::m64s) -> bool {
    let all = simd.equal_u64s(simd.splat_u64s(0), simd.splat_u64s(0));
    // No lane false: the first true lane of the complement is past the end.
    simd.first_true_m64s(simd.xor_m64s(m, all)) == S::F64_LANES
}

/// Blocks of `th` from the first while all their lanes lie in piece `k` of
/// cycle `c`, into `out`: how many blocks (0 if the first does not).
#[inline(always)]
fn run<S: pulp::Simd, const COPY: bool>(
    simd: S,
    program: &Program,
    (k, c): (usize, f64),
    th: &[S::f64s],
    out: [&mut [S::f64s]; 5],
) -> usize {
    let f = &program.fast[k];
    let lo = program.starts[k];
    let hi = program.starts.get(k + 1).copied().unwrap_or(TAU).min(TAU);
    let win = Window { lo, hi, c };
    // A first block that leaves the piece (an unsorted grid: most blocks)
    // costs no more than this check.
    if th.first().is_none_or(|&x| win.on_cycle(simd, x).is_none()) {
        return 0;
    }
    let sine = f.amp[0] != 0.0;
    if sine {
        // The sine's argument ω·t + φ over the piece, t in [0, hi − x0].
        let far = f.freq * (hi - f.x0) + f.phase[0];
        let widest = f.phase[0].abs().max(far.abs());
        if widest.is_nan() || widest > SINE_RANGE {
            return 0;
        }
    }
    // The position gained over c cycles, added where eval adds it.
    let lift = (c != 0.0).then_some(c * program.advance);
    // One loop per shape; longer polynomials (up to MAX_DEGREE + 1
    // coefficients, a rare spline or user law) share the loop of 8 with the
    // rest of their Horner steps unrolled at run time.
    macro_rules! shapes {
        ($($d:literal)*) => {
            match (f.poly[0].len(), sine) {
                $(
                    ($d, false) => blocks::<S, $d, false, COPY>(simd, f, win, lift, th, out),
                    ($d, true) => blocks::<S, $d, true, COPY>(simd, f, win, lift, th, out),
                )*
                (_, false) => blocks::<S, 9, false, COPY>(simd, f, win, lift, th, out),
                (_, true) => blocks::<S, 9, true, COPY>(simd, f, win, lift, th, out),
            }
        };
    }
    shapes!(0 1 2 3 4 5 6 7 8)
}

/// [`run`] for a piece of `D` coefficients of s (D = 9: any number ≥ 9), with
/// or without its sine term.
#[inline(always)]
fn blocks<S: pulp::Simd, const D: usize, const SINE: bool, const COPY: bool>(
    simd: S,
    f: &Fast,
    win: Window,
    lift: Option<f64>,
    th: &[S::f64s],
    out: [&mut [S::f64s]; 5],
) -> usize {
    let [copy, s, v, a, j] = out;
    let x0 = simd.splat_f64s(f.x0);
    let lift_v = simd.splat_f64s(lift.unwrap_or(0.0));
    let zero = simd.splat_f64s(0.0);
    // The coefficients of order o, lowest first, splatted once per run (the
    // first D − o of poly[o]; D = 9 holds the top 9, the rest are read in the
    // loop).
    let coef: [[S::f64s; D]; 4] = std::array::from_fn(|o| {
        let c = &f.poly[o];
        let skip = c.len().saturating_sub(D);
        std::array::from_fn(|m| simd.splat_f64s(c.get(skip + m).copied().unwrap_or(0.0)))
    });
    let (freq, phase) = (simd.splat_f64s(f.freq), simd.splat_f64s(f.phase[0]));
    let amp = f.amp.map(|x| simd.splat_f64s(x));
    let n = th.len().min(s.len()).min(v.len()).min(a.len()).min(j.len());
    let n = if COPY { n.min(copy.len()) } else { n };
    for b in 0..n {
        let x = th[b];
        let Some(t_cycle) = win.on_cycle(simd, x) else {
            return b;
        };
        let t = simd.sub_f64s(t_cycle, x0);
        let mut p = [zero; 4];
        for o in 0..4 {
            if D <= 8 {
                // D − o coefficients (none: p stays 0, as the scalar path's):
                // 0·t + c_top is c_top + 0, then Horner.
                let top = D.saturating_sub(o);
                if top == 0 {
                    continue;
                }
                let c = &coef[o];
                let mut acc = simd.add_f64s(c[top - 1], zero);
                for m in (0..top - 1).rev() {
                    acc = simd.add_f64s(simd.mul_f64s(acc, t), c[m]);
                }
                p[o] = acc;
            } else {
                // Long polynomials: the low coefficients from memory last.
                let c = &f.poly[o];
                let skip = c.len().saturating_sub(D);
                let mut acc = zero;
                for m in (0..D.min(c.len())).rev() {
                    acc = simd.add_f64s(simd.mul_f64s(acc, t), coef[o][m]);
                }
                for &cm in c[..skip].iter().rev() {
                    acc = simd.add_f64s(simd.mul_f64s(acc, t), simd.splat_f64s(cm));
                }
                p[o] = acc;
            }
        }
        if SINE {
            let u = simd.add_f64s(simd.mul_f64s(freq, t), phase);
            let (sn, cs) = sin_cos_simd(simd, u);
            p[0] = simd.add_f64s(p[0], simd.mul_f64s(amp[0], sn));
            p[1] = simd.add_f64s(p[1], simd.mul_f64s(amp[1], cs));
            p[2] = simd.sub_f64s(p[2], simd.mul_f64s(amp[2], sn));
            p[3] = simd.sub_f64s(p[3], simd.mul_f64s(amp[3], cs));
        }
        if lift.is_some() {
            p[0] = simd.add_f64s(p[0], lift_v);
        }
        if COPY {
            copy[b] = x;
        }
        s[b] = p[0];
        v[b] = p[1];
        a[b] = p[2];
        j[b] = p[3];
    }
    n
}

#[cfg(test)]
mod tests {
    use super::super::super::law::Segment as Piece;
    use super::*;
    use pulp::Simd;

    /// A program of hand-made pieces (the rules of `Program::new` are not what
    /// these tests are about): the shapes the lane loop has no law for.
    fn of_pieces(pieces: &[Piece]) -> Program {
        Program {
            specs: Vec::new(),
            spans: Vec::new(),
            fast: pieces.iter().map(Fast::new).collect(),
            starts: pieces.iter().map(|p| p.x0).collect(),
            advance: 0.3,
        }
    }

    fn piece(x0: f64, x1: f64, poly: Vec<f64>, amp: f64, freq: f64, phase: f64) -> Piece {
        Piece {
            x0,
            x1,
            poly,
            amp,
            freq,
            phase,
        }
    }

    /// Angles that exercise every path: a sorted grid (long runs), a shuffled
    /// one (every block leaves its piece), angles outside one cycle and on the
    /// piece boundaries, each from several offsets (so that the register
    /// alignment of the rows' starts and the tail's length vary).
    fn angles(program: &Program) -> Vec<f64> {
        let n = 1031;
        let mut theta: Vec<f64> = (0..n).map(|i| i as f64 * TAU / n as f64).collect();
        theta.extend((0..n).map(|i| ((i * 7919) % n) as f64 * TAU / n as f64));
        theta.extend([-1.0, 7.0, 100.0, TAU, 0.0, -0.0, 1e-300, TAU - 1e-15]);
        for &x0 in &program.starts {
            theta.extend([x0, x0.next_down(), x0.next_up()]);
        }
        // Sorted over several cycles either side (runs on cycles c ≠ 0, the
        // position lifted by c·advance), and the cycles' own boundaries.
        theta.extend((0..2003).map(|i| -13.0 + i as f64 * 33.0 / 2003.0));
        for c in -3..4 {
            let b = c as f64 * TAU;
            theta.extend([b, b.next_down(), b.next_up(), b + 1e-9, b - 1e-9]);
        }
        theta.extend((0..64).map(|i| 3.0 * TAU + (i as f64 - 32.0) * 1e-15));
        theta.extend((0..64).map(|i| -TAU + (i as f64 - 32.0) * 1e-15));
        theta
    }

    /// Every instruction set's lane loop against [`Program::eval`], bit for bit,
    /// at every offset of the angles into the output rows, with and without
    /// the copy of the angles.
    fn check(program: &Program) {
        let theta = angles(program);
        for offset in 0..9 {
            let th = &theta[offset..];
            let m = th.len();
            for copy in [false, true] {
                let runs = on_each_isa!(|simd| {
                    let mut out = vec![f64::NAN; 5 * m + 3];
                    // Rows that start at every alignment: out[1..] too.
                    let (c, rest) = out[1..].split_at_mut(m);
                    let (s, rest) = rest.split_at_mut(m);
                    let (v, rest) = rest.split_at_mut(m);
                    let (a, rest) = rest.split_at_mut(m);
                    let finite = Simd::vectorize(
                        simd,
                        LaneFill {
                            program,
                            th,
                            out: [s, v, a, &mut rest[..m]],
                            copy: copy.then_some(c),
                        },
                    );
                    assert!(finite);
                    out
                });
                assert!(runs.len() >= 2 || !cfg!(target_arch = "x86_64"));
                for (isa, out) in runs {
                    for (i, &x) in th.iter().enumerate() {
                        let want = program.eval(x);
                        let copied = if copy { x } else { f64::NAN };
                        assert_eq!(out[1 + i].to_bits(), copied.to_bits(), "{isa}: θ = {x}");
                        for k in 0..4 {
                            let got = out[1 + (k + 1) * m + i];
                            assert_eq!(
                                got.to_bits(),
                                want[k].to_bits(),
                                "{isa}: θ = {x}, order {k}, offset {offset}: {got} vs {}",
                                want[k]
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn every_piece_shape_is_the_pointwise_path_bit_for_bit() {
        // Polynomials of 0 to 12 coefficients (9 and more share one loop), with
        // and without a sine, −0 among the coefficients.
        let mut pieces = Vec::new();
        let n = 26;
        for d in 0..13 {
            for sine in [false, true] {
                let x0 = pieces.len() as f64 * TAU / n as f64;
                let poly = (0..d)
                    .map(|k| {
                        if k == d - 1 && d % 3 == 0 {
                            -0.0
                        } else {
                            0.3 - 0.07 * k as f64
                        }
                    })
                    .collect();
                let (amp, freq) = if sine {
                    (0.02, 3.0 + d as f64)
                } else {
                    (0.0, 0.0)
                };
                pieces.push(piece(
                    x0,
                    x0 + TAU / n as f64,
                    poly,
                    amp,
                    freq,
                    0.1 * d as f64,
                ));
            }
        }
        check(&of_pieces(&pieces));
    }

    #[test]
    fn a_sine_beyond_the_exact_reduction_is_the_pointwise_path_bit_for_bit() {
        // ω·t reaches 3e6 rad: the lane loop leaves this piece to the pointwise
        // path (the platform's sine there).
        let p = of_pieces(&[
            piece(0.0, 1.0, vec![0.1, 0.2], 0.01, 3e6, 0.5),
            piece(1.0, TAU, vec![0.3], 0.01, 2.0, -1e6),
        ]);
        check(&p);
    }

    #[test]
    fn a_non_finite_angle_is_named_whatever_the_threads() {
        let p = of_pieces(&[piece(0.0, TAU, vec![0.1, 0.2, 0.3], 0.01, 1.0, 0.0)]);
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            for (n, at) in [(7, 3), (20_000, 17_777)] {
                let mut theta: Vec<f64> = (0..n).map(|i| i as f64 * 6.0 / n as f64).collect();
                theta[at] = bad;
                for threads in [1, 2] {
                    let mut out = vec![0.0; 4 * n];
                    let e = p.eval_into(&theta, Some(threads), &mut out).unwrap_err();
                    let (mut copy, mut out) = (vec![0.0; n], vec![0.0; 4 * n]);
                    let f = p.eval_with_theta_into(&theta, Some(threads), &mut copy, &mut out);
                    for e in [e.to_string(), f.unwrap_err().to_string()] {
                        assert!(e.contains("theta") && e.contains(&format!("{at}")), "{e}");
                    }
                }
            }
        }
    }

    #[test]
    fn the_copy_of_the_angles_is_row_zero_on_every_thread_count() {
        let p = of_pieces(&[
            piece(0.0, 2.0, vec![0.1, 0.2, 0.3], 0.01, 1.0, 0.0),
            piece(2.0, TAU, vec![0.5], 0.0, 0.0, 0.0),
        ]);
        let n = 30_001;
        let theta: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin() * 9.0).collect();
        let mut four = vec![0.0; 4 * n];
        p.eval_into(&theta, Some(1), &mut four).unwrap();
        for threads in [1, 2] {
            let (mut copy, mut out) = (vec![f64::NAN; n], vec![f64::NAN; 4 * n]);
            p.eval_with_theta_into(&theta, Some(threads), &mut copy, &mut out)
                .unwrap();
            assert_eq!(copy, theta);
            assert_eq!(out, four);
        }
        let (mut short, mut out) = (vec![0.0; n - 1], vec![0.0; 4 * n]);
        let e = p.eval_with_theta_into(&theta, Some(1), &mut short, &mut out);
        let e = e.unwrap_err().to_string();
        assert!(e.contains("copy") && e.contains("30001 values"), "{e}");
    }
}
