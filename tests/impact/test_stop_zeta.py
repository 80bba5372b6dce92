"""A cam_stop's ``zeta`` (the lever's free vibration): any ζ ≥ 0. The stop's
response is the exact Duhamel solution of m q̈ + 2ζωm q̇ + mω² q = F(t) for every ζ
(critically and over-damped included) and its first rebound is the first maximum
of q, defined for every ζ; checked here against scipy's solve_ivp.
"""

from __future__ import annotations

import contextlib
import warnings
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.cli import main
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

ROOT = Path(__file__).resolve().parents[2]
LOOM = ROOT / "examples" / "stb_loom.toml"
PULSES = ("decaying", "rectangular", "triangular", "half_sine")


def _ivp_rebound(stop: cm.impact.StopImpact, v0: float) -> float:
    """The first maximum of q by solve_ivp (DOP853), segment by segment of the
    piecewise-linear pulse, then free: independent of the Duhamel recurrence."""
    shape = stop._shape()
    m, w, z = stop.mass, stop.omega_free, stop.zeta
    impulse = m * (1.0 + stop.restitution) * v0
    tb, fb = np.asarray(shape.t), np.asarray(shape.f)
    segments = [
        (tb[i], tb[i + 1], fb[i], fb[i + 1]) for i in range(len(tb) - 1) if tb[i + 1] > tb[i]
    ]
    segments.append((tb[-1], tb[-1] + 200.0 / w, 0.0, 0.0))

    def speed_falls_through_zero(t, y):
        return y[1]

    speed_falls_through_zero.terminal = True  # type: ignore[attr-defined]
    speed_falls_through_zero.direction = -1  # type: ignore[attr-defined]
    y = np.array([0.0, -v0])
    for t0, t1, f0, f1 in segments:

        def rhs(t, y, t0=t0, t1=t1, f0=f0, f1=f1):
            force = impulse * (f0 + (f1 - f0) * (t - t0) / (t1 - t0))
            return [y[1], force / m - 2.0 * z * w * y[1] - w * w * y[0]]

        sol = solve_ivp(
            rhs,
            (t0, t1),
            y,
            method="DOP853",
            rtol=1e-12,
            atol=1e-18,
            events=speed_falls_through_zero,
        )
        if sol.t_events[0].size:
            return float(sol.y_events[0][0][0])
        y = sol.y[:, -1]
    raise AssertionError("no maximum within 200 free time constants")


@pytest.mark.parametrize("pulse", PULSES)
@pytest.mark.parametrize("zeta", [0.05, 0.999999, 1.0, 1.000001, 2.5, 10.0])
def test_the_rebound_at_any_zeta_matches_solve_ivp(zeta, pulse):
    stop = cm.impact.StopImpact.example(zeta=zeta, pulse=pulse)
    v0 = float(stop.impact_speed(300.0, 40.0))
    got = float(stop.rebound(300.0, 40.0))
    assert got == pytest.approx(_ivp_rebound(stop, v0), rel=1e-8)


@settings(max_examples=25, deadline=None)
@given(
    zeta=st.floats(0.9, 6.0),
    rpm=st.floats(150.0, 500.0),
    phase=st.floats(20.0, 90.0),
    pulse=st.sampled_from(PULSES),
)
def test_the_rebound_matches_solve_ivp_around_and_above_critical(zeta, rpm, phase, pulse):
    stop = cm.impact.StopImpact.example(zeta=zeta, pulse=pulse)
    v0 = float(stop.impact_speed(rpm, phase))
    assert float(stop.rebound(rpm, phase)) == pytest.approx(_ivp_rebound(stop, v0), rel=1e-7)


def test_the_rebound_is_continuous_and_falls_through_critical_damping():
    zetas = [0.99, 0.999999, 1.0, 1.000001, 1.01]
    r = [float(cm.impact.StopImpact.example(zeta=z).rebound(300.0, 40.0)) for z in zetas]
    assert r[1] == pytest.approx(r[2], rel=1e-5) and r[3] == pytest.approx(r[2], rel=1e-5)
    assert r == sorted(r, reverse=True)  # more damping, smaller rebound


def _edit(tmp_path: Path, src: Path, old: str, new: str) -> Path:
    text = src.read_text()
    assert old in text
    path = tmp_path / src.name
    path.write_text(text.replace(old, new, 1))
    return path


@pytest.mark.parametrize("zeta", ["0.999999", "1.0", "2.5"])
def test_a_machine_file_takes_a_cam_stop_zeta_of_one_and_above(tmp_path, capsys, zeta):
    path = _edit(tmp_path, LOOM, "zeta = 0.05 ", f"zeta = {zeta} ")
    # ζ ≥ 1 is valid (an overdamped stop), but likelier a percentage: a warning
    over = float(zeta) >= 1.0
    warns = pytest.warns(cm.CyclomechWarning, match=rf"zeta = {zeta} is overdamped")
    with warns if over else contextlib.nullcontext():
        stop = cm.Machine.from_toml(path).mechanisms["lifter"].stop
    assert stop.zeta == float(zeta)
    with warnings.catch_warnings():
        warnings.simplefilter("default")
        argv = ["run", str(path), "--out", str(tmp_path / "o"), "--no-plot", "--quiet"]
        code = main([*argv, "--no-sensitivities"])
    assert code == 0
    err = capsys.readouterr().err
    assert "error" not in err and ("did you mean" in err) == over


def test_a_negative_cam_stop_zeta_is_refused(tmp_path, capsys):
    path = _edit(tmp_path, LOOM, "zeta = 0.05 ", "zeta = -0.1 ")
    assert main(["run", str(path), "--out", str(tmp_path / "o"), "--no-plot", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "stb_loom.toml" in err and "[mechanism.lifter]" in err and "zeta" in err
    assert "-0.1" in err
