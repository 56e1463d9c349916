"""The generalized-alpha integrator of the core against closed forms, on models.

A mass on a spring-damper is the harmonic oscillator; a point mass on a rigid bar
under gravity the nonlinear pendulum; the exercise's slider-crank with a crank
acceleration it cannot follow, a run that fails.
"""

import itertools
import math

import numpy as np
import pytest

import flexmbd as fm
from flexmbd.analysis.integrate import AlphaOptions

OMEGA = 2 * math.pi  # rad/s: a period of 1 s


def oscillator(omega: float = OMEGA, zeta: float = 0.0, mass: float = 1.0) -> fm.Model:
    """``m u'' + c u' + k u = 0``: a point mass on a spring-damper along x."""
    b = fm.ModelBuilder("oscillator")
    b.add_node(1, 0.0, 0.0).add_node(2, 1.0, 0.0)
    b.add_element(1, fm.SpringDamper, (1, 2))
    b.fix(1).fix(2, "y").dynamic_coordinate(2, "x")
    b.set_stiffness(1, spring=mass * omega**2).set_damping(1, spring=2 * zeta * omega * mass)
    b.add_point_mass(2, mass)
    return b.build()


def run(model, step, t_end, start=(1.0, 0.0), label="x2.1", points=11, **options):
    times = np.linspace(0.0, t_end, points)
    return fm.simulate(model, times, initial={label: start}, method="GeneralizedAlpha",
                       step=step, rtol=1e-10, atol=1e-12, **options)


def test_second_order_accurate_for_the_slow_motion():
    errors = []
    for step in (0.01, 0.005, 0.0025):
        result = run(oscillator(), step, 2.0, start=(1.1, 0.0))  # two periods
        exact = 1.0 + 0.1 * np.cos(OMEGA * result.t)
        errors.append(np.max(np.abs(result["x2.1"] - exact)))
    assert errors[0] < 1e-3
    for coarse, fine in itertools.pairwise(errors):
        assert 3.5 < coarse / fine < 4.5  # halving the step quarters the error


def test_outputs_between_steps_are_as_accurate_as_the_steps():
    result = run(oscillator(), 0.013, 1.0, start=(1.1, 0.0))  # outputs fall inside steps
    t = result.t
    np.testing.assert_allclose(result["x2.1"], 1.0 + 0.1 * np.cos(OMEGA * t), atol=5e-4)
    np.testing.assert_allclose(result["xd2.1"], -0.1 * OMEGA * np.sin(OMEGA * t),
                               atol=5e-4 * OMEGA)


def test_unresolved_modes_are_damped_by_rho_inf():
    omega = 1e5  # period 6e-5 s, stepped at 1e-3 s
    start = (1.0 + 1e-6, 0.0)  # small: the predictor's overshoot stays far from the anchor

    def energy(result):
        u, v = result["x2.1"] - 1.0, result["xd2.1"]
        return 0.5 * v**2 + 0.5 * omega**2 * u**2

    # 0.06 steps per period: the step is warned about, naming the one that keeps the lag
    # (omega h)^2 / 12 per period below a tenth of a period over the run's 796 periods
    period = 2 * math.pi / omega
    keeps = period * math.sqrt(12 * 0.1 / (0.05 / period)) / (2 * math.pi)
    with pytest.warns(fm.AccuracyWarning, match=rf"0\.0628 steps.*give step <= {keeps:.3g} s"):
        kept = energy(run(oscillator(omega), 1e-3, 0.05, start=start, rho_inf=1.0))
    with pytest.warns(fm.AccuracyWarning):
        damped = energy(run(oscillator(omega), 1e-3, 0.05, start=start, rho_inf=0.5))
    assert np.all(np.abs(kept / kept[0] - 1) < 1e-6)  # rho_inf = 1: no numerical damping
    assert damped[-1] < 1e-10 * damped[0]  # 50 steps at spectral radius 0.5


def test_matches_a_damped_oscillator():
    zeta = 0.1
    result = run(oscillator(zeta=zeta), 0.002, 1.0, start=(1.1, 0.0))
    wd = OMEGA * math.sqrt(1 - zeta**2)
    t = result.t
    exact = 1.0 + 0.1 * np.exp(-zeta * OMEGA * t) * (np.cos(wd * t)
                                                      + zeta * OMEGA / wd * np.sin(wd * t))
    assert np.max(np.abs(result["x2.1"] - exact)) < 1e-4


