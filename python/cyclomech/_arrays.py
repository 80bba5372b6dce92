"""Coercion of user input to the contiguous float64/int64 arrays the kernels take."""

from __future__ import annotations

import contextlib
import math
import os
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from ._errors import InputError

_I64_MAX = np.iinfo(np.int64).max
#: Largest thread count accepted (matches the Rust core's limit).
MAX_THREADS = 1024


def index_array(name: str, value: Any) -> npt.NDArray[np.int64]:
    """A 1-D C-contiguous int64 array of indices, or :class:`InputError`."""
    try:
        a = np.asarray(value)
    except (TypeError, ValueError) as e:
        raise InputError(f"{name} must be a 1-D sequence of integer indices; {e}") from None
    if a.ndim != 1:
        raise InputError(
            f"{name} must be a 1-D sequence of integer indices; got an array of shape {a.shape}"
        )
    if a.size and a.dtype.kind not in "iu":
        raise InputError(
            f"{name} must hold integer indices; got dtype {a.dtype} (first value {a.flat[0]!r})"
        )
    if a.dtype.kind == "u" and a.size and a.max() > _I64_MAX:
        i = int(np.argmax(a > _I64_MAX))
        raise InputError(f"{name}[{i}] = {a[i]} is not an event index; it exceeds any event count")
    return _contiguous(name, a, np.int64)


def float_array(
    name: str, value: Any, ndims: tuple[int, ...] | None = (1,)
) -> npt.NDArray[np.float64]:
    """A C-contiguous float64 array with one of ``ndims`` dimensions (any number of
    dimensions if None), or :class:`InputError`.

    Finiteness is checked by the kernels, which name the first bad entry (or by
    :func:`real_array`).
    """
    if value is None:
        raise InputError(f"{name} must be an array of real numbers; got None")
    try:
        a = np.asarray(value)
    except (TypeError, ValueError) as e:
        raise InputError(f"{name} must be an array of real numbers; {e}") from None
    # Bools are not numbers (True would be read as 1), nor are strings, bytes
    # or complex numbers (whose imaginary part would be dropped).
    if a.dtype.kind not in "iuf":
        raise InputError(f"{name} must be an array of real numbers; got dtype {a.dtype}")
    if ndims is not None and a.ndim not in ndims:
        want = " or ".join(f"{d}-D" for d in ndims)
        raise InputError(f"{name} must be a {want} array; got shape {a.shape}")
    return _contiguous(name, a, np.float64)


def real_array(
    name: str,
    value: Any,
    unit: str,
    *,
    low: float | None = None,
    strict: bool = False,
    ndims: tuple[int, ...] | None = None,
) -> npt.NDArray[np.float64]:
    """``value`` as a float64 array of finite real numbers (≥ ``low``, > ``low`` if
    ``strict``), of any shape unless ``ndims`` says, or :class:`InputError` naming
    the first bad entry and ``unit``. The array form of :func:`finite_number`: a
    string, a bool, None or a complex number is not a number, nor is NaN or ±inf.

    >>> from cyclomech._arrays import real_array
    >>> real_array("rpm", [280, 420], "[rpm]", low=0.0, strict=True).tolist()
    [280.0, 420.0]
    >>> real_array("rpm", [280, 0], "[rpm]", low=0.0, strict=True)
    Traceback (most recent call last):
    cyclomech._errors.InputError: rpm[1] = 0.0 must be finite and > 0 [rpm]
    >>> real_array("rpm", "280", "[rpm]")
    Traceback (most recent call last):
    cyclomech._errors.InputError: rpm must be an array of real numbers; got dtype <U3
    """
    # ascontiguousarray makes a 0-d array 1-d: keep the shape given.
    a = float_array(name, value, ndims).reshape(np.shape(value))
    ok = np.isfinite(a)
    if low is not None:
        ok &= (a > low) if strict else (a >= low)
    if not ok.all():
        bound = "" if low is None else f" and {'>' if strict else '≥'} {low:g}"
        if a.ndim:
            i = tuple(int(k) for k in np.unravel_index(int(np.argmax(~ok)), a.shape))
            where, v = f"{name}{list(i)}", float(a[i])
        else:
            where, v = name, float(a)
        raise InputError(f"{where} = {v!r} must be finite{bound} {unit}")
    return a


