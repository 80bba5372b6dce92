"""Issue 16 (trust), the whole machine's items: each test is named after its item
and failed before the fix. References are independent of the code under test:
the linkage solved directly on the same grid, the press criteria and the rotor
path's peaks at the reported limit, sums of the file's own angles."""

from __future__ import annotations

import json
import math
import re
import tomllib
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.cli import EXIT_FAILS, main
from cyclomech.machine import analyze, write_report

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
RAD_PER_RPM = 2.0 * math.pi / 60.0

NO_FIT = """\
[machine]
name = "no fit"
speed_rpm = [100.0, 300.0]

[cyclogram]
name = "c"
limiting = ["b", "c"]
events = ["a", "b", "c"]

[[operation]]
from = "a"
to = "b"
min_angle_deg = 200.0
name = "one"

[[operation]]
from = "b"
to = "c"
min_angle_deg = 170.0
name = "two"
min_duration_s = 0.01
"""


def _knife(points: int, limit: float) -> cm.Machine:
    data = tomllib.loads((EXAMPLES / "knife_cutter.toml").read_text("utf-8"))
    data["machine"]["angle_points"] = points
    data["mechanism"]["knife"]["max_acceleration_m_per_s2"] = limit
    return cm.Machine.from_dict(data, "knife.toml")


def test_item5_one_speed_limit_for_one_knife(tmp_path):
    """results.json of the knife cutter with angle_points = 13 and a 5 m/s² limit
    carried 60.736 rpm in one place and 60.960 in another (the report recomputed
    the limit on 361 angles). Now every place holds the one value, and it is the
    one the machine's own 13-angle grid gives, computed here from the linkage
    solved directly."""
    m = _knife(13, 5.0)
    r = analyze(m, progress=False)
    write_report(r, tmp_path, figures=False)
    out = json.loads((tmp_path / "results.json").read_text("utf-8"))
    a = out["speed_limit"]["mechanisms_rpm"]["knife"]
    b = out["mechanisms"]["knife"]["speed_limit_rpm"]
    assert a == b
    # Independent: the same 13 crank angles, the output point's |acc| by hand.
    lk = m.mechanisms["knife"].linkage
    phi = lk.drawn_angle + np.linspace(0.0, 2.0 * math.pi, 13)
    sol = lk.solve(phi)
    acc = np.hypot(*sol.acc[:, sol.index("E")].T)
    expect = math.sqrt(5.0 / acc.max()) / RAD_PER_RPM
    assert a == pytest.approx(expect, rel=1e-12)
    # The 361-angle value is a different (finer) number: the grid is the machine's.
    fine = m.mechanisms["knife"].speed_limit_rpm(361)
    assert abs(fine - a) > 1e-3 * a


def test_item8_a_cyclogram_that_fits_at_no_speed_is_loud(tmp_path, capsys):
    """The minimum angles 200° + 170° = 370° exceed the cycle at any speed: the
    run used to print "Speed limit: 0.00 rpm", blame "at 100 rpm" and exit 0. Now
    it says the machine works at no speed, names the chain and its sum (the sum of
    the file's own angles), writes the report and exits with EXIT_FAILS."""
    path = tmp_path / "nofit.toml"
    path.write_text(NO_FIT, encoding="utf-8")
    lim = cm.Machine.from_toml(path).speed_limit()
    assert lim.rpm == 0.0 and lim.by == "cyclogram"
    assert "at any speed" in lim.reason and "one 200° + two 170° = 370° > 360°" in lim.reason
    argv = ["run", str(path), "--out", str(tmp_path / "out"), "--no-plot", "--quiet"]
    code = main([*argv, "--no-sensitivities"])
    io = capsys.readouterr()
    assert code == EXIT_FAILS != 0
    assert "works at no speed" in io.out and "370° > 360°" in io.out
    assert "Speed limit: 0.00 rpm" not in io.out and "at 100 rpm" not in io.out
    assert "works at no speed" in io.err
    assert (tmp_path / "out" / "report.html").is_file()
    html = (tmp_path / "out" / "report.html").read_text("utf-8")
    assert "works at no speed" in html and "At 100 rpm" not in html
    res = json.loads((tmp_path / "out" / "results.json").read_text("utf-8"))
    assert res["speed_limit"]["rpm"] == 0.0 and "370°" in res["speed_limit"]["reason"]
    assert res["fails"] == [f"the machine works at no speed: {lim.reason}"]


