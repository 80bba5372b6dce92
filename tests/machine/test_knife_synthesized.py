"""A machine file's linkage table that gives requirements instead of dimensions
(``[mechanism.knife.synthesize]``, issue 35 item 8): ``cyclomech run``
synthesises the knife drive, reports what it chose and why with the three
schemes' comparison, and analyses it as any other linkage."""

from __future__ import annotations

import copy
import json
import math
import pickle
from pathlib import Path
from typing import Any

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.machine import analyze, write_report

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "knife_cutter_synthesized.toml"


@pytest.fixture(scope="module")
def machine() -> cm.Machine:
    return cm.Machine.from_toml(EXAMPLE)


def _small(**extra: Any) -> dict[str, Any]:
    """The example's layout with a quick synthesis (no comparison)."""
    d = copy.deepcopy(dict(cm.Machine.from_toml(EXAMPLE).data or {}))
    syn = d["mechanism"]["knife"]["synthesize"]
    for k in ("compare", "compare_rpm", "cut_force_n"):
        syn.pop(k, None)
    syn.update({"maxiter": 40, **extra})
    return d


def test_the_example_synthesises_its_knife_drive(machine: cm.Machine) -> None:
    knife = machine.mechanisms["knife"]
    rec = knife.synthesis
    assert rec is not None and rec.drive.scheme == "br125"
    # The linkage the machine analyses is the synthesis's, and does what was asked:
    # solved here on 0.1° with its own solver.
    lk = knife.linkage
    assert lk is rec.linkage and lk.output == "E"
    y = lk.solve(np.radians(np.arange(0.0, 360.0, 0.1)), points=["E"]).xy[:, 0, 1]
    assert abs(float(y.max() - y.min()) - 0.166) <= 0.5e-3 + 1e-5
    assert abs(rec.drive.cut_deg - 174.0) <= 0.5
    assert rec.drive.feasible
    # The three schemes were compared.
    assert [r["scheme"] for r in rec.comparison.rows] == ["br125", "br136", "brp4"]


def test_the_comparison_is_computed_when_first_read() -> None:
    """Reading the file synthesises the table's scheme only; the comparison, read
    later, is the public comparison of the same requirement, with the same drive."""
    rec = cm.Machine.from_toml(EXAMPLE).mechanisms["knife"].synthesis
    assert "comparison=(computed when first read)" in repr(rec)
    # A pickled record (a Dask worker's machine) computes it the same way.
    again = pickle.loads(pickle.dumps(rec))
    c = rec.comparison
    assert "computed when first read" not in repr(rec) and rec.comparison is c
    req = cm.synthesis.KnifeRequirement(
        0.166, 174.0, knife_m=1.51, min_transmission_deg=30.0, popsize=10, maxiter=60
    )
    want = cm.synthesis.compare_knife_drives(req, rpm=45.0, cut_force_n=30000.0)
    assert c.requirement == req and c.rows == want.rows and c.failed == want.failed
    for s in want.curves:
        for k, v in want.curves[s].items():
            np.testing.assert_array_equal(c.curves[s][k], v)
    assert c.drives["br125"] is rec.drive
    assert again.comparison.rows == want.rows
    np.testing.assert_array_equal(
        again.drive.linkage.dimension_values, rec.drive.linkage.dimension_values
    )


def test_the_report_says_what_it_chose_and_why(machine: cm.Machine, tmp_path: Path) -> None:
    r = analyze(machine, progress=False)
    res = r.mechanisms["knife"]
    _, rows = res.table()
    labels = [row[0] for row in rows]
    assert "synthesised scheme" in labels and "synthesis: what it chose and why" in labels
    assert sum(lab.startswith("scheme ") for lab in labels) == 3
    why = dict((row[0], row[1]) for row in rows)["synthesis: what it chose and why"]
    assert "stroke" in why and "largest least transmission angle" in why
    paths = write_report(r, tmp_path, figures=True)
    names = {p.name for p in paths}
    assert {"knife_schemes.csv", "knife_schemes_motion.png", "knife_schemes_torque.png"} <= names
    info = json.loads((tmp_path / "results.json").read_text("utf-8"))
    syn = info["mechanisms"]["knife"]["synthesis"]
    assert syn["scheme"] == "br125" and len(syn["comparison"]) == 3
    # Analysed as any linkage: its forces and speed limit are there.
    assert info["mechanisms"]["knife"]["peak_torque_nm"] > 0
    assert math.isfinite(info["mechanisms"]["knife"]["speed_limit_rpm"])


def test_without_compare_there_is_no_comparison() -> None:
    m = cm.Machine.from_dict(_small(), str(EXAMPLE))
    rec = m.mechanisms["knife"].synthesis
    assert rec.comparison is None
    assert not any(row[0].startswith("scheme ") for row in rec.rows())


@pytest.mark.parametrize(
    ("change", "match"),
    [
        ({"points": {"A": [0.0, 0.0]}}, "synthesize gives the linkage from requirements"),
        ({"synthesize": {"scheme": "br999", "stroke_m": 0.1, "cut_deg": 170.0}},
         r"scheme = 'br999' has no synthesizer; the schemes are br125, br136, brp4"),
        ({"synthesize": {"scheme": "br125", "cut_deg": 170.0}}, "missing key 'stroke_m'"),
        ({"synthesize": {"scheme": "br125", "stroke_m": 0.1, "cut_deg": 360.0}},
         r"synthesize: cut_deg = 360.0"),
        ({"synthesize": {"scheme": "br125", "stroke_m": 0.1, "cut_deg": 170.0, "bogus": 1}},
         "unknown key 'bogus'"),
        ({"synthesize": {"scheme": "br125", "stroke_m": 0.1, "cut_deg": 170.0,
                         "compare_rpm": 40.0}}, "need compare = true"),
        ({"synthesize": "br125"}, "must be a table"),
    ],
)  # fmt: skip
def test_bad_synthesize_tables_are_refused(change: dict[str, Any], match: str) -> None:
    d = _small()
    d["mechanism"]["knife"].update(change)
    with pytest.raises(cm.InputError, match=match) as e:
        cm.Machine.from_dict(d, str(EXAMPLE))
    assert "[mechanism.knife]" in str(e.value)


def test_an_unreachable_stroke_names_what_fails() -> None:
    d = _small(stroke_m=1.5, maxiter=20)
    with pytest.raises(cm.InputError, match=r"synthesize: .*the stroke.*best achieved"):
        cm.Machine.from_dict(d, str(EXAMPLE))


def test_the_synthesize_keys_are_documented() -> None:
    from cyclomech import _keydocs

    documented = {k.name for k in _keydocs.tables()["linkage.synthesize"].keys}
    assert documented == set(cm.synthesis.SYNTHESIZE_KEYS)


def test_a_stroke_in_millimetres_is_warned_of() -> None:
    """stroke_m = 166 (mm given as m) is not absorbed: the unit-suffix rule of every
    other table warns, naming the slip, and no scheme reaches the stroke."""
    d = _small(stroke_m=166.0, maxiter=2)
    with (
        pytest.warns(cm.CyclomechWarning, match=r"stroke_m = 166.0 m .*millimetres"),
        pytest.raises(cm.InputError, match="stroke"),
    ):
        cm.Machine.from_dict(d, "f.toml")
