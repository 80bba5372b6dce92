"""
A motion program on a cam: a flying knife matched to the web
============================================================

A cam drives a knife carriage that must move with the web while it cuts: a
cycloidal start from rest up to the web's speed, a constant-velocity cut, a
modified-sine stop and a poly5 return (VDI 2143 segments with ends in motion).
The cam follows the program exactly; its SVAJ diagram at 120 rpm shows the
matched velocity over the cut. Below it, a polydyne cam: at its design speed the
elastic follower's output follows its program, off design it does not.
"""

import math

import cyclomech as cm
import matplotlib.pyplot as plt
import numpy as np
from cyclomech.cam.plot import plot_svaj

S = cm.motion.Segment
web = 0.04  # m of web per radian of cam
prog = cm.motion.Program(
    [
        S("cycloidal", 70, end=(0.025, web)),
        S("constant_velocity", 60),
        S("modified_sine", 50, end=0.025 + web * math.pi / 3 + 0.018),
        S("dwell", 40),
        S("poly5", 140, end=0.0),
    ]
)
for i, c in enumerate(prog.characteristics):
    print(f"segment {i} ({prog.segments[i].law}): stroke {c.stroke * 1e3:.2f} mm, C_v {c.cv:.3f}")
cam = cm.cam.Cam(prog, cm.cam.TranslatingRoller(0.09, 0.02))
plot_svaj(cam, rpm=120.0, title="flying knife: a velocity-matched cut")

# A polydyne cam for 900 rpm; the member's residual vibration over speed.
y = cm.motion.Program(
    [S("poly7", 100, end=0.012), S("dwell", 60), S("poly7", 100, end=0.0), S("dwell", 100)],
    continuity="jerk",
)
fn = 110.0  # Hz
mass = 0.6  # kg
pd = cm.cam.Cam(
    cm.cam.polydyne(y, follower_mass=mass, stiffness=mass * (2 * math.pi * fn) ** 2, rpm=900),
    cm.cam.TranslatingRoller(0.05, 0.012),
)
plain = cm.cam.Cam(y, cm.cam.TranslatingRoller(0.05, 0.012))
rpm = np.linspace(600, 1200, 121)
rpm = rpm[np.abs(fn * 60 / rpm - np.round(fn * 60 / rpm)) > 0.02]  # off the resonances
fig, ax = plt.subplots(figsize=(7, 3.5))
for cam_, label in ((plain, "cam = program"), (pd, "polydyne for 900 rpm")):
    r = [cm.cam.follower_response(cam_, n, fn, 0.0).residual.max() * 1e6 for n in rpm]
    ax.semilogy(rpm, np.maximum(r, 1e-6), ".-", label=label)
ax.set_xlabel("cam speed [rpm]")
ax.set_ylabel("largest residual vibration [µm]")
ax.legend()
ax.grid(True, which="both", alpha=0.3)
plt.show()
