"""cyclomech.synthesis.cam_size: the smallest base radius against independent references.

Each reference is worked out here, not by the kernel's search: brentq (scipy) on the
project's public criteria (Cam.solve's pressure angle and curvature, Cam.loads's
Hertz stress, each maximised over a dense grid and refined by a bounded scalar
maximiser), and the translating roller's closed form tan φ = (s′ − e)/(s + √(R_p² − e²))
on a dense grid in numpy.
"""

from __future__ import annotations

import math

import cyclomech as cm
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq, minimize_scalar

S = cm.cam.Segment
TH = np.linspace(0.0, 2.0 * np.pi, 20001)


def segments(rise: float = 90.0, back: float = 150.0, h: float = 0.02) -> list[cm.cam.Segment]:
    rest = (360.0 - rise - back) / 2.0
    return [S("rise", rise, h), S("dwell", rest), S("return", back, h), S("dwell", rest)]


def worst(f) -> float:
    """max f(θ) over the cam: the dense grid, then a bounded maximiser around its best."""
    v = f(TH)
    i = int(np.nanargmax(v))
    lo, hi = TH[max(i - 1, 0)], TH[min(i + 1, TH.size - 1)]
    res = minimize_scalar(
        lambda t: -float(f(np.array([t]))[0]),
        bounds=(lo, hi),
        method="bounded",
        options={"xatol": 1e-12},
    )
    return max(float(v[i]), -float(res.fun))


def with_radius(cam: cm.cam.Cam, rb: float) -> cm.cam.Cam:
    import dataclasses

    return cm.cam.Cam(
        list(cam.segments), dataclasses.replace(cam.follower, base_radius=rb), cam.closure
    )


def max_pressure_deg(cam: cm.cam.Cam, rb: float) -> float:
    c = with_radius(cam, rb)
    return math.degrees(worst(lambda t: np.abs(c.solve(t).pressure_angle)))


def max_stress(cam, rb, rpm, loads, contact) -> float:
    c = with_radius(cam, rb)
    return worst(lambda t: c.loads(t, rpm, loads, contact).contact_stress)


def test_pressure_angle_binds_with_equality_brentq() -> None:
    """The radius meets the pressure-angle limit with equality (brentq on Cam.solve)
    and a radius 0.1 % smaller violates it."""
    cam = cm.cam.Cam(segments(), cm.cam.TranslatingRoller(0.05, 0.01, 0.004))
    got = cm.synthesis.cam_size(
        cam, 200.0, limits=cm.synthesis.CamLimits(28.0), max_base_radius=0.3
    )
    assert (got.status, got.binding) == ("ok", "pressure_angle")
    ref = brentq(lambda r: max_pressure_deg(cam, r) - 28.0, 0.011, 0.3, xtol=1e-14)
    assert got.base_radius == pytest.approx(ref, rel=1e-7)
    assert max_pressure_deg(cam, got.base_radius) == pytest.approx(28.0, rel=1e-8)
    assert max_pressure_deg(cam, got.base_radius * 0.999) > 28.0
    assert got.margins["pressure_angle"] == pytest.approx(0.0, abs=1e-9)
    assert got.cam.follower.base_radius == got.base_radius
    assert got.cam.follower.offset == 0.004  # held


@pytest.mark.parametrize("e", [0.0, 0.006, -0.004])
def test_translating_closed_form(e: float) -> None:
    """Cycloidal rise and return: R_p² = e² + max(|s′ − e|/tan[α] − s)² on a dense
    grid (|φ| ≤ α ⇔ s + √(R_p² − e²) ≥ |s′ − e|/tan α), R_b = R_p − r_r."""
    rr, alpha = 0.01, 30.0
    cam = cm.cam.Cam(segments(), cm.cam.TranslatingRoller(0.05, rr, e))
    got = cm.synthesis.cam_size(cam, 100.0, max_base_radius=0.3)
    beta_r, beta_b, h = math.radians(90.0), math.radians(150.0), 0.02
    x = np.linspace(0.0, 1.0, 400001)
    z = x - np.sin(2 * np.pi * x) / (2 * np.pi)
    dz = 1.0 - np.cos(2 * np.pi * x)
    s = np.concatenate([h * z, h * (1.0 - z), [0.0, h]])
    ds = np.concatenate([h * dz / beta_r, -h * dz / beta_b, [0.0, 0.0]])
    need = np.abs(ds - e) / math.tan(math.radians(alpha)) - s
    rp = math.sqrt(e * e + max(float(need.max()), 0.0) ** 2)
    assert got.base_radius == pytest.approx(rp - rr, rel=1e-8)


