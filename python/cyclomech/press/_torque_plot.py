"""The press's crank torque drawn: the deformation-force diagram and M(α) with its
force and inertia parts (re-exported by :mod:`cyclomech.press.plot` and the
:mod:`cyclomech.plot` facade)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from .._errors import InputError
from .._plotting import MM, angle_axis, pyplot
from ._torque import DeformationForce, PressTorque

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["plot_crank_torque"]

#: Colour of the working stroke and the force (as in :mod:`cyclomech.press.plot`).
WORK_COLOR = "#f28e2b"


def plot_crank_torque(
    torque: PressTorque,
    omega: float,
    *,
    force: DeformationForce | None = None,
    title: str | None = None,
) -> list[Axes]:
    """Draw a press's crank torque M(α) [N·m] and its parts; return the axes.

    The torque of :meth:`~cyclomech.press.GearLeverPress.crank_torque` at crank
    speed ``omega`` over α [deg, from BDC against the motion]: the force's part
    F·Π' (gid ``"force"``), the inertia's ω²·(…) (``"inertia"``) and their sum
    (``"total"``) [N·m], the working stroke shaded; with ``force``, a first plot of
    the deformation-force diagram F [kN] against the slider's height above BDC S
    [mm] (gid ``"F(S)"``).

    Parameters
    ----------
    torque : PressTorque
        The crank torque.
    omega : float
        The crank speed ω [rad/s].
    force : DeformationForce, optional
        The deformation-force diagram, drawn as a first plot; default None.
        Keyword-only.
    title : str, optional
        The figure's title. Keyword-only.

    Returns
    -------
    list of matplotlib.axes.Axes
        The axes (one, or two with ``force``), on a new figure.

    Raises
    ------
    InputError
        If ``torque`` is not a :class:`~cyclomech.press.PressTorque` or ``force`` not
        a :class:`~cyclomech.press.DeformationForce`.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> import numpy as np, cyclomech as cm
    >>> from cyclomech.plot import plot_crank_torque
    >>> p = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.0, L=0.3, phi0=0.0)
    >>> f = cm.press.DeformationForce([0.0, 0.012], [1e5, 1e5])
    >>> t = p.crank_torque(np.radians(np.arange(361.0)), force=f, slider_mass=40.0, k_Sp=0.1)
    >>> axes = plot_crank_torque(t, 4.0, force=f)
    >>> [ln.get_gid() for ln in axes[1].get_lines()][:3]
    ['force', 'inertia', 'total']
    >>> plt.close("all")
    """
    if not isinstance(torque, PressTorque):
        raise InputError(f"torque must be a PressTorque; got {type(torque).__name__}")
    if force is not None and not isinstance(force, DeformationForce):
        raise InputError(f"force must be a DeformationForce or None; got {type(force).__name__}")
    M_inertia = torque.torque_nm(omega) - torque.static
    plt = pyplot()
    n = 1 if force is None else 2
    fig, axs = plt.subplots(1, n, figsize=(4.6 * n + 1.0, 3.6), layout="constrained", squeeze=False)
    axes = list(axs[0])
    if force is not None:
        fa = axes[0]
        fa.plot(
            force.s * MM, force.force * 1e-3, color=WORK_COLOR, lw=1.8, marker="o", ms=3, gid="F(S)"
        )
        fa.axvline(
            torque.S_p * MM, color="0.4", ls="--", lw=1, label=f"S_p = {torque.S_p * MM:.4g} mm"
        )
        fa.set_xlim(0.0, torque.S_p * MM * 1.05)
        fa.set_ylim(bottom=0.0)
        fa.invert_xaxis()
        fa.set_xlabel("slider height above BDC S [mm]  (the slider comes down →)")
        fa.set_ylabel("deformation force F [kN]")
        fa.set_title(f"force diagram: ∫F dS = {torque.energy_per_stroke_j:.4g} J", fontsize=10.5)
        fa.grid(color="0.9", linewidth=0.6)
        fa.legend(fontsize=8)
    ax = axes[-1]
    order = np.argsort(np.mod(torque.alpha, 2 * math.pi))
    deg = np.degrees(np.mod(torque.alpha, 2 * math.pi))[order]
    ax.axvspan(
        0.0,
        math.degrees(torque.alpha_p),
        color=WORK_COLOR,
        alpha=0.2,
        lw=0,
        label="working stroke",
        zorder=0.4,
    )
    # The parts dashed over the total (the force part is most of it on the stroke).
    ax.plot(
        deg,
        torque.static[order],
        color=WORK_COLOR,
        lw=1.6,
        ls="--",
        label="force F·Π'",
        gid="force",
        zorder=3,
    )
    ax.plot(
        deg,
        M_inertia[order],
        color="#4e79a7",
        lw=1.4,
        ls="--",
        label="inertia",
        gid="inertia",
        zorder=3,
    )
    total = torque.torque_nm(omega)[order]
    ax.plot(deg, total, color="k", lw=1.6, label="crank torque M", gid="total")
    ax.axhline(0.0, color="0.55", linewidth=0.6, zorder=0.5)
    angle_axis(ax, 360.0, "crank angle α from BDC (against the motion)")
    ax.set_xticks(np.arange(0.0, 361.0, 60.0), [f"{v}°" for v in range(0, 361, 60)])
    ax.set_ylabel("torque [N·m]")
    rpm, peak = omega * 30 / math.pi, torque.peak_torque_nm(omega)
    ax.set_title(f"crank torque at {rpm:.4g} rpm: peak {peak:.4g} N·m", fontsize=10.5)
    ax.grid(color="0.9", linewidth=0.6)
    ax.legend(fontsize=8, loc="upper right")
    if title is not None:
        fig.suptitle(title)
    return axes
