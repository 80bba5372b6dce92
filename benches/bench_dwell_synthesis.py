"""Six-bar dwell candidates: cyclomech's batch evaluation against numpy and numba.

``_core.dwell_batch`` (``rust/core/src/synthesis/dwell.rs``, the kernel behind
:func:`cyclomech.synthesis.dwell_sixbar`: one call per generation of its
differential evolution) evaluates K candidate four-bars with coupler points — a
dwell of 60°, a swing of 40°, transmission angles ≥ 30°, link ratio ≤ 10, 25
crank angles over the dwell and 360 over the turn (the function's defaults) —
against :func:`numpy_batch`, the same evaluation written with numpy, vectorised
over the candidates (and over both sides of the pivot placement at once):

* Grashof and the four-bar's transmission extremes (at θ = 0 and π) in closed form;
* the coupler points at the dwell's 25 angles in closed form, the Kåsa fit as
  batched 3 × 3 normal equations (centred), then Gauss–Newton steps batched
  (each candidate stops where the kernel's does: a step below 1e-15 of the radius);
* the farthest coupler point of the turn, the pivot's construction, and the
  secant steps on the chord angle q run in lockstep over the (candidate, side)
  pairs still iterating (the kernel's rule, step for step);
* the measures: the output angle on the kernel's grids (101 crank angles over
  the dwell, 363 over the turn), whose coupler points do not change with q and
  are computed once per candidate (the kernel recomputes them at every secant
  step: a user of numpy would cache them), then the four extremes refined by
  golden-section search, all four batched into one array, to the kernel's
  1e-13 rad bracket; the second loop's transmission angle on the 360-angle grid.

And against :func:`numba_batch`: the same rule step for step in scalar loops, one
candidate per ``prange`` iteration, with the same cached grids.

Both peers give the same 18 fields per candidate: they are compared to 1e-9
(radians, metres on a 1 m ground) before anything is timed
(:func:`test_numpy_agrees`, :func:`test_numba_agrees`), but for a few
ill-conditioned infeasible candidates (see :func:`test_numpy_agrees`). The
candidates are uniform in the search's bounds (``_dwell._BOUNDS``): what the
first generation of the search evaluates; about a fifth of them (828 of the 4000
timed) have a crank that turns, an arc and a placement, and are built and measured
(about 12 placements each: 2 sides × ~6 secant steps), the rest are rejected in a
few operations by all. The output is small (K × 18), so there is no page-state question here.

Default test run (``--benchmark-disable`` in addopts): each row once on 200
candidates, without numba (compiling it takes 20–30 s the first time; cached in
``benches/__pycache__``; ``CYCLOMECH_BENCH_NUMBA=1`` includes it). For timings,
the ratio tables and (``-s``) the interleaved rounds' medians and ratios::

    python -m pytest benches/bench_dwell_synthesis.py --benchmark-enable -q -p no:cacheprovider -s
"""

from __future__ import annotations

import math
import os
from typing import Any

import cyclomech as cm  # noqa: F401 - the package loads the core
import numpy as np
import numpy.typing as npt
import pytest
from _timing import interleaved, timed_run
from cyclomech import _core
from cyclomech.synthesis._dwell import _BOUNDS

Array = npt.NDArray[np.float64]
GROUP = "synthesis: six-bar dwell candidates (dwell_batch), per candidate"
K_TIMED = 4_000
K_SMOKE = 200
SPAN, SWING, MIN_MU, MAX_RATIO = math.radians(60.0), math.radians(40.0), math.radians(30.0), 10.0
N_DWELL, N_TURN = 25, 360
SIGMA = 1.0
GN_STEPS, SWING_TOL, REJECTED = 20, 1e-9, 1e9
GOLD = (math.sqrt(5.0) - 1.0) / 2.0
FIELDS = tuple(_core.dwell_fields())


def candidates(k: int, seed: int = 0) -> Array:
    """K rows (a, b, c, d, u, v, θm), uniform in the search's bounds, ground 1."""
    rng = np.random.default_rng(seed)
    x = np.column_stack([rng.uniform(lo, hi, k) for lo, hi in _BOUNDS])
    return np.ascontiguousarray(np.column_stack([x[:, :3], np.ones(k), x[:, 3:]]))


def cyclomech_batch(p: Array, threads: int | None) -> Array:
    return _core.dwell_batch(
        p, SIGMA, SPAN, SWING, MIN_MU, MAX_RATIO, N_DWELL, N_TURN, n_threads=threads
    )


# ------------------------------------------------------------------ the peer
def coupler(g: tuple[Array, ...], t: Array) -> tuple[Array, Array, Array]:
    """Coupler point (x, y) and whether it assembles; g = (a, b, c, d, u, v) each
    broadcastable against the crank angles t."""
    a, b, c, d, u, v = g
    ct, st = np.cos(t), np.sin(t)
    bx, by = a * ct - d, a * st
    f2 = bx * bx + by * by
    f = np.sqrt(f2)
    cos_g = (c * c + f2 - b * b) / (2.0 * c * f)
    ok = (np.abs(cos_g) <= 1.0) & (f != 0.0)
    t4 = np.arctan2(by, bx) + SIGMA * np.arccos(np.clip(cos_g, -1.0, 1.0))
    px, py = a * ct, a * st
    ex, ey = (d + c * np.cos(t4) - px) / b, (c * np.sin(t4) - py) / b
    return px + u * ex - v * ey, py + u * ey + v * ex, ok


