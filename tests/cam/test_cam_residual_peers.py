"""The residual vibration of every built-in law in SIMD lanes (issue 37 row 1)
against the numpy closed forms derived by hand in ``residual_peers.py`` (the
bench's peers), and those against scipy's ``solve_ivp`` of the textbook z''."""

from __future__ import annotations

import itertools
import math
import sys
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

sys.path.insert(0, str(Path(__file__).parent))
import residual_peers as peers

LAWS = tuple(peers.PEERS)


def _envelope(tau: np.ndarray, zeta: float) -> np.ndarray:
    """R's envelope: the small-τ value 1/√(1 − ζ²), then 100/τ²."""
    return np.minimum(1 / math.sqrt(1 - zeta * zeta), 100 / tau**2)


def _zpp(law: str, u: float) -> float:
    """The textbook z''(u) (as in test_cam_vibration.py, written out again)."""
    ca_s, ca_t, w = peers.CA_MODSINE, peers.CA_MODTRAP, 4 * math.pi
    table = {
        "cycloidal": lambda: 2 * math.pi * math.sin(2 * math.pi * u),
        "harmonic": lambda: peers.PI2 / 2 * math.cos(math.pi * u),
        "polynomial_345": lambda: 60 * u - 180 * u**2 + 120 * u**3,
        "polynomial_4567": lambda: 420 * u**2 - 1680 * u**3 + 2100 * u**4 - 840 * u**5,
        "modified_sine": lambda: (
            ca_s * math.sin(w * u)
            if u <= 1 / 8
            else ca_s * math.cos(w * (u - 1 / 8) / 3)
            if u <= 7 / 8
            else -ca_s * math.cos(w * (u - 7 / 8))
        ),
        "modified_trapezoid": lambda: (
            ca_t * math.sin(w * u)
            if u <= 1 / 8
            else ca_t
            if u <= 3 / 8
            else ca_t * math.cos(w * (u - 3 / 8))
            if u <= 5 / 8
            else -ca_t
            if u <= 7 / 8
            else -ca_t * math.cos(w * (u - 7 / 8))
        ),
    }
    return table[law]()


def _ivp(law: str, tau: float, zeta: float) -> float:
    """R from x'' + 2ζτx' + τ²x = −z''(u), at rest at u = 0, integrated by DOP853
    piece by piece over the law's breakpoints."""
    knots = {
        "modified_sine": (0, 1 / 8, 7 / 8, 1),
        "modified_trapezoid": (0, 1 / 8, 3 / 8, 5 / 8, 7 / 8, 1),
    }.get(law, (0, 1))
    y = np.zeros(2)
    for a, b in itertools.pairwise(knots):

        def f(u: float, s: np.ndarray, a: float = a, b: float = b) -> list[float]:
            uu = min(max(u, a), b)
            return [s[1], -2 * zeta * tau * s[1] - tau * tau * s[0] - _zpp(law, uu)]

        y = solve_ivp(f, (a, b), y, method="DOP853", rtol=1e-11, atol=1e-14).y[:, -1]
    wd = tau * math.sqrt(1 - zeta * zeta)
    return math.hypot(y[0], (y[1] + zeta * tau * y[0]) / wd)


@pytest.mark.parametrize("law", LAWS)
@pytest.mark.parametrize("zeta", [0.0, 0.05, 0.5])
def test_peers_against_solve_ivp(law: str, zeta: float) -> None:
    """The hand-derived closed forms are the textbook laws' responses."""
    tau = np.array([4.5, 9.0, 23.0])
    got = peers.PEERS[law](tau, zeta)
    want = [_ivp(law, t, zeta) for t in tau]
    np.testing.assert_allclose(got, want, rtol=1e-8, atol=1e-12)


@pytest.mark.parametrize("law", LAWS)
@pytest.mark.parametrize("zeta", [0.0, 0.05, 0.5, 0.95])
def test_lanes_against_the_numpy_peers(law: str, zeta: float) -> None:
    """Densely (2e4 τ to 1e4, beside the resonances of the sines) within
    1e-11 of R's envelope; relative 1e-10 where R is not near a zero."""
    tau = np.concatenate(
        [
            np.geomspace(peers.TAU_FROM.get(law, 0.5), 1e4, 20_000),
            # Beside the sines' resonances (where the peers' own 0/0 is not),
            # on both sides of the lanes' NEAR = 0.25.
            np.outer(np.pi * np.array([1.0, 2.0, 4.0 / 3.0, 4.0]), [1 - 1e-3, 1 + 1e-3]).ravel(),
            np.outer(np.pi * np.array([1.0, 2.0, 4.0 / 3.0, 4.0]), [1.0, 1.0]).ravel()
            + [-0.26, -0.24, 0.24, 0.26] * 2,
        ]
    )
    got = cm.cam.residual_vibration(law, tau, zeta, n_threads=1)
    want = peers.PEERS[law](tau, zeta)
    env = _envelope(tau, zeta)
    assert np.all(np.abs(got - want) <= 1e-11 * env), law
    away = want > 1e-3 * env
    np.testing.assert_allclose(got[away], want[away], rtol=1e-10)


@settings(max_examples=60, deadline=None)
@given(
    law=st.sampled_from(LAWS),
    tau=st.lists(st.floats(0.01, 3e3), min_size=1, max_size=40),
    zeta=st.floats(0.0, 0.99),
    start=st.integers(0, 7),
)
def test_lanes_property(law: str, tau: list[float], zeta: float, start: int) -> None:
    """Any τ list: the peer's value (where it is well conditioned) within 1e-11
    of the envelope, and each τ's value independent of its place in the array."""
    t = np.array(tau)
    got = cm.cam.residual_vibration(law, t, zeta, n_threads=1)
    shifted = cm.cam.residual_vibration(law, t[start:], zeta, n_threads=1)
    np.testing.assert_array_equal(got[start:], shifted)
    ok = t >= max(peers.TAU_FROM.get(law, 0.5), 0.5)
    want = peers.PEERS[law](t[ok], zeta)
    assert np.all(np.abs(got[ok] - want) <= 1e-11 * _envelope(t[ok], zeta))
