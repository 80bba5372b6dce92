"""Three-position motion generation (synthesis/_motion.py): a known four-bar's
coupler poses give it back (its ground pivots as the centre points), the
centre points against the perpendicular bisectors solved with numpy, every clean
candidate of a scan analysed by the position solver passes through the poses,
the branch and order defects, and bad input."""

from __future__ import annotations

import math
import pickle

import cyclomech as cm
import numpy as np
import pytest
from cyclomech import synthesis as syn
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from numpy.testing import assert_allclose

KNOWN = {"A0": (0.0, 0.0), "A": (1.0, 0.0), "B": (3.5, 2.5), "B0": (4.0, 0.0)}


def _known_poses(angles_deg, uv=(1.2, 0.8), mirror=()):
    """Poses of the known crank-rocker's coupler (the frame at A, x along A → B,
    the pose point P at `uv` in it) at crank angles, by the position solver; the
    poses listed in `mirror` are taken on the other assembly."""
    out = []
    for i, th in enumerate(angles_deg):
        pts = dict(KNOWN)
        if i in mirror:  # B reflected through the line B0 → A: the other branch
            pts["B"] = (3.5, -2.5)
        lk = cm.Linkage(pts, [("A0", "A"), ("A", "B"), ("B", "B0")], ["A0", "B0"], ("A0", "A"))
        sol = lk.solve([math.radians(th)])
        a, b = sol["A"][0], sol["B"][0]
        ang = math.atan2(b[1] - a[1], b[0] - a[0])
        p = a + np.array(
            [
                uv[0] * math.cos(ang) - uv[1] * math.sin(ang),
                uv[0] * math.sin(ang) + uv[1] * math.cos(ang),
            ]
        )
        out.append((float(p[0]), float(p[1]), math.degrees(ang)))
    return out


def _frame(pose, xy):
    """World point xy in the coupler frame of `pose`."""
    x, y, t = pose
    c, s = math.cos(math.radians(t)), math.sin(math.radians(t))
    dx, dy = xy[0] - x, xy[1] - y
    return (c * dx + s * dy, -s * dx + c * dy)


def _passes_through(cand, poses, atol=1e-9):
    """The candidate's Linkage, solved at its crank angles, puts P and the
    coupler's angle at the poses."""
    sol = cand.linkage().solve(np.radians(cand.crank_angles_deg))
    assert sol.ok.all()
    assert_allclose(sol["P"], [p[:2] for p in poses], atol=atol)
    # The coupler's angle: the line A → B turns with the pose angle.
    ab = sol["B"] - sol["A"]
    turn = np.degrees(np.arctan2(ab[:, 1], ab[:, 0]))
    want = np.array([p[2] for p in poses])
    d = (turn - turn[0]) - (want - want[0])
    assert_allclose(np.radians((d + 180) % 360 - 180), 0, atol=atol)


def test_a_known_four_bar_is_recovered_from_three_coupler_poses() -> None:
    poses = _known_poses([20, 70, 130])
    # Its moving pivots, in the coupler frame of pose 1, are the circle points.
    lk = cm.Linkage(KNOWN, [("A0", "A"), ("A", "B"), ("B", "B0")], ["A0", "B0"], ("A0", "A"))
    sol = lk.solve(np.radians([20.0]))
    uv1 = _frame(poses[0], sol["A"][0])
    uv2 = _frame(poses[0], sol["B"][0])
    (c,) = syn.motion_generation(poses, circle_points=(uv1, uv2))
    assert_allclose(c.centre_points, [(0, 0), (4, 0)], atol=1e-12)
    assert_allclose(
        [c.lengths[k] for k in ("crank", "coupler", "rocker", "ground")],
        [1, math.hypot(2.5, 2.5), math.hypot(0.5, 2.5), 4],
        rtol=1e-12,
    )
    assert_allclose(c.crank_angles_deg, [20, 70, 130], atol=1e-10)
    assert c.direction == 1 and c.clean
    assert c.margins.grashof == "crank-rocker"
    _passes_through(c, poses)
    assert pickle.loads(pickle.dumps(c)) == c


def _standard_form_dyad(poses, beta2_deg, beta3_deg):
    """Erdman & Sandor's standard-form dyad (*Mechanism Design*, vol. 1, ch. 8),
    a different method: with the crank's rotations β2, β3 chosen, solve
    W(e^{iβj} − 1) + Z(e^{iαj} − 1) = δj (j = 2, 3) for the link W (ground pivot
    → moving pivot) and Z (moving pivot → pose point), complex and linear."""
    p = np.array([complex(x, y) for x, y, _ in poses])
    alpha = np.radians([t - poses[0][2] for _, _, t in poses])
    beta = np.radians([0.0, beta2_deg, beta3_deg])
    m = np.array([[np.exp(1j * beta[j]) - 1, np.exp(1j * alpha[j]) - 1] for j in (1, 2)])
    w, z = np.linalg.solve(m, p[1:] - p[0])
    moving = p[0] - z
    return moving - w, moving  # ground pivot, moving pivot (pose 1)


