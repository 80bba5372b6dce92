//! Shaking force, shaking moment and driving torque of many counterweight
//! designs at once (issue 34, item 4): the batch behind
//! `cyclomech.dynamics.balance` and its sweeps.
//!
//! **The linear form.** A counterweight on a link pivoted to the frame is the
//! vector w = (m r cos α, m r sin α) [kg·m] in the link's frame. At a given
//! speed, each of the four channels c (the shaking force's x and y [N], the
//! shaking moment [N·m], the driving torque [N·m]) at angle n is
//!
//! v_c(n) = base_c(n) + Σ_j ( lin_cj(n) · w_j + nrm_cj(n) · |w_j| ),
//!
//! linear in the counterweights' vectors, plus a term in their lengths: the
//! counterweight's own inertia about its pivot (a point mass m = |w|/r at its
//! radius r has J = m r² = |w| r) enters the moment and the torque. The Python
//! layer builds base, lin and nrm from the linkage's kinematics; this kernel
//! evaluates D designs over N angles, designs in parallel, and keeps only
//! their statistics ([`STATS`]), so 10 000 designs × 3600 angles never hold
//! the 10 000 × 3600 curves.
//!
//! Statistics over the N samples (a uniform grid over the cycle): RMS =
//! √(mean of squares) and peak = the largest magnitude; for the force, of
//! |(F_x, F_y)|.

use rayon::prelude::*;

use crate::input::InvalidInput;
use crate::parallel::{pool, resolve_threads};

/// The channels of the linear form, in the order of its leading axis.
pub const CHANNELS: [&str; 4] = ["force_x", "force_y", "moment", "torque"];

/// The columns of [`balance_stats_into`]'s rows, in order.
pub const STATS: [&str; 6] = [
    "rms_force",
    "peak_force",
    "rms_moment",
    "peak_moment",
    "rms_torque",
    "peak_torque",
];

/// Values per design in [`balance_stats_into`].
pub const N_STATS: usize = STATS.len();

const C: usize = CHANNELS.len();

/// The sizes of a linear form: `n` angles, `j` counterweights.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FormShape {
    pub n: usize,
    pub j: usize,
}

fn bad_len(field: &'static str, got: usize, want: usize, shape: &str) -> InvalidInput {
    InvalidInput::bad_value(
        field,
        got as f64,
        format!("values given; need {want} ({shape})"),
    )
}

/// Check the arrays of a linear form and of `designs` against `shape`.
fn check(
    base: &[f64],
    lin: &[f64],
    nrm: &[f64],
    designs: &[f64],
    shape: FormShape,
) -> Result<usize, InvalidInput> {
    let FormShape { n, j } = shape;
    if n == 0 {
        return Err(InvalidInput::bad_value(
            "angles",
            0.0,
            "must be >= 1 sample over the cycle",
        ));
    }
    if base.len() != C * n {
        return Err(bad_len("base", base.len(), C * n, "4 channels × N angles"));
    }
    if lin.len() != C * j * n * 2 {
        return Err(bad_len("lin", lin.len(), C * j * n * 2, "4 × J × N × 2"));
    }
    if nrm.len() != C * j * n {
        return Err(bad_len("nrm", nrm.len(), C * j * n, "4 × J × N"));
    }
    let per = 2 * j;
    let count = match designs.len().checked_div(per) {
        Some(d) if d * per == designs.len() => d,
        None if designs.is_empty() => 0,
        _ => {
            return Err(bad_len(
                "designs",
                designs.len(),
                per,
                "a multiple of J × 2",
            ))
        }
    };
    InvalidInput::check_finite("base", base)?;
    InvalidInput::check_finite("lin", lin)?;
    InvalidInput::check_finite("nrm", nrm)?;
    InvalidInput::check_finite("designs", designs)?;
    Ok(count)
}

/// Designs evaluated together: each angle's row of the form is read once for
/// all of them, and the arithmetic runs across them in SIMD lanes.
const BLOCK: usize = 8;

/// The form packed by angle: for angle n and channel c, the 3J coefficients
/// (lin_x, lin_y, nrm) of every counterweight in a row, so that a block of
/// designs reads one contiguous row per (n, c).
fn pack(lin: &[f64], nrm: &[f64], shape: FormShape) -> Vec<f64> {
    let FormShape { n, j } = shape;
    let mut out = vec![0.0; n * C * 3 * j];
    for k in 0..n {
        for c in 0..C {
            let row = &mut out[(k * C + c) * 3 * j..(k * C + c + 1) * 3 * j];
            for jj in 0..j {
                let at = (c * j + jj) * n + k;
                row[3 * jj] = lin[2 * at];
                row[3 * jj + 1] = lin[2 * at + 1];
                row[3 * jj + 2] = nrm[at];
            }
        }
    }
    out
}

