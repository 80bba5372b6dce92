"""The two-period law's fused SIMD kernel (issue 20) against exact values.

Arrays of angles go through one fused pass (FMA, the periods' scalings folded into
the pieces, a sine reduced once by π): its values are checked here against the
closed forms of the half laws evaluated in 40-digit arithmetic (mpmath), every
order, on a dense grid and random angles; and every angle gives the same value alone
as inside an array (the kernel pads the last, partial register).
"""

from __future__ import annotations

import cyclomech as cm
import numpy as np
import pytest

mp = pytest.importorskip("mpmath")
mp.mp.dps = 40


def _cycloidal(j, n):
    pj = mp.pi * j
    return [j - mp.sin(pj) / mp.pi, 1 - mp.cos(pj), mp.pi * mp.sin(pj), mp.pi**2 * mp.cos(pj)][n]


def _harmonic(j, n):
    h = mp.pi / 2
    x = h * j
    return [1 - mp.cos(x), h * mp.sin(x), h**2 * mp.cos(x), -(h**3) * mp.sin(x)][n]


def _poly4567(j, n):
    # Z_h(j) = 2·Z(j/2), Z = 35x⁴ − 84x⁵ + 70x⁶ − 20x⁷.
    c = {4: 35, 5: -84, 6: 70, 7: -20}
    terms = [2 * ck * mp.ff(k, n) * j ** (k - n) / mp.mpf(2) ** k for k, ck in c.items() if k >= n]
    return sum(terms)


HALF = {"cycloidal": _cycloidal, "harmonic": _harmonic, "polynomial_4567": _poly4567}


def _exact(lw: cm.motion.TwoPeriodLaw, names: tuple[str, str], alpha, n: int) -> np.ndarray:
    """Π^(n)(α) from the seed's definition, in 40 digits."""
    p1, a1, p2, a2 = map(mp.mpf, (lw.stroke1, lw.angle1, lw.stroke, lw.angle))
    out = []
    for a in alpha:
        a = mp.mpf(float(a))
        if a <= a1:
            out.append(p1 / a1**n * HALF[names[0]](a / a1, n))
        else:
            v = (p2 - p1) * (-1 / (a2 - a1)) ** n * HALF[names[1]]((a2 - a) / (a2 - a1), n)
            out.append(p2 - v if n == 0 else -v)
    return np.array([float(v) for v in out])


@pytest.mark.parametrize(
    "names",
    [
        ("cycloidal", "cycloidal"),
        ("harmonic", "cycloidal"),
        ("cycloidal", "harmonic"),
        ("polynomial_4567", "cycloidal"),
        ("cycloidal", "polynomial_4567"),
    ],
)
def test_fused_two_period_is_within_a_few_ulp_of_exact(names):
    lw = cm.motion.two_period(0.2, np.pi, *names, asymmetry=2.0)
    rng = np.random.default_rng(20)
    alpha = np.concatenate(
        [np.linspace(0.0, np.pi, 601), rng.uniform(0.0, np.pi, 400), [lw.angle1, np.pi]]
    )
    eps = np.finfo(float).eps
    for n, f in enumerate(["position", "velocity", "acceleration"]):
        exact = _exact(lw, names, alpha, n)
        got = getattr(lw, f)(alpha)
        scale = np.abs(exact).max()
        # Measured: ≤ 3.7 ε·scale for the sines, 12 for the 4-5-6-7 polynomial's
        # acceleration (Horner with cancellation; the unfused kernel had 10.4).
        assert np.abs(got - exact).max() <= 16 * eps * scale, (names, f)


def test_fused_values_do_not_depend_on_the_place_in_the_array():
    lw = cm.motion.two_period(0.2, np.pi, "cycloidal", "modified_sine", asymmetry=2.0)
    alpha = np.linspace(0.0, np.pi, 1003)
    for f in ("position", "velocity", "acceleration"):
        whole = getattr(lw, f)(alpha, n_threads=1)
        for k in (1, 7, 33, 100):
            assert np.array_equal(getattr(lw, f)(alpha[k:], n_threads=1), whole[k:])
        alone = np.array([getattr(lw, f)(float(a)) for a in alpha[::37]])
        assert np.array_equal(alone, whole[::37])
