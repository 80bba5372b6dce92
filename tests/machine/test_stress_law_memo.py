"""The cam's Hertz stress laws keep their answers (``cyclomech.cam._kind._MEMO``):
given again only for the same inputs and speeds, and then bit for bit what the Rust
call without the memo gives (the present path, :meth:`Cam.min_phase_angles`)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.cam import _kind

ROOT = Path(__file__).resolve().parents[2]
LOOM = ROOT / "examples" / "stb_loom.toml"


def stress_laws(machine: cm.Machine) -> list[_kind._PerSpeed]:
    laws = machine.mechanisms["lifter cam"].laws()
    return [law for law in laws if isinstance(law, _kind._PerSpeed)]


def direct(law: _kind._PerSpeed, speeds: np.ndarray) -> np.ndarray:
    """The law's column from the Rust call itself, no memo in the way."""
    d = law.design
    m = d.cam.min_phase_angles(
        speeds,
        loads=d.loads,
        contact=d.contact,
        max_stress=d.max_stress,
        max_pressure_angle_deg=d.max_pressure_angle_deg,
        segments=[law.segment],
    )
    return m.angle_deg[:, 0, law.column]


def same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    a, b = np.asarray(a, np.float64), np.asarray(b, np.float64)
    return a.shape == b.shape and a.tobytes() == b.tobytes()


def test_a_kept_answer_is_the_rust_calls_bit_for_bit():
    _kind._MEMO.clear()
    speeds = np.array([[430.0, 400.0, 415.5], [400.0, 430.0, 430.0]])
    first = stress_laws(cm.Machine.from_toml(LOOM))
    again = stress_laws(cm.Machine.from_toml(LOOM))  # new objects, the same inputs
    assert len(first) == 3
    for a, b in zip(first, again, strict=True):
        assert a is not b and a._key == b._key
        want = direct(a, np.unique(speeds))[np.unique(speeds, return_inverse=True)[1]]
        want = want.reshape(speeds.shape)
        got = a(speeds)  # the Rust call, kept
        assert np.all(np.isfinite(got)) and same_bits(got, want)
        assert same_bits(b(speeds), want)  # given again, to the bit
    assert len(_kind._MEMO) == 3  # one per segment: the second machine asked nothing new
    # The kept arrays cannot be changed by a caller.
    assert not any(v.flags.writeable for v in _kind._MEMO.values())


@pytest.mark.parametrize(
    "key",
    [
        "lifter cam.base_radius_m",
        "lifter cam.roller_radius_m",
        "lifter cam.pivot_distance_m",
        "lifter cam.arm_length_m",
        "lifter cam.inertia_kg_m2",
        "lifter cam.width_m",
        "lifter cam.max_stress_pa",
        "lifter cam.max_pressure_angle_deg",
        "lifter cam.segment.1.load_nm",
    ],
)
def test_every_input_of_the_call_is_in_the_key(key):
    m = cm.Machine.from_toml(LOOM)
    base = {law.segment: law._key for law in stress_laws(m)}
    v = m.with_values({key: _value(m, key) * 1.001})
    changed = {law.segment: law._key for law in stress_laws(v)}
    assert base.keys() == changed.keys()
    assert all(changed[k] != base[k] for k in base)


def _value(m: cm.Machine, key: str) -> float:
    """The number at ``key`` in the machine's file (dotted path, lists from 1)."""
    name, *path = key.replace("lifter cam", "lifter_cam").split(".")
    name = name.replace("_", " ")
    x = m.data["mechanism"][name]
    for p in path:
        x = x[int(p) - 1] if isinstance(x, list) else x[p]
    return float(x)


def test_a_variant_that_leaves_the_cam_shares_its_answers_and_its_limit_is_the_same():
    m = cm.Machine.from_toml(LOOM)
    variants = [
        m,
        m.with_values({"lifter cam.damping_ratio": 0.05 * 1.001}),  # vibration only
        m.with_values({"lifter.a_max_m": 1.001e-4}),  # another mechanism's key
        m.with_values({"lifter cam.max_stress_pa": 9e8 * 1.001}),  # the stress law's
    ]
    calls = []
    real = cm.cam.Cam.min_phase_angles

    def counted(self, *args, **kwargs):
        calls.append(1)
        return real(self, *args, **kwargs)

    mp = pytest.MonkeyPatch()
    mp.setattr(cm.cam.Cam, "min_phase_angles", counted)
    try:
        mp.setattr(_kind, "_MEMO_SIZE", 0)  # the present path: every answer computed
        _kind._MEMO.clear()
        fresh = cm.machine.speed_limits([x for x in map(_rebuilt, variants)])
        without = len(calls)
        mp.setattr(_kind, "_MEMO_SIZE", 1024)
        _kind._MEMO.clear()
        calls.clear()
        kept = cm.machine.speed_limits([x for x in map(_rebuilt, variants)])
    finally:
        mp.undo()
    assert [x.rpm for x in kept] == [x.rpm for x in fresh]
    assert [x.binding for x in kept] == [x.binding for x in fresh]
    assert kept[3].rpm != kept[0].rpm  # the stress binds: its variant moved the limit
    assert len(calls) < without


def _rebuilt(m: cm.Machine) -> cm.Machine:
    """The variant with fresh mechanisms (their laws not yet worked out)."""
    return m.with_values({})


def test_a_cam_of_a_motion_program_is_not_kept():
    """Its kernel is built from the program, which the key does not hold by value."""
    law = stress_laws(cm.Machine.from_toml(LOOM))[0]
    M = cm.motion.Segment
    program = cm.motion.Program([M("poly5", 120, end=0.02), M("dwell", 90), M("poly5", 150, end=0)])
    cam = cm.cam.Cam(program, cm.cam.TranslatingRoller(0.05, 0.012, 0.004))
    design = replace(law.design, cam=cam, loads=None, contact=None, max_stress=None)
    assert _kind._PerSpeed(design, 0, law.column)._key is None
