"""
The whole machine against speed
===============================

The STB loom example machine: its mechanisms, the rebound at the lifter's stop
and the optimised cyclogram at every speed of a sweep, with the speed limit.
``cyclomech run examples/stb_loom.toml`` writes the same as an HTML report.
"""

import cyclomech as cm
import matplotlib.pyplot as plt
from cyclomech.plot import plot_speed_sweep

m = cm.Machine.example()
limit = m.speed_limit()
print(f"speed limit: {limit.rpm:.1f} rpm")
plot_speed_sweep(m.speed_sweep(), limit_rpm=limit.rpm)
plt.show()
