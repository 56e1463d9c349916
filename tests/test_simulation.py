"""Forward simulation: energy conservation, failures with partial results, errors."""

import math

import numpy as np
import pytest

import flexmbd as fm
from flexmbd.engine import Workspace, resolve_laws
from flexmbd.engine import compile as compiling
from flexmbd.engine.diagnosis import weakest_direction

from . import reference
from .elementwise import dense_jacobian

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
        kinetic = 0.5 * xd @ fm.mass_matrix(model, x) @ xd
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


def test_outputs_match_the_dense_reduced_equations():
    """The run's accelerations and constraint stresses (saddle-point system, THEORY 8)
    against F_q, Mbar and D_c^T sigma in dense form (tests/reference.py) at the same
    states, for RK45 and generalized-alpha."""
    model = flexible_pendulum()
    for method in ("RK45", "GeneralizedAlpha"):
        result = fm.simulate(model, np.linspace(0, 0.4, 9), initial={"e1.2": (0.01, 0.3)},
                             with_reactions=True, method=method)
        for k in range(len(result.t)):
            terms = reference.terms(model, result.q[k], result.qd[k], x_guess=result.x[k])
            qdd = reference.accelerations(model, terms, np.zeros(0))
            np.testing.assert_allclose(result.qdd[k], qdd, rtol=1e-9, atol=1e-9)
            sigma, loads = reference.reactions(model, terms, qdd)
            np.testing.assert_allclose(result.sigma[k], sigma, rtol=1e-8, atol=1e-8)
            np.testing.assert_allclose(result.reactions[k], loads, rtol=1e-8, atol=1e-8)
    assert np.abs(result["sig1.1"]).max() > 1.0  # the rigid elongation pulls the body round


def flexible_slider_crank_one_beam(damped: bool = False):
    b = fm.ModelBuilder("flexible slider-crank")
    b.add_node(1, 0, 0).add_node(3, 0.15, 0).add_node(5, 0.45, 0)
    b.add_rigid_beam(1, 1, 2, 3).add_beam(2, 3, 4, 5, 6)
    b.fix(1).fix(5, "y").dynamic_deformation(2, *((1, 2, 3) if damped else (2, 3)))
    b.set_mass(2, 0.06676 / 0.30).set_stiffness(2, bending=12.72)
    if damped:
        b.set_stiffness(2, axial=5e6).set_damping(2, axial=40.0, bending=0.02)
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
    with pytest.raises(fm.ArgumentError, match=r"initial: x2\.1 is prescribed, not dynamic"):
        fm.simulate(flexible_slider_crank_one_beam(), [0.0, 0.1], initial={"x2.1": (0, 1)})
    with pytest.raises(ValueError, match="unknown method"):
        fm.simulate(flexible_pendulum(), [0.0, 0.1], method="Euler")


@pytest.mark.parametrize("method", ["GeneralizedAlpha", "RK45"])
def test_fewer_outputs_record_the_same_states(method):
    """Positions (or rates) alone are solved for at each output by a shorter path: the
    same states as the full outputs, to the position tolerance (1e-10 of the model
    size), and the rest not recorded."""
    model = flexible_slider_crank_one_beam()
    times = np.linspace(0.0, 0.02, 41)
    options = {"step": 1e-4, "iterations": 1} if method == "GeneralizedAlpha" else {}
    full = fm.simulate(model, times, method=method, **options)
    for outputs, same in (("positions", ("x", "e", "q")),
                          ("velocities", ("x", "e", "q", "xd", "ed", "qd"))):
        part = fm.simulate(model, times, method=method, outputs=outputs, **options)
        for name in same:
            np.testing.assert_allclose(getattr(part, name), getattr(full, name), rtol=0,
                                       atol=1e-10 * np.max(np.abs(getattr(full, name))))
        assert part.xdd is None and part.sigma is None and part.driving is None
        assert set(part.columns()) < set(full.columns())
        with pytest.raises(KeyError, match="not recorded"):
            part["xdd2.1"]
    with pytest.raises(ValueError, match="outputs: must be one of"):
        fm.simulate(model, times, outputs="x")
    with pytest.raises(ValueError, match="with_reactions: needs outputs='all'"):
        fm.simulate(model, times, outputs="positions", with_reactions=True)


def test_band_orderings_change_nothing_but_the_cost(monkeypatch):
    """The square systems are factorised in bands chosen by reverse Cuthill-McKee; with the
    identity ordering the band of a mechanism's D_c and saddle-point matrix is (nearly)
    full, a dense LU. Both give the same run to round-off."""
    from flexmbd.examples import slider_crank_flex as example

    def run():
        model = example.build_model(4, eps1flex=True)
        return Workspace(model).bands(), fm.simulate(
            model, example.output_times(0.05), method="GeneralizedAlpha",
            step=example.turn_time(1.0) / 800, iterations=1, with_reactions=True)

    banded_bands, banded = run()
    monkeypatch.setattr(compiling, "reverse_cuthill_mckee", lambda graph: list(range(len(graph))))
    dense_bands, dense = run()
    assert banded_bands["saddle_kl"] < dense_bands["saddle_kl"]
    for name in ("x", "xd", "xdd", "e", "sigma", "reactions", "driving"):
        scale = max(np.abs(getattr(dense, name)).max(), 1.0)
        np.testing.assert_allclose(getattr(banded, name), getattr(dense, name),
                                   rtol=0, atol=1e-9 * scale, err_msg=name)


