"""
Frequencies of the flexible rod along a crank revolution
========================================================

The linearized equations of motion about each configuration of a revolution
give the rod's vibration frequencies there. At rest the rod of the
slider-crank is pinned at both ends in every configuration, so its frequencies
are those of a pinned-pinned beam; in motion the inertia terms ``N0`` and
``C0`` change them by a few per cent, symmetrically about the half turn.
"""

# %%
# The model: exercise 4's slider-crank, the rod of four beams whose bending (not their
# elongation) is free, pinned to the crank at A and to the slider at B.
import math
import os

from flexmbd.examples import slider_crank_modes as modes

import flexmbd as fm

QUICK = os.environ.get("FLEXMBD_DOCS_QUICK") == "1"
n, l1, l2, m2, EI = 4, 0.15, 0.30, 0.06676, 12.72
EA = 2e11 * math.pi * 0.003**2

b = fm.ModelBuilder("flexible slider-crank, 4 beams")
b.add_node(1, 0.0, 0.0).add_node(3, l1, 0.0).add_node(5, l1 + l2, 0.0)
b.add_rigid_beam(1, 1, 2, 3)                                  # the crank
points, angles = [3, 7, 9, 11, 5], [4, 8, 10, 12, 6]          # along the rod, A to B
for k in range(1, n):
    b.add_node(points[k], l1 + l2 * k / n, 0.0)
for k in range(n):
    b.add_beam(k + 2, points[k], angles[k], points[k + 1], angles[k + 1])
    b.set_mass(k + 2, m2 / l2).set_stiffness(k + 2, axial=EA, bending=EI)
    b.dynamic_deformation(k + 2, 2, 3)
b.fix(1).fix(5, "y").add_point_mass(5, m2 / 2)
b.input_coordinate(2, law=fm.Polynomial(0.0, 150.0))
model = b.build()
path = modes.motion(model, points=19 if QUICK else 73, simulated=False, omega=modes.OMEGA)
along = fm.modes_along(path, 3, progress=False)
columns = modes.table(along)
print(f"f1 from {along.frequencies[:, 0].min():.5g} to {along.frequencies[:, 0].max():.5g} Hz")

# %%
fig = modes.plot_frequencies(model, columns, window=True)
