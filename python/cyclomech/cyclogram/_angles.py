"""An operation's arc (:data:`Arc`) and the one rule for minimum angles against
speed (:func:`minimum_angles`); part of :mod:`cyclomech.cyclogram`, the ground
its operations, results and solvers stand on."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from .._arrays import real_array
from .._errors import InputError
from .._units import DEG_PER_S_PER_RPM

#: An operation's key in results: its arc ``(x, y)``, the ids of its start and end
#: events.
Arc = tuple[str, str]


def minimum_angles(
    angle_deg: npt.NDArray[np.float64], secs: npt.NDArray[np.float64], rpm: npt.ArrayLike
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_]]:
    """Each operation's minimum angle [deg] at each speed, and whether its duration sets it.

    max(min_angle_deg, 6·n·min_duration_s) for the operations with a duration
    (``secs`` > 0), the angle alone for the others. The one place this rule is
    written.

    Parameters
    ----------
    angle_deg : ndarray of float, shape (E,)
        Each operation's minimum angle at rest [deg].
    secs : ndarray of float, shape (E,)
        Each operation's minimum duration [s] (0 for none).
    rpm : float or array_like of float
        The main-shaft speed(s) n [rpm].

    Returns
    -------
    mins : ndarray of float, shape ``rpm.shape + (E,)``
        The minimum angles [deg].
    timed : ndarray of bool, shape ``rpm.shape + (E,)``
        Whether the duration sets the minimum (6·n·s > the angle).

    Examples
    --------
    >>> import numpy as np
    >>> from cyclomech.cyclogram import minimum_angles
    >>> mins, timed = minimum_angles(np.array([120.0, 30.0]), np.array([0.1, 0.0]), [100.0, 300.0])
    >>> mins.tolist(), timed.tolist()
    ([[120.0, 30.0], [180.0, 30.0]], [[False, False], [True, False]])
    """
    # One rule for every public number (issue 31): NaN, a string or a bool is
    # refused by name, never carried into the minimum angles.
    angle_deg = real_array("angle_deg", angle_deg, "[deg]", low=0.0, ndims=(1,))
    secs = real_array("secs", secs, "[s]", low=0.0, ndims=(1,))
    if secs.shape != angle_deg.shape:
        raise InputError(f"secs {secs.shape} must have the shape of angle_deg {angle_deg.shape}")
    n = real_array("rpm", rpm, "[rpm]", low=0.0)[..., None]
    dur = np.where(secs > 0, DEG_PER_S_PER_RPM * n * secs, -np.inf)
    by_time = dur > angle_deg
    return np.where(by_time, dur, angle_deg), by_time
