"""Plot of a servo axis's duty: the motor's torque and speed over the machine's cycle.

:func:`plot_duty` takes a :class:`cyclomech.servo.Duty` at one speed (its curves)
and, optionally, the :class:`~cyclomech.servo.Motor` whose limits to draw.

matplotlib is an optional dependency (``pip install 'cyclomech[plot]'``), imported
only when the function draws; it draws on the axes it is given (or on a new figure),
returns what it drew on, and never calls ``plt.show()``.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt

from .._errors import InputError
from .._plotting import CRITICAL_COLOR, angle_axis, axes_arg, pyplot
from ._axis import Duty
from ._parts import Motor

__all__ = ["plot_duty"]


def plot_duty(
    duty: Duty,
    motor: Motor | None = None,
    *,
    axes: Any = None,
    title: str | None = None,
) -> npt.NDArray[Any]:
    """The motor's torque and speed over one cycle of the master, on two stacked axes.

    The torque [N·m] with its RMS over the cycle dashed; the speed [rpm]. With
    ``motor``, its peak torque (±) and rated torque (the RMS's limit) and its maximum
    speed (±) as red lines. The binding check and the status are in the title.

    Parameters
    ----------
    duty : cyclomech.servo.Duty
        The duty at one speed (:meth:`cyclomech.servo.ServoAxis.duty` with a scalar ``rpm``: it has
        the curves).
    motor : cyclomech.servo.Motor, optional
        The motor whose limits to draw; default None (none drawn).
    axes : sequence of 2 matplotlib.axes.Axes, optional
        The axes to draw on; default None (a new figure).
    title : str, optional
        The figure's title; default the speed and the status.

    Returns
    -------
    ndarray of matplotlib.axes.Axes, shape (2,)
        The torque's and the speed's axes.

    Raises
    ------
    InputError
        If ``duty`` is not a :class:`~cyclomech.servo.Duty` with curves, ``motor`` is
        neither None nor a :class:`~cyclomech.servo.Motor`, or ``axes`` is not two Axes.
    ImportError
        If matplotlib is not installed.

    Notes
    -----
    Artists, by gid: ``"torque"``, ``"rms"``, ``"speed"``, and with a motor
    ``"peak limit"``, ``"rated"``, ``"speed limit"``.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import cyclomech as cm
    >>> from cyclomech.servo.plot import plot_duty
    >>> S = cm.motion.Segment
    >>> prog = cm.motion.Program([S("cycloidal", 120, end=0.1), S("dwell", 60),
    ...                           S("cycloidal", 120, end=0.0), S("dwell", 60)])
    >>> motor = cm.servo.Motor(1.3, 3.9, 3000, 6000, 1.4e-4)
    >>> ax = cm.servo.ServoAxis(prog, cm.servo.LinearLoad(mass_kg=8.0, lead_m=0.02), motor=motor)
    >>> axes = plot_duty(ax.duty(60.0), motor)
    >>> [a.get_ylabel() for a in axes]
    ['motor torque  [N·m]', 'motor speed  [rpm]']
    """
    if not isinstance(duty, Duty) or duty.torque_nm is None or duty.motor_rpm is None:
        raise InputError(
            "duty must be a cyclomech.servo.Duty at one speed (ServoAxis.duty(rpm) with a "
            f"scalar rpm, which has the curves); got {duty!r}"
        )
    if motor is not None and not isinstance(motor, Motor):
        raise InputError(f"motor must be None or a cyclomech.servo.Motor; got {motor!r}")
    given = axes_arg(axes, (2,), "plot_duty")
    plt = pyplot()
    if given is None:
        _fig, new = plt.subplots(2, 1, figsize=(7.5, 5.0), sharex=True, layout="constrained")
        given = list(new)
    deg = np.append(duty.theta_deg, 360.0)
    torque = np.append(duty.torque_nm, duty.torque_nm[0])
    speed = np.append(duty.motor_rpm, duty.motor_rpm[0])
    ax_t, ax_w = given
    ax_t.plot(deg, torque, color="#1f77b4", lw=1.4, gid="torque", label="torque")
    rms = float(duty.rms_torque_nm)
    ax_t.axhline(rms, color="#1f77b4", ls="--", lw=1.0, gid="rms", label=f"RMS {rms:.3g} N·m")
    ax_w.plot(deg, speed, color="#2ca02c", lw=1.4, gid="speed")
    if motor is not None:
        for sign in (1.0, -1.0):
            ax_t.axhline(
                sign * motor.peak_torque_nm,
                color=CRITICAL_COLOR,
                lw=1.0,
                gid="peak limit",
                label="peak torque" if sign > 0 else None,
            )
            ax_w.axhline(sign * motor.max_rpm, color=CRITICAL_COLOR, lw=1.0, gid="speed limit")
        ax_t.axhline(
            motor.rated_torque_nm,
            color=CRITICAL_COLOR,
            ls=":",
            lw=1.0,
            gid="rated",
            label="rated torque (RMS limit)",
        )
    for ax, label in ((ax_t, "motor torque  [N·m]"), (ax_w, "motor speed  [rpm]")):
        ax.axhline(0.0, color="0.6", lw=0.6)
        ax.set_ylabel(label)
        ax.grid(True, lw=0.4, alpha=0.5)
        angle_axis(ax, 360.0, "")
    # Above the plot, out of the curve's way.
    ax_t.legend(fontsize=8, loc="lower center", ncols=4, bbox_to_anchor=(0.5, 1.0), frameon=False)
    ax_w.set_xlabel("master angle θ  [deg]")
    rpm = float(np.asarray(duty.rpm).reshape(-1)[0])
    ax_t.figure.suptitle(title or f"servo duty at {rpm:g} rpm: {duty.status}", fontsize=11)
    return np.array(given, dtype=object)
