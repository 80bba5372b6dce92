"""Three-position motion generation on Norton's Example 5-2 (R. L. Norton, *Design of
Machinery*, §5.7 "analytical three-position synthesis", Example 5-2; its data as a
course script reproduces them): the coupler's displacements p21 = 2.798 at
δ2 = −31.19°, p31 = 3.919 at δ3 = −16.34°, its rotations α2 = −45°, α3 = 9.3°, and the
free choices β2 = 342.3°, β3 = 324.8° (dyad WZ), γ2 = 30.9°, γ3 = 80.6° (dyad US).

The stored sources give the example's data but not the link lengths the book prints,
so this test does not compare with printed numbers: it solves the example by the
book's own method — Norton's dyad equations W(e^{iβ} − 1) + Z(e^{iα} − 1) = P, a
2 × 2 complex linear system per dyad, written here with numpy — and checks that
cyclomech's circle-point construction (circumcentres, a different method) builds the
same linkage from the same moving pivots, and that the linkage, solved by the
position solver, takes the three poses to 1e-9."""

from __future__ import annotations

import cmath
import math

import cyclomech as cm
import numpy as np

P21, D2 = 2.798, math.radians(-31.19)
P31, D3 = 3.919, math.radians(-16.34)
A2, A3 = math.radians(-45.0), math.radians(9.3)
B2, B3 = math.radians(342.3), math.radians(324.8)
G2, G3 = math.radians(30.9), math.radians(80.6)


def _dyad(r2: float, r3: float) -> tuple[complex, complex]:
    """Norton's equations for one dyad: the link W (ground pivot → moving pivot) and
    the coupler's vector Z (moving pivot → the pose point) at pose 1."""
    e = cmath.exp
    m = np.array([[e(1j * r2) - 1, e(1j * A2) - 1], [e(1j * r3) - 1, e(1j * A3) - 1]])
    rhs = np.array([P21 * e(1j * D2), P31 * e(1j * D3)])
    w, z = np.linalg.solve(m, rhs)
    return complex(w), complex(z)


def test_nortons_example_5_2_by_both_methods():
    (w, z), (u, s) = _dyad(B2, B3), _dyad(G2, G3)
    # Pose 1 at the origin with the coupler line along x; poses 2 and 3 displaced and
    # turned as the example says.
    p2, p3 = P21 * cmath.exp(1j * D2), P31 * cmath.exp(1j * D3)
    poses = [
        (0.0, 0.0, 0.0),
        (p2.real, p2.imag, math.degrees(A2)),
        (p3.real, p3.imag, math.degrees(A3)),
    ]
    # The moving pivots in the coupler frame at pose 1: −Z and −S from the pose point.
    circle = ((-z.real, -z.imag), (-s.real, -s.imag))
    (c,) = cm.synthesis.motion_generation(poses, circle_points=circle)
    a0, b0 = -z - w, -s - u  # Norton's ground pivots
    np.testing.assert_allclose(c.centre_points[0], (a0.real, a0.imag), rtol=0, atol=1e-9)
    np.testing.assert_allclose(c.centre_points[1], (b0.real, b0.imag), rtol=0, atol=1e-9)
    assert math.isclose(c.lengths["crank"], abs(w), rel_tol=1e-12)
    assert math.isclose(c.lengths["rocker"], abs(u), rel_tol=1e-12)
    assert math.isclose(c.lengths["coupler"], abs(z - s), rel_tol=1e-12)
    assert math.isclose(c.lengths["ground"], abs(a0 - b0), rel_tol=1e-12)
    # The crank turns by β between the poses, as chosen.
    turn = np.diff(np.unwrap(np.radians(c.crank_angles_deg)))
    np.testing.assert_allclose(
        np.mod(turn, 2 * np.pi),
        np.mod(np.diff(np.unwrap([0.0, B2, B3])), 2 * np.pi),
        atol=1e-9,
    )
    # Solved by the position solver, the linkage takes the three poses.
    sol = c.linkage().solve(np.radians(c.crank_angles_deg))
    np.testing.assert_allclose(sol["P"], [p[:2] for p in poses], rtol=0, atol=1e-9)