@pytest.mark.parametrize(
    ("example", "mech", "words"),
    [
        ("extrusion_press_line.toml", "drive", ("V_np", "max_V_np = 5 mm/s")),
        ("rotor_line.toml", "line", ("jerk", "max_jerk = 10 m/s³")),
    ],
)
def test_item12_a_mechanisms_speed_limit_says_why(example, mech, words, cli_run):
    """ "set by mechanism 'drive'" did not say why. The limit now names the
    criterion and its limit, and the criterion at that speed equals the limit
    (evaluated independently of the limit's formula: the press's criteria, the
    rotor path's peaks)."""
    m = cm.Machine.from_toml(EXAMPLES / example)
    lim = m.speed_limit()
    assert lim.by == mech
    assert all(w in lim.reason for w in words)
    assert lim.mechanisms_reason[mech] == lim.reason
    x = m.mechanisms[mech]
    if mech == "drive":
        assert x.criteria(lim.rpm).V_np == pytest.approx(x.max_V_np, rel=1e-9)
    else:
        _, jerk = x.peaks(lim.rpm)
        assert jerk == pytest.approx(x.max_jerk, rel=1e-9)
    run = cli_run(EXAMPLES / example, "--no-plot", "--quiet")
    assert run.code == 0
    assert f"set by mechanism {mech!r}: {lim.reason}" in run.stdout


def test_item12_cyclogram_limit_names_its_chain():
    """A limit set by the cyclogram names the bounds on its chain, and binding is a
    tuple like Cyclogram.max_speed_rpm()'s (it was a "; "-joined string)."""
    lim = cm.Machine.example().speed_limit()
    assert lim.by == "cyclogram"
    assert isinstance(lim.binding, tuple) and "rebound[lifter]" in lim.binding
    assert "rebound[lifter]" in lim.reason


def test_item6_a_sweep_goes_on_past_invalid_designs(tmp_path, capsys):
    """`cyclomech sweep … --set drive.L_m=0.3:0.5:5` aborted at L = 0.35 (invalid) and
    did not say which design. Now it records the invalid designs as not fitting,
    with the reason in a 'problem' column, goes on, and counts them. Reference:
    each L read on its own as a machine file (valid or refused)."""
    press = EXAMPLES / "extrusion_press_line.toml"
    Ls = np.linspace(0.2, 0.3, 5)  # the example's press since issue 16 item 1 (L 0.25)
    valid = []
    for L in Ls:
        try:
            cm.Machine.from_toml(press).with_values({"drive.L_m": float(L)})
            valid.append(True)
        except cm.InputError:
            valid.append(False)
    assert not all(valid) and any(valid)  # the case the issue names has both kinds
    r = cm.sweep(
        cm.Machine.from_toml(press), {"drive.L_m": Ls, "speed_rpm": [30.0, 40.0]}, progress=False
    )
    problem = r.columns["problem"].reshape(5, 2)
    assert ((problem == "").all(axis=1) == np.array(valid)).all()
    assert all(
        "drive.L_m = " in p and "[mechanism.drive]" in p for p in problem[~np.array(valid), 0]
    )
    fits = r.columns["fits"].reshape(5, 2)
    assert not fits[~np.array(valid)].any()
    assert np.isnan(r.columns["limiting_deg"].reshape(5, 2)[~np.array(valid)]).all()
    assert r.n_invalid == 2 * (5 - sum(valid))
    # A valid design's rows are what the design alone gives.
    k = int(np.flatnonzero(valid)[0])
    alone = cm.Machine.from_toml(press).with_values({"drive.L_m": float(Ls[k])})
    s = alone.speed_sweep([30.0, 40.0])
    assert np.array_equal(r.columns["limiting_deg"].reshape(5, 2)[k], s.limiting_deg)
    # The command: exit 0, a summary line counting them, the file has the column.
    code = main(["sweep", str(press), "--set", "drive.L_m=0.2:0.3:5", "--out", str(tmp_path)])
    out = capsys.readouterr().out
    assert code == 0
    assert f"{5 - sum(valid)} designs of 5 are invalid" in out
    back = cm.SweepResult.read(tmp_path / "sweep.parquet")
    assert back.n_invalid == (5 - sum(valid)) * 81
    # Every design invalid: the files are written, and the exit status says so.
    code = main(["sweep", str(press), "--set", "drive.L_m=0.3:0.4:2", "--out", str(tmp_path)])
    assert code == EXIT_FAILS


