"""The machine's shaking force in ``cyclomech run`` (issue 34 item 6, the frame's
part): what the report, results.json and the CLI carry. The force itself is checked
against the momentum balance and closed forms in ``test_shaking*.py``; here, that the
machine's figures are the phased sum of its mechanisms' own (each mechanism's
shaking at its phase in the optimised cyclogram, from :func:`cyclomech.dynamics.shaking`
of its kinetostatics, rolled by hand), and what a machine without inertia forces
at a phase gets.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from typing import Any

import cyclomech as cm
import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def knife() -> Any:
    return cm.machine.analyze(
        cm.Machine.from_toml(ROOT / "examples/knife_cutter.toml"), progress=False
    )


def test_the_machine_is_its_linkage_at_its_phase(knife: Any) -> None:
    res = knife.mechanisms["knife"]
    own = cm.dynamics.shaking(res.kinetostatics, linkage=res.mech.linkage)
    phase = res.shaft_torque()[2]
    n = knife.nominal_rpm
    # The machine's cycle angle θ sees the crank at θ − phase: roll by hand on the
    # 3600-sample grid (the phase is a whole number of samples here).
    steps = phase / 0.1
    assert abs(steps - round(steps)) < 1e-9
    want = np.roll(own.force(n), round(steps) % 3600, axis=0)
    got = knife.shaking.shaking.force(n)
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-9 * np.abs(want).max())
    st = knife.shaking.stats()
    f = np.hypot(*want.T)
    assert st["peak_force_n"] == pytest.approx(f.max(), rel=1e-12)
    assert st["rms_force_n"] == pytest.approx(np.sqrt(np.mean(f**2)), rel=1e-12)


def test_report_json_and_cli(knife: Any, tmp_path: Path) -> None:
    files = cm.machine.write_report(knife, tmp_path, figures=True)
    assert "shaking.png" in {p.name for p in files}
    g = json.loads((tmp_path / "results.json").read_text())["shaking"]
    assert g["rpm"] == 45.0 and list(g["mechanisms"]) == ["knife"]
    assert g["peak_force_n"] == pytest.approx(knife.shaking.stats()["peak_force_n"], rel=1e-12)
    assert len(g["force_x_n"]) == 360
    page = (tmp_path / "report.html").read_text()
    assert "Frame: the shaking force" in page and "its hodograph" in page  # the figure
    assert "knife balanced (rms_force)" in page
    run = subprocess.run(
        [
            sys.executable,
            "-m",
            "cyclomech",
            "run",
            str(ROOT / "examples/knife_cutter.toml"),
            "--out",
            str(tmp_path / "o"),
            "--no-plot",
        ],
        capture_output=True,
        text=True,
        cwd=ROOT,
    )
    assert run.returncode == 0, run.stderr
    assert "Shaking force on the frame at 45 rpm: peak" in run.stdout


def test_without_inertia_forces_at_a_phase() -> None:
    """The example's cam stop alone puts no inertia force on the frame at a phase:
    the machine has no shaking figure and says nothing false about it."""
    r = cm.machine.analyze(cm.Machine.example(), progress=False)
    assert r.shaking is None
    assert cm.dynamics.machine_shaking(r) is None
    with pytest.raises(TypeError, match="MachineResult"):
        cm.dynamics.machine_shaking({"mechanisms": {}})
    for bad in ("r", {}, None, 3):  # not an AttributeError from deep inside
        with pytest.raises(TypeError, match="result must be a MachineResult"):
            cm.dynamics.machine_balances(bad, [])
    with pytest.raises(cm.InputError, match="rpm"):
        cm.dynamics.machine_shaking(r, rpm=-1.0)


def _knife_data() -> dict[str, Any]:
    import tomllib

    with open(ROOT / "examples/knife_cutter.toml", "rb") as f:
        return tomllib.load(f)


def test_balance_rows_balance_the_knife(knife: Any) -> None:
    """The file's three counterweights (on the links pivoted to the frame) are the
    least-RMS-force ones: the same as balance() called on the knife's result, and
    the force they leave is the balance's after-shaking (the force's linear part
    vanishes: a planar linkage whose every moving mass can be balanced by its
    ground-pivoted links' counterweights)."""
    b = knife.shaking.balances["knife"]
    res = knife.mechanisms["knife"]
    direct = cm.dynamics.balance(
        res, counterweights=[("O", "F"), ("A", "B"), ("D", "C")], rpm=45.0, gravity=(0, -9.81)
    )
    for got, want in zip(b.counterweights, direct.counterweights, strict=True):
        assert got.mass_radius_kg_m == pytest.approx(want.mass_radius_kg_m, rel=1e-12)
        assert got.angle_deg == pytest.approx(want.angle_deg, abs=1e-9)
    assert b.before["rms_force_n"] == pytest.approx(knife.shaking.stats()["rms_force_n"], rel=1e-9)
    assert b.after["rms_force_n"] < 1e-6 * b.before["rms_force_n"]
    g = knife.shaking.json()["balance"]["knife"]
    assert [c["link"] for c in g["counterweights"]] == [c.link for c in b.counterweights]