def joint_angle(o: tuple[Array, ...], px: Array, py: Array) -> tuple[Array, Array]:
    """The angle of F → E for the coupler point P, and whether the dyad assembles;
    o = (pivot x, pivot y, dyad R, rocker e, branch τ)."""
    fx0, fy0, r, e, tau = o
    fx, fy = px - fx0, py - fy0
    f2 = fx * fx + fy * fy
    f = np.sqrt(f2)
    cos_g = (e * e + f2 - r * r) / (2.0 * e * f)
    ok = (np.abs(cos_g) <= 1.0) & (f != 0.0)
    return np.arctan2(fy, fx) + tau * np.arccos(np.clip(cos_g, -1.0, 1.0)), ok


def wrap(x: Array) -> Array:
    """Into (−π, π] (the kernel's formula)."""
    return x - 2 * np.pi * np.ceil((x + np.pi) / (2 * np.pi)) + 2 * np.pi


def solve3(m: Array, r: Array) -> tuple[Array, Array]:
    """Batched 3 × 3 solves and which are regular (the kernel's pivot test, by the
    determinant's scale instead)."""
    big = np.abs(m).max(axis=(1, 2))
    ok = np.abs(np.linalg.det(m)) > 1e-14 * big**3
    m = np.where(ok[:, None, None], m, np.eye(3))
    return np.linalg.solve(m, r[:, :, None])[:, :, 0], ok


def fit_circles(x: Array, y: Array) -> tuple[Array, Array, Array, Array]:
    """Kåsa then Gauss–Newton over rows of points (K, n): centre, radius, ok."""
    n = x.shape[1]
    mx, my = x.sum(1) / n, y.sum(1) / n
    x, y = x - mx[:, None], y - my[:, None]
    z = -(x * x + y * y)
    sx, sy, sxx, sxy, syy = x.sum(1), y.sum(1), (x * x).sum(1), (x * y).sum(1), (y * y).sum(1)
    m = np.stack(
        [
            np.stack([sxx, sxy, sx], -1),
            np.stack([sxy, syy, sy], -1),
            np.stack([sx, sy, np.full_like(sx, n)], -1),
        ],
        1,
    )
    rhs = np.stack([(x * z).sum(1), (y * z).sum(1), z.sum(1)], -1)
    sol, ok = solve3(m, rhs)
    cx, cy = -sol[:, 0] / 2, -sol[:, 1] / 2
    r2 = cx * cx + cy * cy - sol[:, 2]
    ok &= r2 > 0
    rad = np.sqrt(np.where(ok, r2, 1.0))
    live = ok.copy()
    for _ in range(GN_STEPS):
        i = np.flatnonzero(live)
        if i.size == 0:
            break
        dx, dy = x[i] - cx[i, None], y[i] - cy[i, None]
        di = np.hypot(dx, dy)
        zero = (di == 0).any(1)
        di = np.where(di == 0, 1.0, di)
        rows = np.stack([-dx / di, -dy / di, -np.ones_like(di)], -1)  # (m, n, 3)
        res = di - rad[i, None]
        jtj = np.einsum("kni,knj->kij", rows, rows)
        jtr = -np.einsum("kni,kn->ki", rows, res)
        step, reg = solve3(jtj, jtr)
        ok[i[zero]] = False
        go = reg & ~zero
        j = i[go]
        cx[j] += step[go, 0]
        cy[j] += step[go, 1]
        rad[j] += step[go, 2]
        small = np.abs(step[go]).max(1) <= 1e-15 * np.abs(rad[j])
        live[i[~go]] = False
        live[j[small]] = False
    ok &= np.isfinite(rad) & (rad > 0)
    return cx + mx, cy + my, rad, ok


def golden_max(f: Any, lo: Array, hi: Array) -> Array:
    """The kernel's golden-section search, in lockstep over rows (each row stops
    where the kernel's would: a bracket ≤ 1e-13)."""
    lo, hi = lo.copy(), hi.copy()
    x1, x2 = hi - GOLD * (hi - lo), lo + GOLD * (hi - lo)
    f1, f2 = f(x1, slice(None)), f(x2, slice(None))
    live = np.ones(lo.shape, bool)
    for _ in range(80):
        i = np.flatnonzero(live)
        if i.size == 0:
            break
        up = f1[i] < f2[i]
        iu, idn = i[up], i[~up]
        lo[iu] = x1[iu]
        x1[iu], f1[iu] = x2[iu], f2[iu]
        hi[idn] = x2[idn]
        x2[idn], f2[idn] = x1[idn], f1[idn]
        xn = np.where(up, lo[i] + GOLD * (hi[i] - lo[i]), hi[i] - GOLD * (hi[i] - lo[i]))
        fn = f(xn, i)
        x2[iu], f2[iu] = xn[up], fn[up]
        x1[idn], f1[idn] = xn[~up], fn[~up]
        live[i[hi[i] - lo[i] <= 1e-13]] = False
    return np.maximum(f1, f2)


