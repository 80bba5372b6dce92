"""Planar linkages: position analysis over crank-angle grids by Assur groups (seed 001).

A linkage is given as a drawn, assembled pose: points with coordinates [m], rigid
links by their joints, the ground joints and the driving crank. The pose fixes the
link dimensions and the assembly mode. :class:`Linkage` decomposes the topology
into Assur groups in solving order and compiles them for the Rust kernel, which
solves every crank angle with positions, velocity analogs d xy/dφ [m/rad] and
acceleration analogs d²xy/dφ² [m/rad²], exactly (no finite differences).

Class II groups are solved in closed form: the RRR dyad and a further joint of a
rigid body (a coupler point) as two circles, the RRP dyad (a slider on a guide, the
slider-crank) as circle and line, the PRP dyad as two lines, and the RPR dyad (a
link turning about a pivot whose line passes through a sliding block, the
inverted slider-crank) by aiming the link at the block. Class III groups (a
ternary link held by three binary links, the knife drives of seed 001) are
solved by Newton continuation from the drawn pose with the seed's bracketing as
the fallback. :func:`solve_geometries` solves K geometries of one linkage over one
crank-angle grid in one call.

A linkage file (``cyclomech linkage FILE.toml``) is read by
:meth:`Linkage.from_toml`; ``cyclomech.linkage.presets`` holds the seed's knife
drives.
"""

from __future__ import annotations

from . import presets
from ._file import DYNAMICS_KEYS
from ._geometries import solve_geometries
from ._kind import LinkageMechanism
from ._linkage import Linkage
from ._solution import LinkageSolution
from ._synthesize import SYNTHESIZERS, register_synthesizer

__all__ = [
    "DYNAMICS_KEYS",
    "SYNTHESIZERS",
    "Linkage",
    "LinkageMechanism",
    "LinkageSolution",
    "presets",
    "register_synthesizer",
    "solve_geometries",
]
