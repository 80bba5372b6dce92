"""Issue 16, class III walks: items 2, 3, 10 and the class III part of 15.

Independent references, none of them the kernel:

* closure of every link length, in numpy;
* scipy's ``least_squares`` on the six closure equations, warm-started from a
  neighbouring pose (whether a continuous pose exists) and stepped in small
  increments (an independent continuation of the drawn branch);
* the seed's bracketing re-implemented in numpy, vectorised over the crank angles
  (at which angles the group can be assembled at all);
* numpy's own trigonometric reduction of large angles (``np.cos``/``np.sin``).
"""

from __future__ import annotations

import math
import time

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.linkage import presets
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose

TAU = 2 * math.pi
JOINTS = ("B", "C", "E")


# ---------------------------------------------------------------- references
def circles(c1, r1, c2, r2, sign):
    """Intersection(s) of circle(c1, r1) and circle(c2, r2) on side `sign` of c1→c2,
    vectorised over leading axes; NaN where they do not meet."""
    d = c2 - c1
    dd = (d**2).sum(-1)
    ln = np.sqrt(dd)
    x = (r1 * r1 - r2 * r2 + dd) / (2 * ln)
    with np.errstate(invalid="ignore"):
        h = np.sqrt(r1 * r1 - x * x)
    e = d / ln[..., None]
    n = np.stack([-e[..., 1], e[..., 0]], -1)
    return c1 + x[..., None] * e + sign * h[..., None] * n


def stephenson() -> cm.Linkage:
    """Issue 16 item 2's six-bar: group B–C–E held by AB, DC and EF, driven by G–F."""
    b, d = np.array([1.0, 0.0]), np.array([4.0, 0.0])
    c = circles(b, 3.5, d, 2.6, 1.0)
    pts = {
        "A": (0, 0),
        "B": tuple(b),
        "D": tuple(d),
        "C": tuple(c),
        "E": (2, 3.5),
        "F": (1.15, 5.6),
        "G": (1, 5.6),
    }
    links = [("A", "B"), ("B", "C", "E"), ("D", "C"), ("E", "F"), ("G", "F")]
    return cm.Linkage(pts, links, ["A", "D", "G"], ("G", "F"))


def closure_pairs(lk: cm.Linkage, ef: float | None = None) -> list[tuple[str, str, float]]:
    """The group's six links and their lengths (|EF| = ``ef`` if given)."""
    pairs = [("A", "B"), ("D", "C"), ("F", "E"), ("B", "C"), ("C", "E"), ("E", "B")]
    out = [(a, b, lk.length(a, b)) for a, b in pairs]
    return out if ef is None else [(a, b, ef if (a, b) == ("F", "E") else n) for a, b, n in out]


def closure_error(lk: cm.Linkage, sol: cm.LinkageSolution) -> np.ndarray:
    """Largest |(|PQ| − length)| per angle over the group's six links [m]."""
    err = [np.abs(np.linalg.norm(sol[a] - sol[b], axis=-1) - n) for a, b, n in closure_pairs(lk)]
    return np.max(err, axis=0)


def crank_tip(lk: cm.Linkage, phi: float) -> np.ndarray:
    pivot, tip = lk._driver
    return np.array(lk._points[pivot]) + lk.length(pivot, tip) * np.array(
        [math.cos(phi), math.sin(phi)]
    )


def scipy_pose(
    lk: cm.Linkage, phi: float, start: np.ndarray, ef: float | None = None
) -> tuple[np.ndarray, float]:
    """B, C, E (3, 2) closing the group at crank angle phi, by scipy's least squares
    from `start`; and the largest closure residual [m] it reached."""
    from scipy.optimize import least_squares

    fixed = {k: np.array(lk._points[k]) for k in ("A", "D")}
    fixed["F"] = crank_tip(lk, phi)
    pairs = closure_pairs(lk, ef)

    def f(x: np.ndarray) -> np.ndarray:
        pos = dict(fixed, B=x[0:2], C=x[2:4], E=x[4:6])
        return np.array([np.linalg.norm(pos[a] - pos[b]) - n for a, b, n in pairs])

    fit = least_squares(f, start.ravel(), xtol=1e-15, ftol=1e-15, gtol=1e-15)
    return fit.x.reshape(3, 2), float(np.abs(fit.fun).max())


def group(sol: cm.LinkageSolution, i: int) -> np.ndarray:
    return np.array([sol[j][i] for j in JOINTS])


def scipy_walk(lk: cm.Linkage, to: float, step: float) -> np.ndarray:
    """The drawn branch continued by scipy in small steps from the drawn angle to `to`."""
    pose = np.array([lk._points[j] for j in JOINTS])
    n = max(2, math.ceil(abs(to - lk.drawn_angle) / step))
    for phi in np.linspace(lk.drawn_angle, to, n + 1)[1:]:
        pose, res = scipy_pose(lk, phi, pose)
        assert res < 1e-12
    return pose


