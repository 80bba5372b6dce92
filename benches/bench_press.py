"""The gear-lever press and the two-period law against numpy, in one run.

Groups (each prints one ratio table; ``cyclomech`` rows are the references, at one
and two threads; numpy's ufuncs run on one thread):

- ``press.design_grid`` over a (d, L, φ0) grid of designs × 360 carrier angles, against
  :func:`numpy_sweep`: the same kinematics and criteria written with numpy,
  broadcast over (designs, angles) in chunks of designs. The default grid is
  20 × 20 × 25 designs (3.6e6 positions); the issue's 100 × 100 × 100 grid
  (3.6e8 positions; numpy ~22 s per round, the whole file ~95 s with it) runs
  only with ``CYCLOMECH_BENCH_FULL=1``, in addition to the default grid. Both tools
  always run on the same grid.
- ``two_period(...).position`` on 1e6 angles, cycloidal + modified sine and
  cycloidal + cycloidal, against :func:`numpy_two_period` (``np.piecewise`` on the
  half laws' closed forms; the modified sine written from its acceleration pieces).
  Also ``position(alpha, out=buf)`` into a reused buffer (issue 20): an 8 MB fresh
  output's pages, faulted in and zeroed by the OS on first touch, cost about as
  much as the law itself on this VM.
- ``GearLeverPress.solve`` on 1e6 angles (positions of centre, pin and slider, Π,
  Π', Π''), against :func:`numpy_solve`.

Equal work. The numpy sweep computes every criterion cyclomech returns, on the same
360 samples, but stops at the grid: cyclomech refines the dead centres, the start
of the working stroke and the speed and acceleration peaks to roots of the next
derivative, numpy takes the nearest sample (a user could add that, at the price of
more passes). So the two agree to the grid's resolution h = 1°, not to rounding:
:func:`check_sweep` asserts bounds derived from h (α_p within 2h, S_n within
(J_max/ω²)·h²/2, speeds within 2h·J_max/ω, …) and equal status codes, on a small
grid in every run and on the timed grid after timing. Designs with two equally low
dead centres (mirror-symmetric ones, φ0 = π/3 here) are the exception: numpy's
argmin takes whichever of the two BDCs' samples rounding makes lower, cyclomech the
one at the smaller θ (its stated rule for ties, ``press::TIE`` in the Rust core),
and every working-stroke criterion depends on the pick; :func:`bdc_ties` checks
that they are such ties, and only S_n and J_max are compared for them (4 designs of
the check grid, none of the default grid, 614 of the full grid). cyclomech samples
each pin path (everything that does not depend on L) once per (d, φ0) and reuses
it for every L; so does :func:`numpy_sweep_pinned`, numpy at its best here (issue
37, round 2: about twice as fast as the plain broadcast :func:`numpy_sweep`, the
same bits), which the ratio table compares against, next to the plain one.
The two-period law and ``solve`` agree with cyclomech to 1e-12 m (checked).

Issue 37's row (:func:`ratio_table`): the 100 × 100 × 20 grid, one thread, interleaved
rounds, both page states, checked first::

    taskset -c 1 python benches/bench_press.py

Default test run (``--benchmark-disable`` in addopts): each benchmark once, a few
seconds in all. For timings::

    python -m pytest benches/bench_press.py --benchmark-enable -q -p no:cacheprovider
    CYCLOMECH_BENCH_FULL=1 python -m pytest benches/bench_press.py --benchmark-enable -q
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from typing import Any

import cyclomech as cm
import numpy as np
import numpy.typing as npt
import pytest
from _timing import page_states, print_states, timed_run
from numpy.testing import assert_allclose, assert_array_equal

Array = npt.NDArray[np.float64]

# --- the design grid ----------------------------------------------------------------

R, r = 0.09, 0.03
K_SP, OMEGA = 0.1, 4.0
SAMPLES = cm.press.SAMPLES  # carrier angles per turn, both tools
FULL = os.environ.get("CYCLOMECH_BENCH_FULL", "") not in ("", "0")
DEFAULT_GRID = (20, 20, 25)
FULL_GRID = (100, 100, 100)
CHECK_GRID = (6, 5, 12)
#: Designs per numpy chunk: 8192 × 360 doubles = 24 MB per temporary. Chunks of 64 to
#: 1024 designs (arrays under numpy's 4 MB huge-page threshold) ran 1.5-2x slower.
CHUNK = 8192


def design_axes(shape: tuple[int, int, int]) -> tuple[Array, Array, Array]:
    """d in [0, 0.04] m, L in [0.3, 0.5] m, φ0 in [0, 2π/3) rad (one period in φ0)."""
    nd, nl, nphi = shape
    return (
        np.linspace(0.0, 0.04, nd),
        np.linspace(0.3, 0.5, nl),
        np.linspace(0.0, 2 * np.pi / 3, nphi, endpoint=False),
    )


def cm_sweep(axes: tuple[Array, Array, Array], n_threads: int | None) -> cm.press.PressGrid:
    d, length, phi0 = axes
    return cm.press.design_grid(
        R=R,
        r=r,
        d=d,
        L=length,
        phi0=phi0,
        k_Sp=K_SP,
        omega=OMEGA,
        n_threads=n_threads,
        progress=False,
    )


# --- numpy reference: kinematics ------------------------------------------------------


def numpy_kinematics(
    ct: Array, st: Array, cb: Array, sb: Array, d: Any, length: Any, offset: float = 0.0
) -> tuple[Array, ...]:
    """Planet centre, pin, and slider height y with dy/dθ, d²y/dθ², from cos/sin of
    the carrier angle θ and of the planet angle β = −kθ + i(φ0 − π/2).

    P = (R − r)e^{iθ} + d·e^{iβ}, k = (R − r)/r; y = P_y − √(L² − (P_x − offset)²).
    Returns (cx, cy, px, py, w2, y, dy, ddy); w2 = L² − (P_x − offset)² > 0 where
    the rod reaches the guide (y is NaN elsewhere).
    """
    a, k = R - r, R / r - 1.0
    cx, cy = a * ct, a * st
    dcb, dsb = d * cb, d * sb
    px, py = cx + dcb, cy + dsb
    px1, py1 = k * dsb - cy, cx - k * dcb
    px2, py2 = -cx - (k * k) * dcb, -cy - (k * k) * dsb
    u = px - offset if offset else px
    w2 = length * length - u * u
    with np.errstate(invalid="ignore", divide="ignore"):
        w = np.sqrt(w2)
        g = u * px1 / w
        y = py - w
        dy = py1 + g
        ddy = py2 + (px1 * px1 + u * px2 + g * g) / w
    return cx, cy, px, py, w2, y, dy, ddy


def _numpy_criteria_chunk(
    d: Array, length: Array, phi0: Array, table: tuple[Array, ...], out: dict[str, Array]
) -> None:
    """Criteria of a chunk of designs (written into ``out``'s rows), on the grid."""
    ct, st, cbk, sbk = table
    i = round(R / r)
    beta0 = i * (phi0 - np.pi / 2)
    c0, s0 = np.cos(beta0)[:, None], np.sin(beta0)[:, None]
    # cos/sin of β = −kθ + β0 by the addition theorem: no trig on the (K, M) grid.
    cb = cbk * c0 - sbk * s0
    sb = sbk * c0 + cbk * s0
    *_, w2, y, dy, ddy = numpy_kinematics(ct, st, cb, sb, d[:, None], length[:, None])
    _numpy_criteria_rows(w2, y, dy, ddy, out)


def _numpy_criteria_rows(w2: Array, y: Array, dy: Array, ddy: Array, out: dict[str, Array]) -> None:
    """Criteria from the sampled kinematics (designs, angles), into ``out``'s rows."""
    n, m = y.shape
    h = 2 * np.pi / m
    rows = np.arange(n)
    reach = (w2 > 0).all(axis=1)
    # BDC: the lowest sample; S_n from the sample extremes.
    jb = np.argmin(y, axis=1)
    y_b = y[rows, jb]
    s_n = y.max(axis=1) - y_b
    s_p = K_SP * s_n
    # Walk back in time from BDC: column q of `back` is the sample q steps before it.
    back = (jb[:, None] - np.arange(m)) % m
    s = y[rows[:, None], back] - y_b[:, None]
    v = -dy[rows[:, None], back]  # Π' = −dy/dθ
    # First contact, coming down from TDC (column n_t): the sample with S ≥ S_p just
    # before the last one below S_p met going back from BDC to TDC.
    q = np.arange(m)
    n_t = np.argmax(s, axis=1)
    below = (s < s_p[:, None]) & (q < n_t[:, None])
    last = m - 1 - np.argmax(below[:, ::-1], axis=1)
    n_p = last + 1
    # Re-contacts: back above S_p after that (by more than 1e-9 of the stroke).
    inside = np.where(q < last[:, None], s, -np.inf)
    recontacts = (inside > (s_p + 1e-9 * s_n)[:, None]).any(axis=1)
    alpha_p = n_p * h
    v_np = v[rows, n_p]
    before = np.arange(m) < n_p[:, None]
    v_max = np.maximum(np.where(before, v, -np.inf).max(axis=1), v_np)
    reverses = (np.where(before[:, 1:], v[:, 1:], np.inf) < -1e-12 * s_n[:, None]).any(axis=1)
    j_max = np.abs(ddy).max(axis=1)
    v_cp = s_p / alpha_p
    cols = {
        "S_n": s_n,
        "S_p": s_p,
        "alpha_p": alpha_p,
        "V_np": v_np * OMEGA,
        "V_cp": v_cp * OMEGA,
        "V_pmax": v_max * OMEGA,
        "J_max": j_max * OMEGA**2,
        "torque_arm": v_max,
        "k_Sp": s_p / s_n,
        "k_Vp": v_np / v_cp,
        "k_Vmax": v_max / v_cp,
        "k_M": v_max / (0.5 * s_n),
        "k_J": j_max / (0.5 * s_n),
        "theta_bdc": jb * h,
    }
    for name, col in cols.items():
        out[name][:] = np.where(reach, col, np.nan)
    out["status"][:] = np.where(reach, np.where(recontacts, 4, np.where(reverses, 2, 0)), 1)


def _flat_designs(axes: tuple[Array, Array, Array]) -> tuple[Array, Array, Array]:
    d, length, phi0 = (g.ravel() for g in np.meshgrid(*axes, indexing="ij"))
    return d, length, phi0


def numpy_sweep_pinned(
    axes: tuple[Array, Array, Array], samples: int = SAMPLES, chunk: int = CHUNK
) -> dict[str, Array]:
    """:func:`numpy_sweep` exploiting the grid's structure as cyclomech does: the pin
    path's rows that do not depend on the rod length (u², u·P_x', P_x'² + u·P_x'',
    P_y, P_y', P_y'') computed once per (d, φ0) and broadcast over L, so that each
    (design, angle) costs the rod's few operations (√, two divisions, five adds and
    multiplies) instead of the whole kinematics. The same values bit for bit as
    :func:`numpy_sweep` (the same operations in the same order); chunks of whole d
    values, about ``chunk`` designs each."""
    d_ax, l_ax, phi_ax = axes
    nd, nl, nphi = d_ax.size, l_ax.size, phi_ax.size
    th = 2 * np.pi * np.arange(samples) / samples
    a, k = R - r, R / r - 1.0
    ct, st, cbk, sbk = np.cos(th), np.sin(th), np.cos(-k * th), np.sin(-k * th)
    beta0 = round(R / r) * (phi_ax - np.pi / 2)
    c0, s0 = np.cos(beta0)[:, None], np.sin(beta0)[:, None]
    cb = cbk * c0 - sbk * s0  # (φ0, angles)
    sb = sbk * c0 + cbk * s0
    cx, cy = a * ct, a * st
    length = l_ax[None, :, None, None]
    n = nd * nl * nphi
    out = {name: np.empty(n) for name in cm.press.CRITERIA}
    out["status"] = np.empty(n, dtype=np.uint8)
    step = max(1, chunk // (nl * nphi))
    for start in range(0, nd, step):
        dd = d_ax[start : start + step, None, None]  # (d, 1, 1)
        dcb, dsb = dd * cb, dd * sb  # (d, φ0, angles)
        u = cx + dcb  # P_x − offset, offset 0
        px1, py1 = k * dsb - cy, cx - k * dcb
        px2, py2 = -cx - (k * k) * dcb, -cy - (k * k) * dsb
        u2, upx1, hh, py = u * u, u * px1, px1 * px1 + u * px2, cy + dsb
        pin = [v[:, None] for v in (u2, upx1, hh, py, py1, py2)]  # (d, 1, φ0, angles)
        with np.errstate(invalid="ignore", divide="ignore"):
            w2 = length * length - pin[0]
            w = np.sqrt(w2)
            g = pin[1] / w
            y = pin[3] - w
            dy = pin[4] + g
            ddy = pin[5] + (pin[2] + g * g) / w
        lo, hi = start * nl * nphi, min(start + step, nd) * nl * nphi
        part = {name: col[lo:hi] for name, col in out.items()}
        _numpy_criteria_rows(*(v.reshape(hi - lo, samples) for v in (w2, y, dy, ddy)), part)
    return out


def numpy_sweep(
    axes: tuple[Array, Array, Array], samples: int = SAMPLES, chunk: int = CHUNK
) -> dict[str, Array]:
    """Criteria of every design of the (d, L, φ0) grid, flat in C order, with numpy.

    The carrier-angle tables (cos/sin of θ_j = 2πj/M and of −kθ_j) are computed
    once; each chunk of designs is broadcast against them as (designs, angles).
    """
    d, length, phi0 = _flat_designs(axes)
    th = 2 * np.pi * np.arange(samples) / samples
    k = R / r - 1.0
    table = (np.cos(th), np.sin(th), np.cos(-k * th), np.sin(-k * th))
    n = d.size
    out = {name: np.empty(n) for name in cm.press.CRITERIA}
    out["status"] = np.empty(n, dtype=np.uint8)
    for start in range(0, n, chunk):
        sl = slice(start, start + chunk)
        part = {name: col[sl] for name, col in out.items()}
        _numpy_criteria_chunk(d[sl], length[sl], phi0[sl], table, part)
    return out


def _heights(d: Array, length: Array, phi0: Array, samples: int) -> Array:
    """Slider heights y (designs, samples) on the carrier-angle grid."""
    th = 2 * np.pi * np.arange(samples) / samples
    beta = round(R / r) * (phi0[:, None] - np.pi / 2) - (R / r - 1.0) * th
    return numpy_kinematics(
        np.cos(th), np.sin(th), np.cos(beta), np.sin(beta), d[:, None], length[:, None]
    )[5]


def bdc_ties(
    ref: dict[str, Array], sw: cm.press.PressGrid, axes: tuple[Array, Array, Array], samples: int
) -> npt.NDArray[np.intp]:
    """Designs whose BDC the two tools place at different lowest samples, each checked
    to be a tie: the lowest sample next to cyclomech's θ_B is as low as numpy's, to
    1e-12 m. With offset 0 a design is mirror-symmetric when φ0 is a multiple of
    π/3; at odd multiples the pin points inwards at θ = −π/2 and, once d is large
    enough, the slider has two equally low dead centres: numpy's argmin lets rounding
    pick one, cyclomech takes the one at the smaller θ. Returns their flat indices."""
    h = 2 * np.pi / samples
    diff = np.abs(ref["theta_bdc"] - sw["theta_bdc"].ravel())
    far = np.flatnonzero(np.minimum(diff, 2 * np.pi - diff) > 1.5 * h)
    if far.size == 0:
        return far
    d, length, phi0 = (v[far] for v in _flat_designs(axes))
    y = _heights(d, length, phi0, samples)
    rows = np.arange(far.size)
    y_b = y.min(axis=1)
    near = np.round(sw["theta_bdc"].ravel()[far] / h).astype(np.int64)[:, None] + [-1, 0, 1]
    y_cm = y[rows[:, None], near % samples].min(axis=1)
    assert (y_cm - y_b <= 1e-12).all(), (
        f"cyclomech's BDC of flat designs {far[y_cm - y_b > 1e-12].tolist()} is not the "
        "lowest position sampled"
    )
    return far


def check_sweep(
    ref: dict[str, Array],
    sw: cm.press.PressGrid,
    axes: tuple[Array, Array, Array],
    samples: int = SAMPLES,
) -> int:
    """numpy's grid criteria against cyclomech's refined ones, to the grid's resolution;
    returns the number of designs with two equally low BDCs (see :func:`bdc_ties`),
    for which only S_n and J_max (independent of the pick) are compared.

    With h the sample step and a = J_max/ω² (the largest |Π''| [m/rad²]): the
    sampled extremes of y miss the true ones by at most a·h²/8 each, so S_n within
    a·h²/2; BDC and the start of the working stroke each within h, so α_p within
    2h, and Π' there within 2h·a; the sampled |Π''| peak misses the true one by a
    second-order amount (rtol h is generous). Ratios carry their parts' bounds.
    """
    h = 2 * np.pi / samples
    got = {name: sw[name].ravel() for name in cm.press.CRITERIA}
    status = sw.status.ravel()
    ties = bdc_ties(ref, sw, axes, samples)
    same = np.ones(status.size, dtype=bool)
    same[ties] = False
    assert_array_equal(ref["status"][same], status[same])
    ok = ref["status"] != 1
    for name in cm.press.CRITERIA:
        assert np.isnan(ref[name][~ok]).all() and np.isnan(got[name][~ok]).all(), name
    g = {name: col[ok] for name, col in got.items()}
    e = {name: col[ok] for name, col in ref.items()}
    same = same[ok]
    acc = g["J_max"] / OMEGA**2  # a [m/rad²]
    tol = {
        "S_n": acc * h * h / 2,
        "S_p": K_SP * acc * h * h / 2,
        "alpha_p": np.full_like(acc, 2 * h),
        "V_np": 2 * h * acc * OMEGA,
        "V_pmax": 2 * h * acc * OMEGA,
        "torque_arm": 2 * h * acc,
        "J_max": h * g["J_max"],
        "theta_bdc": np.full_like(acc, h),
        "k_Sp": np.full_like(acc, 1e-12),
    }
    # V_cp = S_p·ω/α_p.
    tol["V_cp"] = g["V_cp"] * (
        tol["S_p"] / g["S_p"] + tol["alpha_p"] / np.maximum(g["alpha_p"] - 2 * h, h)
    )

    def ratio(num: str, den: str, scale: float) -> Array:
        # |Δ(a/b)| ≤ (|Δa| + |a/b|·|Δb|)/(|b| − |Δb|)
        a_, b_ = g[num] * scale, g[den]
        return (tol[num] * scale + np.abs(a_ / b_) * tol[den]) / (np.abs(b_) - tol[den])

    tol["k_Vp"] = ratio("V_np", "V_cp", 1.0)
    tol["k_Vmax"] = ratio("V_pmax", "V_cp", 1.0)
    tol["k_M"] = ratio("torque_arm", "S_n", 2.0)
    tol["k_J"] = ratio("J_max", "S_n", 2.0 / OMEGA**2)
    for name in cm.press.CRITERIA:
        diff = np.abs(e[name] - g[name])
        if name == "theta_bdc":
            diff = np.minimum(diff, 2 * np.pi - diff)
        bad = ~(diff <= tol[name] + 1e-15)
        if name not in ("S_n", "J_max"):
            bad &= same
        bad = np.flatnonzero(bad)
        assert bad.size == 0, (
            f"{name}: numpy {e[name][bad[0]]!r} vs cyclomech {g[name][bad[0]]!r} "
            f"(|diff| {diff[bad[0]]:.3g} > grid tolerance {tol[name][bad[0]]:.3g}) "
            f"at flat design {np.flatnonzero(ok)[bad[0]]}; {bad.size} designs out"
        )
    return int(ties.size)


def test_numpy_sweep_agrees() -> None:
    """The comparison is of the same work: checked on a small grid in every run."""
    axes = design_axes(CHECK_GRID)
    ref = numpy_sweep(axes, chunk=64)  # several chunks, one partial
    sw = cm_sweep(axes, n_threads=1)
    assert sw.ok.sum() > 0.9 * sw.ok.size  # the check is not vacuous
    check_sweep(ref, sw, axes)
    # The pin-path formulation: the same operations, so the same bits; chunks of
    # 4 d values (240 designs), the last one partial.
    pinned = numpy_sweep_pinned(axes, chunk=4 * CHECK_GRID[1] * CHECK_GRID[2])
    for name, col in ref.items():
        assert_array_equal(pinned[name], col, err_msg=name)


# --- press.design_grid benchmarks -----------------------------------------------------------


def _label(benchmark, tool: str, what: str) -> None:
    benchmark.extra_info["tool"] = tool
    benchmark.extra_info["what"] = what


def _group(shape: tuple[int, int, int]) -> str:
    n = math.prod(shape)
    return (
        f"press.design_grid: {' x '.join(map(str, shape))} designs (d, L, phi0) x {SAMPLES} "
        f"angles = {n * SAMPLES:.1e} positions"
    )


GROUP_SWEEP = _group(DEFAULT_GRID)
GROUP_SWEEP_FULL = _group(FULL_GRID)
full_only = pytest.mark.skipif(not FULL, reason="the 3.6e8-position grid: CYCLOMECH_BENCH_FULL=1")


@pytest.fixture(scope="module")
def grid() -> tuple[Array, Array, Array]:
    return design_axes(DEFAULT_GRID)


@pytest.fixture(scope="module")
def full_grid() -> tuple[Array, Array, Array]:
    return design_axes(FULL_GRID)


@pytest.mark.benchmark(group=GROUP_SWEEP)
@pytest.mark.parametrize("threads", [2, 1])
def test_sweep_cyclomech(benchmark, grid, threads) -> None:
    _label(benchmark, "cyclomech", f"press.design_grid (criteria, refined), n_threads={threads}")
    sw = benchmark(cm_sweep, grid, threads)
    assert sw.shape == DEFAULT_GRID and sw.ok.mean() > 0.9


@pytest.mark.benchmark(group=GROUP_SWEEP)
def test_sweep_numpy(benchmark, grid) -> None:
    _label(benchmark, "numpy", f"broadcast (designs, angles) in chunks of {CHUNK}, on the grid")
    ref = benchmark(numpy_sweep, grid)
    check_sweep(ref, cm_sweep(grid, None), grid)


@pytest.mark.benchmark(group=GROUP_SWEEP)
def test_sweep_numpy_pinned(benchmark, grid) -> None:
    _label(benchmark, "numpy", "pin path once per (d, phi0), broadcast over L, on the grid")
    ref = benchmark(numpy_sweep_pinned, grid)
    check_sweep(ref, cm_sweep(grid, None), grid)


@full_only
@pytest.mark.benchmark(group=GROUP_SWEEP_FULL)
@pytest.mark.parametrize("threads", [2, 1])
def test_sweep_full_cyclomech(benchmark, full_grid, threads) -> None:
    _label(benchmark, "cyclomech", f"press.design_grid (criteria, refined), n_threads={threads}")
    sw = benchmark.pedantic(cm_sweep, args=(full_grid, threads), rounds=3, iterations=1)
    assert sw.shape == FULL_GRID and sw.ok.mean() > 0.9


@full_only
@pytest.mark.benchmark(group=GROUP_SWEEP_FULL)
def test_sweep_full_numpy(benchmark, full_grid) -> None:
    _label(benchmark, "numpy", f"broadcast (designs, angles) in chunks of {CHUNK}, on the grid")
    ref = benchmark.pedantic(numpy_sweep, args=(full_grid,), rounds=3, iterations=1)
    check_sweep(ref, cm_sweep(full_grid, None), full_grid)


#: Issue 37's grid: 100 × 100 × 20 designs (d, L, φ0) × 360 angles (7.2e7 positions).
ISSUE37_GRID = (100, 100, 20)


def ratio_table(rounds: int = 5, shape: tuple[int, int, int] = ISSUE37_GRID) -> None:
    """Issue 37's measurement: one thread (run under ``taskset -c 1``), interleaved
    rounds, both page states, the results checked against each other first
    (:func:`check_sweep` on the timed grid, and the two numpy formulations equal bit
    for bit). Prints µs per design and numpy / cyclomech for both numpy peers: the
    one that reuses each pin path across rod lengths (:func:`numpy_sweep_pinned`,
    numpy at its best here) and the plain broadcast (:func:`numpy_sweep`, the
    peer of the earlier rounds)."""
    axes = design_axes(shape)
    ref = numpy_sweep_pinned(axes)
    plain = numpy_sweep(axes)
    for name, col in ref.items():
        assert_array_equal(col, plain[name], err_msg=name)
    check_sweep(ref, cm_sweep(axes, 1), axes)
    tools = {
        "cyclomech press.design_grid, n_threads=1": lambda: cm_sweep(axes, 1),
        "numpy, pin path once per (d, phi0)": lambda: numpy_sweep_pinned(axes),
        f"numpy, broadcast in chunks of {CHUNK} designs": lambda: numpy_sweep(axes),
    }
    n = math.prod(shape)
    names = list(tools)
    states = page_states(tools, rounds)
    print_states(
        f"press sweep {' x '.join(map(str, shape))} designs x {SAMPLES} angles",
        states,
        n * 1e-6,
        "us/design",
        {names[0]: names[1]},
    )
    for state, t in states.items():
        (w, c), (wr, cr) = t[names[0]], t[names[2]]
        print(f"  {state} pages: {names[2]} / {names[0]}: wall {wr / w:.3f}x  cpu {cr / c:.3f}x")


def test_ratio_table(request: pytest.FixtureRequest) -> None:
    """The issue-37 table on the default grid in timed runs (the issue's grid:
    ``taskset -c 1 python benches/bench_press.py``)."""
    if not timed_run(request.config):
        pytest.skip("timed runs only (--benchmark-enable)")
    ratio_table(3, DEFAULT_GRID)


# --- two-period law: numpy reference --------------------------------------------------

N_LAW = 1_000_000
STROKE, ANGLE = 0.2, math.pi
#: Amplitude of the modified-sine rise's acceleration, from Z(1/2) = 1/2: Ca = 4π²/(π + 4).
MS_A = 4 * np.pi**2 / (np.pi + 4)
MS_W = 4 * np.pi / 3  # the middle sine: period 3/2 over the rise's middle 3/4
MS_V1 = MS_A / (4 * np.pi)  # Z' at x = 1/8, the end of the first ramp
MS_Z1 = MS_V1 * (1 / 8 - 1 / (4 * np.pi))  # Z at x = 1/8


def half_cycloidal(j: Array) -> Array:
    """Cycloidal half law Z = j − sin(πj)/π."""
    return j - np.sin(np.pi * j) / np.pi


def half_modified_sine(j: Array) -> Array:
    """Modified-sine half law Z_h(j) = 2·Z(j/2), Z the rise built from its acceleration:
    A·sin(4πx) on x ≤ 1/8, then A·cos(4π/3·(x − 1/8)), integrated twice."""

    def ramp(j: Array) -> Array:  # 0 ≤ j ≤ 1/4
        x = 0.5 * j
        return 2 * MS_V1 * (x - np.sin(4 * np.pi * x) / (4 * np.pi))

    def middle(j: Array) -> Array:  # 1/4 < j ≤ 1
        t = 0.5 * j - 0.125
        return 2 * (MS_Z1 + MS_V1 * t + MS_A / MS_W**2 * (1 - np.cos(MS_W * t)))

    return np.piecewise(j, [j <= 0.25], [ramp, middle])


HALF_LAWS: dict[str, Callable[[Array], Array]] = {
    "cycloidal": half_cycloidal,
    "modified_sine": half_modified_sine,
}


def numpy_two_period(law: cm.motion.TwoPeriodLaw, alpha: Array) -> Array:
    """Π(α): Π1·Z1(α/α1) on α ≤ α1, Π2 − (Π2 − Π1)·Z2((α2 − α)/(α2 − α1)) after."""
    z1, z2 = HALF_LAWS[law.law1.name], HALF_LAWS[law.law2.name]
    p1, a1, p2, a2 = law.stroke1, law.angle1, law.stroke, law.angle
    return np.piecewise(
        alpha,
        [alpha <= a1],
        [
            lambda a: p1 * z1(a / a1),
            lambda a: p2 - (p2 - p1) * z2(np.maximum((a2 - a) / (a2 - a1), 0.0)),
        ],
    )


LAWS = {
    "cycloidal+modified_sine": ("cycloidal", "modified_sine"),
    "cycloidal+cycloidal": ("cycloidal", "cycloidal"),
}


@pytest.fixture(scope="module", params=list(LAWS))
def two_period_law(request) -> tuple[str, cm.motion.TwoPeriodLaw, Array]:
    law = cm.motion.two_period(STROKE, ANGLE, *LAWS[request.param], asymmetry=2.0)
    alpha = np.linspace(0.0, ANGLE, N_LAW)
    # The same law, checked once: the numpy reference to 1e-12 m, and the closed-form
    # modified sine's peaks against cyclomech's (Z_h'max = Cv, Z_h''max = Ca/2).
    assert_allclose(numpy_two_period(law, alpha), law.position(alpha), rtol=0, atol=1e-12)
    ms = cm.motion.law("modified_sine")
    assert_allclose([MS_A / np.pi, MS_A / 2], [ms.dz_max, ms.ddz_max], rtol=1e-12)
    return request.param, law, alpha


def _law_group(name: str) -> str:
    return f"two_period({name}).position, {N_LAW:.0e} angles"


@pytest.mark.parametrize("threads", [2, 1])
def test_two_period_cyclomech(benchmark, two_period_law, threads) -> None:
    name, law, alpha = two_period_law
    benchmark.group = _law_group(name)
    _label(benchmark, "cyclomech", f"TwoPeriodLaw.position, n_threads={threads}")
    benchmark(law.position, alpha, n_threads=threads)


@pytest.mark.parametrize("threads", [1])
def test_two_period_cyclomech_out(benchmark, two_period_law, threads) -> None:
    """The same into a reused buffer (issue 20, no fresh-page tax): bit for bit."""
    name, law, alpha = two_period_law
    benchmark.group = _law_group(name)
    _label(benchmark, "cyclomech", f"TwoPeriodLaw.position(out=buf), n_threads={threads}")
    buf = np.empty_like(alpha)
    benchmark(law.position, alpha, n_threads=threads, out=buf)
    assert_array_equal(buf, law.position(alpha))


def test_two_period_numpy(benchmark, two_period_law) -> None:
    name, law, alpha = two_period_law
    benchmark.group = _law_group(name)
    _label(benchmark, "numpy", "np.piecewise over the periods and the law's pieces")
    benchmark(numpy_two_period, law, alpha)


# --- GearLeverPress.solve -------------------------------------------------------------

N_SOLVE = 1_000_000
GROUP_SOLVE = f"GearLeverPress.solve, {N_SOLVE:.0e} angles"
PRESS = {"R": R, "r": r, "d": 0.025, "L": 0.3, "phi0": 0.3}


def numpy_bdc(p: cm.press.GearLeverPress, samples: int = 4 * SAMPLES) -> tuple[float, float]:
    """(θ_B, y_B): the lowest of ``samples`` carrier angles, then Newton on dy/dθ."""
    k, beta0 = p.ratio - 1.0, p.ratio * (p.phi0 - np.pi / 2)

    def kin(th: Any) -> tuple[Array, ...]:
        b = beta0 - k * th
        return numpy_kinematics(np.cos(th), np.sin(th), np.cos(b), np.sin(b), p.d, p.L, p.offset)

    th = 2 * np.pi * np.arange(samples) / samples
    t = float(th[np.argmin(kin(th)[5])])
    for _ in range(6):
        *_, dy, ddy = kin(np.array(t))
        t -= float(dy / ddy)
    return t % (2 * np.pi), float(kin(np.array(t))[5])


def numpy_solve(p: cm.press.GearLeverPress, alpha: Array) -> dict[str, npt.NDArray[Any]]:
    """Everything ``GearLeverPress.solve`` returns, at θ = θ_B − α."""
    th_b, y_b = numpy_bdc(p)
    th = th_b - alpha
    b = p.ratio * (p.phi0 - np.pi / 2) - (p.ratio - 1.0) * th
    cx, cy, px, py, w2, y, dy, ddy = numpy_kinematics(
        np.cos(th), np.sin(th), np.cos(b), np.sin(b), p.d, p.L, p.offset
    )
    slider = np.empty((alpha.size, 2))
    slider[:, 0] = p.offset
    slider[:, 1] = y
    return {
        "s": y - y_b,
        "ds": -dy,
        "dds": ddy,
        "centre": np.stack([cx, cy], axis=1),
        "pin": np.stack([px, py], axis=1),
        "slider": slider,
        "ok": w2 > 0,
    }


@pytest.fixture(scope="module")
def press() -> tuple[cm.press.GearLeverPress, Array]:
    p = cm.press.GearLeverPress(**PRESS)
    alpha = np.linspace(0.0, 2 * np.pi, N_SOLVE)
    kin, ref = p.solve(alpha), numpy_solve(p, alpha)
    assert kin.ok.all() and ref["ok"].all()
    for name in ("s", "ds", "dds", "centre", "pin", "slider"):
        assert_allclose(ref[name], getattr(kin, name), rtol=0, atol=1e-12, err_msg=name)
    return p, alpha


@pytest.mark.benchmark(group=GROUP_SOLVE)
@pytest.mark.parametrize("threads", [2, 1])
def test_solve_cyclomech(benchmark, press, threads) -> None:
    _label(benchmark, "cyclomech", f"GearLeverPress.solve, n_threads={threads}")
    p, alpha = press
    benchmark(p.solve, alpha, n_threads=threads)


@pytest.mark.benchmark(group=GROUP_SOLVE)
def test_solve_numpy(benchmark, press) -> None:
    _label(benchmark, "numpy", "BDC by Newton, then the kinematics broadcast over the angles")
    p, alpha = press
    benchmark(numpy_solve, p, alpha)


if __name__ == "__main__":
    import sys

    ratio_table(int(sys.argv[1]) if len(sys.argv) > 1 else 5)
