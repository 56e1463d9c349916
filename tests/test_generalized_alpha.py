"""The generalized-alpha integrator (in the compiled core) against closed forms.

flexmbd.integrate drives the same integrator that simulations use with a Python
``y' = fun(t, y)`` called back, its Newton matrix by finite differences.
"""

import itertools
import math

import numpy as np
import pytest

from flexmbd.errors import ConvergenceError
from flexmbd.integrate import AlphaOptions, integrate

OMEGA = 2 * math.pi


def oscillator(omega=OMEGA, damping=0.0):
    """``q'' = -omega^2 q - 2 damping omega q'`` as ``y = [q; v]``."""
    def fun(t, y):
        q, v = y
        return np.array([v, -(omega**2) * q - 2 * damping * omega * v])
    return fun


def run(fun, step, t_end, y0=(1.0, 0.0), **options):
    times = np.linspace(0.0, t_end, 11)
    return integrate(fun, np.array(y0), times, method="GeneralizedAlpha", step=step,
                     rtol=1e-10, atol=1e-12, **options)


def test_second_order_accurate_for_the_slow_motion():
    errors = []
    for step in (0.01, 0.005, 0.0025):
        result = run(oscillator(), step, 2.0)  # two periods
        exact = np.cos(OMEGA * result.t)
        errors.append(np.max(np.abs(result.y[:, 0] - exact)))
    assert errors[0] < 1e-2
    for coarse, fine in itertools.pairwise(errors):
        assert 3.5 < coarse / fine < 4.5  # halving the step quarters the error


def test_dense_output_between_steps_is_as_accurate_as_the_steps():
    result = run(oscillator(), 0.013, 1.0)  # output times fall inside steps
    exact = np.stack([np.cos(OMEGA * result.t), -OMEGA * np.sin(OMEGA * result.t)], axis=1)
    assert np.max(np.abs(result.y - exact) / [1.0, OMEGA]) < 5e-3


def test_unresolved_modes_are_damped_by_rho_inf():
    omega = 1e5  # period 6e-5 s, stepped at 1e-3 s

    def energy(result):
        return 0.5 * result.y[:, 1] ** 2 + 0.5 * omega**2 * result.y[:, 0] ** 2

    kept = energy(run(oscillator(omega), 1e-3, 0.05, rho_inf=1.0))
    damped = energy(run(oscillator(omega), 1e-3, 0.05, rho_inf=0.5))
    assert np.all(np.abs(kept / kept[0] - 1) < 1e-6)  # rho_inf = 1: no numerical damping
    assert damped[-1] < 1e-10 * damped[0]  # 50 steps at spectral radius 0.5


def test_matches_a_damped_oscillator():
    zeta = 0.1
    result = run(oscillator(damping=zeta), 0.002, 1.0)
    wd = OMEGA * math.sqrt(1 - zeta**2)
    t = result.t
    exact = np.exp(-zeta * OMEGA * t) * (np.cos(wd * t) + zeta * OMEGA / wd * np.sin(wd * t))
    assert np.max(np.abs(result.y[:, 0] - exact)) < 1e-3


def test_a_failing_right_hand_side_ends_the_run_with_its_time():
    base = oscillator()

    def fun(t, y):
        if y[0] < -0.5:  # the "position solve" fails past a quarter period and a bit
            raise ConvergenceError(f"no solution at t = {t:.6g} s", t)
        return base(t, y)

    result = run(fun, 0.01, 1.0)
    assert not result.success and isinstance(result.error, ConvergenceError)
    assert 0.3 < result.error.time < 0.4  # cos(2 pi t) = -0.5 at t = 1/3
    assert 0 < len(result.t) < 11 and result.t[-1] <= result.error.time


def pendulum(t, y):
    """``q'' = -omega^2 sin q``: nonlinear, so a kept Newton matrix is not exact."""
    return np.array([y[1], -(OMEGA**2) * math.sin(y[0])])


@pytest.mark.parametrize("renew_every", [1, 2])
def test_linearly_implicit_steps_stay_second_order(renew_every):
    """One Newton correction per step (the matrix renewed every step or every other)
    converges at second order to an error-controlled RK45 solution."""
    y0 = (1.5, 0.0)  # a large swing: sin q far from q
    reference = integrate(pendulum, np.array(y0), np.linspace(0.0, 2.0, 11), method="RK45",
                          rtol=1e-12, atol=1e-12).y[:, 0]
    errors = []
    for step in (0.004, 0.002, 0.001):
        result = run(pendulum, step, 2.0, y0=y0, iterations=1, renew_every=renew_every)
        errors.append(np.max(np.abs(result.y[:, 0] - reference)))
    iterated = np.max(np.abs(run(pendulum, 0.004, 2.0, y0=y0).y[:, 0] - reference))
    assert errors[0] < 2 * iterated  # as accurate as Newton iterated to convergence
    for coarse, fine in itertools.pairwise(errors):
        assert 3.0 < coarse / fine < 5.0


def test_bad_options():
    with pytest.raises(ValueError, match="even length"):
        integrate(lambda t, y: y, np.zeros(3), [0.0, 1.0], method="GeneralizedAlpha")
    with pytest.raises(ValueError, match="rho_inf"):
        AlphaOptions(0.1, rho_inf=1.5)
    with pytest.raises(ValueError, match="step must be positive"):
        AlphaOptions(0.0)
    with pytest.raises(ValueError, match="iterations"):
        AlphaOptions(0.1, iterations=0)
    with pytest.raises(ValueError, match="renew_every"):
        AlphaOptions(0.1, iterations=1, renew_every=0)
    with pytest.raises(ValueError, match="strictly increasing"):
        integrate(oscillator(), np.zeros(2), [0.0, 0.0], method="GeneralizedAlpha")


def test_counters_of_the_linearly_implicit_method():
    """One evaluation per step (plus the initial accelerations), a Newton matrix every
    ``renew_every`` steps, each from 2 m differenced evaluations; outputs within round-off
    of a step's end (fixed steps accumulate round-off in t) are that step's."""
    dt = 0.1  # not a binary fraction: t = k dt drifts from the output times
    times = dt * np.arange(31)
    result = integrate(oscillator(), np.array([1.0, 0.0]), times, method="GeneralizedAlpha",
                       step=dt, iterations=1, renew_every=4)
    assert result.success and len(result.t) == 31
    stats = result.stats
    assert stats["nsteps"] == 30 and stats["njev"] == 8  # steps 1, 5, 9, ..., 29
    assert stats["nfev"] == 1 + 30 + 2 * stats["njev"]


def test_a_python_error_is_not_swallowed():
    def fun(t, y):
        if t > 0.3:
            raise KeyError("a bug in the user's code")
        return oscillator()(t, y)

    with pytest.raises(KeyError, match="a bug"):
        run(fun, 0.01, 1.0)
