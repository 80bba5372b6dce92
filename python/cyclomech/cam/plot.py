"""Plots of a disc cam: the cam itself, its SVAJ diagram, its loads along the
cycle and its smallest phase angles against speed.

:func:`plot_cam` draws the cam in its own frame (lengths in mm, equal aspect):
the profile coloured by the pressure angle or the contact stress, the pitch curve,
the base circle and the follower at a few cam angles. :func:`plot_svaj` draws the
follower's displacement and its derivatives against cam angle, per radian of cam
or (with a speed) per second; :func:`plot_along_cycle` the pressure angle, normal
force, Hertz stress and shaft torque at a speed; :func:`plot_min_phase_angles` a
:class:`cyclomech.cam.MinPhaseAngles` against speed, per criterion and segment;
:func:`plot_size_tradeoff` the smallest phase angles against the base radius
(:func:`cyclomech.synthesis.cam_size_tradeoff`).

matplotlib is an optional dependency (``pip install 'cyclomech[plot]'``), imported
only when a function draws; the functions draw on the axes they are given (or on a
new figure), return what they drew on, and never call ``plt.show()``. Artists carry
a ``gid`` (named in each docstring) so that what is drawn can be found again.
"""

from __future__ import annotations

import itertools
import math
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from .._arrays import float_array, positive, real_array
from .._errors import InputError
from .._notebook import register_figure
from .._plotting import (
    CRITICAL_COLOR,
    LINK_COLOR,
    MM,
    angle_axis,
    axes_arg,
    deg_text,
    frame_equal,
    pyplot,
    true_runs,
)
from .._units import RAD_PER_S_PER_RPM
from ._followers import FlatFaced, OscillatingRoller
from ._loads import CamLoads, Contact, FollowerLoads, MinPhaseAngles, default_pressure_angle_deg
from ._program import Cam
from ._size import CamSizeTradeoff

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = [
    "plot_along_cycle",
    "plot_cam",
    "plot_min_phase_angles",
    "plot_size_tradeoff",
    "plot_svaj",
]

Array = npt.NDArray[np.float64]
#: Cam-angle steps of a turn in the drawings (0.25°).
_STEPS = 1440
#: What :func:`plot_cam` can colour the profile by.
COLOR_BY = ("pressure_angle", "contact_stress")
#: Line styles of the criteria of :data:`cyclomech.cam.CRITERIA` in
#: :func:`plot_min_phase_angles`.
_CRITERION_STYLES: tuple[Any, ...] = ("-", "--", ":", "-.", (0, (1.5, 4)))
#: Line style of a segment's own angle in :func:`plot_min_phase_angles`.
_NOMINAL_STYLE = (0, (6, 2, 1, 2, 1, 2))
_SEPARATION_COLOR = "#ff7f0e"
_ROLLER_COLOR = "#7f7f7f"


def _check_cam(cam: Any, what: str) -> Cam:
    if not isinstance(cam, Cam):
        raise InputError(f"{what}: cam must be a cyclomech.cam.Cam; got {cam!r}")
    return cam


def _rot(theta: Array, v: Array) -> Array:
    """R(−θ)·v for each θ: a fixed-frame vector seen in the cam frame."""
    c, s = np.cos(theta), np.sin(theta)
    return np.stack([c * v[..., 0] + s * v[..., 1], -s * v[..., 0] + c * v[..., 1]], axis=-1)


def _segments_xy(points: Array) -> Any:
    """(n, 2) vertices of a closed curve -> (n, 2, 2) line segments i -> i+1."""
    return np.stack([points, np.roll(points, -1, axis=0)], axis=1)


def _boundaries_deg(cam: Cam) -> Array:
    return np.concatenate([[0.0], np.cumsum([g.angle_deg for g in cam.segments])])


def _cycle_grid(cam: Cam) -> tuple[Array, Array, npt.NDArray[np.intp]]:
    """Cam angles over one turn segment by segment, each segment's ends just
    inside it, so that a jump at a boundary (the jerk, a segment's load) is a gap,
    not a steep line: (deg with a NaN between segments, the angles [rad] to solve
    at, their indices in deg)."""
    edges = _boundaries_deg(cam)
    parts: list[Array] = []
    for a, b in itertools.pairwise(edges):
        n = max(round(2 * _STEPS * (b - a) / 360.0), 64)
        parts += [np.linspace(a + 1e-7, b - 1e-7, n), np.array([np.nan])]
    deg = np.concatenate(parts[:-1])
    idx = np.flatnonzero(np.isfinite(deg))
    return deg, np.radians(deg[idx]), idx


def _spread(values: Any, idx: npt.NDArray[np.intp], size: int, fill: Any = np.nan) -> Any:
    out = np.full(size, fill, dtype=np.asarray(values).dtype)
    out[idx] = values
    return out


