"""A cyclogram's labels are whole and inside the figure (new-user review): a Gantt
bar too short for its 40-character title had the title cut short (``"carry…"``);
now the bar gets a number and the whole title is keyed beside the axes, as on the
circular diagram. Checked on the saved figure: the text artists' rendered extents."""

from __future__ import annotations

import io

import matplotlib
import matplotlib.legend

matplotlib.use("Agg")

import cyclomech as cm
import matplotlib.pyplot as plt
import pytest
from cyclomech.plot import plot_cyclogram, plot_cyclogram_pair
from matplotlib.figure import Figure
from matplotlib.text import Text

LONG = "carry the weft across the whole loom web"
OTHER = "another rather long operation name here"


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def loom(*, gripper: bool = False) -> cm.Optimum:
    cg = cm.Cyclogram("group 1", limiting=("10.1", "10.2"))
    cg.add_operation("1", "3", min_angle_deg=45, name="lift", mechanism="lifter")
    cg.add_operation("3", "7", min_angle_deg=20, name=LONG, mechanism="lifter")
    cg.add_operation("7", "10.1", min_angle_deg=20, mechanism="lifter")
    cg.add_operation("10.1", "10.2", min_angle_deg=120, name="weft insertion")
    if gripper:
        cg.add_operation("3", "4", min_angle_deg=10, name=OTHER, mechanism="gripper")
    return cg.optimize()


def saved_texts(fig: Figure) -> list[Text]:
    """The operations' labels and the legends' texts of ``fig``, drawn as saved."""
    fig.savefig(io.BytesIO(), format="png", dpi=100)
    out: list[Text] = []
    for ax in fig.axes:
        out += ax.texts
        legends = [a for a in ax.get_children() if isinstance(a, matplotlib.legend.Legend)]
        for lg in legends:
            out += [*lg.get_texts(), lg.get_title()]
    return [t for t in out if t.get_visible() and t.get_text()]


def whole_and_inside(fig: Figure, title: str) -> list[Text]:
    """The texts holding ``title`` whole; each text of the figure lies inside it."""
    texts = saved_texts(fig)
    box = fig.bbox
    renderer = fig.canvas.get_renderer()
    for t in texts:
        e = t.get_window_extent(renderer)
        assert box.x0 <= e.x0 and e.x1 <= box.x1 + 0.5, (t.get_text(), e, box)
        assert box.y0 <= e.y0 and e.y1 <= box.y1 + 0.5, (t.get_text(), e, box)
        assert "…" not in t.get_text().replace("… ", ""), t.get_text()  # never cut short
    return [t for t in texts if title in t.get_text().replace("\n", " ")]


def test_a_long_title_on_a_short_gantt_bar_is_keyed_whole():
    assert len(LONG) == 40
    ax = plot_cyclogram(loom())
    holding = whole_and_inside(ax.figure, LONG)
    # Numbered by its position in the cyclogram (the second operation), in every
    # figure alike.
    assert [t.get_text() for t in holding] == [f"2  {LONG}"]  # in the legend's key
    on_bars = [t.get_text() for t in ax.texts]
    assert "2" in on_bars  # the bar's number
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert legend[-2:] == ["numbered operations", f"2  {LONG}"]


def test_a_title_that_fits_is_not_keyed():
    _, ax = plt.subplots(figsize=(30, 3), layout="constrained")  # room on every bar
    plot_cyclogram(loom(), ax=ax)
    assert any(LONG in t.get_text().replace("\n", " ") for t in ax.texts)
    assert "numbered operations" not in [t.get_text() for t in ax.get_legend().get_texts()]


def test_the_pair_keys_both_diagrams_inside_the_figure():
    fig = plot_cyclogram_pair(loom(gripper=True))
    gantt, _ = fig.axes
    assert whole_and_inside(fig, LONG)
    assert whole_and_inside(fig, OTHER)
    assert gantt.get_legend() is None  # the Gantt's key is an artist of its own
    keys = [a for ax in fig.axes for a in ax.artists if a.get_gid() == "key"]
    assert len(keys) == 2  # one key per diagram, not one per layout pass


def test_the_pair_numbers_an_operation_alike_in_both_diagrams():
    """A new user's loom figures numbered 'open gripper spring' 2 on the Gantt chart
    and 'approach upper stop' 2 on the circular diagram: an operation's number is
    its position in the cyclogram, in both keys."""
    fig = plot_cyclogram_pair(loom(gripper=True))
    titles = [op.title for op in loom(gripper=True).operations]
    keyed = [
        t.get_text()
        for leg in fig.findobj(matplotlib.legend.Legend)
        for t in leg.get_texts()
        if t.get_text()[:1].isdigit()
    ]
    assert keyed, "nothing numbered: the test needs a keyed title"
    for entry in keyed:
        k, title = entry.split("  ", 1)
        assert titles[int(k) - 1] == title, entry


def _outline_width(text: str, size: float, bold: bool) -> float:
    """The width as matplotlib measures a text's outline, here, no memo."""
    from matplotlib.font_manager import FontProperties
    from matplotlib.textpath import TextPath

    prop = FontProperties(size=size, weight="bold" if bold else "normal")
    return float(TextPath((0, 0), text, prop=prop).get_extents().width)


def test_a_measured_width_is_kept_and_the_font_is_in_its_key():
    """text_width_pt keeps what it measured (the labels' fitting tries each title in
    several forms, in two figures): a kept width is the measure's to the bit, and a
    change of the font's settings is measured anew, not answered from the memo."""
    from cyclomech.cyclogram import _labels

    _labels._WIDTHS.clear()
    for text, size, bold in [(LONG, 7.5, False), (LONG, 7.5, True), ("lift 45°", 9.0, False)]:
        want = _outline_width(text, size, bold)
        assert _labels.text_width_pt(text, size, bold) == want  # measured
        assert _labels.text_width_pt(text, size, bold) == want  # kept
    assert len(_labels._WIDTHS) == 3
    with matplotlib.rc_context({"font.family": "serif", "font.serif": ["DejaVu Serif"]}):
        serif = _labels.text_width_pt(LONG, 7.5)
        assert serif == _outline_width(LONG, 7.5, False)
    assert serif != _labels.text_width_pt(LONG, 7.5)  # the sans-serif width, kept
    assert len(_labels._WIDTHS) == 4
    assert _labels.text_width_pt("$x^2$ lift", 7.5) == _outline_width("$x^2$ lift", 7.5, False)
    assert len(_labels._WIDTHS) == 4  # mathtext is measured every time
