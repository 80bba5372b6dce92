"""The kernels fuzzed (issue 16): every public kernel of cyclomech._core and the
public numeric functions of cm.impact / cm.transfer / cm.motion, called with
arbitrary floats, return or refuse within a time bound; the calls the harness
found raising Python's arithmetic errors are InputErrors, and their valid
neighbours keep their closed forms."""

from __future__ import annotations

import contextlib
import math
import os
import subprocess
import sys

import cyclomech as cm
import numpy as np
import pytest
from cyclomech import _core
from hypothesis import given, settings
from hypothesis import strategies as st

# ---------------------------------------------------------------------------
# The fuzzing harness: every public kernel of cyclomech._core and the public
# numeric functions of cm.impact / cm.transfer / cm.motion, called with arbitrary
# floats. Each call must return or raise CyclomechError/TypeError (a clear
# refusal), within a time bound. Calls run in a worker process, so that a hang
# (or a crash) fails the test instead of hanging CI; the worker is restarted
# after one. CI runs FUZZ_EXAMPLES examples per callable (~30 s in all); set
# CYCLOMECH_FUZZ_EXAMPLES for a longer campaign.

FUZZ_EXAMPLES = int(
    os.environ.get("CYCLOMECH_FUZZ_EXAMPLES", "12" if os.environ.get("CI") else "60")
)
#: Seconds one fuzzed call may take (the kernels answer in milliseconds).
CALL_BOUND_S = 20.0

# The worker reads (steps) pickled on stdin and answers one line per request.
# A step is (callable, args, kwargs); a callable "cyclomech.x.y" is imported, ".m"
# is the method m of the previous step's result.
WORKER = r"""
import importlib, pickle, sys, warnings
warnings.simplefilter("ignore")
import cyclomech
inp, out = sys.stdin.buffer, sys.stdout
while True:
    try:
        steps = pickle.load(inp)
    except EOFError:
        break
    try:
        prev = None
        for name, args, kwargs in steps:
            if name.startswith("."):
                f = getattr(prev, name[1:])
            else:
                mod, _, attr = name.rpartition(".")
                try:
                    f = getattr(importlib.import_module(mod), attr)
                except ModuleNotFoundError:
                    mod, _, cls = mod.rpartition(".")
                    f = getattr(getattr(importlib.import_module(mod), cls), attr)
            prev = f(*args, **kwargs)
        res = "ok"
    except (cyclomech.CyclomechError, TypeError):
        res = "refused"
    except BaseException as e:
        res = "WRONG " + type(e).__module__ + "." + type(e).__qualname__ + ": " + str(e)[:300]
    out.write(res.replace("\n", " ") + "\n")
    out.flush()
"""


class Worker:
    """One worker process; restarted after a hang or a crash."""

    proc: subprocess.Popen | None = None

    @classmethod
    def call(cls, steps):
        import pickle
        import select

        if cls.proc is None or cls.proc.poll() is not None:
            cls.proc = subprocess.Popen(
                [sys.executable, "-c", WORKER],
                stdin=subprocess.PIPE,
                stdout=subprocess.PIPE,
                stderr=subprocess.DEVNULL,
                text=False,
                env={**os.environ, "RAYON_NUM_THREADS": "1"},
            )
        p = cls.proc
        try:
            pickle.dump(steps, p.stdin)
            p.stdin.flush()
        except BrokenPipeError:
            code = cls.stop(kill=True)
            return f"WRONG the process died before reading the call (exit status {code})"
        ready, _, _ = select.select([p.stdout], [], [], CALL_BOUND_S)
        if not ready:
            cls.stop(kill=True)
            return f"HANG (still running after {CALL_BOUND_S} s)"
        line = p.stdout.readline().decode()
        if not line:
            code = cls.stop(kill=True)
            return f"WRONG the process died (exit status {code})"
        return line.strip()

    @classmethod
    def stop(cls, kill=False):
        p, cls.proc = cls.proc, None
        if p is None:
            return None
        if kill:
            p.kill()
        for f in (p.stdin, p.stdout):
            with contextlib.suppress(OSError):
                f.close()
        return p.wait(timeout=30)


@pytest.fixture(scope="module", autouse=False)
def worker():
    yield Worker
    Worker.stop()


# Arbitrary floats: NaN, ±inf, subnormals, huge and tiny magnitudes, and the
# ordinary values where the interesting branches are.
ANY = st.floats(allow_nan=True, allow_infinity=True) | st.sampled_from(
    [0.0, -0.0, 1.0, -1.0, 0.5, 2.0, 1e-300, 1e300, 5e-324, math.nan, math.inf, -math.inf]
)
NICE = st.floats(-10.0, 10.0) | st.sampled_from([1e-9, 1e9, 0.0])
F = ANY | NICE


