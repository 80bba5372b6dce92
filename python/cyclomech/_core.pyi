"""Type stubs of the Rust extension module ``cyclomech._core`` (the public contract).

Arrays in are C-contiguous (the Python layer coerces user input); arrays out are
new float64/int64/bool arrays. Every error is a ``cyclomech.CyclomechError``.
"""

from typing import Any, Literal, final

import numpy as np
import numpy.typing as npt

__all__ = [
    "EventGraph",
    "LinkageProgram",
    "__version__",
    "longest_path",
    "max_cycle_ratio",
    "max_speed",
]

__version__: str

def longest_path(
    n_events: int,
    src: npt.NDArray[np.int64],
    dst: npt.NDArray[np.int64],
    weights: npt.NDArray[np.float64],
    *,
    n_threads: int | None = None,
) -> npt.NDArray[np.float64]: ...
def max_cycle_ratio(
    n_events: int,
    src: npt.NDArray[np.int64],
    dst: npt.NDArray[np.int64],
    weights: npt.NDArray[np.float64],
    heights: npt.NDArray[np.float64],
) -> tuple[float, npt.NDArray[np.int64]] | None: ...
def max_speed(
    n_events: int,
    src: npt.NDArray[np.int64],
    dst: npt.NDArray[np.int64],
    angle_deg: npt.NDArray[np.float64],
    seconds: npt.NDArray[np.float64],
    heights: npt.NDArray[np.float64],
    cycle_deg: float,
) -> tuple[Literal["limited", "unlimited", "infeasible"], float, float, npt.NDArray[np.int64]]: ...

@final
class EventGraph:
    def __new__(
        cls, n_events: int, src: npt.NDArray[np.int64], dst: npt.NDArray[np.int64]
    ) -> EventGraph: ...
    @property
    def n_events(self) -> int: ...
    @property
    def n_arcs(self) -> int: ...
    @property
    def src(self) -> npt.NDArray[np.int64]: ...
    @property
    def dst(self) -> npt.NDArray[np.int64]: ...
    @property
    def topological_order(self) -> npt.NDArray[np.int64]: ...
    def longest_path(
        self, weights: npt.NDArray[np.float64], *, n_threads: int | None = None
    ) -> npt.NDArray[np.float64]: ...
    def latest(
        self, weights: npt.NDArray[np.float64], horizon: float
    ) -> npt.NDArray[np.float64]: ...
    def analyze(
        self, weights: npt.NDArray[np.float64], horizon: float | None = None
    ) -> dict[str, Any]: ...
    def __reduce__(self) -> tuple[Any, ...]: ...

@final
class LinkageProgram:
    """A linkage compiled into solving steps.

    kind[s]: 0 driver (idx = pivot, tip; dims = radius), 1 two circles (idx = a, b, p;
    dims = ra, rb, sign), 2 class III group (idx = 3 anchors, 3 joints; dims = 3 arms,
    3 sides, orientation). idx rows have 6 entries, dims rows 7.
    """

    def __new__(
        cls,
        n_points: int,
        fixed_idx: npt.NDArray[np.int64],
        fixed_xy: npt.NDArray[np.float64],
        kind: npt.NDArray[np.int64],
        idx: npt.NDArray[np.int64],
        dims: npt.NDArray[np.float64],
        drawn_phi: float,
        drawn_xy: npt.NDArray[np.float64],
    ) -> LinkageProgram: ...
    @property
    def n_points(self) -> int: ...
    def solve(
        self, angles: npt.NDArray[np.float64], *, n_threads: int | None = None
    ) -> tuple[
        npt.NDArray[np.float64],
        npt.NDArray[np.float64],
        npt.NDArray[np.float64],
        npt.NDArray[np.bool_],
        npt.NDArray[np.bool_],
    ]: ...
