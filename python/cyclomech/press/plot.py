"""Plots of the gear-lever press: the mechanism with its pin's path and the
slider's motion, maps of the working-stroke criteria and the non-dominated designs.

:func:`plot_press` takes a :class:`cyclomech.press.GearLeverPress` and a crank
angle α [rad] from BDC, :func:`plot_press_criteria` a
:class:`~cyclomech.press.PressGrid` (with, optionally, a
:class:`~cyclomech.press.PressOptimum`). They show lengths in millimetres and
angles in degrees.

matplotlib is an optional dependency (``pip install 'cyclomech[plot]'``), imported
only when a function draws; the functions draw on the axes they are given (or on a
new figure), return what they drew on, and never call ``plt.show()``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from .._arrays import count, flag, real
from .._errors import InputError
from .._plotting import (
    DRIVER_COLOR,
    LINK_COLOR,
    MM,
    MOTION_COLORS,
    PLATE_COLOR,
    TRACE_COLORS,
    angle_axis,
    axes_arg,
    deg_text,
    frame_equal,
    ground_symbol,
    halo,
    label_direction,
    mechanism_figure,
    num_text,
    point_label,
    pyplot,
    slider_block,
    true_runs,
)
from . import GearLeverPress

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["plot_crank_torque", "plot_press", "plot_press_criteria"]


#: Colour of the working stroke (shading and the pin's path over it).
WORK_COLOR = "#f28e2b"
_CHAIN = (0, (9.0, 2.5, 1.5, 2.5))  # dash-dot line style of a pitch circle


def _press_arg(press: Any) -> GearLeverPress:
    if not isinstance(press, GearLeverPress):
        raise InputError(
            f"press must be a cyclomech.press.GearLeverPress; got {type(press).__name__}"
        )
    return press


def _design_text(press: GearLeverPress) -> str:
    """The design's parameters in mm and degrees, for titles."""
    mm = ", ".join(
        f"{k} = {num_text(getattr(press, k) * MM)}"
        for k in ("R", "r", "d", "L") + (("offset",) if press.offset != 0.0 else ())
    )
    return f"{mm} mm, φ0 = {deg_text(math.degrees(press.phi0))}"


