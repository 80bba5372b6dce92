"""The batched stop designs of a machine sweep (issue 20): one Rust call builds and
solves every design of a chunk, bit for bit the per-design path (one Machine and
one StopImpact per design, ``sweep(..., batch=False)``), which stays the reference."""

from __future__ import annotations

from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
from cyclomech import _core
from cyclomech.impact._batch import BATCH_KEYS
from cyclomech.machine._batch import batch_designs, plan
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

DATA = Path(__file__).parent / "data"
LOOM = DATA / "stb_loom_stop_only.toml"
LOOM_CAM = Path(__file__).parents[2] / "examples" / "stb_loom.toml"


def same(a: cm.SweepResult, b: cm.SweepResult) -> None:
    assert list(a.columns) == list(b.columns)
    for k, v in b.columns.items():
        w = a.columns[k]
        if v.dtype == object:
            assert (w == v).all(), k
        else:
            assert np.array_equal(w, v, equal_nan=v.dtype.kind == "f"), k


@pytest.fixture(scope="module")
def loom() -> cm.Machine:
    return cm.Machine.from_toml(LOOM)


def test_preload_sweep_is_bit_for_bit(loom) -> None:
    grid = {"lifter.preload_m": np.linspace(1e-4, 5e-4, 70), "speed_rpm": np.linspace(200, 500, 9)}
    a = cm.sweep(loom, grid, progress=False, chunk=16)
    b = cm.sweep(loom, grid, progress=False, n_threads=1, batch=False)
    same(a, b)
    assert a.columns["fits"].any() and not a.columns["fits"].all()


def test_the_loom_with_its_cam_is_bit_for_bit() -> None:
    # The cam's bounds are shared by the designs; the stop takes its law from the cam.
    m = cm.Machine.from_toml(LOOM_CAM)
    grid = {"lifter.preload_m": [1e-4, 3e-4, 9.5e-3], "speed_rpm": [250.0, 400.0, 480.0]}
    a = cm.sweep(m, grid, progress=False)
    same(a, cm.sweep(m, grid, progress=False, batch=False))
    assert a.n_invalid == 3  # preload beyond the stroke: the reader's own message
    assert "must be smaller than stroke" in a.columns["problem"][-1]


# Each key with values around the loom's lifter, some of them invalid.
_VALUES = {
    "preload_m": st.floats(-1e-4, 1.2e-2),
    "stroke_m": st.floats(2e-3, 2e-2),
    "a_max_m": st.floats(-1e-5, 5e-4),
    "zeta": st.floats(-0.01, 0.5),
    "restitution": st.floats(0.0, 1.05),
    "E_pa": st.floats(5e10, 3e11),
    "a_m": st.floats(0.01, 0.2),
    "b_m": st.floats(0.02, 0.2),
    "J_A_kg_m2": st.floats(1e-5, 3e-4),
    "J_x_m4": st.floats(1e-11, 2e-10),
    "lever_length_m": st.floats(0.05, 0.2),
    "mass_kg": st.floats(1e-3, 2e-2),
    "contact_time_s": st.floats(1e-4, 3e-3),
    "contact_stiffness_n_per_m": st.floats(1e4, 5e5),
}


@st.composite
def grids(draw):
    keys = draw(st.lists(st.sampled_from(sorted(_VALUES)), min_size=1, max_size=3, unique=True))
    grid = {
        f"lifter.{k}": draw(st.lists(_VALUES[k], min_size=1, max_size=4, unique=True)) for k in keys
    }
    grid["speed_rpm"] = draw(st.lists(st.floats(50.0, 900.0), min_size=1, max_size=5))
    pulse = draw(st.sampled_from(["decaying", "rectangular", "triangular"]))
    return grid, pulse


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(grids())
# A subnormal rebound limit: its slope passes the float range (inf: fits at no speed).
@example(({"lifter.a_max_m": [5e-324], "speed_rpm": [50.0]}, "decaying"))
def test_random_grids_are_bit_for_bit(case) -> None:
    grid, pulse = case
    m = cm.Machine.example()
    data = dict(m.data)
    data["mechanism"] = {"lifter": {**m.data["mechanism"]["lifter"], "pulse": pulse}}
    m = cm.Machine.from_dict(data, "<test>")
    assert plan(m, [k for k in grid if k != "speed_rpm"]) is not None
    a = cm.sweep(m, grid, progress=False, chunk=5)
    b = cm.sweep(m, grid, progress=False, n_threads=1, batch=False)
    same(a, b)


