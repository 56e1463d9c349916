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


def test_newton_operator_is_the_reduced_newton_matrix(monkeypatch):
    """Generalized-alpha's Newton correction ``-S^-1 R`` with ``S = Mbar + c_q K + c_v C``:
    the small-model form (q-space, from D_c's inverse) and the sparse saddle-point form
    against ``Mbar = F_q^T M F_q`` and ``K = E_q^T S E_q`` of :mod:`flexmbd.dynamics`."""
    from flexmbd import assembly
    from flexmbd.equations import EquationsOfMotion
    from flexmbd.inputs import resolve_laws

    c_q, c_v = 2e-6, 3e-3
    residual = np.array([[0.3, -1.2]])

    def operator_and_reference():
        model = flexible_slider_crank_one_beam()
        equations = EquationsOfMotion(model, resolve_laws(model, None))
        q, qd = np.array([0.4, 2e-3, -1e-3]), np.array([150.0, 0.5, -0.2])
        t = np.array([0.01])
        state = equations.kinematics(t, q[None], qd[None], np.zeros((1, 3)), model.x0[None])
        terms = dynamics.dynamic_terms(model, q, qd, 0.01, x_guess=state.x[0])
        d = ~model.q_is_input
        asm = model.assembly
        stiffness = terms.E_q.T @ asm.stiffness @ terms.E_q if asm.stiffness is not None \
            else None
        return model, equations.iteration_operator(state, c_q, c_v)(residual), terms, d, \
            stiffness

    dense_model, dense, terms, d, K = operator_and_reference()
    assert not dense_model.assembly.sparse
    S = terms.reduced_mass + c_q * K
    expected = -np.linalg.solve(S[np.ix_(d, d)], residual[0])
    np.testing.assert_allclose(dense, expected, rtol=1e-10)
    monkeypatch.setattr(assembly, "SPARSE_SIZE", 0)
    sparse_model, sparse, _, _, _ = operator_and_reference()
    assert sparse_model.assembly.sparse
    np.testing.assert_allclose(sparse, expected, rtol=1e-10)


def test_rho_inf_reaches_generalized_alpha_only():
    model = flexible_pendulum()
    with pytest.raises(ValueError, match="rho_inf"):
        fm.simulate(model, [0.0, 0.1], method="GeneralizedAlpha", rho_inf=1.5)
    with pytest.raises(ValueError, match="belong to GeneralizedAlpha"):
        fm.simulate(model, [0.0, 0.1], rho_inf=0.5)
    runs = [fm.simulate(model, np.linspace(0, 0.5, 11), method="GeneralizedAlpha",
                        initial={"e1.2": (0.01, 0.0)}, rho_inf=rho) for rho in (0.0, 1.0)]
    # the bending vibration, unresolved by these steps, decays only with rho_inf < 1
    assert np.ptp(runs[0]["e1.2"][5:]) < 0.5 * np.ptp(runs[1]["e1.2"][5:])


def test_reduced_and_saddle_point_accelerations_agree():
    """The output pass's two ways to the accelerations and constraint stresses (the
    reduced equations for models with many constraints, the saddle-point system
    otherwise) give the same outputs, on the rigid-elongation slider-crank (the reduced
    way is its own) and on the model with every element type, input and load."""
    from flexmbd.examples import slider_crank_flex as example

    from flexmbd.dat.reader import model_from_text
    from flexmbd.equations import EquationsOfMotion
    from flexmbd.inputs import resolve_laws
    from tests.test_dat import EVERYTHING

    rigid = example.build_model(4, eps1flex=False)
    everything = model_from_text(EVERYTHING, "everything.dat")
    for model, times in ((rigid, example.output_times(0.05)),
                         (everything, np.linspace(0.0, 0.02, 5))):
        result = fm.simulate(model, times, method="GeneralizedAlpha", iterations=1)
        equations = EquationsOfMotion(model, resolve_laws(model, None))
        d = ~model.q_is_input
        found = []
        for reduced in (True, False):
            equations.reduced_accelerations = reduced
            found.append(equations.outputs(result.t, result.q[:, d], result.qd[:, d],
                                           result.x))
        assert rigid.assembly.n_saddle >= 2 * rigid.n_dof  # the reduced way is chosen
        for name in ("qdd", "xdd", "sigma", "reactions", "driving"):
            scale = max(np.abs(found[1][name]).max(), 1.0)
            np.testing.assert_allclose(found[0][name], found[1][name], rtol=0,
                                       atol=1e-9 * scale, err_msg=name)
