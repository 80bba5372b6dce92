"""The cam domain (issue 18, items 1-3): program, followers, exact kinematics and
geometry — each checked against something independent: textbook closed forms,
the motion laws evaluated on their own, and finite differences of the sampled
curves (test only)."""

from __future__ import annotations

import math

import cyclomech as cm
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

S = cm.cam.Segment
TAU = 2 * math.pi


def _dwell_program(law: str = "cycloidal", h: float = 0.02) -> list[cm.cam.Segment]:
    return [S("rise", 120, h, law), S("dwell", 60), S("return", 100, h, law), S("dwell", 80)]


def _fd_curvature_radius(theta: np.ndarray, pts: np.ndarray, step: float) -> np.ndarray:
    """Signed radius (+ convex, the curve running clockwise) of sampled points
    at theta − step, theta, theta + step (central differences)."""
    p0, p1, p2 = pts
    d1 = (p2 - p0) / (2 * step)
    d2 = (p2 - 2 * p1 + p0) / step**2
    k = d1[..., 0] * d2[..., 1] - d1[..., 1] * d2[..., 0]
    return -(np.hypot(d1[..., 0], d1[..., 1]) ** 3) / k


def _sampled(cam: cm.cam.Cam, theta: np.ndarray, step: float, what: str) -> np.ndarray:
    return np.stack([getattr(cam.solve(theta + d), what) for d in (-step, 0.0, step)])


# --- displacement and its derivatives ------------------------------------------


@pytest.mark.parametrize("law", cm.motion.NAMES)
def test_displacement_matches_the_motion_law_scaled(law: str) -> None:
    h, beta = 0.015, math.radians(110)
    cam = cm.cam.Cam(
        [S("dwell", 30), S("rise", 110, h, law), S("dwell", 40), S("return", 180, h, law)],
        cm.cam.TranslatingRoller(0.05, 0.01),
    )
    x = np.linspace(0.0, 1.0, 201)
    theta = math.radians(30) + x * beta
    k = cam.solve(theta)
    lw = cm.motion.law(law, form="rise")
    np.testing.assert_allclose(k.s, h * lw.z(x), atol=1e-15)
    np.testing.assert_allclose(k.ds, h * lw.dz(x) / beta, atol=1e-13)
    # The segment's end belongs to the next one (where Z'' of some laws jumps).
    np.testing.assert_allclose(k.dds[:-1], h * lw.ddz(x[:-1]) / beta**2, atol=1e-12)
    inner = (x > 0.001) & (x < 0.999)  # dddz may jump at the law's breaks
    xi = x[inner]
    ki = cam.solve(theta[inner])
    np.testing.assert_allclose(ki.ddds, h * lw.dddz(xi) / beta**3, rtol=1e-9, atol=1e-10)
    # The return: s = h − h·Z over its 180°.
    x2 = np.linspace(0.0, 1.0, 51)
    k2 = cam.solve(math.radians(180) + x2 * math.pi)
    np.testing.assert_allclose(k2.s, h - h * lw.z(x2), atol=1e-15)
    np.testing.assert_allclose(k2.ds, -h * lw.dz(x2) / math.pi, atol=1e-13)


def test_cycloidal_displacement_against_its_closed_form() -> None:
    h, beta = 0.02, math.radians(120)
    cam = cm.cam.Cam(_dwell_program(h=h), cm.cam.TranslatingRoller(0.05, 0.01))
    x = np.linspace(0, 1, 101)
    k = cam.solve(x * beta)
    w = 2 * math.pi
    np.testing.assert_allclose(k.s, h * (x - np.sin(w * x) / w), atol=1e-15)
    np.testing.assert_allclose(k.ds, h / beta * (1 - np.cos(w * x)), atol=1e-14)
    np.testing.assert_allclose(k.dds, h / beta**2 * w * np.sin(w * x), atol=1e-12)
    # The segment's end belongs to the next one (a dwell: s''' = 0 there).
    np.testing.assert_allclose(k.ddds[:-1], h / beta**3 * w**2 * np.cos(w * x[:-1]), atol=1e-10)


