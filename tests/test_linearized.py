"""Linearized analyses (THEORY 9) against closed forms, an elastica, a rotating-beam
Ritz solution, finite differences of the engine's driving loads and a simulation."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import scipy.linalg as linalg
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

import flexmbd as fm
from examples.slider_crank_flex import build_model
from flexmbd.analysis.linearization import equilibrium_state, linearize
from flexmbd.analysis.modes import buckling, compliance, modes_along, vibration_modes
from flexmbd.analysis.statespace import state_space
from flexmbd.analysis.statics import static_equilibrium
from flexmbd.engine import Workspace

from .models import two_beam_column

L, EI, RHO_A = 1.0, 2.0, 0.5
#: (beta_n L) of the first three bending modes of a clamped-free beam
CLAMPED_FREE = np.array([1.8751040687119611, 4.6940911329741745, 7.8547574382376126])


def beam_line(n, *, ends=("clamped", "free"), deformations=(2, 3), EA=1e6, second_order=False,
              tip=None, hub=False):
    """``n`` equal beams along x from 0 to L; node 1 and its angle node 2 at x = 0, the
    tip at node 2n+1. ``hub``: node 2 is a prescribed angle (a rotor)."""
    b = fm.ModelBuilder(f"{n} beams")
    for k in range(n + 1):
        b.add_node(2 * k + 1, L * k / n, 0.0)
    for k in range(n):
        b.add_beam(k + 1, 2 * k + 1, 2 * k + 2, 2 * k + 3, 2 * k + 4, second_order=second_order)
        b.dynamic_deformation(k + 1, *deformations)
        b.set_stiffness(k + 1, axial=EA, bending=EI).set_mass(k + 1, RHO_A)
    b.fix(1)
    if hub:
        b.input_coordinate(2)
    elif ends[0] == "clamped":
        b.fix(2)
    if ends[1] == "pinned":
        b.fix(2 * n + 1)
    elif ends[1] == "roller":
        b.fix(2 * n + 1, "y")
    if tip is not None:
        b.add_force(2 * n + 1, *tip)
    return b.build()


def frequencies(model, count=3, **state):
    return np.sqrt(vibration_modes(linearize(model, **state), count).omega2)


def test_clamped_free_bending_frequencies_converge_to_the_closed_form():
    exact = CLAMPED_FREE**2 * np.sqrt(EI / (RHO_A * L**4))
    error8 = np.abs(frequencies(beam_line(8)) / exact - 1)
    error16 = np.abs(frequencies(beam_line(16)) / exact - 1)
    assert error8[0] < 1e-3 and np.all(error8 < 1e-3)
    assert np.all(error16 < error8 / 8)  # O(n^-4)


def test_low_frequencies_keep_their_digits_next_to_stiff_axial_ones():
    """200 axially stiff beams (EA/EI = 1.2e6 / L^2, axial frequencies 1e5 times the
    first): the first bending frequency to 1e-9 of the closed form; reducing by M0
    loses 1e-5 of it to rounding (THEORY 9, modes.py)."""
    model = beam_line(200, deformations=(1, 2, 3), EA=1.2e6 * EI, second_order=True)
    exact = CLAMPED_FREE[0] ** 2 * np.sqrt(EI / (RHO_A * L**4))
    omega2 = vibration_modes(linearize(model), 2).omega2
    assert np.sqrt(omega2[0]) == pytest.approx(exact, rel=1e-9)


def test_pinned_pinned_bending_frequencies_converge_to_the_closed_form():
    exact = (np.pi * np.arange(1, 4)) ** 2 * np.sqrt(EI / (RHO_A * L**4))
    error8 = np.abs(frequencies(beam_line(8, ends=("pinned", "roller"))) / exact - 1)
    error16 = np.abs(frequencies(beam_line(16, ends=("pinned", "roller"))) / exact - 1)
    assert error8[0] < 1e-3
    assert np.all(error16 < error8 / 8)


def axial_bar(n, EA=3e4):
    """``n`` trusses along x, clamped at node 1, free at the end, moving along x only."""
    b = fm.ModelBuilder("bar")
    for k in range(n + 1):
        b.add_node(k + 1, L * k / n, 0.0)
    for k in range(n):
        b.add_truss(k + 1, k + 1, k + 2).dynamic_deformation(k + 1)
        b.set_stiffness(k + 1, axial=EA).set_mass(k + 1, RHO_A)
    b.fix(1)
    for k in range(2, n + 2):
        b.fix(k, "y")
    return b.build(), EA


def test_axial_frequencies_of_a_free_clamped_bar_converge_to_the_closed_form():
    errors = []
    for n in (8, 16, 32):
        model, EA = axial_bar(n)
        exact = (2 * np.arange(1, 4) - 1) * np.pi / 2 * np.sqrt(EA / RHO_A) / L
        errors.append(np.abs(frequencies(model) / exact - 1))
    assert np.all(errors[1] < errors[0] / 3.5) and np.all(errors[2] < errors[1] / 3.5)  # O(n^-2)
    assert errors[2][0] < 1e-3


def test_a_free_pivot_gives_a_rigid_mode_and_the_pinned_free_frequency():
    """A beam on a free pivot (its angle dynamic): K0 is singular, so the generalized
    solver runs. omega = 0 for the swing, then the first elastic mode of a pinned-free
    beam, (beta L)^2 = 3.9266^2."""
    n = 8
    b = fm.ModelBuilder("free pivot")
    for k in range(n + 1):
        b.add_node(2 * k + 1, L * k / n, 0.0)
    for k in range(n):
        b.add_beam(k + 1, 2 * k + 1, 2 * k + 2, 2 * k + 3, 2 * k + 4).dynamic_deformation(
            k + 1, 2, 3).set_stiffness(k + 1, axial=1e6, bending=EI).set_mass(k + 1, RHO_A)
    modes = vibration_modes(linearize(b.fix(1).dynamic_coordinate(2).build()), 2)
    # the swing's omega^2 is rounding of either sign, whatever the CPU: reported as 0
    assert modes.omega2[0] == 0.0 and modes.frequencies[0] == 0.0
    omega = np.sqrt(modes.omega2)
    assert omega[1] == pytest.approx(3.926602312047919**2 * np.sqrt(EI / (RHO_A * L**4)),
                                     rel=1e-4)


def test_a_singular_stiffness_that_factors_by_rounding_is_not_taken_as_regular():
    """A singular K = v v^T + diag(0, 0, 2) whose Cholesky factorization succeeds with a
    pivot of rounding size (2^-54, one unit in the last place of its diagonal): the
    reduced path would give a rigid mode of omega^2 ~ 1e-16 and swamp the other
    eigenvalues, so it must take the general one. Every number is exact in binary, so
    every BLAS kernel factors it alike."""
    from flexmbd.analysis.eigen import cholesky, well_posed

    v = np.array([1.0, 0.5, 0.75])
    K = np.outer(v, v) + np.diag([0.0, 0.0, 2.0])
    K[1, 1] += 2.0**-54
    factor = cholesky(K)
    assert factor[1, 1] ** 2 == 2.0**-54
    assert factor is not None and not well_posed(factor, K)
    assert well_posed(np.linalg.cholesky(np.diag([1.0, 1e-10])), np.diag([1.0, 1e-10]))


def test_a_column_beyond_its_euler_load_vibrates_with_negative_omega_squared():
    """Pinned-pinned under twice its Euler load: K0 + G0 is indefinite and the first
    omega^2 = (pi/L)^2 ((pi/L)^2 EI - P) / rhoA = -(pi/L)^4 EI / rhoA."""
    model = beam_line(8, ends=("pinned", "roller"), deformations=(1, 2, 3), second_order=True,
                      tip=(-2 * np.pi**2 * EI / L**2, 0.0))
    modes = vibration_modes(linearize(model), 2)
    assert modes.omega2[0] == pytest.approx(-(np.pi / L) ** 4 * EI / RHO_A, rel=1e-4)
    assert modes.frequencies[0] < 0 < modes.frequencies[1]


@pytest.mark.parametrize("ends, effective_length", [(("clamped", "free"), 2 * L),
                                                     (("pinned", "roller"), L)])
def test_euler_buckling_loads_within_a_thousandth_at_eight_beams(ends, effective_length):
    """Columns of second-order beams under a unit axial load at the tip: the smallest
    load factor is the Euler load pi^2 EI / (K L)^2."""
    model = beam_line(8, ends=ends, deformations=(1, 2, 3), second_order=True,
                      tip=(-1.0, 0.0))
    factors = buckling(linearize(model), 2).factors
    assert abs(factors[0] / (np.pi**2 * EI / effective_length**2) - 1) < 1e-3


def elastica_tip(k):
    """Tip of an inextensible cantilever of unit length under a transverse tip load with
    ``P L^2 / EI = k``: shooting on ``theta'' = -k cos(theta)``, ``theta(0) = 0``,
    ``theta'(1) = 0``. Returns ``(x, y)`` of the tip, deflected towards +y."""
    def shoot(curvature0):
        end = solve_ivp(lambda s, y: [y[1], -k * np.cos(y[0]), np.cos(y[0]), np.sin(y[0])],
                        (0.0, 1.0), [0.0, curvature0, 0.0, 0.0], rtol=1e-12, atol=1e-12)
        return end.y[:, -1]

    end = shoot(brentq(lambda c: shoot(c)[1], 0.0, k + 1e-9))
    return end[2], end[3]


