"""A ``_deg`` angle table given in radians warns (probe B6): the knife's load table
over 140–250° of crank typed as 2.443–4.363 was read as a 30 kN cut over 1.9°.
The rule (``_keyrules.radian_table``): an array, or the first column of rows (the
angle along the cycle; the other columns are values, an arm's swing of a few degrees
among them), of at least two distinct values, all within ±2π and spanning at most 2π."""

from __future__ import annotations

import copy
import math
import tomllib
import warnings
from pathlib import Path

import cyclomech as cm
import pytest
from cyclomech._keyrules import radian_table

ROOT = Path(__file__).resolve().parents[2]
KNIFE = tomllib.loads((ROOT / "examples" / "knife_cutter.toml").read_text(encoding="utf-8"))


def load_warnings(data: dict) -> list[str]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        cm.Machine.from_dict(data, "knife.toml")
    return [str(w.message) for w in caught if "radians" in str(w.message)]


def test_a_load_table_in_radians_warns_once_naming_where_and_the_degrees():
    data = copy.deepcopy(KNIFE)
    (load,) = data["mechanism"]["knife"]["load"]
    degrees = list(load["angle_deg"])
    load["angle_deg"] = [round(math.radians(d), 3) for d in degrees]
    (msg,) = load_warnings(data)
    assert msg.startswith("knife.toml: [mechanism.knife] load #1: angle_deg = [")
    assert repr(load["angle_deg"]) in msg
    # The degrees it proposes are the example's own, to the 3 decimals of radians.
    shown = [float(x) for x in msg.rsplit("angle_deg = [", 1)[1].split("]")[0].split(",")]
    assert shown == pytest.approx(degrees, abs=0.03)


def test_the_load_table_in_degrees_does_not_warn():
    assert load_warnings(copy.deepcopy(KNIFE)) == []


@pytest.mark.parametrize(
    ("value", "warns"),
    [
        ([0.0, 2.0 * math.pi], True),  # one turn in radians
        ([0.0, 2.0 * math.pi + 1e-6], False),  # more than a turn: degrees
        ([-3.0, 3.0], True),
        ([-4.0, 4.0], False),  # spans 8 > 2π
        ([7.0, 8.0], False),  # beyond ±2π
        ([3.0, 3.0], False),  # no span
        ([0.44, 0.96, 4], True),  # a phase grid [start, stop, count] in radians
        ([25.0, 55.0, 4], False),
        ([[0.0, 0.0], [30.0, 0.2], [60.0, 0.5]], False),  # column 2: a value (a 0.5° swing)
        ([[0.0, 0.0], [0.52, 0.2], [1.05, 0.5]], True),  # column 1, the angle, in radians
        ([[0.0, 0.0], [30.0, 20.0], [60.0, 30.0]], False),
        ([[0.0, 0.0], [5.0, 0.0]], True),  # a cam angle column over 5°: flagged too
        ([1.0], False),
        (["a", "b"], False),
        ([[0.0, 1.0], [2.0]], False),  # ragged: the reader's own error
    ],
)
def test_the_rule_at_its_edges(value, warns):
    assert bool(radian_table("x_deg", value, "f")) is warns


def test_a_table_of_rows_names_the_column():
    assert radian_table("p_deg", [[0.0, 0.0], [30.0, 0.2]], "f") == ""  # a value column
    assert "(column 1)" in radian_table("p_deg", [[0.0, 0.0], [5.0, 0.0]], "f")
