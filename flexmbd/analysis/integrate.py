"""Time integration: the methods by name with the options each takes (:data:`METHODS`),
and the front end over SciPy's ``OdeSolver``s.

``GeneralizedAlpha`` is flexmbd's own integrator; it lives in the compiled core
(``flexmbd/engine/csrc/alpha.c``) and integrates models, through :func:`flexmbd.simulate`.
SciPy's methods (``RK45``, the course's ode45, and the others) are stepped here by hand
like ``solve_ivp`` (:func:`integrate`), so that a failed right-hand side (a position
solve that does not converge, a singular configuration) ends the run with the output
computed so far instead of losing it, and so that a run that cannot succeed is stopped
soon (:mod:`flexmbd.analysis.watch`).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from contextlib import nullcontext
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .. import checks
from ..errors import ArgumentError, ConvergenceError, SimulationError
from ..progress import progress_bar
from ..summary import dataclass_repr
from .watch import Crawl, Stiffness


@dataclass(frozen=True)
class Method:
    """An integration method: its name, whether it is explicit, whether the compiled core
    runs it (else SciPy), the options it takes besides ``rtol`` and ``atol`` (keyword
    arguments of :func:`flexmbd.simulate`) and what it is."""

    name: str
    explicit: bool
    in_core: bool
    options: tuple[str, ...]
    summary: str


#: the tolerances of every method by default (relative; absolute on ``[q_d, qdot_d]``)
RTOL, ATOL = 1e-6, 1e-9
#: SciPy's options that flexmbd passes on: the largest step and the first one [s]
SCIPY_OPTIONS = ("max_step", "first_step")
#: generalized-alpha's options (:class:`AlphaOptions`)
ALPHA_OPTIONS = ("step", "rho_inf", "iterations", "renew_every", "max_step", "first_step")

#: the integration methods by name
METHODS: dict[str, Method] = {method.name: method for method in (
    Method("RK45", True, False, SCIPY_OPTIONS, "explicit Runge-Kutta 5(4), Dormand-Prince"),
    Method("RK23", True, False, SCIPY_OPTIONS, "explicit Runge-Kutta 3(2), Bogacki-Shampine"),
    Method("DOP853", True, False, SCIPY_OPTIONS, "explicit Runge-Kutta 8(5,3), Dormand-Prince"),
    Method("Radau", False, False, SCIPY_OPTIONS, "implicit Runge-Kutta (Radau IIA, order 5)"),
    Method("BDF", False, False, SCIPY_OPTIONS, "backward differentiation formulas"),
    Method("LSODA", False, False, SCIPY_OPTIONS, "Adams and BDF, switching (ODEPACK)"),
    Method("GeneralizedAlpha", False, True, ALPHA_OPTIONS,
           "generalized-alpha, implicit, in the compiled core: steps controlled by its "
           "local error, or fixed ones of `step`"),
)}
#: :func:`flexmbd.simulate`'s method when none is given: error-controlled generalized-alpha,
#: which steps over the stiff modes of flexible bodies that explicit methods must resolve
DEFAULT_METHOD = "GeneralizedAlpha"
#: the explicit methods' names
EXPLICIT = tuple(name for name, method in METHODS.items() if method.explicit)


def check_method(method: str) -> Method:
    """The :class:`Method` named ``method``, or an :class:`ArgumentError` listing them."""
    if not isinstance(method, str) or method not in METHODS:
        raise ArgumentError("method", f"unknown method {method!r}; choose from "
                                      f"{', '.join(METHODS)}")
    return METHODS[method]


def check_options(method: Method, options: Mapping[str, Any]) -> dict[str, Any]:
    """``options`` for ``method``; a name it does not take is refused, saying which
    method it belongs to and which options ``method`` takes."""
    for name in options:
        if name in method.options:
            continue
        owners = [m.name for m in METHODS.values() if name in m.options]
        whose = (f"options that belong to {' and '.join(sorted(set(owners)))} are not "
                 f"{method.name}'s" if owners else "no method takes it")
        raise ArgumentError(name, f"{whose}; {method.name} takes {', '.join(method.options)} "
                                  f"(and rtol, atol)")
    return dict(options)


@dataclass(frozen=True)
class ScipyOptions:
    """The settings of one of SciPy's methods (see :func:`flexmbd.simulate`)."""

    rtol: float = RTOL
    atol: float = ATOL
    max_step: float = np.inf
    first_step: float | None = None

    def __post_init__(self):
        if not (isinstance(self.max_step, float) and self.max_step == np.inf) and \
                not checks.real(self.max_step, "max_step") > 0:
            raise ArgumentError("max_step", f"must be positive, got {self.max_step!r}")
        if self.first_step is not None and not checks.real(self.first_step,
                                                            "first_step") > 0:
            raise ArgumentError("first_step", f"must be positive, got {self.first_step!r}")

    def solver_arguments(self) -> dict[str, float]:
        """The keyword arguments of SciPy's solver."""
        out = {"rtol": self.rtol, "atol": self.atol, "max_step": float(self.max_step)}
        if self.first_step is not None:
            out["first_step"] = float(self.first_step)
        return out


