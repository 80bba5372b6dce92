//! Bracketed one-dimensional searches behind the cam's loads and bounds:
//! the maximum of a function over a segment (a grid, then Brent's maximiser on
//! each leading local maximum) and Brent's root.

/// Grid points over a segment's unit interval before refinement.
pub const GRID: usize = 49;

/// Local grid maxima refined, at most.
const REFINE: usize = 4;

/// Maximum of `f` over x ∈ [0, 1] and where it is, as (value, x): `f` on a
/// grid of [`GRID`] points, then every local grid maximum within 5 % of the
/// best (at most [`REFINE`]) refined by Brent's maximiser on its two
/// neighbouring cells to 1e-10 in x. A NaN anywhere counts as +∞ (a violated
/// criterion), so the result is +∞ there.
pub fn max_unit(f: impl Fn(f64) -> f64) -> (f64, f64) {
    max_unit_cut(f, f64::NEG_INFINITY)
}

/// [`max_unit`], but where the grid's best is below `cut` the grid's best is
/// returned unrefined (a bound search that only needs to know the worst value
/// is well under its limit saves the refinement there).
pub fn max_unit_cut(f: impl Fn(f64) -> f64, cut: f64) -> (f64, f64) {
    let h = 1.0 / (GRID - 1) as f64;
    let mut v = [0.0; GRID];
    for (i, vi) in v.iter_mut().enumerate() {
        *vi = f(i as f64 * h);
    }
    refine(&f, &v, cut)
}

/// The refinement of [`max_unit_cut`] given `f`'s values `v` on its grid.
pub fn refine(f: &impl Fn(f64) -> f64, v: &[f64; GRID], cut: f64) -> (f64, f64) {
    let h = 1.0 / (GRID - 1) as f64;
    if let Some(i) = v.iter().position(|y| y.is_nan() || *y == f64::INFINITY) {
        return (f64::INFINITY, i as f64 * h);
    }
    let (mut bi, mut best) = (0, v[0]);
    for (i, &y) in v.iter().enumerate() {
        if y > best {
            (bi, best) = (i, y);
        }
    }
    if best < cut {
        return (best, bi as f64 * h);
    }
    let floor = best - 0.05 * best.abs();
    let mut top = (best, bi as f64 * h);
    let mut refined = 0;
    for i in 0..GRID {
        let left = i == 0 || v[i] >= v[i - 1];
        let right = i == GRID - 1 || v[i] >= v[i + 1];
        if !(left && right && v[i] >= floor) || refined == REFINE {
            continue;
        }
        refined += 1;
        let (x, y) = brent_max(f, cell(i).0, cell(i).1, 1e-10);
        if y.is_nan() {
            return (f64::INFINITY, x);
        }
        if y > top.0 {
            top = (y, x);
        }
    }
    top
}

/// The two grid cells around grid point `i` (one at an end), as [lo, hi].
pub fn cell(i: usize) -> (f64, f64) {
    let h = 1.0 / (GRID - 1) as f64;
    let lo = if i == 0 { 0.0 } else { (i - 1) as f64 * h };
    let hi = if i == GRID - 1 {
        1.0
    } else {
        (i + 1) as f64 * h
    };
    (lo, hi)
}

