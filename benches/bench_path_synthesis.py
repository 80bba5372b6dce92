"""Path generation: cyclomech's optimiser against pylinkage's on the same target,
and the raw candidate throughput against numpy.

**Same target.** Six points on the coupler curve of a known crank-rocker (ground
pivots A = (0, 0), D = (4, 0), crank 1, coupler 3.5, rocker 2.5, coupler point at
1.389 from B, 0.528 rad from B→C), taken from pylinkage's own simulation of it
(frames 15, 31, …, 95 of 96: crank angles 60°, 120°, …, 360°) and reproduced by
``cm.Linkage.solve`` to 1e-12 (:func:`test_targets_agree`). No timing: each
tool's error is the RMS over the targets of the distance to the coupler curve.

* **pylinkage** 1.3.0, ``pylinkage.optimization.differential_evolution_optimization``
  with a ``kinematic_minimization`` fitness (the RMS of each target's distance to
  the nearest of the coupler point's 96 frames a turn), pylinkage's own defaults
  (scipy DE, best1bin, popsize 15, tol 0.01, scipy's polish) but ``maxiter``
  ``PL_ITERS``, a seed, and bounds like cyclomech's (links 0.05–4 × the targets'
  extent S, the coupler point's distance 0–3S and angle ±π). In its favour: it
  searches only the five lengths and angles of a four-bar whose ground pivots are
  given at the true ones (cyclomech searches all ten dimensions, pivots and
  ground angle included), and its curve's frames fall exactly on the targets'
  crank angles at the true linkage.
* **cyclomech** ``cm.synthesis.path_generation`` (scipy DE, vectorized: a
  generation is one Rust call; then least squares), with the smallest
  ``maxiter`` of (10, 20, 40, 80, 160, 320, 1000) whose result is at least as
  good as pylinkage's (its reported error is the distance to the curve refined to
  1e-9 rad; cyclomech's runs reach ~1e-8 m once in the basin).

The ratio is pylinkage's time over cyclomech's, to the same error or better.

**Throughput.** ``cm.synthesis.path_evaluate`` on K = 10⁶ timed candidates (N = 6
targets, constraints checked in the same pass) against the best numpy a user
would write: every candidate × target at once, broadcast over (K, N), the same
closed forms (:func:`numpy_timed`; it agrees with cyclomech to 1e-9,
:func:`test_numpy_agrees`). Candidates per second.

Default test run (``--benchmark-disable``): each row once on small budgets.
For timings and the ratio tables::

    python -m pytest benches/bench_path_synthesis.py --benchmark-enable -q -p no:cacheprovider
"""

from __future__ import annotations

import functools
import math
import time
import warnings
from typing import Any

import cyclomech as cm
import numpy as np
import numpy.typing as npt
import pytest

Array = npt.NDArray[np.float64]
GROUP_OPT = "synthesis: path generation, time to pylinkage's error"
GROUP_RAW = "synthesis: path evaluation, candidates per second"
FRAMES = (15, 31, 47, 63, 79, 95)  # of 96 a turn: crank at 60°, 120°, …, 360°
CRANK, COUPLER, ROCKER, GROUND = 1.0, 3.5, 2.5, 4.0
PL_ITERS = 100  # pylinkage's generations when timed
K_RAW = 1_000_000


def _pylinkage() -> Any:
    # The peer (the bench extra): without it the targets, taken from its own
    # simulation, are not there, and every test here is skipped.
    pytest.importorskip("pylinkage", minversion="1.0")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        import pylinkage as pl
        from pylinkage.dyads import FixedDyad
    return pl, FixedDyad


@functools.cache
def pylinkage_problem() -> tuple[Any, Array, tuple[Any, ...], list[float]]:
    """The known four-bar in pylinkage, the targets from its own simulation, its
    initial coordinates and true constraints."""
    pl, fixed = _pylinkage()
    a, d = pl.Ground(0, 0, name="A"), pl.Ground(GROUND, 0, name="D")
    crank = pl.Crank(anchor=a, radius=CRANK, angular_velocity=2 * math.pi / 96, name="B")
    c = pl.RRRDyad(anchor1=crank.output, anchor2=d, distance1=COUPLER, distance2=ROCKER, name="C")
    p = fixed(
        anchor1=crank.output,
        anchor2=c,
        distance=1.3892443989449803,
        angle=0.5280744484263599,
        name="P",
    )
    link = pl.Linkage([a, d, crank, c, p])
    init = tuple(link.get_coords())
    truth = list(link.get_constraints())
    loci = list(link.step(iterations=96))
    targets = np.array([loci[k][4] for k in FRAMES], dtype=float)
    link.set_coords(init)
    return link, targets, init, truth


