"""Type stubs of the Rust extension module ``cyclomech._core`` (the public contract).

Arrays in are C-contiguous (the Python layer coerces user input); arrays out are
new float64/int64/bool arrays. Every error is a ``cyclomech.CyclomechError``.
"""

from typing import Any, Literal, final, overload

import numpy as np
import numpy.typing as npt

__all__ = [
    "CAM_CRITERIA",
    "CAM_LOAD_COLUMNS",
    "CAM_SIZE_COLUMNS",
    "CAM_SIZE_CRITERIA",
    "CAM_SIZE_STATUS",
    "DEG_PER_S_PER_RPM",
    "MOTION_LAWS",
    "PRESS_STATUS",
    "RAD_PER_S_PER_RPM",
    "SEGMENT_LAWS",
    "SERVO_BOUNDS",
    "SERVO_CHECKS",
    "SERVO_DUTY",
    "SHAFT_STATS",
    "SHAKING_STATS",
    "CamKernel",
    "EventGraph",
    "ForceModel",
    "LinkageProgram",
    "MotionLaw",
    "ProgramKernel",
    "TwoPeriodKernel",
    "__version__",
    "cam_size",
    "cam_size_tradeoff",
    "contact_rebound_batch",
    "contact_response",
    "contact_sample",
    "duhamel",
    "duhamel_batch",
    "first_rebound_batch",
    "longest_path",
    "max_cycle_ratio",
    "max_difference",
    "max_speed",
    "pareto_mask",
    "press_check",
    "press_criteria_names",
    "press_solve",
    "press_sweep",
]

__version__: str

# Constants the Python layer shares with the core: one copy, in Rust.

#: Names of the built-in motion laws (cyclomech.motion.NAMES).
MOTION_LAWS: tuple[str, ...]
SEGMENT_LAWS: tuple[str, ...]
#: What each press status code means, indexed by code (cyclomech.press.STATUS).
PRESS_STATUS: tuple[str, ...]
#: Angular speed [rad/s] of a shaft turning at 1 rpm: 2π/60.
RAD_PER_S_PER_RPM: float
#: Angular speed [deg/s] of a shaft turning at 1 rpm: 6.
DEG_PER_S_PER_RPM: float
#: The cam's bound criteria, in the order of CamKernel.min_angles's last axis.
CAM_CRITERIA: tuple[str, ...]
#: The columns of CamKernel.loads.
CAM_LOAD_COLUMNS: tuple[str, ...]
#: cam_size: its criteria (binding index), statuses (status index) and columns.
CAM_SIZE_CRITERIA: tuple[str, ...]
CAM_SIZE_STATUS: tuple[str, ...]
CAM_SIZE_COLUMNS: tuple[str, ...]
#: The statistics of shaft_stats, in its columns' order.
SHAFT_STATS: tuple[str, ...]
#: The columns of dynamics_steady_batch's rows, in order.
DYNAMICS_STEADY_COLUMNS: tuple[str, ...]
#: The steady state's outcomes, by status code.
DYNAMICS_STEADY_STATUS: tuple[str, ...]
#: The statistics of shaking_batch, in its columns' order.
SHAKING_STATS: tuple[str, ...]
#: The checks of a servo motor, in the order of servo_size's last axis.
SERVO_CHECKS: tuple[str, ...]
#: The criteria of servo_min_angles, in its last axis' order.
SERVO_BOUNDS: tuple[str, ...]
#: The statistics of servo_duty, in its columns' order.
SERVO_DUTY: tuple[str, ...]

# cyclogram: longest paths, event graphs, cycle ratios, difference constraints.

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
def max_difference(
    n_nodes: int,
    src: npt.NDArray[np.int64],
    dst: npt.NDArray[np.int64],
    weights: npt.NDArray[np.float64],
    source: int,
    target: int,
    *,
    n_threads: int | None = None,
) -> tuple[float | npt.NDArray[np.float64], npt.NDArray[np.bool_]]: ...
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
        self,
        weights: npt.NDArray[np.float64],
        *,
        n_threads: int | None = None,
        out: npt.NDArray[np.float64] | None = None,
    ) -> npt.NDArray[np.float64]: ...
    def latest(
        self, weights: npt.NDArray[np.float64], horizon: float
    ) -> npt.NDArray[np.float64]: ...
    def analyze(
        self, weights: npt.NDArray[np.float64], horizon: float | None = None
    ) -> dict[str, Any]: ...
    def __reduce__(self) -> tuple[Any, ...]: ...

