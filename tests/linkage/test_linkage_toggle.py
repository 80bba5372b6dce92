"""A dyad at its fold is singular in the linkage's own solution (issue 31, item 2).

At the exact toggle of the issue's non-Grashof four-bar (coupler and rocker in
line) the linkage solver gave ``singular`` False and analogs of about 1e22 times
the crank: its height h² there is round-off, h ~1e-8 of the links, and the
determinant test (1e-9) did not see it. The rule now: an RRR dyad whose h² is
within 1e-12·ra² of zero is at its fold (about 1e-12 rad of crank angle from
it): singular, analogs NaN, positions kept. The toggle angle is found
independently by the cosine law; the analogs away from it are checked against
central differences of the positions.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest

# The issue's four-bar and its toggle angle by the cosine law, shared with the forces' test.
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "forces"))
from test_forces_dead_centre import toggle_angle, toggle_four_bar

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _near_toggle() -> list[float]:
    t = toggle_angle()
    near = [t]
    for _ in range(3):  # a few ulps either side (some do not assemble)
        near = [math.nextafter(near[0], 0.0), *near, math.nextafter(near[-1], 4.0)]
    return near


@pytest.mark.parametrize("n_copies", [1, 64])  # the scalar path and the lanes
def test_the_exact_toggle_is_singular_with_nan_analogs(n_copies: int) -> None:
    lk = toggle_four_bar()
    for phi in _near_toggle():
        sol = lk.solve(np.full(n_copies, phi))
        if not sol.ok[0]:
            continue  # an ulp past the toggle: it does not assemble
        assert sol.singular.all(), phi
        assert np.isnan(sol.vel[:, lk.names.index("C")]).all()
        assert np.isnan(sol.acc[:, lk.names.index("C")]).all()
        assert np.isfinite(sol.xy).all()  # the pose itself is kept
    assert lk.solve(np.array([toggle_angle()])).ok[0]  # the toggle itself assembles


@pytest.mark.parametrize("delta", [1e-9, 1e-6, 1e-3])
def test_near_the_toggle_the_pose_is_regular_and_its_analogs_right(delta: float) -> None:
    """Short of the fold the dyad is regular: no flag, and the velocity analog is
    the central difference of the positions (step δ/100)."""
    lk = toggle_four_bar()
    phi = toggle_angle() - delta
    step = delta / 100
    sol = lk.solve(np.array([phi - step, phi, phi + step]))
    assert sol.ok.all() and not sol.singular.any()
    c = lk.names.index("C")
    fd = (sol.xy[2, c] - sol.xy[0, c]) / (2 * step)
    np.testing.assert_allclose(sol.vel[1, c], fd, rtol=1e-4)


def test_the_example_crank_rocker_is_never_singular() -> None:
    lk = cm.Linkage.from_toml(EXAMPLES / "crank_rocker.toml")
    sol = lk.solve(np.linspace(0.0, 2 * math.pi, 100_001))
    assert sol.ok.all() and not sol.singular.any()
