"""The registry of mechanism kinds (issue 17): a kind defined here, in the test
file, is registered and runs through ``cyclomech run`` to a report, with no change
anywhere else. Its one bound is checked against an independent solver: a dwell of
τ seconds on an operation is the cyclogram's own ``min_duration_s``, whose speed
limit :meth:`Cyclogram.max_speed_rpm` finds by Howard's cycle ratio."""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, ClassVar

import cyclomech as cm
import numpy as np
import pytest
from cyclomech import _toml
from cyclomech.cli import main
from cyclomech.machine import (
    KINDS,
    Bound,
    Context,
    KeyDoc,
    KeyTable,
    Mechanism,
    MechanismResult,
    PlainResult,
    Proportional,
    TableContext,
    register,
)


@dataclass(frozen=True)
class Dwell:
    """A toy kind: a mechanism that must rest on the operation ``arc`` for
    ``dwell_s`` seconds at constant speed, so the operation's angle is at least
    6·n·dwell_s degrees at n rpm."""

    kind: ClassVar[str] = "dwell"
    keys: ClassVar[frozenset[str]] = frozenset({"kind", "arc", "dwell_s"})
    fixed_keys: ClassVar[frozenset[str]] = frozenset({"kind", "arc"})
    json_groups: ClassVar[tuple[str, ...]] = ()
    sweep_columns: ClassVar[tuple[str, ...]] = ()
    # Its keys for the format reference: a kind carries its own documentation.
    key_docs: ClassVar[tuple[KeyTable, ...]] = (
        KeyTable(
            "dwell",
            "kind = dwell",
            (
                KeyDoc("kind", "The mechanism's kind.", "—", "text", "required", "dwell", False),
                KeyDoc("arc", "The operation it rests on.", "—", "array", "required",
                       "[from, to], an operation of the cyclogram", False),
                KeyDoc("dwell_s", "How long it rests.", "s", "number", "required",
                       "finite, > 0", True),
            ),
        ),
    )  # fmt: skip
    name: str
    arc: tuple[str, str]
    dwell_s: float

    @classmethod
    def from_table(cls, name: str, table: Mapping[str, Any], ctx: TableContext) -> Dwell:
        where = ctx.where(name)
        _toml.check_keys(table, set(cls.keys), ctx.source, f"[mechanism.{name}]")
        _toml.require(table, ("arc", "dwell_s"), where)
        dwell = _toml.optional_positive(table, "dwell_s", where, "[s]")
        assert dwell is not None
        arc = tuple(table["arc"])
        if arc not in [op.arc for op in ctx.cyclogram.operations]:
            raise cm.InputError(f"{where}: arc = {table['arc']!r} is not an operation")
        return cls(name, (arc[0], arc[1]), dwell)

    def speed_limit_rpm(self) -> float:
        return math.inf

    def limit_reason(self) -> str:
        return ""

    def bounds(self) -> tuple[Bound, ...]:
        return (Bound(self.arc, f"dwell[{self.name}]", self.name),)

    def constraints(self, rpm: float, *, linear: bool = False) -> tuple[cm.Constraint, ...]:
        t = 6.0 * rpm * self.dwell_s
        return (cm.Constraint(((self.arc, 1.0),), ">=", t, f"dwell[{self.name}]"),)

    @classmethod
    def bound_laws(
        cls, mechanisms: Sequence[Any], *, linear: bool = False, n_threads: int | None = None
    ) -> list[list[Any]]:
        return [[Proportional(6.0 * m.dwell_s)] for m in mechanisms]

    @classmethod
    def sweep_values(cls, *args: Any, **kwargs: Any) -> dict[str, np.ndarray]:
        return {}

    def analyze(self, ctx: Context) -> DwellResult:
        return DwellResult(self, 6.0 * ctx.nominal_rpm * self.dwell_s)


@dataclass(frozen=True)
class DwellResult(PlainResult):
    mech: Dwell
    angle_at_nominal: float

    def json(self) -> dict[str, dict[str, Any]]:
        return {
            "mechanisms": {
                "kind": "dwell",
                "arc": self.mech.arc,
                "dwell_angle_deg_at_nominal": self.angle_at_nominal,
            }
        }

    def table(self) -> tuple[list[str], list[list[Any]]]:
        return ["quantity", "value"], [["dwell [s]", self.mech.dwell_s]]

    def figures(self, save: Any) -> None:
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots()
        ax.bar(["dwell"], [self.angle_at_nominal])
        save(fig, f"{self.mech.name}_dwell", "The dwell's angle at the nominal speed.")


