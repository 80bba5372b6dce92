"""Six-bar dwell linkages: a four-bar's coupler point whose
curve holds a nearly circular arc while the crank turns the dwell angle, and a
dyad from that point to the output rocker's joint, which sits at the arc's
centre during the dwell — so the output stands (nearly) still — and swings the
output outside it. The candidates come from :func:`scipy.optimize.differential_evolution`
whose whole population is evaluated in one Rust call (``synthesis/dwell.rs``,
whose module docs give the circle fit, the pivot placement and the ranking
rule).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import _core
from .._arrays import count, finite_number, positive, threads_arg
from .._errors import InputError
from ..linkage import Linkage
from ._fourbar import Margins, _coupler_body, _coupler_point, four_bar_margins

__all__ = ["DwellCandidate", "dwell_sixbar"]

#: The kernel's objective for a candidate it rejects (``dwell.rs``, REJECTED).
_REJECTED = 1e9
#: Bounds of the search, in units of the ground length d: crank, coupler, rocker,
#: coupler point (u, v); the dwell's middle crank angle [rad] over a turn. The
#: crank's upper bound keeps it the shortest link often enough for the search to
#: find crank-rockers quickly.
_BOUNDS = ((0.1, 0.5), (0.4, 2.0), (0.4, 2.0), (-1.0, 2.0), (-1.5, 1.5), (0.0, 2.0 * math.pi))


@dataclass(frozen=True)
class DwellCandidate:
    """One six-bar dwell linkage from :func:`dwell_sixbar`.

    The four-bar A (crank pivot, origin), B, C, D (rocker pivot, on +x) carries
    the coupler point P; the dyad P–E (length ``lengths["dyad"]``, the arc's
    radius) drives the output rocker F–E (length ``lengths["output"]``) about
    the pivot F. The output angle is the angle of F → E.

    Attributes
    ----------
    lengths : dict of str to float
        ``crank``, ``coupler``, ``rocker``, ``ground`` (the four-bar), ``dyad``
        (P–E) and ``output`` (F–E) [m].
    coupler_point : (float, float)
        P = (u, v) [m] in the coupler's frame (u along B → C, v to its left).
    mode : int
        The four-bar's assembly branch (+1, see :func:`four_bar_linkage`; the
        mirror image about the ground line is the −1 design).
    dwell_deg : float
        The dwell's crank angle [deg] (as asked).
    dwell_mid_deg : float
        The crank angle at the dwell's middle [deg], from the ground line A → D.
    dwell_joint : (float, float)
        E0, the arc's centre [m]: where the output joint E stands during the dwell.
    output_pivot : (float, float)
        F, the output rocker's pivot [m].
    dyad_branch : int
        The side (±1) of the ray F → P that E is on.
    residual_deg : float
        The output's peak-to-peak motion over the dwell range [deg], from the
        six-bar's position solution (not from the fit).
    swing_deg : float
        The output's peak-to-peak motion over a whole crank turn [deg] (the
        swing achieved; equals the one asked for within 1e-9 rad where
        ``feasible``).
    arc_deviation : float
        The coupler point's largest distance from the fitted arc over the dwell [m].
    margins : Margins
        The four-bar's margins over a full turn.
    output_transmission_min_deg, output_transmission_max_deg : float
        The second loop's transmission angle (between E → P and E → F) over the
        turn [deg], on a grid of ``n_turn`` crank angles.
    length_ratio : float
        The six links' longest over shortest (crank, coupler, rocker, ground,
        dyad, output).
    feasible : bool
        Both loops' transmission angles at least the limit, the swing met and
        the length ratio within its limit.

    Examples
    --------
    >>> import cyclomech as cm
    >>> c = cm.synthesis.dwell_sixbar(dwell_deg=60, swing_deg=40, maxiter=10)[0]
    >>> c.feasible, round(c.swing_deg, 6), sorted(c.lengths)
    (True, 40.0, ['coupler', 'crank', 'dyad', 'ground', 'output', 'rocker'])
    """

    lengths: dict[str, float]
    coupler_point: tuple[float, float]
    mode: int
    dwell_deg: float
    dwell_mid_deg: float
    dwell_joint: tuple[float, float]
    output_pivot: tuple[float, float]
    dyad_branch: int
    residual_deg: float
    swing_deg: float
    arc_deviation: float
    margins: Margins
    output_transmission_min_deg: float
    output_transmission_max_deg: float
    length_ratio: float
    feasible: bool

    @property
    def dwell_range_deg(self) -> tuple[float, float]:
        """The dwell's crank range (start, end) [deg] from the ground line.

        Examples
        --------
        >>> import cyclomech as cm
        >>> c = cm.synthesis.dwell_sixbar(dwell_deg=60, swing_deg=40, maxiter=10)[0]
        >>> lo, hi = c.dwell_range_deg
        >>> round(hi - lo, 9)
        60.0
        """
        half = self.dwell_deg / 2.0
        return (self.dwell_mid_deg - half, self.dwell_mid_deg + half)

    def linkage(self, *, name: str | None = None) -> Linkage:
        """The six-bar as a :class:`cyclomech.Linkage`, drawn at the dwell's middle.

        Points A, B, C, D (the four-bar), P (coupler point; with a helper Q where
        P is on the line BC), E (output joint), F (output pivot); ground A, D, F;
        driver (A, B), its angle the crank angle from +x (the ground line);
        output E.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> c = cm.synthesis.dwell_sixbar(dwell_deg=60, swing_deg=40, maxiter=10)[0]
        >>> sol = c.linkage().solve(np.radians(np.linspace(*c.dwell_range_deg, 61)))
        >>> psi = np.degrees(np.arctan2(*(sol["E"] - sol["F"]).T[::-1]))
        >>> bool(np.ptp(psi) <= c.residual_deg + 1e-9)
        True
        """
        ln = self.lengths
        a, b, c, d = ln["crank"], ln["coupler"], ln["rocker"], ln["ground"]
        th = math.radians(self.dwell_mid_deg)
        (t4,) = _core.fourbar_output_angle(a, b, c, d, [th], float(self.mode))
        pts = {
            "A": (0.0, 0.0),
            "B": (a * math.cos(th), a * math.sin(th)),
            "C": (d + c * math.cos(t4), c * math.sin(t4)),
            "D": (d, 0.0),
        }
        pts["P"] = _coupler_point(self.coupler_point, pts["B"], pts["C"])
        body = _coupler_body(pts, "B", "C")
        pts["E"] = self._joint(pts["P"])
        pts["F"] = self.output_pivot
        return Linkage(
            pts,
            [("A", "B"), body, ("C", "D"), ("P", "E"), ("E", "F")],
            ["A", "D", "F"],
            ("A", "B"),
            name=name,
            output="E",
        )

    def _joint(self, p: tuple[float, float]) -> tuple[float, float]:
        """E for the coupler point p: the dyad's circle–circle solution on its branch
        (the kernel's ``Output::joint``)."""
        fx, fy = self.output_pivot
        dx, dy = p[0] - fx, p[1] - fy
        f = math.hypot(dx, dy)
        r, e = self.lengths["dyad"], self.lengths["output"]
        cos_g = max(-1.0, min(1.0, (e * e + f * f - r * r) / (2.0 * e * f)))
        ang = math.atan2(dy, dx) + self.dyad_branch * math.acos(cos_g)
        return (fx + e * math.cos(ang), fy + e * math.sin(ang))


def _population(x: np.ndarray, d: float) -> np.ndarray:
    """Candidates (S, 6) → the kernel's rows (a, b, c, d, u, v, θm)."""
    x = np.atleast_2d(x)
    return np.ascontiguousarray(
        np.column_stack([x[:, 0], x[:, 1], x[:, 2], np.full(len(x), d), x[:, 3:]])
    )


def _candidate(row: np.ndarray, p: np.ndarray, dwell: float, min_mu: float) -> DwellCandidate:
    """One kernel row (``_core.dwell_fields()``) as a candidate."""
    f = dict(zip(_core.dwell_fields(), row, strict=True))
    a, b, c, d, u, v, tm = (float(t) for t in p)
    m = four_bar_margins(a, b, c, d)
    mu2 = min(f["mu2_min"], math.pi - f["mu2_max"])
    return DwellCandidate(
        lengths={
            "crank": a,
            "coupler": b,
            "rocker": c,
            "ground": d,
            "dyad": float(f["radius"]),
            "output": float(f["rocker"]),
        },
        coupler_point=(u, v),
        mode=1,
        dwell_deg=dwell,
        dwell_mid_deg=math.degrees(tm),
        dwell_joint=(float(f["e0_x"]), float(f["e0_y"])),
        output_pivot=(float(f["pivot_x"]), float(f["pivot_y"])),
        dyad_branch=int(f["branch"]),
        residual_deg=math.degrees(f["residual"]),
        swing_deg=math.degrees(f["swing"]),
        arc_deviation=float(f["arc_dev"]),
        margins=m,
        output_transmission_min_deg=math.degrees(f["mu2_min"]),
        output_transmission_max_deg=math.degrees(f["mu2_max"]),
        length_ratio=float(f["ratio"]),
        feasible=bool(f["violation"] == 0.0 and mu2 >= min_mu),
    )


def dwell_sixbar(
    dwell_deg: float,
    swing_deg: float,
    *,
    ground_m: float = 1.0,
    min_transmission_deg: float = 30.0,
    max_length_ratio: float = 10.0,
    n_candidates: int = 5,
    seed: int = 0,
    popsize: int = 20,
    maxiter: int = 30,
    n_dwell: int = 25,
    n_turn: int = 360,
    n_threads: int | None = None,
) -> list[DwellCandidate]:
    """Six-bar dwell linkages (Stephenson III): the output rocker stands (nearly)
    still while the crank turns ``dwell_deg`` and swings ``swing_deg`` over the
    rest of the turn — candidates with their margins, best first.

    A four-bar (crank-rocker, the crank turning fully) carries a coupler point
    whose curve holds a nearly circular arc over the dwell; the arc is fitted by
    least squares (Kåsa's algebraic fit refined by Gauss–Newton on the geometric
    distances; a fit over the whole arc rather than the osculating circle at its
    middle, which drifts away towards the dwell's ends). A dyad of the arc's
    radius joins the coupler point to the output joint E, which stands at the
    arc's centre during the dwell; the output's pivot lies on the perpendicular
    bisector of E's two extreme positions, placed so that the swing measured on
    the six-bar's own position solution is the one asked for. The search is
    :func:`scipy.optimize.differential_evolution` over the four-bar's crank,
    coupler and rocker, the coupler point and the dwell's middle crank angle
    (ground fixed at ``ground_m``, branch +1), its whole population evaluated
    in one parallel Rust call per generation; its objective is the output's
    residual motion over the dwell [deg] plus 1000 × the constraints' violation
    (transmission angles of both loops below ``min_transmission_deg``, swing
    missed, link-length ratio above ``max_length_ratio``) — so feasible
    candidates rank by residual alone.

    Parameters
    ----------
    dwell_deg : float
        The crank angle of the dwell [deg], in (0, 360).
    swing_deg : float
        The output's swing outside the dwell [deg], in (0, 180).
    ground_m : float
        The four-bar's ground length A–D [m] (angles do not depend on it; every
        length scales with it).
    min_transmission_deg : float
        The least transmission angle allowed in both loops [deg], in [0, 90].
    max_length_ratio : float
        The largest ratio allowed of the six links' longest to shortest (≥ 1).
    n_candidates : int
        How many candidates to return at most (distinct members of the final
        population, best first).
    seed : int
        The search's seed (the same seed gives the same candidates).
    popsize, maxiter : int
        Differential evolution's population multiplier and generations.
    n_dwell, n_turn : int
        Crank angles sampled over the dwell for the fit (≥ 3) and over the turn
        for the swing, the farthest coupler point and the second loop's
        transmission angle (≥ 8); the residual and swing are refined between
        samples to ~1e-12 rad.
    n_threads : int, optional
        Threads of the kernel (default: ``CYCLOMECH_THREADS`` or all cores).

    Returns
    -------
    list of DwellCandidate
        Feasible candidates first, then by residual, then by the larger worst
        transmission angle of the two loops.

    Raises
    ------
    InputError
        ``dwell_deg`` not in (0, 360), ``swing_deg`` not in (0, 180), a bad
        option (each named) — or no six-bar found at all.

    Examples
    --------
    >>> import cyclomech as cm
    >>> best = cm.synthesis.dwell_sixbar(dwell_deg=60, swing_deg=40, maxiter=10)[0]
    >>> best.margins.grashof, best.feasible, best.residual_deg < 1.0
    ('crank-rocker', True, True)
    """
    dwell = finite_number("dwell_deg", dwell_deg, "[deg]", low=0.0, strict=True)
    if dwell >= 360.0:
        raise InputError(f"dwell_deg must be < 360 [deg] (a dwell within one turn); got {dwell:g}")
    swing = finite_number("swing_deg", swing_deg, "[deg]", low=0.0, strict=True)
    if swing >= 180.0:
        raise InputError(f"swing_deg must be < 180 [deg] (an output rocker); got {swing:g}")
    d = positive("ground_m", ground_m, "[m]")
    mu = finite_number("min_transmission_deg", min_transmission_deg, "[deg]", low=0.0)
    if mu > 90.0:
        raise InputError(f"min_transmission_deg must be ≤ 90 [deg]; got {mu:g}")
    want = count("n_candidates", n_candidates, what="candidates")
    seed = count("seed", seed, low=0, what="seed")
    args = (
        1.0,
        math.radians(dwell),
        math.radians(swing),
        math.radians(mu),
        finite_number("max_length_ratio", max_length_ratio, "", low=1.0),
        count("n_dwell", n_dwell, low=3, what="dwell samples"),
        count("n_turn", n_turn, low=8, what="turn samples"),
    )
    threads = threads_arg(n_threads)

    def rows(p: np.ndarray) -> np.ndarray:
        return _core.dwell_batch(p, *args, n_threads=threads)

    def objective(x: np.ndarray) -> np.ndarray:
        # vectorized: x is (6, S), one Rust call per generation.
        return rows(_population(x.T, d))[:, 0]

    from scipy.optimize import differential_evolution  # here: ~0.3 s to import

    bounds = [(lo * d, hi * d) if i < 5 else (lo, hi) for i, (lo, hi) in enumerate(_BOUNDS)]
    res = differential_evolution(
        objective,
        bounds,
        seed=int(seed),
        popsize=count("popsize", popsize, what="population multiplier"),
        maxiter=count("maxiter", maxiter, what="generations"),
        vectorized=True,
        updating="deferred",
        polish=False,
        tol=0.0,
    )
    return _ranked(np.vstack([res.x, res.population]), d, dwell, math.radians(mu), want, rows)


def _ranked(
    x: np.ndarray, d: float, dwell: float, min_mu: float, want: int, rows: Any
) -> list[DwellCandidate]:
    """Distinct evaluated members of the population, best first (see
    :func:`dwell_sixbar`)."""
    p = _population(x, d)
    # Members that differ only in the last digits are one design.
    _, first = np.unique(np.round(p, 9), axis=0, return_index=True)
    p = p[np.sort(first)]
    r = rows(p)
    keep = r[:, 0] < _REJECTED
    if not keep.any():
        raise InputError(
            f"no six-bar dwell linkage found for dwell_deg = {dwell:g}, at any of "
            f"{len(p)} searched designs: none has a crank turning fully with a fittable "
            "arc and an output dyad that assembles over the turn; try a smaller dwell_deg "
            "or swing_deg, or more generations (maxiter)"
        )
    made = [_candidate(row, q, dwell, min_mu) for row, q in zip(r[keep], p[keep], strict=True)]

    def worst(c: DwellCandidate) -> float:
        return min(
            c.margins.worst_transmission_deg,
            c.output_transmission_min_deg,
            180.0 - c.output_transmission_max_deg,
        )

    made.sort(key=lambda c: (not c.feasible, c.residual_deg, -worst(c)))
    return made[:want]