def targets() -> Array:
    return pylinkage_problem()[1]


def pylinkage_run(maxiter: int, seed: int = 1) -> float:
    """pylinkage's optimiser on the targets: its best error [m]."""
    pytest.importorskip("pylinkage", minversion="1.0")
    from pylinkage.optimization import differential_evolution_optimization
    from pylinkage.optimization.utils import kinematic_minimization

    link, t, init, _ = pylinkage_problem()

    @kinematic_minimization
    def fitness(loci: Any, **_: Any) -> float:
        pts = np.array([f[4] for f in loci], dtype=float)
        d = np.hypot(*(pts[:, None, :] - t[None]).transpose(2, 0, 1)).min(0)
        return float(np.sqrt(np.mean(d**2)))

    s = float(np.ptp(t, axis=0).max())
    lo = [0.05 * s, 0.1 * s, 0.1 * s, 0.0, -math.pi]
    hi = [2 * s, 4 * s, 4 * s, 3 * s, math.pi]
    link.set_coords(init)
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        ens = differential_evolution_optimization(
            fitness,
            link,
            bounds=(lo, hi),
            order_relation=min,
            maxiter=maxiter,
            seed=seed,
            verbose=False,
        )
    return float(ens[0].score)


def cyclomech_run(maxiter: int, n_threads: int | None = None, seed: int = 1) -> float:
    best = cm.synthesis.path_generation(targets(), seed=seed, maxiter=maxiter, n_threads=n_threads)
    return best[0].rms


@functools.cache
def pylinkage_error(maxiter: int) -> float:
    return pylinkage_run(maxiter)


@functools.cache
def cyclomech_budget(error: float) -> int:
    """The smallest maxiter of the ladder whose run reaches ``error`` or better."""
    for it in (10, 20, 40, 80, 160, 320, 1000):
        if cyclomech_run(it) <= error:
            return it
    raise AssertionError(f"cyclomech did not reach pylinkage's error {error:g}")


def test_targets_agree() -> None:
    """The targets are on cyclomech's solve of the same linkage (mode −1: the
    branch pylinkage's simulation follows)."""
    lk = cm.synthesis.four_bar_linkage(
        CRANK, COUPLER, ROCKER, GROUND, coupler_point=(1.2, 0.7), mode=-1
    )
    angles = np.radians([(k + 1) * 3.75 for k in FRAMES])
    np.testing.assert_allclose(lk.solve(angles)["P"], targets(), atol=1e-12)


# ---------------------------------------------------------------- throughput
def random_rows(k: int, seed: int = 0) -> Array:
    rng = np.random.default_rng(seed)
    s = float(np.ptp(targets(), axis=0).max())
    cols = [
        rng.uniform(-3 * s, 3 * s, k),
        rng.uniform(-3 * s, 3 * s, k),
        rng.uniform(-math.pi, math.pi, k),
        rng.uniform(0.1 * s, 4 * s, k),
        rng.uniform(0.05 * s, 2 * s, k),
        rng.uniform(0.1 * s, 4 * s, k),
        rng.uniform(0.1 * s, 4 * s, k),
        rng.uniform(-3 * s, 3 * s, k),
        rng.uniform(-3 * s, 3 * s, k),
        rng.choice([-1.0, 1.0], k),
        rng.uniform(-math.pi, math.pi, k),
    ]
    return np.ascontiguousarray(np.column_stack(cols))


TIMING = np.radians([0.0, 60.0, 120.0, 180.0, 240.0, 300.0])