class Grids:
    """Per (candidate, side) pair: the design and the coupler points on the
    kernel's fixed grids (computed once; they do not depend on the placement)."""

    def __init__(self, g: tuple[Array, ...], tm: Array) -> None:
        self.g, self.tm = g, tm
        col = [x[:, None] for x in g]
        n = 4 * N_DWELL
        lo, hi = tm - SPAN / 2.0, tm + SPAN / 2.0
        self.dwell = (lo, (hi - lo) / n, n)
        st = 2 * np.pi / N_TURN
        lo2, hi2 = tm - np.pi - st, tm + np.pi + st
        self.turn = (lo2, (hi2 - lo2) / (N_TURN + 2), N_TURN + 2)
        self.pts = []
        for lo_, step, m in (self.dwell, self.turn):
            t = lo_[:, None] + step[:, None] * np.arange(m + 1)
            px, py, ok = coupler(tuple(col), t)
            self.pts.append((px, py, ok.all(1)))
        t = tm[:, None] + 2 * np.pi * np.arange(N_TURN) / N_TURN
        self.mu_pts = coupler(tuple(col), t)
        self.mid = coupler(g, tm)

    def take(self, i: Array) -> Grids:
        new = object.__new__(Grids)
        new.g = tuple(x[i] for x in self.g)
        new.tm = self.tm[i]
        new.dwell = tuple(x[i] if isinstance(x, np.ndarray) else x for x in self.dwell)
        new.turn = tuple(x[i] if isinstance(x, np.ndarray) else x for x in self.turn)
        new.pts = [(px[i], py[i], ok[i]) for px, py, ok in self.pts]
        new.mu_pts = tuple(x[i] for x in self.mu_pts)
        new.mid = tuple(x[i] for x in self.mid)
        return new


def measure(gr: Grids, o: tuple[Array, ...]) -> tuple[Array, ...]:
    """(residual, swing, μ2 min, μ2 max, ok) of the placements o over the rows."""
    ang_mid, ok = joint_angle(o, gr.mid[0], gr.mid[1])
    ok &= gr.mid[2]
    col = tuple(x[:, None] for x in o)
    # Sampled ψ on both grids; first max / first min as the kernel's folds.
    los, his, signs, samples = [], [], [], []
    for (lo, step, n), (px, py, pok) in zip((gr.dwell, gr.turn), gr.pts, strict=True):
        a, jok = joint_angle(col, px, py)
        ok &= pok & jok.all(1)
        psi = wrap(a - ang_mid[:, None])
        imax, imin = psi.argmax(1), psi.argmin(1)
        rows = np.arange(len(psi))
        for idx, sign in ((imax, 1.0), (imin, -1.0)):
            los.append(lo + step * np.maximum(idx - 1, 0))
            his.append(lo + step * np.minimum(idx + 1, n))
            signs.append(np.full(len(lo), sign))
            samples.append(sign * psi[rows, idx])
    # The four refinements (dwell max/min, turn max/min) in one batch.
    reps = 4
    g4 = tuple(np.tile(x, reps) for x in gr.g)
    o4 = tuple(np.tile(x, reps) for x in o)
    mid4 = np.tile(ang_mid, reps)
    sg = np.concatenate(signs)

    def f(t: Array, i: Any) -> Array:
        gi = tuple(x[i] for x in g4)
        px, py, cok = coupler(gi, t)
        a, jok = joint_angle(tuple(x[i] for x in o4), px, py)
        v = sg[i] * wrap(a - mid4[i])
        return np.where(cok & jok, v, -np.inf)

    with np.errstate(invalid="ignore", divide="ignore"):
        best = golden_max(f, np.concatenate(los), np.concatenate(his))
    best = np.maximum(best, np.concatenate(samples)).reshape(reps, -1)
    residual = best[0] + best[1]
    swing = best[2] + best[3]
    px, py, mok = gr.mu_pts
    f2 = (px - o[0][:, None]) ** 2 + (py - o[1][:, None]) ** 2
    r, e = o[2][:, None], o[3][:, None]
    cmu = (r * r + e * e - f2) / (2.0 * r * e)
    ok &= mok.all(1)
    mu2_min = np.arccos(np.clip(cmu.max(1), -1, 1))
    mu2_max = np.arccos(np.clip(cmu.min(1), -1, 1))
    return residual, swing, mu2_min, mu2_max, ok


def construct(
    centre: tuple[Array, Array],
    rad: Array,
    far: tuple[Array, Array],
    pmid: Any,
    q: Array,
    side: Array,
) -> tuple[tuple[Array, ...], Array]:
    """The pivot placement for chord angle q on each side (kernel's
    ``construct`` and the branch τ): (pivot x, pivot y, R, e, τ), ok."""
    dx, dy = far[0] - centre[0], far[1] - centre[1]
    dist = np.hypot(dx, dy)
    h = dist - rad
    ok = h > 1e-9 * dist
    ux, uy = dx / dist, dy / dist
    mx, my = centre[0] + ux * h / 2.0, centre[1] + uy * h / 2.0
    off = side * h / 2.0 / np.tan(q / 2.0)
    fx, fy = mx - uy * off, my + ux * off
    e = h / 2.0 / np.sin(q / 2.0)
    gx, gy = pmid[0] - fx, pmid[1] - fy
    kx, ky = centre[0] - fx, centre[1] - fy
    tau = np.where(gx * ky - gy * kx >= 0.0, 1.0, -1.0)
    return (fx, fy, rad, e, tau), ok