@pytest.mark.parametrize("law", ["cycloidal", "polynomial_4567", "modified_sine"])
def test_derivatives_against_finite_differences(law: str) -> None:
    cam = cm.cam.Cam(_dwell_program(law), cm.cam.TranslatingRoller(0.05, 0.01))
    theta = np.linspace(0.05, TAU - 0.05, 997)
    hstep = 1e-5
    for lo, hi in (("s", "ds"), ("ds", "dds"), ("dds", "ddds")):
        a = getattr(cam.solve(theta + hstep), lo)
        b = getattr(cam.solve(theta - hstep), lo)
        exact = getattr(cam.solve(theta), hi)
        scale = np.max(np.abs(exact))
        # Skip the few samples that straddle a break of the law's pieces.
        err = np.abs((a - b) / (2 * hstep) - exact) / scale
        assert np.quantile(err, 0.98) < 1e-6, (lo, hi, np.quantile(err, 0.98))


# --- pressure angle ---------------------------------------------------------------


@pytest.mark.parametrize("offset", [0.0, 0.008, -0.012])
@pytest.mark.parametrize("law", ["cycloidal", "harmonic", "polynomial_345"])
def test_translating_pressure_angle_is_the_textbook_closed_form(offset: float, law: str) -> None:
    rb, rr = 0.04, 0.012
    cam = cm.cam.Cam(_dwell_program(law, 0.025), cm.cam.TranslatingRoller(rb, rr, offset))
    theta = np.linspace(0, TAU, 1441)
    k = cam.solve(theta)
    rp = rb + rr
    expected = np.arctan((k.ds - offset) / (k.s + math.sqrt(rp**2 - offset**2)))
    np.testing.assert_allclose(k.pressure_angle, expected, atol=1e-13)


def test_oscillating_pressure_angle_against_the_sampled_geometry() -> None:
    a, arm, rb, rr = 0.12, 0.09, 0.045, 0.012
    f = cm.cam.OscillatingRoller(a, arm, rb, rr)
    prog = [S("rise", 100, math.radians(18)), S("dwell", 50), S("return", 130, math.radians(18))]
    cam = cm.cam.Cam([*prog, S("dwell", 80)], f)
    theta = np.linspace(0.01, TAU - 0.01, 1201)
    step = 1e-6
    p = _sampled(cam, theta, step, "pitch")
    tangent = (p[2] - p[0]) / (2 * step)  # cam frame
    c, sn = np.cos(theta), np.sin(theta)
    # To the fixed frame (rotate by +θ): the roller centre and the tangent.
    fixed = np.stack([c * p[1][:, 0] - sn * p[1][:, 1], sn * p[1][:, 0] + c * p[1][:, 1]], -1)
    tf = np.stack(
        [c * tangent[:, 0] - sn * tangent[:, 1], sn * tangent[:, 0] + c * tangent[:, 1]], -1
    )
    normal = np.stack([-tf[:, 1], tf[:, 0]], -1)
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    arm_vec = fixed - np.array([a, 0.0])
    np.testing.assert_allclose(np.linalg.norm(arm_vec, axis=1), arm, rtol=1e-12)
    path = np.stack([-arm_vec[:, 1], arm_vec[:, 0]], -1) / arm  # ⟂ the arm
    angle = np.arccos(np.clip(np.abs(np.sum(normal * path, axis=1)), 0, 1))
    k = cam.solve(theta)
    np.testing.assert_allclose(np.abs(k.pressure_angle), angle, atol=1e-7)


