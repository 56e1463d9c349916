"""A linear state-space model of a linearized state (SPACAR's INPUTF, OUTX, OUTXP).

With the state ``z = [dq_d; dq_d']`` of the dynamic degrees of freedom (prescribed
entries held), force inputs ``u`` on chosen coordinates and outputs ``y`` of chosen
coordinates or their rates:

    z' = A z + B u,   y = C z + D u,
    A = [[0, I], [-M^-1 K, -M^-1 C]],   B = [[0], [M^-1 F_in^T]],

with ``M = M0``, ``K = K0 + N0 + G0``, ``C = C0 + D0`` (or modal damping), ``F_in`` the
rows of ``F_q`` of the loaded coordinates; a position output is ``[F_out, 0]``, a rate
output ``[d(F_out qdot)/dq, F_out]``; ``D = 0``. Its static gain ``D - C A^-1 B`` is the
compliance (:func:`flexmbd.analysis.modes.compliance`) and its poles are ``+-i omega`` of the
vibration modes when undamped.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as linalg

from .. import checks
from ..engine import workspace_of
from ..errors import ArgumentError, SingularConfigurationError
from ..summary import dataclass_repr
from .linearization import Linearization, central_differences
from .modes import linearization_of, vibration_modes

__all__ = ["StateSpace", "equilibrated_solve", "mass_solver", "state_space"]


@dataclass(frozen=True, eq=False)
class StateSpace:
    """``z' = A z + B u``, ``y = C z + D u`` (module docstring).

    Attributes:
        A: state matrix ``(2 nd, 2 nd)`` for ``nd`` dynamic degrees of freedom.
        B: input matrix ``(2 nd, ni)`` for ``ni`` inputs.
        C: output matrix ``(no, 2 nd)`` for ``no`` outputs.
        D: feedthrough ``(no, ni)``.
        inputs: labels of the loaded coordinates (``"x5.2"``) [N, N m].
        outputs: labels of the outputs: coordinates (``"x5.2"``) [m, rad] and rates
            (``"xd5.2"``) [m/s, rad/s].
        states: labels of the states: the dynamic entries of ``q``, then their rates.
    """

    __repr__ = dataclass_repr

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    inputs: tuple[str, ...]
    outputs: tuple[str, ...]
    states: tuple[str, ...]

    def to_scipy(self):
        """The model as ``scipy.signal.StateSpace`` (for ``bode``, ``lsim``, ...)."""
        from scipy import signal

        return signal.StateSpace(self.A, self.B, self.C, self.D)

    def static_gain(self) -> np.ndarray:
        """``D - C A^-1 B`` ``(no, ni)``: the outputs per unit constant input."""
        return self.D - self.C @ equilibrated_solve(self.A, self.B)

    def truncated(self, count: int) -> StateSpace:
        """The model reduced to its ``count`` modes of lowest natural frequency ``|p|``.

        Modal truncation with static correction: the kept modes in real modal
        coordinates (two states ``Re c, Im c`` per complex pole pair ``p``, one per real
        pole), and ``D`` corrected so that the static gain is the full model's. The
        response is then exact at zero frequency and close below the first dropped mode.
        A few modes are what control design and ``scipy.signal.bode`` need: converting
        the full model to a transfer function loses all precision beyond some 20 states.

        Raises:
            ArgumentError: ``count`` is not between 1 and the number of modes.
            SingularConfigurationError: ``A`` is singular (a mechanism: no static gain).
        """
        poles, right = linalg.eig(self.A)
        if np.min(np.abs(poles)) <= 1e-12 * np.max(np.abs(poles)):
            raise SingularConfigurationError(
                "A is singular (a rigid-body mode or mechanism): a truncated model has no "
                "static gain to keep")
        upper = np.flatnonzero(poles.imag >= 0.0)  # one pole of each conjugate pair
        if not (isinstance(count, (int, np.integer)) and 1 <= count <= len(upper)):
            raise ArgumentError("count", f"must be a whole number from 1 to {len(upper)}, "
                                         f"got {count!r}")
        kept = upper[np.argsort(np.abs(poles[upper]), kind="stable")[:count]]
        left = equilibrated_solve(right, np.eye(len(poles)))[kept]  # rows of V^-1: c = w z
        blocks, inputs, outputs = [], [], []
        for p, v, w in zip(poles[kept], right[:, kept].T, left, strict=True):
            wB, Cv = w @ self.B, self.C @ v
            if p.imag == 0.0:  # z = v c
                blocks.append(np.array([[p.real]]))
                inputs.append(wB.real[None])
                outputs.append(Cv.real[:, None])
            else:  # z = 2 Re(v c) = [2 Re v, -2 Im v] [Re c, Im c]
                blocks.append(np.array([[p.real, -p.imag], [p.imag, p.real]]))
                inputs.append(np.stack([wB.real, wB.imag]))
                outputs.append(np.stack([2 * Cv.real, -2 * Cv.imag], axis=1))
        A, B, C = linalg.block_diag(*blocks), np.vstack(inputs), np.hstack(outputs)
        D = self.static_gain() + C @ equilibrated_solve(A, B)
        states = tuple(f"{part} c{k}" for k, p in enumerate(poles[kept], 1)
                       for part in (("re", "im") if p.imag else ("re",)))
        return StateSpace(A, B, C, D, self.inputs, self.outputs, states)


def equilibrated_solve(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """``A^-1 B`` for a square ``A`` whose rows and columns differ in scale by units (a
    state matrix with warping coordinates spans 1e20): solved as ``(R A S) y = R B``,
    ``A^-1 B = S y``, with ``R`` scaling each row of ``A`` to a largest entry of 1 and then
    ``S`` each column. What is left of the condition is the model's own, and LAPACK's
    warning, where it still comes, is about that."""
    rows = 1.0 / np.max(np.abs(A), axis=1)
    scaled = A * rows[:, None]
    columns = 1.0 / np.max(np.abs(scaled), axis=0)
    return columns[:, None] * linalg.solve(scaled * columns[None, :], rows[:, None] * B)


def state_space(linearization, inputs, outputs=(), rate_outputs=(), *,
                damping_ratio: float | None = None, row: int | None = None) -> StateSpace:
    """The state-space model of a linearized state.

    Args:
        linearization: the state: a :class:`~flexmbd.Linearization`, a ``Model`` (its
            reference configuration), a static result or a motion's result (its last
            row, or ``row``), as for :func:`~flexmbd.vibration_modes`.
        inputs: coordinates loaded by the force inputs (``["x5.2"]``, INPUTF).
        outputs: coordinates given as outputs (OUTX).
        rate_outputs: coordinates whose rates are outputs (OUTXP).
        damping_ratio: modal damping ratio ``zeta`` of every mode, replacing ``C0 + D0``
            by ``M Phi diag(2 zeta omega) Phi^T M``; default the model's damping.
        row: the result's row, for a result.

    Returns:
        :class:`StateSpace` with ``A`` ``(2 nd, 2 nd)``, ``B`` ``(2 nd, ni)``, ``C``
        ``(no, 2 nd)`` and ``D`` ``(no, ni)``; inputs in [N, N m], outputs in [m, rad] and
        rates in [m/s, rad/s].
    """
    lin = linearization_of(linearization, row)
    model, dynamic = lin.model, lin.dynamic
    inputs, outputs, rate_outputs = (checks.coordinates_named(model, v, name)[0]
                                     for v, name in ((inputs, "inputs"), (outputs, "outputs"),
                                                     (rate_outputs, "rate_outputs")))
    nd = len(dynamic)
    M, K = lin.block("M0"), lin.block("K")
    damping = lin.block("C") if damping_ratio is None else _modal_damping(lin, damping_ratio)
    A = np.zeros((2 * nd, 2 * nd))
    A[:nd, nd:] = np.eye(nd)
    mass_solve = mass_solver(M, [model.q_labels[j] for j in dynamic])
    A[nd:, :nd] = -mass_solve(K)
    A[nd:, nd:] = -mass_solve(damping)
    B = np.zeros((2 * nd, len(inputs)))
    B[nd:] = mass_solve(lin.transfer(inputs, "inputs").T)
    rows = [np.concatenate([position, np.zeros(nd)])
            for position in lin.transfer(outputs, "outputs")]
    velocity = _rate_transfer(lin) if rate_outputs else np.zeros((0, 0))
    for i, rate in zip(lin.rows_of(rate_outputs, "rate_outputs"),
                       lin.transfer(rate_outputs, "rate_outputs"), strict=True):
        rows.append(np.concatenate([velocity[i], rate]))
    C = np.array(rows).reshape(len(rows), 2 * nd)
    names = [model.q_labels[j] for j in dynamic]
    return StateSpace(A, B, C, np.zeros((len(rows), len(inputs))), tuple(inputs),
                      tuple(outputs) + tuple("xd" + label.strip()[1:] for label in rate_outputs),
                      tuple(names + [f"d/dt {n}" for n in names]))


def mass_solver(M: np.ndarray, labels: list[str]):
    """``R -> M^-1 R`` for the mass matrix ``M`` ``(nd, nd)`` of the degrees of freedom
    ``labels``, by Cholesky of ``M`` scaled to a unit diagonal. The scaling changes
    nothing in exact arithmetic and removes what is only units: a warping beam's warping
    coordinate carries some 1e-17 of a translation's mass, so ``M`` itself has a condition
    of 1e18 where the scaled one has the physical 1e8 (LAPACK's warning about the former
    would be about the units, not the answer).

    Raises:
        SingularConfigurationError: a degree of freedom has no mass (named), or the
            masses are not positive definite.
    """
    diagonal = np.diag(M)
    if np.any(diagonal <= 0.0):
        massless = [labels[j] for j in np.flatnonzero(diagonal <= 0.0)]
        raise SingularConfigurationError(
            f"no mass on {', '.join(massless[:8])}{' ...' if len(massless) > 8 else ''}: "
            f"a state-space model needs mass on every degree of freedom (give the elements "
            f"or nodes mass, or make those entries rigid)")
    scale = 1.0 / np.sqrt(diagonal)
    try:
        factor = linalg.cho_factor(M * scale[:, None] * scale[None, :])
    except linalg.LinAlgError:
        raise SingularConfigurationError(
            "the mass matrix of the degrees of freedom is not positive definite (a motion "
            "of them moves no mass): give it mass, or make those entries rigid") from None
    return lambda rhs: scale[:, None] * linalg.cho_solve(factor, scale[:, None] * rhs)


def _modal_damping(lin: Linearization, ratio: float) -> np.ndarray:
    """``M Phi diag(2 zeta omega) Phi^T M`` over the dynamic entries."""
    if checks.real(ratio, "damping_ratio") < 0.0:
        raise ArgumentError("damping_ratio", f"must be a number >= 0, got {ratio!r}")
    modes = vibration_modes(lin)
    M = lin.block("M0")
    omega = np.sqrt(np.clip(modes.omega2, 0.0, None))
    MPhi = M @ modes.shapes
    return MPhi @ np.diag(2 * ratio * omega) @ MPhi.T


def _rate_transfer(lin: Linearization) -> np.ndarray:
    """``d(F_q qdot)/dq_d`` ``(nx, nd)``: how the velocities change with the position of the
    degrees of freedom at the state's rates (zero at rest), by central differences."""
    model, dynamic = lin.model, lin.dynamic
    if not np.any(lin.qd):
        return np.zeros((model.n_coordinates, len(dynamic)))
    return central_differences(workspace_of(model), lin.q, lin.qd, lin.qdd, lin.x,
                               lambda state: state["xd"], dynamic)
