"""Generalized-alpha time stepping for second-order systems, in the ``OdeSolver`` style.

The flexible slider-crank with several beams has bending (and, with a flexible
elongation, axial) modes far above the motion of interest. Explicit methods
must resolve them for stability; the generalized-alpha method of Chung and
Hulbert (1993) steps over them with controllable numerical damping (spectral
radius ``rho_inf`` at infinite frequency) and stays second-order accurate for
the slow motion. This is the integrator of Exudyn and most multibody codes.

The state is ``y = [q; v]``. Per step the unknown is the acceleration
``a_{n+1}`` at the end of the step; the Newmark formulas turn it into
``q_{n+1}, v_{n+1}`` and Newton's method drives a residual to zero. The
problem comes as a :class:`SecondOrderSystem`:

* a mechanical system (what :func:`flexmbd.simulate` passes) supplies its own
  residual and an approximate inverse of its Newton matrix ``Mbar + c_q K +
  c_v C`` from the element stiffness, so no Jacobian is differenced;
* any first-order ``fun(t, y) -> [v; a]`` works too (:class:`FirstOrderSystem`),
  with the Newton matrix from finite differences.

By default Newton iterates to the tolerance, keeping the Newton matrix while
it converges fast (modified Newton) and renewing it otherwise. With
``iterations=1`` the method is *linearly implicit*: one Newton correction per
step with the Newton matrix renewed at every step's predictor. Because the
residual is nearly linear in the step's acceleration and the matrix is exact
up to terms of order ``h``, the error per step stays of the method's order (a
W-method argument), so the accuracy of the slow motion is that of the fully
iterated method at the cost of one evaluation per step; measured on the
flexible slider-crank in ``benchmarks/``. ``renew_every=2`` keeps each Newton
matrix for two steps, which costs no accuracy there either. The step is fixed (``step``), halved
only when Newton fails. Like scipy's solvers, this class has ``step()``, ``status``,
``dense_output()`` and the counters ``nfev``, ``njev``, ``nlu``; it is driven
by :func:`flexmbd.integrate.integrate` and needs no SciPy.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol

import numpy as np

from .errors import SimulationError

_MAX_NEWTON = 8
_SLOW_RATE = 0.5  # contraction per Newton iteration above which an iteration has failed
_RENEW_AFTER = 3  # Newton iterations after which the Newton matrix is renewed next step
_MAX_HALVINGS = 12


class SecondOrderSystem(Protocol):
    """What :class:`GeneralizedAlpha` needs of a problem ``R(t, q, v, a) = 0``.

    ``q``, ``v`` and ``a`` have shape ``(m,)``.
    """

    nfev: int  #: residual and acceleration evaluations so far

    def accelerations(self, t: float, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """The accelerations ``a`` ``(m,)`` that solve the equations at ``(t, q, v)``."""

    def residual(self, t: float, q: np.ndarray, v: np.ndarray, a: np.ndarray):
        """The residual at ``(t, q, v, a)``, in whatever form the operator takes."""

    def iteration_operator(self, c_q: float, c_v: float) -> Callable:
        """``op(residual) -> delta a``, an approximate Newton correction at the state
        evaluated last, for ``dq/da = c_q`` and ``dv/da = c_v``."""


class FirstOrderSystem:
    """``y' = fun(t, y)`` with ``y = [q; v]`` as a second-order system.

    The residual is ``a - fun(t, [q; v])[m:]``; the Newton matrix ``I - c_q da/dq -
    c_v da/dv`` comes from forward differences at the state evaluated last.
    """

    def __init__(self, fun: Callable[[float, np.ndarray], np.ndarray], m: int,
                 rtol: float, atol: float):
        self.fun, self.m, self.rtol, self.atol = fun, m, rtol, atol
        self.nfev = 0
        self._last = None

    def _accel(self, t, y):
        self.nfev += 1
        return np.asarray(self.fun(t, y), dtype=float)[self.m:]

    def accelerations(self, t, q, v):
        y = np.concatenate([q, v])
        a = self._accel(t, y)
        self._last = (t, y, a)
        return a

    def residual(self, t, q, v, a):
        return a - self.accelerations(t, q, v)

    def iteration_operator(self, c_q, c_v):
        t, y, f = self._last
        delta = 1e-6 * np.maximum(np.abs(y), self.atol / self.rtol)
        jac = np.empty((self.m, 2 * self.m))
        for j in range(2 * self.m):
            shifted = y.copy()
            shifted[j] += delta[j]
            jac[:, j] = (self._accel(t, shifted) - f) / delta[j]
        matrix = np.eye(self.m) - c_q * jac[:, :self.m] - c_v * jac[:, self.m:]
        inverse = np.linalg.inv(matrix)
        return lambda residual: -(inverse @ residual)


class GeneralizedAlpha:
    """Fixed-step generalized-alpha method (Chung-Hulbert) for ``y = [q; v]``.

    Args:
        fun: ``fun(t, y) -> [v; a]``, with ``y`` of even length ``2 m``; not used
            when ``system`` is given.
        t0, y0, t_bound: start time [s], start state, end time [s] (forward only).
        step: step size [s] (default: 1/1000 of the interval). There is no error
            control: choose it from the frequencies that matter (20 or more steps
            per period for about 1e-3 relative accuracy per period).
        rho_inf: spectral radius at infinite frequency, 0 (strongest damping of
            unresolved modes) to 1 (none, the trapezoidal rule). Default 0.8.
        rtol, atol: tolerances of the Newton iteration on ``[q; v]``.
        max_step: an upper bound on ``step`` (as in the other solvers).
        system: a :class:`SecondOrderSystem` with its own residual and Newton
            operator (default: ``fun`` as a :class:`FirstOrderSystem`).
        iterations: ``None`` (default) to iterate Newton to ``rtol``/``atol``, or a
            fixed number of corrections per step with the Newton matrix renewed at
            every step (``1``: linearly implicit, one evaluation per step).
        renew_every: with ``iterations`` set, the Newton matrix is renewed every
            ``renew_every`` steps (default 1) and kept in between; also renewed when
            the step size changes or a step fails.
    """

    def __init__(self, fun, t0, y0, t_bound, *, step: float | None = None,
                 rho_inf: float = 0.8, rtol: float = 1e-6, atol: float = 1e-9,
                 max_step: float = np.inf, system: SecondOrderSystem | None = None,
                 iterations: int | None = None, renew_every: int = 1,
                 vectorized: bool = False, **extraneous):
        self.t, self.y = float(t0), np.array(y0, dtype=float)
        self.t_bound, self.t_old = float(t_bound), None
        self.n = len(self.y)
        if self.n % 2:
            raise ValueError("generalized-alpha needs a state [q; v] of even length")
        if not 0.0 <= rho_inf <= 1.0:
            raise ValueError(f"rho_inf must lie in [0, 1], got {rho_inf}")
        if iterations is not None and not (isinstance(iterations, int) and iterations >= 1):
            raise ValueError(f"iterations must be None or a positive integer, got {iterations!r}")
        if not (isinstance(renew_every, int) and renew_every >= 1):
            raise ValueError(f"renew_every must be a positive integer, got {renew_every!r}")
        self.iterations = iterations
        if self.t_bound < self.t:
            raise ValueError("generalized-alpha integrates forward in time only")
        span = self.t_bound - self.t
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
        self.system = system if system is not None else FirstOrderSystem(fun, self.m, rtol,
                                                                         atol)
        self.a = np.asarray(self.system.accelerations(self.t, self.y[:self.m],
                                                      self.y[self.m:]), dtype=float)
        self.aa = self.a.copy()  # the algorithmic acceleration of the method
        self.operator, self.operator_step, self.operator_fresh = None, None, False
        self.renew = False
        self.renew_every, self._since_renewal = renew_every, 0
        self.njev = self.nlu = 0
        self.status = "running" if span > 0 else "finished"
        self._previous = None
        self.trial_error: SimulationError | None = None
        self._predictor_step = self._predictor_matrix = self._predictor_gain = None

    @property
    def nfev(self) -> int:
        return self.system.nfev

    # --- Newton ingredients -------------------------------------------------------------
    def _coefficients(self, h):
        """``dq/da`` and ``dv/da`` of the Newmark update for step ``h``."""
        c = (1 - self.alpha_f) / (1 - self.alpha_m)
        return self.beta * h**2 * c, self.gamma * h * c

    def _renew_operator(self, h):
        """A Newton operator at the state the system evaluated last."""
        self.operator = self.system.iteration_operator(*self._coefficients(h))
        self.operator_step, self.operator_fresh, self.renew = h, True, False
        self.njev += 1
        self.nlu += 1

    def _newmark(self, h) -> Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]:
        """The step's update as a map of the end acceleration ``a_new`` to ``[q; v]`` at
        the end of the step and the algorithmic acceleration there; both are affine,
        ``y0 + [c_q; c_v] a_new`` and ``aa0 + k a_new``, with ``y0``, ``aa0`` computed
        here once per step (one product: on a few dozen unknowns numpy's cost per call,
        not arithmetic, is what counts)."""
        start = self._predictor(h) @ np.concatenate([self.y, self.a, self.aa]).reshape(4, -1)
        y0, aa0 = start[:2], start[2]
        gain, k = self._predictor_gain, (1 - self.alpha_f) / (1 - self.alpha_m)

        def update(a_new):
            return (y0 + gain * a_new).ravel(), aa0 + k * a_new
        return update

    def _predictor(self, h) -> np.ndarray:
        """``(3, 4)``: the Newmark formulas taking ``[q, v, a, aa]`` (start of the step) to
        ``q, v`` at its end for ``a_new = 0`` and to ``aa0``, with the algorithmic
        acceleration at the end ``aa_new = aa0 + k a_new``, ``aa0 = (alpha_f a - alpha_m
        aa) / (1 - alpha_m)``."""
        if self._predictor_step != h:
            w_a, w_aa = self.alpha_f / (1 - self.alpha_m), -self.alpha_m / (1 - self.alpha_m)
            b, g = self.beta, self.gamma
            self._predictor_matrix = np.array([
                [1.0, h, h * h * b * w_a, h * h * (0.5 - b + b * w_aa)],
                [0.0, 1.0, h * g * w_a, h * (1 - g + g * w_aa)],
                [0.0, 0.0, w_a, w_aa]])
            self._predictor_gain = np.array(self._coefficients(h))[:, None]  # [c_q; c_v]
            self._predictor_step = h
        return self._predictor_matrix

    def _operator_stale(self, h) -> bool:
        """Whether the Newton matrix must be renewed before a step of size ``h``."""
        return self.operator is None or self.renew or self.operator_step != h

    def _newton(self, h):
        """Solve the step of size ``h``; returns ``(y, a, aa)`` or ``None`` if it failed."""
        if self.iterations is not None:
            return self._fixed_newton(h)
        t_new = self.t + h
        c_q, c_v = self._coefficients(h)
        update = self._newmark(h)
        a_new = self.a.copy()
        previous = None
        for iteration in range(1, _MAX_NEWTON + 1):
            y_new, _ = update(a_new)
            try:
                residual = self.system.residual(t_new, y_new[:self.m], y_new[self.m:], a_new)
            except SimulationError as err:
                self.trial_error = err  # a state the position solve rejects: retry smaller
                return None
            if self._operator_stale(h):
                self._renew_operator(h)
            da = self.operator(residual)
            a_new = a_new + da
            dy = np.concatenate([c_q * da, c_v * da])
            size = np.sqrt(np.mean((dy / (self.atol + self.rtol * np.abs(y_new))) ** 2))
            if size < 0.1:
                self.renew = iteration > _RENEW_AFTER
                y_new, aa_new = update(a_new)
                return y_new, a_new, aa_new
            if previous is not None and size > _SLOW_RATE * previous and size > 1.0:
                return None
            previous = size
        return None

    def _fixed_newton(self, h):
        """``iterations`` corrections with a Newton matrix renewed at the predictor (every
        ``renew_every`` steps)."""
        m = self.m
        update = self._newmark(h)
        a_new = self.a.copy()
        self._since_renewal += 1
        for iteration in range(self.iterations):
            y_new, _ = update(a_new)
            try:
                residual = self.system.residual(self.t + h, y_new[:m], y_new[m:], a_new)
            except SimulationError as err:
                self.trial_error = err
                return None
            if iteration == 0 and (self._operator_stale(h)
                                   or self._since_renewal >= self.renew_every):
                self._renew_operator(h)
                self._since_renewal = 0
            a_new = a_new + self.operator(residual)
        if not np.isfinite(a_new).all():
            return None
        y_new, aa_new = update(a_new)
        return y_new, a_new, aa_new

    # --- the OdeSolver interface -----------------------------------------------------------
    def step(self) -> str | None:
        """Take one step; returns ``None`` or, when the step failed, the reason."""
        if self.status != "running":
            raise RuntimeError("attempt to step on a finished or failed solver")
        h = min(self.h_nominal, self.t_bound - self.t)
        outcome, self.trial_error = None, None
        for _ in range(_MAX_HALVINGS):
            outcome = self._newton(h)
            if outcome is not None:
                break
            if self.trial_error is None and not self.operator_fresh:
                self.renew = True  # a stale Newton matrix may be to blame: renew it first
                continue
            h /= 2
            self.renew = True
        if outcome is None:
            if self.trial_error is not None:
                raise self.trial_error
            self.status = "failed"
            return (f"Newton iteration of the generalized-alpha step failed at "
                    f"t = {self.t:.6g} s even with step {h:.3g} s")
        y_new, a_new, aa_new = outcome
        self._previous = (self.t, self.y, self.a)
        self.t_old = self.t
        self.t = self.t_bound if self.t_bound - (self.t + h) < 1e-12 * h else self.t + h
        self.y, self.a, self.aa = y_new, a_new, aa_new
        self.operator_fresh, self.trial_error = False, None
        if self.t >= self.t_bound:
            self.status = "finished"
        return None

    def dense_output(self) -> HermiteOutput:
        """Interpolant over the last step."""
        t0, y0, a0 = self._previous
        return HermiteOutput(t0, self.t, y0, a0, self.y, self.a)


class HermiteOutput:
    """Cubic Hermite interpolation of ``q`` (with ``v``) and of ``v`` (with ``a``) over
    ``[t_old, t]``; call it with a time or an array of times."""

    def __init__(self, t0, t1, y0, a0, y1, a1):
        m = len(y0) // 2
        self.t_old, self.t, self.h = t0, t1, t1 - t0
        self.values = (y0, y1)
        self.slopes = (np.concatenate([y0[m:], a0]), np.concatenate([y1[m:], a1]))

    def __call__(self, t):
        s = (np.asarray(t) - self.t_old) / self.h
        h00, h10 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s
        h01, h11 = -2 * s**3 + 3 * s**2, s**3 - s**2
        (y0, y1), (d0, d1) = self.values, self.slopes
        if np.ndim(t) == 0:
            return h00 * y0 + h10 * self.h * d0 + h01 * y1 + h11 * self.h * d1
        return (np.outer(y0, h00) + np.outer(d0, h10 * self.h) + np.outer(y1, h01)
                + np.outer(d1, h11 * self.h))
