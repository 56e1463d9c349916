"""
Where the strips of a cross-spring pivot should cross: Wittrick's optimum
=========================================================================

A cross-spring pivot's rotational stiffness changes with the load it carries along its
axis: tension stiffens it, compression softens it, by an amount that depends on where
its two strips cross. Wittrick (1951) found that strips crossing at ``1/2 - sqrt(5)/6 =
0.1273`` of their length make the stiffness independent of that load. Here
``design.optimize`` finds that point: three pivots alike in one model, one unloaded,
one pulled and one pushed along the axis; the crossing is the one where the pulled and
the pushed pivot turn alike under a moment.
"""

# %%
# The model: three planar pivots side by side, each two strips at +-45 degrees crossing
# at ``crossing`` of their length from the ground, clamped there and joined at the top
# by a rigid stage; the axial load acts through the crossing point (the pivot's axis).
# The strips cross without touching (they lie side by side in depth). The design tests
# take the same model from ``flexmbd.examples.crossing_pivots``; a gallery script shows
# its ModelBuilder code.
import math
import os

import matplotlib.pyplot as plt
import numpy as np

import flexmbd as fm
from flexmbd import design

QUICK = os.environ.get("FLEXMBD_DOCS_QUICK") == "1"
LENGTH, WIDTH, THICKNESS = 0.05, 0.01, 0.2e-3     # strips [m], steel
EI = 210e9 * WIDTH * THICKNESS**3 / 12
LOAD = 0.1 * EI / LENGTH**2                        # a tenth of the strips' Euler scale
WITTRICK = 0.5 - math.sqrt(5) / 6


def pivots(crossing, beams=24):
    b = fm.ModelBuilder("three cross-spring pivots")
    c = math.cos(math.pi / 4)
    for k in range(3):                              # unloaded, pulled, pushed
        base, x0 = 10000 * k, 1.0 * k               # pivot k's numbers and place
        ends = []
        for strip, ux in enumerate((c, -c)):
            first = base + 1000 * (strip + 1)       # the strip's nodes, odd from first + 1
            points = [first + 1 + 2 * j for j in range(beams + 1)]
            for j, node in enumerate(points):
                f = j / beams - crossing
                b.add_node(node, x0 + f * LENGTH * ux, f * LENGTH * c)
            for j in range(beams):
                number = first + j + 1
                b.add_beam(number, points[j], points[j] + 1, points[j + 1], points[j + 1] + 1)
                b.set_mass(number, 7800.0 * WIDTH * THICKNESS)
                b.set_stiffness(number, axial=210e9 * WIDTH * THICKNESS, bending=EI)
                if strip and j == beams - 1:       # the stage closes a loop: released
                    b.release(number, 1, 2, 3)
                else:
                    b.dynamic_deformation(number)
            b.fix(points[0]).fix(points[0] + 1)
            ends.append(points[-1])
        stage = base + 5                            # at the crossing point, on the stage
        b.add_node(stage, x0, 0.0)
        b.add_rigid_beam(base + 1, ends[0], ends[0] + 1, ends[1])
        b.add_hinge(base + 2, ends[0] + 1, ends[1] + 1)   # one rigid stage
        b.add_rigid_beam(base + 3, ends[0], ends[0] + 1, stage)
    loads = {f"x{10000 + 5}.2": LOAD, f"x{20000 + 5}.2": -LOAD}
    return b.build(), fm.RunSettings(load_increment=loads, load_steps=1)


def stage_compliance(k: int, beams=24) -> str:
    """The rotational compliance of pivot ``k``'s stage (its angle is the first strip's
    top rotation) [rad/(N m)]."""
    top = 10000 * k + 1000 + 1 + 2 * beams + 1
    return f"C[{10000 * k + 5},{top}][2,2]"


# %%
# How the pulled and the pushed pivot differ in compliance, along the crossing point,
# for three meshes of the strips: the difference changes sign near Wittrick's point.
meshes = (6, 12) if QUICK else (6, 12, 24)
crossings = np.linspace(0.05, 0.25, 5 if QUICK else 9)
fig, ax = plt.subplots(figsize=(6.5, 4))
for beams in meshes:
    names = [stage_compliance(k, beams) for k in range(3)]
    spread = []
    for crossing in crossings:
        v = design.evaluate(lambda crossing, beams=beams: pivots(crossing, beams),
                            {"crossing": crossing}, names, gradient=False).values
        spread.append((v[names[1]] - v[names[2]]) / v[names[0]])
    ax.plot(crossings, spread, "o-", label=f"{beams} beams per strip")
ax.axhline(0.0, color="k", lw=0.8)
ax.axvline(WITTRICK, color="r", ls="--", label="Wittrick, 0.1273")
ax.set_xlabel("crossing point [share of the strip length from the ground]")
ax.set_ylabel("(C pulled - C pushed) / C unloaded")
ax.legend()
fig.tight_layout()

# %%
# The optimum: the stiffest unloaded pivot whose pulled and pushed twins turn alike (an
# equality on the difference of two outputs), on the finest mesh.
beams = meshes[-1]
names = [stage_compliance(k, beams) for k in range(3)]
found = design.optimize(lambda crossing: pivots(crossing, beams), {"crossing": 0.2},
                        names[0], constraints={f"{names[1]} - {names[2]}": (0.0, 0.0)},
                        bounds={"crossing": (0.05, 0.3)})
print(f"{beams} beams per strip: the strips should cross at {found.x['crossing']:.5f} of "
      f"their length (Wittrick: {WITTRICK:.5f}), found in {found.nfev} analyses")
assert found.success
assert abs(found.x["crossing"] - WITTRICK) < (0.01 if QUICK else 1e-3)
