"""Sweeps of a whole machine over its parameters and speeds, in-process or on Dask.

:func:`sweep` evaluates every combination of the named parameters (a Cartesian
grid of designs) at every speed and reduces each point to the report's key
figures, in a columnar :class:`SweepResult`. The designs are cut into chunks;
each chunk is one task: per design, one call per stop kernel and one
shortest-path call for all its speeds. Chunks run in this process (rayon
threads inside each kernel), or on a Dask cluster: pass a
``dask.distributed.Client`` or any ``concurrent.futures.Executor`` (for
example ``client.get_executor()``); inside the tasks the kernels run on one
thread each, so the workers' processes are not oversubscribed. The results do
not depend on where the chunks ran: bit for bit.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import logging
import math
import os
import signal
import threading
import time
import warnings
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, cast

import numpy as np
import numpy.typing as npt

from .._arrays import check_bytes, file_path, instance, plain_pages, speeds_rpm
from .._errors import CyclomechWarning, InputError
from .._files import file_target, partial, whole
from .._progress import progress as progress_bar
from ._batch import batch_designs, batch_figures, plan
from ._model import SCHEMA, Machine, check_parameter, speed_limits, speed_sweeps
from ._sweep_shaft import SHAFT_COLUMNS, has_shaft, shaft_columns

__all__ = ["SweepResult", "dask_client", "dask_workers", "parse_range", "sweep"]

#: Key of the grid that holds the speeds [rpm].
SPEED = "speed_rpm"
#: The key figures of a sweep point, in the order of the columns.
FIGURES = (
    "fits",
    "limiting_deg",
    "limiting_s",
    "productivity_per_min",
    "max_rebound_m",
    "speed_limit_rpm",
    "speed_limit_by",
    "binding",
    "problem",
)
#: The text columns.
TEXT = ("speed_limit_by", "binding", "problem")
#: Former names of key figures → their names now (files written before the rename).
RENAMED = {"productivity": "productivity_per_min"}


@dataclass(frozen=True)
class SweepResult:
    """Key figures at every point of a sweep, in columns of one row per point.

    Built by :func:`sweep` and :meth:`read`; each parameter is kept as the
    attribute of the same name. The rows: the parameters vary slowest, the speed
    fastest. ``speed_limit_rpm`` and ``speed_limit_by`` belong to the design (the
    same at each of its speeds); ``binding`` is text. ``problem`` is empty for a
    valid design; a design the file's rules refuse (a press whose rod cannot reach
    its guide, say) does not stop the sweep: its rows do not fit (NaN figures,
    productivity 0) and ``problem`` holds the reason. With ``sweep(...,
    shaft=True)`` the main shaft's columns follow (``SHAFT_COLUMNS``: mean, peak
    and RMS torque [N·m], motor power [W], flywheel [kg·m²]), the ``cyclomech run``
    report's numbers for the design at each speed; NaN where there is none (a
    machine whose mechanisms do not load its main shaft, an invalid design, one
    without an optimum).

    Parameters
    ----------
    columns : dict of str to ndarray, shape (N,) each
        The parameter names, ``speed_rpm`` [rpm] and the key figures (``FIGURES``:
        ``fits``, ``limiting_deg`` [deg], ``limiting_s`` [s], ``productivity_per_min``
        [1/min], ``max_rebound_m`` [m], ``speed_limit_rpm`` [rpm], ``speed_limit_by``,
        ``binding``, ``problem``), then the shaft's columns if any, each mapped to a
        1-D array of one row per point; empty when the rows were streamed to ``path``.
    parameters : tuple of str
        The swept parameters' names (``"<mechanism>.<key>"`` or
        ``"machine.<key>"``), in the order of the columns.
    seconds : float, default 0.0
        The wall time of the sweep [s].
    path : Path, optional
        Where the rows were streamed (``sweep(..., out=path)``); ``columns`` is
        then empty and ``summary`` counts the rows. Default None.
    summary : dict of str to Any, optional
        With ``path``: ``points`` (rows), ``fits`` (rows that fit), ``invalid``
        (rows of invalid designs) and the first ``problem``; default an empty dict.

    Examples
    --------
    >>> import cyclomech as cm
    >>> r = cm.sweep(cm.Machine.example(), {"lifter.preload_m": [2e-4, 3e-4],
    ...                                     "speed_rpm": [300.0, 400.0]})
    >>> r.n_points, r.columns["lifter.preload_m"].tolist()
    (4, [0.0002, 0.0002, 0.0003, 0.0003])
    """

    columns: dict[str, npt.NDArray[Any]]
    parameters: tuple[str, ...]
    seconds: float = 0.0
    path: Path | None = None
    summary: dict[str, Any] = field(default_factory=dict)

    @property
    def n_points(self) -> int:
        """Number of rows (points), also of a sweep streamed to a file.

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.sweep(cm.Machine.example(), {"speed_rpm": [300.0, 400.0]}).n_points
        2
        """
        if SPEED not in self.columns:
            return int(self.summary.get("points", 0))
        return int(self.columns[SPEED].size)

    @property
    def n_invalid(self) -> int:
        """Number of rows whose design is invalid (a non-empty ``problem``).

        Examples
        --------
        >>> import cyclomech as cm
        >>> cm.sweep(cm.Machine.example(), {"speed_rpm": [300.0]}).n_invalid
        0
        """
        if "problem" not in self.columns:
            return int(self.summary.get("invalid", 0))
        return int((self.columns["problem"] != "").sum())

    def write(self, path: str | Path) -> Path:
        """Write the columns to a Parquet or NumPy ``.npz`` file.

        The file is written beside the target under a temporary name and renamed
        when complete: an interrupted write leaves no file that looks like a result.

        Parameters
        ----------
        path : str or Path
            The file, ending in ``.parquet`` or ``.npz``: Parquet (pyarrow) for
            ``.parquet`` when pyarrow is installed, else NumPy ``.npz`` (the suffix
            is changed to say which, with a CyclomechWarning).

        Returns
        -------
        Path
            The path written.

        Raises
        ------
        InputError
            If the name ends in neither ``.parquet`` nor ``.npz``.

        Examples
        --------
        >>> import pathlib, tempfile, cyclomech as cm
        >>> r = cm.sweep(cm.Machine.example(), {"speed_rpm": [300.0]})
        >>> r.write(pathlib.Path(tempfile.mkdtemp()) / "s.npz").suffix
        '.npz'
        """
        p = file_target("path", path)
        if p.suffix not in (".parquet", ".npz"):
            raise InputError(
                f"{p}: SweepResult.write writes .parquet or .npz files; got the suffix "
                f"{p.suffix!r} (for CSV, pandas: pd.DataFrame(r.columns).to_csv(...))"
            )
        parquet = p.suffix == ".parquet"
        if parquet:
            try:
                import pyarrow as pa
                import pyarrow.parquet as pq
            except ImportError:  # written all the same, but said: the suffix changes
                parquet = False
                npz = p.with_suffix(".npz").name
                msg = f"{p}: pyarrow is not installed, so {npz} (NumPy) is written instead"
                warnings.warn(msg + " (pip install pyarrow)", CyclomechWarning, stacklevel=2)
        p = p if parquet else p.with_suffix(".npz")
        with whole(p) as tmp:  # an interrupt leaves no file that looks like a result
            if parquet:
                table = pa.table({k: pa.array(v) for k, v in self.columns.items()})
                meta = {
                    b"schema": SCHEMA.encode(),
                    b"parameters": ",".join(self.parameters).encode(),
                }
                pq.write_table(table.replace_schema_metadata(meta), tmp)
            else:
                cols = {
                    k: (v.astype(str) if v.dtype == object else v) for k, v in self.columns.items()
                }
                np.savez_compressed(tmp, **cast(dict[str, Any], cols))
        return p

    @classmethod
    def read(cls, path: str | Path) -> SweepResult:
        """Read a file written by :meth:`write`.

        A file written before the ``problem`` column existed reads with an empty
        ``problem`` (no invalid design); one written before ``productivity_per_min``
        was so named (``productivity``) reads with the column renamed.

        Parameters
        ----------
        path : str or Path
            The file (``.parquet``, which needs pyarrow, or ``.npz``).

        Returns
        -------
        SweepResult
            Its columns, and the parameters (the columns that are neither
            ``speed_rpm``, a key figure nor a shaft column).

        Raises
        ------
        InputError
            If the file cannot be read, Parquet is read without pyarrow, or it is
            no sweep file (a missing column, columns of different lengths).

        Examples
        --------
        >>> import pathlib, tempfile, cyclomech as cm
        >>> r = cm.sweep(cm.Machine.example(), {"speed_rpm": [300.0, 900.0]})
        >>> back = cm.SweepResult.read(r.write(pathlib.Path(tempfile.mkdtemp()) / "s.npz"))
        >>> back.columns["fits"].tolist()
        [True, False]
        """
        p = file_path("path", path)
        what = "a sweep file written by SweepResult.write (.parquet or .npz)"
        try:
            if p.suffix == ".parquet":
                try:
                    import pyarrow.parquet as pq
                except ImportError:
                    raise InputError(
                        f"{p}: reading Parquet needs pyarrow (`pip install pyarrow`)"
                    ) from None
                t = pq.read_table(p)
                cols = {
                    k: np.asarray(t.column(k).to_numpy(zero_copy_only=False))
                    for k in t.column_names
                }
            else:
                # np.load leaks its file when the archive is broken: hold it here.
                with open(p, "rb") as fh:
                    z = np.load(fh, allow_pickle=False)
                    if not hasattr(z, "files"):
                        raise ValueError("a single array, not an archive of columns")
                    with z:
                        cols = {k: z[k] for k in z.files}
        except InputError:
            raise
        except Exception as e:  # OSError, a broken archive, pyarrow's ArrowInvalid, …
            raise InputError(f"{p}: cannot be read as {what}: {e}") from None
        cols = {RENAMED.get(k, k): v for k, v in cols.items()}
        missing = [k for k in (SPEED, *FIGURES) if k not in cols]
        if missing == ["problem"]:  # written before the column existed: no invalid design
            cols["problem"] = np.full(cols[SPEED].shape, "", dtype=object)
            missing = []
        if missing:
            raise InputError(f"{p}: not {what}: missing the column(s) {', '.join(missing)}")
        n = cols[SPEED].shape
        ragged = [k for k, v in cols.items() if v.ndim != 1 or v.shape != n]
        if ragged:
            raise InputError(f"{p}: not {what}: columns of different lengths ({ragged[0]!r})")
        for k in TEXT:
            cols[k] = cols[k].astype(object)
        params = tuple(k for k in cols if k not in (SPEED, *FIGURES, *SHAFT_COLUMNS))
        return cls(cols, params)


def parse_range(text: str, what: str) -> npt.NDArray[np.float64]:
    """``"from:to:count"`` → ``count`` evenly spaced values (``"v"`` → one value).

    Parameters
    ----------
    text : str
        ``"from:to:count"`` (a whole count ≥ 1) or one value ``"v"``.
    what : str
        What the text is (``"--speed"``), in messages.

    Returns
    -------
    ndarray of float, shape (count,)
        The values, from ``from`` to ``to`` inclusive (``[v]`` for one value).

    Raises
    ------
    InputError
        If the text is not of that form or a value is not finite.

    Examples
    --------
    >>> from cyclomech.machine import parse_range
    >>> parse_range("200:500:4", "--speed").tolist()
    [200.0, 300.0, 400.0, 500.0]
    """
    parts = instance("text", text, str).split(":")
    try:
        if len(parts) == 1:
            vals = np.array([float(parts[0])])
        elif len(parts) == 3:
            count = int(parts[2])
            if count < 1:
                raise ValueError
            vals = np.linspace(float(parts[0]), float(parts[1]), count)
        else:
            raise ValueError
    except ValueError:
        raise InputError(
            f"{what} {text!r} must be from:to:count (a whole count ≥ 1) or one value"
        ) from None
    if not np.isfinite(vals).all():
        raise InputError(f"{what} {text!r} must be finite numbers")
    return vals


#: Bytes a point of a sweep takes in its result: a float64 or an object pointer per
#: column, and the text of the three text columns (short strings, shared where equal).
_POINT_BYTES = 8 * len(FIGURES) + 3 * 8


def _check_size(designs: int, speeds: int, params: int, *, streamed: bool = False) -> None:
    """Refuse, before allocating, a sweep whose result cannot fit in memory (it
    used to die in a bare MemoryError, or be killed by the system, after
    allocating its index grid): :func:`cyclomech._arrays.check_bytes`. A
    streamed sweep (``out=``) holds its design index, one task's working set
    (~1.7 KB a point) and the results of the tasks in flight, not its result."""
    if streamed:
        task = min(designs * speeds, _TASK_POINTS)
        result = _POINT_BYTES + 8 * (params + 1)  # a point of a task's result
        need = designs * 8 * (params + 1) + task * 1700 + _IN_FLIGHT * task * result
        what = f"the streamed sweep's index and tasks ({designs:,} designs)"
    else:
        need = designs * (8 * params) + designs * speeds * (_POINT_BYTES + 8 * (params + 1))
        what = (
            f"the sweep's result ({designs:,} designs × {speeds:,} speeds = "
            f"{designs * speeds:,} points)"
        )
    check_bytes(what, need, "sweep fewer designs or speeds, or the grid in parts; out= streams")


def _chunks(n_designs: int, size: int) -> Iterator[range]:
    for start in range(0, n_designs, size):
        yield range(start, min(start + size, n_designs))


def _axis(key: str, values: npt.ArrayLike) -> npt.NDArray[Any]:
    """A parameter's values as a 1-D array of finite numbers (integers kept)."""
    v = np.asarray(values).reshape(-1)
    if v.size == 0 or v.dtype.kind not in "iuf" or not np.isfinite(v).all():
        raise InputError(
            f"grid[{key!r}] must hold one or more finite numbers in the file's units; "
            f"got {values!r}"
        )
    return v