def plot_press(
    press: GearLeverPress,
    alpha: float = 0.0,
    ax: Axes | Any = None,
    *,
    show_motion: bool = False,
    k_Sp: float | None = None,
    n: int = 720,
    title: str | None = None,
) -> Axes | tuple[Axes, Axes]:
    """Draw the gear-lever press at crank angle ``alpha`` [rad]; return the axes.

    ``alpha`` counts from BDC against the motion, as
    :meth:`~cyclomech.press.GearLeverPress.solve`.

    At equal scale in millimetres, in the frame of the guide gear's centre O: the
    fixed guide gear (a hatched ring on its pitch circle of radius R, drawn
    dash-dot), the planet's pitch circle (radius r) round its centre C, the
    carrier O → C in red, the planet's arm C → P to the rod pin P, the rod
    P → slider, the slider block between the rails of its vertical guide
    (x = ``offset``, drawn over the slider's travel), the ground symbol at O, an
    arrow for the carrier's (counterclockwise) turn, and the pin's whole path over
    one crank turn (a hypotrochoid, ``n`` + 1 angles from 0 to 2π) as a thin
    line. With ``k_Sp`` (the working stroke as a fraction of the nominal stroke,
    see :meth:`~cyclomech.press.GearLeverPress.criteria`) the part of the pin's
    path over the working stroke and the slider's working stroke beside its guide
    are drawn in orange.

    ``show_motion=True`` adds a second plot: S = Π(α) [mm], Π' [mm/rad] and Π''
    [mm/rad²] over the turn against α [deg], the angle drawn as a dotted line and
    the working stroke (0 … α_p) shaded when ``k_Sp`` is given; ``ax`` must then be
    None (a new figure with both) or two axes, and the pair (mechanism, motion) is
    returned. ``title`` defaults to the angle and the design's parameters.

    Artists, by gid: ``"guide gear"`` (the ring), ``"guide pitch circle"``,
    ``"planet"``, ``"planet pitch circle"`` (patches), the lines ``"carrier"``,
    ``"arm"``, ``"rod"`` (two points each), ``"pin path"`` (x, y [mm] of the pin
    at ``np.linspace(0, 2π, n + 1)``), ``"pin path, working stroke"``,
    ``"working stroke"``, ``"rotation"``, the collections ``"joints"`` (O, C, P,
    slider), ``"slider"``, ``"guides"``, ``"guide hatching"``, ``"ground"``,
    ``"ground hatching"``, texts ``"label:O"`` …; on the motion plot the curves
    ``"S"``, ``"Π'"``, ``"Π''"`` (x data α [deg]), the line ``"α"`` and the
    shading ``"working stroke"``.

    Parameters
    ----------
    press : GearLeverPress
        The design to draw.
    alpha : float, default 0.0
        The crank angle [rad], from BDC against the motion.
    ax : matplotlib.axes.Axes or tuple of (Axes, Axes), optional
        The axes to draw on (two with ``show_motion=True``); default None (a new
        figure).
    show_motion : bool, default False
        Add the plot of S, Π' and Π'' over the turn. Keyword-only, as are the
        parameters below.
    k_Sp : float, optional
        The working stroke as a fraction of the nominal stroke, drawn in orange;
        default None (not drawn).
    n : int, default 720
        The pin's path is drawn at ``n`` + 1 angles over the turn (≥ 8).
    title : str, optional
        The title; default None (the angle and the design's parameters).

    Returns
    -------
    matplotlib.axes.Axes or tuple of (Axes, Axes)
        The axes drawn on, or the pair (mechanism, motion) with
        ``show_motion=True``.

    Raises
    ------
    InputError
        If ``alpha`` is not a finite angle, ``n`` is out of range, or the rod cannot
        reach the slider's guide at ``alpha``.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt
    >>> import numpy as np, cyclomech as cm
    >>> from cyclomech.press.plot import plot_press
    >>> p = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.025, L=0.3, phi0=0.29)
    >>> ax = plot_press(p, np.radians(60))
    >>> ax.get_title().splitlines()[0]
    'Gear-lever press at α = 60° from BDC'
    >>> path = next(ln for ln in ax.get_lines() if ln.get_gid() == "pin path")
    >>> pin = p.solve(np.linspace(0, 2 * np.pi, 721)).pin * 1000   # [mm]
    >>> bool(np.allclose(path.get_xydata(), pin)), ax.get_xlabel()
    (True, 'x [mm]')
    >>> mech, motion = plot_press(p, np.radians(60), show_motion=True, k_Sp=0.1)
    >>> [ln.get_gid() for ln in motion.get_lines()][:3]
    ['S', "Π'", "Π''"]
    >>> plt.close("all")
    """
    pyplot()  # before the arguments: without matplotlib, that is the error to see
    press, a0, n, show_motion, given, now = _pose_args(press, alpha, ax, n, show_motion)
    turn = np.linspace(0.0, 2.0 * math.pi, n + 1)
    kin = press.solve(turn)
    alpha_p, k_text, why = _working_stroke(press, k_Sp)
    sc = _scene(press, now, kin)
    axes = _press_axes(sc.box, show_motion) if given is None else given
    mech = axes[0]

    # The layers, in the order they were always added (artists of equal zorder
    # overlap in that order, and the legend lists them in it).
    _draw_gears(mech, sc)
    _draw_pin_path(mech, press, sc, n, alpha_p, k_text)
    _draw_guide(mech, sc)
    _draw_ground(mech, sc)
    _draw_links(mech, sc)
    u = _draw_rotation(mech, sc)
    _label_joints(mech, press, sc, u)

    frame_equal(mech, sc.box, "mm", grid="0.92")
    mech.legend(loc="upper center", bbox_to_anchor=(0.5, -0.09), frameon=False, fontsize=8)
    if title is None:
        title = (
            f"Gear-lever press at α = {deg_text(math.degrees(a0))} from BDC\n"
            f"{_design_text(press)}{why}"
        )
    mech.set_title(title, fontsize=10.5)
    if not show_motion:
        return mech

    motion = axes[1]
    _draw_motion(motion, kin, turn, a0, alpha_p, k_text)
    return mech, motion