def floats(n):
    return st.tuples(*[F] * n)


def arr(min_size=0, max_size=6):
    return st.lists(F, min_size=min_size, max_size=max_size).map(
        lambda v: np.array(v, dtype=np.float64)
    )


def rows(cols, max_rows=3):
    return st.lists(st.tuples(*[F] * cols), min_size=0, max_size=max_rows).map(
        lambda v: np.array(v, dtype=np.float64).reshape(-1, cols)
    )


def one(name, *args, **kwargs):
    return [(name, args, kwargs)]


@st.composite
def batch(draw, name, **extra):
    t = draw(arr(1, 5))
    b = draw(st.integers(1, 3))
    forces = draw(st.lists(st.tuples(*[F] * len(t)), min_size=b, max_size=b))
    cases = [np.array(draw(st.tuples(*[F] * b)), dtype=np.float64) for _ in range(5)]
    return one(name, t, np.array(forces, dtype=np.float64), *cases, **extra)


@st.composite
def graph(draw, name, extra):
    n = draw(st.integers(1, 4))
    e = draw(st.integers(0, 5))
    idx = st.integers(0, n - 1)
    src = np.array(draw(st.lists(idx, min_size=e, max_size=e)), dtype=np.int64)
    dst = np.array(draw(st.lists(idx, min_size=e, max_size=e)), dtype=np.int64)
    w = [np.array(draw(st.tuples(*[F] * e)), dtype=np.float64) for _ in range(extra)]
    return n, src, dst, w


LAWS = st.sampled_from(["cycloidal", "simple_harmonic", "modified_trapezoid", "bogus"])
C = "cyclomech._core."
IM = "cyclomech.impact."
T = "cyclomech.transfer."
M = "cyclomech.motion."

