"""Plots of a cyclogram (a Gantt chart over the cycle and a circular diagram), of
a linkage (the mechanism at one crank angle, the paths of its points, the position
and analogs of a point over the crank turn, an animated GIF), of motion laws and of
the gear-lever press (the mechanism with its pin's path, the slider's motion, maps
of the working-stroke criteria and the non-dominated designs).

Cyclograms: :func:`plot_cyclogram` and :func:`plot_cyclogram_pair` take the result
of :meth:`cyclomech.Cyclogram.schedule` (a :class:`Schedule`:
every operation at its minimum angle, with its total slack) or of
:meth:`cyclomech.Cyclogram.optimize` (an :class:`Optimum`: the optimised angles, the
part of each beyond its minimum, the limiting operation). Angles are degrees of
main-shaft rotation, 0 to ``cycle_deg``; an operation that runs past the end of
the cycle (it crosses into the next one, ``height >= 1``, or simply starts late)
wraps round to 0°.

Linkages: :func:`plot_linkage`, :func:`plot_analogs` and :func:`animate_linkage`
take a :class:`cyclomech.Linkage` and the :class:`~cyclomech.linkage.LinkageSolution`
of :meth:`~cyclomech.Linkage.solve` (lengths in metres, crank angles shown in
degrees).

Motion laws and presses: :func:`plot_law` takes a :class:`cyclomech.motion.MotionLaw`
or a :class:`~cyclomech.motion.TwoPeriodLaw`, :func:`plot_press` a
:class:`cyclomech.press.GearLeverPress` and a crank angle α [rad] from BDC, and
:func:`plot_press_criteria` a :class:`~cyclomech.press.PressGrid` (with, optionally,
a :class:`~cyclomech.press.PressOptimum`). They show lengths in millimetres and
angles in degrees.

matplotlib is an optional dependency: ``pip install 'cyclomech[plot]'``. The
functions draw on the axes they are given (or on a new figure), return what they
drew on, and never call ``plt.show()``.

The artists are findable for tests and restyling: the operation bars are the
:class:`~matplotlib.container.BarContainer` labelled ``"operations"`` in
``ax.containers`` (one rectangle per piece of a bar, in the order of
``result.operations``; a bar that wraps is two pieces), the hatched parts beyond
the minimum angle the one labelled ``"beyond minimum"``, and the slack whiskers
the :class:`~matplotlib.collections.LineCollection` labelled ``"total slack"``.
The artists of a linkage drawing are listed in :func:`plot_linkage` and
:func:`plot_analogs`.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

import numpy as np
import numpy.typing as npt

from ._errors import InputError
from .cyclogram import Operation, Optimum, Schedule
from .linkage import Linkage, LinkageSolution
from .motion import MotionLaw, TwoPeriodLaw
from .press import GearLeverPress, PressGrid, PressOptimum

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from matplotlib.projections.polar import PolarAxes

__all__ = [
    "animate_linkage",
    "plot_analogs",
    "plot_cyclogram",
    "plot_cyclogram_pair",
    "plot_law",
    "plot_linkage",
    "plot_min_phase",
    "plot_press",
    "plot_press_criteria",
    "plot_rebound_vs_speed",
    "plot_response",
    "plot_speed_sweep",
    "plot_transfer",
]

#: Row name of the operations that belong to no mechanism.
OTHER_ROW = "(other)"
#: Edge colour of critical operations (zero slack / held at their minimum by a priced bound).
CRITICAL_COLOR = "#d62728"
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


def _matplotlib() -> Any:
    try:
        import matplotlib.pyplot as plt
    except ImportError as e:  # pragma: no cover - exercised only without matplotlib
        raise ImportError(
            "cyclomech's plots need matplotlib; install cyclomech[plot] "
            "(pip install 'cyclomech[plot]')"
        ) from e
    return plt


def _deg(x: float) -> str:
    """An angle as text, at most one decimal: 245°, 36.5°."""
    r = round(float(x), 1) + 0.0  # + 0.0 turns -0.0 into 0.0
    return f"{r:.1f}".rstrip("0").rstrip(".") + "°"


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


def _layout(result: Schedule | Optimum) -> _Layout:
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
            stretch = float(result.stretch[op.arc])
            minimum, slack = angle - (stretch if stretch > eps else 0.0), 0.0
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
        return f"{head} — {op.title} (limiting) gets {_deg(result.objective)}"
    return f"{head} — duration {_deg(result.duration)}"


def _tick_step(cycle: float) -> float:
    """30° on a 360° cycle; in general the smallest of 5, 10, 15, 30, 45, 90, … [deg]
    that leaves at most 12 intervals."""
    for step in (5.0, 10.0, 15.0, 30.0, 45.0, 90.0, 180.0):
        if cycle / step <= 12.0 + 1e-9:
            return step
    return 90.0 * 2.0 ** math.ceil(math.log2(cycle / (90.0 * 12.0)))


def _text_width_pt(text: str, size: float, bold: bool = False) -> float:
    """Width [pt] of one line of text at ``size`` pt in the default font."""
    from matplotlib.font_manager import FontProperties
    from matplotlib.textpath import TextPath

    prop = FontProperties(size=size, weight="bold" if bold else "normal")
    return float(TextPath((0, 0), text, prop=prop).get_extents().width)


def _two_lines(text: str) -> str | None:
    """``text`` broken at the space nearest its middle, or None without a space."""
    spaces = [i for i, c in enumerate(text) if c == " "]
    if not spaces:
        return None
    k = min(spaces, key=lambda i: abs(2 * i - len(text)))
    return text[:k] + "\n" + text[k + 1 :]


def _candidates(title: str, angle: str | None) -> list[str]:
    """Labels from the most to the least informative: title and angle, on one or two
    lines, then the title alone, on one or two lines."""
    out = [] if angle is None else [f"{title} {angle}", f"{title}\n{angle}"]
    out.append(title)
    wrapped = _two_lines(title)
    if wrapped is not None:
        out.append(wrapped)
    return out


def _fit_label(
    title: str,
    angle: str | None,
    width_pt: float,
    height_pt: float,
    size: float,
    bold: bool = False,
    *,
    truncate: bool = True,
    lines: int = 2,
) -> str | None:
    """The first of :func:`_candidates` (of at most ``lines`` lines) that fits in a box
    ``width_pt`` × ``height_pt``, else (with ``truncate``) the title cut short with
    an ellipsis, else None."""
    line_pt = 1.2 * size
    for text in _candidates(title, angle):
        rows = text.split("\n")
        if len(rows) > lines or len(rows) * line_pt > height_pt:
            continue
        if max(_text_width_pt(row, size, bold) for row in rows) <= width_pt:
            return text
    if not truncate or line_pt > height_pt:
        return None
    for n in range(len(title) - 1, 2, -1):
        cut = title[:n].rstrip() + "…"
        if _text_width_pt(cut, size, bold) <= width_pt:
            return cut
    return None


def _halo() -> list[Any]:
    """A faint white outline that keeps labels legible over hatching and edges."""
    from matplotlib import patheffects

    return [patheffects.withStroke(linewidth=2.0, foreground=(1.0, 1.0, 1.0, 0.75))]


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
) -> Axes:
    """Draw a cyclogram (a :class:`Schedule` or an :class:`Optimum`) and return the axes.

    ``kind="gantt"``: main-shaft angle [deg] from 0 to ``result.cycle_deg`` across,
    one row per mechanism (in order of first appearance; operations without one in
    a row ``"(other)"``), each operation a bar from p(src) to p(src) + angle,
    wrapped modulo the cycle (a bar past the end continues from 0°, as does an
    operation that ends in the next cycle). Operations of one mechanism that
    overlap share its row in separate lanes. Critical operations have a red edge.
    For a :class:`Schedule` a whisker from a bar's end shows its total slack [deg];
    for an :class:`Optimum` the part of a bar beyond the operation's minimum angle
    is hatched and the limiting operation is orange, labelled with its angle.

    ``kind="circular"``: the same on a polar axes, 0° at the top, angles clockwise,
    one ring per mechanism (from the centre out). ``ax`` must then be polar
    (``plt.subplots(subplot_kw={"projection": "polar"})``).

    With ``ax=None`` a new figure is made. ``title`` defaults to the duration of the
    group, or to the angle the limiting operation gets.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> import cyclomech as cm
    >>> from cyclomech.plot import plot_cyclogram
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
    plt = _matplotlib()
    if kind not in ("gantt", "circular"):
        raise InputError(f"kind must be 'gantt' or 'circular'; got {kind!r}")
    lay = _layout(result)
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
    ax.legend(
        handles=handles,
        loc="upper left",
        frameon=False,
        fontsize=8,
        **(_POLAR_LEGEND if kind == "circular" else {"bbox_to_anchor": (1.01, 1.0)}),
    )
    _label(ax, lay, kind)
    return ax


def plot_cyclogram_pair(result: Schedule | Optimum, *, title: str | None = None) -> Figure:
    """A figure with the Gantt chart (wide, left) and the circular diagram (right).

    See :func:`plot_cyclogram`; ``title`` (default: the duration or the limiting
    operation's angle) goes above both, and one legend, right of the circle, serves
    both. The Gantt axes is ``fig.axes[0]``, the polar one ``fig.axes[1]``.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> import cyclomech as cm
    >>> from cyclomech.plot import plot_cyclogram_pair
    >>> cg = cm.Cyclogram(limiting=("1", "2"))
    >>> cg.add_operation("1", "2", 40, mechanism="lifter", name="lift")
    >>> cg.add_operation("2", "1", 90, mechanism="lifter", name="return", height=1)
    >>> fig = plot_cyclogram_pair(cg.optimize())
    >>> fig.get_suptitle(), [a.name for a in fig.axes]
    ('Cyclogram — lift (limiting) gets 270°', ['rectilinear', 'polar'])
    >>> plt.close(fig)
    """
    plt = _matplotlib()
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
    _label(gantt, lay, "gantt")
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
    from matplotlib.ticker import FuncFormatter, MultipleLocator

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
                label=f"group ends, {_deg(result.duration)}",
            )
        )

    ax.set_xlim(0.0, cycle)
    ax.xaxis.set_major_locator(MultipleLocator(_tick_step(cycle)))
    ax.xaxis.set_major_formatter(FuncFormatter(lambda x, _pos: _deg(x)))
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
    import numpy as np
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

    step = _tick_step(cycle)
    ticks = np.arange(0.0, cycle - eps, step)
    ax.set_xticks(ticks * rad, labels=[_deg(t) for t in ticks], fontsize=8)
    ax.set_ylim(0.0, base[-1])
    ax.set_yticks([r - _ROW_GAP / 2 for r in base[1:-1]], labels=[])  # circles between rings
    ax.grid(color="0.85", linewidth=0.6)
    ax.set_axisbelow(True)
    ax.spines["polar"].set_color("0.6")
    return handles


# -------------------------------------------------------------------- labels
def _label_gantt(ax: Axes, lay: _Layout, pt_per_deg: float, pt_y: float) -> None:
    """Label each bar inside if its title fits, else beside it where its lane is free
    (on one or two lines, as inside), else inside cut short; zero-angle operations
    (diamonds) are not labelled."""
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
    for b, y in zip(lay.bars, y_of, strict=True):
        if b.angle <= eps:
            continue
        pieces = _pieces(b.start, b.angle, cycle)
        a, w = max(pieces, key=lambda p: p[1])  # the title goes on the longest piece
        style: dict[str, Any] = {
            "fontsize": _FONT,
            "path_effects": _halo(),
            "zorder": 4,
            "fontweight": "bold" if b.limiting else "normal",
            "va": "center",
            "multialignment": "center",
            "clip_on": True,
        }
        for a2, w2 in pieces:  # the other pieces of a wrapped bar say whose they are
            cont = _fit_label(
                f"… {b.op.title}",
                None,
                w2 * pt_per_deg - 4.0,
                bar_h,
                _FONT,
                b.limiting,
                truncate=False,
                lines=1,
            )
            if (a2, w2) != (a, w) and cont is not None:
                ax.text(a2 + w2 / 2, y, cont, ha="center", **style)
        angle = _deg(b.angle)
        text = _fit_label(
            b.op.title, angle, w * pt_per_deg - 4.0, bar_h, _FONT, b.limiting, truncate=False
        )
        if text is not None:
            ax.text(a + w / 2, y, text, ha="center", **style)
            continue
        others = [p for p in lane_pieces[y] if p != (a, w)]
        right = min([p[0] for p in others if p[0] >= a + w - eps], default=cycle) - (a + w)
        left = a - max([p[0] + p[1] for p in others if p[0] + p[1] <= a + eps], default=0.0)
        for room, x, ha in ((right, a + w + gap, "left"), (left, a - gap, "right")):
            text = _fit_label(
                b.op.title,
                angle,
                (room - 3 * gap) * pt_per_deg,
                bar_h,
                _FONT,
                b.limiting,
                truncate=False,
            )
            if text is not None:
                ax.text(x, y, text, ha=ha, **style)
                break
        else:
            text = _fit_label(b.op.title, angle, w * pt_per_deg - 4.0, bar_h, _FONT, b.limiting)
            if text is not None:
                ax.text(a + w / 2, y, text, ha="center", **style)
            elif b.limiting:
                del style["va"], style["clip_on"]
                ax.annotate(
                    f"{b.op.title} {angle}",
                    (a + w / 2, y - _BAR_H / 2),
                    xytext=(0, 6),
                    textcoords="offset points",
                    va="bottom",
                    ha="center",
                    arrowprops={"arrowstyle": "-", "color": _EDGE, "linewidth": 0.7},
                    **style,
                )