def test_stress_binds_with_equality_brentq() -> None:
    """A stress limit tighter than the pressure angle: brentq on Cam.loads's σ_H."""
    cam = cm.cam.Cam(segments(120, 120), cm.cam.TranslatingRoller(0.05, 0.01))
    loads, contact = cm.cam.FollowerLoads(1.0, 2000.0, 50.0), cm.cam.Contact(0.01)
    lim = cm.synthesis.CamLimits(30.0, 2e8)
    got = cm.synthesis.cam_size(
        cam, 300.0, limits=lim, loads=loads, contact=contact, max_base_radius=0.2
    )
    assert got.binding == "contact_stress"
    ref = brentq(lambda r: max_stress(cam, r, 300.0, loads, contact) - 2e8, 0.015, 0.2, xtol=1e-14)
    assert got.base_radius == pytest.approx(ref, rel=1e-7)
    assert max_stress(cam, got.base_radius * 0.999, 300.0, loads, contact) > 2e8
    assert max_pressure_deg(cam, got.base_radius) < 30.0  # the other limit holds
    assert got.ratios["pressure_angle"] < 1.0


def test_oscillating_pressure_brentq() -> None:
    """An oscillating roller (pivot distance and arm held): brentq on Cam.solve."""
    segs = segments(90, 150, 0.35)  # arm strokes [rad]
    cam = cm.cam.Cam(segs, cm.cam.OscillatingRoller(0.12, 0.08, 0.04, 0.01))
    got = cm.synthesis.cam_size(cam, 100.0, max_base_radius=0.1)
    assert got.binding == "pressure_angle"
    ref = brentq(
        lambda r: max_pressure_deg(cam, r) - 45.0,
        got.base_radius * 0.9,
        got.base_radius * 1.1,
        xtol=1e-14,
    )
    assert got.base_radius == pytest.approx(ref, rel=1e-7)
    assert max_pressure_deg(cam, got.base_radius * 0.999) > 45.0


def test_offset_search_no_grid_offset_does_better() -> None:
    """The best offset: no offset on an independent grid needs a smaller radius."""
    segs = [S("rise", 80, 0.02), S("return", 280, 0.02)]
    cam = cm.cam.Cam(segs, cm.cam.TranslatingRoller(0.05, 0.01))
    best = cm.synthesis.cam_size(cam, 100.0, max_base_radius=0.3, offset=(-0.02, 0.02))
    assert best.searched == ("base_radius", "offset")
    held = cm.synthesis.cam_size(cam, 100.0, max_base_radius=0.3)
    assert best.base_radius < 0.95 * held.base_radius
    e = best.cam.follower.offset
    assert 0.0 < e < 0.02  # toward the fast rise's side
    for ei in np.linspace(-0.02, 0.02, 41):
        c = cm.cam.Cam(segs, cm.cam.TranslatingRoller(0.05, 0.01, float(ei)))
        r = cm.synthesis.cam_size(c, 100.0, max_base_radius=0.3)
        assert r.base_radius >= best.base_radius * (1.0 - 1e-9)


def test_optimum_at_the_lower_bound_is_reported() -> None:
    cam = cm.cam.Cam(segments(), cm.cam.TranslatingRoller(0.05, 0.01))
    got = cm.synthesis.cam_size(
        cam, 100.0, limits=cm.synthesis.CamLimits(85.0), min_base_radius=0.04, max_base_radius=0.3
    )
    assert (got.status, got.binding, got.base_radius) == ("at_lower_bound", "", 0.04)
    assert all(v <= 1.0 for v in got.ratios.values())


