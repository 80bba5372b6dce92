"""Motion generation: four-bars whose coupler takes three,
four or five given poses. Three by circle points and centre points (the
classical construction; ``rust/core/src/synthesis/motion.rs`` has its
derivation and the rules for the degenerate choices and the defects); four by
dyads on Burmester's curves and five by pairs of Burmester's points
(``rust/core/src/synthesis/burmester.rs``; :mod:`._burmester`).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import _core
from .._arrays import count, finite_number, float_array, positive
from .._errors import InputError
from ..linkage import Linkage
from ._fourbar import Margins, _coupler_body

__all__ = ["MotionCandidate", "motion_generation"]

Point = tuple[float, float]


@dataclass(frozen=True)
class MotionCandidate:
    """One four-bar from :func:`motion_generation`, with its defects and margins.

    Attributes
    ----------
    poses : three to five (x [m], y [m], angle [deg])
        The poses asked for.
    circle_points : ((u, v), (u, v))
        The moving pivots A (the crank's) and B (the rocker's) in the coupler
        frame [m]: u along the pose angle from the pose point, v to its left.
    centre_points : ((x, y), (x, y))
        The ground pivots A0 and B0 [m]: the centres of the circles that A's
        and B's positions lie on (with three poses their circumcentres).
    moving_pivots : ((x, y), (x, y))
        A and B in the first pose [m] (the drawn pose of :meth:`linkage`).
    lengths : dict of str to float
        ``crank`` |A0A|, ``coupler`` |AB|, ``rocker`` |B0B|, ``ground`` |A0B0| [m].
    crank_angles_deg : tuple of float
        The crank's absolute angle A0 → A at each pose [deg].
    direction : int
        +1 if the crank turns counter-clockwise from pose 1 through the others
        in order, −1 clockwise (with an order defect among four or five poses:
        the shorter turn from pose 1 to pose 2).
    branches : tuple of int
        The assembly branch at each pose (the side of the ray B0 → A that B is
        on; 0 where folded).
    branch_defect : bool
        A pose is reached on the other branch: the linkage cannot pass from one
        pose to the next without being taken apart.
    order_defect : bool
        The crank cannot sweep the arc from pose 1 through the others on one
        branch (it breaks in between), or, with four or five poses, turning
        one way it meets them out of order: it would meet the poses out of order.
    working_arc_deg : (float, float)
        That arc as absolute crank angles (lo, hi) [deg], lo < hi.
    margins : Margins
        Over the working arc (pose 1 through the others to the last).

    Examples
    --------
    >>> import cyclomech as cm
    >>> poses = [(0, 0, 0), (0.5, 0.2, 20), (0.9, 0.6, 45)]
    >>> c = cm.synthesis.motion_generation(poses, circle_points=((0, -0.5), (0.6, -0.4)))[0]
    >>> c.branch_defect, c.order_defect, sorted(c.lengths)
    (False, False, ['coupler', 'crank', 'ground', 'rocker'])
    """

    poses: tuple[tuple[float, float, float], ...]
    circle_points: tuple[Point, Point]
    centre_points: tuple[Point, Point]
    moving_pivots: tuple[Point, Point]
    lengths: dict[str, float]
    crank_angles_deg: tuple[float, ...]
    direction: int
    branches: tuple[int, ...]
    branch_defect: bool
    order_defect: bool
    working_arc_deg: tuple[float, float]
    margins: Margins

    @property
    def clean(self) -> bool:
        """No branch or order defect and the working arc held on one branch
        without a fold: the ranking's first key.

        Examples
        --------
        >>> import cyclomech as cm
        >>> poses = [(0, 0, 0), (0.5, 0.2, 20), (0.9, 0.6, 45)]
        >>> cm.synthesis.motion_generation(poses, circle_points=((0, -0.5), (0.6, -0.4)))[0].clean
        True
        """
        return not (self.branch_defect or self.order_defect) and self.margins.branch_ok

    def linkage(self, *, name: str | None = None) -> Linkage:
        """The :class:`cyclomech.Linkage` drawn in the first pose: ground pivots
        ``A0``, ``B0``, moving pivots ``A``, ``B``, the pose point ``P`` on the
        coupler (the output), driver (A0, A). ``solve`` at
        ``np.radians(crank_angles_deg)`` puts P and the coupler at the poses.
        Where P lies on the line AB, a helper point ``Q`` of the coupler
        (A + AB turned 90°) is drawn too, so that the solver knows P's side.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> poses = [(0, 0, 0), (0.5, 0.2, 20), (0.9, 0.6, 45)]
        >>> c = cm.synthesis.motion_generation(poses, circle_points=((0, -0.5), (0.6, -0.4)))[0]
        >>> sol = c.linkage().solve(np.radians(c.crank_angles_deg))
        >>> np.round(sol["P"], 9).tolist()
        [[0.0, 0.0], [0.5, 0.2], [0.9, 0.6]]
        """
        (a0, b0), (a, b) = self.centre_points, self.moving_pivots
        x, y, _ = self.poses[0]
        pts = {"A0": a0, "A": a, "B": b, "B0": b0, "P": (x, y)}
        body = _coupler_body(pts, "A", "B")
        return Linkage(
            pts,
            [("A0", "A"), body, ("B", "B0")],
            ["A0", "B0"],
            ("A0", "A"),
            name=name,
            output="P",
        )


def _poses(poses: Any) -> list[tuple[float, float, float]]:
    a = float_array("poses", poses, (2,))
    if a.shape[1] != 3:
        raise InputError(f"poses must be (x [m], y [m], angle [deg]) triples; got shape {a.shape}")
    if not 3 <= a.shape[0] <= 5:
        raise InputError(
            "motion generation needs 3, 4 or 5 poses (three by circumcentres, four by "
            f"Burmester's curves, five by Burmester's points); got {a.shape[0]}"
        )
    bad = np.argwhere(~np.isfinite(a))
    if bad.size:
        i, k = bad[0]
        raise InputError(f"poses[{i}][{k}] = {a[i, k]} is not finite")
    n = a.shape[0]
    for i, j in itertools.combinations(range(n), 2):
        same_place = math.hypot(a[i, 0] - a[j, 0], a[i, 1] - a[j, 1]) <= 1e-12 * (
            1 + float(np.abs(a[:, :2]).max())
        )
        same_angle = abs((a[i, 2] - a[j, 2] + 180) % 360 - 180) <= 1e-9
        if same_place and same_angle:
            raise InputError(
                f"poses[{i}] and poses[{j}] are coincident ({a[i, 0]:g}, {a[i, 1]:g}, "
                f"{a[i, 2]:g} deg): {n} distinct poses are needed"
            )
    return [(float(x), float(y), float(t)) for x, y, t in a]


def _rad(poses: list[tuple[float, float, float]]) -> list[tuple[float, float, float]]:
    return [(x, y, math.radians(t)) for x, y, t in poses]


def _candidate(poses: list[tuple[float, float, float]], uv1: Point, uv2: Point) -> MotionCandidate:
    return _from_tuple(poses, uv1, uv2, _core.motion_fourbar(_rad(poses), uv1, uv2))


def _from_tuple(
    poses: list[tuple[float, float, float]], uv1: Point, uv2: Point, tup: Any
) -> MotionCandidate:
    a0, b0, pa, pb, dims, th, direction, br, arc, t, in_order = tup
    a, b, c, d = dims
    ground = math.atan2(b0[1] - a0[1], b0[0] - a0[0])
    branches = tuple(int(x) for x in br)
    branch_defect = branches[0] == 0 or len(set(branches)) > 1
    order_defect = not (t[0] and in_order)
    kind, turns, _ = _core.fourbar_grashof(a, b, c, d)
    ok = t[0] and t[1] > 0.0 and t[2] < math.pi
    margins = Margins(
        grashof=kind,
        crank_turns=turns,
        transmission_min_deg=math.degrees(t[1]) if t[0] else math.nan,
        transmission_max_deg=math.degrees(t[2]) if t[0] else math.nan,
        branch_ok=bool(ok and not branch_defect),
        length_ratio=max(dims) / min(dims),
    )
    return MotionCandidate(
        poses=tuple(poses),
        circle_points=(_pt(uv1), _pt(uv2)),
        centre_points=(_pt(a0), _pt(b0)),
        moving_pivots=(_pt(pa[0]), _pt(pb[0])),
        lengths={"crank": a, "coupler": b, "rocker": c, "ground": d},
        crank_angles_deg=tuple(math.degrees(x) for x in th),
        direction=int(direction),
        branches=branches,
        branch_defect=branch_defect,
        order_defect=order_defect,
        working_arc_deg=(math.degrees(arc[0] + ground), math.degrees(arc[1] + ground)),
        margins=margins,
    )


def _pairs(
    poses: list[tuple[float, float, float]],
    dyads: list[tuple[Point, Point]],
    pairs: list[tuple[int, int]],
) -> list[MotionCandidate | str]:
    """Four-bars of pairs (crank, rocker) of dyads (circle point, centre) through
    the poses, in one kernel call: each a candidate or the reason it is none."""
    out: list[MotionCandidate | str] = []
    for (i, j), (tup, why) in zip(
        pairs, _core.motion_fourbars(_rad(poses), dyads, pairs), strict=True
    ):
        if tup is None:
            out.append(why or "no four-bar")
        else:
            out.append(_from_tuple(poses, dyads[i][0], dyads[j][0], tup))
    return out


def _pt(p: Sequence[float]) -> Point:
    return (float(p[0]), float(p[1]))


def _uv(name: str, value: Any) -> Point:
    try:
        u, v = value
    except (TypeError, ValueError):
        raise InputError(
            f"{name} must be a point (u, v) [m] of the coupler frame; got {value!r}"
        ) from None
    return (finite_number(f"{name}[0]", u, "[m]"), finite_number(f"{name}[1]", v, "[m]"))


def _rank(c: MotionCandidate) -> tuple[bool, float, float]:
    worst = c.margins.worst_transmission_deg
    return (not c.clean, -(worst if math.isfinite(worst) else -1.0), c.margins.length_ratio)


def motion_generation(
    poses: Sequence[Sequence[float]],
    *,
    circle_points: Sequence[Sequence[float]] | None = None,
    free_choices: Sequence[Sequence[float]] | None = None,
    grid: tuple[float, int] | None = None,
    keep: int = 10,
) -> list[MotionCandidate]:
    """Four-bars whose coupler takes three, four or five poses: candidates with
    their defects and margins, best first.

    A pose is (x [m], y [m], angle [deg]): where a point P of the coupler is and
    the angle of a line of the coupler through it. A circle point (u, v) in the
    coupler frame (u along that line from P, v to its left) takes one position
    per pose; if they lie on a circle, its centre is the centre point, the
    ground pivot of a link that keeps it there. Two such dyads (the crank's,
    then the rocker's) make a four-bar through the poses.

    * **Three poses:** every circle point has a centre (the circumcentre of
      its three positions); the family has four free numbers, the two circle
      points (``circle_points=``, or a ``grid=`` scan).
    * **Four poses:** the circle points lie on Burmester's circle-point curve
      (:func:`burmester_curves`); each dyad is one free number, the crank's
      rotation β from pose 1 (``free_choices=``), or a scan of dyads along the
      curves (``grid=``).
    * **Five poses:** at most four dyads, Burmester's points
      (:func:`burmester_points`); every pair of them is a candidate (at most
      six). None or one real point raises :class:`~cyclomech.InputError` ("no
      four-bar passes these five poses"), never an empty list.

    Parameters
    ----------
    poses : three to five (x, y, angle_deg)
        The poses, in the order the coupler must take them.
    circle_points : ((u1, v1), (u2, v2)), optional
        Three poses: the two moving pivots [m] in the coupler frame: one candidate.
    free_choices : ((beta1_deg, branch1), (beta2_deg, branch2)), optional
        Four poses: the crank's and the rocker's dyads on Burmester's curves,
        each by its rotation β [deg] from pose 1 to pose
        ``burmester_curves(poses).parameter_pose`` and its branch (±1): one
        candidate.
    grid : (extent_m, n), optional
        Otherwise a scan. Three poses: circle points on an n × n grid over
        [−extent, extent]² of the coupler frame around P, every pair of them
        (each pair once, the first as the crank's), ranked; n ≤ 15; default
        extent the poses' largest distance from the first (at least 1 mm),
        n = 7; pairs with no centre point (collinear positions: a slider; a
        pole) are left out. Four poses: n ≤ 200 dyads spread along Burmester's
        curves whose moving and ground pivots lie within ±extent of the first
        pose point, every pair; default extent twice the poses' spread, n = 24.
    keep : int
        How many ranked candidates a scan returns.

    Returns
    -------
    list of MotionCandidate
        Best first: clean candidates (no branch or order defect, no fold over the
        working arc) first; then the larger worst transmission angle; then the
        smaller link-length ratio.

    Raises
    ------
    InputError
        Fewer than three or more than five poses, coincident poses, a choice
        that does not fit the number of poses, a circle point whose three
        positions are collinear (its centre at infinity: that dyad would be a
        slider) or a pole, circle points sharing a centre point, five poses
        with fewer than two real Burmester points — or a scan leaving nothing.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> poses = [(0, 0, 0), (0.5, 0.2, 20), (0.9, 0.6, 45)]
    >>> best = cm.synthesis.motion_generation(poses, grid=(1.0, 5), keep=3)
    >>> len(best), best[0].clean
    (3, True)
    >>> sol = best[0].linkage().solve(np.radians(best[0].crank_angles_deg))
    >>> bool(np.allclose(sol["P"], [p[:2] for p in poses], atol=1e-9))
    True
    >>> four = cm.synthesis.motion_generation(poses + [(1.2, 1.1, 70)], keep=2)
    >>> len(four[0].crank_angles_deg)
    4
    """
    ps = _poses(poses)
    keep = count("keep", keep, what="candidates")
    if len(ps) > 3:
        from ._burmester import _five_poses, _four_poses

        if circle_points is not None:
            raise InputError(
                f"circle_points= is for three poses; with {len(ps)} the circle points lie on "
                "Burmester's curves: give free_choices= (four poses) or nothing"
            )
        if len(ps) == 4:
            return _four_poses(ps, free_choices, grid, keep)
        if free_choices is not None or grid is not None:
            raise InputError(
                "five poses leave no free choice: every pair of Burmester points is a "
                "candidate; drop free_choices= and grid="
            )
        return _five_poses(ps, keep)
    if free_choices is not None:
        raise InputError(
            "free_choices= is for four poses (dyads on Burmester's curves); with three "
            "give circle_points="
        )
    if circle_points is not None:
        if grid is not None:
            raise InputError("give circle_points= or grid=, not both")
        try:
            p1, p2 = circle_points
        except (TypeError, ValueError):
            raise InputError(
                f"circle_points must be ((u1, v1), (u2, v2)) [m]; got {circle_points!r}"
            ) from None
        return [_candidate(ps, _uv("circle_points[0]", p1), _uv("circle_points[1]", p2))]

    extent, n = _grid(grid, ps, scale=1.0, n=7, high=15, what="points per side")
    axis = np.linspace(-extent, extent, n)
    pts = [(float(u), float(v)) for u in axis for v in axis]
    found: list[MotionCandidate] = []
    for uv1, uv2 in itertools.combinations(pts, 2):
        try:
            found.append(_candidate(ps, uv1, uv2))
        except InputError:
            continue  # no centre point for this pair (slider, pole, shared centre)
    if not found:
        raise InputError(
            f"no pair of circle points on the {n} × {n} grid of ±{extent:g} m gives a four-bar "
            "through these poses; widen the grid or give circle_points="
        )
    found.sort(key=_rank)
    return found[:keep]


def _grid(
    grid: Any, ps: list[tuple[float, float, float]], *, scale: float, n: int, high: int, what: str
) -> tuple[float, int]:
    """A scan's ``grid = (extent_m, n)``, checked; default: ``scale`` times the poses'
    largest distance from the first (at least 1 mm), and ``n``."""
    if grid is None:
        spread = max(math.hypot(x - ps[0][0], y - ps[0][1]) for x, y, _ in ps)
        return scale * max(spread, 1e-3), n
    try:
        ext_v, n_v = grid
    except (TypeError, ValueError):
        raise InputError(f"grid must be (extent_m, n); got {grid!r}") from None
    return positive("grid[0]", ext_v, "[m]"), count("grid[1]", n_v, low=2, high=high, what=what)
