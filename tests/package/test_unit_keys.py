"""Keys that say their units, and values a user cannot have meant (issue 31, item 4).

A stop's rebound limit written in millimetres (``a_max = 0.1`` on the loom's 9.4 mm
stroke) or its damping ratio in percent (``zeta = 5``) used to raise the loom's
speed limit from 420.32 to 445.10 rpm with exit 0. Now every key with a unit says it
in its name (``a_max_m``), an old name is an error naming the new one, a value that
cannot be meant is an error and an unusual one a warning naming the likely slip.
"""

from __future__ import annotations

import contextlib
import re
import warnings
from pathlib import Path

import cyclomech as cm
import pytest
from cyclomech._keyrules import RENAMED
from cyclomech.cli import main
from cyclomech.transfer.cli import read_transfer_file

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
LOOM = EXAMPLES / "stb_loom.toml"


def _read(path: Path) -> object:
    """The example read by its own command's reader."""
    text = path.read_text(encoding="utf-8")
    if "[machine]" in text:
        return cm.Machine.from_toml(path)
    if "[stop]" in text:
        return cm.impact.ImpactStudy.from_toml(path)
    if "[press]" in text:
        return cm.press.PressStudy.from_toml(path)
    if "[cam]" in text:
        return cm.cam.CamDesign.from_toml(path)
    if "[linkage]" in text:
        return cm.linkage.Linkage.from_toml(path)
    if "[transfer]" in text:
        return read_transfer_file(path)
    return cm.Cyclogram.from_toml(path)


def _loom_with(tmp_path: Path, old: str, new: str) -> Path:
    text = LOOM.read_text(encoding="utf-8")
    assert re.search(rf"^{re.escape(old)}$", text, flags=re.M), old
    f = tmp_path / "loom.toml"
    f.write_text(re.sub(rf"^{re.escape(old)}$", new, text, flags=re.M), encoding="utf-8")
    return f


A_MAX = "a_max_m = 1e-4                 # first rebound at most 0.1 mm"
ZETA = "zeta = 0.05                    # damping ratio of the free vibration"


def test_a_rebound_limit_in_millimetres_is_an_error_naming_the_key(tmp_path):
    f = _loom_with(tmp_path, A_MAX, "a_max_m = 0.1")
    with pytest.raises(cm.InputError) as e:
        cm.Machine.from_toml(f)
    msg = str(e.value)
    assert "[mechanism.lifter]: a_max_m = 0.1" in msg
    # the stroke it is compared with comes from the cam: 5.385803274° at 0.1 m = 9.4 mm
    assert "stroke_m = 0.0094" in msg and "millimetres (a_max_m = 0.0001)" in msg