def _run_chunk(
    data: Mapping[str, Any],
    source: str,
    names: Sequence[str],
    axes: Sequence[npt.NDArray[Any]],
    designs: npt.NDArray[np.intp],
    speeds: npt.NDArray[np.float64],
    n_threads: int | None,
    *,
    batch: bool = True,
    base: Machine | None = None,
    shaft: bool | None = None,
) -> dict[str, npt.NDArray[Any]]:
    """The key figures of the designs (k, P) (indices into ``axes``) at ``speeds``:
    one task. The designs are variants of one file, so every kernel runs once for
    the chunk: with ``batch`` the swept stops of every design in one Rust call
    (:mod:`cyclomech.machine._batch`, through the kind's hook; the designs it cannot
    take go the other way), else one machine per design, their bounds worked out
    together, one shortest-path call for every design at every speed, one per step
    of the speed-limit search. ``base``: the file's machine, when the caller has
    built it (in-process: once for all the chunks). ``shaft``: the main-shaft
    columns too (:mod:`cyclomech.machine._sweep_shaft`; False: NaN ones; None:
    none)."""
    base = Machine.from_dict(data, source) if base is None else base
    D, S = len(designs), speeds.size
    pl = plan(base, names) if batch else None
    if pl is None:
        cols = _per_design(base, names, axes, designs, speeds, n_threads)
        return _flat(cols, base, names, axes, designs, speeds, shaft)
    values = {k: axes[j][designs[:, j]] for j, k in enumerate(names)}
    tables, ok = batch_designs(base, pl, values)
    if ok.all():  # the usual case: the batch's columns as they are, no masked copies
        cols = batch_figures(base, pl, tables, speeds, n_threads)
        cols["problem"] = np.full((D, S), "", dtype=object)
        return _flat(cols, base, names, axes, designs, speeds, shaft)
    cols = _empty(D, S)
    if ok.any():
        got = batch_figures(base, pl, {k: t[:, ok] for k, t in tables.items()}, speeds, n_threads)
        for k, v in got.items():
            cols[k][ok] = v
    for k, v in _per_design(base, names, axes, designs[~ok], speeds, n_threads).items():
        cols[k][~ok] = v
    return _flat(cols, base, names, axes, designs, speeds, shaft)


