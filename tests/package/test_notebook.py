"""Results in a notebook (issue 36, item 5): each main result shows itself as HTML
(``_repr_html_``: its key numbers and its key figure inline) and gives its tables as
pandas DataFrames (``to_pandas()``) equal to what the rest of the package computes."""

from __future__ import annotations

import math
import sys
from html.parser import HTMLParser
from pathlib import Path

import cyclomech as cm
import numpy as np
import pytest

pd = pytest.importorskip("pandas")
ROOT = Path(__file__).resolve().parents[2]


class _Page(HTMLParser):
    """Counts the tags of an HTML fragment and collects its table cells' text."""

    def __init__(self) -> None:
        super().__init__()
        self.tags: dict[str, int] = {}
        self.cells: list[str] = []
        self._in_cell = False

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        self.tags[tag] = self.tags.get(tag, 0) + 1
        self._in_cell = tag in ("td", "th")
        if self._in_cell:
            self.cells.append("")

    def handle_endtag(self, tag: str) -> None:
        if tag in ("td", "th"):
            self._in_cell = False

    def handle_data(self, data: str) -> None:
        if self._in_cell:
            self.cells[-1] += data


def _page(html: str) -> _Page:
    p = _Page()
    p.feed(html)
    return p


@pytest.fixture(scope="module")
def knife() -> cm.machine.MachineResult:
    path = ROOT / "examples" / "knife_cutter.toml"  # the wheel's test runs elsewhere
    return cm.machine.analyze(cm.Machine.from_toml(path), progress=False)


def _cam() -> cm.cam.Cam:
    S = cm.cam.Segment
    return cm.cam.Cam(
        [S("rise", 120, 0.02), S("dwell", 60), S("return", 120, 0.02), S("dwell", 60)],
        cm.cam.TranslatingRoller(0.05, 0.01),
    )


def test_machine_tables_equal_the_report_files(knife, tmp_path):
    written = cm.machine.write_report(knife, tmp_path, figures=False)
    names = ["speed_sweep.csv", "operations.csv", "main_shaft.csv", "main_shaft_speed.csv"]
    csvs = [*names, "knife_forces.csv"]  # the tables; the drawing table is a part, not one
    assert set(csvs) <= {p.name for p in written}
    for name in csvs:
        df = knife.to_pandas(name)
        on_disk = pd.read_csv(tmp_path / name, index_col=df.index.name)
        assert list(on_disk.columns) == list(df.columns), name
        for col in df.columns:
            if df[col].dtype.kind == "f":
                np.testing.assert_allclose(
                    on_disk[col], df[col], rtol=1e-9, err_msg=f"{name}: {col}"
                )


def test_machine_operations_frame_is_the_optimum(knife):
    df, o = knife.to_pandas(), knife.optimum
    assert o is not None
    for op in knife.machine.cyclogram.operations:
        assert df.loc[op.title, "angle_deg"] == o.angles[op.arc]
        assert df.loc[op.title, "start_deg"] == o.times[op.src]


def test_machine_unknown_table_names_those_it_has(knife):
    with pytest.raises(cm.InputError, match=r"'shaft\.csv'.*speed_sweep\.csv, operations\.csv"):
        knife.to_pandas("shaft.csv")


def test_machine_html_shows_the_limit_the_operations_and_the_cyclogram(knife):
    html = knife._repr_html_()
    page = _page(html)
    assert page.tags["table"] == 2 and page.tags["svg"] == 1 and "<?xml" not in html
    cells = page.cells
    assert cells[cells.index("speed limit [rpm]") + 1] == f"{knife.limit.rpm:.6g}"
    titles = [op.title for op in knife.machine.cyclogram.operations]
    assert all(t in cells for t in titles)


def test_optimum_frame_and_html():
    cg = cm.Cyclogram()
    cg.add_operation("a", "b", 30, mechanism="m")
    cg.add_operation("b", "c", 50, mechanism="m")
    cg.add_operation("a", "c", 100, mechanism="n")
    o = cg.optimize()
    df = o.to_pandas()
    assert df["angle_deg"].tolist() == [o.angles[op.arc] for op in o.operations]
    assert df["start_deg"].tolist() == [o.times[op.src] for op in o.operations]
    # a→b→c must last as long as a→c's 100°: the chain's 20° to spare go to its parts.
    assert df.loc["b→c", "start_deg"] == df.loc["a→b", "angle_deg"]
    assert math.isclose(df.loc["a→b", "angle_deg"] + df.loc["b→c", "angle_deg"], 100.0)
    assert math.isclose(df["beyond_minimum_deg"].sum(), 20.0)
    assert bool(df.loc["a→c", "critical"])
    page = _page(o._repr_html_())
    assert page.tags["svg"] == 1 and page.tags["table"] == 2
    assert page.cells[page.cells.index("optimum [deg]") + 1] == "100"


def test_cam_frame_is_its_geometry():
    cam = _cam()
    df = cam.to_pandas(720)
    theta = np.radians(df.index.to_numpy())
    k = cam.solve(theta)
    np.testing.assert_array_equal(df["s_m"], k.s)
    np.testing.assert_array_equal(df["profile_x_m"], k.profile[:, 0])
    # Half the stroke at mid-rise: every built-in law is odd about its middle.
    assert math.isclose(df.loc[60.0, "s_m"], 0.01, rel_tol=1e-12)
    page = _page(cam._repr_html_())
    assert page.tags["svg"] == 1
    cells = page.cells
    alpha = float(cells[cells.index("largest |pressure angle| [deg]") + 1])
    assert math.isclose(
        alpha,
        np.degrees(np.abs(cam.solve(np.radians(np.arange(3600) / 10)).pressure_angle)).max(),
        rel_tol=1e-5,
    )
    assert cells[cells.index("undercut") + 1] == "none"


def test_kinetostatics_frame_is_the_closed_form():
    # A crank of radius r with a point mass m at its end: the frame bearing carries
    # m ω² r outwards, (m ω² r cos θ, m ω² r sin θ), and the static torque is m g r cos θ.
    r, m, rpm = 0.3, 2.0, 60.0
    crank = cm.Linkage({"O": (0, 0), "A": (r, 0)}, [("O", "A")], ["O"], ("O", "A"))
    theta = np.radians(np.arange(0.0, 360.0, 15.0))
    k = cm.forces.kinetostatics(crank, theta, point_masses={"A": m}, gravity=(0, -9.81))
    df = k.to_pandas(rpm)
    w2 = (rpm * 2 * math.pi / 60) ** 2
    np.testing.assert_allclose(df["fx_n[O on frame]"], m * w2 * r * np.cos(theta), atol=1e-9)
    np.testing.assert_allclose(
        df["fy_n[O on frame]"], m * w2 * r * np.sin(theta) - m * 9.81, atol=1e-9
    )
    np.testing.assert_allclose(df["torque_nm"], m * 9.81 * r * np.cos(theta), atol=1e-9)
    np.testing.assert_allclose(df.index, np.degrees(theta))
    page = _page(k._repr_html_())
    assert page.tags["svg"] == 1
    cells = page.cells
    assert float(
        cells[cells.index("peak |static torque| (gravity, loads) [N·m]") + 1]
    ) == pytest.approx(m * 9.81 * r, rel=1e-5)


def test_without_pandas_the_error_says_how_to_install_it(monkeypatch, knife):
    monkeypatch.setitem(sys.modules, "pandas", None)
    for call in (lambda: _cam().to_pandas(36), lambda: knife.to_pandas()):
        with pytest.raises(ImportError, match="pip install pandas"):
            call()
