"""Keys in sub-tables and lists (issue 36, item 2): a linkage's points and lengths,
a cam's segments, force curves. Paths into them (positions from 1) set the same
machine as the dict edited by hand; the sensitivities of such keys agree with
re-runs of machines built from hand-edited dicts (not ``with_values``), and with
the closed form where one holds: a linkage whose speed limit is its output's peak
acceleration a = ω²·A(geometry) has n ∝ √a_max, so +1 % of a_max buys 0.5 % of n."""

from __future__ import annotations

import copy
import math
import tomllib
from pathlib import Path
from typing import Any

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.cli import main
from cyclomech.machine import _sensitivity
from cyclomech.machine._sensitivity import SCALED, STEP

ROOT = Path(__file__).resolve().parents[2]
KNIFE = ROOT / "examples" / "knife_cutter.toml"


def _knife(a_max: float = 0.5) -> dict[str, Any]:
    """The knife cutter with its knife's acceleration limit lowered until the
    linkage, not the cyclogram, sets the speed limit."""
    d = tomllib.loads(KNIFE.read_text())
    d["mechanism"]["knife"]["max_acceleration_m_per_s2"] = a_max
    return d


def _by_hand(d: dict[str, Any], where: tuple[Any, ...], factor: float) -> float:
    """The speed limit of a machine built from ``d`` with the number at ``where``
    (keys and 0-based positions, walked by hand) times ``factor``."""
    d = copy.deepcopy(d)
    node = d["mechanism"]
    for k in where[:-1]:
        node = node[k]
    node[where[-1]] = np.multiply(node[where[-1]], factor).tolist()
    return cm.Machine.from_dict(d, "by hand").speed_limit().rpm


@pytest.fixture(scope="module")
def knife() -> tuple[dict[str, Any], cm.Machine, dict[str, cm.machine.Sensitivity]]:
    d = _knife()
    m = cm.Machine.from_dict(d, "knife")
    return d, m, {s.key: s for s in cm.machine.sensitivities(m)}


def test_a_path_sets_what_the_hand_edited_dict_holds():
    d = _knife()
    m = cm.Machine.from_dict(d, "knife")
    new = m.with_values({"knife.lengths.3.length": 1.52, "knife.points.O.2": 1.19})
    by_hand = copy.deepcopy(d)
    by_hand["mechanism"]["knife"]["lengths"][2]["length"] = 1.52
    by_hand["mechanism"]["knife"]["points"]["O"][1] = 1.19
    want = cm.Machine.from_dict(by_hand, "by hand")
    assert new.data == want.data
    assert new.speed_limit().rpm == want.speed_limit().rpm
    # The machine it came from is untouched.
    assert m.data["mechanism"]["knife"]["lengths"][2]["length"] == 1.51


def test_linkage_dimensions_bind_as_re_runs_of_hand_edited_files_say(knife):
    d, m, table = knife
    lim = m.speed_limit()
    assert lim.by == "knife" and "max_acceleration" in lim.reason
    cases = {
        "knife.lengths.3.length": ("knife", "lengths", 2, "length"),
        "knife.lengths.5.length": ("knife", "lengths", 4, "length"),
        "knife.points.O.2": ("knife", "points", "O", 1),
        "knife.points.D.1": ("knife", "points", "D", 0),
    }
    for key, where in cases.items():
        s = table[key]
        assert s.status == "binds", key
        value = d["mechanism"]
        for k in where:
            value = value[k]
        up, down = _by_hand(d, where, 1 + STEP), _by_hand(d, where, 1 - STEP)
        assert s.value == value
        assert s.rpm_per_unit == pytest.approx((up - down) / (2 * STEP * value), rel=1e-2), key


def test_the_acceleration_limit_buys_half_a_percent_per_percent(knife):
    # n ∝ √a_max: +1 % of a_max is +0.5 % of n, to first order (the central
    # difference's error is O(h²)).
    _, m, table = knife
    n = m.speed_limit().rpm
    s = table["knife.max_acceleration_m_per_s2"]
    assert s.rpm_per_percent == pytest.approx(0.005 * n, rel=1e-6)


