"""Mechanisms sized at the machine's own timing, iterated to a fixed point (issue 35,
items 7 and 8).

A mechanism kind may implement the optional hook ``resize(rpm, angles) ->
Mechanism | None`` with a ``resizes`` flag (a cam whose table asks to be sized,
:meth:`cyclomech.cam.CamMechanism.resize`): given the optimum's phase angles [deg]
at the nominal speed [rpm], the mechanism re-dimensioned for them, or None where
its dimensions would not change. The machine knows no kind by name: it calls the
hook where a mechanism has it, and iterates

    LP timing → each hook sizes at those angles → the new bounds → LP again

until every hook returns None (its dimensions repeat within its own tolerance, a
cam's 1e-9 relative; then the bounds, and so the LP's angles, repeat exactly). A
round whose angles equal (within 1e-9°) those of a round two or more before while
a hook still changes is a cycle; no fixed point after :data:`MAX_ROUNDS` rounds,
or a cycle, is a loud :class:`cyclomech.CyclomechWarning` and a failure of the run
(exit status 3), the last round's machine analysed. A cyclogram that does not fit
in a round stops the loop there, a failure too (in round 1, with every mechanism at
its loosest size, no size asked would fit).

**What the fixed point is.** The loop starts from each mechanism's loosest size (a
cam's ``max_base_radius_m``). The LP, which maximises the limiting operation, takes
a phase angle down to its bound at the current size; sized at that angle, a cam
keeps its size (its limit already binds there). So where a cam's own bounds set its
angles, the fixed point is the largest radius asked (a larger cam shortens the
phase angles: :func:`cyclomech.synthesis.cam_size_tradeoff`); where other bounds or
the operations' own minimums set them, it is the smallest radius that holds at
those angles: the smallest cam that does not slow the machine.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from .._errors import CyclomechWarning, InfeasibleError
from ._model import with_mechanisms

if TYPE_CHECKING:
    from ._model import Machine

__all__ = ["MAX_ROUNDS", "Resizing", "resize_machine"]

#: Rounds of LP and sizing before the loop gives up.
MAX_ROUNDS = 20

#: Two rounds' phase angles are the same within this [deg] (cycle detection).
ANGLE_TOL_DEG = 1e-9


@dataclass
class Resizing:
    """How the mechanisms that size themselves were sized: the rounds and their end.

    Each parameter is kept as the attribute of the same name.

    Parameters
    ----------
    rounds : int
        LP-and-sizing rounds run.
    converged : bool
        Whether a fixed point was reached.
    note : str
        Why not ("" when converged).
    history : list of dict
        Per round: the speed [rpm], the phase angles [deg] by arc (as "from→to") and
        each resized mechanism's dimensions (its ``resized_values()``).

    Examples
    --------
    >>> Resizing(2, True, "").failures()
    []
    """

    rounds: int
    converged: bool
    note: str
    history: list[dict[str, Any]] = field(default_factory=list)

    def failures(self) -> list[str]:
        """The loop's failure ([] when it converged).

        Returns
        -------
        list of str
            One line when it did not converge.

        Examples
        --------
        >>> Resizing(20, False, "no fixed point").failures()
        ['sizing: no fixed point']
        """
        return [] if self.converged else [f"sizing: {self.note}"]

    def json(self) -> dict[str, Any]:
        """The ``resizing`` entry of ``results.json``.

        Returns
        -------
        dict of str to Any
            rounds, converged, note and history.

        Examples
        --------
        >>> Resizing(1, True, "").json()["converged"]
        True
        """
        return {
            "rounds": self.rounds,
            "converged": self.converged,
            "note": self.note,
            "history": self.history,
        }


def _hooks(machine: Machine) -> list[str]:
    # A kind with the hook says whether this one sizes itself (``resizes``): a cam
    # without a synthesize table costs the run nothing.
    return [
        k
        for k, m in machine.mechanisms.items()
        if callable(getattr(m, "resize", None)) and getattr(m, "resizes", False)
    ]


def resize_machine(machine: Machine) -> tuple[Machine, Resizing | None]:
    """The machine with its self-sizing mechanisms sized at its own optimised timing.

    See the module's loop, tolerances and failures.

    Parameters
    ----------
    machine : Machine
        The machine.

    Returns
    -------
    machine : Machine
        The last round's machine (the given one without a hook that sizes).
    resizing : Resizing or None
        The rounds; None where no mechanism sizes itself.

    Examples
    --------
    >>> import cyclomech as cm
    >>> m, r = resize_machine(cm.Machine.example())
    >>> r is None
    True
    """
    names = _hooks(machine)
    if not names:
        return machine, None
    m = machine
    seen: list[np.ndarray] = []
    history: list[dict[str, Any]] = []
    for i in range(1, MAX_ROUNDS + 1):
        rpm = m.nominal_speed()
        try:
            opt = m.optimize(rpm)
        except InfeasibleError as e:
            # The run reports the cyclogram that does not fit; the sizing says at
            # which sizes (in round 1, the loosest: no size asked would fit).
            first = " with each mechanism at its largest size (a cam's max_base_radius_m)"
            note = f"round {i}{first if i == 1 else ''}: {e}"
            _warn(machine, note)
            return m, Resizing(i, False, note, history)
        angles = dict(opt.angles)
        new: dict[str, Any] = {}
        for k in names:
            r = m.mechanisms[k].resize(rpm, angles)
            if r is not None:
                new[k] = r
        sizes: dict[str, Any] = {
            k: getattr(new.get(k, m.mechanisms[k]), "resized_values", dict)() for k in names
        }
        history.append(
            {
                "round": i,
                "rpm": rpm,
                "angles_deg": {f"{a}→{b}": v for (a, b), v in angles.items()},
                "sizes": sizes,
            }
        )
        if not new:
            if i == 1:
                return m, None  # nothing asked to be sized
            return m, Resizing(i, True, "", history)
        vec = np.array([angles[a] for a in sorted(angles)])
        if any(np.allclose(vec, v, rtol=0.0, atol=ANGLE_TOL_DEG) for v in seen[:-1]):
            note = (
                f"the timing repeats an earlier round's at round {i} while "
                f"{', '.join(new)} still change: a cycle, no fixed point"
            )
            _warn(machine, note)
            return with_mechanisms(m, new), Resizing(i, False, note, history)
        seen.append(vec)
        m = with_mechanisms(m, new)
    note = f"no fixed point after {MAX_ROUNDS} rounds of timing and sizing"
    _warn(machine, note)
    return m, Resizing(MAX_ROUNDS, False, note, history)


def _warn(machine: Machine, note: str) -> None:
    warnings.warn(
        f"{machine.source}: sizing: {note}; the last round is analysed and the run fails",
        CyclomechWarning,
        stacklevel=3,
    )
