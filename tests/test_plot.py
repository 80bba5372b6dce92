"""Tests of cyclomech.plot: what is drawn, not only that drawing does not fail; and
of the house of the plots (each domain's plot module, the facade that re-exports them,
doors that never import matplotlib)."""

from __future__ import annotations

import doctest
import importlib
import subprocess
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import cyclomech as cm
import cyclomech.plot as cplot
import matplotlib.pyplot as plt
import numpy as np
import pytest
from cyclomech.plot import plot_cyclogram, plot_cyclogram_pair
from matplotlib.collections import LineCollection, PathCollection
from matplotlib.colors import to_rgba
from numpy.testing import assert_allclose

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
RED = to_rgba(cplot.CRITICAL_COLOR)
ORANGE = to_rgba(cplot.LIMITING_COLOR)


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def stb() -> cm.Cyclogram:
    """Group 1 of the STB loom (illustrative angles), limited by weft insertion."""
    cg = cm.Cyclogram("STB group 1", limiting=("10.1", "10.2"))
    cg.add_operation("1", "3", 45, mechanism="microshuttle lifter", name="lift")
    cg.add_operation("3", "7", 20, mechanism="microshuttle lifter", name="dwell at stop")
    cg.add_operation("3", "2", 20, mechanism="lifter spring opener", name="open spring")
    cg.add_operation("1", "4", 55, 90, mechanism="weft returner", name="carry weft")
    cg.add_operation("2", "5", 15, mechanism="lifter spring opener", name="close on weft")
    cg.add_operation("4", "5", 5, mechanism="weft returner", name="wait")
    cg.add_operation("5", "6", 15, mechanism="returner spring opener", name="release weft")
    cg.add_operation("6", "8", 40, mechanism="weft returner", name="return")
    cg.add_operation("6", "10.1", 0, mechanism="weft returner")
    cg.add_operation("7", "10.1", 0, mechanism="microshuttle lifter")
    cg.add_operation("10.1", "10.2", 150, mechanism="weft insertion", name="weft insertion")
    cg.add_constraint({("3", "7"): -0.003}, "<=", 0.1 - 0.208, name="lifter rebound")
    return cg


STB_ROWS = [
    "microshuttle lifter",
    "lifter spring opener",
    "weft returner",
    "returner spring opener",
    "weft insertion",
]


def press() -> cm.Cyclogram:
    """A press: the ram returns across the end of the cycle (height 1) to the next stroke."""
    cg = cm.Cyclogram("press")
    cg.add_operation("1", "2", 90, mechanism="feeder", name="feed strip")
    cg.add_operation("2", "1", 150, mechanism="feeder", name="feeder return", height=1)
    cg.add_operation("2", "3", 100, mechanism="ram", name="press stroke")
    cg.add_operation("3", "4", 20, mechanism="ram", name="dwell")
    cg.add_operation("4", "2", 120, mechanism="ram", name="ram return", height=1)
    cg.add_operation("3", "5", 60, name="eject part")
    return cg


def late() -> cm.Cyclogram:
    """A chain longer than the cycle: the second operation runs from 300° past 360° to 40°."""
    cg = cm.Cyclogram("late")
    cg.add_operation("a", "b", 300, mechanism="m1", name="long")
    cg.add_operation("b", "c", 100, mechanism="m2", name="over the top")
    return cg


def bars(ax, label="operations"):
    """The rectangles of the bar container with this label."""
    (container,) = [c for c in ax.containers if c.get_label() == label]
    return list(container)


def whisker_segments(ax) -> list[np.ndarray]:
    (lc,) = [
        c
        for c in ax.collections
        if isinstance(c, LineCollection) and c.get_label() == "total slack"
    ]
    return lc.get_segments()


def expected_pieces(result) -> list[tuple[cm.Operation, float, float]]:
    """(operation, left, width) of every bar piece, computed independently of plot.py."""
    out = []
    C = result.cycle_deg
    for op in result.operations:
        s = result.times[op.src] % C
        a = result.angles[op.arc]
        if s + a > C + 1e-9:
            out += [(op, s, C - s), (op, 0.0, s + a - C)]
        else:
            out.append((op, s, a))
    return out