def _pose_args(
    press: Any, alpha: Any, ax: Any, n: Any, show_motion: Any
) -> tuple[GearLeverPress, float, int, bool, list[Axes] | None, Any]:
    """:func:`plot_press`'s arguments checked, in the order it always checked them
    (so the first bad one is the one named), and the pose at ``alpha`` solved:
    (press, α [rad], n, show_motion, the given axes or None, the pose). The pose
    must be assembled: a drawing of a rod that cannot reach its guide would show a
    mechanism that does not exist."""
    press = _press_arg(press)
    try:
        a0 = real(alpha)  # not float(): "0.5" and True are not angles
    except (TypeError, ValueError):
        raise InputError(f"alpha must be a crank angle [rad]; got {alpha!r}") from None
    if not math.isfinite(a0):
        raise InputError(f"alpha = {alpha!r} must be a finite crank angle [rad]")
    n = count("n", n, low=8)
    show_motion = flag("show_motion", show_motion)
    given = axes_arg(
        ax,
        (2,) if show_motion else (1,),
        "plot_press with show_motion=True" if show_motion else "plot_press",
    )
    now = press.solve(np.array([a0]))
    if not now.ok[0]:
        raise InputError(
            f"alpha = {a0!r} rad ({deg_text(math.degrees(a0))}): the rod "
            f"(L = {num_text(press.L * MM)} mm) cannot reach the slider's guide at this angle; "
            "pick an angle where press.solve(alpha).ok is True"
        )
    return press, a0, n, show_motion, given, now


def _working_stroke(press: GearLeverPress, k_Sp: float | None) -> tuple[float, str, str]:
    """The working stroke's end α_p [rad] (nan without ``k_Sp`` or without a working
    stroke), its text for the legends, and the title's line saying why there is
    none; α_p does not depend on ω, so the criteria are taken at ω = 1."""
    alpha_p = math.nan
    why = ""
    k_text = ""
    if k_Sp is not None:
        crit = press.criteria(k_Sp=k_Sp, omega=1.0)  # α_p does not depend on ω
        alpha_p = crit.alpha_p
        k_text = f"k_Sp = {num_text(crit.k_Sp)}"
        if not math.isfinite(alpha_p):
            why = f"\nno working stroke: {crit.status}"
    return alpha_p, k_text, why


@dataclass(frozen=True)
class _Scene:
    """The pose at the angle drawn and the drawing's sizes [mm], shared by the layers
    of :func:`plot_press`: computed once from the pose and the whole turn, so that
    every layer draws its symbols at one size inside one frame."""

    o: npt.NDArray[np.float64]  # the guide gear's centre O
    c: npt.NDArray[np.float64]  # the planet's centre C
    pin: npt.NDArray[np.float64]  # the rod's pin P
    b: npt.NDArray[np.float64]  # the slider's joint
    big: float  # the guide gear's pitch radius R
    small: float  # the planet's pitch radius r
    off: float  # the slider guide's x
    path: npt.NDArray[np.float64]  # the pin's path over the turn, (n + 1, 2)
    y_lo: float  # the slider's lowest y over the turn
    y_hi: float  # and its highest
    s: float  # size of the symbols
    ring: float  # width of the guide gear's ring
    box: tuple[float, float, float, float]  # (x0, x1, y0, y1) holding everything drawn


