"""
A spatial example: a flexible arm spun up under gravity
=======================================================

A flexible aluminium arm (1 m, 20 x 4 mm, four spatial beams) with a 50 g tip mass is
turned about the vertical axis by a driven hinge, 2 rad/s^2 from rest, while gravity
pulls it down. Its weight, switched on at once on an undamped arm, swings the tip down
to twice the static cantilever sag ``q L^4 / (8 EI) + P L^3 / (3 EI)`` and back; the spin
stiffens it a little. The same model as the file ``rotating_arm.dat`` (``flexmbd
example --file rotating_arm.dat``).
"""

# %%
# The model
# ---------
# Spatial nodes have ``(x, y, z)``; rotational nodes are four Euler parameters. The
# hinge about ``z`` joins the fixed rotational node 2 to the arm's root rotation 3, and
# its rotation is prescribed. The arm's beams take their stiffness, mass and section
# inertia from a section and a material.
import os

import matplotlib.pyplot as plt
import numpy as np

import flexmbd as fm
from flexmbd import plot

QUICK = os.environ.get("FLEXMBD_DOCS_QUICK") == "1"
N, LENGTH, TIP = 4, 1.0, 0.05
section, aluminium = fm.Rectangle(0.02, 0.004), fm.Material.from_poisson(70e9, 0.33, 2700.0)

b = fm.ModelBuilder("rotating arm")
b.add_node(1, 0.0, 0.0, 0.0)
points, rotations = [1], [3]
for k in range(1, N + 1):
    b.add_node(2 * k + 2, LENGTH * k / N, 0.0, 0.0)
    points.append(2 * k + 2)
    rotations.append(2 * k + 3)
b.add_spatial_hinge(1, 2, 3, axis=(0, 0, 1))
for k in range(N):   # the 20 mm width along y: the arm bends easily about y, under gravity
    b.add_spatial_beam(k + 2, points[k], rotations[k], points[k + 1], rotations[k + 1],
                       orientation=(0, 1, 0))
    b.set_section(k + 2, section, aluminium).dynamic_deformation(k + 2, 2, 3, 4, 5, 6)
b.add_point_mass(points[-1], TIP)
b.fix(1).fix(2).input_deformation(1, 1, law=fm.Polynomial(0.0, 0.0, 2.0))
b.set_gravity(0.0, 0.0, -9.81)
model = b.build()

# %%
# The spin-up
# -----------
run = fm.simulate(model, np.linspace(0.0, 1.0, 101 if QUICK else 401),
                  method="GeneralizedAlpha")
EI = aluminium.E * 0.02 * 0.004**3 / 12
weight = aluminium.rho * 0.02 * 0.004 * 9.81
sag = weight * LENGTH**4 / (8 * EI) + TIP * 9.81 * LENGTH**3 / (3 * EI)
tip = run["x10.3"]
print(f"lowest tip: {-tip.min() * 1e3:.1f} mm; twice the static sag: {2 * sag * 1e3:.1f} mm")

fig, ax = plt.subplots(figsize=(7, 4))
ax.plot(run.t, tip * 1e3, label="tip height")
ax.axhline(-sag * 1e3, ls="--", color="gray", label="static sag")
ax.axhline(-2 * sag * 1e3, ls=":", color="gray", label="twice the static sag")
ax.set_xlabel("t [s]")
ax.set_ylabel("z of the tip [mm]")
ax.grid(True, alpha=0.3)
ax.legend()
fig.tight_layout()

# %%
anim = plot.animate(run, max_frames=25 if QUICK else 80, window=True, arrows=False,
                    sections=True)
plot.show()   # run as a script: plays it in a window (on a screen)
