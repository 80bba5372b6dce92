"""Tests of the linkage plots in cyclomech.plot: the artists carry the solution's
numbers, and every bad argument is an InputError that says what would be valid."""

from __future__ import annotations

import dataclasses
import math
import sys

import matplotlib

matplotlib.use("Agg")

import cyclomech as cm
import matplotlib.pyplot as plt
import numpy as np
import pytest
from cyclomech.linkage import presets
from cyclomech.plot import animate_linkage, plot_analogs, plot_linkage
from numpy.testing import assert_allclose, assert_array_equal

ANGLES = np.radians(np.arange(0.0, 361.0, 5.0))  # 73 angles, 0° … 360°


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def crank_rocker(name: str | None = None) -> cm.Linkage:
    return cm.Linkage(
        points={"A": (0, 0), "B": (1, 0), "C": (3.5, 2.5), "D": (4, 0)},
        links=[("A", "B"), ("B", "C"), ("C", "D")],
        ground=["A", "D"],
        driver=("A", "B"),
        name=name,
    )


def slider_crank() -> cm.Linkage:
    return cm.Linkage(
        {"A": (0, 0), "B": (0.1, 0), "C": (0.45, 0)},
        [("A", "B"), ("B", "C")],
        ["A"],
        ("A", "B"),
        sliders={"C": ("ground", (1, 0))},
    )


def short_rocker() -> cm.Linkage:
    """The crank is too long to turn: assembled only near 0° (ok False at 80°–280°)."""
    return cm.Linkage(
        {"A": (0, 0), "B": (2, 0), "C": (3, 1.5), "D": (3, 0)},
        [("A", "B"), ("B", "C"), ("C", "D")],
        ["A", "D"],
        ("A", "B"),
    )


def collection(ax, label):
    (c,) = [c for c in ax.collections if c.get_label() == label]
    return c


def line(ax, gid):
    (ln,) = [ln for ln in ax.get_lines() if ln.get_gid() == gid]
    return ln


def labels(ax) -> dict[str, object]:
    return {t.get_gid()[6:]: t for t in ax.texts if (t.get_gid() or "").startswith("label:")}


def pose(sol: cm.LinkageSolution, i: int) -> dict[str, np.ndarray]:
    return {p: sol.xy[i, k] for k, p in enumerate(sol.names)}


# ------------------------------------------------------------------ plot_linkage
@pytest.mark.parametrize("index", [0, 7, 40, 72, -1, np.int64(18)])
def test_crank_rocker_drawn_at_the_solution_row(index):
    lk = crank_rocker()
    sol = lk.solve(ANGLES)
    ax = plot_linkage(lk, sol, index)
    i = int(index) % len(ANGLES)
    at = pose(sol, i)
    segs = collection(ax, "links").get_segments()
    assert len(segs) == 3
    for seg, (a, b) in zip(segs, [("A", "B"), ("B", "C"), ("C", "D")], strict=True):
        assert_allclose(seg, [at[a], at[b]], atol=1e-12)
    driver = line(ax, "driver")
    assert_allclose(np.column_stack(driver.get_data()), [at["A"], at["B"]], atol=1e-12)
    assert_allclose(collection(ax, "joints").get_offsets(), sol.xy[i], atol=1e-12)
    text = labels(ax)
    assert sorted(text) == ["A", "B", "C", "D"]
    for p, t in text.items():
        assert t.get_text() == p
        assert_allclose(t.xy, at[p], atol=1e-12)  # anchored on its point (not a slider)
    assert ax.get_aspect() == 1.0
    assert ax.get_title() == f"Crank angle {round(math.degrees(ANGLES[i]))}°"
    assert ax.get_xlabel() == "x [m]" and ax.get_ylabel() == "y [m]"


def test_ground_symbols_under_the_ground_joints():
    lk = crank_rocker()
    sol = lk.solve(ANGLES)
    ax = plot_linkage(lk, sol, 3)
    tri = collection(ax, "ground").get_paths()
    assert len(tri) == 2
    for path, p in zip(tri, ["A", "D"], strict=True):
        v = path.vertices
        assert_allclose(v[0], sol[p][3], atol=1e-12)  # the apex on the pivot
        assert (v[1:3, 1] < v[0, 1]).all()  # the base under it
    hatch = collection(ax, "ground hatching").get_segments()
    assert len(hatch) == 2 * 7  # per pivot: the base and six hatch strokes
    assert all(seg[:, 1].max() < 0.0 for seg in hatch)