@pytest.mark.parametrize(
    ("betas", "poses", "clean"),
    [
        (((40, 95), (-30, -70)), [(0.0, 0.0, 0.0), (0.5, 0.2, 20.0), (0.9, 0.6, 45.0)], False),
        (((25, 60), (15, 50)), [(1.0, 2.0, 30.0), (1.4, 2.1, 10.0), (1.9, 1.8, -15.0)], True),
    ],
)
def test_centre_points_match_the_standard_form_dyads(betas, poses, clean) -> None:
    (g1, m1), (g2, m2) = (_standard_form_dyad(poses, *b) for b in betas)
    uv1 = _frame(poses[0], (m1.real, m1.imag))
    uv2 = _frame(poses[0], (m2.real, m2.imag))
    (c,) = syn.motion_generation(poses, circle_points=(uv1, uv2))
    assert_allclose(c.centre_points, [(g1.real, g1.imag), (g2.real, g2.imag)], atol=1e-12)
    # The crank turns by the β's chosen for its dyad.
    turn = np.array(c.crank_angles_deg) - c.crank_angles_deg[0]
    assert_allclose((turn[1:] - betas[0] + 180) % 360 - 180, 0, atol=1e-9)
    assert c.clean == clean
    if clean:
        _passes_through(c, poses)
    else:
        # The branch defect is real: driven from pose 1 on its branch, the
        # solver's linkage misses the poses reached on the other one.
        assert c.branch_defect
        sol = c.linkage().solve(np.radians(c.crank_angles_deg))
        miss = np.linalg.norm(sol["P"] - [p[:2] for p in poses], axis=1)
        bad = [i for i, b in enumerate(c.branches) if b != c.branches[0]]
        assert (miss[bad] > 1e-3).all() or not sol.ok[bad].all()


@settings(max_examples=60, deadline=None)
@given(
    xy=st.lists(st.floats(-1, 1), min_size=6, max_size=6),
    t=st.lists(st.floats(-90, 90), min_size=3, max_size=3),
    uv=st.tuples(st.floats(-1, 1), st.floats(-1, 1)),
)
def test_centre_points_are_the_bisectors_intersection(xy, t, uv) -> None:
    poses = [(xy[0], xy[1], t[0]), (xy[2], xy[3], t[1]), (xy[4], xy[5], t[2])]
    try:
        (c,) = syn.motion_generation(poses, circle_points=(uv, (uv[0] + 0.3, uv[1] - 0.2)))
    except cm.InputError:
        return
    q = []
    for x, y, th in poses:
        a = math.radians(th)
        q.append(
            (
                x + uv[0] * math.cos(a) - uv[1] * math.sin(a),
                y + uv[0] * math.sin(a) + uv[1] * math.cos(a),
            )
        )
    q = np.array(q)
    # 2 (q_k − q_0) · o = |q_k|² − |q_0|², k = 1, 2.
    m = 2 * (q[1:] - q[0])
    rhs = (q[1:] ** 2).sum(axis=1) - (q[0] ** 2).sum()
    assume(abs(np.linalg.det(m)) > 1e-6)
    o = np.linalg.solve(m, rhs)
    assert_allclose(c.centre_points[0], o, atol=1e-8 * (1 + np.abs(o).max()))


@settings(max_examples=12, deadline=None)
@given(
    d2=st.tuples(st.floats(0.2, 1.0), st.floats(-0.5, 0.5), st.floats(-40, 40)),
    d3=st.tuples(st.floats(0.2, 1.0), st.floats(0.2, 1.0), st.floats(-60, 60)),
)
def test_every_clean_candidate_passes_through_the_poses(d2, d3) -> None:
    poses = [(0.0, 0.0, 0.0), (d2[0], d2[1], d2[2]), (d2[0] + d3[0], d2[1] + d3[1], d3[2])]
    try:
        found = syn.motion_generation(poses, grid=(1.0, 4), keep=6)
    except cm.InputError:
        return
    for c in found:
        if not c.clean:
            continue
        _passes_through(c, poses, atol=1e-8)
        # Margins against the solver sampled over the working arc.
        lo, hi = c.working_arc_deg
        sol = c.linkage().solve(np.radians(np.linspace(lo, hi, 721)))
        assert sol.ok.all()
        u, v = sol["A"] - sol["B"], sol["B0"] - sol["B"]
        mu = np.degrees(
            np.arccos(
                np.clip(
                    np.sum(u * v, axis=1) / np.linalg.norm(u, axis=1) / np.linalg.norm(v, axis=1),
                    -1,
                    1,
                )
            )
        )
        assert mu.min() >= c.margins.transmission_min_deg - 1e-7
        assert mu.max() <= c.margins.transmission_max_deg + 1e-7
    keys = [
        (not c.clean, -np.nan_to_num(c.margins.worst_transmission_deg, nan=-1.0)) for c in found
    ]
    assert keys == sorted(keys)


