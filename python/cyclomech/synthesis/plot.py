"""Plots of the knife-drive comparison (:func:`plot_knife_motion`,
:func:`plot_knife_torque`) and of Burmester's curves (:func:`plot_burmester`).
matplotlib is imported only when drawing."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from .._errors import InputError
from .._plotting import angle_axis, axes_arg, pyplot
from ._burmester import BurmesterCurves
from ._knife_compare import KnifeComparison
from ._motion import MotionCandidate

__all__ = ["plot_burmester", "plot_knife_motion", "plot_knife_torque"]

_DYAD_COLORS = ("#9467bd", "#2ca02c", "#8c564b", "#e377c2", "#17becf", "#ff7f0e")


def _check(c: Any) -> KnifeComparison:
    if not isinstance(c, KnifeComparison):
        raise InputError(
            "needs a KnifeComparison (cyclomech.synthesis.compare_knife_drives); "
            f"got {type(c).__name__}"
        )
    return c


def plot_knife_motion(comparison: KnifeComparison, *, title: str | None = None) -> Any:
    """The knife's displacement [mm] and acceleration [m/s²] over the crank angle
    for each compared scheme, the angle counted from each one's top.

    Parameters
    ----------
    comparison : KnifeComparison
        The result of :func:`~cyclomech.synthesis.compare_knife_drives`.
    title : str, optional
        The top axes' title.

    Returns
    -------
    matplotlib.figure.Figure
        Two axes (displacement, acceleration); artists by gid ``"s[<scheme>]"``,
        ``"acc[<scheme>]"``.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import cyclomech as cm
    >>> from cyclomech.synthesis.plot import plot_knife_motion
    >>> c = cm.synthesis.compare_knife_drives(
    ...     cm.synthesis.KnifeRequirement(0.15, 175.0, popsize=8, maxiter=30), schemes=("br125",))
    >>> fig = plot_knife_motion(c)
    >>> [ax.get_ylabel() for ax in fig.axes]
    ['knife displacement  [mm]', 'knife acceleration  [m/s²]']
    >>> import matplotlib.pyplot as plt
    >>> plt.close(fig)
    """
    c = _check(comparison)
    plt = pyplot()
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8.0, 5.6), sharex=True, layout="constrained")
    for i, (s, cv) in enumerate(c.curves.items()):
        top.plot(c.angles, 1e3 * cv["s"], color=f"C{i}", lw=1.4, label=s, gid=f"s[{s}]")
        bottom.plot(c.angles, cv["acc"], color=f"C{i}", lw=1.4, label=s, gid=f"acc[{s}]")
    r = c.requirement
    top.axvline(r.cut_deg, color="0.5", lw=0.8, ls="--")
    top.set_ylabel("knife displacement  [mm]")
    top.set_title(
        title
        or f"knife motion, stroke {r.stroke_m * 1e3:g} mm, cut {r.cut_deg:g}°, at {c.rpm:g} rpm"
    )
    top.legend(fontsize=8, title="scheme")
    bottom.axhline(0.0, color="0.6", lw=0.8)
    bottom.set_ylabel("knife acceleration  [m/s²]")
    angle_axis(bottom, 360.0, "crank angle from the top  [deg]")
    return fig


def plot_knife_torque(comparison: KnifeComparison, *, title: str | None = None) -> Any:
    """The driving torque [N·m] of each compared scheme over the crank angle from
    its top, at the comparison's speed.

    Parameters
    ----------
    comparison : KnifeComparison
        The result of :func:`~cyclomech.synthesis.compare_knife_drives`.
    title : str, optional
        The axes' title.

    Returns
    -------
    matplotlib.figure.Figure
        One axes; artists by gid ``"torque[<scheme>]"``.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import cyclomech as cm
    >>> from cyclomech.synthesis.plot import plot_knife_torque
    >>> c = cm.synthesis.compare_knife_drives(
    ...     cm.synthesis.KnifeRequirement(0.15, 175.0, popsize=8, maxiter=30), schemes=("br125",))
    >>> fig = plot_knife_torque(c)
    >>> fig.axes[0].get_ylabel()
    'driving torque  [N·m]'
    >>> import matplotlib.pyplot as plt
    >>> plt.close(fig)
    """
    c = _check(comparison)
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8.0, 3.6), layout="constrained")
    for i, (s, cv) in enumerate(c.curves.items()):
        ax.plot(c.angles, cv["torque"], color=f"C{i}", lw=1.4, label=s, gid=f"torque[{s}]")
    ax.axhline(0.0, color="0.6", lw=0.8)
    ax.set_ylabel("driving torque  [N·m]")
    ax.set_title(title or f"driving torque at {c.rpm:g} rpm")
    ax.legend(fontsize=8, title="scheme")
    angle_axis(ax, 360.0, "crank angle from the top  [deg]")
    return fig


def plot_burmester(
    curves: BurmesterCurves,
    candidates: Sequence[MotionCandidate] = (),
    *,
    ax: Any = None,
    extent_m: float | None = None,
    title: str | None = None,
) -> Any:
    """Burmester's curves of four poses in the fixed frame: the circle-point curve
    drawn in the first pose, the centre-point curve, the poses (a point and an
    arrow along each pose angle) and the dyads of the chosen four-bars (ground
    pivot to moving pivot in the first pose, and the coupler).

    Parameters
    ----------
    curves : BurmesterCurves
        From :func:`~cyclomech.synthesis.burmester_curves`.
    candidates : sequence of MotionCandidate
        Four-bars whose dyads to draw (from
        :func:`~cyclomech.synthesis.motion_generation` with the same poses).
    ax : matplotlib Axes, optional
        Where to draw; a new figure if None.
    extent_m : float, optional
        Half-width of the view around the poses [m]; default three times their
        spread (the curves run off to infinity).
    title : str, optional
        The axes' title.

    Returns
    -------
    matplotlib.figure.Figure
        Artists by gid ``"circle_points"``, ``"centre_points"``, ``"poses"``,
        ``"dyad[<k>]"``.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import cyclomech as cm
    >>> from cyclomech.synthesis.plot import plot_burmester
    >>> poses = [(0, 0, 0), (0.5, 0.2, 20), (0.9, 0.6, 45), (1.2, 1.1, 70)]
    >>> fig = plot_burmester(cm.synthesis.burmester_curves(poses, samples=256))
    >>> fig.axes[0].get_xlabel()
    'x  [m]'
    >>> import matplotlib.pyplot as plt
    >>> plt.close(fig)
    """
    if not isinstance(curves, BurmesterCurves):
        raise InputError(
            "plot_burmester needs a BurmesterCurves (cyclomech.synthesis.burmester_curves); "
            f"got {type(curves).__name__}"
        )
    cands = _candidates(candidates)
    plt = pyplot()
    axes = axes_arg(ax, (1,), "plot_burmester")
    if axes is None:
        fig, a = plt.subplots(figsize=(7.0, 6.0), layout="constrained")
    else:
        a = axes[0]
        fig = a.figure
    xy = np.array([p[:2] for p in curves.poses])
    spread = float(np.ptp(xy, axis=0).max()) or 1.0
    half = 3.0 * spread if extent_m is None else float(extent_m)
    mid = xy.mean(axis=0)
    moving = curves.moving_points()
    a.plot(
        moving[:, 0],
        moving[:, 1],
        color="#1f77b4",
        lw=1.3,
        gid="circle_points",
        label="circle points (pose 1)",
    )
    a.plot(
        curves.centre_points[:, 0],
        curves.centre_points[:, 1],
        color="#d62728",
        lw=1.3,
        gid="centre_points",
        label="centre points",
    )
    _draw_poses(a, curves.poses, spread)
    for k, c in enumerate(cands):
        (a0, b0), (pa, pb) = c.centre_points, c.moving_pivots
        pts = np.array([a0, pa, pb, b0])
        a.plot(
            pts[:, 0],
            pts[:, 1],
            "-o",
            color=_DYAD_COLORS[k % len(_DYAD_COLORS)],
            lw=2.0,
            ms=5,
            gid=f"dyad[{k}]",
            label=f"four-bar {k + 1}",
        )
        a.plot([a0[0], b0[0]], [a0[1], b0[1]], "^", color=_DYAD_COLORS[k % len(_DYAD_COLORS)], ms=9)
    a.set_xlim(mid[0] - half, mid[0] + half)
    a.set_ylim(mid[1] - half, mid[1] + half)
    a.set_aspect("equal")
    a.grid(True, color="0.9")
    a.set_xlabel("x  [m]")
    a.set_ylabel("y  [m]")
    a.legend(fontsize=8, loc="best")
    a.set_title(title or "Burmester's curves of four poses")
    return fig


def _candidates(candidates: Any) -> list[MotionCandidate]:
    try:
        cands = list(candidates)
    except TypeError:
        cands = [candidates]
    if not all(isinstance(c, MotionCandidate) for c in cands):
        raise InputError(
            "plot_burmester: candidates must be MotionCandidates "
            f"(cyclomech.synthesis.motion_generation); got {candidates!r}"
        )
    return cands


def _draw_poses(a: Any, poses: Sequence[Sequence[float]], spread: float) -> None:
    """Each pose as a point with an arrow along its angle and its number."""
    arrow = 0.25 * spread
    for k, (x, y, t) in enumerate(poses):
        dx, dy = arrow * math.cos(math.radians(t)), arrow * math.sin(math.radians(t))
        a.annotate(
            "", (x + dx, y + dy), (x, y), arrowprops={"arrowstyle": "->", "color": "0.2", "lw": 1.2}
        )
        a.text(x - 0.5 * dy, y + 0.5 * dx, str(k + 1), fontsize=9, ha="center", va="center")
    xy = np.array([p[:2] for p in poses])
    a.plot(xy[:, 0], xy[:, 1], "o", color="0.2", ms=4, gid="poses", label="poses")
