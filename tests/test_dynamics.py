"""Reduced equations, inverse dynamics and reactions against independent derivations."""

import math

import numpy as np
import pytest
import sympy as sp

import flexmbd as fm

from . import reference

L1, L2 = 0.15, 0.30
M1, M2, M5 = 0.05, 0.06676, 0.03338  # crank, rod (uniform), slider [kg]
GRAVITY = (0.0, -9.81)


def rigid_slider_crank(formulation="consistent", gravity=GRAVITY, law=None):
    b = fm.ModelBuilder("slider-crank")
    b.add_node(1, 0.0, 0.0).add_node(3, L1, 0.0).add_node(5, L1 + L2, 0.0)
    b.add_rigid_beam(1, 1, 2, 3).add_rigid_beam(2, 3, 4, 5)
    b.fix(1).fix(5, "y")
    b.input_coordinate(2, law=law or fm.Polynomial(0.0, 150.0))
    b.set_mass(1, M1 / L1, formulation).set_mass(2, M2 / L2, formulation)
    b.add_point_mass(5, M5)
    b.set_gravity(*gravity)
    return b.build()


@pytest.fixture(scope="module")
def lagrange_torque():
    """Driving torque ``tau(phi, omega, alpha)`` from Lagrange's equation, by SymPy."""
    t = sp.symbols("t")
    phi = sp.Function("phi")(t)
    gx, gy = GRAVITY
    a = sp.Matrix([L1 * sp.cos(phi), L1 * sp.sin(phi)])
    psi = -sp.asin(L1 * sp.sin(phi) / L2)
    b = sp.Matrix([L1 * sp.cos(phi) + L2 * sp.cos(psi), 0])
    rod_centre, crank_centre = (a + b) / 2, a / 2
    kinetic = (sp.Rational(1, 2) * (M1 * L1**2 / 3) * phi.diff(t) ** 2
               + sp.Rational(1, 2) * M2 * rod_centre.diff(t).dot(rod_centre.diff(t))
               + sp.Rational(1, 2) * (M2 * L2**2 / 12) * psi.diff(t) ** 2
               + sp.Rational(1, 2) * M5 * b.diff(t).dot(b.diff(t)))
    g = sp.Matrix([gx, gy])
    potential = -(M1 * g.dot(crank_centre) + M2 * g.dot(rod_centre) + M5 * g.dot(b))
    lagrangian = kinetic - potential
    tau = lagrangian.diff(phi.diff(t)).diff(t) - lagrangian.diff(phi)
    p, w, al = sp.symbols("p w al")
    tau = tau.subs(phi.diff(t, 2), al).subs(phi.diff(t), w).subs(phi, p)
    return sp.lambdify((p, w, al), tau, "numpy")


@pytest.mark.parametrize("formulation", ["consistent", "lumped"])
@pytest.mark.parametrize(("omega", "alpha"), [(150.0, 0.0), (20.0, 300.0)])
def test_driving_torque_matches_lagrange(lagrange_torque, formulation, omega, alpha):
    model = rigid_slider_crank(formulation)
    x = np.array(model.x0)
    scale = M2 * L1 * L1 * max(omega**2, abs(alpha))
    for phi in np.linspace(0.0, 2 * math.pi, 25):
        terms = reference.terms(model, np.array([phi]), np.array([omega]), x_guess=x)
        x = terms.x
        tau = reference.driving_forces(terms, np.array([alpha]))[0]
        expected = lagrange_torque(phi, omega, alpha)
        assert tau == pytest.approx(expected, rel=1e-9, abs=1e-9 * scale)


def test_lumped_and_consistent_reduced_mass_agree():
    consistent, lumped = rigid_slider_crank("consistent"), rigid_slider_crank("lumped")
    x = fm.solve_position(consistent, np.array([0.9]))
    m_c, m_l = fm.reduced_mass_matrix(consistent, x), fm.reduced_mass_matrix(lumped, x)
    np.testing.assert_allclose(m_l, m_c, rtol=1e-13)
    assert not np.allclose(fm.mass_matrix(consistent, x), fm.mass_matrix(lumped, x))