/// [`STATS`] of up to [`BLOCK`] designs (`w` row-major, one per row of `out`)
/// into `out` (rows × [`N_STATS`]), from the packed form.
fn block_stats(base: &[f64], packed: &[f64], w: &[f64], shape: FormShape, out: &mut [f64]) {
    let FormShape { n, j } = shape;
    let rows = out.len() / N_STATS;
    // x[k][b]: design b's k-th coefficient (w_x, w_y, |w| per counterweight);
    // the lanes past `rows` stay 0 and are not written out.
    let mut x = vec![[0.0f64; BLOCK]; 3 * j];
    for b in 0..rows {
        for jj in 0..j {
            let (w0, w1) = (w[(b * j + jj) * 2], w[(b * j + jj) * 2 + 1]);
            x[3 * jj][b] = w0;
            x[3 * jj + 1][b] = w1;
            x[3 * jj + 2][b] = w0.hypot(w1);
        }
    }
    let zero = [0.0f64; BLOCK];
    let (mut sf, mut pf, mut sm, mut pm, mut st, mut pt) = (zero, zero, zero, zero, zero, zero);
    for k in 0..n {
        let mut v = [zero; C];
        for (c, vc) in v.iter_mut().enumerate() {
            *vc = [base[c * n + k]; BLOCK];
            let row = &packed[(k * C + c) * 3 * j..(k * C + c + 1) * 3 * j];
            for (coef, xk) in row.iter().zip(&x) {
                for (o, xb) in vc.iter_mut().zip(xk) {
                    *o += coef * xb;
                }
            }
        }
        // Maxima as selects (the inputs are finite): the lanes stay in SIMD
        // registers, where f64::max's NaN rule would split them.
        for b in 0..BLOCK {
            let f2 = v[0][b] * v[0][b] + v[1][b] * v[1][b];
            sf[b] += f2;
            pf[b] = if f2 > pf[b] { f2 } else { pf[b] };
            let (m2, t2) = (v[2][b] * v[2][b], v[3][b] * v[3][b]);
            sm[b] += m2;
            pm[b] = if m2 > pm[b] { m2 } else { pm[b] };
            st[b] += t2;
            pt[b] = if t2 > pt[b] { t2 } else { pt[b] };
        }
    }
    let nf = n as f64;
    for (b, row) in out.chunks_exact_mut(N_STATS).enumerate() {
        row.copy_from_slice(&[
            (sf[b] / nf).sqrt(),
            pf[b].sqrt(),
            (sm[b] / nf).sqrt(),
            pm[b].sqrt(),
            (st[b] / nf).sqrt(),
            pt[b].sqrt(),
        ]);
    }
}

/// The four channels of one design `w` (J × 2) into `buf` (4 × N).
fn channels(base: &[f64], lin: &[f64], nrm: &[f64], w: &[f64], shape: FormShape, buf: &mut [f64]) {
    let FormShape { n, j } = shape;
    buf.copy_from_slice(base);
    for c in 0..C {
        let out = &mut buf[c * n..(c + 1) * n];
        for (k, wk) in w.chunks_exact(2).enumerate().take(j) {
            let (w0, w1) = (wk[0], wk[1]);
            let len = w0.hypot(w1);
            let l = &lin[(c * j + k) * n * 2..(c * j + k + 1) * n * 2];
            let q = &nrm[(c * j + k) * n..(c * j + k + 1) * n];
            for ((o, lv), &qv) in out.iter_mut().zip(l.chunks_exact(2)).zip(q) {
                *o += lv[0] * w0 + lv[1] * w1 + qv * len;
            }
        }
    }
}

/// The four channels (4 × N, row-major) of one counterweight design `w`
/// (J × 2 [kg·m]) of the linear form (`base` 4 × N, `lin` 4 × J × N × 2,
/// `nrm` 4 × J × N; see the module's docs).
pub fn balance_channels(
    base: &[f64],
    lin: &[f64],
    nrm: &[f64],
    w: &[f64],
    shape: FormShape,
) -> Result<Vec<f64>, InvalidInput> {
    let d = check(base, lin, nrm, w, shape)?;
    if d != 1 {
        return Err(bad_len(
            "designs",
            w.len(),
            2 * shape.j,
            "one design: J × 2",
        ));
    }
    let mut buf = vec![0.0; C * shape.n];
    channels(base, lin, nrm, w, shape, &mut buf);
    Ok(buf)
}

