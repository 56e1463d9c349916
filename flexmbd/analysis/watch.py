"""What ends a run of one of SciPy's integrators that cannot succeed, soon after it
becomes clear: a point the steps cannot get past (:class:`Crawl`) and a stiffness the
method cannot step over (:class:`Stiffness`)."""

from __future__ import annotations

import time
from collections import deque

import numpy as np

from ..errors import SimulationError, StiffnessError


class StepsCollapsedError(SimulationError):
    """An error-controlled integrator's steps shrank to nothing (see :class:`Crawl`)."""


class Crawl:
    """Ends a run that no longer gets anywhere: the last :data:`CRAWL_STEPS` steps together
    covered less than :data:`CRAWL_SHARE` of the run, so at that pace the run would need
    billions of steps (hours); scipy gives up only at the spacing of floating-point
    numbers. Step sizes that bounce up and down at a point the integrator cannot pass
    (an implicit method at aligned redundant constraints) are caught as well as steady
    shrinking, a fraction of a second after the point is reached."""

    def __init__(self, span: float, method: str, explicit: bool):
        self.least = CRAWL_SHARE * span
        self.method, self.explicit = method, explicit
        self.steps: deque[float] = deque(maxlen=CRAWL_STEPS)

    def check(self, solver) -> None:
        method = self.method
        self.steps.append(solver.step_size)
        if len(self.steps) == CRAWL_STEPS and sum(self.steps) < self.least:
            raise StepsCollapsedError(
                f"the {method} integrator cannot get past t = {solver.t:.6g} s: its last "
                f"{CRAWL_STEPS} steps together covered {sum(self.steps):.2g} s (the last "
                f"{solver.step_size:.2g} s); the motion is not smooth enough there for its "
                f"tolerance (near a singular configuration round-off grows); loosen rtol, "
                f"or use {_OTHERS[self.explicit]}", float(solver.t))


#: what else to try where a method cannot get past a point: for an explicit one (True),
#: an implicit one
_OTHERS = {True: "method='GeneralizedAlpha'",
           False: "method='GeneralizedAlpha' or an explicit method (DOP853, RK45)"}
#: a run stops when its last ``CRAWL_STEPS`` steps together covered less than
#: ``CRAWL_SHARE`` of it
CRAWL_STEPS, CRAWL_SHARE = 200, 1e-7


#: how far an explicit method's step reaches along the imaginary axis, ``h rho``, before
#: it turns unstable on an undamped mode (RK23 1.7, RK45 3.3, DOP853 6)
STABLE_REACH = {"RK23": 1.7, "RK45": 3.3, "DOP853": 6.0}
#: an explicit step that reaches at least this share of :data:`STABLE_REACH` on the fastest
#: mode is held there by stability, not by the accuracy the tolerances ask (a mode
#: resolved to rtol 1e-6 takes steps of about 0.3 / rho, to 1e-10 about 0.5 / rho with
#: DOP853)
HELD_BY_FASTEST = 0.5
#: an implicit step shorter than this many ``1/rho`` (half a period) does not step over
#: the fastest mode, as an implicit method is meant to
STEPS_OVER = 3.0
#: a mode that makes at least this many periods over the run is fast against the motion:
#: resolving it is what makes the run slow (the course's rod vibrates 30 times in its
#: run, a rod of 1e8 times its stiffness 3e5 times)
FAST_PERIODS = 1000.0
#: wall-clock seconds between looks at a run's pace, and the projected duration beyond
#: which a stiff run is stopped
STIFF_LOOK, STIFF_PROJECTED = 2.0, 30.0


class Stiffness:
    """Stops a run that crawls because the problem is stiff for its method. Every
    :data:`STIFF_LOOK` seconds, when the run at its pace so far would take longer than
    :data:`STIFF_PROJECTED` seconds, the fastest mode's rate ``rho`` (the spectral radius
    of ``df/dy``, by power iteration on finite differences of ``fun``) is compared with
    the step and the run's span. A mode fast against the motion (:data:`FAST_PERIODS` of
    its periods or more over the run) that sets the steps of an explicit method (``h rho``
    at least :data:`HELD_BY_FASTEST` of its :data:`STABLE_REACH`: stability, not accuracy,
    sets them) or that an implicit one does not step over (``h
    rho`` below :data:`STEPS_OVER`: its finite-difference Jacobian of the accelerations
    does not follow that mode) is what generalized-alpha steps over. The outputs play no
    part: how often a run reports does not change how stiff it is."""

    def __init__(self, fun, t_eval: np.ndarray, method: str, explicit: bool,
                 clock=time.monotonic):
        self.fun, self.method, self.explicit, self.clock = fun, method, explicit, clock
        self.t0, self.t_end = float(t_eval[0]), float(t_eval[-1])
        self.start = clock()
        self.next = self.start + STIFF_LOOK

    def check(self, solver) -> None:
        now = self.clock()
        if now < self.next:
            return
        self.next = now + STIFF_LOOK
        done = (solver.t - self.t0) / (self.t_end - self.t0)
        projected = (now - self.start) / max(done, 1e-12)
        if projected < STIFF_PROJECTED:
            return
        rho = spectral_radius(self.fun, solver.t, solver.y)
        if rho is None or rho * (self.t_end - self.t0) < 2 * np.pi * FAST_PERIODS:
            return
        reach = solver.step_size * rho
        explicit = self.explicit
        if (reach < HELD_BY_FASTEST * STABLE_REACH[self.method]) if explicit else \
                (reach >= STEPS_OVER):
            return
        why = ("holds its steps to" if explicit else
               "is not stepped over (its finite-difference Jacobian of the accelerations "
               "does not follow that mode): its steps are")
        raise StiffnessError(
            f"the model is stiff for {self.method}: a mode of {rho:.3g} rad/s (a period of "
            f"{2 * np.pi / rho:.2g} s) {why} {solver.step_size:.2g} s, so the run would take "
            f"about "
            f"{_duration(projected)} (t = {solver.t:.6g} s of {self.t_end:.6g} s after "
            f"{now - self.start:.0f} s); use method='GeneralizedAlpha' (the default; flexmbd "
            f"run --method GeneralizedAlpha), which steps over the fast mode",
            float(solver.t))


def _duration(seconds: float) -> str:
    if seconds < 120:
        return f"{seconds:.0f} s"
    return f"{seconds / 60:.0f} min" if seconds < 7200 else f"{seconds / 3600:.0f} h"


def spectral_radius(fun, t: float, y: np.ndarray, iterations: int = 12) -> float | None:
    """``max |lambda|`` of ``df/dy`` at ``(t, y)`` [1/s], by power iteration on ``J^2``
    (whose eigenvalues ``-omega^2`` are real for a mechanism's oscillations ``+-i omega``)
    with ``J v`` from forward differences of ``fun``; ``None`` when ``fun`` fails
    there."""
    try:
        f0 = np.asarray(fun(t, y), dtype=float)
        v = np.random.default_rng(0).standard_normal(len(y))
        v /= np.linalg.norm(v)
        estimate = None
        for _ in range(iterations):
            for _square in range(2):
                delta = np.sqrt(np.finfo(float).eps) * (1.0 + np.linalg.norm(y))
                v = (np.asarray(fun(t, y + delta * v), dtype=float) - f0) / delta
            size = np.linalg.norm(v)
            if not np.isfinite(size) or size == 0.0:
                return None
            estimate, v = np.sqrt(size), v / size
        return estimate
    except SimulationError:
        return None
