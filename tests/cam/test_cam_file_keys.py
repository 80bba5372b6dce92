"""A cam table's mistakes name the file's key, and a key that would be ignored is
refused: a constructor's argument (``roller_radius``) is ``roller_radius_m`` in a
file, and ``spring_rate_n_per_m`` without ``mass_kg`` used to be accepted, even as
text, and never read."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import cyclomech as cm
import pytest

CamDesign = cm.cam.CamDesign
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _translating(**extra: Any) -> dict[str, Any]:
    table = {
        "follower": "translating",
        "base_radius_m": 0.05,
        "roller_radius_m": 0.01,
        "segment": [
            {"kind": "rise", "angle_deg": 180, "stroke_m": 0.02},
            {"kind": "return", "angle_deg": 180, "stroke_m": 0.02},
        ],
    }
    return table | extra


def _oscillating(**extra: Any) -> dict[str, Any]:
    table = {
        "follower": "oscillating",
        "pivot_distance_m": 0.13,
        "arm_length_m": 0.1,
        "base_radius_m": 0.06,
        "roller_radius_m": 0.012,
        "segment": [
            {"kind": "rise", "angle_deg": 180, "stroke_deg": 10},
            {"kind": "return", "angle_deg": 180, "stroke_deg": 10},
        ],
    }
    return table | extra


@pytest.mark.parametrize(
    ("table", "key"),
    [
        (_translating(roller_radius_m=-0.01), "roller_radius_m"),
        (_translating(base_radius_m=-0.05), "base_radius_m"),
        (_translating(offset_m=float("nan")), "offset_m"),
        (_oscillating(pivot_distance_m=-1.0), "pivot_distance_m"),
        (_oscillating(arm_length_m=-1.0), "arm_length_m"),
        (_translating(mass_kg=-1.0), "mass_kg"),
        (_oscillating(inertia_kg_m2=-1.0), "inertia_kg_m2"),
        (_translating(mass_kg=1.0, spring_rate_n_per_m="x"), "spring_rate_n_per_m"),
        (_oscillating(inertia_kg_m2=0.03, spring_rate_nm_per_rad=-2.0), "spring_rate_nm_per_rad"),
        (_translating(width_m=-0.008), "width_m"),
        (_translating(width_m=0.008, follower_modulus_pa=-1.0), "follower_modulus_pa"),
        (_translating(width_m=0.008, cam_modulus_pa="x"), "cam_modulus_pa"),
        (_translating(width_m=0.008, cam_poisson=0.7), "cam_poisson"),
    ],
)
def test_an_invalid_value_names_the_file_key(table: dict[str, Any], key: str) -> None:
    with pytest.raises(cm.InputError, match=rf"^f\.toml: \[cam\]: {key}\b"):
        CamDesign.from_table(table, "[cam]", source="f.toml")


@pytest.mark.parametrize(
    ("table", "key", "need"),
    [
        (_translating(spring_rate_n_per_m="x"), "spring_rate_n_per_m", "mass_kg"),
        (_translating(preload_n=10.0), "preload_n", "mass_kg"),
        (_oscillating(spring_rate_nm_per_rad=5.0), "spring_rate_nm_per_rad", "inertia_kg_m2"),
        (_oscillating(preload_nm=1.0), "preload_nm", "inertia_kg_m2"),
        (_translating(follower_modulus_pa=2e11), "follower_modulus_pa", "width_m"),
        (_translating(follower_poisson=0.3), "follower_poisson", "width_m"),
        (_translating(cam_modulus_pa=2e11), "cam_modulus_pa", "width_m"),
        (_translating(cam_poisson="abc"), "cam_poisson", "width_m"),
    ],
)
def test_a_key_read_only_beside_another_is_refused_without_it(
    table: dict[str, Any], key: str, need: str
) -> None:
    with pytest.raises(cm.InputError, match=rf"{key} is read only with {need}"):
        CamDesign.from_table(table, "[cam]")
    # With the key it needs, a valid value is read.
    table[need] = {"mass_kg": 1.0, "inertia_kg_m2": 0.03, "width_m": 0.008}[need]
    if isinstance(table[key], str):
        table[key] = 0.3
    CamDesign.from_table(table, "[cam]")


def test_a_segment_load_without_the_mass_is_refused() -> None:
    t = _translating()
    t["segment"][0]["load_n"] = 50.0
    with pytest.raises(cm.InputError, match=r"a segment's load_n is read only with mass_kg"):
        CamDesign.from_table(t, "[cam]")
    assert CamDesign.from_table(t | {"mass_kg": 1.0}, "[cam]").loads is not None


@pytest.mark.parametrize(
    ("table", "key"),
    [
        (_translating(follower="flat", roller_radius_m="abc"), "roller_radius_m"),
        (_translating(pivot_distance_m=0.13), "pivot_distance_m"),
        (_translating(arm_length_m=0.1), "arm_length_m"),
        (_oscillating(offset_m=0.01), "offset_m"),
    ],
)
def test_geometry_the_follower_does_not_use_is_refused(table: dict[str, Any], key: str) -> None:
    kind = table["follower"]
    with pytest.raises(cm.InputError, match=rf"{key} is not used by a {kind} follower"):
        CamDesign.from_table(table, "[cam]")


def test_the_examples_still_read() -> None:
    """Every example with a cam reads as before (no example relied on an ignored key)."""
    _, _, design = CamDesign.from_toml(EXAMPLES / "lifter_cam.toml")
    assert design.loads is not None and design.contact is not None
    for name in ("stb_loom.toml", "knife_cutter.toml"):
        m = cm.Machine.from_toml(EXAMPLES / name)
        assert re.search(r"\w", m.name)


@pytest.mark.parametrize("value", ["-0.1", "0.0", "inf", "nan"])
def test_a_stop_on_a_cam_names_its_bad_lever_length(tmp_path, value: str) -> None:
    """The loom's lifter takes its stroke from the cam's rotation times lever_length;
    a bad lever_length is named as such, not as the derived stroke."""
    src = (EXAMPLES / "stb_loom.toml").read_text(encoding="utf-8")
    assert "lever_length_m = 0.1 " in src
    bad = tmp_path / "bad.toml"
    bad.write_text(src.replace("lever_length_m = 0.1 ", f"lever_length_m = {value} ", 1))
    with pytest.raises(cm.InputError, match=r"\[mechanism.lifter\]: lever_length_m\b"):
        cm.Machine.from_toml(bad)