def test_the_loom_with_a_rebound_limit_in_millimetres_exits_2(tmp_path, capsys):
    f = _loom_with(tmp_path, A_MAX, "a_max_m = 0.1")
    assert main(["run", str(f), "--out", str(tmp_path / "o"), "--no-plot", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "a_max_m = 0.1" in err and "did you give millimetres" in err


def test_a_damping_ratio_in_percent_warns_naming_the_key_and_the_slip(tmp_path):
    f = _loom_with(tmp_path, ZETA, "zeta = 5")
    with pytest.warns(cm.CyclomechWarning, match=r"\[mechanism.lifter\]: zeta = 5 is overdamped"):
        m = cm.Machine.from_toml(f)
    # a warning, not an error: ζ ≥ 1 is a valid (overdamped) stop
    assert m.mechanisms["lifter"].stop.zeta == 5.0


def test_run_prints_the_damping_ratio_warning(tmp_path, capsys):
    f = _loom_with(tmp_path, ZETA, "zeta = 5")
    with warnings.catch_warnings():
        warnings.simplefilter("default")
        argv = ["run", str(f), "--out", str(tmp_path / "o"), "--no-plot", "--quiet"]
        code = main([*argv, "--no-sensitivities"])
    assert code == 0
    err = capsys.readouterr().err
    assert "cyclomech: warning:" in err
    assert "zeta = 5 is overdamped" in err and "did you mean 0.05?" in err


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.toml")), ids=lambda p: p.name)
def test_every_old_key_name_in_every_example_is_an_error_naming_the_new_one(path, tmp_path):
    text = path.read_text(encoding="utf-8")
    olds = [(old, new) for old, (new, _) in RENAMED.items()
            if re.search(rf"^{re.escape(new)}\s*=", text, flags=re.M)]  # fmt: skip
    for old, new in olds:
        f = tmp_path / path.name
        f.write_text(
            re.sub(rf"^{re.escape(new)}(\s*)=", rf"{old}\1=", text, count=1, flags=re.M),
            encoding="utf-8",
        )
        with pytest.raises(cm.InputError) as e:
            _read(f)
        assert f"`{old}` is now `{new}` ({RENAMED[old][1]})" in str(e.value), str(e.value)
        assert str(f) in str(e.value)


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.toml")), ids=lambda p: p.name)
def test_every_example_reads_without_a_warning(path):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _read(path)


def test_the_renamed_loom_keeps_its_speed_limit():
    # the same numbers under the new names: the speed limit of the loom
    m = cm.Machine.from_toml(LOOM)
    assert round(m.speed_limit().rpm, 2) == 420.32


@pytest.mark.parametrize(
    ("old", "new", "match"),
    [
        # a lever 100 m long is a lever of 100 mm
        ("lever_length_m = 0.1           # [m]", "lever_length_m = 100",
         r"lever_length_m = 100 m is over 10 m — did you mean millimetres "
         r"\(lever_length_m = 0.1\)"),
        # ±0.001 rad of vibration is 0.0573°: radians in a degree key
        ("max_vibration_deg = 0.0573       # residual vibration after a rise or return: ±0.1 mm",
         "max_vibration_deg = 0.001", r"max_vibration_deg = 0.001 ° is under 0.01° — did you "
         r"give radians \(max_vibration_deg = 0.0573 if so\)"),
        # a pressure-angle limit of 0.785 is 45° in radians
        ("max_pressure_angle_deg = 45.0", "max_pressure_angle_deg = 0.785",
         r"max_pressure_angle_deg = 0.785 ° admits almost no cam — did you give radians "
         r"\(max_pressure_angle_deg = 45\)"),
        # [σ_H] = 900 is 900 MPa
        ("max_stress_pa = 9e8              # [σ_H] of a hardened steel cam",
         "max_stress_pa = 900", r"max_stress_pa = 900 Pa is under 1e\+06 Pa .* did you give "
         r"MPa \(max_stress_pa = 9e\+08\)"),
    ],
)  # fmt: skip
def test_unit_slips_by_key_suffix_warn(tmp_path, old, new, match):
    f = _loom_with(tmp_path, old, new)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        # a slip may also break the design (an error after the warning)
        with contextlib.suppress(cm.InputError):
            cm.Machine.from_toml(f)
    msgs = [str(w.message) for w in caught if issubclass(w.category, cm.CyclomechWarning)]
    # once: a cam stop read its cam's table and its own twice (probe 4)
    assert sum(bool(re.search(match, m)) for m in msgs) == 1, msgs


def _lengths_in_millimetres(text: str) -> str:
    """Every number of a ``_m`` key in the machine's mechanism tables times 1000."""
    out, table = [], ""
    for line in text.splitlines():
        if head := re.match(r"\s*\[+([^\]]*)\]", line):
            table = head.group(1)
        key = re.match(r"^(\w+_m)\s*=\s*([-+0-9.eE]+)(.*)$", line)
        if key and table.startswith("mechanism"):
            line = f"{key.group(1)} = {float(key.group(2)) * 1000!r}{key.group(3)}"
        out.append(line)
    return "\n".join(out)


@pytest.mark.parametrize(
    "name", ["stb_loom.toml", "extrusion_press_line.toml", "lifter_cam_sized.toml"]
)
def test_a_machine_warns_of_each_slipped_value_once(name, tmp_path):
    # The loom's cam stop reads its cam (the lifter cam's lengths), the press line's
    # mechanism its drive: both warned of the same key twice.
    f = tmp_path / name
    f.write_text(_lengths_in_millimetres((EXAMPLES / name).read_text(encoding="utf-8")))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with contextlib.suppress(cm.InputError):
            cm.Machine.from_toml(f)
    msgs = [str(w.message) for w in caught if issubclass(w.category, cm.CyclomechWarning)]
    slips = [m for m in msgs if "did you mean millimetres" in m]
    assert len(slips) >= 4, msgs
    assert len(set(msgs)) == len(msgs), sorted(msgs)


def test_an_impact_file_checks_its_rebound_limit_against_its_stroke(tmp_path):
    text = (EXAMPLES / "stb_lifter.toml").read_text(encoding="utf-8")
    f = tmp_path / "lifter.toml"
    f.write_text(re.sub(r"^a_max_m = 1e-4", "a_max_m = 0.1", text, flags=re.M), encoding="utf-8")
    with pytest.raises(cm.InputError, match=r"\[study\]: a_max_m = 0.1 is not below the stroke"):
        cm.impact.ImpactStudy.from_toml(f)


def test_a_press_slider_speed_in_mm_per_s_warns(tmp_path):
    text = (EXAMPLES / "extrusion_press_line.toml").read_text(encoding="utf-8")
    f = tmp_path / "press.toml"
    f.write_text(
        re.sub(r"^max_V_np_m_per_s = 0.005", "max_V_np_m_per_s = 50", text, flags=re.M),
        encoding="utf-8",
    )
    with pytest.warns(cm.CyclomechWarning, match=r"max_V_np_m_per_s = 50 m/s is over 10 m/s"):
        cm.Machine.from_toml(f)


def test_an_old_key_in_a_python_table_names_the_new_one():
    data = dict(cm.Machine.example().data or {})
    lifter = dict(data["mechanism"]["lifter"])
    lifter["a_max"] = lifter.pop("a_max_m")
    data["mechanism"] = {"lifter": lifter}
    with pytest.raises(cm.InputError, match=r"`a_max` is now `a_max_m` \(metres\)"):
        cm.Machine.from_dict(data, "loom")


def test_a_sweep_of_an_old_key_names_the_new_one(tmp_path, capsys):
    m = cm.Machine.from_toml(LOOM)
    with pytest.raises(cm.InputError, match=r"`a_max` is now `a_max_m` \(metres\)"):
        cm.sweep(m, {"lifter.a_max": [1e-4, 2e-4]}, progress=False)
    argv = ["sweep", str(LOOM), "--set", "lifter.a_max=1e-4:2e-4:2", "--out", str(tmp_path)]
    assert main(argv) == 2
    assert "`a_max` is now `a_max_m`" in capsys.readouterr().err


def test_a_rate_per_metre_is_not_a_length():
    # the suffix rules go by the unit's last word: N/m is no length in metres
    from cyclomech._keyrules import check

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check({"contact_stiffness_n_per_m": 1e4, "gravity_m_per_s2": 9.81}, (), "f")
    with pytest.warns(cm.CyclomechWarning, match="base_radius_m = 60"):
        check({"base_radius_m": 60}, (), "f")


def test_every_new_name_is_a_documented_key_and_the_page_lists_the_renames():
    from cyclomech import _keydocs

    documented = {k.name for t in _keydocs.tables().values() for k in t.keys}
    page = _keydocs.render_page()
    for old, (new, _) in RENAMED.items():
        assert new in documented, new
        assert old not in documented or old == "mass", old  # a linkage's [[…mass]] rows
        assert f"   * - ``{old}``\n     - ``{new}``" in page
