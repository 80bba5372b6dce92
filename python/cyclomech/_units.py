"""Units: the one place where shaft speeds are converted between rpm, rad/s and deg/s.

SI inside; the edges that take rpm or degrees say so in their names.

>>> from cyclomech._units import DEG_PER_S_PER_RPM, RAD_PER_S_PER_RPM
>>> round(60.0 * RAD_PER_S_PER_RPM, 12), 60.0 * DEG_PER_S_PER_RPM   # one turn a second
(6.28318530718, 360.0)
"""

from __future__ import annotations

import math

__all__ = ["DEG_PER_S_PER_RPM", "RAD_PER_S_PER_RPM"]

#: Angular speed [rad/s] of a shaft turning at 1 rpm: 2π/60.
RAD_PER_S_PER_RPM = 2.0 * math.pi / 60.0
#: Angular speed [deg/s] of a shaft turning at 1 rpm: 360/60.
DEG_PER_S_PER_RPM = 6.0