def numpy_batch(params: Array) -> Array:
    """The kernel's 18 fields per candidate (``dwell_fields()``), numpy."""
    k = len(params)
    out = np.full((k, len(FIELDS)), np.nan)
    out[:, 0] = REJECTED
    a, b, c, d, u, v, tm = params.T
    srt = np.sort(params[:, :4], axis=1)
    s, p_, q_, l_ = srt.T
    excess = (s + l_) - (p_ + q_)
    grashof = (np.abs(excess) <= 1e-12 * (a + b + c + d)) | (excess <= 0)
    turns = grashof & (np.minimum(a, d) == s)
    c_lo = (b * b + c * c - a * a - d * d + 2.0 * a * d) / (2.0 * b * c)
    c_hi = (b * b + c * c - a * a - d * d - 2.0 * a * d) / (2.0 * b * c)
    turns &= (c_lo <= 1.0) & (c_hi >= -1.0)
    i = np.flatnonzero(turns)
    g = tuple(x[i] for x in (a, b, c, d, u, v))
    tm = tm[i]
    mu4_min, mu4_max = np.arccos(c_lo[i]), np.arccos(c_hi[i])
    # The arc.
    col = tuple(x[:, None] for x in g)
    lo = tm - SPAN / 2.0
    t = lo[:, None] + SPAN * np.arange(N_DWELL) / (N_DWELL - 1)
    px, py, ok = coupler(col, t)
    ok = ok.all(1)
    with np.errstate(invalid="ignore", divide="ignore"):
        cx, cy, rad, fit = fit_circles(np.where(ok[:, None], px, 0), np.where(ok[:, None], py, 1))
    ok &= fit
    dev = np.abs(np.hypot(px - cx[:, None], py - cy[:, None]) - rad[:, None]).max(1)
    # The farthest coupler point of the turn.
    fx_, fy_, fok = coupler(col, 2 * np.pi * np.arange(N_TURN) / N_TURN)
    dist = np.where(fok, np.hypot(fx_ - cx[:, None], fy_ - cy[:, None]), -np.inf)
    j = dist.argmax(1)
    far = (fx_[np.arange(len(j)), j], fy_[np.arange(len(j)), j])
    keep = np.flatnonzero(ok)
    i, g, tm = i[keep], tuple(x[keep] for x in g), tm[keep]
    mu4_min, mu4_max, dev = mu4_min[keep], mu4_max[keep], dev[keep]
    cx, cy, rad = cx[keep], cy[keep], rad[keep]
    far = (far[0][keep], far[1][keep])
    # Both sides as rows 0..n-1 (side +1) and n..2n-1 (side −1).
    n = len(i)
    two = lambda x: np.concatenate([x, x])  # noqa: E731
    g2, tm2 = tuple(two(x) for x in g), two(tm)
    side = np.concatenate([np.ones(n), -np.ones(n)])
    centre, rad2, far2 = (two(cx), two(cy)), two(rad), (two(far[0]), two(far[1]))
    gr = Grids(g2, tm2)
    pmid = (gr.mid[0], gr.mid[1])

    def evaluate(rows: Array, q: Array) -> tuple[tuple[Array, ...], tuple[Array, ...], Array]:
        o, ok = construct(
            (centre[0][rows], centre[1][rows]),
            rad2[rows],
            (far2[0][rows], far2[1][rows]),
            (pmid[0][rows], pmid[1][rows]),
            q,
            side[rows],
        )
        with np.errstate(invalid="ignore", divide="ignore"):
            m = measure(gr.take(rows), o)
        return o, m[:4], ok & m[4]

    clamp = lambda x: np.clip(x, 1e-3, np.pi - 1e-3)  # noqa: E731
    allr = np.arange(2 * n)
    q0 = np.full(2 * n, SWING)
    q1 = clamp(q0 * 1.05)
    bo, bm, alive = evaluate(allr, q0)
    bo, bm = [x.copy() for x in bo], [x.copy() for x in bm]
    g0 = bm[1] - SWING
    live = alive & ~(np.abs(g0) <= SWING_TOL * 0.01)
    for _ in range(30):
        r = np.flatnonzero(live)
        if r.size == 0:
            break
        o, m, ok = evaluate(r, q1[r])
        live[r[~ok]] = False
        r, o, m = r[ok], [x[ok] for x in o], [x[ok] for x in m]
        g1 = m[1] - SWING
        better = np.abs(g1) < np.abs(g0[r])
        for dst, src in zip(bo + bm, o + m, strict=True):
            dst[r[better]] = src[better]
        same = g1 == g0[r]
        live[r[same]] = False
        r, g1 = r[~same], g1[~same]
        q2 = clamp(q1[r] - g1 * (q1[r] - q0[r]) / (g1 - g0[r]))
        q0[r], g0[r], q1[r] = q1[r], g1, q2
        live[r[np.abs(g1) <= SWING_TOL * 0.01]] = False
    # The measures, the violation and the objective of each side; the better kept.
    residual, swing, mu2_min, mu2_max = bm
    pfx, pfy, _, rocker, tau = bo
    lens = np.column_stack([*g2[:4], rad2, rocker])
    ratio = lens.max(1) / lens.min(1)
    mu4 = two(np.minimum(mu4_min, np.pi - mu4_max))
    mu2 = np.minimum(mu2_min, np.pi - mu2_max)
    miss = np.abs(swing - SWING)
    viol = (
        np.maximum(MIN_MU - mu4, 0.0)
        + np.maximum(MIN_MU - mu2, 0.0)
        + np.maximum(np.log(ratio / MAX_RATIO), 0.0)
        + np.where(miss > SWING_TOL, miss, 0.0)
    )
    obj = np.degrees(residual + 1000.0 * viol)
    obj = np.where(alive, obj, np.inf)
    pick = np.where(obj[n:] < obj[:n], np.arange(n) + n, np.arange(n))
    found = alive[pick]
    cols = np.column_stack(
        [
            obj[pick],
            viol[pick],
            residual[pick],
            swing[pick],
            cx,
            cy,
            rad,
            pfx[pick],
            pfy[pick],
            rocker[pick],
            tau[pick],
            dev,
            two(mu4_min)[pick],
            two(mu4_max)[pick],
            mu2_min[pick],
            mu2_max[pick],
            side[pick],
            ratio[pick],
        ]
    )
    out[i[found]] = cols[found]
    return out