def _mark_segments(cam: Cam, axes: list[Axes], *, label_on: Axes | None) -> None:
    """Dotted lines at the segments' boundaries; each segment's kind above ``label_on``."""
    edges = _boundaries_deg(cam)
    for ax in axes:
        for x in edges[1:-1]:
            ax.axvline(float(x), color="0.35", ls=":", lw=0.9, gid="boundary", zorder=1.5)
    if label_on is not None:
        for i, g in enumerate(cam.segments):
            mid = 0.5 * (edges[i] + edges[i + 1])
            label_on.annotate(
                g.kind,
                (float(mid), 1.0),
                xycoords=("data", "axes fraction"),
                xytext=(0, 3),
                textcoords="offset points",
                ha="center",
                va="bottom",
                fontsize=8,
                color="0.25",
                gid=f"kind:{i}",
            )


def plot_cam(
    cam: Cam,
    *,
    positions_deg: npt.ArrayLike | None = None,
    color_by: str = "pressure_angle",
    loads: FollowerLoads | None = None,
    contact: Contact | None = None,
    rpm: float | None = None,
    ax: Axes | None = None,
    title: str | None = None,
) -> Axes:
    """Draw ``cam`` in its frame, lengths in mm at equal scale; return the axes.

    The profile (and a groove's outer flank) is a LineCollection coloured, with a
    colorbar, by |pressure angle| [deg] (``color_by="pressure_angle"``) or by the
    Hertz stress σ_H [MPa] at ``rpm`` with ``loads`` and ``contact``
    (``color_by="contact_stress"``; the unloaded flank of a groove, and where the
    follower is separated, are grey). Each line segment takes the value at its
    middle cam angle, solved exactly (1440 segments a turn). The pitch curve is
    dashed, the base circle thin, the cam centre a cross; undercut stretches are
    red. The follower is drawn at the cam angles ``positions_deg`` where it is in
    the cam frame at those angles: the roller at the pitch point (a dot for a knife
    edge, the face for a flat-faced follower), a translating follower's stem along
    its line of motion, an oscillating follower's arm from its pivot, which is at
    R(−θ)·(a, 0).

    Parameters
    ----------
    cam : Cam
        The cam.
    positions_deg : array_like of float, optional
        The cam angles at which the follower is drawn [deg]; default None (six:
        0°, 60°, … 300°).
    color_by : {"pressure_angle", "contact_stress"}, default "pressure_angle"
        What colours the profile.
    loads : FollowerLoads, optional
        The follower's loads (needed for ``color_by="contact_stress"``); default None.
    contact : Contact, optional
        The Hertz contact (needed for ``color_by="contact_stress"``); default None.
    rpm : float, optional
        The cam speed of the stress [rpm] (needed for ``color_by="contact_stress"``);
        default None.
    ax : matplotlib.axes.Axes, optional
        The axes to draw on; default None (a new figure).
    title : str, optional
        The title; default None (the follower's kind and the closure).

    Returns
    -------
    matplotlib.axes.Axes
        The axes drawn on.

    Raises
    ------
    InputError
        If ``cam`` is not a :class:`~cyclomech.cam.Cam`, ``color_by`` is unknown, a
        position is not finite, or ``color_by="contact_stress"`` lacks ``loads``,
        ``contact`` or ``rpm``.

    Notes
    -----
    Artists, by gid: ``"profile"``, ``"profile_outer"`` (groove), ``"pitch"``,
    ``"base"``, ``"centre"``, ``"undercut"``, ``"follower:<deg>"`` (roller or face),
    ``"arm:<deg>"``, ``"pivot:<deg>"``, ``"stem:<deg>"``, ``"label:<deg>"``.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import cyclomech as cm
    >>> from cyclomech.cam.plot import plot_cam
    >>> S = cm.cam.Segment
    >>> cam = cm.cam.Cam([S("rise", 120, 0.02), S("dwell", 60), S("return", 120, 0.02),
    ...                   S("dwell", 60)], cm.cam.TranslatingRoller(0.05, 0.01, offset=0.01))
    >>> ax = plot_cam(cam, positions_deg=[0, 90])
    >>> ax.get_xlabel(), len(ax.collections[0].get_array())
    ('x [mm]', 1440)
    """
    _check_cam(cam, "plot_cam")
    if color_by not in COLOR_BY:
        raise InputError(f"color_by must be one of {COLOR_BY}; got {color_by!r}")
    shown: Array = (
        np.arange(6, dtype=np.float64) * 60.0
        if positions_deg is None
        else float_array("positions_deg", positions_deg, ndims=(0, 1)).reshape(-1)
    )
    if not np.isfinite(shown).all():
        raise InputError(f"positions_deg must be finite [deg]; got {shown.tolist()}")
    stress = color_by == "contact_stress"
    if stress:
        missing = [
            n for n, v in (("loads", loads), ("contact", contact), ("rpm", rpm)) if v is None
        ]
        if missing:
            raise InputError(
                f"color_by='contact_stress' needs loads, contact and rpm; missing {missing}"
            )
    plt = pyplot()
    from matplotlib.collections import LineCollection
    from matplotlib.patches import Circle

    # Vertices at even steps, colour values at the odd (middle) ones: one solve.
    theta = np.arange(2 * _STEPS) * (math.pi / _STEPS)
    k = cam.solve(theta)
    vert, mid = slice(0, None, 2), slice(1, None, 2)
    groove = k.profile_outer is not None
    inner_value = np.degrees(np.abs(k.pressure_angle[mid]))
    outer_value = inner_value
    label = "|pressure angle|  [deg]"
    cmap = plt.get_cmap("viridis")
    if stress:
        assert loads is not None and rpm is not None
        ld = cam.loads(theta[mid], positive("rpm", rpm, "[rpm]"), loads, contact)
        sigma = np.where(ld.separated, np.nan, ld.contact_stress / 1e6)
        inner_value = np.where(ld.normal_force >= 0.0, sigma, np.nan)
        outer_value = np.where(ld.normal_force < 0.0, sigma, np.nan)
        label = f"σ_H at {rpm:g} rpm  [MPa]"
        cmap = plt.get_cmap("inferno")
    cmap = cmap.with_extremes(bad="0.75")  # the unloaded flank, separation
    finite = np.concatenate([inner_value, outer_value if groove else []])
    finite = finite[np.isfinite(finite)]
    lo, hi = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
    norm = plt.Normalize(lo, hi if hi > lo else lo + 1.0)

    box = _box(cam, k, shown)
    if ax is None:
        _fig, ax = plt.subplots(figsize=(8.4, 7.0), layout="constrained")
    assert ax is not None
    # The base circle and pitch curve under the profile.
    ax.add_patch(
        Circle((0.0, 0.0), _base_radius(cam) * MM, fill=False, lw=0.6, ec="0.55", gid="base")
    )
    pitch = k.pitch[vert] * MM
    closed = np.vstack([pitch, pitch[:1]])
    ax.plot(closed[:, 0], closed[:, 1], ls="--", lw=0.9, color="#1f77b4", gid="pitch")
    lines = {"profile": (k.profile[vert], inner_value)}
    if groove:
        assert k.profile_outer is not None
        lines["profile_outer"] = (k.profile_outer[vert], outer_value)
    lc = None
    for gid, (pts, value) in lines.items():
        lc = LineCollection(
            _segments_xy(pts * MM), array=value, cmap=cmap, norm=norm, lw=2.4, gid=gid, zorder=3
        )
        ax.add_collection(lc, autolim=False)
    _undercut(ax, cam, k, vert)
    ax.plot([0.0], [0.0], "+", color=LINK_COLOR, ms=10, mew=1.4, gid="centre", zorder=4)
    _rotation_arrow(ax, 0.3 * _base_radius(cam) * MM)
    _followers(ax, cam, shown)
    frame_equal(ax, box, "mm", grid="0.92")
    assert lc is not None
    ax.figure.colorbar(lc, ax=ax, label=label, shrink=0.8)
    kind = cam.follower.title
    ax.set_title(title or f"cam, {kind} follower, {cam.closure} closure", fontsize=10)
    return ax


