"""The press design grid's criteria map (:func:`plot_press_criteria`); part of
:mod:`cyclomech.press.plot`, which re-exports it."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from .._arrays import real
from .._errors import InputError
from .._plotting import (
    CRITICAL_COLOR,
    MM,
    axes_arg,
    deg_text,
    num_text,
    pyplot,
)
from . import PressGrid, PressOptimum

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["plot_press_criteria"]


#: How :func:`plot_press_criteria` shows each criterion: scale from SI, unit, name.
_CRITERION_SHOWN: dict[str, tuple[float, str, str]] = {
    "S_n": (MM, "mm", "nominal stroke S_n"),
    "S_p": (MM, "mm", "working stroke S_p"),
    "alpha_p": (180.0 / math.pi, "°", "crank angle of the working stroke α_p"),
    "V_np": (MM, "mm/s", "speed at the start of the working stroke V_np"),
    "V_cp": (MM, "mm/s", "mean speed over the working stroke V_cp"),
    "V_pmax": (MM, "mm/s", "top speed over the working stroke V_pmax"),
    "J_max": (1.0, "m/s²", "largest acceleration J_max"),
    "torque_arm": (MM, "mm", "torque arm (max Π' over the working stroke)"),
    "k_Sp": (1.0, "", "k_Sp = S_p/S_n"),
    "k_Vp": (1.0, "", "k_Vp = V_np/V_cp  (→ 0)"),
    "k_Vmax": (1.0, "", "k_Vmax = V_pmax/V_cp  (→ 1)"),
    "k_M": (1.0, "", "k_M = torque arm/(S_n/2)  (→ min)"),
    "k_J": (1.0, "", "k_J = J_max/(ω²·S_n/2)  (→ min)"),
    "theta_bdc": (180.0 / math.pi, "°", "carrier angle of BDC θ_bdc"),
}


def _criterion_label(name: str) -> str:
    _, unit, text = _CRITERION_SHOWN[name]
    return f"{text}  [{unit}]" if unit else f"{text}  [–]"


def _badness(name: str, v: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """How bad a criterion's value is (lower is better): |k_Vmax − 1| for k_Vmax."""
    return np.abs(v - 1.0) if name == "k_Vmax" else v


