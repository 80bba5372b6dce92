"""Fitting the operations' labels to their bars, for :mod:`cyclomech.cyclogram.plot`.

A label is never cut short: a title that fits neither on its bar nor beside it is
replaced there by a number, and the numbers are keyed, with the whole titles, in a
legend beside the axes. matplotlib is imported only inside the functions.

>>> fit_label("lift", "45°", 60.0, 20.0, 7.5)           # a bar 60 pt × 20 pt, 7.5 pt text
'lift 45°'
>>> fit_label("carry the weft across", None, 60.0, 20.0, 7.5)   # on two lines
'carry the\\nweft across'
>>> print(fit_label("carry the weft across the whole loom web", None, 60.0, 20.0, 7.5))
None
>>> key_entries([(3, "carry the weft across the whole loom web")], heading=True)[1]
['numbered operations', '3  carry the weft across the whole loom web']
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from collections.abc import Sequence

    from matplotlib.axes import Axes
    from matplotlib.legend import Legend

#: Title of the key of numbered operations.
KEY_TITLE = "numbered operations"


#: Widths measured (:func:`text_width_pt`), by the text and everything about its font
#: that the measure reads; at most :data:`_WIDTHS_SIZE`.
_WIDTHS: dict[tuple[Any, ...], float] = {}
_WIDTHS_SIZE = 4096


def text_width_pt(text: str, size: float, bold: bool = False) -> float:
    """Width [pt] of one line of text at ``size`` pt in the default font.

    The width of the text's outline (a ``TextPath``'s extents: a few ms, most of
    the time a figure's labels take, each label tried in up to four forms in each
    of two figures) is measured once for a text, its font's properties and the
    font file they resolve to; a text with ``$`` (mathtext, which reads more
    settings) is measured every time."""
    import matplotlib as mpl
    from matplotlib.font_manager import FontProperties, findfont
    from matplotlib.textpath import TextPath

    prop = FontProperties(size=size, weight="bold" if bold else "normal")
    key = None
    if "$" not in text:
        font = (
            tuple(prop.get_family()),
            prop.get_style(),
            prop.get_variant(),
            prop.get_weight(),
            prop.get_stretch(),
            prop.get_size_in_points(),
            prop.get_file(),
            prop.get_math_fontfamily(),
        )
        key = (text, font, findfont(prop), mpl.rcParams["text.parse_math"])
        if key in _WIDTHS:
            return _WIDTHS[key]
    width = float(TextPath((0, 0), text, prop=prop).get_extents().width)
    if key is not None and len(_WIDTHS) < _WIDTHS_SIZE:
        _WIDTHS[key] = width
    return width


def _two_lines(text: str) -> str | None:
    """``text`` broken at the space nearest its middle, or None without a space."""
    spaces = [i for i, c in enumerate(text) if c == " "]
    if not spaces:
        return None
    k = min(spaces, key=lambda i: abs(2 * i - len(text)))
    return text[:k] + "\n" + text[k + 1 :]


def _candidates(title: str, angle: str | None) -> list[str]:
    """Labels from the most to the least informative: title and angle, on one or two
    lines, then the title alone, on one or two lines."""
    out = [] if angle is None else [f"{title} {angle}", f"{title}\n{angle}"]
    out.append(title)
    wrapped = _two_lines(title)
    if wrapped is not None:
        out.append(wrapped)
    return out


def fit_label(
    title: str,
    angle: str | None,
    width_pt: float,
    height_pt: float,
    size: float,
    bold: bool = False,
    *,
    lines: int = 2,
) -> str | None:
    """The first of :func:`_candidates` (of at most ``lines`` lines) that fits whole
    in a box ``width_pt`` × ``height_pt``, else None (never a title cut short)."""
    line_pt = 1.2 * size
    for text in _candidates(title, angle):
        rows = text.split("\n")
        if len(rows) > lines or len(rows) * line_pt > height_pt:
            continue
        if max(text_width_pt(row, size, bold) for row in rows) <= width_pt:
            return text
    return None


def key_entries(
    titles: Sequence[tuple[int, str]], heading: bool = False
) -> tuple[list[Any], list[str]]:
    """Legend handles (invisible) and labels ``"k  title"`` of numbered operations
    ``(k, title)`` (k: the operation's position in the cyclogram, the same in every
    figure), with ``heading`` after a first entry :data:`KEY_TITLE` (none without
    titles)."""
    from matplotlib.patches import Patch

    labels = [f"{k}  {t}" for k, t in sorted(titles)]
    if heading and titles:
        labels.insert(0, KEY_TITLE)
    return [Patch(visible=False) for _ in labels], labels


def key_legend(ax: Axes, titles: Sequence[tuple[int, str]], **where: Any) -> Legend | None:
    """The key of the numbered operations (``(number, title)``, see :func:`key_entries`),
    added to ``ax`` at ``where`` (``loc``, ``bbox_to_anchor``, …) in place of a key
    drawn before (none without titles); its gid is ``"key"``."""
    from matplotlib.legend import Legend

    for old in [a for a in ax.artists if a.get_gid() == "key"]:
        old.remove()  # a key drawn before
    if not titles:
        return None
    handles, labels = key_entries(titles)
    style: dict[str, Any] = {
        "alignment": "left",
        "title": KEY_TITLE,
        "title_fontsize": 8,
        "fontsize": 8,
    }
    key = Legend(ax, handles, labels, **style, handlelength=0, handletextpad=0, **where)
    key.set_clip_on(False)  # else add_artist clips it to the axes: out of the layout
    key.set_gid("key")
    ax.add_artist(key)
    return key
