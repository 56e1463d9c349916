"""Kinematic analysis (THEORY sections 3 and 4).

Functions of ``(model, state)`` with the state in plain arrays:

* :func:`deformations`, :func:`jacobian`, :func:`hessian`, :func:`quadratic_velocity`
  assemble the element kernels over all elements;
* :func:`partition_jacobian` splits ``D_x`` into the ``x(o)``, ``x(c)`` and ``x(m)``
  columns and factorises ``D_c``;
* :func:`solve_position` is the Newton-Raphson position solve;
* :func:`velocities`, :func:`accelerations` and the transfer functions
  :func:`first_order_transfer`, :func:`deformation_transfer`,
  :func:`second_order_transfer` follow from it.

Shapes: ``nx`` coordinates, ``ne`` deformations, ``nq = model.n_dof`` generalized
coordinates ``q = [x(m); e(m)]``. Units: m and rad, seconds for time.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import ConvergenceError, SingularConfigurationError
from .factor import DenseFactor
from .model import Model

#: default Newton tolerance relative to the model's characteristic length (THEORY 3)
RELATIVE_TOLERANCE = 1e-10
#: residuals below this share of the tolerance are round-off: x no longer moves
_ROUND_OFF = 1e-6
#: scaled smallest singular value of ``D_c`` below which a factorisation fails
SINGULAR_RCOND = 1e-13


# --- assembly of the element kernels ------------------------------------------------
def deformations(model: Model, x: np.ndarray) -> np.ndarray:
    """Deformation parameters ``e = D(x)``, shape ``(ne,)``."""
    e = np.empty(model.n_deformations)
    for g in model.groups:
        e[g.deformations] = g.type.deformations(x[g.coordinates], g.reference)
    return e


def jacobian(model: Model, x: np.ndarray) -> np.ndarray:
    """``D_x = dD/dx``, shape ``(ne, nx)`` (dense)."""
    D_x = np.zeros((model.n_deformations, model.n_coordinates))
    for g in model.groups:
        # each deformation belongs to one element, so rows are written once
        D_x[g.deformations[:, :, None], g.coordinates[:, None, :]] = g.type.jacobian(
            x[g.coordinates], g.reference
        )
    return D_x


def hessian(model: Model, x: np.ndarray) -> np.ndarray:
    """``D_xx``, shape ``(ne, nx, nx)`` (dense; meant for small models and checks)."""
    D_xx = np.zeros((model.n_deformations, model.n_coordinates, model.n_coordinates))
    for g in model.groups:
        D_xx[
            g.deformations[:, :, None, None],
            g.coordinates[:, None, :, None],
            g.coordinates[:, None, None, :],
        ] = g.type.hessian(x[g.coordinates], g.reference)
    return D_xx


def quadratic_velocity(model: Model, x: np.ndarray, xd: np.ndarray) -> np.ndarray:
    """``(D_xx xdot) xdot`` per deformation, shape ``(ne,)`` (THEORY section 2)."""
    out = np.empty(model.n_deformations)
    for g in model.groups:
        out[g.deformations] = g.type.quadratic_velocity(
            x[g.coordinates], xd[g.coordinates], g.reference
        )
    return out


def constraint_jacobian(model: Model, x: np.ndarray) -> np.ndarray:
    """``D_c``: rows ``e(o), e(m)``, columns ``x(c)``, shape ``(n_constrained, n_dependent)``."""
    return jacobian(model, x)[np.ix_(model.constrained, model.dependent)]


# --- the partitioned Jacobian ---------------------------------------------------------
@dataclass(frozen=True, eq=False)
class PartitionedJacobian:
    """``D_x`` at one configuration, split by coordinate class, with ``D_c`` factorised.

    Attributes:
        full: ``D_x``, ``(ne, nx)``.
        fixed: columns ``x(o)``, ``(ne, n_fixed)``.
        dependent: columns ``x(c)``, ``(ne, n_dependent)``.
        independent: columns ``x(m)``, ``(ne, n_xm)``.
        D_c: rows ``e(o), e(m)`` of ``dependent``, square.
        conditioning: estimate of the smallest singular value of ``D_c`` after
            scaling angles by the model size and normalising each row (1 for a
            well-conditioned mechanism, 0 at a singular configuration).
    """

    model: Model
    full: np.ndarray
    fixed: np.ndarray
    dependent: np.ndarray
    independent: np.ndarray
    D_c: np.ndarray
    conditioning: float
    _factors: DenseFactor | None

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """``D_c^-1 rhs`` for ``rhs`` of shape ``(n_dependent,)`` or ``(n_dependent, k)``."""
        if self._factors is None:
            return np.zeros_like(rhs)
        return self._factors.inverse[0] @ np.asarray(rhs, dtype=float)


def partition_jacobian(model: Model, x: np.ndarray, time: float | None = None,
                       D_x: np.ndarray | None = None) -> PartitionedJacobian:
    """Split ``D_x`` at ``x`` into ``x(o)``, ``x(c)``, ``x(m)`` columns and factorise ``D_c``.

    Raises:
        SingularConfigurationError: ``D_c`` is singular at ``x`` (names the time
            and the coordinates and deformations involved).
    """
    if D_x is None:
        D_x = jacobian(model, x)
    dependent = D_x[:, model.dependent]
    D_c = dependent[model.constrained]
    factors, conditioning = None, 1.0
    if D_c.size:
        factors = _factorize(model, D_x, D_c, time)
        conditioning = float(factors.conditioning[0])
    return PartitionedJacobian(
        model=model,
        full=D_x,
        fixed=D_x[:, model.fixed],
        dependent=dependent,
        independent=D_x[:, model.independent_coordinates],
        D_c=D_c,
        conditioning=conditioning,
        _factors=factors,
    )


def _factorize(model: Model, D_x: np.ndarray, D_c: np.ndarray, time: float | None
               ) -> DenseFactor:
    """Factorise the scaled ``D_c`` and estimate its smallest singular value.

    Angles are scaled by the model size and every row by the norm of its full
    ``D_x`` row, so the estimate is free of units: a constraint that can hardly
    move the dependent coordinates any more, compared with how it moves all
    coordinates, shows as a small value (e.g. the sliding bar lying flat).
    """
    if not np.all(np.isfinite(D_c)):
        raise ConvergenceError(f"{_at(time)}: the configuration is not finite", time)
    scaled_rows = D_x[model.constrained] * model.coordinate_scale
    row_scale = 1.0 / np.maximum(np.linalg.norm(scaled_rows, axis=1), 1e-300)
    factor = DenseFactor(D_c[None], row_scale, model.coordinate_scale[model.dependent])
    if not factor.conditioning[0] > SINGULAR_RCOND:
        raise singular_error(model, D_c, time, "D_c is singular")
    return factor


def singular_error(model: Model, D_c: np.ndarray, time: float | None, what: str
                   ) -> SingularConfigurationError:
    """The error of a singular ``D_c`` at ``time``, naming what no longer holds."""
    return SingularConfigurationError(
        f"singular configuration {_at(time)}: {what}; {weakest_direction(model, D_c)}; the "
        f"mechanism is at a dead point or at the end of its range of motion, where the "
        f"inputs cannot drive it further",
        time,
    )


def weakest_direction(model: Model, D_c: np.ndarray) -> str:
    """Name the coordinates and deformations of the smallest singular value of ``D_c``."""
    scaled = D_c * model.coordinate_scale[model.dependent]
    norms = np.linalg.norm(scaled, axis=1, keepdims=True)
    u, _, vt = np.linalg.svd(scaled / np.maximum(norms, 1e-300))
    coords = _largest(vt[-1])
    defs = _largest(u[:, -1])
    constraints = ", ".join(model.describe_deformation(model.constrained[i]) for i in defs)
    coordinates = ", ".join(model.describe_coordinate(model.dependent[j]) for j in coords)
    return f"the constraints {constraints} no longer determine {coordinates}"


def _largest(vector: np.ndarray, share: float = 0.1) -> np.ndarray:
    a = np.abs(vector)
    return np.flatnonzero(a >= share * a.max())


def diagnose_rank(model: Model, D_c: np.ndarray, rtol: float = 1e-10) -> str:
    """Explain a rank-deficient or non-square ``D_c`` in words; ``""`` if it is regular.

    The right null space of ``D_c`` holds the dependent-coordinate motions that
    leave every constrained deformation unchanged; the left null space holds
    combinations of constraint equations that are redundant.
    """
    rows, cols = D_c.shape
    u, s, vt = np.linalg.svd(D_c)
    rank = int(np.sum(s > rtol * (s[0] if s.size else 0.0)))
    if rank == rows == cols:
        return ""
    parts = [f"rank {rank} for {rows} equations in {cols} dependent coordinates"]
    free = vt[rank:]
    if len(free):
        involved = np.flatnonzero(np.abs(free).max(axis=0) > 1e-8)
        names = ", ".join(model.describe_coordinate(model.dependent[j]) for j in involved)
        parts.append(f"the coordinates {names} can move without changing any rigid or "
                     f"independent deformation")
    redundant = u[:, rank:]
    if redundant.shape[1]:
        involved = np.flatnonzero(np.abs(redundant).max(axis=1) > 1e-8)
        names = ", ".join(model.describe_deformation(model.constrained[i]) for i in involved)
        parts.append(f"the equations of {names} are linearly dependent")
    return "; ".join(parts)


def _at(time: float | None) -> str:
    return "in the given configuration" if time is None else f"at t = {time:.6g} s"


# --- positions --------------------------------------------------------------------------
def split_q(model: Model, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``q = [x(m); e(m)]`` into its coordinate and deformation parts."""
    nxm = len(model.independent_coordinates)
    return q[:nxm], q[nxm:]


