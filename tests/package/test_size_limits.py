"""No allocation that cannot fit (issue 16, items 13 and 14): a call whose
results or input copies would take more memory than the budget
(``CYCLOMECH_MAX_BYTES``, ``cyclomech._arrays``) is refused before allocating,
with an InputError naming the sizes, and numpy's own allocation failure is an
InputError too, never a Rust panic. The sizes are checked against the size
arithmetic done by hand. One rule for every domain's kernels, so its tests are
here together."""

from __future__ import annotations

import math
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
from cyclomech import _core
from cyclomech.cli import main

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"

#: Seconds a call that used to hang may take in its own process (imports included).
BOUND_S = 60.0


def run_bounded(code: str, *, timeout: float = BOUND_S, env: dict[str, str] | None = None):
    """Run ``code`` in a fresh interpreter; a hang fails the test, not CI."""
    try:
        return subprocess.run(
            [sys.executable, "-c", textwrap.dedent(code)],
            capture_output=True,
            text=True,
            timeout=timeout,
            env={**os.environ, **(env or {})},
        )
    except subprocess.TimeoutExpired:
        pytest.fail(f"still running after {timeout} s (a hang):\n{code}")


# ---------------------------------------------------------------------------
# Item 14: a Rust panic reached Python when numpy could not allocate.


FOUR_BAR = """
import numpy as np, cyclomech as cm
lk = cm.Linkage({"A": (0, 0), "B": (1, 0), "C": (3.5, 2.5), "D": (4, 0)},
                [("A", "B"), ("B", "C"), ("C", "D")], ["A", "D"], ("A", "B"))
"""


def test_item14_numpy_allocation_failure_is_a_cyclomech_error_not_a_panic():
    # Under a 3 GB address-space limit numpy cannot allocate the 3.2 GB arrays
    # of 5e7 angles' results (9.6 GB in all); on main pyo3 then
    # panicked ("PyObject pointer is null") and a PanicException (a
    # BaseException) escaped. Now it is an InputError, caught by `except
    # Exception`. The size check is lifted (CYCLOMECH_MAX_BYTES) so that the
    # allocation itself is what fails.
    r = run_bounded(
        FOUR_BAR
        + """
import resource
resource.setrlimit(resource.RLIMIT_AS, (3 * 2**30, resource.RLIM_INFINITY))
a = np.zeros(5 * 10**7)
try:
    lk.solve(a)
    print("solved")
except Exception as e:
    print(type(e).__name__, isinstance(e, cm.CyclomechError), e)
""",
        env={"CYCLOMECH_MAX_BYTES": "1e15", "RAYON_NUM_THREADS": "1"},
    )
    assert "PanicException" not in r.stdout + r.stderr
    assert r.returncode == 0, r.stderr
    assert r.stdout.startswith("InputError True the linkage's results"), r.stdout
    assert "which the system could not allocate" in r.stdout


@pytest.mark.parametrize("analogs", [True, False])
def test_item14_linkage_results_that_cannot_fit_are_refused_before_allocating(monkeypatch, analogs):
    lk = cm.Linkage(
        {"A": (0, 0), "B": (1, 0), "C": (3.5, 2.5), "D": (4, 0)},
        [("A", "B"), ("B", "C"), ("C", "D")],
        ["A", "D"],
        ("A", "B"),
    )
    n = 1000
    # The size by hand: N × M × 2 float64, three copies with analogs, and three
    # bool flags per angle.
    need = n * 4 * 2 * 8 * (3 if analogs else 1) + 3 * n
    monkeypatch.setenv("CYCLOMECH_MAX_BYTES", str(need - 1))
    with pytest.raises(cm.InputError, match=r"the linkage's results .* needs .* GB, more than"):
        lk.solve(np.zeros(n), analogs=analogs)
    with pytest.raises(cm.InputError, match=r"solve fewer angles, points or geometries"):
        cm.linkage.solve_geometries(lk, np.zeros(n), lk.dimension_values[None], analogs=analogs)
    monkeypatch.setenv("CYCLOMECH_MAX_BYTES", str(need))
    assert lk.solve(np.zeros(n), analogs=analogs).xy.shape == (n, 4, 2)
    # A size whose element count overflows is refused without any environment.
    monkeypatch.delenv("CYCLOMECH_MAX_BYTES")
    sol = lk.solve(np.zeros(3))
    assert sol.ok.all()


_HUGE = 10**10  # 80 GB as float64 or int64


def _four_bar() -> cm.Linkage:
    return cm.Linkage(
        {"A": (0, 0), "B": (1, 0), "C": (3.5, 2.5), "D": (4, 0)},
        [("A", "B"), ("B", "C"), ("C", "D")],
        ["A", "D"],
        ("A", "B"),
    )


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda f, i: _four_bar().solve(f), "a float64 copy of angles"),
        (lambda f, i: _four_bar().solve(i), "a float64 copy of angles"),
        (
            lambda f, i: cm.impact.duhamel(f, f, omega_n=10.0, zeta=0.1, mass=1.0),
            "a float64 copy of t",
        ),
        (lambda f, i: cm.cyclogram.longest_path(3, i, i, f), "a float64 copy of weights"),
        (lambda f, i: cm.cyclogram.longest_path(3, i, i, f[:2]), "an int64 copy of src"),
    ],
    ids=["linkage angles", "linkage int angles", "duhamel t", "path weights", "path src"],
)
def test_an_input_copy_that_cannot_fit_is_refused_before_numpy_tries(call, message):
    """A broadcast view of 1e10 values must be copied before a kernel can read it
    (80 GB): an InputError naming the argument, its shape and the size, not numpy's
    MemoryError (which is not a CyclomechError) or the OOM killer."""
    f = np.broadcast_to(np.float64(0.1), (_HUGE,))
    i = np.broadcast_to(np.int32(1), (_HUGE,))
    with pytest.raises(cm.InputError, match=rf"{message} \(10000000000,\) needs 80 GB, more than"):
        call(f, i)


