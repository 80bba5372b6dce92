"""Spline segments of a motion program against scipy's splines through the same table.

A segment's table is (angle from its start [deg], s); the program's spline in
master angle [rad] must be scipy's ``CubicSpline`` (natural or clamped) or
``make_interp_spline(k=5)`` (given or natural ends: s‴ = s⁗ = 0) through the same
points, with its first three derivatives, to rounding.
"""

from __future__ import annotations

import math

import cyclomech as cm
import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.interpolate import CubicSpline, make_interp_spline

S = cm.motion.Segment
P = cm.motion.Program
DEG = np.array([0.0, 20.0, 35.0, 60.0, 100.0, 140.0, 180.0])
Y = np.array([0.0, 0.004, 0.011, 0.022, 0.030, 0.033, 0.035])
X = np.radians(DEG)


def _program(degree: int, start=None, end=None) -> cm.motion.Program:
    return P(
        [
            S(
                "spline",
                180,
                start=start,
                end=end,
                points=list(zip(DEG, Y, strict=True)),
                degree=degree,
            ),
            S("poly7", 180, end=(0.0, 0.0, 0.0, 0.0)),
        ],
        continuity="position",
    )


def _check(prog: cm.motion.Program, ref) -> None:
    u = np.linspace(0.0, X[-1] * (1 - 1e-12), 301)
    m = prog.evaluate(u)
    for k, got in enumerate((m.s, m.v, m.a, m.j)):
        want = ref(u, k)
        assert_allclose(got, want, rtol=1e-9, atol=1e-11 * (1 + np.abs(want).max()))


def test_natural_cubic_is_scipys():
    _check(_program(3), CubicSpline(X, Y, bc_type="natural"))


def test_clamped_cubic_is_scipys():
    prog = _program(3, start=(None, 0.01), end=(None, 0.0))
    _check(prog, CubicSpline(X, Y, bc_type=((1, 0.01), (1, 0.0))))
    b = prog.boundaries[0]
    assert b[2][1] == pytest.approx(0.01) and b[3][1] == pytest.approx(0.0, abs=1e-15)


def test_quintic_with_given_ends_is_scipys():
    prog = _program(5, start=(None, 0.01, 0.0), end=(None, 0.0, -0.02))
    ref = make_interp_spline(X, Y, k=5, bc_type=([(1, 0.01), (2, 0.0)], [(1, 0.0), (2, -0.02)]))
    _check(prog, ref)


def test_natural_quintic_is_scipys():
    # scipy's "natural" for k = 5 is s″ = 0 only; the natural quintic (s‴ = s⁗ = 0
    # at both ends) is asked of it by its derivatives.
    ref = make_interp_spline(X, Y, k=5, bc_type=([(3, 0.0), (4, 0.0)], [(3, 0.0), (4, 0.0)]))
    _check(_program(5), ref)


def test_a_spline_joins_and_its_table_is_checked():
    # Joined to the velocity by a poly5 that starts with the spline's end values.
    prog = P(
        [
            S("spline", 180, points=list(zip(DEG, Y, strict=True)), start=(0, 0), end=(None, 0)),
            S("poly5", 180, end=0.0),
        ],
        continuity="velocity",
    )
    # (The poly5 starts with the spline's end acceleration: not rest to rest either.)
    assert prog.scalable == (False, False)
    with pytest.raises(cm.InputError, match=r"segment 1 \(spline\): its points must run from 0°"):
        P([S("spline", 180, points=[(0, 0), (170, 0.01)]), S("poly5", 180, end=0.0)])
    with pytest.raises(cm.InputError, match=r"velocity and acceleration together"):
        P(
            [
                S("spline", 180, points=list(zip(DEG, Y, strict=True)), degree=5, end=(None, 0.0)),
                S("poly5", 180, end=0.0),
            ]
        )
    with pytest.raises(cm.InputError, match=r"segment 1 \(spline\): .*increas"):
        P(
            [
                S("spline", 180, points=[(0, 0), (90, 0.01), (60, 0.0), (180, 0.02)]),
                S("poly5", 180, end=0.0),
            ]
        )
    with pytest.raises(cm.InputError, match=r"a spline needs its point table"):
        P([S("spline", 360)])
    assert math.isfinite(prog.characteristics[0].cv)


# ---------------------------------------------------------------- periodic
PDEG = np.array([0.0, 45.0, 100.0, 170.0, 230.0, 300.0, 360.0])
PY = np.array([0.0, 0.01, 0.03, 0.02, 0.035, 0.012, 0.0])


@pytest.mark.parametrize("degree", [3, 5])
def test_a_whole_cycle_table_is_periodic(degree: int) -> None:
    """One spline segment over the cycle with free ends runs into the next cycle:
    scipy's periodic spline through the same table, and its joins hold to the
    acceleration (natural ends would leave a kink in s′ at the wrap)."""
    prog = P([S("spline", 360, points=list(zip(PDEG, PY, strict=True)), degree=degree)])
    ref = make_interp_spline(np.radians(PDEG), PY, k=degree, bc_type="periodic")
    u = np.linspace(0.0, 2 * math.pi * (1 - 1e-12), 401)
    m = prog.evaluate(u)
    for k, got in enumerate((m.s, m.v, m.a, m.j)):
        want = ref(u, k)
        assert_allclose(got, want, rtol=1e-9, atol=1e-11 * (1 + np.abs(want).max()))
    P(prog.segments, continuity="acceleration")  # continuous across the wrap
    ends = prog.evaluate(np.array([0.0, 2 * math.pi * (1 - 1e-15)]))
    assert ends.v[0] == pytest.approx(ends.v[1], abs=1e-9)


def test_a_whole_cycle_table_with_an_advance() -> None:
    """A feed's table moves on by its advance each cycle: periodic about the line
    from its first to its last value (the line's slope a constant velocity)."""
    advance = 0.25
    y = PY + advance * PDEG / 360.0
    prog = P(
        [S("spline", 360, points=list(zip(PDEG, y, strict=True)))],
        continuity="acceleration",
        advance=advance,
    )
    slope = advance / (2 * math.pi)
    ref = CubicSpline(np.radians(PDEG), PY, bc_type="periodic")
    u = np.linspace(0.0, 2 * math.pi * (1 - 1e-12), 401)
    m = prog.evaluate(u)
    assert_allclose(m.s, ref(u) + slope * u, atol=1e-14)
    assert_allclose(m.v, ref(u, 1) + slope, atol=1e-13)
    assert_allclose(m.a, ref(u, 2), atol=1e-12)
