"""The cyclogram's and a stop's arguments are checked (issue 16, item 18):
values they accepted without a word are InputErrors naming the argument."""

from __future__ import annotations

import math
import re

import cyclomech as cm
import pytest


@pytest.mark.parametrize(
    ("call", "words"),
    [
        (lambda: cm.Operation("a", "b", min_angle_deg=math.nan), "min_angle_deg must be finite"),
        (lambda: cm.Operation("a", "b", min_duration_s=-5.0), "min_duration_s must be >= 0"),
        (lambda: cm.Operation("a", "b", height=-1), "height must be a non-negative integer"),
        (lambda: cm.Operation("a", "a"), "two different events"),
        (lambda: cm.Cyclogram(limiting=3), "limiting = 3 must be an operation's name"),
        (
            lambda: cm.Operation("a", "b", 120.0, min_duration_s=0.1).min_angle_at(math.nan),
            "speed_rpm must be finite",
        ),
        (
            lambda: cm.impact.StopImpact.example().constraint("abc", 1e-4, 280.0),
            "arc = 'abc' must be an operation's two event names",
        ),
    ],
)
def test_item18_cyclogram_and_stop_arguments_are_checked(call, words):
    """These were accepted: Operation(min_angle_deg=nan, min_duration_s=-5,
    height=-1), Cyclogram(limiting=3), min_angle_at(nan) → 120, and
    StopImpact.constraint("abc", …) made the arc ('a', 'b')."""
    with pytest.raises(cm.InputError, match=re.escape(words)):
        call()
