"""The bound laws a mechanism puts on a cyclogram operation: :data:`BoundLaw` (the
smallest angle at each speed) and the law of a bound that grows in proportion to
the speed (a stop's rebound bound), :class:`Proportional`; part of
:mod:`cyclomech.cyclogram`, whose speed network evaluates them (the mechanism-kind
contract of :mod:`cyclomech._kind` re-exports them)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from .._arrays import broadcast, finite_number, float_array, real_array
from .._errors import InputError

#: A float64 NumPy array (speeds [rpm], angles [deg]).
Array = npt.NDArray[np.float64]
#: The smallest angle [deg] of a bound at each speed [rpm] (same shape; NaN where
#: even the whole cycle is too short).
BoundLaw = Callable[[Array], Array]


def proportional_law(rpm: Array, per_rpm: Array) -> Array:
    """:meth:`Proportional.evaluate` without its checks, for the machine's sweeps,
    whose slopes were checked when their laws were built (one pass less over
    arrays of a million speeds).

    >>> proportional_law(np.array([100.0]), np.array([0.1])).tolist()
    [10.0]
    """
    # A product past the float range (a rebound limit of 1e-313 m, say) is inf,
    # over 360°: NaN like any other, not a warning.
    with np.errstate(over="ignore"):
        t = np.maximum(np.multiply(rpm, per_rpm), 1e-9)
    return np.where(t <= 360.0, t, np.nan)


@dataclass(frozen=True)
class Proportional:
    """A bound law that grows in proportion to the speed.

    The smallest angle is n·``per_rpm`` [deg] at n rpm (at least 1e-9°; NaN over
    360°, where no phase angle of one turn will do), as a stop's rebound bound (its
    impact speed grows as n/t). Calling it evaluates the law at an array of speeds
    [rpm]. The machine evaluates many of them in one vectorised step. The parameter
    is kept as the attribute of the same name.

    Parameters
    ----------
    per_rpm : float
        The smallest angle per unit of speed [deg/rpm].

    Examples
    --------
    >>> import numpy as np
    >>> Proportional(0.1)(np.array([100.0, 4000.0])).tolist()
    [10.0, nan]
    """

    per_rpm: float

    def __post_init__(self) -> None:
        # NaN would make every angle NaN, and a string or a bool is not a slope;
        # +inf is a bound that no speed meets (a stop whose v* is 0).
        v = finite_number("per_rpm", self.per_rpm, "[deg/rpm] (inf: no speed)", low=0.0, inf=True)
        object.__setattr__(self, "per_rpm", v)

    def __call__(self, rpm: Array) -> Array:
        return self.evaluate(rpm, self.per_rpm)

    @staticmethod
    def evaluate(rpm: npt.ArrayLike, per_rpm: npt.ArrayLike) -> Array:
        """The law n·per_rpm [deg], at least 1e-9, NaN over 360 (broadcast).

        Parameters
        ----------
        rpm : array_like of float
            The speeds n [rpm], each finite and > 0.
        per_rpm : array_like of float
            The smallest angle per unit of speed [deg/rpm], each ≥ 0 (+inf: no
            speed will do), broadcast against ``rpm``.

        Returns
        -------
        ndarray of float
            The smallest angles [deg] (NaN over 360°), of the broadcast shape.

        Raises
        ------
        InputError
            If a speed is not a finite number > 0, a slope is NaN, negative or not
            a number, or the shapes do not broadcast.

        Examples
        --------
        >>> Proportional.evaluate([100.0, 200.0], [0.1, 2.0]).tolist()
        [10.0, nan]
        >>> Proportional.evaluate(50.0, 1e307).tolist()       # past the float range
        nan
        """
        n = real_array("rpm", rpm, "[rpm]", low=0.0, strict=True)
        k = float_array("per_rpm", per_rpm, tuple(range(33))).reshape(np.shape(per_rpm))
        bad = np.isnan(k) | (k < 0.0)
        if bad.any():
            i = int(np.argmax(bad.ravel()))
            raise InputError(
                f"per_rpm entry {i} = {k.ravel()[i]!r} must be ≥ 0 [deg/rpm] (inf: no speed)"
            )
        return proportional_law(*broadcast(rpm=n, per_rpm=k))