@pytest.fixture(scope="module")
def numpy_checked() -> None:
    """numpy_batch checked against cyclomech (:func:`test_numpy_agrees`), before
    any row that times it."""
    p = candidates(1_000, seed=3)
    _agreement(cyclomech_batch(p, None), numpy_batch(p), len(p))


def test_numpy_agrees(numpy_checked: None) -> None:
    """The same rejections and feasible designs, and all 18 fields to 1e-9 (relative
    or absolute) on the candidates both evaluate but for the ill-conditioned few.

    Those few (3–6 % of the evaluated ones on seeds 3 and 4, none feasible): arcs
    so nearly straight that the fitted radius is tens of links (Gauss–Newton has
    not converged in its 20 steps, and its last iterate depends on rounding), or
    an output that turns a full circle (a swing of 2π, whose peak-to-peak depends
    on where ψ wraps); their secant steps part on the last bits. Every feasible
    candidate agrees to 1e-9 (to 3e-11 with numba, 2.5e-12 with numpy on seed 3)."""


def _k(benchmark: Any) -> int:
    return K_SMOKE if benchmark.disabled else K_TIMED


@pytest.mark.benchmark(group=GROUP)
@pytest.mark.parametrize("threads", [1, None], ids=["1-thread", "all-cores"])
def test_dwell_cyclomech(benchmark, threads: int | None) -> None:
    k = _k(benchmark)
    p = candidates(k)
    benchmark.extra_info["tool"] = "cyclomech"
    where = "all cores" if threads is None else "1 thread"
    benchmark.extra_info["what"] = f"_core.dwell_batch, {k} candidates, {where}"
    benchmark.extra_info["items"] = k
    out = benchmark.pedantic(cyclomech_batch, (p, threads), rounds=3, iterations=1)
    assert out.shape == (k, len(FIELDS))


@pytest.mark.benchmark(group=GROUP)
def test_dwell_numpy(benchmark, numpy_checked: None) -> None:
    k = _k(benchmark)
    p = candidates(k)
    benchmark.extra_info["tool"] = "numpy"
    benchmark.extra_info["what"] = f"batched over {k} candidates x 2 sides"
    benchmark.extra_info["items"] = k
    out = benchmark.pedantic(numpy_batch, (p,), rounds=3, iterations=1)
    assert out.shape == (k, len(FIELDS))


# ------------------------------------------------------------- the numba peer
try:
    import numba
except ImportError:  # pragma: no cover - depends on the environment
    numba = None

# The numba peer: the same evaluation, one candidate per loop iteration (``prange``
# over candidates), the kernel's rule step for step, with the coupler points of
# the fixed grids computed once per candidate (as numpy's). Compiled on first use
# and cached on disk (benches/__pycache__).
PI, TAU = math.pi, 2 * math.pi
if numba is not None:
    _jit = numba.njit(cache=True, error_model="numpy")
    _pjit = numba.njit(parallel=True, cache=True, error_model="numpy")
    _prange = numba.prange
else:  # the functions below are then never called
    _jit = _pjit = lambda f: f
    _prange = range


@_jit
def nb_coupler(g, t):  # type: ignore[no-untyped-def]
    a, b, c, d, u, v = g[0], g[1], g[2], g[3], g[4], g[5]
    bx, by = a * math.cos(t) - d, a * math.sin(t)
    f2 = bx * bx + by * by
    f = math.sqrt(f2)
    if f == 0.0:
        return 0.0, 0.0, False
    cg = (c * c + f2 - b * b) / (2.0 * c * f)
    if not (-1.0 <= cg <= 1.0):
        return 0.0, 0.0, False
    t4 = math.atan2(by, bx) + SIGMA * math.acos(cg)
    px, py = a * math.cos(t), a * math.sin(t)
    ex, ey = (d + c * math.cos(t4) - px) / b, (c * math.sin(t4) - py) / b
    return px + u * ex - v * ey, py + u * ey + v * ex, True


@_jit
def nb_joint(o, px, py):  # type: ignore[no-untyped-def]
    fx, fy = px - o[0], py - o[1]
    f2 = fx * fx + fy * fy
    f = math.sqrt(f2)
    r, e = o[2], o[3]
    if f == 0.0:
        return 0.0, False
    cg = (e * e + f2 - r * r) / (2.0 * e * f)
    if not (-1.0 <= cg <= 1.0):
        return 0.0, False
    return math.atan2(fy, fx) + o[4] * math.acos(cg), True


@_jit
def nb_wrap1(x):  # type: ignore[no-untyped-def]
    return x - TAU * math.ceil((x + PI) / TAU) + TAU


@_jit
def nb_solve3(m, r):  # type: ignore[no-untyped-def]
    big = np.abs(m).max()
    for k in range(3):
        p = k
        for i in range(k + 1, 3):
            if abs(m[i, k]) > abs(m[p, k]):
                p = i
        piv = abs(m[p, k])
        if not (piv > 1e-14 * big):
            return False
        for j in range(3):
            m[k, j], m[p, j] = m[p, j], m[k, j]
        r[k], r[p] = r[p], r[k]
        for i in range(k + 1, 3):
            f = m[i, k] / m[k, k]
            for j in range(k, 3):
                m[i, j] -= f * m[k, j]
            r[i] -= f * r[k]
    for k in range(2, -1, -1):
        s = 0.0
        for j in range(k + 1, 3):
            s += m[k, j] * r[j]
        r[k] = (r[k] - s) / m[k, k]
    return np.isfinite(r).all()


