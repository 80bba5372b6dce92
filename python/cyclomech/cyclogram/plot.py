"""Plots of a cyclogram: a Gantt chart over the cycle and a circular diagram.

:func:`plot_cyclogram` and :func:`plot_cyclogram_pair` take the result of
:meth:`cyclomech.Cyclogram.schedule` (a :class:`~cyclomech.cyclogram.Schedule`:
every operation at its minimum angle, with its total slack) or of
:meth:`cyclomech.Cyclogram.optimize` (an :class:`~cyclomech.cyclogram.Optimum`: the
optimised angles, the part of each beyond its minimum, the limiting operation).
Angles are degrees of main-shaft rotation, 0 to ``cycle_deg``; an operation that
runs past the end of the cycle (it crosses into the next one, ``height >= 1``, or
simply starts late) wraps round to 0°.

The artists are findable for tests and restyling: the operation bars are the
:class:`~matplotlib.container.BarContainer` labelled ``"operations"`` in
``ax.containers`` (one rectangle per piece of a bar, in the order of
``result.operations``; a bar that wraps is two pieces), the hatched parts beyond
the minimum angle the one labelled ``"beyond minimum"``, and the slack whiskers
the :class:`~matplotlib.collections.LineCollection` labelled ``"total slack"``.
A title is never cut short: one that fits neither on its bar nor beside it is
replaced there by a number, keyed with the whole title under "numbered
operations" (in the legend of a Gantt chart, beside the rings of a circular one).

matplotlib is an optional dependency (``pip install 'cyclomech[plot]'``), imported
only when a function draws; the functions draw on the axes they are given (or on a
new figure), return what they drew on, and never call ``plt.show()``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, cast

from .._errors import InputError
from .._notebook import register_figure
from .._plotting import deg_text, pyplot
from . import Arc, Optimum, Schedule
from ._circular import (
    _circular,
    _label_circular,
    _require_polar,
)
from ._gantt import (
    _gantt,
    _gantt_size,
    _label_gantt,
)
from ._labels import key_entries, key_legend
from ._lanes import LIMITING_COLOR as LIMITING_COLOR
from ._lanes import MECHANISM_COLORS as MECHANISM_COLORS
from ._lanes import OTHER_ROW as OTHER_ROW
from ._lanes import (
    _Layout,
    _layout,
    _settle_layout,
)

if TYPE_CHECKING:
    from collections.abc import Callable, Mapping, Sequence

    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from matplotlib.projections.polar import PolarAxes


__all__ = ["plot_cyclogram", "plot_cyclogram_pair"]


def _default_title(result: Schedule | Optimum) -> str:
    head = "Cyclogram" if result.name == "cyclogram" else result.name
    if (
        isinstance(result, Optimum)
        and result.goal == "max_limiting"
        and result.limiting is not None
    ):
        op = next(o for o in result.operations if o.arc == result.limiting)
        return f"{head} — {op.title} (limiting) gets {deg_text(result.objective)}"
    return f"{head} — duration {deg_text(result.duration)}"


def plot_cyclogram(
    result: Schedule | Optimum,
    ax: Axes | None = None,
    *,
    kind: str = "gantt",
    title: str | None = None,
    minimums: Mapping[Arc, float] | None = None,
) -> Axes:
    """Draw a cyclogram (a Schedule or an Optimum) and return the axes.

    With ``kind="gantt"``: main-shaft angle [deg] from 0 to ``result.cycle_deg`` across,
    one row per mechanism (in order of first appearance; operations without one in
    a row ``"(other)"``), each operation a bar from p(src) to p(src) + angle,
    wrapped modulo the cycle (a bar past the end continues from 0°, as does an
    operation that ends in the next cycle). Operations of one mechanism that
    overlap share its row in separate lanes. Critical operations have a red edge.
    For a :class:`~cyclomech.cyclogram.Schedule` a whisker from a bar's end shows its
    total slack [deg]; for an :class:`~cyclomech.cyclogram.Optimum` the part of a bar
    beyond the operation's minimum angle is hatched and the limiting operation is
    orange, labelled with its angle.

    With ``kind="circular"``: the same on a polar axes, 0° at the top, angles
    clockwise, one ring per mechanism (from the centre out).

    Parameters
    ----------
    result : Schedule or Optimum
        The result of :meth:`~cyclomech.cyclogram.Cyclogram.schedule` or
        :meth:`~cyclomech.cyclogram.Cyclogram.optimize` (angles in degrees).
    ax : matplotlib.axes.Axes, optional
        The axes to draw on; None (default) makes a new figure. For
        ``kind="circular"`` it must be polar
        (``plt.subplots(subplot_kw={"projection": "polar"})``).
    kind : {"gantt", "circular"}, default "gantt"
        A Gantt chart over the cycle, or the circular diagram.
    title : str, optional
        The axes' title; default the duration of the group [deg], or the angle the
        limiting operation gets [deg].
    minimums : mapping of arc to float, optional
        Each operation's smallest angle [deg] where it is larger than its own
        minimum (a mechanism's bound in force, as the machine report's
        ``minimums``): the hatch of an Optimum starts there. Default: each
        operation's own minimum angle or duration.

    Returns
    -------
    matplotlib.axes.Axes
        The axes drawn on (polar for ``kind="circular"``).

    Raises
    ------
    InputError
        If ``result`` is neither a Schedule nor an Optimum, ``kind`` is unknown, or
        ``ax`` is not polar for ``kind="circular"``.
    ImportError
        If matplotlib is not installed.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> import cyclomech as cm
    >>> from cyclomech.cyclogram.plot import plot_cyclogram
    >>> cg = cm.Cyclogram()
    >>> cg.add_operation("1", "2", 40, mechanism="lifter", name="lift")
    >>> cg.add_operation("2", "3", 20, mechanism="lifter", name="dwell")
    >>> cg.add_operation("1", "3", 30, mechanism="gripper", name="close")
    >>> ax = plot_cyclogram(cg.schedule())
    >>> ax.get_title()
    'Cyclogram — duration 60°'
    >>> ax.get_xlim() == (0.0, 360.0), len(ax.containers[0])  # x in degrees; one bar per op
    (True, 3)
    >>> [t.get_text() for t in ax.get_yticklabels()]
    ['lifter', 'gripper']
    >>> polar = plot_cyclogram(cg.schedule(), kind="circular")
    >>> polar.name
    'polar'
    >>> plt.close("all")
    """
    plt = pyplot()
    if kind not in ("gantt", "circular"):
        raise InputError(f"kind must be 'gantt' or 'circular'; got {kind!r}")
    lay = _layout(result, minimums)
    if ax is not None and not hasattr(ax, "add_collection"):
        raise InputError(f"ax must be None (a new figure) or a matplotlib Axes; got {ax!r}")
    if ax is not None and kind == "circular":
        _require_polar(ax)
    if ax is None:
        if kind == "gantt":
            _, ax = plt.subplots(figsize=_gantt_size(lay), layout="constrained")
        else:
            fig, ax = plt.subplots(
                figsize=(8.0, 6.4), layout="constrained", subplot_kw={"projection": "polar"}
            )
            # Constrained layout under-counts the angle labels round a polar axes.
            fig.get_layout_engine().set(w_pad=0.25, h_pad=0.1)
    ax.set_title(_default_title(result) if title is None else title)
    handles = _draw(ax, result, lay, kind)

    def legend(keyed: Sequence[tuple[int, str]] = ()) -> None:
        """The legend, then (a Gantt chart's) numbered titles under their heading."""
        more, titles = key_entries(keyed, heading=True)
        ax.legend(
            handles=[*handles, *more],
            labels=[*(h.get_label() for h in handles), *titles],
            loc="upper left",
            frameon=False,
            fontsize=8,
            **(_POLAR_LEGEND if kind == "circular" else {"bbox_to_anchor": (1.01, 1.0)}),
        )

    legend()
    _label(ax, lay, kind, legend)
    return ax


def plot_cyclogram_pair(result: Schedule | Optimum, *, title: str | None = None) -> Figure:
    """A figure with the Gantt chart (wide, left) and the circular diagram (right).

    Drawn as by :func:`plot_cyclogram`; one legend, right of the circle, serves
    both.

    Parameters
    ----------
    result : Schedule or Optimum
        The result of :meth:`~cyclomech.cyclogram.Cyclogram.schedule` or
        :meth:`~cyclomech.cyclogram.Cyclogram.optimize` (angles in degrees).
    title : str, optional
        The figure's title, above both; default the duration [deg] or the limiting
        operation's angle [deg].

    Returns
    -------
    matplotlib.figure.Figure
        The figure: the Gantt axes is ``fig.axes[0]``, the polar one
        ``fig.axes[1]``.

    Raises
    ------
    InputError
        If ``result`` is neither a Schedule nor an Optimum.
    ImportError
        If matplotlib is not installed.

    See Also
    --------
    plot_cyclogram : One of the two diagrams, on axes of your own.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> import cyclomech as cm
    >>> from cyclomech.cyclogram.plot import plot_cyclogram_pair
    >>> cg = cm.Cyclogram(limiting=("1", "2"))
    >>> cg.add_operation("1", "2", 40, mechanism="lifter", name="lift")
    >>> cg.add_operation("2", "1", 90, mechanism="lifter", name="return", height=1)
    >>> fig = plot_cyclogram_pair(cg.optimize())
    >>> fig.get_suptitle(), [a.name for a in fig.axes]
    ('Cyclogram — lift (limiting) gets 270°', ['rectilinear', 'polar'])
    >>> plt.close(fig)
    """
    plt = pyplot()
    lay = _layout(result)
    w, h = _gantt_size(lay)
    fig = plt.figure(figsize=(w + 6.5, max(h, 5.5)), layout="constrained")
    grid = fig.add_gridspec(1, 2, width_ratios=(w, 6.5))
    gantt = fig.add_subplot(grid[0, 0])
    polar = fig.add_subplot(grid[0, 1], projection="polar")
    fig.suptitle(_default_title(result) if title is None else title)
    handles = _draw(polar, result, lay, "circular")
    labels = {h.get_label() for h in handles}
    handles += [h for h in _draw(gantt, result, lay, "gantt") if h.get_label() not in labels]
    polar.legend(handles=handles, loc="upper left", frameon=False, fontsize=8, **_POLAR_LEGEND)
    where = {"loc": "upper left", "bbox_to_anchor": (1.01, 1.0), "frameon": False}
    _label(gantt, lay, "gantt", lambda keyed: key_legend(gantt, keyed, **where))
    _label(polar, lay, "circular")
    return fig


_POLAR_LEGEND: dict[str, Any] = {
    "bbox_to_anchor": (1.08, 1.0),
    "alignment": "left",
    "title": "rings, centre outwards",
    "title_fontsize": 8,
}


def _draw(ax: Axes, result: Schedule | Optimum, lay: _Layout, kind: str) -> list[Any]:
    """Draw the bars and marks on ``ax``; return the legend handles."""
    if kind == "gantt":
        return _gantt(ax, result, lay)
    _require_polar(ax)
    return _circular(cast("PolarAxes", ax), result, lay)


def _label(
    ax: Axes, lay: _Layout, kind: str, key: Callable[[list[tuple[int, str]]], Any] | None = None
) -> None:
    """Write the operations' titles (and angles) on the bars where they fit; the
    limiting operation's, in bold, always (above its bar on a Gantt chart if need be).
    A title that does not fit gets a number, keyed beside the axes (a Gantt chart's
    by ``key``, called with the numbered titles).

    Text is fitted to the axes as laid out, so this runs after everything else."""
    if kind == "gantt":
        _label_gantt(ax, lay, key)
        return
    # The key takes room from the axes: label again until the numbered titles stay.
    before, keyed = list(ax.texts), None
    for _ in range(4):
        _settle_layout(ax)
        for text in [t for t in ax.texts if t not in before]:
            text.remove()
        now = _label_circular(ax, lay)
        if now == keyed:
            break
        key_legend(ax, now, loc="lower left", bbox_to_anchor=(1.08, 0.0))
        keyed = now
        if not now:
            break


# The notebook's figure of an Optimum (its ``_repr_html_``).
register_figure(Optimum, lambda o: plot_cyclogram(o).figure)
