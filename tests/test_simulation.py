"""Forward simulation: energy conservation, failures with partial results, errors."""

import math

import numpy as np
import pytest

import flexmbd as fm
from flexmbd import dynamics
from flexmbd.inertia import mass_matrix

GRAVITY = np.array([0.0, -9.81])
LENGTH, MASS, TIP, EI = 1.0, 1.0, 0.5, 5.0


def flexible_pendulum():
    """One flexible beam hanging from a pivot: angle and both bendings are dynamic."""
    b = fm.ModelBuilder("flexible pendulum")
    b.add_node(1, 0.0, 0.0).add_node(3, LENGTH, 0.0)
    b.add_beam(1, 1, 2, 3, 4)
    b.fix(1).dynamic_coordinate(2).dynamic_deformation(1, 2, 3)
    b.set_mass(1, MASS / LENGTH).set_stiffness(1, bending=EI)
    b.add_point_mass(3, TIP)
    b.set_gravity(*GRAVITY)
    return b.build()


def total_energy(model, result):
    """Kinetic + gravity + bending energy, from the formulas of THEORY 5-6 directly."""
    energies = []
    stiffness = EI / LENGTH**3 * np.array([[4.0, -2.0], [-2.0, 4.0]])
    for x, xd, e in zip(result.x, result.xd, result.e, strict=True):
        kinetic = 0.5 * xd @ mass_matrix(model, x) @ xd
        rp, rq = x[0:2], x[3:5]
        e_p = np.array([math.cos(x[2]), math.sin(x[2])])
        e_q = np.array([math.cos(x[5]), math.sin(x[5])])
        centre_sum = rp / 2 + LENGTH * e_p / 12 + rq / 2 - LENGTH * e_q / 12  # int r dxi
        potential = -MASS * GRAVITY @ centre_sum - TIP * GRAVITY @ rq
        elastic = 0.5 * e[1:] @ stiffness @ e[1:]
        energies.append(kinetic + potential + elastic)
    return np.array(energies)


def test_flexible_pendulum_conserves_energy():
    model = flexible_pendulum()
    assert model.q_labels == ("x2.1", "e1.2", "e1.3")
    times = np.linspace(0.0, 3.0, 61)  # about two swings and three bending periods
    result = fm.simulate(model, times, initial={"x2.1": (-0.6, 0.0), "e1.2": (0.0, 0.05)},
                         method="DOP853", rtol=1e-9, atol=1e-11)
    assert result.success and len(result.t) == len(times)
    energy = total_energy(model, result)
    swing = np.ptp(result["x2.1"])
    assert swing > 0.5  # it really swings
    assert np.ptp(result["e1.2"]) > 1e-2  # and really bends
    np.testing.assert_allclose(result["x4.1"][0], result["x2.1"][0])  # straight at the start
    assert np.max(np.abs(energy - energy[0])) <= 1e-6 * np.max(np.abs(energy))


def test_elastic_stress_follows_the_bending_law():
    model = flexible_pendulum()
    result = fm.simulate(model, np.linspace(0, 0.2, 5), initial={"e1.2": (0.01, 0.0)})
    e = result.e
    np.testing.assert_allclose(result["sig1.2"], EI / LENGTH**3 * (4 * e[:, 1] - 2 * e[:, 2]))


def test_outputs_match_the_reduced_equations_of_the_dynamics_module():
    """The run's accelerations and constraint stresses (saddle-point system, THEORY 8)
    against F_q, Mbar and D_c^T sigma of :mod:`flexmbd.dynamics` at the same states."""
    model = flexible_pendulum()
    result = fm.simulate(model, np.linspace(0, 0.4, 9), initial={"e1.2": (0.01, 0.3)},
                         with_reactions=True)
    for k in range(len(result.t)):
        terms = dynamics.dynamic_terms(model, result.q[k], result.qd[k], result.t[k],
                                       x_guess=result.x[k])
        qdd = dynamics.generalized_accelerations(model, terms, np.zeros(0))
        np.testing.assert_allclose(result.qdd[k], qdd, rtol=1e-9, atol=1e-9)
        found = dynamics.reactions(model, terms, qdd)
        np.testing.assert_allclose(result.sigma[k], found.sigma, rtol=1e-8, atol=1e-8)
        np.testing.assert_allclose(result.reactions[k], found.nodal, rtol=1e-8, atol=1e-8)
    assert np.abs(result["sig1.1"]).max() > 1.0  # the rigid elongation pulls the body round


