"""Checks of the stops' inputs shared by :mod:`cyclomech.impact`'s modules: numbers ≥ 0
and arrays of positive numbers, with the name and unit in the message."""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt

from .._arrays import finite_number
from .._errors import InputError

Array = npt.NDArray[np.float64]


def _nonnegative(name: str, value: Any, unit: str) -> float:
    """``value`` as a finite float ≥ 0, or :class:`InputError` naming ``name``,
    the value and ``unit``.

    >>> from cyclomech.impact._checks import _nonnegative
    >>> _nonnegative("preload", 0.0, "[m]")
    0.0
    """
    return finite_number(name, value, unit, low=0.0)


def _positive_array(name: str, value: Any, unit: str) -> Array:
    """``value`` as a float64 array of finite numbers > 0, or :class:`InputError`
    naming the first bad entry and ``unit``.

    >>> from cyclomech.impact._checks import _positive_array
    >>> _positive_array("rpm", [280, 420], "[rpm]").tolist()
    [280.0, 420.0]
    >>> _positive_array("rpm", [280, 0], "[rpm]")
    Traceback (most recent call last):
    cyclomech._errors.InputError: rpm[1] = 0.0 must be finite and > 0 [rpm]
    """
    try:
        a = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be positive numbers {unit}; got {value!r}") from None
    bad = ~(np.isfinite(a) & (a > 0.0))
    if bad.any():
        if a.ndim:
            i = tuple(int(k) for k in np.unravel_index(int(np.argmax(bad)), a.shape))
            where, v = f"{name}{list(i)}", float(a[i])
        else:
            where, v = name, float(a)
        raise InputError(f"{where} = {v!r} must be finite and > 0 {unit}")
    return a
