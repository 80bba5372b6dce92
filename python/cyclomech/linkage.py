"""Planar linkages: position analysis over crank-angle grids by Assur groups (seed 001).

A linkage is given as a drawn, assembled pose: points with coordinates [m], rigid
links by their joints, the ground joints and the driving crank. The pose fixes the
link dimensions and the assembly mode. :class:`Linkage` decomposes the topology
into Assur groups in solving order and compiles them for the Rust kernel, which
solves every crank angle with positions, velocity analogs d xy/dφ [m/rad] and
acceleration analogs d²xy/dφ² [m/rad²], exactly (no finite differences).

This version solves class II groups (RRR dyads) and further joints of rigid
bodies (coupler points) in closed form, and class III groups (a ternary link held
by three binary links, the knife drives of seed 001) by Newton continuation from
the drawn pose with the seed's bracketing as fallback. Sliders come next.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from . import _core
from ._arrays import float_array, threads_arg
from ._errors import InputError

__all__ = ["Linkage", "LinkageSolution"]

_DRIVER, _CIRCLES, _TRIAD = 0, 1, 2


@dataclass(frozen=True)
class LinkageSolution:
    """Positions and analogs of every point over a crank-angle grid.

    ``xy``, ``vel`` = d xy/dφ and ``acc`` = d² xy/dφ² have shape (N, P, 2), points
    in the order of ``names``; lengths in metres, φ the absolute crank angle [rad].
    ``ok[i]`` is False where the mechanism cannot be assembled (all its moving
    points NaN there); ``singular[i]`` is True at a dead centre of a dyad, where the
    analogs are infinite (NaN).
    """

    angles: npt.NDArray[np.float64]
    names: tuple[str, ...]
    xy: npt.NDArray[np.float64]
    vel: npt.NDArray[np.float64]
    acc: npt.NDArray[np.float64]
    ok: npt.NDArray[np.bool_]
    singular: npt.NDArray[np.bool_]

    def index(self, name: str) -> int:
        """Column of point ``name`` in ``xy``.

        >>> import cyclomech as cm
        >>> lk = cm.Linkage({"A": (0, 0), "B": (1, 0)}, [("A", "B")], ["A"], ("A", "B"))
        >>> lk.solve([0.0]).index("B")
        1
        """
        try:
            return self.names.index(name)
        except ValueError:
            raise InputError(f"no point {name!r}; the points are {', '.join(self.names)}") from None

    def __getitem__(self, name: str) -> npt.NDArray[np.float64]:
        """Positions of one point, shape (N, 2) [m]."""
        return self.xy[:, self.index(name)]

    def link_angle(
        self, a: str, b: str
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """Angle of the line a→b [rad] and its first and second analogs [rad/rad, rad/rad²].

        θ = atan2(d), θ' = d × d' / |d|², θ'' = d × d'' / |d|² − 2 (d·d')(d × d') / |d|⁴,
        with d = b − a; vectorised over the grid.

        >>> import numpy as np, cyclomech as cm
        >>> lk = cm.Linkage({"A": (0, 0), "B": (1, 0)}, [("A", "B")], ["A"], ("A", "B"))
        >>> theta, dtheta, ddtheta = lk.solve([0.0, 0.5]).link_angle("A", "B")
        >>> np.round(theta, 12).tolist(), np.round(dtheta, 12).tolist()
        ([0.0, 0.5], [1.0, 1.0])
        """
        i, j = self.index(a), self.index(b)
        d = self.xy[:, j] - self.xy[:, i]
        dv = self.vel[:, j] - self.vel[:, i]
        da = self.acc[:, j] - self.acc[:, i]
        n2 = np.einsum("ij,ij->i", d, d)
        cross_v = d[:, 0] * dv[:, 1] - d[:, 1] * dv[:, 0]
        cross_a = d[:, 0] * da[:, 1] - d[:, 1] * da[:, 0]
        dot_v = np.einsum("ij,ij->i", d, dv)
        theta = np.arctan2(d[:, 1], d[:, 0])
        return theta, cross_v / n2, cross_a / n2 - 2.0 * dot_v * cross_v / n2**2


class Linkage:
    """A planar linkage given by a drawn, assembled pose.

    Parameters
    ----------
    points : name → (x, y) [m] of an assembled pose. The pose fixes every link's
        dimensions (unless ``lengths`` overrides a distance) and the assembly mode.
    links : rigid bodies, each by its joints; a body with 3+ joints is rigid
        (a ternary link with a coupler point, …).
    ground : the fixed joints.
    driver : ``(pivot, tip)``, the crank; its absolute angle is the input.
    lengths : optional ``{(a, b): length}`` [m] for pairs of joints on one link.
    sliders : prismatic joints; not in this version (refused with a clear error).

    Examples
    --------
    A crank-rocker: crank AB, coupler BC, rocker CD, ground A and D.

    >>> import numpy as np, cyclomech as cm
    >>> lk = cm.Linkage(
    ...     points={"A": (0, 0), "B": (1, 0), "C": (3.5, 2.5), "D": (4, 0)},
    ...     links=[("A", "B"), ("B", "C"), ("C", "D")], ground=["A", "D"], driver=("A", "B"))
    >>> lk.structure
    [('driver', ('B',)), ('II', ('C',))]
    >>> sol = lk.solve(np.linspace(0, 2 * np.pi, 361))
    >>> bool(sol.ok.all()), round(float(np.linalg.norm(sol["C"][0] - sol["B"][0])), 12)
    (True, 3.535533905933)
    """

    def __init__(
        self,
        points: Mapping[str, Sequence[float]],
        links: Iterable[Sequence[str]],
        ground: Iterable[str],
        driver: tuple[str, str],
        lengths: Mapping[tuple[str, str], float] | None = None,
        sliders: Mapping[str, Any] | None = None,
    ) -> None:
        if sliders:
            raise InputError(
                f"sliders = {dict(sliders)!r}: prismatic joints are not solved by this version "
                "of cyclomech; model the mechanism with revolute joints only for now"
            )
        self._points = _points(points)
        self._names = tuple(self._points)
        self._links = _links(links, self._points)
        self._ground = _ground(ground, self._points)
        self._driver = _driver(driver, self._points, self._ground, self._links)
        self._lengths = _lengths(lengths, self._links)
        self._check_mobility()
        self._structure, self._program, self.drawn_angle = self._compile()

    # ---------------------------------------------------------------- queries
    @property
    def names(self) -> tuple[str, ...]:
        """Point names, in the order of the solution's columns."""
        return self._names

    @property
    def structure(self) -> list[tuple[str, tuple[str, ...]]]:
        """The Assur-group decomposition in solving order.

        ``("driver", (tip,))`` for the crank, ``("II", (p,))`` for a dyad placing
        joint p, ``("point", (p,))`` for a further joint of a rigid body already
        placed (a coupler point), ``("III", (j0, j1, j2))`` for a class III group.
        """
        return list(self._structure)

    def length(self, a: str, b: str) -> float:
        """Distance [m] between joints a and b of one link (drawn, or overridden).

        >>> import cyclomech as cm
        >>> pts = {"A": (0, 0), "B": (3, 4)}
        >>> cm.Linkage(pts, [("A", "B")], ["A"], ("A", "B")).length("A", "B")
        5.0
        """
        key = (a, b) if (a, b) in self._lengths else (b, a)
        if key in self._lengths:
            return self._lengths[key]
        pa, pb = self._points[a], self._points[b]
        return math.hypot(pb[0] - pa[0], pb[1] - pa[1])

    # ---------------------------------------------------------------- solving
    def solve(self, angles: npt.ArrayLike, n_threads: int | None = None) -> LinkageSolution:
        """Solve at absolute crank angles [rad] (any shape-(N,) grid), in parallel.

        Returns a :class:`LinkageSolution`. Angles where the linkage cannot be
        assembled are ``ok = False`` with NaN coordinates, not an error.

        >>> import cyclomech as cm
        >>> lk = cm.Linkage({"A": (0, 0), "B": (2, 0), "C": (3, 1.5), "D": (3, 0)},
        ...                 [("A", "B"), ("B", "C"), ("C", "D")], ["A", "D"], ("A", "B"))
        >>> lk.solve([0.0, 3.14159]).ok.tolist()    # the crank is too long to turn
        [True, False]
        """
        a = float_array("angles", angles)
        xy, vel, acc, ok, singular = self._program.solve(a, n_threads=threads_arg(n_threads))
        return LinkageSolution(a, self._names, xy, vel, acc, ok, singular)

    def __reduce__(self) -> tuple[Any, ...]:
        return (
            Linkage,
            (self._points, self._links, sorted(self._ground), self._driver, self._lengths),
        )

    def __repr__(self) -> str:
        n, k = len(self._names), len(self._links)
        return f"Linkage(points={n}, links={k}, structure={self._structure})"

    # ---------------------------------------------------------------- compiling
    def _check_mobility(self) -> None:
        """Gruebler–Kutzbach: M = 3·(moving links) − 2·(revolute joints) must be 1."""
        moving = [ln for ln in self._links if not set(ln) <= self._ground]
        joints = 0
        for p in self._names:
            k = sum(p in ln for ln in moving) + (p in self._ground)
            joints += max(k - 1, 0)
        mobility = 3 * len(moving) - 2 * joints
        if mobility < 1:
            raise InputError(
                f"the linkage is over-constrained: mobility M = 3·{len(moving)} links − "
                f"2·{joints} joints = {mobility} < 1, so it cannot move; remove a link "
                "or a joint (a redundant link makes a truss)"
            )
        if mobility > 1:
            raise InputError(
                f"the linkage is under-constrained: mobility M = 3·{len(moving)} links − "
                f"2·{joints} joints = {mobility}, but one crank fixes only one degree of "
                "freedom; add a link, or ground a joint"
            )

    def _compile(self) -> tuple[list[tuple[str, tuple[str, ...]]], Any, float]:
        idx = {n: i for i, n in enumerate(self._names)}
        pivot, tip = self._driver
        # Joints that share a link are at fixed distances: the constraint graph.
        near: dict[str, dict[str, int]] = {n: {} for n in self._names}
        for k, ln in enumerate(self._links):
            for a in ln:
                for b in ln:
                    if a != b:
                        near[a].setdefault(b, k)
        known = set(self._ground) | {tip}
        structure: list[tuple[str, tuple[str, ...]]] = [("driver", (tip,))]
        # Rows of the compiled program: 6 indices and 7 dimensions each (see _core).
        kind = [_DRIVER]
        rows: list[tuple[int, ...]] = [(idx[pivot], idx[tip], 0, 0, 0, 0)]
        dims: list[tuple[float, ...]] = [(self.length(pivot, tip), 0, 0, 0, 0, 0, 0)]
        scale = max(self.length(a, b) for ln in self._links for a in ln for b in ln if a != b)
        pending = [n for n in self._names if n not in known]
        while pending:
            placed: list[str] = []
            for p in pending:
                anchors = [q for q in near[p] if q in known]
                if len(anchors) < 2:
                    continue
                # The best-conditioned pair: the largest area with p in the drawn pose.
                a, b = max(
                    ((a, b) for i, a in enumerate(anchors) for b in anchors[i + 1 :]),
                    key=lambda ab: abs(_cross(self._points, ab[0], ab[1], p)),
                )
                area = _cross(self._points, a, b, p)
                if abs(area) <= 1e-9 * scale * scale:
                    raise InputError(
                        f"joint {p!r} is drawn on the line through {a!r} and {b!r}, so the "
                        "assembly mode (which side of that line) is undefined; draw the pose "
                        "with the mechanism off that dead centre"
                    )
                label = "II" if near[p][a] != near[p][b] else "point"
                structure.append((label, (p,)))
                kind.append(_CIRCLES)
                rows.append((idx[a], idx[b], idx[p], 0, 0, 0))
                sign = math.copysign(1.0, area)
                dims.append((self.length(a, p), self.length(b, p), sign, 0, 0, 0, 0))
                placed = [p]
                break
            if not placed:
                ends, joints = self._triad(known, pending)
                j0, j1, j2 = joints
                structure.append(("III", (j0, j1, j2)))
                kind.append(_TRIAD)
                rows.append(tuple(idx[q] for q in (*ends, *joints)))
                arms = [self.length(a, j) for a, j in zip(ends, joints, strict=True)]
                sides = [self.length(j0, j1), self.length(j1, j2), self.length(j2, j0)]
                turn = math.copysign(1.0, _cross(self._points, j0, j1, j2))
                dims.append((*arms, *sides, turn))
                placed = list(joints)
            for q in placed:
                known.add(q)
                pending.remove(q)
        fixed = sorted(self._ground)
        pv, tp = self._points[pivot], self._points[tip]
        drawn = math.atan2(tp[1] - pv[1], tp[0] - pv[0])
        program = _core.LinkageProgram(
            len(self._names),
            np.array([idx[g] for g in fixed], dtype=np.int64),
            np.array([self._points[g] for g in fixed], dtype=np.float64).reshape(-1, 2),
            np.array(kind, dtype=np.int64),
            np.array(rows, dtype=np.int64).reshape(-1, 6),
            np.array(dims, dtype=np.float64).reshape(-1, 7),
            drawn,
            np.array([self._points[n] for n in self._names], dtype=np.float64),
        )
        return structure, program, drawn

    def _triad(self, known: set[str], pending: list[str]) -> tuple[list[str], list[str]]:
        """A class III group among the pending joints: a link with exactly three
        pending joints, each joined by another link to exactly one placed joint."""
        for k, ln in enumerate(self._links):
            joints = [q for q in ln if q in pending]
            if len(joints) != 3:
                continue
            ends = []
            for j in joints:
                outside = {
                    q
                    for m, other in enumerate(self._links)
                    if m != k and j in other
                    for q in other
                    if q in known
                }
                if len(outside) != 1:
                    break
                ends.append(outside.pop())
            else:
                if abs(_cross(self._points, *joints)) <= 1e-12:
                    raise InputError(
                        f"the ternary link {ln!r} is drawn with {', '.join(joints)} on one "
                        "line; a class III group needs a triangle"
                    )
                return ends, joints
        raise InputError(
            f"joints {', '.join(map(repr, pending))} cannot be placed by class II or class "
            "III groups: none of them is joined by links to two joints already placed, and no "
            "link with three of them is held by one link each to placed joints"
        )


