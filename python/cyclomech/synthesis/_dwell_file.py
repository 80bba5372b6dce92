"""The ``dwell_sixbar`` scheme of a linkage's ``synthesize`` table: a Stephenson
III six-bar whose output rocker dwells while the crank turns a given angle
(:func:`~cyclomech.synthesis.dwell_sixbar`)."""

from __future__ import annotations

import functools
from collections.abc import Mapping
from typing import Any

import numpy as np

from .._errors import InputError
from ..linkage import register_synthesizer
from ._dwell import DwellCandidate, dwell_sixbar
from ._linkage_file import LinkageSynthesis, check_table, fmt, number, refused, warn_array_slips
from ._linkage_file import whole as _whole

__all__ = ["KEYS", "from_table", "output_angle_deg"]

#: Every key of a ``scheme = "dwell_sixbar"`` table.
KEYS = frozenset(
    {
        "scheme",
        "dwell_deg",
        "swing_deg",
        "ground_m",
        "min_transmission_deg",
        "max_length_ratio",
        "max_residual_deg",
        "seed",
        "popsize",
        "maxiter",
    }
)


@functools.lru_cache(maxsize=16)
def _candidates(req: tuple[float, float, float, float, float, int, int, int]) -> Any:
    # A machine file is parsed again by sweeps and checks: synthesise once.
    dwell, swing, ground, mu, ratio, seed, popsize, maxiter = req
    return dwell_sixbar(
        dwell,
        swing,
        ground_m=ground,
        min_transmission_deg=mu,
        max_length_ratio=ratio,
        seed=seed,
        popsize=popsize,
        maxiter=maxiter,
    )


def output_angle_deg(c: DwellCandidate, crank_deg: Any) -> np.ndarray:
    """The output rocker's angle F → E [deg] (unwrapped) at crank angles [deg],
    solved on the candidate's own linkage.

    Examples
    --------
    >>> from cyclomech.synthesis._dwell_file import from_table
    >>> rec = from_table({"scheme": "dwell_sixbar", "dwell_deg": 60, "swing_deg": 40,
    ...                   "maxiter": 10}, "<doc>")
    >>> psi = output_angle_deg(rec.candidate, [i / 10 for i in range(3600)])
    >>> round(float(psi.max() - psi.min()), 3)      # the swing, sampled every 0.1°
    40.0
    """
    lk = c.linkage()
    sol = lk.solve(np.radians(np.asarray(crank_deg, dtype=float)), points=["E", "F"])
    d = sol["E"] - sol["F"]
    return np.degrees(np.unwrap(np.arctan2(d[:, 1], d[:, 0])))


def from_table(table: Mapping[str, Any], where: str) -> LinkageSynthesis:
    """The six-bar dwell linkage of a ``scheme = "dwell_sixbar"`` table.

    Parameters
    ----------
    table : mapping
        The table: ``scheme``, ``dwell_deg``, ``swing_deg`` and the optional keys
        of :data:`KEYS` (defaults :func:`~cyclomech.synthesis.dwell_sixbar`'s,
        ``max_residual_deg`` none).
    where : str
        The place messages name.

    Returns
    -------
    LinkageSynthesis
        The best candidate: feasible (both loops' transmission angles at the
        limit or above, the swing met, the length ratio within its limit), the
        smallest residual motion over the dwell.

    Raises
    ------
    InputError
        For an unknown or missing key, a malformed value, no feasible candidate,
        or a best residual above ``max_residual_deg`` (naming ``where``).

    Examples
    --------
    >>> rec = from_table({"scheme": "dwell_sixbar", "dwell_deg": 60, "swing_deg": 40,
    ...                   "maxiter": 10}, "<doc>")
    >>> rec.linkage.output, rec.candidate.feasible
    ('E', True)
    """
    check_table(table, KEYS, ("scheme", "dwell_deg", "swing_deg"), where)
    try:
        req = (
            number(table, "dwell_deg", None, "[deg]"),
            number(table, "swing_deg", None, "[deg]"),
            number(table, "ground_m", 1.0, "[m]", low=0.0, strict=True),
            number(table, "min_transmission_deg", 30.0, "[deg]", low=0.0),
            number(table, "max_length_ratio", 10.0, "", low=1.0),
            _whole(table, "seed", 0, 0, "seed"),
            _whole(table, "popsize", 20, 1, "population multiplier"),
            _whole(table, "maxiter", 30, 1, "generations"),
        )
        limit = number(table, "max_residual_deg", None, "[deg]", low=0.0, strict=True)
        warn_array_slips(table, where)
        found = _candidates(req)
    except InputError as e:
        raise refused(where, e) from None
    best: DwellCandidate = found[0]
    if not best.feasible:
        raise InputError(
            f"{where}: no feasible six-bar found for dwell_deg = {req[0]:g}, swing_deg = "
            f"{req[1]:g}: the best of {len(found)} has swing {best.swing_deg:.4g}°, "
            f"transmission angles {_mu(best)}, length ratio {best.length_ratio:.3g} "
            f"(max_length_ratio = {req[4]:g}); try more generations (maxiter), another seed, "
            "a lower min_transmission_deg, or a smaller dwell or swing"
        )
    if limit is not None and best.residual_deg > limit:
        raise InputError(
            f"{where}: the best six-bar's output moves {best.residual_deg:.3g}° over the "
            f"dwell, above max_residual_deg = {limit:g}; try more generations (maxiter), "
            "another seed, or a shorter dwell"
        )
    return _record(best, len(found), req, limit)