@_jit
def nb_fit(xs, ys):  # type: ignore[no-untyped-def]
    n = xs.size
    mx, my = xs.sum() / n, ys.sum() / n
    m, r = np.zeros((3, 3)), np.zeros(3)
    row = np.zeros(3)
    for i in range(n):
        x, y = xs[i] - mx, ys[i] - my
        row[0], row[1], row[2] = x, y, 1.0
        z = -(x * x + y * y)
        for p in range(3):
            for q in range(3):
                m[p, q] += row[p] * row[q]
            r[p] += row[p] * z
    if not nb_solve3(m, r):
        return 0.0, 0.0, 0.0, False
    cx, cy = -r[0] / 2.0, -r[1] / 2.0
    r2 = cx * cx + cy * cy - r[2]
    if not (r2 > 0.0):
        return 0.0, 0.0, 0.0, False
    rad = math.sqrt(r2)
    for _ in range(GN_STEPS):
        jtj, jtr = np.zeros((3, 3)), np.zeros(3)
        for i in range(n):
            dx, dy = xs[i] - mx - cx, ys[i] - my - cy
            di = math.hypot(dx, dy)
            if di == 0.0:
                return 0.0, 0.0, 0.0, False
            row[0], row[1], row[2] = -dx / di, -dy / di, -1.0
            res = di - rad
            for p in range(3):
                for q in range(3):
                    jtj[p, q] += row[p] * row[q]
                jtr[p] -= row[p] * res
        if not nb_solve3(jtj, jtr):
            break
        cx += jtr[0]
        cy += jtr[1]
        rad += jtr[2]
        if np.abs(jtr).max() <= 1e-15 * abs(rad):
            break
    return cx + mx, cy + my, rad, math.isfinite(rad) and rad > 0.0


@_jit
def nb_psi(g, o, mid, t, sign):  # type: ignore[no-untyped-def]
    px, py, ok = nb_coupler(g, t)
    if not ok:
        return -np.inf
    a, ok = nb_joint(o, px, py)
    if not ok:
        return -np.inf
    return sign * nb_wrap1(a - mid)


@_jit
def nb_golden(g, o, mid, lo, hi, sign):  # type: ignore[no-untyped-def]
    x1, x2 = hi - GOLD * (hi - lo), lo + GOLD * (hi - lo)
    f1, f2 = nb_psi(g, o, mid, x1, sign), nb_psi(g, o, mid, x2, sign)
    for _ in range(80):
        if f1 < f2:
            lo = x1
            x1, f1 = x2, f2
            x2 = lo + GOLD * (hi - lo)
            f2 = nb_psi(g, o, mid, x2, sign)
        else:
            hi = x2
            x2, f2 = x1, f1
            x1 = hi - GOLD * (hi - lo)
            f1 = nb_psi(g, o, mid, x1, sign)
        if hi - lo <= 1e-13:
            break
    return max(f1, f2)


@_jit
def nb_p2p(g, o, mid, gx, gy, lo, step, n):  # type: ignore[no-untyped-def]
    """Peak-to-peak over a grid whose coupler points are (gx, gy); nan: breaks."""
    vals = np.empty(n + 1)
    for i in range(n + 1):
        a, ok = nb_joint(o, gx[i], gy[i])
        if not ok:
            return np.nan
        vals[i] = nb_wrap1(a - mid)
    imax, imin = 0, 0
    for i in range(1, n + 1):
        if vals[i] > vals[imax]:
            imax = i
        if vals[i] < vals[imin]:
            imin = i
    a, b = lo + step * max(imax - 1, 0), lo + step * min(imax + 1, n)
    top = max(nb_golden(g, o, mid, a, b, 1.0), vals[imax])
    a, b = lo + step * max(imin - 1, 0), lo + step * min(imin + 1, n)
    bottom = -max(nb_golden(g, o, mid, a, b, -1.0), -vals[imin])
    return top - bottom