@dataclass(frozen=True)
class AlphaOptions:
    """The settings of generalized-alpha (see :func:`flexmbd.simulate` for their meaning):
    fixed steps of ``step`` [s], or with ``adaptive`` steps that follow the local error,
    the first ``step`` (0: chosen from the state), at most ``max_step``."""

    step: float
    rho_inf: float = 0.8
    rtol: float = RTOL
    atol: float = ATOL
    iterations: int | None = None
    renew_every: int = 1
    adaptive: bool = False
    max_step: float = np.inf

    def __post_init__(self):
        if not (checks.real(self.step, "step") > 0 or (self.adaptive and self.step == 0)):
            raise ArgumentError("step", f"must be positive, got {self.step}")
        if not 0.0 <= checks.real(self.rho_inf, "rho_inf") <= 1.0:
            raise ArgumentError("rho_inf", f"must lie in [0, 1], got {self.rho_inf}")
        if self.iterations is not None:
            checks.whole(self.iterations, "iterations", 1, checks.LARGEST_ITERATIONS)
        checks.whole(self.renew_every, "renew_every", 1, checks.LARGEST_STEPS)

    def core_arguments(self) -> dict[str, float | int | bool]:
        """The keyword arguments of the core's generalized-alpha runs."""
        return {"step": float(self.step), "rho_inf": float(self.rho_inf),
                "rtol": float(self.rtol), "atol": float(self.atol),
                "iterations": int(self.iterations or 0), "renew_every": int(self.renew_every),
                "adaptive": bool(self.adaptive), "max_step": float(self.max_step)}


@dataclass(eq=False)
class IntegrationResult:
    """Solution at the requested times and the solver's counters.

    Attributes:
        t: output times reached ``(nt,)``; y: states ``(nt, ny)``.
        success, message, error: as in ``solve_ivp``, plus the exception that stopped the run.
        stats: ``nfev``, ``njev``, ``nlu``, ``nsteps``.
    """

    __repr__ = dataclass_repr

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
              t_eval: np.ndarray, *, method: str = "RK45", rtol: float = RTOL,
              atol: float = ATOL, progress: bool | Callable | None = None,
              on_output: Callable[[int, float, np.ndarray], None] | None = None,
              on_reject: Callable[[float, np.ndarray], None] | None = None,
              stop: Callable[[float, np.ndarray], bool] | None = None,
              **options) -> IntegrationResult:
    """Integrate ``y' = fun(t, y)`` from ``t_eval[0]`` to ``t_eval[-1]`` with one of
    SciPy's methods, output at ``t_eval``; ``options`` are the method's
    (:data:`METHODS`: ``max_step``, ``first_step`` [s]).

    ``on_output(k, t, y)``, when given, is called as soon as output ``k`` is reached (right
    after the step that passes it); a :class:`SimulationError` it raises ends the run
    there. An explicit method's trial step whose stages leave the reach of the position
    solve (``fun`` raises a :class:`ConvergenceError`) is retried smaller, and
    ``on_reject(t, y)`` is told the state the step started from. ``stop(t, y)``, when
    given, is asked after every step (and its outputs) whether the run ends there; the
    result then has ``stopped`` set and ``end`` at that step. An interrupt (Ctrl-C) ends
    the run like a failure: the outputs so far are returned, with the
    ``KeyboardInterrupt`` as ``error``.

    Raises:
        ArgumentError: an unknown ``method`` or option, GeneralizedAlpha (it integrates
            models only, with :func:`flexmbd.simulate`), or bad ``t_eval``.
    """
    spec = check_method(method)
    if spec.in_core:
        raise ArgumentError("method", "GeneralizedAlpha integrates models in the compiled "
                                      "core: use flexmbd.simulate(model, ..., "
                                      "method='GeneralizedAlpha')")
    settings = ScipyOptions(rtol, atol, **check_options(spec, options))
    return _integrate_scipy(fun, np.array(y0, dtype=float), _check_grid(t_eval), spec,
                            settings, progress=progress, on_output=on_output,
                            on_reject=on_reject, stop=stop)


