"""The main shaft's torsion and the working members' dynamic errors (issue 34 item 3)
against independent references: scipy's solve_ivp on the chain's equations written
here in time (a different integrator, variable and step), closed forms, and the
rigid machine's steady state as the shaft grows stiff."""

from __future__ import annotations

import math

import cyclomech as cm
import numpy as np
import pytest
from cyclomech import InputError, SolverError
from scipy.integrate import solve_ivp

N = 720
PHI = np.arange(N) * (2 * np.pi / N)


def _chain_rhs(nodes, motor_torque, j_head, members):
    """The chain in time: state (φ₀, ω₀, φ_1, ω_1, …, u, u̇ per member)."""
    n = len(nodes)

    def f(_t, z):
        phi = z[0 : 2 * n + 2 : 2]
        w = z[1 : 2 * n + 2 : 2]
        s = [
            nd["c"] * (phi[k] - phi[k + 1]) + nd["d"] * (w[k] - w[k + 1])
            for k, nd in enumerate(nodes)
        ]
        out = np.zeros_like(z)
        out[0], out[1] = w[0], (motor_torque(w[0]) - s[0]) / j_head
        accs = []
        for k, nd in enumerate(nodes):
            p, v = phi[k + 1], w[k + 1]
            nxt = s[k + 1] if k + 1 < n else 0.0
            jj, dj, q = nd["J"](p), nd["dJ"](p), nd["Q"](p)
            a = (s[k] - nxt - 0.5 * dj * v * v - q) / (jj + nd["hub"])
            out[2 + 2 * k], out[3 + 2 * k] = v, a
            accs.append(a)
        at = 2 * n + 2
        for k, (wn, zeta, d1, d2) in members.items():
            p, v = phi[k + 1], w[k + 1]
            u, du = z[at], z[at + 1]
            yy = d2(p) * v * v + d1(p) * accs[k]
            out[at], out[at + 1] = du, -yy - 2 * zeta * wn * du - wn * wn * u
            at += 2
        return out

    return f


