"""The ``function`` scheme of a linkage's ``synthesize`` table: a four-bar function
generator (:func:`~cyclomech.synthesis.function_generation`) whose output rocker's
angle ψ follows the crank angle φ, for a machine that turns the crank fully."""

from __future__ import annotations

import functools
from collections.abc import Mapping
from typing import Any

import numpy as np

from .._errors import InputError
from ..linkage import register_synthesizer
from ._fourbar import four_bar_margins
from ._function import FunctionCandidate, function_generation
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

__all__ = ["KEYS", "from_table"]

#: Every key of a ``scheme = "function"`` table.
KEYS = frozenset(
    {
        "scheme",
        "precision_points_deg",
        "function_deg",
        "input_range_deg",
        "output_range_deg",
        "points",
        "spacing",
        "ground_m",
        "offsets_deg",
        "min_transmission_deg",
    }
)


@functools.lru_cache(maxsize=32)
def _candidates(
    pairs: Any, function: Any, x_range: Any, n: int, spacing: str, ground: float, offsets: Any
) -> list[FunctionCandidate]:
    # A machine file is parsed again by sweeps and checks: synthesise once.
    return function_generation(
        None if pairs is None else [list(p) for p in pairs],
        function=None if function is None else [list(p) for p in function],
        x_range_deg=x_range,
        n=n,
        spacing=spacing,
        ground_m=ground,
        offsets=None if offsets is None else [list(o) for o in offsets],
    )


def _relation(table: Mapping[str, Any]) -> tuple[Any, Any, Any]:
    """(precision points, tabulated function, input range) from the table's one
    way of giving the relation."""
    given = [k for k in ("precision_points_deg", "function_deg", "output_range_deg") if k in table]
    if len(given) != 1:
        raise InputError(
            "give the relation ψ(φ) one way: precision_points_deg = [[φ, ψ], …] (3 or more), "
            "function_deg = [[φ, ψ], …] (a table, interpolated linearly), or input_range_deg "
            "with output_range_deg (ψ linear in φ); got "
            + (", ".join(given) if given else "none of them")
        )
    x_range = None
    if "input_range_deg" in table:
        (x_range,) = points({"input_range_deg": [table["input_range_deg"]]}, "input_range_deg", 2,
                            "[deg]")  # fmt: skip
        if not x_range[0] < x_range[1]:
            raise InputError(f"input_range_deg = {list(x_range)} must be [lo, hi], lo < hi [deg]")
    if given == ["precision_points_deg"]:
        for k in ("points", "spacing"):
            if k in table:
                raise InputError(
                    f"{k} places precision points on function_deg or the ranges; with "
                    "precision_points_deg they are given: drop it"
                )
        return points(table, "precision_points_deg", 2, "[deg]", rows=3), None, x_range
    if given == ["function_deg"]:
        return None, points(table, "function_deg", 2, "[deg]", rows=2), x_range
    if x_range is None:
        raise InputError("output_range_deg = [ψ at lo, ψ at hi] needs input_range_deg = [lo, hi]")
    (y,) = points({"output_range_deg": [table["output_range_deg"]]}, "output_range_deg", 2,
                  "[deg]")  # fmt: skip
    return None, ((x_range[0], y[0]), (x_range[1], y[1])), x_range


def _given(table: Mapping[str, Any]) -> str:
    """The key(s) the relation came from, for messages."""
    if "output_range_deg" in table:
        return "input_range_deg and output_range_deg"
    return "precision_points_deg" if "precision_points_deg" in table else "function_deg"


def _full_turn(c: FunctionCandidate) -> Any:
    ln = c.lengths
    return four_bar_margins(ln["crank"], ln["coupler"], ln["rocker"], ln["ground"])


def _defects(c: FunctionCandidate, min_mu: float) -> list[str]:
    """Why a candidate cannot run in a machine (none: it can)."""
    out = []
    if c.branch_defect:
        out.append("a precision point is reached only on the other branch")
    if not c.margins.branch_ok:
        out.append("the input range is not held on one branch (it folds)")
    if not c.margins.crank_turns:
        out.append(f"its crank does not turn fully ({c.margins.grashof})")
    mu = _full_turn(c).worst_transmission_deg
    if c.margins.crank_turns and not mu >= min_mu:
        out.append(f"its worst transmission angle over the turn is {fmt(mu, 3)}° < {min_mu:g}°")
    return out


