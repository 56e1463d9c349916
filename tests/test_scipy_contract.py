"""What flexmbd relies on in SciPy's integrators, tested on SciPy itself.

flexmbd steps SciPy's ``OdeSolver``s by hand (:mod:`flexmbd.analysis.integrate`) through
their public interface only (``step``, ``status``, ``t``, ``y``, ``step_size``,
``dense_output``, the counters), and rejects a trial step whose stages left the reach of
the position solve by returning values that are not finite. That an explicit
Runge-Kutta method then retries the step smaller, instead of failing, is SciPy's
behaviour, not a documented promise: these tests hold SciPy to it, so that a release
that changes it fails here and not in a user's simulation. (``pyproject.toml`` keeps
SciPy below its next major version for the same reason.)
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.integrate

EXPLICIT = ["RK45", "RK23", "DOP853"]


@pytest.mark.parametrize("method", EXPLICIT)
def test_a_step_whose_stages_are_not_finite_is_retried_smaller(method):
    failed = []

    def fun(t, y):
        if t > 0 and not failed:   # the first trial step's stages: not finite, once
            failed.append(t)
            return np.full_like(y, np.nan)
        return -y

    solver = getattr(scipy.integrate, method)(fun, 0.0, np.array([1.0]), 1.0,
                                              first_step=0.1)
    assert solver.step() is None and solver.status == "running"
    assert failed and 0.0 < solver.t < 0.1   # taken, and smaller than the rejected trial
    np.testing.assert_allclose(solver.y, np.exp(-solver.t), rtol=1e-6)


@pytest.mark.parametrize("method", EXPLICIT)
def test_a_step_that_never_becomes_finite_fails_the_solver(method):
    """Without a finite stage ever again the step shrinks until SciPy gives up: the
    status flexmbd reads as a failed step (and then reports the position solve's own
    failure)."""
    def fun(t, y):
        return -y if t == 0 else np.full_like(y, np.nan)

    solver = getattr(scipy.integrate, method)(fun, 0.0, np.array([1.0]), 1.0)
    message = solver.step()
    assert solver.status == "failed" and message


@pytest.mark.parametrize("method", [*EXPLICIT, "Radau", "BDF", "LSODA"])
def test_the_interface_flexmbd_steps_through(method):
    """step, status, t, y, step_size, dense_output and the counters nfev, njev, nlu."""
    solver = getattr(scipy.integrate, method)(lambda t, y: -y, 0.0, np.array([1.0]), 1.0,
                                              rtol=1e-8, atol=1e-10)
    while solver.status == "running":
        solver.step()
        assert solver.step_size is not None and solver.step_size > 0
        dense = solver.dense_output()
        middle = solver.t - solver.step_size / 2
        np.testing.assert_allclose(dense(middle), np.exp(-middle), rtol=1e-6)
    assert solver.status == "finished" and solver.t == 1.0
    assert all(isinstance(getattr(solver, name), int | np.integer)
               for name in ("nfev", "njev", "nlu"))
