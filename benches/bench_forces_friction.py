"""Kinetostatics with friction (issue 34 item 5) against what a numpy user would
write, in one run.

A four-bar with mass in every link, gravity, a load torque on its rocker and
Coulomb friction in its four pins, over 3600 crank angles at a batch of 8 steady
speeds (28 800 fixed points). cyclomech:
:func:`cyclomech.forces.kinetostatics_with_friction`, end to end (positions and
analogs, then per angle the frictionless forces and each pin's response to a
unit friction torque on the block-triangular LU, and per speed the fixed point
R⁽ᵏ⁺¹⁾ = solve(… + friction(R⁽ᵏ⁾)) on the four friction sizes), one thread and
all cores. numpy:
the same fixed point on the dense pin-node system of
``tests/forces/forces_reference.py`` (which the tests use as an independent
check), every angle at once, a stacked ``numpy.linalg.solve`` per iteration (LAPACK's
LU per angle) until every angle has converged, speed by speed; and the same with
the matrices inverted once and a stacked product per step; given the
positions and analogs from cyclomech's solver (not timed: numpy's row is
favoured). The ratio table is per (angle, speed) (``extra_info["items"]``).

Default test run (``--benchmark-disable`` in addopts): each benchmark once. For
timings::

    python -m pytest benches/bench_forces_friction.py --benchmark-enable -q -p no:cacheprovider
"""

from __future__ import annotations

import sys
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "forces"))
from forces_reference import dense_system

GROUP = "kinetostatics with friction, four-bar, per crank angle and speed"
N = 3600
RPM = np.linspace(60.0, 480.0, 8)
RAD = 2 * np.pi / 60
MASSES = {
    ("A", "B"): (1.0, None, 0.002),
    ("B", "C"): (3.0, None, 0.03),
    ("C", "D"): (2.0, None, 0.015),
}
G = (0.0, -9.81)
LOAD = -25.0  # N·m on the rocker
MU, R_PIN = 0.15, 0.01
TOL, MAX_ITER = 1e-12, 2000


def four_bar() -> cm.Linkage:
    return cm.Linkage(
        {"A": (0, 0), "B": (0.1, 0), "C": (0.3, 0.25), "D": (0.4, 0)},
        [("A", "B"), ("B", "C"), ("C", "D")],
        ["A", "D"],
        ("A", "B"),
    )


def angles(n: int) -> np.ndarray:
    return np.linspace(0.0, 2 * np.pi, n, endpoint=False)


def ours(n: int, n_threads: int | None = None, sol=None):
    f = cm.forces
    return f.kinetostatics_with_friction(
        four_bar(),
        angles(n) if sol is None else sol,
        f.Friction(pins={p: f.PinFriction(R_PIN, MU) for p in "ABCD"}),
        RPM,
        masses={k: f.LinkMass(*v) for k, v in MASSES.items()},
        loads=[f.LinkTorque(("C", "D"), LOAD)],
        gravity=G,
        n_threads=n_threads,
    )


