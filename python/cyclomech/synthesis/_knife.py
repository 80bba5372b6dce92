"""Seed 001's knife drives synthesised for a required knife motion.

The three generalised schemes of seed 001 (``br125`` p = 1, structure 1–3;
``br136`` p = 2, 1–2–3; ``brp4`` p = 3, 1–2–2–3; their topology and frame are
:mod:`cyclomech.linkage.presets`') dimensioned by differential evolution whose
whole population is solved in one call of
:func:`cyclomech.linkage.solve_geometries` per generation.

**The knife motion, defined.** The knife point is ``E``. Its displacement is
s(φ) = −y_E(φ): the knife cuts downwards along −y (the frame's y axis is up, as
in the seed). The *stroke* is max s − min s over one crank turn; the *top* is
the crank angle of min s, the *bottom* that of max s; the *cut* ``cut_deg`` is
the crank angle the knife takes from the top to the bottom, the crank turning
the positive way, and the return takes the rest (360° − cut). These linkages
have no true dwell (the knife stops only instantaneously at its ends), so no
dwell is offered. The knife must make one stroke per turn: s has exactly one
maximum and one minimum (two sign changes of ds/dφ); a knife that stops and
turns back within its stroke is refused, so top and bottom are never ambiguous.

**What is varied.** Every link length of the scheme except the knife holder's
BC (``knife_m``), between bounds about the preset's (the crank 0.3–3×, the
others 0.6–1.6×). The ground pivots are the preset's frame scaled to
``knife_m``: the batch solver varies lengths over one frame, so pivot positions
are not design variables; the frame envelope is a box the whole mechanism (the
pivots and every joint over the turn) must stay in.

**Transmission angles** (the acute angle μ ∈ [0°, 90°], 90° best, 0° a dead
centre): at a dyad's joint P placed from a and b, the angle between the lines Pa
and Pb; at the class III group, the one at its driven joint E: between the rod
FE and the velocity of E as a point of the knife holder, which turns about its
instantaneous centre I (where the hangers' lines AB, DC meet): μ = arcsin|r̂ ×
êᵢ| with r̂ along the rod and êᵢ along IE. μ = 0 exactly where the rod's line
passes through I, the group's singular pose.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
import numpy.typing as npt

from .._arrays import count, finite_number, positive
from .._errors import InputError
from ..linkage import Linkage, LinkageSolution, presets, solve_geometries

__all__ = ["SCHEMES", "KnifeDrive", "KnifeRequirement", "knife_drive", "knife_motion"]

Array = npt.NDArray[np.float64]

#: The schemes: name → (the preset with the scheme's topology and frame, the
#: transmission checks: ("II", P, a, b) a dyad's joint, ("III", E, F, (A, B), (D, C))
#: the class III group's driven joint E, rod end F and hangers).
SCHEMES: dict[str, tuple[Callable[[], Linkage], tuple[tuple[Any, ...], ...]]] = {
    "br125": (presets.br125, (("III", "E", "F", ("A", "B"), ("D", "C")),)),
    "br136": (
        presets.br136,
        (("II", "F", "G", "J"), ("III", "E", "F", ("A", "B"), ("D", "C"))),
    ),
    "brp4": (
        presets.brp4,
        (
            ("II", "K", "J", "P"),
            ("II", "F", "M", "G"),
            ("III", "E", "F", ("A", "B"), ("D", "C")),
        ),
    ),
}

#: Crank angles per turn of the optimiser's grid (2°): extremes are refined on the
#: analogs' cubic Hermite interpolant (:func:`knife_motion`), so stroke and timing
#: are accurate to ~1e-9 of the stroke and ~1e-6° (the tests measure against
#: brentq).
_GRID = 180


@dataclass(frozen=True)
class KnifeRequirement:
    """What a knife drive must do and the constraints it must hold.

    Parameters
    ----------
    stroke_m : float
        The knife's stroke [m]: max − min of −y_E over the turn.
    cut_deg : float
        The crank angle [deg] of the working stroke, top to bottom, in (0, 360).
    knife_m : float, optional
        The knife holder's length BC [m]; the frame is the scheme's preset scaled
        to it. Default: each preset's own.
    envelope : (float, float, float, float), optional
        The frame box (x_min, y_min, x_max, y_max) [m] every joint stays in over
        the turn (frame coordinates: A at the origin); None (default) for none.
    min_transmission_deg : float, default 30
        The least transmission angle allowed at every checked joint [deg].
    max_length_ratio : float, default 25
        The longest link over the shortest, at most.
    stroke_tol_m : float, default 0.5e-3
        How close the stroke must come [m].
    cut_tol_deg : float, default 0.5
        How close the cut's crank angle must come [deg].
    seed : int, default 1
        The optimiser's seed (results repeat for a seed).
    popsize : int, default 15
        Candidates per design variable in each generation.
    maxiter : int, default 120
        Generations at most.

    Examples
    --------
    >>> from cyclomech.synthesis import KnifeRequirement
    >>> KnifeRequirement(0.16, 180.0).cut_deg
    180.0
    """

    stroke_m: float
    cut_deg: float
    knife_m: float | None = None
    envelope: tuple[float, float, float, float] | None = None
    min_transmission_deg: float = 30.0
    max_length_ratio: float = 25.0
    stroke_tol_m: float = 0.5e-3
    cut_tol_deg: float = 0.5
    seed: int = 1
    popsize: int = 15
    maxiter: int = 120

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        set_(self, "stroke_m", positive("stroke_m", self.stroke_m, "[m]"))
        cut = finite_number("cut_deg", self.cut_deg, "[deg]")
        if not 0.0 < cut < 360.0:
            raise InputError(
                f"cut_deg = {cut!r}: the cut's crank angle must lie in (0, 360) degrees "
                "(the return takes the rest of the turn)"
            )
        set_(self, "cut_deg", cut)
        if self.knife_m is not None:
            set_(self, "knife_m", positive("knife_m", self.knife_m, "[m]"))
        if self.envelope is not None:
            box = np.asarray(self.envelope, dtype=float) if _seq(self.envelope) else None
            if box is None or box.shape != (4,) or not np.isfinite(box).all():
                raise InputError(
                    f"envelope = {self.envelope!r} must be four finite numbers "
                    "(x_min, y_min, x_max, y_max) [m]"
                )
            if not (box[0] < box[2] and box[1] < box[3]):
                raise InputError(
                    f"envelope = {self.envelope!r}: x_min < x_max and y_min < y_max are needed"
                )
            set_(self, "envelope", tuple(float(v) for v in box))
        mu = finite_number("min_transmission_deg", self.min_transmission_deg, "[deg]")
        if not 0.0 <= mu < 90.0:
            raise InputError(f"min_transmission_deg = {mu!r} must lie in [0, 90) degrees")
        set_(self, "min_transmission_deg", mu)
        ratio = positive("max_length_ratio", self.max_length_ratio, "")
        if ratio <= 1.0:
            raise InputError(f"max_length_ratio = {ratio!r} must exceed 1")
        set_(self, "max_length_ratio", ratio)
        set_(self, "stroke_tol_m", positive("stroke_tol_m", self.stroke_tol_m, "[m]"))
        set_(self, "cut_tol_deg", positive("cut_tol_deg", self.cut_tol_deg, "[deg]"))
        set_(self, "seed", count("seed", self.seed, low=0, what="seed"))
        set_(self, "popsize", count("popsize", self.popsize, low=5, what="candidates"))
        set_(self, "maxiter", count("maxiter", self.maxiter, low=1, what="generations"))


def _seq(v: Any) -> bool:
    return isinstance(v, Sequence | np.ndarray) and not isinstance(v, str)


def _scheme(scheme: Any) -> tuple[Callable[[], Linkage], tuple[tuple[Any, ...], ...]]:
    if not isinstance(scheme, str) or scheme not in SCHEMES:
        raise InputError(
            f"scheme = {scheme!r}: no such knife-drive scheme; the schemes are "
            f"{', '.join(SCHEMES)} (seed 001's p = 1, 2, 3)"
        )
    return SCHEMES[scheme]


def _scaled(lk: Linkage, factor: float) -> Linkage:
    """``lk`` with every coordinate and length times ``factor``."""
    d = lk.to_dict()
    d["points"] = {n: [factor * x, factor * y] for n, (x, y) in d["points"].items()}
    for row in d.get("lengths", []):
        row["length"] *= factor
    return Linkage.from_dict(d)


def knife_motion(sol: LinkageSolution, output: str = "E") -> dict[str, Array]:
    """The knife's stroke, top and bottom angles and cut of solved geometries.

    Each extreme of s = −y is the grid's, moved to the root of ds/dφ on the cubic
    Hermite interpolant of the analogs (s', s'') between that grid point and its
    neighbour on the root's side; the angles are accurate to O(h⁴) in the grid
    step h (~1e-6° on a 2° grid), the stroke to O(h⁵).

    Parameters
    ----------
    sol : LinkageSolution
        A solution with analogs over a uniform grid of one crank turn with both
        ends (the last angle = the first + 2π): of :meth:`cyclomech.Linkage.solve`
        (shape (N+1, M, 2)) or :func:`cyclomech.linkage.solve_geometries` (K, N+1,
        M, 2).
    output : str, default "E"
        The knife point.

    Returns
    -------
    dict of str to ndarray
        ``stroke`` [m], ``top`` and ``bottom`` [rad, absolute], ``cut`` [rad in
        [0, 2π)], ``turns`` (sign changes of ds/dφ over the turn), each (K,) or
        scalar arrays.

    Examples
    --------
    >>> import numpy as np
    >>> from cyclomech.linkage import presets
    >>> from cyclomech.synthesis import knife_motion
    >>> lk = presets.br125()
    >>> sol = lk.solve(lk.drawn_angle + np.linspace(0, 2 * np.pi, 361))
    >>> m = knife_motion(sol)
    >>> round(float(m["stroke"]), 4), int(m["turns"])
    (0.1385, 2)
    """
    if not isinstance(sol, LinkageSolution) or sol.vel is None or sol.acc is None:
        raise InputError(
            f"sol must be a LinkageSolution with analogs (analogs=True); got {type(sol).__name__}"
        )
    if not isinstance(output, str) or output not in sol.names:
        raise InputError(f"output = {output!r} is not a point of sol: {', '.join(sol.names)}")
    if sol.angles.size < 4:
        raise InputError(f"sol has {sol.angles.size} angles; a turn needs at least 4")
    k = sol.index(output)
    s = -sol.xy[..., :-1, k, 1]
    v = -sol.vel[..., :-1, k, 1]
    a = -sol.acc[..., :-1, k, 1]
    phi = sol.angles[:-1]
    h = phi[1] - phi[0]

    n = phi.size

    def at(q: Array, i: npt.NDArray[np.int64]) -> Array:
        return np.take_along_axis(q, i[..., None], -1)[..., 0]

    def extreme(i: npt.NDArray[np.int64]) -> tuple[Array, Array]:
        # The root of s' next to the grid's extreme i, on the side s'/s'' points
        # to: on the cubic Hermite interpolant of s' from (s', s'') at i and at
        # its neighbour j there (O(h⁴); one Newton step from i alone was O(h²):
        # 2e-3° on the 2° grid), by Newton on that cubic from the Newton step's
        # point; s there by the interpolant's integral (O(h⁵)).
        si, vi, ai = at(s, i), at(v, i), at(a, i)
        with np.errstate(divide="ignore", invalid="ignore"):
            d0 = np.nan_to_num(np.where(ai != 0.0, -vi / ai, 0.0))
        side = np.where(d0 < 0.0, -1, 1)
        j = (i + side) % n
        vj, aj = at(v, j), at(a, j)
        g = side * h  # the signed step to the neighbour
        t = np.clip(d0 / g, 0.0, 1.0)
        for _ in range(4):
            t2, t3 = t * t, t * t * t
            f = (
                (2 * t3 - 3 * t2 + 1) * vi
                + (t3 - 2 * t2 + t) * g * ai
                + (3 * t2 - 2 * t3) * vj
                + (t3 - t2) * g * aj
            )
            df = (6 * t2 - 6 * t) * vi + (3 * t2 - 4 * t + 1) * g * ai
            df = df + (6 * t - 6 * t2) * vj + (3 * t2 - 2 * t) * g * aj
            with np.errstate(divide="ignore", invalid="ignore"):
                t = np.clip(np.nan_to_num(t - f / df), 0.0, 1.0)
        t2, t3, t4 = t * t, t * t * t, t * t * t * t
        ds = g * (
            (t - t3 + 0.5 * t4) * vi
            + (0.5 * t2 - 2 * t3 / 3 + 0.25 * t4) * g * ai
            + (t3 - 0.5 * t4) * vj
            + (0.25 * t4 - t3 / 3) * g * aj
        )
        return si + ds, phi[i] + g * t

    smax, bottom = extreme(np.argmax(s, axis=-1))
    smin, top = extreme(np.argmin(s, axis=-1))
    # A zero of ds/dφ on a grid point counts with the positive side, so an extreme
    # that falls on the grid is one sign change, not two.
    sg = np.where(v >= 0.0, 1, -1)
    turns = np.sum(sg != np.roll(sg, -1, axis=-1), axis=-1)
    cut = np.mod(bottom - top, 2.0 * math.pi)
    return {"stroke": smax - smin, "top": top, "bottom": bottom, "cut": cut, "turns": turns}


def transmission_angles(sol: Any, checks: Sequence[tuple[Any, ...]]) -> Array:
    """Transmission angles [deg] (acute, 90° best) at each check over the grid.

    Shape (..., N, C) for a solution of shape (..., N, M, 2) and C checks (see
    the module's definition).
    """

    def pt(n: str) -> Array:
        return np.asarray(sol.xy[..., :, sol.index(n), :])

    def acute(u: Array, w: Array) -> Array:
        cr = np.abs(u[..., 0] * w[..., 1] - u[..., 1] * w[..., 0])
        nrm = np.hypot(*np.moveaxis(u, -1, 0)) * np.hypot(*np.moveaxis(w, -1, 0))
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.degrees(np.arcsin(np.clip(cr / nrm, 0.0, 1.0)))

    out = []
    for c in checks:
        if c[0] == "II":
            p, a, b = (pt(n) for n in c[1:])
            out.append(acute(a - p, b - p))
        else:
            e, f = pt(c[1]), pt(c[2])
            (a, b), (d, cc) = ((pt(x), pt(y)) for x, y in (c[3], c[4]))
            # Homogeneous lines AB and DC and their meet I = (ix, iy, w): w = 0
            # for parallel hangers, I then a direction along them.
            one = np.ones((*a.shape[:-1], 1))
            h = [np.concatenate([q, one], axis=-1) for q in (a, b, d, cc)]
            i_h = np.cross(np.cross(h[0], h[1]), np.cross(h[2], h[3]))
            r = i_h[..., 2:3] * e - i_h[..., :2]  # w·(E − I): along IE
            out.append(acute(f - e, r))
    return np.stack(out, axis=-1)


@dataclass(frozen=True)
class KnifeDrive:
    """A synthesised knife drive: the linkage, its motion against the requirement,
    the constraints' margins and the candidates best first.

    Attributes
    ----------
    scheme : str
        ``"br125"``, ``"br136"`` or ``"brp4"``.
    requirement : KnifeRequirement
        What it was asked.
    linkage : Linkage
        The linkage (output ``E``), drawn in its pose at the drawn crank angle.
    stroke_m, cut_deg, top_deg : float
        The stroke [m], the cut's crank angle [deg] and the crank angle of the top
        [deg, in [0, 360)] achieved.
    margins : dict of str to float
        Each requirement's and constraint's margin (≥ 0 where it holds):
        ``stroke_m`` (tolerance − |error|), ``cut_deg`` (same), ``transmission_deg``
        (least angle − the minimum), ``length_ratio`` (the limit − the ratio),
        ``envelope_m`` (the least clearance to the box; inf without one).
    min_transmission_deg : dict of str to float
        The least transmission angle over the turn at each checked joint.
    candidates : list of (float, ndarray)
        The last generation's (cost, lengths in ``Linkage.dimensions``
        order), best first; the first is the linkage's.
    feasible : bool
        Every margin ≥ 0.
    """

    scheme: str
    requirement: KnifeRequirement
    linkage: Linkage
    stroke_m: float
    cut_deg: float
    top_deg: float
    margins: dict[str, float]
    min_transmission_deg: dict[str, float]
    candidates: list[tuple[float, Array]] = field(repr=False)
    generations: int = 0

    @property
    def feasible(self) -> bool:
        """True when every margin is ≥ 0 (every requirement met)."""
        return all(v >= 0.0 for v in self.margins.values())

    def why(self) -> str:
        """What was chosen and why, in one paragraph of words."""
        r = self.requirement
        mu = ", ".join(f"{k} {v:.1f}°" for k, v in self.min_transmission_deg.items())
        return (
            f"{self.scheme}: stroke {self.stroke_m * 1e3:.2f} mm (asked "
            f"{r.stroke_m * 1e3:.2f} ± {r.stroke_tol_m * 1e3:.2g} mm), cut "
            f"{self.cut_deg:.2f}° (asked {r.cut_deg:g} ± {r.cut_tol_deg:g}°), top at crank "
            f"{self.top_deg:.1f}°; least transmission angles {mu} (at least "
            f"{r.min_transmission_deg:g}°); chosen by differential evolution as the "
            "candidate meeting the stroke and timing with the largest least "
            f"transmission angle ({self.generations} generations)"
        )


def _grid(lk: Linkage) -> Array:
    # Both ends of the turn about the drawn angle: the solver walks from the drawn
    # pose up to +π and down to −π; the two ends are one crank position, so equal
    # poses there prove the two walks ended on one assembly (no branch change).
    return lk.drawn_angle + np.linspace(-math.pi, math.pi, _GRID + 1)


class _Problem:
    """The scheme's batch cost: every candidate of a generation in one solve."""

    def __init__(self, scheme: str, req: KnifeRequirement) -> None:
        make, self.checks = _scheme(scheme)
        base = make()
        knife = base.length("B", "C") if req.knife_m is None else req.knife_m
        self.linkage = _scaled(base, knife / base.length("B", "C"))
        self.req, self.scheme = req, scheme
        dims = self.linkage.dimensions
        self.base = self.linkage.dimension_values
        fixed = {("B", "C"), ("C", "B")}
        self.free = np.array([j for j, p in enumerate(dims) if p not in fixed])
        lo = np.where(np.arange(len(dims)) == 0, 0.3, 0.6)[self.free] * self.base[self.free]
        hi = np.where(np.arange(len(dims)) == 0, 3.0, 1.6)[self.free] * self.base[self.free]
        self.bounds = list(zip(lo, hi, strict=True))
        self.angles = _grid(self.linkage)
        if req.envelope is not None:
            x0, y0, x1, y1 = req.envelope
            fx = np.array(
                [
                    xy
                    for n, xy in self.linkage.to_dict()["points"].items()
                    if n in self.linkage.to_dict()["ground"]
                ]
            )
            outside = (fx[:, 0] < x0) | (fx[:, 0] > x1) | (fx[:, 1] < y0) | (fx[:, 1] > y1)
            if outside.any():
                raise InputError(
                    f"envelope = {req.envelope!r}: the {scheme} frame's ground pivots "
                    f"({', '.join(f'({x:.3g}, {y:.3g})' for x, y in fx[outside])} m) lie "
                    "outside it; widen the box or change knife_m"
                )

    def lengths(self, x: Array) -> Array:
        """(K, D) lengths of the design vectors x (K, F)."""
        out = np.repeat(self.base[None], x.shape[0], axis=0)
        out[:, self.free] = x
        return out

    def evaluate(self, lengths: Array) -> dict[str, Array]:
        """Every measure of K geometries, from one :func:`solve_geometries` call."""
        sol = solve_geometries(self.linkage, self.angles, lengths)
        m = knife_motion(sol)
        ok = sol.ok.all(axis=1) & ~sol.branch_change.any(axis=1) & ~sol.singular.any(axis=1)
        size = float(self.base.max())
        with np.errstate(invalid="ignore"):
            gap = np.abs(sol.xy[:, 0] - sol.xy[:, -1]).max(axis=(1, 2))
            ok &= gap <= 1e-7 * size
            mu = transmission_angles(sol, self.checks).min(axis=1)  # (K, C)
        ok &= m["turns"] == 2
        ratio = lengths.max(axis=1) / lengths.min(axis=1)
        if self.req.envelope is not None:
            x0, y0, x1, y1 = self.req.envelope
            xs, ys = sol.xy[..., 0], sol.xy[..., 1]
            with np.errstate(invalid="ignore"):
                clear = np.minimum.reduce(
                    [
                        (xs - x0).min(axis=(1, 2)),
                        (x1 - xs).min(axis=(1, 2)),
                        (ys - y0).min(axis=(1, 2)),
                        (y1 - ys).min(axis=(1, 2)),
                    ]
                )
        else:
            clear = np.full(len(lengths), np.inf)
        return {**m, "ok": ok, "mu": mu, "ratio": ratio, "clear": clear, "sol": sol}

    def margins(self, e: Mapping[str, Array]) -> dict[str, Array]:
        r = self.req
        cut_err = np.degrees(np.abs(e["cut"] - math.radians(r.cut_deg)))
        return {
            "stroke_m": r.stroke_tol_m - np.abs(e["stroke"] - r.stroke_m),
            "cut_deg": r.cut_tol_deg - np.minimum(cut_err, 360.0 - cut_err),
            "transmission_deg": e["mu"].min(axis=1) - r.min_transmission_deg,
            "length_ratio": r.max_length_ratio - e["ratio"],
            "envelope_m": e["clear"],
        }

    def cost(self, e: Mapping[str, Array]) -> Array:
        """Lower is better: a mechanism that does not turn through costs most; then
        the constraints' shortfalls, then the requirements' errors beyond their
        tolerances, and among those meeting everything the larger least
        transmission angle wins (the 1 − μ/90° term)."""
        mg = self.margins(e)
        r = self.req
        short = (
            np.maximum(-mg["transmission_deg"], 0.0) / 90.0
            + np.maximum(-mg["length_ratio"], 0.0) / r.max_length_ratio
            + np.maximum(-mg["envelope_m"], 0.0) / float(self.base.max())
        )
        err = np.maximum(
            np.abs(mg["stroke_m"] - r.stroke_tol_m) / r.stroke_tol_m,
            np.abs(mg["cut_deg"] - r.cut_tol_deg) / r.cut_tol_deg,
        )
        c = 100.0 * short + 10.0 * np.maximum(err - 1.0, 0.0) + 0.2 * err
        c = c + 1.0 - np.clip(e["mu"].min(axis=1), 0.0, 90.0) / 90.0
        c = np.where(e["ok"] & np.isfinite(c), c, 1e6)
        return np.asarray(c, dtype=float)


def knife_drive(
    scheme: str = "br125",
    stroke_m: float | None = None,
    cut_deg: float | None = None,
    *,
    requirement: KnifeRequirement | None = None,
    candidates: int = 5,
    **options: Any,
) -> KnifeDrive:
    """Synthesise one of seed 001's knife-drive schemes for a required knife motion.

    Differential evolution (:func:`scipy.optimize.differential_evolution`,
    ``vectorized=True``, no polish) over the scheme's link lengths; each
    generation's candidates are solved together in one call of
    :func:`cyclomech.linkage.solve_geometries` on a 2° grid of one crank turn.
    A candidate must turn through the whole turn on one assembly (the solver's
    ``ok``, no ``branch_change``, no singular pose, the two walks from the drawn
    pose meeting on one pose), make one stroke per turn and hold the
    constraints; among those meeting the stroke and timing, the largest least
    transmission angle wins. See the module's docs for the definitions.

    Parameters
    ----------
    scheme : str, default "br125"
        ``"br125"`` (p = 1), ``"br136"`` (p = 2) or ``"brp4"`` (p = 3).
    stroke_m : float
        The knife's stroke [m] (max − min of −y_E).
    cut_deg : float
        The working stroke's crank angle [deg], top to bottom, in (0, 360).
    requirement : KnifeRequirement, optional
        All of it at once instead of ``stroke_m``, ``cut_deg`` and ``options``.
    candidates : int, default 5
        How many of the last generation's best to keep.
    **options
        The other fields of :class:`KnifeRequirement` (``knife_m``,
        ``envelope``, ``min_transmission_deg``, ``max_length_ratio``,
        ``stroke_tol_m``, ``cut_tol_deg``, ``seed``, ``popsize``, ``maxiter``).

    Returns
    -------
    KnifeDrive
        The best linkage, the motion it achieves, the margins and the candidates.

    Raises
    ------
    InputError
        For an unknown scheme or a malformed requirement, or when no candidate
        meets every requirement: the message names what fails and the best
        achieved.

    Examples
    --------
    >>> import cyclomech as cm
    >>> k = cm.synthesis.knife_drive("br125", 0.15, 175.0, popsize=8, maxiter=30)
    >>> k.feasible, abs(k.stroke_m - 0.15) <= 0.5e-3
    (True, True)
    >>> k.why().split(":")[0]
    'br125'
    """
    _scheme(scheme)
    if requirement is None:
        if stroke_m is None or cut_deg is None:
            raise InputError("knife_drive needs stroke_m and cut_deg, or a requirement")
        requirement = KnifeRequirement(stroke_m, cut_deg, **options)
    elif not isinstance(requirement, KnifeRequirement):
        raise InputError(
            f"requirement must be a KnifeRequirement; got {type(requirement).__name__}"
        )
    elif options:
        requirement = replace(requirement, **options)
    keep = count("candidates", candidates, low=1, what="candidates")
    got = _synthesise(scheme, requirement, keep)
    if isinstance(got, str):
        raise InputError(got)
    return got


#: Generations without a better best cost (by 1e-6 of it) after which the
#: optimiser stops: a requirement met with its transmission angle settled, or one
#: out of reach, stops early instead of running to ``maxiter``.
PATIENCE = 40


@functools.lru_cache(maxsize=64)
def _synthesise(scheme: str, requirement: KnifeRequirement, keep: int) -> KnifeDrive | str:
    # Deterministic for a seed: a machine file parsed again (sweeps, checks) and a
    # comparison after a single synthesis reuse the result, or the reason it failed
    # (the message, as a string: lru_cache keeps no exceptions).
    from scipy.optimize import differential_evolution  # here: ~0.3 s to import

    prob = _Problem(scheme, requirement)

    def batch(x: Array) -> Array:
        # scipy hands the population as (F, S); one solve for all S candidates.
        return prob.cost(prob.evaluate(prob.lengths(np.atleast_2d(x.T))))

    best = [math.inf, 0]

    def settled(intermediate_result: Any) -> bool:
        f = float(intermediate_result.fun)
        if not math.isfinite(best[0]) or f < best[0] - 1e-6 * abs(best[0]):
            best[0], best[1] = f, 0
        else:
            best[1] += 1
        return best[1] >= PATIENCE

    res = differential_evolution(
        batch,
        prob.bounds,
        vectorized=True,
        updating="deferred",
        seed=requirement.seed,
        popsize=requirement.popsize,
        maxiter=requirement.maxiter,
        polish=False,
        tol=1e-8,
        init="sobol",
        x0=prob.base[prob.free],  # the preset's lengths: a candidate that turns through
        callback=settled,
    )
    order = np.argsort(res.population_energies, kind="stable")
    pop = res.population[order]
    best_x = np.asarray(res.x, dtype=float)
    lengths = prob.lengths(np.vstack([best_x[None], pop]))
    ev = prob.evaluate(lengths[:1])
    try:
        return _result(prob, lengths, res, ev, keep)
    except InputError as e:
        return str(e)


def _result(prob: _Problem, lengths: Array, res: Any, ev: dict[str, Any], keep: int) -> KnifeDrive:
    req = prob.req
    mg = {k: float(v[0]) for k, v in prob.margins(ev).items()}
    names = [f"{c[1]}" for c in prob.checks]
    mu = {n: float(v) for n, v in zip(names, ev["mu"][0], strict=True)}
    if not ev["ok"][0]:
        raise InputError(
            f"knife_drive({prob.scheme!r}): no candidate turns through the whole crank turn "
            "on one assembly within the bounds of its lengths; the stroke "
            f"{req.stroke_m:g} m and cut {req.cut_deg:g}° may be out of this scheme's reach"
        )
    failed = [k for k, v in mg.items() if v < 0.0]
    if failed:
        best = (
            f"best achieved: stroke {float(ev['stroke'][0]):.5g} m (asked {req.stroke_m:g} ± "
            f"{req.stroke_tol_m:g}), cut {math.degrees(float(ev['cut'][0])):.4g}° (asked "
            f"{req.cut_deg:g} ± {req.cut_tol_deg:g}), least transmission angle "
            f"{min(mu.values()):.3g}° (at least {req.min_transmission_deg:g}), length ratio "
            f"{float(ev['ratio'][0]):.3g} (at most {req.max_length_ratio:g}), envelope "
            f"clearance {mg['envelope_m']:.3g} m"
        )
        raise InputError(
            f"knife_drive({prob.scheme!r}): the requirement cannot be met — "
            f"{', '.join(_WHAT[k] for k in failed)} {'fails' if len(failed) == 1 else 'fail'}; "
            f"{best}"
        )
    sol = ev["sol"]
    lk = _posed(prob.linkage, lengths[0], sol)
    costs = prob.cost(prob.evaluate(lengths[1:]))
    order = np.argsort(costs, kind="stable")
    cands = [(float(costs[i]), lengths[1 + i].copy()) for i in order[:keep]]
    cands.insert(0, (float(prob.cost(ev)[0]), lengths[0].copy()))
    return KnifeDrive(
        prob.scheme,
        req,
        lk,
        float(ev["stroke"][0]),
        math.degrees(float(ev["cut"][0])),
        math.degrees(float(ev["top"][0])) % 360.0,
        mg,
        mu,
        cands[:keep],
        int(res.nit),
    )


_WHAT = {
    "stroke_m": "the stroke",
    "cut_deg": "the cut's timing",
    "transmission_deg": "the least transmission angle",
    "length_ratio": "the link-length ratio",
    "envelope_m": "the frame envelope",
}


def _posed(base: Linkage, lengths: Array, sol: Any) -> Linkage:
    """The linkage with ``lengths``, drawn at its pose at the drawn crank angle
    (the middle of the grid), so that its own solve starts from that assembly."""
    d = base.to_dict()
    mid = sol.xy.shape[1] // 2
    d["points"] = {
        n: [float(x), float(y)] for n, (x, y) in zip(sol.names, sol.xy[0, mid], strict=True)
    }
    d["lengths"] = [
        {"joints": [a, b], "length": float(v)}
        for (a, b), v in zip(base.dimensions, lengths, strict=True)
    ]
    return Linkage.from_dict(d)