def _flat(
    cols: dict[str, npt.NDArray[Any]],
    base: Machine,
    names: Sequence[str],
    axes: Sequence[npt.NDArray[Any]],
    designs: npt.NDArray[np.intp],
    speeds: npt.NDArray[np.float64],
    shaft: bool | None,
) -> dict[str, npt.NDArray[Any]]:
    """A task's columns in row order: the figures (D, S), then with ``shaft`` the
    main shaft's (None: no such columns; False: NaN, the machine has no shaft)."""
    if shaft is None:
        return {k: cols[k].reshape(-1) for k in FIGURES}
    if shaft:
        cols.update(shaft_columns(base, names, axes, designs, speeds, cols["problem"][:, 0]))
    else:
        cols.update({c: np.full(cols["fits"].shape, np.nan) for c in SHAFT_COLUMNS})
    return {k: cols[k].reshape(-1) for k in (*FIGURES, *SHAFT_COLUMNS)}


def _empty(D: int, S: int) -> dict[str, npt.NDArray[Any]]:
    """The figures (D, S) of designs that do not fit (NaN, productivity 0)."""
    return {
        "fits": np.zeros((D, S), dtype=bool),
        "limiting_deg": np.full((D, S), np.nan),
        "limiting_s": np.full((D, S), np.nan),
        "productivity_per_min": np.zeros((D, S)),
        "max_rebound_m": np.full((D, S), np.nan),
        "binding": np.full((D, S), "", dtype=object),
        "speed_limit_rpm": np.full((D, S), np.nan),
        "speed_limit_by": np.full((D, S), "", dtype=object),
        "problem": np.full((D, S), "", dtype=object),
    }