def test_branch_defect_a_pose_on_the_other_assembly() -> None:
    poses = _known_poses([20, 70, 130], mirror=(2,))
    lk = cm.Linkage(KNOWN, [("A0", "A"), ("A", "B"), ("B", "B0")], ["A0", "B0"], ("A0", "A"))
    sol = lk.solve(np.radians([20.0]))
    (c,) = syn.motion_generation(
        poses, circle_points=(_frame(poses[0], sol["A"][0]), _frame(poses[0], sol["B"][0]))
    )
    assert_allclose(c.centre_points, [(0, 0), (4, 0)], atol=1e-12)  # the same four-bar
    assert len(set(c.branches)) == 2 and c.branch_defect and not c.clean


def test_order_defect_a_rocker_meeting_the_poses_out_of_order() -> None:
    # A non-Grashof triple-rocker (3, 3, 3, 4): its crank cannot pass 180°.
    pts = {"A0": (0.0, 0.0), "A": (3.0, 0.0), "B0": (4.0, 0.0)}
    pts["B"] = (3.5, math.sqrt(9 - 0.25))  # |B − A| = |B − B0| = 3
    lk = cm.Linkage(pts, [("A0", "A"), ("A", "B"), ("B", "B0")], ["A0", "B0"], ("A0", "A"))
    th = [-40.0, 40.0, 0.0]  # pose 3 lies between poses 1 and 2: out of order
    sol = lk.solve(np.radians(th))
    assert sol.ok.all()
    poses = []
    for k in range(3):
        a, b = sol["A"][k], sol["B"][k]
        poses.append((float(a[0]), float(a[1]), math.degrees(math.atan2(*(b - a)[::-1]))))
    (c,) = syn.motion_generation(poses, circle_points=((0.0, 0.0), (3.0, 0.0)))
    assert_allclose(c.centre_points, [(0, 0), (4, 0)], atol=1e-12)
    assert c.margins.grashof == "triple-rocker"
    assert c.order_defect and not c.branch_defect and not c.clean
    # In order it is clean.
    (ok,) = syn.motion_generation(
        [poses[0], poses[2], poses[1]], circle_points=((0.0, 0.0), (3.0, 0.0))
    )
    assert not ok.order_defect and ok.clean


@pytest.mark.parametrize(
    ("args", "kwargs", "needle"),
    [
        ([(0, 0, 0), (1, 0, 10)], {}, "needs 3, 4 or 5 poses"),
        ([(0, 0, 0), (1, 0, 10), (2, 1, 20), (3, 1, 5), (4, 0, 0), (5, 0, 9)], {}, "Burmester"),
        ([(0, 0, 0), (1, 0, 10), (0, 0, 360)], {}, "poses[0] and poses[2] are coincident"),
        ([(0, 0, 0), (1, 0, 0), (2.5, 0, 0)], {"circle_points": ((0.3, 0.2), (0, 1))}, "slider"),
        ([(0, 0, 0), (1, 0, 0), (2.5, 0, 0)], {}, "no pair of circle points"),
        ([(0, 0, 0), (0, 0, 30), (1, 0, 60)], {"circle_points": ((0, 0), (1, 1))}, "pole"),
        (
            [(0, 0, 0), (1, 0, 10), (2, 1, 20)],
            {"circle_points": ((0, 0),)},
            "circle_points must be",
        ),
        ([(0, 0, 0), (1, 0, 10), (2, 1, 20)], {"grid": (1.0, 99)}, "grid[1]"),
        ([(0, 0, 0), (1, 0, 10), (2, 1, 20)], {"grid": (-1.0, 5)}, "grid[0]"),
        ([(0, 0), (1, 0), (2, 1)], {}, "poses must be (x [m], y [m], angle [deg])"),
    ],
)
def test_bad_input_says_what_and_which(args, kwargs, needle) -> None:
    with pytest.raises(cm.InputError) as info:
        syn.motion_generation(args, **kwargs)
    assert needle in str(info.value)
