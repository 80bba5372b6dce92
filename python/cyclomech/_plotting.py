"""Helpers that the domains' plot modules share (private): the matplotlib import,
the colours and number formats common to several plots, the checks of the ``ax``
argument, the degree axes, and the pieces of a mechanism drawing (links, slider
blocks, joint labels at equal scale) that the linkage and press plots both draw.

Each domain's plots live in its own public module (:mod:`cyclomech.cyclogram.plot`,
:mod:`cyclomech.linkage.plot`, …; :mod:`cyclomech.plot` re-exports them all). This
module imports matplotlib only inside its functions, so importing it (or a plot
module) works without matplotlib; :func:`pyplot` raises the ImportError that says
how to install it. Angles are degrees, lengths metres unless a name says mm.

>>> from cyclomech._plotting import deg_text, num_text, tick_step
>>> deg_text(245.0), deg_text(36.54), deg_text(-0.01)
('245°', '36.5°', '0°')
>>> tick_step(360.0), tick_step(120.0)
(30.0, 10.0)
>>> num_text(0.0123456), num_text(2.5e-5)
('0.0123', '2.500e-05')
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from ._errors import InputError

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.axis import Axis

#: Red of what is critical: the edges of critical operations in a cyclogram (zero
#: slack / held at their minimum by a priced bound), the limit lines of the stop,
#: press and machine plots.
CRITICAL_COLOR = "#d62728"
#: Colours of a position, its first and its second derivative (law and press plots).
MOTION_COLORS = ("#1f77b4", "#2ca02c", "#d62728")
MM = 1000.0  # mm per m: law and press plots show lengths in millimetres


def pyplot() -> Any:
    """matplotlib.pyplot, or an ImportError that says how to install it."""
    try:
        import matplotlib.pyplot as plt
    except ImportError as e:  # pragma: no cover - exercised only without matplotlib
        raise ImportError(
            "cyclomech's plots need matplotlib; install cyclomech[plot] "
            "(pip install 'cyclomech[plot]')"
        ) from e
    return plt


def halo() -> list[Any]:
    """A faint white outline that keeps labels legible over hatching and edges."""
    from matplotlib import patheffects

    return [patheffects.withStroke(linewidth=2.0, foreground=(1.0, 1.0, 1.0, 0.75))]


# ------------------------------------------------------------------ numbers and angles
def deg_text(x: float) -> str:
    """An angle as text, at most one decimal: 245°, 36.5°."""
    r = round(float(x), 1) + 0.0  # + 0.0 turns -0.0 into 0.0
    return f"{r:.1f}".rstrip("0").rstrip(".") + "°"


def num_text(v: float) -> str:
    """A value with three significant figures, no exponent for everyday sizes."""
    return f"{v:.3g}" if 1e-3 <= abs(v) < 1e5 or v == 0.0 else f"{v:.3e}"


def tick_step(cycle: float) -> float:
    """30° on a 360° cycle; in general the smallest of 5, 10, 15, 30, 45, 90, … [deg]
    that leaves at most 12 intervals."""
    for step in (5.0, 10.0, 15.0, 30.0, 45.0, 90.0, 180.0):
        if cycle / step <= 12.0 + 1e-9:
            return step
    return 90.0 * 2.0 ** math.ceil(math.log2(cycle / (90.0 * 12.0)))


def degree_ticks(axis: Axis, span: float) -> None:
    """Ticks on ``axis`` every :func:`tick_step` of ``span`` [deg], labelled 30°, 45°, …"""
    from matplotlib.ticker import FuncFormatter, MultipleLocator

    axis.set_major_locator(MultipleLocator(tick_step(span)))
    axis.set_major_formatter(FuncFormatter(lambda v, _pos: deg_text(v)))


def angle_axis(ax: Axes, hi_deg: float, label: str) -> None:
    """x from 0 to ``hi_deg`` [deg], ticks every 15°, 30°, … with ° labels."""
    ax.set_xlim(0.0, hi_deg)
    degree_ticks(ax.xaxis, hi_deg)
    ax.set_xlabel(label)


def true_runs(mask: npt.NDArray[np.bool_]) -> list[tuple[int, int]]:
    """(first, last) index of each run of True in ``mask``."""
    padded = np.concatenate([[False], mask, [False]]).astype(np.int8)
    d = np.diff(padded)
    return list(
        zip(np.flatnonzero(d == 1).tolist(), (np.flatnonzero(d == -1) - 1).tolist(), strict=True)
    )


# --------------------------------------------------------------------- the ax argument
def axes_arg(ax: Any, counts: tuple[int, ...], what: str) -> list[Axes] | None:
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


# ----------------------------------------- mechanism drawings (linkages and the press)
#: Colour of the links, joints and symbols of a linkage drawing.
LINK_COLOR = "#262626"
#: Face colour of the plates of links with three or more joints.
PLATE_COLOR = "#d6e2f0"
#: Colour of the driving crank.
DRIVER_COLOR = "#c0392b"
#: Colours of the traced paths, in the order of ``trace`` (then round again).
TRACE_COLORS = ("#1f77b4", "#2ca02c", "#9467bd", "#8c564b", "#e377c2", "#17becf")


def ground_symbol(
    x: float, y: float, s: float
) -> tuple[list[tuple[float, float]], list[list[tuple[float, float]]]]:
    """The ground symbol under a fixed pivot at (x, y) [m or mm], of size ``s`` (same
    unit): the support triangle's corners and the lines of its hatched base."""
    yb = y - 1.5 * s
    triangle = [(x, y), (x - 0.85 * s, yb), (x + 0.85 * s, yb)]
    hatch = [[(x - 1.5 * s, yb), (x + 1.5 * s, yb)]]
    for xk in np.linspace(x - 1.05 * s, x + 1.5 * s, 6):
        hatch.append([(xk, yb), (xk - 0.55 * s, yb - 0.6 * s)])
    return triangle, hatch


def unit_vector(v: Any) -> npt.NDArray[np.float64]:
    u = np.asarray(v, dtype=float)
    n = float(np.hypot(u[0], u[1]))
    return u / n if n > 0.0 else np.array([1.0, 0.0])


def slider_block(centre: Any, u: Any, s: float) -> npt.NDArray[np.float64]:
    """Corners of a slider block [m]: 2.6 s along the unit vector u, 1.5 s across."""
    u = unit_vector(u)
    n = np.array([-u[1], u[0]])
    a, b = 1.3 * s * u, 0.75 * s * n
    c = np.asarray(centre, dtype=float)
    return np.array([c - a - b, c + a - b, c + a + b, c - a + b])


def label_direction(blocked: list[npt.NDArray[np.float64]]) -> npt.NDArray[np.float64]:
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


def point_label(
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
        path_effects=halo(),
        gid=f"label:{name}",
        zorder=5.0,
    )


def frame_equal(ax: Any, box: Any, unit: str, *, grid: str) -> None:
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


def mechanism_figure(box: tuple[float, float, float, float]) -> Any:
    """A figure [in] whose axes fit a drawing of the extent ``box`` [m] at equal scale."""
    plt = pyplot()
    w, h = box[1] - box[0], box[3] - box[2]
    r = h / w if w > 0 else 1.0
    if r <= 1.1:
        size = (7.5, min(max(7.5 * r + 0.9, 3.2), 9.0))
    else:
        size = (min(max(7.0 / r + 1.0, 3.5), 7.5), 8.0)
    fig, ax = plt.subplots(figsize=size, layout="constrained")
    return fig, ax
