"""The speed-limit search of a design sweep in one Rust call (issue 20):
``SpeedNetwork.speed_limits_proportional`` must give, bit for bit, what the
Python search ``SpeedNetwork.speed_limits`` (the general path, the reference)
gives with the same speed-proportional bounds; and both must be the speed
limit: checked against scipy's LP over the event angles and the speed, against
Howard's ``Cyclogram.max_speed_rpm`` (a proportional bound is a duration of
per_rpm/6 s), and by fitting just below and not just above."""

from __future__ import annotations

import math
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
from cyclomech._arrays import SPEED_CAP_RPM
from cyclomech._kind import Proportional
from cyclomech.cyclogram import SpeedNetwork
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy.optimize import linprog


def python_limits(net: SpeedNetwork, per: np.ndarray, start: float, rtol: float) -> np.ndarray:
    """The Python search with the same bounds (the reference)."""

    def at(designs, rpm):
        rows = rpm.reshape(-1)
        m = rpm.shape[1]
        return [
            Proportional.evaluate(rows, np.repeat(per[designs, k], m)) for k in range(per.shape[1])
        ]

    return net.speed_limits(at, per.shape[0], start, 1, rtol)


@st.composite
def networks(draw):
    """A random cyclogram: a chain of 2–6 events (maybe closed into a ring whose
    last operation crosses into the next cycle), a chord, angles, durations,
    maximum angles, a single-operation constraint; 0–3 proportional bounds on
    random operations; 1–6 designs of slopes (0, tiny, huge, or ~the ring's)."""
    n = draw(st.integers(2, 6))
    cg = cm.Cyclogram(limiting=("e0", "e1"))
    arcs = [(f"e{i}", f"e{i + 1}") for i in range(n - 1)]
    for a, b in arcs:
        cg.add_operation(
            a,
            b,
            min_angle_deg=draw(st.floats(0.0, 120.0)),
            min_duration_s=draw(st.sampled_from([0.0, 0.0, 0.01, 0.03]) | st.floats(1e-4, 0.05)),
            max_angle_deg=draw(st.none() | st.floats(150.0, 300.0)),
        )
    if n > 2 and draw(st.booleans()):
        a = draw(st.integers(0, n - 3))
        arcs.append((f"e{a}", f"e{n - 1}"))
        cg.add_operation(*arcs[-1], min_angle_deg=draw(st.floats(0.0, 200.0)))
    if draw(st.booleans()):
        cg.add_constraint({arcs[-1]: 1.0}, ">=", draw(st.floats(0.0, 90.0)), name="user")
    if draw(st.booleans()):  # the ring closed into the next cycle
        arcs.append((f"e{n - 1}", "e0"))
        cg.add_operation(*arcs[-1], min_angle_deg=draw(st.floats(0.0, 90.0)), height=1)
    k = draw(st.integers(0, 3))
    bounds = [(draw(st.sampled_from(arcs)), f"b{i}") for i in range(k)]
    net = SpeedNetwork(cg, bounds)
    slope = st.sampled_from([0.0, 1e-12, 1e3, 1e9]) | st.floats(1e-4, 2.0)
    d = draw(st.integers(1, 6))
    per = np.array([[draw(slope) for _ in range(k)] for _ in range(d)]).reshape(d, k)
    start = draw(st.sampled_from([1.0, 100.0, 500.0, SPEED_CAP_RPM]) | st.floats(1.0, 5e3))
    rtol = draw(st.sampled_from([1e-10, 1e-14, 0.5]) | st.floats(1e-12, 1e-3))
    return net, per, start, rtol


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(networks())
def test_bit_for_bit_the_python_search(case) -> None:
    net, per, start, rtol = case
    want = python_limits(net, per, start, rtol)
    got = net.speed_limits_proportional(per, start, 1, rtol)
    assert np.array_equal(got, want), (got, want)
    assert np.array_equal(net.speed_limits_proportional(per, start, 2, rtol), want)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(networks(), st.lists(st.floats(1e-6, 3e3) | st.sampled_from([1e-6, 1e6]), max_size=12))
