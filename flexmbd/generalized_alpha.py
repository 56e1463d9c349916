"""Generalized-alpha time stepping for second-order systems, as a scipy ``OdeSolver``.

The flexible slider-crank with several beams has bending (and, with a flexible
elongation, axial) modes far above the motion of interest. Explicit methods
must resolve them for stability; the generalized-alpha method of Chung and
Hulbert (1993) steps over them with controllable numerical damping (spectral
radius ``rho_inf`` at infinite frequency) and stays second-order accurate for
the slow motion. This is the integrator of Exudyn and most multibody codes.

The system is ``y = [q; v]``, ``y' = [v; a(t, q, v)]`` (the form of
:func:`flexmbd.simulate`'s state). Per step the unknown is ``a_{n+1}``; the
Newmark formulas turn it into ``q_{n+1}, v_{n+1}`` and Newton solves
``a_{n+1} = a(t_{n+1}, q_{n+1}, v_{n+1})`` with a finite-difference Jacobian
that is kept as long as Newton converges fast (modified Newton). The step is
fixed (``step``), halved only when Newton fails.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
from scipy.integrate import DenseOutput, OdeSolver

from .errors import SimulationError

_MAX_NEWTON = 8
_SLOW_RATE = 0.5  # contraction per Newton iteration above which the Jacobian is renewed
_MAX_HALVINGS = 12


class GeneralizedAlpha(OdeSolver):
    """Fixed-step generalized-alpha method (Chung-Hulbert) for ``y = [q; v]``.

    Args:
        fun: ``fun(t, y) -> [v; a]``, with ``y`` of even length ``2 n``.
        t0, y0, t_bound: as for every ``OdeSolver``.
        step: step size [s] (default: 1/1000 of the interval). There is no error
            control: choose it from the frequencies that matter (20 or more steps
            per period for about 1e-3 relative accuracy per period).
        rho_inf: spectral radius at infinite frequency, 0 (strongest damping of
            unresolved modes) to 1 (none, the trapezoidal rule). Default 0.8.
        rtol, atol: tolerances of the Newton iteration on ``[q; v]``.
        max_step: an upper bound on ``step`` (as in the other solvers).
    """

    def __init__(self, fun, t0, y0, t_bound, *, step: float | None = None,
                 rho_inf: float = 0.8, rtol: float = 1e-6, atol: float = 1e-9,
                 max_step: float = np.inf, vectorized: bool = False, **extraneous):
        super().__init__(fun, t0, y0, t_bound, vectorized)
        if self.n % 2:
            raise ValueError("generalized-alpha needs a state [q; v] of even length")
        if not 0.0 <= rho_inf <= 1.0:
            raise ValueError(f"rho_inf must lie in [0, 1], got {rho_inf}")
        span = abs(t_bound - t0)
        step = span / 1000 if step is None else float(step)
        if not step > 0:
            raise ValueError(f"step must be positive, got {step}")
        self.h_nominal = min(step, max_step, span) if span > 0 else step
        self.rtol, self.atol = rtol, atol
        # Chung-Hulbert parameters: second order, damping set by rho_inf
        self.alpha_m = (2 * rho_inf - 1) / (rho_inf + 1)
        self.alpha_f = rho_inf / (rho_inf + 1)
        self.gamma = 0.5 - self.alpha_m + self.alpha_f
        self.beta = 0.25 * (1 - self.alpha_m + self.alpha_f) ** 2
        self.m = self.n // 2
        self.a = self.fun(self.t, self.y)[self.m:]
        self.aa = self.a.copy()  # the algorithmic acceleration of the method
        self.jacobian: np.ndarray | None = None
        self.jacobian_fresh = False
        self.lu, self.lu_step = None, None
        self.njev = self.nlu = 0
        self._previous = None
        self.trial_error: SimulationError | None = None

    # --- Newton ingredients -------------------------------------------------------------
    def _update_jacobian(self, t, y, f):
        """Forward differences of ``a(t, q, v)`` with respect to ``[q; v]``, ``(m, 2m)``."""
        delta = 1e-6 * np.maximum(np.abs(y), self.atol / self.rtol)
        J = np.empty((self.m, self.n))
        for j in range(self.n):
            yj = y.copy()
            yj[j] += delta[j]
            J[:, j] = (self.fun(t, yj)[self.m:] - f) / delta[j]
        self.jacobian, self.jacobian_fresh, self.lu = J, True, None
        self.njev += 1

    def _factor(self, h):
        """LU of ``I - c (beta h^2 da/dq + gamma h da/dv)``, ``c = (1-alpha_f)/(1-alpha_m)``."""
        c = (1 - self.alpha_f) / (1 - self.alpha_m)
        J = self.jacobian
        G = np.eye(self.m) - c * (self.beta * h**2 * J[:, :self.m] + self.gamma * h * J[:, self.m:])
        self.lu, self.lu_step = scipy.linalg.lu_factor(G, check_finite=False), h
        self.nlu += 1

    def _predict(self, h, a_new):
        """``q, v`` at the end of the step for the end acceleration ``a_new``."""
        m = self.m
        q, v = self.y[:m], self.y[m:]
        aa_new = ((1 - self.alpha_f) * a_new + self.alpha_f * self.a
                  - self.alpha_m * self.aa) / (1 - self.alpha_m)
        q_new = q + h * v + h**2 * ((0.5 - self.beta) * self.aa + self.beta * aa_new)
        v_new = v + h * ((1 - self.gamma) * self.aa + self.gamma * aa_new)
        return np.concatenate([q_new, v_new]), aa_new

    def _newton(self, h):
        """Solve the step of size ``h``; returns ``(y, a, aa)`` or ``None`` if it failed."""
        t_new = self.t + h * self.direction
        if self.lu is None or self.lu_step != h:
            self._factor(h)
        c = (1 - self.alpha_f) / (1 - self.alpha_m)
        a_new = self.a.copy()
        previous = None
        for _ in range(_MAX_NEWTON):
            y_new, aa_new = self._predict(h, a_new)
            try:
                residual = a_new - self.fun(t_new, y_new)[self.m:]
            except SimulationError as err:
                self.trial_error = err  # a state the position solve rejects: retry smaller
                return None
            da = -scipy.linalg.lu_solve(self.lu, residual, check_finite=False)
            a_new = a_new + da
            dy = np.concatenate([self.beta * h**2 * c * da, self.gamma * h * c * da])
            size = np.sqrt(np.mean((dy / (self.atol + self.rtol * np.abs(y_new))) ** 2))
            if size < 0.1:
                y_new, aa_new = self._predict(h, a_new)
                return y_new, a_new, aa_new
            if previous is not None and size > _SLOW_RATE * previous and size > 1.0:
                return None
            previous = size
        return None

    # --- OdeSolver interface ------------------------------------------------------------
    def _step_impl(self):
        h = min(self.h_nominal, abs(self.t_bound - self.t))
        if self.jacobian is None:
            self._update_jacobian(self.t, self.y, self.a)
        outcome = None
        for _ in range(_MAX_HALVINGS):
            outcome = self._newton(h)
            if outcome is not None:
                break
            if not self.jacobian_fresh:  # first renew the Jacobian, then halve the step
                self._update_jacobian(self.t, self.y, self.fun(self.t, self.y)[self.m:])
                continue
            h /= 2
        if outcome is None:
            if self.trial_error is not None:
                raise self.trial_error
            return False, (f"Newton iteration of the generalized-alpha step failed at "
                           f"t = {self.t:.6g} s even with step {h:.3g} s")
        y_new, a_new, aa_new = outcome
        self._previous = (self.t, self.y, self.a)
        self.t_old = self.t
        self.t = self.t + h * self.direction
        self.y, self.a, self.aa = y_new, a_new, aa_new
        self.jacobian_fresh, self.trial_error = False, None
        return True, None

    def _dense_output_impl(self):
        t0, y0, a0 = self._previous
        return _HermiteOutput(t0, self.t, y0, a0, self.y, self.a)


class _HermiteOutput(DenseOutput):
    """Cubic Hermite interpolation of ``q`` (with ``v``) and of ``v`` (with ``a``)."""

    def __init__(self, t0, t1, y0, a0, y1, a1):
        super().__init__(t0, t1)
        m = len(y0) // 2
        self.h = t1 - t0
        self.values = (y0, y1)
        self.slopes = (np.concatenate([y0[m:], a0]), np.concatenate([y1[m:], a1]))

    def _call_impl(self, t):
        s = (np.asarray(t) - self.t_old) / self.h
        h00, h10 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s
        h01, h11 = -2 * s**3 + 3 * s**2, s**3 - s**2
        (y0, y1), (d0, d1) = self.values, self.slopes
        if np.ndim(t) == 0:
            return h00 * y0 + h10 * self.h * d0 + h01 * y1 + h11 * self.h * d1
        return (np.outer(y0, h00) + np.outer(d0, h10 * self.h) + np.outer(y1, h01)
                + np.outer(d1, h11 * self.h))