def _label(ax: Axes, lay: _Layout, kind: str) -> None:
    """Write the operations' titles (and angles) on the bars where they fit; the
    limiting operation's, in bold, always (above its bar on a Gantt chart if need be).

    Text is fitted to the axes as laid out, so this runs after everything else."""
    _settle_layout(ax)
    fig = ax.figure
    pt_x = ax.bbox.width * 72.0 / fig.dpi  # axes size [pt]
    pt_y = ax.bbox.height * 72.0 / fig.dpi
    cycle = lay.cycle
    if kind == "gantt":
        _label_gantt(ax, lay, pt_x / cycle, pt_y)
        return
    base, r_of = _ring_r(lay)
    radius_pt = min(pt_x, pt_y) / 2  # of the outer circle, r = base[-1]
    size = _FONT - 0.5
    thick = (_BAR_H + 0.1) * radius_pt / base[-1]
    # A title that does not fit whole on its bar gets a number there, and the
    # numbers are keyed beside the rings: a name is never cut short.
    keyed: list[str] = []
    for b, r in zip(lay.bars, r_of, strict=True):
        arc_pt = b.angle / cycle * 2.0 * math.pi * r / base[-1] * radius_pt
        # A chord is shorter than its arc: leave room for straight text on a curved bar.
        text = _fit_label(
            b.op.title,
            _deg(b.angle) if b.limiting else None,
            0.85 * arc_pt - 4.0,
            thick - 1.0,
            size,
            bold=b.limiting,
            truncate=False,
        )
        if text is None:
            if 0.85 * arc_pt - 2.0 < _text_width_pt(str(len(keyed) + 1), size):
                continue  # a bar too short to hold even its number stays bare
            keyed.append(b.op.title)
            text = str(len(keyed))
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
            path_effects=_halo(),
            zorder=4,
            gid=f"key:{len(keyed)}" if text == str(len(keyed)) and keyed else None,
        )
    if keyed:
        from matplotlib.legend import Legend
        from matplotlib.patches import Patch

        key = Legend(
            ax,
            [Patch(visible=False) for _ in keyed],
            [f"{k}  {title}" for k, title in enumerate(keyed, 1)],
            loc="lower left",
            bbox_to_anchor=(1.08, 0.0),
            alignment="left",
            title="numbered operations",
            title_fontsize=8,
            fontsize=8,
            handlelength=0,
            handletextpad=0,
        )
        key.set_gid("key")
        ax.add_artist(key)


# ================================================================== linkages
#: Colour of the links, joints and symbols of a linkage drawing.
LINK_COLOR = "#262626"
#: Face colour of the plates of links with three or more joints.
PLATE_COLOR = "#d6e2f0"
#: Colour of the driving crank.
DRIVER_COLOR = "#c0392b"
#: Colours of the traced paths, in the order of ``trace`` (then round again).
TRACE_COLORS = ("#1f77b4", "#2ca02c", "#9467bd", "#8c564b", "#e377c2", "#17becf")
#: Colours of the x and y components in :func:`plot_analogs`.
XY_COLORS = ("#1f77b4", "#d62728")
_GUIDE = "0.4"
_SYMBOL = 0.035  # ground and slider symbols, as a fraction of the drawn pose's extent
_SYMBOL_LINK = 0.4  # … and at most this fraction of the shortest moving link


def _check_solution(solution: Any) -> LinkageSolution:
    if not isinstance(solution, LinkageSolution):
        raise InputError(
            "solution must be a cyclomech.linkage.LinkageSolution (Linkage.solve()); "
            f"got {type(solution).__name__}"
        )
    if solution.xy.ndim == 4:
        raise InputError(
            f"solution is a sweep over {solution.xy.shape[0]} geometries (xy of shape "
            f"{solution.xy.shape}); plot one geometry: solve it with Linkage.solve"
        )
    if len(solution.angles) == 0:
        raise InputError("the solution has no crank angles")
    return solution


def _columns(linkage: Any, solution: Any) -> list[int]:
    """The solution's column of each point of ``linkage``, in ``linkage.names`` order."""
    if not isinstance(linkage, Linkage):
        raise InputError(f"linkage must be a cyclomech.Linkage; got {type(linkage).__name__}")
    _check_solution(solution)
    missing = [p for p in linkage.names if p not in solution.names]
    if missing:
        raise InputError(
            f"the solution lacks the point(s) {', '.join(missing)} of the linkage (it holds "
            f"only {', '.join(solution.names)}: solved with points=[...]); solve all points, "
            "linkage.solve(angles), to draw the mechanism"
        )
    return [solution.names.index(p) for p in linkage.names]


def _row(solution: LinkageSolution, index: Any) -> int:
    """``index`` as a row of the solution (negative counts from the end); the
    mechanism must be assembled there."""
    n = len(solution.angles)
    if isinstance(index, bool) or not isinstance(index, int | np.integer):
        raise InputError(
            f"index must be an integer row of solution.angles, 0 … {n - 1}; got {index!r}"
        )
    if not -n <= index < n:
        raise InputError(
            f"index = {index} is out of range: the solution has {n} crank angles, "
            f"index 0 … {n - 1} (or -{n} … -1 from the end)"
        )
    i = int(index) % n
    if not solution.ok[i]:
        good = np.flatnonzero(solution.ok)
        hint = (
            f"the first assembled row is index {int(good[0])} "
            f"({_deg(math.degrees(solution.angles[good[0]]))})"
            if good.size
            else "it cannot be assembled at any angle of this solution"
        )
        raise InputError(
            f"index = {index}: the mechanism cannot be assembled at crank angle "
            f"{_deg(math.degrees(solution.angles[i]))} (solution.ok[{i}] is False); "
            f"pick a row where solution.ok is True ({hint})"
        )
    return i


def _trace_names(trace: Any, solution: LinkageSolution) -> list[str]:
    if trace is None:
        return []
    names = [trace] if isinstance(trace, str) else trace
    try:
        names = list(names)
    except TypeError:
        raise InputError(f"trace must be a list of point names; got {trace!r}") from None
    for p in names:
        if p not in solution.names:
            raise InputError(
                f"trace: no point {p!r} in the solution; its points are {', '.join(solution.names)}"
            )
    return names


def _unit(v: Any) -> npt.NDArray[np.float64]:
    u = np.asarray(v, dtype=float)
    n = float(np.hypot(u[0], u[1]))
    return u / n if n > 0.0 else np.array([1.0, 0.0])


def _symbol_size(linkage: Linkage) -> float:
    """Size [m] of the ground and slider symbols: a fixed fraction of the drawn
    pose, smaller on a short link so the symbols do not hide it."""
    pts = np.array(list(linkage._points.values()))
    extent = float(np.max(pts.max(axis=0) - pts.min(axis=0)))
    moving = [ln for ln in linkage._links if not set(ln) <= linkage._ground]
    lengths = [linkage.length(a, b) for ln in moving for k, a in enumerate(ln) for b in ln[k + 1 :]]
    shortest = min((v for v in lengths if v > 0.0), default=extent)
    s = min(_SYMBOL * extent, _SYMBOL_LINK * shortest)
    return s if s > 0.0 else 1.0


def _ground_guides(
    linkage: Linkage, solution: LinkageSolution, s: float
) -> list[tuple[str, npt.NDArray[np.float64], npt.NDArray[np.float64]]]:
    """(point, start, end) [m] of each ground guide: the line through the point's drawn
    position along the guide, over the point's travel in the solution and a block's
    length beyond."""
    out = []
    for p, guides in linkage._sliders.items():
        path = solution.xy[solution.ok, solution.index(p)]
        origin = np.asarray(linkage._points[p], dtype=float)
        for kind, arg in guides:
            if kind != "ground":
                continue
            u = _unit(arg)
            t = (path - origin) @ u
            lo, hi = (float(t.min()), float(t.max())) if t.size else (0.0, 0.0)
            out.append((p, origin + (lo - 2.5 * s) * u, origin + (hi + 2.5 * s) * u))
    return out


def _extent(
    linkage: Linkage,
    solution: LinkageSolution,
    cols: list[int],
    rows: list[int],
    trace: list[str],
    s: float,
) -> tuple[float, float, float, float]:
    """(xmin, xmax, ymin, ymax) [m] of a drawing of ``rows`` with its traces, guides
    and ground symbols, with room for the labels."""
    pts = [solution.xy[np.ix_(rows, cols)].reshape(-1, 2)]
    pts += [solution.xy[:, solution.index(p)] for p in trace]
    pts += [np.array([a, b]) for _, a, b in _ground_guides(linkage, solution, s)]
    pts += [
        np.asarray(linkage._points[g], dtype=float) + np.array([[-1.6, -2.4], [1.6, 0.0]]) * s
        for g in linkage._ground
    ]
    allp = np.concatenate(pts)
    allp = allp[np.isfinite(allp).all(axis=1)]
    (x0, y0), (x1, y1) = allp.min(axis=0), allp.max(axis=0)
    pad = 0.06 * max(x1 - x0, y1 - y0) + 2.0 * s
    return float(x0 - pad), float(x1 + pad), float(y0 - pad), float(y1 + pad)


def _outline(pts: list[npt.NDArray[np.float64]]) -> list[npt.NDArray[np.float64]]:
    """The joints of a link with 3+ joints in order round their centre (a simple
    polygon for a convex plate)."""
    c = np.mean(pts, axis=0)
    return sorted(pts, key=lambda q: math.atan2(q[1] - c[1], q[0] - c[0]))


def _block(centre: Any, u: Any, s: float) -> npt.NDArray[np.float64]:
    """Corners of a slider block [m]: 2.6 s along the unit vector u, 1.5 s across."""
    u = _unit(u)
    n = np.array([-u[1], u[0]])
    a, b = 1.3 * s * u, 0.75 * s * n
    c = np.asarray(centre, dtype=float)
    return np.array([c - a - b, c + a - b, c + a + b, c - a + b])


def _point_label(
    ax: Any, name: str, xy: Any, d: npt.NDArray[np.float64], *, text: str | None = None
) -> None:
    """Label a joint 8 points from ``xy`` along the unit direction ``d``."""
    ax.annotate(
        name if text is None else text,
        tuple(xy),
        xytext=(8.0 * d[0], 8.0 * d[1]),
        textcoords="offset points",
        ha="left" if d[0] > 0.38 else "right" if d[0] < -0.38 else "center",
        va="bottom" if d[1] > 0.38 else "top" if d[1] < -0.38 else "center",
        fontsize=9,
        path_effects=_halo(),
        gid=f"label:{name}",
        zorder=5.0,
    )


def _frame_equal(ax: Any, box: Any, unit: str, *, grid: str) -> None:
    """Limits by autoscaling to ``box`` = (x0, x1, y0, y1) (everything drawn is
    inside it), so that the equal aspect may widen them to fill the axes; axis
    labels in ``unit``."""
    ax.update_datalim([(box[0], box[2]), (box[1], box[3])])
    ax.margins(0.0)
    ax.set_aspect("equal", adjustable="datalim")
    ax.autoscale_view()
    ax.set_xlabel(f"x [{unit}]")
    ax.set_ylabel(f"y [{unit}]")
    ax.grid(color=grid, linewidth=0.6)
    ax.set_axisbelow(True)


def _label_direction(blocked: list[npt.NDArray[np.float64]]) -> npt.NDArray[np.float64]:
    """A unit vector in the middle of the widest gap between the ``blocked``
    directions (links, symbols) at a point; up-right when nothing is in the way."""
    angles = sorted(math.atan2(v[1], v[0]) for v in blocked if float(np.hypot(v[0], v[1])) > 0.0)
    if not angles:
        return np.array([math.sqrt(0.5), math.sqrt(0.5)])
    gaps = [(angles[(k + 1) % len(angles)] - a) % (2 * math.pi) for k, a in enumerate(angles)]
    if len(angles) == 1:
        gaps = [2 * math.pi]
    k = int(np.argmax(gaps))
    mid = angles[k] + gaps[k] / 2
    return np.array([math.cos(mid), math.sin(mid)])


def _draw_linkage(
    ax: Axes,
    linkage: Linkage,
    solution: LinkageSolution,
    cols: list[int],
    i: int,
    trace: list[str],
    box: tuple[float, float, float, float],
    title: str | None,
) -> None:
    from matplotlib.collections import LineCollection, PolyCollection

    s = _symbol_size(linkage)
    names = linkage.names
    xy = solution.xy[i, cols]
    pos = {p: xy[k] for k, p in enumerate(names)}
    ground = [g for g in names if g in linkage._ground]
    moving = [ln for ln in linkage._links if not set(ln) <= linkage._ground]

    for k, p in enumerate(trace):
        path = solution.xy[:, solution.index(p)]
        ax.plot(
            path[:, 0],
            path[:, 1],
            color=TRACE_COLORS[k % len(TRACE_COLORS)],
            linewidth=1.0,
            label=f"trace:{p}",
            gid=f"trace:{p}",
            zorder=1.7,  # over the plates, under the links
        )

    # Guides: the ground lines the blocks slide on; for a block on a link beyond the
    # link's joints, the link's line continued to the block.
    guides = [[a, b] for _, a, b in _ground_guides(linkage, solution, s)]
    blocks = []
    blocked: dict[str, list[Any]] = {p: [] for p in names}  # directions to keep labels off
    clear: dict[str, list[Any]] = {p: [] for p in names}  # guides of the blocks at a point
    for p, gs in linkage._sliders.items():
        for kind, arg in gs:
            if kind == "ground":
                u = _unit(arg)
            else:
                b, c = arg
                u = _unit(pos[c] - pos[b])
                t = float((pos[p] - pos[b]) @ u)
                length = float(np.hypot(*(pos[c] - pos[b])))
                if t < 0.0:
                    guides.append([pos[b], pos[p] - 1.5 * s * u])
                elif t > length:
                    guides.append([pos[c], pos[p] + 1.5 * s * u])
            blocks.append(_block(pos[p], u, s))
            blocked[p] += [u, -u]
            clear[p].append(u)
    ax.add_collection(
        LineCollection(
            guides,
            colors=_GUIDE,
            linewidths=0.9,
            linestyles=(0, (6.0, 3.0)),
            label="guides",
            gid="guides",
            zorder=1.2,
        )
    )

    ax.add_collection(
        PolyCollection(
            [_outline([pos[j] for j in ln]) for ln in moving if len(ln) >= 3],
            facecolors=PLATE_COLOR,
            edgecolors="none",
            label="plates",
            gid="plates",
            zorder=1.5,
        )
    )
    # The ground symbol under each fixed pivot: a support triangle on a hatched base.
    tri, hatch = [], []
    for g in ground:
        x, y = pos[g]
        yb = y - 1.5 * s
        tri.append([(x, y), (x - 0.85 * s, yb), (x + 0.85 * s, yb)])
        hatch.append([(x - 1.5 * s, yb), (x + 1.5 * s, yb)])
        for xk in np.linspace(x - 1.05 * s, x + 1.5 * s, 6):
            hatch.append([(xk, yb), (xk - 0.55 * s, yb - 0.6 * s)])
        blocked[g] += [np.array([-1.0, -1.0]), np.array([0.0, -1.0]), np.array([1.0, -1.0])]
    ax.add_collection(
        PolyCollection(
            tri,
            facecolors="white",
            edgecolors=LINK_COLOR,
            linewidths=1.0,
            label="ground",
            gid="ground",
            zorder=1.8,
        )
    )
    ax.add_collection(
        LineCollection(
            hatch,
            colors=LINK_COLOR,
            linewidths=0.8,
            label="ground hatching",
            gid="ground hatching",
            zorder=1.8,
        )
    )

    paths = []
    for ln in moving:
        pts = [pos[j] for j in ln]
        paths.append(pts if len(ln) == 2 else [*_outline(pts), _outline(pts)[0]])
        for a in ln:
            blocked[a] += [pos[b] - pos[a] for b in ln if b != a]
    ax.add_collection(
        LineCollection(
            paths,
            colors=LINK_COLOR,
            linewidths=2.0,
            capstyle="round",
            joinstyle="round",
            label="links",
            gid="links",
            zorder=2.0,
        )
    )
    pivot, tip = linkage._driver
    ax.plot(
        [pos[pivot][0], pos[tip][0]],
        [pos[pivot][1], pos[tip][1]],
        color=DRIVER_COLOR,
        linewidth=3.4,
        solid_capstyle="round",
        label="driver",
        gid="driver",
        zorder=2.5,
    )
    ax.add_collection(
        PolyCollection(
            blocks,
            facecolors="#f4f4f4",
            edgecolors=LINK_COLOR,
            linewidths=1.2,
            label="sliders",
            gid="sliders",
            zorder=3.0,
        )
    )

    # A point on one link only, neither fixed nor sliding, is a point of a body
    # (a coupler point), not a pin: a filled dot.
    body = [
        sum(p in ln for ln in linkage._links) == 1
        and p not in linkage._ground
        and p not in linkage._sliders
        for p in names
    ]
    ax.scatter(
        xy[:, 0],
        xy[:, 1],
        s=26.0,
        c=[LINK_COLOR if b else "white" for b in body],
        edgecolors=LINK_COLOR,
        linewidths=1.2,
        label="joints",
        gid="joints",
        zorder=4.0,
    )
    # Labels keep clear of close points too (a crank's pivot beside a coupler joint).
    near = 0.05 * float(np.max(np.ptp(xy, axis=0)))
    for p in names:
        blocked[p] += [
            pos[q] - pos[p] for q in names if q != p and np.hypot(*(pos[q] - pos[p])) < near
        ]
    for p in names:
        d = _label_direction(blocked[p])
        # From the edge of a slider's block: half its length along the guide, half its
        # width across.
        edge = max(
            (
                1.3 * abs(float(d @ u)) + 0.75 * abs(float(d[0] * u[1] - d[1] * u[0]))
                for u in clear[p]
            ),
            default=0.0,
        )
        _point_label(ax, p, pos[p] + edge * s * d, d)

    _frame_equal(ax, box, "m", grid="0.9")
    if title is None:
        angle = f"crank angle {_deg(math.degrees(solution.angles[i]))}"
        title = f"C{angle[1:]}" if linkage.name is None else f"{linkage.name} — {angle}"
    ax.set_title(title)


