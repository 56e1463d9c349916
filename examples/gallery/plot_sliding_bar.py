"""
Sliding bar: positions, velocities and accelerations (exercise 1)
=================================================================

A bar of length ``l0 = 2`` m slides with end p on the x axis and end q on the
y axis. As a truss whose end p is driven at 4 m/s, its one dependent coordinate
``y_q`` follows from the constraint that the truss keeps its length. flexmbd
solves it by Newton-Raphson at every output time, and the velocity and
acceleration from the transfer functions; all three are compared with the
closed form ``y_q = sqrt(l0^2 - x_p^2)``.
"""

# %%
# The model and the motion
# ------------------------
# Node 1 (p) on the x axis and node 2 (q) on the y axis, drawn at 30 degrees, joined
# by a truss; p keeps ``y = 0`` and q ``x = 0``, and ``x_p = -l0 + 4 t`` is the input.
# The motion runs over the quarter turn, stopping just short of the positions where
# the bar lies along an axis and ``y_q`` is no longer determined.
import math
import os

import matplotlib.pyplot as plt
import numpy as np

import flexmbd as fm
from flexmbd import plot

# the documentation's quick build (FLEXMBD_DOCS_QUICK=1) draws fewer points and frames
QUICK = os.environ.get("FLEXMBD_DOCS_QUICK") == "1"
l0, v = 2.0, 4.0                     # bar length [m], speed of p [m/s]

b = fm.ModelBuilder("sliding bar (truss)")
b.add_node(1, -l0 * math.cos(math.radians(30)), 0.0)     # p
b.add_node(2, 0.0, l0 * math.sin(math.radians(30)))      # q
b.add_truss(1, 1, 2)                                      # keeps its length
b.fix(1, "y").fix(2, "x")                                 # p slides along x, q along y
b.input_coordinate(1, "x", law=fm.Polynomial(-l0, v))     # x_p = -l0 + v t
model = b.build()

result = fm.kinematic_analysis(model, np.linspace(0.005, 0.995 * 2 * l0 / v,
                                                  60 if QUICK else 200))
x_p, y_q = result["x1.1"], result["x2.2"]
exact = np.sqrt(l0**2 - x_p**2)
print(f"largest |y_q - sqrt(l0^2 - x_p^2)|: {np.abs(y_q - exact).max():.1e} m")

# %%
# Against the closed form
# -----------------------
# Differentiating ``y_q = sqrt(l0^2 - x_p^2)`` gives ``ydot_q = -x_p v / y_q`` and
# ``yddot_q = -(v^2 + ydot_q^2) / y_q``. Near the ends both grow without bound.
fig, axes = plt.subplots(3, 1, sharex=True, figsize=(7, 7))
exact_rate = -x_p * v / exact
exact_acc = -(v**2 + exact_rate**2) / exact
for ax, name, closed, unit in zip(axes, ("x2.2", "xd2.2", "xdd2.2"),
                                  (exact, exact_rate, exact_acc), ("m", "m/s", "m/s^2"),
                                  strict=True):
    ax.plot(result.t, result[name], label=f"flexmbd {name}")
    ax.plot(result.t, closed, "--", label="closed form")
    ax.set_ylabel(f"{name} [{unit}]")
    ax.legend(fontsize="small")
    ax.grid(True, alpha=0.3)
axes[1].set_ylim(-40, 40)
axes[2].set_ylim(-400, 50)
axes[-1].set_xlabel("t [s]")
fig.tight_layout()

# %%
# The moving bar
# --------------
# :func:`flexmbd.plot.animate` draws the bar with blue velocity and red
# acceleration arrows at its ends.
anim = plot.animate(result, max_frames=20 if QUICK else 60, window=True)
plot.show()   # run as a script: plays it in a window (on a screen)
