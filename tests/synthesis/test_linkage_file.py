"""A machine file's linkage table that asks for a function, path or motion
generator or a six-bar dwell linkage (``[mechanism.X.synthesize]``, issue 35 item
8): the linkage the machine analyses meets the requirement when solved by its own
position solver (the requirement itself, and dense sampling, the references), the
report says what was chosen, and bad tables are refused naming the key."""

from __future__ import annotations

import contextlib
import json
import math
import pickle
import time
import tomllib
import warnings
from pathlib import Path
from typing import Any

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.machine import analyze
from cyclomech.synthesis import _dwell_file, _function_file, _motion_file, _path_file

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "transfer_arm_synthesized.toml"

FUNCTION = {"scheme": "function", "ground_m": 0.2,
            "precision_points_deg": [[30.0, 80.0], [60.0, 90.0], [90.0, 100.0]]}  # fmt: skip
#: y = x² on [0, 1] as φ from 0° to 120°, ψ from 60° to 110° (tabulated).
SQUARE = [[phi, 60.0 + 50.0 * (phi / 120.0) ** 2] for phi in np.linspace(0.0, 120.0, 41)]
TARGETS = [[0.1, 0.2], [0.25, 0.3], [0.35, 0.2], [0.2, 0.05], [0.15, 0.1]]
PATH = {"scheme": "path", "targets_m": TARGETS, "maxiter": 200,
        "min_transmission_deg": 30.0, "max_error_m": 1e-4}  # fmt: skip
POSES = [(0.0, 0.0, 0.0), (0.05, 0.02, 20.0), (0.09, 0.06, 45.0)]
MOTION = {"scheme": "motion", "pose_points_m": [list(p[:2]) for p in POSES],
          "pose_angles_deg": [p[2] for p in POSES], "min_transmission_deg": 40.0,
          "max_length_ratio": 5.0}  # fmt: skip
DWELL = {"scheme": "dwell_sixbar", "dwell_deg": 80.0, "swing_deg": 30.0, "ground_m": 0.2,
         "popsize": 8, "maxiter": 10, "max_residual_deg": 0.5}  # fmt: skip


def machine(syn: dict[str, Any], **extra: Any) -> cm.Machine:
    """The example machine with its arm replaced by a linkage from ``syn``."""
    d = tomllib.loads(EXAMPLE.read_text("utf-8"))
    d["mechanism"]["arm"] = {"kind": "linkage", "synthesize": syn, **extra}
    return cm.Machine.from_dict(d, str(EXAMPLE))


def rocker_deg(sol: Any, pivot: str, joint: str) -> np.ndarray:
    d = sol[joint] - sol[pivot]
    return np.degrees(np.arctan2(d[:, 1], d[:, 0]))


def wrap(a: Any) -> np.ndarray:
    return (np.asarray(a) + 180.0) % 360.0 - 180.0


# ---------------------------------------------------------------- function
def test_function_generator_meets_its_precision_points() -> None:
    m = machine(FUNCTION)
    arm = m.mechanisms["arm"]
    c = arm.synthesis.candidate
    assert arm.linkage is arm.synthesis.linkage and arm.output == "C"
    phi = np.array([p for p, _ in FUNCTION["precision_points_deg"]])
    psi = np.array([q for _, q in FUNCTION["precision_points_deg"]])
    crank = phi + (180.0 if c.crank_flipped else 0.0)
    sol = arm.linkage.solve(np.radians(crank))
    got = rocker_deg(sol, "D", "C") - (180.0 if c.output_flipped else 0.0)
    np.testing.assert_allclose(wrap(got - psi), 0.0, atol=1e-9)
    # The machine turns it fully: it assembles at every angle of a dense turn.
    assert arm.linkage.solve(np.radians(np.arange(0.0, 360.0, 0.25))).ok.all()
    assert c.margins.crank_turns


