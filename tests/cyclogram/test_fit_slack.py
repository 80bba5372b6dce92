"""One tolerance for "fits" (probe B3): the speed-limit search
(``SpeedNetwork.speed_limits``, Rust shortest paths) and the fit check before
every solve (``check_fits``, Howard's cycle ratio) must agree, so the cyclogram
solves at the very speed the search reports. Random chains of operations whose
durations fill the cycle at the limit; the limit checked against Howard's
``max_speed_rpm`` (a different algorithm) and solved there by the LP."""

from __future__ import annotations

import re
from pathlib import Path

import cyclomech as cm
from cyclomech.cyclogram._speed import DIFFERENCE_RTOL
from hypothesis import given, settings
from hypothesis import strategies as st

ROOT = Path(__file__).resolve().parents[2]


def test_the_tolerance_is_the_rust_solvers():
    src = (ROOT / "rust" / "core" / "src" / "cyclogram" / "difference.rs").read_text()
    (value,) = re.findall(r"pub const DIFFERENCE_RTOL: f64 = ([0-9.e-]+);", src)
    assert float(value) == DIFFERENCE_RTOL


@settings(max_examples=40, deadline=None)
@given(
    st.lists(
        st.tuples(st.floats(0.0, 90.0), st.sampled_from([0.0, 0.01, 0.35]) | st.floats(1e-4, 0.4)),
        min_size=2,
        max_size=7,
    )
)
def test_the_cyclogram_solves_at_the_limit_it_reports(ops):
    cg = cm.Cyclogram(limiting=("e0", "e1"))
    for i, (angle, secs) in enumerate(ops):
        cg.add_operation(f"e{i}", f"e{i + 1}", min_angle_deg=angle, min_duration_s=secs)
    if sum(a for a, _ in ops) >= 350.0 or not any(s for _, s in ops):
        return
    net = cm.cyclogram.SpeedNetwork(cg)
    limit = float(net.speed_limits(lambda d, n: [], 1, 10.0)[0])
    howard = cg.max_speed_rpm().rpm
    assert abs(limit / howard - 1.0) <= 1e-9
    cg.optimize(speed_rpm=limit)  # no "360° > 360°"
