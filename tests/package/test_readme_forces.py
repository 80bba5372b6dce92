"""README's "Forces in Python": its code block runs as it is, and the numbers its
comments and prose give are what the library returns (so the two cannot drift)."""

from __future__ import annotations

import re
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest

README = Path(__file__).resolve().parents[2] / "README.md"


def section() -> str:
    return (
        README.read_text(encoding="utf-8").split("## Forces in Python", 1)[1].split("\n## ", 1)[0]
    )


def test_the_readme_forces_block_runs_and_its_numbers_hold():
    code = re.search(r"```python\n(.*?)```", section(), re.S)
    assert code is not None
    ns: dict = {}
    exec(compile(code.group(1), "README.md", "exec"), ns)
    k, t, s = ns["k"], ns["t"], ns["s"]
    assert t.max() == pytest.approx(736.55, abs=0.005)
    assert np.degrees(k.angles[t.argmax()]) == pytest.approx(150.0, abs=1e-9)
    joint, peak, at = k.most_loaded(120)
    assert (joint, at) == ("C", pytest.approx(150.0, abs=1e-9))
    assert peak == pytest.approx(19975.15, abs=0.005)
    assert abs(k.guide_forces(120)).max() == pytest.approx(2634.99, abs=0.005)
    assert float(s.power_w) == pytest.approx(398.85, abs=0.005)
    assert float(s.flywheel_kg_m2) == pytest.approx(22.58, abs=0.005)


def test_the_readme_knife_cutter_numbers():
    r = cm.machine.analyze(
        cm.Machine.from_toml(README.parent / "examples" / "knife_cutter.toml"), progress=False
    )
    s, text = r.shaft.at_nominal, section().replace("\n", " ")
    assert f"mean torque of {float(s.mean_torque_nm):.1f} N·m" in text
    assert f"peak of {float(s.peak_torque_nm):.0f} N·m" in text
    assert f"a {float(s.power_w):.0f} W motor" in text
    assert f"ΔE = {float(s.energy_fluctuation_j):.0f} J" in text
    assert f"a {float(s.flywheel_kg_m2):.0f} kg·m² flywheel" in text
    joint, peak, at = r.mechanisms["knife"].kinetostatics.most_loaded(45.0)
    assert f"joint {joint} ({peak / 1e3:.1f} kN at crank {at:.0f}°)" in text


def test_the_readme_press_torque_numbers():
    text = README.read_text(encoding="utf-8").split("## Motion laws and press drives", 1)[1]
    text = text.split("\n## ", 1)[0]
    assert "≈ 2312.5 J, 1810.5 N·m" in text
    p = cm.press.GearLeverPress(R=0.09, r=0.03, d=0.029, L=0.25, phi0=np.radians(55.95))
    f = cm.press.DeformationForce(
        [0, 0.001, 0.0105, 0.0115, 0.0127], [200e3, 200e3, 190e3, 150e3, 0]
    )
    t = p.crank_torque(
        np.radians(np.arange(3600) / 10), force=f, slider_mass=60.0, rod_mass=15.0, k_Sp=0.1
    )
    assert t.energy_per_stroke_j == pytest.approx(2312.5, abs=0.05)
    assert t.peak_torque_nm(2 * np.pi * 40 / 60) == pytest.approx(1810.5, abs=0.05)
