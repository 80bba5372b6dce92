"""The rotor transfer's Rust kernels (issue 20) against today's numpy code path,
kept as the reference in ``tests/transfer/transfer_reference.py``: the quintic's values,
curvature and arc length, the composed path's sample, the kinematics for a speed
law, the longest transitions and the design's candidate scan.

Tolerances (relative to each array's scale): 1e-12. The kernels evaluate the
same formulas in the same order (Horner, the same Gauss–Legendre nodes, numpy's
``linspace``), so most values agree to a few ulps; what differs, and why it
stays within 1e-12:

* (1 + y'²)^{3/2} as (1 + y'²)·√(1 + y'²) (numpy: ``pow``): an ulp.
* Arc sines and cosines rotated from an exact pair every 64 points: 1e-16 m.
* The heading's atan a branchless Cephes atan (within 2 ulps, tested in Rust).
* Running sums (arc length along the transitions, time) restarted every 4096
  points — from the 16-point quadrature for the arc length, from the blocks'
  totals for the time — instead of one ``cumsum``: rounding of ≤ 4096 terms.
* The design's minimiser sees peak jerks equal to ~1e-15; its answer is kept to
  its own tolerance (xatol = 1e-6 of the bracket).
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
from cyclomech import _core
from cyclomech import transfer as tr
from cyclomech.transfer._path import _longest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from numpy.testing import assert_array_equal

sys.path.insert(0, str(Path(__file__).parent))
import transfer_reference as ref

RTOL = 1e-12
FAST = settings(max_examples=40, deadline=None)


def close(got: np.ndarray, want: np.ndarray, rtol: float = RTOL, what: str = "") -> None:
    """|got − want| ≤ rtol · max|want| (element-wise, on the array's scale)."""
    got, want = np.asarray(got), np.asarray(want)
    assert got.shape == want.shape, what
    scale = float(np.max(np.abs(want))) if want.size else 0.0
    err = float(np.max(np.abs(got - want))) if want.size else 0.0
    assert err <= rtol * max(scale, 1e-300), f"{what}: error {err:.3g} on scale {scale:.3g}"


radii = st.floats(0.02, 1.0)
gaps = st.floats(1e-3, 0.2)


@FAST
@given(
    R=st.floats(1e-3, 10.0),
    k=st.floats(-2.0, 2.0),
    b=st.floats(-0.05, 0.05),
    x2=st.floats(1e-3, 1.0),
)
def test_quintic_values_and_arc_length_equal_the_numpy_code(R, k, b, x2):
    q = tr.quintic_transition(R, k, b, x2)
    x = np.linspace(-0.2 * x2, x2, 257).reshape(1, 257)
    for order, method in enumerate((q.y, q.dy, q.ddy, q.dddy)):
        close(method(x), ref.poly(q, x, order), what=f"order {order}")
    kappa, rate = ref.curvature(q, x)
    close(q.curvature(x), kappa, what="curvature")
    close(q.curvature_rate(x), rate, what="curvature_rate")
    close(q.arc_length(x), ref.arc_length(q, x), what="arc_length")
    assert q.length == pytest.approx(float(ref.arc_length(q, q.x2)), rel=RTOL)
    assert isinstance(q.y(0.5 * x2), float)


def _path(R_t, R_p, gap, f_t, f_p, angle, ccw):
    d = R_t + R_p + gap
    c_p = (d * math.cos(angle), d * math.sin(angle))
    top = _longest(np.array([R_t, R_p]), np.zeros(2), np.array(c_p), np.ones(2))[0]
    return tr.TransferPath(R_t, R_p, (0.0, 0.0), c_p, x2=(f_t * top, f_p * top), ccw=ccw)


def _compare_samples(p, n, threads=None):
    got = p.sample(n, n_threads=threads)
    want = ref.sample(p, n)
    assert_array_equal(got.piece, want.piece)
    close(got.points, want.points, what="points")
    close(got.s, want.s, what="s")
    close(got.heading, want.heading, what="heading")
    close(got.curvature, want.curvature, what="curvature")
    close(got.curvature_rate, want.curvature_rate, what="curvature_rate")


@FAST
@given(
    R_t=radii,
    R_p=radii,
    gap=gaps,
    f_t=st.floats(0.05, 1.0),
    f_p=st.floats(0.05, 1.0),
    angle=st.floats(-math.pi, math.pi),
    ccw=st.booleans(),
    n=st.integers(10, 30_000),
)
def test_sample_equals_the_numpy_code(R_t, R_p, gap, f_t, f_p, angle, ccw, n):
    _compare_samples(_path(R_t, R_p, gap, f_t, f_p, angle, ccw), n)


@pytest.mark.parametrize("n", [10, 11, 2001, 100_003])
def test_sample_equals_the_numpy_code_on_the_readme_path(n):
    p = tr.TransferPath(0.15, 0.25, (0.0, 0.0), (0.41, 0.0), x2=0.04)
    _compare_samples(p, n)


def test_sample_does_not_depend_on_the_thread_count():
    p = tr.TransferPath(0.15, 0.25, (0.0, 0.0), (0.41, 0.0), x2=0.04)
    one, two = p.sample(200_001, n_threads=1), p.sample(200_001, n_threads=2)
    for f in ("points", "s", "heading", "curvature", "curvature_rate", "piece"):
        assert_array_equal(getattr(one, f), getattr(two, f), err_msg=f)


@FAST
@given(
    R_t=radii,
    R_p=radii,
    gap=gaps,
    f=st.floats(0.05, 1.0),
    v_t=st.floats(0.01, 5.0),
    v_p=st.floats(0.01, 5.0),
    n=st.integers(10, 20_000),
)
def test_acceleration_equals_the_numpy_code(R_t, R_p, gap, f, v_t, v_p, n):
    p = _path(R_t, R_p, gap, f, f, 0.0, True)
    got, want = p.acceleration((v_t, v_p), n), ref.acceleration(p, (v_t, v_p), n)
    for name in (
        "s",
        "time",
        "speed",
        "normal",
        "tangential",
        "total",
        "normal_rate",
        "tangential_rate",
        "jerk",
    ):
        close(getattr(got, name), getattr(want, name), what=name)
    assert got.max_jerk == pytest.approx(ref.max_jerk(p, (v_t, v_p), n), rel=RTOL)


@FAST
@given(R_t=radii, R_p=radii, gap=gaps, f=st.floats(0.1, 10.0), angle=st.floats(-3.0, 3.0))
def test_longest_equals_the_numpy_bisection(R_t, R_p, gap, f, angle):
    d = R_t + R_p + gap
    r, c_t = np.array([R_t, R_p]), np.zeros(2)
    c_p = np.array([d * math.cos(angle), d * math.sin(angle)])
    ratio = np.array([1.0, f]) / max(1.0, f)
    close(_longest(r, c_t, c_p, ratio), ref._longest(r, c_t, c_p, ratio), what="longest")


@settings(max_examples=15, deadline=None)
@given(
    R_t=radii,
    R_p=radii,
    gap=gaps,
    v_t=st.floats(0.05, 2.0),
    v_p=st.floats(0.05, 2.0),
    m=st.integers(16, 801),
)
@example(R_t=0.9529447438747511, R_p=0.99999, gap=0.105, v_t=1.0, v_p=1.0, m=16)  # x2 at the edge
def test_design_scan_equals_the_numpy_code(R_t, R_p, gap, v_t, v_p, m):
    r, c_t, c_p = np.array([R_t, R_p]), np.zeros(2), np.array([R_t + R_p + gap, 0.0])
    top = float(_longest(r, c_t, c_p, np.ones(2))[0])
    cands = np.geomspace(min(R_t, R_p) / 100.0, top, 32)
    cands = cands[cands <= top]
    got = _core.transfer_peak_jerk((R_t, R_p), float(c_p[0]), cands, (v_t, v_p), m)
    want = ref._peak_jerk(r, c_t, c_p, cands, (v_t, v_p), m)
    # At x2 = the longest transition exactly, the straight segment between the two
    # transitions is zero long: the kernel takes it as zero (feasible), the numpy
    # code could round it to −1e-17 and say inf. The rule is the kernel's; there
    # it must equal the numpy code a hair inside the limit.
    edge = ~np.isfinite(want)
    assert not edge[:-1].any() and (not edge[-1] or cands[-1] == top)
    if edge[-1]:
        inside = ref._peak_jerk(r, c_t, c_p, np.array([top * (1 - 1e-12)]), (v_t, v_p), m)
        want[-1] = inside[0]
    assert np.isfinite(got).all()
    close(got, want, what="peak_jerk")
    # Past the longest: infinite, as in the numpy code.
    assert _core.transfer_peak_jerk((R_t, R_p), float(c_p[0]), np.array([2 * top]), (v_t, v_p), m)[
        0
    ] == float(ref._peak_jerk(r, c_t, c_p, np.array([2 * top]), (v_t, v_p), m)[0])


@pytest.mark.parametrize("speed", [0.15708, (0.1, 0.3), (0.4, 0.2)])
@pytest.mark.parametrize("rotors", [(0.15, 0.25, 0.01), (0.05, 0.4, 0.03), (0.3, 0.1, 0.002)])
def test_design_equals_the_numpy_code(rotors, speed):
    got = cm.transfer.design_transfer(*rotors, speed)
    want = ref.design_transfer(*rotors, speed)
    close(got.candidates, want["candidates"], what="candidates")
    close(got.peak_jerk, want["peak_jerk"], what="peak_jerk")
    # The minimiser's own tolerance, 1e-6 of its bracket.
    assert got.x2 == pytest.approx(want["x2"], rel=1e-6)
    assert got.at_limit == want["at_limit"]
    for name in ("max_acceleration", "max_jerk", "jump", "transfer_time"):
        assert getattr(got, name) == pytest.approx(want[name], rel=1e-6), name


def test_design_does_not_depend_on_the_thread_count():
    one = cm.transfer.design_transfer(0.15, 0.25, 0.01, (0.1, 0.3), n_threads=1)
    two = cm.transfer.design_transfer(0.15, 0.25, 0.01, (0.1, 0.3), n_threads=2)
    assert_array_equal(one.peak_jerk, two.peak_jerk)
    assert one.x2 == two.x2 and one.max_jerk == two.max_jerk


def test_kernel_errors_are_input_errors_naming_the_field():
    q = tr.smooth_transition(0.15, 0.05)
    with pytest.raises(cm.InputError, match="what"):
        _core.transfer_quintic(q.coeffs, np.zeros(3), "slope")
    with pytest.raises(cm.InputError, match=r"x\[1\] = NaN"):
        _core.transfer_quintic(q.coeffs, np.array([0.0, np.nan]), "y")
    with pytest.raises(cm.InputError, match="coeffs"):
        _core.transfer_quintic(q.coeffs[:5], np.zeros(3), "y")
    with pytest.raises(cm.InputError, match="C-contiguous"):
        _core.transfer_quintic(q.coeffs, np.zeros(6)[::2], "y")
    with pytest.raises(cm.InputError, match="spec"):
        _core.transfer_sample(np.zeros(3), np.full(5, 2, dtype=np.int64), True)
    p = tr.TransferPath(0.15, 0.25, (0.0, 0.0), (0.41, 0.0), x2=0.04)
    with pytest.raises(cm.InputError, match="counts"):
        _core.transfer_sample(p._spec, np.array([2, 2, 1, 2, 2], dtype=np.int64), True)
    with pytest.raises(cm.InputError, match="v_t"):
        _core.transfer_kinematics(np.zeros(3), np.zeros(3), np.zeros(3), (0.0, 1.0, 0.0, 1.0))
    with pytest.raises(cm.InputError, match="curvature"):
        _core.transfer_kinematics(np.zeros(3), np.zeros(2), np.zeros(3), (1.0, 1.0, 0.0, 1.0))
    with pytest.raises(cm.InputError, match="distance"):
        _core.transfer_peak_jerk((0.15, 0.25), 0.3, np.array([0.01]), (0.1, 0.1), 64)
    with pytest.raises(cm.InputError, match="x2"):
        _core.transfer_peak_jerk((0.15, 0.25), 0.41, np.array([-0.01]), (0.1, 0.1), 64)
    with pytest.raises(cm.InputError, match="R_p"):
        _core.transfer_longest((0.15, -0.25), 0.41, (1.0, 1.0))
    with pytest.raises(cm.InputError, match="n_threads"):
        p.sample(100, n_threads=0)
    with pytest.raises(ValueError):
        cm.transfer.design_transfer(0.15, 0.25, 0.01, 0.1, n_threads=-1)


def test_an_overlap_of_rounding_size_fits_in_both_layers() -> None:
    """The straight length is not monotone in x2 at the ulp: one ulp under the
    longest transition that fits, it is −1.6e-16 m. Both the path
    (``TransferPath``) and the candidate scan (``transfer_peak_jerk``, which
    ``design_transfer`` uses) take an overlap within 1e-12·d as rounding (the
    straight is 0): the path is built and the jerk is finite; a real overlap
    (the longest + 1e-6 relative) is refused by both."""
    from cyclomech import _core
    from cyclomech.transfer._path import _STRAIGHT_RTOL

    rt, rp, gap = 0.4816596191697546, 0.39349413550424783, 0.04701661543068728
    d = rt + rp + gap
    top = _core.transfer_longest((rt, rp), d, (1.0, 1.0))
    assert top is not None
    below = top[0] * 7.0 / 7.0  # one ulp under
    assert below < top[0]
    path = cm.transfer.TransferPath(rt, rp, (0.0, 0.0), (d, 0.0), below)
    assert path.straight_length == 0.0
    over = top[0] * (1.0 + 1e-6)
    jerk = _core.transfer_peak_jerk((rt, rp), d, np.array([below, over]), (0.05, 0.05), 64)
    assert np.isfinite(jerk[0]) and jerk[0] > 0.0 and jerk[1] == np.inf
    with pytest.raises(cm.InfeasibleError, match="too long"):
        cm.transfer.TransferPath(rt, rp, (0.0, 0.0), (d, 0.0), over)
    assert _STRAIGHT_RTOL == 1e-12  # STRAIGHT_RTOL of rust/core/src/transfer/design.rs
