"""fm.energy: each term against its closed form on a model whose energy is known by hand,
and the total kept by a free motion (the check a simulation is judged by)."""

import numpy as np
import pytest

import flexmbd as fm

G = 9.81


def _rod(length=0.8, mass=1.5):
    """A uniform rigid rod on a pivot at the origin, released horizontal."""
    b = fm.ModelBuilder("rod")
    b.add_node(1, 0.0, 0.0).add_node(3, length, 0.0).add_rigid_beam(1, 1, 2, 3)
    b.set_mass(1, mass / length).fix(1).dynamic_coordinate(2).set_gravity(0.0, -G)
    return b.build()


def test_a_swinging_rod_s_kinetic_and_gravity_energy_are_the_closed_forms():
    """T = 1/2 (m L^2 / 3) phidot^2 and V = m g y_centre of the rod, at every row; their
    sum stays at its start (0) to the integrator's accuracy."""
    length, mass = 0.8, 1.5
    run = fm.simulate(_rod(length, mass), np.linspace(0.0, 1.0, 51), rtol=1e-10,
                      atol=1e-12)
    energy = fm.energy(run)
    rate, centre = run["xd2.1"], 0.5 * (run["x1.2"] + run["x3.2"])
    # to the position solve's tolerance (1e-10 of the rod's length)
    np.testing.assert_allclose(energy["kinetic"], 0.5 * mass * length**2 / 3 * rate**2,
                               rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(energy["gravity"], mass * G * centre, rtol=1e-9, atol=1e-12)
    assert np.abs(energy["total"]).max() < 1e-7 * energy["kinetic"].max()


def test_a_spring_s_elastic_energy_is_half_k_stretch_squared():
    """A truss spring (EA/l0 = k) to a point mass under gravity: 1/2 k (l - l0)^2, and a
    pre-stress sigma0 adds sigma0 (l - l0)."""
    k, l0, mass, sigma0 = 400.0, 0.5, 0.2, 3.0
    b = fm.ModelBuilder("spring")
    b.add_node(1, 0.0, 0.0).add_node(2, 0.0, -l0).add_truss(1, 1, 2)
    b.dynamic_deformation(1).set_stiffness(1, axial=k * l0).set_prestress(1, 1, sigma0)
    b.add_point_mass(2, mass).fix(1).fix(2, "x").set_gravity(0.0, -G)
    run = fm.simulate(b.build(), np.linspace(0.0, 0.5, 51), rtol=1e-10, atol=1e-12)
    energy = fm.energy(run)
    stretch = -run["x2.2"] - l0
    np.testing.assert_allclose(energy["elastic"], 0.5 * k * stretch**2 + sigma0 * stretch,
                               rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(energy["gravity"], mass * G * run["x2.2"], rtol=1e-12)
    scale = energy["kinetic"].max()
    np.testing.assert_allclose(energy["total"], energy["total"][0], atol=1e-7 * scale)


def test_a_flexible_double_pendulum_keeps_its_energy():
    """A rigid rod and a link of two flexible beams with consistent masses (whose weight
    turns with their rotations): the total of the three terms stays at its start to
    1e-7 of the largest kinetic energy."""
    b = fm.ModelBuilder("flexible double pendulum")
    b.add_node(1, 0.0, 0.0).add_node(3, 0.5, 0.0).add_node(5, 0.75, 0.0)
    b.add_node(7, 1.0, 0.0).add_rigid_beam(1, 1, 2, 3)
    b.add_beam(2, 3, 4, 5, 6).add_beam(3, 5, 6, 7, 8)
    b.fix(1).dynamic_coordinate(2).dynamic_coordinate(4)
    for k in (2, 3):
        b.dynamic_deformation(k, 2, 3).set_stiffness(k, bending=1.0).set_mass(k, 1.0)
    b.set_mass(1, 2.0).set_gravity(0.0, -G)
    run = fm.simulate(b.build(), np.linspace(0.0, 0.5, 51), rtol=1e-10, atol=1e-12)
    energy = fm.energy(run)
    assert energy["elastic"].max() > 1e-3 * energy["kinetic"].max()   # it does bend
    np.testing.assert_allclose(energy["total"], energy["total"][0],
                               atol=1e-7 * energy["kinetic"].max())


def test_energy_needs_velocities():
    run = fm.simulate(_rod(), np.linspace(0.0, 0.1, 5), outputs="positions")
    with pytest.raises(fm.ArgumentError, match="no velocities"):
        fm.energy(run)
