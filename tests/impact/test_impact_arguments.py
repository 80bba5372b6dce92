"""The impact functions' arguments: inputs they took without a word (a second new
user's review, each case the review's own; issue 16, items 16, 18 and 19) are now
refused by name, and the valid ones keep their closed forms."""

from __future__ import annotations

import math
import warnings

import cyclomech as cm
import numpy as np
import pytest


def test_natural_frequency_names_shapes_that_do_not_broadcast() -> None:
    # Was numpy's raw "operands could not be broadcast together" from deep inside.
    with pytest.raises(cm.InputError, match=r"stiffness \(3,\), mass \(4,\): these shapes"):
        cm.impact.natural_frequency(np.ones(3) * 1e5, np.ones(4) * 1e-3)
    with pytest.raises(cm.InputError, match=r"stiffness \(2,\), mass \(3,\)"):
        cm.impact.contact_time(np.ones(2), np.ones(3))
    # Broadcasting still works, and the value is the closed form √(c/m)/2π.
    f = cm.impact.natural_frequency(np.array([1e5, 4e5]), 1e-3)
    np.testing.assert_allclose(f, np.sqrt(np.array([1e5, 4e5]) / 1e-3) / (2 * np.pi))


@pytest.mark.parametrize(
    ("t", "f", "match"),
    [
        ("abc", [1.0, 0.0], "arrays of numbers"),
        ([0.0, np.nan], [1.0, 0.0], r"t\[1\] = nan must be finite"),
        ([0.0, 1e-3, 2e-3], [1.0, 2.0], "one length"),
        ([1e-3, 2e-3], [1.0, 0.0], r"t\[0\] = 0.001 must be 0"),
    ],
)
def test_a_pulse_built_directly_is_checked_as_a_table(t, f, match) -> None:
    # Pulse(...) took all of these; only Pulse.table checked.
    with pytest.raises(cm.InputError, match=match):
        cm.impact.Pulse(t, f)


def test_a_pulse_built_directly_is_read_only_floats() -> None:
    p = cm.impact.Pulse([0, 1e-3, 2e-3], [0, 5, 0])
    assert p.t.dtype == np.float64 and not p.t.flags.writeable and p.peak == 5.0
    assert cm.impact.Pulse.rectangular(2.0, 1e-3).t.tolist() == [0.0, 1e-3, 1e-3]


def test_a_bad_number_prints_as_a_plain_float() -> None:
    # Was "a_max = np.float64(-0.0001) must be ...".
    with pytest.raises(cm.InputError, match=r"^a_max = -0\.0001 must be finite and > 0 \[m\]"):
        cm.impact.max_impact_speeds([cm.impact.StopImpact.example()], np.array([-1e-4]))


def test_a_reversed_phase_grid_of_a_stop_is_refused() -> None:
    import tomllib
    from pathlib import Path

    loom = Path(__file__).resolve().parents[2] / "examples" / "stb_loom.toml"
    data = tomllib.loads(loom.read_text("utf-8"))
    data["mechanism"]["lifter"]["phase_deg"] = [55.0, 25.0, 4]
    with pytest.raises(cm.InputError, match=r"phase_deg = \[55.0, 25.0, 4\] must go up"):
        cm.Machine.from_dict(data, "loom.toml")


# ---------------------------------------------------------------------------
# Item 16: tolerances and counts of the impact functions.


@pytest.mark.parametrize("rtol", [math.nan, 0.0, -1e-6, 1e-300, 1.0, math.inf, "1e-9", True])
def test_item16_max_impact_speed_rtol_outside_its_range_is_refused(rtol):
    # Rule: rtol in [1e-15, 0.5]. Below, the rebounds' rounding (~1e-16) cannot
    # meet it; at 1 or more it is no tolerance (main took 1e-300 and 1.0).
    stop = cm.impact.StopImpact.example()
    with pytest.raises(cm.InputError, match=r"rtol"):
        cm.impact.max_impact_speeds([stop], 0.1e-3, rtol=rtol)


def test_item16_max_impact_speed_tolerance_is_met_at_both_ends_of_its_range():
    # Reference: the pulse model's rebound is linear in the impact speed, so
    # v* = a_max / rebound(1 m/s), a closed form independent of the search.
    stop = cm.impact.StopImpact.example(model="contact")
    a_max = 0.1e-3
    v_tight = cm.impact.max_impact_speeds([stop], a_max, rtol=1e-15)[0]
    v_loose = cm.impact.max_impact_speeds([stop], a_max, rtol=0.5)[0]
    # Both are admissible (rebound ≤ a_max), the loose one within 50 % below.
    r = cm.impact.rebounds([stop, stop], [[v_tight], [v_loose]])
    assert r[0, 0] <= a_max and r[1, 0] <= a_max
    assert 0.5 * v_tight <= v_loose <= v_tight
    # Just above v* is too much: v_tight is the edge to ~1e-12.
    assert cm.impact.rebounds([stop], [[v_tight * (1 + 1e-11)]])[0, 0] > a_max
    with pytest.raises(cm.InputError, match=r"tol_deg = 1e-20 must lie in \[3.6e-13, 180\]"):
        cm.impact.StopImpact.example().min_phase_angle(a_max, 280, tol_deg=1e-20)


