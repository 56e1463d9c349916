"""
A pendulum's period against its amplitude
=========================================

The first model to build: a uniform rigid rod on a pivot, released from rest at an
angle. Its period grows with the amplitude; the exact period of a physical pendulum is
``T = 4 sqrt(I / (m g d)) K(sin(theta0 / 2))`` with ``I = m L^2 / 3``, ``d = L / 2`` and
``K`` the complete elliptic integral of the first kind. flexmbd's period, measured from
the simulated swing, follows it.
"""

# %%
# The model
# ---------
# Node 1 is the pivot, node 3 the rod's end; the rigid beam carries the rod's angle
# at rotational node 2, which is the one degree of freedom.
import os

import matplotlib.pyplot as plt
import numpy as np
from scipy.special import ellipk

import flexmbd as fm

QUICK = os.environ.get("FLEXMBD_DOCS_QUICK") == "1"
L, MASS, G = 0.6, 0.8, 9.81         # [m], [kg], [m/s^2]

b = fm.ModelBuilder("pendulum")
b.add_node(1, 0.0, 0.0)             # the pivot
b.add_node(3, 0.0, -L)              # the rod's end, hanging down
b.add_rigid_beam(1, 1, 2, 3)        # the rod; rotational node 2 is its angle
b.set_mass(1, MASS / L)             # a uniform rod [kg/m]
b.fix(1)                            # the pivot does not move
b.dynamic_coordinate(2)             # the rod swings about it
b.set_gravity(0.0, -G)
model = b.build()
print(model)

# %%
# Swings of growing amplitude
# ---------------------------
# Each swing starts at rest at ``theta0``; the period is twice the time between two
# zero crossings of the angle, interpolated.
amplitudes = np.radians([10, 45, 90, 135] if QUICK else [5, 20, 45, 70, 90, 110, 135, 160])
periods = []
for theta0 in amplitudes:
    times = np.linspace(0.0, 6.0, 3001)
    run = fm.simulate(model, times, initial={"x2.1": (theta0, 0.0)}, rtol=1e-10, atol=1e-12)
    angle = run["x2.1"]
    down = np.flatnonzero(np.sign(angle[:-1]) != np.sign(angle[1:]))[:2]
    crossings = times[down] - angle[down] * (times[down + 1] - times[down]) / (
        angle[down + 1] - angle[down])
    periods.append(2 * (crossings[1] - crossings[0]))
periods = np.array(periods)
exact = 4 * np.sqrt((L**2 / 3) / (G * L / 2)) * ellipk(np.sin(amplitudes / 2) ** 2)
print(f"largest period error: {np.abs(periods / exact - 1).max():.1e}")

# %%
fig, ax = plt.subplots(figsize=(7, 4))
ax.plot(np.degrees(amplitudes), exact, "-", label="exact (elliptic integral)")
ax.plot(np.degrees(amplitudes), periods, "o", label="flexmbd")
ax.set_xlabel("amplitude [deg]")
ax.set_ylabel("period [s]")
ax.grid(True, alpha=0.3)
ax.legend()
fig.tight_layout()
