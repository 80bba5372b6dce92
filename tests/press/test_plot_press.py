"""Tests of the press plots in cyclomech.plot: the artists carry the numbers of
cm.press (lengths in mm, angles in degrees), and every bad argument is an
InputError that says what would be valid."""

from __future__ import annotations

import math

import pytest

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")

import cyclomech as cm  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from cyclomech.plot import plot_press, plot_press_criteria  # noqa: E402
from numpy.testing import assert_allclose, assert_array_equal  # noqa: E402

MM = 1000.0


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def line(ax, gid):
    (ln,) = [ln for ln in ax.get_lines() if ln.get_gid() == gid]
    return ln


def artist(ax, gid):
    (a,) = [a for a in [*ax.collections, *ax.patches] if a.get_gid() == gid]
    return a


def texts(ax) -> dict[str, str]:
    return {t.get_gid(): t.get_text() for t in ax.texts if t.get_gid()}


def press(**kw) -> cm.press.GearLeverPress:
    par = {"R": 0.09, "r": 0.03, "d": 0.025, "L": 0.3, "phi0": 0.29, **kw}
    return cm.press.GearLeverPress(**par)


def two_period() -> cm.motion.TwoPeriodLaw:
    return cm.motion.two_period(0.2, np.pi, "cycloidal", "modified_sine", asymmetry=2.0)


@pytest.fixture(scope="module")
def grid() -> cm.press.PressGrid:
    """Small sweep with failures: short rods cannot reach the guide at large d."""
    return cm.press.design_grid(
        R=0.09,
        r=0.03,
        d=np.linspace(0.0, 0.04, 9),
        L=np.array([0.07, 0.1, 0.2, 0.3, 0.4]),
        phi0=np.radians([0.0, 20.0, 40.0, 55.0]),
        k_Sp=0.1,
        omega=4.0,
    )


@pytest.fixture(scope="module")
def optimum() -> cm.press.PressOptimum:
    return cm.press.optimize(
        R=0.09,
        r=0.03,
        d=np.linspace(0.0, 0.04, 9),
        L=[0.3, 0.4, 0.5],
        phi0=np.radians(np.arange(0.0, 120.0, 10.0)),
        k_Sp=0.1,
        omega=4.0,
        refine=1,
    )


# -------------------------------------------------------------------- plot_press
def test_press_pin_path_is_the_hypotrochoid_of_solve():
    p = press()
    ax = plot_press(p, math.radians(60.0), n=360)
    path = line(ax, "pin path")
    kin = p.solve(np.linspace(0.0, 2 * np.pi, 361))
    assert_allclose(path.get_xydata(), kin.pin * MM, rtol=0, atol=1e-9)
    assert_allclose(path.get_xydata()[0], path.get_xydata()[-1], atol=1e-9)  # one closed turn


@pytest.mark.parametrize("alpha_deg", [0.0, 60.0, 200.0, -30.0])
def test_press_pose_is_the_solution_at_alpha(alpha_deg):
    p = press(offset=0.01)
    a = math.radians(alpha_deg)
    ax = plot_press(p, a)
    k = p.solve([a])
    o, c, pin, b = np.zeros(2), k.centre[0] * MM, k.pin[0] * MM, k.slider[0] * MM
    assert_allclose(line(ax, "carrier").get_xydata(), [o, c], atol=1e-9)
    assert_allclose(line(ax, "arm").get_xydata(), [c, pin], atol=1e-9)
    assert_allclose(line(ax, "rod").get_xydata(), [pin, b], atol=1e-9)
    assert_allclose(artist(ax, "joints").get_offsets(), [o, c, pin, b], atol=1e-9)
    # Invariants of the drawing: |OC| = R − r, |CP| = d, |PB| = L, B on the guide.
    assert np.hypot(*c) == pytest.approx((p.R - p.r) * MM)
    assert np.hypot(*(pin - c)) == pytest.approx(p.d * MM)
    assert np.hypot(*(b - pin)) == pytest.approx(p.L * MM)
    assert b[0] == pytest.approx(p.offset * MM)
    planet = artist(ax, "planet pitch circle")
    assert_allclose(planet.center, c) and planet.radius == pytest.approx(p.r * MM)
    guide = artist(ax, "guide pitch circle")
    assert_allclose(guide.center, o) and guide.radius == pytest.approx(p.R * MM)
    # The slider's rails run along x = offset, either side of the block.
    rails = artist(ax, "guides").get_segments()
    assert len(rails) == 2 and all(np.ptp(r[:, 0]) == 0.0 for r in rails)
    assert np.mean([r[0, 0] for r in rails]) == pytest.approx(p.offset * MM)
    assert ax.get_aspect() == 1.0
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("x [mm]", "y [mm]")
    assert ax.get_title().startswith(f"Gear-lever press at α = {alpha_deg:g}° from BDC")
    assert {"label:O", "label:C", "label:P", "label:slider", "label:ω"} <= set(texts(ax))


