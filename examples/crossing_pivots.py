"""Three planar cross-spring pivots alike, for where their strips should cross.

Each pivot has two steel strips (length 50 mm, width 10 mm, thickness 0.2 mm) at +-45
degrees that cross, without touching, at ``crossing`` of their length from the ground;
they are clamped there and joined at the top by a rigid stage. The first pivot is
unloaded, the second pulled and the third pushed along its axis by a tenth of the
strips' Euler scale ``EI/L^2``, through the crossing point. Wittrick (1951): strips that
cross at ``1/2 - sqrt(5)/6`` of their length turn with a stiffness independent of that
load, so there the pulled and the pushed pivot have the same rotational compliance
(:func:`stage_compliance`). Used by the gallery's *Wittrick's crossing point* and the
design tests.

Nodes of pivot ``k``: strip 1 from ``10000 k + 1001`` (odd, rotations even), strip 2
from ``10000 k + 2001``, the stage point ``10000 k + 5``; elements alike.
"""

from __future__ import annotations

import math

import flexmbd as fm

LENGTH, WIDTH, THICKNESS = 0.05, 0.01, 0.2e-3     #: strips [m], steel
E, RHO = 210e9, 7800.0                            #: [Pa], [kg/m^3]
EI = E * WIDTH * THICKNESS**3 / 12
LOAD = 0.1 * EI / LENGTH**2                        #: a tenth of the strips' Euler scale [N]
WITTRICK = 0.5 - math.sqrt(5) / 6                  #: the closed form, of the strip length


def pivots(crossing: float, beams: int = 24) -> tuple[fm.Model, fm.RunSettings]:
    """The three pivots with strips of ``beams`` beams crossing at ``crossing`` of their
    length, and the static run that loads the second and the third."""
    b = fm.ModelBuilder("three cross-spring pivots")
    c = math.cos(math.pi / 4)
    for k in range(3):                              # unloaded, pulled, pushed
        base = 10000 * k                            # pivot k's numbers, and x = k m
        ends = []
        for strip, ux in enumerate((c, -c)):
            first = base + 1000 * (strip + 1)       # the strip's nodes, odd from first + 1
            points = [first + 1 + 2 * j for j in range(beams + 1)]
            for j, node in enumerate(points):
                f = j / beams - crossing
                b.add_node(node, k + f * LENGTH * ux, f * LENGTH * c)
            for j in range(beams):
                number = first + j + 1
                b.add_beam(number, points[j], points[j] + 1, points[j + 1], points[j + 1] + 1)
                b.set_mass(number, RHO * WIDTH * THICKNESS)
                b.set_stiffness(number, axial=E * WIDTH * THICKNESS, bending=EI)
                if strip and j == beams - 1:       # the stage closes a loop: released
                    b.release(number, 1, 2, 3)
                else:
                    b.dynamic_deformation(number)
            b.fix(points[0]).fix(points[0] + 1)
            ends.append(points[-1])
        stage = base + 5                            # at the crossing point, on the stage
        b.add_node(stage, k, 0.0)
        b.add_rigid_beam(base + 1, ends[0], ends[0] + 1, ends[1])
        b.add_hinge(base + 2, ends[0] + 1, ends[1] + 1)   # one rigid stage
        b.add_rigid_beam(base + 3, ends[0], ends[0] + 1, stage)
    loads = {"x10005.2": LOAD, "x20005.2": -LOAD}
    return b.build(), fm.RunSettings(load_increment=loads, load_steps=1)


def stage_compliance(k: int, beams: int = 24) -> str:
    """The output name of pivot ``k``'s rotational compliance [rad/(N m)] (its stage's
    angle is the first strip's top rotation), for :mod:`flexmbd.design`."""
    top = 10000 * k + 1000 + 1 + 2 * beams + 1
    return f"C[{10000 * k + 5},{top}][2,2]"
