"""
A flexure: a cross-spring pivot turned in load steps
====================================================

Two steel leaves (0.1 m, 30 x 0.5 mm) cross at their middles at 90 degrees, side by
side along the pivot axis ``y``, clamped below and joined above by a rigid stage. A
moment about the axis turns the stage to 0.3 rad in 20 load steps; at every step the
equilibrium gives the stiffness about the axis and the linearization the lowest
frequency with the stage's mass. The small-angle stiffness is ``2 EI / L``.
"""

# %%
# The model
# ---------
# ``add_spatial_beams`` chains a leaf of ``n`` beams with new intermediate nodes;
# ``set_section`` comes with it. The stage is two rigid beams from the leaves' tops to
# its centre, where its mass sits. The stage over-constrains the leaves six times:
# ``release_overconstraints`` releases six deformations as SPACAR Light does.
import math
import os

import matplotlib.pyplot as plt
import numpy as np

import flexmbd as fm

QUICK = os.environ.get("FLEXMBD_DOCS_QUICK") == "1"
L, GAP, BEAMS = 0.1, 0.04, 4 if QUICK else 8
steel, leaf = fm.Material.from_poisson(210e9, 0.3, 7800.0), fm.Rectangle(0.03, 0.5e-3)
h = L / math.sqrt(2)

b = fm.ModelBuilder("cross-spring pivot")
b.add_node(1, -h / 2, 0, 0).add_node(3, h / 2, 0, h)          # leaf 1, bottom to top
b.add_node(5, h / 2, GAP, 0).add_node(7, -h / 2, GAP, h)      # leaf 2
b.add_spatial_beams(1, 1, 2, 3, 4, BEAMS, (0, 1, 0), new_nodes=1000, section=leaf,
                    material=steel)
b.add_spatial_beams(201, 5, 6, 7, 8, BEAMS, (0, 1, 0), new_nodes=2000, section=leaf,
                    material=steel)
b.add_node(9, 0, GAP / 2, h)                                   # the stage's centre
b.add_spatial_beam(401, 3, 4, 9, 10, (0, 0, 1)).add_spatial_beam(402, 9, 10, 7, 8, (0, 0, 1))
b.fix(1).fix(2).fix(5).fix(6)                                  # clamped below
b.add_point_mass(9, 0.25).add_rotary_inertia(10, 1e-4, 0, 0, 1e-4, 0, 1e-4)
print("released:", b.release_overconstraints())
model = b.build()

# %%
# Load steps
# ----------
# The moment's load ``x10.3`` is the y component of a global moment on the stage's
# rotational node 10. Its rotation angle is ``2 asin(lam2)``.
EI = steel.E * 0.03 * 0.5e-3**3 / 12
moment = 0.3 * 2 * EI / L
statics = fm.static_equilibrium(model, load_increment={"x10.3": moment}, steps=20)
table = fm.load_step_table(statics, modes=1)
angle = 2 * np.arcsin(statics["x10.3"])
stiffness = table["load"][1:] * moment / angle[1:]
print(f"stiffness at the first step: {stiffness[0] / (2 * EI / L):.5f} x 2EI/L")

fig, (left, right) = plt.subplots(1, 2, figsize=(9, 3.5))
left.plot(np.degrees(angle[1:]), stiffness / (2 * EI / L), "o-")
left.set_xlabel("stage rotation [deg]")
left.set_ylabel("M / theta over 2EI/L")
right.plot(np.degrees(angle), table["f1"], "o-")
right.set_xlabel("stage rotation [deg]")
right.set_ylabel("lowest frequency [Hz]")
for ax in (left, right):
    ax.grid(True, alpha=0.3)
fig.tight_layout()
