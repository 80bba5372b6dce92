"""A counterweight on the gear-lever press's carrier (a ``[[balance]]`` row on the
press line): the press's shaking force before and after against −Σ m·a_G of the
slider, the rod and the counterweight computed here from the drive's positions
(finite differences in time, not the library's stencil), and the least-RMS
counterweight against a least-squares solve built here from the same positions."""

from __future__ import annotations

import json
import math
import tomllib
from pathlib import Path
from typing import Any

import cyclomech as cm
import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
PRESS = ROOT / "examples" / "extrusion_press_line.toml"


@pytest.fixture(scope="module")
def press() -> Any:
    return cm.machine.analyze(cm.Machine.from_toml(PRESS), progress=False)


def _positions(p: Any, t: Any, omega: float) -> dict[str, Any]:
    """The slider, the rod's centre and the carrier's unit vector at times ``t``
    [s], the carrier turning at ``omega`` from BDC (α = −ω·t)."""
    k = p.solve(np.mod(-omega * np.asarray(t), 2 * np.pi))
    unit = k.centre / np.hypot(k.centre[:, 0], k.centre[:, 1])[:, None]
    return {"slider": k.slider, "rod": 0.5 * (k.slider + k.pin), "carrier": unit}


def _accelerations(p: Any, t: Any, omega: float) -> dict[str, Any]:
    # Central second difference in time, step 1e-5 of a turn's period
    h = 1e-5 * 2 * np.pi / omega
    a, b, c = (_positions(p, t + k * h, omega) for k in (-1, 0, 1))
    return {key: (a[key] - 2 * b[key] + c[key]) / h**2 for key in a}


def test_the_press_counterweight_against_momentum_from_positions(press: Any) -> None:
    res = press.mechanisms["drive"]
    b = press.shaking.balances["drive"]
    p, m = res.mech.press, res.mech
    n = press.nominal_rpm
    omega = n * math.pi / 30.0
    psi = np.radians(b.shaking_before.angles_deg)
    acc = _accelerations(p, psi / omega, omega)
    before = -(m.slider_mass * acc["slider"] + m.rod_mass * acc["rod"])
    scale = np.abs(before).max()
    np.testing.assert_allclose(b.shaking_before.force(n), before, atol=1e-5 * scale)
    # The counterweight: m·r at angle α in the carrier's frame, a point at its radius.
    (c,) = b.counterweights
    assert (c.link, c.pivot, c.towards) == ("O-planet", "O", "planet")
    assert c.radius_m == pytest.approx(p.R - p.r, rel=1e-12)  # the carrier's length
    u = acc["carrier"]  # the unit vector's acceleration; the point's is r times it
    ca, sa = math.cos(math.radians(c.angle_deg)), math.sin(math.radians(c.angle_deg))
    turned = np.stack([ca * u[:, 0] - sa * u[:, 1], sa * u[:, 0] + ca * u[:, 1]], 1)
    after = before - c.mass_kg * c.radius_m * turned
    np.testing.assert_allclose(b.shaking_after.force(n), after, atol=1e-5 * scale)
    # The least RMS: min over w of Σ|before − A w|², A's columns the force of a unit
    # m·r along the carrier and across it, here by numpy's least squares.
    cols = [u, np.stack([-u[:, 1], u[:, 0]], 1)]
    mat = np.stack([col.ravel() for col in cols], 1)
    w, *_ = np.linalg.lstsq(mat, before.ravel(), rcond=None)
    np.testing.assert_allclose(c.vector_kg_m, w, rtol=1e-5)
    rms = np.sqrt(np.mean(np.sum(after**2, 1)))
    assert b.after["rms_force_n"] == pytest.approx(rms, rel=1e-5)
    assert b.after["rms_force_n"] < b.before["rms_force_n"]


def test_the_press_row_in_the_report(press: Any, tmp_path: Path) -> None:
    cm.machine.write_report(press, tmp_path, figures=False)
    g = json.loads((tmp_path / "results.json").read_text())["shaking"]["balance"]["drive"]
    assert g["objective"] == "rms_force" and g["counterweights"][0]["link"] == "O-planet"
    assert [k for k, _ in press.shaking.balance_figures()] == ["drive"]


def _data() -> dict[str, Any]:
    with open(PRESS, "rb") as f:
        return tomllib.load(f)


@pytest.mark.parametrize(
    ("links", "words"),
    [
        ([["O", "P"]], ["[[balance]] #1", "its carrier ['O', 'planet']"]),
        ([["O", "planet"], ["O", "planet"]], ["[[balance]] #1", "one link"]),
    ],
)
def test_a_press_row_names_its_carrier(links: list[list[str]], words: list[str]) -> None:
    d = _data()
    d["balance"][0]["links"] = links
    with pytest.raises(cm.InputError) as e:
        cm.machine.analyze(cm.Machine.from_dict(d, "press.toml"), progress=False)
    for w in words:
        assert w in str(e.value), (w, str(e.value))


@pytest.mark.parametrize("objective", ["peak_force", "rms_force+torque"])
def test_the_other_objectives_on_the_press(objective: str) -> None:
    d = _data()
    d["balance"][0].update(objective=objective, max_mass_radius_kg_m=1.5)
    r = cm.machine.analyze(cm.Machine.from_dict(d, "press.toml"), progress=False)
    b = r.shaking.balances["drive"]
    (c,) = b.counterweights
    assert c.mass_radius_kg_m <= 1.5 * (1 + 1e-9)
    assert b.at_bound == ("O-planet",)  # unbounded, it wants 2.4 (RMS) to 3.6 (peak)
    key = "peak_force_n" if objective == "peak_force" else "rms_force_n"
    assert b.after[key] < b.before[key]