@pytest.mark.parametrize(
    ("row", "words"),
    [
        ({"mechanism": "knfe", "links": [["O", "F"]]}, ["[[balance]]", "'knfe'", "'knife'"]),
        ({"mechanism": "knife", "links": [["O"]]}, ["[[balance]] #1", "links"]),
        ({"mechanism": "knife", "links": []}, ["[[balance]] #1", "links"]),
        (
            {"mechanism": "knife", "links": [["O", "F"]], "objective": "min"},
            ["[[balance]] #1", "objective", "rms_force"],
        ),
        (
            {"mechanism": "knife", "links": [["O", "F"]], "torque_weight": -1.0},
            ["[[balance]] #1", "torque_weight"],
        ),
        (  # ignored silently before: the default objective has no torque term
            {"mechanism": "knife", "links": [["O", "F"]], "torque_weight": 2.0},
            [
                "[[balance]] #1",
                "torque_weight = 2.0",
                'objective = "rms_force+torque"',
                "'rms_force'",
            ],
        ),
        (
            {
                "mechanism": "knife",
                "links": [["O", "F"]],
                "objective": "peak_force",
                "torque_weight": 1.0,
            },
            ["[[balance]] #1", "torque_weight = 1.0", "only applies", "'peak_force'"],
        ),
        (
            {"mechanism": "knife", "links": [["O", "F"]], "max_mass_radius_kg_m": 0.0},
            ["[[balance]] #1", "max_mass_radius_kg_m = 0.0", "> 0 [kg·m]"],
        ),
        ({"mechanism": 3, "links": [["O", "F"]]}, ["[[balance]] #1", "mechanism"]),
        ({"links": [["O", "F"]]}, ["[[balance]] #1", "mechanism"]),
        ({"mechanism": "knife", "links": [["O", "F"]], "bogus": 1}, ["[[balance]] #1", "bogus"]),
    ],
)
def test_bad_balance_rows_are_named(row: dict[str, Any], words: list[str]) -> None:
    d = _knife_data()
    d["balance"] = [row]
    with pytest.raises(cm.InputError) as e:
        cm.Machine.from_dict(d, "dir/knife.toml")
    for w in ["dir/knife.toml", *words]:
        assert w in str(e.value), (w, str(e.value))


def test_a_link_not_on_the_frame_is_refused_by_name() -> None:
    d = _knife_data()
    d["balance"] = [{"mechanism": "knife", "links": [["B", "C"]]}]
    with pytest.raises(cm.InputError, match=r"\[\[balance\]\] #1: .*B"):
        cm.machine.analyze(cm.Machine.from_dict(d, "dir/knife.toml"), progress=False)


def test_a_balance_row_on_a_machine_without_shaking_is_refused() -> None:
    """A [[balance]] row naming the loom's cam (not a linkage) was silently ignored
    (exit 0) when the loom had no shaking; it is refused by name."""
    import tomllib

    with open(ROOT / "examples/stb_loom.toml", "rb") as f:
        d = tomllib.load(f)
    d["balance"] = [{"mechanism": "lifter cam", "links": [["O", "A"]]}]
    with pytest.raises(cm.InputError, match=r"\[\[balance\]\] #1: mechanism = 'lifter cam'"):
        cm.machine.analyze(cm.Machine.from_dict(d, "loom.toml"), progress=False)