@_jit
def nb_evaluate(p, out):  # type: ignore[no-untyped-def]
    g = p[:6]
    a, b, c, d, tm = p[0], p[1], p[2], p[3], p[6]
    out[:] = np.nan
    out[0] = REJECTED
    srt = np.sort(p[:4])
    excess = (srt[0] + srt[3]) - (srt[1] + srt[2])
    gr = abs(excess) <= 1e-12 * (a + b + c + d) or excess <= 0.0
    if not (gr and min(a, d) == srt[0]):
        return
    c_lo = (b * b + c * c - a * a - d * d + 2.0 * a * d * math.cos(0.0)) / (2.0 * b * c)
    c_hi = (b * b + c * c - a * a - d * d + 2.0 * a * d * math.cos(PI)) / (2.0 * b * c)
    if c_lo > 1.0 or c_hi < -1.0:
        return
    mu_min, mu_max = math.acos(c_lo), math.acos(c_hi)
    # The arc.
    xs, ys = np.empty(N_DWELL), np.empty(N_DWELL)
    lo = tm - SPAN / 2.0
    for i in range(N_DWELL):
        xs[i], ys[i], ok = nb_coupler(g, lo + SPAN * i / (N_DWELL - 1))
        if not ok:
            return
    cx, cy, rad, ok = nb_fit(xs, ys)
    if not ok:
        return
    dev = 0.0
    for i in range(N_DWELL):
        dev = max(dev, abs(math.hypot(xs[i] - cx, ys[i] - cy) - rad))
    far_x, far_y, best = 0.0, 0.0, -1.0
    for i in range(N_TURN):
        x, y, ok = nb_coupler(g, TAU * i / N_TURN)
        if ok and math.hypot(x - cx, y - cy) >= best:
            far_x, far_y, best = x, y, math.hypot(x - cx, y - cy)
    # The grids' coupler points (they do not depend on the placement).
    nd, nt = 4 * N_DWELL, N_TURN + 2
    dlo, dhi = tm - SPAN / 2.0, tm + SPAN / 2.0
    dstep = (dhi - dlo) / nd
    st = TAU / N_TURN
    tlo, thi = tm - PI - st, tm + PI + st
    tstep = (thi - tlo) / nt
    dx_, dy_ = np.empty(nd + 1), np.empty(nd + 1)
    tx_, ty_ = np.empty(nt + 1), np.empty(nt + 1)
    mx_, my_ = np.empty(N_TURN), np.empty(N_TURN)
    for i in range(nd + 1):
        dx_[i], dy_[i], ok = nb_coupler(g, dlo + dstep * i)
        if not ok:
            return
    for i in range(nt + 1):
        tx_[i], ty_[i], ok = nb_coupler(g, tlo + tstep * i)
        if not ok:
            return
    for i in range(N_TURN):
        mx_[i], my_[i], ok = nb_coupler(g, tm + TAU * i / N_TURN)
        if not ok:
            return
    pmx, pmy, ok = nb_coupler(g, tm)
    if not ok:
        return
    lens_lo, lens_hi = srt[0], srt[3]
    mu4 = min(mu_min, PI - mu_max)
    o = np.empty(5)
    bo = np.empty(5)
    best_obj = np.inf
    for side in (1.0, -1.0):
        # Construct, measure, and the secant steps on q (the kernel's rule).
        ddx, ddy = far_x - cx, far_y - cy
        dist = math.hypot(ddx, ddy)
        h = dist - rad
        if not (h > 1e-9 * dist):
            continue
        ux, uy = ddx / dist, ddy / dist
        midx, midy = cx + ux * h / 2.0, cy + uy * h / 2.0
        q0 = SWING
        q1 = min(max(SWING * 1.05, 1e-3), PI - 1e-3)
        have = False
        g0 = 0.0
        s_o = np.empty(5)
        s_m = np.empty(4)
        for it in range(31):
            q = q0 if it == 0 else q1
            off = side * h / 2.0 / math.tan(q / 2.0)
            o[0], o[1] = midx - uy * off, midy + ux * off
            o[2], o[3] = rad, h / 2.0 / math.sin(q / 2.0)
            fx, fy = pmx - o[0], pmy - o[1]
            gx, gy = cx - o[0], cy - o[1]
            o[4] = 1.0 if fx * gy - fy * gx >= 0.0 else -1.0
            amid, ok = nb_joint(o, pmx, pmy)
            res = nb_p2p(g, o, amid, dx_, dy_, dlo, dstep, nd) if ok else np.nan
            sw = nb_p2p(g, o, amid, tx_, ty_, tlo, tstep, nt) if ok else np.nan
            if not (ok and math.isfinite(res) and math.isfinite(sw)):
                break
            cmin, cmax = np.inf, -np.inf
            for i in range(N_TURN):
                f2 = (mx_[i] - o[0]) ** 2 + (my_[i] - o[1]) ** 2
                cm_ = (o[2] * o[2] + o[3] * o[3] - f2) / (2.0 * o[2] * o[3])
                cmin, cmax = min(cmin, cm_), max(cmax, cm_)
            g1 = sw - SWING
            if it == 0:
                have = True
                s_o[:] = o
                s_m[0], s_m[1] = res, sw
                s_m[2] = math.acos(min(max(cmax, -1.0), 1.0))
                s_m[3] = math.acos(min(max(cmin, -1.0), 1.0))
                g0 = g1
                if abs(g0) <= SWING_TOL * 0.01:
                    break
                continue
            if abs(g1) < abs(g0):
                s_o[:] = o
                s_m[0], s_m[1] = res, sw
                s_m[2] = math.acos(min(max(cmax, -1.0), 1.0))
                s_m[3] = math.acos(min(max(cmin, -1.0), 1.0))
            if g1 == g0:
                break
            q2 = min(max(q1 - g1 * (q1 - q0) / (g1 - g0), 1e-3), PI - 1e-3)
            q0, g0, q1 = q1, g1, q2
            if abs(g0) <= SWING_TOL * 0.01:
                break
        if not have:
            continue
        ratio = max(lens_hi, s_o[2], s_o[3]) / min(lens_lo, s_o[2], s_o[3])
        mu2 = min(s_m[2], PI - s_m[3])
        miss = abs(s_m[1] - SWING)
        viol = (
            max(MIN_MU - mu4, 0.0)
            + max(MIN_MU - mu2, 0.0)
            + max(math.log(ratio / MAX_RATIO), 0.0)
            + (miss if miss > SWING_TOL else 0.0)
        )
        obj = (s_m[0] + 1000.0 * viol) * 180.0 / PI
        if obj < best_obj:
            best_obj = obj
            bo[:] = s_o
            out[0], out[1], out[2], out[3] = obj, viol, s_m[0], s_m[1]
            out[7], out[8], out[9], out[10] = bo[0], bo[1], bo[3], bo[4]
            out[14], out[15], out[16], out[17] = s_m[2], s_m[3], side, ratio
    if best_obj < np.inf:
        out[4], out[5], out[6], out[11] = cx, cy, rad, dev
        out[12], out[13] = mu_min, mu_max


