"""
A disc cam with a translating roller follower
=============================================

A rise-dwell-return-dwell program on the default law, an offset roller follower,
and the exact profile coloured by the pressure angle.
"""

import cyclomech as cm
import matplotlib.pyplot as plt
from cyclomech.plot import plot_cam

S = cm.cam.Segment
cam = cm.cam.Cam(
    [S("rise", 120, 0.02), S("dwell", 60), S("return", 120, 0.02), S("dwell", 60)],
    cm.cam.TranslatingRoller(0.05, 0.01, offset=0.01),  # base radius, roller radius [m]
)
plot_cam(cam, positions_deg=[0, 90])
plt.show()