def _scene(press: GearLeverPress, now: Any, kin: Any) -> _Scene:
    """The :class:`_Scene` of the pose ``now`` (a one-angle solution) and the turn
    ``kin``: symbols sized by the span of everything drawn (the pin's path, the
    slider's travel, the guide gear's ring), and a frame round all of it with room
    for the symbols and labels."""
    o = np.zeros(2)  # the guide gear's centre O
    c, pin, b = now.centre[0] * MM, now.pin[0] * MM, now.slider[0] * MM
    big, small, off = press.R * MM, press.r * MM, press.offset * MM
    path = kin.pin * MM
    slide = kin.slider[kin.ok, 1] * MM
    y_lo, y_hi = float(slide.min()), float(slide.max())
    allp = np.concatenate([path, [c, pin, b, [off, y_lo], [off, y_hi]]])
    span = max(float(np.ptp(allp[:, 0])), float(np.ptp(allp[:, 1])), 2.0 * big)
    s = 0.03 * span  # size of the symbols [mm]
    ring = max(0.09 * big, 0.6 * s)  # width of the guide gear's ring [mm]
    pad = 0.05 * span + 2.0 * s
    box = (
        min(-big - ring, float(allp[:, 0].min()), off - 2.0 * s) - pad,
        max(big + ring, float(allp[:, 0].max()), off + 2.0 * s) + pad,
        min(-big - ring, float(allp[:, 1].min()), y_lo - 2.0 * s) - pad,
        max(big + ring, float(allp[:, 1].max()), y_hi + 2.0 * s) + pad,
    )
    return _Scene(o, c, pin, b, big, small, off, path, y_lo, y_hi, s, ring, box)


def _press_axes(box: tuple[float, float, float, float], show_motion: bool) -> list[Axes]:
    """A new figure for :func:`plot_press`: the mechanism's axes sized to ``box`` at
    equal scale, and with ``show_motion`` the motion plot beside it, the mechanism's
    width following its aspect within bounds so that neither plot is squeezed."""
    if show_motion:
        plt = pyplot()
        w, h = box[1] - box[0], box[3] - box[2]
        height = 7.4
        mech_w = min(max(height * w / h + 0.9, 3.6), 8.0)
        fig = plt.figure(figsize=(mech_w + 7.8, height), layout="constrained")
        grid = fig.add_gridspec(1, 2, width_ratios=(mech_w, 7.8))
        return [fig.add_subplot(grid[0, 0]), fig.add_subplot(grid[0, 1])]
    _, ax0 = mechanism_figure(box)
    return [ax0]


def _draw_gears(mech: Axes, sc: _Scene) -> None:
    """The gears: the fixed guide gear (a hatched ring outside its dash-dot pitch
    circle, radius R) and the planet (a plate under its pitch circle, radius r,
    round C). The pitch circles carry the legend's entry for both radii."""
    from matplotlib.patches import Annulus, Circle

    # The fixed guide gear: a hatched ring outside its pitch circle.
    mech.add_patch(
        Annulus(
            (0.0, 0.0),
            sc.big + sc.ring,
            sc.ring,
            facecolor="0.93",
            edgecolor="0.45",
            hatch="////",
            linewidth=0.8,
            gid="guide gear",
            zorder=0.8,
        )
    )
    mech.add_patch(
        Circle(
            (0.0, 0.0),
            sc.big,
            fill=False,
            edgecolor="0.25",
            linestyle=_CHAIN,
            linewidth=0.9,
            gid="guide pitch circle",
            label=f"pitch circles (R = {num_text(sc.big)} mm, r = {num_text(sc.small)} mm)",
            zorder=0.9,
        )
    )
    mech.add_patch(
        Circle(
            tuple(sc.c),
            sc.small,
            facecolor=PLATE_COLOR,
            edgecolor="none",
            alpha=0.85,
            gid="planet",
            zorder=1.0,
        )
    )
    mech.add_patch(
        Circle(
            tuple(sc.c),
            sc.small,
            fill=False,
            edgecolor="0.25",
            linestyle=_CHAIN,
            linewidth=0.9,
            gid="planet pitch circle",
            zorder=1.1,
        )
    )