def test_solve_is_bit_for_bit_the_python_solve(case, speeds) -> None:
    net, per, _, _ = case
    rpm = np.array(speeds, dtype=np.float64)
    rows = np.tile(rpm, per.shape[0])
    t_bound = [
        Proportional.evaluate(rows, np.repeat(per[:, k], rpm.size)) for k in range(per.shape[1])
    ]
    value, fits, named, mins = net.solve(rows, t_bound, 1)
    for threads in (1, 2):
        v, f, n, t = net.solve_proportional(per, rpm, threads)
        assert np.array_equal(v, value, equal_nan=True)
        assert np.array_equal(f, fits)
        assert (n == named).all(), (n, named)
        assert np.array_equal(t, mins[:, net.bound_op].reshape(rows.size, len(net.bound_op)))


def loom_case(n_designs: int = 40) -> tuple[SpeedNetwork, np.ndarray, float]:
    loom = cm.Machine.from_toml("tests/machine/data/stb_loom_stop_only.toml")
    per0 = loom.bound_laws()[0].per_rpm
    per = per0 * np.geomspace(0.05, 20.0, n_designs)[:, None]
    return loom.speed_network, per, loom.search_start_rpm


def test_the_loom_bit_for_bit_and_threads() -> None:
    net, per, start = loom_case()
    want = python_limits(net, per, start, 1e-10)
    for threads in (1, 2):
        assert np.array_equal(net.speed_limits_proportional(per, start, threads), want)


def lp_limit(net: SpeedNetwork, per_row: np.ndarray) -> float:
    """The largest n with the difference system feasible, by scipy's LP over
    the node angles and n (the proportional bounds as their lines, no floor)."""
    V = net.n
    rows, rhs = [], []

    def arc(s: int, d: int, w: float, coef_n: float = 0.0) -> None:
        r = np.zeros(V + 1)
        r[d] += 1.0
        r[s] -= 1.0
        r[V] = coef_n
        rows.append(r)
        rhs.append(w)

    for e in range(net.src.size):
        arc(int(net.src[e]), int(net.dst[e]), float(net.base[e]))
    for o, e in enumerate(net.min_edge.tolist()):
        s, d, b = int(net.src[e]), int(net.dst[e]), float(net.base[e])
        arc(s, d, b - net.angle[o])
        if net.secs[o] > 0:
            arc(s, d, b, 6.0 * net.secs[o])
    for k, o in enumerate(net.bound_op):
        e = int(net.min_edge[o])
        arc(int(net.src[e]), int(net.dst[e]), float(net.base[e]), float(per_row[k]))
    c = np.zeros(V + 1)
    c[V] = -1.0
    bounds = [(None, None)] * V + [(0.0, SPEED_CAP_RPM)]
    res = linprog(c, A_ub=np.array(rows), b_ub=np.array(rhs), bounds=bounds, method="highs")
    assert res.status == 0, res.message
    return float(res.x[V])


def test_the_loom_limit_is_scipy_lp() -> None:
    net, per, start = loom_case(12)
    got = net.speed_limits_proportional(per, start)
    checked = 0
    for lim, row in zip(got.tolist(), per, strict=True):
        if row[0] * lim > 360.0 * (1 - 1e-9):
            continue  # capped by the 360° rule, not by the network
        assert lim == pytest.approx(lp_limit(net, row), rel=1e-8)
        checked += 1
    assert checked >= 8


@pytest.mark.parametrize("per", [0.05, 0.2, 0.45, 0.7])
def test_a_chain_limit_is_howard(per) -> None:
    # The bound n·per on a→b is a duration of per/6 s: Howard's cycle ratio.
    def chain(secs: float) -> cm.Cyclogram:
        cg = cm.Cyclogram(limiting=("c", "d"))
        cg.add_operation("a", "b", min_angle_deg=40, min_duration_s=secs)
        cg.add_operation("b", "c", min_angle_deg=30, min_duration_s=0.01)
        cg.add_operation("c", "d", min_angle_deg=60)
        return cg

    net = SpeedNetwork(chain(0.02), [(("a", "b"), "r")])
    got = float(net.speed_limits_proportional(np.array([[per]]), 100.0)[0])
    want = chain(max(0.02, per / 6.0)).max_speed_rpm().rpm
    assert got == pytest.approx(want, rel=1e-9)
    assert got == pytest.approx(lp_limit(net, np.array([per])), rel=1e-9)


