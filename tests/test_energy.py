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


# --- work and balance -----------------------------------------------------------------------
TIGHT = {"rtol": 1e-10, "atol": 1e-12}


def test_a_crank_turned_against_gravity_takes_the_work_of_lifting_it():
    """A rigid rod turned at a constant rate w from horizontal: the drive's work is the
    rise of its centre, m g l/2 sin(w t), and its kinetic energy stays m l^2 w^2 / 6."""
    length, mass, rate = 0.8, 1.5, 2.0
    b = fm.ModelBuilder("turned rod")
    b.add_node(1, 0.0, 0.0).add_node(3, length, 0.0).add_rigid_beam(1, 1, 2, 3)
    b.set_mass(1, mass / length).fix(1).set_gravity(0.0, -G)
    b.input_coordinate(2, law=fm.Polynomial(0.0, rate))
    t = np.linspace(0.0, 0.6, 121)
    energy = fm.energy(fm.inverse_dynamics(b.build(), t))
    lift = mass * G * length / 2 * np.sin(rate * t)
    np.testing.assert_allclose(energy["input_work"], lift, rtol=1e-7, atol=1e-9)
    np.testing.assert_allclose(energy["balance"], 0.0, atol=1e-7 * lift.max())
    assert np.all(energy["load_work"] == 0.0) and np.all(energy["dissipated"] == 0.0)


def test_an_actuator_s_work_is_the_kinetic_energy_it_gives():
    """A truss actuator whose length grows as a t^2 / 2 (``Polynomial(0, 0, a)``) pushes
    a free mass m: the force m a over that stroke is the work m (a t)^2 / 2 (the input is
    a deformation, its driving load the actuator's force)."""
    mass, a = 0.3, 4.0
    b = fm.ModelBuilder("actuator")
    b.add_node(1, 0.0, 0.0).add_node(2, 0.5, 0.0).add_truss(1, 1, 2).fix(1)
    b.fix(2, "y").add_point_mass(2, mass).input_deformation(1, law=fm.Polynomial(0, 0, a))
    b.add_node(3, 0.0, 1.0).add_node(4, 0.2, 1.0).add_truss(2, 3, 4).fix(3).fix(4, "y")
    b.dynamic_deformation(2).set_stiffness(2, axial=50.0).add_point_mass(4, 0.1)
    t = np.linspace(0.0, 0.5, 101)
    energy = fm.energy(fm.simulate(b.build(), t, **TIGHT))
    np.testing.assert_allclose(energy["input_work"], 0.5 * mass * (a * t)**2, rtol=1e-7,
                               atol=1e-12)
    np.testing.assert_allclose(energy["balance"], 0.0, atol=1e-7 * energy["kinetic"].max())


def _free_mass(force=None):
    b = fm.ModelBuilder("free mass")
    b.add_node(1, 0.0, 0.0).add_node(2, 1.0, 0.0).add_truss(1, 1, 2).fix(1).fix(2, "y")
    b.dynamic_deformation(1).add_point_mass(2, 2.0)
    if force is not None:
        b.add_force(2, force, 0.0)
    return b.build()


def test_the_work_of_a_constant_load_and_of_a_forces_function():
    """On a free mass m: a constant force F does F (x - x0); F0 cos t given as
    ``forces`` does F0^2 sin^2 t / (2 m), its kinetic energy (kept on the result, or
    passed again)."""
    t = np.linspace(0.0, 1.0, 101)
    run = fm.simulate(_free_mass(3.0), t, **TIGHT)
    energy = fm.energy(run)
    np.testing.assert_allclose(energy["load_work"], 3.0 * (run["x2.1"] - 1.0), rtol=1e-9)
    np.testing.assert_allclose(energy["load_work"], 3.0**2 * t**2 / 4, rtol=1e-7)

    def push(time, x, xd):
        return {"x2.1": 5.0 * np.cos(time)}

    t = np.linspace(0.0, 1.0, 401)     # rows that resolve the power to rtol
    run = fm.simulate(_free_mass(), t, forces=push, **TIGHT)
    closed = 5.0**2 * np.sin(t)**2 / 4
    for energy in (fm.energy(run), fm.energy(run, forces=push)):
        np.testing.assert_allclose(energy["load_work"], closed, atol=1e-7 * closed.max())
        np.testing.assert_allclose(energy["balance"], 0.0, atol=1e-7 * closed.max())


def test_a_moment_s_work_on_a_spatial_body_is_moment_times_angle():
    """A constant moment M about a principal axis of a free body: M theta = (M t)^2/(2 J)."""
    moment, J = 0.7, 2.5
    b = fm.ModelBuilder("spun body")
    b.add_node(1, 0, 0, 0).add_node(3, 1, 0, 0)
    b.add_spatial_beam(1, 1, 2, 3, 4, orientation=(0, 1, 0))
    b.fix(1).dynamic_coordinate(2, 2, 3, 4).add_rotary_inertia(2, 1.0, 0, 0, 2.0, 0, J)
    b.add_force(2, 0.0, 0.0, moment)
    t = np.linspace(0.0, 1.0, 101)
    energy = fm.energy(fm.simulate(b.build(), t, **TIGHT))
    np.testing.assert_allclose(energy["load_work"], (moment * t)**2 / (2 * J), rtol=1e-7,
                               atol=1e-12)
    np.testing.assert_allclose(energy["balance"], 0.0, atol=1e-7 * energy["kinetic"].max())