@pytest.mark.parametrize("k", [1, 2, 5])
def test_large_deflection_cantilever_matches_the_elastica(k):
    """Tip within 1e-3 L at 16 large-deflection beams (PLBEAM2, exact end rotations and
    the arc length): they converge as n^-4, 7e-7 L at P L^2/EI = 5."""
    tip = cantilever_tip(16, k, second_order=True)
    x_tip, y_tip = elastica_tip(k)
    assert np.hypot(tip[0] - x_tip, tip[1] + y_tip) < 1e-3 * L


def test_the_course_beam_follows_the_elastica_to_second_order():
    """The course's beam (e2 = l sin theta) softens a bend by theta^2/6: its error at
    P L^2/EI = 5 falls fourfold per halving of the beams, 1.3e-3 L at 16 beams."""
    x_tip, y_tip = elastica_tip(5)
    errors = [np.hypot(tip[0] - x_tip, tip[1] + y_tip) / L
              for tip in (cantilever_tip(n, 5, second_order=False) for n in (16, 32))]
    assert errors[0] / errors[1] == pytest.approx(4.0, rel=0.05)


def cantilever_tip(n, k, second_order):
    """``(x, y)`` [m] of the tip of an ``n``-beam cantilever (axially stiff) under the
    transverse tip load ``-k EI / L^2``."""
    model = beam_line(n, deformations=(1, 2, 3), EA=1e9, tip=(0.0, -k * EI / L**2),
                      second_order=second_order)
    result = static_equilibrium(model)
    return np.array([result[f"x{2 * n + 1}.1"][-1], result[f"x{2 * n + 1}.2"][-1]])


