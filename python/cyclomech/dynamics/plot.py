"""Plots of the frame's shaking (:func:`plot_shaking`): the shaking force's
hodograph, before and after balancing, and the shaking moment over the cycle.
matplotlib is imported only when drawing."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .._arrays import finite_number
from .._errors import InputError
from .._plotting import angle_axis, pyplot
from ._balance import Balance
from ._shaking import Shaking

__all__ = ["plot_shaking", "plot_torsion"]


def plot_shaking(
    shaking: Any, rpm: Any, *, title: str | None = None, angle_name: str | None = None
) -> Any:
    """The shaking force's hodograph (a polar plot) and the shaking moment over the cycle.

    Left: the tip of the force vector (F_x, F_y) [N] over the cycle, as a closed
    curve around the origin (the frame sees this force turn and pulse), its peak
    marked with the angle of the cycle it occurs at (the polar plot's own angles
    are the force's direction); right: the shaking moment [N·m] against that
    angle. Given a :class:`~cyclomech.dynamics.Balance`, both before (grey) and
    after balancing.

    Parameters
    ----------
    shaking : Shaking or Balance
        A mechanism's or machine's shaking (:func:`cyclomech.dynamics.shaking`), or a
        balance (:func:`cyclomech.dynamics.balance`).
    rpm : float
        The speed [rpm] of the inertia forces.
    title : str, optional
        The figure's title; default names the speed.
    angle_name : str, optional
        What the angles are, for the peak's label and the moment's axis; default
        "cycle angle" for a machine's shaking (one with ``parts``), "crank angle"
        for a mechanism's or a balance.

    Returns
    -------
    matplotlib.figure.Figure
        The figure; ``fig.axes`` the hodograph (polar) and the moment axes.

    Raises
    ------
    InputError
        If ``shaking`` is neither a Shaking nor a Balance or ``rpm`` is not a finite
        number.
    ImportError
        If matplotlib is not installed.

    Notes
    -----
    Artists by gid: ``"force"``, ``"force before"``, ``"peak"``, ``"moment"``,
    ``"moment before"``; the hodograph's title names the peak and the angle it is at.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import numpy as np, cyclomech as cm
    >>> crank = cm.Linkage({"O": (0, 0), "A": (0.1, 0)}, [("O", "A")], ["O"], ("O", "A"))
    >>> k = cm.forces.kinetostatics(crank, np.radians(np.arange(0.0, 360.0, 5.0)),
    ...                             point_masses={"A": 2.0})
    >>> fig = plot_shaking(cm.dynamics.shaking(k), 300.0)
    >>> fig.axes[0].name, fig.axes[1].get_ylabel(), fig.axes[1].get_xlabel()
    ('polar', 'shaking moment  [N·m]', 'crank angle  [deg]')
    >>> import matplotlib.pyplot as plt
    >>> plt.close(fig)
    """
    if isinstance(shaking, Balance):
        after, before = shaking.shaking_after, shaking.shaking_before
    elif isinstance(shaking, Shaking):
        after, before = shaking, None
    else:
        raise InputError(
            "plot_shaking needs a Shaking (cyclomech.dynamics.shaking) or a Balance "
            f"(cyclomech.dynamics.balance); got {type(shaking).__name__}"
        )
    n = finite_number("rpm", rpm, "[rpm]")
    if angle_name is None:
        angle_name = "cycle angle" if after.parts else "crank angle"
    elif not isinstance(angle_name, str):
        raise InputError(f"angle_name = {angle_name!r} must be a str (e.g. 'crank angle')")
    plt = pyplot()
    from matplotlib.ticker import MultipleLocator

    fig = plt.figure(figsize=(10.0, 4.4), layout="constrained")
    polar = fig.add_subplot(1, 2, 1, projection="polar")
    right = fig.add_subplot(1, 2, 2)

    def closed(v: Any) -> Any:
        return np.concatenate([v, v[:1]])

    for s, name, style in (
        (before, "before", {"color": "0.55", "lw": 1.0, "ls": "--"}),
        (after, "", {"color": "C0", "lw": 1.6}),
    ):
        if s is None:
            continue
        f = s.force(n)
        mag, ang = np.hypot(f[:, 0], f[:, 1]), np.arctan2(f[:, 1], f[:, 0])
        gid = f"force {name}".strip()
        label = "balanced" if before is not None and not name else (name or "shaking force")
        polar.plot(closed(ang), closed(mag), gid=gid, label=label, **style)
        x = np.mod(s.angles_deg, 360.0)
        order = np.argsort(x)
        m = s.moment(n)
        right.plot(x[order], m[order], gid=f"moment {name}".strip(), label=label, **style)
    f = after.force(n)
    mag = np.hypot(f[:, 0], f[:, 1])
    # A force that is zero to rounding (balanced, or a lever shaking by a couple
    # only) has no peak to place: its "angle" would be the rounding's.
    scale = float(mag.max(initial=0.0))
    if before is not None:
        scale = max(scale, float(np.hypot(*before.force(n).T).max(initial=0.0)))
    if mag.size and float(mag.max()) > 1e-9 * scale:
        i = int(np.argmax(mag))
        polar.plot([np.arctan2(f[i, 1], f[i, 0])], [mag[i]], "o", color="C3", gid="peak")
        peak = f"peak {mag[i]:,.0f} N (red) at {angle_name} {after.angles_deg[i] % 360:.0f}°"
    else:
        peak = "no shaking force" + (" left" if before is not None else "")
        if np.abs(after.moment(n)).max(initial=0.0) > 0.0:
            peak += ": a couple only (right)"
    if scale == 0.0:  # no curve to scale the radius by: no radial labels
        polar.set_ylim(0.0, 1.0)
        polar.set_yticklabels([])
    # The peak in the title: the polar plot's own angles are the force's direction,
    # so the cycle angle is said in words, off the plot.
    polar.set_title(f"shaking force  [N] (direction on the frame)\n{peak}", fontsize=9)
    polar.set_rlabel_position(112.5)  # radial labels off the 0° axis the curves often cross
    polar.tick_params(axis="y", labelsize=7)
    right.axhline(0.0, color="0.6", lw=0.8)
    right.set_ylabel("shaking moment  [N·m]")
    angle_axis(right, 360.0, f"{angle_name}  [deg]")
    # Every 60°: the 30° of a full-width axis crowd this half-width one.
    right.xaxis.set_major_locator(MultipleLocator(60.0))
    right.grid(True, lw=0.4, alpha=0.5)
    if before is not None:
        polar.legend(fontsize=8, loc="upper left", bbox_to_anchor=(-0.25, 0.02))
        right.legend(fontsize=8)
    fig.suptitle(title or f"shaking of the frame at {n:g} rpm")
    return fig


def plot_torsion(t: Any, *, title: str | None = None) -> Any:
    """The working members' dynamic errors (top) and the shaft's twist at each
    take-off (bottom) over the cycle, of :func:`cyclomech.dynamics.torsion`.

    Parameters
    ----------
    t : Torsion
        The steady state.
    title : str, optional
        The figure's title (default: the head's mean speed).

    Returns
    -------
    matplotlib.figure.Figure
        Two axes; errors in mm (a member that travels) or degrees (one that turns).

    Raises
    ------
    InputError
        If ``t`` is not a :class:`~cyclomech.dynamics.Torsion`.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> phi = np.linspace(0.0, 2 * np.pi, 360, endpoint=False)
    >>> m = cm.dynamics.WorkingMember(0.01 * np.sin(phi), 0.01 * np.cos(phi), -0.01 * np.sin(phi))
    >>> node = cm.dynamics.ShaftNode("crank", np.zeros(360), np.zeros(360),
    ...                              np.full(360, 20.0), 0.02, 2e4, 2.0, m)
    >>> fig = plot_torsion(cm.dynamics.torsion([node], rpm=300.0))
    >>> [a.get_ylabel() for a in fig.axes]
    ['dynamic error  [mm or deg]', 'twist behind the motor end  [deg]']
    """
    from ._torsion import Torsion

    if not isinstance(t, Torsion):
        raise InputError(
            f"plot_torsion needs a Torsion (cyclomech.dynamics.torsion); got {type(t).__name__}"
        )
    plt = pyplot()
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8.0, 5.6), sharex=True, layout="constrained")
    x = np.append(t.theta_deg, 360.0)
    for name, e in t.error.items():
        unit = t.units[name]
        scale = 1e3 if unit == "m" else math.degrees(1.0)
        label = f"{name} [{'mm' if unit == 'm' else 'deg'}]"
        if e.shape[0] == 2:  # a point: its distance from the rigid machine's
            v = np.hypot(e[0], e[1])
            label = f"{name}, |e| [mm]"
        else:
            v = e[0]
        top.plot(x, scale * np.append(v, v[0]), gid=f"error {name}", label=label)
    top.axhline(0.0, color="0.6", lw=0.8)
    top.set_ylabel("dynamic error  [mm or deg]")
    top.grid(True, lw=0.4, alpha=0.5)
    if t.error:
        top.legend(fontsize=8)
    for k, name in enumerate(t.names):
        tw = np.degrees(t.twist_rad[k])
        bottom.plot(x, np.append(tw, tw[0]), gid=f"twist {name}", label=name)
    bottom.set_ylabel("twist behind the motor end  [deg]")
    angle_axis(bottom, 360.0, "main-shaft angle at the motor end  [deg]")
    bottom.grid(True, lw=0.4, alpha=0.5)
    bottom.legend(fontsize=8)
    fig.suptitle(title or f"elastic main shaft at {t.mean_rpm:.2f} rpm (under the motor)")
    return fig
