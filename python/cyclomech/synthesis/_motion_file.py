"""The ``motion`` scheme of a linkage's ``synthesize`` table: a four-bar whose
coupler takes three poses (:func:`~cyclomech.synthesis.motion_generation`), its
crank turning fully and counter-clockwise through them in order."""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from .._errors import InputError
from ..linkage import register_synthesizer
from ._fourbar import four_bar_margins
from ._linkage_file import (
    LinkageSynthesis,
    check_table,
    fmt,
    number,
    points,
    refused,
    warn_array_slips,
    whole,
)
from ._motion import MotionCandidate, motion_generation

__all__ = ["KEYS", "from_table"]

#: Every key of a ``scheme = "motion"`` table.
KEYS = frozenset(
    {
        "scheme",
        "pose_points_m",
        "pose_angles_deg",
        "circle_points_m",
        "grid_extent_m",
        "grid_points",
        "min_transmission_deg",
        "max_length_ratio",
    }
)


@functools.lru_cache(maxsize=32)
def _candidates(poses: Any, circle: Any, grid: Any) -> list[MotionCandidate]:
    # A machine file is parsed again by sweeps and checks: synthesise once. A scan
    # keeps every pair: the machine's filter (below) is not motion generation's.
    if circle is not None:
        return motion_generation(poses, circle_points=circle)
    return motion_generation(poses, grid=grid, keep=15**4)


def _turn_mu(c: MotionCandidate) -> float:
    ln = c.lengths
    return four_bar_margins(
        ln["crank"], ln["coupler"], ln["rocker"], ln["ground"]
    ).worst_transmission_deg


def _defects(c: MotionCandidate, min_mu: float, ratio: float = math.inf) -> list[str]:
    """Why a candidate cannot run in a machine, or breaks the table's limits
    (none: it can)."""
    out = []
    if c.margins.length_ratio > ratio:
        out.append(f"its length ratio is {c.margins.length_ratio:.3g} > {ratio:g}")
    if c.branch_defect:
        out.append("a pose is reached only on the other branch")
    if c.order_defect:
        out.append("the poses come out of order")
    if not c.margins.crank_turns:
        out.append(f"its crank does not turn fully ({c.margins.grashof})")
    elif c.direction != 1:
        out.append("its crank meets the poses in order turning clockwise")
    elif not _turn_mu(c) >= min_mu:
        out.append(f"its worst transmission angle over the turn is {fmt(_turn_mu(c), 3)}°")
    return out


def from_table(table: Mapping[str, Any], where: str) -> LinkageSynthesis:
    """The motion generator of a ``scheme = "motion"`` table.

    Parameters
    ----------
    table : mapping
        The table: ``scheme``, ``pose_points_m`` (three [x, y]),
        ``pose_angles_deg`` (three angles) and the optional keys of :data:`KEYS`.
    where : str
        The place messages name.

    Returns
    -------
    LinkageSynthesis
        Of the candidates (the two circle points given, or every pair of a
        ``grid_points`` × ``grid_points`` grid of circle points), those a machine
        can run — the crank turning fully and counter-clockwise through the poses
        in order on one branch — the one with the largest worst transmission
        angle over the turn (at least ``min_transmission_deg``).

    Raises
    ------
    InputError
        For an unknown or missing key, a malformed value, or no candidate a
        machine can run (naming ``where``).

    Examples
    --------
    >>> rec = from_table({"scheme": "motion", "pose_points_m": [[0, 0], [0.05, 0.02],
    ...                   [0.09, 0.06]], "pose_angles_deg": [0, 20, 45]}, "<doc>")
    >>> rec.linkage.output, rec.candidate.margins.crank_turns
    ('P', True)
    """
    check_table(table, KEYS, ("scheme", "pose_points_m", "pose_angles_deg"), where)
    try:
        xy = points(table, "pose_points_m", 2, "[m]", rows=3)
        (ang,) = points({"pose_angles_deg": [table["pose_angles_deg"]]}, "pose_angles_deg", 3,
                        "[deg]")  # fmt: skip
        if len(xy) != 3:
            raise InputError(
                f"pose_points_m has {len(xy)} points; three-position motion generation "
                "takes exactly 3 poses"
            )
        poses = tuple((x, y, a) for (x, y), a in zip(xy, ang, strict=True))
        circle = grid = None
        if "circle_points_m" in table:
            if "grid_extent_m" in table or "grid_points" in table:
                raise InputError("give circle_points_m, or the grid's keys, not both")
            circle = points(table, "circle_points_m", 2, "[m]", rows=2)
            if len(circle) != 2:
                raise InputError(
                    f"circle_points_m must be two [u, v] (the crank's, the rocker's); got "
                    f"{len(circle)}"
                )
        else:
            spread = max(math.hypot(x - xy[0][0], y - xy[0][1]) for x, y in xy)
            extent = number(table, "grid_extent_m", max(spread, 1e-3), "[m]", low=0.0,
                            strict=True)  # fmt: skip
            n = whole(table, "grid_points", 7, 2, "points per side")
            if n > 15:
                raise InputError(f"grid_points = {n} must be at most 15")
            grid = (extent, n)
        min_mu = number(table, "min_transmission_deg", 0.0, "[deg]", low=0.0, below=90.0)
        ratio = number(table, "max_length_ratio", math.inf, "", low=1.0)
        assert min_mu is not None and ratio is not None
        warn_array_slips(table, where)
        found = _candidates(poses, circle, grid)
    except InputError as e:
        raise refused(where, e) from None
    usable = sorted(
        (c for c in found if not _defects(c, min_mu, ratio)), key=lambda c: -_turn_mu(c)
    )
    if not usable:
        why = "; ".join(", ".join(_defects(c, min_mu, ratio)) for c in found[:3])
        raise InputError(
            f"{where}: none of the {len(found)} four-bar(s) through these poses can run in a "
            "machine (the crank turning fully, counter-clockwise, through the poses in order "
            f"on one branch, transmission ≥ {min_mu:g}°, length ratio ≤ {ratio:g}); the "
            f"first ones: {why}; try other "
            "circle_points_m, a wider grid_extent_m, or poses in the other order"
        )
    return _record(usable[0], len(found), len(usable), min_mu)  # ratio in the margins row


