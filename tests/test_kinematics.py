"""Kinematic analysis against closed forms, SymPy and finite differences."""

import math

import numpy as np
import pytest
import sympy as sp

import flexmbd as fm

from .models import slider_crank

L1, L2 = 0.7, 2.1  # not the exercise's ratio, so nothing hides behind sqrt(3)
OMEGA0, ALPHA = 3.0, 0.8  # crank speed [rad/s] and acceleration [rad/s^2]


@pytest.fixture(scope="module")
def crank_closed_form():
    """Slider-crank positions and their first two phi-derivatives, derived by SymPy."""
    phi = sp.symbols("phi")
    exprs = {
        "x3.1": L1 * sp.cos(phi),
        "x3.2": L1 * sp.sin(phi),
        "x4.1": -sp.asin(L1 * sp.sin(phi) / L2),
        "x5.1": L1 * sp.cos(phi) + sp.sqrt(L2**2 - L1**2 * sp.sin(phi) ** 2),
    }
    return {
        label: tuple(sp.lambdify(phi, sp.diff(e, phi, k), "numpy") for k in range(3))
        for label, e in exprs.items()
    }


def assert_relative(actual, expected, rtol=1e-10):
    """Agreement relative to the range of ``expected`` (values may cross zero)."""
    scale = np.max(np.abs(expected))
    np.testing.assert_allclose(actual, expected, rtol=0, atol=rtol * scale)


def test_slider_crank_revolution_matches_closed_form(crank_closed_form):
    model = slider_crank(L1, L2, fm.Polynomial(0.0, OMEGA0, ALPHA))
    t_rev = (-OMEGA0 + math.sqrt(OMEGA0**2 + 4 * math.pi * ALPHA)) / ALPHA  # phi = 2 pi
    times = np.linspace(0.0, t_rev, 361)
    r = fm.kinematic_analysis(model, times)
    phi = r["x2.1"]
    np.testing.assert_allclose(phi[-1], 2 * math.pi, rtol=1e-12)
    phid, phidd = OMEGA0 + ALPHA * times, np.full_like(times, ALPHA)
    for label, (f0, f1, f2) in crank_closed_form.items():
        d1, d2 = np.broadcast_to(f1(phi), phi.shape), np.broadcast_to(f2(phi), phi.shape)
        assert_relative(r[label], np.broadcast_to(f0(phi), phi.shape))
        assert_relative(r["xd" + label[1:]], d1 * phid)
        assert_relative(r["xdd" + label[1:]], d1 * phidd + d2 * phid**2)
    np.testing.assert_allclose(r.e, 0.0, atol=1e-12)
    np.testing.assert_allclose(r.ed, 0.0, atol=1e-11)
    np.testing.assert_allclose(r.edd, 0.0, atol=1e-10)


def test_slider_crank_transfer_functions_match_closed_form(crank_closed_form):
    model = slider_crank(L1, L2)
    for phi in np.linspace(0.0, 2 * math.pi, 37):
        x = fm.solve_position(model, np.array([phi]), _nearby_guess(model, phi))
        F_q = fm.first_order_transfer(model, x)
        F_qq, E_qq = fm.second_order_transfer(model, x)
        for label, (_, f1, f2) in crank_closed_form.items():
            i = model.coordinate_index(label)
            np.testing.assert_allclose(F_q[i, 0], f1(phi), rtol=1e-10, atol=1e-10 * L1)
            np.testing.assert_allclose(F_qq[i, 0, 0], f2(phi), rtol=1e-10, atol=1e-10 * L1)
        np.testing.assert_allclose(fm.deformation_transfer(model, x, F_q), 0.0, atol=1e-14)
        np.testing.assert_allclose(E_qq, 0.0, atol=1e-13)


def _nearby_guess(model, phi):
    """A start on the right branch: the closed-form configuration, perturbed."""
    x = np.array(model.x0, dtype=float)
    psi = -math.asin(L1 * math.sin(phi) / L2)
    x[model.coordinate_index("x3.1")] = L1 * math.cos(phi) + 0.01
    x[model.coordinate_index("x3.2")] = L1 * math.sin(phi) - 0.01
    x[model.coordinate_index("x4.1")] = psi + 0.01
    x[model.coordinate_index("x5.1")] = L1 * math.cos(phi) + L2 * math.cos(psi) + 0.01
    return x


