"""How results show themselves in a notebook (private): the HTML that Jupyter
displays for a result (``_repr_html_``: a short table of its key numbers and its
key figure inline as SVG) and the pandas DataFrame of a result's table
(``to_pandas()``).

A result's figure is drawn by its domain's plot module (``cyclomech.<domain>.plot``),
which registers the drawing with :func:`register_figure` when it is imported; the
result's module does not import its plot module (plots stand on results, not the
reverse): :func:`figure_of` imports the domain's plot module by name when a figure
is asked for.

Both are optional: without matplotlib the HTML has the table and a line saying
how to get the figure; without pandas ``to_pandas()`` raises the ImportError that
says how to install it. Nothing here computes a number: the results hand over
the rows and columns their reports and CSV files already use.

>>> from cyclomech._notebook import html_card
>>> html = html_card("Demo", [("speed limit [rpm]", 123.456789), ("status", "a < b")])
>>> "<table" in html, "123.457" in html, "a &lt; b" in html
(True, True, True)
"""

from __future__ import annotations

import html
import importlib
import io
import math
import re
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

__all__ = [
    "FIGURES",
    "data_frame",
    "figure_of",
    "html_card",
    "html_table",
    "pandas",
    "register_figure",
    "table_frame",
]

#: The figure's width in the notebook [px]: wide enough to read, narrow enough to
#: sit beside the table on a laptop's screen.
FIGURE_WIDTH_PX = 800


def _cell(v: Any) -> str:
    """A value as the text of a table cell: numbers to 6 significant digits."""
    if isinstance(v, bool | np.bool_):
        return "yes" if v else "no"
    if isinstance(v, int | np.integer):
        return str(int(v))
    if isinstance(v, float | np.floating):
        x = float(v)
        return "∞" if math.isinf(x) and x > 0 else f"{x:.6g}"
    return html.escape(str(v))


def html_table(header: Sequence[str] | None, rows: Sequence[Sequence[Any]]) -> str:
    """An HTML table of ``rows`` (each a sequence of cells) under ``header``.

    Examples
    --------
    >>> html_table(["a", "b"], [[1, 2.5]])
    '<table><thead><tr><th>a</th><th>b</th></tr></thead><tbody><tr><td>1</td><td>2.5</td></tr></tbody></table>'
    """
    head = ""
    if header is not None:
        head = (
            "<thead><tr>" + "".join(f"<th>{html.escape(h)}</th>" for h in header) + "</tr></thead>"
        )
    body = "".join("<tr>" + "".join(f"<td>{_cell(c)}</td>" for c in row) + "</tr>" for row in rows)
    return f"<table>{head}<tbody>{body}</tbody></table>"


#: Result type → the function that draws its key figure (registered by the
#: domain's plot module).
FIGURES: dict[type, Callable[[Any], Any]] = {}


def register_figure(cls: type, draw: Callable[[Any], Any]) -> None:
    """Register ``draw(result) -> Figure`` as the notebook figure of ``cls``'s results.

    Examples
    --------
    >>> class R: ...
    >>> register_figure(R, lambda r: None)
    >>> R in FIGURES
    True
    """
    FIGURES[cls] = draw


def figure_of(result: Any) -> Callable[[], Any] | None:
    """The drawing of ``result``'s key figure (None without one): its domain's plot
    module, imported here by name, registers it.

    Examples
    --------
    >>> import cyclomech as cm
    >>> cg = cm.Cyclogram()
    >>> cg.add_operation("a", "b", 30)
    >>> callable(figure_of(cg.optimize())), figure_of(object())
    (True, None)
    """
    module = type(result).__module__
    if module.startswith("cyclomech."):
        try:
            importlib.import_module(module.split(".")[0] + "." + module.split(".")[1] + ".plot")
        except ModuleNotFoundError:
            return None
    draw = FIGURES.get(type(result))
    return None if draw is None else (lambda: draw(result))


def _svg(draw: Callable[[], Any]) -> str:
    """The figure ``draw()`` makes, as inline SVG (closed after), or a line saying
    how to get it when matplotlib is missing."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:  # pragma: no cover - exercised only without matplotlib
        return "<p><em>The figure needs matplotlib: pip install 'cyclomech[plot]'.</em></p>"
    import matplotlib.pyplot as plt

    fig = draw()
    try:
        buf = io.StringIO()
        fig.savefig(buf, format="svg", bbox_inches="tight")
    finally:
        plt.close(fig)
    svg = buf.getvalue()
    svg = svg[svg.index("<svg") :]  # drop the XML prologue and doctype: it is inline
    # The root's fixed size in pt: scaled to the box instead (the viewBox keeps its shape).
    head, rest = svg.split(">", 1)
    head = re.sub(r'\s(width|height)="[^"]*"', "", head) + ' style="width:100%;height:auto"'
    return f'<div style="max-width:{FIGURE_WIDTH_PX}px">{head}>{rest}</div>'


def html_card(
    title: str,
    rows: Sequence[tuple[str, Any]],
    figure: Callable[[], Any] | None = None,
    *,
    tables: Sequence[tuple[str, Sequence[str], Sequence[Sequence[Any]]]] = (),
) -> str:
    """A result's notebook view: a title, a two-column table of ``rows``
    (quantity, value), optional further ``tables`` (caption, header, rows), and
    the figure ``figure()`` draws, inline as SVG.

    Examples
    --------
    >>> out = html_card("T", [("x", 1.0)], tables=[("ops", ["a"], [["b"]])])
    >>> out.count("<table"), "<h4>ops</h4>" in out
    (2, True)
    """
    parts = [f"<div><h3>{html.escape(title)}</h3>", html_table(None, [list(r) for r in rows])]
    for caption, header, body in tables:
        parts += [f"<h4>{html.escape(caption)}</h4>", html_table(header, body)]
    if figure is not None:
        parts.append(_svg(figure))
    parts.append("</div>")
    return "".join(parts)


def pandas() -> Any:
    """The pandas module, or an ImportError that says how to install it (called
    first by a ``to_pandas()`` that computes before it builds the frame).

    Examples
    --------
    >>> pandas().__name__
    'pandas'
    """
    try:
        import pandas as pd
    except ImportError as e:
        raise ImportError(
            "to_pandas() needs pandas; install it (pip install pandas, or "
            "pip install 'cyclomech[notebook]')"
        ) from e
    return pd


def data_frame(columns: Mapping[str, Any], *, index: str | None = None) -> Any:
    """A pandas DataFrame of ``columns`` (name → 1-d array, equal lengths), with the
    column ``index`` as its index (:func:`pandas`'s ImportError without pandas).

    Examples
    --------
    >>> df = data_frame({"theta_deg": [0.0, 1.0], "s_m": [0.0, 0.5]}, index="theta_deg")
    >>> df.index.name, df["s_m"].tolist()
    ('theta_deg', [0.0, 0.5])
    """
    df = pandas().DataFrame({k: np.asarray(v) for k, v in columns.items()})
    return df.set_index(index) if index is not None else df


def table_frame(
    header: Sequence[str], rows: Sequence[Sequence[Any]], *, index: str | None = None
) -> Any:
    """:func:`data_frame` of a CSV-shaped table: its ``header`` and ``rows``.

    Examples
    --------
    >>> table_frame(["a", "b"], [[1, "x"], [2, "y"]], index="a")["b"].tolist()
    ['x', 'y']
    """
    cols = {h: [row[i] for row in rows] for i, h in enumerate(header)}
    return data_frame(cols, index=index)