def numpy_timed(rows: Array, t: Array, tau: Array) -> tuple[Array, Array]:
    """RMS error of timed four-bar candidates (K, 11) and whether each assembles
    at every target, broadcast over (K, N): what a numpy user writes."""
    x0, y0, th, r1, r2, r3, r4, u, v, mode, phi1 = (rows[:, i : i + 1] for i in range(11))
    phi = phi1 + tau[None]
    bx, by = x0 + r2 * np.cos(phi), y0 + r2 * np.sin(phi)
    dx, dy = x0 + r1 * np.cos(th) - bx, y0 + r1 * np.sin(th) - by
    dd = dx * dx + dy * dy
    dist = np.sqrt(dd)
    ex, ey = dx / dist, dy / dist
    along = (r3 * r3 - r4 * r4 + dd) / (2 * dist)
    h2 = r3 * r3 - along * along
    h = -np.sign(mode) * np.sqrt(np.maximum(h2, 0.0))
    fx, fy = (along * ex - h * ey) / r3, (along * ey + h * ex) / r3
    px, py = bx + u * fx - v * fy, by + u * fy + v * fx
    e2 = (px - t[:, 0]) ** 2 + (py - t[:, 1]) ** 2
    return np.sqrt(e2.mean(axis=1)), (h2 >= 0).all(axis=1)


K_UNTIMED = 100_000
SAMPLES = 90


def numpy_untimed(rows: Array, t: Array, samples: int = SAMPLES, chunk: int = 5_000) -> Array:
    """RMS distance of each target to the nearest of ``samples`` curve points a
    turn (the evaluator's rule without its golden-section steps), broadcast over
    (chunk, M, N) a chunk of candidates at a time (a whole (K, M, N) array would
    not fit): what a numpy user writes. Unassembled samples are +inf away."""
    phi = 2 * np.pi * np.arange(samples) / samples
    out = np.empty(len(rows))
    for s0 in range(0, len(rows), chunk):
        r = rows[s0 : s0 + chunk]
        x0, y0, th, r1, r2, r3, r4, u, v, mode = (r[:, i : i + 1] for i in range(10))
        bx, by = x0 + r2 * np.cos(phi), y0 + r2 * np.sin(phi)
        dx, dy = x0 + r1 * np.cos(th) - bx, y0 + r1 * np.sin(th) - by
        dd = dx * dx + dy * dy
        dist = np.sqrt(dd)
        ex, ey = dx / dist, dy / dist
        along = (r3 * r3 - r4 * r4 + dd) / (2 * dist)
        h2 = r3 * r3 - along * along
        h = -np.sign(mode) * np.sqrt(np.maximum(h2, 0.0))
        fx, fy = (along * ex - h * ey) / r3, (along * ey + h * ex) / r3
        px, py = bx + u * fx - v * fy, by + u * fy + v * fx
        e2 = (px[:, :, None] - t[:, 0]) ** 2 + (py[:, :, None] - t[:, 1]) ** 2
        e2 = np.where((h2 >= 0)[:, :, None], e2, np.inf)
        out[s0 : s0 + chunk] = np.sqrt(e2.min(axis=1).mean(axis=1))
    return out


def test_numpy_untimed_agrees() -> None:
    rows = np.ascontiguousarray(random_rows(5_000, seed=6)[:, :10])
    r = cm.synthesis.path_evaluate(rows, targets(), samples=SAMPLES, refine=0)
    rms = numpy_untimed(rows, targets())
    fine = np.isfinite(rms) & np.isfinite(r["rms"])
    assert fine.sum() > 500
    np.testing.assert_allclose(r["rms"][fine], rms[fine], rtol=0, atol=1e-9)


@pytest.mark.benchmark(group=GROUP_RAW + " (untimed)")
@pytest.mark.parametrize("threads", [1, None], ids=["1-thread", "all-cores"])
def test_raw_untimed_cyclomech(benchmark, threads: int | None) -> None:
    k = 5_000 if benchmark.disabled else K_UNTIMED
    rows = np.ascontiguousarray(random_rows(k)[:, :10])
    benchmark.extra_info["tool"] = "cyclomech"
    where = "all cores" if threads is None else "1 thread"
    benchmark.extra_info["what"] = (
        f"path_evaluate untimed, {k} candidates, {SAMPLES} samples, no refinement, {where}"
    )
    benchmark.extra_info["items"] = k
    r = benchmark.pedantic(
        cm.synthesis.path_evaluate,
        (rows, targets()),
        {"n_threads": threads, "samples": SAMPLES, "refine": 0},
        rounds=3,
        iterations=1,
    )
    assert r["cost"].shape == (k,)