def test_flat_face_has_zero_pressure_angle_and_contact_at_s_prime() -> None:
    rb = 0.05
    cam = cm.cam.Cam(_dwell_program(), cm.cam.FlatFaced(rb))
    theta = np.linspace(0, TAU, 721)
    k = cam.solve(theta)
    assert np.all(k.pressure_angle == 0.0)
    c, sn = np.cos(theta), np.sin(theta)
    fixed_x = c * k.profile[:, 0] - sn * k.profile[:, 1]
    fixed_y = sn * k.profile[:, 0] + c * k.profile[:, 1]
    np.testing.assert_allclose(fixed_x, k.ds, atol=1e-15)
    np.testing.assert_allclose(fixed_y, rb + k.s, atol=1e-15)


# --- radius of curvature --------------------------------------------------------


def test_dwell_is_an_arc_of_radius_rp_plus_s() -> None:
    rb, rr, h = 0.05, 0.01, 0.02
    cam = cm.cam.Cam(_dwell_program(h=h), cm.cam.TranslatingRoller(rb, rr), closure="groove")
    top = np.radians(np.linspace(125, 175, 11))
    bottom = np.radians(np.linspace(285, 355, 11))
    for theta, s in ((top, h), (bottom, 0.0)):
        k = cam.solve(theta)
        np.testing.assert_allclose(k.pitch_radius_of_curvature, rb + rr + s, rtol=1e-12)
        np.testing.assert_allclose(k.profile_radius_of_curvature, rb + rr + s - rr, rtol=1e-12)
        np.testing.assert_allclose(np.linalg.norm(k.pitch, axis=-1), rb + rr + s, rtol=1e-14)
        np.testing.assert_allclose(np.linalg.norm(k.profile, axis=-1), rb + s, rtol=1e-14)
        assert k.profile_outer is not None
        np.testing.assert_allclose(np.linalg.norm(k.profile_outer, axis=-1), rb + 2 * rr + s)
    # Oscillating: a dwell keeps the roller centre on a circle about the cam centre.
    f = cm.cam.OscillatingRoller(0.12, 0.09, 0.045, 0.012)
    ocam = cm.cam.Cam([S("rise", 90, 0.3), S("dwell", 90), S("return", 180, 0.3)], f)
    k = ocam.solve(np.radians(np.linspace(95, 175, 9)))
    radius = np.linalg.norm(k.pitch, axis=-1)
    np.testing.assert_allclose(k.pitch_radius_of_curvature, radius, rtol=1e-12)
    np.testing.assert_allclose(radius, radius[0], rtol=1e-14)


@pytest.mark.parametrize(
    "follower",
    [
        cm.cam.TranslatingRoller(0.04, 0.01, 0.006),
        cm.cam.TranslatingRoller(0.04, 0.0),
        cm.cam.OscillatingRoller(0.12, 0.09, 0.045, 0.012),
    ],
    ids=["offset-roller", "knife-edge", "oscillating"],
)
def test_radii_of_curvature_against_finite_differences(follower: object) -> None:
    stroke = 0.3 if isinstance(follower, cm.cam.OscillatingRoller) else 0.02
    prog = [S("rise", 140, stroke, "polynomial_345"), S("dwell", 40)]
    cam = cm.cam.Cam([*prog, S("return", 120, stroke, "harmonic"), S("dwell", 60)], follower)
    theta = np.linspace(0.02, TAU - 0.02, 1701)
    step = 2e-5
    k = cam.solve(theta)
    for what, exact in (
        ("pitch", k.pitch_radius_of_curvature),
        ("profile", k.profile_radius_of_curvature),
    ):
        fd = _fd_curvature_radius(theta, _sampled(cam, theta, step, what), step)
        ok = np.abs(exact) < 1.0  # nearly straight parts are ill-conditioned by FD
        err = np.abs(1 / fd[ok] - 1 / exact[ok]) * np.abs(exact[ok])
        assert np.quantile(err, 0.99) < 1e-4, (what, np.quantile(err, 0.99))