def test_load_steps_follow_the_increment_and_give_stresses_in_equilibrium():
    n = 8
    model = beam_line(n, deformations=(1, 2, 3), EA=1e9)
    steps = static_equilibrium(model, load_increment={f"x{2 * n + 1}.2": -2 * EI}, steps=4)
    assert np.allclose(steps["load"], [0, 0.25, 0.5, 0.75, 1.0])
    assert steps["x17.2"][0] == pytest.approx(0.0, abs=1e-12)
    assert np.all(np.diff(steps["x17.2"]) < 0)
    # the clamp carries the tip load and its moment about the clamp
    f = steps.reactions[-1, list(model.nodes[1].coordinates)]
    assert f == pytest.approx([0.0, 2 * EI], abs=1e-6)
    moment = steps.reactions[-1, model.nodes[2].coordinates[0]]
    assert moment == pytest.approx(2 * EI * steps["x17.1"][-1], rel=1e-8)
    # equilibrium to the rounding of EA e1 (EA = 1e9 N: 1e-16 m of position is 1e-7 N)
    assert np.max(np.abs(steps.driving[-1])) < 1e-6 * 2 * EI


def test_a_load_the_structure_cannot_carry_names_the_last_converged_load():
    """A beam on a free pivot (its angle a dynamic degree of freedom) is a mechanism: no
    tangent, and the failure says how far the loads got."""
    b = fm.ModelBuilder("pendulum").add_node(1, 0, 0).add_node(3, 1, 0)
    b.add_beam(1, 1, 2, 3, 4).dynamic_deformation(1).set_stiffness(1, axial=1e3, bending=EI)
    model = b.fix(1).dynamic_coordinate(2).add_force(3, 0.0, -1.0).build()
    with pytest.raises(fm.ConvergenceError, match="last converged: the initial loads"):
        static_equilibrium(model)


def ritz_rotating_cantilever(speed, terms=10):
    """First in-plane frequency [rad/s] of a cantilever of unit length spinning at
    ``speed`` about its clamped end: Rayleigh-Ritz with ``x^2 .. x^(terms+1)`` on
    ``EI w'''' - (T w')' - rhoA speed^2 w = rhoA omega^2 w``, ``T = rhoA speed^2 (L^2 -
    x^2)/2``."""
    P = np.polynomial.polynomial
    basis = [np.r_[np.zeros(k + 2), 1.0] for k in range(terms)]

    def integral(c):
        antiderivative = P.polyint(c)
        return P.polyval(L, antiderivative) - P.polyval(0.0, antiderivative)

    tension = RHO_A * speed**2 * np.array([L**2 / 2, 0.0, -0.5])
    K, M = np.zeros((terms, terms)), np.zeros((terms, terms))
    for i, a in enumerate(basis):
        for j, b in enumerate(basis):
            K[i, j] = (EI * integral(P.polymul(P.polyder(a, 2), P.polyder(b, 2)))
                       + integral(P.polymul(tension, P.polymul(P.polyder(a), P.polyder(b))))
                       - RHO_A * speed**2 * integral(P.polymul(a, b)))
            M[i, j] = RHO_A * integral(P.polymul(a, b))
    return np.sqrt(linalg.eigh(K, M, eigvals_only=True)[0])