def test_bad_api_arguments(knife: Any) -> None:
    with pytest.raises(TypeError, match="requests"):
        cm.dynamics.machine_shaking(knife, requests=["knife"])
    with pytest.raises(TypeError, match="requests"):
        cm.dynamics.machine_balances(knife, [("knife", [("O", "F")])])
    res = knife.mechanisms["knife"]
    with pytest.raises(TypeError, match="linkage"):
        cm.dynamics.shaking(res.kinetostatics, linkage="x")
    with pytest.raises(cm.InputError, match="rpm"):
        cm.dynamics.balance(res, counterweights=[("O", "F")], rpm=-1.0)
    with pytest.raises(cm.InputError, match="rpm"):
        knife.shaking.shaking.stats(-5.0)


@pytest.fixture(scope="module")
def loom() -> Any:
    return cm.machine.analyze(cm.Machine.from_toml(ROOT / "examples/stb_loom.toml"), progress=False)


def test_an_oscillating_follower_shakes_by_a_couple(loom: Any, tmp_path: Path) -> None:
    """The loom's lifter cam: an oscillating follower given by its inertia J about
    the pivot alone, its centre of mass taken at the pivot: no force, and the
    moment −dH/dt of the lever, here from positions: the roller centre's path in
    the cam frame turned back into the fixed frame by the cam angle, the arm's
    angle about the pivot (a, 0) from it, differentiated twice in time by finite
    differences (the kernel's s″ is not used)."""
    res = loom.mechanisms["lifter cam"]
    cam, j = res.cam, float(res.mech.design.loads.mass)
    f = cam.follower
    n, w = 3600, 300.0 * np.pi / 30.0
    h = 2 * np.pi / n
    theta = np.arange(n) * h
    # The cam frame at θ = 0 sits at an angle r0 to the fixed one: the roller centre
    # at ψ0 is (a − l·cos ψ0, l·sin ψ0) in the fixed frame (cyclomech.cam's convention).
    psi0 = np.radians(f.initial_arm_angle_deg)
    start = np.array([f.pivot_distance - f.arm_length * np.cos(psi0), f.arm_length * np.sin(psi0)])
    p0 = cam.solve([0.0]).pitch[0]
    r0 = np.arctan2(start[1], start[0]) - np.arctan2(p0[1], p0[0])

    def arm_angle(t: Any) -> Any:
        p = cam.solve(t).pitch
        c, s = np.cos(t + r0), np.sin(t + r0)  # the cam turns counter-clockwise
        x, y = c * p[:, 0] - s * p[:, 1], s * p[:, 0] + c * p[:, 1]
        # the roller stays on its arm: |roller − pivot| = l (the frames agree)
        np.testing.assert_allclose(np.hypot(x - f.pivot_distance, y), f.arm_length, rtol=1e-9)
        return np.unwrap(np.arctan2(y, x - f.pivot_distance))

    k = 1e-3  # rad of cam: d²/dt² = ω² d²/dθ² at constant speed, 4th-order stencil
    a = [arm_angle(theta + i * k) for i in (-2, -1, 0, 1, 2)]
    acc = (-a[0] + 16 * a[1] - 30 * a[2] + 16 * a[3] - a[4]) / (12 * k * k) * w**2
    want = -j * acc  # −dH/dt, H = J·(the arm's angular velocity)
    part = loom.shaking.shaking.parts["lifter cam"]
    got = part.moment(300.0)
    assert np.abs(part.force(300.0)).max() == 0.0
    # At its phase: the machine's cycle angle θ sees the cam at θ − phase (read
    # between the samples: the phase is not a whole number of them).
    phase = res.shaft_torque()[2]
    at = np.interp(part.angles_deg - phase, np.degrees(theta), want, period=360.0)
    scale = np.abs(want).max()
    assert scale > 50.0  # a real moment
    # Two linear interpolations on the 0.1° grid (the machine's phasing and this
    # one) of a curve that turns within a few degrees: ~1e-3 of its peak each.
    np.testing.assert_allclose(got, at, atol=5e-3 * scale)
    # ... and the report, results.json and the CLI say so plainly.
    rows = loom.shaking.table()[1]
    assert any(r[0] == "assumed for lifter cam" and "centre of mass" in r[1] for r in rows)
    # no zero force "at 0.0°": no force, said so; the cam stop's absence explained
    assert rows[0][1].startswith("0: no shaking force")
    assert any(r[0] == "left out: lifter" and r[1].startswith("a cam stop") for r in rows)
    cm.machine.write_report(loom, tmp_path, figures=False)
    g = json.loads((tmp_path / "results.json").read_text())["shaking"]
    assert "moment only" in g["assumed"]["lifter cam"]
    assert g["peak_moment_nm"] == pytest.approx(np.abs(got).max(), rel=1e-12)


