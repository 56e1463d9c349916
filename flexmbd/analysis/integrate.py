"""Time integration: the methods by name, and the front end over scipy's ``OdeSolver``s.

``GeneralizedAlpha`` is flexmbd's own integrator and lives in the compiled core
(``flexmbd/engine/csrc/alpha.c``): for a model it runs the whole simulation there
(:func:`flexmbd.simulate`), and for any ``y' = fun(t, y)`` with ``y = [q; v]``
:func:`integrate` drives it with ``fun`` called back. scipy's methods (``RK45``,
the course's ode45, and the others) are stepped here by hand like ``solve_ivp``,
so that a failed right-hand side (a position solve that does not converge, a
singular configuration) ends the run with the output computed so far instead of
losing it.
"""

from __future__ import annotations

import time
from collections import deque
from collections.abc import Callable
from contextlib import nullcontext
from dataclasses import dataclass, field

import numpy as np

from .. import checks
from ..errors import ArgumentError, ConvergenceError, SimulationError, StiffnessError
from ..progress import progress_bar

#: integration methods by name (the course's ode45 is RK45, the default); all but
#: GeneralizedAlpha (fixed step, for second-order systems y = [q; v]) are scipy's
METHODS = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA", "GeneralizedAlpha")


def check_method(method: str) -> None:
    """Raise ``ValueError`` for a ``method`` that is not in :data:`METHODS`."""
    if not isinstance(method, str) or method not in METHODS:
        raise ArgumentError("method", f"unknown method {method!r}; choose from "
                                      f"{', '.join(METHODS)}")


@dataclass(frozen=True)
class AlphaOptions:
    """The settings of generalized-alpha (see :func:`flexmbd.simulate` for their meaning)."""

    step: float
    rho_inf: float = 0.8
    rtol: float = 1e-6
    atol: float = 1e-9
    iterations: int | None = None
    renew_every: int = 1

    def __post_init__(self):
        if not checks.real(self.step, "step") > 0:
            raise ArgumentError("step", f"must be positive, got {self.step}")
        if not 0.0 <= checks.real(self.rho_inf, "rho_inf") <= 1.0:
            raise ArgumentError("rho_inf", f"must lie in [0, 1], got {self.rho_inf}")
        if self.iterations is not None:
            checks.whole(self.iterations, "iterations", 1, checks.LARGEST_ITERATIONS)
        checks.whole(self.renew_every, "renew_every", 1, checks.LARGEST_STEPS)

    def core_arguments(self) -> dict[str, float | int]:
        """The keyword arguments of the core's generalized-alpha runs."""
        return {"step": float(self.step), "rho_inf": float(self.rho_inf),
                "rtol": float(self.rtol), "atol": float(self.atol),
                "iterations": int(self.iterations or 0), "renew_every": int(self.renew_every)}


@dataclass(eq=False)
class IntegrationResult:
    """Solution at the requested times and the solver's counters.

    Attributes:
        t: output times reached ``(nt,)``; y: states ``(nt, ny)``.
        success, message, error: as in ``solve_ivp``, plus the exception that stopped the run.
        stats: ``nfev``, ``njev``, ``nlu``, ``nsteps``.
    """

    t: np.ndarray
    y: np.ndarray
    success: bool
    message: str
    error: SimulationError | KeyboardInterrupt | None = None
    stats: dict[str, int] = field(default_factory=dict)
    #: where the integrator stood when the run ended: time [s] and state ``(ny,)``
    end: tuple[float, np.ndarray] | None = None
    #: whether ``stop`` ended the run
    stopped: bool = False


def _check_grid(t_eval) -> np.ndarray:
    t_eval = checks.time_grid(t_eval, "t_eval")
    if t_eval.size < 2:
        raise ArgumentError("t_eval", "needs at least two times (a start and an end)")
    return t_eval


def integrate(fun: Callable[[float, np.ndarray], np.ndarray], y0: np.ndarray,
              t_eval: np.ndarray, *, method: str = "RK45", rtol: float = 1e-6,
              atol: float = 1e-9, max_step: float = np.inf, progress: bool | None = None,
              on_output: Callable[[int, float, np.ndarray], None] | None = None,
              on_reject: Callable[[float, np.ndarray], None] | None = None,
              stop: Callable[[float, np.ndarray], bool] | None = None,
              **options) -> IntegrationResult:
    """Integrate ``y' = fun(t, y)`` from ``t_eval[0]`` to ``t_eval[-1]`` with one of scipy's
    methods, output at ``t_eval``.

    ``on_output(k, t, y)``, when given, is called as soon as output ``k`` is reached (right
    after the step that passes it); a :class:`SimulationError` it raises ends the run
    there. ``on_reject(t, y)`` is called when an explicit Runge-Kutta step from ``(t, y)``
    is retried smaller because ``fun`` raised a :class:`ConvergenceError`. ``stop(t, y)``,
    when given, is asked after every step (and its outputs) whether the run ends there;
    the result then has ``stopped`` set and ``end`` at that step. Other
    ``options`` go to scipy's solver. An interrupt (Ctrl-C) ends the run like a failure:
    the outputs so far are returned, with the ``KeyboardInterrupt`` as ``error``.

    Raises:
        ArgumentError: an unknown ``method`` (GeneralizedAlpha integrates models only, with
            :func:`flexmbd.simulate`) or bad ``t_eval``.
    """
    check_method(method)
    if method == "GeneralizedAlpha":
        raise ArgumentError("method", "GeneralizedAlpha integrates models in the compiled "
                                      "core: use flexmbd.simulate(model, ..., "
                                      "method='GeneralizedAlpha')")
    return _integrate_scipy(fun, np.array(y0, dtype=float), _check_grid(t_eval), method, rtol,
                            atol, max_step, progress, on_output, on_reject, stop, **options)