def test_drawn_positions_of_moving_joints_do_not_bind(knife):
    # With every moving link's length given, B, C and E's drawn positions only pick
    # the assembly: the limit does not move with them.
    d, _, table = knife
    base = cm.Machine.from_dict(d, "knife").speed_limit().rpm
    for joint in "BCE":
        for i in (1, 2):
            s = table[f"knife.points.{joint}.{i}"]
            assert (s.status, s.rpm_per_percent) == ("does not bind", 0.0)
    up = _by_hand(d, ("knife", "points", "B", 0), 1.01)
    assert up == pytest.approx(base, rel=1e-9)
    # The crank pin F sits level with its pivot O: the crank's length, hence the
    # limit, has an extremum in F's y there — both ways change it alike, a kink by
    # the rule (no slope holds on both sides), as the re-runs by hand say.
    s = table["knife.points.F.2"]
    assert s.status == "kink" and math.isnan(s.rpm_per_percent)
    up = _by_hand(d, ("knife", "points", "F", 1), 1 + STEP)
    down = _by_hand(d, ("knife", "points", "F", 1), 1 - STEP)
    assert (up - base) * (down - base) > 0
    # A zero (the pivot A at the origin) has no relative step: it is not listed.
    assert "knife.points.A.1" not in table and "knife.points.D.2" not in table


def test_a_curve_is_scaled_as_a_whole(knife):
    d, m, table = knife
    s = table["knife.load.1.force_n"]
    assert s.value == 1.0 and SCALED.format(n=10) in s.note
    scaled = m.with_values(
        {
            "knife.load.1.force_n": [
                [0.0, 2.0 * f] for _, f in d["mechanism"]["knife"]["load"][0]["force_n"]
            ]
        }
    )
    assert scaled.data["mechanism"]["knife"]["load"][0]["force_n"][1] == [0.0, 60000.0]
    # The knife's forces do not set its speed limit (no motor bound here): 0, as a
    # re-run with the force doubled says.
    assert s.status == "does not bind"
    assert _by_hand(d, ("knife", "load", 0, "force_n"), 2.0) == pytest.approx(
        m.speed_limit().rpm, rel=1e-12
    )


def test_keys_past_the_cap_are_listed_not_varied(monkeypatch):
    monkeypatch.setattr(_sensitivity, "MAX_NESTED", 3)
    m = cm.Machine.from_dict(_knife(), "knife")
    table = cm.machine.sensitivities(m)
    deep = [s for s in table if s.key.count(".") > 1 and not s.key.startswith("operation.")]
    varied = [s for s in deep if s.status != "not varied"]
    skipped = [s for s in deep if s.status == "not varied"]
    assert len(varied) == 3 and len(skipped) == len(deep) - 3
    assert all(math.isnan(s.rpm_per_percent) and "first 3" in s.note for s in skipped)
    assert table[-len(skipped) :] == skipped  # ranked last
    # The top-level keys and the operations are varied all the same.
    assert {s.status for s in table if s.key == "knife.max_acceleration_m_per_s2"} == {"binds"}


def test_tied_segment_numbers_cannot_vary_alone_and_say_why():
    # A cam's rise stroke alone breaks its return to the start: refused, with why.
    m = cm.Machine.from_toml(ROOT / "examples" / "stb_loom.toml")
    cam = "lifter cam"
    s = {x.key: x for x in cm.machine.sensitivities(m)}[f"{cam}.segment.1.stroke_deg"]
    assert s.status == "cannot vary" and "does not return to its start" in s.note