@pytest.mark.parametrize("formulation", ["consistent", "lumped"])
def test_reactions_balance_linear_momentum(formulation):
    """Support reactions plus gravity equal the rate of linear momentum of all bodies."""
    omega, alpha = 40.0, 500.0
    model = rigid_slider_crank(formulation)
    phi = 1.1
    run = fm.inverse_dynamics(model, [0.0], inputs={"x2.1": fm.Polynomial(phi, omega, alpha)})
    nodal = run.reactions[0]
    # centres of mass accelerations: closed-form positions differentiated twice by
    # central differences with Richardson extrapolation (error of order h^4)

    def centres(s):
        p = phi + omega * s + 0.5 * alpha * s * s
        a = np.array([L1 * math.cos(p), L1 * math.sin(p)])
        psi = -math.asin(L1 * math.sin(p) / L2)
        b = np.array([L1 * math.cos(p) + L2 * math.cos(psi), 0.0])
        return np.concatenate([a / 2, (a + b) / 2, b])

    def second_difference(h):
        return (centres(h) - 2 * centres(0) + centres(-h)) / h**2

    h = 1e-3
    acc = (4 * second_difference(h / 2) - second_difference(h)) / 3
    masses = np.repeat([M1, M2, M5], 2)
    momentum_rate = (masses * acc).reshape(3, 2).sum(axis=0)
    weight = (M1 + M2 + M5) * np.array(GRAVITY)
    support = nodal[[model.coordinate_index("x1.1"), model.coordinate_index("x1.2")]]
    support = support + np.array([0.0, nodal[model.coordinate_index("x5.2")]])
    # 1e-6: the limit of the finite differences, whose own error here is about 6e-8
    np.testing.assert_allclose(support + weight, momentum_rate, rtol=1e-6)
    # the drive's torque on the input coordinate is the inverse-dynamics torque, and the
    # stresses and loads are those of the dense nodal equilibrium (THEORY 8)
    assert nodal[model.coordinate_index("x2.1")] == pytest.approx(run.driving[0, 0],
                                                                   rel=1e-10)
    terms = reference.terms(model, np.array([phi]), np.array([omega]))
    sigma, loads = reference.reactions(model, terms, np.array([alpha]))
    np.testing.assert_allclose(run.sigma[0], sigma, rtol=1e-10, atol=1e-10 * np.abs(sigma).max())
    np.testing.assert_allclose(nodal, loads, rtol=1e-10, atol=1e-10 * np.abs(loads).max())


@pytest.mark.parametrize("formulation", ["consistent", "lumped"])
def test_inverse_dynamics_over_a_revolution_matches_lagrange(lagrange_torque, formulation):
    omega0, alpha = 20.0, 300.0  # phi = omega0 t + alpha t^2 / 2
    t_rev = (-omega0 + math.sqrt(omega0**2 + 4 * math.pi * alpha)) / alpha
    model = rigid_slider_crank(formulation, law=fm.Polynomial(0.0, omega0, alpha))
    result = fm.inverse_dynamics(model, np.linspace(0.0, t_rev, 90))
    assert result.success and result["x2.1"][-1] == pytest.approx(2 * math.pi)
    omega = omega0 + alpha * result.t
    expected = lagrange_torque(result["x2.1"], omega, alpha)
    scale = np.max(np.abs(expected))
    np.testing.assert_allclose(result["f2.1"], expected, rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(result.driving[:, 0], result["f2.1"], rtol=1e-12)
    assert "f1.2" in result.columns() and "f5.2" in result.columns()


def test_inverse_dynamics_failures():
    b = fm.ModelBuilder("rod shorter than the crank")  # cannot pass phi = 30 deg
    b.add_node(1, 0, 0).add_node(3, 1, 0).add_node(5, 1.5, 0)
    b.add_rigid_beam(1, 1, 2, 3).add_rigid_beam(2, 3, 4, 5).fix(1).fix(5, "y")
    b.input_coordinate(2, law=fm.Polynomial(0.0, 1.0))
    massless = b.build()
    with pytest.raises(fm.ModelError, match="no mass"):
        fm.inverse_dynamics(massless, [0.0, 1.0])
    b.set_mass(2, 1.0)
    model = b.build()
    times = np.linspace(0.0, 3.0, 31)
    result = fm.inverse_dynamics(model, times, on_failure="return")
    assert not result.success and isinstance(result.error, fm.SimulationError)
    assert 0 < len(result.t) < len(times) and result.t[-1] < math.pi / 6
    assert math.pi / 6 - 0.1 <= result.error.time <= math.pi / 6 + 0.1
    with pytest.raises(ValueError, match="times: must increase strictly"):
        fm.inverse_dynamics(model, [1.0, 0.5])