MACHINE = """
[machine]
name = "a press with a dwell"
speed_rpm = [105.0, 905.0]  # (no speed at the limit itself, 700 rpm)
speed_points = 9

[mechanism.hold]
kind = "dwell"
arc = ["2", "3"]
dwell_s = {dwell}

[cyclogram]
limiting = ["3", "4"]

[[operation]]
from = "1"
to = "2"
min_angle_deg = 90.0
name = "feed"

[[operation]]
from = "2"
to = "3"
min_angle_deg = 30.0
name = "hold"
mechanism = "hold"

[[operation]]
from = "3"
to = "4"
min_angle_deg = 60.0
name = "cut"
"""


@pytest.fixture
def dwell_kind():
    register(Dwell)
    try:
        yield Dwell
    finally:
        del KINDS["dwell"]


def test_the_toy_kind_satisfies_the_protocol(dwell_kind):
    d = Dwell("hold", ("2", "3"), 0.05)
    assert isinstance(d, Mechanism)
    assert isinstance(DwellResult(d, 1.0), MechanismResult)


def test_a_kind_defined_in_a_test_runs_through_cyclomech_run(dwell_kind, tmp_path, capsys):
    pytest.importorskip("matplotlib")
    path = tmp_path / "dwell.toml"
    path.write_text(MACHINE.format(dwell=0.05), encoding="utf-8")
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 0
    r = json.loads((out / "results.json").read_text(encoding="utf-8"))
    # Independent: the dwell as the operation's own min_duration_s, and Howard's
    # maximum cycle ratio: 90 + 6·n·0.05 + 60 = 360 at n = 700 rpm.
    plain = cm.Cyclogram(limiting=("3", "4"))
    plain.add_operation("1", "2", min_angle_deg=90.0)
    plain.add_operation("2", "3", min_angle_deg=30.0, min_duration_s=0.05)
    plain.add_operation("3", "4", min_angle_deg=60.0)
    want = plain.max_speed_rpm().rpm
    assert want == pytest.approx(700.0, rel=1e-12)
    assert r["speed_limit"]["rpm"] == pytest.approx(want, rel=1e-9)
    assert r["speed_limit"]["by"] == "cyclogram"
    assert "dwell[hold]" in r["speed_limit"]["binding"]
    assert r["mechanisms"]["hold"] == {
        "kind": "dwell",
        "arc": "2→3",  # (results.json writes an arc as from→to)
        "dwell_angle_deg_at_nominal": pytest.approx(6.0 * r["nominal_rpm"] * 0.05),
    }
    # At the nominal speed the optimum gives the limiting operation what the others
    # leave: 360 − 90 − max(30, 6·n·0.05).
    n = r["nominal_rpm"]
    assert r["optimum"]["limiting_deg"] == pytest.approx(360 - 90 - max(30.0, 0.3 * n))
    # The report has the kind's section, table and figure.
    html = (out / "report.html").read_text(encoding="utf-8")
    assert "Mechanism “hold” (dwell)" in html and "dwell [s]" in html
    assert (out / "figures" / "hold_dwell.png").is_file()
    # The speed sweep's bound column, exact, on every speed where it fits.
    sw = r["speed_sweep"]
    rpm = np.array(sw["speed_rpm"])
    fits = np.array(sw["fits"])
    assert fits.tolist() == (rpm <= want).tolist()
    lim = np.array([np.nan if v is None else v for v in sw["limiting_deg"]])
    np.testing.assert_allclose(lim[fits], 270.0 - np.maximum(30.0, 0.3 * rpm[fits]), rtol=1e-12)


def test_an_unregistered_kind_is_a_clear_error(tmp_path):
    path = tmp_path / "dwell.toml"
    path.write_text(MACHINE.format(dwell=0.05), encoding="utf-8")
    with pytest.raises(cm.InputError, match=r"\[mechanism.hold\]: kind = 'dwell' must be one of"):
        cm.Machine.from_toml(path)


def test_a_kind_name_cannot_be_taken_twice(dwell_kind):
    other = type("Other", (Dwell,), {})
    with pytest.raises(cm.InputError, match="the kind 'dwell' is taken by Dwell"):
        register(other)


def test_a_sweep_sets_a_registered_kinds_key(dwell_kind, tmp_path):
    path = tmp_path / "dwell.toml"
    path.write_text(MACHINE.format(dwell=0.05), encoding="utf-8")
    m = cm.Machine.from_toml(path)
    res = cm.sweep(m, {"hold.dwell_s": [0.05, 0.1]}, progress=False)
    # The speed limit of each design: (360 − 150)/(6·τ).
    limits = sorted(set(np.asarray(res.columns["speed_limit_rpm"]).tolist()))
    np.testing.assert_allclose(limits, [350.0, 700.0], rtol=1e-9)
    with pytest.raises(cm.InputError, match="has no key 'arc' a sweep can set"):
        cm.machine.check_parameter(m, "hold.arc")