def peer(sol, inverse: bool = False) -> np.ndarray:
    """The driving torque (S, N) by the fixed point on the dense system, every
    angle at once: friction torques ∓μ·r·|R| on the two members of each pin
    (|R| the larger of the forces on them), added to their moment rows. With
    ``inverse``, the matrices are inverted once and each step is a stacked
    matrix-vector product (the matrix does not change)."""
    A, R, info = dense_system(four_bar(), sol.xy, sol.vel, sol.acc, masses=MASSES, gravity=G)
    n = sol.xy.shape[0]
    om, sides, col_m = info["omega"], info["sides"], info["col_m"]
    R = R.copy()
    R[:, 3 * 2 + 2, 2] -= LOAD  # the rocker is body 2
    frame = np.zeros(n)
    pins = []
    for p, s, _ in info["pins"]:
        k0 = sides.index((p, s[0]))
        w0 = frame if s[0] < 0 else om[s[0]]
        rel = om[s[1]] - w0
        # The kernel's rule: kinetic friction with sign(0) = 0 within 1e-12 rad/rad
        # (at 0° the coupler and the rocker of this four-bar turn alike).
        pins.append((s[0], s[1], k0, k0 + 1, np.where(np.abs(rel) <= 1e-12, 0.0, np.sign(rel))))
    a_inv = np.linalg.inv(A) if inverse else None
    out = np.empty((RPM.size, n))
    for i, rpm in enumerate(RPM):
        w = rpm * RAD
        base = w * w * R[:, :, 0] + R[:, :, 2]
        mags = np.zeros((len(pins), n))
        for _ in range(MAX_ITER):
            rhs = base.copy()
            for (b0, b1, _, _, sgn), m in zip(pins, mags, strict=True):
                t = -m * sgn  # on member b1; −t on member b0
                rhs[:, 3 * b1 + 2] -= t
                if b0 >= 0:
                    rhs[:, 3 * b0 + 2] += t
            if inverse:
                x = np.einsum("nij,nj->ni", a_inv, rhs)
            else:
                x = np.linalg.solve(A, rhs[:, :, None])[:, :, 0]
            forces = x[:, : 2 * len(sides)].reshape(n, len(sides), 2)
            size = np.hypot(forces[..., 0], forces[..., 1])
            new = np.array(
                [MU * R_PIN * np.maximum(size[:, k0], size[:, k1]) for _, _, k0, k1, _ in pins]
            )
            done = np.abs(new - mags).max() <= TOL * new.max()
            mags = new
            if done:
                break
        out[i] = x[:, col_m]
    return out


def test_numpy_agrees() -> None:
    f = ours(360)
    assert f.ok.all()
    for inverse in (False, True):
        ref = peer(f.solution, inverse)
        assert np.abs(f.torque - ref).max() < 1e-9 * np.abs(ref).max()


@pytest.mark.benchmark(group=GROUP)
@pytest.mark.parametrize("threads", [1, None], ids=["1-thread", "all-cores"])
def test_friction_cyclomech(benchmark, threads: int | None) -> None:
    benchmark.extra_info["tool"] = "cyclomech"
    where = "all cores" if threads is None else "1 thread"
    benchmark.extra_info["what"] = f"kinetostatics_with_friction, 8 speeds, {where}"
    benchmark.extra_info["items"] = N * RPM.size
    f = benchmark(ours, N, threads)
    assert f.ok.all() and f.torque.shape == (RPM.size, N)


@pytest.mark.benchmark(group=GROUP)
def test_friction_cyclomech_from_a_solution(benchmark) -> None:
    """The forces alone, from the same solution numpy is given (equal input)."""
    sol = four_bar().solve(angles(N))
    benchmark.extra_info["tool"] = "cyclomech"
    benchmark.extra_info["what"] = "kinetostatics_with_friction from a solution, 1 thread"
    benchmark.extra_info["items"] = N * RPM.size
    f = benchmark(ours, N, 1, sol)
    assert f.ok.all()


@pytest.mark.benchmark(group=GROUP)
def test_friction_numpy(benchmark) -> None:
    sol = four_bar().solve(angles(N))
    benchmark.extra_info["tool"] = "numpy"
    benchmark.extra_info["what"] = "dense pin-node fixed point, stacked numpy.linalg.solve"
    benchmark.extra_info["items"] = N * RPM.size
    ref = benchmark(peer, sol)
    assert ref.shape == (RPM.size, N)


@pytest.mark.benchmark(group=GROUP)
def test_friction_numpy_inverse(benchmark) -> None:
    sol = four_bar().solve(angles(N))
    benchmark.extra_info["tool"] = "numpy"
    benchmark.extra_info["what"] = "dense fixed point, numpy.linalg.inv once, einsum per step"
    benchmark.extra_info["items"] = N * RPM.size
    ref = benchmark(peer, sol, True)
    assert ref.shape == (RPM.size, N)