def from_table(table: Mapping[str, Any], where: str) -> LinkageSynthesis:
    """The four-bar function generator of a ``scheme = "function"`` table.

    Parameters
    ----------
    table : mapping
        The table: ``scheme``, the relation (``precision_points_deg``, or
        ``function_deg``, or ``input_range_deg`` with ``output_range_deg``) and the
        optional keys of :data:`KEYS`.
    where : str
        The place messages name.

    Returns
    -------
    LinkageSynthesis
        The chosen four-bar: the best candidate (function generation's ranking)
        whose crank turns fully, meeting every precision point on one branch, with
        its worst transmission angle over the turn at least
        ``min_transmission_deg``.

    Raises
    ------
    InputError
        For an unknown or missing key, a malformed value, or no candidate a
        machine can run (naming ``where`` and what each candidate missed).

    Examples
    --------
    >>> rec = from_table({"scheme": "function", "ground_m": 0.2,
    ...                   "precision_points_deg": [[30, 80], [60, 90], [90, 100]]}, "<doc>")
    >>> rec.candidate.margins.grashof
    'crank-rocker'
    """
    check_table(table, KEYS, ("scheme",), where)
    try:
        pairs, function, x_range = _relation(table)
        ground = number(table, "ground_m", 1.0, "[m]", low=0.0, strict=True)
        min_mu = number(table, "min_transmission_deg", 0.0, "[deg]", low=0.0, below=90.0)
        spacing = table.get("spacing", "chebyshev")
        if spacing not in ("chebyshev", "uniform"):
            raise InputError(f"spacing = {spacing!r} must be 'chebyshev' or 'uniform'")
        offsets = points(table, "offsets_deg", 2, "[deg]") if "offsets_deg" in table else None
        n = whole(table, "points", 3, 3, "precision points")
        warn_array_slips(table, where)
        assert ground is not None and min_mu is not None
        found = _candidates(pairs, function, x_range, n, spacing, ground, offsets)
    except InputError as e:
        raise refused(where, e) from None
    usable = [c for c in found if not _defects(c, min_mu)]
    if not usable:
        why = "; ".join(f"offset {c.offset}: {', '.join(_defects(c, min_mu))}" for c in found[:4])
        raise InputError(
            f"{where}: no four-bar a machine can run meets these precision points (of "
            f"{_given(table)}; its "
            f"crank must turn fully, every point on one branch): {why}; try other "
            "precision points, a wider output range, or offsets_deg = [[Δφ, Δψ], …] "
            "(other origins of the scales)"
        )
    rng = x_range or (function or pairs)
    lo, hi = (rng[0], rng[1]) if x_range else (min(p[0] for p in rng), max(p[0] for p in rng))
    best = usable[0]
    how = (
        "the precision points given"
        if pairs is not None
        else f"{n} {spacing} points of "
        + ("function_deg" if "function_deg" in table else "ψ linear over the ranges")
    )
    span = (lo + best.offset[0], hi + best.offset[0])
    return _record(best, len(found), span, function, min_mu, how)


