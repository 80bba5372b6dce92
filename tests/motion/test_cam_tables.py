"""Electronic cam tables: the written files rebuild the program.

The coefficient file is read back with numpy and evaluated here (``np.polyval``
and ``np.sin`` per piece: another evaluation of the closed form); it must equal
:meth:`Program.evaluate` to rounding at angles between the table's points. The
table file must hold :meth:`Program.evaluate`'s values at its master angles, the
last row a cycle on (``advance`` added).
"""

from __future__ import annotations

import math

import cyclomech as cm
import numpy as np
import pytest
from numpy.testing import assert_allclose

S = cm.motion.Segment


def _program() -> cm.motion.Program:
    feed = 0.3
    v = 0.06
    return cm.motion.Program(
        [
            S("constant_velocity", 100, start=(0.0, v)),
            S("modified_sine", 80, end=(v * math.radians(100) + 0.12, 0.0)),
            S("dwell", 40),
            S("poly7", 140, end=(feed, v, 0.0, 0.0)),
        ],
        advance=feed,
    )


def test_the_coefficients_rebuild_the_program(tmp_path):
    prog = _program()
    path = cm.motion.write_cam_coefficients(prog, tmp_path / "c.csv")
    header = path.read_text().splitlines()[0].split(",")
    assert tuple(header) == cm.motion.COEFFICIENT_COLUMNS
    rows = np.loadtxt(path, delimiter=",", skiprows=1)
    assert sorted(set(rows[:, 0].astype(int))) == [0, 1, 2, 3]
    theta = np.random.default_rng(7).uniform(0.0, 2 * math.pi, 5000)
    rebuilt = np.empty_like(theta)
    starts = np.radians(rows[:, 1])
    for i, t in enumerate(theta):
        k = np.searchsorted(starts, t, side="right") - 1
        r = rows[k]
        u = t - math.radians(r[1])
        c = r[3:11]
        rebuilt[i] = np.polyval(c[::-1], u) + r[11] * math.sin(r[12] * u + r[13])
    assert_allclose(rebuilt, prog.evaluate(theta).s, rtol=1e-12, atol=1e-14)
    # Master angles in degrees cover the cycle without gaps.
    assert rows[0, 1] == 0.0 and rows[-1, 2] == pytest.approx(360.0, abs=1e-12)
    assert_allclose(rows[1:, 1], rows[:-1, 2], atol=1e-12)


@pytest.mark.parametrize(
    "law", ["cycloidal", "harmonic", "modified_sine", "modified_trapezoid",
            "polynomial_345", "polynomial_4567"],
)  # fmt: skip
def test_every_named_law_is_written_and_rebuilt(tmp_path, law):
    """Each rest-to-rest law's pieces fit c0 … c7 (polynomial_4567's and
    polynomial_345's come one coefficient longer, the last 0: the file used to fail
    to be written, a ValueError); the rebuilt rise against VDI 2143's closed forms
    (polynomials, and the cycloid h(z − sin 2πz/2π)), else Program.evaluate."""
    h = 0.02
    prog = cm.motion.Program(
        [S(law, 120, end=h), S("dwell", 60), S(law, 120, end=0.0), S("dwell", 60)]
    )
    rows = np.loadtxt(
        cm.motion.write_cam_coefficients(prog, tmp_path / "c.csv"), delimiter=",", skiprows=1
    )
    z = np.linspace(0.0, 1.0, 241)
    u = z * math.radians(120)
    first = rows[rows[:, 0] == 0]
    pieces = []
    for r in first:
        t = u[(u >= math.radians(r[1])) & (u < math.radians(r[2]))] - math.radians(r[1])
        pieces.append(np.polyval(r[3:11][::-1], t) + r[11] * np.sin(r[12] * t + r[13]))
    rebuilt = np.concatenate(pieces)
    closed = {
        "polynomial_345": h * (10 * z**3 - 15 * z**4 + 6 * z**5),
        "polynomial_4567": h * (35 * z**4 - 84 * z**5 + 70 * z**6 - 20 * z**7),
        "cycloidal": h * (z - np.sin(2 * math.pi * z) / (2 * math.pi)),
    }
    want = closed.get(law, prog.evaluate(u).s)[: len(rebuilt)]
    assert len(rebuilt) == len(z) - 1  # all but the end point (the next piece's)
    assert_allclose(rebuilt, want, rtol=0, atol=1e-15)


def test_the_table_holds_the_program(tmp_path):
    prog = _program()
    path = cm.motion.write_cam_table(prog, tmp_path / "t.csv", points=720)
    assert path.read_text().splitlines()[0] == ",".join(cm.motion.TABLE_COLUMNS)
    t = np.loadtxt(path, delimiter=",", skiprows=1)
    assert t.shape == (721, 5)
    m = prog.evaluate(np.radians(t[:, 0]))
    assert_allclose(t[:, 1:], np.column_stack([m.s, m.v, m.a, m.j]), rtol=0, atol=0)
    assert t[-1, 1] == pytest.approx(t[0, 1] + 0.3, abs=1e-15)


def test_bad_arguments(tmp_path):
    with pytest.raises(cm.InputError, match="points"):
        cm.motion.write_cam_table(_program(), tmp_path / "t.csv", points=1)
    with pytest.raises(TypeError, match="program must be a Program"):
        cm.motion.write_cam_table("cam", tmp_path / "t.csv")