def _per_design(
    base: Machine,
    names: Sequence[str],
    axes: Sequence[npt.NDArray[Any]],
    designs: npt.NDArray[np.intp],
    speeds: npt.NDArray[np.float64],
    n_threads: int | None,
) -> dict[str, npt.NDArray[Any]]:
    """The figures (D, S) of one machine per design (the reference path)."""
    machines: list[Machine] = []
    problems = np.full(len(designs), "", dtype=object)
    for d, row in enumerate(designs):
        if not names:
            machines.append(base)
            continue
        values = {k: axes[j][i].item() for j, (k, i) in enumerate(zip(names, row, strict=True))}
        try:
            machines.append(base.with_values(values))
        except InputError as e:
            # An invalid design is a result of the sweep, not its end: its rows do not fit.
            at = ", ".join(f"{k} = {v!r}" for k, v in values.items())
            problems[d] = f"{at}: {e}"
    ok = problems == ""
    S = speeds.size
    per_speed = (*FIGURES[:5], "binding")  # fits … max_rebound_m: SpeedSweep attributes
    cols = _empty(len(designs), S)
    cols["problem"] = np.repeat(problems[:, None], S, axis=1)
    if machines:
        sweeps = speed_sweeps(machines, speeds, n_threads=n_threads)
        limits = speed_limits(machines, n_threads=n_threads)
        for k in per_speed:
            cols[k][ok] = np.stack([getattr(s, k) for s in sweeps])
        cols["speed_limit_rpm"][ok] = np.array([lim.rpm for lim in limits])[:, None]
        cols["speed_limit_by"][ok] = np.array([lim.by for lim in limits], dtype=object)[:, None]
    return cols