# ------------------------------------------------------------------ gantt
def test_gantt_schedule_bars_axes_and_rows():
    s = stb().schedule()
    ax = plot_cyclogram(s)
    rects = bars(ax)
    assert len(rects) == len(s.operations) == 11  # nothing wraps
    for r, (op, left, width) in zip(rects, expected_pieces(s), strict=True):
        assert_allclose([r.get_x(), r.get_width()], [left, width], atol=1e-9, err_msg=op.title)
    assert ax.get_xlim() == (0.0, 360.0)
    assert [t.get_text() for t in ax.get_yticklabels()] == STB_ROWS
    ticks = ax.get_xticks()
    assert_allclose(np.diff(ticks[(ticks >= 0) & (ticks <= 360)]), 30.0)
    assert ax.get_title() == "STB group 1 — duration 245°"


def test_rows_top_to_bottom_in_order_of_first_appearance():
    ax = plot_cyclogram(stb().schedule())
    ys = {t.get_text(): y for t, y in zip(ax.get_yticklabels(), ax.get_yticks(), strict=True)}
    bottom, top = ax.get_ylim()
    assert bottom > top  # y grows downwards: the first mechanism is on top
    assert [ys[m] for m in STB_ROWS] == sorted(ys.values())


def test_critical_bars_are_red_and_others_not():
    for result in (stb().schedule(), stb().optimize(), press().optimize()):
        ax = plot_cyclogram(result)
        crit = set(result.critical)
        assert crit
        for r, (op, _, _) in zip(bars(ax), expected_pieces(result), strict=True):
            assert (r.get_edgecolor() == RED) == (op.arc in crit), op.title
        legend = [t.get_text() for t in ax.get_legend().get_texts()]
        assert "critical" in legend


def test_wrap_past_360_is_two_pieces():
    s = late().schedule()
    ax = plot_cyclogram(s)
    rects = bars(ax)
    assert len(rects) == 3
    assert_allclose([(r.get_x(), r.get_width()) for r in rects[1:]], [(300, 60), (0, 40)])
    assert rects[1].get_y() == rects[2].get_y()  # one row
    assert "over the top" in {t.get_text().split(" 100°")[0] for t in ax.texts}


def test_height_one_operation_wraps_and_its_stretch_too():
    o = press().optimize()
    assert o.angles[("4", "2")] == pytest.approx(240.0)  # 210° → 90° of the next cycle
    ax = plot_cyclogram(o)
    rects = bars(ax)
    pieces = expected_pieces(o)
    assert len(rects) == len(pieces) == len(o.operations) + 1
    ram = [
        (r.get_x(), r.get_width())
        for r, (op, _, _) in zip(rects, pieces, strict=True)
        if op.name == "ram return"
    ]
    assert_allclose(ram, [(210, 150), (0, 90)])
    # Beyond the minimum of 120°: 330° → 360° and 0° → 90°.
    hatched = [(r.get_x(), r.get_width()) for r in bars(ax, "beyond minimum")]
    assert (330.0, 30.0) in [tuple(np.round(h, 9)) for h in hatched]
    assert (0.0, 90.0) in [tuple(np.round(h, 9)) for h in hatched]
    assert sum(w for _, w in hatched) == pytest.approx(sum(v for v in o.stretch.values()))
    assert ax.get_title() == "press — duration 250°"


def test_hatch_starts_at_the_minimum_in_force_when_given():
    # The loom's lifter operations sit on their mechanisms' bounds (undercut,
    # rebound, pressure angle) above the file's 20°: with the report's minimums
    # nothing of them is hatched; without, 7.06°, 10.03° and 15.40° would be.
    from cyclomech.machine import analyze

    r = analyze(cm.Machine.from_toml(EXAMPLES / "stb_loom.toml"), progress=False)
    o, ops = r.optimum, r.machine.cyclogram.operations
    floors = {op.arc: float(v) for op, v in zip(ops, r.minimums, strict=True)}
    want = sum(max(o.angles[a] - f, 0.0) for a, f in floors.items() if o.angles[a] - f > 1e-9)
    for kind in ("gantt", "circular"):
        ax = plot_cyclogram(o, kind=kind, minimums=floors)
        if kind == "gantt":
            got = sum(rect.get_width() for rect in bars(ax, "beyond minimum"))
            assert got == pytest.approx(want, abs=1e-9)
            plain = sum(rect.get_width() for rect in bars(plot_cyclogram(o), "beyond minimum"))
            assert plain == pytest.approx(want + 7.0579 + 10.0306 + 15.3982, abs=1e-3)
    plt.close("all")