def test_frame_link_is_not_drawn():
    lk = cm.Linkage(
        {"A": (0, 0), "B": (1, 0), "C": (3.5, 2.5), "D": (4, 0)},
        [("A", "B"), ("B", "C"), ("C", "D"), ("A", "D")],
        ["A", "D"],
        ("A", "B"),
    )
    ax = plot_linkage(lk, lk.solve(ANGLES))
    assert len(collection(ax, "links").get_segments()) == 3


def test_trace_lines_are_the_paths():
    lk = crank_rocker("crank-rocker")
    sol = lk.solve(ANGLES)
    ax = plot_linkage(lk, sol, 10, trace=["B", "C"])
    for p in ("B", "C"):
        ln = line(ax, f"trace:{p}")
        assert ln.get_label() == f"trace:{p}"
        assert_array_equal(ln.get_xdata(), sol[p][:, 0])
        assert_array_equal(ln.get_ydata(), sol[p][:, 1])
    assert ax.get_title() == "crank-rocker — crank angle 50°"
    # A single name is one trace, not a list of characters.
    assert line(plot_linkage(lk, sol, trace="C"), "trace:C") is not None


def test_trace_breaks_where_not_assembled():
    lk = short_rocker()
    sol = lk.solve(ANGLES)
    assert not sol.ok.all() and sol.ok[2]
    ax = plot_linkage(lk, sol, 2, trace=["C"])
    ln = line(ax, "trace:C")
    assert_array_equal(ln.get_xdata(), sol["C"][:, 0])  # NaN where ok is False
    assert np.isnan(np.asarray(ln.get_xdata())[~sol.ok]).all()


def test_slider_crank_block_on_its_guide():
    lk = slider_crank()
    sol = lk.solve(ANGLES)
    ax = plot_linkage(lk, sol, 10)
    c = sol["C"][10]
    (block,) = collection(ax, "sliders").get_paths()
    corners = block.vertices[:4]
    assert_allclose(corners.mean(axis=0), c, atol=1e-12)  # centred on C
    sides = np.diff(np.vstack([corners, corners[:1]]), axis=0)
    assert abs(sides[0, 1]) < 1e-12 and abs(sides[0, 0]) > abs(sides[1, 1])  # long along x
    (guide,) = collection(ax, "guides").get_segments()
    assert_allclose(guide[:, 1], [0.0, 0.0], atol=1e-12)  # the frame's x axis through C
    travel = sol["C"][:, 0]
    assert guide[0, 0] < travel.min() and guide[1, 0] > travel.max()  # covers the stroke
    assert tuple(collection(ax, "guides").get_linestyle()[0][1]) != ()  # dashed
    assert_allclose(collection(ax, "joints").get_offsets(), sol.xy[10], atol=1e-12)
    assert len(collection(ax, "ground").get_paths()) == 1
    # C's label is set off the block, not on its point.
    label = labels(ax)["C"]
    assert np.hypot(*(np.asarray(label.xy) - c)) > 0.0


def test_block_on_a_link_guide_and_the_line_continued_to_it():
    lk = cm.Linkage(
        {"A": (0, 0), "B": (0, 0.1), "C": (0.3, 0), "D": (0.15, 0.05)},
        [("A", "B"), ("C", "D")],
        ["A", "C"],
        ("A", "B"),
        sliders={"B": ("link", ("C", "D"))},
    )
    sol = lk.solve(ANGLES)
    ax = plot_linkage(lk, sol, 0)
    at = pose(sol, 0)
    (block,) = collection(ax, "sliders").get_paths()
    assert_allclose(block.vertices[:4].mean(axis=0), at["B"], atol=1e-12)
    (ext,) = collection(ax, "guides").get_segments()  # B is beyond D on the line C–D
    assert_allclose(ext[0], at["D"], atol=1e-12)
    u = (at["D"] - at["C"]) / np.hypot(*(at["D"] - at["C"]))
    w = ext[1] - at["C"]
    assert abs(u[0] * w[1] - u[1] * w[0]) < 1e-12  # along the link's line
    assert (ext[1] - at["B"]) @ u > 0.0  # past the block