def _linkage_figure(box: tuple[float, float, float, float]) -> Any:
    """A figure [in] whose axes fit a drawing of the extent ``box`` [m] at equal scale."""
    plt = _matplotlib()
    w, h = box[1] - box[0], box[3] - box[2]
    r = h / w if w > 0 else 1.0
    if r <= 1.1:
        size = (7.5, min(max(7.5 * r + 0.9, 3.2), 9.0))
    else:
        size = (min(max(7.0 / r + 1.0, 3.5), 7.5), 8.0)
    fig, ax = plt.subplots(figsize=size, layout="constrained")
    return fig, ax


def plot_linkage(
    linkage: Linkage,
    solution: LinkageSolution,
    index: int = 0,
    *,
    ax: Axes | None = None,
    trace: list[str] | None = None,
    title: str | None = None,
) -> Axes:
    """Draw the mechanism at crank-angle row ``index`` of ``solution``; return the axes.

    The pose is ``solution.xy[index]`` [m] (``index`` negative counts from the end);
    ``solution`` must be a :meth:`Linkage.solve` of every point of ``linkage`` (not
    a :func:`~cyclomech.linkage.solve_geometries`, not ``points=`` a subset), assembled at
    that row. Drawn at equal scale in metres: the links as lines between their
    joints (a link with three or more joints as a light plate with its outline; a
    link of ground joints only, the frame, is not drawn), the driving crank in
    red, the joints as small circles (a point of a body that is no joint, a filled
    dot), each ground joint on the ground symbol (a support on a hatched base), a
    block at each sliding point along its guide and a ground guide as a dashed
    line over the point's travel, every point labelled. ``trace`` lists points
    whose paths over the whole solution are drawn as thin lines (broken where the
    mechanism cannot be assembled). ``title`` defaults to the linkage's name and
    the crank angle [deg].

    Artists (for tests and restyling), by label and gid: ``"links"``, a
    :class:`~matplotlib.collections.LineCollection` with one path per link in the
    order of the linkage's links (the two joints of a binary link; the closed
    outline of a larger one), ``"plates"`` the fills of the larger links,
    ``"driver"`` the crank (a ``Line2D`` pivot → tip), ``"joints"`` the points in
    the order of ``linkage.names``, ``"ground"`` one support triangle per ground
    joint (apex on the joint) and ``"ground hatching"`` their bases, ``"sliders"``
    one block per guide, ``"guides"`` the guide lines, ``"trace:P"`` the path of
    point P, and texts with gid ``"label:P"``.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> import numpy as np, cyclomech as cm
    >>> from cyclomech.plot import plot_linkage
    >>> lk = cm.Linkage({"A": (0, 0), "B": (1, 0), "C": (3.5, 2.5), "D": (4, 0)},
    ...                 [("A", "B"), ("B", "C"), ("C", "D")], ["A", "D"], ("A", "B"),
    ...                 name="crank-rocker")
    >>> sol = lk.solve(np.radians(np.arange(0, 361, 5)))
    >>> ax = plot_linkage(lk, sol, 18, trace=["C"])    # 18 × 5° = 90°
    >>> ax.get_title()
    'crank-rocker — crank angle 90°'
    >>> links = next(c for c in ax.collections if c.get_label() == "links")
    >>> np.round(links.get_segments()[0], 12).tolist()   # the crank A–B at 90°
    [[0.0, 0.0], [0.0, 1.0]]
    >>> plt.close("all")
    """
    _matplotlib()  # ImportError before anything else without matplotlib
    cols = _columns(linkage, solution)
    i = _row(solution, index)
    names = _trace_names(trace, solution)
    box = _extent(linkage, solution, cols, [i], names, _symbol_size(linkage))
    if ax is None:
        _, ax = _linkage_figure(box)
    elif not hasattr(ax, "add_collection"):
        raise InputError(f"ax must be a matplotlib Axes; got {type(ax).__name__}")
    _draw_linkage(ax, linkage, solution, cols, i, names, box, title)
    return ax


def _runs(mask: npt.NDArray[np.bool_]) -> list[tuple[int, int]]:
    """(first, last) index of each run of True in ``mask``."""
    padded = np.concatenate([[False], mask, [False]]).astype(np.int8)
    d = np.diff(padded)
    return list(
        zip(np.flatnonzero(d == 1).tolist(), (np.flatnonzero(d == -1) - 1).tolist(), strict=True)
    )


def plot_analogs(solution: LinkageSolution, point: str, *, title: str | None = None) -> Figure:
    """Position, velocity analog and acceleration analog of one point over the crank
    angle: three stacked plots sharing the crank-angle axis [deg] (seed 001, fig. 4).

    Top: x and y of ``point`` [m]; middle: dx/dφ and dy/dφ [m/rad]; bottom:
    d²x/dφ² and d²y/dφ² [m/rad²] (φ the crank angle in radians; multiply by ω and
    ω² [rad/s, rad/s²] for the velocity and acceleration at a constant crank
    speed ω). The curves run in order of the angle. Angles where the mechanism
    cannot be assembled (``solution.ok`` False) are shaded grey, dead centres
    (``solution.singular``) marked by dotted lines, branch changes of a class III
    group (``solution.branch_change``) by dash-dotted ones. ``solution`` must be a
    :meth:`Linkage.solve` with analogs (not a sweep); ``title`` defaults to the
    point's name.

    Artists, by gid: the curves ``"x"``, ``"y"``, ``"dx/dφ"``, ``"dy/dφ"``,
    ``"d²x/dφ²"``, ``"d²y/dφ²"`` (x data the angles [deg]), the shading
    ``"not assembled"``, the marks ``"singular"`` and ``"branch change"``.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> import numpy as np, cyclomech as cm
    >>> from cyclomech.plot import plot_analogs
    >>> sc = cm.Linkage({"A": (0, 0), "B": (0.1, 0), "C": (0.45, 0)},
    ...                 [("A", "B"), ("B", "C")], ["A"], ("A", "B"),
    ...                 sliders={"C": ("ground", (1, 0))})
    >>> sol = sc.solve(np.radians(np.arange(0, 361, 2)))
    >>> fig = plot_analogs(sol, "C")
    >>> [ax.get_ylabel() for ax in fig.axes]
    ['position [m]', 'velocity analog [m/rad]', 'acceleration analog [m/rad²]']
    >>> dx = next(ln for ln in fig.axes[1].get_lines() if ln.get_gid() == "dx/dφ")
    >>> bool(np.array_equal(dx.get_ydata(), sol.vel[:, sol.index("C"), 0]))
    True
    >>> plt.close(fig)
    """
    plt = _matplotlib()
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch
    from matplotlib.ticker import FuncFormatter, MultipleLocator

    _check_solution(solution)
    if solution.vel is None or solution.acc is None:
        raise InputError(
            "the solution has no analogs (solved with analogs=False); "
            "solve with analogs=True to plot them"
        )
    k = solution.index(point)
    deg = np.degrees(solution.angles)
    order = np.argsort(deg, kind="stable")
    x = deg[order]
    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(8.0, 7.6), layout="constrained")
    panels = (
        (solution.xy, "position [m]", ("x", "y")),
        (solution.vel, "velocity analog [m/rad]", ("dx/dφ", "dy/dφ")),
        (solution.acc, "acceleration analog [m/rad²]", ("d²x/dφ²", "d²y/dφ²")),
    )
    lo, hi = float(x[0]), float(x[-1])
    half = np.diff(x) / 2  # half the step to each neighbour [deg]
    spans = [
        (x[a] - (half[a - 1] if a > 0 else 0.0), x[b] + (half[b] if b < len(half) else 0.0))
        for a, b in _runs(~solution.ok[order])
    ]
    singular = x[solution.singular[order]]
    branch = x[solution.branch_change[order]]
    for ax, (arr, ylabel, comps) in zip(axes, panels, strict=True):
        for c, (name, color) in enumerate(zip(comps, XY_COLORS, strict=True)):
            ax.plot(x, arr[order, k, c], color=color, linewidth=1.4, label=name, gid=name)
        handles = list(ax.get_lines())
        for a, b in spans:
            ax.axvspan(a, b, color="0.85", linewidth=0.0, gid="not assembled", zorder=0)
        for v in singular:
            ax.axvline(v, color="0.25", linestyle=":", linewidth=1.1, gid="singular")
        for v in branch:
            ax.axvline(v, color="#ff7f0e", linestyle="-.", linewidth=1.1, gid="branch change")
        if ax is not axes[0]:
            ax.axhline(0.0, color="0.55", linewidth=0.6, zorder=0.5, gid="zero")
        if ax is axes[0]:  # the marks are the same in every panel: one legend for them
            if spans:
                handles.append(Patch(color="0.85", label="not assembled"))
            if singular.size:
                handles.append(
                    Line2D([], [], color="0.25", linestyle=":", linewidth=1.1, label="dead centre")
                )
            if branch.size:
                handles.append(
                    Line2D([], [], color="#ff7f0e", linestyle="-.", label="branch change")
                )
        ax.legend(
            handles=handles,
            loc="upper left",
            bbox_to_anchor=(1.01, 1.0),
            frameon=False,
            fontsize=8.5,
        )
        ax.set_ylabel(ylabel)
        ax.grid(color="0.9", linewidth=0.6)
        ax.set_axisbelow(True)
    bottom = axes[-1]
    bottom.set_xlim(*((lo, hi) if hi > lo else (lo - 1.0, hi + 1.0)))
    bottom.xaxis.set_major_locator(MultipleLocator(_tick_step(max(hi - lo, 1.0))))
    bottom.xaxis.set_major_formatter(FuncFormatter(lambda v, _pos: _deg(v)))
    bottom.set_xlabel("crank angle φ")
    fig.suptitle(f"Point {point}: position and analogs" if title is None else title)
    return cast("Figure", fig)


def animate_linkage(
    linkage: Linkage,
    solution: LinkageSolution,
    path: str | os.PathLike[str],
    *,
    fps: float = 30,
    trace: list[str] | None = None,
    every: int = 1,
    dpi: float = 100,
) -> Path:
    """Write an animated GIF of the mechanism over the solution; return its path.

    One frame (as :func:`plot_linkage`, at fixed limits) for every ``every``-th row
    of ``solution`` where the mechanism is assembled, shown for 1/``fps`` s each
    (GIF stores whole hundredths of a second); ``trace`` as in :func:`plot_linkage`.
    ``path`` must end in ``.gif``; the frames are ``dpi`` dots per inch. Uses
    matplotlib's :class:`~matplotlib.animation.PillowWriter` (Pillow comes with
    matplotlib).

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import pathlib, tempfile
    >>> import numpy as np, cyclomech as cm
    >>> from PIL import Image
    >>> from cyclomech.plot import animate_linkage
    >>> lk = cm.Linkage({"A": (0, 0), "B": (1, 0), "C": (3.5, 2.5), "D": (4, 0)},
    ...                 [("A", "B"), ("B", "C"), ("C", "D")], ["A", "D"], ("A", "B"))
    >>> sol = lk.solve(np.radians(np.arange(0, 360, 30)))
    >>> gif = animate_linkage(lk, sol, pathlib.Path(tempfile.mkdtemp()) / "crank.gif",
    ...                       fps=10, trace=["C"], dpi=40)
    >>> with Image.open(gif) as im:                      # 12 angles, 30° apart
    ...     im.n_frames
    12
    """
    plt = _matplotlib()
    from matplotlib.animation import PillowWriter

    cols = _columns(linkage, solution)
    names = _trace_names(trace, solution)
    if not isinstance(path, str | os.PathLike):
        raise InputError(f"path must be a file name ending in .gif; got {path!r}")
    out = Path(path)
    if out.suffix.lower() != ".gif":
        raise InputError(f"path = {str(out)!r} must end in .gif (an animated GIF is written)")
    if isinstance(every, bool) or not isinstance(every, int | np.integer) or every < 1:
        raise InputError(f"every must be a positive integer (every n-th row); got {every!r}")
    for name, v in (("fps", fps), ("dpi", dpi)):
        if (
            isinstance(v, bool)
            or not isinstance(v, int | float)
            or not (math.isfinite(v) and v > 0)
        ):
            raise InputError(f"{name} must be a positive number; got {v!r}")
    rows = (np.flatnonzero(solution.ok[:: int(every)]) * int(every)).tolist()
    if not rows:
        raise InputError(
            f"the mechanism cannot be assembled at any of the {len(solution.angles)} angles "
            f"of the solution taken every {every}: no frame to draw"
        )
    box = _extent(linkage, solution, cols, rows, names, _symbol_size(linkage))
    fig, ax = _linkage_figure(box)
    try:
        writer = PillowWriter(fps=cast(Any, float(fps)))  # typed int; a float works (ms per frame)
        with writer.saving(fig, str(out), float(dpi)):
            for i in rows:
                ax.clear()
                _draw_linkage(ax, linkage, solution, cols, i, names, box, None)
                writer.grab_frame()
    finally:
        plt.close(fig)
    return out