def test_item6_a_key_the_file_cannot_take_still_fails_first(tmp_path):
    press = EXAMPLES / "extrusion_press_line.toml"
    with pytest.raises(cm.InputError, match=r"'drive\.LL'.*has no key 'LL'.*L_m, R_m, d_m"):
        cm.sweep(cm.Machine.from_toml(press), {"drive.LL": [0.4]}, progress=False)


@pytest.mark.parametrize("suffix", [".parquet", ".npz"])
def test_item17_an_interrupted_write_leaves_no_result_file(tmp_path, monkeypatch, suffix):
    """Ctrl-C while a sweep file was written left a file that looked like a result
    (a 0-row Parquet, a 0-byte or truncated npz). The file is written under a
    temporary name and renamed when complete: interrupted, nothing is left."""
    import pyarrow.parquet as pq

    r = cm.sweep(cm.Machine.example(), {"speed_rpm": [300.0, 400.0]}, progress=False)
    target = tmp_path / f"sweep{suffix}"

    def interrupted(*args, **kwargs):
        where = args[1] if suffix == ".parquet" else args[0]
        Path(where).write_bytes(b"PAR1 half")  # what a cut-off write leaves
        raise KeyboardInterrupt

    monkeypatch.setattr(pq, "write_table", interrupted)
    monkeypatch.setattr(np, "savez_compressed", interrupted)
    with pytest.raises(KeyboardInterrupt):
        r.write(target)
    assert list(tmp_path.iterdir()) == []
    monkeypatch.undo()
    # Complete, it is there and reads back.
    assert cm.SweepResult.read(r.write(target)).n_points == 2


@pytest.mark.parametrize(
    ("content", "name"),
    [
        (b"", "empty.parquet"),
        (b"PAR1 not parquet", "junk.parquet"),
        (b"", "empty.npz"),
        (b"PK\x03\x04 truncated", "junk.npz"),
    ],
)
def test_item19_a_bad_sweep_file_is_named(tmp_path, content, name):
    """SweepResult.read raised raw pyarrow errors, KeyError or EOFError."""
    path = tmp_path / name
    path.write_bytes(content)
    with pytest.raises(cm.InputError, match=rf"{name}.*sweep file"):
        cm.SweepResult.read(path)


def test_item19_a_sweep_file_without_its_columns_is_named(tmp_path):
    path = tmp_path / "other.npz"
    np.savez(path, speed_rpm=np.arange(3.0))
    with pytest.raises(cm.InputError, match=r"other\.npz.*missing the column.*fits"):
        cm.SweepResult.read(path)


def _chain_machine(n: int, order: np.ndarray) -> cm.Machine:
    ops = [
        {"from": str(i), "to": str(i + 1), "min_angle_deg": 100.0 / n, "name": f"op{i}"}
        for i in order
    ]
    ops.append(
        {"from": str(n), "to": "end", "min_angle_deg": 10.0, "min_duration_s": 0.05, "name": "L"}
    )
    return cm.Machine.from_dict(
        {
            "machine": {"name": "chain", "speed_rpm": [100.0, 200.0]},
            "cyclogram": {"name": "c", "limiting": "L"},
            "operation": ops,
        }
    )