@pytest.mark.benchmark(group=GROUP_RAW + " (untimed)")
def test_raw_untimed_numpy(benchmark) -> None:
    k = 5_000 if benchmark.disabled else K_UNTIMED
    rows = np.ascontiguousarray(random_rows(k)[:, :10])
    benchmark.extra_info["tool"] = "numpy"
    benchmark.extra_info["what"] = f"broadcast over (5000, {SAMPLES}, 6) chunks, nearest sample"
    benchmark.extra_info["items"] = k
    with np.errstate(all="ignore"):
        rms = benchmark.pedantic(numpy_untimed, (rows, targets()), rounds=3, iterations=1)
    assert rms.shape == (k,)


def test_numpy_agrees() -> None:
    rows = random_rows(20_000, seed=5)
    r = cm.synthesis.path_evaluate(rows, targets(), np.degrees(TIMING), full_turn=False)
    rms, ok = numpy_timed(rows, targets(), TIMING)
    both = ok & np.isfinite(r["rms"])
    assert both.sum() > 1000
    np.testing.assert_allclose(r["rms"][both], rms[both], rtol=0, atol=1e-9)


@pytest.mark.benchmark(group=GROUP_RAW)
@pytest.mark.parametrize("threads", [1, None], ids=["1-thread", "all-cores"])
def test_raw_cyclomech(benchmark, threads: int | None) -> None:
    k = 20_000 if benchmark.disabled else K_RAW
    rows = random_rows(k)
    benchmark.extra_info["tool"] = "cyclomech"
    where = "all cores" if threads is None else "1 thread"
    benchmark.extra_info["what"] = f"path_evaluate, {k} timed candidates × 6 targets, {where}"
    benchmark.extra_info["items"] = k
    r = benchmark.pedantic(
        cm.synthesis.path_evaluate,
        (rows, targets(), np.degrees(TIMING)),
        {"n_threads": threads, "full_turn": False},
        rounds=3,
        iterations=1,
    )
    assert r["cost"].shape == (k,)


@pytest.mark.benchmark(group=GROUP_RAW)
def test_raw_numpy(benchmark) -> None:
    k = 20_000 if benchmark.disabled else K_RAW
    rows = random_rows(k)
    benchmark.extra_info["tool"] = "numpy"
    benchmark.extra_info["what"] = f"broadcast over (K, N) = ({k}, 6), RMS and assembly only"
    benchmark.extra_info["items"] = k
    with np.errstate(all="ignore"):
        rms, _ = benchmark.pedantic(numpy_timed, (rows, targets(), TIMING), rounds=3, iterations=1)
    assert rms.shape == (k,)


# ---------------------------------------------------------------- optimisers
def _iters(benchmark: Any) -> int:
    return 3 if benchmark.disabled else PL_ITERS


@pytest.mark.benchmark(group=GROUP_OPT)
def test_opt_pylinkage(benchmark) -> None:
    it = _iters(benchmark)
    benchmark.extra_info["tool"] = "pylinkage"
    benchmark.extra_info["what"] = f"differential_evolution_optimization, maxiter {it}"
    err = benchmark.pedantic(pylinkage_run, (it,), rounds=3, iterations=1)
    benchmark.extra_info["error"] = err
    print(f"\npylinkage maxiter {it}: error {err:.3g} m")


@pytest.mark.benchmark(group=GROUP_OPT)
@pytest.mark.parametrize("threads", [1, None], ids=["1-thread", "all-cores"])
def test_opt_cyclomech(benchmark, threads: int | None) -> None:
    target = pylinkage_error(_iters(benchmark))
    it = cyclomech_budget(target)
    benchmark.extra_info["tool"] = "cyclomech"
    where = "all cores" if threads is None else "1 thread"
    benchmark.extra_info["what"] = f"path_generation, maxiter {it}, {where}"
    t0 = time.perf_counter()
    err = benchmark.pedantic(cyclomech_run, (it, threads), rounds=3, iterations=1)
    benchmark.extra_info["error"] = err
    print(
        f"\ncyclomech maxiter {it} ({where}): error {err:.3g} m "
        f"(pylinkage's {target:.3g} m), {time.perf_counter() - t0:.3g} s for 3 rounds"
    )
    assert err <= target
