"""README's "Cams in Python": its code block runs as it is, and the numbers its
comments and prose give are what the library returns (so the two cannot drift)."""

from __future__ import annotations

import math
import re
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest

README = Path(__file__).resolve().parents[2] / "README.md"


def block() -> str:
    text = README.read_text(encoding="utf-8")
    section = text.split("## Cams in Python", 1)[1].split("\n## ", 1)[0]
    code = re.search(r"```python\n(.*?)```", section, re.S)
    assert code is not None
    return code.group(1)


def test_the_readme_cam_block_runs_and_its_numbers_hold(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    ns: dict = {}
    exec(compile(block(), "README.md", "exec"), ns)
    k, ld, m, cam, loads = ns["k"], ns["ld"], ns["m"], ns["cam"], ns["loads"]
    i = np.argmax(np.abs(k.pressure_angle))
    assert math.degrees(abs(k.pressure_angle[i])) == pytest.approx(15.38, abs=0.005)
    assert math.degrees(k.theta[i]) == pytest.approx(56.5, abs=1e-9)
    assert k.profile_radius_of_curvature.min() == pytest.approx(0.0469, abs=5e-5)
    assert not k.undercut.any()
    j = np.argmax(ld.contact_stress)
    assert ld.contact_stress[j] / 1e6 == pytest.approx(194.36, abs=0.005)
    assert math.degrees(k.theta[j]) == pytest.approx(120.0, abs=1e-9)
    rpm, where = cam.jump_rpm(loads)
    assert (rpm, where) == (pytest.approx(523.55, abs=0.005), pytest.approx(88.47, abs=0.005))
    np.testing.assert_allclose(m.bound_deg[:, 0], [57.18, 68.76, 137.52], atol=0.005)
    assert m.binding[:, 0].tolist() == ["pressure_angle", "jump", "jump"]
    assert (tmp_path / "cam.csv").stat().st_size > 0
    assert (tmp_path / "cam.dxf").stat().st_size > 0


def test_the_readme_loom_limit_and_reason():
    text = README.read_text(encoding="utf-8")
    lim = cm.Machine.from_toml(README.parent / "examples" / "stb_loom.toml").speed_limit()
    assert f"{lim.rpm:.2f} rpm" in text and f".rpm {lim.rpm:.2f}," in text
    assert f'("bounded by {", ".join(lim.binding)}")' in text.replace("\n", " ")
