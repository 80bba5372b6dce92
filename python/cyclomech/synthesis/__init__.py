"""Synthesis: mechanisms dimensioned from what they must do.

Where the other domains analyse a mechanism whose dimensions the designer
brings, this one starts a step earlier, from what the mechanism must do: an
input–output relation (function generation), points a coupler point must pass
(path generation), poses a coupler must take (motion generation), a cam's
limits at given phase angles and speed (cam sizing). Every function returns
the dimensions with the margins of the constraints it was asked to hold.

Four-bars and slider-cranks, function and motion generation
-----------------------------------------------------------
Every four-bar or slider-crank result reports a :class:`Margins` (Grashof type,
whether the crank turns fully, the transmission angle's extremes over the
working range in closed form, branch, link-length ratio; also
:func:`four_bar_margins`, :func:`slider_crank_margins`) and builds its
:class:`cyclomech.Linkage` (:func:`four_bar_linkage`,
:func:`slider_crank_linkage`), so that the position solver analyses it like any
drawn linkage. :func:`function_generation` solves Freudenstein's equation (in
Norton's convention, angles from the ground line A → D) exactly through three
precision points — Chebyshev-spaced by :func:`chebyshev_points` or given —
or by least squares through more, reports the structural error over the whole
input range, and does the same for a slider-crank's position.
:func:`motion_generation` takes three, four or five poses of the coupler and
builds four-bars from two dyads (a circle point of the coupler whose positions
lie on a circle about a centre point, the ground pivot). Three poses: two circle
points (given, or scanned on a grid and ranked), their centre points the
circumcentres of their three positions. Four poses: dyads on Burmester's
circle-point and centre-point curves (:func:`burmester_curves`, traced in closed
form), chosen by the crank's rotation or scanned along the curves. Five poses:
every pair of Burmester's points (:func:`burmester_points`, at most four, all
of them bracketed along the curves; none or one raises). Candidates come best
first: clean ones (no branch or order defect, no fold over the range) before
the others, each with its defects and margins.

Path generation
---------------
:func:`path_generation` finds a four-bar or slider-crank whose coupler point
passes N target points, with the crank angles prescribed (timing) or free, by
differential evolution whose every generation is one parallel call of the Rust
batch evaluator (:func:`path_evaluate`, millions of candidates per call for a
user's own sweep), then least squares from the best. The constraints (a crank
that turns fully, the transmission angle, the link-length ratio, a box for the
ground pivots) are checked in closed form over the working range; a candidate
that breaks one ranks after every one that does not.

Cams sized against the cyclogram
--------------------------------
:func:`cam_size` gives a cam's smallest base radius (with the best offset of a
translating roller, or the pivot distance of an oscillating one) that meets its
pressure-angle, undercut and Hertz-stress limits at its phase angles and speed,
the binding limit and every margin; :func:`cam_size_tradeoff` the smallest
phase angles against the base radius, the trade the cyclogram makes. A machine
file's cam table asks for it with ``[mechanism.<name>.synthesize]`` and
``cyclomech run`` sizes it at the optimised timing, to a fixed point.

Seed 001's knife drives
-----------------------
:func:`knife_drive` dimensions one of the three generalised knife-drive schemes
(``br125``, ``br136``, ``brp4``) for a required knife motion (stroke, the crank
angle of the cut) by differential evolution, every generation solved in one
:func:`cyclomech.linkage.solve_geometries` call; :func:`compare_knife_drives`
synthesises each and compares them (transmission angles, peak acceleration and
jerk, driving torque and joint loads, speed limit). A machine file's linkage
table asks for it with ``[mechanism.<name>.synthesize]``.

Machine files
-------------
A machine file's linkage table may give requirements instead of dimensions,
``[mechanism.<name>.synthesize]`` with a ``scheme``: the knife drives above,
``function`` (:func:`function_generation`), ``path`` (:func:`path_generation`),
``motion`` (:func:`motion_generation`) or ``dwell_sixbar`` (:func:`dwell_sixbar`).
``cyclomech run`` synthesises the linkage, keeps the best candidate a machine can
run (its crank turning fully, counter-clockwise, on one branch; the table's own
limits held; a file none meets is refused, saying what the best one missed),
reports what it chose and why, and analyses it as any other linkage.

Six-bar dwell linkages
----------------------
:func:`dwell_sixbar` builds Stephenson III six-bars whose output rocker stands
(nearly) still while the crank turns a given dwell angle and swings a given
angle over the rest of the turn: a crank-rocker's coupler point traces a nearly
circular arc over the dwell (fitted by least squares, Kåsa's fit refined by
Gauss–Newton), a dyad of that arc's radius joins it to the output joint, which
stands at the arc's centre during the dwell, and the output's pivot is placed on
the perpendicular bisector of that joint's extreme positions so that the swing
measured on the six-bar's position solution is the one asked for. A
differential-evolution search over the four-bar and its coupler point, its whole
population evaluated in one parallel Rust call per generation, ranks the
candidates (:class:`DwellCandidate`) feasible first (both loops' transmission
angles at the limit or above, swing met), then by the output's residual motion
over the dwell; each builds its :class:`cyclomech.Linkage`.

>>> import cyclomech as cm
>>> six = cm.synthesis.dwell_sixbar(dwell_deg=60, swing_deg=40, maxiter=10)[0]
>>> six.feasible, round(six.swing_deg, 6), six.residual_deg < 1.0
(True, 40.0, True)

>>> import cyclomech as cm
>>> best = cm.synthesis.function_generation([(30, 80), (60, 90), (90, 100)], ground_m=0.2)[0]
>>> best.margins.grashof, best.clean
('crank-rocker', True)
"""