#: times an explicit Runge-Kutta step is retried smaller before the run gives up
STEP_RETRIES = 40


def _step(solver, on_reject) -> str | None:
    """One step of ``solver``. An explicit Runge-Kutta trial step whose stages leave the
    reach of the position solve (a :class:`ConvergenceError`, common at the first, guessed
    step of a stiff model) is a rejected step: ``on_reject(t, y)`` is told the state the
    step started from, and the step is retried at a quarter of its size. Such a failure
    leaves scipy's Runge-Kutta state as it was before the step."""
    from scipy.integrate._ivp.rk import RungeKutta

    for _ in range(STEP_RETRIES if isinstance(solver, RungeKutta) else 0):
        try:
            return solver.step()
        except ConvergenceError:
            if on_reject is not None:
                on_reject(solver.t, solver.y)
            solver.h_abs *= 0.25
    return solver.step()


class StepsCollapsedError(SimulationError):
    """An error-controlled integrator's steps shrank to nothing (see :class:`_Crawl`)."""


class _Crawl:
    """Ends a run that no longer gets anywhere: the last :data:`CRAWL_STEPS` steps together
    covered less than :data:`CRAWL_SHARE` of the run, so at that pace the run would need
    billions of steps (hours); scipy gives up only at the spacing of floating-point
    numbers. Step sizes that bounce up and down at a point the integrator cannot pass
    (an implicit method at aligned redundant constraints) are caught as well as steady
    shrinking, a fraction of a second after the point is reached."""

    def __init__(self, span: float):
        self.least = CRAWL_SHARE * span
        self.steps: deque[float] = deque(maxlen=CRAWL_STEPS)

    def check(self, solver, method: str) -> None:
        self.steps.append(solver.step_size)
        if len(self.steps) == CRAWL_STEPS and sum(self.steps) < self.least:
            raise StepsCollapsedError(
                f"the {method} integrator cannot get past t = {solver.t:.6g} s: its last "
                f"{CRAWL_STEPS} steps together covered {sum(self.steps):.2g} s (the last "
                f"{solver.step_size:.2g} s); the motion is not smooth enough there for its "
                f"tolerance (near a singular configuration round-off grows); loosen rtol, "
                f"or use {_OTHERS[method in EXPLICIT]}", float(solver.t))


#: scipy's explicit methods; the others (Radau, BDF, LSODA) solve for their steps
EXPLICIT = ("RK45", "RK23", "DOP853")
#: what else to try where a method cannot get past a point: for an explicit one (True),
#: an implicit one
_OTHERS = {True: "method='GeneralizedAlpha'",
           False: "method='GeneralizedAlpha' or an explicit method (DOP853, RK45)"}
#: a run stops when its last ``CRAWL_STEPS`` steps together covered less than
#: ``CRAWL_SHARE`` of it
CRAWL_STEPS, CRAWL_SHARE = 200, 1e-7


#: an explicit step longer than this share of the fastest mode's ``1/rho`` is set by that
#: mode (resolving it to a tolerance of 1e-6 takes steps of about 0.3 / rho; stability
#: allows up to 1.7 / rho for RK23, 3.3 for RK45, 6 for DOP853)
HELD_BY_FASTEST = 0.3
#: an implicit step shorter than this many ``1/rho`` (half a period) does not step over
#: the fastest mode, as an implicit method is meant to
STEPS_OVER = 3.0
#: outputs this many periods of the fastest mode apart cannot show it: a mode the
#: outputs cannot show, which sets the steps, makes the problem stiff for the method
UNSEEN_PERIODS = 10.0
#: wall-clock seconds between looks at a run's pace, and the projected duration beyond
#: which a stiff run is stopped
STIFF_LOOK, STIFF_PROJECTED = 2.0, 30.0