def test_burg_trimmer_ternary_link_is_a_plate():
    lk = presets.burg_trimmer()
    sol = lk.solve(ANGLES)
    ax = plot_linkage(lk, sol, 20, trace=["E"])
    at = pose(sol, 20)
    (plate,) = collection(ax, "plates").get_paths()
    corners = plate.vertices[:3]
    expected = np.array([at["B"], at["C"], at["E"]])
    assert_allclose(
        np.sort(corners.view("f8,f8"), axis=0).view("f8"),
        np.sort(expected.view("f8,f8"), axis=0).view("f8"),
        atol=1e-12,
    )
    segs = collection(ax, "links").get_segments()
    assert len(segs) == len(lk._links) == 5
    for seg, ln in zip(segs, lk._links, strict=True):
        if len(ln) == 2:
            assert_allclose(seg, [at[ln[0]], at[ln[1]]], atol=1e-12)
        else:  # the closed outline through the three joints
            assert len(seg) == 4
            assert_allclose(seg[0], seg[-1])
            assert_allclose(
                np.sort(seg[:3].view("f8,f8"), axis=0).view("f8"),
                np.sort(expected.view("f8,f8"), axis=0).view("f8"),
                atol=1e-12,
            )
    apexes = [p.vertices[0] for p in collection(ax, "ground").get_paths()]
    assert_allclose(apexes, [at["A"], at["D"], at["O"]], atol=1e-12)
    assert_allclose(np.column_stack(line(ax, "driver").get_data()), [at["O"], at["F"]])
    assert_array_equal(line(ax, "trace:E").get_ydata(), sol["E"][:, 1])
    assert ax.get_title() == "Burg trimmer — crank angle 100°"


@pytest.mark.parametrize("make", [crank_rocker, slider_crank, presets.burg_trimmer, presets.brp4])
def test_labels_do_not_overlap(make):
    lk = make()
    sol = lk.solve(np.radians(np.arange(0.0, 360.0, 30.0)))
    for i in range(len(sol.angles)):
        ax = plot_linkage(lk, sol, i)
        fig = ax.figure
        fig.canvas.draw()
        boxes = [t.get_window_extent() for t in labels(ax).values()]
        for a in range(len(boxes)):
            for b in range(a + 1, len(boxes)):
                assert not boxes[a].overlaps(boxes[b]), f"row {i}"
        # Every point is inside the axes.
        xmin, xmax = ax.get_xlim()
        ymin, ymax = ax.get_ylim()
        assert (sol.xy[i, :, 0] > xmin).all() and (sol.xy[i, :, 0] < xmax).all()
        assert (sol.xy[i, :, 1] > ymin).all() and (sol.xy[i, :, 1] < ymax).all()
        plt.close(fig)


def test_on_given_axes_with_title(tmp_path):
    lk = slider_crank()
    sol = lk.solve(ANGLES)
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
    assert plot_linkage(lk, sol, 0, ax=left, title="dead centre") is left
    assert plot_linkage(lk, sol, 36, ax=right) is right
    assert left.get_title() == "dead centre" and right.get_title() == "Crank angle 180°"
    fig.savefig(tmp_path / "pair.png")
    assert (tmp_path / "pair.png").stat().st_size > 0


def test_plot_linkage_bad_arguments():
    lk = crank_rocker()
    sol = lk.solve(ANGLES)
    with pytest.raises(cm.InputError, match=r"index = 73 is out of range.*0 … 72"):
        plot_linkage(lk, sol, 73)
    with pytest.raises(cm.InputError, match=r"index = -74 is out of range"):
        plot_linkage(lk, sol, -74)
    for bad in (1.0, True, "3", None):
        with pytest.raises(cm.InputError, match=r"index must be an integer.*got"):
            plot_linkage(lk, sol, bad)
    with pytest.raises(cm.InputError, match=r"trace: no point 'X'.*A, B, C, D"):
        plot_linkage(lk, sol, trace=["C", "X"])
    with pytest.raises(cm.InputError, match=r"trace must be a list"):
        plot_linkage(lk, sol, trace=3)
    part = lk.solve(ANGLES, points=["A", "C"])
    with pytest.raises(cm.InputError, match=r"lacks the point\(s\) B, D.*solve all points"):
        plot_linkage(lk, part)
    with pytest.raises(cm.InputError, match=r"must be a cyclomech.Linkage"):
        plot_linkage("crank", sol)
    with pytest.raises(cm.InputError, match=r"LinkageSolution.*got ndarray"):
        plot_linkage(lk, sol.xy)
    lengths = np.tile(lk.dimension_values, (2, 1))
    with pytest.raises(cm.InputError, match=r"sweep over 2 geometries"):
        plot_linkage(lk, cm.linkage.solve_geometries(lk, ANGLES, lengths))
    with pytest.raises(cm.InputError, match=r"must be a matplotlib Axes"):
        plot_linkage(lk, sol, ax="left")