def test_a_chain_of_beams_keeps_narrow_bands():
    """The cost per step grows linearly along a chain: the bands of D_c and of the
    saddle-point matrix do not grow with the number of beams."""
    from flexmbd.examples import slider_crank_flex as example

    bands = [Workspace(example.build_model(n, eps1flex=True)).bands() for n in (10, 40, 160)]
    for name in ("dc_kl", "dc_ku", "saddle_kl"):
        assert bands[0][name] == bands[1][name] == bands[2][name] <= 12, (name, bands)
    assert bands[2]["saddle_n"] > 15 * bands[0]["saddle_kl"]


def test_a_long_chain_is_regular_though_less_well_conditioned():
    """D_c of a rod of 200 beams is regular but less well conditioned than a short one's;
    the dead-point check measures the conditioning against the reference configuration's,
    so the long rod runs, and a dead point names its largest contributors, not all 600."""
    from flexmbd.examples import slider_crank_flex as example

    model = example.build_model(200, eps1flex=True)
    run = fm.simulate(model, np.linspace(0.0, 5e-4, 3), method="GeneralizedAlpha",
                      step=2.5e-4, iterations=1, outputs="positions")
    assert run.success and len(run.t) == 3
    D_x = dense_jacobian(model, np.asarray(model.x0))
    D_c = D_x[np.ix_(model.constrained, model.dependent)]
    words = weakest_direction(model, D_c)
    assert " more" in words and words.count("(beam") <= 8
    assert 0.0 < Workspace(model).regularity_limit < 1e-4


def test_newton_operator_is_the_reduced_newton_matrix():
    """Generalized-alpha's Newton correction ``-S^-1 R`` (the saddle-point system of the core)
    against ``S = Mbar + c_q (K + G) + c_v D`` in dense form (tests/reference.py), with
    flexible elongations, damping and the geometric stiffness of elastic and constraint
    stresses, at a state away from equilibrium."""
    model = flexible_slider_crank_one_beam(damped=True)
    c_q, c_v = 2e-6, 3e-3
    rng = np.random.default_rng(2)
    d = int(np.count_nonzero(~model.q_is_input))
    y = np.concatenate([rng.normal(scale=1e-3, size=d), rng.normal(scale=0.1, size=d)])
    a, r = rng.normal(scale=100.0, size=d), np.array([0.3, -1.2, 0.7])
    run = Workspace(model)
    run.prepare(resolve_laws(model), 1, integrated=True, dynamics=True)
    core = run._core   # the binding's own entry points of the Newton step, for this test
    core.reset()
    t = 0.002  # the crank at 0.3 rad: Newton from the reference pose finds the same branch
    core.residual(t, y, a, np.empty(d))
    correction = np.empty(d)
    core.correction(c_q, c_v, r, correction)
    terms = reference.terms(model, np.concatenate([[150.0 * t], y[:d]]),
                            np.concatenate([[150.0], y[d:]]))
    x = np.empty(model.n_coordinates)
    core.configuration(x)  # the configuration of the last evaluation
    np.testing.assert_allclose(x, terms.x, atol=1e-12)
    S = reference.newton_matrix(model, terms, np.concatenate([[0.0], a]), c_q, c_v)
    dyn = ~model.q_is_input
    np.testing.assert_allclose(correction, -np.linalg.solve(S[np.ix_(dyn, dyn)], r), rtol=1e-9)


def test_rho_inf_reaches_generalized_alpha_only():
    model = flexible_pendulum()
    with pytest.raises(ValueError, match="rho_inf"):
        fm.simulate(model, [0.0, 0.1], method="GeneralizedAlpha", rho_inf=1.5)
    with pytest.raises(ValueError, match="belong to GeneralizedAlpha"):
        fm.simulate(model, [0.0, 0.1], method="RK45", rho_inf=0.5)
    runs = [fm.simulate(model, np.linspace(0, 0.5, 11), method="GeneralizedAlpha",
                        step=0.05, initial={"e1.2": (0.01, 0.0)}, rho_inf=rho)
            for rho in (0.0, 1.0)]
    # the bending vibration, unresolved by these steps, decays only with rho_inf < 1
    assert np.ptp(runs[0]["e1.2"][5:]) < 0.5 * np.ptp(runs[1]["e1.2"][5:])


def test_a_run_starts_on_the_branch_of_the_reference_configuration():
    """A position problem has several solutions (a rigid bar pointing either way along its
    line). A run that starts away from the reference configuration starts on the solution
    the model was drawn in, continued there: here a pendulum released near its bottom
    swings there, instead of starting upside down (Newton straight from the drawing,
    90 degrees away, finds the mirrored solution)."""
    from tests.test_generalized_alpha import pendulum

    start = -1.5  # rad: 0.07 rad from hanging straight down
    result = fm.simulate(pendulum(), np.linspace(0.0, 1.0, 21), initial={"x2.1": (start, 0.0)},
                         method="DOP853", rtol=1e-10, atol=1e-12)
    swing = result["x2.1"] + math.pi / 2
    assert np.max(np.abs(swing)) == pytest.approx(math.pi / 2 + start, rel=1e-6)
    assert result["x3.2"][0] < 0.0  # the mass below the pivot
    # a kinematic run of the slider-crank starting at 160 degrees: the rod keeps its side
    from .models import slider_crank

    model = slider_crank(1.0, 2.0, fm.Polynomial(math.radians(160.0), 1.0))
    run = fm.kinematic_analysis(model, [0.0, 0.1])
    phi = run["x2.1"]
    np.testing.assert_allclose(run["x5.1"], np.cos(phi) + np.sqrt(4.0 - np.sin(phi) ** 2),
                               rtol=1e-12)
