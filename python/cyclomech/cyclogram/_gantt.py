"""The Gantt chart of a cyclogram over its cycle: the bars, the parts beyond the
minimum, the slack whiskers and the labels; part of
:mod:`cyclomech.cyclogram.plot`.

>>> from cyclomech.cyclogram._lanes import _layout
>>> import cyclomech as cm
>>> cg = cm.Cyclogram()
>>> cg.add_operation("a", "b", 300, mechanism="cam")
>>> cg.add_operation("b", "c", 100, mechanism="cam")   # 300° to 400°: wraps round to 0°
>>> cg.add_operation("a", "d", 90)
>>> lay = _layout(cg.schedule())
>>> _lane_y(lay)[0]                     # each row's first lane: the cam's two, then a gap
[0.0, 2.3, 3.5999999999999996]
>>> round(_gantt_size(lay)[1], 6)        # figure height [in]: 1.3 + 0.42·3 lanes + 0.15·2 rows
2.86
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from .._plotting import CRITICAL_COLOR, deg_text, degree_ticks, halo
from ._labels import fit_label
from ._lanes import (
    _BAR_H,
    _EDGE,
    _FONT,
    _HATCH,
    _ROW_GAP,
    _SLACK,
    LIMITING_COLOR,
    _face,
    _first_free_lane,
    _Layout,
    _pieces,
    _settle_layout,
    _zero_marks,
)
from ._types import Optimum, Schedule

if TYPE_CHECKING:
    from collections.abc import Callable

    from matplotlib.axes import Axes


def _gantt_size(lay: _Layout) -> tuple[float, float]:
    """Figure size [in] of a Gantt chart: 0.42 in per lane, 0.15 in between rows."""
    return 11.0, 1.3 + 0.42 * sum(lay.lanes) + 0.15 * len(lay.rows)


# --------------------------------------------------------------------- gantt
def _lane_y(lay: _Layout) -> tuple[list[float], list[float]]:
    """Centre of each row's first lane and of each bar [y units, one per lane]."""
    base = [0.0]
    for n in lay.lanes:
        base.append(base[-1] + n + _ROW_GAP)
    return base, [base[b.row] + b.lane for b in lay.bars]


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
