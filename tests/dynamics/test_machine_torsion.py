"""A machine file's ``[drive.shaft]`` and ``[drive.link.<mechanism>]``: the working
members' dynamic errors in ``cyclomech run`` (issue 34 item 3, the machine's part).

The chain kernel is checked against closed forms and solve_ivp in
``test_torsion.py``; here: that the machine puts the right curves on the right node
(the knife's dynamic error on a stiff shaft and a stiff link is the link's
quasi-static deflection −Π″·ω²/ω_n², computed here from the linkage's own
acceleration analogs, and its lag on a soft shaft is Π′·θ), that an error bound
lowers the machine's speed limit, and the keys' errors.
"""

from __future__ import annotations

import copy
import math
import tomllib
from pathlib import Path
from typing import Any

import cyclomech as cm
import numpy as np
import pytest
from cyclomech import InputError
from cyclomech.dynamics import torsion_sweep
from cyclomech.dynamics._elastic import _MAX_CYCLES, _TOL, _nodes

ROOT = Path(__file__).resolve().parents[2]
KNIFE = ROOT / "examples" / "knife_cutter.toml"


def knife() -> dict[str, Any]:
    with open(KNIFE, "rb") as f:
        return tomllib.load(f)


def run(d: dict[str, Any]) -> Any:
    return cm.machine.analyze(cm.Machine.from_dict(d, "dir/knife.toml"), progress=False)


@pytest.fixture(scope="module")
def result() -> Any:
    return cm.machine.analyze(cm.Machine.from_toml(KNIFE), progress=False)


def test_the_file_is_read_and_reported(result: Any) -> None:
    e = cm.Machine.from_toml(KNIFE).drive.elastic
    assert e.take_off == ("knife",) and e.stiffness_nm_per_rad == (1.6e6,)
    assert e.links["knife"].frequency_hz == 40.0 and e.links["knife"].max_error_m == 1e-3
    t = result.torsion
    assert t.nominal is not None and t.failures() == []
    # under the motor, the head turns at the rigid steady state's mean speed
    assert t.nominal.mean_rpm == pytest.approx(result.dynamics.steady.mean_rpm, rel=1e-4)
    j = t.json()
    assert j["nodes"][0]["mechanism"] == "knife" and j["nodes"][0]["max_error"] == 1e-3
    assert j["nodes"][0]["peak_error"] == pytest.approx(t.nominal.peak_error["knife"])
    assert "Elastic shaft: dynamic error of knife" in t.line()
    # its events: those of the operations it performs and its phase's
    cg, opt = result.machine.cyclogram, result.optimum
    own = {e for o in cg.operations if o.mechanism == "knife" for e in o.arc} | {"clamped"}
    lags = t.event_lags_deg["knife"]
    assert set(lags) == own
    grid = np.append(t.nominal.theta_deg, 360.0)
    for e, lag in lags.items():
        tw = np.append(t.nominal.twist_rad[0], t.nominal.twist_rad[0, 0])
        assert lag == pytest.approx(np.degrees(np.interp(opt.times[e] % 360.0, grid, tw)))


def test_a_stiff_shaft_and_link_give_the_quasi_static_deflection() -> None:
    """Shaft 1e9 N·m/rad, link 400 Hz: at 45 rpm the knife point's error is its
    link's quasi-static deflection u = −ÿ/ω_n² = −Π″·ω²/ω_n² (the knife's
    harmonics are far below 400 Hz), Π″ from the linkage's own analogs. The sweep
    on 40, 45 and 50 rpm only: each speed's steady state is its own, and the stiff
    chain over the file's 41 speeds cost 7 of this test's CPU-s (the file's own
    sweep over its whole range: ``test_the_file_is_read_and_reported``)."""
    d = knife()
    d["drive"]["shaft"]["stiffness_nm_per_rad"] = [1e9]
    d["drive"]["link"]["knife"] = {"frequency_hz": 400.0, "damping_ratio": 0.05}
    d["machine"]["speed_rpm"], d["machine"]["speed_points"] = [40.0, 50.0], 3
    r = run(d)
    s = r.torsion.sweep
    wn = 2 * math.pi * 400.0
    i = int(np.argmin(np.abs(s.rpm - 45.0)))
    assert s.rpm[i] == 45.0
    w = s.rpm[i] * math.pi / 30
    knife_r = r.mechanisms["knife"]
    k = knife_r.kinetostatics.solution
    acc = k.acc[:, k.index(knife_r.mech.output), :]
    want = w * w * np.hypot(acc[:, 0], acc[:, 1]).max() / wn**2
    assert s.peak_error[i, 0] == pytest.approx(want, rel=1e-2)


