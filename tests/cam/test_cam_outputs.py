"""The cam's outputs (issue 18, item 8): the figures (what is drawn, checked against
:meth:`Cam.solve` and :meth:`Cam.loads`, not only that drawing does not fail), the
profile table and its CSV and DXF files (read back and compared with the exact
geometry; the chordal error against the deviation measured on the densely sampled
curve) and ``cyclomech cam`` end to end, its exit statuses and bad input."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import cyclomech as cm
import matplotlib.image as mpimg
import matplotlib.pyplot as plt
import numpy as np
import pytest
from cyclomech.cam.plot import plot_along_cycle, plot_cam, plot_min_phase_angles, plot_svaj
from cyclomech.cli import main
from cyclomech.plot import CRITICAL_COLOR
from matplotlib.collections import LineCollection
from numpy.testing import assert_allclose, assert_array_equal

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "lifter_cam.toml"
S = cm.cam.Segment


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def lifter() -> tuple[float, cm.cam.CamDesign]:
    _, rpm, d = cm.cam.CamDesign.from_toml(EXAMPLE)
    assert rpm is not None
    return rpm, d


def offset_cam() -> cm.cam.Cam:
    """A spring-closed translating roller follower with an offset."""
    return cm.cam.Cam(
        [S("rise", 120, 0.025), S("dwell", 60), S("return", 120, 0.025, "modified_trapezoid"),
         S("dwell", 60)],
        cm.cam.TranslatingRoller(0.04, 0.012, offset=0.01),
    )  # fmt: skip


SPRING_LOADS = cm.cam.FollowerLoads(1.2, 3000.0, 40.0)
CONTACT = cm.cam.Contact(0.01)


def undercut_cam() -> cm.cam.Cam:
    return cm.cam.Cam(
        [S("rise", 40, 0.04), S("return", 320, 0.04)],
        cm.cam.TranslatingRoller(0.025, 0.015),
        "groove",
    )


def by_gid(ax, gid):
    found = [a for a in ax.get_children() if a.get_gid() == gid]
    return found


def one(ax, gid):
    found = by_gid(ax, gid)
    assert len(found) == 1, (gid, found)
    return found[0]


def png_is_a_picture(fig, path: Path) -> None:
    fig.savefig(path, dpi=60)
    assert path.stat().st_size > 5_000
    img = mpimg.imread(path)
    assert img.ndim == 3 and float(img[..., :3].std()) > 0.02  # not a blank page


# ---------------------------------------------------------------------- plot_cam
def _mid_angles() -> np.ndarray:
    # plot_cam: 1440 segments a turn, each coloured at its middle angle
    return (np.arange(1440) + 0.5) * (2 * math.pi / 1440)


@pytest.mark.parametrize("which", ["lifter", "offset"])
def test_plot_cam_colours_the_profile_by_the_pressure_angle(which, tmp_path):
    cam = lifter()[1].cam if which == "lifter" else offset_cam()
    ax = plot_cam(cam)
    lc = one(ax, "profile")
    assert isinstance(lc, LineCollection)
    k_mid = cam.solve(_mid_angles())
    assert_allclose(lc.get_array(), np.degrees(np.abs(k_mid.pressure_angle)), rtol=0, atol=1e-12)
    # Its vertices are the profile at the even angles, in mm.
    k = cam.solve(np.arange(1440) * (2 * math.pi / 1440))
    segs = np.array(lc.get_segments())
    assert_allclose(segs[:, 0, :], k.profile * 1e3, rtol=0, atol=1e-12)
    assert_allclose(segs[-1, 1, :], k.profile[0] * 1e3, rtol=0, atol=1e-12)  # closed
    if cam.closure == "groove":
        outer = one(ax, "profile_outer")
        assert_allclose(np.array(outer.get_segments())[:, 0, :], k.profile_outer * 1e3, atol=1e-12)
        assert_allclose(outer.get_array(), lc.get_array())
    else:
        assert by_gid(ax, "profile_outer") == []
    pitch = one(ax, "pitch")
    assert pitch.get_linestyle() == "--"
    assert_allclose(pitch.get_xydata()[:-1], k.pitch * 1e3, atol=1e-12)
    assert one(ax, "base").get_radius() == pytest.approx(cam.follower.base_radius * 1e3)
    assert_array_equal(one(ax, "centre").get_xydata(), [[0.0, 0.0]])
    assert ax.get_aspect() == 1.0
    assert len(ax.figure.axes) == 2  # the colorbar
    assert "pressure angle" in ax.figure.axes[1].get_ylabel()
    assert by_gid(ax, "undercut") == []
    # Six followers by default, each where the pitch point of its cam angle is.
    shown = np.arange(6) * 60.0
    k6 = cam.solve(np.radians(shown))
    for deg, p in zip(shown, k6.pitch * 1e3, strict=True):
        roller = one(ax, f"follower:{deg:g}")
        assert_allclose(roller.center, p, atol=1e-12)
        assert roller.get_radius() == pytest.approx(cam.follower.roller_radius * 1e3)
        assert one(ax, f"label:{deg:g}").get_text() == f"{deg:g}°"
        if which == "lifter":
            a = cam.follower.pivot_distance * 1e3
            t = math.radians(deg)
            pivot = [a * math.cos(t), -a * math.sin(t)]  # R(−θ)·(a, 0)
            assert_allclose(one(ax, f"pivot:{deg:g}").get_xydata()[0], pivot, atol=1e-9)
            assert_allclose(one(ax, f"arm:{deg:g}").get_xydata(), [pivot, p], atol=1e-9)
        else:
            stem = one(ax, f"stem:{deg:g}").get_xydata()
            # along the follower's line of motion, +y of the fixed frame seen in the cam's
            up = np.array([math.sin(math.radians(deg)), math.cos(math.radians(deg))])
            d = stem[1] - stem[0]
            assert_allclose(d / np.hypot(*d), up, atol=1e-12)
    png_is_a_picture(ax.figure, tmp_path / "cam.png")


def test_plot_cam_colours_the_loaded_flank_by_the_contact_stress():
    rpm, d = lifter()
    ax = plot_cam(d.cam, color_by="contact_stress", loads=d.loads, contact=d.contact, rpm=rpm,
                  positions_deg=[])  # fmt: skip
    ld = d.cam.loads(_mid_angles(), rpm, d.loads, d.contact)
    sigma = ld.contact_stress / 1e6
    inner, outer = one(ax, "profile").get_array(), one(ax, "profile_outer").get_array()
    on_inner = ld.normal_force >= 0
    assert on_inner.any() and (~on_inner).any()  # the groove's two flanks both carry
    assert_allclose(inner[on_inner], sigma[on_inner], rtol=1e-12)
    assert_allclose(outer[~on_inner], sigma[~on_inner], rtol=1e-12)
    assert np.isnan(np.asarray(inner)[~on_inner]).all()
    assert np.isnan(np.asarray(outer)[on_inner]).all()
    assert "σ_H" in ax.figure.axes[1].get_ylabel()
    assert [a for a in ax.get_children() if str(a.get_gid()).startswith("follower:")] == []


def test_plot_cam_marks_undercut_in_red_where_the_profile_cusps():
    cam = undercut_cam()
    ax = plot_cam(cam, positions_deg=[0.0])
    lines = by_gid(ax, "undercut")
    assert lines
    k = cam.solve(np.arange(1440) * (2 * math.pi / 1440))
    flagged = np.concatenate([k.profile[k.undercut], k.profile_outer[k.undercut]]) * 1e3
    for ln in lines:
        assert ln.get_color() == CRITICAL_COLOR
        # every red run starts at a flagged point
        start = ln.get_xydata()[0]
        assert np.min(np.hypot(*(flagged - start).T)) < 1e-9


def test_plot_cam_flat_faced_and_knife_edge():
    flat = cm.cam.Cam([S("rise", 180, 0.02), S("return", 180, 0.02)], cm.cam.FlatFaced(0.04))
    ax = plot_cam(flat, positions_deg=[90.0])
    face = one(ax, "follower:90").get_xydata()
    k = flat.solve(math.radians(90.0))
    assert_allclose(face.mean(axis=0), k.pitch * 1e3, atol=1e-9)  # centred on the axis point
    knife = cm.cam.Cam(
        [S("rise", 180, 0.02), S("return", 180, 0.02)], cm.cam.TranslatingRoller(0.04, 0.0)
    )
    ax = plot_cam(knife, positions_deg=[30.0])
    assert_allclose(
        one(ax, "follower:30").get_xydata()[0], knife.solve(math.radians(30)).pitch * 1e3
    )


def test_plot_cam_bad_input_names_the_field():
    cam = offset_cam()
    with pytest.raises(cm.InputError, match="color_by"):
        plot_cam(cam, color_by="stress")
    with pytest.raises(cm.InputError, match=r"missing \['contact', 'rpm'\]"):
        plot_cam(cam, color_by="contact_stress", loads=SPRING_LOADS)
    with pytest.raises(cm.InputError, match="positions_deg"):
        plot_cam(cam, positions_deg=[np.nan])
    with pytest.raises(cm.InputError, match=r"cam must be a cyclomech\.cam\.Cam"):
        plot_cam("cam")
    with pytest.raises(ValueError, match="rpm"):
        plot_cam(cam, color_by="contact_stress", loads=SPRING_LOADS, contact=CONTACT, rpm=-1.0)


# ---------------------------------------------------------------------- plot_svaj
@pytest.mark.parametrize("rpm", [None, 450.0])
def test_plot_svaj_shows_the_derivatives_per_radian_or_per_second(rpm, tmp_path):
    cam = offset_cam()
    axes = plot_svaj(cam, rpm=rpm)
    assert axes.shape == (4,)
    w = 1.0 if rpm is None else rpm * math.pi / 30
    for ax, gid, power in zip(axes, "svaj", range(4), strict=True):
        line = one(ax, gid)
        x, y = line.get_xdata(), line.get_ydata()
        ok = np.isfinite(x)
        assert (~ok).sum() == 3  # a gap at each inner boundary
        k = cam.solve(np.radians(x[ok]))
        ref = (k.s, k.ds, k.dds, k.ddds)[power] * w**power
        assert_allclose(y[ok], ref, rtol=1e-12, atol=1e-15)
        boundaries = sorted(b.get_xdata()[0] for b in by_gid(ax, "boundary"))
        assert_allclose(boundaries, [120.0, 180.0, 300.0])
    units = ("m/rad", "m/rad²", "m/rad³") if rpm is None else ("m/s", "m/s²", "m/s³")
    for ax, unit in zip(axes[1:], units, strict=True):
        assert ax.get_ylabel().endswith(f"[{unit}]")
    kinds = [one(axes[0], f"kind:{i}").get_text() for i in range(4)]
    assert kinds == ["rise", "dwell", "return", "dwell"]
    png_is_a_picture(axes[0].figure, tmp_path / "svaj.png")


def test_plot_svaj_of_an_oscillating_follower_shows_s_in_degrees():
    rpm, d = lifter()
    axes = plot_svaj(d.cam, rpm=rpm)
    s = one(axes[0], "s").get_ydata()
    assert np.nanmax(s) == pytest.approx(12.0, rel=1e-9)
    assert axes[0].get_ylabel() == "s  [deg]" and axes[1].get_ylabel() == "v  [rad/s]"
    with pytest.raises(cm.InputError, match="4 Axes"):
        plot_svaj(d.cam, axes=axes[:2])


# ---------------------------------------------------------------- plot_along_cycle
def test_plot_along_cycle_of_the_example(tmp_path):
    rpm, d = lifter()
    axes = plot_along_cycle(d.cam, rpm, d.loads, d.contact, max_stress=d.max_stress,
                            max_pressure_angle_deg=d.max_pressure_angle_deg)  # fmt: skip
    assert len(axes) == 4
    line = one(axes[0], "pressure_angle")
    x, y = line.get_xdata(), line.get_ydata()
    ok = np.isfinite(x)
    theta = np.radians(x[ok])
    assert_allclose(y[ok], np.degrees(d.cam.solve(theta).pressure_angle), rtol=1e-12)
    ld = d.cam.loads(theta, rpm, d.loads, d.contact)
    assert_allclose(one(axes[1], "normal_force").get_ydata()[ok], ld.normal_force, rtol=1e-12)
    assert_allclose(one(axes[2], "contact_stress").get_ydata()[ok], ld.contact_stress / 1e6)
    assert_allclose(one(axes[3], "shaft_torque").get_ydata()[ok], ld.shaft_torque, rtol=1e-12)
    alphas = sorted(a.get_ydata()[0] for a in by_gid(axes[0], "alpha_max"))
    assert alphas == [-45.0, 45.0]
    assert one(axes[2], "sigma_max").get_ydata()[0] == pytest.approx(900.0)
    assert by_gid(axes[1], "separated") == []  # a groove holds its follower
    png_is_a_picture(axes[0].figure, tmp_path / "along.png")


def test_plot_along_cycle_shades_where_a_spring_closed_follower_jumps():
    cam = offset_cam()
    jump_rpm, _ = cam.jump_rpm(SPRING_LOADS)
    axes = plot_along_cycle(cam, 1.4 * jump_rpm, SPRING_LOADS)  # no contact: 3 axes
    assert len(axes) == 3 and axes[1].get_ylabel() == "normal force  [N]"
    spans = by_gid(axes[1], "separated")
    assert spans
    ld = cam.loads(np.radians(np.arange(0, 360, 0.25)), 1.4 * jump_rpm, SPRING_LOADS)
    assert ld.separated.any()
    # Each shaded stretch is where the kernel says the follower is separated.
    for sp in spans:
        x0, x1 = sp.get_x(), sp.get_x() + sp.get_width()
        mid = np.radians([(x0 + x1) / 2])
        assert cam.loads(mid, 1.4 * jump_rpm, SPRING_LOADS).separated.all()
    below = plot_along_cycle(cam, 0.9 * jump_rpm, SPRING_LOADS, CONTACT, max_stress=8e8)
    assert len(below) == 4 and by_gid(below[1], "separated") == []
    # Default [α] of a translating follower: 30°.
    assert sorted(a.get_ydata()[0] for a in by_gid(below[0], "alpha_max")) == [-30.0, 30.0]


# ------------------------------------------------------------ plot_min_phase_angles
def test_plot_min_phase_angles_draws_each_criterion_and_the_bound(tmp_path):
    rpm, d = lifter()
    speeds = np.linspace(0.25 * rpm, 2 * rpm, 21)
    m = d.min_phase_angles(speeds)
    ax = plot_min_phase_angles(m, labels=["rise", "return"], nominal_deg=[70.0, 80.0])
    for i, seg in enumerate(m.segments):
        assert_allclose(one(ax, f"{seg}:bound").get_ydata(), m.bound_deg[:, i])
        for j, crit in enumerate(m.criteria):
            lines = by_gid(ax, f"{seg}:{crit}")
            if crit == "jump":  # a groove: 0 at every speed, left out
                assert lines == [] and (m.angle_deg[:, i, j] == 0).all()
                continue
            # 0 (does not bound the segment at that speed) is a gap.
            want = np.where(m.angle_deg[:, i, j] == 0.0, np.nan, m.angle_deg[:, i, j])
            assert_allclose(lines[0].get_ydata(), want)
            assert_allclose(lines[0].get_xdata(), speeds)
        assert one(ax, f"{seg}:nominal").get_ydata()[0] == [70.0, 80.0][i]
    # The bound is bold, the criteria thin; the segments' colours differ.
    assert one(ax, "0:bound").get_linewidth() > one(ax, "0:undercut").get_linewidth()
    assert one(ax, "0:undercut").get_color() != one(ax, "2:undercut").get_color()
    texts = [t.get_text() for t in ax.get_legend().get_texts()]
    assert texts[:2] == ["rise: bound", "return: bound"] and "jump" not in texts
    png_is_a_picture(ax.figure, tmp_path / "min_phase.png")


def test_plot_min_phase_angles_leaves_nan_as_a_gap():
    angle = np.array([[[20.0, 10.0]], [[np.nan, 12.0]], [[25.0, 14.0]]])
    m = cm.cam.MinPhaseAngles(np.array([100.0, 200.0, 300.0]), (0,), ("a", "b"), angle)
    ax = plot_min_phase_angles(m)
    assert np.isnan(one(ax, "0:a").get_ydata()[1])
    assert np.isnan(one(ax, "0:bound").get_ydata()[1])  # no bound where one criterion has none
    with pytest.raises(cm.InputError, match="labels holds 2 names"):
        plot_min_phase_angles(m, labels=["x", "y"])
    with pytest.raises(cm.InputError, match="nominal_deg holds 2"):
        plot_min_phase_angles(m, nominal_deg=[1.0, 2.0])


def test_the_facade_re_exports_the_cam_plots_and_doors_stay_light():
    import cyclomech.plot as cplot

    assert cplot.plot_cam is plot_cam and cplot.plot_svaj is plot_svaj
    assert cplot.plot_along_cycle is plot_along_cycle
    assert cplot.plot_min_phase_angles is plot_min_phase_angles
    code = (
        "import sys, cyclomech.cam, cyclomech.cli\n"
        "print('matplotlib' in sys.modules, 'ezdxf' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["False", "False"]


# ------------------------------------------------------------- the profile table
@pytest.mark.parametrize("which", ["lifter", "offset"])
def test_profile_table_is_the_exact_geometry(which):
    cam = lifter()[1].cam if which == "lifter" else offset_cam()
    t = cm.cam.profile_table(cam, 1200)
    assert_array_equal(t["theta_deg"], np.arange(1200) * 0.3)
    k = cam.solve(np.radians(t["theta_deg"]))
    assert_array_equal(t["s_rad" if which == "lifter" else "s_m"], k.s)
    assert_array_equal(np.column_stack([t["profile_x_m"], t["profile_y_m"]]), k.profile)
    assert_array_equal(np.column_stack([t["pitch_x_m"], t["pitch_y_m"]]), k.pitch)
    assert_array_equal(t["pressure_angle_deg"], np.degrees(k.pressure_angle))
    assert_array_equal(t["profile_curvature_radius_m"], k.profile_radius_of_curvature)
    assert_array_equal(t["undercut"], k.undercut)
    assert ("outer_x_m" in t) == (which == "lifter")


def _dense_deviation(cam: cm.cam.Cam, n: int) -> np.ndarray:
    """Per chord of an n-gon on each flank, the largest distance from the chord to
    the curve sampled at 200 points between its ends (the larger of the flanks)."""
    f = np.linspace(0.0, 1.0, 201)
    k = cam.solve(np.radians((np.arange(n)[:, None] + f[None, :]) * 360.0 / n))
    dev = np.zeros(n)
    for pts in (k.profile, k.profile_outer):
        if pts is None:
            continue
        a, b = pts[:, 0, :], pts[:, -1, :]
        ab = b - a
        cross = (pts[..., 0] - a[:, None, 0]) * ab[:, None, 1] - (pts[..., 1] - a[:, None, 1]) * ab[
            :, None, 0
        ]
        dev = np.maximum(dev, np.abs(cross).max(axis=1) / np.hypot(*ab.T))
    return dev


@pytest.mark.parametrize("which", ["lifter", "offset"])
def test_the_chordal_error_is_the_chords_distance_from_the_curve(which):
    cam = lifter()[1].cam if which == "lifter" else offset_cam()
    n = 120
    with pytest.warns(cm.CyclomechWarning, match="chordal error") as rec:
        t = cm.cam.profile_table(cam, n)
    dev = _dense_deviation(cam, n)
    est = t["chordal_error_m"]
    assert_allclose(est.max(), dev.max(), rtol=0.02)
    assert (dev <= est * 1.01).all()  # h²/(8ρ) is the sagitta, to second order
    # The samples the warning asks for are enough.
    need = int(str(rec[0].message).split("samples ≥ ")[1].split()[0])
    t = cm.cam.profile_table(cam, need)  # no warning (pytest turns warnings into errors)
    assert np.nanmax(t["chordal_error_m"]) <= 1e-6


def test_the_default_samples_keep_the_example_within_a_micrometre():
    t = cm.cam.profile_table(lifter()[1].cam)
    assert len(t["theta_deg"]) == 3600 and np.nanmax(t["chordal_error_m"]) < 1e-6


def test_an_undercut_point_has_no_chordal_error():
    cam = undercut_cam()
    t = cm.cam.profile_table(cam, 3600)
    assert t["undercut"].any()
    assert np.isnan(t["chordal_error_m"][t["undercut"]]).all()


@pytest.mark.parametrize("bad", [1, 2, 2.5, True, "3600", None])
def test_profile_table_refuses_a_bad_sample_count(bad):
    with pytest.raises(cm.InputError, match="samples must be an integer ≥ 3"):
        cm.cam.profile_table(offset_cam(), bad)


# ----------------------------------------------------------------------- CSV
# (The undercut cam's profile cusps: near a cusp no sample count keeps the chord
# within 1e-3 mm, and the table says so.)
@pytest.mark.filterwarnings("ignore:samples = 1000 leaves a chordal error")
@pytest.mark.parametrize("which", ["lifter", "undercut"])
def test_the_csv_round_trips_to_cam_solve(which, tmp_path):
    cam = lifter()[1].cam if which == "lifter" else undercut_cam()
    p = cm.cam.write_profile_csv(cam, tmp_path / "p.csv", 1000)
    header = p.read_text(encoding="utf-8").splitlines()[0].split(",")
    assert header[:2] == ["theta_deg", "s_rad" if which == "lifter" else "s_m"]
    assert header[-1] == "undercut" and all(
        h.endswith(("_m", "_deg", "_rad")) or h == "undercut" for h in header
    )
    a = np.genfromtxt(p, delimiter=",", names=True)
    assert len(a) == 1000
    k = cam.solve(np.radians(a["theta_deg"]))
    assert_array_equal(a["theta_deg"], np.arange(1000) * 0.36)
    assert_array_equal(a["profile_x_m"], k.profile[:, 0])  # 17 digits: exact
    assert_array_equal(a["profile_y_m"], k.profile[:, 1])
    assert_array_equal(a["outer_x_m"], k.profile_outer[:, 0])
    assert_array_equal(a["pitch_y_m"], k.pitch[:, 1])
    assert_array_equal(a["pressure_angle_deg"], np.degrees(k.pressure_angle))
    assert_array_equal(a["pitch_curvature_radius_m"], k.pitch_radius_of_curvature)
    assert_array_equal(a["undercut"].astype(bool), k.undercut)


def test_a_csv_that_cannot_be_written_is_a_clear_error(tmp_path):
    with pytest.raises(cm.InputError, match=r"the folder .* does not exist"):
        cm.cam.write_profile_csv(offset_cam(), tmp_path / "no" / "such" / "p.csv")


# ----------------------------------------------------------------------- DXF
@pytest.mark.parametrize("which", ["lifter", "offset"])
def test_the_dxf_reads_back_as_the_profile_in_mm(which, tmp_path):
    ezdxf = pytest.importorskip("ezdxf")
    cam = lifter()[1].cam if which == "lifter" else offset_cam()
    p = cm.cam.write_profile_dxf(cam, tmp_path / "cam.dxf", 1200)
    doc = ezdxf.readfile(p)
    assert doc.header["$INSUNITS"] == 4 and doc.header["$MEASUREMENT"] == 1
    msp = doc.modelspace()
    k = cam.solve(np.radians(np.arange(1200) * 0.3))
    expected = {"PROFILE": k.profile, "PITCH": k.pitch}
    if which == "lifter":
        expected["GROOVE_OUTER"] = k.profile_outer
    polylines = msp.query("LWPOLYLINE")
    assert sorted(e.dxf.layer for e in polylines) == sorted(expected)
    for e in polylines:
        assert e.closed
        v = np.array(e.get_points("xy"))
        assert_allclose(v, expected[e.dxf.layer] * 1e3, rtol=0, atol=1e-9)
    (circle,) = msp.query("CIRCLE")
    assert circle.dxf.layer == "BASE"
    assert circle.dxf.radius == pytest.approx(cam.follower.base_radius * 1e3, abs=1e-12)
    (point,) = msp.query("POINT")
    assert point.dxf.layer == "CENTRE" and tuple(point.dxf.location) == (0.0, 0.0, 0.0)
    assert {"PROFILE", "PITCH", "BASE", "CENTRE", "GROOVE_OUTER"} <= {
        layer.dxf.name for layer in doc.layers
    }


def test_without_ezdxf_the_dxf_writer_says_how_to_install_it(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "ezdxf", None)  # import ezdxf raises ImportError
    target = tmp_path / "cam.dxf"
    with pytest.raises(cm.cam.DxfUnavailableError, match=r"pip install 'cyclomech\[dxf\]'") as e:
        cm.cam.write_profile_dxf(offset_cam(), target)
    assert isinstance(e.value, cm.CyclomechError) and isinstance(e.value, ValueError)
    assert not target.exists()


# ----------------------------------------------------------------------- CLI
def _write(tmp_path: Path, text: str, name: str = "cam.toml") -> Path:
    f = tmp_path / name
    f.write_text(text, encoding="utf-8")
    return f


def test_cam_command_on_the_example(tmp_path, capsys):
    out_dir = tmp_path / "out"
    code = main(["cam", str(EXAMPLE), "--out", str(out_dir), "--samples", "1800"])
    out, err = capsys.readouterr()
    assert code == 0 and err == ""
    assert "loom lifter cam: oscillating roller follower" in out and "groove closure" in out
    assert "the design holds every criterion" in out and "FAILS" not in out
    names = {"profile.csv", "profile.dxf", "results.json", "min_phase.csv"}
    names |= {"cam.png", "svaj.png", "along_cycle.png", "min_phase.png"}
    assert {p.name for p in out_dir.iterdir()} == names
    for png in out_dir.glob("*.png"):
        assert png.stat().st_size > 10_000
    rpm, d = lifter()
    # results.json against the API
    res = json.loads((out_dir / "results.json").read_text(encoding="utf-8"))
    assert res["rpm"] == rpm and res["closure"] == "groove" and res["fails"] == []
    deg = np.arange(1800) * 0.2
    k = d.cam.solve(np.radians(deg))
    phi = np.degrees(np.abs(k.pressure_angle))
    assert res["pressure_angle"]["max_deg"] == pytest.approx(phi.max(), rel=1e-12)
    assert res["pressure_angle"]["at_deg"] == pytest.approx(deg[phi.argmax()])
    sigma = d.cam.loads(np.radians(deg), rpm, d.loads, d.contact).contact_stress
    assert res["contact_stress"]["max_pa"] == pytest.approx(sigma.max(), rel=1e-12)
    assert f"{phi.max():.4g}°" in out and f"{sigma.max() / 1e6:.4g} MPa" in out
    m = d.min_phase_angles([rpm])
    for entry, i in zip(res["min_phase"], range(2), strict=True):
        assert entry["bound_deg"] == pytest.approx(m.bound_deg[0, i], rel=1e-12)
        assert entry["binding"] == m.binding[0, i] and entry["ok"]
    # min_phase.csv: 41 speeds from 0.25x to 2x the rpm, each criterion as the API says
    a = np.genfromtxt(out_dir / "min_phase.csv", delimiter=",", names=True)
    assert len(a) == 41
    assert_allclose(a["rpm"], np.linspace(0.25 * rpm, 2.0 * rpm, 41))
    ref = d.min_phase_angles(a["rpm"])
    assert_allclose(a["seg1_rise_contact_stress_deg"], ref.angle_deg[:, 0, 3], rtol=1e-11)
    assert_allclose(a["seg3_return_bound_deg"], ref.bound_deg[:, 1], rtol=1e-11)
    # the profile files hold --samples points
    csv = np.genfromtxt(out_dir / "profile.csv", delimiter=",", names=True)
    assert len(csv) == 1800


LIFTER = EXAMPLE.read_text(encoding="utf-8")


def test_a_segment_shorter_than_its_bound_fails_with_the_reason(tmp_path, capsys):
    # The rise squeezed to 25° (its bound at 300 rpm is 31.4°, undercut), the
    # following dwell widened to keep the turn.
    text = LIFTER.replace("angle_deg = 70.0", "angle_deg = 25.0").replace(
        "angle_deg = 110.0", "angle_deg = 155.0"
    )
    f = _write(tmp_path, text)
    code = main(["cam", str(f), "--out", str(tmp_path / "out"), "--no-plot"])
    out, _ = capsys.readouterr()
    assert code == 3
    line = next(ln for ln in out.splitlines() if ln.startswith("FAILS: segment 1 (rise)"))
    assert "25° < " in line and "undercut at 300 rpm" in line
    res = json.loads((tmp_path / "out" / "results.json").read_text(encoding="utf-8"))
    assert res["min_phase"][0]["ok"] is False and res["min_phase"][1]["ok"] is True
    assert (tmp_path / "out" / "profile.csv").exists()  # the job is done all the same


@pytest.mark.parametrize(
    ("edit", "reason"),
    [
        (("max_stress_pa = 9e8", "max_stress_pa = 1.0e8"), "σ_H reaches"),
        (("max_pressure_angle_deg = 45.0", "max_pressure_angle_deg = 20.0"), "pressure angle"),
    ],
)
def test_stress_and_pressure_angle_limits_fail_the_design(edit, reason, tmp_path, capsys):
    f = _write(tmp_path, LIFTER.replace(*edit))
    code = main(["cam", str(f), "--out", str(tmp_path / "out"), "--no-plot", "--no-dxf"])
    out, _ = capsys.readouterr()
    assert code == 3
    assert any(ln.startswith("FAILS: ") and reason in ln for ln in out.splitlines())
    assert not (tmp_path / "out" / "profile.dxf").exists()


SPRING = """
[cam]
name = "spring cam"
rpm = 300.0
follower = "translating"
base_radius_m = 0.04
roller_radius_m = 0.012
offset_m = 0.01
mass_kg = 1.2
spring_rate_n_per_m = 3000.0
preload_n = 40.0
width_m = 0.01
max_stress_pa = 8e8

