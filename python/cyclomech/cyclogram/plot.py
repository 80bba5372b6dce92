"""Plots of a cyclogram: a Gantt chart over the cycle and a circular diagram.

:func:`plot_cyclogram` and :func:`plot_cyclogram_pair` take the result of
:meth:`cyclomech.Cyclogram.schedule` (a :class:`~cyclomech.cyclogram.Schedule`:
every operation at its minimum angle, with its total slack) or of
:meth:`cyclomech.Cyclogram.optimize` (an :class:`~cyclomech.cyclogram.Optimum`: the
optimised angles, the part of each beyond its minimum, the limiting operation).
Angles are degrees of main-shaft rotation, 0 to ``cycle_deg``; an operation that
runs past the end of the cycle (it crosses into the next one, ``height >= 1``, or
simply starts late) wraps round to 0°.

The artists are findable for tests and restyling: the operation bars are the
:class:`~matplotlib.container.BarContainer` labelled ``"operations"`` in
``ax.containers`` (one rectangle per piece of a bar, in the order of
``result.operations``; a bar that wraps is two pieces), the hatched parts beyond
the minimum angle the one labelled ``"beyond minimum"``, and the slack whiskers
the :class:`~matplotlib.collections.LineCollection` labelled ``"total slack"``.
A title is never cut short: one that fits neither on its bar nor beside it is
replaced there by a number, keyed with the whole title under "numbered
operations" (in the legend of a Gantt chart, beside the rings of a circular one).

matplotlib is an optional dependency (``pip install 'cyclomech[plot]'``), imported
only when a function draws; the functions draw on the axes they are given (or on a
new figure), return what they drew on, and never call ``plt.show()``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from .._errors import InputError
from .._plotting import CRITICAL_COLOR, deg_text, degree_ticks, halo, pyplot, tick_step
from . import Arc, Operation, Optimum, Schedule
from ._labels import fit_label, key_entries, key_legend, text_width_pt

if TYPE_CHECKING:
    from collections.abc import Callable, Mapping, Sequence

    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from matplotlib.projections.polar import PolarAxes

__all__ = ["plot_cyclogram", "plot_cyclogram_pair"]


#: Row name of the operations that belong to no mechanism.
OTHER_ROW = "(other)"
#: Face colour of the limiting operation of an :class:`Optimum`.
LIMITING_COLOR = "#ff7f0e"
#: Face colours of the mechanisms' rows, in order (light, so black labels stay legible;
#: no red or orange, which mark critical and limiting operations).
MECHANISM_COLORS = (
    "#9ecae1",
    "#a1d99b",
    "#c5b0d5",
    "#d9c3a5",
    "#9edae5",
    "#dbdb8d",
    "#c7c7c7",
    "#f7b6d2",
    "#bcbddc",
    "#c7e9c0",
)
_EDGE = "#404040"
_SLACK = "#303030"
_BAR_H = 0.62  # bar height as a fraction of a lane
_FONT = 7.5  # pt, bar labels


def _pieces(start: float, length: float, cycle: float) -> list[tuple[float, float]]:
    """Split the span [start, start + length] [deg] into (left, width) pieces inside
    [0, cycle]: a span past the end of the cycle continues from 0°."""
    eps = 1e-9 * cycle
    s = start % cycle
    if cycle - s <= eps:
        s = 0.0
    if length <= eps:
        return [(s, 0.0)]
    out = []
    left, pos = length, s
    while left > eps:
        w = min(left, cycle - pos)
        out.append((pos, w))
        left -= w
        pos = 0.0
    return out


@dataclass(frozen=True)
class _Bar:
    op: Operation
    row: int
    lane: int
    start: float  # p(src) [deg], reduced into [0, cycle)
    angle: float  # the operation's angle in this result [deg]
    minimum: float  # its minimum angle [deg]
    slack: float  # total slack of a Schedule [deg]; 0 for an Optimum
    critical: bool
    limiting: bool


@dataclass(frozen=True)
class _Layout:
    rows: tuple[str, ...]
    lanes: tuple[int, ...]  # lanes per row (operations of one mechanism that overlap)
    bars: tuple[_Bar, ...]
    cycle: float


def _overlap(p: tuple[float, float], q: tuple[float, float], eps: float) -> bool:
    (a1, w1), (a2, w2) = p, q
    b1, b2 = a1 + w1, a2 + w2
    if w1 > eps and w2 > eps:
        return max(a1, a2) < min(b1, b2) - eps
    if w1 <= eps and w2 <= eps:
        return abs(a1 - a2) <= eps
    s, (a, b) = (a1, (a2, b2)) if w1 <= eps else (a2, (a1, b1))
    return a + eps < s < b - eps


def _layout(result: Schedule | Optimum, minimums: Mapping[Arc, float] | None = None) -> _Layout:
    if not isinstance(result, Schedule | Optimum):
        raise InputError(
            "result must be a cyclomech.Schedule (Cyclogram.schedule()) or a cyclomech.Optimum "
            f"(Cyclogram.optimize()); got {type(result).__name__}"
        )
    cycle = float(result.cycle_deg)
    eps = 1e-9 * cycle
    critical = set(result.critical)
    limiting = result.limiting if isinstance(result, Optimum) else None
    rows: dict[str, int] = {}
    taken: dict[int, list[list[tuple[float, float]]]] = {}  # row -> lane -> pieces
    bars = []
    for op in result.operations:
        row = rows.setdefault(op.mechanism if op.mechanism is not None else OTHER_ROW, len(rows))
        start = float(result.times[op.src]) % cycle
        angle = float(result.angles[op.arc])
        if isinstance(result, Optimum):
            beyond = float(result.stretch[op.arc])
            if minimums is not None and op.arc in minimums:  # the bounds in force
                beyond = angle - float(minimums[op.arc])
            minimum, slack = angle - (beyond if beyond > eps else 0.0), 0.0
        else:
            minimum, slack = angle, float(result.slack[op.arc])
        pieces = _pieces(start, angle, cycle)
        lane = _first_free_lane(taken.setdefault(row, []), pieces, eps)
        bars.append(
            _Bar(
                op, row, lane, start, angle, minimum, slack, op.arc in critical, op.arc == limiting
            )
        )
    return _Layout(tuple(rows), tuple(len(taken[r]) for r in range(len(rows))), tuple(bars), cycle)


def _first_free_lane(
    lanes: list[list[tuple[float, float]]], pieces: list[tuple[float, float]], eps: float
) -> int:
    """The first lane in which ``pieces`` (start, width) [deg] overlap nothing; a
    new lane if none. The pieces are recorded in the lane chosen."""
    lane = next(
        (
            k
            for k, used in enumerate(lanes)
            if not any(_overlap(p, q, eps) for p in pieces for q in used)
        ),
        len(lanes),
    )
    if lane == len(lanes):
        lanes.append([])
    lanes[lane] += pieces
    return lane


def _default_title(result: Schedule | Optimum) -> str:
    head = "Cyclogram" if result.name == "cyclogram" else result.name
    if (
        isinstance(result, Optimum)
        and result.goal == "max_limiting"
        and result.limiting is not None
    ):
        op = next(o for o in result.operations if o.arc == result.limiting)
        return f"{head} — {op.title} (limiting) gets {deg_text(result.objective)}"
    return f"{head} — duration {deg_text(result.duration)}"


def _settle_layout(ax: Axes) -> None:
    """Let a layout engine (constrained layout) place the axes before text is fitted."""
    from matplotlib.figure import Figure

    root = getattr(ax.figure, "figure", ax.figure)  # a SubFigure's root figure
    if isinstance(root, Figure) and root.get_layout_engine() is not None:
        root.draw_without_rendering()


def plot_cyclogram(
    result: Schedule | Optimum,
    ax: Axes | None = None,
    *,
    kind: str = "gantt",
    title: str | None = None,
    minimums: Mapping[Arc, float] | None = None,
) -> Axes:
    """Draw a cyclogram (a Schedule or an Optimum) and return the axes.

    With ``kind="gantt"``: main-shaft angle [deg] from 0 to ``result.cycle_deg`` across,
    one row per mechanism (in order of first appearance; operations without one in
    a row ``"(other)"``), each operation a bar from p(src) to p(src) + angle,
    wrapped modulo the cycle (a bar past the end continues from 0°, as does an
    operation that ends in the next cycle). Operations of one mechanism that
    overlap share its row in separate lanes. Critical operations have a red edge.
    For a :class:`~cyclomech.cyclogram.Schedule` a whisker from a bar's end shows its
    total slack [deg]; for an :class:`~cyclomech.cyclogram.Optimum` the part of a bar
    beyond the operation's minimum angle is hatched and the limiting operation is
    orange, labelled with its angle.

    With ``kind="circular"``: the same on a polar axes, 0° at the top, angles
    clockwise, one ring per mechanism (from the centre out).

    Parameters
    ----------
    result : Schedule or Optimum
        The result of :meth:`~cyclomech.cyclogram.Cyclogram.schedule` or
        :meth:`~cyclomech.cyclogram.Cyclogram.optimize` (angles in degrees).
    ax : matplotlib.axes.Axes, optional
        The axes to draw on; None (default) makes a new figure. For
        ``kind="circular"`` it must be polar
        (``plt.subplots(subplot_kw={"projection": "polar"})``).
    kind : {"gantt", "circular"}, default "gantt"
        A Gantt chart over the cycle, or the circular diagram.
    title : str, optional
        The axes' title; default the duration of the group [deg], or the angle the
        limiting operation gets [deg].
    minimums : mapping of arc to float, optional
        Each operation's smallest angle [deg] where it is larger than its own
        minimum (a mechanism's bound in force, as the machine report's
        ``minimums``): the hatch of an Optimum starts there. Default: each
        operation's own minimum angle or duration.

    Returns
    -------
    matplotlib.axes.Axes
        The axes drawn on (polar for ``kind="circular"``).

    Raises
    ------
    InputError
        If ``result`` is neither a Schedule nor an Optimum, ``kind`` is unknown, or
        ``ax`` is not polar for ``kind="circular"``.
    ImportError
        If matplotlib is not installed.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> import cyclomech as cm
    >>> from cyclomech.cyclogram.plot import plot_cyclogram
    >>> cg = cm.Cyclogram()
    >>> cg.add_operation("1", "2", 40, mechanism="lifter", name="lift")
    >>> cg.add_operation("2", "3", 20, mechanism="lifter", name="dwell")
    >>> cg.add_operation("1", "3", 30, mechanism="gripper", name="close")
    >>> ax = plot_cyclogram(cg.schedule())
    >>> ax.get_title()
    'Cyclogram — duration 60°'
    >>> ax.get_xlim() == (0.0, 360.0), len(ax.containers[0])  # x in degrees; one bar per op
    (True, 3)
    >>> [t.get_text() for t in ax.get_yticklabels()]
    ['lifter', 'gripper']
    >>> polar = plot_cyclogram(cg.schedule(), kind="circular")
    >>> polar.name
    'polar'
    >>> plt.close("all")
    """
    plt = pyplot()
    if kind not in ("gantt", "circular"):
        raise InputError(f"kind must be 'gantt' or 'circular'; got {kind!r}")
    lay = _layout(result, minimums)
    if ax is not None and kind == "circular":
        _require_polar(ax)
    if ax is None:
        if kind == "gantt":
            _, ax = plt.subplots(figsize=_gantt_size(lay), layout="constrained")
        else:
            fig, ax = plt.subplots(
                figsize=(8.0, 6.4), layout="constrained", subplot_kw={"projection": "polar"}
            )
            # Constrained layout under-counts the angle labels round a polar axes.
            fig.get_layout_engine().set(w_pad=0.25, h_pad=0.1)
    ax.set_title(_default_title(result) if title is None else title)
    handles = _draw(ax, result, lay, kind)

    def legend(keyed: Sequence[tuple[int, str]] = ()) -> None:
        """The legend, then (a Gantt chart's) numbered titles under their heading."""
        more, titles = key_entries(keyed, heading=True)
        ax.legend(
            handles=[*handles, *more],
            labels=[*(h.get_label() for h in handles), *titles],
            loc="upper left",
            frameon=False,
            fontsize=8,
            **(_POLAR_LEGEND if kind == "circular" else {"bbox_to_anchor": (1.01, 1.0)}),
        )

    legend()
    _label(ax, lay, kind, legend)
    return ax


def plot_cyclogram_pair(result: Schedule | Optimum, *, title: str | None = None) -> Figure:
    """A figure with the Gantt chart (wide, left) and the circular diagram (right).

    Drawn as by :func:`plot_cyclogram`; one legend, right of the circle, serves
    both.

    Parameters
    ----------
    result : Schedule or Optimum
        The result of :meth:`~cyclomech.cyclogram.Cyclogram.schedule` or
        :meth:`~cyclomech.cyclogram.Cyclogram.optimize` (angles in degrees).
    title : str, optional
        The figure's title, above both; default the duration [deg] or the limiting
        operation's angle [deg].

    Returns
    -------
    matplotlib.figure.Figure
        The figure: the Gantt axes is ``fig.axes[0]``, the polar one
        ``fig.axes[1]``.

    Raises
    ------
    InputError
        If ``result`` is neither a Schedule nor an Optimum.
    ImportError
        If matplotlib is not installed.

    See Also
    --------
    plot_cyclogram : One of the two diagrams, on axes of your own.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> import cyclomech as cm
    >>> from cyclomech.cyclogram.plot import plot_cyclogram_pair
    >>> cg = cm.Cyclogram(limiting=("1", "2"))
    >>> cg.add_operation("1", "2", 40, mechanism="lifter", name="lift")
    >>> cg.add_operation("2", "1", 90, mechanism="lifter", name="return", height=1)
    >>> fig = plot_cyclogram_pair(cg.optimize())
    >>> fig.get_suptitle(), [a.name for a in fig.axes]
    ('Cyclogram — lift (limiting) gets 270°', ['rectilinear', 'polar'])
    >>> plt.close(fig)
    """
    plt = pyplot()
    lay = _layout(result)
    w, h = _gantt_size(lay)
    fig = plt.figure(figsize=(w + 6.5, max(h, 5.5)), layout="constrained")
    grid = fig.add_gridspec(1, 2, width_ratios=(w, 6.5))
    gantt = fig.add_subplot(grid[0, 0])
    polar = fig.add_subplot(grid[0, 1], projection="polar")
    fig.suptitle(_default_title(result) if title is None else title)
    handles = _draw(polar, result, lay, "circular")
    labels = {h.get_label() for h in handles}
    handles += [h for h in _draw(gantt, result, lay, "gantt") if h.get_label() not in labels]
    polar.legend(handles=handles, loc="upper left", frameon=False, fontsize=8, **_POLAR_LEGEND)
    where = {"loc": "upper left", "bbox_to_anchor": (1.01, 1.0), "frameon": False}
    _label(gantt, lay, "gantt", lambda keyed: key_legend(gantt, keyed, **where))
    _label(polar, lay, "circular")
    return fig


_POLAR_LEGEND: dict[str, Any] = {
    "bbox_to_anchor": (1.08, 1.0),
    "alignment": "left",
    "title": "rings, centre outwards",
    "title_fontsize": 8,
}


def _gantt_size(lay: _Layout) -> tuple[float, float]:
    """Figure size [in] of a Gantt chart: 0.42 in per lane, 0.15 in between rows."""
    return 11.0, 1.3 + 0.42 * sum(lay.lanes) + 0.15 * len(lay.rows)


def _draw(ax: Axes, result: Schedule | Optimum, lay: _Layout, kind: str) -> list[Any]:
    """Draw the bars and marks on ``ax``; return the legend handles."""
    if kind == "gantt":
        return _gantt(ax, result, lay)
    _require_polar(ax)
    return _circular(cast("PolarAxes", ax), result, lay)


def _require_polar(ax: Axes) -> None:
    if getattr(ax, "name", None) != "polar":
        raise InputError(
            "kind='circular' needs a polar axes, e.g. "
            "plt.subplots(subplot_kw={'projection': 'polar'}); "
            f"got a {getattr(ax, 'name', type(ax).__name__)!r} axes"
        )


def _zero_marks(ax: Axes, x: list[float], y: list[float], bars: list[_Bar]) -> Any:
    """Zero-angle operations (pure precedence links) as diamonds; None if there are none."""
    if not bars:
        return None
    from matplotlib.lines import Line2D

    ax.scatter(
        x,
        y,
        s=34.0,
        marker="D",
        zorder=5,
        label="zero-angle operations",
        c=[_face(b) for b in bars],
        edgecolors=[CRITICAL_COLOR if b.critical else _EDGE for b in bars],
        linewidths=[1.6 if b.critical else 0.7 for b in bars],
    )
    return Line2D(
        [],
        [],
        linestyle="none",
        marker="D",
        markersize=5.5,
        markerfacecolor="white",
        markeredgecolor=_EDGE,
        label="zero-angle operation",
    )


def _face(b: _Bar) -> str:
    return LIMITING_COLOR if b.limiting else MECHANISM_COLORS[b.row % len(MECHANISM_COLORS)]


_HATCH: dict[str, Any] = {
    "facecolor": (1.0, 1.0, 1.0, 0.45),
    "edgecolor": "#555555",
    "hatch": "////",
    "linewidth": 0.0,
}


# --------------------------------------------------------------------- gantt
def _lane_y(lay: _Layout) -> tuple[list[float], list[float]]:
    """Centre of each row's first lane and of each bar [y units, one per lane]."""
    base = [0.0]
    for n in lay.lanes:
        base.append(base[-1] + n + _ROW_GAP)
    return base, [base[b.row] + b.lane for b in lay.bars]


_ROW_GAP = 0.3  # extra space between mechanisms' rows [lanes]


def _gantt(ax: Axes, result: Schedule | Optimum, lay: _Layout) -> list[Any]:
    from matplotlib.collections import LineCollection
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    cycle = lay.cycle
    eps = 1e-9 * cycle
    base, y_of = _lane_y(lay)

    left, width, ys, face, edge, lw = [], [], [], [], [], []
    for b, y in zip(lay.bars, y_of, strict=True):
        for a, w in _pieces(b.start, b.angle, cycle):
            left.append(a)
            width.append(w)
            ys.append(y)
            face.append(_face(b))
            edge.append(CRITICAL_COLOR if b.critical else _EDGE)
            lw.append(0.0 if w <= eps else 2.0 if b.critical else 0.7)
    ax.barh(
        ys,
        width,
        height=_BAR_H,
        left=left,
        color=face,
        edgecolor=edge,
        linewidth=lw,
        label="operations",
        zorder=2,
    )

    handles: list[Any] = [
        Patch(facecolor="white", edgecolor=CRITICAL_COLOR, linewidth=2.0, label="critical")
    ]
    zero = [(b, y) for b, y in zip(lay.bars, y_of, strict=True) if b.angle <= eps]
    mark = _zero_marks(
        ax, [b.start for b, _ in zero], [y - _BAR_H / 2 for _, y in zero], [b for b, _ in zero]
    )
    if isinstance(result, Optimum):
        s_left, s_width, s_y = [], [], []
        for b, y in zip(lay.bars, y_of, strict=True):
            if b.angle - b.minimum > eps:
                for a, w in _pieces(b.start + b.minimum, b.angle - b.minimum, cycle):
                    s_left.append(a)
                    s_width.append(w)
                    s_y.append(y)
        ax.barh(
            s_y, s_width, height=_BAR_H, left=s_left, label="beyond minimum", zorder=2.5, **_HATCH
        )
        if s_y:
            handles.append(Patch(label="beyond minimum angle", **_HATCH))
        if result.limiting is not None:
            handles.append(
                Patch(
                    facecolor=LIMITING_COLOR,
                    edgecolor=_EDGE,
                    linewidth=0.7,
                    label="limiting operation",
                )
            )
    else:
        segs, caps = _whiskers(lay, y_of)
        ax.add_collection(
            LineCollection(segs, colors=_SLACK, linewidths=1.0, label="total slack", zorder=3)
        )
        ax.add_collection(
            LineCollection(caps, colors=_SLACK, linewidths=1.0, label="total slack caps", zorder=3)
        )
        if segs:
            handles.append(
                Line2D(
                    [],
                    [],
                    color=_SLACK,
                    linewidth=1.0,
                    marker="|",
                    markersize=6,
                    label="total slack",
                )
            )
    if mark is not None:
        handles.append(mark)
    if eps < result.duration < cycle - eps:
        ax.axvline(result.duration, color="0.35", linestyle="--", linewidth=0.9, zorder=1)
        handles.append(
            Line2D(
                [],
                [],
                color="0.35",
                linestyle="--",
                linewidth=0.9,
                label=f"group ends, {deg_text(result.duration)}",
            )
        )

    ax.set_xlim(0.0, cycle)
    degree_ticks(ax.xaxis, cycle)
    ax.set_xlabel("main-shaft angle")
    centres = [base[r] + (lay.lanes[r] - 1) / 2 for r in range(len(lay.rows))]
    ax.set_yticks(centres, labels=list(lay.rows))
    ax.tick_params(axis="y", length=0)
    ax.set_ylim(base[-1] - _ROW_GAP - 0.5 + _ROW_GAP / 2, -0.5 - _ROW_GAP / 2)  # first on top
    ax.grid(axis="x", color="0.88", linewidth=0.8)
    ax.set_axisbelow(True)
    for r in range(1, len(lay.rows)):
        ax.axhline(base[r] - 0.5 - _ROW_GAP / 2, color="0.8", linewidth=0.6, zorder=0)
    return handles


def _whiskers(lay: _Layout, y_of: list[float]) -> tuple[list[Any], list[Any]]:
    """Slack whiskers under the bars: the horizontal segments (end of the bar to end +
    slack, wrapped) and the ticks (down from the bar, across the whisker's end).
    Whiskers that would overlap in one lane go one level lower; identical ones (a
    zero-angle link ending where its predecessor does) are drawn once."""
    cycle = lay.cycle
    eps = 1e-9 * cycle
    segs: list[Any] = []
    caps: list[Any] = []
    levels: dict[float, list[list[tuple[float, float]]]] = {}
    seen: set[tuple[float, float, float]] = set()
    for b, y in zip(lay.bars, y_of, strict=True):
        if b.slack <= eps:
            continue
        key = (y, round((b.start + b.angle) % cycle, 9), round(b.slack, 9))
        if key in seen:
            continue
        seen.add(key)
        pieces = _pieces(b.start + b.angle, b.slack, cycle)
        k = _first_free_lane(levels.setdefault(y, []), pieces, eps)
        y_w = y + _BAR_H / 2 + 0.1 + 0.09 * k
        segs += [((a, y_w), (a + w, y_w)) for a, w in pieces]
        end = pieces[-1][0] + pieces[-1][1]
        caps += [
            ((pieces[0][0], y + _BAR_H / 2), (pieces[0][0], y_w)),
            ((end, y_w - 0.06), (end, y_w + 0.06)),
        ]
    return segs, caps


# ------------------------------------------------------------------ circular
_HOLE = 1.2  # radius of the empty centre [lanes], so that the inner rings are not slivers


def _ring_r(lay: _Layout) -> tuple[list[float], list[float]]:
    base = [_HOLE]
    for n in lay.lanes:
        base.append(base[-1] + n + _ROW_GAP)
    return base, [base[b.row] + b.lane + 0.5 for b in lay.bars]


def _circular(ax: PolarAxes, result: Schedule | Optimum, lay: _Layout) -> list[Any]:
    from matplotlib.patches import Patch

    cycle = lay.cycle
    eps = 1e-9 * cycle
    rad = 2.0 * np.pi / cycle  # radians per degree of the cycle
    base, r_of = _ring_r(lay)
    thick = _BAR_H + 0.1

    ax.set_theta_zero_location("N")
    ax.set_theta_direction(-1)
    theta = np.array([b.start for b in lay.bars]) * rad
    span = np.array([b.angle for b in lay.bars]) * rad
    ax.bar(
        theta,
        thick,
        width=span,
        bottom=np.array(r_of) - thick / 2,
        align="edge",
        color=[_face(b) for b in lay.bars],
        edgecolor=[CRITICAL_COLOR if b.critical else _EDGE for b in lay.bars],
        linewidth=[0.0 if b.angle <= eps else 2.0 if b.critical else 0.7 for b in lay.bars],
        label="operations",
        zorder=2,
    )
    only_limiting = [all(b.limiting for b in lay.bars if b.row == r) for r in range(len(lay.rows))]
    handles: list[Any] = [
        Patch(
            facecolor=LIMITING_COLOR
            if only_limiting[r]
            else MECHANISM_COLORS[r % len(MECHANISM_COLORS)],
            edgecolor=_EDGE,
            linewidth=0.7,
            label=name,
        )
        for r, name in enumerate(lay.rows)
    ]
    handles.append(
        Patch(facecolor="white", edgecolor=CRITICAL_COLOR, linewidth=2.0, label="critical")
    )
    if isinstance(result, Optimum):
        over = [(b, r) for b, r in zip(lay.bars, r_of, strict=True) if b.angle - b.minimum > eps]
        ax.bar(
            [(b.start + b.minimum) * rad for b, _ in over],
            thick,
            width=[(b.angle - b.minimum) * rad for b, _ in over],
            bottom=[r - thick / 2 for _, r in over],
            align="edge",
            label="beyond minimum",
            zorder=2.5,
            **_HATCH,
        )
        if over:
            handles.append(Patch(label="beyond minimum angle", **_HATCH))
        if result.limiting is not None:
            handles.append(
                Patch(
                    facecolor=LIMITING_COLOR,
                    edgecolor=_EDGE,
                    linewidth=0.7,
                    label="limiting operation",
                )
            )
    zero = [(b, r) for b, r in zip(lay.bars, r_of, strict=True) if b.angle <= eps]
    mark = _zero_marks(
        ax, [b.start * rad for b, _ in zero], [r + thick / 2 for _, r in zero], [b for b, _ in zero]
    )
    if mark is not None:
        handles.append(mark)

    step = tick_step(cycle)
    ticks = np.arange(0.0, cycle - eps, step)
    ax.set_xticks(ticks * rad, labels=[deg_text(t) for t in ticks], fontsize=8)
    ax.set_ylim(0.0, base[-1])
    ax.set_yticks([r - _ROW_GAP / 2 for r in base[1:-1]], labels=[])  # circles between rings
    ax.grid(color="0.85", linewidth=0.6)
    ax.set_axisbelow(True)
    ax.spines["polar"].set_color("0.6")
    return handles


# -------------------------------------------------------------------- labels
def _label_gantt(
    ax: Axes, lay: _Layout, key: Callable[[list[tuple[int, str]]], Any] | None = None
) -> None:
    """Label each bar inside if its title fits, else beside it where its lane is free
    (on one or two lines, as inside), else with a number keyed by ``key`` (called
    with the numbered titles; the limiting operation's title goes above its bar
    instead); zero-angle operations (diamonds) are not labelled. A label is never
    cut short. The key takes room from the axes, which can number more bars: the
    plan is made again until the numbered bars stay the same."""
    keyed: list[int] = []  # bars numbered, in the order of their numbers
    while True:
        _settle_layout(ax)
        fig = ax.figure
        pt_x = ax.bbox.width * 72.0 / fig.dpi  # axes size [pt]
        pt_y = ax.bbox.height * 72.0 / fig.dpi
        n = len(keyed)
        plan = _gantt_plan(ax, lay, pt_x / lay.cycle, pt_y, keyed)
        if len(keyed) == n or key is None:
            break
        key([(i + 1, lay.bars[i].op.title) for i in keyed])
    for method, args, kw in plan:
        getattr(ax, method)(*args, **kw)


def _gantt_plan(
    ax: Axes, lay: _Layout, pt_per_deg: float, pt_y: float, keyed: list[int]
) -> list[tuple[str, tuple[Any, ...], dict[str, Any]]]:
    """The labels of :func:`_label_gantt` as ``(ax method, args, kwargs)``; a bar in
    ``keyed`` keeps its number, a bar newly numbered is appended to it."""
    cycle = lay.cycle
    eps = 1e-9 * cycle
    _, y_of = _lane_y(lay)
    y0, y1 = ax.get_ylim()
    bar_h = _BAR_H * pt_y / abs(y0 - y1) - 1.0
    lane_pieces: dict[float, list[tuple[float, float]]] = {}
    for b, y in zip(lay.bars, y_of, strict=True):
        if b.angle > eps:
            lane_pieces.setdefault(y, []).extend(_pieces(b.start, b.angle, cycle))
    gap = 1.5 / pt_per_deg  # 1.5 pt between a bar and a label beside it [deg]
    plan: list[tuple[str, tuple[Any, ...], dict[str, Any]]] = []
    for i, (b, y) in enumerate(zip(lay.bars, y_of, strict=True)):
        if b.angle <= eps:
            continue
        pieces = _pieces(b.start, b.angle, cycle)
        a, w = max(pieces, key=lambda p: p[1])  # the title goes on the longest piece
        style: dict[str, Any] = {
            "fontsize": _FONT,
            "path_effects": halo(),
            "zorder": 4,
            "fontweight": "bold" if b.limiting else "normal",
            "va": "center",
            "multialignment": "center",
            "clip_on": True,
        }
        others = [p for p in lane_pieces[y] if p != (a, w)]
        right = min([p[0] for p in others if p[0] >= a + w - eps], default=cycle) - (a + w)
        left = a - max([p[0] + p[1] for p in others if p[0] + p[1] <= a + eps], default=0.0)
        spots = [
            (a + w / 2, "center", w * pt_per_deg - 4.0),
            (a + w + gap, "left", (right - 3 * gap) * pt_per_deg),
            (a - gap, "right", (left - 3 * gap) * pt_per_deg),
        ]

        def place(title: str, angle: str | None) -> tuple[float, str, str] | None:
            for x, ha, room in spots:  # noqa: B023 (called at once, in this iteration)
                text = fit_label(title, angle, room, bar_h, _FONT, b.limiting)  # noqa: B023
                if text is not None:
                    return x, ha, text
            return None

        angle = deg_text(b.angle)
        got = None if i in keyed else place(b.op.title, angle)
        name = b.op.title
        if got is None and b.limiting and i not in keyed:
            del style["va"], style["clip_on"]
            xy = (a + w / 2, y - _BAR_H / 2)
            arrow = {"arrowstyle": "-", "color": _EDGE, "linewidth": 0.7}
            kw = {"xytext": (0, 6), "textcoords": "offset points", "va": "bottom"}
            plan.append(
                (
                    "annotate",
                    (f"{b.op.title} {angle}", xy),
                    {**kw, "ha": "center", "arrowprops": arrow, **style},
                )
            )
            continue
        if got is None:
            name = str(i + 1)  # its position in the cyclogram, as on the circular diagram
            got = place(name, None)
            if got is None:
                continue  # a bar too short to hold even its number stays bare
            if i not in keyed:
                keyed.append(i)
        plan.append(("text", (got[0], y, got[2]), {"ha": got[1], **style}))
        for a2, w2 in pieces:  # the other pieces of a wrapped bar say whose they are
            room = w2 * pt_per_deg - 4.0
            cont = fit_label(f"… {name}", None, room, bar_h, _FONT, b.limiting, lines=1)
            if (a2, w2) != (a, w) and cont is not None:
                plan.append(("text", (a2 + w2 / 2, y, cont), {"ha": "center", **style}))
    return plan


def _label(
    ax: Axes, lay: _Layout, kind: str, key: Callable[[list[tuple[int, str]]], Any] | None = None
) -> None:
    """Write the operations' titles (and angles) on the bars where they fit; the
    limiting operation's, in bold, always (above its bar on a Gantt chart if need be).
    A title that does not fit gets a number, keyed beside the axes (a Gantt chart's
    by ``key``, called with the numbered titles).

    Text is fitted to the axes as laid out, so this runs after everything else."""
    if kind == "gantt":
        _label_gantt(ax, lay, key)
        return
    # The key takes room from the axes: label again until the numbered titles stay.
    before, keyed = list(ax.texts), None
    for _ in range(4):
        _settle_layout(ax)
        for text in [t for t in ax.texts if t not in before]:
            text.remove()
        now = _label_circular(ax, lay)
        if now == keyed:
            break
        key_legend(ax, now, loc="lower left", bbox_to_anchor=(1.08, 0.0))
        keyed = now
        if not now:
            break


def _label_circular(ax: Axes, lay: _Layout) -> list[tuple[int, str]]:
    """Label the rings' bars (:func:`_label`); return the numbered (number, title)."""
    fig = ax.figure
    pt_x = ax.bbox.width * 72.0 / fig.dpi  # axes size [pt]
    pt_y = ax.bbox.height * 72.0 / fig.dpi
    cycle = lay.cycle
    base, r_of = _ring_r(lay)
    radius_pt = min(pt_x, pt_y) / 2  # of the outer circle, r = base[-1]
    size = _FONT - 0.5
    thick = (_BAR_H + 0.1) * radius_pt / base[-1]
    # A title that does not fit whole on its bar gets a number there, and the
    # numbers are keyed beside the rings: a name is never cut short.
    keyed: list[tuple[int, str]] = []
    for i, (b, r) in enumerate(zip(lay.bars, r_of, strict=True)):
        arc_pt = b.angle / cycle * 2.0 * math.pi * r / base[-1] * radius_pt
        # A chord is shorter than its arc: leave room for straight text on a curved bar.
        text = fit_label(
            b.op.title,
            deg_text(b.angle) if b.limiting else None,
            0.85 * arc_pt - 4.0,
            thick - 1.0,
            size,
            bold=b.limiting,
        )
        if text is None:
            # Its number is its position in the cyclogram, as on the Gantt chart.
            if 0.85 * arc_pt - 2.0 < text_width_pt(str(i + 1), size):
                continue  # a bar too short to hold even its number stays bare
            keyed.append((i + 1, b.op.title))
            text = str(i + 1)
        mid = b.start + b.angle / 2
        rot = (-mid * 360.0 / cycle) % 360.0  # the tangent, in display degrees
        if 90.0 < rot <= 270.0:
            rot -= 180.0  # never upside down
        ax.text(
            mid / cycle * 2.0 * math.pi,
            r,
            text,
            rotation=rot,
            rotation_mode="anchor",
            ha="center",
            va="center",
            multialignment="center",
            fontsize=size,
            fontweight="bold" if b.limiting else "normal",
            path_effects=halo(),
            zorder=4,
            gid=f"key:{i + 1}" if keyed and keyed[-1][0] == i + 1 and text == str(i + 1) else None,
        )
    return keyed
