"""Checks of the rotor transfer's inputs shared by :mod:`cyclomech.transfer`'s
modules: pitch radii, finite arrays, points and workpiece speeds, with the name
and unit in the message."""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt

from .._arrays import finite_number, float_array
from .._errors import InputError

Array = npt.NDArray[np.float64]


#: Lengths [m] the path's closed forms and scans hold in (fifth powers of x2 and
#: their reciprocals, and 1e-9 fractions, stay normal floats); outside, scale
#: the units.
_LENGTH_RANGE = (1e-60, 1e60)


def _radius(name: str, value: Any) -> float:
    """A pitch radius [m]: finite, > 0 and within the lengths the closed forms hold
    in, or :class:`InputError`.

    >>> from cyclomech.transfer._checks import _radius
    >>> _radius("R_t", 0.15)
    0.15
    >>> _radius("R_t", 1e80)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    cyclomech._errors.InputError: R_t = 1e+80 m must lie in [1e-60, 1e+60] m (scale the units)
    """
    r = finite_number(name, value, "m (a pitch radius must be positive)", low=0.0, strict=True)
    lo, hi = _LENGTH_RANGE
    if not lo <= r <= hi:
        raise InputError(f"{name} = {value!r} m must lie in [{lo:g}, {hi:g}] m (scale the units)")
    return r


def _finite_array(name: str, value: Any, unit: str) -> Array:
    a = float_array(name, value, ndims=(0, 1, 2, 3)).reshape(np.shape(value))
    if not np.isfinite(a).all():
        i = int(np.argmax(~np.isfinite(a.ravel())))
        raise InputError(f"{name} must be finite {unit}; entry {i} is {a.ravel()[i]!r}")
    return a


def _point(name: str, value: Any) -> Array:
    a = float_array(name, value, ndims=(1,))
    if a.shape != (2,) or not np.isfinite(a).all():
        raise InputError(f"{name} must be a finite point (x, y) [m]; got {value!r}")
    return a


def _speeds(speed: Any) -> tuple[float, float]:
    """(V_t, V_p) [m/s] from a number V or a pair, checked.

    >>> from cyclomech.transfer._checks import _speeds
    >>> _speeds(0.3), _speeds([0.3, 0.4])
    ((0.3, 0.3), (0.3, 0.4))
    """
    v = _finite_array("speed", speed, "[m/s]")
    if v.ndim == 0:
        v = np.array([float(v), float(v)])
    if v.shape != (2,):
        raise InputError(
            f"speed must be a number V or a pair (V_t, V_p) [m/s]; got shape {v.shape}"
        )
    if (v <= 0).any():
        raise InputError(f"speed must be > 0 m/s; got {speed!r}")
    return float(v[0]), float(v[1])


def _scalar(a: Array) -> Any:
    return float(a) if a.ndim == 0 else a
