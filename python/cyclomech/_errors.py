"""Exceptions of cyclomech.

Every error a user can cause is a :class:`CyclomechError`, which is a
:class:`ValueError`, and names the field, the value and what would be valid. The
Rust kernels raise these classes too (mapped in one place in the bindings).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

__all__ = [
    "CycleError",
    "CyclomechError",
    "CyclomechWarning",
    "InfeasibleError",
    "InputError",
    "InternalError",
    "SolverError",
]


class CyclomechError(ValueError):
    """Base class of every cyclomech error (a ``ValueError``).

    Catching it catches every error a user can cause; each names the field, the
    value and what would be valid.

    Examples
    --------
    >>> import cyclomech as cm
    >>> try:
    ...     cm.Cyclogram(cycle_deg=-1)
    ... except cm.CyclomechError as e:
    ...     print(type(e).__name__, isinstance(e, ValueError))
    InputError True
    """


class CyclomechWarning(UserWarning):
    """Something in the input is probably a mistake, but has a valid reading.

    For example a mechanism name on an operation one letter off a mechanism of the
    machine. A ``UserWarning``: filter it with ``warnings`` as any other.

    Examples
    --------
    >>> import warnings, cyclomech as cm
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     warnings.warn("mechanism 'lifte' is one letter off 'lifter'", cm.CyclomechWarning)
    >>> caught[0].category.__name__, issubclass(cm.CyclomechWarning, UserWarning)
    ('CyclomechWarning', True)
    """


class InputError(CyclomechError):
    """An argument, array or file entry is malformed or out of its domain.

    Examples
    --------
    >>> import cyclomech as cm
    >>> try:
    ...     cm.Cyclogram(cycle_deg=0)
    ... except cm.InputError as e:
    ...     print(e)
    cycle_deg must be a positive angle in degrees (360 for one turn); got 0
    """


class CycleError(CyclomechError):
    """Operations that must happen one after another form a cycle.

    Parameters
    ----------
    message : str
        What is wrong, in words.
    events : sequence, optional
        The events of one such cycle, in arc order (indices from the kernels, names
        from :class:`~cyclomech.cyclogram.Cyclogram`); kept as the tuple ``events``. Default
        empty.

    Examples
    --------
    >>> import cyclomech as cm
    >>> cg = cm.Cyclogram()
    >>> cg.add_operation("a", "b", 10)
    >>> cg.add_operation("b", "a", 10)
    >>> try:
    ...     cg.schedule()
    ... except cm.CycleError as e:
    ...     print(e.events)
    ('a', 'b')
    """

    def __init__(self, message: str, events: Sequence[Any] = ()) -> None:
        super().__init__(message)
        self.events = tuple(events)

    def __reduce__(self) -> tuple[Any, ...]:
        return (type(self), (str(self), self.events))


class InfeasibleError(CyclomechError):
    """Constraints that cannot all hold.

    Parameters
    ----------
    message : str
        What is wrong, in words.
    conflict : sequence, optional
        The operations or constraints that together cannot hold (a chain of
        operations longer than the cycle, or an irreducible infeasible subset of
        the LP's bounds and constraints); kept as the tuple ``conflict``. Default
        empty.

    Examples
    --------
    >>> import cyclomech as cm
    >>> cg = cm.Cyclogram()
    >>> cg.add_operation("a", "b", 200)
    >>> cg.add_operation("b", "c", 200)
    >>> try:
    ...     cg.optimize()
    ... except cm.InfeasibleError as e:
    ...     print(e.conflict)
    (('a', 'b'), ('b', 'c'))
    """

    def __init__(self, message: str, conflict: Sequence[Any] = ()) -> None:
        super().__init__(message)
        self.conflict = tuple(conflict)

    def __reduce__(self) -> tuple[Any, ...]:
        return (type(self), (str(self), self.conflict))


class SolverError(CyclomechError):
    """A numerical solver stopped without an answer (no convergence, LP failure).

    Examples
    --------
    >>> import cyclomech as cm
    >>> err = cm.SolverError("the LP solver stopped: iteration limit")
    >>> isinstance(err, cm.CyclomechError), str(err)
    (True, 'the LP solver stopped: iteration limit')
    """


class InternalError(CyclomechError):
    """A kernel hit a state it should never reach; please report the input.

    Examples
    --------
    >>> import cyclomech as cm
    >>> issubclass(cm.InternalError, cm.CyclomechError)
    True
    """
