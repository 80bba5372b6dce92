"""The cyclogram (cycle diagram) of a machine as a network (seed 000).

Events are characteristic positions of mechanisms, with occurrence angles p(x) in
degrees of main-shaft rotation; operations are arcs (x, y) whose phase angle is
t(x, y) = p(y) - p(x) (+ cycle_deg for an operation that ends in the next cycle).
Each operation has a minimum admissible angle (kinematics, contact stress,
vibration), optionally a maximum, and optionally a minimum duration in seconds,
which takes 6·n·seconds degrees at n rpm.

* :meth:`Cyclogram.schedule` — every operation at its minimum: earliest and latest
  event angles, slack and critical operations (Rust longest-path kernel).
* :meth:`Cyclogram.optimize` — the seed's LP (eq. 1): minimise the group's duration
  p(N) - p(1), or maximise the limiting operation inside the cycle, subject to the
  bounds and the added linear constraints; shadow prices of every bound and
  constraint; infeasibility explained.
* :meth:`Cyclogram.max_speed_rpm` — the highest main-shaft speed at which the
  cyclogram still fits in its cycle (maximum cycle ratio, Howard's policy iteration).
* :meth:`Cyclogram.feasible_set` — the LP's feasible set, for a second objective
  within it (the main shaft's flattening).
* ``BoundLaw`` (a callable of speeds), :class:`Proportional` — the laws of the lower bounds that
  mechanisms put on operations against speed, which :class:`SpeedNetwork` evaluates.
"""

from __future__ import annotations

from ._bounds import BoundLaw, Proportional

# The unchecked law for the machine's sweeps, whose slopes were checked when their
# laws were built: at the door for the mechanism-kind contract (cyclomech._kind),
# not in __all__ (not a user's function: it checks nothing).
from ._bounds import proportional_law as proportional_law
from ._graph import (
    EventGraph,
    GraphAnalysis,
    longest_path,
    max_cycle_ratio,
    max_difference,
)
from ._model import (
    Arc,
    Constraint,
    Cyclogram,
    Operation,
    Optimum,
    Schedule,
    SpeedLimit,
    minimum_angles,
)
from ._network import SPEED_FLOOR_RPM, BoundsAt, SpeedNetwork

__all__ = [
    "SPEED_FLOOR_RPM",
    "Arc",
    "BoundLaw",
    "BoundsAt",
    "Constraint",
    "Cyclogram",
    "EventGraph",
    "GraphAnalysis",
    "Operation",
    "Optimum",
    "Proportional",
    "Schedule",
    "SpeedLimit",
    "SpeedNetwork",
    "longest_path",
    "max_cycle_ratio",
    "max_difference",
    "minimum_angles",
]
