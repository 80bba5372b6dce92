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

_LinkageArrays = tuple[
    npt.NDArray[np.float64],
    npt.NDArray[np.float64] | None,
    npt.NDArray[np.float64] | None,
    npt.NDArray[np.bool_],
    npt.NDArray[np.bool_],
    npt.NDArray[np.bool_],
]

@final
class LinkageProgram:
    """A linkage compiled into solving steps.

    Rows of idx have 6 entries and rows of dims 8. kind[s]: 0 driver (idx = pivot,
    tip; dims = radius); 1 two circles (idx = a, b, p; dims = ra, rb, sign); 2 class
    III group (idx = 3 anchors, 3 joints; dims = 3 arms, 3 sides, orientation); 3
    circle and guide (idx = a, p, b, c; dims = r, sign, ox, oy, ux, uy); 4 two
    guides (idx = p, b1, c1, b2, c2; dims = o1, u1, o2, u2); 5 link aimed through a
    block (idx = b, s, c; dims = len, sign). A guide with b = -1 is fixed.
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
        self,
        angles: npt.NDArray[np.float64],
        points: npt.NDArray[np.int64],
        *,
        analogs: bool = True,
        n_threads: int | None = None,
    ) -> _LinkageArrays: ...
    def solve_many(
        self,
        dims: npt.NDArray[np.float64],
        angles: npt.NDArray[np.float64],
        points: npt.NDArray[np.int64],
        *,
        analogs: bool = True,
        n_threads: int | None = None,
    ) -> _LinkageArrays: ...