def test_function_generator_with_offsets_meets_its_shifted_points() -> None:
    offsets = [[0.0, 0.0], [40.0, 10.0], [-20.0, 30.0]]
    c = machine({**FUNCTION, "offsets_deg": offsets}).mechanisms["arm"].synthesis.candidate
    assert list(c.offset) in offsets
    lk = c.linkage()
    phi = np.array([p for p, _ in c.precision])
    sol = lk.solve(np.radians(phi + (180.0 if c.crank_flipped else 0.0)))
    got = rocker_deg(sol, "D", "C") - (180.0 if c.output_flipped else 0.0)
    want = np.array([q for _, q in FUNCTION["precision_points_deg"]]) + c.offset[1]
    np.testing.assert_allclose(wrap(got - want), 0.0, atol=1e-9)


def test_function_generator_structural_error_by_dense_sampling() -> None:
    """function_deg: the reported structural error is the largest difference from
    the table on a dense grid, solved by the linkage itself."""
    rec = machine({"scheme": "function", "function_deg": SQUARE, "ground_m": 0.2})
    c = rec.mechanisms["arm"].synthesis.candidate
    phi = np.linspace(0.0, 120.0, 2401)
    crank = phi + (180.0 if c.crank_flipped else 0.0)
    sol = rec.mechanisms["arm"].linkage.solve(np.radians(crank))
    got = rocker_deg(sol, "D", "C") - (180.0 if c.output_flipped else 0.0)
    want = 60.0 + 50.0 * (phi / 120.0) ** 2
    dense = float(np.max(np.abs(wrap(got - want))))
    # The table is linear between its 41 rows: the difference from x² there is ≤ 50/(8·40²).
    assert dense == pytest.approx(c.structural_error, abs=0.05 + 50.0 / (8 * 40**2))
    assert 0.0 < c.structural_error < 3.0


def test_function_from_ranges_is_linear() -> None:
    rec = machine({"scheme": "function", "input_range_deg": [0.0, 120.0],
                   "output_range_deg": [60.0, 110.0], "ground_m": 0.2, "points": 4})  # fmt: skip
    c = rec.mechanisms["arm"].synthesis.candidate
    assert len(c.precision) == 4
    for phi, psi in c.precision:  # on the line, Chebyshev-placed inside the range
        assert 0.0 < phi < 120.0 and psi == pytest.approx(60.0 + 50.0 * phi / 120.0, abs=1e-12)


# ---------------------------------------------------------------- path
def test_path_generator_passes_its_targets() -> None:
    arm = machine(PATH).mechanisms["arm"]
    c = arm.synthesis.candidate
    assert arm.output == "P"
    sol = arm.linkage.solve(c.angles)
    err = np.hypot(*(sol["P"] - np.array(TARGETS)).T)
    assert err.max() <= PATH["max_error_m"]
    assert err.max() == pytest.approx(c.max, abs=1e-9)
    # Dense sampling of P's path over the turn (the machine's): no target farther.
    turn = arm.linkage.solve(np.radians(np.arange(0.0, 360.0, 0.05)), points=["P"])
    assert turn.ok.all()
    near = np.min(np.hypot(*(turn["P"][:, None, :] - np.array(TARGETS)[None]).T), axis=1)
    assert near.max() <= PATH["max_error_m"] + 1e-3 * 0.05 * 0.3
    assert c.margins.worst_transmission_deg >= 30.0


def test_path_bounds_hold() -> None:
    syn = {**PATH, "bounds": {"crank_m": [0.03, 0.05], "x0_m": [-0.2, 0.0]}, "maxiter": 30,
           "polish": False}  # fmt: skip
    syn.pop("max_error_m")
    p = machine(syn).mechanisms["arm"].synthesis.candidate.params
    assert 0.03 <= p["r2"] <= 0.05 and -0.2 <= p["x0"] <= 0.0