#: times in a row an explicit trial step is retried smaller because its stages left the
#: reach of the position solve, before the run gives up with that failure
STEP_RETRIES = 40


class _Retrying:
    """``fun`` for an explicit method of SciPy's: a trial stage beyond the reach of the
    position solve (a :class:`ConvergenceError`, as a stiff model's first, guessed step
    can ask for) gives a value that is not finite, which rejects the trial step: SciPy's
    Runge-Kutta methods then retry it five times smaller (their public behaviour for an
    error estimate that is not finite; they offer no hook to retry a step, and flexmbd
    writes none of their attributes). ``on_reject`` restarts the position solves from
    the state the step started from. After :data:`STEP_RETRIES` such failures in a row
    the last one ends the run."""

    def __init__(self, fun, on_reject):
        self.fun, self.on_reject = fun, on_reject
        self.solver, self.failures = None, 0
        self.last: ConvergenceError | None = None  #: the last failure of this step

    def __call__(self, t, y):
        if self.failures and not np.all(np.isfinite(y)):  # a later stage of a failed trial
            return np.full(len(y), np.nan)
        try:
            value = self.fun(t, y)
        except ConvergenceError as failure:
            self.failures += 1
            self.last = failure
            if self.solver is None or self.failures > STEP_RETRIES:
                raise
            if self.on_reject is not None:
                self.on_reject(self.solver.t, self.solver.y)
            return np.full(len(y), np.nan)
        return value

    def accepted(self) -> None:
        """A step was taken: the failures in a row start again from zero."""
        self.failures, self.last = 0, None


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


def _integrate_scipy(fun, y0: np.ndarray, t_eval: np.ndarray, spec: Method,
                     settings: ScipyOptions, *, progress, on_output, on_reject,
                     stop) -> IntegrationResult:
    import scipy.integrate

    method = spec.name
    if spec.explicit:
        fun = _Retrying(fun, on_reject)
    ys = np.empty((len(t_eval), len(y0)))
    k, nsteps, error, message, stopped = 0, 0, None, "completed", False
    try:  # the start evaluates the state: a failure there is a run of no (or one) output
        if on_output is not None:
            on_output(0, t_eval[0], y0)
        ys[0], k = y0, 1
        solver = getattr(scipy.integrate, method)(fun, t_eval[0], y0, t_eval[-1],
                                                  **settings.solver_arguments())
    except (SimulationError, KeyboardInterrupt) as err:
        return IntegrationResult(t_eval[:k], ys[:k], False, str(err) or "interrupted", err,
                                 {"nfev": 1, "njev": 0, "nlu": 0, "nsteps": 0})
    if spec.explicit:
        fun.solver = solver
    bar = nullcontext(progress) if callable(progress) else \
        progress_bar(t_eval, f"simulating ({method})", progress)
    crawl = Crawl(t_eval[-1] - t_eval[0], method, spec.explicit)
    stiffness = Stiffness(fun, t_eval, method, spec.explicit)
    with bar as advance:
        while solver.status == "running":
            try:
                step_message = solver.step()
                nsteps += 1
                if solver.status == "failed":
                    if spec.explicit and fun.last is not None:  # why the step shrank
                        raise fun.last
                    message = (f"the {method} integrator failed at t = {solver.t:.6g} s: "
                               f"{step_message}")
                    break
                if spec.explicit:
                    fun.accepted()
                crawl.check(solver)
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
