"""Motion generation through four and five poses: Burmester's
circle-point and centre-point curves of four poses, Burmester's points of five,
and the four-bars made of their dyads. The kernels and the derivation are in
``rust/core/src/synthesis/burmester.rs``.
"""

from __future__ import annotations

import itertools
import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from .. import _core
from .._arrays import count, finite_number
from .._errors import CyclomechWarning, InputError
from ._motion import MotionCandidate, Point, _grid, _pairs, _poses, _rad, _rank

__all__ = ["BurmesterCurves", "BurmesterPoint", "burmester_curves", "burmester_points"]


@dataclass(frozen=True, eq=False)
class BurmesterCurves:
    """Burmester's curves of four poses (:func:`burmester_curves`): every point is
    a dyad — a circle point of the coupler whose four positions lie on a circle
    about its centre point.

    The points are sampled along the curves' parameter, the crank's rotation β
    [deg] from pose 1 to pose ``parameter_pose``; each β gives two dyads or none
    (``branch`` ±1). The arrays are polylines with a NaN row between them; they
    break where a curve runs off to infinity (a dyad that would be a slider).

    Attributes
    ----------
    poses : four (x [m], y [m], angle [deg])
        The poses.
    parameter_pose : int
        The pose (numbered from 1: 2, 3 or 4) whose crank rotation is β.
    beta_deg : ndarray, shape (n,)
        β at each point [deg].
    branch : ndarray, shape (n,)
        The branch (+1 or −1) of each point.
    circle_points : ndarray, shape (n, 2)
        The circle-point curve in the coupler frame [m] (u along the pose
        angle from the pose point, v to its left).
    centre_points : ndarray, shape (n, 2)
        The centre-point curve in the fixed frame [m].

    Examples
    --------
    >>> import cyclomech as cm
    >>> poses = [(0, 0, 0), (0.5, 0.2, 20), (0.9, 0.6, 45), (1.2, 1.1, 70)]
    >>> curves = cm.synthesis.burmester_curves(poses, samples=256)
    >>> curves.circle_points.shape[1], curves.parameter_pose in (2, 3, 4)
    (2, True)
    """

    poses: tuple[tuple[float, float, float], ...]
    parameter_pose: int
    beta_deg: npt.NDArray[np.float64]
    branch: npt.NDArray[np.float64]
    circle_points: npt.NDArray[np.float64]
    centre_points: npt.NDArray[np.float64]

    def moving_points(self) -> npt.NDArray[np.float64]:
        """The circle-point curve drawn in the first pose (fixed frame) [m], shape (n, 2).

        Examples
        --------
        >>> import cyclomech as cm
        >>> poses = [(0, 0, 0), (0.5, 0.2, 20), (0.9, 0.6, 45), (1.2, 1.1, 70)]
        >>> cm.synthesis.burmester_curves(poses, samples=64).moving_points().shape[1]
        2
        """
        x, y, t = self.poses[0]
        c, s = math.cos(math.radians(t)), math.sin(math.radians(t))
        u, v = self.circle_points[:, 0], self.circle_points[:, 1]
        return np.column_stack([x + c * u - s * v, y + s * u + c * v])

    def dyad(self, beta_deg: float, branch: int) -> tuple[Point, Point] | None:
        """The dyad at crank rotation ``beta_deg`` [deg] on ``branch`` (±1), in closed
        form (not interpolated): (circle point (u, v) [m, coupler frame], centre
        point (x, y) [m]), or None where that branch has no dyad.

        Examples
        --------
        >>> import cyclomech as cm
        >>> poses = [(0, 0, 0), (0.5, 0.2, 20), (0.9, 0.6, 45), (1.2, 1.1, 70)]
        >>> curves = cm.synthesis.burmester_curves(poses, samples=64)
        >>> d = curves.dyad(float(curves.beta_deg[0]), int(curves.branch[0]))
        >>> d is not None
        True
        """
        b = finite_number("beta_deg", beta_deg, "[deg]")
        if isinstance(branch, bool) or branch not in (1, -1):
            raise InputError(f"branch must be +1 or -1; got {branch!r}")
        d = _core.burmester_dyad(_rad(list(self.poses)), math.radians(b), float(branch))
        return None if d is None else ((d[0][0], d[0][1]), (d[1][0], d[1][1]))