# ============================================================ motion laws and presses
#: Colours of a position, its first and its second derivative (law and press plots).
MOTION_COLORS = ("#1f77b4", "#2ca02c", "#d62728")
#: Colour of the working stroke (shading and the pin's path over it).
WORK_COLOR = "#f28e2b"
_MM = 1000.0  # mm per m: law and press plots show lengths in millimetres
_CHAIN = (0, (9.0, 2.5, 1.5, 2.5))  # dash-dot line style of a pitch circle


def _axes_arg(ax: Any, counts: tuple[int, ...], what: str) -> list[Axes] | None:
    """``ax`` as a list of axes (None for a new figure): one Axes, or a sequence
    of as many as one of ``counts``."""
    if ax is None:
        return None
    axes = [ax] if hasattr(ax, "add_collection") else None
    if axes is None:
        try:
            axes = list(ax)
        except TypeError:
            axes = []
    if len(axes) not in counts or not all(hasattr(a, "add_collection") for a in axes):
        want = " or ".join(
            "one matplotlib Axes" if c == 1 else f"a sequence of {c} Axes" for c in counts
        )
        raise InputError(f"{what}: ax must be None (a new figure) or {want}; got {ax!r}")
    return axes


def _count_arg(name: str, value: Any, lo: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < lo:
        raise InputError(f"{name} must be an integer ≥ {lo}; got {value!r}")
    return int(value)


def _angle_axis(ax: Axes, hi_deg: float, label: str) -> None:
    """x from 0 to ``hi_deg`` [deg], ticks every 15°, 30°, … with ° labels."""
    from matplotlib.ticker import FuncFormatter, MultipleLocator

    ax.set_xlim(0.0, hi_deg)
    ax.xaxis.set_major_locator(MultipleLocator(_tick_step(hi_deg)))
    ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _pos: _deg(v)))
    ax.set_xlabel(label)


def _mark_peak(ax: Axes, x: float, y: float, text: str, gid: str, color: str) -> None:
    """A dot on a curve's peak and its value beside it, kept inside the axes."""
    ax.plot([x], [y], linestyle="none", marker="o", markersize=5.5, color=color, gid=gid)
    x0, x1 = ax.get_xlim()
    f = (x - x0) / (x1 - x0) if x1 > x0 else 0.5
    up = y >= 0.0
    ax.annotate(
        text,
        (x, y),
        xytext=(-7.0 if f > 0.6 else 7.0, 6.0 if up else -6.0),
        textcoords="offset points",
        ha="right" if f > 0.6 else "left",
        va="bottom" if up else "top",
        fontsize=8.5,
        path_effects=_halo(),
        gid=f"label:{gid}",
        zorder=5.0,
    )


def _fmt(v: float) -> str:
    """A value with three significant figures, no exponent for everyday sizes."""
    return f"{v:.3g}" if 1e-3 <= abs(v) < 1e5 or v == 0.0 else f"{v:.3e}"


def plot_law(
    law: MotionLaw | TwoPeriodLaw,
    ax: Axes | Any = None,
    *,
    n: int = 401,
    title: str | None = None,
) -> tuple[Axes, ...]:
    """Draw a motion law and its derivatives; return the axes drawn on.

    A :class:`~cyclomech.motion.MotionLaw`: Z, Z' and Z'' (dimensionless) against
    j from 0 to 1, with the speed peak Z'max and the acceleration peak
    Z''max = max |Z''| marked by a dot and their values. A
    :class:`~cyclomech.motion.TwoPeriodLaw`: Π [mm], Π' [mm/rad] and Π''
    [mm/rad²] against the crank angle α [deg] from 0 (BDC) to α2, with α1 (the
    speed peak, where the periods meet) as a dashed line, periods I (0 … α1) and
    II (α1 … α2) spanned above the top plot, and Π'max and the two periods'
    acceleration peaks marked.

    With ``ax=None`` a figure with three stacked plots sharing the angle axis is
    made (position, speed, acceleration, top to bottom); ``ax`` may also be three
    axes to draw them on, or one Axes, which then holds all three curves and a
    legend. ``n`` is the number of points per curve (the law's breaks and α1 are
    added). ``title`` defaults to the law's name.

    Artists, by gid: the curves ``"Z"``, ``"Z'"``, ``"Z''"`` (``"Π"``, ``"Π'"``,
    ``"Π''"`` for a two-period law; x data j, or α in degrees), the peak dots
    ``"Z'max"``, ``"Z''max"`` (``"Π'max"``, ``"Π''1max"``, ``"Π''2max"``) with
    texts ``"label:…"``, and for a two-period law the lines ``"α1"`` (one per
    axes; the first labelled ``"α1 (speed peak)"``) and the texts ``"period I"``
    and ``"period II"``.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> import numpy as np, cyclomech as cm
    >>> from cyclomech.plot import plot_law
    >>> axes = plot_law(cm.motion.law("modified_sine"))
    >>> [a.get_ylabel() for a in axes]
    ['Z  (position)', "Z' = dZ/dj  (speed)", "Z'' = d²Z/dj²  (acceleration)"]
    >>> peak = next(ln for ln in axes[1].get_lines() if ln.get_gid() == "Z'max")
    >>> round(float(peak.get_ydata()[0]), 2)                 # the speed peak Z'max
    1.76
    >>> lw = cm.motion.two_period(0.2, np.pi, "cycloidal", "modified_sine", asymmetry=2.0)
    >>> axes = plot_law(lw)
    >>> a1 = next(ln for ln in axes[0].get_lines() if ln.get_gid() == "α1")
    >>> a1.get_label(), round(float(a1.get_xdata()[0]), 6)   # α1 = 180°/(1 + f_A)
    ('α1 (speed peak)', 60.0)
    >>> axes[2].get_xlabel(), axes[0].get_ylabel()
    ('crank angle α from BDC', 'Π  [mm]')
    >>> plt.close("all")
    """
    plt = _matplotlib()
    from matplotlib.transforms import blended_transform_factory

    if not isinstance(law, MotionLaw | TwoPeriodLaw):
        raise InputError(
            "law must be a cyclomech.motion.MotionLaw (cm.motion.law(...)) or a "
            f"cyclomech.motion.TwoPeriodLaw (cm.motion.two_period(...)); got {type(law).__name__}"
        )
    n = _count_arg("n", n, 3)
    given = _axes_arg(ax, (1, 3), "plot_law")
    if given is None:
        fig, arr = plt.subplots(3, 1, sharex=True, figsize=(7.5, 7.6), layout="constrained")
        axes: list[Axes] = list(arr)
    else:
        fig, axes = None, given
    one = len(axes) == 1
    panels = axes * 3 if one else axes

    if isinstance(law, MotionLaw):
        x = np.union1d(np.linspace(0.0, 1.0, n), [b for b in law.breaks if 0.0 <= b <= 1.0])
        ys = (law.z(x), law.dz(x), law.ddz(x))
        names = ("Z", "Z'", "Z''")
        ylabels = ("Z  (position)", "Z' = dZ/dj  (speed)", "Z'' = d²Z/dj²  (acceleration)")
        spelled = law.name.replace("_", " ")
        head = f"Motion law: {spelled} ({'half law' if law.form == 'half' else 'full rise'})"
        for k, p in enumerate(panels):
            p.plot(x, ys[k], color=MOTION_COLORS[k], linewidth=1.6, label=names[k], gid=names[k])
        for p in panels:
            p.set_xlim(0.0, 1.0)
        panels[-1].set_xlabel("j  (fraction of the law's crank angle)")
        i1 = int(np.argmax(ys[1]))
        i2 = int(np.argmax(np.abs(ys[2])))
        _mark_peak(
            panels[1], x[i1], ys[1][i1], f"Z'max = {law.dz_max:.4g}", "Z'max", MOTION_COLORS[1]
        )
        _mark_peak(
            panels[2], x[i2], ys[2][i2], f"Z''max = {law.ddz_max:.4g}", "Z''max", MOTION_COLORS[2]
        )
        ylabel_one = "Z, Z', Z''  (dimensionless)"
    else:
        a1, a2 = law.angle1, law.angle
        alpha = np.union1d(np.linspace(0.0, a2, n), [a1])
        x = np.degrees(alpha)
        ys = (
            law.position(alpha) * _MM,
            law.velocity(alpha) * _MM,
            law.acceleration(alpha) * _MM,
        )
        names = ("Π", "Π'", "Π''")
        ylabels = ("Π  [mm]", "Π' = dΠ/dα  [mm/rad]", "Π'' = d²Π/dα²  [mm/rad²]")
        head = (
            f"Two-period law: {law.law1.name.replace('_', ' ')} (I) + "
            f"{law.law2.name.replace('_', ' ')} (II)\nΠ2 = {_fmt(law.stroke * _MM)} mm "
            f"in α2 = {_deg(math.degrees(a2))}, f_A = {_fmt(law.asymmetry)}, "
            f"α1 = {_deg(math.degrees(a1))}"
        )
        for k, p in enumerate(panels):
            p.plot(x, ys[k], color=MOTION_COLORS[k], linewidth=1.6, label=names[k], gid=names[k])
        for k, p in enumerate(axes):
            _angle_axis(p, float(x[-1]), "crank angle α from BDC" if p is axes[-1] else "")
            p.axvline(
                math.degrees(a1),
                color="0.3",
                linestyle="--",
                linewidth=1.0,
                label="α1 (speed peak)" if k == 0 else "_α1",
                gid="α1",
                zorder=1.5,
            )
        if not one:
            for p in axes[:-1]:
                p.tick_params(labelbottom=False)
        i1 = int(np.searchsorted(alpha, a1))
        _mark_peak(
            panels[1],
            x[i1],
            ys[1][i1],
            f"Π'max = {_fmt(law.max_speed * _MM)} mm/rad",
            "Π'max",
            MOTION_COLORS[1],
        )
        first = alpha <= a1
        j1 = int(np.argmax(np.abs(np.where(first, ys[2], 0.0))))
        j2 = int(np.argmax(np.abs(np.where(first, 0.0, ys[2]))))
        for j, label in ((j1, "Π''1max"), (j2, "Π''2max")):
            _mark_peak(
                panels[2],
                x[j],
                ys[2][j],
                f"{label} = {_fmt(abs(float(ys[2][j])))} mm/rad²",
                label,
                MOTION_COLORS[2],
            )
        top = axes[0]
        tr = blended_transform_factory(top.transData, top.transAxes)
        for lo, hi, text in (
            (0.0, a1, f"period I  ({_deg(math.degrees(a1))})"),
            (a1, a2, f"period II  ({_deg(math.degrees(a2 - a1))})"),
        ):
            lo_d, hi_d = math.degrees(lo), math.degrees(hi)
            top.annotate(
                "",
                xy=(lo_d, 1.03),
                xytext=(hi_d, 1.03),
                xycoords=tr,
                textcoords=tr,
                arrowprops={
                    "arrowstyle": "<|-|>",
                    "color": "0.3",
                    "linewidth": 0.9,
                    "shrinkA": 0.0,
                    "shrinkB": 0.0,
                    "mutation_scale": 8.0,
                },
                annotation_clip=False,
            )
            top.text(
                (lo_d + hi_d) / 2,
                1.05,
                text,
                transform=tr,
                ha="center",
                va="bottom",
                fontsize=9,
                gid=text.split("  ")[0],
            )
        ylabel_one = "Π [mm], Π' [mm/rad], Π'' [mm/rad²]"

    for k, p in enumerate(axes):
        p.axhline(0.0, color="0.55", linewidth=0.6, zorder=0.5, gid="zero")
        p.set_ylabel(ylabel_one if one else ylabels[k])
        p.margins(y=0.16)
        p.grid(color="0.9", linewidth=0.6)
        p.set_axisbelow(True)
    if one:
        axes[0].legend(loc="best", frameon=False, fontsize=8.5)
    elif isinstance(law, TwoPeriodLaw):
        axes[0].legend(
            handles=[ln for ln in axes[0].get_lines() if ln.get_label() == "α1 (speed peak)"],
            loc="upper left",
            frameon=False,
            fontsize=8.5,
        )
    text = head if title is None else title
    if fig is not None:
        fig.suptitle(text)
    else:
        axes[0].set_title(text, pad=34.0 if isinstance(law, TwoPeriodLaw) else 6.0)
    return tuple(axes)


def _press_arg(press: Any) -> GearLeverPress:
    if not isinstance(press, GearLeverPress):
        raise InputError(
            f"press must be a cyclomech.press.GearLeverPress; got {type(press).__name__}"
        )
    return press


def _design_text(press: GearLeverPress) -> str:
    """The design's parameters in mm and degrees, for titles."""
    mm = ", ".join(
        f"{k} = {_fmt(getattr(press, k) * _MM)}"
        for k in ("R", "r", "d", "L") + (("offset",) if press.offset != 0.0 else ())
    )
    return f"{mm} mm, φ0 = {_deg(math.degrees(press.phi0))}"


