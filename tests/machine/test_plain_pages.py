"""A sweep's result is allocated without numpy's huge-page advice (issue 20): on
VMs whose kernel finds no free huge page, the advice made the first touch of the
result's columns stall (~150 ms a 10⁶-point sweep). The switch must be restored
after the block, an exception included."""

from __future__ import annotations

import numpy as np
import pytest
from cyclomech._arrays import plain_pages

multiarray = pytest.importorskip("numpy._core.multiarray")
toggle = getattr(multiarray, "_set_madvise_hugepage", None)
pytestmark = pytest.mark.skipif(toggle is None, reason="this numpy has no huge-page switch")


def advice_on() -> bool:
    """numpy's current setting (read by setting it back to what it was)."""
    assert toggle is not None
    was = toggle(True)
    toggle(was)
    return bool(was)


@pytest.mark.parametrize("start", [True, False])
def test_the_switch_is_off_inside_and_restored_after(start: bool) -> None:
    assert toggle is not None
    before = toggle(start)
    try:
        with plain_pages():
            assert advice_on() is False
        assert advice_on() is start
        with pytest.raises(RuntimeError), plain_pages():
            raise RuntimeError("an allocation that fails")
        assert advice_on() is start
    finally:
        toggle(before)


def advised(a: np.ndarray) -> bool | None:
    """Whether a memory mapping holding part of ``a`` carries the huge-page advice
    (``hg`` in /proc/self/smaps' VmFlags: numpy advises the 2 MB-aligned part, a
    mapping of its own); None where there is no such file."""
    try:
        with open("/proc/self/smaps", encoding="ascii") as f:
            text = f.read()
    except OSError:
        return None
    lo_a, hi_a = a.ctypes.data, a.ctypes.data + a.nbytes
    found, inside = False, False
    for line in text.splitlines():
        head = line.split()[0]
        if "-" in head and ":" not in head:
            lo, hi = (int(x, 16) for x in head.split("-"))
            inside = lo < hi_a and lo_a < hi
        elif inside and head == "VmFlags:":
            found |= "hg" in line.split()[1:]
    return found


_SWEEP_IN_A_FRESH_PROCESS = """
import sys
import numpy as np
import cyclomech as cm
sys.path.insert(0, "tests/machine")
from test_plain_pages import advice_on, advised

loom = cm.Machine.from_toml("tests/machine/data/stb_loom_stop_only.toml")
grid = {"lifter.preload_m": np.linspace(1e-4, 5e-4, 6000), "speed_rpm": np.linspace(200, 500, 100)}
col = cm.sweep(loom, grid, progress=False).columns["limiting_deg"]
assert col.nbytes > 1 << 22 and advice_on() is True
print(advised(col), advised(np.zeros(10**6)))
"""


def test_a_sweeps_columns_carry_no_advice_and_the_switch_is_restored() -> None:
    # 6000 designs × 100 speeds: each float column 4.8 MB, above numpy's 4 MiB. In
    # a fresh process: in this one, glibc may place the columns in heap memory an
    # earlier array was advised on (the flag stays with the mapping).
    import subprocess
    import sys
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    out = subprocess.run(
        [sys.executable, "-c", _SWEEP_IN_A_FRESH_PROCESS],
        cwd=root,
        capture_output=True,
        text=True,
        check=True,
    ).stdout.split()
    if out[0] == "None" or out[1] != "True":
        pytest.skip("no huge-page advice to see on this system")
    assert out[0] == "False"
