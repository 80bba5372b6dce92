"""``kinetostatics(..., out=previous)`` (issue 37: ``out=`` on every large output):
bit for bit a fresh solve whatever the previous result held (other masses, loads,
angles; poses that do not assemble and a dead centre, whose rows the kernel does not
solve), into the previous result's memory, and a clear error for an ``out`` that
cannot take the solve. The fresh solve itself is checked against independent
references in test_forces.py."""

from __future__ import annotations

import math

import cyclomech as cm
import numpy as np
import pytest
from test_forces import slider_crank

F = cm.forces
G = (0.0, -9.81)


def four_bar(b: float = 0.1, c: tuple[float, float] = (0.3, 0.25), d: float = 0.4) -> cm.Linkage:
    return cm.Linkage(
        {"A": (0, 0), "B": (b, 0), "C": c, "D": (d, 0)},
        [("A", "B"), ("B", "C"), ("C", "D")],
        ["A", "D"],
        ("A", "B"),
    )


MASSES = {
    ("B", "C"): F.LinkMass(1.2, inertia_kg_m2=0.01),
    ("C", "D"): F.LinkMass(0.8, inertia_kg_m2=0.004),
}
LOADS = [F.PointLoad("C", [40.0, -25.0])]


def same(a: F.Kinetostatics, b: F.Kinetostatics) -> None:
    for name in ("torque_parts", "guide_parts", "reaction_parts", "conditioning"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    assert (a.pairs, a.guides) == (b.pairs, b.guides)


@pytest.mark.parametrize("n", [37, 3600])  # a tail past the 8-angle lanes; many lanes
@pytest.mark.parametrize("reactions", [True, False])
def test_out_is_bit_for_bit_a_fresh_solve(n: int, reactions: bool) -> None:
    lk = four_bar()
    first = F.kinetostatics(lk, np.linspace(0.0, 1.0, n), reactions=reactions)
    before = first.torque_parts.copy()
    angles = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    kw = {"masses": MASSES, "loads": LOADS, "gravity": G, "reactions": reactions}
    fresh = F.kinetostatics(lk, angles, **kw)
    again = F.kinetostatics(lk, angles, out=first, **kw)
    same(again, fresh)
    assert not np.array_equal(before, again.torque_parts)  # it was overwritten
    for name in ("torque_parts", "guide_parts", "reaction_parts"):
        if getattr(again, name).size:  # (no guides here; no joint forces without reactions)
            assert np.shares_memory(getattr(again, name), getattr(first, name)), name
    # Twice into the same arrays: still the fresh values.
    same(F.kinetostatics(lk, angles, out=again, **kw), fresh)


def test_rows_the_kernel_does_not_solve_are_not_left_stale() -> None:
    """A four-bar whose crank cannot turn fully (NaN poses) and a slider-crank with a
    dead centre (the kernel stops at the singular block): into an `out` full of
    finite forces, every row equals the fresh solve's, NaN where it has NaN."""
    lk = four_bar(0.3, (0.45, 0.15), 0.5)  # not Grashof: the crank swings, not turns
    angles = np.linspace(0.0, 2 * np.pi, 45, endpoint=False)
    sol = lk.solve(angles)
    assert not sol.ok.all() and sol.ok.any()
    full = F.kinetostatics(four_bar(), angles, masses=MASSES, gravity=G)
    assert np.isfinite(full.torque_parts).all()
    fresh = F.kinetostatics(lk, sol, masses=MASSES, gravity=G)
    same(F.kinetostatics(lk, sol, masses=MASSES, gravity=G, out=full), fresh)
    assert np.isnan(fresh.torque_parts[:, ~sol.ok]).all()

    sc = slider_crank(0.1, 0.1)  # folds at 90° (C on O)
    angles = np.radians(np.arange(0.0, 180.0, 10.0))
    kw = {"point_masses": {"C": 1.0}}
    prev = F.kinetostatics(slider_crank(0.1, 0.35), angles, **kw)
    assert np.isfinite(prev.torque_parts).all()
    fresh = F.kinetostatics(sc, angles, **kw)
    assert math.isnan(fresh.torque(100.0)[9]) and not fresh.ok[9]
    same(F.kinetostatics(sc, angles, out=prev, **kw), fresh)


def test_an_out_that_cannot_take_the_solve_is_refused_by_name() -> None:
    lk = four_bar()
    angles = np.linspace(0.0, 1.0, 16)
    k = F.kinetostatics(lk, angles)
    other_n = F.kinetostatics(lk, np.linspace(0.0, 1.0, 17))
    lean = F.kinetostatics(lk, angles, reactions=False)
    with pytest.raises(cm.InputError, match=r"out must be a Kinetostatics .* for 16 angles"):
        F.kinetostatics(lk, angles, out=other_n)
    with pytest.raises(cm.InputError, match=r"with 1 values an angle and part .*; got a result"):
        F.kinetostatics(lk, angles, reactions=False, out=k)
    with pytest.raises(cm.InputError, match=r"got a result for 16 angles with 1 values"):
        F.kinetostatics(lk, angles, out=lean)
    with pytest.raises(cm.InputError, match=r"out must be a Kinetostatics .*; got ndarray"):
        F.kinetostatics(lk, angles, out=np.zeros((3, 16, 9)))  # type: ignore[arg-type]
    frozen = F.kinetostatics(lk, angles)
    frozen.torque_parts.base.flags.writeable = False
    with pytest.raises(cm.InputError, match=r"read-only"):
        F.kinetostatics(lk, angles, out=frozen)
    # A refused out is left as it was.
    np.testing.assert_array_equal(k.torque_parts, F.kinetostatics(lk, angles).torque_parts)