def test_a_motor_driven_chain_against_solve_ivp():
    """Two mechanisms on an elastic shaft under a linear motor: the steady state
    against solve_ivp (Radau-free explicit DOP853 to 1e-11) run long enough to
    settle, compared over the last cycle at the same head angles."""
    a_j, a_q = (0.02, 0.01, 0.0), (3.0, 2.0, 0.0)  # J = a0 + a1 cos 2φ, Q = q0 + q1 sin φ
    b_j, b_q = (0.01, 0.005, 0.0), (1.0, 0.0, 1.5)  # Q = q0 + q2 cos φ

    def curves(jc, qc):
        j = jc[0] + jc[1] * np.cos(2 * PHI)
        dj = -2 * jc[1] * np.sin(2 * PHI)
        q = qc[0] + qc[1] * np.sin(PHI) + qc[2] * np.cos(PHI)
        return j, dj, q

    amp = 0.01
    member = cm.dynamics.WorkingMember(
        amp * np.sin(PHI),
        amp * np.cos(PHI),
        -amp * np.sin(PHI),
        frequency_hz=40.0,
        damping_ratio=0.1,
    )
    nodes = [
        cm.dynamics.ShaftNode("a", *curves(a_j, a_q), 0.05, 2e3, 1.5),
        cm.dynamics.ShaftNode("b", *curves(b_j, b_q), 0.03, 1e3, 1.0, member),
    ]
    motor = cm.dynamics.LinearMotor(20.0, 300.0)  # stall torque [N·m], no-load speed [rpm]
    t = cm.dynamics.torsion(nodes, motor=motor, head_inertia_kg_m2=0.3, start_rpm=250.0)

    spec = [
        {
            "J": lambda p, c=a_j: c[0] + c[1] * np.cos(2 * p),
            "dJ": lambda p, c=a_j: -2 * c[1] * np.sin(2 * p),
            "Q": lambda p, c=a_q: c[0] + c[1] * np.sin(p) + c[2] * np.cos(p),
            "hub": 0.05,
            "c": 2e3,
            "d": 1.5,
        },
        {
            "J": lambda p, c=b_j: c[0] + c[1] * np.cos(2 * p),
            "dJ": lambda p, c=b_j: -2 * c[1] * np.sin(2 * p),
            "Q": lambda p, c=b_q: c[0] + c[1] * np.sin(p) + c[2] * np.cos(p),
            "hub": 0.03,
            "c": 1e3,
            "d": 1.0,
        },
    ]
    wn = 2 * np.pi * 40.0
    members = {1: (wn, 0.1, lambda p: amp * np.cos(p), lambda p: -amp * np.sin(p))}
    no_load = 300.0 * np.pi / 30
    f = _chain_rhs(spec, lambda w: 20.0 * (1 - w / no_load), 0.3, members)
    w0 = 250.0 * np.pi / 30
    z0 = np.array([0.0, w0, 0.0, w0, 0.0, w0, 0.0, 0.0])
    # settle (the slow mode: the motor's slope over the whole inertia), then one cycle
    sol = solve_ivp(f, (0, 40.0), z0, method="DOP853", rtol=1e-11, atol=1e-12)
    z = sol.y[:, -1].copy()
    turns = np.ceil(z[0] / (2 * np.pi))
    target = turns * 2 * np.pi + np.radians(t.theta_deg)

    def at_angle(ev_phi):
        def ev(_t, zz):
            return zz[0] - ev_phi

        ev.terminal = False
        return ev

    events = [at_angle(p) for p in target[::60]]
    sol2 = solve_ivp(f, (0, 2.0), z, method="DOP853", rtol=1e-11, atol=1e-12, events=events)
    for i, ys in zip(range(0, N, 60), sol2.y_events, strict=True):
        y = ys[0]
        assert y[1] == pytest.approx(t.omega[i], rel=1e-7)
        assert y[0] - y[2] == pytest.approx(t.twist_rad[0, i], rel=1e-5, abs=1e-9)
        assert y[0] - y[4] == pytest.approx(t.twist_rad[1, i], rel=1e-5, abs=1e-9)
        # the member's error: Π(φ_b) − Π(φ₀) + u
        e = amp * np.sin(y[4]) - amp * np.sin(y[0]) + y[6]
        assert e == pytest.approx(t.error["b"][0, i], rel=1e-5, abs=1e-10)


def test_the_steady_state_repeats():
    """One more cycle from the returned state's first angle comes back to it: the
    twist at the last sample runs smoothly into the first (a periodic curve)."""
    j = 0.01 + 0.005 * np.cos(2 * PHI)
    node = cm.dynamics.ShaftNode("a", j, -0.01 * np.sin(2 * PHI), 2 + np.sin(PHI), 0.02, 5e3, 1.0)
    t = cm.dynamics.torsion([node], rpm=200.0, tol=1e-12)
    tw = t.twist_rad[0]
    # the periodic extension's step at the seam is a step like any other
    seam = abs(tw[0] - tw[-1])
    assert seam <= 1.05 * np.abs(np.diff(tw)).max()
    assert t.residual <= 1e-12


def test_stiffer_shaft_smaller_error_and_rigid_limit():
    member = cm.dynamics.WorkingMember(0.02 * np.sin(PHI), 0.02 * np.cos(PHI), -0.02 * np.sin(PHI))
    peaks = []
    for c in (1e3, 1e4, 1e5, 1e6, 1e7):
        node = cm.dynamics.ShaftNode(
            "a",
            np.zeros(N),
            np.zeros(N),
            4 + 3 * np.sin(PHI),
            0.01,
            c,
            2 * 0.1 * math.sqrt(c * 0.01),
            member,
        )
        peaks.append(cm.dynamics.torsion([node], rpm=100.0).peak_error["a"])
    ratios = np.array(peaks[:-1]) / np.array(peaks[1:])
    assert (ratios > 8).all(), ratios  # ~ 1/c: the static lag dominates at this speed
    assert peaks[-1] < 2e-8


