"""A second new user's review: inputs the API took without a word, now refused by
name (each case the review's own)."""

from __future__ import annotations

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


def test_residual_vibration_refuses_a_size_that_cannot_fit() -> None:
    # 1e9 broadcast values ran to 9.8 GB and ~70 minutes without a word.
    with pytest.raises(cm.InputError, match=r"residual_vibration of 1000000000000 values needs"):
        cm.cam.residual_vibration("cycloidal", np.broadcast_to(1.0, (10**12,)))
    with pytest.raises(cm.InputError, match=r"tau\[1\] = nan must be finite"):
        cm.cam.residual_vibration("cycloidal", [1.0, np.nan])


def test_a_bad_number_prints_as_a_plain_float() -> None:
    # Was "a_max = np.float64(-0.0001) must be ...".
    with pytest.raises(cm.InputError, match=r"^a_max = -0\.0001 must be finite and > 0 \[m\]"):
        cm.impact.max_impact_speeds([cm.impact.StopImpact.example()], np.array([-1e-4]))


def test_a_cam_segment_no_angle_can_carry_is_said_so(tmp_path, capsys) -> None:
    from pathlib import Path

    from cyclomech.cli import main

    lifter = Path(__file__).resolve().parents[1] / "examples" / "lifter_cam.toml"
    code = main(["cam", str(lifter), "--rpm", "5000", "--no-plot", "--out", str(tmp_path)])
    out, err = capsys.readouterr()
    text = out + err
    assert code == 3
    # Was "70° < more than a whole turn, the smallest phase angle …".
    assert "segment 0 (rise): 70°, but no phase angle up to a whole turn meets" in text
    assert "more than a whole turn" not in text and "verdict" in out


def test_a_link_drawn_with_zero_length_is_named() -> None:
    # Was "step 0 of the program is invalid: lengths must be finite and positive".
    with pytest.raises(cm.InputError, match=r"link AB has zero length: A and B are drawn"):
        cm.Linkage(
            points={"A": (0, 0), "B": (0, 0), "C": (3.5, 2.5), "D": (4, 0)},
            links=[("A", "B"), ("B", "C"), ("C", "D")],
            ground=["A", "D"],
            driver=("A", "B"),
        )


def test_a_reversed_phase_grid_of_a_stop_is_refused() -> None:
    import tomllib
    from pathlib import Path

    loom = Path(__file__).resolve().parents[1] / "examples" / "stb_loom.toml"
    data = tomllib.loads(loom.read_text("utf-8"))
    data["mechanism"]["lifter"]["phase_deg"] = [55.0, 25.0, 4]
    with pytest.raises(cm.InputError, match=r"phase_deg = \[55.0, 25.0, 4\] must go up"):
        cm.Machine.from_dict(data, "loom.toml")