def bracketing_assembles(lk: cm.Linkage, phi: np.ndarray, samples: int = 1440) -> np.ndarray:
    """:func:`_bracketing` in chunks of angles (bounded memory)."""
    return np.concatenate(
        [_bracketing(lk, phi[i : i + 128], samples) for i in range(0, phi.size, 128)]
    )


def _bracketing(lk: cm.Linkage, phi: np.ndarray, samples: int) -> np.ndarray:
    """The seed's bracketing in numpy: open the group at C, turn B about A over a full
    turn (ψ), place E on circle(B, |BE|) ∩ circle(F, |EF|) (both), C rigidly on the
    triangle B–C–E with the drawn orientation, and look for a sign change of
    |C − D| − |DC| over ψ. True where some assembly exists."""
    a, d = np.array(lk._points["A"]), np.array(lk._points["D"])
    pv, tp = lk._driver
    f_tip = np.array(lk._points[pv]) + lk.length(pv, tp) * np.stack([np.cos(phi), np.sin(phi)], -1)
    l1, l2, l5 = lk.length("A", "B"), lk.length("D", "C"), lk.length("E", "F")
    l3, l4, ce = lk.length("B", "C"), lk.length("B", "E"), lk.length("C", "E")
    pts = {k: np.array(v) for k, v in lk._points.items()}
    (bc, be) = (pts["C"] - pts["B"], pts["E"] - pts["B"])
    turn = np.sign(bc[0] * be[1] - bc[1] * be[0])
    at_b = math.acos((l3 * l3 + l4 * l4 - ce * ce) / (2 * l3 * l4))  # angle C-B-E
    rot = -turn * at_b  # from B→E to B→C
    psi = np.linspace(0, TAU, samples, endpoint=False)
    bb = a + l1 * np.stack([np.cos(psi), np.sin(psi)], -1)  # (S, 2)
    found = np.zeros(phi.shape, bool)
    for sign in (1.0, -1.0):
        e = circles(bb[None], l4, f_tip[:, None], l5, sign)  # (N, S, 2)
        u = (e - bb) * (l3 / l4)
        cs, sn = math.cos(rot), math.sin(rot)
        c = bb + np.stack([cs * u[..., 0] - sn * u[..., 1], sn * u[..., 0] + cs * u[..., 1]], -1)
        g = np.linalg.norm(c - d, axis=-1) - l2
        g = np.concatenate([g, g[:, :1]], axis=1)
        with np.errstate(invalid="ignore"):
            change = (g[:, :-1] * g[:, 1:] <= 0).any(axis=1)
        found |= change
    return found


def trimmer(l5: float) -> cm.Linkage:
    base = presets.burg_trimmer()
    lengths = dict(base._lengths)
    lengths[("E", "F")] = l5
    return cm.Linkage(base._points, base._links, base._ground, base._driver, lengths=lengths)


# ---------------------------------------------------------------- item 2
def test_item2_class3_fold_is_never_a_silent_jump():
    lk = stephenson()
    assert lk.structure[-1] == ("III", JOINTS)
    phi = np.radians(np.arange(0, 250.0001, 0.01))
    sol = lk.solve(phi)
    assert sol.ok.all() and closure_error(lk, sol).max() < 1e-12
    # On main, E jumped 0.91 m between 247.13° and 247.14° with every flag False.
    moved = np.linalg.norm(np.diff(sol.xy, axis=0), axis=2).max(axis=1)
    flagged = sol.branch_change[1:] | sol.branch_change[:-1]
    jumps = np.flatnonzero(moved > 0.05)  # elsewhere no joint moves 5 cm in 0.01°
    assert jumps.size and flagged[jumps].all(), np.degrees(phi[jumps])
    assert moved[~flagged].max() < 0.05
    # Independently (scipy from each neighbour's pose): at every flagged angle no
    # closed pose continues the neighbour's, so the jump is real and must be flagged.
    for f in np.flatnonzero(sol.branch_change):
        for nb in (f - 1, f + 1):
            pose, res = scipy_pose(lk, phi[f], group(sol, nb))
            continued = res < 1e-9 and np.abs(pose - group(sol, nb)).max() < 0.05
            assert not (continued and np.abs(pose - group(sol, f)).max() > 0.05)
        # The walk's neighbour on the drawn side is continuous with a pose that no
        # longer exists at the flagged angle: scipy cannot close the group near it.
        near = [scipy_pose(lk, phi[f], group(sol, nb)) for nb in (f - 1, f + 1)]
        assert any(
            res > 1e-9 or np.abs(p - group(sol, nb)).max() > 0.05
            for (p, res), nb in zip(near, (f - 1, f + 1), strict=True)
        )
    # Around the old silent jump every step is continuous: scipy from the neighbour
    # lands on the kernel's pose.
    for i in range(24710, 24720):
        pose, res = scipy_pose(lk, phi[i + 1], group(sol, i))
        assert res < 1e-12
        assert_allclose(pose, group(sol, i + 1), atol=1e-9)