def test_a_soft_shaft_lags_the_knife_by_its_twist() -> None:
    """A rigid link on a soft shaft: e = Π(φ − θ) − Π(φ) ≈ −Π′·θ; checked at the
    nominal state's peak twist against the analogs read at that angle."""
    d = knife()
    d["drive"]["shaft"]["stiffness_nm_per_rad"] = [2e5]
    del d["drive"]["link"]
    r = run(d)
    t = r.torsion.nominal
    k = int(np.argmax(t.twist_rad[0]))
    e = t.error["knife"][:, k]
    part = r.shaft.parts["knife"]
    assert part.static.size == t.twist_rad.shape[1]
    node = r.torsion.nodes[0]
    d1 = node.member.d1[:, k]
    theta = t.twist_rad[0, k]
    assert np.hypot(*e) == pytest.approx(np.hypot(*d1) * theta, rel=2e-2)
    assert theta > 1e-3  # a real twist, not a rounding


def test_an_error_bound_lowers_the_speed_limit() -> None:
    d = knife()
    d["drive"]["link"]["knife"]["max_error_m"] = 2.0e-4
    # the file's nominal 45 rpm is above the lowered limit: a warning (and exit 3)
    with pytest.warns(cm.CyclomechWarning, match=r"knife \(dynamic error\)"):
        r = run(d)
    lim = r.torsion.limits_rpm["knife"]
    assert 20.0 < lim < 100.0
    assert r.limit.rpm == lim and r.limit.by == "knife (dynamic error)"
    assert r.limit.mechanisms_rpm["knife (dynamic error)"] == lim
    assert "dynamic error" in r.limit.reason
    sw = r.sweep
    assert (sw.productivity_per_min[sw.rpm > lim] == 0).all()
    assert (sw.productivity_per_min[(sw.rpm <= lim) & sw.fits] > 0).all()
    # the sweep's errors bracket the bound at the limit, and the limit is the root:
    # the chain solved at a constant speed just under it is within the bound, just
    # over it not (the sweep's straight line was 0.04 rpm under it)
    s = r.torsion.sweep
    j = int(np.searchsorted(s.rpm, lim))
    assert s.peak_error[j - 1, 0] <= 2.0e-4 < s.peak_error[j, 0]
    nodes = _nodes(r, r.machine.drive.elastic, "knife.toml")
    around = [lim * (1 - 1e-7), lim * (1 + 1e-7)]
    near = torsion_sweep(nodes, around, tol=_TOL, max_cycles=_MAX_CYCLES)
    assert near.settled.all() and near.peak_error[0, 0] <= 2.0e-4 < near.peak_error[1, 0]
    assert lim - s.limit_rpm("knife", 2.0e-4) > 0.03
    assert r.nominal_rpm > lim and "knife (dynamic error)" in r.above_speed_limit


def test_limits_below_a_speed_keep_the_whole_sweeps_min(result: Any) -> None:
    # below_rpm stops the sweep at its first speed ≥ below (the grid is 20, 22, …,
    # 100 rpm, the crossing of 0.2 mm between 36 and 38): min(below, limit) is the
    # whole sweep's, at a grid speed, between two, on the limit and past the range.
    tight = result.machine.with_values({"drive.link.knife.max_error_m": 2e-4}).drive.elastic
    whole = cm.dynamics.error_limits(result, tight)["knife"]
    assert whole == pytest.approx(37.45, abs=0.01)
    for below in [20.0, 36.0, 37.0, whole, 39.0, 1e9]:
        part = cm.dynamics.error_limits(result, tight, below_rpm=below)["knife"]
        assert min(below, part) == min(below, whole), below
        assert part == (whole if below > 36.0 else math.inf), below  # the bracket is in
    with pytest.raises(InputError, match=r"below_rpm = 0.0 must be finite and > 0 \[rpm\] \(inf"):
        cm.dynamics.error_limits(result, tight, below_rpm=0.0)
    for bad in ("38", -1.0, math.nan, -math.inf, True):
        with pytest.raises(InputError, match=r"below_rpm .*\[rpm\] \(inf: the whole range\)"):
            cm.dynamics.error_limits(result, tight, below_rpm=bad)


