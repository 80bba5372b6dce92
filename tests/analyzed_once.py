"""One analysis of each machine for the docstring examples' runs.

About 90 docstring examples open with ``analyze(Machine.from_toml(...))`` of the
same five example files (39 of them the knife cutter's, 32 the loom's), then show
one attribute of the result. Run one after the other (``test_docstrings.py``, and
the valid calls ``test_fuzz_public.py`` records), they solved the same machine
again and again: most of those files' time. :func:`analyze_each_machine_once`
makes the first call of each distinct machine and keyword set a real one and
answers the later calls with a copy of its result.

What a later call gets is what it would compute, by construction: the key is the
pickle of the machine as given (two machines read from one file pickle to the same
bytes; one changed in any attribute does not), taken before the analysis (which
caches its own work inside the machine), and each call gets a fresh unpickled copy
of the result, so no example sees another's changes. A machine or result that does
not pickle is analysed for real every time. ``analyze`` itself is still run on every
example file, and ``tests/machine`` tests it against independent references.
"""

from __future__ import annotations

import contextlib
import hashlib
import pickle
from collections.abc import Iterator, MutableMapping
from typing import Any

import cyclomech.machine


def _key(args: tuple[Any, ...], kwargs: dict[str, Any]) -> str | None:
    try:
        blob = pickle.dumps((args, sorted(kwargs.items())), protocol=pickle.HIGHEST_PROTOCOL)
    except Exception:
        return None
    return hashlib.sha256(blob).hexdigest()


@contextlib.contextmanager
def analyze_each_machine_once(results: MutableMapping[str, bytes] | None = None) -> Iterator[None]:
    """``cyclomech.machine.analyze`` answers a repeated call by a copy of the first
    call's result while the block runs (examples look it up on the module at run
    time, as ``cm.machine.analyze`` or ``from cyclomech.machine import analyze``).

    ``results`` (digest of the pickled arguments -> the pickled result) is the
    cache: pass one dict (or a mapping that reads and writes only those keys, as
    ``cli_run``'s folder shared by the workers) to several blocks to share it, or
    none for a fresh one. A
    block whose first calls must run for real (the fuzz's profiler records what
    they call) takes a fresh one: another test file in the same worker may have
    analysed the same machines already."""
    real = cyclomech.machine.analyze
    cache: MutableMapping[str, bytes] = {} if results is None else results

    def analyze(*args: Any, **kwargs: Any) -> Any:
        key = _key(args, kwargs)
        if key is not None and key in cache:
            return pickle.loads(cache[key])
        result = real(*args, **kwargs)
        if key is not None:
            with contextlib.suppress(Exception):
                cache[key] = pickle.dumps(result, protocol=pickle.HIGHEST_PROTOCOL)
        return result

    cyclomech.machine.analyze = analyze
    try:
        yield
    finally:
        cyclomech.machine.analyze = real