def _cross(points: Mapping[str, tuple[float, float]], a: str, b: str, p: str) -> float:
    pa, pb, pp = points[a], points[b], points[p]
    return (pb[0] - pa[0]) * (pp[1] - pa[1]) - (pb[1] - pa[1]) * (pp[0] - pa[0])


def _points(points: Any) -> dict[str, tuple[float, float]]:
    if not isinstance(points, Mapping) or not points:
        raise InputError(f"points must map joint names to (x, y) [m]; got {points!r}")
    out = {}
    for name, xy in points.items():
        if not isinstance(name, str) or not name:
            raise InputError(f"points: joint names must be non-empty strings; got {name!r}")
        try:
            x, y = (float(v) for v in xy)
        except (TypeError, ValueError):
            raise InputError(f"points[{name!r}] must be (x, y) in metres; got {xy!r}") from None
        if not (math.isfinite(x) and math.isfinite(y)):
            raise InputError(f"points[{name!r}] = {xy!r} must be finite coordinates [m]")
        out[name] = (x, y)
    return out


def _links(links: Any, points: Mapping[str, Any]) -> list[tuple[str, ...]]:
    out = []
    for k, ln in enumerate(links):
        if isinstance(ln, str) or not isinstance(ln, Sequence) or len(ln) < 2:
            raise InputError(f"links[{k}] = {ln!r} must list at least two joints")
        if len(set(ln)) != len(ln):
            raise InputError(f"links[{k}] = {ln!r} lists a joint twice")
        for p in ln:
            if p not in points:
                raise InputError(
                    f"links[{k}] = {ln!r}: no point {p!r}; known points are {', '.join(points)}"
                )
        out.append(tuple(ln))
    if not out:
        raise InputError("links must list at least the crank")
    for p in points:
        if not any(p in ln for ln in out):
            raise InputError(f"point {p!r} is on no link; join it to the mechanism or remove it")
    return out


