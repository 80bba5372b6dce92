"""Plots of a linkage: the mechanism at one crank angle with the paths of its
points, the position and analogs of a point over the crank turn, an animated GIF.

:func:`plot_linkage`, :func:`plot_analogs` and :func:`animate_linkage` take a
:class:`cyclomech.Linkage` and the :class:`~cyclomech.linkage.LinkageSolution` of
:meth:`~cyclomech.Linkage.solve` (lengths in metres, crank angles shown in
degrees). Their artists are listed in :func:`plot_linkage` and
:func:`plot_analogs`.

matplotlib is an optional dependency (``pip install 'cyclomech[plot]'``), imported
only when a function draws; the functions draw on the axes they are given (or on a
new figure), return what they drew on, and never call ``plt.show()``.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

import numpy as np
import numpy.typing as npt

from .._errors import InputError
from .._plotting import (
    DRIVER_COLOR,
    LINK_COLOR,
    PLATE_COLOR,
    TRACE_COLORS,
    deg_text,
    degree_ticks,
    frame_equal,
    ground_symbol,
    label_direction,
    mechanism_figure,
    point_label,
    pyplot,
    slider_block,
    true_runs,
    unit_vector,
)
from . import Linkage, LinkageSolution

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["animate_linkage", "plot_analogs", "plot_linkage"]


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
            f"({deg_text(math.degrees(solution.angles[good[0]]))})"
            if good.size
            else "it cannot be assembled at any angle of this solution"
        )
        raise InputError(
            f"index = {index}: the mechanism cannot be assembled at crank angle "
            f"{deg_text(math.degrees(solution.angles[i]))} (solution.ok[{i}] is False); "
            f"pick a row where solution.ok is True ({hint})"
        )
    return i


def _trace_names(trace: Any, solution: LinkageSolution) -> list[str]:
    if trace is None:
        return []
    names = [trace] if isinstance(trace, str) else trace
    if isinstance(names, Mapping):  # its keys are no list of names
        raise InputError(f"trace must be a list of point names; got {trace!r}")
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
            u = unit_vector(arg)
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
                u = unit_vector(arg)
            else:
                b, c = arg
                u = unit_vector(pos[c] - pos[b])
                t = float((pos[p] - pos[b]) @ u)
                length = float(np.hypot(*(pos[c] - pos[b])))
                if t < 0.0:
                    guides.append([pos[b], pos[p] - 1.5 * s * u])
                elif t > length:
                    guides.append([pos[c], pos[p] + 1.5 * s * u])
            blocks.append(slider_block(pos[p], u, s))
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
        corners, base = ground_symbol(x, y, s)
        tri.append(corners)
        hatch += base
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
        d = label_direction(blocked[p])
        # From the edge of a slider's block: half its length along the guide, half its
        # width across.
        edge = max(
            (
                1.3 * abs(float(d @ u)) + 0.75 * abs(float(d[0] * u[1] - d[1] * u[0]))
                for u in clear[p]
            ),
            default=0.0,
        )
        point_label(ax, p, pos[p] + edge * s * d, d)

    frame_equal(ax, box, "m", grid="0.9")
    if title is None:
        angle = f"crank angle {deg_text(math.degrees(solution.angles[i]))}"
        title = f"C{angle[1:]}" if linkage.name is None else f"{linkage.name} — {angle}"
    ax.set_title(title)


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

    The pose is ``solution.xy[index]`` [m]. Drawn at equal scale in metres: the
    links as lines between their joints (a link with three or more joints as a
    light plate with its outline; a link of ground joints only, the frame, is not
    drawn), the driving crank in red, the joints as small circles (a point of a
    body that is no joint, a filled dot), each ground joint on the ground symbol (a
    support on a hatched base), a block at each sliding point along its guide and a
    ground guide as a dashed line over the point's travel, every point labelled.

    Parameters
    ----------
    linkage : Linkage
        The linkage.
    solution : LinkageSolution
        A :meth:`~cyclomech.linkage.Linkage.solve` of every point of ``linkage`` (not a
        :func:`~cyclomech.linkage.solve_geometries`, not ``points=`` a subset),
        assembled at row ``index``.
    index : int, default 0
        The crank-angle row to draw (negative counts from the end).
    ax : matplotlib.axes.Axes, optional
        The axes to draw on; None (default) makes a new figure.
    trace : list of str, optional
        Points whose paths over the whole solution are drawn as thin lines (broken
        where the mechanism cannot be assembled).
    title : str, optional
        The axes' title; default the linkage's name and the crank angle [deg].

    Returns
    -------
    matplotlib.axes.Axes
        The axes drawn on (x and y in metres).

    Raises
    ------
    InputError
        If the solution is not one of every point of ``linkage``, ``index`` is out
        of range or the mechanism is not assembled there, a traced point is
        unknown, or ``ax`` is not an Axes.
    ImportError
        If matplotlib is not installed.

    Notes
    -----
    Artists (for tests and restyling), by label and gid: ``"links"``, a
    ``LineCollection`` with one path per link in the
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
    >>> from cyclomech.linkage.plot import plot_linkage
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
    pyplot()  # ImportError before anything else without matplotlib
    cols = _columns(linkage, solution)
    i = _row(solution, index)
    names = _trace_names(trace, solution)
    box = _extent(linkage, solution, cols, [i], names, _symbol_size(linkage))
    if ax is None:
        _, ax = mechanism_figure(box)
    elif not hasattr(ax, "add_collection"):
        raise InputError(f"ax must be a matplotlib Axes; got {type(ax).__name__}")
    _draw_linkage(ax, linkage, solution, cols, i, names, box, title)
    return ax


def plot_analogs(solution: LinkageSolution, point: str, *, title: str | None = None) -> Figure:
    """Position, velocity analog and acceleration analog of one point over the crank angle.

    Three stacked plots sharing the crank-angle axis [deg] (seed 001, fig. 4).
    Top: x and y of ``point`` [m]; middle: dx/dφ and dy/dφ [m/rad]; bottom:
    d²x/dφ² and d²y/dφ² [m/rad²] (φ the crank angle in radians; multiply by ω and
    ω² [rad/s, rad/s²] for the velocity and acceleration at a constant crank
    speed ω). The curves run in order of the angle. Angles where the mechanism
    cannot be assembled (``solution.ok`` False) are shaded grey, dead centres
    (``solution.singular``) marked by dotted lines, branch changes of a class III
    group (``solution.branch_change``) by dash-dotted ones.

    Parameters
    ----------
    solution : LinkageSolution
        A :meth:`~cyclomech.linkage.Linkage.solve` with analogs (not a sweep).
    point : str
        The point to plot.
    title : str, optional
        The figure's title; default names the point.

    Returns
    -------
    matplotlib.figure.Figure
        The figure, its three axes top to bottom in ``fig.axes``.

    Raises
    ------
    InputError
        If the solution is a sweep's or has no analogs, or has no such point.
    ImportError
        If matplotlib is not installed.

    Notes
    -----
    Artists, by gid: the curves ``"x"``, ``"y"``, ``"dx/dφ"``, ``"dy/dφ"``,
    ``"d²x/dφ²"``, ``"d²y/dφ²"`` (x data the angles [deg]), the shading
    ``"not assembled"``, the marks ``"singular"`` and ``"branch change"``.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> import numpy as np, cyclomech as cm
    >>> from cyclomech.linkage.plot import plot_analogs
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
    plt = pyplot()
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

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
        for a, b in true_runs(~solution.ok[order])
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
    degree_ticks(bottom.xaxis, max(hi - lo, 1.0))
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
    of ``solution`` where the mechanism is assembled. Uses matplotlib's
    ``PillowWriter`` (Pillow comes with matplotlib).

    Parameters
    ----------
    linkage : Linkage
        The linkage.
    solution : LinkageSolution
        A :meth:`~cyclomech.linkage.Linkage.solve` of every point of ``linkage``.
    path : str or os.PathLike
        The file to write; it must end in ``.gif``.
    fps : float, default 30
        Frames per second [1/s]: each frame is shown for 1/``fps`` s (GIF stores
        whole hundredths of a second).
    trace : list of str, optional
        Points whose paths are drawn, as in :func:`plot_linkage`.
    every : int, default 1
        Take every n-th row of the solution.
    dpi : float, default 100
        The frames' resolution [dots per inch].

    Returns
    -------
    pathlib.Path
        The GIF written.

    Raises
    ------
    InputError
        If ``path`` does not end in ``.gif``, ``every``, ``fps`` or ``dpi`` is not
        positive, a traced point is unknown, or the mechanism is assembled at none
        of the rows taken.
    ImportError
        If matplotlib is not installed.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import pathlib, tempfile
    >>> import numpy as np, cyclomech as cm
    >>> from PIL import Image
    >>> from cyclomech.linkage.plot import animate_linkage
    >>> lk = cm.Linkage({"A": (0, 0), "B": (1, 0), "C": (3.5, 2.5), "D": (4, 0)},
    ...                 [("A", "B"), ("B", "C"), ("C", "D")], ["A", "D"], ("A", "B"))
    >>> sol = lk.solve(np.radians(np.arange(0, 360, 30)))
    >>> gif = animate_linkage(lk, sol, pathlib.Path(tempfile.mkdtemp()) / "crank.gif",
    ...                       fps=10, trace=["C"], dpi=40)
    >>> with Image.open(gif) as im:                      # 12 angles, 30° apart
    ...     im.n_frames
    12
    """
    plt = pyplot()
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
    fig, ax = mechanism_figure(box)
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
