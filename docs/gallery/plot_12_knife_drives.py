"""
Seed 001's three knife drives, synthesised for one knife motion and compared
============================================================================

Seed 001 analyses three generalised knife-drive schemes of single-knife cutting
machines: BR-125 (p = 1, a crank and one class III group, structure 1–3), BR-136
(p = 2, a dyad between them, 1–2–3) and BRP-4 (p = 3, two dyads, 1–2–2–3). Which
one should a designer take? :func:`cyclomech.synthesis.knife_drive` dimensions
each for the same required knife motion — the knife point E's stroke along −y
and the crank angle its working stroke takes, from the top to the bottom — by
differential evolution whose whole population is solved in one batch call per
generation; :func:`cyclomech.synthesis.compare_knife_drives` then puts them side
by side: transmission angles, the knife's peak acceleration and jerk, the
driving torque and joint loads by the kinetostatics, and the speed limit.

A machine file asks for the same with ``[mechanism.knife.synthesize]``
(``examples/knife_cutter_synthesized.toml``), and ``cyclomech run`` writes this
comparison into its report. The optimiser here is kept short (``maxiter``) so
that the page builds in seconds; the example's file lets it run longer.
"""

import cyclomech as cm
import matplotlib.pyplot as plt
from cyclomech.synthesis.plot import plot_knife_motion, plot_knife_torque

# A 150 mm stroke in 175° of crank, each scheme's frame at its preset's size;
# transmission angles of at least 30° wherever a dyad or the class III group
# passes force, the longest link at most 25 times the shortest.
req = cm.synthesis.KnifeRequirement(
    stroke_m=0.15, cut_deg=175.0, min_transmission_deg=30.0, popsize=8, maxiter=30, seed=1
)
c = cm.synthesis.compare_knife_drives(req, rpm=45.0, cut_force_n=20000.0)
print(c.table())

# %%
# What each synthesis chose, and why
# ----------------------------------
# Among the candidates that meet the stroke and the timing to their tolerances
# (0.5 mm, 0.5°) the one with the largest least transmission angle wins; every
# margin is reported (≥ 0 where a requirement or constraint holds).
for d in c.drives.values():
    print(d.why())
    print("   margins:", {k: round(v, 4) for k, v in d.margins.items()})

# %%
# The knife's motion
# ------------------
# The same stroke and timing, but not the same law of motion: the schemes with
# more links shape the acceleration differently, and the peak acceleration sets
# the speed limit (it grows with the square of the speed).
plot_knife_motion(c)
plt.show()

# %%
# The driving torque
# ------------------
# With the comparison's mass model (an 80 kg knife holder, 10 kg per metre of
# every other moving link) and a 20 kN cutting force over the working stroke.
plot_knife_torque(c)
plt.show()