def _rotation_arrow(ax: Axes, r: float) -> None:
    """A counter-clockwise arc arrow of radius ``r`` [mm] about the centre: the cam
    turns counter-clockwise at positive ω."""
    from matplotlib.patches import FancyArrowPatch

    a0, a1 = math.radians(200.0), math.radians(320.0)
    ax.add_patch(
        FancyArrowPatch(
            (r * math.cos(a0), r * math.sin(a0)),
            (r * math.cos(a1), r * math.sin(a1)),
            connectionstyle="arc3,rad=0.5",
            arrowstyle="-|>",
            mutation_scale=10,
            color=LINK_COLOR,
            lw=1.0,
            gid="rotation",
        )
    )
    ax.annotate("ω", (0.0, -1.2 * r), ha="center", va="top", fontsize=9, color=LINK_COLOR)


def _base_radius(cam: Cam) -> float:
    return float(cam.follower.base_radius)


def _box(cam: Cam, k: Any, shown: Array) -> tuple[float, float, float, float]:
    """The extent [mm] of everything :func:`plot_cam` draws."""
    pts = [k.pitch.reshape(-1, 2), k.profile.reshape(-1, 2)]
    if k.profile_outer is not None:
        pts.append(k.profile_outer.reshape(-1, 2))
    f = cam.follower
    r = float(np.max(np.hypot(*np.concatenate(pts).T)))
    reach = r + getattr(f, "roller_radius", 0.0)
    if isinstance(f, OscillatingRoller):
        reach = max(reach, f.pivot_distance * 1.06)
    elif shown.size:
        reach *= 1.18  # room for the stems
    if isinstance(f, FlatFaced):
        reach = max(reach, float(np.max(np.hypot(*k.pitch.reshape(-1, 2).T))) * 1.15)
    reach *= MM
    return (-reach, reach, -reach, reach)


