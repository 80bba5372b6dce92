"""
A cyclogram optimised by LP
===========================

Group 1 of the STB loom as a network cyclogram: events, operations with their
minimum phase angles, the time-bound weft insertion and the seed's linearised
rebound constraint. The LP gives the limiting operation the largest part of the
cycle; the speed limit is the fastest speed at which the cycle still fits.
"""

import cyclomech as cm
import matplotlib.pyplot as plt
from cyclomech.plot import plot_cyclogram

cg = cm.Cyclogram("group 1", limiting=("10.1", "10.2"))
cg.add_operation("1", "3", min_angle_deg=45, name="lift", mechanism="lifter")
cg.add_operation("3", "7", min_angle_deg=20, name="approach stop", mechanism="lifter")
cg.add_operation("7", "10.1", min_angle_deg=20, mechanism="lifter")
cg.add_operation(
    "10.1", "10.2", min_angle_deg=120, min_duration_s=0.1, name="weft insertion", mechanism="weft"
)
cg.add_constraint({("3", "7"): -0.003}, "<=", 0.1 - 0.208, name="rebound")

o = cg.optimize(speed_rpm=300)
print(f"approach: {o.angles[('3', '7')]:.1f} deg; rebound's shadow price {o.duals['rebound']:.1f}")
print(f"speed limit: {cg.max_speed_rpm().rpm:.1f} rpm")
plot_cyclogram(o)
plt.show()
