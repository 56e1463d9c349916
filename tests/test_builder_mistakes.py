"""Mistakes of a first model in Python, each with the right result or a message that
names the argument: a law for a free degree of freedom, a start that is no (value, rate)
pair, a section on a truss (its E A and rho A) or on a hinge (none), a material in
another unit or with its moduli swapped."""

import math
import re
import warnings

import numpy as np
import pytest

import flexmbd as fm


def _pendulum() -> fm.Model:
    return (fm.ModelBuilder("pendulum").add_node(1, 0, 0).add_node(3, 0, -1)
            .add_rigid_beam(1, 1, 2, 3).set_mass(1, 1.0).fix(1).dynamic_coordinate(2)
            .set_gravity(0, -9.81).build())


def test_a_law_for_a_free_degree_of_freedom_is_refused():
    with pytest.raises(fm.ArgumentError, match=r"inputs: x2\.1 is a dynamic degree of "
                                               r"freedom, .* initial=\{'x2\.1': \(value, "
                                               r"rate\)\}"):
        fm.simulate(_pendulum(), [0.0, 1.0], inputs={"x2.1": fm.Polynomial(0.0, 1.0)})


@pytest.mark.parametrize("initial, match", [
    ({"x2.1": 0.1}, r"initial: x2\.1 takes \(value, rate\)"),
    ({"x2.1": (np.nan, 0.0)}, r"initial: x2\.1: \(nan, 0\.0\) is not finite"),
])
def test_a_start_that_is_no_value_and_rate_is_named(initial, match):
    with pytest.raises(fm.ArgumentError, match=match):
        fm.simulate(_pendulum(), [0.0, 1.0], initial=initial)


def test_a_truss_from_a_section_has_its_axial_stiffness_and_mass():
    """A steel rod of 10 mm, 1 m, fixed at one end: E A from the section, and its
    consistent mass (m/3 at the free end) gives sqrt(EA / (l m / 3)) / 2 pi."""
    steel = fm.Material(210e9, 80e9, 7800)
    model = (fm.ModelBuilder("rod").add_node(1, 0, 0).add_node(2, 1, 0).add_truss(1, 1, 2)
             .set_section(1, fm.Circle(0.01), steel).fix(1).fix(2, "y")
             .dynamic_deformation(1).build())
    area = math.pi * 0.01**2 / 4
    assert model.element_properties[1].stiffness["axial"] == pytest.approx(210e9 * area)
    frequency = math.sqrt(210e9 * area / (7800 * area / 3)) / (2 * math.pi)
    assert fm.vibration_modes(model).frequencies[0] == pytest.approx(frequency, rel=1e-12)


def test_a_hinge_has_no_section():
    b = (fm.ModelBuilder("hinged").add_node(1, 0, 0).add_node(3, 1, 0)
         .add_rigid_beam(1, 1, 2, 3).add_node(5, 1, 1).add_rigid_beam(2, 5, 4, 3)
         .add_hinge(3, 2, 4).set_section(3, fm.Circle(0.01), fm.Material(210e9, 80e9, 7800)))
    with pytest.raises(fm.ModelError, match=r"set_section element 3: a hinge has no "
                                            r"cross-section; give its stiffness with "
                                            r"set_stiffness\(hinge=\.\.\.\)"):
        b.build()


@pytest.mark.parametrize("material, match", [
    (fm.Material(210, 80, 7800), r"E = 210 Pa is softer than any rubber: moduli are in Pa "
                                 r"\(210 GPa is 2\.1e\+11\)"),
    (fm.Material(210e3, 80e3, 7800), r"\(210000 MPa \(N/mm\^2\) is 2\.1e\+11\)"),
    (fm.Material(210e9, 80e9, 7.8), r"rho = 7\.8 kg/m\^3 is lighter than any foam"),
    (fm.Material(80e9, 210e9, 7800), r"E / \(2 G\) - 1 = -0\.81 is no Poisson's ratio"),
])
def test_a_material_in_another_unit_is_warned_about(material, match):
    b = fm.ModelBuilder("beam").add_node(1, 0, 0).add_node(3, 1, 0).add_beam(1, 1, 2, 3, 4)
    with pytest.warns(fm.ModelWarning) as said:
        b.set_section(1, fm.Rectangle(0.02, 0.001), material)
    assert any(re.search(r"set_section: Material\(.*" + match, str(w.message)) for w in said)


def test_a_material_that_looks_like_one_says_nothing():
    b = fm.ModelBuilder("beam").add_node(1, 0, 0).add_node(3, 1, 0).add_beam(1, 1, 2, 3, 4)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        b.set_section(1, fm.Rectangle(0.02, 0.001), fm.Material.from_poisson(70e9, 0.33, 2700))
        b.set_section(1, fm.Rectangle(0.02, 0.001), fm.Material.rigid(7800))