def _undercut(ax: Axes, cam: Cam, k: Any, vert: slice) -> None:
    """Red over each undercut run, on the flank that cusps: the inner flank where
    the pitch curve is convex, a groove's outer flank where it is concave."""
    flags = k.undercut[vert]
    if not flags.any():
        return
    concave = k.pitch_radius_of_curvature[vert] < 0.0
    flanks = [(k.profile[vert], flags)]
    if k.profile_outer is not None:
        flanks = [(k.profile[vert], flags & ~concave), (k.profile_outer[vert], flags & concave)]
    first = True
    for pts, mask in flanks:
        for a, b in true_runs(mask):
            seg = pts[a : b + 2] * MM  # to the next vertex: the run's last segment too
            ax.plot(
                seg[:, 0],
                seg[:, 1],
                color=CRITICAL_COLOR,
                lw=4.5,
                alpha=0.85,
                solid_capstyle="round",
                gid="undercut",
                label="undercut" if first else None,
                zorder=3.5,
            )
            first = False
    ax.legend(loc="upper right", fontsize=8)


def _followers(ax: Axes, cam: Cam, shown: Array) -> None:
    """The follower at the cam angles ``shown`` [deg], in the cam frame."""
    from matplotlib.patches import Circle

    if not shown.size:
        return
    th = np.radians(shown)
    k = cam.solve(th)
    f = cam.follower
    pitch = k.pitch.reshape(-1, 2) * MM
    rr = getattr(f, "roller_radius", 0.0) * MM
    colors = pyplot().get_cmap("tab10")(np.arange(len(shown)) % 10)
    r_max = float(np.max(np.hypot(*pitch.T)))
    for j, deg in enumerate(shown):
        key = f"{deg:g}"
        p, t, c = pitch[j], float(th[j]), colors[j]
        up = _rot(np.array(t), np.array([0.0, 1.0]))  # the follower's +y in the cam frame
        if isinstance(f, OscillatingRoller):
            pivot = _rot(np.array(t), np.array([f.pivot_distance, 0.0])) * MM
            ax.plot(*zip(pivot, p, strict=True), color=c, lw=1.6, gid=f"arm:{key}", zorder=4)
            ax.plot(*pivot, "o", color=c, mfc="white", ms=6, mew=1.4, gid=f"pivot:{key}", zorder=5)
        elif isinstance(f, FlatFaced):
            half = 0.35 * r_max
            across = np.array([up[1], -up[0]])
            face = np.array([p - half * across, p + half * across])
            ax.plot(face[:, 0], face[:, 1], color=c, lw=2.0, gid=f"follower:{key}", zorder=4)
            stem = np.array([p, p + 0.18 * r_max * up])
            ax.plot(stem[:, 0], stem[:, 1], color=c, lw=1.4, gid=f"stem:{key}", zorder=4)
        else:
            stem = np.array([p + rr * up, p + (rr + 0.16 * r_max) * up])
            ax.plot(stem[:, 0], stem[:, 1], color=c, lw=1.6, gid=f"stem:{key}", zorder=4)
        if not isinstance(f, FlatFaced):
            if rr > 0.0:
                ax.add_patch(
                    Circle(
                        tuple(p), rr, fill=False, ec=c, lw=1.4, gid=f"follower:{key}", zorder=4.5
                    )
                )
            else:
                ax.plot(*p, "o", color=c, ms=4, gid=f"follower:{key}", zorder=4.5)
        # The label outside the roller, away from the centre.
        d = p / (float(np.hypot(*p)) or 1.0)
        ax.annotate(
            deg_text(deg),
            tuple(p),
            xytext=tuple(p + d * (rr + 0.09 * r_max)),
            fontsize=8,
            color=c,
            ha="center",
            va="center",
            gid=f"label:{key}",
            zorder=5,
        )


