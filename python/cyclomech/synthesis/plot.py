"""Plots of the knife-drive comparison (:func:`plot_knife_motion`,
:func:`plot_knife_torque`). matplotlib is imported only when drawing."""

from __future__ import annotations

from typing import Any

from .._errors import InputError
from .._plotting import angle_axis, pyplot
from ._knife_compare import KnifeComparison

__all__ = ["plot_knife_motion", "plot_knife_torque"]


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
    ...     cm.synthesis.KnifeRequirement(0.15, 175.0, maxiter=30), schemes=("br125",))
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
    ...     cm.synthesis.KnifeRequirement(0.15, 175.0, maxiter=30), schemes=("br125",))
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
