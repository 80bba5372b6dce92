"""Change points (probe B2): a class II group whose two assemblies meet while the
crank turns on. The solve follows the smooth motion through them where it repeats
every turn, holds the drawn assembly where it cannot, and a machine warns or
refuses; checked against the mechanisms' closed forms."""

from __future__ import annotations

import math
import textwrap
import warnings
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest


def four_bar(r: float, b: float, c: float, d: float, phi0: float = math.pi / 2) -> cm.Linkage:
    """A(0,0)–B crank r, B–C coupler b, C–D rocker c, D(d, 0), drawn at crank angle
    phi0 with C above the line B→D (the parallelogram's side when r = c, b = d)."""
    bx, by = r * math.cos(phi0), r * math.sin(phi0)
    lx, ly = d - bx, -by
    ln = math.hypot(lx, ly)
    x = (b * b - c * c + ln * ln) / (2 * ln)
    h = math.sqrt(b * b - x * x)
    ex, ey = lx / ln, ly / ln
    pc = (bx + x * ex - h * ey, by + x * ey + h * ex)
    return cm.Linkage(
        {"A": (0, 0), "B": (bx, by), "C": pc, "D": (d, 0)},
        [("A", "B"), ("B", "C"), ("C", "D")],
        ["A", "D"],
        ("A", "B"),
    )


def test_a_parallelogram_moves_as_one_over_the_whole_turn():
    lk = four_bar(0.3, 1.0, 0.3, 1.0)
    found = lk.change_points
    assert [(j, f) for j, _, f in found] == [("C", True), ("C", True)]
    np.testing.assert_allclose([a for _, a, _ in found], [math.pi, 2 * math.pi], atol=1e-9)
    phi = np.linspace(0.0, 2 * math.pi, 3601)
    s = lk.solve(phi)
    b, c = s.xy[:, s.index("B")], s.xy[:, s.index("C")]
    # Its closed form: C = B + (1, 0) at every angle. Within the windows flagged
    # singular the closed form's h = √(round-off) costs digits: 2e-8 m at the change
    # points themselves (φ = 0 and 2π are on this grid).
    live = ~s.singular
    # Flagged where C's height over the diagonal B–D, 0.3 |sin φ| / |BD|, is under
    # 1e-3 of BC (to the window's slope estimate).
    h = 0.3 * np.abs(np.sin(phi)) / np.hypot(1.0 - b[:, 0], b[:, 1])
    assert s.ok.all() and s.singular[h < 0.99e-3].all() and (h[s.singular] < 1.01e-3).all()
    want = np.broadcast_to([1.0, 0.0], c.shape)
    np.testing.assert_allclose((c - b)[live], want[live], atol=1e-12)
    np.testing.assert_allclose(c - b, want, atol=1e-7)
    np.testing.assert_allclose(
        s.vel[live, s.index("C")], s.vel[live, s.index("B")], rtol=0, atol=1e-10
    )
    # The analogs next to a window lose digits: 3.6e-8 m/rad² (1.2e-7 of 0.3) at 0.2°
    # from the change point at 0 (h = 1.5e-3 of BC), 1e-9 at 0.5°.
    np.testing.assert_allclose(
        s.acc[live, s.index("C")], s.acc[live, s.index("B")], rtol=0, atol=5e-8
    )


def test_a_near_parallelogram_has_none():
    # A rocker 3e-4 longer: the assemblies pass 4 mm apart; the drawn one is smooth.
    lk = four_bar(0.3, 1.0, 0.3003, 1.0)
    assert lk.change_points == []
    phi = np.linspace(0.0, 2 * math.pi, 7201)
    s = lk.solve(phi)
    c = s.xy[:, s.index("C")]
    # Smooth: central differences of the positions match the velocity analogs.
    h = phi[1] - phi[0]
    fd = (c[2:] - c[:-2]) / (2 * h)
    v = s.vel[1:-1, s.index("C")]
    assert np.abs(fd - v).max() < 2e-3 * np.abs(v).max()


def test_one_change_point_a_turn_is_held_and_a_machine_refuses_it(tmp_path: Path):
    # 0.2 + 0.9 = 0.5 + 0.6: one change point a turn, at crank angle 0.
    lk = four_bar(0.2, 0.9, 0.5, 0.6, phi0=1.0)
    (joint, angle, followed), *rest = lk.change_points
    assert rest == [] and joint == "C" and not followed
    assert min(abs(angle - 2 * math.pi), abs(angle)) < 1e-9
    with pytest.raises(cm.InputError, match="odd number a crank turn"):
        cm.linkage.LinkageMechanism("lk", lk, "C")