def test_schedule_whiskers_have_the_slack_as_length():
    cg = cm.Cyclogram()
    cg.add_operation("1", "2", 40, mechanism="m", name="long")
    cg.add_operation("1", "3", 10, mechanism="n", name="a")
    cg.add_operation("3", "2", 10, mechanism="n", name="b")
    s = cg.schedule()
    assert s.slack[("1", "3")] == s.slack[("3", "2")] == 20.0
    ax = plot_cyclogram(s)
    segs = sorted((float(p[0, 0]), float(p[1, 0])) for p in whisker_segments(ax))
    assert segs == [(10.0, 30.0), (20.0, 40.0)]  # from each bar's end to end + slack
    ys = {float(p[0, 1]) for p in whisker_segments(ax)}
    assert len(ys) == 2  # overlapping whiskers of one lane are drawn one under the other
    bar_b = bars(ax)[2]
    assert all(y > bar_b.get_y() + bar_b.get_height() for y in ys)  # under the bars
    assert "total slack" in [t.get_text() for t in ax.get_legend().get_texts()]


def test_whisker_wraps_with_a_height_one_operation():
    s = press().schedule()
    ax = plot_cyclogram(s)
    segs = sorted(
        (round(float(p[0, 0]), 9), round(float(p[1, 0]), 9)) for p in whisker_segments(ax)
    )
    # dwell 210→250, feeder return 240→360, ram return 330→360 and on 0→90.
    assert segs == [(0.0, 90.0), (210.0, 250.0), (240.0, 360.0), (330.0, 360.0)]
    total = sum(v for v in s.slack.values() if v > 0)
    assert sum(b - a for a, b in segs) == pytest.approx(total)


def test_stb_whiskers_total_length():
    s = stb().schedule()
    ax = plot_cyclogram(s)
    length = sum(float(p[1, 0] - p[0, 0]) for p in whisker_segments(ax))
    # 7→10.1 (0°, at the end of "dwell at stop", same 30° of slack) is drawn once.
    total = sum(v for v in s.slack.values() if v > 0) - s.slack[("7", "10.1")]
    assert length == pytest.approx(total)


def test_optimum_stretch_limiting_colour_and_annotation():
    o = stb().optimize()
    ax = plot_cyclogram(o)
    hatched = bars(ax, "beyond minimum")
    assert sum(r.get_width() for r in hatched) == pytest.approx(
        sum(v for v in o.stretch.values() if v > 1e-9)
    )
    assert all(r.get_hatch() for r in hatched)
    for r, (op, _, _) in zip(bars(ax), expected_pieces(o), strict=True):
        assert (r.get_facecolor() == ORANGE) == (op.arc == o.limiting)
    assert ax.get_title() == "STB group 1 — weft insertion (limiting) gets 265°"
    assert "weft insertion 265°" in [t.get_text() for t in ax.texts]
    assert not [c for c in ax.collections if c.get_label() == "total slack"]


def test_zero_angle_operations_are_diamonds():
    s = stb().schedule()
    ax = plot_cyclogram(s)
    (marks,) = [c for c in ax.collections if isinstance(c, PathCollection)]
    assert_allclose(sorted(marks.get_offsets()[:, 0]), [65.0, 95.0])  # 7→10.1, 6→10.1
    edges = [tuple(e) for e in marks.get_edgecolors()]
    assert edges.count(RED) == 1  # 6→10.1 is critical, 7→10.1 is not


def test_operations_without_mechanism_go_to_other():
    ax = plot_cyclogram(press().schedule())
    assert [t.get_text() for t in ax.get_yticklabels()] == ["feeder", "ram", "(other)"]


