"""The cyclogram speed limit's reason names what stops the fit just above it
(probe B4): "fills the cycle" only when the minimum angles fill it; when a
speed-dependent minimum rises into a ``max_angle_deg``, the conflicting pair.
Machines built here from the STB loom example, with and without a maximum of 25°
on the approach to the upper stop (3→7), whose lifter's rebound bound rises with
the speed."""

from __future__ import annotations

import copy
import tomllib
from pathlib import Path

import cyclomech as cm
import pytest
from scipy.optimize import brentq

ROOT = Path(__file__).resolve().parents[2]
LOOM = tomllib.loads((ROOT / "examples" / "stb_loom.toml").read_text(encoding="utf-8"))


def loom(max_deg: float | None) -> cm.Machine:
    data = copy.deepcopy(LOOM)
    if max_deg is not None:
        (op,) = [o for o in data["operation"] if (o["from"], o["to"]) == ("3", "7")]
        op["max_angle_deg"] = max_deg
    return cm.Machine.from_dict(data, "loom.toml")


def test_a_rebound_rising_into_a_maximum_is_named_as_the_conflict():
    m = loom(25.0)
    lim = m.speed_limit()
    # Reference: the speed at which the lifter's rebound bound reaches 25°, by a
    # root finder on the bound itself (not the speed-limit search).
    n25 = brentq(lambda n: m.bound_angles([n])["lifter"][0] - 25.0, 100.0, 400.0, xtol=1e-9)
    assert lim.by == "cyclogram"
    assert lim.rpm == pytest.approx(n25, rel=1e-8)
    assert lim.reason.startswith("max[approach upper stop] against rebound[lifter]: ")
    assert "fills the cycle" not in lim.reason
    assert set(lim.binding) == {"max[approach upper stop]", "rebound[lifter]"}
    # Not filling: just under the limit the limiting operation keeps far more than
    # its minimum (the probe: 273° against 147° at 245 rpm).
    opt = m.optimize(0.999 * lim.rpm)
    lo = m.cyclogram_at(0.999 * lim.rpm).min_angles()
    e = [o.arc for o in m.cyclogram.operations].index(m.cyclogram.limiting)
    assert opt.objective > lo[e] + 50.0


def test_minimums_that_fill_the_cycle_say_so():
    m = loom(None)
    lim = m.speed_limit()
    assert lim.reason.startswith("the cyclogram fills the cycle; bounded by ")
    assert "cycle" in lim.binding
    # Reference: the LP (scipy's HiGHS, not the network) just above the limit
    # names a conflict of lower bounds and the cycle alone, no maximum.
    with pytest.raises(cm.InfeasibleError) as got:
        m.optimize(lim.rpm * (1.0 + 1e-6))
    names = [str(c) for c in got.value.conflict]
    assert "cycle" in names
    assert not [c for c in names if c.startswith("max[")]