def test_partitioned_jacobian_columns(crank_model):
    """The blocks of D_x by coordinate class against central differences of the
    deformations (x1, y1, y5 fixed; x3, y3, phi4, x5 dependent; phi2 the input)."""
    x = fm.solve_position(crank_model, np.array([0.4]))
    jac = fm.partition_jacobian(crank_model, x)
    h = 1e-6
    columns = []
    for i in range(crank_model.n_coordinates):
        step = np.zeros(crank_model.n_coordinates)
        step[i] = h
        columns.append((fm.deformations(crank_model, x + step)
                        - fm.deformations(crank_model, x - step)) / (2 * h))
    differences = np.stack(columns, axis=1)
    labels = crank_model.coordinate_labels
    for block, names in ((jac.fixed, ["x1.1", "x1.2", "x5.2"]),
                         (jac.dependent, ["x3.1", "x3.2", "x4.1", "x5.1"]),
                         (jac.independent, ["x2.1"])):
        np.testing.assert_allclose(block, differences[:, [labels.index(n) for n in names]],
                                   atol=1e-9)
    assert jac.D_c.shape == (4, 4)
    rhs = np.arange(1.0, 5.0)
    np.testing.assert_allclose(jac.D_c @ jac.solve(rhs), rhs, atol=1e-14)


# --- a model with every kind of independent and dependent entry -----------------------
def four_bar_with_spring() -> fm.Model:
    """Four-bar: crank driven through a hinge deformation, a released measuring truss.

    Nodes 1, 7 ground pivots; 2, 4, 6 link rotations; 8 ground rotation; 3, 5 pins.
    The hinge 4 between the fixed ground rotation 8 and the crank rotation 2 is
    the input (a prescribed deformation, ``e(m)``); truss 5 from pin 3 to the
    ground point 9 is released (``e(c)``), like a spring that is not a degree
    of freedom.
    """
    # Grashof crank-rocker: ground 2, crank 0.5, coupler 2, rocker 1.5; crank pointing up
    x5 = (48 + math.sqrt(48**2 - 4 * 17 * 32)) / 34  # |r5 - r3| = 2, |r5 - r7| = 1.5
    b = fm.ModelBuilder("four-bar")
    b.add_node(1, 0.0, 0.0).add_node(3, 0.0, 0.5).add_node(5, x5, 4 * x5 - 5.5)
    b.add_node(7, 2.0, 0.0).add_node(9, 1.0, -0.5)
    b.add_rigid_beam(1, 1, 2, 3)  # crank
    b.add_beam(2, 3, 4, 5, 10)  # coupler as a beam, its bending at q released
    b.add_rigid_beam(3, 7, 6, 5)  # rocker
    b.add_hinge(4, 8, 2)
    b.add_truss(5, 3, 9)
    b.add_hinge(6, 10, 6)  # coupler end rotation tied to the rocker's
    b.fix(1).fix(7).fix(8).fix(9)
    b.input_deformation(4, 1, law=fm.Polynomial(0.0, 1.3, 0.4))
    b.release(5, 1).release(6, 1)
    return b.build()


def test_input_deformation_drives_like_an_input_coordinate():
    model = four_bar_with_spring()
    assert model.q_labels == ("e4.1",)
    r = fm.kinematic_analysis(model, np.linspace(0.0, 1.0, 11))
    np.testing.assert_allclose(r["e4.1"], 1.3 * r.t + 0.2 * r.t**2, atol=1e-12)
    np.testing.assert_allclose(r["x2.1"], r["e4.1"], atol=1e-12)  # ground angle fixed at 0
    np.testing.assert_allclose(r["ed4.1"], 1.3 + 0.4 * r.t, atol=1e-12)


