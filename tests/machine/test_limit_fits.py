"""A machine runs at its own speed limit (probe B3): the speed-limit search and the
cyclogram's fit check share one tolerance (``fit_slack``), so the knife cutter
without ``nominal_rpm`` (the nominal is then the limit) runs with exit status 0,
and the limit is the closed form of its cyclogram within 1e-9."""

from __future__ import annotations

import tomllib
from pathlib import Path

import cyclomech as cm
import pytest
from cyclomech.cli import main

ROOT = Path(__file__).resolve().parents[2]
KNIFE = ROOT / "examples" / "knife_cutter.toml"


def knife_without_nominal() -> tuple[str, dict]:
    text = KNIFE.read_text(encoding="utf-8")
    lines = [ln for ln in text.splitlines() if not ln.startswith("nominal_rpm")]
    assert len(lines) == len(text.splitlines()) - 1
    out = "\n".join(lines) + "\n"
    return out, tomllib.loads(out)


def closed_form_limit(data: dict) -> float:
    """The knife's cycle by hand: start → clamped → cut, then the longer of
    cut → knife up → unclamped and cut → unclamped, then the pile's move, whose
    6·n·s degrees take the rest of the cycle: n = (cycle − the rest) / (6·s)."""
    ops = {(o["from"], o["to"]): o for o in data["operation"]}
    a = {k: o.get("min_angle_deg", 0.0) for k, o in ops.items()}
    before = (
        a["start", "clamped"]
        + a["clamped", "cut"]
        + max(a["cut", "knife up"] + a["knife up", "unclamped"], a["cut", "unclamped"])
    )
    move = ops["unclamped", "pile set"]
    assert move["min_angle_deg"] < 360.0 - before  # the duration binds at the limit
    return (data["cyclogram"].get("cycle_deg", 360.0) - before) / (6.0 * move["min_duration_s"])


def test_the_knife_without_nominal_runs_at_its_limit(tmp_path, capsys):
    text, _ = knife_without_nominal()
    path = tmp_path / "knife.toml"
    path.write_text(text, encoding="utf-8")
    argv = ["run", str(path), "--out", str(tmp_path / "o"), "--no-plot", "--quiet"]
    assert main([*argv, "--no-sensitivities"]) == 0
    assert "does not fit" not in capsys.readouterr().out


def test_the_limit_is_the_closed_form_and_fits_where_the_check_does():
    _, data = knife_without_nominal()
    m = cm.Machine.from_dict(data, "knife.toml")
    limit = m.speed_limit().rpm
    exact = closed_form_limit(data)
    assert exact == pytest.approx(120.0 / 2.1, rel=1e-15)
    assert abs(limit / exact - 1.0) <= 1e-9
    m.optimize(limit)  # the fit check accepts the reported limit
    # Not above any speed at which the fit check fails: every speed that fails is
    # above the limit; and the check still refuses a real overrun (1e-7 of speed
    # is 1.2e-5° of the pile's move, far over the tolerance of ~1e-8°).
    for rel in (-1e-7, -1e-9, -1e-11, -1e-13, 0.0, 1e-13, 1e-11, 1e-9, 1e-7):
        rpm = limit * (1.0 + rel)
        try:
            m.optimize(rpm)
        except cm.InfeasibleError:
            assert rpm > limit
    with pytest.raises(cm.InfeasibleError, match="do not fit in the cycle"):
        m.optimize(exact * (1.0 + 1e-7))