def pendulum() -> fm.Model:
    """A point mass on a massless rigid bar of length g / OMEGA^2 (small swings: 1 s)."""
    g = 9.81
    length = g / OMEGA**2
    b = fm.ModelBuilder("pendulum")
    b.add_node(1, 0.0, 0.0).add_node(3, length, 0.0)
    b.add_rigid_beam(1, 1, 2, 3)
    b.fix(1).dynamic_coordinate(2)
    b.add_point_mass(3, 1.0).set_gravity(0.0, -g)
    return b.build()


@pytest.mark.parametrize("renew_every", [1, 2])
def test_linearly_implicit_steps_stay_second_order(renew_every):
    """One Newton correction per step (the matrix renewed every step or every other)
    converges at second order to an error-controlled DOP853 solution."""
    model = pendulum()
    start = (0.0, 0.0)  # released from the horizontal: a swing of pi/2, sin far from linear
    times = np.linspace(0.0, 2.0, 11)
    reference = fm.simulate(model, times, initial={"x2.1": start}, method="DOP853",
                            rtol=1e-12, atol=1e-12)["x2.1"]
    errors = []
    for step in (0.004, 0.002, 0.001):
        result = run(model, step, 2.0, start=start, label="x2.1", iterations=1,
                     renew_every=renew_every)
        errors.append(np.max(np.abs(result["x2.1"] - reference)))
    iterated = np.max(np.abs(run(model, 0.004, 2.0, start=start)["x2.1"] - reference))
    assert errors[0] < 2 * iterated  # as accurate as Newton iterated to convergence
    for coarse, fine in itertools.pairwise(errors):
        assert 3.0 < coarse / fine < 5.0


def test_a_failing_step_ends_the_run_with_its_time_and_the_output_so_far():
    """At an absurd crank acceleration the rod cannot follow: the position solve fails at a
    trial state, halving the step does not get past it, the run ends there."""
    from flexmbd.examples import slider_crank_flex as example

    model = example.build_model(1, alpha=2e6)
    times = np.linspace(0.0, 0.05, 201)
    result = fm.simulate(model, times, method="GeneralizedAlpha", on_failure="return")
    assert not result.success and isinstance(result.error, fm.SimulationError)
    assert 0 < len(result.t) < len(times) and result.t[-1] <= result.error.time < 0.05
    assert f"t = {result.error.time:.6g} s" in result.message


def test_bad_options():
    with pytest.raises(ValueError, match="rho_inf"):
        AlphaOptions(0.1, rho_inf=1.5)
    with pytest.raises(ValueError, match="step: must be positive"):
        AlphaOptions(0.0)
    with pytest.raises(ValueError, match="iterations"):
        AlphaOptions(0.1, iterations=0)
    with pytest.raises(ValueError, match="renew_every"):
        AlphaOptions(0.1, iterations=1, renew_every=0)


def test_counters_of_the_linearly_implicit_method():
    """One evaluation per step (plus the initial accelerations), a Newton matrix every
    ``renew_every`` steps; outputs within round-off of a step's end (fixed steps
    accumulate round-off in t) are that step's, and that step keeps its matrix."""
    dt = 0.1  # not a binary fraction: t = k dt drifts from the output times
    with pytest.warns(fm.AccuracyWarning, match="in 10 steps"):  # a period of 1 s
        result = run(oscillator(), dt, 3.0, start=(1.1, 0.0), points=31, iterations=1,
                     renew_every=4)
    assert result.success and len(result.t) == 31
    assert result.stats["nsteps"] == 30 and result.stats["njev"] == 8  # steps 1, 5, ..., 29
    assert result.stats["nfev"] == 1 + 30


def test_a_python_error_in_the_loads_is_not_swallowed():
    def loads(t, x, xd):
        if t > 0.3:
            raise KeyError("a bug in the user's code")
        return np.zeros(len(x))

    with pytest.raises(fm.SimulationError, match=r"forces raised KeyError: .a bug") as info:
        fm.simulate(oscillator(), np.linspace(0, 1, 11), initial={"x2.1": (1.1, 0.0)},
                    method="GeneralizedAlpha", forces=loads)
    assert isinstance(info.value.__cause__, KeyError)  # the user's own error, kept
    partial = info.value.partial_result
    assert not partial.success and 0 < len(partial.t) < 11 and partial.t[-1] <= 0.3 + 0.1