@_pjit
def numba_batch(params):  # type: ignore[no-untyped-def]
    out = np.empty((params.shape[0], 18))
    for k in _prange(params.shape[0]):
        nb_evaluate(params[k], out[k])
    return out


def _agreement(ours: Array, ref: Array, n: int) -> None:
    """The rule of :func:`test_numpy_agrees`: the same rejections and feasible
    designs, 90 % of the evaluated candidates on all fields to 1e-9, every
    feasible one among them, and what differs infeasible in both."""
    ev_o, ev_r = ours[:, 0] < REJECTED, ref[:, 0] < REJECTED
    assert (ev_o != ev_r).sum() <= n // 500
    both = np.flatnonzero(ev_o & ev_r)
    assert both.size > 150
    same = np.isclose(ref[both], ours[both], rtol=1e-9, atol=1e-9).all(1)
    assert same.mean() >= 0.9, same.mean()
    feas_o, feas_r = ours[both, 1] == 0, ref[both, 1] == 0
    assert (feas_o != feas_r).sum() <= n // 500
    assert feas_o.sum() > 10 and same[feas_o & feas_r].all()
    odd = both[~same]
    assert np.all(ours[odd, 1] > 0.1) and np.all(ref[odd, 1] > 0.1)


@pytest.fixture(scope="module")
def numba_peer(request: pytest.FixtureRequest) -> Any:
    """numba_batch, compiled and checked against cyclomech (skips without numba;
    in the default run, where compiling takes 20–30 s the first time, unless
    CYCLOMECH_BENCH_NUMBA=1)."""
    if numba is None:
        pytest.skip("numba is not installed (pip install numba)")
    if not timed_run(request.config) and os.environ.get("CYCLOMECH_BENCH_NUMBA") != "1":
        pytest.skip("the numba peer compiles for 20-30 s: runs with --benchmark-enable")
    p = candidates(1_000, seed=3)
    _agreement(cyclomech_batch(p, None), numba_batch(p), len(p))
    return numba_batch


def test_numba_agrees(numba_peer: Any) -> None:
    """As :func:`test_numpy_agrees` (the fixture checks; here also seed 4)."""
    p = candidates(1_000, seed=4)
    _agreement(cyclomech_batch(p, None), numba_peer(p), len(p))


@pytest.mark.benchmark(group=GROUP)
@pytest.mark.parametrize("threads", [1, None], ids=["1-thread", "all-cores"])
def test_dwell_numba(benchmark, numba_peer: Any, threads: int | None) -> None:
    k = _k(benchmark)
    p = candidates(k)
    benchmark.extra_info["tool"] = "numba"
    where = "all cores" if threads is None else "1 thread"
    benchmark.extra_info["what"] = f"prange over {k} candidates, {where}"
    benchmark.extra_info["items"] = k
    numba.set_num_threads(threads or numba.config.NUMBA_NUM_THREADS)
    try:
        out = benchmark.pedantic(numba_peer, (p,), rounds=3, iterations=1)
    finally:
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
    assert out.shape == (k, len(FIELDS))


def test_print_ratios(request: pytest.FixtureRequest) -> None:
    """Interleaved rounds in one process, medians and ratios (print with -s). The
    numba rows need numba and a timed run (or CYCLOMECH_BENCH_NUMBA=1)."""
    timed = timed_run(request.config)
    k, rounds = (K_TIMED, 7) if timed else (K_SMOKE, 1)
    request.getfixturevalue("numpy_checked")
    p = candidates(k)
    tools: dict[str, Any] = {
        "cyclomech, 1 thread": lambda: cyclomech_batch(p, 1),
        "cyclomech, all cores": lambda: cyclomech_batch(p, None),
        "numpy": lambda: numpy_batch(p),
    }
    if numba is not None and (timed or os.environ.get("CYCLOMECH_BENCH_NUMBA") == "1"):
        request.getfixturevalue("numba_peer")  # compiled and checked
        every = numba.config.NUMBA_NUM_THREADS

        def numba_on(n: int) -> Any:
            def run() -> None:
                numba.set_num_threads(n)
                try:
                    numba_batch(p)
                finally:
                    numba.set_num_threads(every)

            return run

        tools["numba, 1 thread"] = numba_on(1)
        tools["numba, all cores"] = numba_on(every)
    med = interleaved(tools, rounds)
    print(f"\ndwell_batch, {k} candidates, {rounds} interleaved rounds (median):")
    for name, (t, cpu) in med.items():
        print(
            f"  {name:<22} {t * 1e3:9.1f} ms   {k / t:9.0f} candidates/s   CPU {cpu * 1e3:9.1f} ms"
        )
    for peer in [n for n in med if not n.startswith("cyclomech")]:
        for ref in ("cyclomech, 1 thread", "cyclomech, all cores"):
            wall, cpu = med[peer][0] / med[ref][0], med[peer][1] / med[ref][1]
            print(f"  {peer} / {ref} = {wall:.2f}x  (CPU time: {cpu:.2f}x)")
    assert all(t > 0 for t, _ in med.values())