def test_press_working_stroke_on_the_mechanism():
    p = press(phi0=0.94)
    ax = plot_press(p, 1.0, k_Sp=0.1)
    crit = p.criteria(k_Sp=0.1, omega=4.0)
    work = line(ax, "pin path, working stroke").get_xydata()
    kin = p.solve(np.array([0.0, crit.alpha_p]))
    assert_allclose(work[[0, -1]], kin.pin * MM, atol=1e-9)
    ys = line(ax, "working stroke").get_ydata()  # beside the guide: S_p long
    assert float(np.ptp(ys)) == pytest.approx(crit.S_p * MM, rel=1e-3)


def test_press_with_motion():
    p = press()
    mech, motion = plot_press(p, math.radians(60.0), show_motion=True, k_Sp=0.1, n=360)
    assert mech.figure is motion.figure and len(plt.get_fignums()) == 1
    kin = p.solve(np.linspace(0.0, 2 * np.pi, 361))
    for gid, v in (("S", kin.s), ("Π'", kin.ds), ("Π''", kin.dds)):
        ln = line(motion, gid)
        assert_allclose(ln.get_xdata(), np.linspace(0.0, 360.0, 361))
        assert_allclose(ln.get_ydata(), v * MM, rtol=0, atol=1e-9)
    assert_allclose(line(motion, "α").get_xdata(), [60.0, 60.0])
    (span,) = [pt for pt in motion.patches if pt.get_gid() == "working stroke"]
    x0, x1 = span.get_x(), span.get_x() + span.get_width()
    assert (x0, x1) == pytest.approx((0.0, math.degrees(p.criteria(k_Sp=0.1, omega=1).alpha_p)))
    assert motion.get_xlim() == (0.0, 360.0)
    assert "[mm/rad]" in motion.get_ylabel() and "α" in motion.get_xlabel()
    legend = [t.get_text() for t in motion.get_legend().get_texts()]
    assert any(t.startswith("working stroke, k_Sp = 0.1") for t in legend)


def test_press_not_assembled_everywhere():
    """The rod reaches the guide only near BDC: drawn there, the rest shaded grey."""
    p = press(d=0.02, L=0.1, phi0=0.0, offset=0.12)
    mech, motion = plot_press(p, 0.1, show_motion=True, k_Sp=0.1)
    assert "no working stroke" in mech.get_title()
    assert not [ln for ln in mech.get_lines() if ln.get_gid() == "pin path, working stroke"]
    grey = [pt for pt in motion.patches if pt.get_gid() == "not assembled"]
    assert len(grey) == 1
    with pytest.raises(cm.InputError, match="cannot reach the slider's guide"):
        plot_press(p, math.pi)


def test_press_on_given_axes():
    fig, ax = plt.subplots()
    assert plot_press(press(), 0.5, ax) is ax
    fig2, axes = plt.subplots(1, 2)
    out = plot_press(press(), 0.5, list(axes), show_motion=True)
    assert out == tuple(axes)
    assert plt.get_fignums() == [fig.number, fig2.number]


@pytest.mark.parametrize(
    ("args", "kw", "match"),
    [
        ((object(), 0.0), {}, "press must be a cyclomech.press.GearLeverPress"),
        ((press(), math.nan), {}, "alpha = nan must be a finite"),
        ((press(), "x"), {}, "alpha must be a crank angle"),
        ((press(), 0.0), {"n": 4}, "n must be an integer ≥ 8"),
        ((press(), 0.0), {"k_Sp": 1.5}, "k_Sp"),
    ],
)
def test_press_bad_arguments(args, kw, match):
    with pytest.raises(cm.InputError, match=match):
        plot_press(*args, **kw)


def test_press_motion_needs_two_axes():
    _, ax = plt.subplots()
    with pytest.raises(cm.InputError, match=r"show_motion=True: ax must be None .* 2 Axes"):
        plot_press(press(), 0.0, ax, show_motion=True)


# ----------------------------------------------------------- plot_press_criteria
def test_criteria_map_is_the_slice_with_failures_masked(grid):
    k = 2  # φ0 = 40°
    ax = plot_press_criteria(grid, phi0=math.radians(41.0))
    mesh = artist(ax, "criterion")
    data = mesh.get_array()
    ok = grid.ok[:, :, k].T  # rows L, columns d
    assert data.shape == (5, 9)
    assert not ok.all() and ok.any()
    assert_array_equal(np.ma.getmaskarray(data), ~ok)
    assert_allclose(data.compressed(), grid["k_Vp"][:, :, k].T[ok])
    failed = artist(ax, "failed")
    assert len(failed.get_paths()) == int((~ok).sum()) and failed.get_hatch() == "xxx"
    # Cells centred on the grid values [mm].
    centres = np.array([p.vertices[:4].mean(axis=0) for p in failed.get_paths()])
    rows, cols = np.nonzero(~ok)
    assert_allclose(centres, np.column_stack([grid.axes["d"][cols], grid.axes["L"][rows]]) * MM)
    assert "φ0 = 40°" in ax.get_title()
    assert ax.get_xlabel().startswith("eccentricity d [mm]")
    assert ax.get_ylabel() == "rod length L [mm]"
    (cbar,) = [a for a in ax.figure.axes if a is not ax]
    assert cbar.get_ylabel().startswith("k_Vp = V_np/V_cp")
    # The best design of the map, starred.
    (x,), (y,) = line(ax, "best in map").get_data()
    shown = np.where(ok, grid["k_Vp"][:, :, k].T, np.inf)
    i, j = np.unravel_index(np.argmin(shown), shown.shape)
    assert (x, y) == pytest.approx((grid.axes["d"][j] * MM, grid.axes["L"][i] * MM))


