"""
A curvature-continuous transfer between two rotors
==================================================

Seed 002: a workpiece leaving a transport rotor for a process rotor meets a jump
in acceleration where the pitch circles touch. A quintic transition with
continuous curvature from each circle to the common tangent line removes the
jump; the figure shows the path, its curvature, and the acceleration and jerk
at a transport speed.
"""

import cyclomech as cm
import matplotlib.pyplot as plt
from cyclomech.plot import plot_transfer

path = cm.transfer.TransferPath(0.15, 0.25, (0, 0), (0.41, 0), x2=0.05)  # radii, centres [m]
print(
    f"acceleration jump without a transition at 0.157 m/s: "
    f"{cm.transfer.acceleration_jump_at_speed(0.157, 0.15, 0.25):.4f} m/s^2"
)
plot_transfer(path, speed=0.157)
plt.show()