def _draw_pin_path(
    mech: Axes, press: GearLeverPress, sc: _Scene, n: int, alpha_p: float, k_text: str
) -> None:
    """The pin's path over the turn (a hypotrochoid), and, when there is a working
    stroke (α_p finite), its part over the working stroke and the slider's working
    stroke beside the guide in orange. The working part is solved again at its own
    angles (about as dense as the path's) so that it ends exactly at α_p."""
    path = sc.path
    mech.plot(
        path[:, 0],
        path[:, 1],
        color=TRACE_COLORS[0],
        linewidth=0.9,
        label="pin path (hypotrochoid)",
        gid="pin path",
        zorder=1.3,
    )
    if math.isfinite(alpha_p):
        work = press.solve(np.linspace(0.0, alpha_p, max(16, int(n * alpha_p / math.tau) + 2)))
        wp = work.pin * MM
        mech.plot(
            wp[:, 0],
            wp[:, 1],
            color=WORK_COLOR,
            linewidth=2.6,
            solid_capstyle="butt",
            label=f"working stroke ({k_text})",
            gid="pin path, working stroke",
            zorder=1.35,
        )
        ys = work.slider[work.ok, 1] * MM
        xw = sc.off + 1.9 * sc.s
        mech.plot(
            [xw, xw],
            [float(ys.min()), float(ys.max())],
            color=WORK_COLOR,
            linewidth=3.2,
            solid_capstyle="butt",
            gid="working stroke",
            zorder=1.35,
        )


def _draw_guide(mech: Axes, sc: _Scene) -> None:
    """The slider's vertical guide at x = offset (two rails over its travel, hatched
    on the outside) and the slider's block on it."""
    from matplotlib.collections import LineCollection, PolyCollection

    s, off = sc.s, sc.off
    # The slider's guide: two rails over its travel, hatched on the outside.
    half = 0.75 * s + 0.12 * s
    y0, y1 = sc.y_lo - 1.8 * s, sc.y_hi + 1.8 * s
    rails = [[(off - half, y0), (off - half, y1)], [(off + half, y0), (off + half, y1)]]
    mech.add_collection(
        LineCollection(rails, colors=LINK_COLOR, linewidths=1.0, gid="guides", zorder=1.4)
    )
    ticks = []
    for yk in np.arange(y0 + 0.2 * s, y1, 0.9 * s):
        ticks.append([(off - half, yk), (off - half - 0.5 * s, yk - 0.5 * s)])
        ticks.append([(off + half, yk), (off + half + 0.5 * s, yk - 0.5 * s)])
    mech.add_collection(
        LineCollection(ticks, colors=LINK_COLOR, linewidths=0.6, gid="guide hatching", zorder=1.4)
    )
    mech.add_collection(
        PolyCollection(
            [slider_block(sc.b, (0.0, 1.0), s)],
            facecolors="#f4f4f4",
            edgecolors=LINK_COLOR,
            linewidths=1.2,
            gid="slider",
            zorder=3.0,
        )
    )


def _draw_ground(mech: Axes, sc: _Scene) -> None:
    """The ground symbol under O (the guide gear's fixed centre): a support triangle
    on a hatched base, smaller than the linkages' as the planet passes close to O."""
    from matplotlib.collections import LineCollection, PolyCollection

    # The ground symbol under O: a support triangle on a hatched base.
    corners, hatch = ground_symbol(0.0, 0.0, 0.7 * sc.s)  # smaller: the planet passes close to O
    mech.add_collection(
        PolyCollection(
            [corners],
            facecolors="white",
            edgecolors=LINK_COLOR,
            linewidths=1.0,
            gid="ground",
            zorder=1.8,
        )
    )
    mech.add_collection(
        LineCollection(hatch, colors=LINK_COLOR, linewidths=0.8, gid="ground hatching", zorder=1.8)
    )


