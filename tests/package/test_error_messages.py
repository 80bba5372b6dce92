"""The exact text and class of the errors the Rust core raises, domain by domain.

Every domain's core error used to repeat the same variants (a bad scalar, a
non-finite array entry, a bad thread count, an output array that cannot be
filled); they now share one type (``rust/core/src/input.rs``) that each domain
wraps. The messages are a public contract (users match on them, results folders
record them), so each repeated variant is triggered here through the extension
module, in each domain that has it, and its text is checked against a literal:
byte for byte, before and after the sharing.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import cyclomech as cm
import numpy as np
import pytest
from cyclomech import _core


def f64(*values: float) -> np.ndarray:
    return np.array(values, dtype=np.float64)


def i64(*values: int) -> np.ndarray:
    return np.array(values, dtype=np.int64)


#: A servo load (φ_L′, φ_L″ at 4 angles, J_L, T_ext, η) for the servo kernels.
SERVO = (f64(0.0, 1.0, 0.0, -1.0), f64(1.0, 0.0, -1.0, 0.0), 0.1, 0.0, 1.0)


def cam() -> _core.CamKernel:
    """A rise and a return of 10 mm over half a turn each, flat-faced follower."""
    return _core.CamKernel(
        ["rise", "return"], [math.pi] * 2, [0.01] * 2, ["cycloidal"] * 2, "flat", [0.05], False
    )


def linkage_program() -> Any:
    four_bar = cm.Linkage(
        {"A": (0, 0), "B": (1, 0), "C": (3.5, 2.5), "D": (4, 0)},
        [("A", "B"), ("B", "C"), ("C", "D")],
        ["A", "D"],
        ("A", "B"),
    )
    return four_bar._program


def force_model() -> _core.ForceModel:
    """One body on two points, the first grounded; no guides, no gravity."""
    return _core.ForceModel(
        2,
        i64(0, 2),
        i64(0, 1),
        f64(1.0),
        np.zeros((1, 2)),
        f64(0.0),
        i64(0),
        f64(0, 0),
        np.zeros((0, 4), dtype=np.int64),
        np.zeros((0, 2)),
        0,
        f64(0, 0),
    )


def cycloidal() -> _core.MotionLaw:
    return _core.MotionLaw.named("cycloidal", True)


def two_period() -> _core.TwoPeriodKernel:
    return _core.TwoPeriodKernel(cycloidal(), cycloidal(), 0.5, 1.0, 1.0, 2.0)


#: A press design (R, r, d, l, φ0, offset) with R/r = 3, a whole number.
PRESS = np.array([[0.9, 0.3, 0.2, 1.0, 0.0, 0.0]])

#: One duhamel_batch case: force 0 on t = 0, 1; ω_n = 1 rad/s, ζ = 0.1, m = 1 kg.
IMPACT = (f64(0, 1), np.zeros((1, 2)), f64(1), f64(0.1), f64(1), f64(0), f64(0))

THREADS = "n_threads must be an integer between 1 and 1024; got 0"

#: (domain and variant, call, exception class, exact message)
CASES: list[tuple[str, Callable[[], object], type[Exception], str]] = [
    # The thread count, refused by every domain that runs on the pool.
    ("parallel", lambda: _core.threads(0), cm.InputError, THREADS),
    (
        "cyclogram threads",
        lambda: _core.longest_path(2, i64(0), i64(1), f64(1.0), n_threads=0),
        cm.InputError,
        THREADS,
    ),
    (
        "linkage threads",
        lambda: linkage_program().solve(np.zeros(3), i64(0, 1), n_threads=0),
        cm.InputError,
        THREADS,
    ),
    ("cam threads", lambda: cam().solve(np.zeros(3), n_threads=0), cm.InputError, THREADS),
    (
        "cam vibration threads",
        lambda: _core.cam_residual_ratio("cycloidal", f64(1.0), 0.1, n_threads=0),
        cm.InputError,
        THREADS,
    ),
    (
        "servo threads",
        lambda: _core.servo_duty(*SERVO, 1.0, 1.0, f64(1.0), n_threads=0),
        cm.InputError,
        THREADS,
    ),
    (
        "shaft threads",
        lambda: _core.shaft_stats(np.ones(4), np.ones(4), f64(1.0), 0.1, n_threads=0),
        cm.InputError,
        THREADS,
    ),
    (
        "motion threads",
        lambda: cycloidal().eval(np.zeros(3), 0, n_threads=0),
        cm.InputError,
        THREADS,
    ),
    (
        "motion two-period threads",
        lambda: two_period().eval(f64(0.0), 0, n_threads=0),
        cm.InputError,
        THREADS,
    ),
    (
        "impact threads",
        lambda: _core.duhamel_batch(*IMPACT, n_threads=0),
        cm.InputError,
        THREADS,
    ),
    (
        "press threads",
        lambda: _core.press_solve(PRESS, f64(0.0), n_threads=0),
        cm.InputError,
        THREADS,
    ),
    (
        "transfer threads",
        lambda: _core.transfer_quintic(np.zeros(6), np.zeros(3), "y", n_threads=0),
        cm.InputError,
        THREADS,
    ),
    (
        "forces threads",
        lambda: force_model().solve(
            np.zeros((1, 2, 2)), np.zeros((1, 2, 2)), np.zeros((1, 2, 2)), n_threads=0
        ),
        cm.InputError,
        THREADS,
    ),
    # A NaN or an infinity in an array.
    (
        "cam not finite",
        lambda: cam().solve(f64(0.0, np.nan)),
        cm.InputError,
        "theta[1] = NaN is not finite",
    ),
    (
        "cam vibration not finite",
        lambda: _core.cam_follower_response(
            ["rise", "return"],
            [math.pi] * 2,
            [0.01] * 2,
            ["cycloidal"] * 2,
            10.0,
            100.0,
            0.1,
            f64(0.0, np.nan),
        ),
        cm.InputError,
        "theta[1] = NaN is not finite",
    ),
    (
        "servo not finite",
        lambda: _core.servo_duty(
            f64(0.0, np.nan), f64(0.0, 0.0), 1.0, 0.0, 1.0, 1.0, 1.0, f64(1.0)
        ),
        cm.InputError,
        "vel[1] = NaN is not finite",
    ),
    (
        "shaft not finite",
        lambda: _core.shaft_sum(np.array([[1.0, 2.0, np.nan]]), f64(0.0)),
        cm.InputError,
        "curves[2] = NaN is not finite",
    ),
    (
        "motion not finite",
        lambda: cycloidal().eval(f64(0.0, np.inf), 0),
        cm.InputError,
        "x[1] = inf is not finite",
    ),
    (
        "motion program not finite",
        lambda: cm.motion.Program([cm.motion.Segment("dwell", 360)])._kernel.eval(f64(0.0, np.nan)),
        cm.InputError,
        "theta[1] = NaN is not finite",
    ),
    (
        "motion two-period not finite",
        lambda: two_period().eval(f64(0.0, np.nan), 0),
        cm.InputError,
        "alpha[1] = NaN is not finite",
    ),
    (
        "press not finite",
        lambda: _core.press_solve(PRESS, f64(np.nan)),
        cm.InputError,
        "alpha[0] = NaN is not finite",
    ),
    (
        "transfer not finite",
        lambda: _core.transfer_quintic(np.zeros(6), f64(0, np.nan), "y"),
        cm.InputError,
        "x[1] = NaN is not finite",
    ),
    # A scalar outside the values its key takes.
    (
        "cam bad value",
        lambda: cam().loads(np.zeros(3), float("nan"), (1.0, 0.0, 0.0, [0.0, 0.0])),
        cm.InputError,
        "omega = NaN [rad/s] must be finite",
    ),
    (
        "servo bad value (efficiency)",
        lambda: _core.servo_duty(f64(0.0, 1.0), f64(0.0, 0.0), 1.0, 0.0, 1.5, 1.0, 1.0, f64(1.0)),
        cm.InputError,
        "efficiency = 1.5 must be in (0, 1]",
    ),
    (
        "servo bad value (a ratio)",
        lambda: _core.servo_size(
            *SERVO, f64(2.0, -1.0), 0.0, f64(1.0), f64(3.0), f64(1.0), f64(300.0), f64(1.0), 10.0
        ),
        cm.InputError,
        "ratio = -1 (at index 1) must be > 0",
    ),
    (
        "servo bad value (a count)",
        lambda: _core.servo_duty(f64(0.0), f64(0.0), 1.0, 0.0, 1.0, 1.0, 1.0, f64(1.0)),
        cm.InputError,
        "samples = 1 must be >= 2 angles over the cycle, the same for vel and acc (acc has 1)",
    ),
    (
        "shaft bad value (a count)",
        lambda: _core.shaft_sum(np.array([[1.0, 2.0]]), f64(0.0)),
        cm.InputError,
        "samples = 2 must be >= 3 points over the turn",
    ),
    (
        "shaft bad value",
        lambda: _core.shaft_stats(np.ones(4), np.ones(4), f64(1.0), -0.1),
        cm.InputError,
        "speed_fluctuation = -0.1 (δ) must be finite and > 0",
    ),
    (
        "press bad design",
        lambda: _core.press_check(1.0, -0.3, 0.2, 1.0, 0.0, 0.0),
        cm.InputError,
        "r = -0.3 must be a positive radius [m]",
    ),
    (
        "transfer bad value",
        lambda: _core.transfer_longest((1.0, 1.0), float("nan"), (0.5, 0.5)),
        cm.InputError,
        "distance = NaN must be finite and above R_t + R_p (the centres' distance)",
    ),
    (
        "cyclogram bad scalar",
        lambda: _core.EventGraph(2, i64(0), i64(1)).latest(f64(1.0), float("nan")),
        cm.InputError,
        "horizon = NaN is invalid: the horizon must be a finite angle in degrees",
    ),
    (
        "cyclogram bad scalar (max_speed)",
        lambda: _core.max_speed(2, i64(0), i64(1), f64(1.0), f64(1.0), f64(1.0), float("nan")),
        cm.InputError,
        "cycle_deg = NaN is invalid: the cycle must be a finite positive number of degrees"
        " (360 for one revolution)",
    ),
    # An array that is not C-contiguous (said through each domain's own variant).
    (
        "servo layout",
        lambda: _core.servo_duty(np.ones(8)[::2], np.ones(4), 1.0, 0.0, 1.0, 1.0, 1.0, f64(1.0)),
        cm.InputError,
        "vel = NaN must be a C-contiguous array",
    ),
    (
        "shaft layout",
        lambda: _core.shaft_sum(np.ones((1, 8))[:, ::2], f64(0.0)),
        cm.InputError,
        "curves = NaN must be a C-contiguous array",
    ),
    (
        "cyclogram layout",
        lambda: _core.longest_path(3, i64(0, 1), i64(1, 2), np.ones(4)[::2]),
        cm.InputError,
        "weights = NaN is invalid: the array must be C-contiguous",
    ),
    (
        "cam layout",
        lambda: cam().solve(np.zeros(6)[::2]),
        cm.InputError,
        "follower theta = NaN must be a C-contiguous array",
    ),
    (
        "transfer layout",
        lambda: _core.transfer_quintic(np.zeros(12)[::2], np.zeros(3), "y"),
        cm.InputError,
        "coeffs must be a C-contiguous array",
    ),
    # An output array the kernel cannot fill in place.
    (
        "cyclogram output",
        lambda: _core.EventGraph(2, i64(0), i64(1)).longest_path(f64(1.0), out=np.zeros(3)),
        cm.InputError,
        "out must be a writeable C-contiguous float64 array of shape (1, 2);"
        " got another object or dtype",
    ),
    (
        "impact output",
        lambda: _core.duhamel_batch(*IMPACT, out=np.zeros(5)),
        cm.InputError,
        "out must be a writeable C-contiguous float64 array of shape (B, N) = (1, 2)"
        " that overlaps no input; got ndarray with dtype float64 and shape (5,)",
    ),
    # Domain-specific variants beside the shared ones keep their own classes.
    (
        "cyclogram cycle",
        lambda: _core.longest_path(2, i64(0, 1), i64(1, 0), f64(1.0, 1.0)),
        cm.CycleError,
        "the arcs contain a cycle through events [0, 1]; the operations of one machine cycle"
        " must form an acyclic graph",
    ),
    (
        "cam vibration (an impact parameter)",
        lambda: _core.cam_residual_ratio("cycloidal", f64(1.0), -0.1),
        cm.InputError,
        "zeta must be finite and in [0, 1) (an under-damped follower); got -0.1",
    ),
]


@pytest.mark.parametrize(
    ("call", "cls", "message"), [c[1:] for c in CASES], ids=[c[0] for c in CASES]
)
def test_each_core_error_keeps_its_class_and_text(
    call: Callable[[], object], cls: type[Exception], message: str
) -> None:
    with pytest.raises(cm.CyclomechError) as err:
        call()
    assert type(err.value) is cls
    assert str(err.value) == message


def test_a_bad_thread_count_in_the_environment_names_the_variable(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setenv("CYCLOMECH_THREADS", " x7")
    with pytest.raises(cm.InputError) as err:
        _core.transfer_quintic(np.zeros(6), np.zeros(3), "y")
    assert str(err.value) == (
        'environment variable CYCLOMECH_THREADS must be an integer between 1 and 1024; got " x7"'
    )