# cam: a validated disc cam; errors are cyclomech.InputError.

@final
class CamKernel:
    """A disc cam: program (angles [rad]), follower and closure (cyclomech.cam)."""

    def __new__(
        cls,
        kinds: list[str],
        angles: list[float],
        strokes: list[float],
        laws: list[str],
        follower: str,
        params: list[float],
        groove: bool,
        program: ProgramKernel | None = None,
    ) -> CamKernel: ...
    @property
    def initial_arm_angle(self) -> float | None: ...
    def solve(
        self,
        theta: npt.NDArray[np.float64],
        *,
        n_threads: int | None = None,
        out: npt.NDArray[np.float64] | None = None,
        undercut: npt.NDArray[np.bool_] | None = None,
        theta_copy: npt.NDArray[np.float64] | None = None,
    ) -> npt.NDArray[np.float64]: ...
    def loads(
        self,
        theta: npt.NDArray[np.float64],
        omega: float,
        loads: tuple[float, float, float, list[float]],
        contact: tuple[float, float, float, float, float] | None = None,
        *,
        n_threads: int | None = None,
    ) -> npt.NDArray[np.float64]: ...
    def jump_speed(self, loads: tuple[float, float, float, list[float]]) -> tuple[float, float]: ...
    def min_angles(
        self,
        segments: list[int],
        omegas: npt.NDArray[np.float64],
        max_pressure_angle: float,
        loads: tuple[float, float, float, list[float]] | None = None,
        contact: tuple[float, float, float, float, float] | None = None,
        max_stress: float | None = None,
        *,
        n_threads: int | None = None,
    ) -> npt.NDArray[np.float64]: ...

# synthesis: cam sizing (cyclomech.synthesis.cam_size); errors are cyclomech.InputError.

def cam_size(
    cam: CamKernel,
    omegas: npt.NDArray[np.float64],
    max_pressure_angle: float,
    min_radius: float,
    max_radius: float,
    loads: tuple[float, float, float, list[float]] | None = None,
    contact: tuple[float, float, float, float, float] | None = None,
    max_stress: float | None = None,
    second: tuple[float, float] | None = None,
    *,
    n_threads: int | None = None,
) -> npt.NDArray[np.float64]: ...
def cam_size_tradeoff(
    cam: CamKernel,
    radii: npt.NDArray[np.float64],
    segments: list[int],
    omegas: npt.NDArray[np.float64],
    max_pressure_angle: float,
    loads: tuple[float, float, float, list[float]] | None = None,
    contact: tuple[float, float, float, float, float] | None = None,
    max_stress: float | None = None,
    *,
    n_threads: int | None = None,
) -> npt.NDArray[np.float64]: ...

# linkage

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
    def change_points(self) -> list[tuple[int, float, bool, float]]: ...
    def solve(
        self,
        angles: npt.NDArray[np.float64],
        points: npt.NDArray[np.int64],
        *,
        analogs: bool = True,
        n_threads: int | None = None,
        out: _LinkageArrays | None = None,
    ) -> _LinkageArrays: ...
    def solve_many(
        self,
        dims: npt.NDArray[np.float64],
        angles: npt.NDArray[np.float64],
        points: npt.NDArray[np.int64],
        *,
        analogs: bool = True,
        n_threads: int | None = None,
        out: _LinkageArrays | None = None,
    ) -> _LinkageArrays: ...

# motion

@final
class MotionLaw:
    """A dimensionless law Z(x) on the unit square (rise or half law)."""

    @staticmethod
    def named(name: str, rise: bool) -> MotionLaw: ...
    @staticmethod
    def polynomial(coeffs: npt.NDArray[np.float64], rise: bool) -> MotionLaw: ...
    @property
    def dz_max(self) -> float: ...
    @property
    def ddz_max(self) -> float: ...
    @property
    def breaks(self) -> list[float]: ...
    def eval(
        self, x: npt.NDArray[np.float64], order: int, *, n_threads: int | None = None
    ) -> npt.NDArray[np.float64]: ...

