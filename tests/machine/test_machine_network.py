"""The machine's cyclogram at many speeds: the shortest-path optimum and the LP
fallback for constraints over several operations, against Cyclogram.optimize."""

from __future__ import annotations

import cyclomech as cm
import numpy as np
import pytest


def _machine(constraints: list[dict]) -> cm.Machine:
    ops = [
        {"from": "a", "to": "b", "min_angle_deg": 40.0, "name": "ab"},
        {"from": "b", "to": "c", "min_angle_deg": 30.0, "min_duration_s": 0.02, "name": "bc"},
        {"from": "a", "to": "d", "min_angle_deg": 20.0, "name": "ad"},
        {"from": "d", "to": "c", "min_angle_deg": 25.0, "max_angle_deg": 60.0, "name": "dc"},
        {"from": "c", "to": "e", "min_angle_deg": 100.0, "min_duration_s": 0.05, "name": "ce"},
    ]
    return cm.Machine.from_dict(
        {
            "machine": {"name": "m", "speed_rpm": [100.0, 600.0]},
            "cyclogram": {"limiting": ["c", "e"]},
            "operation": ops,
            "constraint": constraints,
        }
    )


def _reference(m: cm.Machine, rpm: float) -> float:
    try:
        return m.cyclogram.optimize(speed_rpm=rpm).objective
    except cm.InfeasibleError:
        return float("nan")


SPEEDS = np.array([100.0, 250.0, 400.0, 500.0, 600.0])


@pytest.mark.parametrize(
    "constraints",
    [
        [],
        [
            {
                "name": "one op",
                "terms": [{"from": "a", "to": "b", "coeff": -1.0}],
                "sense": "<=",
                "rhs": -55.0,
            }
        ],
        [
            {
                "name": "two ops",
                "terms": [
                    {"from": "a", "to": "b", "coeff": 1.0},
                    {"from": "d", "to": "c", "coeff": 1.0},
                ],
                "sense": ">=",
                "rhs": 90.0,
            }
        ],
    ],
    ids=["bounds only", "single-operation constraint", "two-operation constraint (LP)"],
)
def test_speed_sweep_equals_the_lp_at_every_speed(constraints):
    m = _machine(constraints)
    s = m.speed_sweep(SPEEDS)
    ref = np.array([_reference(m, n) for n in SPEEDS])
    np.testing.assert_array_equal(np.isnan(s.limiting_deg), np.isnan(ref))
    np.testing.assert_allclose(s.limiting_deg, ref, rtol=0, atol=1e-7)
    assert s.fits.tolist() == np.isfinite(ref).tolist()


def test_the_lp_fallback_names_the_constraint_over_two_operations():
    con = {
        "name": "two ops",
        "terms": [{"from": "a", "to": "b", "coeff": 1.0}, {"from": "d", "to": "c", "coeff": 1.0}],
        "sense": ">=",
        "rhs": 90.0,
    }
    s = _machine([con]).speed_sweep([250.0])
    assert "two ops" in s.binding[0].split("; ")
    assert "cycle" in s.binding[0].split("; ")


def test_speed_limit_without_stops_is_the_cyclograms():
    m = _machine([])
    assert m.cyclogram_speed_limit() == pytest.approx(m.cyclogram.max_speed_rpm().rpm, rel=1e-9)
