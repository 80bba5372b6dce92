"""Longest-path scheduling of event networks (Rust kernels, thin wrappers).

Events are vertices ``0 … n_events-1``; operations are arcs ``src[e] -> dst[e]``
with a phase angle ``weights[e]`` in degrees of main-shaft rotation (negative for
operations that overlap). The earliest occurrence angle of each event is 0 for an
event without incoming arcs and ``max(p(x) + w)`` over its incoming arcs otherwise.

:func:`max_difference` solves the linear programs of a cyclogram with cycles: the
largest ``x[t] - x[s]`` under difference constraints ``x[dst] - x[src] <= w``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from .. import _core
from .._arrays import count, float_array, index_array, out_array, real, threads_arg
from .._errors import InputError

__all__ = ["EventGraph", "GraphAnalysis", "longest_path", "max_cycle_ratio", "max_difference"]

_I64_MAX = 2**63 - 1


def longest_path(
    n_events: int,
    src: npt.ArrayLike,
    dst: npt.ArrayLike,
    weights: npt.ArrayLike,
    *,
    n_threads: int | None = None,
) -> npt.NDArray[np.float64]:
    """Earliest occurrence angle of every event, for one or many weight vectors.

    The structure is analysed once per call; to evaluate the same network many
    times, build an :class:`EventGraph` once.

    Parameters
    ----------
    n_events : int
        The number of events V.
    src : array_like of int, shape (E,)
        The tail event of each arc: arc ``e`` goes from event ``src[e]`` to
        ``dst[e]``.
    dst : array_like of int, shape (E,)
        The head event of each arc.
    weights : array_like of float, shape (E,) or (B, E)
        The arcs' phase angles [deg], one vector or a batch of B; negative values
        allowed.
    n_threads : int, optional
        Threads for a batch (default: ``CYCLOMECH_THREADS`` or all cores).

    Returns
    -------
    ndarray of float, shape (V,) or (B, V)
        The earliest event angles [deg].

    Raises
    ------
    CycleError
        If the arcs contain a cycle (its events are in ``.events``).
    InputError
        For out-of-range indices, NaN/inf weights, mismatched shapes.

    Examples
    --------
    >>> import cyclomech as cm
    >>> cm.longest_path(4, [0, 1, 0, 2], [1, 3, 2, 3], [30.0, 50.0, 100.0, -20.0])
    array([  0.,  30., 100.,  80.])
    """
    w = float_array("weights", weights, ndims=(1, 2))
    return _core.longest_path(
        count("n_events", n_events, low=0, high=_I64_MAX),
        index_array("src", src),
        index_array("dst", dst),
        w,
        n_threads=threads_arg(n_threads),
    )


@dataclass(frozen=True)
class GraphAnalysis:
    """Earliest/latest event times, slack and critical arcs of one weight vector.

    Angles in degrees. Built by :meth:`EventGraph.analyze`; each parameter is kept
    as the attribute of the same name.

    Parameters
    ----------
    earliest : ndarray of float, shape (V,)
        The earliest occurrence angle of each event [deg].
    latest : ndarray of float, shape (V,)
        The latest occurrence angle of each event that keeps every event at or
        before the horizon [deg].
    total_slack : ndarray of float, shape (E,)
        Each arc's total slack, latest(y) − earliest(x) − w [deg].
    free_slack : ndarray of float, shape (E,)
        Each arc's free slack, earliest(y) − earliest(x) − w [deg].
    critical : ndarray of bool, shape (E,)
        True for every arc with zero total slack (within ``tolerance``): all ties,
        not one arbitrary longest path.
    horizon : float
        The horizon the latest times were computed for [deg].
    tolerance : float
        The absolute tolerance used to call a slack zero [deg].

    Examples
    --------
    >>> import cyclomech as cm
    >>> a = cm.EventGraph(3, [0, 1], [1, 2]).analyze([10.0, 20.0], horizon=40.0)
    >>> a.latest, a.free_slack, a.horizon
    (array([10., 20., 40.]), array([0., 0.]), 40.0)
    """

    earliest: npt.NDArray[np.float64]
    latest: npt.NDArray[np.float64]
    total_slack: npt.NDArray[np.float64]
    free_slack: npt.NDArray[np.float64]
    critical: npt.NDArray[np.bool_]
    horizon: float
    tolerance: float


class EventGraph:
    """An event network whose structure is analysed once and reused.

    Building the graph validates the arcs, finds a topological order (or raises
    :class:`~cyclomech.CycleError` naming a cycle) and lays the arcs out for the kernels, in
    time linear in V + E; every later call only evaluates weights. Inside, events
    are renumbered by their topological position so that the passes read memory in
    order; every result is by your event and arc numbers.

    Parameters
    ----------
    n_events : int
        The number of events V; events are ``0 … V-1``.
    src : array_like of int, shape (E,)
        The tail event of each arc.
    dst : array_like of int, shape (E,)
        The head event of each arc.

    Raises
    ------
    CycleError
        If the arcs contain a cycle (its events are in ``.events``).
    InputError
        For out-of-range indices or mismatched lengths.

    Examples
    --------
    >>> import numpy as np, cyclomech as cm
    >>> g = cm.EventGraph(3, [0, 1], [1, 2])
    >>> g.longest_path([10.0, 20.0])
    array([ 0., 10., 30.])
    >>> g.longest_path(np.array([[10.0, 20.0], [1.0, 2.0]]))
    array([[ 0., 10., 30.],
           [ 0.,  1.,  3.]])
    >>> g.analyze([10.0, 20.0], horizon=40.0).total_slack
    array([10., 10.])
    """

    __slots__ = ("_g",)

    def __init__(self, n_events: int, src: npt.ArrayLike, dst: npt.ArrayLike) -> None:
        self._g = _core.EventGraph(
            count("n_events", n_events, low=0, high=_I64_MAX),
            index_array("src", src),
            index_array("dst", dst),
        )

    @property
    def n_events(self) -> int:
        """Number of events V.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.EventGraph(3, [0, 1], [1, 2]).n_events
        3
        """
        return int(self._g.n_events)

    @property
    def n_arcs(self) -> int:
        """Number of arcs E.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.EventGraph(3, [0, 1], [1, 2]).n_arcs
        2
        """
        return int(self._g.n_arcs)

    @property
    def src(self) -> npt.NDArray[np.int64]:
        """Tail event of each arc, shape (E,).

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.EventGraph(3, [2, 0], [0, 1]).src
        array([2, 0])
        """
        return self._g.src

    @property
    def dst(self) -> npt.NDArray[np.int64]:
        """Head event of each arc, shape (E,).

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.EventGraph(3, [2, 0], [0, 1]).dst
        array([0, 1])
        """
        return self._g.dst

    @property
    def topological_order(self) -> npt.NDArray[np.int64]:
        """The events in a topological order, shape (V,).

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.EventGraph(3, [2, 0], [0, 1]).topological_order
        array([2, 0, 1])
        """
        return self._g.topological_order

    def longest_path(
        self,
        weights: npt.ArrayLike,
        *,
        n_threads: int | None = None,
        out: npt.NDArray[np.float64] | None = None,
    ) -> npt.NDArray[np.float64]:
        """Earliest event angles [deg] for (E,) or (B, E) weights -> (V,) or (B, V).

        Rows of a batch run in parallel.

        Parameters
        ----------
        weights : array_like of float, shape (E,) or (B, E)
            The arcs' phase angles [deg], one vector or a batch of B.
        n_threads : int, optional
            Threads for a batch (default ``CYCLOMECH_THREADS`` or all cores).
        out : ndarray of float, shape (B, V), optional
            For a batch: a writeable C-contiguous float64 array, sharing no memory
            with the weights, filled in place and returned. A buffer reused across
            calls skips the fresh pages' cost; results are bit for bit those
            without it.

        Returns
        -------
        ndarray of float, shape (V,) or (B, V)
            The earliest event angles [deg] (``out`` itself when given).

        Raises
        ------
        InputError
            For NaN/inf weights or a wrong shape, or ``out`` given for one vector
            or not of the required shape, dtype and layout.

        Examples
        --------
        >>> import numpy as np, cyclomech as cm
        >>> g = cm.EventGraph(3, [0, 1], [1, 2])
        >>> g.longest_path([[10.0, 20.0], [5.0, -1.0]])
        array([[ 0., 10., 30.],
               [ 0.,  5.,  4.]])
        >>> buf = np.empty((2, 3))
        >>> g.longest_path([[10.0, 20.0], [5.0, -1.0]], out=buf) is buf
        True
        """
        w = float_array("weights", weights, ndims=(1, 2))
        if out is None:
            return self._g.longest_path(w, n_threads=threads_arg(n_threads))
        if w.ndim != 2:
            raise InputError(
                "out is for a batch of weight vectors (B, E); one vector returns its (V,) times"
            )
        out_array(out, (w.shape[0], self.n_events), [w], "the earliest event angles [deg]")
        self._g.longest_path(w, n_threads=threads_arg(n_threads), out=out)
        return out

    def latest(self, weights: npt.ArrayLike, horizon: float) -> npt.NDArray[np.float64]:
        """Latest event angles [deg] that keep every event at or before ``horizon`` [deg].

        Parameters
        ----------
        weights : array_like of float, shape (E,)
            The arcs' phase angles [deg].
        horizon : float
            The angle by which every event must occur [deg].

        Returns
        -------
        ndarray of float, shape (V,)
            The latest event angles [deg].

        Raises
        ------
        InputError
            For NaN/inf weights, a wrong shape, or a ``horizon`` that is not a
            number.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.EventGraph(3, [0, 1], [1, 2]).latest([10.0, 20.0], horizon=40.0)
        array([10., 20., 40.])
        """
        return self._g.latest(float_array("weights", weights), _scalar("horizon", horizon))

    def analyze(self, weights: npt.ArrayLike, horizon: float | None = None) -> GraphAnalysis:
        """Earliest and latest times, total and free slack, critical arcs.

        Parameters
        ----------
        weights : array_like of float, shape (E,)
            The arcs' phase angles [deg].
        horizon : float, optional
            The angle by which every event must occur [deg]; defaults to the
            largest earliest time, so the critical arcs are exactly those on
            longest paths.

        Returns
        -------
        GraphAnalysis
            The times [deg], slacks [deg] and critical arcs.

        Raises
        ------
        InputError
            For NaN/inf weights, a wrong shape, or a ``horizon`` that is not a
            number.

        Examples
        --------
        >>> import cyclomech as cm
        >>> a = cm.EventGraph(4, [0, 1, 0, 2], [1, 3, 2, 3]).analyze([40.0, 30.0, 20.0, 30.0])
        >>> a.earliest, a.total_slack
        (array([ 0., 40., 20., 70.]), array([ 0.,  0., 20., 20.]))
        >>> a.critical
        array([ True,  True, False, False])
        """
        h = None if horizon is None else _scalar("horizon", horizon)
        d = self._g.analyze(float_array("weights", weights), h)
        return GraphAnalysis(**d)

    def __reduce__(self) -> tuple[Any, ...]:
        return (EventGraph, (self.n_events, self.src, self.dst))

    def __repr__(self) -> str:
        return f"EventGraph(n_events={self.n_events}, n_arcs={self.n_arcs})"


def _scalar(name: str, value: Any) -> float:
    try:
        return real(value)  # not float(): "360" and True are not numbers
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a real number; got {value!r}") from None


def max_cycle_ratio(
    n_events: int,
    src: npt.ArrayLike,
    dst: npt.ArrayLike,
    weights: npt.ArrayLike,
    heights: npt.ArrayLike,
) -> tuple[float, npt.NDArray[np.int64]] | None:
    """Maximum over cycles of Σweights/Σheights, by Howard's policy iteration.

    With ``weights`` the phase angles [deg] and ``heights`` the number of machine
    cycles each arc crosses, the result is the shortest cycle angle [deg] in which
    the operations can repeat. Arcs of height 0 must form a DAG.

    Parameters
    ----------
    n_events : int
        The number of events V.
    src : array_like of int, shape (E,)
        The tail event of each arc.
    dst : array_like of int, shape (E,)
        The head event of each arc.
    weights : array_like of float, shape (E,)
        The arcs' phase angles [deg].
    heights : array_like of float, shape (E,)
        The number of machine cycles each arc crosses.

    Returns
    -------
    tuple of (float, ndarray of int) or None
        ``(ratio, arcs)`` for a cycle attaining the maximum: the ratio [deg per
        cycle] and the cycle's arc indices in order; ``None`` if the graph has no
        cycle.

    Raises
    ------
    CycleError
        If the arcs of height 0 contain a cycle.
    InputError
        For out-of-range indices, NaN/inf values, mismatched lengths.

    Examples
    --------
    >>> import cyclomech as cm
    >>> r, arcs = cm.max_cycle_ratio(2, [0, 1], [1, 0], [100.0, 200.0], [0.0, 1.0])
    >>> r, arcs.tolist()
    (300.0, [0, 1])
    """
    return _core.max_cycle_ratio(
        count("n_events", n_events, low=0, high=_I64_MAX),
        index_array("src", src),
        index_array("dst", dst),
        float_array("weights", weights),
        float_array("heights", heights),
    )


def _integer(name: str, value: Any, what: str) -> int:
    """``value`` as a Python int (range checks are the kernel's), or :class:`InputError`."""
    if isinstance(value, bool) or not isinstance(value, int | np.integer):
        raise InputError(f"{name} must be {what}; got {value!r}")
    if not -_I64_MAX - 1 <= int(value) <= _I64_MAX:
        raise InputError(f"{name} = {value} is out of range: it must be {what}")
    return int(value)


def max_difference(
    n_nodes: int,
    src: npt.ArrayLike,
    dst: npt.ArrayLike,
    weights: npt.ArrayLike,
    source: int,
    target: int,
    *,
    n_threads: int | None = None,
) -> tuple[float | npt.NDArray[np.float64], npt.NDArray[np.bool_]]:
    """Largest ``x[target] - x[source]`` under difference constraints, for one or many weights.

    For each weight vector ``w`` this is the optimum of the linear program::

        maximise     x[target] - x[source]             over all real x (free),
        subject to   x[dst[e]] - x[src[e]] <= w[e]     for every arc e,

    which by LP duality is the shortest-path distance from ``source`` to
    ``target`` with arc lengths ``w`` (Bellman–Ford; negative lengths allowed).
    A cyclogram LP — event angles with minimum separations ``x[b] - x[a] >= d``,
    written as ``x[a] - x[b] <= -d`` — is evaluated this way thousands of times
    without an LP solver. Units are those of the weights (degrees, seconds, …).

    Parameters
    ----------
    n_nodes : int
        The number of nodes V (at least 1).
    src : array_like of int, shape (E,)
        The tail node of each arc: arc ``e`` constrains ``x[dst[e]] - x[src[e]]``.
    dst : array_like of int, shape (E,)
        The head node of each arc.
    weights : array_like of float, shape (E,) or (B, E)
        The upper bounds ``w``, one vector or a batch of B; negative values allowed.
    source : int
        The node index ``s``.
    target : int
        The node index ``t``.
    n_threads : int, optional
        Threads for a batch (default: ``CYCLOMECH_THREADS`` or all cores).

    Returns
    -------
    value : float or ndarray of float, shape (B,)
        A float for (E,) weights, an array for (B, E) weights. The optimum
        (finite); ``nan`` if the constraints are infeasible, i.e. some cycle
        anywhere in the graph (reachable from ``source`` or not) has negative total
        weight; ``inf`` if they are feasible and ``target`` is unreachable from
        ``source`` (the difference is unbounded). ``source == target`` gives 0.
    on_path : ndarray of bool, shape (E,) or (B, E)
        The arcs of one shortest path from ``source`` to ``target``, whose weights
        sum to ``value`` (summed from the source). All False for ``nan``, ``inf``
        and ``source == target``. The path is deterministic: Bellman–Ford passes
        over the arcs in input order and changes a predecessor only on a strict
        improvement.

    Raises
    ------
    InputError
        If ``n_nodes < 1``, an index, ``source`` or ``target`` is out of range, for
        NaN/inf weights (the row and column are named), mismatched lengths or
        shapes.

    Notes
    -----
    Tolerance: a relaxation counts only when it lowers a distance by more than
    ``eps = 1e-12 * (1 + max|w|) * n_nodes``, with ``max|w|`` over the row. A cycle
    whose weights sum to ``-eps`` or more is feasible — so an exactly tight cycle
    whose float sum comes out at ±1e-13 is not reported infeasible — and a cycle
    summing to less than ``-n_nodes * eps`` is always infeasible; in between either
    verdict is possible. The value is within ``(n_nodes - 1) * eps`` of the exact
    distance. Weights must be finite with magnitude at most 1e12. Each row of a
    batch is bit for bit what a single call on that row gives, whatever the threads.

    Examples
    --------
    ``x1 - x0 <= 4``, ``x2 - x1 <= -1``, ``x2 - x0 <= 5``: at most 3, via 0 -> 1 -> 2.

    >>> import numpy as np
    >>> from cyclomech.cyclogram import max_difference
    >>> value, on_path = max_difference(3, [0, 1, 0], [1, 2, 2], [4.0, -1.0, 5.0], 0, 2)
    >>> value, on_path.tolist()
    (3.0, [True, True, False])

    A batch; adding ``x0 - x2 <= -4`` closes the cycle 0 -> 1 -> 2 -> 0 of weight -1
    in the second row (infeasible), and nothing bounds ``x0 - x2`` without it:

    >>> w = np.array([[4.0, -1.0, 5.0, 10.0], [4.0, -1.0, 5.0, -4.0]])
    >>> values, on_path = max_difference(3, [0, 1, 0, 2], [1, 2, 2, 0], w, 0, 2)
    >>> values
    array([ 3., nan])
    >>> on_path
    array([[ True,  True, False, False],
           [False, False, False, False]])
    >>> max_difference(3, [0, 1, 0], [1, 2, 2], [4.0, -1.0, 5.0], 2, 0)[0]
    inf
    """
    w = float_array("weights", weights, ndims=(1, 2))
    return _core.max_difference(
        _integer("n_nodes", n_nodes, "a positive integer (the number of nodes)"),
        index_array("src", src),
        index_array("dst", dst),
        w,
        _integer("source", source, "an integer node index"),
        _integer("target", target, "an integer node index"),
        n_threads=threads_arg(n_threads),
    )