def plot_press(
    press: GearLeverPress,
    alpha: float = 0.0,
    ax: Axes | Any = None,
    *,
    show_motion: bool = False,
    k_Sp: float | None = None,
    n: int = 720,
    title: str | None = None,
) -> Axes | tuple[Axes, Axes]:
    """Draw the gear-lever press at crank angle ``alpha`` [rad, from BDC against
    the motion, as :meth:`~cyclomech.press.GearLeverPress.solve`]; return the axes.

    At equal scale in millimetres, in the frame of the guide gear's centre O: the
    fixed guide gear (a hatched ring on its pitch circle of radius R, drawn
    dash-dot), the planet's pitch circle (radius r) round its centre C, the
    carrier O → C in red, the planet's arm C → P to the rod pin P, the rod
    P → slider, the slider block between the rails of its vertical guide
    (x = ``offset``, drawn over the slider's travel), the ground symbol at O, an
    arrow for the carrier's (counterclockwise) turn, and the pin's whole path over
    one crank turn (a hypotrochoid, ``n`` + 1 angles from 0 to 2π) as a thin
    line. With ``k_Sp`` (the working stroke as a fraction of the nominal stroke,
    see :meth:`~cyclomech.press.GearLeverPress.criteria`) the part of the pin's
    path over the working stroke and the slider's working stroke beside its guide
    are drawn in orange.

    ``show_motion=True`` adds a second plot: S = Π(α) [mm], Π' [mm/rad] and Π''
    [mm/rad²] over the turn against α [deg], the angle drawn as a dotted line and
    the working stroke (0 … α_p) shaded when ``k_Sp`` is given; ``ax`` must then be
    None (a new figure with both) or two axes, and the pair (mechanism, motion) is
    returned. ``title`` defaults to the angle and the design's parameters.

    Artists, by gid: ``"guide gear"`` (the ring), ``"guide pitch circle"``,
    ``"planet"``, ``"planet pitch circle"`` (patches), the lines ``"carrier"``,
    ``"arm"``, ``"rod"`` (two points each), ``"pin path"`` (x, y [mm] of the pin
    at ``np.linspace(0, 2π, n + 1)``), ``"pin path, working stroke"``,
    ``"working stroke"``, ``"rotation"``, the collections ``"joints"`` (O, C, P,
    slider), ``"slider"``, ``"guides"``, ``"guide hatching"``, ``"ground"``,
    ``"ground hatching"``, texts ``"label:O"`` …; on the motion plot the curves
    ``"S"``, ``"Π'"``, ``"Π''"`` (x data α [deg]), the line ``"α"`` and the
    shading ``"working stroke"``.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> import numpy as np, cyclomech as cm
    >>> from cyclomech.plot import plot_press
    >>> p = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.025, L=0.3, phi0=0.29)
    >>> ax = plot_press(p, np.radians(60))
    >>> ax.get_title().splitlines()[0]
    'Gear-lever press at α = 60° from BDC'
    >>> path = next(ln for ln in ax.get_lines() if ln.get_gid() == "pin path")
    >>> pin = p.solve(np.linspace(0, 2 * np.pi, 721)).pin * 1000   # [mm]
    >>> bool(np.allclose(path.get_xydata(), pin)), ax.get_xlabel()
    (True, 'x [mm]')
    >>> mech, motion = plot_press(p, np.radians(60), show_motion=True, k_Sp=0.1)
    >>> [ln.get_gid() for ln in motion.get_lines()][:3]
    ['S', "Π'", "Π''"]
    >>> plt.close("all")
    """
    plt = _matplotlib()
    from matplotlib.collections import LineCollection, PolyCollection
    from matplotlib.patches import Annulus, Circle

    press = _press_arg(press)
    try:
        a0 = float(alpha)
    except (TypeError, ValueError):
        raise InputError(f"alpha must be a crank angle [rad]; got {alpha!r}") from None
    if not math.isfinite(a0):
        raise InputError(f"alpha = {alpha!r} must be a finite crank angle [rad]")
    n = _count_arg("n", n, 8)
    show_motion = bool(show_motion)
    given = _axes_arg(
        ax,
        (2,) if show_motion else (1,),
        "plot_press with show_motion=True" if show_motion else "plot_press",
    )
    now = press.solve(np.array([a0]))
    if not now.ok[0]:
        raise InputError(
            f"alpha = {a0!r} rad ({_deg(math.degrees(a0))}): the rod (L = {_fmt(press.L * _MM)} "
            "mm) cannot reach the slider's guide at this angle; pick an angle where "
            "press.solve(alpha).ok is True"
        )
    turn = np.linspace(0.0, 2.0 * math.pi, n + 1)
    kin = press.solve(turn)
    alpha_p = math.nan
    why = ""
    k_text = ""
    if k_Sp is not None:
        crit = press.criteria(k_Sp=k_Sp, omega=1.0)  # α_p does not depend on ω
        alpha_p = crit.alpha_p
        k_text = f"k_Sp = {_fmt(crit.k_Sp)}"
        if not math.isfinite(alpha_p):
            why = f"\nno working stroke: {crit.status}"

    o = np.zeros(2)  # the guide gear's centre O
    c, pin, b = now.centre[0] * _MM, now.pin[0] * _MM, now.slider[0] * _MM
    big, small, off = press.R * _MM, press.r * _MM, press.offset * _MM
    path = kin.pin * _MM
    slide = kin.slider[kin.ok, 1] * _MM
    y_lo, y_hi = float(slide.min()), float(slide.max())
    allp = np.concatenate([path, [c, pin, b, [off, y_lo], [off, y_hi]]])
    span = max(float(np.ptp(allp[:, 0])), float(np.ptp(allp[:, 1])), 2.0 * big)
    s = 0.03 * span  # size of the symbols [mm]
    ring = max(0.09 * big, 0.6 * s)  # width of the guide gear's ring [mm]
    pad = 0.05 * span + 2.0 * s
    box = (
        min(-big - ring, float(allp[:, 0].min()), off - 2.0 * s) - pad,
        max(big + ring, float(allp[:, 0].max()), off + 2.0 * s) + pad,
        min(-big - ring, float(allp[:, 1].min()), y_lo - 2.0 * s) - pad,
        max(big + ring, float(allp[:, 1].max()), y_hi + 2.0 * s) + pad,
    )

    if given is None:
        w, h = box[1] - box[0], box[3] - box[2]
        if show_motion:
            height = 7.4
            mech_w = min(max(height * w / h + 0.9, 3.6), 8.0)
            fig = plt.figure(figsize=(mech_w + 7.8, height), layout="constrained")
            grid = fig.add_gridspec(1, 2, width_ratios=(mech_w, 7.8))
            axes = [fig.add_subplot(grid[0, 0]), fig.add_subplot(grid[0, 1])]
        else:
            _, ax0 = _linkage_figure(box)
            axes = [ax0]
    else:
        axes = given
    mech = axes[0]

    # The fixed guide gear: a hatched ring outside its pitch circle.
    mech.add_patch(
        Annulus(
            (0.0, 0.0),
            big + ring,
            ring,
            facecolor="0.93",
            edgecolor="0.45",
            hatch="////",
            linewidth=0.8,
            gid="guide gear",
            zorder=0.8,
        )
    )
    mech.add_patch(
        Circle(
            (0.0, 0.0),
            big,
            fill=False,
            edgecolor="0.25",
            linestyle=_CHAIN,
            linewidth=0.9,
            gid="guide pitch circle",
            label=f"pitch circles (R = {_fmt(big)} mm, r = {_fmt(small)} mm)",
            zorder=0.9,
        )
    )
    mech.add_patch(
        Circle(
            tuple(c),
            small,
            facecolor=PLATE_COLOR,
            edgecolor="none",
            alpha=0.85,
            gid="planet",
            zorder=1.0,
        )
    )
    mech.add_patch(
        Circle(
            tuple(c),
            small,
            fill=False,
            edgecolor="0.25",
            linestyle=_CHAIN,
            linewidth=0.9,
            gid="planet pitch circle",
            zorder=1.1,
        )
    )
    mech.plot(
        path[:, 0],
        path[:, 1],
        color=TRACE_COLORS[0],
        linewidth=0.9,
        label="pin path (hypotrochoid)",
        gid="pin path",
        zorder=1.3,
    )
    if math.isfinite(alpha_p):
        work = press.solve(np.linspace(0.0, alpha_p, max(16, int(n * alpha_p / math.tau) + 2)))
        wp = work.pin * _MM
        mech.plot(
            wp[:, 0],
            wp[:, 1],
            color=WORK_COLOR,
            linewidth=2.6,
            solid_capstyle="butt",
            label=f"working stroke ({k_text})",
            gid="pin path, working stroke",
            zorder=1.35,
        )
        ys = work.slider[work.ok, 1] * _MM
        xw = off + 1.9 * s
        mech.plot(
            [xw, xw],
            [float(ys.min()), float(ys.max())],
            color=WORK_COLOR,
            linewidth=3.2,
            solid_capstyle="butt",
            gid="working stroke",
            zorder=1.35,
        )

    # The slider's guide: two rails over its travel, hatched on the outside.
    half = 0.75 * s + 0.12 * s
    y0, y1 = y_lo - 1.8 * s, y_hi + 1.8 * s
    rails = [[(off - half, y0), (off - half, y1)], [(off + half, y0), (off + half, y1)]]
    mech.add_collection(
        LineCollection(rails, colors=LINK_COLOR, linewidths=1.0, gid="guides", zorder=1.4)
    )
    ticks = []
    for yk in np.arange(y0 + 0.2 * s, y1, 0.9 * s):
        ticks.append([(off - half, yk), (off - half - 0.5 * s, yk - 0.5 * s)])
        ticks.append([(off + half, yk), (off + half + 0.5 * s, yk - 0.5 * s)])
    mech.add_collection(
        LineCollection(ticks, colors=LINK_COLOR, linewidths=0.6, gid="guide hatching", zorder=1.4)
    )
    mech.add_collection(
        PolyCollection(
            [_block(b, (0.0, 1.0), s)],
            facecolors="#f4f4f4",
            edgecolors=LINK_COLOR,
            linewidths=1.2,
            gid="slider",
            zorder=3.0,
        )
    )

    # The ground symbol under O: a support triangle on a hatched base.
    g = 0.7 * s  # smaller than the slider's: the planet passes close to O
    yb = -1.5 * g
    mech.add_collection(
        PolyCollection(
            [[(0.0, 0.0), (-0.85 * g, yb), (0.85 * g, yb)]],
            facecolors="white",
            edgecolors=LINK_COLOR,
            linewidths=1.0,
            gid="ground",
            zorder=1.8,
        )
    )
    hatch = [[(-1.5 * g, yb), (1.5 * g, yb)]] + [
        [(xk, yb), (xk - 0.55 * g, yb - 0.6 * g)] for xk in np.linspace(-1.05 * g, 1.5 * g, 6)
    ]
    mech.add_collection(
        LineCollection(hatch, colors=LINK_COLOR, linewidths=0.8, gid="ground hatching", zorder=1.8)
    )

    mech.plot(
        [o[0], c[0]],
        [o[1], c[1]],
        color=DRIVER_COLOR,
        linewidth=3.4,
        solid_capstyle="round",
        label="carrier (crank)",
        gid="carrier",
        zorder=2.5,
    )
    mech.plot(
        [c[0], pin[0]],
        [c[1], pin[1]],
        color=LINK_COLOR,
        linewidth=2.0,
        solid_capstyle="round",
        gid="arm",
        zorder=2.2,
    )
    mech.plot(
        [pin[0], b[0]],
        [pin[1], b[1]],
        color=LINK_COLOR,
        linewidth=2.4,
        solid_capstyle="round",
        gid="rod",
        zorder=2.2,
    )
    pts = np.array([o, c, pin, b])
    mech.scatter(
        pts[:, 0],
        pts[:, 1],
        s=26.0,
        c="white",
        edgecolors=LINK_COLOR,
        linewidths=1.2,
        gid="joints",
        zorder=4.0,
    )

    # The carrier's sense of rotation, in the freest direction round O.
    down = np.array([0.0, -1.0])
    u = _label_direction([c - o, down, np.array([-0.7, -0.7]), np.array([0.7, -0.7])])
    mid = math.atan2(u[1], u[0])
    rho = 0.45 * (big - small)
    t = np.linspace(mid - 0.6, mid + 0.6, 40)
    arc = rho * np.column_stack([np.cos(t), np.sin(t)])
    mech.plot(arc[:-3, 0], arc[:-3, 1], color=DRIVER_COLOR, linewidth=1.1, gid="rotation")
    mech.annotate(
        "",
        xy=tuple(arc[-1]),
        xytext=tuple(arc[-4]),
        arrowprops={
            "arrowstyle": "-|>",
            "color": DRIVER_COLOR,
            "linewidth": 1.1,
            "shrinkA": 0.0,
            "shrinkB": 0.0,
            "mutation_scale": 11.0,
        },
    )
    mech.text(
        *(1.3 * rho * u),
        "ω",
        color=DRIVER_COLOR,
        fontsize=11,
        ha="center",
        va="center",
        path_effects=_halo(),
        gid="label:ω",
    )

    blocked = {
        "O": [c - o, down, np.array([-0.7, -0.7]), np.array([0.7, -0.7]), u],
        "C": [o - c, pin - c, b - pin],
        "P": [c - pin, b - pin],
        "slider": [pin - b, np.array([0.0, 1.0]), down, np.array([1.0, 0.0])],
    }
    named = [("O", o), ("C", c), ("P", pin), ("slider", b)]
    if press.d == 0.0:  # a crank-slider: the pin is the planet's centre
        named.pop(2)
    for name, q in named:
        d = _label_direction(blocked[name])
        edge = 1.3 * s if name == "slider" else 0.0
        text = "C = P" if name == "C" and press.d == 0.0 else name
        _point_label(mech, name, q + edge * np.array([d[0] * 0.6, d[1]]), d, text=text)

    _frame_equal(mech, box, "mm", grid="0.92")
    mech.legend(loc="upper center", bbox_to_anchor=(0.5, -0.09), frameon=False, fontsize=8)
    if title is None:
        title = (
            f"Gear-lever press at α = {_deg(math.degrees(a0))} from BDC\n{_design_text(press)}{why}"
        )
    mech.set_title(title, fontsize=10.5)
    if not show_motion:
        return mech

    motion = axes[1]
    deg = np.degrees(turn)
    curves = (
        ("S", kin.s, "S = Π(α)  [mm]"),
        ("Π'", kin.ds, "Π' = dS/dα  [mm/rad]"),
        ("Π''", kin.dds, "Π'' = d²S/dα²  [mm/rad²]"),
    )
    for (gid, v, label), color in zip(curves, MOTION_COLORS, strict=True):
        motion.plot(deg, v * _MM, color=color, linewidth=1.6, label=label, gid=gid)
    if math.isfinite(alpha_p):
        motion.axvspan(
            0.0,
            math.degrees(alpha_p),
            color=WORK_COLOR,
            alpha=0.28,
            linewidth=0.0,
            label=f"working stroke, {k_text} (α_p = {_deg(math.degrees(alpha_p))})",
            gid="working stroke",
            zorder=0.4,
        )
    x = deg[:-1]
    step = float(deg[1] - deg[0])
    for i, j in _runs(~kin.ok[:-1]):
        motion.axvspan(
            x[i] - step / 2,
            x[j] + step / 2,
            color="0.85",
            linewidth=0.0,
            label="rod cannot reach the guide" if i == _runs(~kin.ok[:-1])[0][0] else "_",
            gid="not assembled",
            zorder=0.3,
        )
    motion.axvline(
        math.degrees(a0 % math.tau),
        color="0.2",
        linestyle=":",
        linewidth=1.2,
        label=f"α = {_deg(math.degrees(a0))} (drawn)",
        gid="α",
    )
    motion.axhline(0.0, color="0.55", linewidth=0.6, zorder=0.5, gid="zero")
    # Near an angle where the rod cannot reach the guide Π'' runs off to infinity:
    # keep the scale of the rest of the turn.
    every = np.concatenate([kin.s, kin.ds, kin.dds]) * _MM
    every = every[np.isfinite(every)]
    if every.size:
        lo, hi = np.percentile(every, [2.0, 98.0])
        full_lo, full_hi = float(every.min()), float(every.max())
        if full_hi - full_lo > 4.0 * (hi - lo) > 0.0:
            motion.set_ylim(lo - 0.5 * (hi - lo), hi + 0.5 * (hi - lo))
    _angle_axis(motion, 360.0, "crank angle α from BDC (against the motion)")
    motion.set_ylabel("S [mm], Π' [mm/rad], Π'' [mm/rad²]")
    motion.grid(color="0.9", linewidth=0.6)
    motion.set_axisbelow(True)
    motion.legend(
        loc="upper center", bbox_to_anchor=(0.5, -0.09), ncols=2, frameon=False, fontsize=8
    )
    motion.set_title("Slider over one crank turn", fontsize=10.5)
    return mech, motion


