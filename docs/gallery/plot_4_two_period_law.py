"""
Motion laws and the two-period slider law
=========================================

A dimensionless law inscribed in the unit square, then seed 003's two-period law
of a press slider synthesised from its first complex of data (stroke, angle and
asymmetry): period II accelerates from top dead centre, period I slows down to
the working stroke.
"""

import math

import cyclomech as cm
import matplotlib.pyplot as plt
from cyclomech.plot import plot_law

plot_law(cm.motion.law("modified_sine"))
# Stroke 0.2 m over half a turn; asymmetry f_A = (α2 − α1)/α1 = 2.
law = cm.motion.two_period(0.2, math.pi, "cycloidal", "modified_sine", asymmetry=2.0)
print(f"period I: {math.degrees(law.angle1):.1f} deg, {law.stroke1 * 1e3:.2f} mm")
plot_law(law)
plt.show()