def plot_svaj(
    cam: Cam,
    *,
    rpm: float | None = None,
    axes: Any = None,
    title: str | None = None,
) -> npt.NDArray[Any]:
    """The SVAJ diagram of ``cam`` on four stacked axes.

    The follower's displacement s, velocity v, acceleration a and jerk j against cam
    angle [deg] over one turn. Without ``rpm`` the derivatives are per radian of
    cam: s [m], s′ [m/rad], s″ [m/rad²], s‴ [m/rad³] (an oscillating follower:
    [rad/rad^k]); with ``rpm`` they are per second at that speed: v = s′ω [m/s],
    a = s″ω² [m/s²], j = s‴ω³ [m/s³] ([rad/s^k] for an oscillating follower). An
    oscillating follower's s is shown in degrees of arm rotation. The segments'
    boundaries are dotted and each segment's kind is written above the top axes.

    Parameters
    ----------
    cam : Cam
        The cam.
    rpm : float, optional
        The cam speed [rpm]; default None (derivatives per radian of cam).
    axes : sequence of 4 matplotlib.axes.Axes, optional
        The axes to draw on; default None (a new figure).
    title : str, optional
        The figure's title; default None ("follower motion, …").

    Returns
    -------
    ndarray of matplotlib.axes.Axes, shape (4,)
        The axes of s, v, a and j.

    Raises
    ------
    InputError
        If ``cam`` is not a :class:`~cyclomech.cam.Cam`, ``axes`` is not 4 Axes or
        ``rpm`` is not > 0.

    Notes
    -----
    Artists, by gid: ``"s"``, ``"v"``, ``"a"``, ``"j"``, ``"boundary"``,
    ``"kind:<i>"``.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import cyclomech as cm
    >>> from cyclomech.cam.plot import plot_svaj
    >>> S = cm.cam.Segment
    >>> cam = cm.cam.Cam([S("rise", 180, 0.02), S("return", 180, 0.02)],
    ...                  cm.cam.TranslatingRoller(0.05, 0.01))
    >>> axes = plot_svaj(cam, rpm=300.0)
    >>> len(axes), axes[1].get_ylabel()
    (4, 'v  [m/s]')
    """
    _check_cam(cam, "plot_svaj")
    given = axes_arg(axes, (4,), "plot_svaj")
    omega = None if rpm is None else positive("rpm", rpm, "[rpm]") * RAD_PER_S_PER_RPM
    plt = pyplot()
    if given is None:
        _fig, new = plt.subplots(4, 1, figsize=(7.5, 8.0), sharex=True, layout="constrained")
        given = list(new)
    deg, theta, idx = _cycle_grid(cam)
    k = cam.solve(theta)
    angular = isinstance(cam.follower, OscillatingRoller)
    unit = "rad" if angular else "m"
    w = 1.0 if omega is None else omega
    rows = [
        ("s", np.degrees(k.s) if angular else k.s, "deg" if angular else "m"),
        ("v", k.ds * w, f"{unit}/s" if omega else f"{unit}/rad"),
        ("a", k.dds * w**2, f"{unit}/s²" if omega else f"{unit}/rad²"),
        ("j", k.ddds * w**3, f"{unit}/s³" if omega else f"{unit}/rad³"),
    ]
    rows = [(g, _spread(y, idx, deg.size), u) for g, y, u in rows]
    names = ("s", "s′", "s″", "s‴") if omega is None else ("s", "v", "a", "j")
    colors = ("#1f77b4", "#2ca02c", "#d62728", "#9467bd")
    for ax, (gid, y, u), name, c in zip(given, rows, names, colors, strict=True):
        ax.axhline(0.0, color="0.6", lw=0.6)
        ax.plot(deg, y, color=c, lw=1.4, gid=gid)
        ax.set_ylabel(f"{name}  [{u}]")
        ax.grid(True, lw=0.4, alpha=0.5)
        angle_axis(ax, 360.0, "")
    given[-1].set_xlabel("cam angle θ  [deg]")
    _mark_segments(cam, given, label_on=given[0])
    speed = "per radian of cam" if omega is None else f"at {rpm:g} rpm"
    given[0].figure.suptitle(title or f"follower motion, {speed}", fontsize=11)
    return np.array(given, dtype=object)


