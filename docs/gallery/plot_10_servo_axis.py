"""
A servo axis: sized from a catalogue, its duty and its smallest phase angles
=============================================================================

A 12 kg carriage on a 20 mm ball screw follows a cycloidal stroke of 100 mm out and
back once per machine cycle. Every motor of the (illustrative) catalogue is tried
on every gear ratio at two machine speeds in one call; the smallest motor that
passes every check is drawn over the cycle with its limits. Its smallest phase
angles — what the cyclogram would get as bounds on the two strokes — grow with the
machine's speed.
"""

from pathlib import Path

import cyclomech as cm
import matplotlib.pyplot as plt
import numpy as np
from cyclomech.servo.plot import plot_duty

# The examples folder of a clone: in the working directory or one above it (the
# documentation build runs this script from docs/gallery/).
here = Path.cwd().resolve()
motors = next(
    (
        d / "examples" / "motors.csv"
        for d in (here, *here.parents)
        if (d / "examples" / "motors.csv").exists()
    ),
    None,
)
if motors is None:
    raise SystemExit(
        "this script reads examples/motors.csv of a cyclomech clone: run it from the "
        "clone (or a folder in it), or copy the file from the repository's examples/"
    )

S = cm.motion.Segment
prog = cm.motion.Program(
    [S("cycloidal", 120, end=0.1), S("dwell", 60), S("cycloidal", 120, end=0.0), S("dwell", 60)]
)
ax = cm.servo.ServoAxis(
    prog,
    cm.servo.LinearLoad(mass_kg=12.0, lead_m=0.02, force_n=60.0, efficiency=0.9),
    cm.servo.Gearbox(1.0, efficiency=0.95),
)
best = cm.servo.size(ax, motors, [1.0, 1.5, 2.0, 3.0, 5.0], [60.0, 90.0])
print(f"{best.motor.name} on ratio {best.gearbox.ratio:g}: {best.status}")
duty = ax.duty(90.0, motor=best.motor, gearbox=best.gearbox)
plot_duty(duty, best.motor)

rpm = np.linspace(20, 200, 37)
m = ax.min_phase_angles(rpm, motor=best.motor, gearbox=best.gearbox)
fig, axes = plt.subplots(figsize=(7, 3.5), layout="constrained")
for j, seg in enumerate(m.segments):
    for c, style in zip(range(len(m.criteria)), ("-", "--"), strict=True):
        axes.plot(rpm, m.angle_deg[:, j, c], style, label=f"segment {seg}: {m.criteria[c]}")
axes.axhline(120, color="0.5", lw=0.8)
axes.set_xlabel("machine speed [rpm]")
axes.set_ylabel("smallest phase angle [deg]")
axes.legend(fontsize=8)
axes.grid(True, alpha=0.3)
plt.show()
