"""K geometries of one linkage solved over one crank-angle grid in one call
(:func:`solve_geometries`)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import numpy.typing as npt

from .._arrays import flag, float_array, threads_arg
from .._errors import InputError
from ._linkage import Linkage
from ._solution import LinkageSolution, out_arrays

__all__ = ["solve_geometries"]


def solve_geometries(
    linkage: Linkage,
    angles: npt.ArrayLike,
    lengths: npt.ArrayLike,
    *,
    points: Sequence[str] | None = None,
    analogs: bool = True,
    n_threads: int | None = None,
    out: LinkageSolution | Mapping[str, Any] | None = None,
) -> LinkageSolution:
    """Solve K geometries of one linkage over one crank-angle grid in one call.

    In parallel over the geometries. Topology, ground points and assembly mode stay
    those of ``linkage``. A geometry whose drawn pose cannot be closed (class III
    groups start from it) is ``ok = False`` throughout.

    Parameters
    ----------
    linkage : Linkage
        The linkage whose geometry varies.
    angles : array_like of float, shape (N,)
        The absolute crank angles [rad].
    lengths : array_like of float, shape (K, D)
        Each geometry's distances [m] in the order of ``linkage.dimensions`` (start
        from ``linkage.dimension_values``); finite and positive.
    points : sequence of str, optional
        The points to solve for; default every point.
    analogs : bool, default True
        False skips the velocity and acceleration analogs.
    n_threads : int, optional
        Threads (default: ``CYCLOMECH_THREADS`` or all cores).
    out : LinkageSolution or mapping of str to ndarray, optional
        Writes into existing arrays, as :meth:`Linkage.solve`'s: a previous
        solution of this sweep's shape (K, N, M, 2), or a mapping of its arrays.

    Returns
    -------
    LinkageSolution
        Positions [m] and analogs with ``xy`` of shape (K, N, M, 2) and flags
        (K, N), for every point or ``points`` only.

    Raises
    ------
    InputError
        If ``linkage`` is not a :class:`Linkage`, ``lengths`` is not (K, D) or holds
        a length that is not finite and positive, a point is unknown, or ``out`` is
        of the wrong arrays.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> lk = cm.Linkage({"A": (0, 0), "B": (1, 0), "C": (3.5, 2.5), "D": (4, 0)},
    ...                 [("A", "B"), ("B", "C"), ("C", "D")], ["A", "D"], ("A", "B"))
    >>> L = np.tile(lk.dimension_values, (3, 1))
    >>> L[:, 0] = [0.8, 1.0, 1.2]                       # three crank radii
    >>> sol = cm.linkage.solve_geometries(lk, np.linspace(0, 2 * np.pi, 73), L, points=["C"])
    >>> sol.xy.shape, bool(sol.ok.all())
    ((3, 73, 1, 2), True)
    >>> L[:, 1] *= 1.01                                  # longer couplers, same arrays
    >>> again = cm.linkage.solve_geometries(lk, sol.angles, L, points=["C"], out=sol)
    >>> again.xy is sol.xy
    True
    """
    if not isinstance(linkage, Linkage):
        raise InputError(f"linkage must be a cyclomech.Linkage; got {type(linkage).__name__}")
    a = float_array("angles", angles)
    dims = float_array("lengths", lengths, ndims=(2,))
    d = len(linkage._dims)
    if dims.shape[1] != d:
        raise InputError(
            f"lengths must have shape (K, {d}), one column per linkage.dimensions "
            f"({', '.join(f'{p}{q}' for p, q in linkage._dims)}); got {dims.shape}"
        )
    bad = ~(np.isfinite(dims) & (dims > 0))
    if bad.any():
        k, j = (int(v) for v in np.argwhere(bad)[0])
        p, q = linkage._dims[j]
        raise InputError(
            f"lengths[{k}, {j}] = {dims[k, j]!r} (|{p}{q}|) must be a finite, positive length [m]"
        )
    table = np.repeat(linkage._base_dims[None], dims.shape[0], axis=0)
    for row, col, j in linkage._slots:
        table[:, row, col] = dims[:, j] / linkage._kscale
    sel, names = linkage._select(points)
    an = flag("analogs", analogs)
    lead = (dims.shape[0], len(a))
    bufs = None if out is None else out_arrays(out, lead, len(sel), an, [a, dims])
    xy, vel, acc, ok, singular, branch = linkage._program.solve_many(
        table, a, sel, analogs=an, n_threads=threads_arg(n_threads), out=bufs
    )
    xy, vel, acc = linkage._unscale(xy, vel, acc)
    return LinkageSolution(a, names, xy, vel, acc, ok, singular, branch)