def _ground(ground: Any, points: Mapping[str, Any]) -> set[str]:
    g = {ground} if isinstance(ground, str) else set(ground)
    for p in g:
        if p not in points:
            raise InputError(f"ground: no point {p!r}; known points are {', '.join(points)}")
    if not g:
        raise InputError("ground must list at least the crank's pivot")
    return g


def _driver(
    driver: Any, points: Mapping[str, Any], ground: set[str], links: list[tuple[str, ...]]
) -> tuple[str, str]:
    if not (isinstance(driver, tuple | list) and len(driver) == 2):
        raise InputError(f"driver must be (pivot, tip); got {driver!r}")
    pivot, tip = driver
    for p in (pivot, tip):
        if p not in points:
            raise InputError(f"driver = {driver!r}: no point {p!r}")
    if pivot not in ground:
        raise InputError(f"driver = {driver!r}: the crank's pivot {pivot!r} must be a ground joint")
    if tip in ground:
        raise InputError(f"driver = {driver!r}: the crank's tip {tip!r} cannot be a ground joint")
    if not any(pivot in ln and tip in ln for ln in links):
        raise InputError(f"driver = {driver!r}: no link joins {pivot!r} and {tip!r}")
    return (pivot, tip)


def _lengths(lengths: Any, links: list[tuple[str, ...]]) -> dict[tuple[str, str], float]:
    out: dict[tuple[str, str], float] = {}
    for (a, b), value in (lengths or {}).items():
        if not any(a in ln and b in ln for ln in links):
            raise InputError(f"lengths[{(a, b)!r}]: {a!r} and {b!r} are not joints of one link")
        try:
            v = float(value)
        except (TypeError, ValueError):
            raise InputError(f"lengths[{(a, b)!r}] = {value!r} must be a length [m]") from None
        if not (math.isfinite(v) and v > 0):
            raise InputError(f"lengths[{(a, b)!r}] = {value!r} must be a positive length [m]")
        out[(a, b)] = v
    return out