def test_overlapping_operations_of_one_mechanism_get_lanes():
    cg = cm.Cyclogram()
    cg.add_operation("1", "2", 90, mechanism="m", name="x")
    cg.add_operation("1", "3", 60, mechanism="m", name="y")
    cg.add_operation("2", "4", 30, mechanism="m", name="z")
    ax = plot_cyclogram(cg.schedule())
    x, y, z = bars(ax)
    assert x.get_y() != y.get_y()  # both start at 0°
    assert z.get_y() == x.get_y()  # z starts where x ends: same lane
    assert [t.get_text() for t in ax.get_yticklabels()] == ["m"]


def test_labels_do_not_overlap():
    for result in (stb().schedule(), stb().optimize(), press().optimize()):
        ax = plot_cyclogram(result)
        fig = ax.figure
        fig.canvas.draw()
        boxes = [t.get_window_extent() for t in ax.texts]
        assert len(boxes) >= sum(a > 0 for a in result.angles.values())  # every bar labelled
        for i, a in enumerate(boxes):
            for b in boxes[i + 1 :]:
                assert not a.overlaps(b), (a, b)


def test_other_cycle_and_custom_title():
    cg = cm.Cyclogram(cycle_deg=720)
    cg.add_operation("1", "2", 500, mechanism="m")
    cg.add_operation("2", "3", 400, mechanism="m")
    ax = plot_cyclogram(cg.schedule(), title="two turns")
    assert ax.get_title() == "two turns"
    assert ax.get_xlim() == (0.0, 720.0)
    assert len(bars(ax)) == 3  # 500 → 900 wraps at 720°
    ticks = ax.get_xticks()
    assert_allclose(np.diff(ticks[(ticks >= 0) & (ticks <= 720)]), 90.0)


def test_ax_passed_in_is_returned():
    fig, ax = plt.subplots()
    assert plot_cyclogram(stb().schedule(), ax) is ax
    assert ax.figure is fig
    fig, polar = plt.subplots(subplot_kw={"projection": "polar"})
    assert plot_cyclogram(stb().optimize(), polar, kind="circular") is polar


# --------------------------------------------------------------- circular
def test_circular_is_polar_clockwise_from_the_top():
    o = stb().optimize()
    ax = plot_cyclogram(o, kind="circular")
    assert ax.name == "polar"
    assert ax.get_theta_direction() == -1
    assert ax.get_theta_offset() == pytest.approx(np.pi / 2)
    rects = bars(ax)
    assert len(rects) == len(o.operations)  # a polar bar wraps by itself
    for r, op in zip(rects, o.operations, strict=True):
        assert (r.get_edgecolor() == RED) == (op.arc in o.critical)
        assert r.get_width() == pytest.approx(np.deg2rad(o.angles[op.arc]))
    # One ring per mechanism, in order from the centre out.
    radii = [r.get_y() for r in rects]
    ring = {op.mechanism: y for op, y in zip(o.operations, radii, strict=True)}
    assert [ring[m] for m in STB_ROWS] == sorted(ring.values())
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert legend[: len(STB_ROWS)] == STB_ROWS
    assert ax.get_title() == "STB group 1 — weft insertion (limiting) gets 265°"


def test_circular_height_one_arc_runs_over_the_top():
    o = press().optimize()
    ax = plot_cyclogram(o, kind="circular")
    ram = bars(ax)[4]
    assert ram.get_x() == pytest.approx(np.deg2rad(210))
    assert ram.get_width() == pytest.approx(np.deg2rad(240))


def test_circular_needs_a_polar_axes():
    _, ax = plt.subplots()
    with pytest.raises(cm.InputError, match="polar"):
        plot_cyclogram(stb().schedule(), ax, kind="circular")
    assert ax.get_title() == "" and not ax.patches  # untouched


def test_bad_arguments():
    with pytest.raises(cm.InputError, match="kind"):
        plot_cyclogram(stb().schedule(), kind="pie")
    with pytest.raises(cm.InputError, match="Schedule"):
        plot_cyclogram(stb())  # the cyclogram, not a result


