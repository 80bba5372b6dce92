"""Tests of the machine's plots in cyclomech.plot: the machine against speed."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import cyclomech as cm
import cyclomech.plot as cplot
import matplotlib.pyplot as plt
import numpy as np
import pytest
from numpy.testing import assert_allclose

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _gid(fig, gid):
    return [a for ax in fig.axes for a in ax.get_children() if a.get_gid() == gid]


def test_speed_sweep_curves_end_at_the_speed_limit_whatever_sets_it():
    """The rotor line's limit is its transfer's jerk, below the cyclogram's: the
    curves end there, the speeds above are shaded, and without stops there is no
    stop panel and no word of rebound bounds."""
    m = cm.Machine.from_toml(EXAMPLES / "rotor_line.toml")
    lim = m.speed_limit()
    assert lim.by == "line" and lim.rpm < lim.cyclogram_rpm
    s = m.speed_sweep()
    fig = cplot.plot_speed_sweep(s, limit_rpm=lim.rpm, limit_by=lim.by)
    (line,) = _gid(fig, "limiting")
    x, y = line.get_data()
    assert np.isnan(y[x > lim.rpm]).all() and np.isfinite(y[x <= lim.rpm]).all()
    assert len(fig.axes) == 2 and line.get_label() == "optimum"
    (span,) = _gid(fig, "above")
    assert span.get_label() == "above the speed limit"
    (vline,) = _gid(fig, "limit")
    assert vline.get_label() == f"speed limit {lim.rpm:.1f} rpm (line)"
    plt.close(fig)


def test_speed_sweep_with_stops_draws_their_smallest_phase_angles():
    m = cm.Machine.from_toml(EXAMPLES / "stb_loom.toml")
    s, lin = m.speed_sweep(), m.speed_sweep(linear=True)
    fig = cplot.plot_speed_sweep(s, linear=lin, limit_rpm=m.speed_limit().rpm)
    (exact,) = _gid(fig, "stop:lifter")
    (linear,) = _gid(fig, "stop:lifter:linear")
    ok = s.rpm <= m.speed_limit().rpm
    assert_allclose(exact.get_data()[1][ok], s.min_phase_deg["lifter"][ok])
    assert_allclose(linear.get_data()[1][ok], lin.min_phase_deg["lifter"][ok])
    assert fig.axes[2].get_ylabel() == "smallest phase angle  [deg]"
    # 13 bounds (the stop and four criteria on each of the cam's three segments):
    # no two curves look alike; one colour a segment, one line style a criterion.
    lines = [ln for ln in fig.axes[2].get_lines() if str(ln.get_gid()).startswith("stop:")]
    # (matplotlib reports every custom dash pattern as "--": compare the patterns)
    looks = [(ln.get_color(), str(ln._unscaled_dash_pattern)) for ln in lines]
    assert len(lines) == len(s.min_phase_deg) + 1 and len(set(looks)) == len(looks)
    by_segment: dict[str, set[str]] = {}
    for ln in lines:
        seg = ln.get_label().partition("[")[2]
        if seg:
            by_segment.setdefault(seg.split("]")[0], set()).add(ln.get_color())
    assert len(by_segment) == 3 and all(len(c) == 1 for c in by_segment.values())
    plt.close(fig)


def test_speed_sweep_of_a_range_where_nothing_works_says_so():
    m = cm.Machine.example()
    s = m.speed_sweep([600.0, 700.0, 800.0])
    fig = cplot.plot_speed_sweep(s, limit_rpm=m.speed_limit().rpm, limit_by="cyclogram")
    texts = [t.get_text() for t in fig.axes[0].texts]
    assert any("works at no speed of this range" in t and "421.4 rpm" in t for t in texts)
    plt.close(fig)
