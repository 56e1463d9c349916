"""
A flexure: the parallel leaf-spring guide
=========================================

Two leaf springs of ``PLBEAM2`` beams carry a stage with a payload. The
linearized analyses give the guide's lateral stiffness, its frequencies and
mode shapes, the payload at which the leaves buckle, and, by static load
steps, the parasitic drop of the stage along its stroke. The example checks
each against the continuous leaves (within 1e-3).
"""

# %%
# The model: two vertical leaves of ``n`` second-order beams (their elongation includes
# the arc length of their bending, so the payload's compression softens them), clamped
# at the bottom and joined at the top by a rigid stage. The stage closes a loop: the
# right leaf's last beam has its three deformations released (its loop's surplus).
import os

import matplotlib.pyplot as plt
from flexmbd.examples import parallel_guide as guide

import flexmbd as fm
from flexmbd import plot

QUICK = os.environ.get("FLEXMBD_DOCS_QUICK") == "1"
n = 4 if QUICK else 8
L, W, E, t, w, rho = 0.05, 0.04, 210e9, 0.5e-3, 0.02, 7850.0    # leaf [m], steel
EI, EA = E * w * t**3 / 12, E * w * t

b = fm.ModelBuilder(f"parallel leaf-spring guide, {n} beams per leaf")
stage_angle = 2 * n + 2                      # the left leaf's top rotation: the stage's
for offset, x in ((0, 0.0), (100, W)):       # the right leaf numbered from 101
    points = [offset + 1 + 2 * k for k in range(n + 1)]
    angles = [offset + 2 + 2 * k for k in range(n)] + [stage_angle]
    for k, node in enumerate(points):
        b.add_node(node, x, L * k / n)
    for k in range(n):
        b.add_beam(offset + k + 1, points[k], angles[k], points[k + 1], angles[k + 1],
                   second_order=True)
        b.set_mass(offset + k + 1, rho * w * t).set_stiffness(offset + k + 1, axial=EA,
                                                              bending=EI)
        if offset and k == n - 1:
            b.release(offset + k + 1, 1, 2, 3)
        else:
            b.dynamic_deformation(offset + k + 1, 1, 2, 3)
    b.fix(points[0]).fix(angles[0])          # clamped at the bottom
    b.add_point_mass(points[-1], 0.1)        # half of the 0.2 kg stage
    b.add_force(points[-1], 0.0, -25.0)      # half of the 50 N payload
b.add_rigid_beam(200, 2 * n + 1, stage_angle, 100 + 2 * n + 1)   # the stage
model = b.build()
found = guide.analyse(model)
print(f"lateral stiffness {found['stiffness']:.5g} N/m, "
      f"first frequency {found['modes'].frequencies[0]:.5g} Hz, "
      f"buckling at {found['buckling'].factors[0]:.4g} times the payload")

# %%
# The stroke: lateral motion and drop of the stage per load step
lateral, drop = guide.stage_motion(found["statics"])
fig, ax = plt.subplots(figsize=(6, 4))
ax.plot(1e3 * lateral, 1e6 * drop, "o-")
ax.set_xlabel("lateral stroke [mm]")
ax.set_ylabel("parasitic drop [um]")
ax.grid(True, alpha=0.3)
fig.tight_layout()

# %%
# The first mode shapes on the guide
lin = found["statics"].linearization(0)
shapes = fm.vibration_modes(lin, 3)
fig = plot.plot_shapes(model, lin.x, shapes.motion,
                       [f"{f:.4g} Hz" for f in shapes.frequencies], window=True)
