"""Units: the one place where shaft speeds are converted between rpm, rad/s and deg/s.

SI inside; the edges that take rpm or degrees say so in their names.
``RAD_PER_S_PER_RPM`` is the angular speed [rad/s] of a shaft turning at 1 rpm (2π/60),
``DEG_PER_S_PER_RPM`` the same in deg/s (360/60). Both come from the Rust core
(``cyclomech._core``), which uses them too: one copy of each.

>>> from cyclomech._units import DEG_PER_S_PER_RPM, RAD_PER_S_PER_RPM
>>> round(60.0 * RAD_PER_S_PER_RPM, 12), 60.0 * DEG_PER_S_PER_RPM   # one turn a second
(6.28318530718, 360.0)
"""

from __future__ import annotations

from ._core import DEG_PER_S_PER_RPM, RAD_PER_S_PER_RPM

__all__ = ["DEG_PER_S_PER_RPM", "RAD_PER_S_PER_RPM"]