def test_flat_face_radius_is_rb_plus_s_plus_s2_and_matches_finite_differences() -> None:
    rb = 0.05
    cam = cm.cam.Cam(_dwell_program("polynomial_345"), cm.cam.FlatFaced(rb))
    theta = np.linspace(0.02, TAU - 0.02, 1201)
    k = cam.solve(theta)
    np.testing.assert_allclose(k.profile_radius_of_curvature, rb + k.s + k.dds, rtol=1e-14)
    step = 2e-5
    fd = _fd_curvature_radius(theta, _sampled(cam, theta, step, "profile"), step)
    err = np.abs(fd - k.profile_radius_of_curvature) / np.abs(k.profile_radius_of_curvature)
    assert np.quantile(err, 0.99) < 1e-4


# --- undercut -----------------------------------------------------------------------


def test_roller_undercut_where_the_sampled_profile_cusps() -> None:
    # A fast, large rise on a small base circle: the convex pitch curve near the
    # top of the rise is tighter than the roller.
    cam = cm.cam.Cam(
        [S("rise", 40, 0.05), S("return", 320, 0.05)], cm.cam.TranslatingRoller(0.02, 0.015)
    )
    theta = np.linspace(0.0, TAU, 14401)[:-1]
    k = cam.solve(theta)
    assert k.undercut.any()
    # Independent: where the sampled profile runs backwards against the pitch
    # curve, the offset curve has looped: a cusp.
    step = 1e-6
    p = _sampled(cam, theta, step, "pitch")
    q = _sampled(cam, theta, step, "profile")
    back = np.sum((q[2] - q[0]) * (p[2] - p[0]), axis=-1) < 0
    disagree = np.flatnonzero(back != k.undercut)
    # Only at the edges of a run (where ρ_pitch = r_r: a zero of the test's dot).
    assert len(disagree) <= 4, disagree
    runs = cam.undercut_angles_deg(14400)
    assert runs and all(0 <= lo <= hi <= 40 for lo, hi in runs)
    sound = cm.cam.Cam(_dwell_program(), cm.cam.TranslatingRoller(0.05, 0.01))
    assert sound.undercut_angles_deg() == []


def test_flat_face_undercut_where_rb_plus_s_plus_s2_is_negative() -> None:
    cam = cm.cam.Cam([S("rise", 40, 0.04), S("return", 320, 0.04)], cm.cam.FlatFaced(0.02))
    theta = np.linspace(0.0, TAU, 7201)
    k = cam.solve(theta)
    np.testing.assert_array_equal(k.undercut, 0.02 + k.s + k.dds < 0)
    assert k.undercut.any()
    # Independent: the sampled profile runs backwards there (its tangent against
    # the face's direction n_θ = (cos θ, −sin θ) in the cam frame).
    step = 1e-6
    q = _sampled(cam, theta, step, "profile")
    face = np.stack([np.cos(theta), -np.sin(theta)], -1)
    back = np.sum((q[2] - q[0]) * face, axis=-1) < 0
    assert len(np.flatnonzero(back != k.undercut)) <= 4


def test_groove_outer_flank_undercut_on_a_tight_concave_pitch_curve() -> None:
    # A big roller at the foot of a steep rise: the pitch curve turns concave
    # tighter than the roller, which cusps the groove's outer flank only.
    rr = 0.018
    prog = [S("rise", 45, 0.04), S("dwell", 30), S("return", 285, 0.04)]
    spring = cm.cam.Cam(prog, cm.cam.TranslatingRoller(0.03, rr))
    groove = cm.cam.Cam(prog, spring.follower, closure="groove")
    theta = np.linspace(0, TAU, 7201)
    ks, kg = spring.solve(theta), groove.solve(theta)
    rho = ks.pitch_radius_of_curvature
    concave_tight = (rho < 0) & (-rho < rr)
    assert concave_tight.any()
    np.testing.assert_array_equal(kg.undercut, ks.undercut | concave_tight)
    # Independent: there the sampled outer flank runs backwards against the pitch.
    step = 1e-6
    p = _sampled(groove, theta, step, "pitch")
    o = _sampled(groove, theta, step, "profile_outer")
    back = np.sum((o[2] - o[0]) * (p[2] - p[0]), axis=-1) < 0
    assert len(np.flatnonzero(back != concave_tight)) <= 4