[[cam.segment]]
kind = "rise"
angle_deg = 120.0
stroke_m = 0.025

[[cam.segment]]
kind = "dwell"
angle_deg = 60.0

[[cam.segment]]
kind = "return"
angle_deg = 120.0
stroke_m = 0.025
law = "modified_trapezoid"

[[cam.segment]]
kind = "dwell"
angle_deg = 60.0
"""


def test_rpm_from_the_command_line_and_the_jump_of_a_spring(tmp_path, capsys):
    f = _write(tmp_path, SPRING)
    jump, _ = offset_cam().jump_rpm(SPRING_LOADS)
    assert main(["cam", str(f), "--out", str(tmp_path / "a"), "--no-plot"]) == 0
    out, _ = capsys.readouterr()
    assert f"leaves the cam from {jump:.5g} rpm" in out
    code = main(["cam", str(f), "--out", str(tmp_path / "b"), "--rpm", "700", "--no-plot"])
    out, _ = capsys.readouterr()
    assert code == 3 and "at 700 rpm (--rpm)" in out
    assert "FAILS: the follower leaves the cam at 700 rpm" in out
    res = json.loads((tmp_path / "b" / "results.json").read_text(encoding="utf-8"))
    assert res["rpm"] == 700.0 and res["jump"]["rpm"] == pytest.approx(jump)


def test_an_undercut_profile_fails(tmp_path, capsys):
    text = SPRING.replace(
        "angle_deg = 120.0\nstroke_m = 0.025\n", "angle_deg = 20.0\nstroke_m = 0.025\n", 1
    )
    text = text.replace(
        '[[cam.segment]]\nkind = "dwell"\nangle_deg = 60.0',
        '[[cam.segment]]\nkind = "dwell"\nangle_deg = 160.0',
        1,
    )
    f = _write(tmp_path, text)
    code = main(["cam", str(f), "--out", str(tmp_path / "out"), "--no-plot"])
    out, _ = capsys.readouterr()
    assert code == 3 and "FAILS: the profile is undercut at θ = " in out


def test_without_ezdxf_the_command_says_so_and_carries_on(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "ezdxf", None)
    code = main(["cam", str(EXAMPLE), "--out", str(tmp_path / "out"), "--no-plot"])
    out, _ = capsys.readouterr()
    assert code == 0 and "no profile.dxf: ezdxf is not installed" in out
    assert not (tmp_path / "out" / "profile.dxf").exists()


def test_a_coarse_profile_is_noted(tmp_path, capsys):
    code = main(
        ["cam", str(EXAMPLE), "--out", str(tmp_path / "out"), "--no-plot", "--samples", "60"]
    )
    out, _ = capsys.readouterr()
    assert code == 0 and "note: samples = 60 leaves a chordal error" in out


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--samples", "1"], "--samples must be an integer ≥ 3"),
        (["--rpm", "-5"], "--rpm = -5.0 must be finite and > 0"),
        (["--rpm", "nan"], "--rpm = nan must be finite"),
    ],
)
def test_bad_options_exit_2(args, message, tmp_path, capsys):
    code = main(["cam", str(EXAMPLE), "--out", str(tmp_path / "out"), *args])
    _, err = capsys.readouterr()
    assert code == 2 and message in err and str(EXAMPLE) in err
    assert not (tmp_path / "out").exists()


def test_bad_files_exit_2_naming_file_table_and_key(tmp_path, capsys):
    f = _write(tmp_path, LIFTER.replace("rpm = 300.0", "rpm = 300.0\ncolour = 3"))
    assert main(["cam", str(f), "--out", str(tmp_path / "out")]) == 2
    _, err = capsys.readouterr()
    assert f"{f}: [cam]: unknown key 'colour'" in err
    f = _write(tmp_path, LIFTER.replace("law = ", "speed = 3\nlaw = ", 1), "seg.toml")
    assert main(["cam", str(f), "--out", str(tmp_path / "out")]) == 2
    _, err = capsys.readouterr()
    assert f"{f}: [cam]: segment 1: unknown key 'speed'" in err
    missing = tmp_path / "missing.toml"
    assert main(["cam", str(missing), "--out", str(tmp_path / "out")]) == 2
    _, err = capsys.readouterr()
    assert f"{missing}: no such file" in err
    f = _write(tmp_path, LIFTER.replace("rpm = 300.0", ""), "norpm.toml")
    assert main(["cam", str(f), "--out", str(tmp_path / "out")]) == 2
    _, err = capsys.readouterr()
    assert f"{f}: [cam]: no speed" in err and "--rpm" in err
    assert not (tmp_path / "out").exists()


def test_a_cam_without_loads_or_moving_segments(tmp_path, capsys):
    # No mass: no loads, stress or jump, and no along-cycle figure; all dwell: no bounds.
    f = _write(
        tmp_path,
        '[cam]\nrpm = 100.0\nfollower = "flat"\nbase_radius_m = 0.04\n'
        '[[cam.segment]]\nkind = "dwell"\nangle_deg = 360.0\n',
    )
    code = main(["cam", str(f), "--out", str(tmp_path / "out")])
    out, _ = capsys.readouterr()
    assert code == 0
    assert "loads, σ_H and jump: not computed (no mass_kg in the file)" in out
    assert "no rise or return" in out
    assert {p.name for p in (tmp_path / "out").glob("*.png")} == {
        "cam.png",
        "svaj.png",
        "min_phase.png",
    }
    res = json.loads((tmp_path / "out" / "results.json").read_text(encoding="utf-8"))
    assert res["min_phase"] == [] and res["fails"] == []


def test_a_cam_segment_no_angle_can_carry_is_said_so(tmp_path, capsys) -> None:
    from pathlib import Path

    from cyclomech.cli import main

    lifter = Path(__file__).resolve().parents[2] / "examples" / "lifter_cam.toml"
    code = main(["cam", str(lifter), "--rpm", "5000", "--no-plot", "--out", str(tmp_path)])
    out, err = capsys.readouterr()
    text = out + err
    assert code == 3
    # Was "70° < more than a whole turn, the smallest phase angle …".
    assert "segment 1 (rise): 70°, but no phase angle up to a whole turn meets" in text
    assert "more than a whole turn" not in text and "verdict" in out


def test_the_radius_columns_are_radii_of_curvature_and_say_so():
    """The CSV's radius columns were ``pitch_radius_m``/``profile_radius_m``: read as
    the pitch circle's radius, they are radii of curvature. On the dwells of a
    translating roller follower the pitch curve is a circle of radius r_b + s + r_r
    and the profile one of r_b + s (closed form), which the renamed columns hold."""
    S = cm.cam.Segment
    segments = [S("rise", 120, 0.02), S("dwell", 60), S("return", 120, 0.02), S("dwell", 60)]
    cam = cm.cam.Cam(segments, cm.cam.TranslatingRoller(0.05, 0.01))
    t = cm.cam.profile_table(cam, 720)
    radius_columns = [c for c in t if "radius" in c]
    assert radius_columns == ["pitch_curvature_radius_m", "profile_curvature_radius_m"]
    top = (t["theta_deg"] > 122) & (t["theta_deg"] < 178)  # the dwell at s = 20 mm
    low = t["theta_deg"] > 302  # the dwell at s = 0
    assert_allclose(t["pitch_curvature_radius_m"][top], 0.08, rtol=1e-12)
    assert_allclose(t["profile_curvature_radius_m"][top], 0.07, rtol=1e-12)
    assert_allclose(t["pitch_curvature_radius_m"][low], 0.06, rtol=1e-12)
    assert_allclose(t["profile_curvature_radius_m"][low], 0.05, rtol=1e-12)
