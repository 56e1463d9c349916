"""Equations of motion generated from the symbolic path, and a simulation driven by them.

The course derived its equations symbolically and generated numeric functions for its
Simulink models. :class:`GeneratedEquations` does the same from
:mod:`flexmbd.analysis.symbolic`: the deformations and their Jacobian (for the Newton-Raphson
position solve), ``F_q``, ``Mbar`` and the right-hand side of ``Mbar qddot = rhs`` are
turned into numpy functions with common subexpressions eliminated, and
:meth:`GeneratedEquations.simulate` integrates ``Mbar_dd qddot_d = rhs_d - Mbar_dr
qddot_r`` with SciPy's ``solve_ivp``. It is an independent route to the compiled
engine's results (the tests compare the two) and a readable model of what the engine
does; for speed use :func:`flexmbd.simulate`. Needs SymPy and SciPy.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ConvergenceError, SingularConfigurationError
from ..model import Model
from . import symbolic
from .kinematics import initial_q


@dataclass(frozen=True)
class GeneratedRun:
    """A simulation by generated functions: times ``t`` ``(nt,)`` [s], coordinates ``x``
    ``(nt, nx)`` and generalized coordinates ``q`` ``(nt, nq)``."""

    t: np.ndarray
    x: np.ndarray
    q: np.ndarray


class GeneratedEquations:
    """Numeric functions of one model's symbolic equations (generated once, in seconds).

    Args:
        model: the model; its input laws prescribe ``q_r``.
        lumped: lumped or consistent element masses for all elements (default: the
            model's choice).
    """

    def __init__(self, model: Model, lumped: bool | None = None):
        self.model = model
        x = list(symbolic.coordinate_symbols(model))
        qd = list(symbolic.generalized_symbols(model, "d"))
        Mbar, rhs = symbolic.equations_of_motion(model, lumped)
        e = symbolic.deformations(model)
        self._residual = symbolic.numeric_function([x], e)
        self._jacobian = symbolic.numeric_function([x], e.jacobian(x))
        self._transfer = symbolic.numeric_function([x], symbolic.first_order_transfer(
            model, simplify=False))
        self._equations = symbolic.numeric_function([x, qd], [Mbar, rhs])
        self._rows = list(model.rigid) + list(model.independent_deformations)
        self._dependent = list(model.dependent)
        self._x_m = list(model.independent_coordinates)
        self._n_xm = len(self._x_m)
        self._input = np.asarray(model.q_is_input)

    def positions(self, q: np.ndarray, guess: np.ndarray, tolerance: float = 1e-12,
                  iterations: int = 30) -> np.ndarray:
        """``x`` ``(nx,)`` for ``q`` ``(nq,)`` by Newton-Raphson from ``guess`` (THEORY 3)."""
        x = np.array(guess, dtype=float)
        x[self._x_m] = q[:self._n_xm]
        target = np.zeros(len(self._rows))
        target[len(self.model.rigid):] = q[self._n_xm:]
        for _ in range(iterations):
            r = np.ravel(self._residual(x))[self._rows] - target
            if np.max(np.abs(r), initial=0.0) < tolerance:
                return x
            D_c = np.asarray(self._jacobian(x), dtype=float)[np.ix_(self._rows, self._dependent)]
            try:
                x[self._dependent] -= np.linalg.solve(D_c, r)
            except np.linalg.LinAlgError:
                raise SingularConfigurationError("singular D_c in the generated position "
                                                 "solve") from None
        raise ConvergenceError(f"the generated position solve did not converge in "
                               f"{iterations} iterations (residual {np.max(np.abs(r)):.3g})")

    def accelerations(self, x: np.ndarray, qd: np.ndarray, qdd_r: np.ndarray) -> np.ndarray:
        """``qddot_d`` from ``Mbar_dd qddot_d = rhs_d - Mbar_dr qddot_r`` (THEORY 7)."""
        Mbar, rhs = (np.asarray(a, dtype=float) for a in self._equations(x, qd))
        d, r = ~self._input, self._input
        rhs = np.ravel(rhs)[d] - Mbar[np.ix_(d, r)] @ qdd_r
        return np.linalg.solve(Mbar[np.ix_(d, d)], rhs)

    def velocities(self, x: np.ndarray, qd: np.ndarray) -> np.ndarray:
        """``xdot = F_q qdot`` ``(nx,)``."""
        return np.asarray(self._transfer(x), dtype=float) @ qd

    def simulate(self, times, rtol: float = 1e-10, atol: float = 1e-12,
                 method: str = "DOP853") -> GeneratedRun:
        """Integrate from the model's initial configuration, dynamic entries at rest
        (rigid-body velocities of the inputs), to the output ``times`` [s]."""
        from scipy.integrate import solve_ivp

        model, d = self.model, ~self._input
        laws = [model.input_laws[label] for label, is_input
                in zip(model.q_labels, self._input, strict=True) if is_input]
        times = np.asarray(times, dtype=float)
        state = {"x": np.array(model.x0, dtype=float)}

        def full_q(t, y):
            values = np.array([law(t) for law in laws]).reshape(-1, 3)
            q, qd = np.empty(model.n_dof), np.empty(model.n_dof)
            q[d], qd[d] = np.split(y, 2)
            q[self._input], qd[self._input] = values[:, 0], values[:, 1]
            return q, qd, values[:, 2]

        def rhs(t, y):
            q, qd, qdd_r = full_q(t, y)
            state["x"] = x = self.positions(q, state["x"])
            return np.concatenate([qd[d], self.accelerations(x, qd, qdd_r)])

        q0 = initial_q(model)[d]
        y0 = np.concatenate([q0, np.zeros_like(q0)])
        run = solve_ivp(rhs, (times[0], times[-1]), y0, method=method, t_eval=times,
                        rtol=rtol, atol=atol)
        if not run.success:
            raise ConvergenceError(f"the generated simulation stopped: {run.message}")
        q_all, x_all, guess = [], [], np.array(model.x0, dtype=float)
        for t, y in zip(run.t, run.y.T, strict=True):
            q, _, _ = full_q(t, y)
            guess = self.positions(q, guess)
            q_all.append(q)
            x_all.append(guess)
        return GeneratedRun(run.t, np.array(x_all), np.array(q_all))