def test_tradeoff_matches_min_phase_angles_per_radius() -> None:
    """The batched trade-off equals the cam's own min_phase_angles at each radius."""
    cam = cm.cam.Cam(segments(120, 120), cm.cam.TranslatingRoller(0.05, 0.01))
    loads, contact = cm.cam.FollowerLoads(1.0, 2000.0, 50.0), cm.cam.Contact(0.01)
    lim = cm.synthesis.CamLimits(30.0, 6e8)
    radii = [0.02, 0.035, 0.05, 0.08]
    t = cm.synthesis.cam_size_tradeoff(
        cam, [100.0, 600.0], radii, limits=lim, loads=loads, contact=contact
    )
    assert t.angle_deg.shape == (4, 2, 2, 4)
    for i, r in enumerate(radii):
        m = with_radius(cam, r).min_phase_angles(
            [100.0, 600.0],
            loads=loads,
            contact=contact,
            max_stress=6e8,
            max_pressure_angle_deg=30.0,
        )
        np.testing.assert_allclose(t.angle_deg[i], m.angle_deg[..., :4], rtol=1e-12)
    # A larger radius never needs a larger pressure-angle phase angle.
    assert np.all(np.diff(t.angle_deg[:, 0, :, 0], axis=0) <= 1e-12)


def test_unreachable_limit_names_the_requirement() -> None:
    cam = cm.cam.Cam(segments(), cm.cam.TranslatingRoller(0.05, 0.01))
    with pytest.raises(cm.InputError, match=r"pressure_angle reaches at best .*× its limit"):
        cm.synthesis.cam_size(cam, 100.0, limits=cm.synthesis.CamLimits(5.0), max_base_radius=0.05)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"limits": cm.synthesis.CamLimits(30.0, 6e8)}, "needs the follower's loads"),
        ({"max_base_radius": -0.1}, "max_base_radius = -0.1 must be finite and > 0"),
        ({"min_base_radius": 0.005}, "must be > the roller's radius"),
        ({"pivot_distance": (0.1, 0.2)}, "drop pivot_distance="),
        ({"offset": (0.02, 0.01)}, "must have low < high"),
        ({"rpm": [100.0, 200.0]}, "rpm must be one speed"),
        ({"limits": 30.0}, "limits must be a cyclomech.synthesis.CamLimits"),
    ],
)
def test_bad_input(kwargs: dict, match: str) -> None:
    cam = cm.cam.Cam(segments(), cm.cam.TranslatingRoller(0.05, 0.01))
    args = {"rpm": 100.0, "max_base_radius": 0.2, **kwargs}
    rpm = args.pop("rpm")
    with pytest.raises(cm.InputError, match=match):
        cm.synthesis.cam_size(cam, rpm, **args)


@pytest.mark.parametrize(
    "bad",
    [{"max_pressure_angle_deg": -5.0}, {"max_stress": -1.0}, {"max_pressure_angle_deg": 90.0}],
)
def test_negative_limits(bad: dict) -> None:
    with pytest.raises(cm.InputError, match=next(iter(bad))):
        cm.synthesis.CamLimits(**bad)


def max_undercut(cam: cm.cam.Cam, rb: float) -> float:
    """r_r/ρ_p at its worst (Cam.solve's pitch curvature; ≤ 1: no undercut)."""
    c = with_radius(cam, rb)
    rr = c.follower.roller_radius
    return worst(lambda t: rr / c.solve(t).pitch_radius_of_curvature)


@settings(max_examples=12, deadline=None)
@given(
    rise=st.floats(50.0, 150.0),
    h=st.floats(0.005, 0.04),
    alpha=st.floats(20.0, 40.0),
    e=st.floats(-0.005, 0.005),
)
def test_property_tight_on_the_binding_limit(rise, h, alpha, e) -> None:
    """Any cam: the binding criterion (Cam.solve, dense: the pressure angle, or the
    pitch curve's curvature against the roller) is at its limit at the answer and
    over it 0.1 % below; the other holds."""
    cam = cm.cam.Cam(
        segments(rise, 360.0 - rise - 60.0, h), cm.cam.TranslatingRoller(0.08, 0.01, e)
    )
    got = cm.synthesis.cam_size(
        cam, 100.0, limits=cm.synthesis.CamLimits(alpha), max_base_radius=0.5
    )
    p = lambda r: max_pressure_deg(cam, r) / alpha  # noqa: E731
    u = lambda r: max_undercut(cam, r)  # noqa: E731
    if got.status == "at_lower_bound":  # a small stroke: the roller's clearance binds
        assert got.binding == ""
        assert max(p(got.base_radius), u(got.base_radius)) <= 1.0 + 1e-9
        return
    tight, other = {"pressure_angle": (p, u), "undercut": (u, p)}[got.binding]
    assert tight(got.base_radius) == pytest.approx(1.0, rel=1e-7)
    assert tight(got.base_radius * 0.999) > 1.0
    assert other(got.base_radius) <= 1.0 + 1e-9
