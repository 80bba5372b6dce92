"""Sizing against a brute-force search over the catalogue and the ratios, the batch
kernel against the per-candidate duty (hypothesis), and the loud answer when no
motor passes."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose
from servo_reference import CycloidalProgram, brute_choice, brute_margins

CATALOGUE = Path(__file__).resolve().parents[2] / "examples" / "motors.csv"
RATIOS = [0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 5.0, 8.0]


def _axis(load: object, gearbox: cm.servo.Gearbox, points: int = 720) -> cm.servo.ServoAxis:
    program = CycloidalProgram(0.12, 100.0, 80.0, 100.0)
    return cm.servo.ServoAxis(program, load, gearbox, points=points)


@pytest.mark.parametrize("rpm", [120.0, [60.0, 120.0, 160.0]])
def test_sizing_picks_what_a_brute_force_search_picks(rpm: object) -> None:
    """A ball-screw axis with a process force: every motor × ratio × speed by numpy
    sample by sample, the rules applied by a plain loop; the same motor, ratio,
    runners-up (in order) and margins."""
    load = cm.servo.LinearLoad(10.0, 0.05, force_n=80.0, efficiency=0.9)
    ax = _axis(load, cm.servo.Gearbox(1.0, efficiency=0.95, inertia_kg_m2=3e-5))
    got = cm.servo.size(ax, CATALOGUE, RATIOS, rpm, runners_up=6)
    motors = cm.servo.load_catalogue(CATALOGUE)
    want = brute_margins(ax, motors, RATIOS, rpm)
    assert_allclose(got.margins, want, rtol=1e-9, atol=1e-12)
    order = brute_choice(motors, RATIOS, want)
    assert got.status == "ok" and got.motor is not None and got.gearbox is not None
    assert (got.motor.name, got.gearbox.ratio) == order[0]
    assert [(r.motor, r.ratio) for r in got.runners_up] == order[1:7]
    assert got.gearbox.efficiency == 0.95 and got.gearbox.inertia_kg_m2 == 3e-5
    # The chosen motor is the first (by rated torque) with any passing ratio.
    passing = {name for name, _ in order}
    smaller = [m for m in motors if m.rated_torque_nm < got.motor.rated_torque_nm]
    assert smaller and not passing & {m.name for m in smaller}


def test_the_worst_speed_is_where_the_margin_is_smallest() -> None:
    load = cm.servo.RotaryLoad(0.02, torque_nm=3.0)
    ax = _axis(load, cm.servo.Gearbox(1.0, efficiency=0.9))
    rpm = [40.0, 90.0, 200.0]
    got = cm.servo.size(ax, CATALOGUE, [2.0, 4.0], rpm)
    motors = cm.servo.load_catalogue(CATALOGUE)
    each = np.stack([brute_margins(ax, motors, [2.0, 4.0], n) for n in rpm])
    assert_allclose(got.worst_rpm[..., :3], np.array(rpm)[each.argmin(axis=0)][..., :3])


def test_no_motor_passes_is_loud() -> None:
    """An impossible axis: a status, a warning naming the nearest candidate's
    binding check, and the nearest candidates instead of an empty table."""
    ax = _axis(cm.servo.RotaryLoad(50.0), cm.servo.Gearbox(1.0))
    with pytest.warns(
        cm.CyclomechWarning,
        match=r"no motor .* fails (peak_torque|rms_torque|speed|inertia_ratio) \(margin -",
    ):
        got = cm.servo.size(ax, CATALOGUE, [1.0, 3.0], 300.0, runners_up=3)
    assert got.status == "no motor passes" and got.motor is None and got.gearbox is None
    assert not got.choice.passes and len(got.runners_up) == 3
    least = got.margins.min(axis=2)
    assert math.isclose(
        min(getattr(got.choice, f"{c}_margin") for c in cm.servo.CHECKS), least.max()
    )
    assert (
        got.choice.binding
        == cm.servo.CHECKS[
            int(np.argmin([getattr(got.choice, f"{c}_margin") for c in cm.servo.CHECKS]))
        ]
    )


def test_equal_rated_torques_go_by_rotor_inertia() -> None:
    """Two motors of the same rated torque that both pass: the lower rotor inertia
    first, whatever the catalogue's order."""
    a = cm.servo.Motor(2.0, 6.0, 3000, 6000, 3e-4, name="heavy")
    b = cm.servo.Motor(2.0, 6.0, 3000, 6000, 1e-4, name="light")
    ax = _axis(cm.servo.RotaryLoad(1e-3), cm.servo.Gearbox(1.0))
    got = cm.servo.size(ax, [a, b], [1.0], 30.0)
    assert got.motor == b and got.runners_up[0].motor == "heavy"


@settings(max_examples=40, deadline=None)
@given(
    inertia=st.floats(0.0, 0.5),
    torque=st.floats(-20.0, 20.0),
    eta=st.floats(0.3, 1.0),
    gear_inertia=st.floats(0.0, 1e-3),
    ratios=st.lists(st.floats(0.5, 30.0), min_size=1, max_size=4),
    rpm=st.lists(st.floats(5.0, 400.0), min_size=1, max_size=3),
    rise=st.floats(30.0, 180.0),
)
def test_the_batch_kernel_gives_the_margins_of_duty(
    inertia: float,
    torque: float,
    eta: float,
    gear_inertia: float,
    ratios: list[float],
    rpm: list[float],
    rise: float,
) -> None:
    """Each candidate's margins from size (one envelope of lines per speed, RMS from
    three sums) equal the smallest over the speeds of ServoAxis.duty's (every
    sample), motor by motor and ratio by ratio."""
    program = CycloidalProgram(0.7, rise, 20.0, 120.0)
    ax = cm.servo.ServoAxis(
        program,
        cm.servo.RotaryLoad(inertia, torque),
        cm.servo.Gearbox(1.0, eta, gear_inertia),
        points=360,
    )
    motors = cm.servo.load_catalogue(CATALOGUE)[::4]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cm.CyclomechWarning)  # failing candidates count too
        got = cm.servo.size(ax, motors, ratios, rpm)
    for m, motor in enumerate(motors):
        for r, ratio in enumerate(ratios):
            gear = cm.servo.Gearbox(ratio, eta, gear_inertia)
            d = ax.duty(rpm, motor=motor, gearbox=gear)
            assert_allclose(got.margins[m, r], d.margins.min(axis=0), rtol=1e-9, atol=1e-9)
