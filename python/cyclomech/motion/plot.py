"""Plot of a motion law: position, velocity and acceleration over the period.

:func:`plot_law` takes a :class:`cyclomech.motion.MotionLaw` or a
:class:`~cyclomech.motion.TwoPeriodLaw`; it shows lengths in millimetres and angles
in degrees.

matplotlib is an optional dependency (``pip install 'cyclomech[plot]'``), imported
only when the function draws; it draws on the axes it is given (or on a new
figure), returns what it drew on, and never calls ``plt.show()``.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from .._arrays import count
from .._errors import InputError
from .._plotting import MM, MOTION_COLORS, angle_axis, axes_arg, deg_text, halo, num_text, pyplot
from . import MotionLaw, TwoPeriodLaw

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["plot_law"]


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
        path_effects=halo(),
        gid=f"label:{gid}",
        zorder=5.0,
    )


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

    Parameters
    ----------
    law : MotionLaw or TwoPeriodLaw
        The law to draw (:func:`cyclomech.motion.law`,
        :func:`cyclomech.motion.two_period`).
    ax : matplotlib.axes.Axes or sequence of three Axes, optional
        None (default) makes a figure with three stacked plots sharing the angle
        axis (position, speed, acceleration, top to bottom); three axes to draw
        them on; or one Axes, which then holds all three curves and a legend.
    n : int, default 401
        The number of points per curve, at least 3 (the law's breaks and α1 are
        added).
    title : str, optional
        The title; default the law's name.

    Returns
    -------
    tuple of matplotlib.axes.Axes
        The axes drawn on: three (position, speed, acceleration), or the one given.

    Raises
    ------
    InputError
        If ``law`` is neither a MotionLaw nor a TwoPeriodLaw, ``n`` is below 3, or
        ``ax`` is neither one Axes nor three.
    ImportError
        If matplotlib is not installed.

    Notes
    -----
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
    >>> from cyclomech.motion.plot import plot_law
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
    plt = pyplot()
    from matplotlib.transforms import blended_transform_factory

    if not isinstance(law, MotionLaw | TwoPeriodLaw):
        raise InputError(
            "law must be a cyclomech.motion.MotionLaw (cm.motion.law(...)) or a "
            f"cyclomech.motion.TwoPeriodLaw (cm.motion.two_period(...)); got {type(law).__name__}"
        )
    n = count("n", n, low=3)
    given = axes_arg(ax, (1, 3), "plot_law")
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
            law.position(alpha) * MM,
            law.velocity(alpha) * MM,
            law.acceleration(alpha) * MM,
        )
        names = ("Π", "Π'", "Π''")
        ylabels = ("Π  [mm]", "Π' = dΠ/dα  [mm/rad]", "Π'' = d²Π/dα²  [mm/rad²]")
        head = (
            f"Two-period law: {law.law1.name.replace('_', ' ')} (I) + "
            f"{law.law2.name.replace('_', ' ')} (II)\nΠ2 = {num_text(law.stroke * MM)} mm "
            f"in α2 = {deg_text(math.degrees(a2))}, f_A = {num_text(law.asymmetry)}, "
            f"α1 = {deg_text(math.degrees(a1))}"
        )
        for k, p in enumerate(panels):
            p.plot(x, ys[k], color=MOTION_COLORS[k], linewidth=1.6, label=names[k], gid=names[k])
        for k, p in enumerate(axes):
            angle_axis(p, float(x[-1]), "crank angle α from BDC" if p is axes[-1] else "")
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
            f"Π'max = {num_text(law.max_speed * MM)} mm/rad",
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
                f"{label} = {num_text(abs(float(ys[2][j])))} mm/rad²",
                label,
                MOTION_COLORS[2],
            )
        top = axes[0]
        tr = blended_transform_factory(top.transData, top.transAxes)
        for lo, hi, text in (
            (0.0, a1, f"period I  ({deg_text(math.degrees(a1))})"),
            (a1, a2, f"period II  ({deg_text(math.degrees(a2 - a1))})"),
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