def test_a_small_broadcast_view_is_copied_and_solved():
    angles = np.broadcast_to(np.float64(0.3), (4,))
    np.testing.assert_array_equal(
        _four_bar().solve(angles).xy, _four_bar().solve(np.full(4, 0.3)).xy
    )


def test_item14_press_solve_results_that_cannot_fit_are_refused(monkeypatch):
    designs = np.array([[0.09, 0.03, 0.028, 0.46, math.radians(56), 0.0]])
    monkeypatch.setenv("CYCLOMECH_MAX_BYTES", "1000")
    with pytest.raises(cm.InputError, match=r"the press's kinematics .* needs"):
        _core.press_solve(designs, np.linspace(0, 1, 100))


# ---------------------------------------------------------------------------
# Item 13: TransferPath.sample(10**9) was OOM-killed (it grows to ~100 GB).


def test_item13_transfer_sample_that_cannot_fit_is_refused_before_allocating(monkeypatch):
    p = cm.transfer.TransferPath(0.15, 0.25, (0, 0), (0.41, 0), x2=0.05)
    # 1e12 points need ~1e14 bytes: more than any machine has, so refused in
    # microseconds without an environment setting (main allocated until killed).
    with pytest.raises(
        cm.InputError, match=r"TransferPath.sample\(1000000000000\) needs 1.12e\+05 GB"
    ):
        p.sample(10**12)
    # The 1e9 against a budget set below it, so the test does not depend
    # on this machine's memory: 1e9 × 112 bytes.
    monkeypatch.setenv("CYCLOMECH_MAX_BYTES", "1e11")
    with pytest.raises(cm.InputError, match=r"needs 112 GB, more than the 100 GB"):
        p.sample(10**9)
    # The budget is the peak it really takes: 1e5 points fit in 112 × 1e5 bytes.
    monkeypatch.setenv("CYCLOMECH_MAX_BYTES", str(112 * 10**5))
    assert p.sample(10**5).s.shape == (10**5,)


# ---------------------------------------------------------------------------
# Item 13: a sweep and the press's grids that cannot fit.


def test_item13_a_sweep_too_large_for_memory_is_refused_before_allocating():
    """cm.sweep with 1e9 designs raised a bare MemoryError (or was killed) after
    allocating its index grid; it is refused first, naming the sizes."""
    m = cm.Machine.example()
    grid = {
        "lifter.preload_m": np.linspace(1e-4, 3e-4, 100_000),
        "lifter.a_max_m": np.linspace(1e-4, 2e-4, 10_000),
        "speed_rpm": [300.0],
    }
    with pytest.raises(cm.InputError, match=r"1,000,000,000 designs × 1 speeds.*GB"):
        cm.sweep(m, grid, progress=False)


def test_item13_press_command_step_is_bounded(tmp_path, capsys):
    """`--step-deg 1e-6` asked for 3.6e8 angles (gigabytes) before any check."""
    press = str(EXAMPLES / "extrusion_press.toml")
    assert main(["press", press, "--out", str(tmp_path), "--step-deg", "1e-6"]) == 2
    assert "[0.001, 90]" in capsys.readouterr().err


def test_item13_press_design_grid_too_large_is_refused_before_allocating():
    """press.design_grid with 1e9 designs raised a bare MemoryError from its table."""
    axis = np.linspace(0.0, 0.04, 1000)
    with pytest.raises(cm.InputError, match=r"1,000,000,000 designs needs .* GB"):
        cm.press.design_grid(R=0.09, r=0.03, d=axis, L=axis + 0.25, phi0=axis, k_Sp=0.1, omega=4.19)


def test_small_sizes_skip_the_read_of_available_memory_but_not_the_cap(monkeypatch):
    # Reading /proc/meminfo costs ~13 µs, paid by every kernel call; a result of at
    # most UNCHECKED_BYTES cannot be what exhausts memory, so it is not read. The
    # environment's cap holds at every size.
    from cyclomech import _arrays

    reads = []

    def tiny() -> int:
        reads.append(1)
        return 1000

    monkeypatch.delenv("CYCLOMECH_MAX_BYTES", raising=False)
    monkeypatch.setattr(_arrays, "available_bytes", tiny)
    _arrays.check_bytes("a small array", _arrays.UNCHECKED_BYTES, "fewer points")
    assert reads == []
    with pytest.raises(cm.InputError, match=r"a larger array needs .* more than the 1e-06 GB"):
        _arrays.check_bytes("a larger array", _arrays.UNCHECKED_BYTES + 1, "fewer points")
    assert reads == [1]
    with pytest.raises(cm.InputError, match="which the system could not allocate"):
        _arrays.check_bytes("a failed array", 8.0, "fewer points", failed=True)
    monkeypatch.undo()
    monkeypatch.setenv("CYCLOMECH_MAX_BYTES", "100")
    with pytest.raises(cm.InputError, match=r"needs 1e-06 GB, more than the 1e-07 GB"):
        _arrays.check_bytes("a small array", 1000, "fewer points")