TARGETS = {
    # --- cyclomech._core kernels
    "_core.duhamel": st.tuples(arr(0, 5), arr(0, 5), floats(5)).map(
        lambda a: one(C + "duhamel", a[0], a[1], *a[2])
    ),
    "_core.duhamel_batch": batch(C + "duhamel_batch"),
    "_core.first_rebound_batch": st.booleans().flatmap(
        lambda mx: batch(C + "first_rebound_batch", maximum=mx)
    ),
    "_core.contact_response": st.tuples(floats(8), F, st.integers(-2, 50)).map(
        lambda a: one(C + "contact_response", *a[0], t_end=a[1], max_rebounds=a[2], max_events=50)
    ),
    "_core.contact_sample": st.tuples(floats(8), arr(0, 4)).map(
        lambda a: one(C + "contact_sample", *a[0], a[1], max_events=50)
    ),
    "_core.contact_rebound_batch": st.tuples(floats(6), arr(0, 4)).map(
        lambda a: one(C + "contact_rebound_batch", *a[0], a[1])
    ),
    "_core.press_check": floats(6).map(lambda a: one(C + "press_check", *a)),
    "_core.press_solve": st.tuples(rows(6), arr(0, 4)).map(
        lambda a: one(C + "press_solve", a[0], a[1])
    ),
    "_core.pareto_mask": st.integers(1, 3).flatmap(rows).map(lambda a: one(C + "pareto_mask", a)),
    "_core.longest_path": graph(C + "longest_path", 1).map(
        lambda g: one(C + "longest_path", g[0], g[1], g[2], g[3][0])
    ),
    "_core.max_cycle_ratio": graph(C + "max_cycle_ratio", 2).map(
        lambda g: one(C + "max_cycle_ratio", g[0], g[1], g[2], *g[3])
    ),
    "_core.max_speed": st.tuples(graph(C + "max_speed", 3), F).map(
        lambda a: one(C + "max_speed", a[0][0], a[0][1], a[0][2], *a[0][3], a[1])
    ),
    "_core.max_difference": st.tuples(graph(C + "max_difference", 1), st.integers(-1, 4)).map(
        lambda a: one(C + "max_difference", a[0][0], a[0][1], a[0][2], a[0][3][0], 0, a[1])
    ),
    "_core.EventGraph.latest": st.tuples(graph(C + "EventGraph", 1), F).map(
        lambda a: [(C + "EventGraph", a[0][:3], {}), (".latest", (a[0][3][0], a[1]), {})]
    ),
    "_core.MotionLaw.eval": st.tuples(LAWS, st.booleans(), arr(0, 5), st.integers(-1, 4)).map(
        lambda a: [(C + "MotionLaw.named", (a[0], a[1]), {}), (".eval", (a[2], a[3]), {})]
    ),
    "_core.MotionLaw.polynomial": st.tuples(arr(0, 7), st.booleans(), arr(0, 4)).map(
        lambda a: [(C + "MotionLaw.polynomial", (a[0], a[1]), {}), (".eval", (a[2], 1), {})]
    ),
    "_core.servo_duty": st.tuples(arr(0, 5), arr(0, 5), floats(5), arr(0, 3), st.booleans()).map(
        lambda a: one(C + "servo_duty", a[0], a[1], *a[2], a[3], curves=a[4])
    ),
    "_core.servo_size": st.tuples(
        arr(0, 5), arr(0, 5), floats(3), arr(0, 3), F, *[arr(0, 3)] * 5, F
    ).map(lambda a: one(C + "servo_size", *a)),
    # --- cm.impact
    "impact.lever_stiffness": floats(4).map(lambda a: one(IM + "lever_stiffness", *a)),
    "impact.propped_lever_stiffness": floats(5).map(
        lambda a: one(IM + "propped_lever_stiffness", *a)
    ),
    "impact.natural_frequency": floats(2).map(lambda a: one(IM + "natural_frequency", *a)),
    "impact.contact_time": floats(2).map(lambda a: one(IM + "contact_time", *a)),
    "impact.Pulse": st.tuples(
        st.sampled_from(["rectangular", "decaying", "triangular", "half_sine"]), floats(2)
    ).map(lambda a: [(IM + "Pulse." + a[0], a[1], {}), (".scaled", (2.0,), {})]),
    "impact.duhamel": st.tuples(arr(0, 5), arr(0, 5), floats(5)).map(
        lambda a: one(IM + "duhamel", a[0], a[1], *a[2])
    ),
    "impact.first_rebound": st.tuples(arr(0, 5), arr(0, 5), floats(5), st.booleans()).map(
        lambda a: one(IM + "first_rebound", a[0], a[1], *a[2], maximum=a[3])
    ),
    "impact.contact_response": floats(7).map(
        lambda a: one(
            IM + "contact_response",
            **dict(
                zip(
                    ["mass", "k_free", "k_stop", "preload", "zeta_free", "x0", "v0"], a, strict=True
                )
            ),
            max_rebounds=5,
        )
    ),
    "impact.contact_sample": st.tuples(arr(0, 4), floats(4)).map(
        lambda a: one(
            IM + "contact_sample",
            a[0],
            **dict(zip(["mass", "k_free", "k_stop", "v0"], a[1], strict=True)),
        )
    ),
    "impact.min_phase_angles": st.tuples(arr(0, 4), F).map(
        lambda a: one(IM + "min_phase_angles", *a)
    ),
    "impact.StopImpact": st.tuples(floats(3), F, F).map(
        lambda a: [
            (
                IM + "StopImpact.example",
                (),
                dict(zip(["mass", "zeta", "stroke"], a[0], strict=True)),
            ),
            (".min_phase_angle", (a[1], a[2]), {}),
        ]
    ),
    "impact.rebounds": st.tuples(st.sampled_from(["pulse", "contact"]), arr(0, 3)).map(
        lambda a: [
            (IM + "StopImpact.example", (), {"model": a[0]}),
            (".rebound", (300.0, 30.0), {}),
            (IM + "rebounds", ([cm.impact.StopImpact.example(model=a[0])], a[1][None]), {}),
        ]
    ),
    # --- cm.transfer
    "transfer.acceleration_jump": floats(4).map(lambda a: one(T + "acceleration_jump", *a)),
    "transfer.acceleration_jump_at_speed": floats(3).map(
        lambda a: one(T + "acceleration_jump_at_speed", *a)
    ),
    "transfer.quintic_transition": st.tuples(floats(4), arr(0, 4)).map(
        lambda a: [(T + "quintic_transition", a[0], {}), (".curvature", (a[1],), {})]
    ),
    "transfer.smooth_transition": st.tuples(floats(2), arr(0, 4)).map(
        lambda a: [(T + "smooth_transition", a[0], {}), (".arc_length", (a[1],), {})]
    ),
    "transfer.TransferPath": st.tuples(floats(2), floats(2), F, st.integers(-5, 200)).map(
        lambda a: [
            (T + "TransferPath", (a[0][0], a[0][1], (0.0, 0.0), a[1]), {"x2": a[2]}),
            (".sample", (a[3],), {}),
        ]
    ),
    "transfer.TransferPath.max_jerk": st.tuples(F, st.integers(-5, 300)).map(
        lambda a: [
            (T + "TransferPath", (0.15, 0.25, (0, 0), (0.41, 0)), {"x2": 0.05}),
            (".max_jerk", (a[0], a[1]), {}),
        ]
    ),
    # --- cm.motion
    "motion.law": st.tuples(LAWS, st.sampled_from(["half", "rise", "bogus"]), arr(0, 4)).map(
        lambda a: [(M + "law", (a[0], a[1]), {}), (".dz", (a[2],), {})]
    ),
    "motion.polynomial": st.tuples(arr(0, 7), arr(0, 4)).map(
        lambda a: [(M + "polynomial", (a[0],), {}), (".ddz", (a[1],), {})]
    ),
    "motion.two_period": st.tuples(floats(4), arr(0, 4)).map(
        lambda a: [
            (
                M + "two_period",
                (a[0][0], a[0][1], "cycloidal", "cycloidal"),
                {"asymmetry": a[0][2], "accel_ratio": None, "max_speed": None},
            ),
            (".acceleration", (a[1],), {}),
        ]
    ),
}