def test_item20_speed_limit_of_many_operations_is_right_in_any_order():
    """4000 operations took 108 s (one Bellman–Ford pass per operation); the Rust
    test item20_… counts the passes. Here: the limit of a 3000-operation chain,
    given in order and shuffled, is the closed form 100° + 6·n·0.05 s = 360° →
    n = 866.67 rpm, to max_difference's documented tolerance."""
    n = 3000
    exact = 260.0 / (6.0 * 0.05)
    ordered = _chain_machine(n, np.arange(n)).speed_limit()
    shuffled = _chain_machine(n, np.random.default_rng(3).permutation(n)).speed_limit()
    assert ordered.rpm == pytest.approx(exact, rel=1e-7)
    assert shuffled.rpm == pytest.approx(exact, rel=1e-7)
    assert set(ordered.binding) == set(shuffled.binding)


@pytest.mark.parametrize("rtol", [math.nan, 0.0, -1.0, 1e-300, 1.0, math.inf, "1e-6", True])
def test_item16_speed_search_tolerance_is_validated(rtol):
    """rtol = nan, 0, negative or 1e-300 looped forever; ≥ 1 or inf returned the
    1e-6 rpm search floor instead of 421.37."""
    with pytest.raises(cm.InputError, match=r"rtol = .* must be a relative tolerance"):
        cm.Machine.example().cyclogram_speed_limit(rtol=rtol)


def test_item16_speed_search_tolerance_bounds_are_usable():
    m = cm.Machine.example()
    exact = m.cyclogram_speed_limit(rtol=1e-14)
    for rtol in (1e-14, 1e-6, 0.5):
        got = m.cyclogram_speed_limit(rtol=rtol)
        # The search returns a speed that fits, within rtol below the limit.
        assert exact * (1 - rtol) - 1e-9 <= got <= exact
        assert m.fits([got])[0]


@pytest.mark.parametrize(
    ("call", "words"),
    [
        (lambda m: m.bound_angles(np.array([300.0, np.nan])), "rpm"),
        (lambda m: m.mechanisms["lifter"].linear_min_phase_deg(300.0, points=0), "points must"),
        (lambda m: m.mechanisms["lifter"].linear_min_phase_deg(300.0, points=2.5), "points"),
        (
            lambda m: cm.Machine("x", m.cyclogram, {}, speed_range_rpm=(500.0, 200.0)),
            "speed_range_rpm",
        ),
        (
            lambda m: cm.Machine("x", m.cyclogram, {}, speed_range_rpm=(2, 5), nominal_rpm=np.nan),
            "nominal_rpm",
        ),
        (
            lambda m: cm.Machine("x", m.cyclogram, {}, speed_range_rpm=(2, 5), angle_points=-1),
            "angle_points must be an integer between 9",
        ),
        (
            lambda m: cm.Machine("x", m.cyclogram, {}, speed_range_rpm=(2, 5), speed_points=True),
            "speed_points must be an integer",
        ),
        (
            lambda m: (
                cm.Machine.from_toml(EXAMPLES / "rotor_line.toml")
                .mechanisms["line"]
                .speeds(math.nan)
            ),
            "rpm",
        ),
    ],
)
def test_item18_machine_arguments_are_checked(call, words):
    """These returned NaN, garbage or a machine that fails later."""
    with pytest.raises(cm.InputError, match=re.escape(words)):
        call(cm.Machine.example())


def test_item19_numpy_integers_are_counts():
    m = cm.Machine.example()
    a = m.mechanisms["lifter"].linear_min_phase_deg(300.0, points=np.int64(64))
    assert a == m.mechanisms["lifter"].linear_min_phase_deg(300.0, points=64)
    cm.Machine("x", m.cyclogram, {}, speed_range_rpm=(2, 5), angle_points=np.int32(19))


@pytest.mark.parametrize(
    "reader", [cm.Machine.from_toml, cm.Cyclogram.from_toml, cm.Linkage.from_toml]
)
@pytest.mark.parametrize("depth", [200, 100_000])
def test_item19_a_deeply_nested_file_is_named(tmp_path, reader, depth):
    """A deeply nested TOML file gave a RecursionError traceback from every
    from_toml (100 000 levels in the parser; 200 parse, then recursed later)."""
    path = tmp_path / "deep.toml"
    path.write_text("a = " + "[" * depth + "]" * depth + "\n", encoding="utf-8")
    with pytest.raises(cm.InputError, match=r"deep\.toml: .*nested more than 64 levels"):
        reader(path)


