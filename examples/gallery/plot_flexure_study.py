"""
Designing a parallel guide: support stiffness and stress against stroke and thickness
=====================================================================================

A parallel leaf-spring guide (two steel leaves, 50 mm long and 20 mm wide, a rigid
stage) loses support stiffness along its leaves as it is driven along its stroke, and
its leaves' stress grows with the stroke and the thickness. A designer weighs the two.
:func:`flexmbd.sweep` runs one case per stroke and thickness, each a static analysis
in load steps of a model the script builds (as :mod:`flexmbd.light` would from SPACAR
Light's arrays, to the same numbers). It keeps
the stiffness at the last step, with the drive held, and the peak von Mises stress.
Here the cases run in this process (``client="serial"``); without that argument they
run on a local Dask cluster, one worker per core.

At zero stroke the stiffness is ``2 EA/L``. It falls with the stroke, roughly as
``1 / (1 + EA u^2 / (700 EI))``, the beam-constraint model, and faster for thinner
leaves. The stress grows as ``3 E t u / L^2``.
"""

# %%
# A case builds its model from the study's parameters: two leaves of four spatial
# beams each, with their section and material, clamped below (nodes 1 and 5 with their
# rotations 2 and 6); a rigid stage in two halves from the leaves' tops to its middle,
# node 9, whose x is driven by ``stroke`` in four load steps. The stage over-constrains
# the leaves: ``release_overconstraints`` releases six deformations as SPACAR Light
# does. The metrics read each case's equilibria.
import numpy as np
from flexmbd.examples import flexures

import flexmbd as fm

steel = fm.Material(210e9, 210e9 / 2.6, 7800.0)


def guide(stroke, thickness):
    """The guide with leaves ``thickness`` [m] thick, its stage driven ``stroke`` [m]."""
    b = fm.ModelBuilder("parallel guide")
    b.add_node(1, 0, 0, 0).add_node(3, 0, 0, 0.05)               # leaf 1, up along z
    b.add_node(5, 0.04, 0, 0).add_node(7, 0.04, 0, 0.05)         # leaf 2
    b.add_node(9, 0.02, 0, 0.05)                                  # the stage's middle
    leaf = fm.Rectangle(0.02, thickness)                          # 20 mm wide along y
    b.add_spatial_beams(1, 1, 2, 3, 4, 4, (0, 1, 0), new_nodes=100, section=leaf,
                        material=steel)
    b.add_spatial_beams(11, 5, 6, 7, 8, 4, (0, 1, 0), new_nodes=200, section=leaf,
                        material=steel)
    b.add_spatial_beam(21, 3, 4, 9, 10, (0, 1, 0)).add_spatial_beam(22, 9, 10, 7, 8, (0, 1, 0))
    b.fix(1).fix(2).fix(5).fix(6).input_coordinate(9, "x")
    b.release_overconstraints()
    return b.build(), fm.RunSettings(input_increment={"x9.1": stroke}, load_steps=4)


def support_stiffness(statics):
    """The stage's stiffness along the leaves (z) at the last step, the drive held."""
    return 1 / fm.node_compliance(statics.linearization(), 9, 10)[2, 2]


strokes = np.linspace(0.0, 4e-3, 9)
thicknesses = [0.3e-3, 0.5e-3, 0.8e-3]
data = fm.sweep(guide, {"stroke": list(strokes), "thickness": thicknesses}, "static",
                {"support_stiffness": support_stiffness,
                 "peak_stress": flexures.peak_stress}, client="serial", progress=False)
print(data[["stroke", "thickness", "support_stiffness", "peak_stress", "status"]])

# %%
# Stiffness and stress against the stroke, a curve per leaf thickness
fig = flexures.plot_study(data, window=True)