def test_plot_linkage_where_it_cannot_be_assembled():
    lk = short_rocker()
    sol = lk.solve(ANGLES)
    i = 36  # 180°
    assert not sol.ok[i]
    with pytest.raises(
        cm.InputError,
        match=r"index = 36: the mechanism cannot be assembled at crank angle 180° "
        r"\(solution.ok\[36\] is False\).*first assembled row is index 0",
    ):
        plot_linkage(lk, sol, i)
    never = lk.solve([math.pi])
    with pytest.raises(cm.InputError, match=r"cannot be assembled at any angle"):
        plot_linkage(lk, never)


def test_errors_are_value_errors():
    lk = crank_rocker()
    with pytest.raises(ValueError):
        plot_linkage(lk, lk.solve(ANGLES), 100)


def test_without_matplotlib(monkeypatch):
    lk = crank_rocker()
    sol = lk.solve(ANGLES)
    monkeypatch.setitem(sys.modules, "matplotlib.pyplot", None)
    with pytest.raises(ImportError, match=r"cyclomech\[plot\]"):
        plot_linkage(lk, sol)
    with pytest.raises(ImportError, match=r"cyclomech\[plot\]"):
        plot_analogs(sol, "C")


# ------------------------------------------------------------------ plot_analogs
GIDS = (("x", "y"), ("dx/dφ", "dy/dφ"), ("d²x/dφ²", "d²y/dφ²"))


@pytest.mark.parametrize(
    ("make", "point"),
    [(crank_rocker, "C"), (slider_crank, "C"), (presets.burg_trimmer, "E")],
)
def test_analog_lines_are_the_solution_arrays(make, point):
    sol = make().solve(ANGLES)
    fig = plot_analogs(sol, point)
    assert len(fig.axes) == 3
    top, mid, bottom = fig.axes
    assert top.get_shared_x_axes().joined(top, bottom)
    assert mid.get_shared_x_axes().joined(mid, bottom)
    k = sol.index(point)
    for ax, arr, gids in zip(fig.axes, (sol.xy, sol.vel, sol.acc), GIDS, strict=True):
        for c, gid in enumerate(gids):
            ln = line(ax, gid)
            assert_allclose(ln.get_xdata(), np.degrees(sol.angles))
            assert_array_equal(ln.get_ydata(), arr[:, k, c])
    assert [ax.get_ylabel() for ax in fig.axes] == [
        "position [m]",
        "velocity analog [m/rad]",
        "acceleration analog [m/rad²]",
    ]
    assert bottom.get_xlabel() == "crank angle φ"
    assert bottom.get_xlim() == (0.0, 360.0)
    assert fig.get_suptitle() == f"Point {point}: position and analogs"
    assert not [p for ax in fig.axes for p in ax.patches if p.get_gid() == "not assembled"]


def test_analogs_in_order_of_the_angle():
    sol = crank_rocker().solve(np.radians([90.0, 0.0, 45.0, 180.0]))
    fig = plot_analogs(sol, "C", title="rocker tip")
    order = [1, 2, 0, 3]
    ln = line(fig.axes[2], "d²y/dφ²")
    assert_allclose(ln.get_xdata(), [0.0, 45.0, 90.0, 180.0])
    assert_array_equal(ln.get_ydata(), sol.acc[order, sol.index("C"), 1])
    assert fig.get_suptitle() == "rocker tip"


def test_analogs_shade_where_not_assembled():
    sol = short_rocker().solve(ANGLES)
    fig = plot_analogs(sol, "C")
    deg = np.degrees(sol.angles)
    for ax in fig.axes:
        spans = [p for p in ax.patches if p.get_gid() == "not assembled"]
        assert len(spans) == 1  # one run, 80° … 280°
        lo, hi = spans[0].get_x(), spans[0].get_x() + spans[0].get_width()
        assert ((deg[~sol.ok] >= lo) & (deg[~sol.ok] <= hi)).all()
        assert not ((deg[sol.ok] > lo) & (deg[sol.ok] < hi)).any()
    legend = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert legend == ["x", "y", "not assembled"]