def test_centrifugal_stiffening_of_a_rotating_cantilever():
    model = beam_line(8, hub=True, second_order=True)
    first = []
    for speed in (0.0, 5.0, 10.0):
        qd = np.zeros(model.n_dof)
        qd[model.q_labels.index("x2.1")] = speed
        first.append(frequencies(model, 1, qd=qd)[0])
        assert first[-1] == pytest.approx(ritz_rotating_cantilever(speed), rel=1e-4)
    assert first[0] < first[1] < first[2]


def test_the_linearized_matrices_are_the_tangent_of_the_driving_loads():
    """K0 + N0 + G0 and C0 + D0 against central differences of the engine's inverse
    dynamics, at a random moving, accelerating and deformed state of a flexible rotor
    with damping."""
    b = fm.ModelBuilder("damped rotor")
    b.add_node(1, 0, 0).add_node(3, 0.5, 0).add_node(5, 1.0, 0.1)
    for k in range(2):
        b.add_beam(k + 1, 2 * k + 1, 2 * k + 2, 2 * k + 3, 2 * k + 4, second_order=True)
        b.dynamic_deformation(k + 1).set_stiffness(k + 1, axial=50.0, bending=EI)
        b.set_mass(k + 1, RHO_A).set_damping(k + 1, axial=0.3, bending=0.02)
    model = b.fix(1).input_coordinate(2).add_point_mass(5, 0.2).build()
    rng = np.random.default_rng(1)
    engine = Workspace(model)
    q = np.r_[0.3, rng.normal(scale=0.02, size=model.n_dof - 1)]
    qd, qdd = rng.normal(size=model.n_dof), rng.normal(size=model.n_dof)
    x = engine.positions(q)
    lin = linearize(model, x, qd, qdd)

    def driving(q_, qd_):
        return equilibrium_state(engine, engine.positions(q_, x), qd_, qdd,
                                 np.zeros(model.n_coordinates))["driving"]

    unit = np.eye(model.n_dof)
    h = 1e-6
    stiffness = np.stack([(driving(q + h * u, qd) - driving(q - h * u, qd)) / (2 * h)
                          for u in unit], axis=1)
    damping = np.stack([(driving(q, qd + u) - driving(q, qd - u)) / 2 for u in unit], axis=1)
    K, C = lin.K0 + lin.N0 + lin.G0, lin.C0 + lin.D0
    assert np.abs(stiffness - K).max() < 1e-7 * np.abs(K).max()
    assert np.abs(damping - C).max() < 1e-9 * np.abs(C).max()
    assert np.abs(lin.N0).max() > 1e-2 * np.abs(K).max()  # the inertia terms were exercised


def test_static_states_have_no_inertia_terms():
    lin = linearize(beam_line(4, tip=(0.0, -1.0)))
    assert not np.any(lin.N0) and not np.any(lin.C0)


def test_slider_crank_rod_frequencies_vary_smoothly_along_a_revolution():
    model = build_model(4)
    times = np.linspace(0.0, 2 * np.pi / 150.0, 61)
    along = modes_along(fm.inverse_dynamics(model, times), 2)
    first = along.frequencies[:, 0]
    assert 100.0 < first.min() < first.max() < 160.0
    assert first.max() - first.min() > 5.0  # the rod's axial load changes it
    assert np.max(np.abs(np.diff(first, 2))) < 0.05 * (first.max() - first.min())
    assert first[0] == pytest.approx(first[-1], rel=1e-9)  # the motion is periodic


def test_a_frozen_slider_crank_vibrates_at_its_first_eigenfrequency():
    """Crank held at 1 rad: a free vibration started along the first mode (amplitude 1e-6
    of the rod length) has the mode's period."""
    model = build_model(2, omega=0.0)
    start = fm.Polynomial(1.0)
    frozen = fm.kinematic_analysis(model, [0.0], inputs={"x2.1": start})
    lin = linearize(model, frozen.x[0])
    modes = vibration_modes(lin, 1)
    omega = np.sqrt(modes.omega2[0])
    shape = 1e-6 * 0.3 * modes.shapes[:, 0] / np.abs(modes.shapes[:, 0]).max()
    initial = {model.q_labels[j]: (value, 0.0) for j, value in zip(lin.dynamic, shape,
                                                                   strict=True)}
    period = 2 * np.pi / omega
    times = np.linspace(0.0, 10 * period, 2001)
    run = fm.simulate(model, times, inputs={"x2.1": start}, initial=initial, rtol=1e-10,
                      atol=1e-16, method="Radau")
    signal = run.q[:, lin.dynamic[np.argmax(np.abs(shape))]]
    signal = signal - signal.mean()
    crossings = times[:-1][(signal[:-1] < 0) & (signal[1:] >= 0)]
    measured = np.mean(np.diff(crossings))
    assert measured == pytest.approx(period, rel=2e-3)


