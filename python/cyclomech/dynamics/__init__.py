"""Machine dynamics (issue 34).

Shaking force and moment and balancing (item 4): the force and moment a linkage,
and the whole machine with its mechanisms phased by the cyclogram, puts on the
frame over the cycle (:func:`shaking`, :class:`Shaking`), and counterweights on
the links pivoted to the frame that minimise it (:func:`balance`,
:class:`Balance`, :class:`Counterweight`).

**Shaking.** The shaking force is the inertia force the moving parts put on the
frame, −Σ mᵢ·a_Gᵢ, and the shaking moment −dH/dt about a point (the driving
torque's reaction on the motor included); both are ω²·(part 0) + ε·(part 1) at
crank speed ω and acceleration ε, taken from the kinetostatics' frame reactions
(ground joints and frame guides). Gravity and the working loads are not part of
them: they form the static part, which :meth:`Shaking.frame_force` adds (what
the frame's bearings and guides carry). See ``_shaking`` for the equations.

**Balancing.** A counterweight on a link pivoted to the frame is the vector
(m r cos α, m r sin α) [kg·m] in the link's frame, a point mass at a radius r:
the shaking force is linear in these vectors, so the least RMS force is one
least-squares solve; the peak force and SAM's RMS force + weight × RMS torque go
through scipy's optimisers over the Rust batch of designs. See ``_balance``.

Units: SI (N, N·m, kg, m); speeds in rpm where named so; angles of results in
degrees.

>>> import numpy as np, cyclomech as cm
>>> crank = cm.Linkage({"O": (0, 0), "A": (0.1, 0)}, [("O", "A")], ["O"], ("O", "A"))
>>> k = cm.forces.kinetostatics(crank, np.radians(np.arange(0.0, 360.0, 10.0)),
...                             point_masses={"A": 2.0})
>>> round(cm.dynamics.shaking(k).stats(600.0)["rms_force_n"], 3)   # m r ω²
789.568
>>> round(cm.dynamics.balance(k, counterweights=[("O", "A")], rpm=600.0).after["peak_force_n"], 9)
0.0

The code lives in private modules beside this door: ``_shaking``
(:func:`shaking`) and ``_balance`` (:func:`balance`); plots in
:mod:`cyclomech.dynamics.plot`.
"""

from __future__ import annotations

from ._balance import OBJECTIVES, Balance, Counterweight, balance
from ._shaking import Shaking, shaking

__all__ = [
    "OBJECTIVES",
    "Balance",
    "Counterweight",
    "Shaking",
    "balance",
    "shaking",
]
