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
from dataclasses import dataclass, field

import numpy as np

from .errors import SimulationError
from .progress import progress_bar

#: integration methods by name (the course's ode45 is RK45, the default); all but
#: GeneralizedAlpha (fixed step, for second-order systems y = [q; v]) are scipy's
METHODS = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA", "GeneralizedAlpha")


def check_method(method: str) -> None:
    """Raise ``ValueError`` for a ``method`` that is not in :data:`METHODS`."""
    if method not in METHODS:
        raise ValueError(f"unknown method {method!r}; choose from {', '.join(METHODS)}")


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
        if not (np.isfinite(self.step) and self.step > 0):
            raise ValueError(f"step must be positive, got {self.step}")
        if not 0.0 <= self.rho_inf <= 1.0:
            raise ValueError(f"rho_inf must lie in [0, 1], got {self.rho_inf}")
        if self.iterations is not None and not (
                isinstance(self.iterations, (int, np.integer)) and self.iterations >= 1):
            raise ValueError(f"iterations must be None or a positive integer, got "
                             f"{self.iterations!r}")
        if not (isinstance(self.renew_every, (int, np.integer)) and self.renew_every >= 1):
            raise ValueError(f"renew_every must be a positive integer, got "
                             f"{self.renew_every!r}")

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
    error: SimulationError | None = None
    stats: dict[str, int] = field(default_factory=dict)


def _check_grid(t_eval) -> np.ndarray:
    t_eval = np.asarray(t_eval, dtype=float)
    if t_eval.size < 2 or np.any(np.diff(t_eval) <= 0) or not np.all(np.isfinite(t_eval)):
        raise ValueError("output times must be at least two, finite, strictly increasing")
    return t_eval


def integrate(fun: Callable[[float, np.ndarray], np.ndarray], y0: np.ndarray,
              t_eval: np.ndarray, *, method: str = "RK45", rtol: float = 1e-6,
              atol: float = 1e-9, max_step: float = np.inf, progress: bool | None = None,
              on_output: Callable[[int, float, np.ndarray], None] | None = None,
              **options) -> IntegrationResult:
    """Integrate ``y' = fun(t, y)`` from ``t_eval[0]`` to ``t_eval[-1]`` with one of scipy's
    methods, output at ``t_eval``.

    ``on_output(k, t, y)``, when given, is called as soon as output ``k`` is reached (right
    after the step that passes it); a :class:`SimulationError` it raises ends the run
    there. Other ``options`` go to scipy's solver.

    Raises:
        ValueError: an unknown ``method`` (GeneralizedAlpha integrates models only, with
            :func:`flexmbd.simulate`) or bad ``t_eval``.
    """
    check_method(method)
    if method == "GeneralizedAlpha":
        raise ValueError("GeneralizedAlpha integrates models in the compiled core: use "
                         "flexmbd.simulate(model, ..., method='GeneralizedAlpha')")
    return _integrate_scipy(fun, np.array(y0, dtype=float), _check_grid(t_eval), method, rtol,
                            atol, max_step, progress, on_output, **options)


def _integrate_scipy(fun, y0, t_eval, method, rtol, atol, max_step, progress, on_output,
                     **options) -> IntegrationResult:
    import scipy.integrate

    solver = getattr(scipy.integrate, method)(fun, t_eval[0], y0, t_eval[-1], rtol=rtol,
                                              atol=atol, max_step=max_step, **options)
    ys = [y0]
    if on_output is not None:
        on_output(0, t_eval[0], y0)
    k, nsteps, error, message = 1, 0, None, "completed"
    with progress_bar(t_eval, f"simulating ({method})", progress) as advance:
        while solver.status == "running":
            try:
                step_message = solver.step()
            except SimulationError as err:
                error, message = err, str(err)
                break
            nsteps += 1
            if solver.status == "failed":
                message = f"the {method} integrator failed at t = {solver.t:.6g} s: {step_message}"
                break
            dense = None
            while k < len(t_eval) and t_eval[k] <= solver.t:
                if t_eval[k] == solver.t:
                    ys.append(solver.y.copy())
                else:
                    dense = dense or solver.dense_output()
                    ys.append(dense(t_eval[k]))
                if on_output is not None:
                    try:
                        on_output(k, t_eval[k], ys[-1])
                    except SimulationError as err:
                        error, message = err, str(err)
                        ys.pop()
                        break
                k += 1
            if error is not None:
                break
            if advance is not None:
                advance(solver.t)
    stats = {"nfev": solver.nfev, "njev": solver.njev, "nlu": solver.nlu, "nsteps": nsteps}
    success = error is None and solver.status == "finished"
    return IntegrationResult(t_eval[:len(ys)], np.array(ys), success, message, error, stats)
