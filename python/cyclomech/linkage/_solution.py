"""A solved linkage (:class:`LinkageSolution`): positions, velocity and
acceleration analogs of its points over a crank-angle grid."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from .._arrays import out_array
from .._errors import InputError

__all__ = ["LinkageSolution"]

#: The arrays of a solution, in the kernel's order, and what each holds.
_OUT_FIELDS = {
    "xy": "positions [m]",
    "vel": "velocity analogs d xy/dφ [m/rad]",
    "acc": "acceleration analogs d²xy/dφ² [m/rad²]",
    "ok": "assembled flags",
    "singular": "dead-centre flags",
    "branch_change": "branch-change flags",
}


@dataclass(frozen=True)
class LinkageSolution:
    """Positions and analogs of the solved points over a crank-angle grid.

    Built by :meth:`Linkage.solve` and :func:`solve_geometries`; each parameter is
    kept as the attribute of the same name. Lengths in metres, φ the absolute crank
    angle [rad]. For a :func:`solve_geometries` over K geometries the arrays get a
    leading axis K: positions and analogs (K, N, M, 2), the flags (K, N).
    ``solution[name]`` gives one point's positions, shape (N, 2) (or (K, N, 2))
    [m].

    Class III groups are walked from the drawn pose outwards, the short way: an
    angle is first moved by whole turns into half a turn of the drawn angle (θ and
    θ + 2πn are one crank position and get one pose). The walk follows the drawn
    branch while Newton from its predictor stays near it and no group's Jacobian
    determinant changes sign. Where the branch ends (a fold, or the mechanism stops
    assembling) the walk does not jump silently: each later angle is re-acquired by
    the seed's bracketing, on the drawn assembly mode (the determinant's sign at
    the drawn pose) nearest the last pose; the first angle re-acquired is flagged
    ``branch_change``, angles where nothing assembles are ``ok = False``.

    A drawn branch that spans more than a turn (it folds at 247° going up from the
    drawing and at −129° going down, say) has two poses at the angles of the
    overlap; the short way decides which, so a grid wider than half a turn shows
    the fold *going down* inside it (at 231° in that example), flagged, although
    a crank turned up from the drawing would pass 231° regularly and fold at 247°.
    That flag is a real fold of the branch as walked, not a regular pose left
    (checked against an independent Newton continuation in
    ``tests/linkage/test_class3_branch.py``); to follow the crank one way past half a
    turn, draw the linkage nearer the angles of interest.

    Parameters
    ----------
    angles : ndarray of float, shape (N,)
        The absolute crank angles φ [rad].
    names : tuple of str
        The solved points, in the order of the arrays' point axis (M).
    xy : ndarray of float, shape (N, M, 2)
        The positions [m].
    vel : ndarray of float, shape (N, M, 2), or None
        The velocity analogs d xy/dφ [m/rad]; None when solved with
        ``analogs=False``.
    acc : ndarray of float, shape (N, M, 2), or None
        The acceleration analogs d² xy/dφ² [m/rad²]; None when solved with
        ``analogs=False``.
    ok : ndarray of bool, shape (N,)
        False where the mechanism cannot be assembled (its points NaN there).
    singular : ndarray of bool, shape (N,)
        True at a dead centre of a group, where the analogs are infinite (NaN).
    branch_change : ndarray of bool, shape (N,)
        True where the pose of a class III group is not continuous with the one
        solved before it.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> from cyclomech.linkage import presets
    >>> lk = presets.burg_trimmer()
    >>> sol = lk.solve(np.radians([170.0, 170.0 + 360.0]))
    >>> bool(np.allclose(sol["E"][0], sol["E"][1], atol=1e-12)), sol.branch_change.tolist()
    (True, [False, False])
    """

    angles: npt.NDArray[np.float64]
    names: tuple[str, ...]
    xy: npt.NDArray[np.float64]
    vel: npt.NDArray[np.float64] | None
    acc: npt.NDArray[np.float64] | None
    ok: npt.NDArray[np.bool_]
    singular: npt.NDArray[np.bool_]
    branch_change: npt.NDArray[np.bool_]

    def index(self, name: str) -> int:
        """Column of point ``name`` in ``xy``.

        Parameters
        ----------
        name : str
            A solved point's name.

        Returns
        -------
        int
            Its index on the point axis of ``xy``, ``vel`` and ``acc``.

        Raises
        ------
        InputError
            If the solution has no such point.

        Examples
        --------
        >>> import cyclomech as cm
        >>> lk = cm.Linkage({"A": (0, 0), "B": (1, 0)}, [("A", "B")], ["A"], ("A", "B"))
        >>> lk.solve([0.0]).index("B")
        1
        """
        try:
            return self.names.index(name)
        except ValueError:
            raise InputError(
                f"no point {name!r} in this solution; its points are {', '.join(self.names)}"
            ) from None

    def __getitem__(self, name: str) -> npt.NDArray[np.float64]:
        """Positions of one point, shape (N, 2) (or (K, N, 2) for K geometries) [m]."""
        return self.xy[..., self.index(name), :]

    def _analogs(self) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        if self.vel is None or self.acc is None:
            raise InputError("this solution has no analogs: solve with analogs=True")
        return self.vel, self.acc

    def link_angle(
        self, a: str, b: str
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64]]:
        """Angle of the line a→b [rad] and its first and second analogs [rad/rad, rad/rad²].

        θ = atan2(d), θ' = d × d' / |d|², θ'' = d × d'' / |d|² − 2 (d·d')(d × d') / |d|⁴,
        with d = b − a; vectorised over the grid.

        Parameters
        ----------
        a : str
            The point the line starts at.
        b : str
            The point it points to.

        Returns
        -------
        theta : ndarray of float, shape (N,) or (K, N)
            The angle θ of a→b [rad], in [−π, π] (``numpy.arctan2``).
        dtheta : ndarray of float, shape (N,) or (K, N)
            Its first analog θ' = dθ/dφ [rad/rad].
        ddtheta : ndarray of float, shape (N,) or (K, N)
            Its second analog θ'' = d²θ/dφ² [rad/rad²].

        Raises
        ------
        InputError
            If a point is not in the solution, or it was solved without analogs.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> lk = cm.Linkage({"A": (0, 0), "B": (1, 0)}, [("A", "B")], ["A"], ("A", "B"))
        >>> theta, dtheta, ddtheta = lk.solve([0.0, 0.5]).link_angle("A", "B")
        >>> np.round(theta, 12).tolist(), np.round(dtheta, 12).tolist()
        ([0.0, 0.5], [1.0, 1.0])
        """
        vel, acc = self._analogs()
        i, j = self.index(a), self.index(b)
        d = self.xy[..., j, :] - self.xy[..., i, :]
        dv = vel[..., j, :] - vel[..., i, :]
        da = acc[..., j, :] - acc[..., i, :]
        n2 = d[..., 0] ** 2 + d[..., 1] ** 2
        cross_v = d[..., 0] * dv[..., 1] - d[..., 1] * dv[..., 0]
        cross_a = d[..., 0] * da[..., 1] - d[..., 1] * da[..., 0]
        dot_v = d[..., 0] * dv[..., 0] + d[..., 1] * dv[..., 1]
        theta = np.arctan2(d[..., 1], d[..., 0])
        return theta, cross_v / n2, cross_a / n2 - 2.0 * dot_v * cross_v / n2**2

    def stroke(self, point: str) -> float:
        """Stroke of point ``point`` [m]: the diameter of its path.

        The largest distance between two of its positions over the angles where the
        linkage is assembled, over the vertices of the path's convex hull; a
        straight path's extent along its line.

        Parameters
        ----------
        point : str
            A solved point's name.

        Returns
        -------
        float
            The stroke [m]; NaN where the linkage is assembled at no angle.

        Raises
        ------
        InputError
            If the point is not in the solution, or the solution is a
            :func:`solve_geometries` one (one geometry's solution only).

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> lk = cm.Linkage({"A": (0, 0), "B": (0.1, 0)}, [("A", "B")], ["A"], ("A", "B"))
        >>> round(lk.solve(np.radians(np.arange(0.0, 360.0, 1.0))).stroke("B"), 12)
        0.2
        """
        if self.xy.ndim != 3:
            raise InputError(
                f"stroke of a sweep's solution (shape {self.xy.shape}): solve one geometry"
            )
        xy = self.xy[self.ok, self.index(point)]
        if not len(xy):
            return math.nan
        from scipy.spatial import ConvexHull, QhullError

        try:
            pts = xy[ConvexHull(xy).vertices]
        except (QhullError, ValueError):  # on one line (a slider), or too few points
            centred = xy - xy.mean(axis=0)
            axis = np.linalg.svd(centred, full_matrices=False)[2][0]
            along = centred @ axis
            return float(along.max() - along.min())
        d = pts[:, None, :] - pts[None, :, :]
        return float(np.sqrt((d**2).sum(axis=2)).max())


def out_arrays(out: Any, lead: tuple[int, ...], m: int, analogs: bool, inputs: list[Any]) -> Any:
    """The six arrays (xy, vel, acc, ok, singular, branch_change) a solve writes
    into, from ``out``: a :class:`LinkageSolution` (all its arrays), or a mapping
    of those names to arrays (``xy`` required; ``vel`` and ``acc`` exactly when
    ``analogs``; flags not given are allocated). Positions and analogs must be
    writeable C-contiguous float64 arrays of shape ``lead + (m, 2)``, flags bool
    arrays of shape ``lead``, none sharing memory with another or with
    ``inputs``; anything else is an :class:`InputError` naming the array.
    """
    if isinstance(out, LinkageSolution):
        given: dict[str, Any] = {
            "xy": out.xy,
            "vel": out.vel,
            "acc": out.acc,
            "ok": out.ok,
            "singular": out.singular,
            "branch_change": out.branch_change,
        }
    elif isinstance(out, Mapping):
        unknown = [k for k in out if k not in _OUT_FIELDS]
        if unknown:
            raise InputError(
                f"out: unknown array {unknown[0]!r}; the arrays are {', '.join(_OUT_FIELDS)}"
            )
        given = {k: out.get(k) for k in _OUT_FIELDS}
        for k in ("ok", "singular", "branch_change"):
            if given[k] is None:
                given[k] = np.zeros(lead, dtype=bool)
    else:
        raise InputError(
            "out must be a LinkageSolution (a previous result of this shape) or a mapping "
            f"of {', '.join(_OUT_FIELDS)} to arrays; got {type(out).__name__}"
        )
    shape = (*lead, m, 2)
    for k in ("xy", "vel", "acc"):
        arr = given[k]
        if k != "xy" and not analogs:
            if arr is not None:
                raise InputError(
                    f"out.{k} is given but this solve has analogs=False: pass a solution "
                    "solved without analogs, or a mapping without vel and acc"
                )
            continue
        if arr is None:
            raise InputError(
                f"out.{k} is missing: this solve writes {_OUT_FIELDS[k]} of shape {shape}"
            )
        out_array(arr, shape, inputs, f"out.{k}: {_OUT_FIELDS[k]}")
    for k in ("ok", "singular", "branch_change"):
        arr = given[k]
        want = (
            f"out.{k} ({_OUT_FIELDS[k]}) must be a writeable C-contiguous bool numpy array "
            f"of shape {lead} sharing no memory with an input"
        )
        if not isinstance(arr, np.ndarray):
            raise InputError(f"{want}; got {type(arr).__name__}")
        got = f"got a {arr.dtype} array of shape {arr.shape}"
        if arr.dtype != np.bool_ or arr.shape != lead:
            raise InputError(f"{want}; {got}")
        if not arr.flags.c_contiguous or not arr.flags.writeable:
            raise InputError(f"{want}; {got} that is not C-contiguous or is read-only")
    names = [k for k in _OUT_FIELDS if given[k] is not None]
    for i, a in enumerate(names):
        for b in names[i + 1 :]:
            if np.may_share_memory(given[a], given[b]) and np.shares_memory(given[a], given[b]):
                raise InputError(
                    f"out.{a} and out.{b} share memory: each output needs its own array"
                )
        for x in inputs:
            if np.may_share_memory(given[a], x) and np.shares_memory(given[a], x):
                raise InputError(f"out.{a} shares memory with an input (the angles or lengths)")
    return tuple(given[k] for k in _OUT_FIELDS)
