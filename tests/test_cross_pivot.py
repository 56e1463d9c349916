"""FLEXURES 7's cross-spring pivot: leaves of 40 mm, 10 x 0.2 mm, crossing at their
middles at 90 degrees, side by side along the pivot axis z, 4 beams each, a rigid body
across their tops turned by its Euler parameter lam3. Its stiffness about the axis is
2EI/L exactly with the drive free, grows as the body turns (FLEXURES 7: 1.000062 times at
1.146 degrees, 1.006191 at 11.46), and the body's point that was at the crossing moves
along the bisector by sqrt(2) L theta^2 / 12 (second order)."""

import math

import numpy as np
import pytest

import flexmbd as fm

STEEL = fm.Material(210e9, 80e9, 7800.0)
LEAF = fm.Rectangle(0.01, 0.0002)
L = 0.04
HALF = L / (2 * math.sqrt(2))   #: the leaves' ends are (+-HALF, +-HALF) from the crossing
GAP = 0.012
EI = STEEL.E * 0.01 * 0.0002**3 / 12


def _pivot(theta: float):
    """The pivot (leaf A from (-h, -h) to (h, h), leaf B from (h, -h) to (-h, h) at z =
    GAP, the body from A's top node 3 to B's 7), turned by theta about z in 4 steps."""
    b = fm.ModelBuilder("cross-spring pivot")
    b.add_node(1, -HALF, -HALF, 0).add_node(3, HALF, HALF, 0)
    b.add_node(5, HALF, -HALF, GAP).add_node(7, -HALF, HALF, GAP)
    b.add_spatial_beams(1, 1, 2, 3, 4, 4, (0, 0, 1), new_nodes=100, section=LEAF,
                        material=STEEL)
    b.add_spatial_beams(21, 5, 6, 7, 8, 4, (0, 0, 1), new_nodes=200, section=LEAF,
                        material=STEEL)
    b.add_spatial_beam(50, 3, 4, 7, 8, (0, 0, 1))
    b.fix(1).fix(2).fix(5).fix(6).input_coordinate(4, 4)
    b.release_overconstraints()
    model = b.build()
    return model, fm.static_equilibrium(model, input_increment={"x4.4": math.sin(theta / 2)},
                                        steps=4)


def test_the_pivot_s_stiffness_is_2EI_over_L_with_the_drive_free():
    _, statics = _pivot(0.0)
    C = fm.node_compliance(statics.linearization(0), 3, 4, drive="free")
    assert 1 / C[5, 5] == pytest.approx(2 * EI / L, rel=1e-9)


@pytest.mark.parametrize("theta, ratio, tolerance", [(0.02, 1.000062, 2e-6),
                                                     (0.2, 1.006191, 5e-5)])
def test_the_stiffness_grows_as_it_turns(theta, ratio, tolerance):
    model, statics = _pivot(theta)
    moment = statics.reactions[-1][model.coordinate_index("x4.4")]
    assert moment / theta / (2 * EI / L) == pytest.approx(ratio, abs=tolerance)


def test_the_centre_moves_along_the_bisector_to_second_order():
    """The body's point that was at the crossing, at 0.02 rad: up the bisector (y) by
    sqrt(2) L theta^2 / 12 to 1e-3, sideways less than 2 % of that."""
    theta = 0.02
    model, statics = _pivot(theta)
    x = statics.x[-1]
    top = x[list(model.nodes[3].coordinates)]
    turn = fm.rotation_matrix(x[list(model.nodes[4].coordinates)])
    centre = top - turn @ np.array([HALF, HALF, 0.0])
    shift = math.sqrt(2) * L * theta**2 / 12
    assert centre[1] == pytest.approx(shift, rel=1e-3)
    assert abs(centre[0]) < 0.02 * shift and abs(centre[2]) < 1e-3 * shift
