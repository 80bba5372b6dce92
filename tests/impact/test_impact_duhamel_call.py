"""The one-case ``cm.impact.duhamel`` call (issue 20): the common call (float64
1-D C-contiguous arrays and float parameters) goes straight to the kernel, every
other input through the conversions; both give the same numbers bit for bit and
name the field of a bad input alike."""

from __future__ import annotations

import cyclomech as cm
import numpy as np
import pytest
from cyclomech import CyclomechError

T = np.linspace(0.0, 4e-3, 2001)
F = 3.0 * np.maximum(1.0 - T / 6.5e-4, 0.0)
KW = {"omega_n": 1866.0, "zeta": 0.05, "mass": 7.4e-3}


def _ref() -> np.ndarray:
    return cm.impact.duhamel(T, F, **KW)


@pytest.mark.parametrize(
    "t, force, kw",
    [
        (list(T), F, KW),  # a list: converted
        (T.copy(), F.copy(), KW),  # fresh copies
        (np.repeat(T, 2)[::2], F, KW),  # strided: copied
        (T, np.repeat(F, 2)[::2], KW),
        (T, F, {**KW, "omega_n": np.float64(1866.0)}),  # numpy scalars
        (T, F, {**KW, "q0": 0, "v0": 0}),  # integers
        (T.reshape(1, -1)[0], F, KW),
    ],
)
def test_every_path_gives_the_same_numbers(t, force, kw) -> None:
    np.testing.assert_array_equal(cm.impact.duhamel(t, force, **kw), _ref())


def test_velocity_false_and_true_agree_on_q() -> None:
    q, v = cm.impact.duhamel(T, F, **KW, velocity=True)
    np.testing.assert_array_equal(q, _ref())
    assert v.shape == q.shape


@pytest.mark.parametrize(
    "t, force, kw, field",
    [
        (T, F, {**KW, "zeta": -0.5}, "zeta"),
        (T, F, {**KW, "mass": 0.0}, "mass"),
        (T, F, {**KW, "omega_n": float("nan")}, "omega_n"),
        (T, F, {**KW, "q0": float("inf")}, "q0"),
        (T, F, {**KW, "v0": float("-inf")}, "v0"),
        (T, F[:-1], KW, "force"),
        (T[::-1].copy(), F, KW, "t"),
        (np.where(np.arange(T.size) == 7, np.nan, T), F, KW, "t"),
        (T, np.where(np.arange(T.size) == 9, np.inf, F), KW, "force"),
    ],
)
def test_the_common_call_names_a_bad_field(t, force, kw, field) -> None:
    with pytest.raises(CyclomechError, match=field) as err:
        cm.impact.duhamel(t, force, **kw)
    assert isinstance(err.value, ValueError)
    # The same error through the conversions (a list for t).
    with pytest.raises(type(err.value), match=field):
        cm.impact.duhamel(list(t), force, **kw)


@pytest.mark.parametrize(
    "t, force",
    [
        (np.empty(0), np.empty(0)),
        (T.reshape(1, -1), F),
        (T, F.astype(np.float32)),
    ],
)
def test_other_arrays_take_the_checked_way(t, force) -> None:
    # Empty, 2-D or another dtype: not the common call; the conversions decide
    # (the float32 force is converted and gives the float64 result).
    if force.dtype == np.float32:
        q = cm.impact.duhamel(t, force, **KW)
        ref = cm.impact.duhamel(t, force.astype(np.float64), **KW)
        np.testing.assert_array_equal(q, ref)
        return
    with pytest.raises(CyclomechError):
        cm.impact.duhamel(t, force, **KW)
