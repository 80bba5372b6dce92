"""Kinetostatics of three linkages against the best a numpy user would write, in one run.

The linkages: a four-bar (9 unknowns), an offset-free slider-crank with a slider
mass (6) and the Burg trimmer (seed 001, a class III knife drive, 15); every link
with mass and inertia, gravity acting, so no part of the system is trivially zero.

cyclomech: :func:`cyclomech.forces.kinetostatics` from a solved
:class:`~cyclomech.LinkageSolution` (numpy's input: the positions and analogs are
not part of either side's time), one thread: every joint's force on every part,
the guide forces and the driving torque, as ω², ε and static parts.

numpy (the peer): :func:`forces_reference.compact_kinetostatics`
(``tests/forces/forces_reference.py``, which the tests also use as an
independent check) — the smallest linear system a user writes per angle: each
pin's force on its first part eliminated by the pin's equation, 3 Newton–Euler
equations per moving link in as many unknowns (9×9, 6×6, 15×15), assembled over
all angles at once with numpy and solved by one stacked ``numpy.linalg.solve``,
then the eliminated forces from the pins' equations (so both sides return the
same numbers, checked equal first by :func:`test_compact_agrees`). It replaces
the 29-unknown pin-node system (kept as the tests' second reference), which no
user would prefer: it is ~2× slower for the same answer. A closed-form
elimination for the four-bar and the slider-crank would be faster still; it is
not written here (see BENCHMARKS.md).

Page states (both sides alike, interleaved rounds): ``reused`` — glibc's heap
keeps and reuses the freed outputs and temporaries; ``fresh`` —
``malloc_trim(0)`` before each call, so each call first-touches its pages. Floor:
cyclomech's output array (3, N, W) written once (``np.empty`` + ``fill``).
``cyclomech out=`` solves into the arrays of a previous result (``out=``), which no
page state touches anew.

Default test run (``--benchmark-disable`` in addopts): each check once, the
ratio table skipped. For timings and the table (printed; ``-s``)::

    python -m pytest benches/bench_forces.py --benchmark-enable -q -p no:cacheprovider -s
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.linkage import presets

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "forces"))
sys.path.insert(0, str(Path(__file__).resolve().parent))
from _timing import page_states, timed_run
from forces_reference import compact_kinetostatics, dense_kinetostatics

GROUP = "kinetostatics from a solution, 1e5 crank angles, 1 thread"
N = 100_000
ROUNDS = 7
G = (0.0, -9.81)


def four_bar() -> cm.Linkage:
    return cm.Linkage(
        {"A": (0, 0), "B": (0.1, 0), "C": (0.3, 0.25), "D": (0.4, 0)},
        [("A", "B"), ("B", "C"), ("C", "D")],
        ["A", "D"],
        ("A", "B"),
    )


def slider_crank() -> cm.Linkage:
    return cm.Linkage(
        {"O": (0, 0), "A": (0.1, 0), "C": (0.45, 0)},
        [("O", "A"), ("A", "C")],
        ["O"],
        ("O", "A"),
        sliders={"C": ("ground", (1, 0))},
    )


# name: (linkage, masses {link: (m [kg], centre of mass or None, J [kg·m²])}, point masses)
CASES: dict[str, tuple[Callable[[], cm.Linkage], dict[Any, Any], dict[str, float]]] = {
    "four-bar": (
        four_bar,
        {
            ("A", "B"): (1.0, None, 1e-3),
            ("B", "C"): (2.0, None, 0.01),
            ("C", "D"): (1.5, None, 5e-3),
        },
        {},
    ),
    "slider-crank": (
        slider_crank,
        {("O", "A"): (1.0, None, 1e-3), ("A", "C"): (2.0, None, 0.02)},
        {"C": 3.0},
    ),
    "burg": (
        presets.burg_trimmer,
        {
            ("B", "C", "E"): (80.0, None, 15.0),
            ("A", "B"): (8.0, None, 0.12),
            ("D", "C"): (8.0, None, 0.14),
            ("E", "F"): (10.0, None, 0.62),
            ("O", "F"): (5.0, None, 0.01),
        },
        {},
    ),
}


def setup(name: str, n: int) -> tuple[Callable[..., Any], Callable[[], Any]]:
    """(cyclomech, numpy) for case ``name`` on ``n`` crank angles, from one solution."""
    make, masses, pm = CASES[name]
    lk = make()
    sol = lk.solve(np.linspace(0.0, 2 * np.pi, n, endpoint=False))
    lm = {k: cm.forces.LinkMass(*v) for k, v in masses.items()}

    def ours(out: Any = None) -> Any:
        return cm.forces.kinetostatics(
            lk, sol, masses=lm, point_masses=pm, gravity=G, n_threads=1, out=out
        )

    def peer() -> Any:
        return compact_kinetostatics(
            lk, sol.xy, sol.vel, sol.acc, masses=masses, point_masses=pm, gravity=G
        )

    return ours, peer


@pytest.mark.parametrize("name", list(CASES))
def test_compact_agrees(name: str) -> None:
    ours, peer = setup(name, 3600)
    k, ref = ours(), peer()
    assert k.ok.all()
    scale = np.abs(ref["reactions"]).max()
    assert np.abs(k.reaction_parts - ref["reactions"]).max() < 1e-12 * scale
    assert np.abs(k.torque_parts - ref["torque"]).max() < 1e-12 * scale
    assert np.abs(k.guide_parts - ref["guides"]).max(initial=0.0) < 1e-12 * scale


def test_pin_node_agrees() -> None:
    """The 29-unknown pin-node system (the former peer) gives the same forces."""
    ours, _ = setup("burg", 3600)
    k = ours()
    _, masses, _ = CASES["burg"]
    sol = k.solution
    ref = dense_kinetostatics(
        presets.burg_trimmer(), sol.xy, sol.vel, sol.acc, masses=masses, gravity=G
    )
    scale = np.abs(ref["reactions"]).max()
    assert np.abs(k.reaction_parts - ref["reactions"]).max() < 1e-10 * scale


def test_ratio_table(request: pytest.FixtureRequest) -> None:
    """Interleaved rounds, both page states: medians and numpy / cyclomech."""
    if not timed_run(request.config):
        pytest.skip("timed runs only (--benchmark-enable)")
    print(f"\nkinetostatics, {N} angles, 1 thread, {ROUNDS} interleaved rounds (medians)")
    for name in CASES:
        ours, peer = setup(name, N)
        k = ours()
        width = 1 + k.guide_parts.shape[2] + 2 * k.reaction_parts.shape[2]

        def floor(width: int = width) -> None:
            np.empty((3, N, width)).fill(1.0)

        def into(k: Any = k, ours: Callable[..., Any] = ours) -> None:
            ours(out=k)

        tools = {"cyclomech": ours, "cyclomech out=": into, "numpy": peer, "floor": floor}
        for state, t in page_states(tools, ROUNDS).items():
            for i, clock in enumerate(("wall", "cpu")):
                c, o, p, f = (
                    t[k][i] * 1e3 for k in ("cyclomech", "cyclomech out=", "numpy", "floor")
                )
                print(
                    f"  {name:13s} {state:6s} {clock:4s}  cyclomech {c:7.1f} ms  "
                    f"numpy {p:7.1f} ms  ratio {p / c:5.2f}x  out= {o:7.1f} ms  "
                    f"ratio {p / o:5.2f}x  floor {f:5.1f} ms  cyclomech/floor {c / f:4.1f}"
                )


@pytest.mark.benchmark(group=GROUP)
@pytest.mark.parametrize("name", list(CASES))
def test_kinetostatics_cyclomech(benchmark, name: str) -> None:
    ours, _ = setup(name, N)
    benchmark.extra_info["tool"] = "cyclomech"
    benchmark.extra_info["what"] = f"{name}: kinetostatics from a solution, 1 thread"
    benchmark.extra_info["items"] = N
    k = benchmark(ours)
    assert k.ok.all()


@pytest.mark.benchmark(group=GROUP)
@pytest.mark.parametrize("name", list(CASES))
def test_kinetostatics_numpy(benchmark, name: str) -> None:
    _, peer = setup(name, N)
    benchmark.extra_info["tool"] = "numpy"
    benchmark.extra_info["what"] = f"{name}: compact stacked numpy.linalg.solve"
    benchmark.extra_info["items"] = N
    ref = benchmark(peer)
    assert ref["torque"].shape == (3, N)