def test_state_space_gain_is_the_compliance_and_poles_the_frequencies():
    model = beam_line(6, deformations=(1, 2, 3), EA=1e4)
    lin = linearize(model)
    labels = ["x13.1", "x13.2", "x14.1"]
    system = state_space(lin, labels, labels)
    np.testing.assert_allclose(system.static_gain(), compliance(lin, labels), rtol=1e-8,
                               atol=1e-14)
    # the tip compliance of a cantilever: L^3/(3 EI) transverse, L/EA axial
    assert compliance(lin, ["x13.2"])[0, 0] == pytest.approx(L**3 / (3 * EI), rel=1e-9)
    assert compliance(lin, ["x13.1"])[0, 0] == pytest.approx(L / 1e4, rel=1e-9)
    poles = np.sort(np.abs(np.linalg.eigvals(system.A).imag))[::2]
    np.testing.assert_allclose(poles, np.sqrt(vibration_modes(lin).omega2), rtol=1e-8)
    damped = state_space(lin, labels[:1], rate_outputs=labels[:1], damping_ratio=0.02)
    real = np.linalg.eigvals(damped.A)
    np.testing.assert_allclose(-real.real / np.abs(real), 0.02, rtol=1e-6)


def _response(system, omega):
    """``C (i w - A)^-1 B + D`` ``(nw, no, ni)`` by direct solves."""
    eye = np.eye(system.A.shape[0])
    return np.array([system.C @ np.linalg.solve(1j * w * eye - system.A, system.B) + system.D
                     for w in omega])


def test_a_truncated_state_space_keeps_the_static_gain_and_the_low_modes():
    from scipy import signal

    model = beam_line(8, deformations=(1, 2, 3), EA=1e4)
    lin = linearize(model)
    full = state_space(lin, ["x17.2", "x17.1"], ["x17.2"], ["x17.2"], damping_ratio=0.01)
    reduced = full.truncated(3)
    assert reduced.A.shape == (6, 6)
    np.testing.assert_allclose(reduced.static_gain(), full.static_gain(), rtol=1e-12,
                               atol=1e-15)
    omega = np.sqrt(vibration_modes(lin).omega2)
    poles = np.sort(np.abs(np.linalg.eigvals(reduced.A)))[::2]
    np.testing.assert_allclose(poles, np.sort(np.abs(np.linalg.eigvals(full.A)))[:6:2],
                               rtol=1e-10)
    # below the first dropped mode the responses agree; the error grows towards it
    band = np.linspace(0.0, 0.5 * omega[3], 200)
    near, exact = _response(reduced, band)[:, 0, 0], _response(full, band)[:, 0, 0]
    assert np.max(np.abs(near - exact)) < 1e-3 * abs(exact[0])
    # scipy.signal takes the reduced model; the full one (58 states) it cannot convert
    _, magnitude, _ = signal.bode(signal.StateSpace(reduced.A, reduced.B[:, :1], reduced.C[:1],
                                                    reduced.D[:1, :1]), band[1:])
    np.testing.assert_allclose(magnitude, 20 * np.log10(np.abs(near[1:])), atol=1e-6)
    with pytest.raises(fm.ArgumentError, match="count"):
        full.truncated(0)


def test_a_degree_of_freedom_without_mass_is_named():
    """A point mass on the tip only: the rotations of the tip's inner beam ends have no
    mass, and the frequencies cannot be computed; the message names one."""
    b = fm.ModelBuilder("massless beam")
    b.add_node(1, 0.0, 0.0).add_node(3, L, 0.0)
    b.add_beam(1, 1, 2, 3, 4).dynamic_deformation(1, 2, 3).set_stiffness(1, bending=EI)
    with pytest.warns(fm.ModelWarning, match="no mass moves with e1.3"):   # said at build
        model = b.fix(1).fix(2).add_point_mass(3, 1.0).build()
    with pytest.raises(fm.SingularConfigurationError, match="moves without mass"):
        vibration_modes(linearize(model))
    with pytest.raises(fm.SingularConfigurationError, match="moves without mass"):
        modes_along(fm.kinematic_analysis(model, [0.0, 1.0]), 1)


