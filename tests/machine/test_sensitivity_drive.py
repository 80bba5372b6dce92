"""The drive's keys in the sensitivities (issue 36, item 2): the elastic main
shaft's and links' numbers (``[drive.shaft]``, ``[drive.link.<name>]``), of the
limit the report gives — min(the rigid limit, each working member's dynamic-error
limit). Checked against the dynamic error's slope at the limit, against re-runs
built from hand-edited dicts, and against a whole analysis of the machine with the
key changed."""

from __future__ import annotations

import copy
import math
import tomllib
from pathlib import Path
from typing import Any

import cyclomech as cm
import pytest
from cyclomech.machine._sensitivity import NEAR, STEP

ROOT = Path(__file__).resolve().parents[2]
KNIFE = ROOT / "examples" / "knife_cutter.toml"


def _knife(max_error_m: float) -> dict[str, Any]:
    """The knife cutter with its knife's dynamic error bounded by ``max_error_m``, at
    30 rpm nominal (the error crosses 0.2 mm at 37.4 rpm, rising: above it)."""
    d = tomllib.loads(KNIFE.read_text())
    d["drive"]["link"]["knife"]["max_error_m"] = max_error_m
    d["machine"]["nominal_rpm"] = 30.0
    return d


@pytest.fixture(scope="module")
def tight() -> tuple[dict[str, Any], Any, dict[str, cm.machine.Sensitivity]]:
    """The knife may lag 0.2 mm: its dynamic error sets the limit (37.4 rpm)."""
    d = _knife(2e-4)
    r = cm.machine.analyze(cm.Machine.from_dict(d, "tight"), progress=False, sensitivities=True)
    return d, r, {s.key: s for s in r.sensitivities}


def test_the_dynamic_error_sets_the_limit_and_its_keys_rank_first(tight):
    _, r, _ = tight
    assert r.limit.by == "knife (dynamic error)"
    first = r.sensitivities[0]
    assert first.key.startswith("drive.") and first.status == "binds"
    assert all(s.limit_rpm == r.limit.rpm for s in r.sensitivities)


def test_the_bound_s_rate_is_the_errors_slope_at_the_limit(tight):
    # The limit is the root of e(n) = b, so dL/db = 1 / e'(L): e' from the chain
    # solved at constant speeds L ± 0.05 % (not through the limit's search).
    from cyclomech.dynamics import torsion_sweep
    from cyclomech.dynamics._elastic import _MAX_CYCLES, _TOL, _nodes

    _, r, table = tight
    lim = r.limit.rpm
    nodes = _nodes(r, r.machine.drive.elastic, "tight")
    around = torsion_sweep(nodes, [lim * 0.9995, lim * 1.0005], tol=_TOL, max_cycles=_MAX_CYCLES)
    e = around.peak_error[:, around.names.index("knife")]
    assert e[0] <= 2e-4 < e[1]
    want = (0.001 * lim) / (e[1] - e[0])
    s = table["drive.link.knife.max_error_m"]
    assert s.status == "binds"
    assert s.rpm_per_unit == pytest.approx(want, rel=1e-3)


def test_a_drive_key_is_its_re_run_from_a_hand_edited_file(tight):
    d, r, table = tight
    s = table["drive.shaft.stiffness_nm_per_rad.1"]

    def limit(factor: float) -> float:
        e = copy.deepcopy(d)
        e["drive"]["shaft"]["stiffness_nm_per_rad"][0] *= factor
        elastic = cm.Machine.from_dict(e, "by hand").drive.elastic
        return cm.dynamics.error_limits(r, elastic)["knife"]

    up, down = limit(1 + STEP), limit(1 - STEP)
    assert s.rpm_per_unit == pytest.approx((up - down) / (2 * STEP * 1.6e6), rel=1e-6)
    assert s.rpm_per_percent > 0  # a stiffer shaft lags less: a faster machine


def test_a_whole_analysis_with_the_bound_raised_agrees(tight):
    _, r, table = tight
    s = table["drive.link.knife.max_error_m"]
    e = _knife(2e-4 * 1.01)
    again = cm.machine.analyze(cm.Machine.from_dict(e, "raised"), progress=False)
    assert again.limit.rpm - r.limit.rpm == pytest.approx(s.rpm_per_percent, rel=1e-2)


