"""Cross-sections and materials of beams against SPACAR Light's printed values, the
tables of the torsion constant and closed forms, and a cantilever of sub-beams built in
one call against beam theory."""

import math

import numpy as np
import pytest

import flexmbd as fm
from flexmbd.errors import ArgumentError
from flexmbd.sections import rectangle_torsion

STEEL = fm.Material(210e9, 70e9, 7800.0)


def test_a_leaf_gives_the_values_spacar_light_writes():
    """A 50 x 0.2 mm steel leaf: SPACAR Light 2.01 wrote these ESTIFF and EM values (its
    %20.15f format) into a public cross-hinge file."""
    values = fm.beam_values(fm.Rectangle(0.05, 0.0002), STEEL)
    written = {"estiff": ["2100000.000000000000000", "   0.009309804722106",
                          "   0.007000000000000", " 437.500000000000114",
                          "   0.000000011666667", "   0.000729166666667",
                          "   0.000001458333333"],
               "em": ["   0.078000000000000", "   0.000016250260000", "   0.000000000260000",
                      "   0.000016250000000", "   0.000000000000000", "   0.000000000000054"]}
    assert [f"{v:20.15f}" for v in values.estiff] == written["estiff"]
    assert [f"{v:20.15f}" for v in values.em] == written["em"]


@pytest.mark.parametrize("ratio, beta", [(1, 0.141), (2, 0.229), (10, 0.312)])
def test_the_torsion_constant_of_a_rectangle_is_the_tables(ratio, beta):
    """It = beta b c^3 (Timoshenko and Goodier's table, three digits); SPACAR Light's
    series ends early, within 4.4e-5 of the converged one (the most at a square)."""
    converged = rectangle_torsion(ratio, 1.0, tolerance=0.0) / ratio
    assert converged == pytest.approx(beta, abs=6e-4)
    assert rectangle_torsion(ratio, 1.0) / ratio == pytest.approx(converged, rel=4.4e-5)
    thin = rectangle_torsion(50.0, 1.0, tolerance=0.0)
    assert thin == pytest.approx(50.0 / 3 * (1 - 0.630 / 50), rel=3e-5)  # b/c >= 10


def test_circle_and_tube_are_their_closed_forms():
    d = 0.002
    circle = fm.beam_values(fm.Circle(d), fm.Material.from_poisson(200e9, 0.3, 8000.0))
    inertia = math.pi * d**4 / 64
    G = 200e9 / 2.6
    k = 6 * 1.3 / (7 + 6 * 0.3)
    assert circle.estiff[:4] == pytest.approx([200e9 * math.pi * d**2 / 4, G * 2 * inertia,
                                               200e9 * inertia, 200e9 * inertia], rel=1e-15)
    assert circle.estiff[4] == pytest.approx(200e9 * inertia / (k * G * math.pi * d**2 / 4))
    assert circle.estiff[6] == 0.0 and circle.em[0] == pytest.approx(8000 * math.pi * d**2 / 4)
    tube = fm.Tube(0.01, 0.008).properties()
    assert tube.Iy == pytest.approx(math.pi * (0.01**4 - 0.008**4) / 64) and tube.It == \
        pytest.approx(2 * tube.Iy)
    # a tube of no bore is the circle; of a thin wall, Cowper's thin-ring k -> 2(1+nu)/(4+3nu)
    assert fm.Tube(0.01, 0.0).shear_factor(0.3) == fm.Circle(0.01).shear_factor(0.3)
    assert fm.Tube(0.01, 0.01 * (1 - 1e-9)).shear_factor(0.3) == pytest.approx(
        2 * 1.3 / (4 + 0.9), rel=1e-6)


@pytest.mark.parametrize("make, message", [
    (lambda: fm.Material(-1.0, 1.0), "E: must be positive"),
    (lambda: fm.Material(1.0, 1.0, -5.0), "rho: must be 0 or more"),
    (lambda: fm.Material.from_poisson(1e9, 0.7), "Poisson's ratio"),
    (lambda: fm.Rectangle(0.0, 1.0), "w: must be positive"),
    (lambda: fm.Tube(0.01, 0.02), "inner: must lie in"),
    (lambda: fm.beam_values("steel", STEEL), "must be a Rectangle, Circle or Tube"),
])
def test_bad_sections_and_materials_are_named(make, message):
    with pytest.raises(ArgumentError, match=message):
        make()


