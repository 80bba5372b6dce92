"""Kinetostatics of the Burg trimmer (seed 001, a class III knife drive) against
what a numpy user would write, in one run.

cyclomech: :func:`cyclomech.forces.kinetostatics` over 360 000 crank angles, end
to end (the linkage's positions and analogs, then every joint's force on every
part, the guide forces and the driving torque, as ω², ε and static parts), one
thread and all cores; and with ``reactions=False`` (torque only, what the main
shaft needs). numpy: the same Newton–Euler equations with every joint kept as a
pin node (29 unknowns), assembled over all angles at once and solved by
``numpy.linalg.solve`` (LAPACK's LU per angle; ``tests/forces/forces_reference.py``,
which the tests also use as an independent check), given the positions and
analogs from cyclomech's solver (not timed: numpy's row is favoured). numpy runs
on 36 000 angles to bound its memory (A is 29×29 per angle); the ratio table is
per angle (``extra_info["items"]``).

The masses are illustrative (the knife cutter example's); every link has mass and
inertia and gravity acts, so no part of the system is trivially zero.

Default test run (``--benchmark-disable`` in addopts): each benchmark once. For
timings::

    python -m pytest benches/bench_forces.py --benchmark-enable -q -p no:cacheprovider
"""

from __future__ import annotations

import sys
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.linkage import presets

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "forces"))
from forces_reference import dense_kinetostatics

GROUP = "kinetostatics, Burg trimmer (class III), per crank angle"
N, N_NUMPY = 360_000, 36_000
MASSES = {
    ("B", "C", "E"): (80.0, None, 15.0),
    ("A", "B"): (8.0, None, 0.12),
    ("D", "C"): (8.0, None, 0.14),
    ("E", "F"): (10.0, None, 0.62),
    ("O", "F"): (5.0, None, 0.01),
}
G = (0.0, -9.81)


def angles(n: int) -> np.ndarray:
    return np.linspace(0.0, 2 * np.pi, n, endpoint=False)


def ours(n: int, **kw):
    masses = {k: cm.forces.LinkMass(*v) for k, v in MASSES.items()}
    return cm.forces.kinetostatics(
        presets.burg_trimmer(), angles(n), masses=masses, gravity=G, **kw
    )


def peer(sol):
    return dense_kinetostatics(
        presets.burg_trimmer(), sol.xy, sol.vel, sol.acc, masses=MASSES, gravity=G
    )


def test_numpy_agrees() -> None:
    k = ours(3600)
    ref = peer(k.solution)
    scale = np.abs(ref["reactions"]).max()
    assert np.abs(k.reaction_parts - ref["reactions"]).max() < 1e-10 * scale
    assert np.abs(k.torque_parts - ref["torque"]).max() < 1e-10 * scale


@pytest.mark.benchmark(group=GROUP)
@pytest.mark.parametrize("threads", [1, None], ids=["1-thread", "all-cores"])
def test_kinetostatics_cyclomech(benchmark, threads: int | None) -> None:
    benchmark.extra_info["tool"] = "cyclomech"
    where = "all cores" if threads is None else "1 thread"
    benchmark.extra_info["what"] = f"kinetostatics, positions to reactions, {where}"
    benchmark.extra_info["items"] = N
    k = benchmark(ours, N, n_threads=threads)
    assert k.ok.all() and k.reaction_parts.shape == (3, N, 14, 2)


@pytest.mark.benchmark(group=GROUP)
def test_kinetostatics_cyclomech_torque_only(benchmark) -> None:
    benchmark.extra_info["tool"] = "cyclomech"
    benchmark.extra_info["what"] = "kinetostatics, reactions=False, 1 thread"
    benchmark.extra_info["items"] = N
    k = benchmark(ours, N, n_threads=1, reactions=False)
    assert k.ok.all()


@pytest.mark.benchmark(group=GROUP)
def test_kinetostatics_cyclomech_from_a_solution(benchmark) -> None:
    """The forces alone, from the same solution numpy is given (equal input)."""
    lk = presets.burg_trimmer()
    sol = lk.solve(angles(N))
    masses = {k: cm.forces.LinkMass(*v) for k, v in MASSES.items()}
    benchmark.extra_info["tool"] = "cyclomech"
    benchmark.extra_info["what"] = "kinetostatics from a solution (forces only), 1 thread"
    benchmark.extra_info["items"] = N
    k = benchmark(cm.forces.kinetostatics, lk, sol, masses=masses, gravity=G, n_threads=1)
    assert k.ok.all()


@pytest.mark.benchmark(group=GROUP)
def test_kinetostatics_numpy(benchmark) -> None:
    sol = presets.burg_trimmer().solve(angles(N_NUMPY))
    benchmark.extra_info["tool"] = "numpy"
    benchmark.extra_info["what"] = "dense pin-node system, numpy.linalg.solve (36 000 angles)"
    benchmark.extra_info["items"] = N_NUMPY
    ref = benchmark(peer, sol)
    assert ref["torque"].shape == (3, N_NUMPY)
