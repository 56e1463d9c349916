"""
A flexible double pendulum and its energy
=========================================

The tutorial's model: a rigid rod (1 kg, 0.5 m) on a pivot and, pinned to its end, a
flexible link of four beams (0.5 m, 1 kg/m, ``EI = 20 N m^2``), released horizontal
under gravity. Nothing drives or damps it, so the sum of its kinetic, elastic and
gravitational energy must stay constant: the drift measures the integrator.
"""

# %%
# The model
# ---------
# Odd nodes are points, even ones their rotations. Link 1 has rotational node 2, link 2
# starts with its own rotational node 4 at A: a pin. Beams 2 to 5 share their nodes: one
# flexible link, whose bending is a degree of freedom.
import os

import matplotlib.pyplot as plt
import numpy as np

import flexmbd as fm
from flexmbd import plot

QUICK = os.environ.get("FLEXMBD_DOCS_QUICK") == "1"
L1, L2, N = 0.5, 0.5, 4

b = fm.ModelBuilder("flexible double pendulum")
b.add_node(1, 0.0, 0.0).add_node(3, L1, 0.0)
for k in range(1, N + 1):
    b.add_node(3 + 2 * k, L1 + L2 * k / N, 0.0)
b.add_rigid_beam(1, 1, 2, 3)
for k in range(N):
    b.add_beam(k + 2, 3 + 2 * k, 4 + 2 * k, 5 + 2 * k, 6 + 2 * k)
b.fix(1).dynamic_coordinate(2).dynamic_coordinate(4)
for k in range(N):
    b.dynamic_deformation(k + 2, 2, 3).set_stiffness(k + 2, bending=20.0).set_mass(k + 2, 1.0)
b.set_mass(1, 2.0).set_gravity(0.0, -9.81)
model = b.build()

# %%
# Simulation and energy
# ---------------------
# The implicit generalized-alpha integrator without numerical damping keeps the energy;
# :func:`flexmbd.energy` gives its three parts at every output.
res = fm.simulate(model, np.linspace(0.0, 2.0, 201 if QUICK else 801),
                  method="GeneralizedAlpha")
energy = fm.energy(res)
drift = energy["total"] - energy["total"][0]
print(f"energy drift: {np.abs(drift).max():.1e} J of {energy['kinetic'].max():.2f} J")

fig, ax = plt.subplots(figsize=(7, 4))
for name in ("kinetic", "elastic", "gravity", "total"):
    ax.plot(res.t, energy[name], label=name)
ax.set_xlabel("t [s]")
ax.set_ylabel("energy [J]")
ax.grid(True, alpha=0.3)
ax.legend()
fig.tight_layout()

# %%
# The motion
# ----------
anim = plot.animate(res, max_frames=30 if QUICK else 100, window=True, arrows=False)
plot.show()   # run as a script: plays it in a window (on a screen)