def test_analogs_mark_dead_centres_and_branch_changes():
    sol = crank_rocker().solve(ANGLES)
    singular = np.zeros_like(sol.ok)
    singular[[12, 50]] = True
    branch = np.zeros_like(sol.ok)
    branch[30] = True
    marked = dataclasses.replace(sol, singular=singular, branch_change=branch)
    fig = plot_analogs(marked, "C")
    for ax in fig.axes:
        dead = [ln.get_xdata()[0] for ln in ax.get_lines() if ln.get_gid() == "singular"]
        changes = [ln.get_xdata()[0] for ln in ax.get_lines() if ln.get_gid() == "branch change"]
        assert_allclose(dead, [60.0, 250.0])
        assert_allclose(changes, [150.0])
    legend = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert legend == ["x", "y", "dead centre", "branch change"]


def test_analogs_with_nothing_assembled_still_draw(tmp_path):
    sol = short_rocker().solve(np.radians([150.0, 180.0, 210.0]))
    assert not sol.ok.any()
    fig = plot_analogs(sol, "C")
    fig.savefig(tmp_path / "none.png")
    assert len([p for p in fig.axes[0].patches if p.get_gid() == "not assembled"]) == 1


def test_plot_analogs_bad_arguments():
    lk = crank_rocker()
    with pytest.raises(cm.InputError, match=r"no analogs.*analogs=True"):
        plot_analogs(lk.solve(ANGLES, analogs=False), "C")
    with pytest.raises(cm.InputError, match=r"no point 'Z'.*A, B, C, D"):
        plot_analogs(lk.solve(ANGLES), "Z")
    lengths = np.tile(lk.dimension_values, (3, 1))
    with pytest.raises(cm.InputError, match=r"sweep over 3 geometries"):
        plot_analogs(cm.linkage.solve_geometries(lk, ANGLES, lengths), "C")
    with pytest.raises(cm.InputError, match=r"LinkageSolution"):
        plot_analogs(lk, "C")


# --------------------------------------------------------------- animate_linkage
def test_animation_has_one_frame_per_assembled_row(tmp_path):
    from PIL import Image

    lk = short_rocker()
    sol = lk.solve(np.radians(np.arange(0.0, 360.0, 10.0)))
    every = 3
    expected = int(sol.ok[::every].sum())
    assert 0 < expected < len(sol.angles[::every])
    path = animate_linkage(lk, sol, tmp_path / "rocker.gif", fps=20, trace=["C"], every=every)
    assert path == tmp_path / "rocker.gif"
    with Image.open(path) as im:
        assert im.format == "GIF"
        assert im.n_frames == expected
        assert im.info["duration"] == 50  # ms, 1/20 s
    assert not plt.get_fignums()  # its figure is closed


def test_animate_burg_trimmer(tmp_path):
    from PIL import Image

    lk = presets.burg_trimmer()
    sol = lk.solve(np.radians(np.arange(0.0, 360.0, 15.0)))
    path = animate_linkage(lk, sol, str(tmp_path / "burg.gif"), trace=["E"], dpi=50)
    with Image.open(path) as im:
        assert im.n_frames == 24


def test_animate_bad_arguments(tmp_path):
    lk = crank_rocker()
    sol = lk.solve(ANGLES)
    with pytest.raises(cm.InputError, match=r"must end in .gif"):
        animate_linkage(lk, sol, tmp_path / "a.png")
    with pytest.raises(cm.InputError, match=r"path must be a file name"):
        animate_linkage(lk, sol, 3)
    for every in (0, -1, 1.5, True):
        with pytest.raises(cm.InputError, match=r"every must be a positive integer"):
            animate_linkage(lk, sol, tmp_path / "a.gif", every=every)
    with pytest.raises(cm.InputError, match=r"fps must be a positive number"):
        animate_linkage(lk, sol, tmp_path / "a.gif", fps=0)
    with pytest.raises(cm.InputError, match=r"trace: no point 'Q'"):
        animate_linkage(lk, sol, tmp_path / "a.gif", trace=["Q"])
    never = short_rocker().solve(np.radians([150.0, 180.0]))
    with pytest.raises(cm.InputError, match=r"cannot be assembled at any of the 2 angles"):
        animate_linkage(short_rocker(), never, tmp_path / "a.gif")
    assert not (tmp_path / "a.gif").exists()
