"""Times the machine layer's main calls, to compare two trees of the Python layer
on one Rust build (how issue 17's restructuring was checked; see BENCHMARKS.md).

    python benches/ab_machine_layer.py                           # this tree
    git archive f90fab7 python | tar -x -C /tmp/old              # an older tree …
    cp python/cyclomech/_core.abi3.so /tmp/old/python/cyclomech/ # … on this build
    PYTHONPATH=/tmp/old/python python benches/ab_machine_layer.py

Alternate the two a few times on a busy machine and compare medians. Prints the
median of 5 calls of each, one thread.
"""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable
from pathlib import Path

import cyclomech as cm
import numpy as np

try:
    from cyclomech.machine import analyze
except ImportError:  # the layout before issue 17
    from cyclomech.report import analyze  # type: ignore[no-redef]

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def median_seconds(f: Callable[[], object], n: int = 5) -> float:
    times = []
    for _ in range(n):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def main() -> None:
    loom_file, knife_file = EXAMPLES / "stb_loom.toml", EXAMPLES / "knife_cutter.toml"
    loom = cm.Machine.from_toml(loom_file)
    rpm = np.linspace(200.0, 500.0, 100_000)
    grid = {
        "lifter.preload_m": np.linspace(1e-4, 5e-4, 400),
        "speed_rpm": np.linspace(200, 500, 51),
    }
    calls = {
        "parse loom": lambda: cm.Machine.from_toml(loom_file),
        "loom speed_sweep 1e5 speeds": lambda: loom.speed_sweep(rpm, n_threads=1),
        "loom speed_limit": lambda: cm.Machine.from_toml(loom_file).speed_limit(n_threads=1),
        "loom analyze": lambda: analyze(cm.Machine.from_toml(loom_file), progress=False),
        "knife analyze": lambda: analyze(cm.Machine.from_toml(knife_file), progress=False),
        "loom sweep 400 designs x 51 speeds": lambda: cm.sweep(
            loom, grid, progress=False, n_threads=1
        ),
    }
    for name, f in calls.items():
        print(f"{name:40s} {median_seconds(f) * 1e3:10.2f} ms")


if __name__ == "__main__":
    main()
