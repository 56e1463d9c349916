"""The symbolic path agrees with the numeric one (same element definitions)."""

import numpy as np
import pytest

sp = pytest.importorskip("sympy")

import flexmbd as fm  # noqa: E402
from flexmbd.analysis import symbolic  # noqa: E402

from .models import slider_crank  # noqa: E402
from .test_kinematics import four_bar_with_spring  # noqa: E402


def substitute(model, expr, x, xd=None):
    values = dict(zip(symbolic.coordinate_symbols(model), x, strict=True))
    if xd is not None:
        values.update(zip(symbolic.coordinate_symbols(model, "xd"), xd, strict=True))
    return np.array(expr.subs(values).evalf(), dtype=float)


@pytest.mark.parametrize("build", [slider_crank, four_bar_with_spring])
def test_symbolic_matches_numeric(build):
    model = build()
    x = fm.solve_position(model, np.array([0.6]))
    xd = fm.velocities(model, x, np.array([1.4]))
    np.testing.assert_allclose(substitute(model, symbolic.deformations(model), x).ravel(),
                               fm.deformations(model, x), atol=1e-13)
    np.testing.assert_allclose(substitute(model, symbolic.jacobian(model), x),
                               fm.jacobian(model, x), atol=1e-13)
    np.testing.assert_allclose(substitute(model, symbolic.quadratic_velocity(model), x, xd)
                               .ravel(), fm.quadratic_velocity(model, x, xd), atol=1e-12)
    np.testing.assert_allclose(
        substitute(model, symbolic.first_order_transfer(model, simplify=False), x),
        fm.first_order_transfer(model, x), atol=1e-12)


def test_slider_crank_symbolic_e_q_is_zero_and_lengths_are_exact():
    model = slider_crank()
    assert symbolic.deformation_transfer(model) == sp.zeros(4, 1)
    assert symbolic.deformations(model)[2].has(sp.sqrt(3))


# --- the course's symbolic path: second-order transfer, inertia, equations of motion --------
def _engine_models():
    from flexmbd.examples import slider_crank_dynamics, slider_crank_flex

    return {"consistent": slider_crank_dynamics.build_model("consistent"),
            "lumped, gravity": slider_crank_dynamics.build_model("lumped", gravity=True),
            "one flexible beam": slider_crank_flex.build_model(1)}


@pytest.mark.parametrize("name", ["consistent", "lumped, gravity", "one flexible beam"])
def test_symbolic_dynamics_equal_the_engine_at_random_states(name):
    model = _engine_models()[name]
    rng = np.random.default_rng(7)
    x_sym = list(symbolic.coordinate_symbols(model))
    xd_sym = list(symbolic.coordinate_symbols(model, "xd"))
    qd_sym = list(symbolic.generalized_symbols(model, "d"))
    qdd_sym = list(symbolic.generalized_symbols(model, "dd"))
    F_qq, E_qq = symbolic.second_order_transfer(model)
    functions = symbolic.numeric_function(
        [x_sym, xd_sym, qd_sym, qdd_sym],
        [sp.Matrix(F_qq.reshape(model.n_coordinates, model.n_dof**2)),
         sp.Matrix(E_qq.reshape(model.n_deformations, model.n_dof**2)),
         symbolic.mass_matrix(model), symbolic.velocity_inertia(model),
         symbolic.reduced_mass_matrix(model), symbolic.driving_forces(model)])
    for _ in range(3):
        q = rng.uniform(-1, 1, model.n_dof) * [3.0, 2e-3, 2e-3][:model.n_dof]
        qd = rng.uniform(-1, 1, model.n_dof) * [150.0, 5.0, 5.0][:model.n_dof]
        qdd = rng.uniform(-1, 1, model.n_dof) * [100.0, 5e3, 5e3][:model.n_dof]
        laws = {label: fm.Polynomial(q[j], qd[j], qdd[j]) for j, label in
                enumerate(model.q_labels)}
        run = fm.inverse_dynamics(model, [0.0], inputs=laws)
        x, xd = np.asarray(run.x)[0], fm.velocities(model, np.asarray(run.x)[0], qd)
        got = [np.asarray(a, dtype=float) for a in functions(x, xd, qd, qdd)]
        F2, E2 = fm.second_order_transfer(model, x)
        M, h, _ = fm.engine.Workspace(model).mass(x, xd)
        expected = [F2.reshape(model.n_coordinates, -1), E2.reshape(model.n_deformations, -1),
                    M, h[:, None], fm.reduced_mass_matrix(model, x),
                    np.asarray(run.driving)[0][:, None]]
        for g, e in zip(got, expected, strict=True):
            np.testing.assert_allclose(g, e, rtol=1e-12, atol=1e-12 * max(1.0, np.abs(e).max()))


