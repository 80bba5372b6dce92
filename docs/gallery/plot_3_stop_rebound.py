"""
The rebound of a lever at its stop
==================================

Seed 000's microshuttle lifter: the lever reaches its limit plate, strikes it
and vibrates. cyclomech computes the exact Duhamel response to the impact pulse
(first-order hold, no time-stepping error) and the first rebound against the
main-shaft speed for several phase angles of the approach, with the admissible
rebound of 0.1 mm.
"""

import cyclomech as cm
import matplotlib.pyplot as plt
import numpy as np
from cyclomech.plot import plot_rebound_vs_speed, plot_response

lifter = cm.impact.StopImpact.example()
t, q = lifter.response(280, 40.0)  # 280 rpm, 40 deg phase angle
print(f"first rebound at 280 rpm: {q.max() * 1e3:.4f} mm")
plot_response(t, q, rebound=(float(t[q.argmax()]), float(q.max())))
plot_rebound_vs_speed(lifter, np.linspace(200, 450, 51), phase_deg=[30, 40, 50], a_max=0.1e-3)
plt.show()