def _as_executor(executor: Any) -> cf.Executor | None:
    if executor is None:
        return None
    if hasattr(executor, "get_executor"):  # a dask.distributed.Client
        return executor.get_executor()
    if hasattr(executor, "submit"):
        return executor
    raise InputError(
        f"executor must be None, a dask.distributed.Client or a concurrent.futures.Executor; "
        f"got {type(executor).__name__}"
    )


def sweep(
    machine: Machine,
    grid: Mapping[str, npt.ArrayLike],
    executor: Any = None,
    *,
    chunk: int | None = None,
    progress: bool | None = None,
    n_threads: int | None = None,
    batch: bool = True,
    out: str | Path | None = None,
    shaft: bool = False,
) -> SweepResult:
    """Key figures of a machine at every combination of parameters and speeds.

    The designs are the Cartesian grid of the parameters' values; each is
    evaluated at every speed. A value that makes a design invalid is that design's
    problem (its rows do not fit, ``problem`` says why), not the sweep's. Ctrl-C
    cancels the chunks not yet started and raises ``KeyboardInterrupt``. Without
    ``out`` a sweep whose result cannot fit in memory is refused before it starts.
    The results do not depend on where the chunks ran: bit for bit.

    Parameters
    ----------
    machine : Machine
        The machine, read from a file or a dict (:meth:`Machine.from_toml`,
        :meth:`Machine.from_dict`).
    grid : Mapping of str to array_like
        The parameters (``"<mechanism>.<key>"``, a number in a sub-table or a
        list such as ``"knife.lengths.3.length"`` (positions from 1; see
        :meth:`Machine.with_values`), ``"machine.<key>"`` or
        ``"operation.<k>.<key>"``) → values, in the file's units, and the speeds
        ``grid["speed_rpm"]`` [rpm] (default the machine's speed grid).
    executor : dask.distributed.Client or concurrent.futures.Executor, optional
        None (this process; ``n_threads`` rayon threads per kernel), a
        ``dask.distributed.Client`` or a ``concurrent.futures.Executor`` (one task
        per chunk of ``chunk`` designs, one thread per kernel inside).
    chunk : int, optional
        Designs a task (≥ 1); default about 100 steps of the progress bar but at
        least 64 designs in this process, 64 tasks on an executor, and at most
        2¹⁵ points a task.
    progress : bool, optional
        A bar on stderr (default: when stderr is a terminal).
    n_threads : int, optional
        Rayon threads per kernel in this process (default: ``CYCLOMECH_THREADS``
        or all cores).
    batch : bool, default True
        A sweep of pulse-model stops' numeric keys builds and solves each chunk's
        designs in one Rust call (where every swept key is a stop's number);
        False builds one machine per design (the reference: the same results, bit
        for bit, slower).
    out : str or Path, optional
        A ``.parquet`` path (needs pyarrow): the rows are written to it task by
        task as they finish, in order, and dropped, so that a sweep of any size
        runs in bounded memory; the result then holds no columns, only ``path``
        and ``summary`` (read the rows with :meth:`SweepResult.read`).
    shaft : bool, default False
        Add the main shaft's columns (one ``cyclomech run`` analysis per design,
        ~0.7 s for the loom with its cam; NaN where there is no main shaft).

    Returns
    -------
    SweepResult
        The key figures at every point (the parameters vary slowest, the speed
        fastest), or with ``out`` the file's path and a summary.

    Raises
    ------
    InputError
        If ``machine`` was not read from a file or a dict, a parameter names no key
        its table can take, a value is not a finite number, ``batch``, ``shaft``,
        ``chunk`` or ``executor`` is not of its kind, ``out`` is no ``.parquet``
        path (or pyarrow is missing), or the result cannot fit in memory.

    Examples
    --------
    >>> import cyclomech as cm
    >>> r = cm.sweep(cm.Machine.example(), {"lifter.a_max_m": [1e-4, 2e-4],
    ...                                     "speed_rpm": [300.0]})
    >>> r.columns["limiting_deg"].round(2).tolist()
    [264.97, 275.0]
    """
    if not isinstance(machine, Machine) or machine.data is None:
        raise InputError("machine must be a cyclomech.Machine read from a file or a dict")
    for flag, value in (("batch", batch), ("shaft", shaft)):
        if not isinstance(value, bool):
            raise InputError(f"{flag} must be True or False; got {value!r}")
    instance("grid", grid, Mapping)
    names = [k for k in grid if k != SPEED]
    axes = [_axis(k, grid[k]) for k in names]
    speeds = (
        machine.speed_grid() if SPEED not in grid else speeds_rpm(f"grid[{SPEED!r}]", grid[SPEED])
    )
    # Every parameter must name a key the file can take; a value that makes a design
    # invalid is that design's problem (a column), not the sweep's.
    for k in names:
        check_parameter(machine, k)
    shape = tuple(a.size for a in axes)
    _check_size(math.prod(shape), speeds.size, len(names), streamed=out is not None)
    # Design d takes axes[j][designs[d, j]]: indices, so whole-number keys stay whole.
    designs = np.indices(shape).reshape(len(shape), -1).T if names else np.zeros((1, 0), np.intp)
    D = designs.shape[0]
    ex = _as_executor(executor)
    S = speeds.size
    if chunk is None:
        # In-process: about 100 steps of the progress bar, but at least 64 designs a
        # chunk (each chunk is one call per kernel); on an executor, 64 tasks. At
        # most _TASK_POINTS points a task, so that a task's working set is bounded.
        chunk = math.ceil(D / 64) if ex is not None else max(math.ceil(D / 100), min(D, 64))
        chunk = max(1, min(chunk, _TASK_POINTS // S))
    if isinstance(chunk, bool) or not isinstance(chunk, int) or chunk < 1:
        raise InputError(f"chunk must be a whole number of designs ≥ 1; got {chunk!r}")
    stream = None if out is None else _Stream(out, names)
    tasks = _tasks(D, S, chunk)
    bar = progress_bar(D * S, "sweep", progress)
    t0 = time.perf_counter()
    kept: list[dict[str, npt.NDArray[Any]]] = []
    data, source = machine.data, machine.source

    def emit(i: int, part: dict[str, npt.NDArray[Any]]) -> None:
        """Task i's rows, in order: kept, or written to ``out`` and dropped."""
        r, sl = tasks[i]
        cols: dict[str, npt.NDArray[Any]] = {}
        for j, k in enumerate(names):
            cols[k] = np.repeat(axes[j][designs[r, j]], sl.stop - sl.start)
        cols[SPEED] = np.tile(speeds[sl], r.stop - r.start)
        cols.update(part)
        if stream is None:
            kept.append(cols)
        else:
            stream.write(cols)
        bar.update(cols[SPEED].size)

    base = Machine.from_dict(data, source)
    loads = (has_shaft(base) if shaft else None) if isinstance(shaft, bool) else None

    def args(i: int, threads: int | None) -> tuple[Any, ...]:
        r, sl = tasks[i]
        return (data, source, names, axes, designs[r], speeds[sl], threads)

    def submit(i: int) -> cf.Future[dict[str, npt.NDArray[Any]]]:
        # n_threads=1 last among the positional arguments: the workers' own.
        assert ex is not None
        return ex.submit(_run_chunk, *args(i, 1), batch=batch, shaft=loads)

    try:
        if ex is None:
            for i in range(len(tasks)):
                emit(i, _run_chunk(*args(i, n_threads), batch=batch, base=base, shaft=loads))
        else:
            _run_on(ex, len(tasks), submit, emit)
    except BaseException:
        if stream is not None:
            stream.abort()
        raise
    finally:
        bar.close()
    seconds = time.perf_counter() - t0
    if stream is not None:
        return SweepResult({}, tuple(names), seconds, stream.close(), stream.summary)
    with plain_pages():  # the result's columns, written once (see plain_pages)
        cols = {k: np.concatenate([c[k] for c in kept]) for k in kept[0]}
    return SweepResult(cols, tuple(names), seconds)


#: Most points [design × speed] a task takes by default, and the speeds of one
#: design a task takes at most: a task's working set (~1.7 KB a point: the
#: shortest paths' weights, minimums and chains) stays within ~60 MB, whatever
#: the sweep's size.
_TASK_POINTS = 1 << 15


def _tasks(D: int, S: int, chunk: int) -> list[tuple[slice, slice]]:
    """The tasks in row order: (designs, speeds) of ``chunk`` designs at every
    speed, or, when one design has more than :data:`_TASK_POINTS` speeds, one
    design at blocks of that many speeds (each block works out the design's
    speed limit again: the same number)."""
    if S > _TASK_POINTS:
        return [
            (slice(d, d + 1), slice(s, min(s + _TASK_POINTS, S)))
            for d in range(D)
            for s in range(0, S, _TASK_POINTS)
        ]
    return [(slice(r.start, r.stop), slice(0, S)) for r in _chunks(D, chunk)]


#: Tasks an executor holds at once: submitted as earlier ones finish, so that the
#: results waiting for their turn (rows are emitted in order) stay bounded.
_IN_FLIGHT = 16


def _run_on(
    ex: cf.Executor,
    n: int,
    submit: Any,
    emit: Any,
) -> None:
    """Run tasks 0..n-1 on ``ex`` (``submit(i)`` gives a future), at most
    :data:`_IN_FLIGHT` at once, and ``emit(i, result)`` them in order."""
    running: dict[cf.Future[Any], int] = {}
    done: dict[int, Any] = {}
    nxt = first = 0
    try:
        while first < n:
            while nxt < n and len(running) + len(done) < _IN_FLIGHT:
                running[submit(nxt)] = nxt
                nxt += 1
            finished, _ = cf.wait(list(running), return_when=cf.FIRST_COMPLETED)
            for f in finished:
                done[running.pop(f)] = f.result()
            while first in done:
                emit(first, done.pop(first))
                first += 1
    except BaseException:
        for f in running:
            f.cancel()
        raise


class _Stream:
    """A sweep's rows written to a Parquet file as they come (one row group a
    task) under a temporary name, renamed when complete; ``summary`` counts what
    the caller would read from the columns."""

    def __init__(self, path: str | Path, names: Sequence[str]) -> None:
        p = Path(path)
        if p.suffix != ".parquet":
            raise InputError(
                f"out = {str(path)!r} must name a .parquet file: the rows are streamed to it "
                "as row groups (SweepResult.read reads it)"
            )
        try:
            import pyarrow.parquet  # noqa: F401
        except ImportError:
            raise InputError(
                "out=: streaming a sweep to Parquet needs pyarrow (`pip install pyarrow`)"
            ) from None
        self.path = p
        self.tmp = partial(p)
        self.meta = {b"schema": SCHEMA.encode(), b"parameters": ",".join(names).encode()}
        self.writer: Any = None
        self.summary: dict[str, Any] = {"points": 0, "fits": 0, "invalid": 0, "problem": ""}
        # Folders made for the file (at its first rows), removed again on an abort.
        self.made: list[Path] = []

    def _folder(self) -> None:
        missing = [d for d in (self.path.parent, *self.path.parent.parents) if not d.exists()]
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
        except OSError as e:
            raise InputError(f"out = {str(self.path)!r}: cannot create its folder: {e}") from None
        self.made = missing

    def write(self, cols: Mapping[str, npt.NDArray[Any]]) -> None:
        import pyarrow as pa
        import pyarrow.parquet as pq

        table = pa.table({k: pa.array(v) for k, v in cols.items()})
        if self.writer is None:
            self._folder()
            schema = table.schema.with_metadata(self.meta)
            self.writer = pq.ParquetWriter(self.tmp, schema)
        self.writer.write_table(table.replace_schema_metadata(self.meta))
        sm, problem = self.summary, cols["problem"]
        sm["points"] += int(problem.size)
        sm["fits"] += int(cols["fits"].sum())
        bad = problem != ""
        sm["invalid"] += int(bad.sum())
        if bad.any() and not sm["problem"]:
            sm["problem"] = str(problem[bad][0])

    def close(self) -> Path:
        self.writer.close()  # a sweep has at least one point: one task was written
        os.replace(self.tmp, self.path)
        return self.path

    def abort(self) -> None:
        with contextlib.suppress(Exception):
            if self.writer is not None:
                self.writer.close()
        self.tmp.unlink(missing_ok=True)
        for d in self.made:  # innermost first; only if still empty
            with contextlib.suppress(OSError):
                d.rmdir()


@contextlib.contextmanager
def _sigint_ignored() -> Iterator[None]:
    """SIGINT ignored while the block runs, so that the processes it starts ignore
    it too (an ignored signal stays ignored through exec, and Python then
    installs no handler of its own): Ctrl-C in a terminal reaches the whole
    process group, and this process, not each Dask worker, decides what it
    means. A Ctrl-C during the block is lost."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    old = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, old)


def dask_workers(spec: str) -> int:
    """The ``--dask`` spec checked: the number of local worker processes it asks for.

    Parameters
    ----------
    spec : str
        ``local``, ``local:N`` or a scheduler address ``tcp://HOST:PORT`` (or
        ``tls://``).

    Returns
    -------
    int
        The number of local worker processes: 2 for ``local``, N for
        ``local:N``, 0 for a scheduler address.

    Raises
    ------
    InputError
        If N is not a whole number ≥ 1 or the spec is none of these.

    Examples
    --------
    >>> from cyclomech.machine import dask_workers
    >>> dask_workers("local:3"), dask_workers("tcp://10.0.0.5:8786")
    (3, 0)
    """
    if spec == "local":
        return 2
    if spec.startswith("local:"):
        try:
            n = int(spec.split(":", 1)[1])
        except ValueError:
            n = 0
        if n < 1:
            raise InputError(f"--dask {spec!r}: give local:N with N ≥ 1 worker processes")
        return n
    if not spec.startswith(("tcp://", "tls://")):
        raise InputError(
            f"--dask {spec!r} must be local, local:N or a scheduler address tcp://HOST:PORT"
        )
    return 0


def dask_client(spec: str) -> Any:
    """A ``dask.distributed.Client`` for ``--dask``.

    Close it when done (``client.close()``, and ``client.cluster.close()`` for a
    local one).

    Parameters
    ----------
    spec : str
        ``local`` or ``local:N`` starts a LocalCluster of N worker processes
        (default 2) with one thread each; ``tcp://HOST:PORT`` connects to a
        running scheduler (see :func:`dask_workers`).

    Returns
    -------
    dask.distributed.Client
        The client.

    Raises
    ------
    InputError
        If the spec is invalid, dask.distributed is not installed, or no scheduler
        answers at the address.

    Examples
    --------
    >>> from cyclomech.machine import dask_client
    >>> dask_client("udp://host:1")                        # doctest: +ELLIPSIS
    Traceback (most recent call last):
    cyclomech._errors.InputError: --dask 'udp://host:1' must be local, local:N or a ...
    """
    workers = dask_workers(spec)
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError:
        raise InputError("--dask needs dask.distributed; pip install 'cyclomech[dask]'") from None
    if workers:
        # dashboard_address=None would still bind the scheduler's HTTP server to port
        # 8787 (taken by any other Dask cluster here); ":0" takes a free port.
        with _sigint_ignored():
            cluster = LocalCluster(
                n_workers=workers,
                threads_per_worker=1,
                processes=True,
                dashboard_address=":0",
                # Critical only: after a Ctrl-C the cancelled tasks and a worker's
                # heartbeat to the scheduler that closed first are logged as errors,
                # and are no news. A task's own exception reaches the caller anyway.
                silence_logs=logging.CRITICAL,
            )
        return Client(cluster)
    try:
        return Client(spec)
    except (OSError, TimeoutError) as e:
        raise InputError(
            f"--dask {spec!r}: no Dask scheduler answered there ({e}); start one "
            "(`dask scheduler`) and give its address, or use local:N"
        ) from None
