"""Tests of the motion-law plots in cyclomech.plot: the artists carry the numbers
of cm.motion (lengths in mm, angles in degrees), and every bad argument is an
InputError that says what would be valid."""

from __future__ import annotations

import math

import pytest

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")

import cyclomech as cm  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from cyclomech.plot import plot_law  # noqa: E402
from numpy.testing import assert_allclose  # noqa: E402

MM = 1000.0


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def line(ax, gid):
    (ln,) = [ln for ln in ax.get_lines() if ln.get_gid() == gid]
    return ln


def lines(ax, gid):
    return [ln for ln in ax.get_lines() if ln.get_gid() == gid]


def texts(ax) -> dict[str, str]:
    return {t.get_gid(): t.get_text() for t in ax.texts if t.get_gid()}


def press(**kw) -> cm.press.GearLeverPress:
    par = {"R": 0.09, "r": 0.03, "d": 0.025, "L": 0.3, "phi0": 0.29, **kw}
    return cm.press.GearLeverPress(**par)


def two_period() -> cm.motion.TwoPeriodLaw:
    return cm.motion.two_period(0.2, np.pi, "cycloidal", "modified_sine", asymmetry=2.0)


# ---------------------------------------------------------------------- plot_law
@pytest.mark.parametrize("form", ["half", "rise"])
@pytest.mark.parametrize("name", ["modified_sine", "cycloidal", "modified_trapezoid"])
def test_law_stacked_curves_are_the_law(name, form):
    lw = cm.motion.law(name, form=form)
    axes = plot_law(lw, n=201)
    assert len(axes) == 3 and len({a.figure for a in axes}) == 1
    for ax, gid, f in zip(axes, ("Z", "Z'", "Z''"), (lw.z, lw.dz, lw.ddz), strict=True):
        ln = line(ax, gid)
        j = ln.get_xdata()
        assert j[0] == 0.0 and j[-1] == 1.0 and np.all(np.diff(j) > 0)
        assert set(lw.breaks) <= set(j.tolist())  # the pieces' ends are on the curve
        assert_allclose(ln.get_ydata(), f(j), rtol=0, atol=1e-15)
        assert ax.get_xlim() == (0.0, 1.0)
    assert axes[0].get_ylabel().startswith("Z ")
    assert "speed" in axes[1].get_ylabel() and "acceleration" in axes[2].get_ylabel()
    assert "j" in axes[2].get_xlabel()
    # The peaks: a dot on each curve and its value in the text.
    (x1,), (y1,) = line(axes[1], "Z'max").get_data()
    (x2,), (y2,) = line(axes[2], "Z''max").get_data()
    assert y1 == pytest.approx(lw.dz_max, abs=1e-4)
    assert abs(y2) == pytest.approx(lw.ddz_max, abs=1e-3)
    assert y1 == pytest.approx(lw.dz(x1)) and y2 == pytest.approx(lw.ddz(x2))
    assert texts(axes[1])["label:Z'max"] == f"Z'max = {lw.dz_max:.4g}"
    assert texts(axes[2])["label:Z''max"] == f"Z''max = {lw.ddz_max:.4g}"
    assert name.replace("_", " ") in axes[0].figure.get_suptitle()


def test_law_on_one_axes_has_three_curves_and_a_legend():
    fig, ax = plt.subplots()
    lw = cm.motion.law("cycloidal", form="rise")
    out = plot_law(lw, ax)
    assert out == (ax,) and plt.get_fignums() == [fig.number]
    assert [ln.get_gid() for ln in ax.get_lines()][:3] == ["Z", "Z'", "Z''"]
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["Z", "Z'", "Z''"]
    assert ax.get_ylabel() == "Z, Z', Z''  (dimensionless)"
    assert ax.get_title() == "Motion law: cycloidal (full rise)"


def test_law_on_three_given_axes():
    fig, axes = plt.subplots(1, 3)
    out = plot_law(cm.motion.law("harmonic"), list(axes), title="harmonic")
    assert out == tuple(axes) and plt.get_fignums() == [fig.number]
    assert axes[0].get_title() == "harmonic"


def test_two_period_law_in_mm_against_degrees():
    lw = two_period()
    axes = plot_law(lw, n=181)
    funcs = (lw.position, lw.velocity, lw.acceleration)
    for ax, gid, f in zip(axes, ("Π", "Π'", "Π''"), funcs, strict=True):
        ln = line(ax, gid)
        deg = ln.get_xdata()
        assert deg[0] == 0.0 and deg[-1] == pytest.approx(180.0)
        assert_allclose(ln.get_ydata(), f(np.radians(deg)) * MM, rtol=1e-12, atol=1e-12)
        assert ax.get_xlim() == pytest.approx((0.0, 180.0))
    assert [a.get_ylabel().split("[")[-1] for a in axes] == ["mm]", "mm/rad]", "mm/rad²]"]
    assert axes[2].get_xlabel() == "crank angle α from BDC"


def test_two_period_law_marks_alpha1_and_the_periods():
    lw = two_period()
    axes = plot_law(lw)
    a1 = math.degrees(lw.angle1)
    for k, ax in enumerate(axes):
        (v,) = lines(ax, "α1")
        assert_allclose(v.get_xdata(), [a1, a1])
        assert v.get_label() == ("α1 (speed peak)" if k == 0 else "_α1")
    legend = [t.get_text() for t in axes[0].get_legend().get_texts()]
    assert legend == ["α1 (speed peak)"]
    t = texts(axes[0])
    assert t["period I"].startswith("period I ") and "60°" in t["period I"]
    assert t["period II"].startswith("period II ") and "120°" in t["period II"]
    (x,), (y,) = line(axes[1], "Π'max").get_data()
    assert x == pytest.approx(a1) and y == pytest.approx(lw.max_speed * MM)
    # The two periods' acceleration peaks: their ratio is the law's accel_ratio.
    (_, (p1,)), (_, (p2,)) = (line(axes[2], g).get_data() for g in ("Π''1max", "Π''2max"))
    assert abs(p1) / abs(p2) == pytest.approx(lw.accel_ratio, rel=1e-3)


def test_two_period_law_on_one_axes():
    _, ax = plt.subplots()
    (out,) = plot_law(two_period(), ax)
    assert out is ax
    assert len(lines(ax, "α1")) == 1
    assert {"Π", "Π'", "Π''"} <= {ln.get_gid() for ln in ax.get_lines()}
    assert "[mm/rad²]" in ax.get_ylabel()


@pytest.mark.parametrize(
    ("args", "kw", "match"),
    [
        (("cycloidal",), {}, "law must be a cyclomech.motion.MotionLaw"),
        ((cm.motion.law("cycloidal"),), {"n": 2}, "n must be an integer ≥ 3"),
        ((cm.motion.law("cycloidal"),), {"n": 10.0}, "n must be an integer"),
        ((cm.motion.law("cycloidal"),), {"ax": "axes"}, "ax must be None"),
    ],
)
def test_law_bad_arguments(args, kw, match):
    with pytest.raises(cm.InputError, match=match):
        plot_law(*args, **kw)


def test_law_wrong_number_of_axes():
    _, axes = plt.subplots(1, 2)
    with pytest.raises(cm.InputError, match="a sequence of 3 Axes"):
        plot_law(cm.motion.law("cycloidal"), list(axes))