/// Maximum of `f` on [a, b] by Brent's method (golden sections with parabolic
/// steps; Numerical Recipes' `brent` on −f) to `tol` relative in x; (x, f(x)).
pub fn brent_max(f: &impl Fn(f64) -> f64, a: f64, b: f64, tol: f64) -> (f64, f64) {
    const C: f64 = 0.381_966_011_250_105_1;
    let (mut a, mut b) = (a, b);
    let mut x = a + C * (b - a);
    let (mut w, mut v) = (x, x);
    let mut fx = -f(x);
    let (mut fw, mut fv) = (fx, fx);
    let (mut d, mut e): (f64, f64) = (0.0, 0.0);
    for _ in 0..100 {
        let xm = 0.5 * (a + b);
        let tol1 = tol * x.abs() + 1e-15;
        let tol2 = 2.0 * tol1;
        if (x - xm).abs() <= tol2 - 0.5 * (b - a) {
            break;
        }
        let mut golden = true;
        if e.abs() > tol1 {
            let r = (x - w) * (fx - fv);
            let mut q = (x - v) * (fx - fw);
            let mut p = (x - v) * q - (x - w) * r;
            q = 2.0 * (q - r);
            if q > 0.0 {
                p = -p;
            } else {
                q = -q;
            }
            if p.abs() < (0.5 * q * e).abs() && p > q * (a - x) && p < q * (b - x) {
                e = d;
                d = p / q;
                let u = x + d;
                if u - a < tol2 || b - u < tol2 {
                    d = tol1.copysign(xm - x);
                }
                golden = false;
            }
        }
        if golden {
            e = if x >= xm { a - x } else { b - x };
            d = C * e;
        }
        let u = if d.abs() >= tol1 {
            x + d
        } else {
            x + tol1.copysign(d)
        };
        let fu = -f(u);
        if fu.is_nan() {
            return (u, f64::NAN);
        }
        if fu <= fx {
            if u >= x {
                a = x;
            } else {
                b = x;
            }
            (v, fv, w, fw, x, fx) = (w, fw, x, fx, u, fu);
        } else {
            if u < x {
                a = u;
            } else {
                b = u;
            }
            if fu <= fw || w == x {
                (v, fv, w, fw) = (w, fw, u, fu);
            } else if fu <= fv || v == x || v == w {
                (v, fv) = (u, fu);
            }
        }
    }
    (x, -fx)
}

/// A root of `f` in [a, b] given f(a) = `fa` and f(b) = `fb` of opposite signs
/// (or one of them 0), by Brent's method (scipy's `brentq`), to
/// |Δx| ≤ xtol + rtol·|x|.
pub fn brent_zero(
    mut f: impl FnMut(f64) -> f64,
    a: f64,
    b: f64,
    fa: f64,
    fb: f64,
    xtol: f64,
    rtol: f64,
) -> f64 {
    let (mut xpre, mut xcur, mut fpre, mut fcur) = (a, b, fa, fb);
    if fpre == 0.0 {
        return xpre;
    }
    if fcur == 0.0 {
        return xcur;
    }
    let (mut xblk, mut fblk, mut spre, mut scur) = (0.0, 0.0, 0.0, 0.0);
    for _ in 0..200 {
        if fpre != 0.0 && fcur != 0.0 && (fpre < 0.0) != (fcur < 0.0) {
            (xblk, fblk) = (xpre, fpre);
            spre = xcur - xpre;
            scur = spre;
        }
        if fblk.abs() < fcur.abs() {
            (xpre, xcur, xblk) = (xcur, xblk, xcur);
            (fpre, fcur, fblk) = (fcur, fblk, fcur);
        }
        let delta = 0.5 * (xtol + rtol * xcur.abs());
        let sbis = 0.5 * (xblk - xcur);
        if fcur == 0.0 || sbis.abs() < delta {
            return xcur;
        }
        if spre.abs() > delta && fcur.abs() < fpre.abs() {
            let stry = if xpre == xblk {
                -fcur * (xcur - xpre) / (fcur - fpre)
            } else {
                let dpre = (fpre - fcur) / (xpre - xcur);
                let dblk = (fblk - fcur) / (xblk - xcur);
                -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre))
            };
            if 2.0 * stry.abs() < spre.abs().min(3.0 * sbis.abs() - delta) {
                spre = scur;
                scur = stry;
            } else {
                spre = sbis;
                scur = sbis;
            }
        } else {
            spre = sbis;
            scur = sbis;
        }
        (xpre, fpre) = (xcur, fcur);
        xcur += if scur.abs() > delta {
            scur
        } else {
            delta.copysign(sbis)
        };
        fcur = f(xcur);
    }
    xcur
}