def test_item16_counts_are_integers_in_range():
    # Rule: a count is an int, a numpy integer or a 0-d integer array; a bool, a
    # float (2.5 was truncated to 2), a string is refused, naming the range.
    p = cm.impact.Pulse.half_sine(1.0, 1e-3, points=257)
    for ok in (np.int64(257), np.array(257)):
        q = cm.impact.Pulse.half_sine(1.0, 1e-3, points=ok)
        np.testing.assert_array_equal(q.t, p.t)
    for bad in (257.0, 2.5, True, "257", 2):
        with pytest.raises(cm.InputError, match=r"points must be an integer between 3 and"):
            cm.impact.Pulse.half_sine(1.0, 1e-3, points=bad)
    lever = cm.impact.StopImpact.example()
    with pytest.raises(cm.InputError, match=r"points must be an integer between 2"):
        lever.linearize((30, 45), 420, points=2.5)
    with pytest.raises(cm.InputError, match=r"max_rebounds must be an integer ≥ 1; got 2.5"):
        cm.impact.contact_response(mass=1.0, k_free=1.0, k_stop=99.0, v0=-1.0, max_rebounds=2.5)
    # np.int64 is a count: 2 undamped rebounds, each of height v0·√(m/k_free) = 1
    # (closed form).
    h = cm.impact.contact_response(
        mass=1.0, k_free=1.0, k_stop=99.0, v0=-1.0, max_rebounds=np.int64(2)
    )
    np.testing.assert_allclose(h.rebound_height, [1.0, 1.0], rtol=1e-12)


# ---------------------------------------------------------------------------
# Items 18-19: unchecked arguments and types of the impact functions.


def test_item18_phase_angles_refuses_nan_and_negative_speeds():
    # main: [30, nan, 1e-9] (a negative speed became the 1e-9° floor).
    with pytest.raises(cm.InputError, match=r"rpm\[1\] = nan must be finite and > 0"):
        cm.impact.min_phase_angles([300, math.nan, -300], 0.1)
    with pytest.raises(cm.InputError, match=r"rpm\[0\] = -300.0 must be finite and > 0"):
        cm.impact.min_phase_angles([-300], 0.1)
    with pytest.raises(cm.InputError, match=r"per_rpm = -0.1 must be ≥ 0 \[deg/rpm\] \(inf"):
        cm.impact.min_phase_angles([300], -0.1)
    with pytest.raises(cm.InputError, match=r"per_rpm = nan must be ≥ 0"):
        cm.impact.min_phase_angles([300], math.nan)
    # Valid input: n·per_rpm, by hand, and a scalar stays a scalar.
    np.testing.assert_allclose(cm.impact.min_phase_angles([100.0, 4000.0], 0.1), [10.0, math.nan])
    assert np.ndim(cm.impact.min_phase_angles(100.0, 0.1)) == 0
    # +inf per rpm (v* = 0, or one so small the slope passes the float range): no
    # phase angle of one turn will do, as Proportional's law says.
    assert np.isnan(cm.impact.min_phase_angles([1e-6, 300.0], math.inf)).all()


def test_a_subnormal_rebound_limit_is_a_bound_no_speed_meets():
    # Random sweeps drew a_max = 5e-324 m: v* became subnormal and phase_per_rpm's
    # division overflowed (a RuntimeWarning, then min_phase_angle refused its own inf).
    # Such a limit is met by no speed: inf per rpm, NaN angles, no warning.
    lever = cm.impact.StopImpact.example()
    v = lever.max_impact_speed(5e-324)
    assert 0.0 <= v < 1e-300
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert lever.phase_per_rpm(v) == math.inf
        assert np.isnan(lever.min_phase_angle(5e-324, [1e-6, 100.0])).all()
    # The next limit up still has a finite (huge) slope: the law is n·per_rpm.
    assert math.isfinite(lever.phase_per_rpm(lever.max_impact_speed(1e-300)))


def test_item18_rebounds_refuses_negative_impact_speeds():
    # An impact speed is a magnitude; main returned a rebound for -0.2 m/s.
    lever = cm.impact.StopImpact.example()
    with pytest.raises(cm.InputError, match=r"v0\[0, 1\] = -0.2 must be a finite impact speed"):
        cm.impact.rebounds([lever], [[0.2, -0.2]])


@pytest.mark.parametrize("field", ["x0", "v0"])
@pytest.mark.parametrize("bad", ["1", b"1", True, 1j])
def test_item19_contact_start_refuses_strings_bytes_bools_and_complex(field, bad):
    kw = {"mass": 1.0, "k_free": 1.0, "k_stop": 99.0, "v0": -1.0, field: bad}
    with pytest.raises(cm.InputError, match=field):
        cm.impact.contact_response(**kw)
    with pytest.raises(cm.InputError, match=field):
        cm.impact.contact_sample([0.0], **kw)


@pytest.mark.parametrize(
    "kw",
    [{"omega_n": "1866"}, {"zeta": True}, {"mass": b"1"}, {"omega_n": 1866 + 1j}, {"q0": "0"}],
)
def test_item19_duhamel_refuses_strings_bools_bytes_and_complex(kw):
    # main ran duhamel(omega_n="1866", zeta=True, mass=b"1") as numbers.
    args = {"omega_n": 1866.0, "zeta": 0.1, "mass": 1.0, **kw}
    with pytest.raises(cm.InputError, match=next(iter(kw))):
        cm.impact.duhamel([0.0, 1e-3], [0.0, 1.0], **args)
    # Per-case arrays: a bool array is not numbers either.
    with pytest.raises(
        cm.InputError, match="zeta must be an array of real numbers; got dtype bool"
    ):
        cm.impact.first_rebound([0.0], [[0.0]], 1.0, [True], 1.0)


def test_item19_numpy_scalars_are_numbers():
    # np.float64 and 0-d arrays are accepted, with the closed form of the undamped
    # step response q = F/k·(1 − cos ωt) at ωt = π: 2F/(mω²).
    w = np.float64(2.0)
    q = cm.impact.duhamel(
        [0.0, 0.0, math.pi / 2], [0.0, 1.0, 1.0], omega_n=w, zeta=np.array(0.0), mass=1.0
    )
    assert q[-1] == pytest.approx(2 * 1.0 / 4.0, rel=1e-14)