@final
class ProgramKernel:
    """A motion program over one master cycle."""

    def __new__(
        cls,
        laws: list[str],
        angles: npt.NDArray[np.float64],
        start: npt.NDArray[np.float64],
        end: npt.NDArray[np.float64],
        points: list[list[tuple[float, float]]],
        degrees: list[int],
        continuity: int,
        advance: float,
    ) -> ProgramKernel: ...
    def eval(
        self, theta: npt.NDArray[np.float64], *, n_threads: int | None = None
    ) -> npt.NDArray[np.float64]: ...
    def eval_with_theta(
        self, theta: npt.NDArray[np.float64], *, n_threads: int | None = None
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
    @property
    def spans(
        self,
    ) -> list[tuple[float, float, list[float], list[float], bool, tuple[float, float] | None]]: ...
    def characteristics(self, i: int) -> list[float]: ...
    @property
    def pieces(self) -> list[tuple[int, float, float, list[float], float, float, float]]: ...
    def plus_second_derivative(self, c: float, continuity: int) -> ProgramKernel: ...

@final
class TwoPeriodKernel:
    """The two-period slider law of seed 003."""

    def __new__(
        cls,
        law1: MotionLaw,
        law2: MotionLaw,
        stroke1: float,
        angle1: float,
        stroke: float,
        angle: float,
    ) -> TwoPeriodKernel: ...
    def eval(
        self,
        alpha: npt.NDArray[np.float64],
        order: int,
        *,
        n_threads: int | None = None,
        out: npt.NDArray[np.float64] | None = None,
    ) -> npt.NDArray[np.float64]: ...

# press

def press_check(
    big_r: float, r: float, d: float, l: float, phi0: float, offset: float
) -> float: ...
def press_criteria_names() -> list[str]: ...
def press_solve(
    designs: npt.NDArray[np.float64],
    alpha: npt.NDArray[np.float64],
    *,
    n_threads: int | None = None,
) -> tuple[
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.bool_],
]: ...
def press_sweep(
    big_r: npt.NDArray[np.float64],
    r: npt.NDArray[np.float64],
    d: npt.NDArray[np.float64],
    l: npt.NDArray[np.float64],
    phi0: npt.NDArray[np.float64],
    rows: npt.NDArray[np.float64],
    status: npt.NDArray[np.uint8],
    *,
    offset: float,
    k_sp: float | None,
    working_stroke: float | None,
    omega: float,
    samples: int,
    n_threads: int | None = None,
) -> None: ...
def pareto_mask(points: npt.NDArray[np.float64]) -> npt.NDArray[np.bool_]: ...

# impact: stops (seed 000). Forces are piecewise linear between samples and held
# after the last one; a repeated time is a jump. Per-case arrays of the batches
# have one entry per row of `forces`. Errors are cyclomech.InputError.

