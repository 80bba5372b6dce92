"""`cyclomech sweep`'s per-design summary: the designs with the highest and the
lowest speed limit, read from the kept columns or streamed from the Parquet file."""

from __future__ import annotations

from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.cli import main
from cyclomech.machine.cli import TIE_RTOL, design_range

# Absolute: the module fixture runs before the tests' chdir to the repository root
# (tests/conftest.py), and the installed-wheel job runs from elsewhere.
LOOM = str(Path(__file__).resolve().parents[2] / "examples" / "stb_loom.toml")
PRELOADS = [1e-4, 2.5e-4, 4e-4]


@pytest.fixture(scope="module")
def kept() -> cm.SweepResult:
    m = cm.Machine.from_toml(LOOM)
    return cm.sweep(m, {"lifter.preload_m": PRELOADS, "speed_rpm": [250.0, 300.0]}, progress=False)


def test_the_range_is_the_designs_own_speed_limits(kept: cm.SweepResult) -> None:
    # Independent: each design's speed limit from a machine of its own.
    limits = []
    for p in PRELOADS:
        m = cm.Machine.from_toml(LOOM).with_values({"lifter.preload_m": p})
        limits.append(m.speed_limit().rpm)
    hi, lo = int(np.argmax(limits)), int(np.argmin(limits))
    assert hi != lo
    text = design_range(Path("unused"), kept.columns, ["lifter.preload_m"])
    first, high, low = text.splitlines()
    assert f"{min(limits):.4g}–{max(limits):.4g} rpm" in first
    assert high.split() == [
        "highest",
        f"{limits[hi]:.4g}",
        "rpm",
        "at",
        f"lifter.preload_m={PRELOADS[hi]:g}",
    ]
    assert low.split() == [
        "lowest",
        f"{limits[lo]:.4g}",
        "rpm",
        "at",
        f"lifter.preload_m={PRELOADS[lo]:g}",
    ]


def test_streamed_and_kept_give_the_same_line(kept: cm.SweepResult, tmp_path: Path) -> None:
    pytest.importorskip("pyarrow")
    path = kept.write(tmp_path / "s.parquet")
    assert design_range(path, {}, ["lifter.preload_m"]) == design_range(
        Path("unused"), kept.columns, ["lifter.preload_m"]
    )


def test_ties_name_the_first_design_and_count_the_others() -> None:
    # Two rows a design. Design 0 and 2 tie at the highest exactly, design 3 within
    # TIE_RTOL of it (a tie), design 4 just outside (above: it is the highest, alone).
    hi = 5.0
    limits = [hi, np.nan, hi, hi * (1 + 0.5 * TIE_RTOL), 3.0, 3.0]
    cols = {
        "a.x": np.repeat(np.arange(6.0), 2),
        "speed_limit_rpm": np.repeat(limits, 2),
    }
    first, high, low = design_range(Path("unused"), cols, ["a.x"]).splitlines()
    assert high.endswith("rpm at a.x=0 (and 2 more designs at it)"), high
    assert low.endswith("rpm at a.x=4 (and 1 more design at it)"), low
    cols["speed_limit_rpm"][8:10] = hi * (1 + 3 * TIE_RTOL)  # design 4 now the highest
    high = design_range(Path("unused"), cols, ["a.x"]).splitlines()[1]
    assert high.endswith("rpm at a.x=4"), high
    # every design fitting up to the speed cap: ∞ ties only with ∞
    cols["speed_limit_rpm"][:] = np.repeat([np.inf, 7.0, np.inf, 7.0, 7.0, np.nan], 2)
    first, high, low = design_range(Path("unused"), cols, ["a.x"]).splitlines()
    assert first.endswith("7–inf rpm")
    assert high.endswith("a.x=0 (and 1 more design at it)") and low.endswith(
        "a.x=1 (and 2 more designs at it)"
    )
    cols["speed_limit_rpm"][:] = np.nan
    assert design_range(Path("unused"), cols, ["a.x"]) == ""


def test_ties_are_counted_across_the_streamed_batches(tmp_path: Path) -> None:
    # Parquet is read 65 536 rows at a time: a tie in a later batch is counted, a
    # higher limit there within TIE_RTOL keeps the first design.
    pa = pytest.importorskip("pyarrow")
    import pyarrow.parquet as pq

    n = 200_000
    lim = np.full(n, 4.0)
    lim[[10, 70_000, 150_000]] = [6.0, 6.0 * (1 + 0.2 * TIE_RTOL), 6.0]
    lim[199_999] = 2.0
    path = tmp_path / "s.parquet"
    table = {"a.x": np.arange(n, dtype=np.float64), "speed_limit_rpm": lim}
    pq.write_table(pa.table(table), path)
    streamed = design_range(path, {}, ["a.x"])
    assert streamed == design_range(Path("unused"), table, ["a.x"])
    _, high, low = streamed.splitlines()
    assert high.endswith("rpm at a.x=10 (and 2 more designs at it)"), high
    assert low.endswith("rpm at a.x=199999"), low


def test_the_command_prints_it(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    argv = ["sweep", LOOM, "--set", "lifter.preload_m=1e-4:4e-4:2", "--speed", "250:300:2"]
    assert main([*argv, "--out", str(tmp_path), "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "speed limit over the designs:" in out
    assert "highest" in out and "lowest" in out


@pytest.mark.parametrize(
    ("option", "message"),
    [
        (["--speed", "500:200:7"], "--speed 500:200:7 must go from a lower"),
        (["--threads", "0"], "--threads 0 must be between 1 and 1024"),
    ],
)
def test_a_bad_option_is_named(
    option: list[str], message: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["sweep", LOOM, *option, "--out", str(tmp_path), "--quiet"]) == 2
    # (the file is named too, as for every error of a command on a file)
    err = capsys.readouterr().err
    assert err.startswith(f"cyclomech: error: {LOOM}: {message}") and err.count("\n") == 1


def test_a_sweep_that_fits_nowhere_exits_3_and_one_design_gets_its_limit(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = ["sweep", LOOM, "--out", str(tmp_path), "--quiet"]
    assert main([*argv, "--speed", "900:1000:3"]) == 3
    out, err = capsys.readouterr()
    assert "fits at 0 of them" in out and "fits at no point of the sweep" in err
    assert "speed limit of the design: 420.3 rpm" in out  # the file's own design
    assert main([*argv, "--speed", "300:400:2"]) == 0
    assert "speed limit of the design: 420.3 rpm" in capsys.readouterr().out
