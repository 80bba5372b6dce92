"""``SpeedNetwork.minimums_fit``: the minimum angles alone against the cycle,
checked against the closed form of a two-operation cyclogram (a→b at least
max(100°, wear), at most 110°; b→c at least 60°): the minimums fit while
wear + 60 ≤ 360, the whole cyclogram while wear ≤ 110."""

from __future__ import annotations

import cyclomech as cm
import numpy as np
from hypothesis import given
from hypothesis import strategies as st


@given(st.lists(st.floats(0.0, 400.0), min_size=1, max_size=8))
def test_minimums_fit_is_the_closed_form(wear):
    cg = cm.Cyclogram(limiting=("b", "c"))
    cg.add_operation("a", "b", min_angle_deg=100, max_angle_deg=110)
    cg.add_operation("b", "c", min_angle_deg=60)
    net = cm.cyclogram.SpeedNetwork(cg, [(("a", "b"), "wear")])
    w = np.array(wear)
    rpm = np.ones_like(w)
    got = net.minimums_fit(rpm, [w], 1)
    full = net.solve(rpm, [w], 1)[1]
    far = np.abs(np.maximum(w, 100.0) + 60.0 - 360.0) > 1e-6
    assert (got == (np.maximum(w, 100.0) + 60.0 <= 360.0))[far].all()
    assert (full == (w <= 110.0))[np.abs(w - 110.0) > 1e-6].all()
    assert not (full & ~got).any()  # what fits whole fits by its minimums