def test_a_bound_exceeded_everywhere_fails() -> None:
    d = knife()
    d["drive"]["link"]["knife"]["max_error_m"] = 1e-6
    with pytest.warns(cm.CyclomechWarning, match="above the speed limit"):
        r = run(d)
    assert r.limit.rpm == r.torsion.sweep.rpm[0]  # exceeded from the range's first speed
    assert any("every speed" in f for f in r.failures)
    assert any("under the motor reaches" in f for f in r.failures)


@pytest.mark.parametrize(
    ("change", "match"),
    [
        (
            lambda d: (d["drive"].pop("link"), d["drive"]["shaft"].update(take_off=["knif"])),
            r"did you mean 'knife'",
        ),
        (
            lambda d: d["drive"]["shaft"].update(
                take_off=["knife", "clamp"],
                stiffness_nm_per_rad=[1.0, 2.0],
                hub_inertia_kg_m2=[1.0, 1.0],
            ),
            r"(must list every mechanism|not a mechanism)",
        ),
        (
            lambda d: d["drive"]["shaft"].update(stiffness_nm_per_rad=[-1.0]),
            r"stiffness_nm_per_rad #1",
        ),
        (lambda d: d["drive"]["shaft"].update(hub_inertia_kg_m2=[1.0, 2.0]), r"one per take_off"),
        (lambda d: d["drive"]["shaft"].update(damping_ratio=-0.1), r"damping_ratio"),
        (lambda d: d["drive"]["shaft"].update(stiff=1.0), r"stiff"),
        (lambda d: d["drive"]["shaft"].pop("take_off"), r"take_off is missing"),
        (lambda d: d["drive"]["link"]["knife"].update(max_error_deg=1.0), r"not both"),
        (lambda d: d["drive"]["link"]["knife"].update(frequency_hz=0.0), r"frequency_hz"),
        (lambda d: d["drive"]["link"].update(other={"frequency_hz": 3.0}), r"not a take_off"),
        (lambda d: d["drive"].pop("shaft"), r"needs \[drive.shaft\]"),
    ],
)
def test_bad_keys_are_named(change: Any, match: str) -> None:
    d = copy.deepcopy(knife())
    change(d)
    with pytest.raises(InputError, match=match):
        run(d)


def test_a_degree_bound_on_a_travelling_member_is_refused() -> None:
    d = knife()
    del d["drive"]["link"]["knife"]["max_error_m"]
    d["drive"]["link"]["knife"]["max_error_deg"] = 0.5
    with pytest.raises(InputError, match="max_error_deg bounds a member that turns"):
        run(d)


def test_a_bound_in_millimetres_given_as_metres_is_refused() -> None:
    """1 mm written as max_error_m = 1.0: larger than the knife's whole travel over
    the cycle (its x-y extent, ~0.2 m here), so it could never bind — an error that
    names the likely slip, not a speed limit quietly never reached."""
    d = knife()
    d["drive"]["link"]["knife"]["max_error_m"] = 1.0
    with pytest.raises(InputError, match=r"whole travel.*did you give millimetres"):
        run(d)


@pytest.mark.parametrize("table", ["shaft", "link"])
def test_a_damping_ratio_of_one_or_more_warns(table: str) -> None:
    d = knife()
    where = d["drive"]["shaft"] if table == "shaft" else d["drive"]["link"]["knife"]
    where["damping_ratio"] = 2.0  # 2 %, written as a percentage
    with pytest.warns(cm.CyclomechWarning, match=r"overdamped.*did you mean 0\.02"):
        cm.Machine.from_dict(d, "dir/knife.toml")


def test_a_chain_that_does_not_settle_is_a_failure() -> None:
    """No damping anywhere: no steady state under the motor nor at any speed of the
    sweep; the run fails saying so instead of reporting NaN quietly."""
    d = knife()
    d["drive"]["shaft"]["damping_ratio"] = 0.0
    d["drive"]["link"]["knife"]["damping_ratio"] = 0.0
    del d["drive"]["link"]["knife"]["max_error_m"]
    d["machine"]["speed_rpm"], d["machine"]["speed_points"] = [40.0, 50.0], 3  # quick
    m = cm.Machine.from_dict(d, "dir/knife.toml")
    r = cm.machine.analyze(m, progress=False)
    assert r.torsion.nominal is None
    assert any("did not settle at 3 of the 3 speeds" in f for f in r.failures)
    assert any("no periodic steady state" in f for f in r.failures)