def initial_q(model: Model) -> np.ndarray:
    """``q`` of the initial configuration: ``x(m)`` from ``x0``, ``e(m) = 0``."""
    return np.concatenate([model.x0[model.independent_coordinates],
                           np.zeros(len(model.independent_deformations))])


@dataclass(frozen=True, eq=False)
class PositionSolution:
    """Result of :func:`position_analysis`.

    Attributes:
        x: all coordinates, shape ``(nx,)``.
        jacobian: the partitioned Jacobian at ``x`` (ready for velocities).
        iterations: Newton iterations taken.
        residual: largest constraint residual before the final correction [m, rad].
    """

    x: np.ndarray
    jacobian: PartitionedJacobian
    iterations: int
    residual: float


def solve_position(model: Model, q: np.ndarray, x_guess: np.ndarray | None = None, *,
                   time: float | None = None, tolerance: float | None = None,
                   max_iterations: int = 25) -> np.ndarray:
    """Solve ``e(o)(x) = 0``, ``e(m)(x) = e(m)`` for ``x(c)`` by Newton-Raphson.

    Args:
        model: the mechanism.
        q: generalized coordinates ``[x(m); e(m)]``, shape ``(nq,)``.
        x_guess: start for ``x(c)`` (warm start), shape ``(nx,)``; default ``model.x0``.
        time: only used in messages [s].
        tolerance: on the largest residual [m, rad]; default
            ``1e-10 * model.characteristic_length``.
        max_iterations: Newton iterations before giving up.

    Returns:
        All coordinates ``x``, shape ``(nx,)``.

    Raises:
        ConvergenceError: no convergence (names time, iterations and residual).
        SingularConfigurationError: ``D_c`` singular on the way or at the solution.
    """
    return position_analysis(model, q, x_guess, time=time, tolerance=tolerance,
                             max_iterations=max_iterations).x