from __future__ import annotations

from ..cam import (  # the sizing lives beside the criteria it evaluates (cam/_size.py)
    CAM_SIZE_CRITERIA,
    CamLimits,
    CamSize,
    CamSizeTradeoff,
    cam_size,
    cam_size_tradeoff,
)
from . import (  # noqa: F401 - each registers its linkage synthesizer (a machine file's scheme)
    _dwell_file,
    _function_file,
    _motion_file,
    _path_file,
)
from ._burmester import BurmesterCurves, BurmesterPoint, burmester_curves, burmester_points
from ._dwell import DwellCandidate, dwell_sixbar
from ._fourbar import (
    Margins,
    four_bar_linkage,
    four_bar_margins,
    slider_crank_linkage,
    slider_crank_margins,
)
from ._function import FunctionCandidate, chebyshev_points, function_generation
from ._knife import KnifeDrive, KnifeRequirement, knife_drive, knife_motion
from ._knife_compare import KnifeComparison, compare_knife_drives, knife_forces
from ._knife_file import SYNTHESIZE_KEYS, KnifeSynthesis  # registers the linkage synthesizer
from ._motion import MotionCandidate, motion_generation
from ._path import PathCandidate, path_evaluate, path_generation

__all__ = [
    "CAM_SIZE_CRITERIA",
    "SYNTHESIZE_KEYS",
    "BurmesterCurves",
    "BurmesterPoint",
    "CamLimits",
    "CamSize",
    "CamSizeTradeoff",
    "DwellCandidate",
    "FunctionCandidate",
    "KnifeComparison",
    "KnifeDrive",
    "KnifeRequirement",
    "KnifeSynthesis",
    "Margins",
    "MotionCandidate",
    "PathCandidate",
    "burmester_curves",
    "burmester_points",
    "cam_size",
    "cam_size_tradeoff",
    "chebyshev_points",
    "compare_knife_drives",
    "dwell_sixbar",
    "four_bar_linkage",
    "four_bar_margins",
    "function_generation",
    "knife_drive",
    "knife_forces",
    "knife_motion",
    "motion_generation",
    "path_evaluate",
    "path_generation",
    "slider_crank_linkage",
    "slider_crank_margins",
]