# --- properties -------------------------------------------------------------------


@st.composite
def _programs(draw: st.DrawFn) -> list[cm.cam.Segment]:
    n_rise = draw(st.integers(1, 2))
    strokes = [draw(st.floats(0.2, 1.0)) for _ in range(n_rise)]
    total = sum(strokes)
    kinds: list[tuple[str, float]] = [("rise", h) for h in strokes]
    kinds.append(("return", total))
    if draw(st.booleans()):
        kinds.insert(draw(st.integers(0, len(kinds))), ("dwell", 0.0))
    weights = [draw(st.floats(0.5, 2.0)) for _ in kinds]
    angles = [360.0 * w / sum(weights) for w in weights]
    angles[-1] = 360.0 - sum(angles[:-1])
    laws = st.sampled_from(cm.motion.NAMES)
    return [S(kd, ang, h, draw(laws)) for (kd, h), ang in zip(kinds, angles, strict=True)]


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    prog=_programs(),
    which=st.sampled_from(["translating", "flat", "oscillating"]),
    scale=st.floats(0.005, 0.03),
    rb=st.floats(0.03, 0.08),
    rr_frac=st.floats(0.0, 0.5),
    e_frac=st.floats(-0.5, 0.5),
    groove=st.booleans(),
)
def test_properties(prog, which, scale, rb, rr_frac, e_frac, groove) -> None:  # type: ignore[no-untyped-def]
    rr = rr_frac * rb
    if which == "oscillating":
        prog = [S(g.kind, g.angle_deg, g.stroke * 0.3, g.law) for g in prog]
        follower: object = cm.cam.OscillatingRoller(2.5 * rb, 2.2 * rb, rb, rr)
    else:
        prog = [S(g.kind, g.angle_deg, g.stroke * scale, g.law) for g in prog]
        if which == "flat":
            follower, groove = cm.cam.FlatFaced(rb), False
        else:
            follower = cm.cam.TranslatingRoller(rb, rr, e_frac * (rb + rr))
    cam = cm.cam.Cam(prog, follower, closure="groove" if groove else "spring")  # type: ignore[arg-type]
    theta = np.linspace(0, TAU, 721)
    k = cam.solve(theta)
    for name in ("s", "ds", "dds", "ddds", "pitch", "profile", "pressure_angle"):
        assert np.all(np.isfinite(getattr(k, name))), name
    # Closure: the end of the turn is its start.
    np.testing.assert_allclose(k.s[-1], k.s[0], atol=1e-12)
    np.testing.assert_allclose(k.profile[-1], k.profile[0], atol=1e-12)
    if which != "flat":
        d = k.profile - k.pitch
        np.testing.assert_allclose(np.linalg.norm(d, axis=-1), rr, atol=1e-12)
        # Along the normal: ⟂ to the pitch curve's tangent (finite differences).
        step = 1e-6
        t = (cam.solve(theta + step).pitch - cam.solve(theta - step).pitch) / (2 * step)
        cosang = np.sum(d * t, axis=-1) / np.linalg.norm(t, axis=-1)
        # At a segment's ends the acceleration may jump (harmonic, …): there the
        # central difference is off by O(step·Δa) (4e-8 found at θ = 0), so the
        # points within two steps of an end are left out.
        ends = np.radians(np.cumsum([0.0] + [g.angle_deg for g in prog]))
        gap = np.abs(np.mod(theta[:, None] - ends[None, :] + np.pi, TAU) - np.pi).min(axis=1)
        away = gap > 2 * step
        np.testing.assert_allclose(cosang[away], 0.0, atol=1e-6 * max(rr, 1e-3))
        if groove:
            assert k.profile_outer is not None
            np.testing.assert_allclose(k.profile_outer - k.pitch, -d, atol=1e-12)
    # Shapes follow theta's.
    k2 = cam.solve(theta[:720].reshape(24, 30))
    assert k2.s.shape == (24, 30) and k2.pitch.shape == (24, 30, 2)
    np.testing.assert_array_equal(k2.s.ravel(), k.s[:720])


