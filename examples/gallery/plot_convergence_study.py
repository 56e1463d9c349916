"""
Convergence in the number of beams: a parameter study (exercise 4, part 2)
==========================================================================

How many beams does the rod need? :func:`flexmbd.sweep` runs the flexible
slider-crank once per number of beams and keeps the ``v/l2`` history and its
peak of each case. Here it runs in this process (``client="serial"``); without
that argument the same call runs the cases on a local Dask cluster, one worker
per core. The peaks settle as the rod is refined: from 2 to 8 beams the curve
changes by about 1e-3 of ``l2`` or less.
"""

# %%
# A case is a function of the study's parameters that builds the model: here the
# slider-crank with a rod of ``nbeams`` beams whose bending is free. ``flex.run``
# simulates it with the exercise's generalized-alpha steps; the metrics read the crank
# angle, the rod's mid-point deflection and its peak from each run.
import functools
import math
import os

from flexmbd.examples import slider_crank_flex as flex

import flexmbd as fm

QUICK = os.environ.get("FLEXMBD_DOCS_QUICK") == "1"


def slider_crank(nbeams):
    """Exercise 4's slider-crank, the rod of ``nbeams`` beams."""
    l1, l2, m2 = 0.15, 0.30, 0.06676
    b = fm.ModelBuilder(f"flexible slider-crank, {nbeams} beams")
    b.add_node(1, 0.0, 0.0).add_node(3, l1, 0.0).add_node(5, l1 + l2, 0.0)
    b.add_rigid_beam(1, 1, 2, 3)
    points = [3, *(7 + 2 * k for k in range(nbeams - 1)), 5]
    angles = [4, *(8 + 2 * k for k in range(nbeams - 1)), 6]
    for k in range(1, nbeams):
        b.add_node(points[k], l1 + l2 * k / nbeams, 0.0)
    for k in range(nbeams):
        b.add_beam(k + 2, points[k], angles[k], points[k + 1], angles[k + 1])
        b.set_mass(k + 2, m2 / l2)
        b.set_stiffness(k + 2, axial=2e11 * math.pi * 0.003**2, bending=12.72)
        b.dynamic_deformation(k + 2, 2, 3)
    b.fix(1).fix(5, "y").add_point_mass(5, m2 / 2)
    b.input_coordinate(2, law=fm.Polynomial(0.0, 150.0))
    return b.build()


nbeams = [1, 2, 4] if QUICK else [1, 2, 3, 4, 6, 8]
data = fm.sweep(slider_crank, {"nbeams": nbeams},
                functools.partial(flex.run, revolutions=1.0 if QUICK else 2.0),
                {"phi": flex.crank_angle, "v_over_l2": flex.deflection,
                 "peak": flex.peak_deflection}, client="serial", progress=False)
for n, peak in zip(data["nbeams"].values, data["peak"].values, strict=True):
    print(f"{n} beams: peak |v/l2| = {peak:.6f}")

# %%
# The histories together, and the peak against the number of beams
fig = flex.plot_convergence(data, window=True)