def plot_along_cycle(
    cam: Cam,
    rpm: float,
    loads: FollowerLoads,
    contact: Contact | None = None,
    *,
    max_stress: float | None = None,
    max_pressure_angle_deg: float | None = None,
    axes: Any = None,
    title: str | None = None,
) -> npt.NDArray[Any]:
    """What the cam and follower carry over one turn at ``rpm`` with the follower's ``loads``.

    The pressure angle [deg] with ±[α] dashed; the normal force [N] (signed: − on a
    groove's outer flank, or with a spring the pull the follower would need); with
    ``contact`` the Hertz stress σ_H [MPa] with [σ_H] = ``max_stress`` dashed; the
    shaft torque [N·m]. Where a spring-closed follower leaves the cam the cycle is
    shaded on every axes.

    Parameters
    ----------
    cam : Cam
        The cam.
    rpm : float
        The cam speed [rpm] (> 0).
    loads : FollowerLoads
        The follower's loads.
    contact : Contact, optional
        The Hertz contact; default None (no stress axes).
    max_stress : float, optional
        The allowed Hertz stress [σ_H] [Pa], dashed; default None (not drawn).
    max_pressure_angle_deg : float, optional
        The allowed pressure angle [α] [deg]; default None (30° translating, 45°
        oscillating).
    axes : sequence of matplotlib.axes.Axes, optional
        3 axes, or 4 with ``contact``; default None (a new figure).
    title : str, optional
        The figure's title; default None.

    Returns
    -------
    ndarray of matplotlib.axes.Axes, shape (3,) or (4,)
        The axes: pressure angle, normal force, (Hertz stress,) shaft torque.

    Raises
    ------
    InputError
        If ``cam`` is not a :class:`~cyclomech.cam.Cam`, ``rpm`` or a limit is not
        > 0, or ``axes`` does not hold as many Axes.

    Notes
    -----
    Artists, by gid: ``"pressure_angle"``, ``"alpha_max"``, ``"normal_force"``,
    ``"contact_stress"``, ``"sigma_max"``, ``"shaft_torque"``, ``"separated"``,
    ``"boundary"``.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import cyclomech as cm
    >>> from cyclomech.cam.plot import plot_along_cycle
    >>> _, rpm, d = cm.cam.CamDesign.from_toml("examples/lifter_cam.toml")
    >>> axes = plot_along_cycle(d.cam, rpm, d.loads, d.contact, max_stress=d.max_stress)
    >>> [ax.get_ylabel() for ax in axes][2]
    'σ_H  [MPa]'
    """
    _check_cam(cam, "plot_along_cycle")
    n = positive("rpm", rpm, "[rpm]")
    count = 4 if contact is not None else 3
    given = axes_arg(axes, (count,), "plot_along_cycle")
    alpha = (
        default_pressure_angle_deg(cam.follower)
        if max_pressure_angle_deg is None
        else positive("max_pressure_angle_deg", max_pressure_angle_deg, "[deg]")
    )
    sigma_max = None if max_stress is None else positive("max_stress", max_stress, "[Pa]")
    deg, theta, idx = _cycle_grid(cam)
    k = cam.solve(theta)
    ld: CamLoads = cam.loads(theta, n, loads, contact)
    phi = _spread(np.degrees(k.pressure_angle), idx, deg.size)
    normal = _spread(ld.normal_force, idx, deg.size)
    sigma = _spread(ld.contact_stress / 1e6, idx, deg.size)
    torque = _spread(ld.shaft_torque, idx, deg.size)
    separated = _spread(ld.separated, idx, deg.size, False)
    plt = pyplot()
    if given is None:
        _fig, new = plt.subplots(
            count, 1, figsize=(7.5, 2.0 * count + 0.6), sharex=True, layout="constrained"
        )
        given = list(new)
    it = iter(given)
    ax = next(it)
    ax.plot(deg, phi, color="#1f77b4", lw=1.4, gid="pressure_angle")
    for sign in (1.0, -1.0):
        ax.axhline(
            sign * alpha,
            color=CRITICAL_COLOR,
            ls="--",
            lw=1.0,
            gid="alpha_max",
            label=f"±[α] = {alpha:g}°" if sign > 0 else None,
        )
    ax.set_ylabel("pressure angle  [deg]")
    ax.legend(fontsize=8, loc="lower right")
    ax = next(it)
    ax.plot(deg, normal, color="#2ca02c", lw=1.4, gid="normal_force")
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.set_ylabel("normal force  [N]")
    if contact is not None:
        ax = next(it)
        ax.plot(deg, sigma, color="#d62728", lw=1.4, gid="contact_stress")
        if sigma_max is not None:
            ax.axhline(
                sigma_max / 1e6,
                color=CRITICAL_COLOR,
                ls="--",
                lw=1.0,
                gid="sigma_max",
                label=f"[σ_H] = {sigma_max / 1e6:g} MPa",
            )
            ax.legend(fontsize=8, loc="lower right")
        ax.set_ylim(bottom=0.0)
        ax.set_ylabel("σ_H  [MPa]")
    ax = next(it)
    ax.plot(deg, torque, color="#9467bd", lw=1.4, gid="shaft_torque")
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.set_ylabel("shaft torque  [N·m]")
    ax.set_xlabel("cam angle θ  [deg]")
    runs = true_runs(separated)
    for i, a in enumerate(given):
        a.grid(True, lw=0.4, alpha=0.5)
        angle_axis(a, 360.0, a.get_xlabel())
        for j, (lo, hi) in enumerate(runs):
            a.axvspan(
                deg[lo],
                deg[hi],
                color=_SEPARATION_COLOR,
                alpha=0.22,
                lw=0,
                gid="separated",
                label="follower leaves the cam" if i == 1 and j == 0 else None,
            )
    if runs:
        given[1].legend(fontsize=8, loc="lower right")
    _mark_segments(cam, given, label_on=given[0])
    given[0].figure.suptitle(title or f"along the cycle at {n:g} rpm", fontsize=11)
    return np.array(given, dtype=object)


