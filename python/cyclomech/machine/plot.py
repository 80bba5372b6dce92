"""Plot of the whole machine against speed: the limiting operation's angle and
time, each stop's smallest phase angle, and the speed limit.

:func:`plot_speed_sweep` takes the result of :meth:`cyclomech.machine.Machine.speed_sweep`
(speeds in rpm, angles in degrees, times shown in milliseconds).

matplotlib is an optional dependency (``pip install 'cyclomech[plot]'``), imported
only when the function draws; it returns a new figure and never calls
``plt.show()``.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from .._arrays import finite_number, instance
from .._notebook import register_figure
from .._plotting import CRITICAL_COLOR, pyplot
from ..cyclogram.plot import plot_cyclogram
from . import _result
from ._animation_plot import animate_machine, plot_machine_frame

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["animate_machine", "plot_machine_frame", "plot_speed_sweep"]


def plot_speed_sweep(
    sweep: Any,
    *,
    linear: Any = None,
    limit_rpm: float | None = None,
    limit_by: str | None = None,
    title: str | None = None,
) -> Figure:
    """The whole machine against speed, from :meth:`cyclomech.machine.Machine.speed_sweep`.

    In panels sharing the speed axis [rpm]: the limiting operation's optimal angle
    [deg] and the time it gets [ms], and where the machine has stops, each stop's
    smallest phase angle [deg]; ``linear`` dashed. ``limit_rpm`` is a vertical
    line: the curves end there and the speeds above it are shaded; without it, the
    speeds where the cyclogram does not fit are.

    Parameters
    ----------
    sweep : SpeedSweep
        The machine's key figures against speed (exact bounds).
    linear : SpeedSweep, optional
        A second sweep with the seed's linearised rebound constraints, dashed;
        default None.
    limit_rpm : float, optional
        The machine's speed limit [rpm]; default None.
    limit_by : str, optional
        What sets it (named in the limit's label); default None.
    title : str, optional
        The figure's title; default None.

    Returns
    -------
    matplotlib.figure.Figure
        A new figure of 2 panels, or 3 where the machine has stops.

    Notes
    -----
    Artists, by gid: ``"limiting"``, ``"limiting:linear"``, ``"time"``,
    ``"stop:<name>"``, ``"stop:<name>:linear"``, ``"limit"``, ``"above"``.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import cyclomech as cm
    >>> from cyclomech.machine.plot import plot_speed_sweep
    >>> m = cm.Machine.example()
    >>> fig = plot_speed_sweep(m.speed_sweep(), limit_rpm=m.speed_limit().rpm)
    >>> [ax.get_ylabel() for ax in fig.axes]
    ['limiting operation  [deg]', 'its time  [ms]', 'smallest phase angle  [deg]']
    """
    from ._many import SpeedSweep  # at call time, as pyplot: importing stays light

    instance("sweep", sweep, SpeedSweep)
    if linear is not None:
        instance("linear", linear, SpeedSweep)
    if limit_rpm is not None:  # +inf: no limit (above the speed cap)
        limit_rpm = finite_number("limit_rpm", limit_rpm, "[rpm]", low=0.0, inf=True)
    plt = pyplot()
    stops = dict(sweep.min_phase_deg)
    rows = 3 if stops else 2
    fig, axes = plt.subplots(
        rows,
        1,
        figsize=(8.0, 7.5 if stops else 5.6),
        sharex=True,
        layout="constrained",
        height_ratios=(1.4, 1, 1)[:rows],
    )
    top, mid = axes[0], axes[1]
    n = np.asarray(sweep.rpm)
    limited = limit_rpm is not None and math.isfinite(limit_rpm)
    runs = n <= limit_rpm if limited else np.asarray(sweep.fits)

    def upto(y: Any) -> Any:  # the curve where the machine runs
        return np.where(runs, np.asarray(y, dtype=float), np.nan)

    _limiting(top, mid, n, upto, sweep, linear, bool(stops))
    if stops:
        _bounds(fig, axes[2], n, upto, stops, linear)
    axes[-1].set_xlabel("main-shaft speed  [rpm]")
    by = f" ({limit_by})" if limit_by else ""
    shown = _shown_range(n, runs, limit_rpm if limited else None)
    for ax in axes:
        _speed_range(ax, ax is top, n, runs, limit_rpm if limited else None, by, shown)
    if shown[1] < float(n.max()):
        axes[-1].annotate(
            f"(the sweep runs to {float(n.max()):g} rpm; nothing runs above the limit)",
            xy=(1.0, 0.0),
            xycoords="axes fraction",
            xytext=(0, -28),
            textcoords="offset points",
            ha="right",
            va="top",
            fontsize=7,
            color="0.35",
        )
    if not runs.any():
        _works_at_no_speed(top, mid, limit_rpm if limited else None, by)
    else:  # with nothing drawn, a legend would only name empty lines
        top.legend(fontsize=8, loc="lower left")
    fig.suptitle(title or "the machine against speed", fontsize=11)
    return cast("Figure", fig)


def _limiting(top: Any, mid: Any, n: Any, upto: Any, sweep: Any, linear: Any, stops: bool) -> None:
    """The top two panels: the limiting operation's optimal angle [deg] (exact
    solid; with ``linear``, the seed's linearised bounds dashed) and its time [ms];
    ``upto`` blanks a curve where the machine does not run."""
    top.plot(
        n,
        upto(sweep.limiting_deg),
        "-",
        lw=1.8,
        color="C0",
        label="with the mechanisms' exact bounds" if stops else "optimum",
        gid="limiting",
    )
    if linear is not None:
        top.plot(
            n,
            upto(linear.limiting_deg),
            "--",
            lw=1.3,
            color="C1",
            label="with the seed's linearised bounds",
            gid="limiting:linear",
        )
    top.set_ylabel("limiting operation  [deg]")
    mid.plot(n, upto(sweep.limiting_s * 1e3), "-", lw=1.6, color="C2", gid="time")
    mid.set_ylabel("its time  [ms]")


def _bounds(fig: Any, low: Any, n: Any, upto: Any, stops: dict[str, Any], linear: Any) -> None:
    """The bottom panel: each bound's smallest phase angle [deg] against speed,
    exact, and linearised (dashed) where ``linear`` gives another curve; with many
    bounds the legend goes beside the panel and the figure widens."""
    styles = _bound_styles(list(stops))
    for name, t in stops.items():
        c, style = styles[name]
        # 0 is "no bound" (a cam criterion another one covers): not drawn.
        exact = np.where(np.asarray(t, dtype=float) > 0, t, np.nan)
        low.plot(
            n,
            upto(exact),
            linestyle=style,
            lw=1.6,
            color=c,
            label=f"{name}: exact",
            gid=f"stop:{name}",
        )
        lin = None if linear is None else np.asarray(linear.min_phase_deg[name], dtype=float)
        if lin is not None and not np.array_equal(lin, np.asarray(t, float), equal_nan=True):
            # (a bound without a linearised form, as a cam's, is drawn once)
            low.plot(
                n,
                upto(lin),
                "--",
                lw=1.2,
                color=c,
                label=f"{name}: linearised",
                gid=f"stop:{name}:linear",
            )
    low.set_ylabel("smallest phase angle  [deg]")
    if len(stops) > 10:  # many bounds: a colour per operation, a line per criterion
        handles, labels = _grouped_legend(
            styles, any(ln.get_gid().endswith(":linear") for ln in low.get_lines())
        )
        low.legend(
            handles,
            labels,
            ncols=2,
            fontsize=7,
            loc="upper left",
            bbox_to_anchor=(1.01, 1.0),
            borderaxespad=0,
            title="colour: what is bounded · line: criterion",
            title_fontsize=7,
        )
        fig.set_size_inches(12.0, 7.5)
    elif len(low.get_lines()) > 6:  # the legend beside the panel
        low.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
        fig.set_size_inches(12.0, 7.5)
    else:
        low.legend(fontsize=8, loc="upper left")


def _split(name: str) -> tuple[str, str]:
    """(what is bounded, criterion) of a bound's name: ``σ_H[lifter cam rise 1→3]``
    is (``lifter cam rise 1→3``, ``σ_H``); a stop's, its mechanism's name alone, is
    (that name, ``rebound (a stop)``)."""
    crit, bracket, rest = name.partition("[")
    return (rest.rstrip("]"), crit) if bracket else (name, "rebound (a stop)")


def _grouped_legend(
    styles: dict[str, tuple[str, Any]], linear: bool
) -> tuple[list[Any], list[str]]:
    """The legend of many bounds: one entry per colour (the operation a bound is on,
    by mechanism, in the order of the bounds) in the first column, one per line
    style (the criterion; the seed's linearised bound dashed) in the second; blank
    entries even the columns. 13 bounds of a loom's stop and cam took 13 entries."""
    from matplotlib.lines import Line2D

    colours: dict[str, str] = {}
    lines: dict[str, Any] = {}
    for name, (colour, style) in styles.items():
        what, crit = _split(name)
        colours.setdefault(what, colour)
        lines.setdefault(crit, style)
    left = [(Line2D([], [], color=c, lw=3.0), what) for what, c in colours.items()]
    right = [(Line2D([], [], color="0.25", lw=1.4, ls=st), crit) for crit, st in lines.items()]
    if linear:
        right.append((Line2D([], [], color="0.25", lw=1.2, ls="--"), "linearised (seed)"))
    blank = (Line2D([], [], lw=0, alpha=0), "")
    rows = max(len(left), len(right))
    pairs = [*left, *[blank] * (rows - len(left)), *right, *[blank] * (rows - len(right))]
    return [h for h, _ in pairs], [t for _, t in pairs]


#: When the speeds where the machine runs take less than this share of the sweep's
#: range (the speed limit low in it), the speed axis ends past the limit so that they
#: take :data:`RUNNING_SHARE` of it: the curves are not squeezed into a sliver
#: beside a grey block (once 7 % of the width).
SQUEEZED_SHARE = 0.5
#: The share of the speed axis the running speeds then take.
RUNNING_SHARE = 0.8


def _shown_range(n: Any, runs: Any, limit_rpm: float | None) -> tuple[float, float]:
    """The speed axis' range [rpm]: the sweep's, or where the machine runs in less
    than :data:`SQUEEZED_SHARE` of it, from its start to the last speed it runs at
    (the speed limit) plus what makes that :data:`RUNNING_SHARE` of the axis.

    >>> import numpy as np
    >>> n = np.linspace(200.0, 500.0, 61)
    >>> _shown_range(n, n <= 420.0, 420.0)
    (200.0, 500.0)
    >>> _shown_range(n, n <= 221.0, 221.0)
    (200.0, 226.25)
    """
    lo, hi = float(n.min()), float(n.max())
    if not runs.any():
        return lo, hi  # nothing to show but the range and why
    last = float(n[runs].max()) if limit_rpm is None else min(float(limit_rpm), hi)
    if last <= lo or last - lo >= SQUEEZED_SHARE * (hi - lo):
        return lo, hi
    return lo, lo + (last - lo) / RUNNING_SHARE


def _speed_range(
    ax: Any,
    top: bool,
    n: Any,
    runs: Any,
    limit_rpm: float | None,
    by: str,
    shown: tuple[float, float],
) -> None:
    """One panel's grid and speed range ``shown`` [rpm], with where the machine
    does not run shaded: above the speed limit ``limit_rpm`` [rpm] (its dashed red
    line, when in range), or without a finite limit where the cyclogram does not
    fit. The labels and gids go on the ``top`` panel only."""
    limited = limit_rpm is not None
    lim = math.nan if limit_rpm is None else float(limit_rpm)
    ax.grid(True, lw=0.4, alpha=0.5)
    ax.set_xlim(*shown)
    if limit_rpm is not None and limit_rpm < n.max():
        ax.axvspan(
            max(lim, float(n.min())),
            float(n.max()),
            color="0.85",
            alpha=0.6,
            lw=0,
            label="above the speed limit" if top else None,
            gid="above" if top else None,
        )
    elif not limited and not runs.all():
        ax.fill_between(
            n,
            0,
            1,
            where=~runs,
            transform=ax.get_xaxis_transform(),
            color="0.85",
            alpha=0.6,
            lw=0,
            label="the cyclogram does not fit" if top else None,
            gid="above" if top else None,
        )
    if limit_rpm is not None and n.min() <= limit_rpm <= n.max():
        ax.axvline(
            lim,
            color=CRITICAL_COLOR,
            ls="--",
            lw=1.0,
            gid="limit" if top else None,
            label=f"speed limit {limit_rpm:.1f} rpm{by}" if top else None,
        )


def _works_at_no_speed(top: Any, mid: Any, limit_rpm: float | None, by: str) -> None:
    """Where the machine runs at no speed of the range: the reason in the top
    panel (at standstill, or its speed limit ``limit_rpm`` [rpm] below the range)
    and no angle or time ticks."""
    limited = limit_rpm is not None
    top.text(
        0.5,
        0.5,
        (
            "the machine works at no speed:\nits cyclogram does not fit even at standstill"
            if limited and limit_rpm == 0
            else "the machine works at no speed of this range"
            + (f": its speed limit is {limit_rpm:.4g} rpm{by}" if limited else "")
        ),
        transform=top.transAxes,
        ha="center",
        va="center",
        fontsize=10,
        color=CRITICAL_COLOR,
    )
    top.set_yticks([])
    mid.set_yticks([])


#: Line styles of a bound's criterion when the bounds are many (a stop's rebound
#: and a cam's four criteria on each of its segments): solid, dotted, dash-dot,
#: long dashes, dash-dot-dot. The seed's linearised stop bounds keep "--".
_CRITERION_STYLES = (
    "-",
    (0, (1, 1.5)),
    (0, (5, 1.5, 1, 1.5)),
    (0, (8, 2.5)),
    (0, (5, 1.2, 1, 1.2, 1, 1.2)),
)


def _bound_styles(names: list[str]) -> dict[str, tuple[str, Any]]:
    """(colour, line style) of each bound's curve, all pairs distinct. Up to ten
    bounds: one colour each (C3, C4, …), solid. More: a colour per operation (what
    the brackets of ``criterion[mechanism segment]`` name, or the bound's own name)
    and a line style per criterion, so that 13 bounds do not reuse a colour for
    unrelated curves; past 10 operations × 5 criteria, the colours repeat with the
    next styles.

    >>> s = _bound_styles(["lifter", "σ_H[cam rise 1→3]", "undercut[cam rise 1→3]"])
    >>> s["lifter"]
    ('C3', '-')
    >>> len(set(map(str, s.values()))) == 3
    True
    """
    if len(names) <= 10:
        return {name: (f"C{(i + 3) % 10}", "-") for i, name in enumerate(names)}
    groups: dict[str, int] = {}
    criteria: dict[str, int] = {}
    out: dict[str, tuple[str, Any]] = {}
    used: set[tuple[str, str]] = set()
    for name in names:
        crit, bracket, rest = name.partition("[")
        group = rest.rstrip("]") if bracket else name
        g = groups.setdefault(group, len(groups))
        k = criteria.setdefault(crit if bracket else "", len(criteria))
        colour, step = f"C{(g + 3) % 10}", k + (g // 10) * len(_CRITERION_STYLES)
        style = _CRITERION_STYLES[step % len(_CRITERION_STYLES)]
        while (colour, str(style)) in used:  # only past 50 bounds
            step += 1
            colour = f"C{(g + 3 + step // len(_CRITERION_STYLES)) % 10}"
            style = _CRITERION_STYLES[step % len(_CRITERION_STYLES)]
        used.add((colour, str(style)))
        out[name] = (colour, style)
    return out


# The notebook's figure of a MachineResult (its ``_repr_html_``): the cyclogram at
# the optimum (it has none where the cyclogram does not fit: no figure is asked then).
register_figure(_result.MachineResult, lambda r: plot_cyclogram(r.optimum).figure)