def _draw_links(mech: Axes, sc: _Scene) -> None:
    """The links at the pose: the carrier O → C (the crank, in red), the planet's
    arm C → P and the rod P → slider, and the joints O, C, P and the slider's on
    top of them."""
    o, c, pin, b = sc.o, sc.c, sc.pin, sc.b
    mech.plot(
        [o[0], c[0]],
        [o[1], c[1]],
        color=DRIVER_COLOR,
        linewidth=3.4,
        solid_capstyle="round",
        label="carrier (crank)",
        gid="carrier",
        zorder=2.5,
    )
    mech.plot(
        [c[0], pin[0]],
        [c[1], pin[1]],
        color=LINK_COLOR,
        linewidth=2.0,
        solid_capstyle="round",
        gid="arm",
        zorder=2.2,
    )
    mech.plot(
        [pin[0], b[0]],
        [pin[1], b[1]],
        color=LINK_COLOR,
        linewidth=2.4,
        solid_capstyle="round",
        gid="rod",
        zorder=2.2,
    )
    pts = np.array([o, c, pin, b])
    mech.scatter(
        pts[:, 0],
        pts[:, 1],
        s=26.0,
        c="white",
        edgecolors=LINK_COLOR,
        linewidths=1.2,
        gid="joints",
        zorder=4.0,
    )


def _draw_rotation(mech: Axes, sc: _Scene) -> npt.NDArray[np.float64]:
    """The carrier's (counterclockwise) sense of rotation: an arc with an arrow head
    and "ω" round O, in the freest direction (away from the carrier and the ground
    symbol); returns that direction, which O's label must then avoid."""
    o, c = sc.o, sc.c
    # The carrier's sense of rotation, in the freest direction round O.
    down = np.array([0.0, -1.0])
    u = label_direction([c - o, down, np.array([-0.7, -0.7]), np.array([0.7, -0.7])])
    mid = math.atan2(u[1], u[0])
    rho = 0.45 * (sc.big - sc.small)
    t = np.linspace(mid - 0.6, mid + 0.6, 40)
    arc = rho * np.column_stack([np.cos(t), np.sin(t)])
    mech.plot(arc[:-3, 0], arc[:-3, 1], color=DRIVER_COLOR, linewidth=1.1, gid="rotation")
    mech.annotate(
        "",
        xy=tuple(arc[-1]),
        xytext=tuple(arc[-4]),
        arrowprops={
            "arrowstyle": "-|>",
            "color": DRIVER_COLOR,
            "linewidth": 1.1,
            "shrinkA": 0.0,
            "shrinkB": 0.0,
            "mutation_scale": 11.0,
        },
    )
    wx, wy = 1.3 * rho * u  # where "ω" goes: beyond the arc, on its middle
    mech.text(
        wx,
        wy,
        "ω",
        color=DRIVER_COLOR,
        fontsize=11,
        ha="center",
        va="center",
        path_effects=halo(),
        gid="label:ω",
    )
    return u


def _label_joints(
    mech: Axes, press: GearLeverPress, sc: _Scene, u: npt.NDArray[np.float64]
) -> None:
    """The joints' names O, C, P and "slider", each in the widest gap between the
    links and symbols at it (``u``: the rotation arrow's direction at O); for a
    crank-slider (d = 0) the pin is the planet's centre, labelled once "C = P"."""
    o, c, pin, b = sc.o, sc.c, sc.pin, sc.b
    down = np.array([0.0, -1.0])
    blocked = {
        "O": [c - o, down, np.array([-0.7, -0.7]), np.array([0.7, -0.7]), u],
        "C": [o - c, pin - c, b - pin],
        "P": [c - pin, b - pin],
        "slider": [pin - b, np.array([0.0, 1.0]), down, np.array([1.0, 0.0])],
    }
    named = [("O", o), ("C", c), ("P", pin), ("slider", b)]
    if press.d == 0.0:  # a crank-slider: the pin is the planet's centre
        named.pop(2)
    for name, q in named:
        d = label_direction(blocked[name])
        edge = 1.3 * sc.s if name == "slider" else 0.0
        text = "C = P" if name == "C" and press.d == 0.0 else name
        point_label(mech, name, q + edge * np.array([d[0] * 0.6, d[1]]), d, text=text)