def test_pair():
    o = stb().optimize()
    fig = plot_cyclogram_pair(o)
    gantt, polar = fig.axes
    assert (gantt.name, polar.name) == ("rectilinear", "polar")
    assert fig.get_suptitle() == "STB group 1 — weft insertion (limiting) gets 265°"
    assert len(bars(gantt)) == len(bars(polar)) == len(o.operations)
    assert gantt.get_legend() is None  # one legend serves both
    legend = [t.get_text() for t in polar.get_legend().get_texts()]
    assert len(legend) == len(set(legend))
    assert {"critical", "limiting operation", "beyond minimum angle"} <= set(legend)
    fig = plot_cyclogram_pair(press().schedule(), title="press")
    assert fig.get_suptitle() == "press"
    assert "total slack" in [t.get_text() for t in fig.axes[1].get_legend().get_texts()]


def test_without_matplotlib(monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib.pyplot", None)
    with pytest.raises(ImportError, match=r"cyclomech\[plot\]"):
        plot_cyclogram(stb().schedule())


#: Every domain with its own plots (a ``<domain>/plot.py``), found, not listed.
DOMAINS = tuple(sorted(p.parent.name for p in Path(cm.__file__).parent.glob("*/plot.py")))


@pytest.mark.parametrize("module", ["cyclomech.plot", *(f"cyclomech.{d}.plot" for d in DOMAINS)])
def test_docstring_examples(module):
    result = doctest.testmod(importlib.import_module(module), optionflags=doctest.ELLIPSIS)
    assert result.attempted > 0
    assert result.failed == 0


def test_the_facade_re_exports_each_domains_plots_under_their_old_names():
    assert cplot.__all__ == [
        "animate_linkage",
        "plot_along_cycle",
        "plot_analogs",
        "plot_cam",
        "plot_crank_torque",
        "plot_cyclogram",
        "plot_cyclogram_pair",
        "plot_forces",
        "plot_law",
        "plot_linkage",
        "plot_min_phase",
        "plot_min_phase_angles",
        "plot_press",
        "plot_press_criteria",
        "plot_rebound_vs_speed",
        "plot_response",
        "plot_speed_sweep",
        "plot_svaj",
        "plot_transfer",
    ]
    homes = set()
    for name in cplot.__all__:
        f = getattr(cplot, name)
        # Defined in its domain (its plot module, or a private module beside it)
        # and exported by the domain's plot module.
        domain = f.__module__.split(".")[1]
        assert domain in DOMAINS, name
        home = importlib.import_module(f"cyclomech.{domain}.plot")
        assert name in home.__all__ and getattr(home, name) is f
        homes.add(home.__name__)
    assert homes == {f"cyclomech.{d}.plot" for d in DOMAINS}
    # Every domain plot module's public functions are in the facade.
    assert {n for d in DOMAINS for n in importlib.import_module(f"cyclomech.{d}.plot").__all__} == (
        set(cplot.__all__)
    )
    # The colours stay where they were.
    assert cplot.MECHANISM_COLORS[0] == "#9ecae1" and cplot.WORK_COLOR == "#f28e2b"
    assert cplot.CRITICAL_COLOR == "#d62728" and cplot.XY_COLORS == ("#1f77b4", "#d62728")


def test_import_cyclomech_and_its_plot_modules_needs_no_matplotlib():
    """No door imports a plot module or matplotlib; the plot modules import
    matplotlib only when they draw."""
    code = (
        "import sys\n"
        "sys.modules['matplotlib'] = None\n"
        "import cyclomech, cyclomech.plot\n"
        f"for d in {DOMAINS!r}:\n"
        "    __import__(f'cyclomech.{d}.plot')\n"
        "print('ok')\n"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
    assert run.returncode == 0 and run.stdout == "ok\n", run.stderr
    code = (
        "import sys, cyclomech\n"
        f"for d in {DOMAINS!r}:\n"
        "    __import__(f'cyclomech.{d}')\n"
        "print(sorted(m for m in sys.modules if m.endswith('plot') or 'matplotlib' in m))\n"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
    assert run.returncode == 0 and run.stdout == "[]\n", run.stdout + run.stderr


# ---------------------------------------------------------------------------
# The machine against speed


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