def position_analysis(model: Model, q: np.ndarray, x_guess: np.ndarray | None = None, *,
                      time: float | None = None, tolerance: float | None = None,
                      max_iterations: int = 25) -> PositionSolution:
    """:func:`solve_position` that also returns the Jacobian at the solution.

    Once the residual is below the tolerance, one more correction (with the last
    factorisation, or a new one when the guess was already within tolerance)
    makes the error of ``x`` second order in the residual, so positions are
    accurate far below the tolerance and do not depend on the starting guess
    (the dynamics differentiates through them). The returned Jacobian is
    evaluated at the returned ``x``.
    """
    if tolerance is None:
        tolerance = RELATIVE_TOLERANCE * model.characteristic_length
    x = np.array(model.x0 if x_guess is None else x_guess, dtype=float)
    x_m, e_m = split_q(model, np.asarray(q, dtype=float))
    x[model.fixed] = model.x0[model.fixed]
    x[model.independent_coordinates] = x_m
    rows, dep = model.constrained, model.dependent
    target = np.concatenate([np.zeros(len(model.rigid)), e_m])
    jac = None
    for iteration in range(max_iterations + 1):
        residual = deformations(model, x)[rows] - target
        residual_norm = float(np.max(np.abs(residual), initial=0.0))
        if residual_norm <= tolerance:
            at_x = jac is None  # converged from the guess: factorise here
            if at_x:
                jac = partition_jacobian(model, x, time)
            x[dep] -= jac.solve(residual)
            if not at_x or residual_norm > _ROUND_OFF * tolerance:
                jac = partition_jacobian(model, x, time)  # at the corrected x
            _check_regular(model, jac, time, tolerance)
            return PositionSolution(x, jac, iteration, residual_norm)
        if not np.isfinite(residual_norm) or iteration == max_iterations:
            break
        jac = partition_jacobian(model, x, time)
        x[dep] -= jac.solve(residual)
    worst = (model.describe_deformation(rows[int(np.argmax(np.abs(residual)))])
             if np.all(np.isfinite(residual)) else "a non-finite configuration")
    raise ConvergenceError(
        f"position solve did not converge {_at(time)}: residual {residual_norm:.3g} after "
        f"{iteration} iterations (tolerance {tolerance:.3g}), largest in {worst}; the inputs "
        f"may ask for a configuration the constraints cannot reach (e.g. beyond an element's "
        f"length) or the step from the previous solution is too large",
        time, iterations=iteration, residual=residual_norm,
    )


