"""Plots of a stop impact (seed 000): the motion after contact, the first rebound
against speed, and a stop's smallest admissible phase angle against speed.

:func:`plot_response` takes a response q(t) [m] over t [s] (as from
:meth:`cyclomech.impact.StopImpact.response`), :func:`plot_rebound_vs_speed` a
:class:`cyclomech.impact.StopImpact` and speeds [rpm], :func:`plot_min_phase`
phase angles [deg] against speeds [rpm]. They show q in millimetres and t in
milliseconds.

matplotlib is an optional dependency (``pip install 'cyclomech[plot]'``), imported
only when a function draws; the functions draw on the axes they are given (or on a
new figure), return what they drew on, and never call ``plt.show()``.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, cast

import numpy as np
import numpy.typing as npt

from .._arrays import finite_number, float_array, instance, positive, real_array
from .._errors import InputError
from .._plotting import CRITICAL_COLOR, pyplot

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["plot_min_phase", "plot_rebound_vs_speed", "plot_response"]


def plot_response(
    t: npt.ArrayLike,
    q: npt.ArrayLike,
    ax: Axes | None = None,
    *,
    force: npt.ArrayLike | None = None,
    rebound: tuple[float, float] | None = None,
    label: str | None = None,
    title: str | None = None,
) -> Axes:
    """Draw a response q(t) after an impact: q [mm] against t [ms]; return the axes.

    The stop is q = 0 (a dashed line). Artists, by gid: ``"q"``, ``"force"``,
    ``"rebound"``, ``"label:rebound"``, ``"stop"``.

    Parameters
    ----------
    t : array_like of float, shape (N,)
        The times after contact [s], as from :func:`cyclomech.impact.duhamel` or
        :meth:`cyclomech.impact.StopImpact.response`.
    q : array_like of float, shape (N,)
        The displacement away from the stop [m].
    ax : matplotlib.axes.Axes, optional
        The axes to draw on; default None (a new figure).
    force : array_like of float, shape (N,), optional
        The pulse's force [N] on the same grid, drawn shaded on a second y axis.
    rebound : tuple of (float, float), optional
        The first rebound (time [s], q [m]), marked with a dot and its value.
    label : str, optional
        The legend label of q; default None ("q(t)").
    title : str, optional
        The axes' title.

    Returns
    -------
    matplotlib.axes.Axes
        The axes drawn on.

    Raises
    ------
    InputError
        If ``t`` and ``q`` (or ``force``) are not 1-D arrays of one length.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import cyclomech as cm
    >>> from cyclomech.impact.plot import plot_response
    >>> lifter = cm.impact.StopImpact.example()
    >>> t, q = lifter.response(280, 40.0)
    >>> ax = plot_response(t, q, rebound=(float(t[q.argmax()]), float(q.max())))
    >>> ax.get_xlabel(), ax.get_ylabel()
    ('t after contact  [ms]', 'q, away from the stop  [mm]')
    """
    plt = pyplot()
    ta = real_array("t", t, "[s]")
    qa = real_array("q", q, "[m]")
    if ta.ndim != 1 or qa.shape != ta.shape:
        raise InputError(
            f"t and q must be 1-D arrays of one length; got shapes {ta.shape} and {qa.shape}"
        )
    if ax is None:
        _fig, ax = plt.subplots(figsize=(6.4, 3.6), layout="constrained")
    ax.axhline(0.0, color="0.4", lw=0.8, ls="--", gid="stop")
    ax.plot(ta * 1e3, qa * 1e3, color="C0", lw=1.4, label=label or "q(t)", gid="q")
    if force is not None:
        fa = real_array("force", force, "[N]")
        if fa.shape != ta.shape:
            raise InputError(f"force must have the shape of t {ta.shape}; got {fa.shape}")
        tw = ax.twinx()
        tw.fill_between(ta * 1e3, fa, color="C3", alpha=0.18, lw=0, gid="force")
        tw.plot(ta * 1e3, fa, color="C3", lw=0.8)
        tw.set_ylabel("impact force  [N]", color="C3")
        tw.tick_params(axis="y", colors="C3")
        tw.set_ylim(bottom=min(0.0, float(fa.min())) * 1.1, top=float(fa.max()) * 3.0 or 1.0)
    if rebound is not None:
        pair = float_array("rebound", rebound, ndims=(1,))
        if pair.shape != (2,) or np.isnan(pair).any():
            raise InputError(f"rebound must be (t [s], q [m]), t inf for none; got {rebound!r}")
        tr, qr = float(pair[0]), float(pair[1])
        if math.isfinite(tr):
            ax.plot([tr * 1e3], [qr * 1e3], "o", color="C1", ms=6, zorder=5, gid="rebound")
            ax.annotate(
                f"first rebound {qr * 1e3:.4g} mm",
                (tr * 1e3, qr * 1e3),
                xytext=(8, 6),
                textcoords="offset points",
                fontsize=8.5,
                gid="label:rebound",
            )
    ax.set_xlabel("t after contact  [ms]")
    ax.set_ylabel("q, away from the stop  [mm]")
    ax.set_xlim(float(ta[0]) * 1e3, float(ta[-1]) * 1e3)
    ax.margins(y=0.18)  # room for the rebound's label
    ax.grid(True, lw=0.4, alpha=0.5)
    if title is not None:
        ax.set_title(title)
    return ax


def plot_rebound_vs_speed(
    model: Any,
    rpm: npt.ArrayLike,
    *,
    phase_deg: npt.ArrayLike = (40.0,),
    a_max: float | None = None,
    responses: npt.ArrayLike | None = None,
    title: str | None = None,
) -> Figure:
    """The seed's fig. 8 for a :class:`cyclomech.impact.StopImpact`: the rebound against speed.

    On the left the motion after contact at a few speeds (at the first phase
    angle), on the right the first rebound [mm] against speed for each phase angle
    (one Rust call), with the limit ``a_max`` as a dashed line and the smallest
    admissible phase angle at the top speed noted. Artists, by gid:
    ``"response:<rpm>"``, ``"rebound:<phase>"``, ``"a_max"``.

    Parameters
    ----------
    model : StopImpact
        The lever with its stop.
    rpm : array_like of float
        The speeds [rpm], at least two, positive.
    phase_deg : array_like of float, default (40.0,)
        The phase angles [deg], one curve each.
    a_max : float, optional
        The rebound limit [m], drawn dashed; default None (no limit).
    responses : array_like of float, optional
        The speeds [rpm] whose motion is drawn on the left; default None (the ends
        and the middle of ``rpm``).
    title : str, optional
        The figure's title; default None (names the model).

    Returns
    -------
    matplotlib.figure.Figure
        The figure, of two axes.

    Raises
    ------
    InputError
        If ``rpm`` holds fewer than two positive speeds or ``phase_deg`` is empty.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import numpy as np, cyclomech as cm
    >>> from cyclomech.impact.plot import plot_rebound_vs_speed
    >>> fig = plot_rebound_vs_speed(cm.impact.StopImpact.example(), np.linspace(200, 450, 26),
    ...                             phase_deg=[30, 40, 50], a_max=0.1e-3)
    >>> len(fig.axes), fig.axes[1].get_xlabel()
    (2, 'main-shaft speed  [rpm]')
    """
    plt = pyplot()
    from ._stop import StopImpact  # at call time: plotting stays out of the model's imports

    instance("model", model, StopImpact)
    if a_max is not None:
        a_max = positive("a_max", a_max, "[m]")
    n = float_array("rpm", rpm, ndims=None).reshape(-1)
    if n.size < 2 or not np.isfinite(n).all() or (n <= 0).any():
        raise InputError("rpm must hold at least two positive speeds [rpm]")
    phases = real_array("phase_deg", phase_deg, "[deg]", low=0.0, strict=True).reshape(-1)
    if phases.size < 1:
        raise InputError("phase_deg must hold at least one phase angle [deg]")
    shown = (
        np.array([n.min(), np.median(n), n.max()])
        if responses is None
        else real_array("responses", responses, "[rpm]", low=0.0, strict=True).reshape(-1)
    )
    fig, (left, right) = plt.subplots(
        1, 2, figsize=(11.0, 4.0), layout="constrained", width_ratios=(1.25, 1.0)
    )
    left.axhline(0.0, color="0.4", lw=0.8, ls="--")
    colors = plt.get_cmap("viridis")(np.linspace(0.1, 0.85, max(shown.size, 2)))
    for c, speed in zip(colors, shown, strict=False):
        t, q = model.response(float(speed), float(phases[0]))
        left.plot(
            t * 1e3, q * 1e3, color=c, lw=1.2, label=f"{speed:g} rpm", gid=f"response:{speed:g}"
        )
    left.set_xlabel("t after contact  [ms]")
    left.set_ylabel("q, away from the stop  [mm]")
    left.set_title(f"motion after contact, phase angle {phases[0]:g}°", fontsize=10)
    left.legend(fontsize=8, loc="upper right")
    left.grid(True, lw=0.4, alpha=0.5)
    a = model.rebound(n[:, None], phases[None, :])  # (speeds, phases), one call
    for j, ph in enumerate(phases):
        right.plot(
            n, a[:, j] * 1e3, "-o", ms=2.5, lw=1.4, label=f"t = {ph:g}°", gid=f"rebound:{ph:g}"
        )
    if a_max is not None:
        t_min = float(model.min_phase_angle(float(a_max), float(n.max())))
        note = (
            f"limit [a] = {float(a_max) * 1e3:g} mm: t ≥ {t_min:.3g}° at {n.max():g} rpm"
            if math.isfinite(t_min)
            else f"limit [a] = {float(a_max) * 1e3:g} mm: not reachable at {n.max():g} rpm"
        )
        # The note is the limit line's legend entry: text on the line was struck through.
        right.axhline(
            float(a_max) * 1e3, color=CRITICAL_COLOR, ls="--", lw=1.0, gid="a_max", label=note
        )
        right.set_ylim(0.0, 1.15 * max(float(a_max) * 1e3, float(np.nanmax(a)) * 1e3))
    else:
        right.set_ylim(bottom=0.0)
    right.set_xlabel("main-shaft speed  [rpm]")
    right.set_ylabel("first rebound  [mm]")
    right.legend(fontsize=8, loc="best")
    right.grid(True, lw=0.4, alpha=0.5)
    fig.suptitle(title or f"rebound at the stop ({model.model} model)", fontsize=11)
    return cast("Figure", fig)


def plot_min_phase(
    rpm: npt.ArrayLike,
    exact: npt.ArrayLike,
    linear: npt.ArrayLike | None = None,
    *,
    minimum_deg: float | None = None,
    title: str | None = None,
    ax: Axes | None = None,
) -> Axes:
    """A stop's smallest admissible phase angle [deg] against speed [rpm].

    Artists, by gid: ``"exact"``, ``"linear"``, ``"minimum"``.

    Parameters
    ----------
    rpm : array_like of float
        The speeds [rpm].
    exact : array_like of float
        The exact smallest phase angle at each speed [deg] (solid).
    linear : array_like of float, optional
        The seed's linearised form at each speed [deg] (dashed).
    minimum_deg : float, optional
        The operation's own minimum angle [deg] (dotted).
    title : str, optional
        The axes' title.
    ax : matplotlib.axes.Axes, optional
        The axes to draw on; default None (a new figure).

    Returns
    -------
    matplotlib.axes.Axes
        The axes drawn on.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import numpy as np, cyclomech as cm
    >>> from cyclomech.impact.plot import plot_min_phase
    >>> s = cm.Machine.example().mechanisms["lifter"]
    >>> n = np.linspace(200, 450, 11)
    >>> ax = plot_min_phase(n, s.min_phase_deg(n), s.linear_min_phase_deg(n))
    >>> ax.get_xlabel()
    'main-shaft speed  [rpm]'
    """
    rpm = real_array("rpm", rpm, "[rpm]", low=0.0, strict=True, ndims=(1,))
    # NaN where no phase angle of one turn will do: a gap in the curve.
    exact = _curve("exact", exact, rpm.shape)
    linear = None if linear is None else _curve("linear", linear, rpm.shape)
    if minimum_deg is not None:
        minimum_deg = finite_number("minimum_deg", minimum_deg, "[deg]")
    plt = pyplot()
    if ax is None:
        _, ax = plt.subplots(figsize=(7.0, 4.0), layout="constrained")
    assert ax is not None
    ax.plot(rpm, exact, "-", lw=1.8, color="C0", label="exact", gid="exact")
    if linear is not None:
        ax.plot(rpm, linear, "--", lw=1.3, color="C1", label="seed's linearised form", gid="linear")
    if minimum_deg is not None:
        ax.axhline(
            minimum_deg, color="0.4", ls=":", lw=1.0, label="operation's own minimum", gid="minimum"
        )
    ax.set_xlabel("main-shaft speed  [rpm]")
    ax.set_ylabel("smallest phase angle  [deg]")
    ax.grid(True, lw=0.4, alpha=0.5)
    ax.legend(fontsize=8, loc="upper left")
    ax.set_title(
        title or "smallest phase angle that keeps the rebound within its limit", fontsize=10
    )
    return ax


def _curve(name: str, value: Any, shape: tuple[int, ...]) -> Any:
    """Angles [deg] at each speed: numbers of the speeds' shape, NaN for none."""
    a = float_array(name, value, ndims=(1,))
    if a.shape != shape or np.isinf(a).any():
        raise InputError(f"{name} must hold one angle [deg] a speed {shape} (NaN: none)")
    return a
