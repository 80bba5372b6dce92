"""The ``path`` scheme of a linkage's ``synthesize`` table: a four-bar or
slider-crank whose coupler point passes target points
(:func:`~cyclomech.synthesis.path_generation`), its crank turning fully."""

from __future__ import annotations

import functools
import math
import re
from collections.abc import Mapping
from typing import Any

import numpy as np

from .._arrays import flag
from .._errors import InfeasibleError, InputError
from ..linkage import register_synthesizer
from ._linkage_file import (
    LinkageSynthesis,
    check_table,
    fmt,
    number,
    points,
    warn_array_slips,
    whole,
)
from ._path import PathCandidate, path_generation

__all__ = ["KEYS", "from_table"]

#: Every key of a ``scheme = "path"`` table.
KEYS = frozenset(
    {
        "scheme",
        "targets_m",
        "timing_deg",
        "mechanism",
        "min_transmission_deg",
        "max_length_ratio",
        "pivot_box_m",
        "max_error_m",
        "seed",
        "popsize",
        "maxiter",
        "polish",
        "bounds",
    }
)
_MECHANISMS = ("four_bar", "slider_crank")
#: The keys of ``bounds`` → path generation's variables (a slider-crank's r1 is its
#: guide's offset, a four-bar's its ground link).
BOUND_KEYS = {
    "x0_m": "x0",
    "y0_m": "y0",
    "theta0_deg": "theta0",
    "ground_m": "r1",
    "offset_m": "r1",
    "crank_m": "r2",
    "coupler_m": "r3",
    "rocker_m": "r4",
    "u_m": "u",
    "v_m": "v",
    "phi1_deg": "phi1",
}


def _bounds(table: Mapping[str, Any], kind: str, timed: bool) -> Any:
    """The ``bounds`` table as sorted ((variable, (lo, hi)), …), None when absent."""
    if "bounds" not in table:
        return None
    b = table["bounds"]
    allowed = set(BOUND_KEYS) - {"offset_m" if kind == "four_bar" else "ground_m"}
    allowed -= {"rocker_m"} if kind == "slider_crank" else set()
    allowed -= set() if timed else {"phi1_deg"}
    check_table(b, frozenset(allowed), (), "bounds")
    out = []
    for k in sorted(b):
        (lo, hi) = points({k: [b[k]]}, k, 2, "[deg]" if k.endswith("_deg") else "[m]")[0]
        if not lo < hi:
            raise InputError(f"bounds.{k} = {[lo, hi]} must be [lo, hi] with lo < hi")
        out.append((BOUND_KEYS[k], (lo, hi)))
    return tuple(out)


@functools.lru_cache(maxsize=16)
def _candidates(
    targets: Any, timing: Any, kind: str, mu: float, ratio: float, box: Any, run: Any
) -> list[PathCandidate]:
    # A machine file is parsed again by sweeps and checks: synthesise once.
    seed, popsize, maxiter, polish, bounds = run
    return path_generation(
        [list(p) for p in targets],
        None if timing is None else list(timing),
        kind=kind,
        bounds=None if bounds is None else {k: list(v) for k, v in bounds},
        full_turn=True,
        min_transmission_deg=mu,
        max_ratio=ratio,
        pivot_box=None if box is None else list(box),
        seed=seed,
        popsize=popsize,
        maxiter=maxiter,
        polish=polish,
    )


def _row(table: Mapping[str, Any], key: str, n: int, unit: str) -> tuple[float, ...] | None:
    """A 1-D array key of ``n`` numbers (None when absent)."""
    if key not in table:
        return None
    (r,) = points({key: [table[key]]}, key, n, unit)
    return r


def from_table(table: Mapping[str, Any], where: str) -> LinkageSynthesis:
    """The path generator of a ``scheme = "path"`` table.

    Parameters
    ----------
    table : mapping
        The table: ``scheme``, ``targets_m`` and the optional keys of :data:`KEYS`
        (defaults :func:`~cyclomech.synthesis.path_generation`'s, but ``seed`` 0, so
        that the file gives the same linkage each time it is read).
    where : str
        The place messages name.

    Returns
    -------
    LinkageSynthesis
        The feasible candidate (its crank turning fully, the constraints held)
        nearest the targets.

    Raises
    ------
    InputError
        For an unknown or missing key, a malformed value, no feasible candidate,
        or a best error above ``max_error_m`` (naming ``where``).

    Examples
    --------
    >>> rec = from_table({"scheme": "path", "targets_m": [[0.1, 0.2], [0.25, 0.3],
    ...                   [0.35, 0.2], [0.2, 0.05]], "maxiter": 60}, "<doc>")
    >>> rec.linkage.output, rec.candidate.max < 1e-6
    ('P', True)
    """
    check_table(table, KEYS, ("scheme", "targets_m"), where)
    try:
        targets = points(table, "targets_m", 2, "[m]", rows=3)
        timing = None
        if "timing_deg" in table:
            timing = _row(table, "timing_deg", len(targets), "[deg]")
        kind = table.get("mechanism", "four_bar")
        if kind not in _MECHANISMS:
            raise InputError(f"mechanism = {kind!r} must be one of {', '.join(_MECHANISMS)}")
        mu = number(table, "min_transmission_deg", 0.0, "[deg]", low=0.0, below=90.0)
        ratio = number(table, "max_length_ratio", math.inf, "", low=1.0)
        box = _row(table, "pivot_box_m", 4, "[m]")
        limit = number(table, "max_error_m", None, "[m]", low=0.0, strict=True)
        run = (
            whole(table, "seed", 0, 0, "seed"),
            whole(table, "popsize", 15, 5, "population multiplier"),
            whole(table, "maxiter", 1000, 1, "generations"),
            flag("polish", table.get("polish", True)),
            _bounds(table, kind, timing is not None),
        )
        warn_array_slips(table, where)
        warn_array_slips(table.get("bounds", {}), f"{where}.bounds")
        found = _candidates(targets, timing, kind, mu, ratio, box, run)
    except (InputError, InfeasibleError) as e:
        # path_generation's own names for the file's keys.
        msg = re.sub(r"\bpoints\[", "targets_m[", str(e)).replace("max_ratio", "max_length_ratio")
        other = "ground_m" if table.get("mechanism") == "slider_crank" else "offset_m"
        for key, var in BOUND_KEYS.items():
            if key != other:
                msg = msg.replace(f"bounds[{var!r}]", f"bounds.{key}")
        raise InputError(f"{where}: {msg.replace(' or widen the bounds', '')}") from None
    best = found[0]
    if limit is not None and best.max > limit:
        raise InputError(
            f"{where}: the best {kind} passes the targets within {best.max:.3g} m, above "
            f"max_error_m = {limit:g}; try more generations (maxiter), another seed, "
            "fewer targets, or relax the constraints"
        )
    return _record(best, len(found), targets, timing, (mu, ratio, box, limit))