def test_the_course_symbolic_steps():
    from flexmbd.examples import slider_crank_dynamics, symbolic_course
    from flexmbd.examples.slider_crank_kinematics import closed_form

    x_p, y_q, xd_p = sp.symbols("x_p y_q xdot_p", real=True)
    assert sp.simplify(symbolic_course.sliding_bar_velocity() + x_p * xd_p / y_q) == 0
    phi2, F_q, F_qq = symbolic_course.slider_transfer()
    assert symbolic_course.mass_difference() == sp.zeros(1, 1)
    rng = np.random.default_rng(3)
    for angle in rng.uniform(-np.pi, np.pi, 4):
        _, first, second = closed_form(angle, slider_crank_dynamics.L1, slider_crank_dynamics.L2)[
            "x5.1"]
        assert float(F_q.subs(phi2, angle)) == pytest.approx(first, abs=1e-14)
        assert float(F_qq.subs(phi2, angle)) == pytest.approx(second, abs=1e-13)
        state = (angle, *rng.uniform(-100, 100, 2))
        engine = fm.inverse_dynamics(slider_crank_dynamics.build_model(), [0.0],
                                     inputs={"x2.1": fm.Polynomial(*state)})
        tau = symbolic_course.torque_at(*state, slider_crank_dynamics.M2,
                                        slider_crank_dynamics.M5)
        assert tau == pytest.approx(float(np.asarray(engine.driving)[0, 0]), rel=1e-12, abs=1e-12)


def test_the_generated_flexible_slider_crank_reproduces_the_engine():
    from flexmbd.examples import symbolic_course

    _, generated, engine, _ = symbolic_course.flexible_generated(revolutions=0.25, points=21)
    assert np.abs(engine).max() > 5e-3  # the rod really bends in this quarter revolution
    np.testing.assert_allclose(generated, engine, atol=1e-8, rtol=0)


def test_mass_symbols_carry_into_the_gravity_load():
    from flexmbd.examples import slider_crank_dynamics

    model = slider_crank_dynamics.build_model(gravity=True)
    m2, m5 = sp.symbols("m2 m5", positive=True)
    tau = symbolic.driving_forces(model, element_masses={2: m2}, nodal_masses={5: m5})[0]
    numbers = {m2: slider_crank_dynamics.M2, m5: slider_crank_dynamics.M5}
    x = fm.solve_position(model, np.array([0.7]))
    values = dict(zip(symbolic.coordinate_symbols(model), x, strict=True))
    values.update({symbolic.generalized_symbols(model, "d")[0]: 3.0,
                   symbolic.generalized_symbols(model, "dd")[0]: 2.0, **numbers})
    run = fm.inverse_dynamics(model, [0.0], inputs={"x2.1": fm.Polynomial(0.7, 3.0, 2.0)})
    assert float(tau.xreplace(values)) == pytest.approx(float(run.driving[0, 0]), rel=1e-12)
    assert tau.xreplace({m2: 0, m5: 0}) == 0  # no mass, no torque: gravity scales with them