def test_criteria_map_default_phi0_is_the_best_design(grid):
    ax = plot_press_criteria(grid, criterion="k_J")
    kj = np.where(grid.ok, grid["k_J"], np.inf)
    k = np.unravel_index(np.argmin(kj), kj.shape)[2]
    assert f"φ0 = {math.degrees(grid.axes['phi0'][k]):g}°" in ax.get_title()
    assert ax.get_title().startswith("k_J over (d, L)")


def test_criteria_map_in_display_units(grid):
    ax = plot_press_criteria(grid, criterion="V_np", phi0=0.0)
    data = artist(ax, "criterion").get_array()
    assert_allclose(data.compressed(), grid["V_np"][:, :, 0].T[grid.ok[:, :, 0].T] * MM)
    (cbar,) = [a for a in ax.figure.axes if a is not ax]
    assert cbar.get_ylabel().endswith("[mm/s]")


def test_criteria_map_with_fixed_phi0():
    sw = cm.press.design_grid(
        R=0.09, r=0.03, d=[0.0, 0.02, 0.04], L=[0.3, 0.4], phi0=0.5, k_Sp=0.1, omega=4.0
    )
    ax = plot_press_criteria(sw)
    assert artist(ax, "criterion").get_array().shape == (2, 3)
    assert "φ0 = 28.6°" in ax.get_title()
    assert len(artist(ax, "failed").get_paths()) == 0
    with pytest.raises(cm.InputError, match="holds φ0 fixed"):
        plot_press_criteria(sw, phi0=0.1)


def test_criteria_with_optimum_draws_the_pareto_set(grid, optimum):
    m, p = plot_press_criteria(optimum.grid, optimum=optimum)
    assert m.figure is p.figure
    best = optimum.designs[optimum.best]
    phi = optimum.grid.axes["phi0"]
    k = int(np.argmin(np.abs(phi - best.phi0)))
    assert f"φ0 = {math.degrees(phi[k]):g}°" in m.get_title()
    assert_allclose(line(m, "optimum").get_xydata(), [[best.d * MM, best.L * MM]])
    pareto = artist(p, "pareto")
    crit = optimum.criteria
    assert_allclose(pareto.get_offsets(), [[c.k_Vp, c.k_Vmax] for c in crit])
    assert_allclose(pareto.get_array(), [c.k_J for c in crit])
    b = optimum.baseline
    assert_allclose(line(p, "baseline").get_xydata(), [[b.k_Vp, b.k_Vmax]])
    c = crit[optimum.best]
    assert_allclose(line(p, "best").get_xydata(), [[c.k_Vp, c.k_Vmax]])
    assert_allclose(line(p, "ideal").get_xydata(), [[0.0, 1.0]])
    assert p.get_xlabel().startswith("k_Vp") and p.get_ylabel().startswith("k_Vmax")
    legend = [t.get_text() for t in p.get_legend().get_texts()]
    assert any(t.startswith("crank-slider, d = 0") for t in legend)
    assert any(t.startswith("best design: d = ") for t in legend)
    assert len(m.figure.axes) == 4  # two plots, two colour bars


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        ({"criterion": "k_X"}, "criterion = 'k_X' is not known"),
        ({"optimum": "best"}, "optimum must be a cyclomech.press.PressOptimum"),
        ({"phi0": "x"}, "phi0 must be an angle"),
    ],
)
def test_criteria_bad_arguments(grid, kw, match):
    with pytest.raises(cm.InputError, match=match):
        plot_press_criteria(grid, **kw)


def test_criteria_bad_sweeps(grid, optimum):
    with pytest.raises(cm.InputError, match=r"sweep must be a cyclomech\.press\.PressGrid"):
        plot_press_criteria(optimum)
    one_l = cm.press.design_grid(
        R=0.09, r=0.03, d=[0.0, 0.02], L=0.3, phi0=[0.0, 0.5], k_Sp=0.1, omega=4.0
    )
    with pytest.raises(cm.InputError, match="must vary L over two or more values"):
        plot_press_criteria(one_l)
    two_r = cm.press.design_grid(
        R=0.09, r=[0.03, 0.045], d=[0.0, 0.02], L=[0.3, 0.4], phi0=0.0, k_Sp=0.1, omega=4.0
    )
    with pytest.raises(cm.InputError, match="varies r over 2 values"):
        plot_press_criteria(two_r)
    _, ax = plt.subplots()
    with pytest.raises(cm.InputError, match=r"with optimum: ax must be None .* 2 Axes"):
        plot_press_criteria(optimum.grid, ax, optimum=optimum)
