"""The planetary gear-lever press drive of seed 003: kinematics, working-stroke
criteria, design grids and the non-dominated designs.

The drive: a crank (carrier) turns about the centre O of a fixed internal guide
gear of pitch radius R; a planet gear of radius r rolls inside it (i = R/r, a
whole number; the seed uses 3), so the planet centre is C = (R − r)·e^{iθ} and
the planet turns at −(R − r)/r times the carrier; the rod (length L) hangs on the
planet at eccentricity d, its pin tracing a hypotrochoid; the slider runs on the
vertical guide x = ``offset`` below O. ``phi0`` is the setting angle of the guide
gear: the angle it is turned from the setting in which the pin lies on the
carrier line, outwards, when the carrier points straight down (turning the guide
gear by φ0 turns the planet by i·φ0 relative to the carrier). Designs repeat with
period 2π/i in φ0. With d = 0 the drive is a plain crank-slider of radius R − r,
the baseline every design is compared with.

Angles follow the seed: the carrier turns counterclockwise, and α is the crank
angle counted from the slider's bottom dead centre (BDC) *against* the motion,
so S = Π(α) ≥ 0 is the slider's height above BDC and the working stroke is the
approach to BDC, α from α_p down to 0, where α_p is the first contact with the
blank coming down from TDC (see :class:`PressCriteria` for a slider that leaves
the blank and meets it again). Π' = dS/dα [m/rad], Π'' [m/rad²]; at a
constant crank speed ω the slider speed is |Π'|·ω and its acceleration Π''·ω².

Criteria (:class:`PressCriteria`, all from the Rust kernel): the nominal stroke
S_n, the working stroke S_p = k_Sp·S_n and its crank angle α_p, the slider speed
at its start V_np, its mean V_cp = S_p·ω/α_p and maximum V_pmax over it, the
largest acceleration J_max over the turn, the torque arm ``torque_arm`` (max Π' over the
working stroke: the crank torque per newton of a constant deformation force)
and the dimensionless k_Sp, k_Vp = V_np/V_cp (→ 0), k_Vmax = V_pmax/V_cp
(→ 1), k_M = torque_arm/(S_n/2) and k_J = J_max/(ω²·S_n/2) (→ min; both 1 + λ-ish
for a crank-slider).

The crank torque [N·m] (:meth:`GearLeverPress.crank_torque`, a
:class:`PressTorque`): M(α) = F(Π(α))·Π'(α) on the working stroke for a
deformation-force diagram F(S) (:class:`DeformationForce`, S the slider's height
above BDC inside [0, S_p]) minus ω²·(m_s·Π'·Π'' + a uniform rod's term), from the
power balance; its energy per stroke ∫ F dS and its peak.

Many designs: :func:`design_grid` evaluates a grid of designs in one call and
:func:`pareto_mask` and :func:`optimize` find the non-dominated ones; a press file
(``cyclomech press FILE.toml``) and a machine file's ``kind = "press"`` mechanism
describe one drive.
"""

from __future__ import annotations

from ._drive import CRITERIA, SAMPLES, STATUS, GearLeverPress, PressCriteria, PressKinematics
from ._grid import PressGrid, design_grid
from ._kind import PressMechanism
from ._optimize import OBJECTIVES, PressOptimum, optimize, pareto_mask
from ._study import PressStudy
from ._torque import DeformationForce, PressTorque

__all__ = [
    "CRITERIA",
    "OBJECTIVES",
    "SAMPLES",
    "STATUS",
    "DeformationForce",
    "GearLeverPress",
    "PressCriteria",
    "PressGrid",
    "PressKinematics",
    "PressMechanism",
    "PressOptimum",
    "PressStudy",
    "PressTorque",
    "design_grid",
    "optimize",
    "pareto_mask",
]