def regularity_limit(model: Model, tolerance: float) -> float:
    """Scaled smallest singular value of ``D_c`` below which a position solution at
    ``tolerance`` counts as singular (see :func:`_check_regular`)."""
    return 10.0 * float(np.sqrt(tolerance / model.characteristic_length))


def _check_regular(model: Model, jac: PartitionedJacobian, time: float | None,
                   tolerance: float) -> None:
    """Reject a converged solution that is singular within the position tolerance.

    Near a singular root Newton converges only linearly and stops about
    ``sqrt(tolerance)`` away from it, where ``D_c`` still looks regular. A
    scaled smallest singular value below ``10 sqrt(tolerance / L)`` cannot be
    told apart from zero at that tolerance.
    """
    limit = regularity_limit(model, tolerance)
    if len(model.dependent) and jac.conditioning < limit:
        raise singular_error(model, jac.D_c, time,
                        f"D_c is singular within the position tolerance (scaled smallest "
                        f"singular value {jac.conditioning:.2g} < {limit:.2g})")


# --- velocities and accelerations --------------------------------------------------------
def velocities(model: Model, x: np.ndarray, qd: np.ndarray,
               jac: PartitionedJacobian | None = None) -> np.ndarray:
    """``xdot`` from ``qdot = [xdot(m); edot(m)]`` by the partitioned solve (THEORY 4).

    ``D_c xdot(c) = [0; edot(m)] - [de(o)/dx(m); de(m)/dx(m)] xdot(m)``. Shape ``(nx,)``.
    """
    jac = jac or partition_jacobian(model, x)
    xd_m, ed_m = split_q(model, np.asarray(qd, dtype=float))
    xd = np.zeros(model.n_coordinates)
    xd[model.independent_coordinates] = xd_m
    rhs = np.concatenate([np.zeros(len(model.rigid)), ed_m]) \
        - jac.independent[model.constrained] @ xd_m
    xd[model.dependent] = jac.solve(rhs)
    return xd