def test_event_lag_is_the_twist():
    node = cm.dynamics.ShaftNode("a", np.zeros(N), np.zeros(N), np.full(N, 10.0), 0.05, 1e4, 10.0)
    t = cm.dynamics.torsion([node], rpm=60.0)
    assert t.lag_deg("a", [0.0, 123.4, 720.0]) == pytest.approx(np.degrees(10.0 / 1e4), rel=1e-9)
    with pytest.raises(InputError, match="'b' is not a node"):
        t.lag_deg("b", 0.0)


def test_limit_rpm_takes_the_first_crossing():
    """A link resonance between two speeds: the error rises past the bound, then
    falls back under it at a higher speed; the limit is the first crossing."""
    member = cm.dynamics.WorkingMember(
        0.01 * np.sin(PHI),
        0.01 * np.cos(PHI),
        -0.01 * np.sin(PHI),
        frequency_hz=10.0,
        damping_ratio=0.05,
    )
    # no load on the shaft: it does not twist, the error is the link's alone
    node = cm.dynamics.ShaftNode(
        "a", np.zeros(N), np.zeros(N), np.zeros(N), 0.05, 1e4, 20.0, member
    )
    rpm = np.linspace(60.0, 1800.0, 30)
    s = cm.dynamics.torsion_sweep([node], rpm)
    e = s.peak_error[:, 0]
    # base excitation of the member by sin φ: |u| = A r²/|1 − r² + 2iζr|, r = ω/ω_n
    r = rpm * np.pi / 30 / (2 * np.pi * 10.0)
    closed = 0.01 * r**2 / np.abs(1 - r**2 + 2j * 0.05 * r)
    # e = u here (an unloaded shaft): |e| peaks at |u|
    assert e == pytest.approx(closed, rel=2e-4)
    bound = 0.012
    above = closed > bound
    assert above.any() and not above[-1]  # back under the bound at the top speed
    lim = s.limit_rpm("a", bound)
    first = int(np.argmax(above))
    assert rpm[first - 1] < lim <= rpm[first]
    assert s.limit_rpm("a", 1.0) == math.inf


def test_bad_input_names_the_field():
    good = dict(
        name="a",
        inertia_kg_m2=np.zeros(8),
        d_inertia=np.zeros(8),
        load_torque_nm=np.ones(8),
        hub_inertia_kg_m2=0.1,
        stiffness_nm_per_rad=1e4,
    )
    with pytest.raises(InputError, match="stiffness_nm_per_rad"):
        cm.dynamics.ShaftNode(**{**good, "stiffness_nm_per_rad": -1.0})
    with pytest.raises(InputError, match="hub_inertia_kg_m2"):
        cm.dynamics.ShaftNode(**{**good, "hub_inertia_kg_m2": 0.0})
    with pytest.raises(InputError, match="damping_nm_s_per_rad"):
        cm.dynamics.ShaftNode(**{**good, "damping_nm_s_per_rad": -2.0})
    with pytest.raises(InputError, match="damping_ratio"):
        cm.dynamics.WorkingMember(np.zeros(8), np.zeros(8), np.zeros(8), damping_ratio=-0.1)
    with pytest.raises(InputError, match="frequency_hz"):
        cm.dynamics.WorkingMember(np.zeros(8), np.zeros(8), np.zeros(8), frequency_hz=0.0)
    node = cm.dynamics.ShaftNode(**good)
    with pytest.raises(InputError, match="either rpm"):
        cm.dynamics.torsion([node])
    with pytest.raises(InputError, match="head_inertia_kg_m2"):
        cm.dynamics.torsion([node], motor=cm.dynamics.LinearMotor(10.0, 100.0))
    with pytest.raises(InputError, match="names"):
        cm.dynamics.torsion([node, node], rpm=10.0)
    with pytest.raises(InputError, match="increase"):
        cm.dynamics.torsion_sweep([node], [20.0, 10.0])


def test_an_undamped_chain_is_a_solver_error():
    node = cm.dynamics.ShaftNode("a", np.zeros(8), np.zeros(8), 1 + np.sin(PHI[::90]), 0.1, 1e4)
    with pytest.raises(SolverError, match=r"not settled.*damping"):
        cm.dynamics.torsion([node], rpm=60.0, max_cycles=30)
