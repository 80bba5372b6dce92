"""Output files written whole or not at all.

A command interrupted while it writes (Ctrl-C, a full disk) must not leave a file
that looks like a result: a PNG cut after 124 bytes, a CSV without its last rows.
:func:`whole` hands out a temporary name beside the file and renames it to the
file only when the block ends normally (a rename within one folder is atomic);
otherwise the temporary file is removed and the old file, if any, is left as it was.

>>> import pathlib, tempfile
>>> from cyclomech._files import whole
>>> p = pathlib.Path(tempfile.mkdtemp()) / "a.csv"
>>> with whole(p) as tmp:
...     _ = tmp.write_text("x\\n")
>>> p.read_text(), sorted(f.name for f in p.parent.iterdir())
('x\\n', ['a.csv'])
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator
from pathlib import Path

__all__ = ["partial", "whole"]


def partial(path: Path) -> Path:
    """The temporary name of ``path`` while it is written: hidden, beside it, with
    this process's id and the same suffix (for a writer that renames it itself, as a
    streamed sweep does over many calls).

    Parameters
    ----------
    path : Path
        The file to write.

    Returns
    -------
    Path
        Where to write it until it is whole.

    Examples
    --------
    >>> import os, pathlib
    >>> partial(pathlib.Path("out/s.parquet")).name == f".s.{os.getpid()}.partial.parquet"
    True
    """
    return path.with_name(f".{path.stem}.{os.getpid()}.partial{path.suffix}")


@contextlib.contextmanager
def whole(path: Path) -> Iterator[Path]:
    """A temporary path beside ``path`` (same suffix, so writers that read the
    format from it still can), renamed to ``path`` when the block ends normally and
    removed when it does not.

    Parameters
    ----------
    path : Path
        The file to write.

    Yields
    ------
    Path
        Where to write it.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "b.txt"
    >>> try:
    ...     with whole(p) as tmp:
    ...         _ = tmp.write_text("half")
    ...         raise KeyboardInterrupt
    ... except KeyboardInterrupt:
    ...     pass
    >>> p.exists(), list(p.parent.iterdir())
    (False, [])
    """
    tmp = partial(path)
    try:
        yield tmp
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)
