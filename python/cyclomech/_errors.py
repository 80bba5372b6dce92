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
    """Base class of every cyclomech error (a ``ValueError``)."""


class CyclomechWarning(UserWarning):
    """Something in the input is probably a mistake, but has a valid reading (a
    mechanism name on an operation one letter off a mechanism of the machine)."""


class InputError(CyclomechError):
    """An argument, array or file entry is malformed or out of its domain."""


class CycleError(CyclomechError):
    """Operations that must happen one after another form a cycle.

    ``events`` lists the events of one such cycle, in arc order (indices from the
    kernels, names from :class:`cyclomech.Cyclogram`).
    """

    def __init__(self, message: str, events: Sequence[Any] = ()) -> None:
        super().__init__(message)
        self.events = tuple(events)

    def __reduce__(self) -> tuple[Any, ...]:
        return (type(self), (str(self), self.events))


class InfeasibleError(CyclomechError):
    """Constraints that cannot all hold.

    ``conflict`` names the operations or constraints that together cannot hold
    (a chain of operations longer than the cycle, or an irreducible infeasible
    subset of the LP's bounds and constraints).
    """

    def __init__(self, message: str, conflict: Sequence[Any] = ()) -> None:
        super().__init__(message)
        self.conflict = tuple(conflict)

    def __reduce__(self) -> tuple[Any, ...]:
        return (type(self), (str(self), self.conflict))


class SolverError(CyclomechError):
    """A numerical solver stopped without an answer (no convergence, LP failure)."""


class InternalError(CyclomechError):
    """A kernel hit a state it should never reach; please report the input."""
