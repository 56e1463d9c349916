"""Forward dynamics (THEORY section 7): simulate the dynamic degrees of freedom.

The state is ``y = [q_d, qdot_d]``. Every evaluation solves the position problem
(warm-started from the previous evaluation) and the equations of motion with
:class:`~flexmbd.equations.EquationsOfMotion`; prescribed entries of ``q``
follow their laws. The generalized-alpha integrator iterates on the nodal force
residual with a Newton matrix built from the element stiffness; scipy's
methods get ``y' = [qdot_d, qddot_d]``. After the run, all output times are
evaluated in one batch.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Literal

import numpy as np

from .dynamics import Forces
from .equations import EquationsOfMotion, State
from .errors import ModelError, SimulationError
from .factor import DenseFactor
from .inputs import q_index, resolve_laws
from .integrate import check_method, integrate
from .kinematics import initial_q
from .model import Model
from .motion import Law
from .results import SimulationResult, check_on_failure, conclude
from .threads import blas_threads_for

#: output times evaluated together in the output pass: bounds its memory and keeps a
#: batch's D_c inverses (128 of 26 x 26 on the 8-beam slider-crank) within the CPU's
#: cache; 256 was a quarter slower there
_OUTPUT_BATCH = 128
#: generalized-alpha's position solves take D_x within this share of the model size
_GA_JACOBIAN_POINT = 1e-6
#: memory for the D_c inverses kept for the output pass (beyond it, none are kept)
_KEPT_FACTOR_BYTES = 64 * 2**20


def initial_state(model: Model, initial: Mapping[str, tuple[float, float]] | None
                  ) -> tuple[np.ndarray, np.ndarray]:
    """``q_d(0), qdot_d(0)``: the initial configuration at rest unless the model's
    settings or ``initial`` (which wins) say otherwise (``{"e2.2": (value, rate)}``
    [m or rad, per s])."""
    d = ~model.q_is_input
    q0, qd0 = initial_q(model), np.zeros(model.n_dof)
    for label, pair in {**model.settings.initial, **(initial or {})}.items():
        j = q_index(model, label)
        if not d[j]:
            raise ModelError(f"initial value given for {label}, which is prescribed, not "
                             f"dynamic; its law sets its value")
        try:
            q0[j], qd0[j] = pair
        except (TypeError, ValueError):
            raise ModelError(f"initial value of {label} must be (value, rate), got "
                             f"{pair!r}") from None
    return q0[d], qd0[d]


class MechanicalSystem:
    """The dynamic degrees of freedom of a model as a second-order system.

    Serves both kinds of integrator: as ``fun(t, y) -> [qdot_d, qddot_d]`` for
    scipy's, and through ``residual`` / ``iteration_operator`` for
    :class:`~flexmbd.generalized_alpha.GeneralizedAlpha`. Each evaluation starts the
    position solve from the previous one's solution, extrapolated in time and
    corrected to first order for the change of ``q``. ``jacobian_point``, a share
    of the model size, lets the position solve take ``D_x`` that close to the
    solution instead of at the tolerance (see
    :meth:`~flexmbd.equations.EquationsOfMotion.positions`).
    """

    def __init__(self, equations: EquationsOfMotion, n_outputs: int,
                 jacobian_point: float | None = None):
        self.equations = equations
        model = equations.model
        self.near = (None if jacobian_point is None
                     else jacobian_point * model.characteristic_length)
        self.nfev = 0
        self.last: State | None = None
        self._x, self._xd, self._xdd = np.array(model.x0, dtype=float), None, None
        self._t = None
        #: for each output time, the solution of an evaluation near it (a warm start)
        self.guesses = np.tile(np.asarray(model.x0, dtype=float), (n_outputs, 1))
        # and the inverse of D_c there (small models): the output pass's chord steps
        # need no factorisation of their own
        n = len(equations.asm.dependent)
        keep = not equations.asm.sparse and 0 < n_outputs * n * n * 8 <= _KEPT_FACTOR_BYTES
        self._inverses = np.empty((n_outputs, n, n)) if keep else None
        self._conditioning = np.empty(n_outputs)
        self._kept = np.zeros(n_outputs, dtype=bool)

    def _state(self, t: float, q_d, qd_d, qdd_d) -> State:
        eq = self.equations
        t_arr = np.array([float(t)])
        q, qd, qdd = eq.compose(t_arr, q_d[None], qd_d[None],
                                None if qdd_d is None else qdd_d[None])
        state = eq.kinematics(t_arr, q, qd, qdd, self._guess(t, q), self.near)
        self.nfev += 1
        self._x, self._xd, self._xdd = state.x[0], state.xd[0], state.xdd[0]
        self._t, self.last = t, state
        return state

    def _guess(self, t: float, q: np.ndarray) -> np.ndarray:
        """Start of the position solve: the last solution, extrapolated to ``t`` to second
        order, plus ``F_q`` times what that extrapolation misses of ``q`` (THEORY 3's
        predictor): the motion of the dynamic entries is not smooth in time when stiff
        modes ring."""
        last = self.last
        if last is None:
            return self._x[None]
        dt = t - self._t
        guess = self._x + dt * self._xd + (0.5 * dt * dt) * self._xdd
        missed = q - (last.q + dt * last.qd + (0.5 * dt * dt) * last.qdd)
        eq = self.equations
        change = np.zeros((1, len(guess)))
        change[:, eq.asm.take.q_coordinates] = missed[:, :eq.n_xm]
        change = eq.dependent_rates(change, last.jacobian, last.factor, missed[:, eq.n_xm:])
        return guess[None] + change

    def accelerations(self, t, q_d, qd_d) -> np.ndarray:
        """``qddot_d`` ``(nd,)`` solving the equations of motion at ``(t, q_d, qdot_d)``."""
        state = self._state(t, q_d, qd_d, None)
        qdd_d, _ = self.equations.solve_accelerations(state,
                                                      self.equations.nodal_force(state))
        self._xdd = np.zeros_like(self._x)  # xddot above lacks qddot_d: extrapolate linearly
        return qdd_d[0]

    def residual(self, t, q_d, qd_d, qdd_d) -> np.ndarray:
        """``R = F_q^T y`` ``(1, nd)`` at ``qddot_d``: zero when it solves the equations."""
        state = self._state(t, q_d, qd_d, qdd_d)
        return self.equations.reduced_residual(state, self.equations.nodal_force(state))

    def iteration_operator(self, c_q: float, c_v: float):
        """Newton correction ``op(y) -> delta qddot_d`` at the last evaluated state."""
        return self.equations.iteration_operator(self.last, c_q, c_v)

    def __call__(self, t: float, y: np.ndarray) -> np.ndarray:
        n = len(y) // 2
        return np.concatenate([y[n:], self.accelerations(t, y[:n], y[n:])])

    def keep_guess(self, k: int) -> None:
        """Remember the latest solution as the warm start of output ``k``."""
        self.guesses[k] = self._x
        factor = None if self.last is None else self.last.factor
        if self._inverses is not None and isinstance(factor, DenseFactor):
            self._inverses[k], self._conditioning[k] = factor.inverse[0], factor.conditioning[0]
            self._kept[k] = True

    def kept_factor(self, part: slice) -> DenseFactor | None:
        """The ``D_c`` factorisations kept with the warm starts of outputs ``part``, if
        every one has one."""
        if self._inverses is None or not self._kept[part].all():
            return None
        return DenseFactor.from_inverse(self._inverses[part], self._conditioning[part])


def simulate(
    model: Model,
    times,
    *,
    inputs: Mapping[str, Law] | None = None,
    forces: Forces | None = None,
    initial: Mapping[str, tuple[float, float]] | None = None,
    method: str = "RK45",
    rtol: float = 1e-6,
    atol: float = 1e-9,
    max_step: float = np.inf,
    step: float | None = None,
    iterations: int | None = None,
    renew_every: int = 1,
    rho_inf: float = 0.8,
    tolerance: float | None = None,
    with_reactions: bool = False,
    progress: bool | None = None,
    on_failure: Literal["raise", "return"] = "raise",
) -> SimulationResult:
    """Forward simulation of the dynamic degrees of freedom.

    Args:
        model: a model with dynamic degrees of freedom and mass.
        times: output times [s], increasing; the run starts at ``times[0]``.
        inputs: laws of prescribed entries by label, overriding the model's.
        forces: applied loads ``forces(t, x, xdot)`` -> array ``(nx,)`` or
            ``{"x2.1": torque}`` [N, N m], on top of the model's constant loads.
        initial: ``{label: (value, rate)}`` for dynamic entries of ``q``, on top of
            the model's ``settings.initial``.
        method: ``"RK45"`` (default, as ode45), ``"Radau"``, ``"BDF"``, ``"LSODA"``,
            ``"DOP853"``, ``"RK23"`` (scipy's, error-controlled) or ``"GeneralizedAlpha"``
            (fixed ``step``, numerically damped: the choice for models with stiff,
            barely excited modes such as a rod of many beams or a flexible elongation).
        rtol, atol: integrator tolerances on ``[q_d, qdot_d]`` (for GeneralizedAlpha:
            of its Newton iteration).
        max_step: largest integrator step [s].
        step: step size [s] of GeneralizedAlpha (default: the output interval).
        iterations: GeneralizedAlpha's Newton corrections per step: ``None`` (default)
            iterates to ``rtol``/``atol``; ``1`` is the linearly implicit method, one
            evaluation and one new Newton matrix per step, as accurate for the slow
            motion at a fraction of the cost (see :mod:`flexmbd.generalized_alpha`).
        renew_every: with ``iterations`` set, steps between renewals of
            GeneralizedAlpha's Newton matrix (default 1: every step). ``2`` halves its
            cost; on the flexible slider-crank the accuracy is unchanged (benchmarks/).
        rho_inf: GeneralizedAlpha's spectral radius at infinite frequency, 0 (strongest
            damping of unresolved modes) to 1 (none); default 0.8.
        tolerance: Newton tolerance of the position solve [m, rad].
        with_reactions: also compute constraint stresses and support/drive loads.
        progress: progress bar (default: long interactive runs only).
        on_failure: ``"raise"`` the :class:`SimulationError` (with the output so far
            as ``error.partial_result``) or ``"return"`` it with ``success=False``.

    Returns:
        :class:`~flexmbd.results.SimulationResult` with ``stats`` of the integrator.
    """
    times = np.asarray(times, dtype=float).ravel()
    check_on_failure(on_failure)
    if not np.any(~model.q_is_input):
        raise ModelError("the model has no dynamic degree of freedom to simulate; use "
                         "kinematic_analysis or inverse_dynamics for prescribed motion")
    if not model.has_mass:
        raise ModelError("the model has no mass: give elements set_mass() or nodes "
                         "add_point_mass() before simulating")
    check_method(method)
    laws = resolve_laws(model, inputs)
    # generalized-alpha's residual need not be exact below its truncation error: its
    # position solves take D_x within 1e-6 of the model size (saves chord steps)
    system = MechanicalSystem(EquationsOfMotion(model, laws, forces, tolerance), len(times),
                              _GA_JACOBIAN_POINT if method == "GeneralizedAlpha" else None)
    q0, qd0 = initial_state(model, initial)
    options = {}
    if method == "GeneralizedAlpha":
        interval = float(np.diff(times).min()) if times.size > 1 else None
        options["step"] = step if step is not None else interval
        options["system"], options["iterations"] = system, iterations
        options["renew_every"], options["rho_inf"] = renew_every, rho_inf
    elif step is not None or iterations is not None or renew_every != 1 or rho_inf != 0.8:
        raise ValueError(f"step, iterations, renew_every and rho_inf belong to "
                         f"GeneralizedAlpha; "
                         f"{method} chooses its own steps (bound them with max_step)")
    with blas_threads_for(model.n_coordinates):
        run = integrate(system, np.concatenate([q0, qd0]), times, method=method, rtol=rtol,
                        atol=atol, max_step=max_step, progress=progress,
                        on_output=system.keep_guess, **options)
        result, output_error = _post_process(system, run.t, run.y, with_reactions)
    result.stats = {**run.stats, "method": method}
    error = run.error or output_error
    if error is None and not run.success:
        error = SimulationError(run.message, float(run.t[-1]) if len(run.t) else None)
    return conclude(result, error, on_failure,
                    f"completed {len(times)} points to t = {times[-1]:.6g} s "
                    f"({run.stats['nsteps']} steps, {run.stats['nfev']} evaluations)")


def _post_process(system: MechanicalSystem, t: np.ndarray, y: np.ndarray,
                  with_reactions: bool) -> tuple[SimulationResult, SimulationError | None]:
    """Full kinematics, stresses, driving forces and (optionally) reactions at the output
    times, evaluated in batches; an output that cannot be evaluated (e.g. a state past
    the last good step of a failing run) ends the result there, with its error."""
    equations = system.equations
    model, n = equations.model, y.shape[1] // 2
    columns: dict[str, list[np.ndarray]] = {}
    error = None

    def evaluate(part):
        part = slice(part.start, min(part.stop, len(t)))  # a failed run ends early
        # each output starts from the integration's own solution near it: the position
        # problem has other branches (an end tangent turned by pi), so never go far
        for name, values in equations.outputs(t[part], y[part, :n], y[part, n:],
                                              system.guesses[part],
                                              system.kept_factor(part)).items():
            columns.setdefault(name, []).append(values)

    done = 0
    for start in range(0, len(t), _OUTPUT_BATCH):
        try:
            evaluate(slice(start, start + _OUTPUT_BATCH))
            done = min(start + _OUTPUT_BATCH, len(t))
        except SimulationError:
            for k in range(start, min(start + _OUTPUT_BATCH, len(t))):
                try:
                    evaluate(slice(k, k + 1))
                except SimulationError as err:
                    error = err
                    break
                done = k + 1
            break
    if done:
        arrays = {name: np.concatenate(parts) for name, parts in columns.items()}
    else:
        arrays = {name: np.zeros((0, size)) for name, size in _sizes(model).items()}
    if not with_reactions:
        arrays["reactions"] = None
    return SimulationResult(model, t[:done], **arrays), error


def _sizes(model: Model) -> dict[str, int]:
    nx, ne, nq = model.n_coordinates, model.n_deformations, model.n_dof
    return {"x": nx, "xd": nx, "xdd": nx, "e": ne, "ed": ne, "edd": ne, "q": nq, "qd": nq,
            "qdd": nq, "sigma": ne, "reactions": nx, "driving": nq}
