"""Checks of the stops' inputs shared by :mod:`cyclomech.impact`'s modules: numbers ≥ 0
and arrays of positive numbers, with the name and unit in the message."""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt

from .._arrays import finite_number, real_array

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
    return real_array(name, value, unit, low=0.0, strict=True)