#: How :func:`plot_press_criteria` shows each criterion: scale from SI, unit, name.
_CRITERION_SHOWN: dict[str, tuple[float, str, str]] = {
    "S_n": (_MM, "mm", "nominal stroke S_n"),
    "S_p": (_MM, "mm", "working stroke S_p"),
    "alpha_p": (180.0 / math.pi, "°", "crank angle of the working stroke α_p"),
    "V_np": (_MM, "mm/s", "speed at the start of the working stroke V_np"),
    "V_cp": (_MM, "mm/s", "mean speed over the working stroke V_cp"),
    "V_pmax": (_MM, "mm/s", "top speed over the working stroke V_pmax"),
    "J_max": (1.0, "m/s²", "largest acceleration J_max"),
    "torque": (_MM, "mm", "torque arm (max Π' over the working stroke)"),
    "k_Sp": (1.0, "", "k_Sp = S_p/S_n"),
    "k_Vp": (1.0, "", "k_Vp = V_np/V_cp  (→ 0)"),
    "k_Vmax": (1.0, "", "k_Vmax = V_pmax/V_cp  (→ 1)"),
    "k_M": (1.0, "", "k_M = torque arm/(S_n/2)  (→ min)"),
    "k_J": (1.0, "", "k_J = J_max/(ω²·S_n/2)  (→ min)"),
    "theta_bdc": (180.0 / math.pi, "°", "carrier angle of BDC θ_bdc"),
}


def _criterion_label(name: str) -> str:
    _, unit, text = _CRITERION_SHOWN[name]
    return f"{text}  [{unit}]" if unit else f"{text}  [–]"