def plot_min_phase_angles(
    m: MinPhaseAngles,
    *,
    labels: Any = None,
    nominal_deg: npt.ArrayLike | None = None,
    ax: Axes | None = None,
    title: str | None = None,
) -> Axes:
    """The smallest phase angle [deg] of each segment of ``m`` against speed [rpm].

    One colour per segment, one line style per criterion (solid pressure angle,
    dashed undercut, dotted jump, dash-dot contact stress, sparse dots vibration),
    the bound (the largest) bold and faint under them. A criterion that is 0 at
    every speed (it does not bound the segment) is left out, and where it is 0 at
    some speeds its curve has a gap there; NaN (no angle up to a whole turn will
    do) is a gap too, as is the bound wherever one of its criteria is NaN.

    Parameters
    ----------
    m : MinPhaseAngles
        The smallest phase angles (:class:`cyclomech.cam.MinPhaseAngles`).
    labels : sequence of str, optional
        One name per segment; default None ("segment <i>").
    nominal_deg : array_like of float, optional
        Each segment's own angle [deg], one per segment, drawn as a thin
        horizontal line of its colour; default None (not drawn).
    ax : matplotlib.axes.Axes, optional
        The axes to draw on; default None (a new figure).
    title : str, optional
        The title; default None.

    Returns
    -------
    matplotlib.axes.Axes
        The axes drawn on.

    Raises
    ------
    InputError
        If ``m`` is not a :class:`~cyclomech.cam.MinPhaseAngles`, or ``labels`` or
        ``nominal_deg`` does not hold one item per segment.

    Notes
    -----
    Artists, by gid: ``"<i>:<criterion>"``, ``"<i>:bound"``, ``"<i>:nominal"``.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import numpy as np, cyclomech as cm
    >>> from cyclomech.cam.plot import plot_min_phase_angles
    >>> _, rpm, d = cm.cam.CamDesign.from_toml("examples/lifter_cam.toml")
    >>> m = d.min_phase_angles(np.linspace(100, 600, 11))
    >>> ax = plot_min_phase_angles(m, labels=["rise", "return"], nominal_deg=[70, 80])
    >>> ax.get_xlabel()
    'cam speed  [rpm]'
    """
    if not isinstance(m, MinPhaseAngles):
        raise InputError(f"m must be a cyclomech.cam.MinPhaseAngles; got {m!r}")
    n_seg = len(m.segments)
    if labels is not None and (isinstance(labels, str) or not hasattr(labels, "__len__")):
        raise InputError(f"labels must be one name per segment; got {labels!r}")
    names = [f"segment {i + 1}" for i in m.segments] if labels is None else [str(x) for x in labels]
    if len(names) != n_seg:
        raise InputError(f"labels holds {len(names)} names; m has {n_seg} segments")
    nominal = None
    if nominal_deg is not None:
        nominal = real_array("nominal_deg", nominal_deg, "[deg]", ndims=(1,))
        if nominal.size != n_seg:
            raise InputError(f"nominal_deg holds {nominal.size} angles; m has {n_seg} segments")
    plt = pyplot()
    from matplotlib.lines import Line2D

    if ax is None:
        _fig, ax = plt.subplots(figsize=(9.5, 4.6), layout="constrained")
    assert ax is not None
    rpm = np.asarray(m.rpm, dtype=np.float64).reshape(-1)
    a = np.asarray(m.angle_deg, dtype=np.float64).reshape(rpm.size, n_seg, len(m.criteria))
    marker = "o" if rpm.size < 3 else None
    used: set[int] = set()
    for i, seg in enumerate(m.segments):
        c = f"C{i % 10}"
        ax.plot(
            rpm,
            m.bound_deg.reshape(rpm.size, n_seg)[:, i],
            color=c,
            lw=5.0,
            alpha=0.3,
            solid_capstyle="butt",
            marker=marker,
            gid=f"{seg}:bound",
        )
        for j, crit in enumerate(m.criteria):
            y = a[:, i, j]
            if not (np.nan_to_num(y, nan=1.0) != 0.0).any():
                continue  # does not bound this segment at any speed
            used.add(j)
            # 0 is "does not bound the segment" at that speed: a gap, not a line at
            # 0° with a jump where the criterion starts to bound.
            ax.plot(
                rpm,
                np.where(y == 0.0, np.nan, y),
                color=c,
                lw=1.3,
                ls=_CRITERION_STYLES[j % len(_CRITERION_STYLES)],
                marker=marker,
                ms=3,
                gid=f"{seg}:{crit}",
            )
        if nominal is not None:
            ax.axhline(float(nominal[i]), color=c, lw=0.9, ls=_NOMINAL_STYLE, gid=f"{seg}:nominal")
    handles = [Line2D([], [], color=f"C{i % 10}", lw=5.0, alpha=0.45) for i in range(n_seg)]
    texts = [f"{names[i]}: bound" for i in range(n_seg)]
    handles += [
        Line2D([], [], color="0.2", lw=1.3, ls=_CRITERION_STYLES[j % len(_CRITERION_STYLES)])
        for j in sorted(used)
    ]
    texts += [m.criteria[j].replace("_", " ") for j in sorted(used)]
    if nominal is not None:
        handles.append(Line2D([], [], color="0.2", lw=0.9, ls=_NOMINAL_STYLE))
        texts.append("angle in the design")
    # Beside the axes, not on them: the curves fill the plot at every speed (at
    # "best" the legend covered the bounds between 400 and 500 rpm).
    ax.legend(
        handles, texts, fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0
    )
    ax.set_xlabel("cam speed  [rpm]")
    ax.set_ylabel("smallest phase angle  [deg]")
    ax.set_ylim(bottom=0.0)
    ax.grid(True, lw=0.4, alpha=0.5)
    ax.set_title(title or "smallest phase angle per criterion against speed", fontsize=10)
    return ax


