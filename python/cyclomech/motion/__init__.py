"""Dimensionless motion laws and the two-period slider law (seed 003).

A law Z(j) lives on the unit square: 0 ≤ j ≤ 1, Z(0) = 0, Z(1) = 1, Z'(0) = 0.
Two forms of each named law:

* the **rise** (``form="rise"``): zero speed at both ends, Z' peaking at j = ½,
  with the classical peaks Cv = max Z' and Ca = max |Z''| (cycloidal 2 and 2π);
* the **half law** (``form="half"``, the default): the first half of the rise
  rescaled to the unit square, Z_h(j) = 2·Z(j/2), so Z_h'(0) = 0 and Z_h' peaks at
  j = 1 — the dimensionless characteristic of seed 003 (cycloidal half law
  Z = j − sin(πj)/π, Z'max = 2, Z''max = π).

A **motion program** (:class:`Program`) is what a cam or a servo axis follows over
one master cycle: :class:`Segment` s in VDI 2143's sense, each a law over a master
angle between end values (position, velocity, acceleration, jerk per radian of
master) that may be in motion — rest–rest, rest–velocity, velocity–velocity,
motion–motion — with constant velocity, polynomials from end conditions and splines
through point tables beside the named laws. :meth:`Program.evaluate` gives s and its
derivatives in closed form; joins are checked to the order asked.

:func:`two_period` synthesises the slider law Π(α) of seed 003 from a half law
for each period and one of the seed's three complexes of input data.
Everything is evaluated in Rust, vectorised and exact (no finite differences).
"""

from __future__ import annotations

from ._export import (
    COEFFICIENT_COLUMNS,
    TABLE_COLUMNS,
    write_cam_coefficients,
    write_cam_table,
)
from ._laws import (
    NAMES,
    MotionLaw,
    TwoPeriodLaw,
    law,
    polynomial,
    two_period,
)
from ._program import (
    CONTINUITY,
    SEGMENT_LAWS,
    Characteristics,
    MotionValues,
    Program,
    Segment,
)

__all__ = [
    "COEFFICIENT_COLUMNS",
    "CONTINUITY",
    "NAMES",
    "SEGMENT_LAWS",
    "TABLE_COLUMNS",
    "Characteristics",
    "MotionLaw",
    "MotionValues",
    "Program",
    "Segment",
    "TwoPeriodLaw",
    "law",
    "polynomial",
    "two_period",
    "write_cam_coefficients",
    "write_cam_table",
]
