"""Small models from the exercises, shared by the tests."""

import math

import flexmbd as fm


def slider_crank(l1: float = 1.0, l2: float = math.sqrt(3.0), law=None) -> fm.Model:
    """EXERCISES 2: nodes 1 O, 2 crank angle, 3 A, 4 rod angle, 5 B (y fixed)."""
    b = fm.ModelBuilder("slider-crank")
    b.add_node(1, 0.0, 0.0).add_node(3, l1, 0.0).add_node(5, l1 + l2, 0.0)
    b.add_rigid_beam(1, 1, 2, 3)
    b.add_rigid_beam(2, 3, 4, 5)
    b.fix(1).fix(5, "y")
    b.input_coordinate(2, law=law or fm.Polynomial(0.0, 2.0, 1.5))
    return b.build()