def _badness(name: str, v: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """How bad a criterion's value is (lower is better): |k_Vmax − 1| for k_Vmax."""
    return np.abs(v - 1.0) if name == "k_Vmax" else v


def _edges(v: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """Cell edges round grid values (midpoints; half a step beyond the ends)."""
    mid = (v[1:] + v[:-1]) / 2
    return np.concatenate([[v[0] - (mid[0] - v[0])], mid, [v[-1] + (v[-1] - mid[-1])]])


def plot_press_criteria(
    sweep: PressGrid,
    ax: Axes | Any = None,
    *,
    criterion: str = "k_Vp",
    phi0: float | None = None,
    optimum: PressOptimum | None = None,
    title: str | None = None,
) -> Axes | tuple[Axes, Axes]:
    """Map a working-stroke criterion over (d, L) at one φ0; return the axes.

    ``sweep`` is a :func:`cyclomech.press.design_grid` (or ``optimum.grid``) with d and L
    among its axes (two or more values each; R and r fixed or of one value). The
    map shows ``criterion`` (a name of :data:`cyclomech.press.CRITERIA`; lengths
    in mm, speeds in mm/s, angles in degrees) over d [mm] across and L [mm] up,
    one cell per design, with a colour bar (clipped at the 98th percentile when a
    few designs are far worse) and a few labelled contour lines; designs that
    fail (status ≠ 0, see :data:`cyclomech.press.STATUS`) are masked and hatched.
    The best working design of the map (lowest value, |k_Vmax − 1| for k_Vmax) is
    a white star. d = 0 is the plain crank-slider.

    The map is at the grid's φ0 nearest ``phi0`` [rad]; by default at the φ0 of
    the best design of the whole sweep by ``criterion``, or, with ``optimum``, at
    the φ0 nearest its best design's.

    With ``optimum`` (a :func:`cyclomech.press.optimize`) a second plot shows its
    non-dominated designs: k_Vp across, k_Vmax up, coloured by k_J (refined
    designs as diamonds), the baseline crank-slider (``optimum.baseline``) as a
    black square, the best design circled in red and also starred on the map,
    and the ideal (0, 1). ``ax`` must then be None or two axes, and the pair
    (map, Pareto plot) is returned. ``title`` defaults to the criterion and φ0.

    Artists, by gid: the map ``"criterion"`` (a QuadMesh whose masked array holds
    the values shown, L by d), ``"failed"`` (one hatched square per failed
    design), ``"best in map"``, ``"optimum"``; on the Pareto plot ``"pareto"``
    (offsets k_Vp, k_Vmax; array k_J), ``"baseline"``, ``"best"``, ``"ideal"``.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> import numpy as np, cyclomech as cm
    >>> from cyclomech.plot import plot_press_criteria
    >>> sw = cm.press.design_grid(R=0.09, r=0.03, d=np.linspace(0, 0.04, 9),
    ...                     L=np.linspace(0.25, 0.5, 6), phi0=np.radians([0, 30, 55]),
    ...                     k_Sp=0.1, omega=4.0)
    >>> ax = plot_press_criteria(sw, phi0=np.radians(55))
    >>> ax.get_title().splitlines()[0], ax.get_xlabel()
    ('k_Vp over (d, L) at φ0 = 55°', 'eccentricity d [mm]  (d = 0: crank-slider)')
    >>> mesh = next(c for c in ax.collections if c.get_gid() == "criterion")
    >>> mesh.get_array().shape                               # L by d
    (6, 9)
    >>> plt.close("all")
    """
    plt = _matplotlib()
    from matplotlib.collections import PolyCollection
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    if not isinstance(sweep, PressGrid):
        raise InputError(
            f"sweep must be a cyclomech.press.PressGrid (cm.press.design_grid(...)); "
            f"got {type(sweep).__name__}"
        )
    if criterion not in _CRITERION_SHOWN:
        raise InputError(
            f"criterion = {criterion!r} is not known; criteria are {', '.join(_CRITERION_SHOWN)}"
        )
    if optimum is not None and not isinstance(optimum, PressOptimum):
        raise InputError(
            "optimum must be a cyclomech.press.PressOptimum (cm.press.optimize(...)) or None; "
            f"got {type(optimum).__name__}"
        )
    for name in ("d", "L"):
        if name not in sweep.axes or len(sweep.axes[name]) < 2:
            raise InputError(
                f"the sweep must vary {name} over two or more values to map it; its axes are "
                + ", ".join(f"{k} ({len(v)} values)" for k, v in sweep.axes.items())
            )
    for name, vals in sweep.axes.items():
        if name in ("R", "r") and len(vals) > 1:
            raise InputError(
                f"the sweep varies {name} over {len(vals)} values; map a sweep at one {name} "
                "(sweep it again with a scalar)"
            )
    given = _axes_arg(
        ax,
        (2,) if optimum is not None else (1,),
        "plot_press_criteria with optimum" if optimum is not None else "plot_press_criteria",
    )

    values = sweep.values[criterion]
    ok = sweep.ok
    names = list(sweep.axes)
    if "phi0" in sweep.axes:
        grid_phi = sweep.axes["phi0"]
        if phi0 is not None:
            try:
                target = float(phi0)
            except (TypeError, ValueError):
                raise InputError(f"phi0 must be an angle [rad] or None; got {phi0!r}") from None
            if not math.isfinite(target):
                raise InputError(f"phi0 = {phi0!r} must be a finite angle [rad]")
            k = int(np.argmin(np.abs(grid_phi - target)))
        elif optimum is not None:
            k = int(np.argmin(np.abs(grid_phi - optimum.designs[optimum.best].phi0)))
        else:
            bad = np.where(ok, _badness(criterion, values), np.inf)
            if not np.isfinite(bad).any():
                raise InputError("no design of the sweep works (every status ≠ 0): nothing to map")
            k = int(np.unravel_index(int(np.argmin(bad)), bad.shape)[names.index("phi0")])
        phi_shown = float(grid_phi[k])
    else:
        k = 0
        phi_shown = float(sweep.fixed["phi0"])
        if phi0 is not None and abs(float(phi0) - phi_shown) > 1e-12:
            raise InputError(
                f"the sweep holds φ0 fixed at {phi_shown!r} rad; phi0 = {phi0!r} is not in it"
            )
    idx = tuple(slice(None) if nm in ("d", "L") else (k if nm == "phi0" else 0) for nm in names)
    scale = _CRITERION_SHOWN[criterion][0]
    shown = values[idx] * scale  # (d, L): the axes' order
    good = ok[idx]
    if names.index("d") > names.index("L"):
        shown, good = shown.T, good.T
    shown, good = shown.T, good.T  # rows L, columns d
    data = np.ma.masked_array(shown, mask=~good | ~np.isfinite(shown))
    d_mm, l_mm = sweep.axes["d"] * _MM, sweep.axes["L"] * _MM
    de, le = _edges(d_mm), _edges(l_mm)

    if given is None:
        size = (14.0, 6.0) if optimum is not None else (7.8, 6.0)
        _, arr = plt.subplots(
            1, 2 if optimum is not None else 1, figsize=size, layout="constrained"
        )
        axes = list(np.atleast_1d(arr))
    else:
        axes = given
    m = axes[0]

    vis = data.compressed()
    extend = "neither"
    if vis.size:
        lo, hi = float(vis.min()), float(vis.max())
        top = float(np.percentile(vis, 98.0))
        if hi > lo and top < hi and (hi - lo) > 1.5 * (top - lo):
            hi, extend = top, "max"
    else:
        lo, hi = 0.0, 1.0
    if hi <= lo:
        hi = lo + 1.0
    mesh = m.pcolormesh(
        de, le, data, cmap="viridis", vmin=lo, vmax=hi, shading="flat", gid="criterion", zorder=0.5
    )
    cbar = m.figure.colorbar(mesh, ax=m, extend=extend, pad=0.02)
    cbar.set_label(_criterion_label(criterion))
    if vis.size > 3 and good.sum() >= 4:
        from matplotlib.ticker import MaxNLocator

        ticks = np.asarray(MaxNLocator(6).tick_values(lo, hi), dtype=float)
        levels = ticks[(ticks > lo) & (ticks < hi)]
        if levels.size:
            cs = m.contour(
                d_mm,
                l_mm,
                np.ma.filled(data.astype(float), np.nan),
                levels=levels,
                colors="white",
                linewidths=0.7,
                alpha=0.85,
                zorder=1.0,
            )
            m.clabel(cs, fontsize=7.5, fmt=lambda v: _fmt(float(v)))
            cs.set_gid("contours")
    failed = [
        [(de[j], le[i]), (de[j + 1], le[i]), (de[j + 1], le[i + 1]), (de[j], le[i + 1])]
        for i, j in zip(*np.nonzero(~good), strict=True)
    ]
    m.add_collection(
        PolyCollection(
            failed,
            facecolors="0.88",
            edgecolors="0.45",
            hatch="xxx",
            linewidths=0.0,
            gid="failed",
            zorder=1.2,
        )
    )
    handles: list[Any] = []
    if failed:
        handles.append(
            Patch(facecolor="0.88", edgecolor="0.45", hatch="xxx", label="fails (status ≠ 0)")
        )
    if vis.size:
        bad = np.ma.masked_array(_badness(criterion, shown / scale), mask=data.mask)
        i, j = np.unravel_index(int(np.ma.argmin(bad)), bad.shape)
        m.plot(
            [d_mm[j]],
            [l_mm[i]],
            linestyle="none",
            marker="*",
            markersize=13,
            markerfacecolor="white",
            markeredgecolor="black",
            markeredgewidth=0.8,
            gid="best in map",
            zorder=3.0,
        )
        handles.append(
            Line2D(
                [],
                [],
                linestyle="none",
                marker="*",
                markersize=11,
                markerfacecolor="white",
                markeredgecolor="black",
                label=f"best in this map: {criterion} = {_fmt(float(shown[i, j]))}",
            )
        )
    if optimum is not None:
        best = optimum.designs[optimum.best]
        m.plot(
            [best.d * _MM],
            [best.L * _MM],
            linestyle="none",
            marker="o",
            markersize=12,
            markerfacecolor="none",
            markeredgecolor=CRITICAL_COLOR,
            markeredgewidth=2.0,
            gid="optimum",
            zorder=3.1,
        )
        handles.append(
            Line2D(
                [],
                [],
                linestyle="none",
                marker="o",
                markersize=10,
                markerfacecolor="none",
                markeredgecolor=CRITICAL_COLOR,
                markeredgewidth=2.0,
                label=f"best design (φ0 = {_deg(math.degrees(best.phi0))})",
            )
        )
    m.set_xlim(de[0], de[-1])
    m.set_ylim(le[0], le[-1])
    m.set_xlabel("eccentricity d [mm]  (d = 0: crank-slider)")
    m.set_ylabel("rod length L [mm]")
    if handles:
        m.legend(
            handles=handles,
            loc="upper center",
            bbox_to_anchor=(0.5, -0.11),
            ncols=2,
            frameon=False,
            fontsize=8,
        )
    fixed: dict[str, float] = dict(sweep.fixed)
    fixed.update({nm: float(sweep.axes[nm][0]) for nm in ("R", "r") if nm in sweep.axes})
    stroke = (
        f"k_Sp = {_fmt(sweep.k_Sp)}"
        if sweep.k_Sp is not None
        else f"S_p = {_fmt(float(sweep.working_stroke or 0.0) * _MM)} mm"
    )
    head = f"{criterion} over (d, L) at φ0 = {_deg(math.degrees(phi_shown))}"
    m.set_title(
        (head if title is None else title)
        + f"\nR = {_fmt(fixed['R'] * _MM)} mm, r = {_fmt(fixed['r'] * _MM)} mm, {stroke}, "
        f"ω = {_fmt(sweep.omega)} rad/s",
        fontsize=10.5,
    )
    if optimum is None:
        return m

    p = axes[1]
    crit = optimum.criteria
    kv = np.array([c.k_Vp for c in crit])
    km = np.array([c.k_Vmax for c in crit])
    kj = np.array([c.k_J for c in crit])
    refined = np.array(optimum.refined, dtype=bool)
    base = optimum.baseline
    jlo = float(min(kj.min(), base.k_J))
    jhi = float(max(kj.max(), base.k_J))
    sc = p.scatter(
        kv,
        km,
        c=kj,
        cmap="plasma",
        vmin=jlo,
        vmax=jhi,
        s=30.0,
        marker="o",
        edgecolors="0.25",
        linewidths=0.4,
        gid="pareto",
        zorder=2.0,
    )
    sc.set_sizes(np.where(refined, 46.0, 30.0))
    if refined.any():
        p.scatter(
            kv[refined],
            km[refined],
            s=60.0,
            marker="D",
            facecolors="none",
            edgecolors="black",
            linewidths=0.9,
            gid="refined",
            zorder=2.1,
        )
    cb = p.figure.colorbar(sc, ax=p, pad=0.02)
    cb.set_label(_criterion_label("k_J"))
    top = max(float(kv.max()), float(km.max()), base.k_Vp, base.k_Vmax)
    # V_pmax ≥ V_np and V_pmax ≥ V_cp: no design lies below this line or below 1.
    p.plot(
        [1.0, top * 1.05],
        [1.0, top * 1.05],
        color="0.6",
        linestyle="--",
        linewidth=0.8,
        gid="diagonal",
        zorder=0.8,
        label="k_Vmax = k_Vp: fastest at the start of the working stroke",
    )
    p.plot(
        [base.k_Vp],
        [base.k_Vmax],
        linestyle="none",
        marker="s",
        markersize=9,
        color="black",
        gid="baseline",
        zorder=3.0,
        label=f"crank-slider, d = 0 (k_Vp = {_fmt(base.k_Vp)}, k_J = {_fmt(base.k_J)})",
    )
    bc = crit[optimum.best]
    p.plot(
        [bc.k_Vp],
        [bc.k_Vmax],
        linestyle="none",
        marker="o",
        markersize=14,
        markerfacecolor="none",
        markeredgecolor=CRITICAL_COLOR,
        markeredgewidth=2.0,
        gid="best",
        zorder=3.1,
        label=f"best design: d = {_fmt(best.d * _MM)} mm, L = {_fmt(best.L * _MM)} mm, "
        f"φ0 = {_deg(math.degrees(best.phi0))}",
    )
    p.plot(
        [0.0],
        [1.0],
        linestyle="none",
        marker="P",
        markersize=10,
        color="#2ca02c",
        gid="ideal",
        zorder=3.0,
        label="ideal (k_Vp = 0, k_Vmax = 1)",
    )
    if refined.any():
        p.plot(
            [],
            [],
            linestyle="none",
            marker="D",
            markerfacecolor="none",
            markeredgecolor="black",
            label="refined off the grid by scipy",
        )
    p.set_xlabel(_criterion_label("k_Vp"))
    p.set_ylabel(_criterion_label("k_Vmax"))
    p.set_xlim(left=-0.03 * top)
    p.grid(color="0.9", linewidth=0.6)
    p.set_axisbelow(True)
    p.legend(loc="upper center", bbox_to_anchor=(0.5, -0.11), ncols=1, frameon=False, fontsize=8)
    p.set_title(
        f"Non-dominated designs ({len(crit)}), objectives " + ", ".join(optimum.objectives),
        fontsize=10.5,
    )
    return m, p


# --- stop impact (seed 000) ---------------------------------------------------------


def plot_response(
    t: npt.ArrayLike,
    q: npt.ArrayLike,
    ax: Axes | None = None,
    *,
    force: npt.ArrayLike | None = None,
    rebound: tuple[float, float] | None = None,
    label: str | None = None,
    title: str | None = None,
) -> Axes:
    """Draw a response q(t) after an impact: q [mm] against t [ms]; return the axes.

    ``t`` [s] and ``q`` [m] as from :func:`cyclomech.impact.duhamel` or
    :meth:`cyclomech.impact.StopImpact.response`. ``force`` [N] on the same grid
    adds the pulse on a second y axis (shaded); ``rebound`` = (time [s], q [m])
    marks the first rebound with a dot and its value. The stop is q = 0 (a
    dashed line). Artists, by gid: ``"q"``, ``"force"``, ``"rebound"``,
    ``"label:rebound"``, ``"stop"``.

    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import cyclomech as cm
    >>> from cyclomech.plot import plot_response
    >>> lifter = cm.impact.StopImpact.example()
    >>> t, q = lifter.response(280, 40.0)
    >>> ax = plot_response(t, q, rebound=(float(t[q.argmax()]), float(q.max())))
    >>> ax.get_xlabel(), ax.get_ylabel()
    ('t after contact  [ms]', 'q, away from the stop  [mm]')
    """
    plt = _matplotlib()
    ta = np.asarray(t, dtype=np.float64)
    qa = np.asarray(q, dtype=np.float64)
    if ta.ndim != 1 or qa.shape != ta.shape:
        raise InputError(
            f"t and q must be 1-D arrays of one length; got shapes {ta.shape} and {qa.shape}"
        )
    if ax is None:
        _fig, ax = plt.subplots(figsize=(6.4, 3.6), layout="constrained")
    ax.axhline(0.0, color="0.4", lw=0.8, ls="--", gid="stop")
    ax.plot(ta * 1e3, qa * 1e3, color="C0", lw=1.4, label=label or "q(t)", gid="q")
    if force is not None:
        fa = np.asarray(force, dtype=np.float64)
        if fa.shape != ta.shape:
            raise InputError(f"force must have the shape of t {ta.shape}; got {fa.shape}")
        tw = ax.twinx()
        tw.fill_between(ta * 1e3, fa, color="C3", alpha=0.18, lw=0, gid="force")
        tw.plot(ta * 1e3, fa, color="C3", lw=0.8)
        tw.set_ylabel("impact force  [N]", color="C3")
        tw.tick_params(axis="y", colors="C3")
        tw.set_ylim(bottom=min(0.0, float(fa.min())) * 1.1, top=float(fa.max()) * 3.0 or 1.0)
    if rebound is not None:
        tr, qr = float(rebound[0]), float(rebound[1])
        if math.isfinite(tr):
            ax.plot([tr * 1e3], [qr * 1e3], "o", color="C1", ms=6, zorder=5, gid="rebound")
            ax.annotate(
                f"first rebound {qr * 1e3:.4g} mm",
                (tr * 1e3, qr * 1e3),
                xytext=(8, 6),
                textcoords="offset points",
                fontsize=8.5,
                gid="label:rebound",
            )
    ax.set_xlabel("t after contact  [ms]")
    ax.set_ylabel("q, away from the stop  [mm]")
    ax.set_xlim(float(ta[0]) * 1e3, float(ta[-1]) * 1e3)
    ax.margins(y=0.18)  # room for the rebound's label
    ax.grid(True, lw=0.4, alpha=0.5)
    if title is not None:
        ax.set_title(title)
    return ax


def plot_rebound_vs_speed(
    model: Any,
    rpm: npt.ArrayLike,
    *,
    phase_deg: npt.ArrayLike = (40.0,),
    a_max: float | None = None,
    responses: npt.ArrayLike | None = None,
    title: str | None = None,
) -> Figure:
    """The seed's fig. 8 for a :class:`cyclomech.impact.StopImpact`: on the left
    the motion after contact at a few speeds (``responses`` [rpm], default the
    ends and middle of ``rpm``, at the first phase angle), on the right the first
    rebound [mm] against speed ``rpm`` for each phase angle ``phase_deg`` [deg]
    (one Rust call), with the limit ``a_max`` [m] as a dashed line and the
    smallest admissible phase angle at the top speed noted. Returns the figure.
    Artists, by gid: ``"response:<rpm>"``, ``"rebound:<phase>"``, ``"a_max"``.

    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import numpy as np, cyclomech as cm
    >>> from cyclomech.plot import plot_rebound_vs_speed
    >>> fig = plot_rebound_vs_speed(cm.impact.StopImpact.example(), np.linspace(200, 450, 26),
    ...                             phase_deg=[30, 40, 50], a_max=0.1e-3)
    >>> len(fig.axes), fig.axes[1].get_xlabel()
    (2, 'main-shaft speed  [rpm]')
    """
    plt = _matplotlib()
    n = np.asarray(rpm, dtype=np.float64).reshape(-1)
    if n.size < 2 or not np.isfinite(n).all() or (n <= 0).any():
        raise InputError("rpm must hold at least two positive speeds [rpm]")
    phases = np.asarray(phase_deg, dtype=np.float64).reshape(-1)
    if phases.size < 1:
        raise InputError("phase_deg must hold at least one phase angle [deg]")
    shown = (
        np.array([n.min(), np.median(n), n.max()])
        if responses is None
        else np.asarray(responses, dtype=np.float64).reshape(-1)
    )
    fig, (left, right) = plt.subplots(
        1, 2, figsize=(11.0, 4.0), layout="constrained", width_ratios=(1.25, 1.0)
    )
    left.axhline(0.0, color="0.4", lw=0.8, ls="--")
    colors = plt.get_cmap("viridis")(np.linspace(0.1, 0.85, max(shown.size, 2)))
    for c, speed in zip(colors, shown, strict=False):
        t, q = model.response(float(speed), float(phases[0]))
        left.plot(
            t * 1e3, q * 1e3, color=c, lw=1.2, label=f"{speed:g} rpm", gid=f"response:{speed:g}"
        )
    left.set_xlabel("t after contact  [ms]")
    left.set_ylabel("q, away from the stop  [mm]")
    left.set_title(f"motion after contact, phase angle {phases[0]:g}°", fontsize=10)
    left.legend(fontsize=8, loc="upper right")
    left.grid(True, lw=0.4, alpha=0.5)
    a = model.rebound(n[:, None], phases[None, :])  # (speeds, phases), one call
    for j, ph in enumerate(phases):
        right.plot(
            n, a[:, j] * 1e3, "-o", ms=2.5, lw=1.4, label=f"t = {ph:g}°", gid=f"rebound:{ph:g}"
        )
    if a_max is not None:
        t_min = float(model.min_phase_angle(float(a_max), float(n.max())))
        note = (
            f"limit [a] = {float(a_max) * 1e3:g} mm: t ≥ {t_min:.3g}° at {n.max():g} rpm"
            if math.isfinite(t_min)
            else f"limit [a] = {float(a_max) * 1e3:g} mm: not reachable at {n.max():g} rpm"
        )
        # The note is the limit line's legend entry: text on the line was struck through.
        right.axhline(
            float(a_max) * 1e3, color=CRITICAL_COLOR, ls="--", lw=1.0, gid="a_max", label=note
        )
        right.set_ylim(0.0, 1.15 * max(float(a_max) * 1e3, float(np.nanmax(a)) * 1e3))
    else:
        right.set_ylim(bottom=0.0)
    right.set_xlabel("main-shaft speed  [rpm]")
    right.set_ylabel("first rebound  [mm]")
    right.legend(fontsize=8, loc="best")
    right.grid(True, lw=0.4, alpha=0.5)
    fig.suptitle(title or f"rebound at the stop ({model.model} model)", fontsize=11)
    return cast("Figure", fig)


def plot_transfer(
    path: Any,
    *,
    speed: Any = None,
    n: int = 4001,
    title: str | None = None,
) -> Figure:
    """Draw a rotor transfer path (:class:`cyclomech.transfer.TransferPath`);
    return the figure.

    Top left, the machine at equal scale [mm]: both rotors (light discs, their pitch
    circles dash-dot, centres marked), the path's ``n`` samples coloured by signed
    curvature [1/m] (a colour bar; blue where the path turns left round the
    transport rotor, red where it turns right round the process rotor), the points
    A, B_t, B_p, C where it leaves the transport circle, meets and leaves the
    straight, and joins the process circle. Top right, the same zoomed on the
    transfer A → C. Below, the curvature against arc length [mm] with the pieces
    shaded; with ``speed`` (V or (V_t, V_p) [m/s], see
    :meth:`~cyclomech.transfer.TransferPath.acceleration`) a last plot of the normal
    and tangential acceleration [m/s²] and the jerk |da/dt| [m/s³] (right axis), the
    jump without transitions as a dotted step for comparison.

    Artists, by gid: ``"path"`` (a LineCollection on both maps), ``"rotor t"``,
    ``"rotor p"``, ``"pitch t"``, ``"pitch p"``, ``"points"``, ``"curvature"``,
    ``"normal"``, ``"tangential"``, ``"jerk"``, ``"jump"``.

    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> import cyclomech as cm
    >>> from cyclomech.plot import plot_transfer
    >>> p = cm.transfer.TransferPath(0.15, 0.25, (0, 0), (0.41, 0), x2=0.05)
    >>> fig = plot_transfer(p, speed=0.157)
    >>> [ax.get_xlabel() for ax in fig.axes if ax.get_xlabel()]
    ['x  [mm]', 'x  [mm]', 'arc length s  [mm]', 'arc length s  [mm]']
    >>> sorted(ln.get_gid() for ax in fig.axes for ln in ax.get_lines() if ln.get_gid())[:4]
    ['curvature', 'jerk', 'jump', 'normal']
    >>> plt.close(fig)
    """
    plt = _matplotlib()
    from matplotlib.collections import LineCollection
    from matplotlib.colors import TwoSlopeNorm
    from matplotlib.patches import Circle

    from .transfer import TransferPath
    from .transfer._path import PIECES

    if not isinstance(path, TransferPath):
        raise InputError(
            f"path must be a cyclomech.transfer.TransferPath; got {type(path).__name__}"
        )
    n = _count_arg("n", n, 10)
    smp = path.sample(n)
    acc = path.acceleration(speed, n) if speed is not None else None
    pts = smp.points * 1e3
    kappa = smp.curvature
    rows = 3 if acc is not None else 2
    fig = plt.figure(figsize=(10.0, 3.6 * rows), layout="constrained")
    grid = fig.add_gridspec(rows, 2, height_ratios=[1.6] + [1.0] * (rows - 1))
    ax_map = fig.add_subplot(grid[0, 0])
    ax_zoom = fig.add_subplot(grid[0, 1])
    ax_k = fig.add_subplot(grid[1, :])
    lim = max(1.0 / path.R_t, 1.0 / path.R_p)
    norm = TwoSlopeNorm(vcenter=0.0, vmin=-lim, vmax=lim)
    segs = np.stack([pts[:-1], pts[1:]], axis=1)
    mid_k = 0.5 * (kappa[1:] + kappa[:-1])
    mappable = None
    for ax in (ax_map, ax_zoom):
        for c, r, tag, face in (
            (path.centre_t, path.R_t, "t", "#deebf7"),
            (path.centre_p, path.R_p, "p", "#fdd0a2"),
        ):
            cx, cy = c * 1e3
            ax.add_patch(
                Circle((cx, cy), r * 1e3 * 1.04, color=face, alpha=0.6, gid=f"rotor {tag}")
            )
            ax.add_patch(
                Circle(
                    (cx, cy), r * 1e3, fill=False, ls="-.", lw=0.8, ec="0.35", gid=f"pitch {tag}"
                )
            )
            ax.plot([cx], [cy], "+", color="0.2", ms=8)
        lc = LineCollection(segs, cmap="coolwarm_r", norm=norm, lw=2.4, gid="path")
        lc.set_array(mid_k)
        ax.add_collection(lc)
        mappable = lc
        marks = np.array([path.A, path.B_t, path.B_p, path.C]) * 1e3
        ax.plot(marks[:, 0], marks[:, 1], "o", ms=4.5, color="k", zorder=5, gid="points")
        ax.set_aspect("equal")
        ax.set_xlabel("x  [mm]")
        ax.set_ylabel("y  [mm]")
        ax.grid(True, lw=0.4, alpha=0.4)
    labels = [("A", path.A), ("B_t", path.B_t), ("B_p", path.B_p), ("C", path.C)]
    if path.straight_length < 0.02 * min(path.R_t, path.R_p):
        labels[1:3] = [("B", path.B_t)]  # no straight: the two ends coincide, one label
    for name, p in labels:
        ax_zoom.annotate(
            name,
            p * 1e3,
            xytext=(6, -10),
            textcoords="offset points",
            fontsize=9,
            gid=f"label:{name}",
        )
    everything = np.vstack(
        [
            pts,
            (path.centre_t + path.R_t * 1.05 * np.array([[-1, -1], [1, 1]])) * 1e3,
            (path.centre_p + path.R_p * 1.05 * np.array([[-1, -1], [1, 1]])) * 1e3,
        ]
    )
    lo, hi = everything.min(axis=0), everything.max(axis=0)
    ax_map.set_xlim(lo[0], hi[0])
    ax_map.set_ylim(lo[1], hi[1])
    zone = pts[(smp.piece >= 1) & (smp.piece <= 3)]
    centre = 0.5 * (zone.min(axis=0) + zone.max(axis=0))
    half = 0.65 * float(np.ptp(zone, axis=0).max()) + 1.0
    ax_zoom.set_xlim(centre[0] - half, centre[0] + half)
    ax_zoom.set_ylim(centre[1] - half, centre[1] + half)
    ax_zoom.set_title("transfer zone", fontsize=10)
    fig.colorbar(mappable, ax=ax_zoom, label="curvature  [1/m]", shrink=0.85)
    s_mm = smp.s * 1e3
    shades = ("#deebf7", "#f0f0f0", "white", "#f0f0f0", "#fdd0a2")
    ax_a = fig.add_subplot(grid[2, :]) if acc is not None else None
    for ax in [ax_k] if ax_a is None else [ax_k, ax_a]:
        for i, _name in enumerate(PIECES):
            on = smp.piece == i
            if on.any():
                ax.axvspan(s_mm[on][0], s_mm[on][-1], color=shades[i], lw=0, zorder=0)
        ax.set_xlim(s_mm[0], s_mm[-1])
        ax.set_xlabel("arc length s  [mm]")
        ax.grid(True, lw=0.4, alpha=0.5)
    ax_k.plot(s_mm, kappa, color="C0", lw=1.5, gid="curvature")
    ax_k.axhline(0.0, color="0.3", lw=0.6)
    ax_k.set_ylabel("curvature κ  [1/m]")
    if acc is not None and ax_a is not None:
        ax_a.plot(s_mm, acc.normal, color="C0", lw=1.5, label="normal v²κ", gid="normal")
        ax_a.plot(
            s_mm, acc.tangential, color="C2", lw=1.2, label="tangential v·dv/ds", gid="tangential"
        )
        v = acc.speed[[0, -1]]  # V_t before the transfer, V_p after it
        step = np.where(
            smp.s < path.start_of_transfer + 0.5 * path.transfer_length,
            v[0] ** 2 / path.R_t,
            -(v[1] ** 2) / path.R_p,
        )
        ax_a.plot(
            s_mm, step, color="0.3", lw=1.0, ls=":", label="no transition (a step)", gid="jump"
        )
        ax_a.set_ylabel("acceleration  [m/s²]")
        tw = ax_a.twinx()
        tw.plot(s_mm, acc.jerk, color="C3", lw=1.2, label="jerk |da/dt|", gid="jerk")
        tw.set_ylabel("jerk  [m/s³]", color="C3")
        tw.tick_params(axis="y", colors="C3")
        tw.set_ylim(bottom=0.0, top=float(acc.jerk.max()) * 1.15 or 1.0)
        lines = ax_a.get_lines() + tw.get_lines()
        ax_a.legend(lines, [ln.get_label() for ln in lines], fontsize=8, loc="lower left")
    if title is None:
        title = (
            f"Rotor transfer: R_t = {path.R_t * 1e3:.4g} mm → R_p = {path.R_p * 1e3:.4g} mm, "
            f"gap {path.gap * 1e3:.3g} mm, transitions x2 = {path.x2_t * 1e3:.3g} / "
            f"{path.x2_p * 1e3:.3g} mm, straight {path.straight_length * 1e3:.3g} mm"
        )
    fig.suptitle(title, fontsize=11)
    return fig


def plot_speed_sweep(
    sweep: Any,
    *,
    linear: Any = None,
    limit_rpm: float | None = None,
    limit_by: str | None = None,
    title: str | None = None,
) -> Figure:
    """The whole machine against speed, from :meth:`cyclomech.Machine.speed_sweep`,
    in panels sharing the speed axis [rpm]: the limiting operation's optimal angle
    [deg] and the time it gets [ms], and where the machine has stops, each stop's
    smallest phase angle [deg]; ``linear`` (a second sweep with the seed's
    linearised rebound constraints) dashed. ``limit_rpm`` [rpm], the machine's
    speed limit (set by ``limit_by``), is a vertical line: the curves end there
    and the speeds above it are shaded; without it, the speeds where the
    cyclogram does not fit are. Artists, by gid: ``"limiting"``,
    ``"limiting:linear"``, ``"time"``, ``"stop:<name>"``, ``"stop:<name>:linear"``,
    ``"limit"``, ``"above"``.

    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import cyclomech as cm
    >>> from cyclomech.plot import plot_speed_sweep
    >>> m = cm.Machine.example()
    >>> fig = plot_speed_sweep(m.speed_sweep(), limit_rpm=m.speed_limit().rpm)
    >>> [ax.get_ylabel() for ax in fig.axes]
    ['limiting operation  [deg]', 'its time  [ms]', 'smallest phase angle  [deg]']
    """
    plt = _matplotlib()
    stops = dict(sweep.min_phase_deg)
    rows = 3 if stops else 2
    fig, axes = plt.subplots(
        rows,
        1,
        figsize=(8.0, 7.5 if stops else 5.6),
        sharex=True,
        layout="constrained",
        height_ratios=(1.4, 1, 1)[:rows],
    )
    top, mid = axes[0], axes[1]
    n = np.asarray(sweep.rpm)
    limited = limit_rpm is not None and math.isfinite(limit_rpm)
    runs = n <= limit_rpm if limited else np.asarray(sweep.fits)

    def upto(y: Any) -> Any:  # the curve where the machine runs
        return np.where(runs, np.asarray(y, dtype=float), np.nan)

    top.plot(
        n,
        upto(sweep.limiting_deg),
        "-",
        lw=1.8,
        color="C0",
        label="with the stops' exact rebound bounds" if stops else "optimum",
        gid="limiting",
    )
    if linear is not None:
        top.plot(
            n,
            upto(linear.limiting_deg),
            "--",
            lw=1.3,
            color="C1",
            label="with the seed's linearised bounds",
            gid="limiting:linear",
        )
    top.set_ylabel("limiting operation  [deg]")
    mid.plot(n, upto(sweep.limiting_s * 1e3), "-", lw=1.6, color="C2", gid="time")
    mid.set_ylabel("its time  [ms]")
    if stops:
        low = axes[2]
        for i, (name, t) in enumerate(stops.items()):
            c = f"C{(i + 3) % 10}"
            low.plot(n, upto(t), "-", lw=1.6, color=c, label=f"{name}: exact", gid=f"stop:{name}")
            if linear is not None:
                low.plot(
                    n,
                    upto(linear.min_phase_deg[name]),
                    "--",
                    lw=1.2,
                    color=c,
                    label=f"{name}: linearised",
                    gid=f"stop:{name}:linear",
                )
        low.set_ylabel("smallest phase angle  [deg]")
        low.legend(fontsize=8, loc="upper left")
    axes[-1].set_xlabel("main-shaft speed  [rpm]")
    by = f" ({limit_by})" if limit_by else ""
    for ax in axes:
        ax.grid(True, lw=0.4, alpha=0.5)
        ax.set_xlim(float(n.min()), float(n.max()))
        if limited and limit_rpm < n.max():
            ax.axvspan(
                max(float(limit_rpm), float(n.min())),
                float(n.max()),
                color="0.85",
                alpha=0.6,
                lw=0,  # type: ignore[arg-type]
                label="above the speed limit" if ax is top else None,
                gid="above" if ax is top else None,
            )
        elif not limited and not runs.all():
            ax.fill_between(
                n,
                0,
                1,
                where=~runs,
                transform=ax.get_xaxis_transform(),
                color="0.85",
                alpha=0.6,
                lw=0,
                label="the cyclogram does not fit" if ax is top else None,
                gid="above" if ax is top else None,
            )
        if limited and n.min() <= limit_rpm <= n.max():
            ax.axvline(
                float(limit_rpm),
                color=CRITICAL_COLOR,
                ls="--",
                lw=1.0,  # type: ignore[arg-type]
                gid="limit" if ax is top else None,
                label=f"speed limit {limit_rpm:.1f} rpm{by}" if ax is top else None,
            )
    if not runs.any():
        top.text(
            0.5,
            0.5,
            (
                "the machine works at no speed:\nits cyclogram does not fit even at standstill"
                if limited and limit_rpm == 0
                else "the machine works at no speed of this range"
                + (f": its speed limit is {limit_rpm:.4g} rpm{by}" if limited else "")
            ),
            transform=top.transAxes,
            ha="center",
            va="center",
            fontsize=10,
            color=CRITICAL_COLOR,
        )
        top.set_yticks([])
        mid.set_yticks([])
    else:  # with nothing drawn, a legend would only name empty lines
        top.legend(fontsize=8, loc="lower left")
    fig.suptitle(title or "the machine against speed", fontsize=11)
    return cast("Figure", fig)


def plot_min_phase(
    rpm: npt.ArrayLike,
    exact: npt.ArrayLike,
    linear: npt.ArrayLike | None = None,
    *,
    minimum_deg: float | None = None,
    title: str | None = None,
    ax: Axes | None = None,
) -> Axes:
    """A stop's smallest admissible phase angle [deg] against speed ``rpm``:
    ``exact`` (solid) and the seed's ``linear`` form (dashed); ``minimum_deg`` is
    the operation's own minimum angle (dotted). Returns the axes. Artists, by
    gid: ``"exact"``, ``"linear"``, ``"minimum"``.

    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import numpy as np, cyclomech as cm
    >>> from cyclomech.plot import plot_min_phase
    >>> s = cm.Machine.example().mechanisms["lifter"]
    >>> n = np.linspace(200, 450, 11)
    >>> ax = plot_min_phase(n, s.min_phase_deg(n), s.linear_min_phase_deg(n))
    >>> ax.get_xlabel()
    'main-shaft speed  [rpm]'
    """
    plt = _matplotlib()
    if ax is None:
        _, ax = plt.subplots(figsize=(7.0, 4.0), layout="constrained")
    assert ax is not None
    ax.plot(rpm, exact, "-", lw=1.8, color="C0", label="exact", gid="exact")
    if linear is not None:
        ax.plot(rpm, linear, "--", lw=1.3, color="C1", label="seed's linearised form", gid="linear")
    if minimum_deg is not None:
        ax.axhline(
            minimum_deg, color="0.4", ls=":", lw=1.0, label="operation's own minimum", gid="minimum"
        )
    ax.set_xlabel("main-shaft speed  [rpm]")
    ax.set_ylabel("smallest phase angle  [deg]")
    ax.grid(True, lw=0.4, alpha=0.5)
    ax.legend(fontsize=8, loc="upper left")
    ax.set_title(
        title or "smallest phase angle that keeps the rebound within its limit", fontsize=10
    )
    return ax
