"""The speed-sweep and cam minimum-phase figures are readable (new-user trial).

Figure-level properties, measured on the drawn figure against the data given to
it: the speed axis contains every drawn point and the speeds where the machine
runs are not squeezed (a speed limit near the bottom of the range left them 7 % of
the width beside a grey block); the legend of the loom's 13 bounds names each
colour (what is bounded) and each line style (the criterion) once, so that every
curve is told by one colour entry and one style entry; legends stand beside the
axes, not over the curves (the cam's covered its curves between 400 and 500 rpm).
"""

from __future__ import annotations

import tomllib
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import cyclomech as cm
import matplotlib.pyplot as plt
import numpy as np
import pytest
from cyclomech.cam.plot import plot_min_phase_angles
from cyclomech.machine.plot import RUNNING_SHARE, SQUEEZED_SHARE, plot_speed_sweep
from matplotlib.colors import to_rgba

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _loom(speed_rpm: list[float] | None = None) -> cm.Machine:
    data = tomllib.loads((EXAMPLES / "stb_loom.toml").read_text(encoding="utf-8"))
    if speed_rpm is not None:
        data["machine"]["speed_rpm"] = speed_rpm
    return cm.Machine.from_dict(data, "loom.toml")


@pytest.fixture(scope="module")
def squeezed():
    """The loom swept over 400–700 rpm: its speed limit, 420 rpm, is 7 % in."""
    m = _loom([400.0, 700.0])
    limit = m.speed_limit().rpm
    fig = plot_speed_sweep(m.speed_sweep(), limit_rpm=limit)
    yield fig, limit
    plt.close(fig)


def _drawn_x(ax) -> np.ndarray:
    xs = [
        np.asarray(ln.get_xdata(), float)[np.isfinite(np.asarray(ln.get_ydata(), float))]
        for ln in ax.get_lines()
        if (ln.get_gid() or "").startswith(("limiting", "time", "stop:"))
    ]
    return np.concatenate(xs)


def test_a_low_speed_limit_does_not_squeeze_the_curves(squeezed):
    fig, limit = squeezed
    assert (limit - 400.0) / 300.0 < 0.1  # the case of the trial
    for ax in fig.axes[:3]:
        lo, hi = ax.get_xlim()
        x = _drawn_x(ax)
        assert lo <= x.min() and x.max() <= hi  # every drawn point is on the axis
        assert lo <= limit <= hi  # and the limit
        # the running speeds take the promised share of the width, not 7 %
        assert (limit - lo) / (hi - lo) == pytest.approx(RUNNING_SHARE)
        assert (x.max() - x.min()) / (hi - lo) > 0.7


def test_a_limit_well_inside_the_range_keeps_the_whole_range():
    m = _loom()
    limit = m.speed_limit().rpm
    assert (limit - 200.0) / 300.0 > SQUEEZED_SHARE
    fig = plot_speed_sweep(m.speed_sweep(), limit_rpm=limit)
    assert fig.axes[0].get_xlim() == (200.0, 500.0)
    plt.close(fig)


def _visible_entries(legend) -> list[tuple[str, object]]:
    return [
        (t.get_text(), h)
        for t, h in zip(legend.get_texts(), legend.legend_handles, strict=True)
        if t.get_text()
    ]


def _dashes(line) -> str:
    """A line's dash pattern as drawn (matplotlib has no public getter: its
    ``get_linestyle`` says "--" of every custom pattern)."""
    return str(line._unscaled_dash_pattern)


def test_the_bounds_legend_groups_colours_and_line_styles(squeezed):
    fig, _ = squeezed
    low = fig.axes[2]
    curves = [ln for ln in low.get_lines() if (ln.get_gid() or "").startswith("stop:")]
    assert len(curves) == 13  # a stop and a cam's criteria on three operations
    entries = _visible_entries(low.get_legend())
    assert len(entries) <= 10
    colours = {to_rgba(h.get_color()): t for t, h in entries if h.get_linestyle() == "-"
               and h.get_linewidth() >= 2.5}  # fmt: skip
    styles = {_dashes(h): t for t, h in entries if h.get_linewidth() < 2.5}
    assert set(colours.values()) == {
        "lifter",
        "lifter cam rise 1→3",
        "lifter cam rise 3→7",
        "lifter cam return 7→10.1",
    }
    told = set()
    for ln in curves:
        name = ln.get_gid().removeprefix("stop:")
        what = name.partition("[")[2].rstrip("]") or name
        assert colours[to_rgba(ln.get_color())] == what  # its colour names its operation
        style = _dashes(ln)
        assert style in styles, name  # its line style is an entry (its criterion)
        crit = name.partition("[")[0] if "[" in name else "rebound (a stop)"
        assert styles[style] == crit
        told.add((what, crit))
    assert len(told) == 13  # each curve is told apart


def _beside(ax) -> bool:
    """Whether the axes' legend lies wholly beside (right of) the axes."""
    fig = ax.figure
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    return ax.get_legend().get_window_extent(renderer).x0 >= ax.get_window_extent(renderer).x1


def test_the_legends_stand_beside_the_curves(squeezed):
    fig, _ = squeezed
    assert _beside(fig.axes[2])
    mech = cm.Machine.from_toml(EXAMPLES / "stb_loom.toml").mechanisms["lifter cam"]
    sweep = mech.design.min_phase_angles(np.linspace(200.0, 500.0, 31), segments=[0, 1, 2])
    nominal = [mech.design.cam.segments[j].angle_deg for j in sweep.segments]
    ax = plot_min_phase_angles(sweep, nominal_deg=nominal)
    # the curves fill the plot between 400 and 500 rpm, where "best" put the legend
    assert _beside(ax)
    plt.close(ax.figure)