def test_the_mechanisms_keys_are_not_varied_for_it_and_keep_their_rate(tight):
    _, _, table = tight
    s = table["operation.6.min_duration_s"]
    assert s.status == "not varied" and math.isnan(s.rpm_per_percent)
    assert "a dynamic error sets the limit" in s.note
    assert "on the limit beneath (57.14 rpm) +1 % gives -0.5714 rpm" in s.note


def test_where_no_dynamic_error_is_near_the_drive_keys_do_not_bind():
    r = cm.machine.analyze(cm.Machine.from_toml(KNIFE), progress=False, sensitivities=True)
    assert math.isinf(r.torsion.limits_rpm["knife"])
    drive = [s for s in r.sensitivities if s.key.startswith("drive.")]
    assert {s.key for s in drive} == {
        "drive.shaft.stiffness_nm_per_rad.1",
        "drive.shaft.hub_inertia_kg_m2.1",
        "drive.shaft.damping_ratio",
        "drive.link.knife.frequency_hz",
        "drive.link.knife.damping_ratio",
        "drive.link.knife.max_error_m",
    }
    assert all(s.status == "does not bind" and s.rpm_per_percent == 0.0 for s in drive)
    assert f"within {100 * NEAR:g} %" in drive[0].note
    # The operations keep their rates: the dynamic error does not set the limit.
    assert {s.key: s for s in r.sensitivities}["operation.6.min_duration_s"].status == "binds"


def test_a_drive_path_is_set_by_with_values_and_refused_by_a_sweep():
    d = _knife(1e-3)
    m = cm.Machine.from_dict(d, "knife")
    new = m.with_values({"drive.link.knife.max_error_m": 5e-4})
    assert new.drive.elastic != m.drive.elastic
    e = copy.deepcopy(d)
    e["drive"]["link"]["knife"]["max_error_m"] = 5e-4
    assert new.data == cm.Machine.from_dict(e, "by hand").data
    with pytest.raises(cm.CyclomechError, match="a sweep does not vary the drive's keys"):
        cm.machine.check_parameter(m, "drive.link.knife.max_error_m")


def test_a_mechanism_named_drive_keeps_its_keys_beside_the_drive_table():
    # The extrusion press line's press is the mechanism "drive", beside its
    # [drive] table: drive.R_m is the press's, drive.shaft.… the elastic shaft's.
    m = cm.Machine.from_toml(ROOT / "examples" / "extrusion_press_line.toml")
    press = m.with_values({"drive.k_Sp": 1.05 * m.data["mechanism"]["drive"]["k_Sp"]})
    assert press.data["drive"] is m.data["drive"]  # the [drive] table untouched
    cm.machine.check_parameter(m, "drive.k_Sp")
    shaft = m.data["drive"]["shaft"]
    key = next(k for k, v in shaft.items() if isinstance(v, float))
    other = m.with_values({f"drive.shaft.{key}": 2.0 * shaft[key]})
    assert other.data["drive"]["shaft"][key] == 2.0 * shaft[key]
    assert other.data["mechanism"]["drive"] == m.data["mechanism"]["drive"]
    with pytest.raises(cm.CyclomechError, match="a sweep does not vary the drive's keys"):
        cm.machine.check_parameter(m, f"drive.shaft.{key}")


def test_a_dynamic_error_just_above_the_limit_is_run_and_does_not_bind():
    # The edge of the NEAR rule: the pile's move slowed so that the cyclogram's
    # limit, n = 120° / (6·t), is 37.0 rpm, 1.1 % under the knife's dynamic-error
    # limit (37.41 rpm): within NEAR, so each drive key is run, and none binds,
    # since min(37.0, 37.41 ± its change) stays 37.0.
    d = _knife(2e-4)
    d["operation"][5]["min_duration_s"] = 120.0 / (6.0 * 37.0)
    r = cm.machine.analyze(cm.Machine.from_dict(d, "edge"), progress=False, sensitivities=True)
    assert r.limit.by == "cyclogram" and r.limit.rpm == pytest.approx(37.0, rel=1e-9)
    lowest = r.torsion.limits_rpm["knife"]
    assert r.limit.rpm < lowest <= r.limit.rpm * (1 + NEAR)
    drive = [s for s in r.sensitivities if s.key.startswith("drive.")]
    assert len(drive) == 6
    assert all(s.status == "does not bind" and "within" not in s.note for s in drive)