@overload
def duhamel(
    t: npt.NDArray[np.float64],
    force: npt.NDArray[np.float64],
    omega_n: float,
    zeta: float,
    mass: float,
    q0: float,
    v0: float,
    *,
    with_velocity: Literal[False] = False,
) -> npt.NDArray[np.float64]: ...
@overload
def duhamel(
    t: npt.NDArray[np.float64],
    force: npt.NDArray[np.float64],
    omega_n: float,
    zeta: float,
    mass: float,
    q0: float,
    v0: float,
    *,
    with_velocity: Literal[True],
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
@overload
def duhamel(
    t: npt.NDArray[np.float64],
    force: npt.NDArray[np.float64],
    omega_n: float,
    zeta: float,
    mass: float,
    q0: float,
    v0: float,
    *,
    with_velocity: bool = False,
) -> npt.NDArray[np.float64] | tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
def duhamel_batch(
    t: npt.NDArray[np.float64],
    forces: npt.NDArray[np.float64],
    omega_n: npt.NDArray[np.float64],
    zeta: npt.NDArray[np.float64],
    mass: npt.NDArray[np.float64],
    q0: npt.NDArray[np.float64],
    v0: npt.NDArray[np.float64],
    *,
    n_threads: int | None = None,
    out: npt.NDArray[np.float64] | None = None,
) -> npt.NDArray[np.float64]: ...
def first_rebound_batch(
    t: npt.NDArray[np.float64],
    forces: npt.NDArray[np.float64],
    omega_n: npt.NDArray[np.float64],
    zeta: npt.NDArray[np.float64],
    mass: npt.NDArray[np.float64],
    q0: npt.NDArray[np.float64],
    v0: npt.NDArray[np.float64],
    *,
    maximum: bool = False,
    n_threads: int | None = None,
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
def contact_rebound_batch(
    mass: float,
    k_free: float,
    k_stop: float,
    preload: float,
    zeta_free: float,
    zeta_contact: float,
    v0: npt.NDArray[np.float64],
    *,
    n_threads: int | None = None,
) -> npt.NDArray[np.float64]: ...
def contact_response(
    mass: float,
    k_free: float,
    k_stop: float,
    preload: float,
    zeta_free: float,
    zeta_contact: float,
    x0: float,
    v0: float,
    *,
    t_end: float = ...,
    max_rebounds: int = 1000,
    max_events: int = 10000,
) -> dict[str, Any]: ...
def contact_sample(
    mass: float,
    k_free: float,
    k_stop: float,
    preload: float,
    zeta_free: float,
    zeta_contact: float,
    x0: float,
    v0: float,
    times: npt.NDArray[np.float64],
    *,
    max_events: int = 10000,
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...

# Cam follower dynamics (cyclomech.cam._vibration).

__all__ += ["cam_follower_response", "cam_min_tau", "cam_residual_ratio"]

def cam_residual_ratio(
    law: str,
    tau: npt.NDArray[np.float64],
    zeta: float,
    *,
    n_threads: int | None = None,
) -> npt.NDArray[np.float64]: ...
def cam_min_tau(
    law: str,
    ratio_limit: float,
    zeta: float,
    program: ProgramKernel | None = None,
    index: int = 0,
) -> float: ...
def cam_follower_response(
    kinds: list[str],
    angles: list[float],
    strokes: list[float],
    laws: list[str],
    omega: float,
    omega_n: float,
    zeta: float,
    theta: npt.NDArray[np.float64],
    program: ProgramKernel | None = None,
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...

# servo: motor torque and speed of a servo axis, and the sizing batch.

__all__ += [
    "servo_duty",
    "servo_min_angles",
    "servo_rms_angles",
    "servo_size",
    "servo_speed_limit",
]

def servo_duty(
    vel: npt.NDArray[np.float64],
    acc: npt.NDArray[np.float64],
    inertia: float,
    torque: float,
    efficiency: float,
    ratio: float,
    drive_inertia: float,
    omegas: npt.NDArray[np.float64],
    *,
    curves: bool = False,
    n_threads: int | None = None,
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
def servo_min_angles(
    program: ProgramKernel,
    segments: list[int],
    shaft: float,
    inertia: float,
    torque: float,
    efficiency: float,
    ratio: float,
    drive_inertia: float,
    peak_torque: float,
    max_speed: float,
    omegas: npt.NDArray[np.float64],
) -> npt.NDArray[np.float64]: ...
def servo_size(
    vel: npt.NDArray[np.float64],
    acc: npt.NDArray[np.float64],
    inertia: float,
    torque: float,
    efficiency: float,
    ratios: npt.NDArray[np.float64],
    gear_inertia: float,
    motor_inertia: npt.NDArray[np.float64],
    peak_torque: npt.NDArray[np.float64],
    rated_torque: npt.NDArray[np.float64],
    max_speed: npt.NDArray[np.float64],
    omegas: npt.NDArray[np.float64],
    inertia_limit: float,
    *,
    n_threads: int | None = None,
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.int64]]: ...
def servo_speed_limit(
    program: ProgramKernel,
    segments: list[int],
    shaft: float,
    inertia: float,
    torque: float,
    efficiency: float,
    ratio: float,
    drive_inertia: float,
    peak_torque: float,
    max_speed: float,
    rated: float,
    rms: bool,
) -> tuple[float, float, float]: ...
def servo_rms_angles(
    program: ProgramKernel,
    segment: int,
    dwell: int,
    shaft: float,
    inertia: float,
    torque: float,
    efficiency: float,
    ratio: float,
    drive_inertia: float,
    rated: float,
    omegas: npt.NDArray[np.float64],
    *,
    n_threads: int | None = None,
) -> npt.NDArray[np.float64]: ...

# synthesis: path generation

__all__ += ["path_columns", "path_evaluate", "path_points"]

def path_evaluate(
    kind: str,
    params: npt.NDArray[np.float64],
    targets: npt.NDArray[np.float64],
    timing: npt.NDArray[np.float64] | None = None,
    *,
    samples: int = 90,
    refine: int = 40,
    full_turn: bool = True,
    min_transmission: float = 0.0,
    max_ratio: float = ...,
    pivot_box: tuple[float, float, float, float] | list[float] | None = None,
    angles: bool = False,
    n_threads: int | None = None,
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64] | None]: ...
def path_columns() -> tuple[list[str], list[str], float]: ...
def path_points(
    kind: str, row: npt.NDArray[np.float64], angles: npt.NDArray[np.float64]
) -> npt.NDArray[np.float64]: ...

# shaft

__all__ += ["shaft_stats", "shaft_sum"]

def shaft_sum(
    curves: npt.NDArray[np.float64], phase: npt.NDArray[np.float64]
) -> npt.NDArray[np.float64]: ...
def shaft_stats(
    a: npt.NDArray[np.float64],
    b: npt.NDArray[np.float64],
    omegas: npt.NDArray[np.float64],
    delta: float,
    *,
    n_threads: int | None = None,
) -> npt.NDArray[np.float64]: ...

# dynamics: the shaking force of counterweight designs (issue 34, item 4).

__all__ += ["shaking_batch", "shaking_channels"]

def shaking_batch(
    base: npt.NDArray[np.float64],
    lin: npt.NDArray[np.float64],
    nrm: npt.NDArray[np.float64],
    designs: npt.NDArray[np.float64],
    *,
    n_threads: int | None = None,
) -> npt.NDArray[np.float64]: ...
def shaking_channels(
    base: npt.NDArray[np.float64],
    lin: npt.NDArray[np.float64],
    nrm: npt.NDArray[np.float64],
    w: npt.NDArray[np.float64],
) -> npt.NDArray[np.float64]: ...

# forces: kinetostatics of linkages.

@final
class ForceModel:
    """A linkage's force model: bodies by their joints (body_ptr (B+1,) into
    body_points), masses (B,) [kg], centres of mass in their frames (B, 2),
    inertias (B,) [kg·m²]; ground joints; a mass per point (P,); guides
    (guide_idx (G, 4): point, b, c, body; b = -1 for a frame guide along
    guide_dir (G, 2)); the crank's body; gravity (2,) [m/s²]."""

    def __new__(
        cls,
        n_points: int,
        body_ptr: npt.NDArray[np.int64],
        body_points: npt.NDArray[np.int64],
        body_mass: npt.NDArray[np.float64],
        body_com: npt.NDArray[np.float64],
        body_inertia: npt.NDArray[np.float64],
        ground: npt.NDArray[np.int64],
        point_mass: npt.NDArray[np.float64],
        guide_idx: npt.NDArray[np.int64],
        guide_dir: npt.NDArray[np.float64],
        driver: int,
        gravity: npt.NDArray[np.float64],
    ) -> ForceModel: ...
    def pairs(self) -> list[tuple[int, int]]: ...
    def block_sizes(self) -> list[int]: ...
    def width(self, reactions: bool) -> int: ...
    def solve(
        self,
        xy: npt.NDArray[np.float64],
        vel: npt.NDArray[np.float64],
        acc: npt.NDArray[np.float64],
        force: npt.NDArray[np.float64] | None = None,
        torque: npt.NDArray[np.float64] | None = None,
        *,
        reactions: bool = True,
        n_threads: int | None = None,
        out: npt.NDArray[np.float64] | None = None,
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
    def solve_friction(
        self,
        xy: npt.NDArray[np.float64],
        vel: npt.NDArray[np.float64],
        acc: npt.NDArray[np.float64],
        force: npt.NDArray[np.float64] | None,
        torque: npt.NDArray[np.float64] | None,
        omegas: npt.NDArray[np.float64],
        pin_points: npt.NDArray[np.int64],
        pin_mu_r: npt.NDArray[np.float64],
        pin_viscous: npt.NDArray[np.float64],
        guides: npt.NDArray[np.int64],
        guide_mu: npt.NDArray[np.float64],
        guide_viscous: npt.NDArray[np.float64],
        *,
        n_threads: int | None = None,
    ) -> tuple[
        npt.NDArray[np.float64],
        npt.NDArray[np.float64],
        npt.NDArray[np.int64],
        npt.NDArray[np.float64],
    ]: ...

# --- issue 20, machine sweeps: a batch of stop designs (rust/bindings/src/impact.rs) ---
__all__ += ["stop_design_batch"]

def stop_design_batch(
    law: str,
    rise: bool,
    coeffs: npt.NDArray[np.float64] | None,
    pulse: int,
    designs: npt.NDArray[np.float64],
    rpm: npt.NDArray[np.float64],
    *,
    n_threads: int | None = None,
) -> tuple[
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
]: ...

# --- issue 20, machine sweeps: the speed-limit search of many designs with
# speed-proportional bounds (rust/bindings/src/speed_limit.rs) ---
__all__ += ["solve_proportional", "speed_limits_proportional"]

def solve_proportional(
    n_nodes: int,
    src: npt.NDArray[np.int64],
    dst: npt.NDArray[np.int64],
    base: npt.NDArray[np.float64],
    source: int,
    target: int,
    lim_shift: float,
    min_edge: npt.NDArray[np.int64],
    angle: npt.NDArray[np.float64],
    secs: npt.NDArray[np.float64],
    bound_op: npt.NDArray[np.int64],
    per_rpm: npt.NDArray[np.float64],
    rpm: npt.NDArray[np.float64],
    *,
    n_threads: int | None = None,
) -> tuple[
    npt.NDArray[np.float64], npt.NDArray[np.int16], npt.NDArray[np.float64], npt.NDArray[np.bool_]
]: ...
def speed_limits_proportional(
    n_nodes: int,
    src: npt.NDArray[np.int64],
    dst: npt.NDArray[np.int64],
    base: npt.NDArray[np.float64],
    source: int,
    target: int,
    lim_shift: float,
    min_edge: npt.NDArray[np.int64],
    angle: npt.NDArray[np.float64],
    secs: npt.NDArray[np.float64],
    bound_op: npt.NDArray[np.int64],
    per_rpm: npt.NDArray[np.float64],
    start: float,
    floor: float,
    cap: float,
    rtol: float,
    *,
    n_threads: int | None = None,
) -> npt.NDArray[np.float64]: ...

# transfer: rotor transfer (seed 002), cyclomech.transfer's kernels. Errors are
# cyclomech.InputError.

__all__ += [
    "transfer_kinematics",
    "transfer_longest",
    "transfer_peak_jerk",
    "transfer_quintic",
    "transfer_sample",
]

def transfer_quintic(
    coeffs: npt.NDArray[np.float64],
    x: npt.NDArray[np.float64],
    what: str,
    *,
    n_threads: int | None = None,
) -> npt.NDArray[np.float64]: ...
def transfer_sample(
    spec: npt.NDArray[np.float64],
    counts: npt.NDArray[np.int64],
    ccw: bool,
    *,
    n_threads: int | None = None,
    out: tuple[
        npt.NDArray[np.float64],
        npt.NDArray[np.float64],
        npt.NDArray[np.float64],
        npt.NDArray[np.float64],
        npt.NDArray[np.float64],
        npt.NDArray[np.int8],
    ]
    | None = None,
) -> tuple[
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.int8],
]: ...
def transfer_kinematics(
    s: npt.NDArray[np.float64],
    curvature: npt.NDArray[np.float64],
    curvature_rate: npt.NDArray[np.float64],
    law: tuple[float, float, float, float],
    *,
    n_threads: int | None = None,
) -> npt.NDArray[np.float64]: ...
def transfer_peak_jerk(
    radii: tuple[float, float],
    distance: float,
    x2: npt.NDArray[np.float64],
    speed: tuple[float, float],
    n_points: int,
    *,
    n_threads: int | None = None,
) -> npt.NDArray[np.float64]: ...
def transfer_longest(
    radii: tuple[float, float], distance: float, ratio: tuple[float, float]
) -> tuple[float, float] | None: ...

# threads

__all__ += ["THREADS_ENV", "threads"]

THREADS_ENV: str

def threads(n_threads: int | None = None) -> int: ...

# dynamics: the main shaft's steady state and start-up under a motor.

__all__ += [
    "DYNAMICS_STEADY_COLUMNS",
    "DYNAMICS_STEADY_STATUS",
    "dynamics_start_up",
    "dynamics_steady",
    "dynamics_steady_batch",
]

def dynamics_steady(
    j: npt.NDArray[np.float64],
    dj: npt.NDArray[np.float64],
    q: npt.NDArray[np.float64],
    extra: float,
    kinds: npt.NDArray[np.int64],
    params: npt.NDArray[np.float64],
    ratio: npt.NDArray[np.float64],
    efficiency: npt.NDArray[np.float64],
    table_offsets: npt.NDArray[np.int64],
    table_speed: npt.NDArray[np.float64],
    table_torque: npt.NDArray[np.float64],
    *,
    tol: float,
    max_iter: int,
    omega_start: float,
) -> tuple[
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
]: ...
def dynamics_steady_batch(
    j: npt.NDArray[np.float64],
    dj: npt.NDArray[np.float64],
    q: npt.NDArray[np.float64],
    extra: npt.NDArray[np.float64],
    kinds: npt.NDArray[np.int64],
    params: npt.NDArray[np.float64],
    ratio: npt.NDArray[np.float64],
    efficiency: npt.NDArray[np.float64],
    table_offsets: npt.NDArray[np.int64],
    table_speed: npt.NDArray[np.float64],
    table_torque: npt.NDArray[np.float64],
    *,
    tol: float,
    max_iter: int,
    omega_start: float,
    n_threads: int | None = None,
) -> npt.NDArray[np.float64]: ...
def dynamics_start_up(
    j: npt.NDArray[np.float64],
    dj: npt.NDArray[np.float64],
    q: npt.NDArray[np.float64],
    extra: float,
    kinds: npt.NDArray[np.int64],
    params: npt.NDArray[np.float64],
    ratio: npt.NDArray[np.float64],
    efficiency: npt.NDArray[np.float64],
    table_offsets: npt.NDArray[np.int64],
    table_speed: npt.NDArray[np.float64],
    table_torque: npt.NDArray[np.float64],
    steady: npt.NDArray[np.float64],
    *,
    rtol: float,
    settle: float,
    t_max: float,
    max_steps: int,
) -> tuple[
    int,
    float,
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
]: ...

# dynamics: the main shaft's torsion and the working members' dynamic errors.

__all__ += ["TORSION_STATUS", "dynamics_torsion", "dynamics_torsion_sweep"]

TORSION_STATUS: tuple[str, ...]

def dynamics_torsion(
    curves: npt.NDArray[np.float64],
    nodes: npt.NDArray[np.float64],
    members: npt.NDArray[np.float64],
    speed: float,
    kinds: npt.NDArray[np.int64],
    params: npt.NDArray[np.float64],
    ratio: npt.NDArray[np.float64],
    efficiency: npt.NDArray[np.float64],
    table_offsets: npt.NDArray[np.int64],
    table_speed: npt.NDArray[np.float64],
    table_torque: npt.NDArray[np.float64],
    head_inertia: float,
    omega_start: float,
    *,
    tol: float,
    max_cycles: int,
    accuracy: float,
) -> tuple[
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
]: ...
def dynamics_torsion_sweep(
    curves: npt.NDArray[np.float64],
    nodes: npt.NDArray[np.float64],
    members: npt.NDArray[np.float64],
    speeds: npt.NDArray[np.float64],
    *,
    tol: float,
    max_cycles: int,
    accuracy: float,
    n_threads: int | None = None,
) -> npt.NDArray[np.float64]: ...

# synthesis: the four-bar's and slider-crank's checks (synthesis/fourbar.rs).
# A transmission tuple is (True, mu_min, mu_max, theta_at_min, theta_at_max) [rad]
# where it assembles over the range, else (False, theta_break, cos_mu, nan, nan).

__all__ += ["fourbar_grashof", "fourbar_output_angle", "fourbar_transmission"]
__all__ += ["slider_crank_kind", "slider_crank_position", "slider_crank_transmission"]

def fourbar_grashof(a: float, b: float, c: float, d: float) -> tuple[str, bool, bool]: ...
def fourbar_transmission(
    a: float, b: float, c: float, d: float, lo: float, hi: float
) -> tuple[bool, float, float, float, float]: ...
def fourbar_output_angle(
    a: float, b: float, c: float, d: float, theta: list[float], sigma: float
) -> list[float]: ...
def slider_crank_kind(r: float, rod: float, e: float) -> str: ...
def slider_crank_transmission(
    r: float, rod: float, e: float, lo: float, hi: float
) -> tuple[bool, float, float, float, float]: ...
def slider_crank_position(
    r: float, rod: float, e: float, theta: list[float], sigma: float
) -> list[float]: ...

# synthesis: function generation (synthesis/function.rs). kind is "four-bar" or
# "slider-crank"; dims are (a, b, c, d) or (r, l, e, 0) [m].

__all__ += ["chebyshev_points", "function_branches", "function_error", "function_fit"]
__all__ += ["function_generated"]

def chebyshev_points(lo: float, hi: float, n: int) -> list[float]: ...
def function_fit(
    kind: str, x: list[float], y: list[float], ground: float
) -> tuple[tuple[float, float, float], tuple[float, float, float, float], bool, bool]: ...
def function_branches(
    kind: str,
    dims: tuple[float, float, float, float],
    flip_in: bool,
    flip_out: bool,
    x: list[float],
    y: list[float],
) -> list[float]: ...
def function_error(
    kind: str,
    dims: tuple[float, float, float, float],
    flip_in: bool,
    flip_out: bool,
    sigma: float,
    grid: list[float],
    wanted: list[float],
) -> tuple[float, int]: ...
def function_generated(
    kind: str,
    dims: tuple[float, float, float, float],
    flip_in: bool,
    flip_out: bool,
    sigma: float,
    x: list[float],
    near: float,
) -> list[float]: ...

# synthesis: motion generation (synthesis/motion.rs, three poses; synthesis/burmester.rs,
# four and five). A four-bar is (A0, B0, A positions, B positions, (a, b, c, d), crank
# angles [rad], direction, branches, working arc (lo, hi) [rad], transmission tuple as
# above, in order).

__all__ += [
    "burmester_curves",
    "burmester_det",
    "burmester_dyad",
    "burmester_points",
    "motion_fourbar",
    "motion_fourbars",
]

_MotionTuple = tuple[
    tuple[float, float],
    tuple[float, float],
    list[tuple[float, float]],
    list[tuple[float, float]],
    tuple[float, float, float, float],
    list[float],
    float,
    list[float],
    tuple[float, float],
    tuple[bool, float, float, float, float],
    bool,
]

def motion_fourbar(
    poses: list[tuple[float, float, float]],
    uv1: tuple[float, float],
    uv2: tuple[float, float],
) -> _MotionTuple: ...
def motion_fourbars(
    poses: list[tuple[float, float, float]],
    dyads: list[tuple[tuple[float, float], tuple[float, float]]],
    pairs: list[tuple[int, int]],
) -> list[tuple[_MotionTuple | None, str | None]]: ...
def burmester_curves(
    poses: list[tuple[float, float, float]], samples: int
) -> tuple[int, list[list[float]]]: ...
def burmester_dyad(
    poses: list[tuple[float, float, float]], beta: float, sigma: float
) -> tuple[tuple[float, float], tuple[float, float]] | None: ...
def burmester_det(poses: list[tuple[float, float, float]], uv: tuple[float, float]) -> float: ...
def burmester_points(
    poses: list[tuple[float, float, float]],
) -> tuple[list[tuple[tuple[float, float], tuple[float, float], float, float]], bool]: ...

# synthesis: six-bar dwell linkages (synthesis/dwell.rs). params rows are (a, b,
# c, d, u, v, theta_mid); the result's columns are dwell_fields().

__all__ += ["dwell_batch", "dwell_fields", "fit_circle"]

def dwell_batch(
    params: npt.NDArray[np.float64],
    sigma: float,
    span: float,
    swing: float,
    min_mu: float,
    max_ratio: float,
    n_dwell: int,
    n_turn: int,
    *,
    n_threads: int | None = None,
) -> npt.NDArray[np.float64]: ...
def dwell_fields() -> list[str]: ...
def fit_circle(points: list[tuple[float, float]]) -> tuple[float, float, float] | None: ...
