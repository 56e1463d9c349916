"""Forward dynamics (THEORY section 7): simulate the dynamic degrees of freedom.

The state is ``y = [q_d, qdot_d]``; every right-hand-side call solves the
position problem (warm-started from the previous call), evaluates the reduced
equations and returns ``[qdot_d, qddot_d]``. Prescribed entries of ``q`` follow
their laws.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Literal

import numpy as np

from .dynamics import Forces, dynamic_terms, generalized_accelerations
from .errors import ModelError, SimulationError
from .inputs import evaluate_laws, q_index, resolve_laws
from .integrate import integrate
from .kinematics import initial_q
from .model import Model
from .motion import Law
from .records import DynamicRecord
from .results import SimulationResult, check_on_failure, conclude
from .threads import blas_threads_for


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


class _RightHandSide:
    """``y' = f(t, y)`` with a warm start for the position solve between calls."""

    def __init__(self, model, laws, forces, tolerance):
        self.model, self.laws, self.forces, self.tolerance = model, laws, forces, tolerance
        self.dynamic = ~model.q_is_input
        self.x_last, self.xd_last, self.t_last = np.array(model.x0), None, None
        # (t, x, xdot) whenever time advances: warm starts for the output pass
        self.checkpoints: list[tuple[float, np.ndarray, np.ndarray]] = []

    def terms(self, t, y, start=None):
        """Solve and evaluate at ``(t, y)``; ``start = (t0, x0, xd0)`` overrides the warm start."""
        model, d = self.model, self.dynamic
        n = int(d.sum())
        q, qd, qdd = evaluate_laws(self.laws, t)
        q[d], qd[d] = y[:n], y[n:]
        t0, x0, xd0 = start or (self.t_last, self.x_last, self.xd_last)
        guess = x0 if xd0 is None else x0 + (t - t0) * xd0
        terms = dynamic_terms(model, q, qd, t, x_guess=guess, forces=self.forces,
                              tolerance=self.tolerance)
        self.x_last, self.xd_last, self.t_last = terms.x, terms.xd, t
        if not self.checkpoints or t > self.checkpoints[-1][0]:
            self.checkpoints.append((t, terms.x, terms.xd))
        qdd = generalized_accelerations(model, terms, qdd[~d])
        return terms, q, qd, qdd

    def start_near(self, t):
        """The checkpoint at or before ``t`` (the first one before all)."""
        times = [c[0] for c in self.checkpoints]
        k = max(int(np.searchsorted(times, t, side="right")) - 1, 0)
        return self.checkpoints[k] if self.checkpoints else None

    def __call__(self, t, y):
        _, _, qd, qdd = self.terms(t, y)
        return np.concatenate([qd[self.dynamic], qdd[self.dynamic]])


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
    laws = resolve_laws(model, inputs)
    rhs = _RightHandSide(model, laws, forces, tolerance)
    q0, qd0 = initial_state(model, initial)
    options = {}
    if method == "GeneralizedAlpha":
        interval = float(np.diff(times).min()) if times.size > 1 else None
        options["step"] = step if step is not None else interval
    elif step is not None:
        raise ValueError(f"step is the fixed step of GeneralizedAlpha; {method} chooses its "
                         f"own steps (bound them with max_step)")
    with blas_threads_for(model.n_coordinates):
        run = integrate(rhs, np.concatenate([q0, qd0]), times, method=method, rtol=rtol,
                        atol=atol, max_step=max_step, progress=progress, **options)
        result = _post_process(model, rhs, run.t, run.y, with_reactions)
    result.stats = {**run.stats, "method": method}
    error = run.error
    if error is None and not run.success:
        error = SimulationError(run.message, float(run.t[-1]) if len(run.t) else None)
    return conclude(result, error, on_failure,
                    f"completed {len(times)} points to t = {times[-1]:.6g} s "
                    f"({run.stats['nsteps']} steps, {run.stats['nfev']} evaluations)")


def _post_process(model, rhs, t, y, with_reactions) -> SimulationResult:
    """Full kinematics, stresses, driving forces and (optionally) reactions at the output
    times."""
    record = DynamicRecord(model, len(t), with_reactions)
    for k in range(len(t)):
        # start from the integration's own solution near t[k]: the position problem
        # has other branches (an end tangent turned by pi), so never extrapolate far
        terms, q, qd, qdd = rhs.terms(t[k], y[k], start=rhs.start_near(t[k]))
        record.add(t[k], terms, q, qd, qdd)
    return record.result()