def test_solve_threads_and_scalars() -> None:
    cam = cm.cam.Cam(_dwell_program(), cm.cam.TranslatingRoller(0.05, 0.01))
    theta = np.linspace(-TAU, 2 * TAU, 20001)
    a, b = cam.solve(theta, n_threads=1), cam.solve(theta, n_threads=2)
    np.testing.assert_array_equal(a.profile, b.profile)
    np.testing.assert_allclose(a.s, cam.solve(np.mod(theta, TAU)).s, atol=1e-15)
    assert cam.solve(0.3).s.shape == ()
    assert cam.solve(0.3).profile_outer is None
    with pytest.raises(cm.InputError, match="theta"):
        cam.solve([0.0, float("nan")])
    with pytest.raises(cm.InputError, match="n_threads"):
        cam.solve([0.0], n_threads=0)


# --- bad input ---------------------------------------------------------------------


ROLLER = cm.cam.TranslatingRoller(0.05, 0.01)


@pytest.mark.parametrize(
    ("segments", "match"),
    [
        ([S("rise", 180, 0.02), S("return", 170, 0.02)], r"sum to 350.*not 360"),
        ([S("rise", 180, 0.02), S("return", 180, 0.019)], r"does not return to its start"),
        (
            [S("rise", 180, 0.02, "spline"), S("return", 180, 0.02)],
            r"segment 1 \(rise\).*'spline'.*cycloidal",
        ),
        ([S("rise", 180, 0.02), S("return", 180, 0.02, "nope")], r"segment 2 \(return\).*law"),
        ([S("rise", 180, 0.0), S("return", 180, 0.02)], r"segment 1 \(rise\): stroke"),
        (
            [S("rise", 180, 0.02), S("dwell", 90, 0.01), S("return", 90, 0.02)],
            r"segment 2 \(dwell\): stroke",
        ),
        ([], r"segments"),
    ],
)
def test_bad_programs(segments: list[cm.cam.Segment], match: str) -> None:
    with pytest.raises(cm.InputError, match=match) as err:
        cm.cam.Cam(segments, ROLLER)
    assert isinstance(err.value, ValueError)


