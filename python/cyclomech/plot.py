"""Every plot of cyclomech in one place: a facade over the domains' plot modules.

Each domain owns its plots; this module only re-exports them under the names they
have always had here, so ``from cyclomech.plot import plot_press`` and
``from cyclomech.press.plot import plot_press`` give the same function:

* ``cyclomech.cyclogram.plot`` — :func:`plot_cyclogram`, :func:`plot_cyclogram_pair`
  (a Gantt chart over the cycle and a circular diagram);
* ``cyclomech.dynamics.plot`` — :func:`plot_shaking` (the shaking force's
  hodograph and the shaking moment over the cycle, before and after balancing),
  :func:`plot_torsion` (the working members' dynamic errors and the shaft's twist);
* ``cyclomech.forces.plot`` — :func:`plot_forces` (a linkage's driving torque
  and joint loads over the crank angle);
* ``cyclomech.linkage.plot`` — :func:`plot_linkage`, :func:`plot_analogs`,
  :func:`animate_linkage` (the mechanism, a point's position and analogs, a GIF);
* ``cyclomech.motion.plot`` — :func:`plot_law` (a motion law);
* ``cyclomech.press.plot`` — :func:`plot_press`, :func:`plot_press_criteria`,
  :func:`plot_crank_torque` (the gear-lever press, the maps of its working-stroke
  criteria, its deformation force and crank torque);
* ``cyclomech.impact.plot`` — :func:`plot_response`, :func:`plot_rebound_vs_speed`,
  :func:`plot_min_phase` (a stop: the motion after contact, the first rebound and
  the smallest phase angle against speed);
* ``cyclomech.cam.plot`` — :func:`plot_cam`, :func:`plot_svaj`, :func:`plot_along_cycle`,
  :func:`plot_min_phase_angles`, :func:`plot_size_tradeoff` (a disc cam: the cam and
  its follower, the SVAJ diagram, the pressure angle, forces and stress along the
  cycle, the smallest phase angles against speed per criterion, and against the base
  radius);
* ``cyclomech.transfer.plot`` — :func:`plot_transfer` (a rotor transfer path);
* ``cyclomech.servo.plot`` — :func:`plot_duty` (a servo motor's torque and speed
  over the cycle, with its limits);
* ``cyclomech.machine.plot`` — :func:`plot_speed_sweep` (the machine against speed),
  :func:`plot_machine_frame` and :func:`animate_machine` (the machine moving: one
  frame, or a GIF over the cycle).
* ``cyclomech.synthesis.plot`` — :func:`plot_knife_motion`, :func:`plot_knife_torque`
  (compared knife drives), :func:`plot_burmester` (Burmester's curves of four poses
  with the chosen dyads).

The colours the plots use are here too (``CRITICAL_COLOR``,
``LIMITING_COLOR``, …). Lengths are metres in and millimetres on the axes where
a function says so, angles degrees on the axes. matplotlib is an optional dependency
(``pip install 'cyclomech[plot]'``), imported only when a function draws; the
functions never call ``plt.show()``.

>>> from cyclomech.plot import plot_press
>>> from cyclomech.press.plot import plot_press as same
>>> plot_press is same, plot_press.__module__
(True, 'cyclomech.press.plot')
"""

from __future__ import annotations

from ._plotting import CRITICAL_COLOR as CRITICAL_COLOR
from ._plotting import DRIVER_COLOR as DRIVER_COLOR
from ._plotting import LINK_COLOR as LINK_COLOR
from ._plotting import MOTION_COLORS as MOTION_COLORS
from ._plotting import PLATE_COLOR as PLATE_COLOR
from ._plotting import TRACE_COLORS as TRACE_COLORS
from .cam.plot import (
    plot_along_cycle,
    plot_cam,
    plot_min_phase_angles,
    plot_size_tradeoff,
    plot_svaj,
)
from .cyclogram.plot import LIMITING_COLOR as LIMITING_COLOR
from .cyclogram.plot import MECHANISM_COLORS as MECHANISM_COLORS
from .cyclogram.plot import OTHER_ROW as OTHER_ROW
from .cyclogram.plot import plot_cyclogram, plot_cyclogram_pair
from .dynamics.plot import plot_shaking, plot_torsion
from .forces.plot import plot_forces
from .impact.plot import plot_min_phase, plot_rebound_vs_speed, plot_response
from .linkage.plot import XY_COLORS as XY_COLORS
from .linkage.plot import animate_linkage, plot_analogs, plot_linkage
from .machine.plot import animate_machine, plot_machine_frame, plot_speed_sweep
from .motion.plot import plot_law
from .press.plot import WORK_COLOR as WORK_COLOR
from .press.plot import plot_crank_torque, plot_press, plot_press_criteria
from .servo.plot import plot_duty
from .synthesis.plot import plot_burmester, plot_knife_motion, plot_knife_torque
from .transfer.plot import plot_transfer

__all__ = [
    "animate_linkage",
    "animate_machine",
    "plot_along_cycle",
    "plot_analogs",
    "plot_burmester",
    "plot_cam",
    "plot_crank_torque",
    "plot_cyclogram",
    "plot_cyclogram_pair",
    "plot_duty",
    "plot_forces",
    "plot_knife_motion",
    "plot_knife_torque",
    "plot_law",
    "plot_linkage",
    "plot_machine_frame",
    "plot_min_phase",
    "plot_min_phase_angles",
    "plot_press",
    "plot_press_criteria",
    "plot_rebound_vs_speed",
    "plot_response",
    "plot_shaking",
    "plot_size_tradeoff",
    "plot_speed_sweep",
    "plot_svaj",
    "plot_torsion",
    "plot_transfer",
]