def test_path_with_timing_meets_the_crank_angles() -> None:
    timing = [0.0, 60.0, 130.0, 220.0, 300.0]
    # Targets of a known four-bar at those crank angles: the requirement is reachable.
    known = cm.synthesis.four_bar_linkage(0.05, 0.2, 0.15, 0.2, coupler_point=(0.08, 0.05))
    pts = known.solve(np.radians(timing), points=["P"])["P"]
    syn = {"scheme": "path", "targets_m": pts.tolist(), "timing_deg": timing,
           "maxiter": 150, "max_error_m": 1e-3}  # fmt: skip
    arm = machine(syn).mechanisms["arm"]
    c = arm.synthesis.candidate
    at = np.degrees(c.angles)
    np.testing.assert_allclose(wrap(at - at[0] - np.array(timing)), 0.0, atol=1e-9)
    got = arm.linkage.solve(c.angles)["P"]
    assert np.hypot(*(got - pts).T).max() <= 1e-3


# ---------------------------------------------------------------- motion
def test_motion_generator_takes_its_poses_in_order() -> None:
    arm = machine(MOTION).mechanisms["arm"]
    c = arm.synthesis.candidate
    lk = arm.linkage
    sol = lk.solve(np.radians(c.crank_angles_deg))
    np.testing.assert_allclose(sol["P"], [p[:2] for p in POSES], atol=1e-9)
    turned = rocker_deg(sol, "A", "B")  # the coupler line A → B turns with the poses
    want = np.array([p[2] for p in POSES])
    np.testing.assert_allclose(wrap(turned - turned[0] - (want - want[0])), 0.0, atol=1e-9)
    # Counter-clockwise from pose 1, the crank meets pose 2 before pose 3.
    t = np.array(c.crank_angles_deg)
    assert 0.0 < (t[1] - t[0]) % 360.0 < (t[2] - t[0]) % 360.0
    # It turns fully, and its transmission angle over a dense turn (between the
    # coupler A → B and the rocker B0 → B) stays within the table's limit.
    turn = lk.solve(np.radians(t[0] + np.arange(0.0, 360.0, 0.1)))
    assert turn.ok.all()
    u, v = turn["A"] - turn["B"], turn["B0"] - turn["B"]
    mu = np.degrees(np.arccos(np.sum(u * v, 1) / np.hypot(*u.T) / np.hypot(*v.T)))
    assert np.minimum(mu, 180.0 - mu).min() >= 40.0 - 1e-9
    assert c.margins.length_ratio <= 5.0


def test_motion_with_given_circle_points() -> None:
    syn = {**MOTION, "circle_points_m": [[0.0, -0.05], [0.06, -0.04]]}
    syn.pop("min_transmission_deg")
    syn.pop("max_length_ratio")
    c = machine(syn).mechanisms["arm"].synthesis.candidate
    assert c.circle_points == ((0.0, -0.05), (0.06, -0.04))


# ---------------------------------------------------------------- dwell
def test_dwell_sixbar_dwells_and_swings() -> None:
    arm = machine(DWELL).mechanisms["arm"]
    c = arm.synthesis.candidate
    assert arm.output == "E" and c.feasible
    lo, hi = c.dwell_range_deg
    sol = arm.linkage.solve(np.radians(np.linspace(lo, hi, 4001)), points=["E", "F"])
    still = np.unwrap(np.radians(rocker_deg(sol, "F", "E")))
    assert math.degrees(np.ptp(still)) <= c.residual_deg + 1e-9
    assert c.residual_deg <= DWELL["max_residual_deg"]
    turn = arm.linkage.solve(np.radians(np.arange(0.0, 360.0, 0.01)), points=["E", "F"])
    swing = math.degrees(np.ptp(np.unwrap(np.radians(rocker_deg(turn, "F", "E")))))
    assert swing == pytest.approx(30.0, abs=1e-5)


