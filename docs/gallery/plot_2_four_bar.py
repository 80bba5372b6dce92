"""
A four-bar linkage over one turn
================================

A crank-rocker solved at 3601 crank angles by its Assur groups (the crank, then
one RRR dyad in closed form): positions, velocity and acceleration analogs of
every joint in one call. The figure shows the drawn mechanism with the coupler
point's path, then the rocker's analogs.
"""

import cyclomech as cm
import matplotlib.pyplot as plt
import numpy as np
from cyclomech.plot import plot_analogs, plot_linkage

lk = cm.Linkage(
    points={"A": (0, 0), "B": (1, 0), "C": (3.5, 2.5), "D": (4, 0)},  # drawn pose [m]
    links=[("A", "B"), ("B", "C"), ("C", "D")],
    ground=["A", "D"],
    driver=("A", "B"),
    name="crank-rocker",
)
print(lk.structure)  # the crank, then one class II group
sol = lk.solve(np.linspace(0, 2 * np.pi, 3601))  # absolute crank angles [rad]
theta, dtheta, ddtheta = sol.link_angle("C", "D")
print(f"rocker swing: {np.degrees(np.ptp(theta)):.2f} deg, assembled everywhere: {sol.ok.all()}")

plot_linkage(lk, sol, 300, trace=["C"])
plot_analogs(sol, "C")
plt.show()