def _draw_motion(
    motion: Axes, kin: Any, turn: npt.NDArray[np.float64], a0: float, alpha_p: float, k_text: str
) -> None:
    """The slider's motion over the turn: S, Π' and Π'' [mm, mm/rad, mm/rad²]
    against α [deg], the working stroke (0 … α_p) shaded, the angles where the rod
    cannot reach the guide shaded grey, and the angle drawn as a dotted line."""
    deg = np.degrees(turn)
    curves = (
        ("S", kin.s, "S = Π(α)  [mm]"),
        ("Π'", kin.ds, "Π' = dS/dα  [mm/rad]"),
        ("Π''", kin.dds, "Π'' = d²S/dα²  [mm/rad²]"),
    )
    for (gid, v, label), color in zip(curves, MOTION_COLORS, strict=True):
        motion.plot(deg, v * MM, color=color, linewidth=1.6, label=label, gid=gid)
    if math.isfinite(alpha_p):
        motion.axvspan(
            0.0,
            math.degrees(alpha_p),
            color=WORK_COLOR,
            alpha=0.28,
            linewidth=0.0,
            label=f"working stroke, {k_text} (α_p = {deg_text(math.degrees(alpha_p))})",
            gid="working stroke",
            zorder=0.4,
        )
    x = deg[:-1]
    step = float(deg[1] - deg[0])
    for i, j in true_runs(~kin.ok[:-1]):
        motion.axvspan(
            x[i] - step / 2,
            x[j] + step / 2,
            color="0.85",
            linewidth=0.0,
            label="rod cannot reach the guide" if i == true_runs(~kin.ok[:-1])[0][0] else "_",
            gid="not assembled",
            zorder=0.3,
        )
    motion.axvline(
        math.degrees(a0 % math.tau),
        color="0.2",
        linestyle=":",
        linewidth=1.2,
        label=f"α = {deg_text(math.degrees(a0))} (drawn)",
        gid="α",
    )
    motion.axhline(0.0, color="0.55", linewidth=0.6, zorder=0.5, gid="zero")
    _motion_ylim(motion, kin)
    angle_axis(motion, 360.0, "crank angle α from BDC (against the motion)")
    motion.set_ylabel("S [mm], Π' [mm/rad], Π'' [mm/rad²]")
    motion.grid(color="0.9", linewidth=0.6)
    motion.set_axisbelow(True)
    motion.legend(
        loc="upper center", bbox_to_anchor=(0.5, -0.09), ncols=2, frameon=False, fontsize=8
    )
    motion.set_title("Slider over one crank turn", fontsize=10.5)


def _motion_ylim(motion: Axes, kin: Any) -> None:
    """The motion plot's y range: matplotlib's own, unless a few values run far off
    the rest (near an angle where the rod cannot reach the guide Π'' runs off to
    infinity); then the 2nd to 98th percentiles of S, Π' and Π'' with a margin."""
    # Near an angle where the rod cannot reach the guide Π'' runs off to infinity:
    # keep the scale of the rest of the turn.
    every = np.concatenate([kin.s, kin.ds, kin.dds]) * MM
    every = every[np.isfinite(every)]
    if every.size:
        lo, hi = np.percentile(every, [2.0, 98.0])
        full_lo, full_hi = float(every.min()), float(every.max())
        if full_hi - full_lo > 4.0 * (hi - lo) > 0.0:
            motion.set_ylim(lo - 0.5 * (hi - lo), hi + 0.5 * (hi - lo))


from ._criteria_plot import plot_press_criteria  # noqa: E402 (the criteria map, re-exported)
from ._torque_plot import plot_crank_torque  # noqa: E402 (the crank torque, re-exported)