def _contiguous(name: str, a: npt.NDArray[Any], dtype: type[np.generic]) -> Any:
    """``a`` as a C-contiguous array of ``dtype``. A copy (of a broadcast view, a
    strided slice, another dtype) that cannot fit is refused before numpy tries:
    its MemoryError is not a CyclomechError."""
    if a.dtype != dtype or not a.flags.c_contiguous:
        size = np.dtype(dtype).itemsize * float(a.size)
        kind = np.dtype(dtype).name
        what = f"{'an' if kind[0] in 'aeiou' else 'a'} {kind} copy of {name} {a.shape}"
        check_bytes(what, size, f"pass a smaller array for {name}")
    return np.ascontiguousarray(a, dtype=dtype)


def real(value: Any) -> float:
    """``float(value)`` for a real number only: a string, bytes or a bool is not
    one (``float("30")`` would quietly read a file's ``"30"`` as 30); raises
    ``TypeError`` or ``ValueError`` as ``float`` does."""
    if isinstance(value, str | bytes | bool | np.bool_):
        raise TypeError(f"not a real number: {value!r}")
    return float(value)


def finite_number(
    name: str,
    value: Any,
    unit: str,
    *,
    low: float | None = None,
    strict: bool = False,
    inf: bool = False,
) -> float:
    """``value`` as a finite float, or :class:`InputError` naming ``name``, the value
    and ``unit``; with ``low``, it must be ≥ ``low`` (> ``low`` if ``strict``); with
    ``inf``, +inf is taken too (where it means "no bound"), NaN and -inf never."""
    bound = "" if low is None else f" and {'>' if strict else '≥'} {low:g}"
    try:
        v = real(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number{bound} {unit}; got {value!r}") from None
    inside = low is None or (v > low if strict else v >= low)
    if not ((math.isfinite(v) or (inf and v == math.inf)) and inside):
        # v, not value: a numpy scalar would print as np.float64(-0.0001).
        raise InputError(f"{name} = {v!r} must be finite{bound} {unit}")
    return v


def positive(name: str, value: Any, unit: str) -> float:
    """``value`` as a finite float > 0, or :class:`InputError` naming ``name``, the
    value and ``unit`` (a string, bytes or a bool is not a number).

    >>> from cyclomech._arrays import positive
    >>> positive("stroke", 0.1, "[m]")
    0.1
    >>> positive("stroke", "0.1", "[m]")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    cyclomech._errors.InputError: stroke must be a number and > 0 [m]; got '0.1'
    """
    return finite_number(name, value, unit, low=0.0, strict=True)


def threads_arg(n_threads: Any) -> int | None:
    """Validate ``n_threads`` (None or a positive int) before it reaches Rust."""
    if n_threads is None:
        return None
    if (
        isinstance(n_threads, bool)
        or not isinstance(n_threads, int | np.integer)
        or not 1 <= n_threads <= MAX_THREADS
    ):
        raise InputError(
            f"n_threads must be None or an integer between 1 and {MAX_THREADS}; got {n_threads!r}"
        )
    return int(n_threads)


def count(name: str, value: Any, *, low: int = 1, high: int | None = None, what: str = "") -> int:
    """``value`` as an int count in ``[low, high]``, or :class:`InputError`.

    A count is an integer: a Python ``int``, a numpy integer scalar or a 0-d integer
    array. A bool, a float (even ``3.0``: ``2.5`` would otherwise be truncated
    silently), a string or bytes is refused, naming ``name``, the value and the
    valid range (``what`` says what is counted).
    """
    span = f"between {low} and {high}" if high is not None else f"≥ {low}"
    label = f" ({what})" if what else ""
    v = value
    if isinstance(v, np.ndarray) and v.ndim == 0:
        v = v[()]
    if isinstance(v, bool | np.bool_) or not isinstance(v, int | np.integer):
        raise InputError(f"{name} must be an integer {span}{label}; got {value!r}")
    n = int(v)
    if n < low or (high is not None and n > high):
        raise InputError(f"{name} must be an integer {span}{label}; got {n}")
    return n


#: Environment variable capping the bytes one call may allocate for its results
#: (default: the memory the system reports available).
MAX_BYTES_ENV = "CYCLOMECH_MAX_BYTES"


def available_bytes() -> int:
    """Bytes a call may allocate for its results: ``$CYCLOMECH_MAX_BYTES`` if set,
    else the memory the system reports available (Linux ``MemAvailable``; else
    ``sysconf``'s available pages), else unbounded (2**63 − 1)."""
    env = os.environ.get(MAX_BYTES_ENV)
    if env:
        try:
            return max(0, int(float(env)))
        except ValueError:
            raise InputError(
                f"{MAX_BYTES_ENV} = {env!r} must be a number of bytes (e.g. 8e9)"
            ) from None
    try:
        with open("/proc/meminfo", encoding="ascii") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return int(os.sysconf("SC_AVPHYS_PAGES")) * int(os.sysconf("SC_PAGE_SIZE"))
    except (AttributeError, ValueError, OSError):
        return _I64_MAX


def broadcast(**arrays: Any) -> list[Any]:
    """The arrays broadcast together, or :class:`InputError` naming them and their
    shapes.

    >>> import numpy as np
    >>> [a.shape for a in broadcast(x=np.ones(3), y=np.ones((2, 1)))]
    [(2, 3), (2, 3)]
    >>> broadcast(stiffness=np.ones(3), mass=np.ones(4))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    cyclomech._errors.InputError: stiffness (3,), mass (4,): these shapes do not broadcast together
    """
    try:
        return list(np.broadcast_arrays(*arrays.values()))
    except ValueError:
        shapes = ", ".join(f"{k} {np.shape(v)}" for k, v in arrays.items())
        raise InputError(f"{shapes}: these shapes do not broadcast together") from None


#: Sizes [bytes] :func:`check_bytes` lets pass without reading the system's
#: available memory: too small to be what exhausts it.
UNCHECKED_BYTES = 1 << 24


def check_bytes(what: str, nbytes: float, hint: str, *, failed: bool = False) -> None:
    """Refuse, before allocating, a result of ``nbytes`` bytes that cannot fit.

    The rule: a call's results (and the working arrays the caller counts in)
    must fit in :func:`available_bytes`; a larger size is an :class:`InputError`
    naming ``what``, the size, the memory available and ``hint`` (what to
    lower), instead of a ``MemoryError``, a Rust panic or the OOM killer. With
    ``failed``, the allocation was tried and failed: always an :class:`InputError`.
    A size of at most :data:`UNCHECKED_BYTES` passes without reading the
    system's available memory (~13 µs a read of ``/proc/meminfo``, paid by every
    kernel call otherwise), unless ``$CYCLOMECH_MAX_BYTES`` sets a cap, which
    holds at every size.

    >>> from cyclomech._arrays import check_bytes
    >>> check_bytes("a small array", 8e3, "fewer points")
    >>> check_bytes("a huge array", 1e30, "fewer points")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    cyclomech._errors.InputError: a huge array needs 1e+21 GB, more than the ... GB of ...
    """
    if not failed and nbytes <= UNCHECKED_BYTES and not os.environ.get(MAX_BYTES_ENV):
        return  # too small to be what exhausts memory: no read of /proc/meminfo
    limit = available_bytes()
    if failed:
        raise InputError(
            f"{what} needs {nbytes / 1e9:.3g} GB, which the system could not allocate "
            f"({limit / 1e9:.3g} GB available); {hint}"
        )
    if not nbytes <= limit:
        raise InputError(
            f"{what} needs {nbytes / 1e9:.3g} GB, more than the {limit / 1e9:.3g} GB of "
            f"memory available; {hint}"
        )


#: Highest shaft speed accepted anywhere [rpm]; above it a machine is unlimited.
SPEED_CAP_RPM = 1e6


def speeds_rpm(name: str, value: Any) -> npt.NDArray[np.float64]:
    """Shaft speeds [rpm] as a flat float64 array, each in (0, :data:`SPEED_CAP_RPM`].

    >>> from cyclomech._arrays import speeds_rpm
    >>> speeds_rpm("rpm", 300).tolist()
    [300.0]
    >>> speeds_rpm("rpm", [100, -1])
    Traceback (most recent call last):
    cyclomech._errors.InputError: rpm must hold positive speeds in rpm, each in (0, 1e+06]; got -1
    """
    try:
        n = float_array(name, value, ndims=None).reshape(-1)
    except InputError:
        raise InputError(f"{name} must be speeds in rpm; got {value!r}") from None
    bad = ~(np.isfinite(n) & (n > 0) & (n <= SPEED_CAP_RPM))
    if n.size == 0 or bad.any():
        got = f"{float(n[np.argmax(bad)]):g}" if n.size else "no speeds"
        raise InputError(
            f"{name} must hold positive speeds in rpm, each in (0, {SPEED_CAP_RPM:g}]; got {got}"
        )
    return n


def flag(name: str, value: Any) -> bool:
    """A bool (or numpy bool), or :class:`InputError`: 0, "no" or None are not flags.

    >>> from cyclomech._arrays import flag
    >>> flag("analogs", True)
    True
    >>> flag("analogs", 1)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    cyclomech._errors.InputError: analogs must be True or False; got 1
    """
    if isinstance(value, bool | np.bool_):
        return bool(value)
    raise InputError(f"{name} must be True or False; got {value!r}")


def out_array(out: Any, shape: tuple[int, ...], inputs: list[Any], what: str) -> None:
    """Refuse an ``out`` a kernel cannot fill in place, naming what it is and what
    is expected: a writeable C-contiguous float64 ndarray of ``shape`` that shares
    no memory with ``inputs`` (the arrays the kernel reads while it writes);
    ``what`` says what it will hold. One rule for every ``out=`` of the library.

    >>> import numpy as np
    >>> out_array(np.zeros((2, 3)), (2, 3), [np.ones(3)], "times [deg]")
    >>> try:
    ...     out_array(np.zeros((3, 2)), (2, 3), [], "times [deg]")
    ... except ValueError as e:
    ...     print(str(e).split("; ")[1])
    got a float64 array of shape (3, 2)
    """
    want = (
        f"out must be a writeable C-contiguous float64 numpy array of shape {shape} "
        f"({what}) sharing no memory with an input"
    )
    if not isinstance(out, np.ndarray):
        raise InputError(f"{want}; got {type(out).__name__}")
    got = f"got a {out.dtype} array of shape {out.shape}"
    if out.dtype != np.float64:
        raise InputError(f"{want}; {got}")
    if out.shape != shape:
        raise InputError(f"{want}; {got}")
    if not out.flags.c_contiguous:
        raise InputError(f"{want}; {got} that is not C-contiguous (strides {out.strides})")
    if not out.flags.writeable:
        raise InputError(f"{want}; {got} that is read-only")
    for a in inputs:
        # Bounds first (cheap); the exact test only when they overlap.
        if isinstance(a, np.ndarray) and np.may_share_memory(out, a) and np.shares_memory(out, a):
            raise InputError(
                f"{want}; {got} that shares memory with an input of shape {a.shape} "
                "(the kernel reads every input while it writes out)"
            )


#: Huge-page size of x86-64 and arm64 Linux [bytes]: a large block starts on it.
_HUGE_PAGE = 1 << 21


def one_block(*parts: tuple[tuple[int, ...], Any], what: str, hint: str) -> list[Any]:
    """New C-order arrays of the given (shape, dtype) ``parts``, carved from one block.

    A kernel's outputs are written once and their first touch costs as much as the
    arithmetic: one allocation, started on a 2 MiB boundary when it is 4 MiB or
    more (numpy advises huge pages from 4 MiB up), is backed by whole huge pages
    where the kernel grants them; separate arrays each begin and end in partial
    ones (measured: the six arrays of a 10⁶-point path sample first-touched in
    10 ms, one aligned block in 5.4 ms; BENCHMARKS.md, issue 37 rows 5–6). Each
    array starts on a 64-byte boundary (an empty one is its own). The arrays share
    one base: the block lives while any of them does. Nothing is written
    (``numpy.empty``). A size that cannot fit, or that the system cannot allocate,
    is the :class:`InputError` of :func:`check_bytes` naming ``what`` and ``hint``.

    Examples
    --------
    >>> import numpy as np
    >>> xy, ok = one_block(((3, 2), np.float64), ((3,), np.bool_), what="x", hint="fewer")
    >>> xy.shape, ok.dtype, xy.flags.c_contiguous, xy.base is not None
    ((3, 2), dtype('bool'), True, True)
    """
    # Python integers: a size whose element count overflows int64 is refused too.
    sizes = [math.prod(shape) * np.dtype(dt).itemsize for shape, dt in parts]
    starts = [0]
    for b in sizes:
        starts.append(starts[-1] + -(-b // 64) * 64)
    total = starts[-1]
    check_bytes(what, float(sum(sizes)), hint)  # the arrays' bytes (not the alignment's)
    pad = _HUGE_PAGE if total >= 2 * _HUGE_PAGE else 64
    try:
        raw = np.empty(total + pad, dtype=np.uint8)
    except MemoryError:
        check_bytes(what, float(sum(sizes)), hint, failed=True)
        raise  # pragma: no cover - check_bytes(failed=True) always raises
    base = -raw.ctypes.data % pad
    # An empty part is its own empty array: views of no bytes would all start at
    # the same address, which a kernel's borrow check takes for an overlap.
    return [
        raw[base + at : base + at + size].view(dt).reshape(shape)
        if size
        else np.empty(shape, dtype=dt)
        for (shape, dt), at, size in zip(parts, starts, sizes, strict=False)
    ]


@contextlib.contextmanager
def plain_pages() -> Iterator[None]:
    """Arrays numpy allocates inside the block get no transparent-huge-page advice.

    numpy advises the kernel to back every array of 4 MB or more with huge pages
    (``madvise(MADV_HUGEPAGE)``). Where the kernel honours only advised regions but
    finds no free huge page, it compacts memory on the first touch instead: on the
    VMs we measured, first touching a 10⁶-point sweep's columns (88 MB) took
    ~150 ms more in most trials (BENCHMARKS.md, issue 20), so the sweep's result
    is allocated plainly. Not the kernels' outputs: their threads write them while
    the kernel runs, and there the advice, when the kernel finds huge pages, makes
    the call up to 2× faster (measured side by side). This is numpy's own switch (the one
    ``NUMPY_MADVISE_HUGEPAGE=0`` sets at import), set for the block and restored
    after it; a numpy without it allocates as usual.

    Examples
    --------
    >>> import numpy as np
    >>> with plain_pages():
    ...     a = np.zeros(10**6)
    >>> a.size
    1000000
    """
    core = getattr(np, "_core", None) or getattr(np, "core", None)
    toggle = getattr(getattr(core, "multiarray", None), "_set_madvise_hugepage", None)
    if toggle is None:
        yield
        return
    was = toggle(False)
    try:
        yield
    finally:
        toggle(was)


def instance(name: str, value: Any, cls: type | tuple[type, ...]) -> Any:
    """``value`` if it is a ``cls``, else a ``TypeError`` naming ``name``, the type
    expected and the type given: the one rule for an argument that is an object of
    the library (a Machine, a result), so that a dict or a str given in its place
    fails here, by name, not as a ``KeyError`` or ``AttributeError`` deep inside.

    >>> from pathlib import Path
    >>> instance("out", Path("."), Path)
    PosixPath('.')
    >>> instance("machine", {}, Path)
    Traceback (most recent call last):
    TypeError: machine must be a Path; got dict
    """
    if not isinstance(value, cls):
        want = " or ".join(c.__name__ for c in (cls if isinstance(cls, tuple) else (cls,)))
        raise TypeError(f"{name} must be a {want}; got {type(value).__name__}")
    return value


def instances(name: str, value: Any, cls: type | tuple[type, ...]) -> list[Any]:
    """``value`` as a list of ``cls`` (any sequence of them), else a ``TypeError``
    naming ``name[i]`` (or ``name`` when it is not a sequence): :func:`instance`
    for a list of objects.

    >>> instances("paths", ("a", "b"), str)
    ['a', 'b']
    >>> instances("machines", None, str)
    Traceback (most recent call last):
    TypeError: machines must be a sequence of str; got NoneType
    """
    if isinstance(value, str | bytes | dict) or not hasattr(value, "__len__"):
        want = " or ".join(c.__name__ for c in (cls if isinstance(cls, tuple) else (cls,)))
        raise TypeError(f"{name} must be a sequence of {want}; got {type(value).__name__}")
    return [instance(f"{name}[{i}]", v, cls) for i, v in enumerate(value)]


def tolerance(name: str, value: Any, low: float, high: float, unit: str = "(relative)") -> float:
    """A tolerance: a finite number in [``low``, ``high``], or :class:`InputError`
    naming ``name``, the value and the range (a string or a bool is not one).

    >>> tolerance("rtol", 1e-10, 1e-14, 0.5)
    1e-10
    >>> tolerance("rtol", "1e-10", 1e-14, 0.5)
    Traceback (most recent call last):
    cyclomech._errors.InputError: rtol = '1e-10' must lie in [1e-14, 0.5] (relative)
    """
    try:
        v = real(value)
    except (TypeError, ValueError):
        v = math.nan
    if not low <= v <= high:
        raise InputError(f"{name} = {value!r} must lie in [{low:g}, {high:g}] {unit}")
    return v


#: Relative tolerances a speed search can meet: below 1e-14 the 64-speed
#: refinement cannot shrink its bracket in float64; at 1 and above it would stop
#: at once, at the search's floor.
SPEED_RTOL = (1e-14, 0.5)


def speed_rtol(value: Any) -> float:
    """The relative tolerance ``rtol`` of a speed search, in :data:`SPEED_RTOL`.

    >>> speed_rtol(1e-10)
    1e-10
    """
    try:
        return tolerance("rtol", value, *SPEED_RTOL)
    except InputError:
        lo, hi = SPEED_RTOL
        raise InputError(
            f"rtol = {value!r} must be a relative tolerance in [{lo:g}, {hi:g}]"
        ) from None


def file_path(name: str, value: Any) -> Path:
    """``value`` (a str or a path-like object) as a :class:`~pathlib.Path`, else a
    ``TypeError`` naming ``name``: :func:`instance` for a file argument.

    >>> file_path("path", "examples/stb_loom.toml").name
    'stb_loom.toml'
    >>> file_path("path", None)
    Traceback (most recent call last):
    TypeError: path must be a str or PathLike; got NoneType
    """
    return Path(instance(name, value, (str, os.PathLike)))