def test_item2_class3_the_short_way_decides_which_pose_of_the_branch():
    """Ambiguous case: the drawn branch spans more than a turn (folds near 230.8° going
    down and 247.1° going up), so 240° has two poses on it. Rule: each angle is moved
    by whole turns into half a turn of the drawn angle and reached the short way,
    here downwards from 360°; scipy's continuation along that way agrees."""
    lk = stephenson()
    sol = lk.solve(np.radians([240.0]))
    assert sol.ok.all() and not sol.branch_change.any()
    want = scipy_walk(lk, math.radians(240.0 - 360.0), math.radians(0.5))
    assert_allclose(group(sol, 0), want, atol=1e-9)
    up = scipy_walk(lk, math.radians(240.0), math.radians(0.5))  # the long way
    assert np.abs(up - want).max() > 0.1  # a different pose: the rule matters


# ---------------------------------------------------------------- item 3
@pytest.mark.parametrize("start, step", [(0.0, 1.0), (0.5, 1.0), (0.03, 0.1)])
def test_item3_class3_walk_picks_up_again_after_a_gap(start, step):
    lk = trimmer(0.70)
    phi = np.radians(np.arange(start, 360.0, step))
    sol = lk.solve(phi)
    want = bracketing_assembles(lk, phi)
    # The reference finds assemblies from about 166° to 378° (18° + 360°).
    deg = np.degrees(phi)
    assert want[(deg > 170) | (deg < 15)].all() and not want[(deg > 22) & (deg < 163)].any()
    # Away from the gap's edges (1°), ok is exactly where the group assembles, on
    # every grid layout (on main: 19°–359° failed, 341 angles).
    edge = np.flatnonzero(np.diff(want.astype(int)) != 0)
    near_edge = np.zeros(phi.size, bool)
    for e in edge:
        near_edge |= np.abs(deg - deg[e]) <= 1.0
    assert (sol.ok == want)[~near_edge].all()
    assert closure_error(lk, sol)[sol.ok].max() < 1e-12
    # The re-entry after the gap is flagged, once, at the first angle re-acquired.
    (flag,) = np.flatnonzero(sol.branch_change)
    assert sol.ok[flag] and not sol.ok[flag - 1] and 160 < deg[flag] < 170
    # It is the drawn branch: scipy continues the drawing down to the same angle.
    want_pose = scipy_walk(lk, phi[flag] - TAU, math.radians(0.5))
    assert_allclose(group(sol, flag), want_pose, atol=1e-9)


@settings(max_examples=15, deadline=None)
@given(start=st.floats(0, 5), step=st.floats(0.2, 7))
def test_item3_class3_assembled_angles_do_not_depend_on_the_grid(start, step):
    lk = trimmer(0.70)
    phi = np.radians(np.arange(start, 360.0, step))
    sol = lk.solve(phi)
    want = bracketing_assembles(lk, phi)
    deg = np.degrees(phi)
    clear = (np.abs(deg - 18.6) > 1.5) & (np.abs(deg - 165.7) > 1.5)
    assert (sol.ok == want)[clear].all()
    assert sol.branch_change.sum() <= 1
    assert closure_error(lk, sol)[sol.ok].max() < 1e-12


# ---------------------------------------------------------------- item 10
def test_item10_class3_drawn_pose_that_does_not_close_fails_at_construction():
    # On main this built, and solve failed with "step 0 of the program is invalid:
    # the drawn pose does not close".
    with pytest.raises(cm.InputError) as info:
        trimmer(0.5)
    msg = str(info.value)
    assert "EF drawn 0.865 m, given 0.5 m" in msg
    assert "(B, C, E)" in msg and "drawn crank angle 0°" in msg
    assert "step 0" not in msg
    # The independent bracketing agrees there is nothing to start from near the drawing.
    base = presets.burg_trimmer()
    pose = np.array([base._points[j] for j in JOINTS])
    _, res = scipy_pose(base, 0.0, pose, ef=0.5)
    assert res > 1e-3
    lengths = dict(base._lengths)
    lengths[("E", "F")] = 0.5
    # A machine file names its source and table too.
    table = base.to_dict()
    table["lengths"] = [
        {"joints": list(k), "length": 0.5 if k == ("E", "F") else v} for k, v in lengths.items()
    ]
    with pytest.raises(cm.InputError, match=r"knife\.toml: \[linkage\]: .*EF drawn"):
        cm.Linkage.from_dict(table, "knife.toml")
    # A length that still closes near the drawing builds (the item 3 trimmer).
    assert trimmer(0.70).solve([0.0]).ok.all()