def assembled_equals_element_by_element(model: fm.Model, rng):
    """Workspace.assembly against the per-element kernels at a random configuration near
    ``x0``: ``e``, ``D_x``, ``D_x A`` and the stress-weighted Hessian times ``A``; returns the
    assembly for checks of the elastic law."""
    from .elementwise import deformations_and_jacobian, dense_hessian, quadratic_velocity

    x = model.x0 + 0.1 * rng.standard_normal(model.n_coordinates)
    sigma = rng.standard_normal(model.n_deformations)
    assembly = Workspace(model).assembly
    e, D_x = assembly.deformations_and_jacobian(x)
    e_each, D_x_each = deformations_and_jacobian(model, x)
    assert np.array_equal(e, e_each) and np.array_equal(D_x, D_x_each)
    assert np.array_equal(assembly.deformations(x), e_each)
    A = rng.standard_normal((model.n_coordinates, 4))
    assert np.allclose(assembly.jacobian_times(x, A), D_x_each @ A, rtol=1e-14, atol=1e-14)
    H_each = dense_hessian(model, x)
    assert np.array_equal(assembly.hessian(x), H_each)
    H = np.einsum("i,ijk->jk", sigma, H_each)
    assert np.allclose(assembly.stress_hessian_times(x, sigma, A), H @ A, rtol=1e-13,
                       atol=1e-13)
    # the quadratic velocity terms from the Hessians against the jets' own kernels
    xd = rng.standard_normal(model.n_coordinates)
    jets = quadratic_velocity(model, x, xd)
    assert np.allclose(assembly.quadratic_velocity(x, xd), jets, rtol=1e-12,
                       atol=1e-12 * np.abs(jets).max())
    return assembly


def test_the_assembled_arrays_equal_the_element_by_element_ones():
    """Workspace.assembly (every element in one core call, scattered by index maps) gives
    D_x, the stress Hessian and the elastic law's products of the per-element kernels,
    on a model of every element type at a random configuration."""
    b = fm.ModelBuilder("every element type")
    for n, (x, y) in {1: (0, 0), 3: (1, 0.2), 5: (2, -0.1), 7: (2.5, 0.6)}.items():
        b.add_node(n, x, y)
    b.add_truss(1, 1, 3).add_beam(2, 1, 2, 3, 4).add_beam(3, 3, 4, 5, 6, second_order=True)
    b.add_rigid_beam(4, 5, 6, 7).add_hinge(5, 4, 6).add_element(6, "spring-damper", (1, 7))
    b.release(1, 1).dynamic_deformation(2, 1, 2, 3).dynamic_deformation(3, 1, 2, 3)
    b.add_beam(7, 1, 2, 5, 6).release(7, 1, 2, 3)  # shares nodes 1, 2 with beam 2
    b.release(5, 1).fix(1).fix(2)
    for k, values in {1: {"axial": 3.0}, 2: {"axial": 5.0, "bending": 2.0},
                      3: {"axial": 7.0, "bending": 1.5}, 5: {"hinge": 0.5},
                      6: {"spring": 4.0}, 7: {"axial": 2.0, "bending": 1.0}}.items():
        b.set_stiffness(k, **values)
    b.set_damping(2, axial=0.3, bending=0.1).set_damping(6, spring=0.2)
    model = b.build()
    assert {e.type for e in model.elements.values()} == {
        t for t in fm.elements.ELEMENT_TYPES.values() if not t.is_spatial()}
    rng = np.random.default_rng(5)
    assembly = assembled_equals_element_by_element(model, rng)
    # the law's blocks: S = diag(EA/l0, EI/l0^3 [[4, -2], [-2, 4]], k) on the beam 2
    A = rng.standard_normal((model.n_deformations, 3))
    rows = [model.deformation_index(f"e2.{k}") for k in (1, 2, 3)]
    l0 = float(np.hypot(1.0, 0.2))
    S_beam = np.diag([5.0 / l0, 0, 0]) + 2.0 / l0**3 * np.array([[0, 0, 0], [0, 4, -2],
                                                                   [0, -2, 4]])
    assert np.allclose(assembly.law_times("S", A)[rows], S_beam @ A[rows], rtol=1e-14)
    spring = model.deformation_index("e6.1")
    assert assembly.law_times("C", A)[spring] == pytest.approx(0.2 * A[spring], rel=1e-14)
    assert not np.any(assembly.law_times("S", A)[model.deformation_index("e4.1")])


