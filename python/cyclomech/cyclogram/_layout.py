"""The cyclogram as its solvers read it (:class:`Layout`): the events numbered, the
operations as arrays of their ends and heights, the constraints and the labels of
the bounds in results; part of :mod:`cyclomech.cyclogram`.

The model (:class:`~cyclomech.cyclogram.Cyclogram`) builds one from its public
contents when it changes and hands it to the LP, the speed limit and the schedule;
the speed network builds its own. No solver reads the model's private state.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from .._errors import CycleError

if TYPE_CHECKING:
    from ._angles import Arc
    from ._operation import Operation
    from ._types import Constraint

_Ints = npt.NDArray[np.int64]
_Floats = npt.NDArray[np.float64]


class Layout:
    """A cyclogram's events, operations and constraints, numbered for the solvers.

    Parameters
    ----------
    name : str
        The cyclogram's name, for messages.
    events : sequence of str
        The event ids, in the cyclogram's order (their numbers).
    operations : sequence of Operation
        The operations, in the cyclogram's order (their numbers).
    constraints : sequence of Constraint
        The added linear constraints.

    Attributes
    ----------
    index : dict of str to int
        Each event's number.
    arc_index : dict of (str, str) to int
        Each operation's number by its arc.
    src, dst : ndarray of int, shape (E,)
        The numbers of each operation's start and end events.
    height : ndarray of float, shape (E,)
        Each operation's height (1: it ends in the next cycle).
    angle : ndarray of float, shape (E,)
        Each operation's minimum angle at rest [deg].
    secs : ndarray of float, shape (E,)
        Each operation's minimum duration [s] (0: none).
    labels : list of str
        The label of each operation's bounds in results (``min[label]``,
        ``max[label]``): its title, with the arc added where several operations
        share a title.

    Examples
    --------
    >>> import cyclomech as cm
    >>> cg = cm.Cyclogram()
    >>> cg.add_operation("a", "b", 30, name="feed")
    >>> cg.add_operation("b", "a", 40, height=1)
    >>> lay = Layout(cg.name, cg.events, cg.operations, cg.constraints)
    >>> lay.src.tolist(), lay.dst.tolist(), lay.height.tolist(), lay.labels
    ([0, 1], [1, 0], [0.0, 1.0], ['feed', 'b→a'])
    """

    def __init__(
        self,
        name: str,
        events: Sequence[str],
        operations: Sequence[Operation],
        constraints: Sequence[Constraint],
    ) -> None:
        self.name = name
        self.events = tuple(events)
        self.ops = tuple(operations)
        self.constraints = tuple(constraints)
        self.index = {e: i for i, e in enumerate(self.events)}
        self.arc_index: dict[Arc, int] = {op.arc: e for e, op in enumerate(self.ops)}
        E = len(self.ops)
        self.src: _Ints = np.fromiter((self.index[op.src] for op in self.ops), np.int64, E)
        self.dst: _Ints = np.fromiter((self.index[op.dst] for op in self.ops), np.int64, E)
        self.height: _Floats = np.fromiter((op.height for op in self.ops), np.float64, E)
        self.angle: _Floats = np.fromiter((op.min_angle_deg for op in self.ops), np.float64, E)
        self.secs: _Floats = np.fromiter((op.min_duration_s for op in self.ops), np.float64, E)
        titles = [op.title for op in self.ops]
        seen: dict[str, int] = {}
        for t in titles:
            seen[t] = seen.get(t, 0) + 1
        self.labels = [
            t if seen[t] == 1 else f"{t} ({op.src}→{op.dst})"
            for t, op in zip(titles, self.ops, strict=True)
        ]

    def op(self, arc: Arc) -> Operation:
        """The operation with this arc (which must exist)."""
        return self.ops[self.arc_index[arc]]

    def constraint(self, name: str) -> Constraint:
        """The constraint with this name (which must exist)."""
        return next(c for c in self.constraints if c.name == name)

    def named_cycle(self, e: CycleError) -> CycleError:
        """The kernel's :class:`CycleError` (event numbers) with the events named."""
        ev = [self.events[i] for i in e.events]
        chain = " → ".join([*ev, ev[0]])
        return CycleError(
            f"cyclogram {self.name!r}: the operations {chain} form a cycle within one machine "
            "cycle; an operation that ends in the next cycle needs height=1",
            ev,
        )


def closed_over_cycle(
    src: _Ints, dst: _Ints, heights: _Floats, n_events: int
) -> tuple[int, _Ints, _Ints, _Floats, int]:
    """The arcs closed over one machine cycle, for the cycle-ratio kernels.

    A virtual start S before and finish F after every event, and F → S crossing
    into the next cycle. Returns (number of events, src, dst, heights, number of
    virtual arcs appended, all of weight 0); the closure F → S is the last arc.
    """
    S, F = n_events, n_events + 1
    ev = np.arange(n_events, dtype=np.int64)
    s2 = np.concatenate([src, np.full(n_events, S), ev, [F]])
    d2 = np.concatenate([dst, ev, np.full(n_events, F), [S]])
    h2 = np.concatenate([heights, np.zeros(2 * n_events), [1.0]])
    return n_events + 2, s2, d2, h2, 2 * n_events + 1


def chain_after(arcs: _Ints, closure: int) -> list[int]:
    """Rotate a cycle's arcs to start right after the closure arc F → S, so that
    the operations read as a chain from the first event to the last."""
    a = [int(e) for e in arcs]
    if closure in a:
        k = a.index(closure)
        a = a[k + 1 :] + a[: k + 1]
    return a