def test_damping_takes_out_what_the_damped_oscillator_loses():
    """m x'' + c x' + k x = 0 from x0 at rest: the dissipated energy is E0 - E(t) of the
    closed-form motion."""
    m, c, k, x0 = 0.5, 0.4, 200.0, 0.01
    b = fm.ModelBuilder("damped spring")
    b.add_node(1, 0.0, 0.0).add_node(2, 1.0, 0.0).add_truss(1, 1, 2).fix(1).fix(2, "y")
    b.dynamic_deformation(1).set_stiffness(1, axial=k * 1.0).set_damping(1, axial=c * 1.0)
    b.add_point_mass(2, m)
    t = np.linspace(0.0, 1.0, 1601)
    energy = fm.energy(fm.simulate(b.build(), t, initial={"e1.1": (x0, 0.0)}, rtol=1e-8,
                                   atol=1e-12))
    zeta, wn = c / (2 * np.sqrt(k * m)), np.sqrt(k / m)
    wd = wn * np.sqrt(1 - zeta**2)
    x = x0 * np.exp(-zeta * wn * t) * (np.cos(wd * t) + zeta * wn / wd * np.sin(wd * t))
    v = -x0 * wn**2 / wd * np.exp(-zeta * wn * t) * np.sin(wd * t)
    lost = 0.5 * k * x0**2 - (0.5 * k * x**2 + 0.5 * m * v**2)
    # at rtol 1e-8 the motion is good to about 2e-6 and generalized-alpha's own damping
    # (rho_inf 0.8) takes out 5e-6 of the loss besides the damper
    np.testing.assert_allclose(energy["dissipated"], lost, rtol=1e-5, atol=1e-5 * lost.max())
    np.testing.assert_allclose(energy["balance"], 0.0, atol=2e-5 * lost.max())


def test_a_balance_over_too_few_rows_says_so():
    """The driven flexible slider-crank output at 21 rows per turn: its power is not
    resolved, and the warning says the balance measures the rows."""
    from flexmbd.examples import slider_crank_flex as example
    model = example.build_model(2)
    run = fm.simulate(model, np.linspace(0.0, 2 * np.pi / example.OMEGA, 21))
    with pytest.warns(fm.AccuracyWarning, match="output at more times"):
        fm.energy(run)


@pytest.mark.parametrize("rtol", [1e-5, 1e-7])
def test_the_driven_flexible_slider_crank_balances_to_the_integrator_s_tolerance(rtol):
    """EXERCISES 4 with four beams, one turn, the default integrator at ``rtol``: the
    energy changes by the drive's work to within a few ``rtol`` of the largest kinetic
    energy (measured: 3e-5 at 1e-4, 9e-7 at 1e-6, 7e-8 at 1e-8)."""
    from flexmbd.examples import slider_crank_flex as example
    model = example.build_model(4)
    run = fm.simulate(model, np.linspace(0.0, 2 * np.pi / example.OMEGA, 1601), rtol=rtol,
                      atol=rtol * 1e-3)
    energy = fm.energy(run)
    assert energy["input_work"].max() > 0.1 * energy["kinetic"].max()   # the drive works
    assert np.abs(energy["balance"]).max() < 5 * rtol * energy["kinetic"].max()


def test_work_needs_the_driving_loads_of_moving_drives():
    from flexmbd.examples import slider_crank_flex as example
    run = fm.simulate(example.build_model(1), np.linspace(0.0, 0.01, 11), outputs="velocities")
    with pytest.raises(fm.ArgumentError, match=r"driving loads.*outputs='all'"):
        fm.energy(run)
    with pytest.raises(fm.ArgumentError, match="forces"):
        fm.energy(fm.simulate(_free_mass(), np.linspace(0, 0.1, 11)), forces=3.0)


def test_load_steps_have_energies_but_no_work_in_time():
    """A static result's rows are load factors, not times: its elastic energy is there
    (a cantilever's P^2 l^3 / (6 EI) at the tip load P), no work or balance columns."""
    b = fm.ModelBuilder("cantilever")
    b.add_node(1, 0, 0).add_node(3, 1, 0).add_beam(1, 1, 2, 3, 4)
    b.set_stiffness(1, axial=1e9, bending=10.0).fix(1).fix(2).dynamic_deformation(1)
    energy = fm.energy(fm.static_equilibrium(b.build(), load_increment={"x3.2": -0.01}))
    assert list(energy) == ["t", "kinetic", "elastic", "gravity", "total"]
    assert energy["elastic"][-1] == pytest.approx(0.01**2 / (6 * 10.0), rel=1e-4)
