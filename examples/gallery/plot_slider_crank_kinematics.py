"""
Slider-crank kinematics against the closed form (exercise 2)
============================================================

Two rigid beams, the crank O-A (``l1 = 1`` m) and the rod A-B
(``l2 = sqrt(3)`` m), and a slider at B. The crank angle is the input; the four
dependent coordinates follow from the four rigid deformations. The crank
starts at 1 revolution per second and accelerates at ``2 pi`` rad/s^2. The
slider's position, velocity and acceleration over the first second are
compared with the closed form ``x_B = l1 cos(phi) + sqrt(l2^2 - l1^2 sin^2(phi))``
and its derivatives.
"""

# %%
# The model: node 1 (O) fixed, the crank to node 3 (A) with its angle at rotational
# node 2 as the input, the rod to node 5 (B), which keeps ``y = 0``.
import math
import os

import matplotlib.pyplot as plt
import numpy as np
from flexmbd.examples import slider_crank_kinematics as kin

import flexmbd as fm

QUICK = os.environ.get("FLEXMBD_DOCS_QUICK") == "1"
l1, l2 = 1.0, math.sqrt(3.0)                           # crank and rod [m]

b = fm.ModelBuilder("slider-crank")
b.add_node(1, 0.0, 0.0).add_node(3, l1, 0.0).add_node(5, l1 + l2, 0.0)
b.add_rigid_beam(1, 1, 2, 3)                           # crank O-A
b.add_rigid_beam(2, 3, 4, 5)                           # rod A-B, pinned at A
b.fix(1).fix(5, "y")                                   # pivot O; slider B on the x axis
b.input_coordinate(2, law=fm.Polynomial(0.0, 2 * math.pi, 2 * math.pi))  # phi(t)
model = b.build()
times = np.linspace(0.0, 1.0, 73 if QUICK else 361)
result = fm.kinematic_analysis(model, times)
phi = result["x2.1"]
closed = kin.closed_form(phi)

# %%
# ``closed_form`` returns, per coordinate, the position and its first and
# second derivatives with respect to the crank angle; with ``phi(t)`` they
# become the velocity and acceleration.
rate, acceleration = result["xd2.1"], result["xdd2.1"]
x5, dx5, ddx5 = closed["x5.1"]
fig, axes = plt.subplots(3, 1, sharex=True, figsize=(7, 7))
for ax, name, exact, unit in zip(
        axes, ("x5.1", "xd5.1", "xdd5.1"),
        (x5, dx5 * rate, ddx5 * rate**2 + dx5 * acceleration), ("m", "m/s", "m/s^2"),
        strict=True):
    ax.plot(np.degrees(phi), result[name], label="flexmbd")
    ax.plot(np.degrees(phi), exact, "--", label="closed form")
    ax.set_ylabel(f"{name} [{unit}]")
    ax.grid(True, alpha=0.3)
    print(f"{name}: largest difference {np.abs(result[name] - exact).max():.1e} {unit}")
axes[0].legend()
axes[-1].set_xlabel("crank angle [deg]")
fig.tight_layout()
