"""The registry of mechanism kinds: ``kind`` name → class (see
:mod:`cyclomech._kind` for what a kind provides). Adding a kind is one line here
(or :func:`register` from outside the package); nothing else in the machine
changes."""

from __future__ import annotations

from .._errors import InputError
from .._kind import Mechanism
from ..cam import CamMechanism
from ..impact import CamStop
from ..linkage import LinkageMechanism
from ..press import PressMechanism
from ..servo import ServoMechanism
from ..transfer import TransferMechanism

__all__ = ["KINDS", "register"]

#: Every mechanism kind a machine file may use: its table's ``kind`` → its class.
KINDS: dict[str, type[Mechanism]] = {
    CamMechanism.kind: CamMechanism,
    CamStop.kind: CamStop,
    LinkageMechanism.kind: LinkageMechanism,
    PressMechanism.kind: PressMechanism,
    ServoMechanism.kind: ServoMechanism,
    TransferMechanism.kind: TransferMechanism,
}


def register(cls: type[Mechanism]) -> type[Mechanism]:
    """Add a mechanism kind to :data:`KINDS` (usable as a class decorator).

    The one argument, ``cls``, is the kind's class: it has a string ``kind`` and
    satisfies :class:`~cyclomech.machine.Mechanism`. (It is described here, not under
    Parameters: numpydoc takes a first parameter named ``cls`` for a classmethod's
    and would report it as unknown.)

    Returns
    -------
    type
        ``cls``, registered under ``cls.kind``.

    Raises
    ------
    InputError
        If ``cls`` is not a class with a string ``kind``, or its kind name is
        already taken by another class.

    Examples
    --------
    >>> from cyclomech.machine import KINDS, register
    >>> register(KINDS["cam_stop"]) is KINDS["cam_stop"]
    True
    """
    if not isinstance(cls, type) or not isinstance(getattr(cls, "kind", None), str):
        raise InputError(f"register: {cls!r} is not a mechanism kind (a class with a `kind`)")
    have = KINDS.get(cls.kind)
    if have is not None and have is not cls:
        raise InputError(f"register: the kind {cls.kind!r} is taken by {have.__qualname__}")
    KINDS[cls.kind] = cls
    return cls