# ---------------------------------------------------------------- the report
@pytest.mark.parametrize(
    ("syn", "words"),
    [(FUNCTION, "function"), (PATH, "path"), (MOTION, "motion"), (DWELL, "dwell_sixbar")],
    ids=["function", "path", "motion", "dwell_sixbar"],
)
def test_report_json_figures_and_files(syn: dict[str, Any], words: str, tmp_path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    m = machine(syn, max_acceleration_m_per_s2=50.0)
    r = analyze(m, progress=False)
    res = r.mechanisms["arm"]
    rows = dict((row[0], row[1]) for row in res.table()[1])
    assert rows["synthesised scheme"].startswith(words)
    assert "synthesis: what it chose and why" in rows and "synthesis margins" in rows
    assert "transmission" in rows["synthesis margins"]
    info = res.json()["mechanisms"]
    assert info["synthesis"]["scheme"] == words
    assert math.isfinite(info["speed_limit_rpm"])  # analysed as any linkage
    rec = m.mechanisms["arm"].synthesis
    # A sweep's workers take the machine by pickle: the record goes too.
    again = pickle.loads(pickle.dumps(m)).mechanisms["arm"].synthesis
    assert again.json() == json.loads(json.dumps(rec.json(), allow_nan=False))
    (path,) = rec.files(tmp_path, "the arm")
    lines = path.read_text("utf-8").splitlines()
    assert lines[0] == "quantity,value,unit" and len(lines) > 4
    stems: list[str] = []
    rec.figures(lambda fig, stem, caption: (stems.append(stem), plt.close(fig)), "arm")
    assert stems == ["arm_synthesis"]


def test_parsing_again_does_not_synthesise_again() -> None:
    syn = {**DWELL, "seed": 7}
    t0 = time.perf_counter()
    first = machine(syn).mechanisms["arm"].synthesis
    t1 = time.perf_counter()
    again = machine(syn).mechanisms["arm"].synthesis
    t2 = time.perf_counter()
    assert again.candidate is first.candidate
    assert t2 - t1 < t1 - t0


# ---------------------------------------------------------------- bad tables
BAD = [
    ({**DWELL, "swing_deg": None}, "missing key 'swing_deg'"),
    ({k: v for k, v in DWELL.items() if k != "dwell_deg"} | {"dwell": 80.0},
     r"unknown key 'dwell': the key says its unit, 'dwell_deg'"),
    ({**PATH, "targets_m": TARGETS[:2]}, r"targets_m must be at least 3 rows"),
    ({**MOTION, "pose_points_m": MOTION["pose_points_m"][:2]}, "pose_points_m must be at least 3"),
    ({**FUNCTION, "precision_points_deg": [[30.0, 80.0], [60.0, 90.0]]},
     "precision_points_deg must be at least 3 rows"),
    ({**FUNCTION, "bogus": 1}, "unknown key 'bogus'"),
    ({**FUNCTION, "points": 4}, "points places precision points"),
    ({**FUNCTION, "function_deg": SQUARE}, "give the relation ψ\\(φ\\) one way"),
    ({**FUNCTION, "precision_points_deg": [[0, 10], [90, 100], [180, 10]]},
     "no four-bar a machine can run"),
    ({**MOTION, "min_transmission_deg": 89.0}, "can run in a machine"),
    ({**DWELL, "swing_deg": 170.0, "min_transmission_deg": 80.0, "maxiter": 3},
     "no feasible six-bar"),
    ({**DWELL, "max_residual_deg": 0.02}, "above max_residual_deg"),
    ({**PATH, "max_error_m": 1e-9, "maxiter": 5, "polish": False}, "above max_error_m"),
    ({**PATH, "min_transmission_deg": 89.5, "maxiter": 5, "polish": False},
     "min_transmission_deg"),
    ({**PATH, "mechanism": "six_bar"}, "mechanism = 'six_bar' must be one of"),
    ({**DWELL, "seed": -1}, "seed"),
    ({**MOTION, "grid_points": 16}, "grid_points = 16"),
    ({**PATH, "bounds": {"crank_m": [0.2, 0.1]}}, r"bounds.crank_m = \[0.2, 0.1\] must be"),
    ({**PATH, "bounds": {"rod_m": [0.1, 0.2]}}, "bounds: unknown key 'rod_m'"),
    ({**PATH, "bounds": {"crank_m": [-0.2, -0.1]}}, r"bounds.crank_m = \(-0.2, -0.1\)"),
]  # fmt: skip


@pytest.mark.parametrize(("syn", "match"), BAD, ids=[m for _, m in BAD])
def test_bad_tables_are_refused_naming_the_key(syn: dict[str, Any], match: str) -> None:
    syn = {k: v for k, v in syn.items() if v is not None}
    with pytest.raises(cm.InputError, match=match) as e:
        machine(syn)
    assert "[mechanism.arm].synthesize" in str(e.value)


@pytest.mark.parametrize(
    ("syn", "match"),
    [
        ({**DWELL, "ground_m": 200.0, "maxiter": 2}, r"ground_m = 200.0 m is over 10 m"),
        ({**PATH, "targets_m": (1000 * np.array(TARGETS)).tolist(), "max_error_m": 1.0,
          "maxiter": 5, "polish": False}, r"targets_m holds 350 m, over 10 m — did you mean mil"),
        ({**MOTION, "pose_points_m": [[0, 0], [50, 20], [90, 60]], "max_length_ratio": 1e9,
          "min_transmission_deg": 0.0}, "pose_points_m holds 90 m"),
    ],
    ids=["number", "path array", "motion array"],
)  # fmt: skip
def test_millimetres_given_as_metres_warn(syn: dict[str, Any], match: str) -> None:
    # The slip may also make the requirement unreachable: warned of first.
    with pytest.warns(cm.CyclomechWarning, match=match), contextlib.suppress(cm.InputError):
        machine(syn)


def test_every_key_is_documented() -> None:
    from cyclomech import _keydocs

    tables = _keydocs.tables()
    for scheme, mod in [("function", _function_file), ("path", _path_file),
                        ("motion", _motion_file), ("dwell_sixbar", _dwell_file)]:  # fmt: skip
        assert {k.name for k in tables[f"linkage.synthesize.{scheme}"].keys} == set(mod.KEYS)
        assert scheme in cm.linkage.SYNTHESIZERS
    assert {k.name for k in tables["linkage.synthesize.path.bounds"].keys} == set(
        _path_file.BOUND_KEYS
    )


#: Values of the wrong type or range for any key (as the file fuzz's).
WRONG: list[Any] = [
    1, 1.5, -1.0, float("nan"), float("inf"), True, "x", "", [], [1], [["A", "D"]],
    {"a": 1}, [{"a": 1}], [1.0, "x"],
]  # fmt: skip
LIGHT = [
    FUNCTION,
    {**PATH, "maxiter": 3, "polish": False, "max_error_m": 1.0},
    {**MOTION, "grid_points": 3},
    {**DWELL, "popsize": 5, "maxiter": 2, "max_residual_deg": 10.0},
]


@pytest.mark.parametrize("syn", LIGHT, ids=[s["scheme"] for s in LIGHT])
def test_any_wrong_value_is_an_input_error(syn: dict[str, Any]) -> None:
    """Every key of each scheme's table replaced by each wrong value: the machine
    reads, or the error is a CyclomechError, never another exception."""
    d = tomllib.loads(EXAMPLE.read_text("utf-8"))
    others = []
    for key in syn:
        for bad in WRONG:
            if (key, bad) == ("polish", True):
                continue  # valid, and a polish after three generations takes ~30 s
            d["mechanism"]["arm"] = {"kind": "linkage", "synthesize": {**syn, key: bad}}
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    cm.Machine.from_dict(d, str(EXAMPLE))
            except cm.CyclomechError:
                pass
            except Exception as e:
                others.append(f"{key} = {bad!r}: {type(e).__name__}: {e}")
    assert not others, "\n".join(others[:10])