# ---------------------------------------------------------------- item 15 (class III)
def test_item15_class3_large_angles_take_bounded_time_and_reduce_modulo_a_turn():
    lk = presets.burg_trimmer()
    t0 = time.perf_counter()
    lk.solve([0.0, 1e5])  # on main 1.6 s (a walk of 1e5 rad)
    assert time.perf_counter() - t0 < 0.2
    big = np.array([0.0, 1e5, 1e9, -3e12, 1e300, -1e300])
    t0 = time.perf_counter()
    sol = lk.solve(big)  # on main: 1e9 rad took about 4.5 h, 1e300 never returned
    assert time.perf_counter() - t0 < 1.0
    assert sol.ok.all() and closure_error(lk, sol).max() < 1e-12
    # Against numpy's own reduction of the crank angle: the crank tip, and the pose
    # at the remainder solved on its own.
    for i, theta in enumerate(big[:4]):
        tip = np.array(lk._points["O"]) + 0.102 * np.array([np.cos(theta), np.sin(theta)])
        rem = math.remainder(theta, TAU)
        assert_allclose(sol["F"][i], tip, atol=abs(theta) * 1e-16 * 0.102 + 1e-15)
        assert_allclose(sol["E"][i], lk.solve([rem])["E"][0], atol=abs(theta) * 1e-15 + 1e-14)
    # Non-finite angles are a clear error naming the field.
    with pytest.raises(cm.CyclomechError, match="angles"):
        lk.solve([0.0, math.inf])


def test_item15_class3_turns_do_not_change_the_pose_even_off_a_full_turn():
    """Rule for a branch that cannot turn fully (the item 3 trimmer): θ and θ + 2πn
    are one crank position and get one pose, the one reached the short way."""
    lk = trimmer(0.70)
    phi = np.radians([10.0, 100.0, 200.0, 300.0])  # 100° is in the gap
    one = lk.solve(phi)
    for n in (-3, 1, 1000):
        other = lk.solve(phi + n * TAU)
        assert (other.ok == one.ok).all() and one.ok.sum() == 3
        assert_allclose(other.xy[one.ok], one.xy[one.ok], atol=1e-9)


# ---------------------------------------------------------------- smaller: scaled geometry
@pytest.mark.parametrize("k", [1e200, 1e-200, 2.0**-60, 1e300])
def test_smaller_class3_scaled_geometry_is_not_a_dead_centre(k):
    """On main a four-bar drawn ×1e200 or ×1e-200 was refused as a dead centre (the
    cross-product check overflowed or underflowed). Reference: the same linkage at
    unit scale, and the four-bar's closed form (Freudenstein's two circles) scaled."""
    pts = {"A": (0, 0), "B": (1, 0), "C": (3.5, 2.5), "D": (4, 0)}
    links = [("A", "B"), ("B", "C"), ("C", "D")]
    big = cm.Linkage(
        {n: (x * k, y * k) for n, (x, y) in pts.items()}, links, ["A", "D"], ("A", "B")
    )
    phi = np.linspace(0, TAU, 73)
    sol = big.solve(phi)
    assert sol.ok.all() and not sol.singular.any()
    b = np.stack([np.cos(phi), np.sin(phi)], -1)
    c = circles(b, math.hypot(2.5, 2.5), np.array([4.0, 0.0]), math.hypot(0.5, 2.5), 1.0)
    assert_allclose(sol["C"] / k, c, atol=1e-12)
    assert_allclose(sol.vel / k, cm.Linkage(pts, links, ["A", "D"], ("A", "B")).solve(phi).vel)
    # A class III group too: the Burg trimmer drawn ×k turns fully, E scaled.
    base = presets.burg_trimmer()
    scaled = cm.Linkage(
        {n: (x * k, y * k) for n, (x, y) in base._points.items()},
        base._links,
        base._ground,
        base._driver,
        lengths={p: v * k for p, v in base._lengths.items()},
    )
    want = base.solve(phi)["E"]
    got = scaled.solve(phi)
    assert got.ok.all() and not got.branch_change.any()
    assert_allclose(got["E"] / k, want, atol=1e-12)
    sw = cm.linkage.solve_geometries(scaled, phi, scaled.dimension_values[None], points=["E"])
    assert_allclose(sw.xy[0, :, 0] / k, want, atol=1e-12)