def test_a_cantilever_of_sub_beams_built_in_one_call():
    """A leaf clamped at one end, 8 beams from one call, under an end force across it:
    the tip deflection of beam theory with shear, P L^3/(3 EI) + P L/(k G A)."""
    b = fm.ModelBuilder("leaf")
    b.add_node(1, 0.0, 0.0, 0.0).add_node(3, 0.1, 0.0, 0.0)
    leaf = fm.Rectangle(0.02, 0.0005)
    b.add_spatial_beams(1, 1, 2, 3, 4, 8, orientation=(0, 1, 0), new_nodes=100,
                        section=leaf, material=STEEL)
    b.fix(1).fix(2)
    model = b.build()
    assert len([e for e in model.elements.values() if e.type is fm.SpatialBeam]) == 8
    assert model.nodes[100].position == pytest.approx((0.0125, 0.0, 0.0))
    load = -0.05
    statics = fm.static_equilibrium(model, loads={"x3.3": load}, tolerance=1e-14)
    props = leaf.properties()
    EI, kGA = STEEL.E * props.Iy, leaf.shear_factor(STEEL.nu) * STEEL.G * props.A
    expected = load * 0.1**3 / (3 * EI) + load * 0.1 / kGA
    assert statics["x3.3"][-1] == pytest.approx(expected, rel=2e-4)  # small-deflection
    # the section's mass: rhoA l, and the torsional inertia on the rotational nodes
    assert sum(p.mass_per_length for p in model.element_properties.values()) * 0.1 / 8 == \
        pytest.approx(STEEL.rho * props.A * 0.1)
    assert np.all([model.element_properties[k].section_inertia[0] ==
                   pytest.approx(STEEL.rho * (props.Iy + props.Iz)) for k in range(1, 9)])


def test_a_planar_beam_takes_a_section_and_a_material():
    """A planar cantilever of 8 beams built from ``Rectangle(w, t)`` and steel: its tip
    deflection under a small load ``P L^3 / (3 E I)`` and its first frequency
    ``1.8751^2 / (2 pi) sqrt(E I / (rho A L^4))`` to 1e-3, ``I = w t^3 / 12``; the beam
    gets SPACAR's planar values (EA, EI, the shear stiffness k G A in N, rhoA, rhoI)."""
    E, rho, w, t, L, P, n = 210e9, 7800.0, 0.02, 0.002, 0.3, 0.1, 8
    steel = fm.Material.from_poisson(E, 0.3, rho)
    b = fm.ModelBuilder("planar cantilever")
    for k in range(n + 1):
        b.add_node(2 * k + 1, L * k / n, 0.0)
    for k in range(n):
        b.add_beam(k + 1, 2 * k + 1, 2 * k + 2, 2 * k + 3, 2 * k + 4)
        b.dynamic_deformation(k + 1).set_section(k + 1, fm.Rectangle(w, t), steel)
    model = b.fix(1).fix(2).build()
    inertia = w * t**3 / 12
    stiffness = dict(model.element_properties[1].stiffness)
    assert stiffness["axial"] == pytest.approx(E * w * t)
    assert stiffness["bending"] == pytest.approx(E * inertia)
    assert stiffness["shear"] == pytest.approx(fm.Rectangle(w, t).shear_factor(0.3) * E /
                                               2.6 * w * t)
    assert model.section_masses[2] == pytest.approx(0.5 * L / n * rho * inertia)
    statics = fm.static_equilibrium(model, loads={f"x{2 * n + 1}.2": -P})
    tip = statics[f"x{2 * n + 1}.2"][-1]
    assert tip == pytest.approx(-P * L**3 / (3 * E * inertia), rel=1e-3)
    first = fm.vibration_modes(statics.linearization(0), 1).frequencies[0]
    closed = 1.8751041**2 / (2 * np.pi) * np.sqrt(E * inertia / (rho * w * t * L**4))
    assert first == pytest.approx(closed, rel=1e-3)


@pytest.mark.parametrize("spatial, values, words", [
    (False, {"axial": 1e6, "bending": 1.0, "shear": 1e-8},
     r"shear = 1e-08 N makes the beam .* times softer in shear than in bending: a planar "
     r"beam's shear is the stiffness G A_s \[N\]"),
    (True, {"axial": 1e6, "torsion": 1.0, "bending_y": 1.0, "bending_z": 1.0,
            "shear_y": 8e7},
     r"shear_y = 8e\+07 m\^2 makes the beam .* a spatial beam's shear_y is the flexibility "
     r"EI/\(G A k\) \[m\^2\]"),
])
def test_a_shear_value_in_the_other_convention_is_refused(spatial, values, words):
    """Planar ``shear`` is a stiffness [N], spatial ``shear_y`` a flexibility [m^2]: a value
    that would make a 0.1 m beam 1e4 times softer in shear than in bending is the other."""
    b = fm.ModelBuilder("shear")
    if spatial:
        b.add_node(1, 0, 0, 0).add_node(3, 0.1, 0, 0).add_spatial_beam(1, 1, 2, 3, 4,
                                                                       (0, 1, 0))
    else:
        b.add_node(1, 0, 0).add_node(3, 0.1, 0).add_beam(1, 1, 2, 3, 4)
    b.dynamic_deformation(1).set_stiffness(1, **values).fix(1).fix(2)
    with pytest.raises(fm.ModelError, match=words):
        b.build()