def test_the_figures_say_which_angle(knife: Any, loom: Any) -> None:
    """The hodograph's peak is at a cycle angle (the machine's) or a crank angle
    (a balanced mechanism's), said in words: the polar plot's own angles are the
    force's direction, so "peak at 344°" read as one. The moment's axis names the
    angle with its unit, ticked every 60° (30° crowded the half-width axis)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = knife.shaking.figure()
    polar, right = fig.axes
    st = knife.shaking.stats()
    assert f"peak {st['peak_force_n']:,.0f} N (red) at cycle angle " in polar.get_title()
    assert f"{st['peak_force_deg'] % 360:.0f}°" in polar.get_title()
    assert right.get_xlabel() == "cycle angle  [deg]"
    lo, hi = right.get_xlim()
    ticks = [t for t in right.get_xticks() if lo <= t <= hi]
    assert (lo, hi) == (0.0, 360.0) and ticks == [0.0, 60.0, 120.0, 180.0, 240.0, 300.0, 360.0]
    plt.close(fig)
    ((name, fig),) = knife.shaking.balance_figures()
    polar, right = fig.axes
    assert right.get_xlabel() == f"crank angle of {name}  [deg]"
    assert np.allclose(np.diff(right.get_xticks()), 60.0)
    # the least-RMS balance leaves no force: no "peak" at a rounding's angle
    assert polar.get_title().endswith("no shaking force left: a couple only (right)")
    plt.close(fig)
    fig = loom.shaking.figure()  # a couple only: said so
    assert fig.axes[0].get_title().endswith("no shaking force: a couple only (right)")
    plt.close(fig)


def test_a_bounded_weighted_balance_row_in_the_results(tmp_path: Path) -> None:
    """A row with the torque objective, its weight and a bound on m·r: the weight and
    the bound are in results.json's balance group (they were not), the counterweights
    the bound stops are named there, in the report's table and in the CLI line, and
    none exceeds it. Two of the file's three counterweights (O-F stays inside the
    bound, A-B stops at it): the Nelder–Mead of three took 8.5 CPU-s, of two 1.1;
    the bounded weighted optimum itself is tests/dynamics/test_shaking_balance.py's."""
    d = _knife_data()
    d["balance"][0].update(
        objective="rms_force+torque",
        torque_weight=3.0,
        max_mass_radius_kg_m=5.0,
        links=[["O", "F"], ["A", "B"]],
    )
    r = cm.machine.analyze(cm.Machine.from_dict(d, "dir/knife.toml"), progress=False)
    b = r.shaking.balances["knife"]
    assert all(c.mass_radius_kg_m <= 5.0 * (1 + 1e-9) for c in b.counterweights)
    # unbounded, A-B wants 25 kg·m (the file's least-RMS row); O-F stays inside
    assert b.at_bound == ("A-B",)
    cm.machine.write_report(r, tmp_path, figures=False)
    g = json.loads((tmp_path / "results.json").read_text())["shaking"]["balance"]["knife"]
    assert g["torque_weight"] == 3.0 and g["max_mass_radius_kg_m"] == 5.0
    assert g["at_bound"] == list(b.at_bound)
    rows = b.table()[1]
    flagged = [row[0] for row in rows if "at the bound max_mass_radius_kg_m = 5" in str(row[2])]
    assert len(flagged) == len(b.at_bound)
    cost = b.after["rms_force_n"] + 3.0 * b.after["rms_torque_nm"]
    assert cost < b.before["rms_force_n"] + 3.0 * b.before["rms_torque_nm"]


def test_an_unbounded_rms_row_keeps_its_results_group(knife: Any) -> None:
    # The file's row (no weight, no bound): results.json's balance entry as before.
    g = knife.shaking.json()["balance"]["knife"]
    assert list(g) == ["objective", "before", "after", "counterweights"]
