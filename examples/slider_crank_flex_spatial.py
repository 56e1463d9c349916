"""Exercise 4's flexible slider-crank built of spatial elements (the spatial theory,
section 8): spatial beams and hinges in the XY plane, the rod's in-plane bending
(about the local y axes, orientation Z) dynamic, its elongation, torsion and
out-of-plane bending rigid.

With ``bending_linked=False`` it is the planar model of
:mod:`flexmbd.examples.slider_crank_flex` term by term (its results agree to
round-off); with SPACAR's bending-linked terms (the default) the rigid elongation
holds the rod's arc length instead of its chord. It is the spatial model of the
benchmark against the planar engine (``benchmarks/spatial_slider_crank.py``).
"""

from __future__ import annotations

import flexmbd as fm

from . import slider_crank_flex as planar

#: the crank's ground hinge (driven) and the slider's pin
DRIVE, PIN = 90, 91


def build_model(nbeams: int = 1, bending_linked: bool = True,
                omega: float = planar.OMEGA) -> fm.Model:
    """The slider-crank with its rod of ``nbeams`` spatial beams, the crank driven at
    ``omega`` [rad/s] by the ground hinge's rotation ``e90.1``."""
    b = fm.ModelBuilder(f"spatial flexible slider-crank, {nbeams} beam(s)")
    r, length = planar.L1, planar.L2
    b.add_node(1, 0, 0, 0).add_node(3, r, 0, 0).add_node(5, r + length, 0, 0)
    b.add_spatial_beam(1, 1, 102, 3, 103, orientation=(0, 0, 1))
    b.add_spatial_hinge(DRIVE, 101, 102).add_spatial_hinge(PIN, 103, 4)
    positions, angles = planar.rod_nodes(nbeams)
    for k in range(1, nbeams):
        b.add_node(positions[k], r + length * k / nbeams, 0, 0)
    for k in range(nbeams):
        element = k + 2
        b.add_spatial_beam(element, positions[k], angles[k], positions[k + 1], angles[k + 1],
                           orientation=(0, 0, 1), bending_linked=bending_linked)
        b.set_mass(element, planar.M2 / length)
        b.set_stiffness(element, axial=planar.EA, bending_y=planar.EI)
        b.dynamic_deformation(element, 3, 4)
    b.fix(1).fix(101).fix(5, "y")
    b.add_point_mass(5, planar.M2 / 2)
    b.input_deformation(DRIVE, 1, law=fm.Polynomial(0.0, omega))
    b.release(PIN, 1)
    return b.build()
