"""Time integration: the methods by name, and the front end over scipy's ``OdeSolver``s.

``GeneralizedAlpha`` is flexmbd's own integrator and lives in the compiled core
(``flexmbd/csrc/alpha.c``): for a model it runs the whole simulation there
(:func:`flexmbd.simulate`), and for any ``y' = fun(t, y)`` with ``y = [q; v]``
:func:`integrate` drives it with ``fun`` called back. scipy's methods (``RK45``,
the course's ode45, and the others) are stepped here by hand like ``solve_ivp``,
so that a failed right-hand side (a position solve that does not converge, a
singular configuration) ends the run with the output computed so far instead of
losing it.
"""

from __future__ import annotations

from collections.abc import Callable
from contextlib import nullcontext
from dataclasses import dataclass, field

import numpy as np

from . import checks
from .errors import ArgumentError, ConvergenceError, SimulationError
from .progress import progress_bar

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
    """Ends a run whose steps have shrunk to nothing: more than :data:`CRAWL_STEPS` steps
    in a row each shorter than :data:`CRAWL_SHARE` of the run would take hours to get
    anywhere (scipy gives up only at the spacing of floating-point numbers)."""

    def __init__(self, span: float):
        self.smallest, self.count = CRAWL_SHARE * span, 0

    def check(self, solver, method: str) -> None:
        self.count = self.count + 1 if solver.step_size < self.smallest else 0
        if self.count > CRAWL_STEPS:
            raise StepsCollapsedError(
                f"the {method} integrator's steps shrank to {solver.step_size:.2g} s at "
                f"t = {solver.t:.6g} s: the motion is not smooth enough there for its "
                f"tolerance (near a singular configuration round-off grows); loosen rtol "
                f"or use method='GeneralizedAlpha'", float(solver.t))


#: a run stops when this many steps in a row each cover less than this share of it
CRAWL_STEPS, CRAWL_SHARE = 1000, 1e-10


def _outputs(solver, t_eval, k: int, ys: list, on_output) -> int:
    """Append the outputs from ``t_eval[k]`` that the solver's last step passed; returns the
    next ``k``. An output whose ``on_output`` raises is not kept."""
    dense = None
    while k < len(t_eval) and t_eval[k] <= solver.t:
        if t_eval[k] == solver.t:
            y = solver.y.copy()
        else:
            dense = dense or solver.dense_output()
            y = dense(t_eval[k])
        if on_output is not None:
            on_output(k, t_eval[k], y)
        ys.append(y)
        k += 1
    return k


def _integrate_scipy(fun, y0, t_eval, method, rtol, atol, max_step, progress, on_output,
                     on_reject, stop, **options) -> IntegrationResult:
    import scipy.integrate

    ys: list[np.ndarray] = []
    k, nsteps, error, message, stopped = 1, 0, None, "completed", False
    try:  # the start evaluates the state: a failure there is a run of no (or one) output
        if on_output is not None:
            on_output(0, t_eval[0], y0)
        ys.append(y0)
        solver = getattr(scipy.integrate, method)(fun, t_eval[0], y0, t_eval[-1], rtol=rtol,
                                                  atol=atol, max_step=max_step, **options)
    except (SimulationError, KeyboardInterrupt) as err:
        return IntegrationResult(t_eval[:len(ys)], np.array(ys).reshape(len(ys), len(y0)),
                                 False, str(err) or "interrupted", err,
                                 {"nfev": 1, "njev": 0, "nlu": 0, "nsteps": 0})
    bar = nullcontext(progress) if callable(progress) else \
        progress_bar(t_eval, f"simulating ({method})", progress)
    crawl = _Crawl(t_eval[-1] - t_eval[0])
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
    return IntegrationResult(t_eval[:len(ys)], np.array(ys), success, message, error, stats,
                             (float(solver.t), solver.y.copy()), stopped)
