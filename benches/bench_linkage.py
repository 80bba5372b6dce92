"""Linkage kernel: a crank-rocker over 360 000 crank angles.

cyclomech computes positions and exact velocity and acceleration analogs of every
joint; the peer is the numpy vectorised closed form of the same dyad (positions
only), which is what a user would write without a library. pylinkage and pyslvs
(the issue's other peers) join with the next linkage slice.
"""

from __future__ import annotations

import cyclomech as cm
import numpy as np
import pytest
from numpy.testing import assert_allclose

N_ANGLES = 360_000
R, L2, L3, D = 1.0, 3.5, 3.0, 4.0
GROUP = "four-bar crank-rocker, 360 000 angles"


def _label(benchmark, tool: str, what: str) -> None:
    benchmark.extra_info["tool"] = tool
    benchmark.extra_info["what"] = what


@pytest.fixture(scope="module")
def setup() -> tuple[cm.Linkage, np.ndarray]:
    # Drawn at φ = 90° with C above B-D.
    b = np.array([0.0, R])
    bd = np.hypot(D, R)
    x = (L2**2 - L3**2 + bd**2) / (2 * bd)
    h = np.sqrt(L2**2 - x**2)
    e = np.array([D, -R]) / bd
    c = b + x * e + h * np.array([-e[1], e[0]])
    lk = cm.Linkage(
        {"A": (0.0, 0.0), "B": tuple(b), "C": tuple(c), "D": (D, 0.0)},
        [("A", "B"), ("B", "C"), ("C", "D")],
        ["A", "D"],
        ("A", "B"),
    )
    return lk, np.linspace(0.0, 2 * np.pi, N_ANGLES)


def numpy_closed_form(phi: np.ndarray) -> np.ndarray:
    """Joint C by the two-circle intersection, vectorised over the angles."""
    bx, by = R * np.cos(phi), R * np.sin(phi)
    dx, dy = D - bx, -by
    dd = dx * dx + dy * dy
    d = np.sqrt(dd)
    x = (L2 * L2 - L3 * L3 + dd) / (2 * d)
    h = np.sqrt(L2 * L2 - x * x)
    ex, ey = dx / d, dy / d
    return np.stack([bx + x * ex - h * ey, by + x * ey + h * ex], axis=1)


@pytest.mark.benchmark(group=GROUP)
def test_linkage_cyclomech(benchmark, setup) -> None:
    _label(benchmark, "cyclomech", "Linkage.solve: positions + velocity + acceleration analogs")
    lk, phi = setup
    sol = benchmark(lk.solve, phi)
    assert_allclose(sol["C"], numpy_closed_form(phi), atol=1e-12)


@pytest.mark.benchmark(group=GROUP)
def test_linkage_cyclomech_one_thread(benchmark, setup) -> None:
    _label(benchmark, "cyclomech", "Linkage.solve, n_threads=1")
    lk, phi = setup
    sol = benchmark(lk.solve, phi, n_threads=1)
    assert sol.ok.all()


@pytest.mark.benchmark(group=GROUP)
def test_linkage_numpy(benchmark, setup) -> None:
    _label(benchmark, "numpy", "vectorised closed form, positions of C only")
    lk, phi = setup
    c = benchmark(numpy_closed_form, phi)
    assert_allclose(c[:1000], lk.solve(phi[:1000])["C"], atol=1e-12)