/// [`STATS`] of each of the D designs (`designs` row-major D × J × 2 [kg·m])
/// of the linear form, into `out` (row-major D × [`N_STATS`]); designs in
/// parallel on `n_threads` threads (None: `CYCLOMECH_THREADS` or every core).
pub fn balance_stats_into(
    base: &[f64],
    lin: &[f64],
    nrm: &[f64],
    designs: &[f64],
    shape: FormShape,
    out: &mut [f64],
    n_threads: Option<i64>,
) -> Result<(), InvalidInput> {
    let d = check(base, lin, nrm, designs, shape)?;
    if out.len() != d * N_STATS {
        return Err(bad_len("out", out.len(), d * N_STATS, "D × 6"));
    }
    if d == 0 {
        return Ok(());
    }
    let per = 2 * shape.j;
    let packed = pack(lin, nrm, shape);
    let pool = pool(resolve_threads(n_threads)?)?;
    pool.install(|| {
        // A task is 8 blocks of designs; each block reads the form once.
        out.par_chunks_mut(N_STATS * BLOCK * 8)
            .enumerate()
            .for_each(|(ci, task)| {
                for (bi, rows) in task.chunks_mut(N_STATS * BLOCK).enumerate() {
                    if crate::cancel::requested() {
                        return;
                    }
                    let first = (ci * 8 + bi) * BLOCK;
                    let count = rows.len() / N_STATS;
                    let w = &designs[first * per..(first + count) * per];
                    block_stats(base, &packed, w, shape, rows);
                }
            });
    });
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A form of N angles and J counterweights with entries from a simple hash.
    fn form(n: usize, j: usize) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let f = |i: usize, s: f64| ((i as f64 * 0.7548776662 + s).fract() - 0.5) * 2.0;
        let base = (0..C * n).map(|i| f(i, 0.1)).collect();
        let lin = (0..C * j * n * 2).map(|i| f(i, 0.3)).collect();
        let nrm = (0..C * j * n).map(|i| f(i, 0.7)).collect();
        (base, lin, nrm)
    }

    #[test]
    fn batch_matches_a_direct_sum() {
        let shape = FormShape { n: 37, j: 2 };
        let (base, lin, nrm) = form(shape.n, shape.j);
        let designs: Vec<f64> = (0..130 * 4).map(|i| (i as f64 * 0.37).sin()).collect();
        let mut out = vec![0.0; 130 * N_STATS];
        balance_stats_into(&base, &lin, &nrm, &designs, shape, &mut out, Some(2)).unwrap();
        for d in [0usize, 63, 64, 129] {
            let w = &designs[d * 4..d * 4 + 4];
            // Straight from the definition, channel by channel.
            let v = |c: usize, k: usize| {
                let mut s = base[c * shape.n + k];
                for jj in 0..2 {
                    let at = (c * 2 + jj) * shape.n + k;
                    let (w0, w1) = (w[2 * jj], w[2 * jj + 1]);
                    s += lin[2 * at] * w0 + lin[2 * at + 1] * w1 + nrm[at] * w0.hypot(w1);
                }
                s
            };
            let f2: Vec<f64> = (0..shape.n)
                .map(|k| v(0, k).powi(2) + v(1, k).powi(2))
                .collect();
            let rms = (f2.iter().sum::<f64>() / shape.n as f64).sqrt();
            let peak = f2.iter().cloned().fold(0.0, f64::max).sqrt();
            let row = &out[d * N_STATS..(d + 1) * N_STATS];
            assert!((row[0] - rms).abs() < 1e-12 * (1.0 + rms));
            assert!((row[1] - peak).abs() < 1e-12 * (1.0 + peak));
            let t: Vec<f64> = (0..shape.n).map(|k| v(3, k)).collect();
            let rt = (t.iter().map(|x| x * x).sum::<f64>() / shape.n as f64).sqrt();
            assert!((row[4] - rt).abs() < 1e-12 * (1.0 + rt));
        }
    }

    #[test]
    fn bad_shapes_and_values_are_refused_by_name() {
        let shape = FormShape { n: 5, j: 1 };
        let (base, lin, mut nrm) = form(5, 1);
        let mut out = vec![0.0; N_STATS];
        let e = balance_stats_into(&base[1..], &lin, &nrm, &[0.0, 0.0], shape, &mut out, None);
        assert!(e.unwrap_err().to_string().starts_with("base = 19"));
        let e = balance_stats_into(&base, &lin, &nrm, &[0.0, 0.0, 1.0], shape, &mut out, None);
        assert!(e.unwrap_err().to_string().starts_with("designs = 3"));
        nrm[3] = f64::NAN;
        let e = balance_stats_into(&base, &lin, &nrm, &[0.0, 0.0], shape, &mut out, None);
        assert!(e.unwrap_err().to_string().contains("nrm[3]"));
        let zero = FormShape { n: 0, j: 1 };
        let e = balance_channels(&[], &[], &[], &[0.0, 0.0], zero);
        assert!(e.unwrap_err().to_string().starts_with("angles = 0"));
    }
}