def plot_size_tradeoff(
    t: CamSizeTradeoff,
    *,
    rpm_index: int = 0,
    labels: Any = None,
    sized_m: float | None = None,
    ax: Axes | None = None,
    title: str | None = None,
) -> Axes:
    """The smallest phase angle [deg] of each segment against the base radius [mm].

    The trade-off of :func:`cyclomech.synthesis.cam_size_tradeoff` at one of its
    speeds: one colour per segment, one line style per criterion (as
    :func:`plot_min_phase_angles`), the bound (the largest) bold and faint under
    them; a criterion 0 at every radius is left out, 0 and NaN are gaps. A larger
    cam takes a shorter phase angle: in a machine the cam's size sets its bounds
    in the timing LP and the LP its phase angles.

    Parameters
    ----------
    t : CamSizeTradeoff
        The trade-off (:func:`cyclomech.synthesis.cam_size_tradeoff`).
    rpm_index : int, default 0
        Which of its speeds to draw.
    labels : sequence of str, optional
        One name per segment; default None ("segment <i>").
    sized_m : float, optional
        A chosen base radius [m] (:func:`cyclomech.synthesis.cam_size`), drawn as a
        vertical line; default None (not drawn).
    ax : matplotlib.axes.Axes, optional
        The axes to draw on; default None (a new figure).
    title : str, optional
        The title; default None.

    Returns
    -------
    matplotlib.axes.Axes
        The axes drawn on.

    Raises
    ------
    InputError
        If ``t`` is not a trade-off, ``rpm_index`` is not one of its speeds' indices
        or ``labels`` does not hold one name per segment.

    Notes
    -----
    Artists, by gid: ``"<i>:<criterion>"``, ``"<i>:bound"``, ``"sized"``.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import numpy as np, cyclomech as cm
    >>> from cyclomech.cam.plot import plot_size_tradeoff
    >>> S = cm.cam.Segment
    >>> cam = cm.cam.Cam([S("rise", 120, 0.02), S("dwell", 60), S("return", 120, 0.02),
    ...                   S("dwell", 60)], cm.cam.TranslatingRoller(0.05, 0.01))
    >>> t = cm.synthesis.cam_size_tradeoff(cam, 300.0, np.linspace(0.015, 0.1, 12))
    >>> plot_size_tradeoff(t, labels=["rise", "return"]).get_xlabel()
    'base radius  [mm]'
    """
    if not isinstance(t, CamSizeTradeoff):
        raise InputError(f"t must be a cyclomech.synthesis.CamSizeTradeoff; got {t!r}")
    n_rpm = t.rpm.size
    if isinstance(rpm_index, bool) or not isinstance(rpm_index, int | np.integer):
        raise InputError(f"rpm_index must be an integer; got {rpm_index!r}")
    if not 0 <= int(rpm_index) < n_rpm:
        raise InputError(f"rpm_index = {rpm_index} must be in [0, {n_rpm}) (t's speeds)")
    n_seg = len(t.segments)
    if labels is not None and (isinstance(labels, str) or not hasattr(labels, "__len__")):
        raise InputError(f"labels must be one name per segment ({n_seg}); got {labels!r}")
    names = [f"segment {i + 1}" for i in t.segments] if labels is None else [str(x) for x in labels]
    if len(names) != n_seg:
        raise InputError(f"labels holds {len(names)} names; t has {n_seg} segments")
    plt = pyplot()
    from matplotlib.lines import Line2D

    if ax is None:
        _fig, ax = plt.subplots(figsize=(7.5, 4.6), layout="constrained")
    assert ax is not None
    r_mm = t.base_radius * MM
    a = t.angle_deg[:, int(rpm_index)]
    bound = t.bound_deg[:, int(rpm_index)]
    used: set[int] = set()
    for i, seg in enumerate(t.segments):
        c = f"C{i % 10}"
        ax.plot(r_mm, bound[:, i], color=c, lw=5.0, alpha=0.3, gid=f"{seg}:bound")
        for j, crit in enumerate(t.criteria):
            y = a[:, i, j]
            if not (np.nan_to_num(y, nan=1.0) != 0.0).any():
                continue
            used.add(j)
            ax.plot(
                r_mm,
                np.where(y == 0.0, np.nan, y),
                color=c,
                lw=1.3,
                ls=_CRITERION_STYLES[j % len(_CRITERION_STYLES)],
                gid=f"{seg}:{crit}",
            )
    handles = [Line2D([], [], color=f"C{i % 10}", lw=5.0, alpha=0.45) for i in range(n_seg)]
    texts = [f"{names[i]}: bound" for i in range(n_seg)]
    handles += [
        Line2D([], [], color="0.2", lw=1.3, ls=_CRITERION_STYLES[j % len(_CRITERION_STYLES)])
        for j in sorted(used)
    ]
    texts += [t.criteria[j].replace("_", " ") for j in sorted(used)]
    if sized_m is not None:
        x = positive("sized_m", sized_m, "[m]") * MM
        ax.axvline(x, color=CRITICAL_COLOR, lw=1.0, ls="--", gid="sized")
        handles.append(Line2D([], [], color=CRITICAL_COLOR, lw=1.0, ls="--"))
        texts.append(f"sized: {x:.4g} mm")
    ax.legend(handles, texts, fontsize=8, loc="best")
    ax.set_xlabel("base radius  [mm]")
    ax.set_ylabel("smallest phase angle  [deg]")
    ax.set_ylim(bottom=0.0)
    ax.grid(True, lw=0.4, alpha=0.5)
    rpm = float(t.rpm[int(rpm_index)])
    ax.set_title(title or f"smallest phase angle against base radius at {rpm:g} rpm", fontsize=10)
    return ax


# The notebook's figure of a Cam (its ``_repr_html_``).
register_figure(Cam, lambda cam: plot_cam(cam).figure)
