"""The bars of a cyclogram's chart laid out in lanes (a row for each mechanism,
an operation that runs past the end of the cycle cut in two) and the style that
the Gantt chart and the circular diagram share; part of
:mod:`cyclomech.cyclogram.plot`.

>>> import cyclomech as cm
>>> cg = cm.Cyclogram()
>>> cg.add_operation("a", "b", 300, mechanism="cam")
>>> cg.add_operation("b", "c", 100, mechanism="cam")   # 300° to 400°: wraps round to 0°
>>> cg.add_operation("a", "d", 90)
>>> lay = _layout(cg.schedule())
>>> lay.rows, lay.lanes                 # the cam's two operations overlap at 0-40°
(('cam', '(other)'), (2, 1))
>>> _pieces(300.0, 100.0, 360.0)
[(300.0, 60.0), (0.0, 40.0)]
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from .._errors import InputError
from .._plotting import CRITICAL_COLOR
from ._angles import Arc
from ._operation import Operation
from ._types import Optimum, Schedule

if TYPE_CHECKING:
    from collections.abc import Mapping

    from matplotlib.axes import Axes


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


def _settle_layout(ax: Axes) -> None:
    """Let a layout engine (constrained layout) place the axes before text is fitted."""
    from matplotlib.figure import Figure

    root = getattr(ax.figure, "figure", ax.figure)  # a SubFigure's root figure
    if isinstance(root, Figure) and root.get_layout_engine() is not None:
        root.draw_without_rendering()


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


_ROW_GAP = 0.3  # extra space between mechanisms' rows [lanes]