def accelerations(model: Model, x: np.ndarray, xd: np.ndarray, qdd: np.ndarray,
                  jac: PartitionedJacobian | None = None) -> np.ndarray:
    """``xddot`` from ``qddot`` with the quadratic velocity terms (THEORY 4). Shape ``(nx,)``."""
    jac = jac or partition_jacobian(model, x)
    xdd_m, edd_m = split_q(model, np.asarray(qdd, dtype=float))
    xdd = np.zeros(model.n_coordinates)
    xdd[model.independent_coordinates] = xdd_m
    rhs = (np.concatenate([np.zeros(len(model.rigid)), edd_m])
           - jac.independent[model.constrained] @ xdd_m
           - quadratic_velocity(model, x, xd)[model.constrained])
    xdd[model.dependent] = jac.solve(rhs)
    return xdd


# --- transfer functions ---------------------------------------------------------------
def first_order_transfer(model: Model, x: np.ndarray,
                         jac: PartitionedJacobian | None = None) -> np.ndarray:
    """``F_q = dx/dq``, shape ``(nx, nq)``: ``xdot = F_q qdot`` (THEORY 4)."""
    jac = jac or partition_jacobian(model, x)
    nxm, nq = len(model.independent_coordinates), model.n_dof
    F_q = np.zeros((model.n_coordinates, nq))
    F_q[model.independent_coordinates, np.arange(nxm)] = 1.0
    rhs = np.zeros((len(model.constrained), nq))
    rhs[:, :nxm] = -jac.independent[model.constrained]
    rhs[len(model.rigid):, nxm:] = np.eye(nq - nxm)
    F_q[model.dependent] = jac.solve(rhs)
    return F_q


def deformation_transfer(model: Model, x: np.ndarray, F_q: np.ndarray | None = None
                         ) -> np.ndarray:
    """``E_q = D_x F_q``, shape ``(ne, nq)``: ``edot = E_q qdot``."""
    if F_q is None:
        F_q = first_order_transfer(model, x)
    return jacobian(model, x) @ F_q


def second_order_transfer(model: Model, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``F_qq`` ``(nx, nq, nq)`` and ``E_qq`` ``(ne, nq, nq)``, the derivatives of F_q, E_q.

    ``xddot = F_q qddot + (F_qq qdot) qdot``. Differentiating ``D_x F_q = const`` on the
    rows ``e(o), e(m)`` gives ``D_c F_qq(c) = -F_q^T D_xx F_q`` there; then
    ``E_qq = F_q^T D_xx F_q + D_x F_qq``. Meant for inspection and small models: the
    analyses use :func:`quadratic_velocity` instead of forming these arrays.
    """
    jac = partition_jacobian(model, x)
    F_q = first_order_transfer(model, x, jac)
    nq = model.n_dof
    curvature = np.einsum("iab,aj,bk->ijk", hessian(model, x), F_q, F_q)
    F_qq = np.zeros((model.n_coordinates, nq, nq))
    if len(model.dependent):
        rhs = -curvature[model.constrained].reshape(len(model.constrained), nq * nq)
        F_qq[model.dependent] = jac.solve(rhs).reshape(len(model.dependent), nq, nq)
    E_qq = curvature + np.einsum("ia,ajk->ijk", jac.full, F_qq)
    return F_qq, E_qq