def test_a_parallelogram_machine_warns_and_gets_the_parallelograms_limit(tmp_path: Path):
    path = tmp_path / "pg.toml"
    path.write_text(
        textwrap.dedent(
            """
            [machine]
            name = "parallelogram"
            speed_rpm = [20.0, 100.0]
            speed_points = 5
            nominal_rpm = 20.0
            unmodelled = ["x"]

            [cyclogram]
            name = "c"
            limiting = ["1", "2"]
            events = ["0", "1", "2"]

            [[operation]]
            from = "0"
            to = "1"
            min_angle_deg = 180.0
            name = "work"
            mechanism = "pg"

            [[operation]]
            from = "1"
            to = "2"
            min_angle_deg = 60.0
            name = "move"
            mechanism = "x"

            [mechanism.pg]
            kind = "linkage"
            links = [["A", "B"], ["B", "C"], ["D", "C"]]
            ground = ["A", "D"]
            driver = ["A", "B"]
            output = "C"
            max_acceleration_m_per_s2 = 8.0

            [mechanism.pg.points]
            A = [0.0, 0.0]
            D = [1.0, 0.0]
            B = [0.0, 0.3]
            C = [1.0, 0.3]
            """
        )
    )
    with pytest.warns(cm.CyclomechWarning, match="change points"):
        m = cm.Machine.from_toml(path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cm.CyclomechWarning)
        limit = m.mechanisms["pg"].speed_limit_rpm()
    # C moves as B: its acceleration analog is the crank's 0.3 m/rad², so ω² · 0.3 = 8.
    assert limit == pytest.approx(math.sqrt(8.0 / 0.3) * 60 / (2 * math.pi), rel=1e-9)


def test_a_sweep_of_geometries_follows_each_one():
    # The parallelogram among other rocker lengths: each row as its own solve.
    lk = four_bar(0.3, 1.0, 0.3, 1.0)
    lengths = lk.dimension_values * np.array([[1, 1, 1], [1, 1, 1.001], [1, 1, 0.999]])
    phi = np.linspace(0.1, 6.2, 50)
    many = cm.linkage.solve_geometries(lk, phi, lengths)
    one = lk.solve(phi)
    np.testing.assert_array_equal(many.xy[0], one.xy)
    b, c = many.xy[0][:, lk.names.index("B")], many.xy[0][:, lk.names.index("C")]
    np.testing.assert_allclose(c - b, np.broadcast_to([1.0, 0.0], c.shape), atol=1e-12)


def _linkage_file(lk: cm.Linkage, path: Path) -> Path:
    lk.to_toml(path)
    return path


def test_the_linkage_command_lists_them(tmp_path: Path, capsys: pytest.CaptureFixture[str]):
    # The parallelogram: both followed, on screen and in linkage.json, exit 0.
    import json

    from cyclomech.cli import main

    path = _linkage_file(four_bar(0.3, 1.0, 0.3, 1.0), tmp_path / "pg.toml")
    assert main(["linkage", str(path), "--out", str(tmp_path / "pg"), "--no-plot"]) == 0
    out, err = capsys.readouterr()
    assert (
        "Change points (a group's two assemblies meet): joint 'C' at 180.00°, joint 'C' at " in out
    )
    assert "followed smoothly" in out and "warning" not in err
    doc = json.loads((tmp_path / "pg" / "linkage.json").read_text(encoding="utf-8"))
    got = doc["change_points"]
    assert [(c["joint"], c["followed"]) for c in got] == [("C", True), ("C", True)]
    assert got[0]["angle_deg"] == pytest.approx(180.0, abs=1e-7)
    assert min(got[1]["angle_deg"], 360.0 - got[1]["angle_deg"]) < 1e-7
    # s + l = p + q: held, and a warning says the velocity jumps there.
    odd = _linkage_file(four_bar(0.2, 0.9, 0.5, 0.6, phi0=1.0), tmp_path / "odd.toml")
    assert main(["linkage", str(odd), "--out", str(tmp_path / "odd"), "--no-plot"]) == 0
    out, err = capsys.readouterr()
    assert "Change points (a group's two assemblies meet): joint 'C' at " in out
    assert "followed smoothly" not in out
    assert "joint 'C' passes an odd number of change points" in err and "jumps" in err
    doc = json.loads((tmp_path / "odd" / "linkage.json").read_text(encoding="utf-8"))
    assert [(c["joint"], c["followed"]) for c in doc["change_points"]] == [("C", False)]
    # A crank-rocker has none: no line, an empty list.
    crank = Path(__file__).resolve().parents[2] / "examples" / "crank_rocker.toml"
    assert main(["linkage", str(crank), "--out", str(tmp_path / "cr"), "--no-plot"]) == 0
    assert "Change points" not in capsys.readouterr().out
    doc = json.loads((tmp_path / "cr" / "linkage.json").read_text(encoding="utf-8"))
    assert doc["change_points"] == []