def test_the_assembled_arrays_equal_the_element_by_element_ones_in_space():
    """The same for a spatial model of every spatial element type (the Euler elements
    are added by the builder), and its elastic law: EA/l0, GIt/l0^3, EIy and EIz pairs."""
    b = fm.ModelBuilder("every spatial element type")
    for n, xyz in {1: (0, 0, 0), 3: (1, 0.2, 0.1), 5: (2, -0.1, 0.3)}.items():
        b.add_node(n, *xyz)
    b.add_spatial_beam(1, 1, 2, 3, 4, orientation=(0, 0, 1))
    b.add_spatial_beam(2, 3, 6, 5, 7, orientation=(0.2, 1, 0), bending_linked=False)
    b.add_spatial_truss(3, 1, 5).add_spatial_hinge(4, 4, 6, axis=(1, 1, 0))
    b.add_node(9, 2.5, 0.1, -0.2).add_element(5, "RBEAM", (5, 7, 9), orientation=(0, 0, 1))
    b.add_warping_beam(6, 1, 2, 10, 5, 7, 11, orientation=(0, 1, 1))
    b.release(1).release(2).release(3).release(4).release(5).release(6)
    for node in (1, 2, 3, 4, 5, 6, 7, 9, 10):
        b.fix(node)  # rotational nodes: lam1..3; the Euler elements solve for lam0
    b.set_stiffness(1, axial=5.0, torsion=0.7, bending_y=2.0, bending_z=3.0)
    b.set_stiffness(6, torsion=0.9, warping=0.4)
    b.set_stiffness(3, axial=1.0).set_stiffness(4, hinge=0.5, tilt_y=1.0, tilt_z=2.0)
    # beam 2 is released without stiffness or mass on purpose: it only adds its arrays
    with pytest.warns(fm.ModelWarning) as said:
        model = b.build()
    assert {str(w.message).split(" ")[0] for w in said} <= {"spatial", "warping", "no"}
    assert {e.type for e in model.elements.values()} == {
        t for t in fm.elements.ELEMENT_TYPES.values() if t.is_spatial()}
    rng = np.random.default_rng(6)
    assembly = assembled_equals_element_by_element(model, rng)
    A = rng.standard_normal((model.n_deformations, 2))
    rows = [model.deformation_index(f"e1.{k}") for k in range(1, 7)]
    l0 = float(np.linalg.norm([1, 0.2, 0.1]))
    pair = np.array([[4, -2], [-2, 4]]) / l0**3
    S_beam = np.zeros((6, 6))
    S_beam[0, 0], S_beam[1, 1] = 5.0 / l0, 0.7 / l0**3
    S_beam[2:4, 2:4], S_beam[4:6, 4:6] = 2.0 * pair, 3.0 * pair
    assert np.allclose(assembly.law_times("S", A)[rows], S_beam @ A[rows], rtol=1e-14)
    # the warping beam's (e7, e8): ECw/l0^5 [[4, -2], [-2, 4]] + GIt/(30 l0^3) [[4, 1], [1, 4]]
    warp = [model.deformation_index(f"e6.{k}") for k in (7, 8)]
    l0 = float(np.linalg.norm([2, -0.1, 0.3]))
    S_warp = 0.4 / l0**5 * np.array([[4, -2], [-2, 4]]) + 0.9 / (30 * l0**3) * np.array(
        [[4, 1], [1, 4]])
    assert np.allclose(assembly.law_times("S", A)[warp], S_warp @ A[warp], rtol=1e-14)


def test_the_layers_of_a_scatter_hold_each_index_once():
    from flexmbd.engine.assembly import _layers

    indices = np.random.default_rng(2).integers(0, 7, size=40)
    layers = _layers(indices)
    assert sorted(np.concatenate(layers)) == list(range(40))
    assert all(len(set(indices[layer])) == len(layer) for layer in layers)
    assert len(layers) == np.bincount(indices).max()