@pytest.mark.parametrize(
    ("make", "match"),
    [
        (lambda: S("rise", -10, 0.01), "angle_deg"),
        (lambda: S("rise", float("nan"), 0.01), "angle_deg"),
        (lambda: S("rise", 10, -0.01), "stroke"),
        (lambda: S("up", 10, 0.01), "kind"),
        (lambda: cm.cam.TranslatingRoller(0.02, 0.02), "roller_radius"),
        (lambda: cm.cam.TranslatingRoller(0.02, 0.03), "roller_radius"),
        (lambda: cm.cam.TranslatingRoller(-0.02, 0.01), "base_radius"),
        (lambda: cm.cam.TranslatingRoller(0.02, -0.01), "roller_radius"),
        (lambda: cm.cam.TranslatingRoller(0.02, 0.01, 0.03), "offset"),
        (lambda: cm.cam.TranslatingRoller(0.02, 0.01, -0.03), "offset"),
        (lambda: cm.cam.FlatFaced(0.0), "base_radius"),
        (lambda: cm.cam.OscillatingRoller(0.1, 0.02, 0.03, 0.01), "pitch base circle"),
        (lambda: cm.cam.OscillatingRoller(-0.1, 0.08, 0.03, 0.01), "pivot_distance"),
        (lambda: cm.cam.OscillatingRoller(0.1, 0.08, 0.03, 0.04), "roller_radius"),
        (
            lambda: cm.cam.Cam([S("rise", 180, 0.01), S("return", 180, 0.01)], ROLLER, "chain"),
            "closure",
        ),
        (
            lambda: cm.cam.Cam(
                [S("rise", 180, 0.01), S("return", 180, 0.01)], cm.cam.FlatFaced(0.03), "groove"
            ),
            "groove",
        ),
        (lambda: cm.cam.Cam([S("rise", 180, 0.01), S("return", 180, 0.01)], "roller"), "follower"),
        # A return first takes s to −0.02: the roller's centre (R_b + r_r = 0.015) and
        # the flat face (R_b = 0.01, accepted until now) would cross the cam centre.
        (
            lambda: cm.cam.Cam(
                [S("return", 180, 0.02), S("rise", 180, 0.02)],
                cm.cam.TranslatingRoller(0.01, 0.005),
            ),
            "base_radius.*cross the cam centre",
        ),
        (
            lambda: cm.cam.Cam(
                [S("return", 180, 0.02), S("rise", 180, 0.02)], cm.cam.FlatFaced(0.01)
            ),
            "base_radius.*cross the cam centre",
        ),
        (
            lambda: cm.cam.Cam(
                [S("rise", 180, 3.0), S("return", 180, 3.0)],
                cm.cam.OscillatingRoller(0.1, 0.08, 0.03, 0.01),
            ),
            "arm",
        ),
    ],
)
def test_bad_fields_are_input_errors_naming_the_field(make, match: str) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(cm.InputError, match=match) as err:
        make()
    assert isinstance(err.value, ValueError)


def test_kernel_validates_on_its_own() -> None:
    """The Rust kernel refuses bad input too (a typed error, never a panic)."""
    from cyclomech import _core

    with pytest.raises(cm.InputError, match=r"segment 1 \(rise\): unknown motion law"):
        _core.CamKernel(
            ["rise", "return"],
            [math.pi, math.pi],
            [0.01, 0.01],
            ["x", "cycloidal"],
            "flat",
            [0.05],
            False,
        )
    with pytest.raises(cm.InputError, match="not 360"):
        _core.CamKernel(
            ["rise", "return"], [1.0, 1.0], [0.01, 0.01], ["cycloidal"] * 2, "flat", [0.05], False
        )
    with pytest.raises(cm.InputError, match="roller_radius"):
        _core.CamKernel(
            ["rise", "return"],
            [math.pi] * 2,
            [0.01] * 2,
            ["cycloidal"] * 2,
            "translating",
            [0.01, 0.02, 0.0],
            False,
        )
    with pytest.raises(cm.InputError, match="follower"):
        _core.CamKernel(
            ["rise", "return"], [math.pi] * 2, [0.01] * 2, ["cycloidal"] * 2, "cone", [0.01], False
        )
    with pytest.raises(cm.InputError, match="kind"):
        _core.CamKernel(
            ["up", "return"], [math.pi] * 2, [0.01] * 2, ["cycloidal"] * 2, "flat", [0.05], False
        )


@pytest.mark.parametrize("theta", [np.array([True, False]), "0.5", [0.1, "x"]])
def test_solve_refuses_angles_that_are_not_numbers(theta):
    # A bool would have been read as 1 rad, a string parsed by numpy.
    S = cm.cam.Segment
    cam = cm.cam.Cam(
        [S("rise", 180, 0.02), S("return", 180, 0.02)], cm.cam.TranslatingRoller(0.05, 0.01)
    )
    with pytest.raises(ValueError, match="theta must be an array of real numbers"):
        cam.solve(theta)


def test_solve_keeps_the_shape_of_a_scalar_angle():
    S = cm.cam.Segment
    cam = cm.cam.Cam(
        [S("rise", 180, 0.02), S("return", 180, 0.02)], cm.cam.TranslatingRoller(0.05, 0.01)
    )
    k = cam.solve(0.5)
    assert k.s.shape == () and k.theta.shape == () and k.pitch.shape == (2,)
