"""Impact of a driven link on its limit stop (seed 000).

A cam-driven lever pressed with preload against a stop strikes it, vibrates, and
rebounds; the first rebound must stay under a limit (0.1 mm for the STB loom's
microshuttle lifter), which bounds the phase angle of the operation that brings
the lever to the stop. This module holds the physics layer:

* the lever's reduced stiffness, free (:func:`lever_stiffness`, the seed's
  3·E·J_x/((a+b)·b²)) and propped at the stop (:func:`propped_lever_stiffness`),
  :func:`natural_frequency`, :func:`contact_time` and :func:`impact_force`;
* force pulses as piecewise-linear tables (:class:`Pulse`);
* the exact response of a damped oscillator to such a force (:func:`duhamel`,
  :func:`duhamel_batch`, :func:`first_rebound`), in Rust;
* the stop as a unilateral contact (:func:`contact_response`);
* :class:`StopImpact`, the lever with its stop, whose rebound against speed and
  phase angle becomes a constraint of the :class:`cyclomech.Cyclogram`;
* :class:`ImpactStudy`, the impact file.

Functions over many stops at once (:func:`rebounds`, :func:`max_impact_speeds`,
:func:`min_phase_angles`) evaluate every stop in one Rust call.

SI units: m, kg, N, s, rad; speeds in rpm and phase angles in degrees where the
names say so.
"""

from __future__ import annotations

from ._contact import ContactHistory, contact_response, contact_sample
from ._kind import CamStop
from ._lever import (
    contact_time,
    impact_force,
    lever_stiffness,
    natural_frequency,
    propped_lever_stiffness,
)
from ._pulse import Pulse
from ._response import Rebound, duhamel, duhamel_batch, first_rebound
from ._stop import StopImpact
from ._stops import max_impact_speeds, min_phase_angles, rebounds
from ._study import ImpactStudy

__all__ = [
    "CamStop",
    "ContactHistory",
    "ImpactStudy",
    "Pulse",
    "Rebound",
    "StopImpact",
    "contact_response",
    "contact_sample",
    "contact_time",
    "duhamel",
    "duhamel_batch",
    "first_rebound",
    "impact_force",
    "lever_stiffness",
    "max_impact_speeds",
    "min_phase_angles",
    "natural_frequency",
    "propped_lever_stiffness",
    "rebounds",
]
