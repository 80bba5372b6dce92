"""
The knife cutter's dynamics: its motor, its elastic shaft, its frame and its friction
=====================================================================================

The single-knife paper cutter (``examples/knife_cutter.toml``) as a whole machine
with its drive: an induction motor through a gear turns the main shaft, which is a
steel shaft (not rigid) to the knife drive's crank; the knife sits on its linkage's
elasticity; counterweights balance the linkage on the frame; and every joint has
friction. One call, :func:`cyclomech.machine.analyze`, gives all of it; this example
shows each part in turn. ``cyclomech run examples/knife_cutter.toml`` writes the
same as an HTML report.
"""

import math
from pathlib import Path

import cyclomech as cm
import matplotlib.pyplot as plt
import numpy as np

# The examples folder of a clone: in the working directory or one above it (the
# documentation build runs this script from docs/gallery/).
here = Path.cwd().resolve()
cutter = next(
    (
        d / "examples" / "knife_cutter.toml"
        for d in (here, *here.parents)
        if (d / "examples" / "knife_cutter.toml").exists()
    ),
    None,
)
if cutter is None:
    raise SystemExit(
        "this script reads examples/knife_cutter.toml of a cyclomech clone: run it from the "
        "clone (or a folder in it), or copy the file from the repository's examples/"
    )
r = cm.machine.analyze(cm.Machine.from_toml(cutter), progress=False)
print(f"nominal speed {r.nominal_rpm:g} rpm; speed limit {r.limit.rpm:.2f} rpm ({r.limit.by})")

# %%
# The main shaft's real speed under its motor
# -------------------------------------------
# The knife drive, reduced to the main shaft, has an inertia J(φ) that changes
# with the crank angle φ and a load torque Q(φ) with the cut's peak. The shaft's
# equation of motion, J·φ̈ + ½·J′·φ̇² = M(φ̇) − Q(φ), with M the motor's torque
# through the gear (falling as the speed rises: the induction motor's slip),
# has a periodic steady state; its real coefficient of speed fluctuation
# δ = (ω_max − ω_min)/ω_mean depends on the flywheel. The flywheel is sized so
# that δ meets ``[machine] speed_fluctuation`` by simulating that steady state,
# beside the classical energy method J = ΔE/(ω²·δ) (which takes the speed as
# constant in the load's work and the motor as ideal).
d = r.dynamics
s, f = d.steady, d.sizing
print(
    f"real δ = {s.speed_fluctuation:.4f} (target {d.target_speed_fluctuation:g}) at a mean "
    f"{s.mean_rpm:.2f} rpm"
)
print(
    f"flywheel: {f.flywheel_kg_m2:.0f} kg·m² by simulation, {f.energy_method_kg_m2:.0f} kg·m² by "
    f"the energy method ({100 * f.difference:+.1f} %)"
)
print(f"start-up from rest under load: {d.start}")
d.figure()
plt.show()

# %%
# The knife's dynamic error and the shaft's twist
# -----------------------------------------------
# The main shaft twists under the load between the motor's end and the crank
# (stiffness c: the crank lags behind the motor's end by θ, with
# (J + H)·φ̈ + ½·J′·φ̇² = c·θ + d·θ̇ − Q at the crank, H its hub), and the knife
# rides on its linkage's elasticity as one mass on a spring of 40 Hz:
# ü + 2ζω_n·u̇ + ω_n²·u = −d²Π/dt², Π(φ) the knife's rigid position. The dynamic
# error is where the knife is minus where the rigid machine puts it at the same
# motor angle, e = Π(φ − θ) + u − Π(φ): the lag and the vibration together. It
# grows with the speed (the twist with the inertia torques, the vibration with
# the acceleration): the speed at which its peak reaches the bound
# ``max_error_m`` limits the machine as the knife's acceleration does.
t = r.torsion
bound = t.bounds()["knife"]
print(
    f"knife: peak dynamic error {1e3 * t.nominal.peak_error['knife']:.3f} mm under the motor "
    f"at {t.nominal.mean_rpm:.2f} rpm (bound {1e3 * bound:g} mm); peak twist "
    f"{math.degrees(np.abs(t.nominal.twist_rad).max()):.3f}°"
)
t.figure()
plt.show()

