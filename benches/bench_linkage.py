"""Linkage kernels against what a user would otherwise pick, in one run.

Groups (each prints one ratio table; ``cyclomech`` rows are the references):

- four-bar crank-rocker, 360 000 angles: cyclomech with analogs (default threads and
  one thread, into fresh arrays and into a previous solution's, ``out=``) and
  positions only (1 and 2 threads, fresh and ``out=``); the numpy vectorised closed
  form (positions of C, into its own fresh arrays);
  pylinkage's numba path, ``Linkage.step_fast`` (positions) and
  ``Linkage.step_fast_with_kinematics`` (positions, velocities, accelerations; with
  ω = 1 rad/s and α = 0 these are the analogs d/dφ, d²/dφ² that cyclomech returns).
  pylinkage is sequential: the crank turns by one step and the dyad takes the
  intersection nearest the previous pose.
- class III group, 720 angles, walked out from the drawn 90° as cyclomech does: scipy
  least squares continued angle by angle; pyslvs (its BFGS ``SolverSystem``
  warm-started from the angle before; ``expr_solving``, BFGS from the drawn pose at
  every angle); python-solvespace (the crank tip dragged to each angle). The peers
  compute positions only.
- the Burg trimmer (seed 001, class III), 360 000 angles: cyclomech with analogs,
  closure residual checked ≤ 1e-10 at every angle; pyslvs's SolverSystem on the
  same grid (one round: it takes about ten seconds).
- a sweep of 10 000 four-bar geometries × 360 angles: ``cm.linkage.solve_geometries`` with one
  and two threads, against numpy's closed form broadcast over (K, N).

Accuracy on these grids (max over the grid of |joint distance − link length|, 2-core
x86-64): cyclomech 2e-15 (four-bar) and 2e-13 (class III); pylinkage 2e-15, but it
turns its crank by increments of atan2, so its angles drift from the grid by up to
3e-11 rad and its points by 3e-11 from the closed form (its analogs agree with
cyclomech's to 7e-11); pyslvs 6e-12 (SolverSystem) and 2e-10 (expr_solving);
python-solvespace 1e-8 (its convergence tolerance).

``test_ratio_table`` (issue 37): the four-bar with analogs on one thread against
pylinkage's ``step_fast_with_kinematics`` in both page states (fresh pages:
``malloc_trim(0)`` before each call), into new arrays and ``out=previous``, with the
floors of writing the solution's arrays once (new and existing) and the ratio to the
floor of the same page state. Run::

    taskset -c 1 python -m pytest benches/bench_linkage.py -k ratio_table \
        --benchmark-enable -q -p no:cacheprovider -s

The peers are in the ``[bench]`` extras, not ``[test]``: each row skips when its peer
is not installed (pylinkage without numba too, whose fallback is pure Python).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from types import ModuleType
from typing import Any

import cyclomech as cm
import numpy as np
import pytest
from _timing import page_states, timed_run
from cyclomech._arrays import one_block
from numpy.testing import assert_allclose

N_ANGLES = 360_000
R, L2, L3, D = 1.0, 3.5, 3.0, 4.0
GROUP = "four-bar crank-rocker, 360 000 angles"
ROUNDS = 7


def _label(benchmark, tool: str, what: str) -> None:
    benchmark.extra_info["tool"] = tool
    benchmark.extra_info["what"] = what


@pytest.fixture(scope="module")
def setup() -> tuple[cm.Linkage, np.ndarray]:
    # Drawn at φ = 90° with C above B-D.
    b = np.array([0.0, R])
    bd = np.hypot(D, R)
    x = (L2**2 - L3**2 + bd**2) / (2 * bd)
    h = np.sqrt(L2**2 - x**2)
    e = np.array([D, -R]) / bd
    c = b + x * e + h * np.array([-e[1], e[0]])
    lk = cm.Linkage(
        {"A": (0.0, 0.0), "B": tuple(b), "C": tuple(c), "D": (D, 0.0)},
        [("A", "B"), ("B", "C"), ("C", "D")],
        ["A", "D"],
        ("A", "B"),
    )
    return lk, np.linspace(0.0, 2 * np.pi, N_ANGLES)


def numpy_closed_form(phi: np.ndarray) -> np.ndarray:
    """Joint C by the two-circle intersection, vectorised over the angles."""
    bx, by = R * np.cos(phi), R * np.sin(phi)
    dx, dy = D - bx, -by
    dd = dx * dx + dy * dy
    d = np.sqrt(dd)
    x = (L2 * L2 - L3 * L3 + dd) / (2 * d)
    h = np.sqrt(L2 * L2 - x * x)
    ex, ey = dx / d, dy / d
    return np.stack([bx + x * ex - h * ey, by + x * ey + h * ex], axis=1)


@pytest.mark.benchmark(group=GROUP)
def test_linkage_cyclomech(benchmark, setup) -> None:
    _label(benchmark, "cyclomech", "Linkage.solve: positions + velocity + acceleration analogs")
    lk, phi = setup
    sol = benchmark(lk.solve, phi)
    assert_allclose(sol["C"], numpy_closed_form(phi), atol=1e-12)


@pytest.mark.benchmark(group=GROUP)
def test_linkage_cyclomech_one_thread(benchmark, setup) -> None:
    _label(benchmark, "cyclomech", "Linkage.solve, n_threads=1")
    lk, phi = setup
    sol = benchmark(lk.solve, phi, n_threads=1)
    assert sol.ok.all()


@pytest.mark.benchmark(group=GROUP)
def test_linkage_cyclomech_positions(benchmark, setup) -> None:
    _label(benchmark, "cyclomech", "Linkage.solve(points=['C'], analogs=False): positions of C")
    lk, phi = setup
    sol = benchmark(lk.solve, phi, points=["C"], analogs=False)
    assert_allclose(sol["C"], numpy_closed_form(phi), atol=1e-12)


@pytest.mark.benchmark(group=GROUP)
@pytest.mark.parametrize("threads", [1, 2])
def test_linkage_cyclomech_out(benchmark, setup, threads) -> None:
    _label(
        benchmark,
        "cyclomech",
        f"Linkage.solve(out=previous), n_threads={threads}: analogs into reused arrays",
    )
    lk, phi = setup
    prev = lk.solve(phi, n_threads=threads)
    sol = benchmark(lk.solve, phi, n_threads=threads, out=prev)
    assert sol.xy is prev.xy
    assert_allclose(sol["C"], numpy_closed_form(phi), atol=1e-12)


@pytest.mark.benchmark(group=GROUP)
@pytest.mark.parametrize("threads", [1, 2])
def test_linkage_cyclomech_positions_threads(benchmark, setup, threads) -> None:
    _label(benchmark, "cyclomech", f"solve(points=['C'], analogs=False), n_threads={threads}")
    lk, phi = setup
    sol = benchmark(lk.solve, phi, n_threads=threads, points=["C"], analogs=False)
    assert_allclose(sol["C"], numpy_closed_form(phi), atol=1e-12)


@pytest.mark.benchmark(group=GROUP)
@pytest.mark.parametrize("threads", [1, 2])
def test_linkage_cyclomech_positions_out(benchmark, setup, threads) -> None:
    _label(benchmark, "cyclomech", f"solve(points=['C'], analogs=False, out=), n_threads={threads}")
    lk, phi = setup
    prev = lk.solve(phi, points=["C"], analogs=False)
    sol = benchmark(lk.solve, phi, n_threads=threads, points=["C"], analogs=False, out=prev)
    assert_allclose(sol["C"], numpy_closed_form(phi), atol=1e-12)


@pytest.mark.benchmark(group=GROUP)
def test_linkage_numpy(benchmark, setup) -> None:
    _label(benchmark, "numpy", "vectorised closed form, positions of C only")
    lk, phi = setup
    c = benchmark(numpy_closed_form, phi)
    assert_allclose(c[:1000], lk.solve(phi[:1000])["C"], atol=1e-12)


# --- class III ----------------------------------------------------------------------

GROUP_III = "class III group (ternary link on three binary links), 720 angles"
TRIAD_POINTS = {
    "A": (0.0, 0.0),
    "B": (0.0, 0.2),
    "C": (1.5, 1.2),
    "E": (2.5, 0.8),
    "G": (2.0, 2.2),
    "F": (3.2, -0.6),
    "H": (3.1, 3.4),
}
TRIAD_LINKS = [("A", "B"), ("B", "C"), ("C", "E", "G"), ("E", "F"), ("G", "H")]
TRIAD_PAIRS = [("B", "C"), ("E", "F"), ("G", "H"), ("C", "E"), ("E", "G"), ("G", "C")]


@pytest.fixture(scope="module")
def triad() -> tuple[cm.Linkage, np.ndarray]:
    lk = cm.Linkage(TRIAD_POINTS, TRIAD_LINKS, ["A", "F", "H"], ("A", "B"))
    # The range this group can reach from its drawn pose (it locks past ~111°).
    return lk, np.radians(np.linspace(0.0, 110.0, 720))


def scipy_continuation(angles: np.ndarray) -> np.ndarray:
    """What a user would write: scipy least squares on the closure, angle by angle."""
    from scipy.optimize import least_squares

    p = {k: np.array(v) for k, v in TRIAD_POINTS.items()}
    length = {ab: math.dist(TRIAD_POINTS[ab[0]], TRIAD_POINTS[ab[1]]) for ab in TRIAD_PAIRS}
    r = math.dist(TRIAD_POINTS["A"], TRIAD_POINTS["B"])

    def residual(x: np.ndarray, phi: float) -> list[float]:
        at = {"C": x[:2], "E": x[2:4], "G": x[4:], "F": p["F"], "H": p["H"]}
        at["B"] = r * np.array([math.cos(phi), math.sin(phi)])
        return [np.linalg.norm(at[a] - at[b]) - length[a, b] for a, b in TRIAD_PAIRS]

    x = np.r_[p["C"], p["E"], p["G"]]
    out = []
    for phi in angles:  # a continuation is sequential by nature
        x = least_squares(residual, x, args=(phi,), xtol=1e-15, ftol=1e-15, gtol=1e-15).x
        out.append(x.reshape(3, 2))
    return np.array(out)


@pytest.mark.benchmark(group=GROUP_III)
def test_triad_cyclomech(benchmark, triad) -> None:
    _label(benchmark, "cyclomech", "Linkage.solve: positions + analogs (Newton continuation)")
    lk, phi = triad
    sol = benchmark(lk.solve, phi)
    assert sol.ok.all()


@pytest.mark.benchmark(group=GROUP_III)
def test_triad_scipy(benchmark, triad) -> None:
    _label(benchmark, "scipy", "least_squares continued angle by angle, positions only")
    lk, phi = triad
    # Descending from the drawn 90° would match cyclomech's walk; scipy starts at
    # the drawn pose and goes up the grid from 0°, so give it the grid from 90° down
    # and up, as cyclomech walks it.
    below, above = phi[phi < np.radians(90.0)][::-1], phi[phi >= np.radians(90.0)]
    got = benchmark.pedantic(
        lambda: (scipy_continuation(above), scipy_continuation(below)), rounds=3, iterations=1
    )
    sol = lk.solve(above)
    assert_allclose(np.stack([sol["C"], sol["E"], sol["G"]], axis=1), got[0], atol=1e-9)


TRIAD_GROUND = ("A", "F", "H")
DRAWN_RAD = math.pi / 2  # both mechanisms are drawn with the crank at 90°


def _closure(xy: dict[str, np.ndarray], lengths: dict[tuple[str, str], float]) -> float:
    """Largest |distance − link length| [m] over the grid and the listed pairs."""
    return max(
        float(np.abs(np.hypot(*(xy[a] - xy[b]).T) - length).max())
        for (a, b), length in lengths.items()
    )


# --- four-bar: pylinkage --------------------------------------------------------------

FOUR_BAR_LENGTHS = {("B", "C"): L2, ("C", "D"): L3}


@pytest.fixture(scope="module")
def pylinkage_four_bar() -> tuple[Any, list[tuple[float, float]]]:
    """The crank-rocker in pylinkage, compiled; and its start pose, to reset each round."""
    pytest.importorskip("numba")
    pl = pytest.importorskip("pylinkage", minversion="1.0")
    step = 2 * np.pi / (N_ANGLES - 1)  # the spacing of bench_linkage.py's grid
    a, d = pl.Ground(0.0, 0.0, name="A"), pl.Ground(D, 0.0, name="D")
    # The crank turns before each solve: one step before 0 puts row k at angle k·step.
    crank = pl.Crank(a, radius=R, angular_velocity=step, initial_angle=-step, name="B")
    cx, cy = numpy_closed_form(np.array([-step]))[0]
    rocker = pl.RRRDyad(crank.output, d, distance1=L2, distance2=L3, x=cx, y=cy, name="C")
    lk = pl.Linkage([a, d, crank, rocker], name="crank-rocker")
    lk.set_input_velocity(crank, omega=1.0, alpha=0.0)
    start = lk.get_coords()
    lk.step_fast(2)  # numba compiles here, not in the timing
    lk.step_fast_with_kinematics(2)
    return lk, start


def _pylinkage_points(pos: np.ndarray) -> dict[str, np.ndarray]:
    return dict(zip("ADBC", pos.transpose(1, 0, 2), strict=True))


@pytest.mark.benchmark(group=GROUP)
def test_linkage_pylinkage(benchmark, setup, pylinkage_four_bar) -> None:
    _label(benchmark, "pylinkage", "Linkage.step_fast (numba, sequential), positions only")
    _, phi = setup
    lk, start = pylinkage_four_bar
    pos = benchmark.pedantic(
        lk.step_fast, args=(N_ANGLES,), setup=lambda: lk.set_coords(start), rounds=20
    )
    xy = _pylinkage_points(pos)
    assert _closure(xy, FOUR_BAR_LENGTHS) < 1e-13
    # Its crank angle is stepped, not set: the grid drifts by rounding, not more.
    assert_allclose(xy["C"], numpy_closed_form(phi), atol=1e-9)


@pytest.mark.benchmark(group=GROUP)
def test_linkage_pylinkage_kinematics(benchmark, setup, pylinkage_four_bar) -> None:
    _label(benchmark, "pylinkage", "Linkage.step_fast_with_kinematics: positions + vel + acc")
    lk_cm, phi = setup
    lk, start = pylinkage_four_bar
    pos, vel, acc = benchmark.pedantic(
        lk.step_fast_with_kinematics,
        args=(N_ANGLES,),
        setup=lambda: lk.set_coords(start),
        rounds=10,
    )
    sol, c = lk_cm.solve(phi), 3  # C is pylinkage's fourth component
    assert_allclose(pos[:, c], sol["C"], atol=1e-9)
    assert sol.vel is not None and sol.acc is not None
    assert_allclose(vel[:, c], sol.vel[:, sol.index("C")], atol=1e-8)
    assert_allclose(acc[:, c], sol.acc[:, sol.index("C")], atol=1e-8)


def test_ratio_table(request: pytest.FixtureRequest, setup, pylinkage_four_bar) -> None:
    """Four-bar with analogs, one thread, interleaved rounds (medians, wall and CPU),
    both page states (``_timing.page_states``): cyclomech into new arrays and into a
    previous solution's (``out=``), pylinkage's fastest path with analogs
    (``step_fast_with_kinematics``, numba), and the floors: the solution's arrays
    new (one block, as ``solve`` allocates them) and existing, written once
    (``fill``). The results are checked equal first. The ratio to the floor is
    taken against the new arrays' floor in fresh pages and the existing arrays' in
    reused ones."""
    if not timed_run(request.config):
        pytest.skip("timed runs only (--benchmark-enable)")
    lk_cm, phi = setup
    lk, start = pylinkage_four_bar
    prev = lk_cm.solve(phi, n_threads=1)
    lk.set_coords(start)
    pos, vel, acc = lk.step_fast_with_kinematics(N_ANGLES)
    for ours, theirs in ((prev.xy, pos), (prev.vel, vel), (prev.acc, acc)):
        # pylinkage's points are A, D, B, C; ours A, B, C, D.
        assert_allclose(ours, theirs[:, [0, 2, 3, 1]], atol=1e-8)
    # The floor's output: the solution's arrays, one block as solve allocates them.
    shapes = [(a.shape, a.dtype) for a in (prev.xy, prev.vel, prev.acc, prev.ok)]
    shapes += [(prev.ok.shape, prev.ok.dtype)] * 2
    existing = one_block(*shapes, what="floor", hint="")

    def pylinkage_run() -> None:
        lk.set_coords(start)
        lk.step_fast_with_kinematics(N_ANGLES)

    tools: dict[str, Callable[[], Any]] = {
        "cyclomech 1 thread": lambda: lk_cm.solve(phi, n_threads=1),
        "cyclomech 1 thread, out=": lambda: lk_cm.solve(phi, n_threads=1, out=prev),
        "pylinkage step_fast_with_kinematics": pylinkage_run,
        "floor: new block written once": lambda: [
            a.fill(1) for a in one_block(*shapes, what="floor", hint="")
        ],
        "floor: existing block written": lambda: [a.fill(1) for a in existing],
    }
    mb = sum(a.nbytes for a in existing) / 1e6
    for state, t in page_states(tools, ROUNDS).items():
        print(
            f"\nfour-bar with analogs, {N_ANGLES} angles, {state} pages, output {mb:.0f} MB, "
            f"{ROUNDS} interleaved rounds (medians)"
        )
        peer = t["pylinkage step_fast_with_kinematics"]
        floor = (
            t["floor: new block written once"]
            if state == "fresh"
            else t["floor: existing block written"]
        )
        for name, (w, c) in t.items():
            print(
                f"  {name:38s} wall {w * 1e3:6.1f} ms  cpu {c * 1e3:6.1f} ms  "
                f"pylinkage/this {peer[0] / w:5.2f}x (cpu {peer[1] / c:5.2f}x)  "
                f"this/floor {w / floor[0]:4.2f} (cpu {c / floor[1]:4.2f})"
            )


# --- class III: pyslvs, python-solvespace ---------------------------------------------

TRIAD_LENGTHS = {ab: math.dist(TRIAD_POINTS[ab[0]], TRIAD_POINTS[ab[1]]) for ab in TRIAD_PAIRS}
TRIAD_NAMES = tuple(TRIAD_POINTS)


def _walk(solve, phi: np.ndarray) -> np.ndarray:
    """Positions (N, points, 2) on the grid, solved outwards from the drawn angle."""
    up = phi >= DRAWN_RAD
    down = np.flatnonzero(~up)[::-1]
    out = np.empty((len(phi), len(TRIAD_NAMES), 2))
    out[up] = solve(phi[up])
    out[down] = solve(phi[down])
    return out


def _check_triad(xy: np.ndarray, lk: cm.Linkage, phi: np.ndarray, atol: float) -> None:
    sol = lk.solve(phi)
    assert_allclose(xy, np.stack([sol[p] for p in TRIAD_NAMES], axis=1), atol=atol)
    points = dict(zip(TRIAD_NAMES, xy.transpose(1, 0, 2), strict=True))
    assert _closure(points, TRIAD_LENGTHS) < atol


@pytest.fixture(scope="module")
def pyslvs() -> ModuleType:
    with warnings.catch_warnings():
        # pyslvs's parser, lark-parser 0.12, imports the deprecated sre_parse.
        warnings.simplefilter("ignore", DeprecationWarning)
        return pytest.importorskip("pyslvs")


def _pyslvs_points(pyslvs: ModuleType) -> tuple[list[Any], tuple[int, int]]:
    """The group as pyslvs VPoints (links named L0…, the frame "ground"), and its input."""
    links: dict[str, list[str]] = {p: [] for p in TRIAD_NAMES}
    for p in TRIAD_GROUND:
        links[p].append(pyslvs.VLink.FRAME)
    for k, link in enumerate(TRIAD_LINKS):
        for p in link:
            links[p].append(f"L{k}")
    vpoints = [pyslvs.VPoint.r_joint(links[p], *TRIAD_POINTS[p]) for p in TRIAD_NAMES]
    return vpoints, (TRIAD_NAMES.index("A"), TRIAD_NAMES.index("B"))


def pyslvs_continuation(pyslvs: ModuleType, phi: np.ndarray) -> np.ndarray:
    """One BFGS system; each solve starts from the last (inputs in degrees)."""
    vpoints, drive = _pyslvs_points(pyslvs)
    system = pyslvs.SolverSystem(vpoints, {drive: math.degrees(DRAWN_RAD)})
    out = np.empty((len(phi), len(vpoints), 2))
    for k, angle in enumerate(phi):
        system.set_inputs({drive: math.degrees(angle)})
        out[k] = system.solve()
    return out


def pyslvs_expr(pyslvs: ModuleType, phi: np.ndarray) -> np.ndarray:
    """The triangle stack places B; BFGS places the group from the drawn pose."""
    vpoints, drive = _pyslvs_points(pyslvs)
    exprs = pyslvs.t_config(vpoints, [drive])
    return np.array([pyslvs.expr_solving(exprs, vpoints, {drive: math.degrees(a)}) for a in phi])


def solvespace_continuation(slvs: ModuleType, phi: np.ndarray) -> np.ndarray:
    """Ground joints and crank tip B dragged (fixed where put); B put at each angle."""
    system = slvs.SolverSystem()
    wp = system.create_2d_base()
    system.set_group(2)  # solve group 2 only: the workplane (group 1) stays put
    pt = {p: system.add_point_2d(*TRIAD_POINTS[p], wp) for p in TRIAD_NAMES}
    for p in (*TRIAD_GROUND, "B"):
        system.dragged(pt[p], wp)
    for (a, b), length in TRIAD_LENGTHS.items():
        system.distance(pt[a], pt[b], length, wp)
    r = math.dist(TRIAD_POINTS["A"], TRIAD_POINTS["B"])
    out = np.empty((len(phi), len(TRIAD_NAMES), 2))
    for k, angle in enumerate(phi):
        system.set_params(pt["B"].params, (r * math.cos(angle), r * math.sin(angle)))
        if system.solve() != slvs.ResultFlag.OKAY:
            raise AssertionError(f"python-solvespace failed at {math.degrees(angle):.3f}°")
        out[k] = [system.params(pt[p].params) for p in TRIAD_NAMES]
    return out


@pytest.mark.benchmark(group=GROUP_III)
def test_triad_pyslvs(benchmark, triad, pyslvs) -> None:
    _label(benchmark, "pyslvs", "SolverSystem (BFGS) continued angle by angle, positions only")
    lk, phi = triad
    xy = benchmark(_walk, lambda a: pyslvs_continuation(pyslvs, a), phi)
    _check_triad(xy, lk, phi, atol=1e-9)


@pytest.mark.benchmark(group=GROUP_III)
def test_triad_pyslvs_expr(benchmark, triad, pyslvs) -> None:
    _label(benchmark, "pyslvs", "expr_solving per angle from the drawn pose, positions only")
    lk, phi = triad
    xy = benchmark(pyslvs_expr, pyslvs, phi)
    _check_triad(xy, lk, phi, atol=1e-8)


@pytest.mark.benchmark(group=GROUP_III)
def test_triad_solvespace(benchmark, triad) -> None:
    slvs = pytest.importorskip("python_solvespace")
    _label(benchmark, "python-solvespace", "SolverSystem continued angle by angle, positions only")
    lk, phi = triad
    xy = benchmark(_walk, lambda a: solvespace_continuation(slvs, a), phi)
    _check_triad(xy, lk, phi, atol=1e-6)


# --- the Burg trimmer (class III), 360 000 angles -------------------------------------

GROUP_BURG = "Burg trimmer knife drive (class III, seed 001), 360 000 angles"


@pytest.fixture(scope="module")
def burg() -> tuple[cm.Linkage, np.ndarray]:
    from cyclomech.linkage import presets

    return presets.burg_trimmer(), np.linspace(0.0, 2 * np.pi, N_ANGLES)


def _burg_lengths(lk: cm.Linkage) -> dict[tuple[str, str], float]:
    return {(a, b): lk.length(a, b) for a, b in lk.dimensions}


@pytest.mark.benchmark(group=GROUP_BURG)
def test_burg_cyclomech(benchmark, burg) -> None:
    _label(benchmark, "cyclomech", "Linkage.solve: positions + analogs, full turn")
    lk, phi = burg
    sol = benchmark(lk.solve, phi)
    assert sol.ok.all() and not sol.branch_change.any()
    assert _closure({p: sol[p] for p in lk.names}, _burg_lengths(lk)) <= 1e-10


@pytest.mark.benchmark(group=GROUP_BURG)
def test_burg_pyslvs(benchmark, burg, pyslvs) -> None:
    _label(benchmark, "pyslvs", "SolverSystem (BFGS) continued angle by angle, positions only")
    lk, phi = burg
    links: dict[str, list[str]] = {p: [] for p in lk.names}
    for p in ("A", "D", "O"):
        links[p].append(pyslvs.VLink.FRAME)
    for k, link in enumerate([("A", "B"), ("D", "C"), ("B", "C", "E"), ("E", "F"), ("O", "F")]):
        for p in link:
            links[p].append(f"L{k}")
    sol0 = lk.solve(phi[:1])  # the closed pose at 0°: pyslvs starts from it

    def run() -> np.ndarray:
        vpoints = [pyslvs.VPoint.r_joint(links[p], *sol0[p][0]) for p in lk.names]
        drive = (lk.names.index("O"), lk.names.index("F"))
        system = pyslvs.SolverSystem(vpoints, {drive: 0.0})
        out = np.empty((len(phi), len(vpoints), 2))
        for k, angle in enumerate(phi):
            system.set_inputs({drive: math.degrees(angle)})
            out[k] = system.solve()
        return out

    xy = benchmark.pedantic(run, rounds=1, iterations=1)
    assert (
        _closure(dict(zip(lk.names, xy.transpose(1, 0, 2), strict=True)), _burg_lengths(lk)) < 1e-7
    )


# --- a sweep of geometries ------------------------------------------------------------

GROUP_SWEEP = "sweep: 10 000 four-bar geometries x 360 angles, positions of C"
K_GEOMETRIES = 10_000


@pytest.fixture(scope="module")
def geometries(setup) -> tuple[cm.Linkage, np.ndarray, np.ndarray]:
    lk, _ = setup
    rng = np.random.default_rng(1)
    lengths = lk.dimension_values * rng.uniform(0.97, 1.03, size=(K_GEOMETRIES, 3))
    return lk, np.linspace(0.0, 2 * np.pi, 360), lengths


def numpy_sweep(phi: np.ndarray, lengths: np.ndarray) -> np.ndarray:
    """C for every geometry and angle: the closed form broadcast over (K, N)."""
    r, l2, l3 = (lengths[:, k, None] for k in range(3))
    bx, by = r * np.cos(phi), r * np.sin(phi)
    dx, dy = D - bx, -by
    dd = dx * dx + dy * dy
    d = np.sqrt(dd)
    x = (l2 * l2 - l3 * l3 + dd) / (2 * d)
    h = np.sqrt(l2 * l2 - x * x)
    ex, ey = dx / d, dy / d
    return np.stack([bx + x * ex - h * ey, by + x * ey + h * ex], axis=-1)


@pytest.mark.benchmark(group=GROUP_SWEEP)
@pytest.mark.parametrize("threads", [2, 1])
def test_sweep_cyclomech(benchmark, geometries, threads) -> None:
    _label(
        benchmark,
        "cyclomech",
        f"linkage.solve_geometries(points=['C'], analogs=False), {threads} threads",
    )
    lk, phi, lengths = geometries
    sol = benchmark(
        cm.linkage.solve_geometries,
        lk,
        phi,
        lengths,
        points=["C"],
        analogs=False,
        n_threads=threads,
    )
    assert sol.ok.all()
    assert_allclose(sol["C"][:50], numpy_sweep(phi, lengths[:50]), atol=1e-12)


@pytest.mark.benchmark(group=GROUP_SWEEP)
@pytest.mark.parametrize("threads", [2, 1])
def test_sweep_cyclomech_analogs(benchmark, geometries, threads) -> None:
    _label(
        benchmark,
        "cyclomech",
        f"linkage.solve_geometries with analogs, all points, {threads} threads",
    )
    lk, phi, lengths = geometries
    sol = benchmark(cm.linkage.solve_geometries, lk, phi, lengths, n_threads=threads)
    assert sol.ok.all()


@pytest.mark.benchmark(group=GROUP_SWEEP)
def test_sweep_numpy(benchmark, geometries) -> None:
    _label(benchmark, "numpy", "closed form broadcast over (K, N), positions of C")
    _, phi, lengths = geometries
    c = benchmark(numpy_sweep, phi, lengths)
    assert c.shape == (K_GEOMETRIES, 360, 2)
