"""The motion laws refuse what is not a number or not a form, by name (issue 16,
items 18 and 19); the valid forms keep their closed forms."""

from __future__ import annotations

import cyclomech as cm
import pytest


@pytest.mark.parametrize("bad", ["0.1", b"0.1", True])
@pytest.mark.parametrize("key", ["stroke", "angle", "max_speed"])
def test_item19_motion_two_period_takes_numbers_only(bad, key):
    """motion's own copy of the positive-number check used float(): the string
    "0.1" was read as 0.1 and True as 1. One check (_arrays.positive) serves the
    impact, transfer and motion modules now."""
    kw = {"stroke": 0.1, "angle": 3.0, "law1": "cycloidal", "law2": "cycloidal"}
    kw["max_speed" if key == "max_speed" else "asymmetry"] = 0.08 if key == "max_speed" else 0.5
    kw[key] = bad
    with pytest.raises(cm.InputError, match=rf"{key} must be a number"):
        cm.motion.two_period(**kw)


def test_item19_motion_law_form_is_checked_by_the_constructor_too():
    # main: MotionLaw("cycloidal", "bogus") was silently the half law.
    with pytest.raises(cm.InputError, match=r"form = 'bogus' must be 'half'"):
        cm.motion.MotionLaw("cycloidal", "bogus")
    # The valid forms: the cycloidal rise's peak speed Z' is 2 (closed form
    # Z = x − sin(2πx)/(2π)), the same law as cm.motion.law gives.
    assert cm.motion.MotionLaw("cycloidal", "rise").dz_max == pytest.approx(2.0, rel=1e-12)