def _edges(v: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """Cell edges round grid values (midpoints; half a step beyond the ends)."""
    mid = (v[1:] + v[:-1]) / 2
    return np.concatenate([[v[0] - (mid[0] - v[0])], mid, [v[-1] + (v[-1] - mid[-1])]])


def plot_press_criteria(
    sweep: PressGrid,
    ax: Axes | Any = None,
    *,
    criterion: str = "k_Vp",
    phi0: float | None = None,
    optimum: PressOptimum | None = None,
    title: str | None = None,
) -> Axes | tuple[Axes, Axes]:
    """Map a working-stroke criterion over (d, L) at one φ0; return the axes.

    ``sweep`` is a :func:`cyclomech.press.design_grid` (or ``optimum.grid``) with d and L
    among its axes (two or more values each; R and r fixed or of one value). The
    map shows ``criterion`` (a name of :data:`cyclomech.press.CRITERIA`; lengths
    in mm, speeds in mm/s, angles in degrees) over d [mm] across and L [mm] up,
    one cell per design, with a colour bar (clipped at the 98th percentile when a
    few designs are far worse) and a few labelled contour lines; designs that
    fail (status ≠ 0, see :data:`cyclomech.press.STATUS`) are masked and hatched.
    The best working design of the map (lowest value, |k_Vmax − 1| for k_Vmax) is
    a white star. d = 0 is the plain crank-slider.

    The map is at the grid's φ0 nearest ``phi0`` [rad]; by default at the φ0 of
    the best design of the whole sweep by ``criterion``, or, with ``optimum``, at
    the φ0 nearest its best design's.

    With ``optimum`` (a :func:`cyclomech.press.optimize`) a second plot shows its
    non-dominated designs: k_Vp across, k_Vmax up, coloured by k_J (refined
    designs as diamonds), the baseline crank-slider (``optimum.baseline``) as a
    black square, the best design circled in red and also starred on the map,
    and the ideal (0, 1). ``ax`` must then be None or two axes, and the pair
    (map, Pareto plot) is returned. ``title`` defaults to the criterion and φ0.

    Artists, by gid: the map ``"criterion"`` (a QuadMesh whose masked array holds
    the values shown, L by d), ``"failed"`` (one hatched square per failed
    design), ``"best in map"``, ``"optimum"``; on the Pareto plot ``"pareto"``
    (offsets k_Vp, k_Vmax; array k_J), ``"baseline"``, ``"best"``, ``"ideal"``.

    Parameters
    ----------
    sweep : PressGrid
        A :func:`cyclomech.press.design_grid` (or ``optimum.grid``) with d and L
        among its axes (two or more values each; R and r fixed or of one value).
    ax : matplotlib.axes.Axes or tuple of (Axes, Axes), optional
        The axes to draw on (two with ``optimum``); default None (a new figure).
    criterion : str, default "k_Vp"
        The criterion mapped, a name of :data:`cyclomech.press.CRITERIA`.
        Keyword-only, as are the parameters below.
    phi0 : float, optional
        The map is at the grid's φ0 nearest this [rad]; default None (see above).
    optimum : PressOptimum, optional
        A :func:`cyclomech.press.optimize` result, drawn as the second plot.
    title : str, optional
        The title; default None (the criterion and φ0).

    Returns
    -------
    matplotlib.axes.Axes or tuple of (Axes, Axes)
        The map's axes, or the pair (map, Pareto plot) with ``optimum``.

    Raises
    ------
    InputError
        If ``sweep`` is not a :class:`~cyclomech.press.PressGrid` with d and L among
        its axes, ``criterion`` is not known, or ``optimum`` is not a
        :class:`~cyclomech.press.PressOptimum`.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> import numpy as np, cyclomech as cm
    >>> from cyclomech.press.plot import plot_press_criteria
    >>> sw = cm.press.design_grid(R=0.09, r=0.03, d=np.linspace(0, 0.04, 9),
    ...                     L=np.linspace(0.25, 0.5, 6), phi0=np.radians([0, 30, 55]),
    ...                     k_Sp=0.1, omega=4.0)
    >>> ax = plot_press_criteria(sw, phi0=np.radians(55))
    >>> ax.get_title().splitlines()[0], ax.get_xlabel()
    ('k_Vp over (d, L) at φ0 = 55°', 'eccentricity d [mm]  (d = 0: crank-slider)')
    >>> mesh = next(c for c in ax.collections if c.get_gid() == "criterion")
    >>> mesh.get_array().shape                               # L by d
    (6, 9)
    >>> plt.close("all")
    """
    pyplot()  # before the arguments: without matplotlib, that is the error to see
    given = _criteria_args(sweep, ax, criterion, optimum)
    k, phi_shown = _map_phi(sweep, criterion, phi0, optimum)
    mp = _criteria_map(sweep, criterion, k)
    axes = _criteria_axes(optimum) if given is None else given
    m = axes[0]

    # The map's layers, in the order they were always added (artists of equal
    # zorder overlap in that order, and the legend lists them in it).
    _draw_colours(m, mp)
    handles: list[Any] = _draw_failed(m, mp)
    if mp.data.compressed().size:
        handles.append(_mark_best_in_map(m, mp))
    if optimum is not None:
        handles.append(_mark_optimum(m, optimum))
    _frame_map(m, mp, handles)
    _title_map(m, sweep, criterion, phi_shown, title)
    if optimum is None:
        return m

    p = axes[1]
    top = _draw_pareto_front(p, optimum)
    _mark_pareto_references(p, optimum, top)
    _frame_pareto(p, optimum, top)
    return m, p


def _criteria_args(sweep: Any, ax: Any, criterion: Any, optimum: Any) -> list[Axes] | None:
    """:func:`plot_press_criteria`'s arguments checked, in the order it always
    checked them (so the first bad one is the one named); the given axes or None.
    The sweep must vary d and L (the map's two axes) and hold R and r at one value
    each (a map at several gears would mix designs of different strokes)."""
    if not isinstance(sweep, PressGrid):
        raise InputError(
            f"sweep must be a cyclomech.press.PressGrid (cm.press.design_grid(...)); "
            f"got {type(sweep).__name__}"
        )
    if not isinstance(criterion, str) or criterion not in _CRITERION_SHOWN:
        raise InputError(
            f"criterion = {criterion!r} is not known; criteria are {', '.join(_CRITERION_SHOWN)}"
        )
    if optimum is not None and not isinstance(optimum, PressOptimum):
        raise InputError(
            "optimum must be a cyclomech.press.PressOptimum (cm.press.optimize(...)) or None; "
            f"got {type(optimum).__name__}"
        )
    for name in ("d", "L"):
        if name not in sweep.axes or len(sweep.axes[name]) < 2:
            raise InputError(
                f"the sweep must vary {name} over two or more values to map it; its axes are "
                + ", ".join(f"{k} ({len(v)} values)" for k, v in sweep.axes.items())
            )
    for name, vals in sweep.axes.items():
        if name in ("R", "r") and len(vals) > 1:
            raise InputError(
                f"the sweep varies {name} over {len(vals)} values; map a sweep at one {name} "
                "(sweep it again with a scalar)"
            )
    return axes_arg(
        ax,
        (2,) if optimum is not None else (1,),
        "plot_press_criteria with optimum" if optimum is not None else "plot_press_criteria",
    )


def _map_phi(
    sweep: PressGrid, criterion: str, phi0: Any, optimum: PressOptimum | None
) -> tuple[int, float]:
    """The index on the sweep's φ0 axis of the map (0 when φ0 is fixed) and that φ0
    [rad]: the grid's nearest ``phi0``; else the nearest the optimum's best design;
    else the φ0 of the sweep's best working design by ``criterion``."""
    values = sweep.values[criterion]
    ok = sweep.ok
    names = list(sweep.axes)
    if "phi0" in sweep.axes:
        grid_phi = sweep.axes["phi0"]
        if phi0 is not None:
            try:
                target = real(phi0)  # not float(): "0.5" and True are not angles
            except (TypeError, ValueError):
                raise InputError(f"phi0 must be an angle [rad] or None; got {phi0!r}") from None
            if not math.isfinite(target):
                raise InputError(f"phi0 = {phi0!r} must be a finite angle [rad]")
            k = int(np.argmin(np.abs(grid_phi - target)))
        elif optimum is not None:
            k = int(np.argmin(np.abs(grid_phi - optimum.designs[optimum.best].phi0)))
        else:
            bad = np.where(ok, _badness(criterion, values), np.inf)
            if not np.isfinite(bad).any():
                raise InputError("no design of the sweep works (every status ≠ 0): nothing to map")
            k = int(np.unravel_index(int(np.argmin(bad)), bad.shape)[names.index("phi0")])
        phi_shown = float(grid_phi[k])
    else:
        k = 0
        phi_shown = float(sweep.fixed["phi0"])
        if phi0 is not None and abs(float(phi0) - phi_shown) > 1e-12:
            raise InputError(
                f"the sweep holds φ0 fixed at {phi_shown!r} rad; phi0 = {phi0!r} is not in it"
            )
    return k, phi_shown


@dataclass(frozen=True)
class _Map:
    """One map of :func:`plot_press_criteria`, shared by its layers: the criterion's
    values at one φ0 in display units, rows L and columns d, and the cells' centres
    and edges [mm]."""

    criterion: str
    scale: float  # display unit per SI unit of the criterion
    shown: npt.NDArray[np.float64]  # the values shown, rows L, columns d
    good: npt.NDArray[np.bool_]  # the designs that work (status 0)
    data: Any  # ``shown`` masked where a design fails or its value is not finite
    d_mm: npt.NDArray[np.float64]  # the cells' centres across
    l_mm: npt.NDArray[np.float64]  # and up
    de: npt.NDArray[np.float64]  # the cells' edges across
    le: npt.NDArray[np.float64]  # and up


def _criteria_map(sweep: PressGrid, criterion: str, k: int) -> _Map:
    """The :class:`_Map` of ``criterion`` at the ``k``-th φ0 of ``sweep`` (R and r at
    their one value), transposed to rows L and columns d whatever the order of the
    sweep's axes."""
    values = sweep.values[criterion]
    ok = sweep.ok
    names = list(sweep.axes)
    idx = tuple(slice(None) if nm in ("d", "L") else (k if nm == "phi0" else 0) for nm in names)
    scale = _CRITERION_SHOWN[criterion][0]
    shown = values[idx] * scale  # (d, L): the axes' order
    good = ok[idx]
    if names.index("d") > names.index("L"):
        shown, good = shown.T, good.T
    shown, good = shown.T, good.T  # rows L, columns d
    data = np.ma.masked_array(shown, mask=~good | ~np.isfinite(shown))
    d_mm, l_mm = sweep.axes["d"] * MM, sweep.axes["L"] * MM
    de, le = _edges(d_mm), _edges(l_mm)
    return _Map(criterion, scale, shown, good, data, d_mm, l_mm, de, le)


def _criteria_axes(optimum: PressOptimum | None) -> list[Axes]:
    """A new figure for :func:`plot_press_criteria`: the map, and with ``optimum``
    the Pareto plot beside it."""
    plt = pyplot()
    size = (14.0, 6.0) if optimum is not None else (7.8, 6.0)
    _, arr = plt.subplots(1, 2 if optimum is not None else 1, figsize=size, layout="constrained")
    return list(np.atleast_1d(arr))


def _colour_range(vis: npt.NDArray[np.float64]) -> tuple[float, float, str]:
    """The colour bar's range (lo, hi) over the values shown ``vis``, and its
    ``extend``: clipped at the 98th percentile ("max") when a few designs are so
    much worse that they would wash out the rest of the map."""
    extend = "neither"
    if vis.size:
        lo, hi = float(vis.min()), float(vis.max())
        top = float(np.percentile(vis, 98.0))
        if hi > lo and top < hi and (hi - lo) > 1.5 * (top - lo):
            hi, extend = top, "max"
    else:
        lo, hi = 0.0, 1.0
    if hi <= lo:
        hi = lo + 1.0
    return lo, hi, extend


def _draw_colours(m: Axes, mp: _Map) -> None:
    """The map's colours: one cell per design (failed ones masked), its colour bar
    labelled with the criterion and unit, and a few labelled white contour lines at
    the colour bar's ticks when the map has enough working designs to draw them."""
    vis = mp.data.compressed()
    lo, hi, extend = _colour_range(vis)
    mesh = m.pcolormesh(
        mp.de,
        mp.le,
        mp.data,
        cmap="viridis",
        vmin=lo,
        vmax=hi,
        shading="flat",
        gid="criterion",
        zorder=0.5,
    )
    cbar = m.figure.colorbar(mesh, ax=m, extend=extend, pad=0.02)
    cbar.set_label(_criterion_label(mp.criterion))
    if vis.size > 3 and mp.good.sum() >= 4:
        from matplotlib.ticker import MaxNLocator

        ticks = np.asarray(MaxNLocator(6).tick_values(lo, hi), dtype=float)
        levels = ticks[(ticks > lo) & (ticks < hi)]
        if levels.size:
            cs = m.contour(
                mp.d_mm,
                mp.l_mm,
                np.ma.filled(mp.data.astype(float), np.nan),
                levels=levels,
                colors="white",
                linewidths=0.7,
                alpha=0.85,
                zorder=1.0,
            )
            m.clabel(cs, fontsize=7.5, fmt=lambda v: num_text(float(v)))
            cs.set_gid("contours")


def _draw_failed(m: Axes, mp: _Map) -> list[Any]:
    """A hatched grey square over each design that fails (status ≠ 0); returns the
    legend's handle for them (none when every design works)."""
    from matplotlib.collections import PolyCollection
    from matplotlib.patches import Patch

    de, le = mp.de, mp.le
    failed = [
        [(de[j], le[i]), (de[j + 1], le[i]), (de[j + 1], le[i + 1]), (de[j], le[i + 1])]
        for i, j in zip(*np.nonzero(~mp.good), strict=True)
    ]
    m.add_collection(
        PolyCollection(
            failed,
            facecolors="0.88",
            edgecolors="0.45",
            hatch="xxx",
            linewidths=0.0,
            gid="failed",
            zorder=1.2,
        )
    )
    handles: list[Any] = []
    if failed:
        handles.append(
            Patch(facecolor="0.88", edgecolor="0.45", hatch="xxx", label="fails (status ≠ 0)")
        )
    return handles


def _mark_best_in_map(m: Axes, mp: _Map) -> Any:
    """A white star on the best working design of the map (the lowest value, or
    |k_Vmax − 1| for k_Vmax, compared in SI units); returns its legend handle, which
    gives the value."""
    from matplotlib.lines import Line2D

    bad = np.ma.masked_array(_badness(mp.criterion, mp.shown / mp.scale), mask=mp.data.mask)
    i, j = np.unravel_index(int(np.ma.argmin(bad)), bad.shape)
    m.plot(
        [mp.d_mm[j]],
        [mp.l_mm[i]],
        linestyle="none",
        marker="*",
        markersize=13,
        markerfacecolor="white",
        markeredgecolor="black",
        markeredgewidth=0.8,
        gid="best in map",
        zorder=3.0,
    )
    return Line2D(
        [],
        [],
        linestyle="none",
        marker="*",
        markersize=11,
        markerfacecolor="white",
        markeredgecolor="black",
        label=f"best in this map: {mp.criterion} = {num_text(float(mp.shown[i, j]))}",
    )


def _mark_optimum(m: Axes, optimum: PressOptimum) -> Any:
    """A red circle on the map at the optimiser's best design (d, L; it may lie off
    the grid and at another φ0); returns its legend handle, which gives its φ0."""
    from matplotlib.lines import Line2D

    best = optimum.designs[optimum.best]
    m.plot(
        [best.d * MM],
        [best.L * MM],
        linestyle="none",
        marker="o",
        markersize=12,
        markerfacecolor="none",
        markeredgecolor=CRITICAL_COLOR,
        markeredgewidth=2.0,
        gid="optimum",
        zorder=3.1,
    )
    return Line2D(
        [],
        [],
        linestyle="none",
        marker="o",
        markersize=10,
        markerfacecolor="none",
        markeredgecolor=CRITICAL_COLOR,
        markeredgewidth=2.0,
        label=f"best design (φ0 = {deg_text(math.degrees(best.phi0))})",
    )


def _frame_map(m: Axes, mp: _Map, handles: list[Any]) -> None:
    """The map's limits (the outer cells' edges), axis labels, and the legend of
    ``handles`` under it."""
    m.set_xlim(mp.de[0], mp.de[-1])
    m.set_ylim(mp.le[0], mp.le[-1])
    m.set_xlabel("eccentricity d [mm]  (d = 0: crank-slider)")
    m.set_ylabel("rod length L [mm]")
    if handles:
        m.legend(
            handles=handles,
            loc="upper center",
            bbox_to_anchor=(0.5, -0.11),
            ncols=2,
            frameon=False,
            fontsize=8,
        )


def _title_map(
    m: Axes, sweep: PressGrid, criterion: str, phi_shown: float, title: str | None
) -> None:
    """The map's title: ``title`` (by default the criterion and the φ0 shown), then a
    line with what the map holds fixed: the gears, the working stroke and ω."""
    fixed: dict[str, float] = dict(sweep.fixed)
    fixed.update({nm: float(sweep.axes[nm][0]) for nm in ("R", "r") if nm in sweep.axes})
    stroke = (
        f"k_Sp = {num_text(sweep.k_Sp)}"
        if sweep.k_Sp is not None
        else f"S_p = {num_text(float(sweep.working_stroke or 0.0) * MM)} mm"
    )
    head = f"{criterion} over (d, L) at φ0 = {deg_text(math.degrees(phi_shown))}"
    m.set_title(
        (head if title is None else title)
        + f"\nR = {num_text(fixed['R'] * MM)} mm, r = {num_text(fixed['r'] * MM)} mm, {stroke}, "
        f"ω = {num_text(sweep.omega)} rad/s",
        fontsize=10.5,
    )


def _draw_pareto_front(p: Axes, optimum: PressOptimum) -> float:
    """The optimum's non-dominated designs: k_Vp across, k_Vmax up, coloured by k_J
    (on one scale with the baseline's), the refined ones larger and in a diamond,
    and the k_J colour bar. Returns the largest k_Vp or k_Vmax of the designs and the
    baseline, which sizes the reference lines and the x range."""
    crit = optimum.criteria
    kv = np.array([c.k_Vp for c in crit])
    km = np.array([c.k_Vmax for c in crit])
    kj = np.array([c.k_J for c in crit])
    refined = np.array(optimum.refined, dtype=bool)
    base = optimum.baseline
    jlo = float(min(kj.min(), base.k_J))
    jhi = float(max(kj.max(), base.k_J))
    sc = p.scatter(
        kv,
        km,
        c=kj,
        cmap="plasma",
        vmin=jlo,
        vmax=jhi,
        s=30.0,
        marker="o",
        edgecolors="0.25",
        linewidths=0.4,
        gid="pareto",
        zorder=2.0,
    )
    sc.set_sizes(np.where(refined, 46.0, 30.0))
    if refined.any():
        p.scatter(
            kv[refined],
            km[refined],
            s=60.0,
            marker="D",
            facecolors="none",
            edgecolors="black",
            linewidths=0.9,
            gid="refined",
            zorder=2.1,
        )
    cb = p.figure.colorbar(sc, ax=p, pad=0.02)
    cb.set_label(_criterion_label("k_J"))
    return max(float(kv.max()), float(km.max()), base.k_Vp, base.k_Vmax)


def _mark_pareto_references(p: Axes, optimum: PressOptimum, top: float) -> None:
    """What the Pareto plot's designs are read against: the diagonal k_Vmax = k_Vp
    (up to ``top``), the baseline crank-slider (a black square), the best design
    (circled in red), the ideal (0, 1), and a legend entry for the refined designs'
    diamonds."""
    base = optimum.baseline
    best = optimum.designs[optimum.best]
    # V_pmax ≥ V_np and V_pmax ≥ V_cp: no design lies below this line or below 1.
    p.plot(
        [1.0, top * 1.05],
        [1.0, top * 1.05],
        color="0.6",
        linestyle="--",
        linewidth=0.8,
        gid="diagonal",
        zorder=0.8,
        label="k_Vmax = k_Vp: fastest at the start of the working stroke",
    )
    p.plot(
        [base.k_Vp],
        [base.k_Vmax],
        linestyle="none",
        marker="s",
        markersize=9,
        color="black",
        gid="baseline",
        zorder=3.0,
        label=f"crank-slider, d = 0 (k_Vp = {num_text(base.k_Vp)}, k_J = {num_text(base.k_J)})",
    )
    bc = optimum.criteria[optimum.best]
    p.plot(
        [bc.k_Vp],
        [bc.k_Vmax],
        linestyle="none",
        marker="o",
        markersize=14,
        markerfacecolor="none",
        markeredgecolor=CRITICAL_COLOR,
        markeredgewidth=2.0,
        gid="best",
        zorder=3.1,
        label=f"best design: d = {num_text(best.d * MM)} mm, L = {num_text(best.L * MM)} mm, "
        f"φ0 = {deg_text(math.degrees(best.phi0))}",
    )
    p.plot(
        [0.0],
        [1.0],
        linestyle="none",
        marker="P",
        markersize=10,
        color="#2ca02c",
        gid="ideal",
        zorder=3.0,
        label="ideal (k_Vp = 0, k_Vmax = 1)",
    )
    if any(optimum.refined):
        p.plot(
            [],
            [],
            linestyle="none",
            marker="D",
            markerfacecolor="none",
            markeredgecolor="black",
            label="refined off the grid by scipy",
        )


def _frame_pareto(p: Axes, optimum: PressOptimum, top: float) -> None:
    """The Pareto plot's axis labels, x range from just left of k_Vp = 0 (``top``
    sets the margin), grid, legend under it, and title naming the objectives."""
    p.set_xlabel(_criterion_label("k_Vp"))
    p.set_ylabel(_criterion_label("k_Vmax"))
    p.set_xlim(left=-0.03 * top)
    p.grid(color="0.9", linewidth=0.6)
    p.set_axisbelow(True)
    p.legend(loc="upper center", bbox_to_anchor=(0.5, -0.11), ncols=1, frameon=False, fontsize=8)
    p.set_title(
        f"Non-dominated designs ({len(optimum.criteria)}), objectives "
        + ", ".join(optimum.objectives),
        fontsize=10.5,
    )
