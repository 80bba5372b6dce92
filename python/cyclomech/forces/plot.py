"""Plots of a linkage's forces: the driving torque and the joints' loads over the
crank angle (:func:`plot_forces`). matplotlib is imported only when drawing."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from .._arrays import finite_number
from .._errors import InputError
from .._notebook import register_figure
from .._plotting import CRITICAL_COLOR, angle_axis, pyplot
from . import _result

if TYPE_CHECKING:
    from ._result import Kinetostatics

__all__ = ["plot_forces"]


def plot_forces(k: Kinetostatics, rpm: float, *, title: str | None = None) -> Any:
    """The driving torque on the crank [N·m] and each joint's load [N] over the crank angle.

    Top: the torque; bottom: each joint's load (the largest force it exerts on a
    part it joins), against the crank angle [deg], the most loaded joint's peak
    marked and its curve drawn on top (the ends of a two-force link carry one
    force: their curves coincide).

    Parameters
    ----------
    k : Kinetostatics
        The forces over the turn (:func:`cyclomech.forces.kinetostatics`).
    rpm : float
        The crank speed [rpm] at which the inertia forces are evaluated.
    title : str, optional
        The top axes' title; default names the speed.

    Returns
    -------
    matplotlib.figure.Figure
        The figure, its two axes (torque, joint loads) in ``fig.axes``.

    Raises
    ------
    InputError
        If ``k`` is not a Kinetostatics or ``rpm`` is not a finite number.
    ImportError
        If matplotlib is not installed.

    Notes
    -----
    Artists by gid: ``"torque"``, ``"load[<joint>]"``, ``"peak"``.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import numpy as np, cyclomech as cm
    >>> from cyclomech.linkage import presets
    >>> lk = presets.burg_trimmer()
    >>> k = cm.forces.kinetostatics(lk, np.radians(np.arange(0.0, 360.0, 2.0)),
    ...                             point_masses={"E": 50.0}, gravity=(0, -9.81))
    >>> fig = plot_forces(k, 45.0)
    >>> [ax.get_ylabel() for ax in fig.axes]
    ['torque  [N·m]', 'joint load  [N]']
    >>> import matplotlib.pyplot as plt
    >>> plt.close(fig)
    """
    from ._result import Kinetostatics

    if not isinstance(k, Kinetostatics):
        raise InputError(
            f"plot_forces needs a Kinetostatics (cyclomech.forces.kinetostatics); got {k!r}"
        )
    n = finite_number("rpm", rpm, "[rpm]")
    plt = pyplot()
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8.0, 5.6), sharex=True, layout="constrained")
    deg = np.mod(np.degrees(k.angles), 360.0)
    order = np.argsort(deg)
    x = deg[order]
    top.plot(x, k.torque(n)[order], color="k", lw=1.4, gid="torque")
    top.axhline(0.0, color="0.6", lw=0.8)
    top.set_ylabel("torque  [N·m]")
    top.set_title(title or f"driving torque and joint loads at {n:g} rpm")
    if k.pairs:
        loads = k.joint_loads(n)
        joint, peak, at = k.most_loaded(n)
        # The most loaded joint drawn last and thicker: curves of joints that carry
        # one force (a two-force link's ends) lie on each other.
        keys = sorted(loads, key=lambda p: p == joint)
        for p in keys:
            i = list(loads).index(p)
            lw = 2.2 if p == joint else 1.1
            bottom.plot(x, loads[p][order], lw=lw, color=f"C{i % 10}", label=p, gid=f"load[{p}]")
        if joint:
            at = at % 360.0
            bottom.plot([at], [peak], "o", color=CRITICAL_COLOR, gid="peak")
            bottom.annotate(
                f"{joint}: {peak:,.0f} N", (at, peak), textcoords="offset points", xytext=(8, -12)
            )
        bottom.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.0, 1.0), title="joint")
    else:
        bottom.text(
            0.5,
            0.5,
            "joint forces not computed (reactions=False)",
            transform=bottom.transAxes,
            ha="center",
            va="center",
            color="0.4",
        )
    bottom.set_ylabel("joint load  [N]")
    angle_axis(bottom, 360.0, "crank angle  [deg]")
    for ax in (top, bottom):
        ax.grid(True, lw=0.4, alpha=0.5)
    return fig


def _torque_parts(k: Kinetostatics) -> Any:
    """The notebook's figure of a Kinetostatics (its ``_repr_html_``): the driving
    torque's three parts against the crank angle (no speed is given there)."""
    fig, axes = pyplot().subplots(3, 1, sharex=True, figsize=(6.4, 5.2), layout="constrained")
    deg = np.degrees(k.angles)
    labels = ["per (rad/s)² [N·m·s²]", "per rad/s² [N·m·s²]", "static [N·m]"]
    for ax, part, label in zip(axes, k.torque_parts, labels, strict=True):
        ax.plot(deg, part)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[0].set_title("Driving torque: ω²·(1) + ε·(2) + (3)")
    axes[-1].set_xlabel("crank angle [deg]")
    return fig


register_figure(_result.Kinetostatics, _torque_parts)