@pytest.mark.parametrize("target", sorted(TARGETS))
def test_fuzz_returns_or_refuses_within_a_time_bound(worker, target):
    @settings(max_examples=FUZZ_EXAMPLES, deadline=None, database=None)
    @given(steps=TARGETS[target])
    def check(steps):
        outcome = worker.call(steps)
        assert outcome in ("ok", "refused"), f"{outcome}\n  call: {steps!r}"

    check()


# Item 19: calls the harness found raising OverflowError, ZeroDivisionError or
# numpy's ValueError on main, now an InputError naming the input; the valid
# neighbours still give the closed forms.
WRONG_TYPES = [
    (lambda: _core.MotionLaw.named("cycloidal", False).eval(np.zeros(2), -1), "order"),
    # Rule: lengths of the path in [1e-60, 1e60] m, so that x2**5 and 1/x2**5
    # are normal floats (at 4.5e61 x2**5 overflowed, or a5 became 0 silently).
    (lambda: cm.transfer.quintic_transition(1.0, 0.0, 0.0, 1e-300), r"x2 = 1e-300 m must lie"),
    (lambda: cm.transfer.quintic_transition(1.0, 0.0, 0.0, 4.5e61), r"x2 = 4.5e\+61 m must lie"),
    (lambda: cm.transfer.quintic_transition(1.0, 1e300, 0.0, 1e10), "overflows"),
    (lambda: cm.transfer.smooth_transition(1.0, 1.3407807929942597e154), "overflows"),
    (lambda: cm.impact.lever_stiffness(1.0, 1.0, 1.0, 4.6e-191), "scale the units"),
    # (a = 3.4e15 was here: the unfactored f_mm − f_mc²/f_cc cancelled to garbage;
    # factored it gives the right 6.0, see the test below. 1e308 still overflows.)
    (lambda: cm.impact.propped_lever_stiffness(1.0, 1.0, 1e308, 2.0, 1.0), "scale the units"),
    (lambda: cm.transfer.TransferPath(5e-324, 5e-324, (0, 0), (0, 0.5), x2=1.0), "R_t"),
]


def test_a_propped_lever_with_a_huge_span_is_its_limit():
    """a = 3.4e15 m against b = 2, at = 1: the long span restrains the roller's slope
    not at all, so the propped overhang tends to a beam simply supported at the
    roller and the stop, 3·E·J·b/(s²(b − s)²) = 6 N/m; the free one is
    3EJ/(s²(a + s)). (The fuzz had it as an error: the unfactored form cancelled.)"""
    free, propped = cm.impact.propped_lever_stiffness(1.0, 1.0, 3.4e15, 2.0, 1.0)
    assert free == pytest.approx(3.0 / (3.4e15 + 1.0), rel=1e-12)
    assert propped == pytest.approx(6.0, rel=1e-12)


@pytest.mark.parametrize("call, match", WRONG_TYPES)
def test_item19_fuzzed_calls_raise_input_errors_not_python_arithmetic_errors(call, match):
    with pytest.raises(cm.InputError, match=match):
        call()


def test_item19_valid_neighbours_of_the_fuzzed_calls_keep_their_closed_forms():
    # c = 3EJ/((a+b)b²) by hand; cycloidal half law's velocity at 0 is 0.
    assert cm.impact.lever_stiffness(2.1e11, 6.1e-11, 0.05, 0.1) == pytest.approx(
        3 * 2.1e11 * 6.1e-11 / (0.15 * 0.01), rel=1e-15
    )
    q = cm.transfer.smooth_transition(0.15, 0.06)
    assert q.coeffs[2] == pytest.approx(1 / 0.3, rel=1e-15)
    np.testing.assert_allclose(
        _core.MotionLaw.named("cycloidal", True).eval(np.array([0.0, 0.5, 1.0]), 0),
        [0.0, 0.5, 1.0],
        atol=1e-15,
    )
