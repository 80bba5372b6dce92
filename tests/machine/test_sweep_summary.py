"""`cyclomech sweep`'s per-design summary: the designs with the highest and the
lowest speed limit, read from the kept columns or streamed from the Parquet file."""

from __future__ import annotations

from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest
from cyclomech.cli import main
from cyclomech.machine.cli import design_range

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


def test_ties_keep_the_first_design_and_no_limit_gives_no_line() -> None:
    cols = {
        "a.x": np.array([1.0, 1.0, 2.0, 2.0, 3.0, 3.0]),
        "speed_limit_rpm": np.array([5.0, 5.0, np.nan, np.nan, 5.0, 5.0]),
    }
    text = design_range(Path("unused"), cols, ["a.x"])
    assert text.splitlines()[1].endswith("a.x=1") and text.splitlines()[2].endswith("a.x=1")
    cols["speed_limit_rpm"][:] = np.nan
    assert design_range(Path("unused"), cols, ["a.x"]) == ""


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