def test_transfer_functions_match_finite_differences():
    model = four_bar_with_spring()
    q = np.array([0.35])
    x = fm.solve_position(model, q)
    F_q = fm.first_order_transfer(model, x)
    E_q = fm.deformation_transfer(model, x, F_q)
    F_qq, E_qq = fm.second_order_transfer(model, x)
    h = 1e-6

    def solved(dq):
        xs = fm.solve_position(model, q + dq, x, tolerance=1e-14)
        return xs, fm.deformations(model, xs)

    (xp, ep), (xm, em) = solved(h), solved(-h)
    np.testing.assert_allclose(F_q[:, 0], (xp - xm) / (2 * h), atol=1e-8)
    np.testing.assert_allclose(E_q[:, 0], (ep - em) / (2 * h), atol=1e-8)
    F_p, F_m = fm.first_order_transfer(model, xp), fm.first_order_transfer(model, xm)
    np.testing.assert_allclose(F_qq[:, :, 0], (F_p - F_m) / (2 * h), atol=1e-7)
    E_p, E_m = fm.deformation_transfer(model, xp), fm.deformation_transfer(model, xm)
    np.testing.assert_allclose(E_qq[:, :, 0], (E_p - E_m) / (2 * h), atol=1e-7)
    released = model.released
    assert np.all(np.abs(E_q[released, 0]) > 1e-3)  # the released truss does move
    assert np.abs(E_qq[released]).max() > 1e-3


def test_velocities_and_accelerations_agree_with_transfer_functions():
    model = four_bar_with_spring()
    q, qd, qdd = np.array([0.8]), np.array([1.7]), np.array([-2.2])
    x = fm.solve_position(model, q)
    xd = fm.velocities(model, x, qd)
    xdd = fm.accelerations(model, x, xd, qdd)
    F_q = fm.first_order_transfer(model, x)
    F_qq, _ = fm.second_order_transfer(model, x)
    np.testing.assert_allclose(xd, F_q @ qd, atol=1e-13)
    np.testing.assert_allclose(xdd, F_q @ qdd + np.einsum("ijk,j,k->i", F_qq, qd, qd),
                               atol=1e-12)
    # along the path q(s) = q + qd s + qdd s^2/2 the positions are x(s): differentiate
    h = 1e-4
    xs = [fm.solve_position(model, q + qd * s + 0.5 * qdd * s * s, x, tolerance=1e-14)
          for s in (-h, 0.0, h)]
    np.testing.assert_allclose(xd, (xs[2] - xs[0]) / (2 * h), atol=1e-7)
    np.testing.assert_allclose(xdd, (xs[2] - 2 * xs[1] + xs[0]) / h**2, atol=1e-5)


def test_hessian_assembly_matches_element_kernels():
    model = four_bar_with_spring()
    rng = np.random.default_rng(3)
    x = model.x0 + rng.normal(scale=0.05, size=model.n_coordinates)
    xd = rng.normal(size=model.n_coordinates)
    np.testing.assert_allclose(np.einsum("iab,a,b->i", fm.hessian(model, x), xd, xd),
                               fm.quadratic_velocity(model, x, xd), atol=1e-12)


# --- failures -------------------------------------------------------------------------
def sliding_bar() -> fm.Model:
    b = fm.ModelBuilder("bar")
    b.add_node(1, -math.sqrt(3), 0.0).add_node(2, 0.0, 1.0)
    b.add_truss(1, 1, 2)
    b.fix(1, "y").fix(2, "x").input_coordinate(1, "x", law=fm.Polynomial(-2.0, 4.0))
    return b.build()


def test_newton_divergence_names_time_iterations_and_residual():
    model = sliding_bar()
    with pytest.raises(fm.ConvergenceError) as info:
        fm.solve_position(model, np.array([2.5]), time=1.125)  # beyond the bar's length
    error = info.value
    assert error.time == 1.125 and error.iterations == 25 and error.residual > 1e-3
    message = str(error)
    assert "t = 1.125 s" in message and "25 iterations" in message
    assert "e1.1 (truss 1, elongation)" in message and "residual" in message


def test_run_pulled_past_the_bar_length_keeps_partial_results():
    model = sliding_bar()
    times = np.linspace(0.05, 1.2, 24)
    with pytest.raises(fm.SimulationError) as info:
        fm.kinematic_analysis(model, times)
    partial = info.value.partial_result
    assert partial is not None and not partial.success
    assert 0 < len(partial.t) < len(times) and partial.t[-1] < 1.0
    np.testing.assert_allclose(partial["x2.2"], np.sqrt(4 - partial["x1.1"] ** 2), rtol=1e-12)
    returned = fm.kinematic_analysis(model, times, on_failure="return")
    assert not returned.success and len(returned.t) == len(partial.t)
    assert f"t = {info.value.time:.6g} s" in returned.message
    with pytest.raises(fm.SimulationError):
        returned.raise_for_status()


