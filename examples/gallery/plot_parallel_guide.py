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
import os

import matplotlib.pyplot as plt
from flexmbd.examples import parallel_guide as guide

import flexmbd as fm
from flexmbd import plot

QUICK = os.environ.get("FLEXMBD_DOCS_QUICK") == "1"

model = guide.build_model(4 if QUICK else guide.NBEAMS)
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
