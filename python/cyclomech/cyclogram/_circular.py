"""The circular diagram of a cyclogram: its rings of bars round the cycle and
their labels; part of :mod:`cyclomech.cyclogram.plot`.

>>> from cyclomech.cyclogram._lanes import _layout
>>> import cyclomech as cm
>>> cg = cm.Cyclogram()
>>> cg.add_operation("a", "b", 300, mechanism="cam")
>>> cg.add_operation("b", "c", 100, mechanism="cam")   # 300° to 400°: wraps round to 0°
>>> cg.add_operation("a", "d", 90)
>>> _ring_r(_layout(cg.schedule()))[0]   # each row's inner radius, from the hole out
[1.2, 3.5, 4.8]
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from .._errors import InputError
from .._plotting import CRITICAL_COLOR, deg_text, halo, tick_step
from ._labels import fit_label, text_width_pt
from ._lanes import (
    _BAR_H,
    _EDGE,
    _FONT,
    _HATCH,
    _ROW_GAP,
    LIMITING_COLOR,
    MECHANISM_COLORS,
    _face,
    _Layout,
    _zero_marks,
)
from ._types import Optimum, Schedule

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.projections.polar import PolarAxes


def _require_polar(ax: Axes) -> None:
    if getattr(ax, "name", None) != "polar":
        raise InputError(
            "kind='circular' needs a polar axes, e.g. "
            "plt.subplots(subplot_kw={'projection': 'polar'}); "
            f"got a {getattr(ax, 'name', type(ax).__name__)!r} axes"
        )


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