def test_run_into_the_flat_bar_stops_as_singular_and_says_which_coordinate():
    model = sliding_bar()
    result = fm.kinematic_analysis(model, np.linspace(0.01, 1.0, 100), on_failure="return")
    assert isinstance(result.error, fm.SingularConfigurationError)
    assert result.error.time == 1.0 and result.t[-1] == pytest.approx(0.99)
    assert "x2.2 (node 2, y)" in result.message and "e1.1" in result.message


def test_missing_and_unknown_input_laws():
    b = fm.ModelBuilder()
    b.add_node(1, -math.sqrt(3), 0.0).add_node(2, 0.0, 1.0).add_truss(1, 1, 2)
    model = b.fix(1, "y").fix(2, "x").input_coordinate(1, "x").build()
    with pytest.raises(fm.ModelError, match=r"no motion given for the input\(s\) x1.1"):
        fm.kinematic_analysis(model, [0.1])
    with pytest.raises(fm.ArgumentError, match=r"inputs: x2\.2 is not an input or dynamic"):
        fm.kinematic_analysis(model, [0.1], inputs={"x1.1": fm.Polynomial(-1.9),
                                                    "x2.2": fm.Polynomial(0.0)})
    with pytest.raises(fm.ArgumentError, match=r"inputs: x9\.1: node 9 is not in the model"):
        fm.kinematic_analysis(model, [0.1], inputs={"x9.1": fm.Polynomial(0.0)})
    with pytest.raises(ValueError, match="must increase strictly"):
        fm.kinematic_analysis(model, [0.2, 0.1], inputs={"x1.1": fm.Polynomial(-1.9)})


def test_custom_law_and_result_columns(tmp_path):
    model = sliding_bar()
    law = fm.Custom(lambda t: -1.0 + 0.5 * math.sin(t), lambda t: 0.5 * math.cos(t),
                    lambda t: -0.5 * math.sin(t))
    r = fm.kinematic_analysis(model, np.linspace(0, 3, 7), inputs={"x1.1": law})
    x_p, v, a = r["x1.1"], r["xd1.1"], r["xdd1.1"]
    y = np.sqrt(4 - x_p**2)
    yd = -x_p * v / y
    np.testing.assert_allclose(r["xd2.2"], yd, rtol=1e-12)
    np.testing.assert_allclose(r["xdd2.2"], -(v**2 + yd**2 + x_p * a) / y, rtol=1e-10)
    path = r.to_csv(tmp_path / "bar.csv")
    header = path.read_text().splitlines()[0].split(",")
    assert header[:5] == ["t", "x1.1", "x1.2", "x2.1", "x2.2"] and "edd1.1" in header
    data = np.loadtxt(path, delimiter=",", skiprows=1)
    np.testing.assert_array_equal(data[:, header.index("xdd2.2")], r["xdd2.2"])


def test_a_model_is_compiled_once_and_each_thread_evaluates_on_its_own_workspace():
    """Per-state functions run on the model's workspace (compiled once, kept with the
    model); another thread gets its own engine on the same compiled arrays and the same
    answers; a tolerance asked for once does not stay."""
    import threading

    from flexmbd.engine import workspace_of

    model = slider_crank(L1, L2)
    x = fm.solve_position(model, np.array([0.4]))
    F_q = fm.first_order_transfer(model, x)
    here = workspace_of(model)
    assert workspace_of(model) is here
    there = {}

    def other_thread():
        there["engine"] = workspace_of(model)
        there["F_q"] = fm.first_order_transfer(model, x)

    worker = threading.Thread(target=other_thread)
    worker.start()
    worker.join()
    assert there["engine"] is not here and there["engine"].compiled is here.compiled
    np.testing.assert_array_equal(there["F_q"], F_q)
    default = here.tolerance
    fm.solve_position(model, np.array([0.5]), tolerance=1e-6)
    assert here.tolerance == 1e-6
    fm.first_order_transfer(model, x)
    assert here.tolerance == default