def test_the_kernel_against_stopimpact_and_the_closed_form(loom) -> None:
    preloads = np.linspace(1e-5, 9e-3, 57)
    pl = plan(loom, ["lifter.preload_m"])
    tables, ok = batch_designs(loom, pl, {"lifter.preload_m": preloads})
    assert ok.all()
    rpm = np.array([100.0, 300.0, 5000.0])
    stop = loom.mechanisms["lifter"].stop
    j, dz, v, unit, per, mins, g = _core.stop_design_batch(
        stop.law.name, True, None, 0, tables["lifter"], rpm, n_threads=2
    )
    for i, p in enumerate(preloads):
        s = cm.impact.StopImpact.example(preload=float(p), restitution=0.5556)
        assert (j[i], dz[i]) == (s.j_contact, s.dz_contact)
        assert v[i] == s.max_impact_speed(1e-4)
        assert unit[i] == s.phase_per_rpm(1.0) and per[i] == s.phase_per_rpm(v[i])
        want = s.min_phase_angle(1e-4, rpm)
        assert np.array_equal(mins[i], want, equal_nan=True)
        # Independent: the law meets the stop there, and the pulse model is linear
        # in the impact speed, so the rebound at v* is a_max to rounding.
        assert abs(s.law.z(j[i]) - (1.0 - p / s.stroke)) < 1e-14
        assert abs(float(s.rebound(300.0, mins[i, 1])) - 1e-4) < 1e-15
        # g is the rebound at 1 m/s, bit for bit StopImpact's.
        assert g[i] == cm.impact.rebounds([s], [[1.0]])[0, 0]


def test_binding_errors_are_input_errors(loom) -> None:
    pl = plan(loom, ["lifter.preload_m"])
    tables, _ = batch_designs(loom, pl, {"lifter.preload_m": np.array([1e-4, 2e-4, 3e-4])})
    t = tables["lifter"]
    with pytest.raises(cm.InputError, match="designs must have 8 rows"):
        _core.stop_design_batch("modified_sine", True, None, 0, t[:7].copy(), np.ones(1))
    with pytest.raises(cm.InputError, match="designs must be a C-contiguous"):
        _core.stop_design_batch("modified_sine", True, None, 0, np.asfortranarray(t), np.ones(1))
    with pytest.raises(cm.InputError, match="pulse must be 0"):
        _core.stop_design_batch("modified_sine", True, None, 7, t, np.ones(1))
    with pytest.raises(ValueError, match="law"):
        _core.stop_design_batch("no_such_law", True, None, 0, t, np.ones(1))


def test_what_falls_back_to_the_per_design_path(loom) -> None:
    assert plan(loom, ["machine.speed_points"]) is None
    assert plan(loom, ["lifter.phase_deg"]) is None
    assert plan(loom, []) is None
    assert {"preload_m", "a_max_m", "contact_time_s"} <= BATCH_KEYS
    contact = cm.Machine.example()
    data = dict(contact.data)
    data["mechanism"] = {"lifter": {**data["mechanism"]["lifter"], "model": "contact"}}
    assert plan(cm.Machine.from_dict(data), ["lifter.preload_m"]) is None
    data["mechanism"] = {"lifter": {**contact.data["mechanism"]["lifter"], "pulse": "half_sine"}}
    assert plan(cm.Machine.from_dict(data), ["lifter.preload_m"]) is None
    cam = cm.Machine.from_toml(LOOM_CAM)
    assert plan(cam, ["lifter.lever_length_m"]) is None  # the stroke follows the cam's lever
    assert plan(cam, ["lifter.preload_m", "lifter cam.base_radius_m"]) is None
    assert plan(cam, ["lifter.preload_m"]) is not None
    # A fallback still sweeps: a machine key, the per-design way.
    r = cm.sweep(loom, {"machine.speed_fluctuation": [0.05], "speed_rpm": [300.0]}, progress=False)
    assert r.n_points == 1
    with pytest.raises(cm.InputError, match="batch must be True or False"):
        cm.sweep(loom, {"speed_rpm": [300.0]}, batch=1)  # type: ignore[arg-type]


def test_results_do_not_depend_on_chunks_or_threads(loom) -> None:
    grid = {"lifter.preload_m": np.linspace(1e-4, 5e-4, 23), "speed_rpm": np.linspace(300, 450, 5)}
    ref = cm.sweep(loom, grid, progress=False, n_threads=1)
    for chunk, threads in ((1, 2), (7, 1), (23, 2)):
        same(cm.sweep(loom, grid, progress=False, chunk=chunk, n_threads=threads), ref)