def _record(
    c: FunctionCandidate,
    n_found: int,
    span: tuple[float, float],
    function: Any,
    min_mu: float,
    how: str,
) -> LinkageSynthesis:
    ln, m, full = c.lengths, c.margins, _full_turn(c)
    x = [p for p, _ in c.precision]
    miss = float(np.max(np.abs(c.generated(x) - np.array([q for _, q in c.precision]))))
    flip = " + 180° (the crank is drawn flipped)" if c.crank_flipped else ""
    out_flip = " − 180°" if c.output_flipped else ""
    lo, hi = span
    asked = ", ".join(f"({p:g}°, {q:g}°)" for p, q in c.precision)
    report = (
        ("synthesised scheme", "function (a four-bar function generator)"),
        ("synthesis: asked", f"ψ(φ) through {asked} ({how})"),
        (
            "synthesis: what it chose and why",
            f"of {n_found} candidate(s), the first in function generation's ranking (clean, "
            "then the smallest structural error) whose crank turns fully and holds every "
            f"precision point on one branch, worst transmission over the turn ≥ {min_mu:g}°",
        ),
        (
            "synthesised lengths [m]",
            ", ".join(f"{k} {ln[k]:.5g}" for k in ("crank", "coupler", "rocker", "ground")),
        ),
        (
            "synthesis: input and output angles",
            f"the linkage's crank angle (A → B from +x) is φ{flip}; ψ is the angle of D → C"
            f"{out_flip}",
        ),
        (
            "synthesis margins",
            f"{m.grashof}, transmission {fmt(m.transmission_min_deg, 3)}°–"
            f"{fmt(m.transmission_max_deg, 3)}° over φ {lo:g}°–{hi:g}° and "
            f"{fmt(full.transmission_min_deg, 3)}°–{fmt(full.transmission_max_deg, 3)}° over "
            f"the turn, structural error {fmt(c.structural_error, 3)}° at φ = "
            f"{c.structural_error_at_deg:g}°, precision points met to {miss:.2g}°",
        ),
    )
    entry = {
        "mechanism": "four-bar",
        "precision_points_deg": [list(p) for p in c.precision],
        "input_range_deg": [lo, hi],
        "lengths_m": dict(ln),
        "crank_flipped": c.crank_flipped,
        "output_flipped": c.output_flipped,
        "branch": c.mode,
        "grashof": m.grashof,
        "transmission_range_deg": [m.transmission_min_deg, m.transmission_max_deg],
        "transmission_turn_deg": [full.transmission_min_deg, full.transmission_max_deg],
        "structural_error_deg": c.structural_error,
        "structural_error_at_deg": c.structural_error_at_deg,
        "precision_error_deg": miss,
        "length_ratio": m.length_ratio,
        **({} if function is None else {"function_deg": [list(p) for p in function]}),
    }
    dims = tuple((k, v, "m") for k, v in ln.items())
    return LinkageSynthesis(
        "function",
        c.linkage(name="function generator"),
        c,
        report,
        entry,
        (*dims, ("crank_offset", 180.0 if c.crank_flipped else 0.0, "deg")),
        _draw,
    )


def _draw(rec: LinkageSynthesis, name: str) -> list[tuple[Any, str, str]]:
    """The generated output over the input range with the precision points, and
    with a wanted relation its difference from it."""
    from .._plotting import pyplot

    function = rec.entry.get("function_deg")
    c: FunctionCandidate = rec.candidate
    x = np.array([p for p, _ in c.precision])
    y = np.array([q for _, q in c.precision])
    lo, hi = rec.entry["input_range_deg"]
    grid = np.linspace(min(lo, x.min()), max(hi, x.max()), 241)
    plt = pyplot()
    rows = 2 if function is not None else 1
    fig, axes = plt.subplots(rows, 1, figsize=(7.5, 2.8 * rows + 0.6), sharex=True,
                             layout="constrained", squeeze=False)  # fmt: skip
    top = axes[0, 0]
    top.plot(grid, c.generated(grid), lw=1.4, label="generated ψ", gid="generated")
    top.plot(x, y, "o", ms=6, mfc="none", label="precision points", gid="precision")
    if function is not None:
        f = np.array(function)
        wanted = np.interp(grid, f[:, 0] + c.offset[0], f[:, 1] + c.offset[1])
        top.plot(grid, wanted, "--", lw=1.0, color="0.4", label="wanted ψ", gid="wanted")
        err = axes[1, 0]
        err.plot(grid, c.generated(grid) - wanted, lw=1.2, gid="error")
        err.axhline(0.0, color="0.6", lw=0.8)
        err.set_ylabel("generated − wanted  [deg]")
    top.set_ylabel("output angle ψ  [deg]")
    top.set_title(f"{name}: the synthesised function generator")
    top.legend(fontsize=8)
    axes[-1, 0].set_xlabel("input angle φ  [deg]")
    return [
        (
            fig,
            f"{name}_synthesis",
            "The output angle the synthesised four-bar generates over the input angle, "
            "through the precision points (and its difference from the wanted relation).",
        )
    ]


register_synthesizer("function", from_table)
