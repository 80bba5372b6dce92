"""What counts as a Ctrl-C: the one rule of the console script, ``python -m
cyclomech`` and :func:`cyclomech.cli.main`. Here, outside the package, so that the
entry point can use it before ``import cyclomech`` (which takes ~0.6 s) has run."""

from __future__ import annotations


def interrupted(error: BaseException) -> bool:
    """Whether ``error`` is a Ctrl-C: a KeyboardInterrupt, or an error raised while
    one was propagating (its ``__cause__`` / ``__context__`` chain holds one).

    >>> interrupted(KeyboardInterrupt())
    True
    >>> try:
    ...     try:
    ...         raise KeyboardInterrupt
    ...     except KeyboardInterrupt as e:
    ...         raise ImportError("initialization failed") from e
    ... except ImportError as e:
    ...     interrupted(e)
    True
    >>> interrupted(ImportError("No module named 'scipy'"))
    False
    """
    seen: set[int] = set()
    link: BaseException | None = error
    while link is not None and id(link) not in seen:
        if isinstance(link, KeyboardInterrupt):
            return True
        seen.add(id(link))
        link = link.__cause__ or link.__context__
    return False