def _record(c: MotionCandidate, n_found: int, n_ok: int, min_mu: float) -> LinkageSynthesis:
    ln, m = c.lengths, c.margins
    (a0, b0), (ua, ub) = c.centre_points, c.circle_points
    mu = _turn_mu(c)
    report = (
        ("synthesised scheme", "motion (a four-bar motion generator, three poses)"),
        (
            "synthesis: asked",
            "poses " + ", ".join(f"({x:g}, {y:g}) m at {t:g}°" for x, y, t in c.poses),
        ),
        (
            "synthesis: what it chose and why",
            f"of {n_found} candidate(s), {n_ok} a machine can run (crank turning fully, "
            "counter-clockwise through the poses in order on one branch); the one with the "
            f"largest worst transmission angle over the turn (≥ {min_mu:g}°)",
        ),
        (
            "synthesised lengths [m]",
            ", ".join(f"{k} {ln[k]:.5g}" for k in ("crank", "coupler", "rocker", "ground")),
        ),
        (
            "synthesised pivots [m]",
            f"A0 ({a0[0]:.5g}, {a0[1]:.5g}), B0 ({b0[0]:.5g}, {b0[1]:.5g}); circle points "
            f"A ({ua[0]:.5g}, {ua[1]:.5g}), B ({ub[0]:.5g}, {ub[1]:.5g}) in the coupler frame",
        ),
        (
            "synthesis: crank angle at each pose [deg]",
            ", ".join(f"{a % 360:.2f}" for a in c.crank_angles_deg),
        ),
        (
            "synthesis margins",
            f"{m.grashof}, transmission {fmt(m.transmission_min_deg, 3)}°–"
            f"{fmt(m.transmission_max_deg, 3)}° over the working arc, worst {fmt(mu, 3)}° "
            f"over the turn, length ratio {m.length_ratio:.3g}",
        ),
    )
    entry = {
        "poses": [list(p) for p in c.poses],
        "lengths_m": dict(ln),
        "centre_points_m": [list(a0), list(b0)],
        "circle_points_m": [list(ua), list(ub)],
        "crank_at_poses_deg": [a % 360.0 for a in c.crank_angles_deg],
        "grashof": m.grashof,
        "transmission_arc_deg": [m.transmission_min_deg, m.transmission_max_deg],
        "worst_transmission_turn_deg": mu,
        "length_ratio": m.length_ratio,
    }
    dims = (
        *((k, v, "m") for k, v in ln.items()),
        ("A0_x", a0[0], "m"),
        ("A0_y", a0[1], "m"),
        ("B0_x", b0[0], "m"),
        ("B0_y", b0[1], "m"),
        ("A_u", ua[0], "m"),
        ("A_v", ua[1], "m"),
        ("B_u", ub[0], "m"),
        ("B_v", ub[1], "m"),
    )
    return LinkageSynthesis(
        "motion", c.linkage(name="motion generator"), c, report, entry, dims, _draw
    )


def _draw(rec: LinkageSynthesis, name: str) -> list[tuple[Any, str, str]]:
    """The linkage in the first pose, P's path, and the three poses as arrows."""
    from ..linkage.plot import plot_linkage

    c: MotionCandidate = rec.candidate
    lk = rec.linkage
    turn = math.radians(c.crank_angles_deg[0]) + np.linspace(0.0, 2.0 * math.pi, 721)
    ax = plot_linkage(lk, lk.solve(turn), 0, trace=["P"],
                      title=f"{name}: the synthesised motion generator")  # fmt: skip
    p = np.array(c.poses)
    size = 0.15 * float(max(np.ptp(p[:, :2], axis=0).max(), c.lengths["coupler"]))
    t = np.radians(p[:, 2])
    h = ax.quiver(p[:, 0], p[:, 1], size * np.cos(t), size * np.sin(t), color="C3",
                  angles="xy", scale_units="xy", scale=1.0, width=0.006, label="poses",
                  gid="poses")  # fmt: skip
    for i, (x, y, _) in enumerate(c.poses):
        ax.annotate(f"pose {i + 1}", (x, y), xytext=(6, -12), textcoords="offset points",
                    fontsize=8, color="C3")  # fmt: skip
    ax.legend(handles=[h], fontsize=8, loc="best")
    return [
        (
            ax.figure,
            f"{name}_synthesis",
            "The synthesised four-bar in its first pose, the path of its coupler point P "
            "over the turn, and the three poses (point and angle) it takes.",
        )
    ]


register_synthesizer("motion", from_table)
