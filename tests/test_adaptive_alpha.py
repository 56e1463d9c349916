"""simulate's default: generalized-alpha with its steps controlled by the local error,
against closed forms; the fixed step's warning; the options that belong to one kind of
step only."""

import math

import numpy as np
import pytest

import flexmbd as fm
from tests.test_generalized_alpha import OMEGA, oscillator, pendulum

AMPLITUDE = 0.1  #: of the oscillator's swing [m], from rest


def swing(rtol: float, points: int = 41, **options) -> fm.SimulationResult:
    """Four undamped periods of the oscillator (1 s each) by the default method."""
    return fm.simulate(oscillator(), np.linspace(0.0, 4.0, points),
                       initial={"x2.1": (1.0 + AMPLITUDE, 0.0)}, rtol=rtol, atol=rtol * 1e-3,
                       **options)


def swing_error(result: fm.SimulationResult) -> float:
    """Largest deviation from ``1 + A cos(omega t)`` relative to the amplitude."""
    exact = 1.0 + AMPLITUDE * np.cos(OMEGA * result.t)
    return float(np.max(np.abs(result["x2.1"] - exact)) / AMPLITUDE)


def test_the_default_method_is_error_controlled_generalized_alpha():
    """At the default tolerances (relative to the mass's position, about 1 m: 1e-5 of the
    swing per step) four periods end within 1 % of the swing (0.54 %)."""
    result = fm.simulate(oscillator(), np.linspace(0.0, 4.0, 41),
                         initial={"x2.1": (1.0 + AMPLITUDE, 0.0)})
    assert result.stats["method"] == "GeneralizedAlpha" and "nrejected" in result.stats
    assert swing_error(result) < 1e-2


def test_tighter_tolerances_take_more_steps_and_reach_closer():
    """A second-order method with its local error held to tol: steps grow as tol^(1/3)
    and the error over the periods falls as tol^(2/3) (1000 times tighter: 10 times the
    steps, 100 times closer)."""
    loose, tight = swing(1e-5), swing(1e-8)
    steps = tight.stats["nsteps"] / loose.stats["nsteps"]
    gain = swing_error(loose) / swing_error(tight)
    assert 6 < steps < 16
    assert 40 < gain < 250


def test_outputs_between_steps_are_interpolated_as_accurately():
    """Outputs far denser than the steps (2001 in 4 s against about 500 steps) keep the
    accuracy of the steps, in positions and velocities."""
    sparse, dense = swing(1e-6), swing(1e-6, points=2001)
    assert dense.stats["nsteps"] < 1000
    assert swing_error(dense) < 2 * swing_error(sparse)
    velocity = -AMPLITUDE * OMEGA * np.sin(OMEGA * dense.t)
    assert np.max(np.abs(dense["xd2.1"] - velocity)) < 5 * swing_error(sparse) * \
        AMPLITUDE * OMEGA


def test_a_large_swing_keeps_its_period():
    """A pendulum released at 170 degrees hangs near the top (slow) and swings through the
    bottom (fast): after the period of the elliptic integral it is back where it started,
    to 1e-4."""
    from scipy.special import ellipk

    start = math.radians(170.0)
    model = pendulum()
    small_period = 2 * math.pi / OMEGA
    period = 2 / math.pi * small_period * ellipk(math.sin(start / 2) ** 2)
    times = np.linspace(0.0, period, 2001)
    result = fm.simulate(model, times, initial={"x2.1": (start - math.pi / 2, 0.0)},
                         rtol=1e-8, atol=1e-11)
    angle = result["x2.1"]
    assert angle[-1] == pytest.approx(angle[0], abs=1e-4 * start)
    assert np.min(angle) < -math.pi / 2 - 0.99 * start  # it swung to the other side


def test_a_fixed_step_that_resolves_the_lowest_mode_poorly_is_warned_about():
    """The oscillator's period is 1 s: fixed steps of 0.1 s take 10 per period, and
    steps of 0.05 s the 20 that keep it; the warning names that step. Over 100 periods
    the lag (omega h)^2 / 12 per period adds up: 20 steps per period lose 0.8 of one,
    and the warning names the step that keeps a tenth."""
    times = np.linspace(0.0, 1.0, 11)
    with pytest.warns(fm.AccuracyWarning, match=r"\(1 Hz, a period of 1 s\) in 10 steps.*"
                                                r"give step <= 0\.05 s"):
        fm.simulate(oscillator(), times, initial={"x2.1": (1.1, 0.0)},
                    method="GeneralizedAlpha", step=0.1)
    fm.simulate(oscillator(), times, initial={"x2.1": (1.1, 0.0)},
                method="GeneralizedAlpha", step=0.05)  # warnings are errors here
    keeps = math.sqrt(12 * 0.1 / 100) / (2 * math.pi)
    with pytest.warns(fm.AccuracyWarning, match=rf"lags by about 0\.82 of one.*"
                                                rf"give step <= {keeps:.3g} s"):
        fm.simulate(oscillator(), [0.0, 100.0], initial={"x2.1": (1.1, 0.0)},
                    method="GeneralizedAlpha", step=0.05, outputs="positions")


@pytest.mark.parametrize("options, words", [
    ({"step": 0.01, "first_step": 0.001}, "first_step: applies to error-controlled steps"),
    ({"renew_every": 3}, "renew_every: applies to fixed steps"),
    ({"first_step": -1.0}, "first_step: must be positive"),
    ({"max_step": 1e-15}, "max_step: 1e-15 s over 1 s makes"),
])
def test_options_of_one_kind_of_step_are_refused_with_the_other(options, words):
    with pytest.raises(fm.ArgumentError, match=words):
        fm.simulate(oscillator(), [0.0, 1.0], method="GeneralizedAlpha", **options)


def test_first_and_largest_steps_are_kept():
    result = swing(1e-6, max_step=0.002)
    assert result.stats["nsteps"] >= 4.0 / 0.002
    assert swing(1e-6, first_step=1e-4).success