def test_fits_just_below_not_just_above() -> None:
    net, per, start = loom_case(8)
    got = net.speed_limits_proportional(per, start)

    def fits(rpm: np.ndarray) -> np.ndarray:
        tb = [Proportional.evaluate(rpm, per[:, k]) for k in range(per.shape[1])]
        return net.solve(rpm, tb, labels=False)[1]

    assert fits(got).all()
    assert not fits(got * (1 + 1e-9)).any()


def test_ends_of_the_range_and_no_bounds() -> None:
    cg = cm.Cyclogram(limiting=("b", "c"))
    cg.add_operation("a", "b", min_angle_deg=100)
    cg.add_operation("b", "c", min_angle_deg=60)
    net = SpeedNetwork(cg, [(("a", "b"), "r")])
    # 0: fits at the cap; 1e12: over 360° already at the floor; 0.5: 300/0.5.
    got = net.speed_limits_proportional(np.array([[0.0], [1e12], [0.5]]), 100.0)
    assert got[0] == math.inf and got[1] == 0.0
    assert got[2] == pytest.approx(600.0, rel=1e-10) and got[2] <= 600.0
    plain = SpeedNetwork(cg)
    assert plain.speed_limits_proportional(np.empty((3, 0)), 100.0).tolist() == [math.inf] * 3


def test_constraints_over_several_operations_take_the_python_search() -> None:
    cg = cm.Cyclogram(limiting=("b", "c"))
    cg.add_operation("a", "b", min_angle_deg=100, min_duration_s=0.02)
    cg.add_operation("b", "c", min_angle_deg=60)
    cg.add_constraint({("a", "b"): 1.0, ("b", "c"): 1.0}, "<=", 300.0, name="pair")
    net = SpeedNetwork(cg, [(("a", "b"), "r")])
    per = np.array([[0.1], [0.3]])
    assert net.general
    assert np.array_equal(
        net.speed_limits_proportional(per, 100.0), python_limits(net, per, 100.0, 1e-10)
    )
    rpm = np.array([100.0, 500.0, 900.0])
    rows = np.tile(rpm, 2)
    t_bound = [Proportional.evaluate(rows, np.repeat(per[:, 0], 3))]
    value, _, named, mins = net.solve(rows, t_bound)
    v, _, n, t = net.solve_proportional(per, rpm)
    assert np.array_equal(v, value, equal_nan=True) and (n == named).all()
    assert np.array_equal(t[:, 0], mins[:, 0])


def test_bad_inputs_are_input_errors() -> None:
    net, per, start = loom_case(2)
    with pytest.raises(cm.InputError, match=r"per_rpm must be \(designs, 1\)"):
        net.speed_limits_proportional(per[:, 0], start)
    with pytest.raises(ValueError, match="rtol"):
        net.speed_limits_proportional(per, start, rtol=0.0)
    with pytest.raises(cm.InputError, match="n_threads"):
        net.speed_limits_proportional(per, start, n_threads=0)


@pytest.mark.parametrize("batch", [True, False])
def test_no_productivity_above_a_mechanisms_own_limit(batch):
    # Found by a new user's trial: the rotor line's sweep gave productivity 240/min
    # at 240 rpm, above its transfer's jerk limit (221.76 rpm), where fits (the
    # cyclogram's alone) is True. The machine does not work there: productivity 0.
    m = cm.Machine.from_toml(Path(__file__).resolve().parents[2] / "examples" / "rotor_line.toml")
    own = m.speed_limit().mechanisms_rpm["line"]
    rpm = [200.0, own * (1 - 1e-12), own * (1 + 1e-12), 240.0]
    r = cm.sweep(m, {"speed_rpm": rpm}, batch=batch)
    assert r.columns["fits"].tolist() == [True] * 4
    assert r.columns["productivity_per_min"].tolist() == [200.0, rpm[1], 0.0, 0.0]
    s = m.speed_sweep(rpm)
    assert s.productivity_per_min.tolist() == [200.0, rpm[1], 0.0, 0.0]