class _Stiffness:
    """Stops a run that crawls because the problem is stiff for its method. Every
    :data:`STIFF_LOOK` seconds, when the run at its pace so far would take longer than
    :data:`STIFF_PROJECTED` seconds, the fastest mode's rate ``rho`` (the spectral radius
    of ``df/dy``, by power iteration on finite differences of ``fun``) is compared with
    the step and the outputs. A mode that the outputs, :data:`UNSEEN_PERIODS` of its
    periods apart, cannot show, and that sets the steps of an explicit method (``h rho``
    at least :data:`HELD_BY_FASTEST`) or that an implicit one does not step over (``h
    rho`` below :data:`STEPS_OVER`: its finite-difference Jacobian of the accelerations
    does not follow that mode), is what generalized-alpha steps over."""

    def __init__(self, fun, t_eval: np.ndarray, method: str, clock=time.monotonic):
        self.fun, self.method, self.clock = fun, method, clock
        self.t0, self.t_end = float(t_eval[0]), float(t_eval[-1])
        self.interval = (self.t_end - self.t0) / (len(t_eval) - 1)
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
        if rho is None or self.interval * rho < 2 * np.pi * UNSEEN_PERIODS:
            return
        reach = solver.step_size * rho
        explicit = self.method in EXPLICIT
        if (reach < HELD_BY_FASTEST) if explicit else (reach >= STEPS_OVER):
            return
        why = ("holds its steps to" if explicit else
               "is not stepped over (its finite-difference Jacobian of the accelerations "
               "does not follow that mode): its steps are")
        raise StiffnessError(
            f"the model is stiff for {self.method}: a mode of {rho:.3g} rad/s (a period of "
            f"{2 * np.pi / rho:.2g} s, far below the output interval {self.interval:.2g} s) "
            f"{why} {solver.step_size:.2g} s, so the run would take about "
            f"{_duration(projected)} (t = {solver.t:.6g} s of {self.t_end:.6g} s after "
            f"{now - self.start:.0f} s); use method='GeneralizedAlpha' (flexmbd run "
            f"--method GeneralizedAlpha), which steps over the fast mode at steps of the "
            f"output interval", float(solver.t))


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


def _outputs(solver, t_eval, k: int, ys: np.ndarray, on_output) -> int:
    """Fill the rows of ``ys`` from ``t_eval[k]`` on that the solver's last step passed;
    returns the next ``k``. An output whose ``on_output`` raises is not kept."""
    dense = None
    while k < len(t_eval) and t_eval[k] <= solver.t:
        if t_eval[k] == solver.t:
            y = solver.y
        else:
            dense = dense or solver.dense_output()
            y = dense(t_eval[k])
        if on_output is not None:
            on_output(k, t_eval[k], y)
        ys[k] = y
        k += 1
    return k


def _integrate_scipy(fun, y0, t_eval, method, rtol, atol, max_step, progress, on_output,
                     on_reject, stop, **options) -> IntegrationResult:
    import scipy.integrate

    ys = np.empty((len(t_eval), len(y0)))
    k, nsteps, error, message, stopped = 0, 0, None, "completed", False
    try:  # the start evaluates the state: a failure there is a run of no (or one) output
        if on_output is not None:
            on_output(0, t_eval[0], y0)
        ys[0], k = y0, 1
        solver = getattr(scipy.integrate, method)(fun, t_eval[0], y0, t_eval[-1], rtol=rtol,
                                                  atol=atol, max_step=max_step, **options)
    except (SimulationError, KeyboardInterrupt) as err:
        return IntegrationResult(t_eval[:k], ys[:k], False, str(err) or "interrupted", err,
                                 {"nfev": 1, "njev": 0, "nlu": 0, "nsteps": 0})
    bar = nullcontext(progress) if callable(progress) else \
        progress_bar(t_eval, f"simulating ({method})", progress)
    crawl = _Crawl(t_eval[-1] - t_eval[0])
    stiffness = _Stiffness(fun, t_eval, method)
    with bar as advance:
        while solver.status == "running":
            try:
                step_message = _step(solver, on_reject)
                nsteps += 1
                if solver.status == "failed":
                    message = (f"the {method} integrator failed at t = {solver.t:.6g} s: "
                               f"{step_message}")
                    break
                crawl.check(solver, method)
                stiffness.check(solver)
                k = _outputs(solver, t_eval, k, ys, on_output)
                if advance is not None:
                    advance(solver.t)
                if stop is not None and solver.status == "running" and stop(solver.t,
                                                                            solver.y):
                    stopped, message = True, f"stopped at t = {solver.t:.6g} s"
                    break
            except (SimulationError, KeyboardInterrupt) as err:  # keep what was computed
                error, message = err, str(err) or "interrupted"
                break
    stats = {"nfev": solver.nfev, "njev": solver.njev, "nlu": solver.nlu, "nsteps": nsteps}
    success = error is None and (stopped or solver.status == "finished")
    return IntegrationResult(t_eval[:k], ys[:k], success, message, error, stats,
                             (float(solver.t), solver.y.copy()), stopped)
