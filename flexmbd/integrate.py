"""Time integration front end over scipy's ``OdeSolver`` classes.

Like ``solve_ivp`` but stepping the solver itself, so that a failed right-hand
side (a position solve that does not converge, a singular configuration) ends
the run with the output computed so far instead of losing it, and a progress
bar can follow the steps.
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


def solver_class(method: str) -> type:
    """The solver class of ``method`` (scipy's are imported only when asked for)."""
    check_method(method)
    if method == "GeneralizedAlpha":
        from .generalized_alpha import GeneralizedAlpha

        return GeneralizedAlpha
    import scipy.integrate

    return getattr(scipy.integrate, method)


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


def integrate(fun: Callable[[float, np.ndarray], np.ndarray], y0: np.ndarray,
              t_eval: np.ndarray, *, method: str = "RK45", rtol: float = 1e-6,
              atol: float | np.ndarray = 1e-9, max_step: float = np.inf,
              progress: bool | None = None, on_output: Callable[[int], None] | None = None,
              **options) -> IntegrationResult:
    """Integrate ``y' = fun(t, y)`` from ``t_eval[0]`` to ``t_eval[-1]``, output at ``t_eval``.

    ``on_output(k)``, when given, is called as soon as output ``k`` is reached (right
    after the step that passes ``t_eval[k]``). Other ``options`` go to the solver
    (e.g. ``step`` and ``system`` of :class:`~flexmbd.generalized_alpha.GeneralizedAlpha`).

    Raises:
        ValueError: an unknown ``method`` or bad ``t_eval``.
    """
    solver_type = solver_class(method)
    t_eval = np.asarray(t_eval, dtype=float)
    if t_eval.size < 2 or np.any(np.diff(t_eval) <= 0):
        raise ValueError("output times must be at least two, strictly increasing")
    ys = [np.array(y0, dtype=float)]
    solver = solver_type(fun, t_eval[0], ys[0], t_eval[-1], rtol=rtol, atol=atol,
                         max_step=max_step, **options)
    if on_output is not None:
        on_output(0)
    k, nsteps, error, message = 1, 0, None, "completed"
    span = t_eval[-1] - t_eval[0]
    with progress_bar(1000, f"simulating ({method})", progress) as bar:
        done_permille = 0
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
            # an output within round-off of the step's end is reached by this step: fixed
            # steps accumulate round-off in t (about 1e-16 t per step); such an output
            # would otherwise wait for the next step (and start its solve from there)
            round_off = 1e-9 * (solver.t - solver.t_old)
            if k < len(t_eval) and t_eval[k] <= solver.t + round_off:
                dense = None
                while k < len(t_eval) and t_eval[k] <= solver.t + round_off:
                    if t_eval[k] >= solver.t - round_off:  # at the end of the step
                        ys.append(solver.y.copy())
                    else:
                        dense = dense or solver.dense_output()
                        ys.append(dense(t_eval[k]))
                    if on_output is not None:
                        on_output(k)
                    k += 1
            permille = int(1000 * (solver.t - t_eval[0]) / span)
            if permille > done_permille:
                bar.update(permille - done_permille)
                done_permille = permille
    stats = {"nfev": solver.nfev, "njev": solver.njev, "nlu": solver.nlu, "nsteps": nsteps}
    success = error is None and solver.status == "finished"
    return IntegrationResult(t_eval[:k], np.array(ys), success, message, error, stats)
