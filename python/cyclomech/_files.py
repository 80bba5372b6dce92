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
import csv
import os
from collections.abc import Iterable, Iterator, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ._arrays import file_path
from ._errors import InputError

__all__ = [
    "file_stem",
    "file_target",
    "folder_problem",
    "folder_target",
    "partial",
    "savetxt",
    "whole",
    "write_csv",
    "write_text",
]


def file_stem(name: str) -> str:
    """A mechanism's name as a file-name stem: letters, digits, ``-`` and ``_`` kept,
    anything else ``_`` (the stem of every file named after a mechanism).

    >>> file_stem("lifter cam"), file_stem("jaw/2")
    ('lifter_cam', 'jaw_2')
    """
    return "".join(c if c.isalnum() or c in "-_" else "_" for c in name)


def _path(name: str, value: Any) -> Path:
    """``value`` as a Path: a str or ``os.PathLike`` (else ``TypeError`` naming
    ``name``, by :func:`cyclomech._arrays.file_path`), and not blank (else
    :class:`InputError`: ``""`` would mean the current folder, a slip)."""
    p = file_path(name, value)
    if not str(os.fspath(value)).strip():
        raise InputError(f"{name} must be a path (a non-empty str or Path); got {value!r}")
    return p


def file_target(name: str, value: Any) -> Path:
    """The file a public writer is asked to write, checked before any work: a
    non-empty path whose folder exists and which is not itself a folder; else
    :class:`~cyclomech.InputError` naming the argument ``name``.

    Parameters
    ----------
    name : str
        The argument's name, for the message.
    value : str or os.PathLike
        The path given.

    Returns
    -------
    Path
        The path.

    Examples
    --------
    >>> import tempfile
    >>> file_target("path", tempfile.gettempdir() + "/x.csv").name
    'x.csv'
    >>> file_target("path", "")
    Traceback (most recent call last):
    cyclomech._errors.InputError: path must be a path (a non-empty str or Path); got ''
    """
    p = _path(name, value)
    if p.is_dir():
        raise InputError(f"{name} = {str(p)!r} is a folder; give a file name in it")
    if not p.parent.is_dir():
        raise InputError(
            f"{name} = {str(p)!r}: the folder {str(p.parent)!r} does not exist; make it first"
        )
    return p


def folder_target(name: str, value: Any) -> Path:
    """The folder a public writer is asked to fill, checked before any work: a
    non-empty path that is a folder or can be made one (``""`` would mean the
    current folder, a slip); else :class:`~cyclomech.InputError` naming ``name``.

    Parameters
    ----------
    name : str
        The argument's name, for the message.
    value : str or os.PathLike
        The path given.

    Returns
    -------
    Path
        The path (not yet made).

    Examples
    --------
    >>> import tempfile
    >>> folder_target("out", tempfile.gettempdir()).is_dir()
    True
    >>> folder_target("out", "  ")
    Traceback (most recent call last):
    cyclomech._errors.InputError: out must be a path (a non-empty str or Path); got '  '
    """
    p = _path(name, value)
    why = folder_problem(p)
    if why:
        raise InputError(f"{name} = {str(p)!r}: {why}; give a folder")
    return p


def folder_problem(folder: Path) -> str:
    """Why ``folder`` cannot take a command's results ("" if it can): it, or the
    nearest of its parents that exists, must be a writable folder. The one rule
    of :func:`folder_target` and the commands' ``--out``.

    >>> import tempfile, pathlib
    >>> folder_problem(pathlib.Path(tempfile.gettempdir()) / "new")
    ''
    """
    near = next((q for q in (folder, *folder.parents) if q.exists()), Path("."))
    if not near.is_dir():
        what = "is a file" if near == folder else f"cannot be made: {near} is a file"
        return f"{what}, not a folder"
    if not os.access(near, os.W_OK | os.X_OK):
        return f"the folder {near} is not writable"
    return ""


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
    removed when it does not. An ``OSError`` while it is written or renamed (a full
    disk) is raised again naming ``path``, not the temporary name, with the
    system's errno and reason.

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
        try:
            yield tmp
            os.replace(tmp, path)
        except OSError as e:
            # The writer names the temporary file, or nothing (a write() on an open
            # file); the user asked for ``path``: name it, keep the system's reason.
            raise OSError(e.errno, e.strerror or str(e), str(path)) from e
    finally:
        tmp.unlink(missing_ok=True)


def write_text(path: Path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` whole or not at all (:func:`whole`).

    Parameters
    ----------
    path : Path
        The file to write.
    text : str
        Its content.

    Returns
    -------
    Path
        ``path``.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> write_text(pathlib.Path(tempfile.mkdtemp()) / "r.json", "{}").read_text()
    '{}'
    """
    with whole(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return path


def savetxt(path: Path, table: Any, **options: Any) -> Path:
    """``numpy.savetxt(path, table, **options)``, whole or not at all (:func:`whole`).

    Parameters
    ----------
    path : Path
        The file to write.
    table : array_like
        The rows.
    **options
        What :func:`numpy.savetxt` takes (``delimiter``, ``header``, ``fmt``, …).

    Returns
    -------
    Path
        ``path``.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> p = savetxt(pathlib.Path(tempfile.mkdtemp()) / "t.csv", [[1, 2]], delimiter=",", fmt="%d")
    >>> p.read_text().split()
    ['1,2']
    """
    import numpy as np

    with whole(path) as tmp:
        np.savetxt(tmp, table, **options)
    return path


def write_csv(path: Path, header: Sequence[str], rows: Iterable[Sequence[Any]]) -> Path:
    """Write a CSV table whole (:func:`whole`): ``header``, then ``rows``, floats
    as their shortest round-tripping text (``repr``), other cells as they are.

    >>> import pathlib, tempfile
    >>> p = write_csv(pathlib.Path(tempfile.mkdtemp()) / "t.csv", ["a", "b"], [[0.1, "x"]])
    >>> p.read_text().splitlines()
    ['a,b', '0.1,x']
    """
    with whole(path) as tmp, tmp.open("w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        w.writerow(header)
        for row in rows:
            w.writerow([repr(float(v)) if isinstance(v, float | np.floating) else v for v in row])
    return path
