"""The whole machine: one machine file in, its key figures against speed out.

A machine file (TOML) holds a ``[machine]`` table, its mechanisms as
``[mechanism.<name>]`` tables with a ``kind``, and its cyclogram in the layout of
:meth:`cyclomech.Cyclogram.from_toml` (``[cyclogram]``, ``[[operation]]``,
``[[constraint]]``). Units: SI (m, s, kg, Pa, N/m), and every key with a unit says
it in its name (``_m``, ``_kg``, ``_pa``, ``_deg``, ``_rpm``, …; an old name such
as ``a_max`` is an error naming the new one). Values a user is unlikely to mean
are an error (a rebound limit not below the stroke) or a
:class:`~cyclomech.CyclomechWarning` naming the likely slip (``zeta = 5``: did you
mean 0.05?; a length over 10 m; an angle under 0.01°). The layout::

    [machine]
    name = "STB loom, group 1"
    speed_rpm = [200.0, 500.0]      # the speed range of the study [rpm]
    speed_points = 61               # optional: speeds in the report's sweep
    nominal_rpm = 300.0             # optional: the speed of the optimised cyclogram
                                    # (default: the top of the range, or the speed
                                    # limit if that is lower)
    angle_points = 361              # optional: crank angles per turn for mechanisms
    speed_fluctuation = 0.05        # optional: the main shaft's δ = (ω_max − ω_min)/ω
                                    # for its flywheel (default 0.05)
    flatten_torque = false          # optional: move the main shaft's parts within the
                                    # cyclogram's slack to the lowest peak |torque|

    [mechanism.lifter]              # a cam-driven lever that hits a limit stop
    kind = "cam_stop"
    law = "modified_sine"           # and cyclomech.impact.StopImpact's values, by keys
    stroke_m = 0.0094               # with units: stroke_m, preload_m, lever_length_m,
    ...                             # J_A_kg_m2, a_m, b_m, E_pa, J_x_m4; optional mass_kg,
                                    # restitution, zeta, contact_stiffness_n_per_m,
                                    # contact_time_s, pulse, model
    arc = ["3", "7"]                # the operation that brings it to the stop
    a_max_m = 1e-4                  # first-rebound limit
    phase_deg = [20.0, 60.0, 5]     # optional: phase angles drawn in the report

    [mechanism.knife]               # a planar linkage, the table of Linkage.from_dict
    kind = "linkage"                # points, links, ground, driver, lengths, sliders, output
    max_acceleration_m_per_s2 = 50.0   # optional: limit on the output point's |a|
    gravity_m_per_s2 = [0, -9.81]   # optional forces (cyclomech.forces): gravity,
    point_mass_kg = {E = 5.0}       # lumped masses [kg], [[…mass]] (link, mass_kg,
    phase = {event = "clamped", crank_deg = 140.0}   # com_m, inertia_kg_m2),
                                    # [[…load]] (point + force_n or link + torque_nm,
                                    # angle_deg for a table); phase: the crank angle
                                    # at that event (its torque on the main shaft)

    [mechanism.drive]               # the planetary gear-lever press drive
    kind = "press"
    R_m = 0.09                      # R_m, r_m, d_m, L_m, phi0_deg, offset_m
    k_Sp = 0.1                      # or working_stroke_m
    max_V_np_m_per_s = 0.05         # optional: limit on the speed at the start of the
                                    # working stroke
    slider_mass_kg = 60.0           # optional crank torque: slider and rod masses, the
    rod_mass_kg = 15.0              # deformation force over the height above BDC:
    deformation_force = {s_above_bdc_m = [0.0, 0.012], force_n = [2e5, 0.0]}
    phase = {event = "bottom", crank_deg = 0.0}      # BDC at that event

    [mechanism.line]                # a transfer between two rotors
    kind = "transfer"
    R_t_m = 0.15                    # pitch radii, the gap between the pitch circles
    R_p_m = 0.25
    gap_m = 0.01
    pockets_t = 8                   # pockets of each rotor: one workpiece per machine cycle
    pockets_p = 12
    x2_m = 0.04                     # optional transition length (default: the length
                                    # of least jerk, cyclomech.transfer.design_transfer)
    max_jerk_m_per_s3 = 5.0         # optional limits
    max_acceleration_m_per_s2 = 2.0

A cam stop constrains the cyclogram: at n rpm the phase angle of its arc must be
at least the smallest one whose first rebound is within ``a_max_m`` (exact, by
:meth:`~cyclomech.impact.StopImpact.min_phase_angle`). The other mechanisms limit
the speed directly where given a limit (their peaks grow as n, n² or n³).

The cyclogram's optimum at many speeds is a system of difference constraints
(every bound is on one operation's angle): its optimum is a shortest path,
computed for all speeds in one Rust call (:func:`cyclomech.cyclogram.max_difference`).
Constraints over several operations need the LP, one per speed.
"""

from __future__ import annotations

from .._keydoc import KeyDoc, KeyTable
from .._kind import (
    Bound,
    BoundsResult,
    Context,
    ExactBounds,
    Mechanism,
    MechanismResult,
    PlainResult,
    Proportional,
    TableContext,
    Unbounded,
)
from .._scene import Body, Scene
from ._kinds import KINDS, register
from ._model import (
    SCHEMA,
    Machine,
    SpeedSweep,
    check_parameter,
    speed_limits,
    speed_sweeps,
)
from ._report import (
    MachineResult,
    analyze,
    write_report,
)
from ._sensitivity import Sensitivity, drive_sensitivities, sensitivities
from ._sweep import (
    SweepResult,
    dask_client,
    dask_workers,
    parse_range,
    sweep,
)

__all__ = [
    "KINDS",
    "SCHEMA",
    "Body",
    "Bound",
    "BoundsResult",
    "Context",
    "ExactBounds",
    "KeyDoc",
    "KeyTable",
    "Machine",
    "MachineResult",
    "Mechanism",
    "MechanismResult",
    "PlainResult",
    "Proportional",
    "Scene",
    "Sensitivity",
    "SpeedSweep",
    "SweepResult",
    "TableContext",
    "Unbounded",
    "analyze",
    "check_parameter",
    "dask_client",
    "dask_workers",
    "drive_sensitivities",
    "parse_range",
    "register",
    "sensitivities",
    "speed_limits",
    "speed_sweeps",
    "sweep",
    "write_report",
]