def _record(
    c: PathCandidate, n_found: int, targets: Any, timing: Any, cons: tuple[Any, ...]
) -> LinkageSynthesis:
    mu, ratio, box, limit = cons
    p, m = c.params, c.margins
    angles = [math.degrees(a) % 360.0 for a in c.angles]
    ln = {k: p[k] for k in ("r1", "r2", "r3", "r4") if k in p}
    names = {"r1": "ground" if c.kind == "four_bar" else "offset", "r2": "crank",
             "r3": "coupler", "r4": "rocker"}  # fmt: skip
    asked = [f"{len(targets)} targets"]
    asked += [] if timing is None else [f"at crank angles {', '.join(f'{t:g}' for t in timing)}°"]
    asked += [f"transmission ≥ {mu:g}°"] if mu else []
    asked += [f"length ratio ≤ {ratio:g}"] if math.isfinite(ratio) else []
    asked += [] if box is None else [f"ground pivots in x {box[0]:g}…{box[1]:g}, y {box[2]:g}…"
                                     f"{box[3]:g} m"]  # fmt: skip
    asked += [] if limit is None else [f"error ≤ {limit:g} m"]
    report = (
        ("synthesised scheme", f"path (a {c.kind.replace('_', '-')} path generator)"),
        ("synthesis: asked", ", ".join(asked)),
        (
            "synthesis: what it chose and why",
            f"of {n_found} distinct feasible candidate(s) (its crank turning fully, the "
            "constraints held), the one nearest the targets",
        ),
        (
            "synthesised dimensions [m]",
            ", ".join(f"{names[k]} {v:.5g}" for k, v in ln.items())
            + f", crank pivot A ({p['x0']:.5g}, {p['y0']:.5g}), ground line at "
            f"{math.degrees(p['theta0']):.4g}°, coupler point (u, v) = ({p['u']:.5g}, "
            f"{p['v']:.5g})",
        ),
        ("synthesis: crank angle at each target [deg]", ", ".join(f"{a:.2f}" for a in angles)),
        (
            "synthesis margins",
            f"{m.grashof}, transmission {fmt(m.transmission_min_deg, 3)}°–"
            f"{fmt(m.transmission_max_deg, 3)}° over the turn, path error RMS {c.rms:.3g} m, "
            f"max {c.max:.3g} m, length ratio {m.length_ratio:.3g}",
        ),
    )
    entry = {
        "mechanism": c.kind,
        "targets_m": [list(t) for t in targets],
        "params": {k: float(v) for k, v in p.items()},
        "crank_at_targets_deg": angles,
        "rms_error_m": c.rms,
        "max_error_m": c.max,
        "grashof": m.grashof,
        "transmission_deg": [m.transmission_min_deg, m.transmission_max_deg],
        "length_ratio": m.length_ratio,
    }
    dims = tuple(
        (k, float(v), "deg" if k in ("theta0", "phi1") else "m")
        for k, v in p.items()
        if k != "mode"
    )
    if "phi1" in p:
        dims = tuple((k, math.degrees(v) if u == "deg" else v, u) for k, v, u in dims)
    else:
        dims = tuple((k, math.degrees(v) if k == "theta0" else v, u) for k, v, u in dims)
    return LinkageSynthesis(
        "path", c.linkage(), c, report, entry, (*dims, ("mode", p["mode"], "")), _draw
    )


def _draw(rec: LinkageSynthesis, name: str) -> list[tuple[Any, str, str]]:
    """The linkage at the first target with its coupler curve, the targets marked."""
    from ..linkage.plot import plot_linkage

    c: PathCandidate = rec.candidate
    lk = rec.linkage
    turn = float(c.angles[0]) + np.linspace(0.0, 2.0 * math.pi, 721)
    ax = plot_linkage(lk, lk.solve(turn), 0, trace=["P"],
                      title=f"{name}: the synthesised path generator")  # fmt: skip
    t = np.asarray(rec.entry["targets_m"])
    (h,) = ax.plot(t[:, 0], t[:, 1], "x", color="C3", ms=9, mew=2, label="targets", gid="targets")
    ax.legend(handles=[h], fontsize=8, loc="best")
    return [
        (
            ax.figure,
            f"{name}_synthesis",
            "The synthesised linkage at its first target, its coupler point's path over "
            f"the turn and the targets (max error {c.max:.3g} m).",
        )
    ]


register_synthesizer("path", from_table)