# %%
# Within the machine's speed range (``speed_rpm``) the error stays under its bound
# (``r.torsion.limits_rpm`` is inf). The same chain at constant head speeds over a
# wider range, in one parallel call, shows where it reaches it:
rpm = np.linspace(20.0, 400.0, 39)
sweep = cm.dynamics.torsion_sweep(t.nodes, rpm)
limit = sweep.limit_rpm("knife", bound)
print(f"the knife's error reaches {1e3 * bound:g} mm at {limit:.1f} rpm")
fig, ax = plt.subplots(figsize=(7, 3.5), layout="constrained")
ax.plot(rpm, 1e3 * sweep.peak_error[:, 0], label="knife: peak dynamic error")
ax.axhline(1e3 * bound, color="C3", lw=0.8, label="max_error_m")
ax.axvline(limit, color="0.5", ls="--", lw=0.8, label=f"{limit:.0f} rpm")
ax.axvspan(t.sweep.rpm[0], t.sweep.rpm[-1], color="0.9", lw=0, label="the machine's speed range")
ax.set_xlabel("main shaft speed [rpm]")
ax.set_ylabel("peak error [mm]")
ax.legend(fontsize=8)
ax.grid(True, alpha=0.3)
plt.show()

# %%
# The shaking force before and after the counterweights
# -----------------------------------------------------
# The moving links' inertia forces, −Σ m·a_G over the links, reach the frame
# through the fixed pivots as the shaking force (and moment). A counterweight on a
# link pivoted to the frame moves its centre of mass; the ``[[balance]]`` row
# chooses each one's mass·radius and angle for the least RMS shaking force over
# the cycle. With one on each of the three links pivoted to the frame the knife
# drive's centre of mass stays put: the force vanishes (to rounding), the moment
# does not (the counterweights add inertia), and the crank needs a little more
# torque. The first figure is the machine's shaking at the nominal speed as the
# file builds it (no counterweights), the second the knife drive's before and
# after.
bal = r.shaking.balances["knife"]
for key, what in (("rms_force_n", "RMS force [N]"), ("rms_moment_nm", "RMS moment [N·m]")):
    print(f"{what}: {bal.before[key]:.4g} before, {bal.after[key]:.4g} after the counterweights")
for c in bal.counterweights:
    print(
        f"  counterweight on {c.link}: m·r = {c.mass_radius_kg_m:.3f} kg·m at "
        f"{c.angle_deg:.1f}° from {c.pivot}→{c.towards} ({c.mass_kg:.1f} kg at {c.radius_m:.3f} m)"
    )
r.shaking.figure()
r.shaking.balance_figures()
plt.show()

# %%
# Efficiency: what friction costs
# -------------------------------
# Each joint's friction moment is μ·r·R (μ the friction coefficient, r the pin's
# radius, R the size of the joint's reaction), solved together with the reactions
# (each depends on the others). The knife drive's efficiency over the cycle is its
# output work over its input work, 1 − (friction work)/(input work); the motor's
# torque on the crank rises by what friction takes (left), mostly in the crank's
# main bearing O and the joint F where the crank drives the rod (right).
knife = r.mechanisms["knife"]
e = knife.efficiency()
print(
    f"knife drive: efficiency {e['cycle_efficiency']:.3f} over the cycle, "
    f"{e['mean_friction_power_w']:.0f} W lost of {e['mean_input_power_w']:.0f} W; peak torque "
    f"{e['peak_torque_nm']:.0f} N·m with friction, {e['peak_torque_nm_without']:.0f} without"
)
losses = e["friction_power_by_element_w"]
crank_deg = np.degrees(knife.friction.angles)
fig, (left, right) = plt.subplots(1, 2, figsize=(9, 3.5), layout="constrained")
left.plot(crank_deg, knife.kinetostatics.torque(r.nominal_rpm), "--", label="without friction")
left.plot(crank_deg, knife.friction.torque[0], label="with friction")
left.set_xlabel("crank angle [deg]")
left.set_ylabel("driving torque on the crank [N·m]")
left.legend(fontsize=8)
left.grid(True, alpha=0.3)
right.bar(list(losses), [v or 0.0 for v in losses.values()])
right.set_xlabel("joint")
right.set_ylabel("mean friction power [W]")
right.set_title("where it is lost", fontsize=9)
plt.show()