def flexible_slider_crank_one_beam():
    b = fm.ModelBuilder("flexible slider-crank")
    b.add_node(1, 0, 0).add_node(3, 0.15, 0).add_node(5, 0.45, 0)
    b.add_rigid_beam(1, 1, 2, 3).add_beam(2, 3, 4, 5, 6)
    b.fix(1).fix(5, "y").dynamic_deformation(2, 2, 3)
    b.set_mass(2, 0.06676 / 0.30).set_stiffness(2, bending=12.72)
    b.add_point_mass(5, 0.06676 / 2)
    b.input_coordinate(2, law=fm.Polynomial(0.0, 150.0))
    return b.build()


def test_rod_breaks_at_absurd_crank_acceleration_with_partial_results():
    model = flexible_slider_crank_one_beam()
    absurd = {"x2.1": fm.Polynomial(0.0, 0.0, 2e6)}
    times = np.linspace(0.0, 0.05, 201)
    with pytest.raises(fm.SimulationError) as info:
        fm.simulate(model, times, inputs=absurd)
    error = info.value
    assert error.time is not None and 0 < error.time < 0.05
    assert f"t = {error.time:.6g} s" in str(error)
    partial = error.partial_result
    assert partial is not None and 0 < len(partial.t) < len(times)
    assert partial.t[-1] <= error.time
    returned = fm.simulate(model, times, inputs=absurd, on_failure="return")
    assert not returned.success and len(returned.t) == len(partial.t)


def test_errors_before_any_work():
    from tests.test_kinematics import sliding_bar

    with pytest.raises(fm.ModelError, match="no dynamic degree of freedom"):
        fm.simulate(sliding_bar(), [0.0, 0.1])
    massless = fm.ModelBuilder()
    massless.add_node(1, 0, 0).add_node(3, 1, 0).add_rigid_beam(1, 1, 2, 3)
    massless.fix(1).dynamic_coordinate(2)
    with pytest.raises(fm.ModelError, match="no mass"):
        fm.simulate(massless.build(), [0.0, 0.1])
    with pytest.raises(fm.ModelError, match="prescribed, not dynamic"):
        fm.simulate(flexible_slider_crank_one_beam(), [0.0, 0.1], initial={"x2.1": (0, 1)})
    with pytest.raises(ValueError, match="unknown method"):
        fm.simulate(flexible_pendulum(), [0.0, 0.1], method="Euler")


def test_sparse_backend_reproduces_the_dense_one(monkeypatch):
    """Long chains switch to sparse assembly and SuperLU (flexmbd.factor); forced onto a
    small model, that path gives the dense path's run to round-off."""
    from flexmbd.examples import slider_crank_flex as example

    from flexmbd import assembly

    def run():
        model = example.build_model(4, eps1flex=True)
        return model, fm.simulate(
            model, example.output_times(0.05), method="GeneralizedAlpha",
            step=example.turn_time(1.0) / 800, iterations=1, with_reactions=True)

    dense_model, dense = run()
    monkeypatch.setattr(assembly, "SPARSE_SIZE", 0)
    sparse_model, sparse = run()
    assert not dense_model.assembly.sparse and sparse_model.assembly.sparse
    for name in ("x", "xd", "xdd", "e", "sigma", "reactions", "driving"):
        scale = max(np.abs(getattr(dense, name)).max(), 1.0)
        np.testing.assert_allclose(getattr(sparse, name), getattr(dense, name),
                                   rtol=0, atol=1e-9 * scale, err_msg=name)
