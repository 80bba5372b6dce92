"""Progress bars for long work, on stderr: one helper on tqdm for every job
(machine runs, sweeps, press design grids). A bar is shown only where asked
(``enabled``; by default when stderr is a terminal) and never in results.

>>> from cyclomech._progress import progress
>>> with progress(3, "designs", enabled=False) as bar:    # (shown only on a terminal)
...     bar.update(3)
>>> bar.disable
True
"""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING

from ._arrays import flag

if TYPE_CHECKING:
    from tqdm import tqdm

__all__ = ["progress"]


def progress(total: int, label: str, enabled: bool | None = None) -> tqdm:
    """A tqdm bar over ``total`` steps named ``label`` on stderr (``enabled``
    None: when stderr is a terminal); use it as a context manager, call
    ``update(n)`` as work is done and ``set_postfix_str`` to name the step.

    >>> from cyclomech._progress import progress
    >>> import io, contextlib
    >>> err = io.StringIO()
    >>> with contextlib.redirect_stderr(err):
    ...     with progress(10, "speeds", enabled=True) as bar:
    ...         bar.update(10)
    >>> "100.0% 10/10" in err.getvalue()
    True
    """
    from tqdm import tqdm  # on first use: importing cyclomech stays light

    # "false" or 0 is not a switch: one rule for every flag (_arrays.flag).
    show = sys.stderr.isatty() if enabled is None else flag("progress", enabled)
    return tqdm(
        total=total,
        desc=label,
        file=sys.stderr,
        disable=not show,
        leave=True,
        dynamic_ncols=True,
        unit="",
        bar_format="{desc} [{bar:30}] {percentage:5.1f}% {n_fmt}/{total_fmt} {elapsed}{postfix}",
    )
