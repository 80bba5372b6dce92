"""
Forces in a knife drive
=======================

Seed 001's Burg trimmer (a class III Assur group) with a 50 kg knife at E and
gravity: the kinetostatics give the crank's driving torque and every joint's load
over the turn at 45 rpm.
"""

import cyclomech as cm
import matplotlib.pyplot as plt
import numpy as np
from cyclomech.linkage import presets
from cyclomech.plot import plot_forces

lk = presets.burg_trimmer()
k = cm.forces.kinetostatics(
    lk, np.radians(np.arange(0.0, 360.0, 1.0)), point_masses={"E": 50.0}, gravity=(0, -9.81)
)
torque = k.torque(45.0)
print(f"peak driving torque at 45 rpm: {np.nanmax(np.abs(torque)):.1f} N*m")
plot_forces(k, 45.0)
plt.show()
