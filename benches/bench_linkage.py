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


# --- class III ----------------------------------------------------------------------

GROUP_III = "class III group (ternary link on three binary links), 720 angles"
TRIAD_POINTS = {
    "A": (0.0, 0.0),
    "B": (0.0, 0.2),
    "C": (1.5, 1.2),
    "E": (2.5, 0.8),
    "G": (2.0, 2.2),
    "F": (3.2, -0.6),
    "H": (3.1, 3.4),
}
TRIAD_LINKS = [("A", "B"), ("B", "C"), ("C", "E", "G"), ("E", "F"), ("G", "H")]
TRIAD_PAIRS = [("B", "C"), ("E", "F"), ("G", "H"), ("C", "E"), ("E", "G"), ("G", "C")]


@pytest.fixture(scope="module")
def triad() -> tuple[cm.Linkage, np.ndarray]:
    lk = cm.Linkage(TRIAD_POINTS, TRIAD_LINKS, ["A", "F", "H"], ("A", "B"))
    # The range this group can reach from its drawn pose (it locks past ~111°).
    return lk, np.radians(np.linspace(0.0, 110.0, 720))


def scipy_continuation(angles: np.ndarray) -> np.ndarray:
    """What a user would write: scipy least squares on the closure, angle by angle."""
    import math

    from scipy.optimize import least_squares

    p = {k: np.array(v) for k, v in TRIAD_POINTS.items()}
    length = {ab: math.dist(TRIAD_POINTS[ab[0]], TRIAD_POINTS[ab[1]]) for ab in TRIAD_PAIRS}
    r = math.dist(TRIAD_POINTS["A"], TRIAD_POINTS["B"])

    def residual(x: np.ndarray, phi: float) -> list[float]:
        at = {"C": x[:2], "E": x[2:4], "G": x[4:], "F": p["F"], "H": p["H"]}
        at["B"] = r * np.array([math.cos(phi), math.sin(phi)])
        return [np.linalg.norm(at[a] - at[b]) - length[a, b] for a, b in TRIAD_PAIRS]

    x = np.r_[p["C"], p["E"], p["G"]]
    out = []
    for phi in angles:  # a continuation is sequential by nature
        x = least_squares(residual, x, args=(phi,), xtol=1e-15, ftol=1e-15, gtol=1e-15).x
        out.append(x.reshape(3, 2))
    return np.array(out)


@pytest.mark.benchmark(group=GROUP_III)
def test_triad_cyclomech(benchmark, triad) -> None:
    _label(benchmark, "cyclomech", "Linkage.solve: positions + analogs (Newton continuation)")
    lk, phi = triad
    sol = benchmark(lk.solve, phi)
    assert sol.ok.all()


@pytest.mark.benchmark(group=GROUP_III)
def test_triad_scipy(benchmark, triad) -> None:
    _label(benchmark, "scipy", "least_squares continued angle by angle, positions only")
    lk, phi = triad
    # Descending from the drawn 90° would match cyclomech's walk; scipy starts at
    # the drawn pose and goes up the grid from 0°, so give it the grid from 90° down
    # and up, as cyclomech walks it.
    below, above = phi[phi < np.radians(90.0)][::-1], phi[phi >= np.radians(90.0)]
    got = benchmark.pedantic(
        lambda: (scipy_continuation(above), scipy_continuation(below)), rounds=3, iterations=1
    )
    sol = lk.solve(above)
    assert_allclose(np.stack([sol["C"], sol["E"], sol["G"]], axis=1), got[0], atol=1e-9)
