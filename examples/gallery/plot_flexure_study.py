"""
Designing a parallel guide: support stiffness and stress against stroke and thickness
=====================================================================================

A parallel leaf-spring guide (two steel leaves, 50 mm long and 20 mm wide, a rigid
stage) loses support stiffness along its leaves as it is driven along its stroke, and
its leaves' stress grows with the stroke and the thickness. A designer weighs the two.
:func:`flexmbd.sweep` runs one case per stroke and thickness, each a static analysis
in load steps through SPACAR Light's front door (:mod:`flexmbd.light`). It keeps
the stiffness at the last step, with the drive held, and the peak von Mises stress.
Here the cases run in this process (``client="serial"``); without that argument they
run on a local Dask cluster, one worker per core.

At zero stroke the stiffness is ``2 EA/L``. It falls with the stroke, roughly as
``1 / (1 + EA u^2 / (700 EI))``, the beam-constraint model, and faster for thinner
leaves. The stress grows as ``3 E t u / L^2``.
"""

# %%
import numpy as np
from flexmbd.examples import flexures

strokes = np.linspace(0.0, 4e-3, 9)
thicknesses = [0.3e-3, 0.5e-3, 0.8e-3]
data = flexures.guide_study(strokes, thicknesses, client="serial", progress=False)
print(data[["stroke", "thickness", "support_stiffness", "peak_stress", "status"]])

# %%
# Stiffness and stress against the stroke, a curve per leaf thickness
fig = flexures.plot_study(data, window=True)
