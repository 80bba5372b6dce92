"""Units: the one place where shaft speeds are converted between rpm, rad/s and deg/s.

SI inside; the edges that take rpm or degrees say so in their names.
``RAD_PER_S_PER_RPM`` is the angular speed [rad/s] of a shaft turning at 1 rpm (2π/60),
``DEG_PER_S_PER_RPM`` the same in deg/s (360/60). Both come from the Rust core
(``cyclomech._core``), which uses them too: one copy of each. :func:`at_speed`
evaluates a quantity kept in parts (per ω², per ε, static) at a shaft speed and
acceleration: the kinetostatics' torques and reactions and the frame's shaking
are kept so.

>>> from cyclomech._units import DEG_PER_S_PER_RPM, RAD_PER_S_PER_RPM
>>> round(60.0 * RAD_PER_S_PER_RPM, 12), 60.0 * DEG_PER_S_PER_RPM   # one turn a second
(6.28318530718, 360.0)
"""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt

from ._arrays import finite_number
from ._core import DEG_PER_S_PER_RPM, RAD_PER_S_PER_RPM

__all__ = ["DEG_PER_S_PER_RPM", "RAD_PER_S_PER_RPM", "at_speed"]


def at_speed(
    parts: npt.NDArray[np.float64],
    rpm: Any,
    crank_acceleration: Any,
    *,
    static: bool = True,
    rpm_low: float | None = None,
) -> npt.NDArray[np.float64]:
    """ω²·parts[0] + ε·parts[1] (+ parts[2] with ``static``) at the shaft speed
    ``rpm`` [rpm] and angular acceleration ``crank_acceleration`` ε [rad/s²].

    Parameters
    ----------
    parts : ndarray of float, shape (3, ...)
        Per ω² [·s²], per ε [·s²] and static.
    rpm : float
        The speed [rpm]; finite (and ≥ ``rpm_low`` when given).
    crank_acceleration : float
        ε [rad/s²], finite.
    static : bool, default True
        Whether to add the static part.
    rpm_low : float, optional
        The least speed allowed [rpm]; default None (any finite speed).

    Returns
    -------
    ndarray of float
        The quantity, of the shape of ``parts[0]``.

    Raises
    ------
    InputError
        Naming ``rpm`` or ``crank_acceleration`` when not a finite number (in range).

    Examples
    --------
    >>> import numpy as np
    >>> at_speed(np.array([[1.0], [2.0], [3.0]]), 60.0 / (2 * np.pi), 0.5).tolist()  # 1 + 1 + 3
    [5.0]
    """
    n = finite_number("rpm", rpm, "[rpm]", low=rpm_low)
    eps = finite_number("crank_acceleration", crank_acceleration, "[rad/s²]")
    out: npt.NDArray[np.float64] = (n * RAD_PER_S_PER_RPM) ** 2 * parts[0] + eps * parts[1]
    return out + parts[2] if static else out
