"""Sphinx extension: the machine-file format reference, generated.

On ``builder-inited`` it writes ``reference/_generated/machine_format.rst`` under
the documentation's source directory from :mod:`cyclomech._keydocs` (whose tests
hold it equal to the parsers' key sets), so the page cannot drift from the code.
Add ``"keys_reference"`` to ``extensions`` in ``docs/conf.py`` with ``docs/_ext``
on ``sys.path``, and include the page from a toctree.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

#: Where the page goes, relative to the documentation's source directory.
TARGET = Path("reference") / "_generated" / "machine_format.rst"


def write(srcdir: str | Path) -> Path:
    """Write the page under ``srcdir`` and return its path; an unchanged page is
    not rewritten (its time stamp stays, so Sphinx does not rebuild it).

    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     print(write(d).read_text(encoding="utf-8").splitlines()[0])
    Machine-file format
    """
    from cyclomech._keydocs import render_page

    path = Path(srcdir) / TARGET
    text = render_page()
    if not path.is_file() or path.read_text(encoding="utf-8") != text:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
    return path


def _on_builder_inited(app: Any) -> None:
    write(app.srcdir)


def setup(app: Any) -> dict[str, Any]:
    """Register the extension with Sphinx.

    >>> class App:
    ...     def connect(self, event, handler):
    ...         print(event)
    >>> setup(App())["parallel_read_safe"]
    builder-inited
    True
    """
    app.connect("builder-inited", _on_builder_inited)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