@dataclass(frozen=True)
class BurmesterPoint:
    """A Burmester point of five poses (:func:`burmester_points`): a dyad through all five.

    Attributes
    ----------
    circle_point : (u, v)
        The circle point in the coupler frame [m].
    centre_point : (x, y)
        Its centre point [m].
    radius_m : float
        The link's length |A − A0| [m].
    residual_m : float
        The largest difference over the five poses between a position's
        distance from the centre and the radius [m].

    Examples
    --------
    >>> import cyclomech as cm
    >>> p = cm.synthesis.BurmesterPoint((0.0, 0.0), (1.0, 0.0), 1.0, 0.0)
    >>> p.radius_m
    1.0
    """

    circle_point: Point
    centre_point: Point
    radius_m: float
    residual_m: float


def burmester_curves(poses: Sequence[Sequence[float]], *, samples: int = 2048) -> BurmesterCurves:
    """Burmester's circle-point and centre-point curves of four poses.

    A pose is (x [m], y [m], angle [deg]) as in :func:`motion_generation`.
    Every point of the circle-point curve (coupler frame) is a circle point
    whose four positions lie on a circle; the matching point of the
    centre-point curve (fixed frame) is that circle's centre. Both are cubics,
    traced in closed form along the crank's rotation β from pose 1 to pose
    ``parameter_pose`` (Erdman & Sandor's compatibility linkage; the
    derivation is in ``rust/core/src/synthesis/burmester.rs``).

    Parameters
    ----------
    poses : four (x, y, angle_deg)
        The poses.
    samples : int
        Values of β per branch over a turn (16 to 2²⁰).

    Returns
    -------
    BurmesterCurves
        The curves as NaN-separated polylines.

    Raises
    ------
    InputError
        Not four poses, coincident or non-finite poses, or poses so special
        that β cannot parametrise the curves.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> poses = [(0, 0, 0), (0.5, 0.2, 20), (0.9, 0.6, 45), (1.2, 1.1, 70)]
    >>> c = cm.synthesis.burmester_curves(poses, samples=512)
    >>> ok = ~np.isnan(c.beta_deg)
    >>> bool(ok.sum() > 100)
    True
    """
    ps = _poses(poses)
    if len(ps) != 4:
        raise InputError(f"burmester_curves needs exactly 4 poses; got {len(ps)}")
    n = count("samples", samples, low=16, high=1 << 20, what="samples per branch")
    p, rows = _core.burmester_curves(_rad(ps), n)
    a = np.array(rows, dtype=np.float64).reshape(-1, 6)
    return BurmesterCurves(
        poses=tuple(ps),
        parameter_pose=int(p),
        beta_deg=np.degrees(a[:, 0]),
        branch=a[:, 1].copy(),
        circle_points=a[:, 2:4].copy(),
        centre_points=a[:, 4:6].copy(),
    )


def burmester_points(poses: Sequence[Sequence[float]]) -> list[BurmesterPoint]:
    """Burmester's points of five poses: every dyad (circle point and centre point)
    whose circle point's five positions lie on one circle.

    There are at most four, real in pairs (0, 2 or 4): where the circle-point
    curves of poses {1, 2, 3, 4} and {1, 2, 3, 5} meet, other than at the
    poles. Each is bracketed by a sign change along the first curve, traced
    densely in closed form, refined by bisection and polished by Newton's
    method on the five circle equations (no search from guesses).

    **Near-degenerate cases.** A root is kept only if every pose's distance
    from the centre equals the radius to 1e-9 of (radius + the poses' spread);
    roots at a pole (two positions closer than 1e-7 spreads), at infinity
    (beyond 1e6 spreads: a slider) or where the curve only passed through
    infinity are dropped; roots closer than 1e-5 of (the spread + their
    distance from the first pose point) are one. A double root
    (the curves tangent) has no sign change and may be missed: it is the
    boundary between two real pairs and none. If the count found is odd, the
    trace is repeated 16 times denser; an odd count after that warns
    (:class:`cyclomech.CyclomechWarning`).

    An empty list is a valid answer (no revolute-revolute dyad passes the five
    poses); :func:`motion_generation` raises :class:`~cyclomech.InputError`
    then rather than returning nothing.

    Parameters
    ----------
    poses : five (x [m], y [m], angle [deg])
        The poses, as in :func:`motion_generation`.

    Returns
    -------
    list of BurmesterPoint
        Sorted by the circle point's u, then v.

    Raises
    ------
    InputError
        Not five poses, coincident or non-finite poses.

    Examples
    --------
    >>> import cyclomech as cm
    >>> poses = [(0, 0, 0), (0.5, 0.2, 20), (0.9, 0.6, 45), (1.2, 1.1, 70), (1.3, 1.6, 80)]
    >>> pts = cm.synthesis.burmester_points(poses)
    >>> len(pts) in (0, 2, 4), all(p.residual_m < 1e-9 for p in pts)
    (True, True)
    """
    ps = _poses(poses)
    if len(ps) != 5:
        raise InputError(f"burmester_points needs exactly 5 poses; got {len(ps)}")
    rows, parity_ok = _core.burmester_points(_rad(ps))
    if not parity_ok:
        warnings.warn(
            f"burmester_points found {len(rows)} points, an odd number: a root was lost "
            "where two are nearly one (a near-tangency of Burmester's curves); the poses "
            "are near the boundary between two real points and none",
            CyclomechWarning,
            stacklevel=2,
        )
    return [
        BurmesterPoint((float(a[0]), float(a[1])), (float(c[0]), float(c[1])), float(r), float(res))
        for a, c, r, res in rows
    ]


