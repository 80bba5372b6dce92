"""Plot of a rotor transfer path: the machine at equal scale, the path's
curvature along its length and, at a given speed, its accelerations and jerk.

:func:`plot_transfer` takes a :class:`cyclomech.transfer.TransferPath`; it shows
lengths in millimetres.

matplotlib is an optional dependency (``pip install 'cyclomech[plot]'``), imported
only when the function draws; it returns a new figure and never calls
``plt.show()``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from .._arrays import count
from .._errors import InputError
from .._plotting import pyplot
from . import TransferPath
from ._path import PIECES

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["plot_transfer"]


def plot_transfer(
    path: Any,
    *,
    speed: Any = None,
    n: int = 4001,
    title: str | None = None,
) -> Figure:
    """Draw a rotor transfer path (:class:`cyclomech.transfer.TransferPath`); return the figure.

    Top left, the machine at equal scale [mm]: both rotors (light discs, their pitch
    circles dash-dot, centres marked), the path's ``n`` samples coloured by signed
    curvature [1/m] (a colour bar; blue where the path turns left round the
    transport rotor, red where it turns right round the process rotor), the points
    A, B_t, B_p, C where it leaves the transport circle, meets and leaves the
    straight, and joins the process circle. Top right, the same zoomed on the
    transfer A → C. Below, the curvature against arc length [mm] with the pieces
    shaded; with ``speed`` a last plot of the normal and tangential acceleration
    [m/s²] and the jerk |da/dt| [m/s³] (right axis), the jump without transitions as
    a dotted step for comparison.

    Artists, by gid: ``"path"`` (a LineCollection on both maps), ``"rotor t"``,
    ``"rotor p"``, ``"pitch t"``, ``"pitch p"``, ``"points"``, ``"curvature"``,
    ``"normal"``, ``"tangential"``, ``"jerk"``, ``"jump"``.

    Parameters
    ----------
    path : TransferPath
        The path to draw.
    speed : float or tuple of (float, float), optional
        The speed law, V or (V_t, V_p) [m/s] (see
        :meth:`~cyclomech.transfer.TransferPath.acceleration`); default None (no
        acceleration plot). Keyword-only, as are the parameters below.
    n : int, default 4001
        The number of samples along the path (≥ 10).
    title : str, optional
        The figure's title.

    Returns
    -------
    matplotlib.figure.Figure
        A new figure.

    Raises
    ------
    InputError
        If ``path`` is not a :class:`~cyclomech.transfer.TransferPath` or ``n`` is out
        of range.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> import cyclomech as cm
    >>> from cyclomech.transfer.plot import plot_transfer
    >>> p = cm.transfer.TransferPath(0.15, 0.25, (0, 0), (0.41, 0), x2=0.05)
    >>> fig = plot_transfer(p, speed=0.157)
    >>> [ax.get_xlabel() for ax in fig.axes if ax.get_xlabel()]
    ['x  [mm]', 'x  [mm]', 'arc length s  [mm]', 'arc length s  [mm]']
    >>> sorted(ln.get_gid() for ax in fig.axes for ln in ax.get_lines() if ln.get_gid())[:4]
    ['curvature', 'jerk', 'jump', 'normal']
    >>> plt.close(fig)
    """
    plt = pyplot()
    from matplotlib.collections import LineCollection
    from matplotlib.colors import TwoSlopeNorm
    from matplotlib.patches import Circle

    if not isinstance(path, TransferPath):
        raise InputError(
            f"path must be a cyclomech.transfer.TransferPath; got {type(path).__name__}"
        )
    n = count("n", n, low=10)
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
    segs: Any = np.stack([pts[:-1], pts[1:]], axis=1)  # (n - 1, 2, 2) [mm]
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