def _mu(c: DwellCandidate) -> str:
    m = c.margins
    return (
        f"{fmt(m.transmission_min_deg, 3)}°–{fmt(m.transmission_max_deg, 3)}° (four-bar), "
        f"{fmt(c.output_transmission_min_deg, 3)}°–{fmt(c.output_transmission_max_deg, 3)}° "
        "(output dyad)"
    )


def _record(
    c: DwellCandidate, n_found: int, req: tuple[Any, ...], limit: float | None
) -> LinkageSynthesis:
    ln = c.lengths
    lo, hi = c.dwell_range_deg
    (fx, fy), (ex, ey) = c.output_pivot, c.dwell_joint
    report = (
        ("synthesised scheme", "dwell_sixbar (a Stephenson III six-bar dwell linkage)"),
        (
            "synthesis: asked",
            f"dwell {req[0]:g}° of crank, swing {req[1]:g}°, transmission ≥ {req[3]:g}° in "
            f"both loops, length ratio ≤ {req[4]:g}"
            + ("" if limit is None else f", residual ≤ {limit:g}°"),
        ),
        (
            "synthesis: what it chose and why",
            f"of {n_found} distinct designs of the last generation (seed {req[5]}), the "
            "feasible one whose output moves least over the dwell",
        ),
        ("synthesised lengths [m]", ", ".join(f"{k} {v:.5g}" for k, v in ln.items())),
        (
            "synthesised points [m]",
            f"A (0, 0), D ({ln['ground']:.5g}, 0), F ({fx:.5g}, {fy:.5g}); E dwells at "
            f"({ex:.5g}, {ey:.5g}); coupler point P (u, v) = ({c.coupler_point[0]:.5g}, "
            f"{c.coupler_point[1]:.5g}) on B → C",
        ),
        ("synthesis: the dwell [crank deg]", f"{lo % 360:.4g} to {(lo % 360) + (hi - lo):.4g}"),
        (
            "synthesis margins",
            f"{c.margins.grashof}, transmission {_mu(c)}, residual {c.residual_deg:.3g}° over "
            f"the dwell, swing {c.swing_deg:.6g}°, arc deviation {c.arc_deviation:.3g} m, "
            f"length ratio {c.length_ratio:.3g}",
        ),
    )
    entry = {
        "lengths_m": dict(ln),
        "coupler_point_m": list(c.coupler_point),
        "output_pivot_m": list(c.output_pivot),
        "dwell_joint_m": list(c.dwell_joint),
        "dwell_deg": c.dwell_deg,
        "dwell_start_deg": lo % 360.0,
        "dwell_mid_deg": c.dwell_mid_deg % 360.0,
        "residual_deg": c.residual_deg,
        "swing_deg": c.swing_deg,
        "arc_deviation_m": c.arc_deviation,
        "grashof": c.margins.grashof,
        "transmission_deg": [c.margins.transmission_min_deg, c.margins.transmission_max_deg],
        "output_transmission_deg": [
            c.output_transmission_min_deg,
            c.output_transmission_max_deg,
        ],
        "length_ratio": c.length_ratio,
        "feasible": c.feasible,
    }
    dims = (
        *((k, v, "m") for k, v in ln.items()),
        ("coupler_point_u", c.coupler_point[0], "m"),
        ("coupler_point_v", c.coupler_point[1], "m"),
        ("output_pivot_x", fx, "m"),
        ("output_pivot_y", fy, "m"),
        ("dwell_start", lo % 360.0, "deg"),
        ("dwell", c.dwell_deg, "deg"),
    )
    return LinkageSynthesis(
        "dwell_sixbar", c.linkage(name="six-bar dwell linkage"), c, report, entry, dims, _draw
    )


def _draw(rec: LinkageSynthesis, name: str) -> list[tuple[Any, str, str]]:
    """The output's angle over the turn, the dwell shaded, and its residual motion."""
    from .._plotting import angle_axis, pyplot

    c: DwellCandidate = rec.candidate
    lo, hi = c.dwell_range_deg
    start = lo % 360.0
    theta = np.linspace(0.0, 360.0, 1441)
    psi = output_angle_deg(c, theta)
    inside = np.linspace(lo, hi, 361)
    still = output_angle_deg(c, inside)
    rest = float(np.mean(still))
    plt = pyplot()
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7.5, 5.6), layout="constrained")
    top.plot(theta, psi - rest, lw=1.4, gid="output")
    for a in (start, start - 360.0):
        top.axvspan(max(a, 0.0), min(a + c.dwell_deg, 360.0), color="C2", alpha=0.15, lw=0)
    top.set_ylabel("output angle from the dwell  [deg]")
    top.set_title(f"{name}: the six-bar's output rocker over the turn (dwell shaded)")
    angle_axis(top, 360.0, "crank angle  [deg]")
    bottom.plot(inside - lo, 60.0 * (still - rest), lw=1.2, color="C2", gid="residual")
    bottom.axhline(0.0, color="0.6", lw=0.8)
    bottom.set_xlabel(f"crank angle from the dwell's start ({start:.1f}°)  [deg]")
    bottom.set_ylabel("output over the dwell  [arcmin]")
    return [
        (
            fig,
            f"{name}_synthesis",
            f"The synthesised six-bar's output angle over the crank turn, the dwell of "
            f"{c.dwell_deg:g}° shaded; below, its residual motion over the dwell "
            f"({c.residual_deg:.3g}° peak to peak).",
        )
    ]


register_synthesizer("dwell_sixbar", from_table)