def _best(found: list[MotionCandidate | str], keep: int, what: str) -> list[MotionCandidate]:
    cands = [c for c in found if isinstance(c, MotionCandidate)]
    if not cands:
        why = next((c for c in found if isinstance(c, str)), "no pair")
        raise InputError(f"{what} gives no four-bar: {why}")
    cands.sort(key=_rank)
    return cands[:keep]


def _four_poses(
    ps: list[tuple[float, float, float]],
    free_choices: Any,
    grid: tuple[float, int] | None,
    keep: int,
) -> list[MotionCandidate]:
    if free_choices is not None:
        if grid is not None:
            raise InputError("give free_choices= or grid=, not both")
        try:
            (b1, s1), (b2, s2) = free_choices
        except (TypeError, ValueError):
            raise InputError(
                "free_choices must be ((beta_deg, branch), (beta_deg, branch)): the crank's and "
                f"the rocker's rotation from pose 1 on Burmester's curves; got {free_choices!r}"
            ) from None
        dyads = []
        for k, (b, s) in enumerate(((b1, s1), (b2, s2))):
            beta = finite_number(f"free_choices[{k}][0]", b, "[deg]")
            if isinstance(s, bool) or s not in (1, -1):
                raise InputError(f"free_choices[{k}][1] (the branch) must be +1 or -1; got {s!r}")
            d = _core.burmester_dyad(_rad(ps), math.radians(beta), float(s))
            if d is None:
                raise InputError(
                    f"free_choices[{k}] = ({beta:g} deg, {s:+d}): Burmester's curves have no "
                    "dyad there (the compatibility linkage does not assemble); take beta_deg "
                    "and branch from a point of burmester_curves(poses)"
                )
            dyads.append(d)
        return _best(_pairs(ps, dyads, [(0, 1)]), keep, f"free_choices={free_choices!r}")
    extent, n = _grid(grid, ps, scale=2.0, n=24, high=200, what="dyads on the curves")
    curves = burmester_curves(ps, samples=4096)
    x0, y0 = ps[0][0], ps[0][1]
    near = np.all(np.abs(curves.moving_points() - (x0, y0)) <= extent, axis=1) & np.all(
        np.abs(curves.centre_points - (x0, y0)) <= extent, axis=1
    )
    idx = np.flatnonzero(near)
    if idx.size < 2:
        raise InputError(
            f"Burmester's curves of these poses have fewer than two dyads within ±{extent:g} m "
            "of the first pose point; widen grid=(extent_m, n)"
        )
    pick = idx[np.unique(np.linspace(0, idx.size - 1, n).round().astype(int))]
    dyads = [
        (
            (float(curves.circle_points[i, 0]), float(curves.circle_points[i, 1])),
            (float(curves.centre_points[i, 0]), float(curves.centre_points[i, 1])),
        )
        for i in pick
    ]
    pairs = list(itertools.combinations(range(len(dyads)), 2))
    return _best(_pairs(ps, dyads, pairs), keep, f"the scan of {len(dyads)} dyads")


def _five_poses(ps: list[tuple[float, float, float]], keep: int) -> list[MotionCandidate]:
    pts = burmester_points(ps)
    if len(pts) < 2:
        raise InputError(
            f"no four-bar passes these five poses: they have {len(pts)} real Burmester points "
            "(a four-bar needs two); move a pose, or use four poses and choose on "
            "Burmester's curves"
        )
    dyads = [(p.circle_point, p.centre_point) for p in pts]
    pairs = list(itertools.combinations(range(len(dyads)), 2))
    return _best(_pairs(ps, dyads, pairs), keep, "every pair of Burmester points")