def test_item19_a_deeply_nested_file_from_the_command_line(tmp_path, capsys):
    path = tmp_path / "deep.toml"
    path.write_text("a = " + "[" * 100_000 + "]" * 100_000 + "\n", encoding="utf-8")
    assert main(["press", str(path), "--out", str(tmp_path / "o")]) == 2
    assert "nested more than 64 levels" in capsys.readouterr().err


def test_small_a_mechanism_name_one_letter_off_is_an_error():
    """`mechanism = "liftr"` on an operation silently made a Gantt row of its own;
    it then warned (issue 16); now it is an error naming both names (issue 31).
    Mechanisms the file does not model are listed in [machine] unmodelled (the
    knife cutter's "clamp", "back gauge")."""
    data = tomllib.loads((EXAMPLES / "stb_loom.toml").read_text("utf-8"))
    data["operation"][0]["mechanism"] = "liftr"
    with pytest.raises(cm.InputError, match=r"'liftr' is not a mechanism.*Did you mean 'lifter'"):
        cm.Machine.from_dict(data, "loom.toml")
    m = cm.Machine.from_toml(EXAMPLES / "knife_cutter.toml")  # warnings are errors here
    assert {"clamp", "back gauge"} <= {op.mechanism for op in m.cyclogram.operations}


@pytest.mark.parametrize("command", ["cyclogram", "linkage", "press", "impact", "cam", "transfer"])
def test_small_a_machine_file_given_to_another_command_points_to_run(command, tmp_path, capsys):
    loom = str(EXAMPLES / "stb_loom.toml")
    assert main([command, loom, "--out", str(tmp_path), "--no-plot"]) == 2
    assert f"run it with `cyclomech run {loom}`" in capsys.readouterr().err


#: Each domain's example file and the command that reads it.
DOMAIN_FILES = {
    "stb_group1.toml": ("a cyclogram file", "cyclogram"),
    "crank_rocker.toml": ("a linkage file", "linkage"),
    "extrusion_press.toml": ("a press file", "press"),
    "stb_lifter.toml": ("an impact file", "impact"),
    "lifter_cam.toml": ("a cam file", "cam"),
    "polydyne_cam.toml": ("a cam file", "cam"),
    "rotor_transfer.toml": ("a rotor transfer file", "transfer"),
}


@pytest.mark.parametrize("run", ["run", "sweep"])
@pytest.mark.parametrize("name", sorted(DOMAIN_FILES))
def test_small_each_domains_file_given_to_run_names_its_command(name, run, tmp_path, capsys):
    """`cyclomech run examples/lifter_cam.toml` said "unknown key 'cam'"; every
    other command's file now says what it looks like and which command runs it."""
    f = str(EXAMPLES / name)
    what, command = DOMAIN_FILES[name]
    assert main([run, f, "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert f"this looks like {what}" in err, err
    assert f"run it with `cyclomech {command} {f}`" in err
    assert "unknown key" not in err


def test_small_every_example_is_a_machine_file_or_named_by_its_command():
    others = {p.name for p in EXAMPLES.glob("*.toml") if "[machine]" not in p.read_text("utf-8")}
    assert others == set(DOMAIN_FILES) | {"burg_trimmer.toml", "flying_knife_cam.toml"}


def test_item6_one_invalid_value_is_a_problem_row_not_an_error():
    """A preload above the lifter's stroke used to abort cm.sweep; it is the
    design's problem now, named in its rows, and the sweep returns."""
    r = cm.sweep(cm.Machine.example(), {"lifter.preload_m": [0.02, 2e-4]}, progress=False)
    rows = r.columns["problem"].reshape(2, -1)
    assert all("lifter.preload_m = 0.02" in p and "smaller than stroke" in p for p in rows[0])
    assert (rows[1] == "").all()
    assert not r.columns["fits"].reshape(2, -1)[0].any()