@pytest.mark.parametrize(
    ("path", "message"),
    [
        (
            "knife.lengths.7.length",
            r"knife.lengths is a list of 6: '7' must be a position in it, 1 to 6",
        ),
        ("knife.lengths.0.length", r"'0' must be a position in it, 1 to 6"),
        ("knife.points.Z.1", r"knife.points has no key 'Z'; its keys are A, D, O, B, C, E, F"),
        ("knife.pointz.B.1", r"knife.pointz is not in the file"),
        ("knife.output.x", r"knife.output is a str, not a table or a list"),
    ],
)
def test_a_bad_path_is_refused_by_name(path, message):
    m = cm.Machine.from_dict(_knife(), "knife")
    with pytest.raises(cm.CyclomechError, match=message):
        m.with_values({path: 1.0})
    with pytest.raises(cm.CyclomechError, match=message):
        cm.machine.check_parameter(m, path)


def test_a_sweep_takes_a_number_not_a_table_nor_an_unvaried_table():
    m = cm.Machine.from_dict(_knife(), "knife")
    cm.machine.check_parameter(m, "knife.lengths.3.length")
    cm.machine.check_parameter(m, "knife.points.O.2")
    with pytest.raises(cm.CyclomechError, match=r"names a list, not a number: .*knife.lengths.1"):
        cm.machine.check_parameter(m, "knife.lengths")
    with pytest.raises(cm.CyclomechError, match=r"names a table, not a number: .*knife.points.A"):
        cm.machine.check_parameter(m, "knife.points")
    with pytest.raises(cm.CyclomechError, match="names 'E', not a number"):
        cm.machine.check_parameter(m, "knife.lengths.4.joints.2")
    synth = cm.Machine.from_toml(ROOT / "examples" / "lifter_cam_sized.toml")
    with pytest.raises(cm.CyclomechError, match="'synthesize' is not a table whose numbers"):
        cm.machine.check_parameter(synth, "lifter cam.synthesize.min_base_radius_m")


def test_a_sweep_varies_a_length_as_hand_edited_files_do():
    d = _knife()
    m = cm.Machine.from_dict(d, "knife")
    lengths = [1.50, 1.51, 1.52]
    r = cm.machine.sweep(
        m, {"knife.lengths.3.length": lengths, "speed_rpm": [10.0]}, progress=False
    )
    want = [_by_hand(d, ("knife", "lengths", 2, "length"), x / 1.51) for x in lengths]
    np.testing.assert_allclose(r.columns["speed_limit_rpm"], want, rtol=1e-12)
    assert want[0] > want[1] > want[2]  # the sign the table gives the coupler


def test_the_sweep_command_takes_a_path(tmp_path, capsys):
    argv = [
        "sweep",
        str(KNIFE),
        "--set",
        "knife.lengths.3.length=1.50:1.52:3",
        "--speed",
        "10:20:2",
    ]
    assert main([*argv, "--out", str(tmp_path), "--quiet"]) == 0
    assert "highest 57.14 rpm at knife.lengths.3.length=1.5" in capsys.readouterr().out
    assert (tmp_path / "sweep.parquet").stat().st_size > 0


class _Backwards(frozenset):
    """A set of table names that iterates them the other way round from the file."""

    def __iter__(self):
        return iter(sorted(frozenset.__iter__(self), key=self.order.index, reverse=True))


def test_sub_tables_are_varied_in_the_files_order(monkeypatch):
    """The kind's varied tables are a set, whose order in one process follows the
    string hashes (the loom's ranking put its cam's ``segment`` and ``friction`` rows,
    tied at "does not bind", in either order from run to run); the keys go in the
    file's order, as tomllib reads it, whatever order the set iterates in."""
    loom = ROOT / "examples" / "stb_loom.toml"
    table = tomllib.loads(loom.read_text())["mechanism"]["lifter cam"]
    in_file = [k for k in table if k in ("segment", "friction")]
    assert len(in_file) == 2
    _Backwards.order = in_file
    from cyclomech.machine import _model

    monkeypatch.setattr(_model, "_varied_tables", lambda mech: _Backwards(in_file))
    keys = [p for p, _, _ in _sensitivity._keys(cm.Machine.from_toml(loom))]
    nested = [p.split(".")[1] for p in keys if p.startswith("lifter cam.") and p.count(".") > 1]
    assert nested and [k for i, k in enumerate(nested) if k not in nested[:i]] == in_file