def test_a_few_lowest_modes_by_iteration_are_the_whole_spectrum_s(monkeypatch):
    """A few modes of a large model come from ARPACK on the factored stiffness: the same
    frequencies and shapes as the whole spectrum, for a symmetric stiffness (at rest) with
    pairs of equal frequencies (four round wires) and an unsymmetric one (a pivot turned
    by a moment of fixed direction, whose load stiffness is not symmetric)."""
    from flexmbd.examples import flexures

    from flexmbd.analysis import eigen as modes_module

    monkeypatch.setattr(modes_module, "FEW_MODES_FROM", 60)   # ARPACK for these sizes

    wires = flexures.wire_buckling().statics.linearization(0)
    from flexmbd import light

    hinge = light.run(flexures.HINGE_NODES, flexures.HINGE_ELEMENTS,
                      {1: {"fix": True}, 4: {"fix": True}, 3: {"moment": [0, 0, 0.02]}},
                      [dict(flexures.HINGE_LEAF, nbeams=8), flexures.HINGE_BODY],
                      {"loadsteps": 2, "silent": True}).statics.linearization()
    for lin, pairs in ((wires, True), (hinge, False)):
        nd = len(lin.dynamic)
        assert nd >= modes_module.FEW_MODES_FROM
        K = lin.block("K")
        symmetric = np.abs(K - K.T).max() <= modes_module.SYMMETRIC * np.abs(K).max()
        assert symmetric == pairs
        with warnings.catch_warnings(record=True) as caught:
            # where a multiple eigenvalue comes out of Arnoldi (unsymmetric) as a complex
            # pair (as the CPU's BLAS kernels round), LAPACK tells the modes, and says so
            warnings.simplefilter("always", fm.AnalysisWarning)
            few = fm.vibration_modes(lin, 6)
        assert (few.path.method == "arpack") == (not caught)
        assert all("complex pair" in str(w.message) for w in caught)
        assert not (pairs and caught)   # symmetric: Lanczos finds every copy of the pairs
        every = fm.vibration_modes(lin)
        np.testing.assert_allclose(few.frequencies, every.frequencies[:6], rtol=1e-10)
        overlap = np.abs(np.einsum("ik,ij,jk->k", few.shapes, lin.block("M0"),
                                   every.shapes[:, :6]))
        distinct = np.r_[True, np.diff(every.frequencies[:6]) > 1e-6 * every.frequencies[5]]
        distinct[:-1] &= distinct[1:]
        np.testing.assert_allclose(overlap[distinct], 1.0, atol=1e-8)
    assert abs(few.frequencies[0] - few.frequencies[1]) > 0   # the hinge has no pair
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", fm.AnalysisWarning)   # as above
        pair = fm.vibration_modes(wires, 6).frequencies
    assert pair[1] == pytest.approx(pair[0], rel=1e-9)      # the wires' sway pair, whole


def test_modes_too_stiff_for_the_reduction_stay_positive(monkeypatch):
    """A cross hinge of 0.1 x 0.1 mm leaves of 10 beams spans 1e8 in frequency: the
    stiffest modes fall below the rounding of 1/omega^2. They come from the generalized
    solver instead, never as negative omega^2 of a stable structure: all frequencies
    positive and ascending, the lowest as ARPACK finds them, the highest those of eigh(K,
    M)."""
    import scipy.linalg
    from flexmbd.examples import flexures

    from flexmbd import light
    from flexmbd.analysis import eigen

    monkeypatch.setattr(eigen, "FEW_MODES_FROM", 60)   # ARPACK for a few of these 114
    leaf = dict(flexures.HINGE_LEAF, dim=[0.1e-3, 0.1e-3], nbeams=10, warping=False)
    body = dict(flexures.HINGE_BODY, warping=False)
    res = light.run(flexures.HINGE_NODES, flexures.HINGE_ELEMENTS,
                    {1: {"fix": True}, 4: {"fix": True}, 3: {"mass": 10}}, [leaf, body],
                    {"silent": True})
    lin = res.statics.linearization(0)
    modes = fm.vibration_modes(lin)
    f = modes.frequencies
    assert np.all(f > 0) and np.all(np.diff(f) >= -1e-9 * f.max())
    K, M = lin.block("K"), lin.block("M0")
    generalized = np.sqrt(scipy.linalg.eigh(K, M, eigvals_only=True)) / (2 * np.pi)
    np.testing.assert_allclose(f[-5:], generalized[-5:], rtol=1e-9)
    # three of 114 take ARPACK on the banded tangent, whose solves lose half the digits
    # to this stiffness span (1e16); Rayleigh-Ritz with exact products takes most back
    few = fm.vibration_modes(lin, 3)
    assert few.path.method == "arpack" and modes.path.method == "dense"
    np.testing.assert_allclose(f[:3], few.frequencies, rtol=1e-7)


def test_modes_past_buckling_are_reported_unstable():
    """A two-beam column: below its buckling load (fm.buckling's factor, an eigenproblem
    of K0 and G0 alone) every mode vibrates; above it the lowest grows, reported so."""
    model = two_beam_column()
    critical = fm.buckling(fm.linearize(model, loads={"x5.1": -1.0})).factors[0]
    below = fm.vibration_modes(fm.linearize(model, loads={"x5.1": -0.9 * critical}))
    above = fm.vibration_modes(fm.linearize(model, loads={"x5.1": -1.1 * critical}))
    assert len(below.unstable) == 0 and "unstable" not in repr(below)
    assert list(above.unstable) == [0] and above.frequencies[0] < 0
    assert "unstable: mode 1 grows instead of vibrating" in repr(above)
