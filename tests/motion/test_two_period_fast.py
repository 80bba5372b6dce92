"""The two-period law's array evaluation (issue 20): the range check runs inside
the lane kernel, block by block. Values against the closed form of the
cycloidal half law, thread counts and lengths that do not fill a lane group or a
block, and the refusal of a bad angle wherever it sits."""

from __future__ import annotations

import math

import cyclomech as cm
import numpy as np
import pytest

STROKE, ANGLE = 0.2, math.pi


def closed_form(law: cm.motion.TwoPeriodLaw, alpha: np.ndarray) -> np.ndarray:
    """Π(α) for cycloidal + cycloidal: Z(j) = j − sin(πj)/π in each period."""

    def z(j):
        return j - np.sin(np.pi * j) / np.pi

    p1, a1, p2, a2 = law.stroke1, law.angle1, law.stroke, law.angle
    return np.where(
        alpha <= a1,
        p1 * z(alpha / a1),
        p2 - (p2 - p1) * z(np.maximum((a2 - alpha) / (a2 - a1), 0.0)),
    )


@pytest.fixture(scope="module")
def law() -> cm.motion.TwoPeriodLaw:
    return cm.motion.two_period(STROKE, ANGLE, "cycloidal", "cycloidal", asymmetry=2.0)


@pytest.mark.parametrize("n", [1, 3, 4, 5, 255, 256, 257, 16_385, 1_000_003])
def test_positions_match_the_closed_form(law, n) -> None:
    alpha = np.linspace(0.0, ANGLE, n)
    got = law.position(alpha, n_threads=1)
    np.testing.assert_allclose(got, closed_form(law, alpha), rtol=0, atol=1e-15 * STROKE)
    np.testing.assert_array_equal(law.position(alpha, n_threads=2), got)


def test_each_angle_alone_is_the_array_value(law) -> None:
    alpha = np.random.default_rng(3).uniform(0.0, ANGLE, 1001)
    got = law.position(alpha)
    alone = np.array([law.position(a) for a in alpha[:50]])
    np.testing.assert_array_equal(alone, got[:50])


@pytest.mark.parametrize("where", [0, 7, 300, 16_384, 99_999])
@pytest.mark.parametrize("bad", [np.nan, -1e-12, ANGLE * (1 + 1e-15), np.inf])
@pytest.mark.parametrize("threads", [1, 2])
def test_a_bad_angle_anywhere_is_named(law, where, bad, threads) -> None:
    alpha = np.linspace(0.0, ANGLE, 100_000)
    alpha[where] = bad
    with pytest.raises(cm.CyclomechError, match=rf"alpha\[{where}\]") as e:
        law.velocity(alpha, n_threads=threads)
    assert isinstance(e.value, ValueError)


def test_the_other_orders_and_the_plain_laws_check_too() -> None:
    lw = cm.motion.two_period(STROKE, ANGLE, "cycloidal", "modified_sine", asymmetry=1.5)
    alpha = np.linspace(0.0, ANGLE, 5000)
    for f in (lw.position, lw.velocity, lw.acceleration):
        assert np.all(np.isfinite(f(alpha)))
    z = cm.motion.law("cycloidal")
    j = np.linspace(0.0, 1.0, 1001)
    np.testing.assert_allclose(z.z(j), j - np.sin(np.pi * j) / np.pi, rtol=0, atol=1e-15)
    j[999] = 1.5
    with pytest.raises(cm.CyclomechError, match=r"x\[999\]"):
        z.dz(j)


def test_out_is_filled_in_place_bit_for_bit(law) -> None:
    alpha = np.linspace(0.0, ANGLE, 7007).reshape(7, -1)[:, :1000].copy()
    for f in (law.position, law.velocity, law.acceleration):
        buf = np.full(alpha.shape, np.nan)
        assert f(alpha, out=buf) is buf
        np.testing.assert_array_equal(buf, f(alpha))
        f(alpha, out=buf, n_threads=2)
        np.testing.assert_array_equal(buf, f(alpha))


@pytest.mark.parametrize(
    ("out", "match"),
    [
        (np.zeros(9), "shape"),
        (np.zeros(10, dtype=np.float32), "float32"),
        (np.zeros(20)[::2], "not C-contiguous"),
        ([0.0] * 10, "list"),
    ],
)
def test_a_bad_out_is_refused(law, out, match) -> None:
    with pytest.raises(cm.CyclomechError, match=match):
        law.position(np.linspace(0.0, 1.0, 10), out=out)


def test_out_may_not_be_the_angles_or_read_only(law) -> None:
    alpha = np.linspace(0.0, 1.0, 10)
    with pytest.raises(cm.CyclomechError, match="shares memory"):
        law.position(alpha, out=alpha)
    ro = np.zeros(10)
    ro.flags.writeable = False
    with pytest.raises(cm.CyclomechError, match="read-only"):
        law.position(alpha, out=ro)
    with pytest.raises(cm.CyclomechError, match="single angle"):
        law.position(0.5, out=np.zeros(()))
