"""The four-bar and the offset slider-crank by their lengths: a drawn
:class:`cyclomech.Linkage` of each (so that every synthesis result is analysed by
the existing position solver) and the :class:`Margins` every synthesis result
reports (Grashof type, transmission angle over the working range, branch, link
ratio). The checks are closed forms in the Rust core
(``rust/core/src/synthesis/fourbar.rs``).

Conventions (the core's): the crank pivot A is at ``origin``, the ground line
runs from A at ``ground_deg`` (four-bar: to the output pivot D at distance
``ground``; slider-crank: along the slide). The crank angle θ is measured from
the ground line, counter-clockwise. The assembly ``mode`` σ = ±1: +1 puts the
rocker pin C on the left of the ray D → B (slider-crank: the slider on the +
side of the crank pin along the slide); it is the branch, kept while the crank
turns as long as the linkage does not fold.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from .. import _core
from .._arrays import finite_number, flag, positive, real
from .._errors import InputError
from ..linkage import Linkage

__all__ = [
    "Margins",
    "four_bar_linkage",
    "four_bar_margins",
    "slider_crank_linkage",
    "slider_crank_margins",
]


@dataclass(frozen=True)
class Margins:
    """The constraint margins every synthesis result reports.

    Attributes
    ----------
    grashof : str
        Four-bar: ``"crank-rocker"``, ``"rocker-crank"``, ``"double-crank"``,
        ``"double-rocker"``, ``"change point"`` or ``"triple-rocker"``;
        slider-crank: ``"crank-slider"``, ``"change point"`` or ``"rocker-slider"``.
    crank_turns : bool
        The crank can turn fully relative to the ground.
    transmission_min_deg, transmission_max_deg : float
        The transmission angle's extremes μ ∈ [0°, 180°] over the working crank
        range [deg] (NaN where it cannot be assembled somewhere in the range).
    branch_ok : bool
        It assembles over the whole working range on one branch without a fold
        (a transmission angle of 0° or 180° anywhere in it is a defect), and every
        precision point or pose the synthesis asked for is reached on that
        branch (and, for poses, in order).
    length_ratio : float
        Longest over shortest link length: of the four links, ground included,
        for a four-bar; of crank and rod for a slider-crank.

    Examples
    --------
    >>> import cyclomech as cm
    >>> m = cm.synthesis.four_bar_margins(1, 3, 3.5, 4)
    >>> m.grashof, m.crank_turns, round(m.worst_transmission_deg, 3)
    ('crank-rocker', True, 54.315)
    """

    grashof: str
    crank_turns: bool
    transmission_min_deg: float
    transmission_max_deg: float
    branch_ok: bool
    length_ratio: float

    @property
    def worst_transmission_deg(self) -> float:
        """The worst (acute) transmission angle min(μ_min, 180° − μ_max) [deg];
        NaN where it does not assemble over the range.

        Examples
        --------
        >>> import cyclomech as cm
        >>> round(cm.synthesis.four_bar_margins(1, 3, 3.5, 4).worst_transmission_deg, 3)
        54.315
        """
        return min(self.transmission_min_deg, 180.0 - self.transmission_max_deg)


def _range(range_deg: Any) -> tuple[float, float]:
    """The working crank range [deg] as (lo, hi) [rad]; None is a full turn."""
    if range_deg is None:
        return 0.0, 2.0 * math.pi
    try:
        lo_v, hi_v = range_deg
    except (TypeError, ValueError):
        raise InputError(
            f"range_deg must be (lo, hi) crank angles in degrees, or None for a full turn; "
            f"got {range_deg!r}"
        ) from None
    lo = finite_number("range_deg[0]", lo_v, "[deg]")
    hi = finite_number("range_deg[1]", hi_v, "[deg]", low=lo)
    return math.radians(lo), math.radians(hi)


def _margins(
    kind: str,
    turns: bool,
    t: tuple[bool, float, float, float, float],
    branch_ok: bool,
    ratio: float,
) -> Margins:
    ok, mu_min, mu_max = t[0], t[1], t[2]
    # A fold (μ = 0° or 180°) inside the range is a branch defect too: there the
    # linkage can leave its branch, so the range is not held on one branch.
    ok = ok and mu_min > 0.0 and mu_max < math.pi
    return Margins(
        grashof=kind,
        crank_turns=turns,
        transmission_min_deg=math.degrees(mu_min) if ok else math.nan,
        transmission_max_deg=math.degrees(mu_max) if ok else math.nan,
        branch_ok=bool(ok and branch_ok),
        length_ratio=ratio,
    )


def four_bar_margins(
    crank: float,
    coupler: float,
    rocker: float,
    ground: float,
    *,
    range_deg: Sequence[float] | None = None,
    branch_ok: bool = True,
) -> Margins:
    """The margins of the four-bar crank, coupler, rocker, ground [m] over the
    crank range ``range_deg`` = (lo, hi) [deg] from the ground line (None: a full
    turn), in closed form.

    ``branch_ok`` is the caller's own branch verdict (precision points reached on
    one branch), and-ed with "assembles over the whole range".

    Examples
    --------
    >>> import cyclomech as cm
    >>> m = cm.synthesis.four_bar_margins(1, 3, 3.5, 4, range_deg=(0, 90))
    >>> m.grashof, round(m.transmission_min_deg, 3), m.branch_ok, round(m.length_ratio, 3)
    ('crank-rocker', 54.315, True, 4.0)
    """
    a = positive("crank", crank, "[m]")
    b = positive("coupler", coupler, "[m]")
    c = positive("rocker", rocker, "[m]")
    d = positive("ground", ground, "[m]")
    lo, hi = _range(range_deg)
    kind, turns, _ = _core.fourbar_grashof(a, b, c, d)
    t = _core.fourbar_transmission(a, b, c, d, lo, hi)
    links = (a, b, c, d)
    return _margins(kind, turns, t, flag("branch_ok", branch_ok), max(links) / min(links))


def slider_crank_margins(
    crank: float,
    rod: float,
    offset: float = 0.0,
    *,
    range_deg: Sequence[float] | None = None,
    branch_ok: bool = True,
) -> Margins:
    """The margins of the offset slider-crank crank, rod [m], offset [m] over the
    crank range ``range_deg`` = (lo, hi) [deg] from the slide (None: a full
    turn), in closed form. The transmission angle is the rod's angle to the
    slide's normal (90° when the rod is parallel to the slide).

    Examples
    --------
    >>> import cyclomech as cm
    >>> m = cm.synthesis.slider_crank_margins(0.1, 0.35)
    >>> m.grashof, round(m.worst_transmission_deg, 3)
    ('crank-slider', 73.398)
    """
    r = positive("crank", crank, "[m]")
    ln = positive("rod", rod, "[m]")
    e = finite_number("offset", offset, "[m]")
    lo, hi = _range(range_deg)
    kind = _core.slider_crank_kind(r, ln, e)
    t = _core.slider_crank_transmission(r, ln, e, lo, hi)
    return _margins(
        kind, kind != "rocker-slider", t, flag("branch_ok", branch_ok), max(r, ln) / min(r, ln)
    )


def _mode(mode: Any) -> float:
    if isinstance(mode, bool) or mode not in (1, -1):
        raise InputError(f"mode must be +1 or -1 (the assembly branch); got {mode!r}")
    return float(mode)


def _xy(name: str, value: Any) -> tuple[float, float]:
    try:
        x, y = value
        return real(x), real(y)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a point (x, y) [m]; got {value!r}") from None


def _place(
    origin: tuple[float, float], angle: float, local: dict[str, tuple[float, float]]
) -> dict[str, tuple[float, float]]:
    """The local frame's points (ground line along +x) rotated by ``angle`` [rad]
    about the origin and moved to ``origin``."""
    c, s = math.cos(angle), math.sin(angle)
    return {
        k: (origin[0] + c * x - s * y, origin[1] + s * x + c * y) for k, (x, y) in local.items()
    }


def _coupler_point(
    value: Any, pin: tuple[float, float], toward: tuple[float, float]
) -> tuple[float, float]:
    """The point (u, v) [m] of the coupler frame: u along pin → toward, v to its left."""
    u, v = _xy("coupler_point", value)
    dx, dy = toward[0] - pin[0], toward[1] - pin[1]
    n = math.hypot(dx, dy)
    ex, ey = dx / n, dy / n
    return pin[0] + u * ex - v * ey, pin[1] + u * ey + v * ex


def _coupler_body(pts: dict[str, tuple[float, float]], a: str, b: str) -> tuple[str, ...]:
    """The coupler's joints: (a, b), with P if drawn, and — where P lies on the
    line through a and b, so that the solver could not tell which side of that
    line it is on — a helper point Q of the coupler, a + (b − a) turned 90°,
    which fixes the side (adds it to ``pts``)."""
    if "P" not in pts:
        return (a, b)
    (xa, ya), (xb, yb), (xp, yp) = pts[a], pts[b], pts["P"]
    ab, ap = math.hypot(xb - xa, yb - ya), math.hypot(xp - xa, yp - ya)
    cross = (xb - xa) * (yp - ya) - (yb - ya) * (xp - xa)
    if abs(cross) > 1e-6 * ab * (ab + ap):
        return (a, b, "P")
    # Q before P: the solver places joints in the drawing's order, and P needs Q.
    p = pts.pop("P")
    pts["Q"] = (xa - (yb - ya), ya + (xb - xa))
    pts["P"] = p
    return (a, b, "Q", "P")


def four_bar_linkage(
    crank: float,
    coupler: float,
    rocker: float,
    ground: float,
    *,
    crank_deg: float = 0.0,
    mode: int = 1,
    coupler_point: Sequence[float] | None = None,
    origin: Sequence[float] = (0.0, 0.0),
    ground_deg: float = 0.0,
    name: str | None = None,
) -> Linkage:
    """A four-bar :class:`cyclomech.Linkage` drawn from its lengths.

    Parameters
    ----------
    crank, coupler, rocker, ground : float
        Link lengths a = AB, b = BC, c = DC, d = AD [m].
    crank_deg : float
        The crank's angle from the ground line A → D in the drawn pose [deg]
        (the solver's crank angle is the absolute one, ``ground_deg + crank_deg``).
    mode : {+1, -1}
        The assembly branch: +1 draws C on the left of the ray D → B.
    coupler_point : (u, v), optional
        A coupler point P [m] in the coupler's frame: u along B → C, v to its
        left; drawn as point ``"P"`` on the coupler (then the linkage's output).
        Where P is on the line BC (v = 0), a helper point ``"Q"`` of the coupler
        (B + BC turned 90°) is drawn too: it tells the solver which side P is on.
    origin : (x, y)
        The crank pivot A [m].
    ground_deg : float
        The ground line's angle from +x [deg].
    name : str, optional
        The linkage's name.

    Returns
    -------
    Linkage
        Points ``A`` (crank pivot), ``B`` (crank pin), ``C`` (rocker pin), ``D``
        (rocker pivot) and ``P`` if asked; driver (A, B); output P or C.

    Raises
    ------
    InputError
        A length not > 0, a mode not ±1, or a pose that cannot be assembled at
        ``crank_deg``.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> lk = cm.synthesis.four_bar_linkage(1, 3, 3.5, 4, crank_deg=90)
    >>> sol = lk.solve(np.radians([90.0, 180.0]))
    >>> round(float(np.hypot(*(sol["C"][1] - sol["D"][1]))), 12)
    3.5
    """
    a = positive("crank", crank, "[m]")
    b = positive("coupler", coupler, "[m]")
    c = positive("rocker", rocker, "[m]")
    d = positive("ground", ground, "[m]")
    th = math.radians(finite_number("crank_deg", crank_deg, "[deg]"))
    sigma = _mode(mode)
    (t4,) = _core.fourbar_output_angle(a, b, c, d, [th], sigma)
    if math.isnan(t4):
        raise InputError(
            f"the four-bar crank={a:g}, coupler={b:g}, rocker={c:g}, ground={d:g} [m] cannot "
            f"be assembled at crank_deg = {math.degrees(th):g}; pick a crank angle where "
            "|b − c| ≤ BD ≤ b + c"
        )
    local = {
        "A": (0.0, 0.0),
        "B": (a * math.cos(th), a * math.sin(th)),
        "C": (d + c * math.cos(t4), c * math.sin(t4)),
        "D": (d, 0.0),
    }
    if coupler_point is not None:
        local["P"] = _coupler_point(coupler_point, local["B"], local["C"])
    o = _xy("origin", origin)
    pts = _place(o, math.radians(finite_number("ground_deg", ground_deg, "[deg]")), local)
    body = _coupler_body(pts, "B", "C")
    return Linkage(
        pts,
        [("A", "B"), body, ("C", "D")],
        ["A", "D"],
        ("A", "B"),
        name=name,
        output="P" if "P" in pts else "C",
    )


def slider_crank_linkage(
    crank: float,
    rod: float,
    offset: float = 0.0,
    *,
    crank_deg: float = 0.0,
    mode: int = 1,
    coupler_point: Sequence[float] | None = None,
    origin: Sequence[float] = (0.0, 0.0),
    ground_deg: float = 0.0,
    name: str | None = None,
) -> Linkage:
    """An offset slider-crank :class:`cyclomech.Linkage` drawn from its lengths.

    Parameters
    ----------
    crank, rod : float
        Crank r = AB and rod l = BC [m].
    offset : float
        The slide's offset e [m]: the slider pin C moves on the line at distance
        e to the left of the slide direction through A.
    crank_deg : float
        The crank's angle from the slide direction in the drawn pose [deg].
    mode : {+1, -1}
        +1 draws the slider ahead of the crank pin along the slide direction.
    coupler_point : (u, v), optional
        A point P on the rod [m]: u along B → C, v to its left (with a helper
        point ``"Q"`` where v = 0, as in :func:`four_bar_linkage`).
    origin : (x, y)
        The crank pivot A [m].
    ground_deg : float
        The slide direction's angle from +x [deg].
    name : str, optional
        The linkage's name.

    Returns
    -------
    Linkage
        Points ``A``, ``B`` (crank pin), ``C`` (slider pin, on a ground guide),
        ``P`` if asked; driver (A, B); output C (or P).

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> lk = cm.synthesis.slider_crank_linkage(0.1, 0.35)
    >>> round(float(lk.solve([np.pi / 2])["C"][0, 0]), 12)   # √(0.35² − 0.1²)
    0.335410196625
    """
    r = positive("crank", crank, "[m]")
    ln = positive("rod", rod, "[m]")
    e = finite_number("offset", offset, "[m]")
    th = math.radians(finite_number("crank_deg", crank_deg, "[deg]"))
    sigma = _mode(mode)
    (x,) = _core.slider_crank_position(r, ln, e, [th], sigma)
    if math.isnan(x):
        raise InputError(
            f"the slider-crank crank={r:g}, rod={ln:g}, offset={e:g} [m] cannot be assembled "
            f"at crank_deg = {math.degrees(th):g}; pick a crank angle where "
            "|offset − crank·sin θ| ≤ rod"
        )
    local = {"A": (0.0, 0.0), "B": (r * math.cos(th), r * math.sin(th)), "C": (x, e)}
    if coupler_point is not None:
        local["P"] = _coupler_point(coupler_point, local["B"], local["C"])
    g = math.radians(finite_number("ground_deg", ground_deg, "[deg]"))
    pts = _place(_xy("origin", origin), g, local)
    body = _coupler_body(pts, "B", "C")
    return Linkage(
        pts,
        [("A", "B"), body],
        ["A"],
        ("A", "B"),
        sliders={"C": ("ground", (math.cos(g), math.sin(g)))},
        name=name,
        output="P" if "P" in pts else "C",
    )
