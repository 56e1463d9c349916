"""Reduced equations of motion, inverse dynamics and reactions (THEORY sections 7, 8).

With ``xdot = F_q qdot`` and ``edot = E_q qdot`` the virtual power of inertia,
applied and elastic forces reduces to

    Mbar qddot = F_q^T (f - h - M (F_qq qdot) qdot) - E_q^T sigma,   Mbar = F_q^T M F_q.

``q`` splits into dynamic entries ``d`` and prescribed (rheonomic) entries ``r``
(``model.q_is_input``); ``Mbar_dd qddot_d = g_d - Mbar_dr qddot_r`` is the ODE of
a forward simulation, ``tau_r = Mbar_rd qddot_d + Mbar_rr qddot_r - g_r`` the
driving force of the prescribed entries.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from .errors import ModelError, SingularConfigurationError
from .inertia import applied_forces, elastic_stresses, inertia_velocity, mass_matrix
from .kinematics import (
    PartitionedJacobian,
    accelerations,
    deformations,
    first_order_transfer,
    position_analysis,
    velocities,
)
from .model import Model

#: applied loads as a function of time and state: ``forces(t, x, xdot)`` returning an
#: array ``(nx,)`` or a mapping from coordinate labels (``"x2.1"``) to values [N, N m]
Forces = Callable[[float, np.ndarray, np.ndarray], "np.ndarray | Mapping[str, float]"]


@dataclass(frozen=True, eq=False)
class DynamicTerms:
    """The terms of the reduced equations at one time and state.

    Attributes:
        time: [s].
        x, xd: coordinates and velocities ``(nx,)``.
        jacobian: the partitioned Jacobian at ``x``.
        F_q, E_q: first-order transfer functions ``(nx, nq)``, ``(ne, nq)``.
        convective: ``(F_qq qdot) qdot`` ``(nx,)``, the acceleration at ``qddot = 0``.
        M, h, f: system mass matrix, velocity term and applied forces.
        e, ed: deformations and their rates ``(ne,)``.
        sigma: stresses of the dynamic and released deformations ``(ne,)``.
        reduced_mass: ``Mbar = F_q^T M F_q`` ``(nq, nq)``.
        generalized_force: ``g = F_q^T (f - h - M convective) - E_q^T sigma`` ``(nq,)``.
    """

    time: float | None
    x: np.ndarray
    xd: np.ndarray
    jacobian: PartitionedJacobian
    F_q: np.ndarray
    E_q: np.ndarray
    convective: np.ndarray
    M: np.ndarray
    h: np.ndarray
    f: np.ndarray
    e: np.ndarray
    ed: np.ndarray
    sigma: np.ndarray
    reduced_mass: np.ndarray
    generalized_force: np.ndarray


def load_vector(model: Model, loads, t, x, xd) -> np.ndarray:
    """User loads (array or label mapping, see :data:`Forces`) as an array ``(nx,)``."""
    value = loads(t, x, xd)
    if isinstance(value, Mapping):
        f = np.zeros(model.n_coordinates)
        for label, v in value.items():
            try:
                f[model.coordinate_index(label)] += v
            except KeyError as err:
                raise ModelError(f"forces: {err.args[0]}") from None
        return f
    f = np.asarray(value, dtype=float)
    if f.shape != (model.n_coordinates,):
        raise ModelError(f"forces must return an array of shape ({model.n_coordinates},) or a "
                         f"mapping of coordinate labels, got shape {f.shape}")
    return f


def dynamic_terms(model: Model, q: np.ndarray, qd: np.ndarray, time: float | None = None, *,
                  x_guess: np.ndarray | None = None, forces: Forces | None = None,
                  tolerance: float | None = None) -> DynamicTerms:
    """Solve the kinematics at ``(q, qdot)`` and evaluate the reduced equations (THEORY 7)."""
    solution = position_analysis(model, q, x_guess, time=time, tolerance=tolerance)
    x, jac = solution.x, solution.jacobian
    xd = velocities(model, x, qd, jac)
    F_q = first_order_transfer(model, x, jac)
    E_q = jac.full @ F_q
    convective = accelerations(model, x, xd, np.zeros(model.n_dof), jac)
    M = mass_matrix(model, x)
    h = inertia_velocity(model, x, xd)
    f = applied_forces(model, x)
    if forces is not None:
        f = f + load_vector(model, forces, time, x, xd)
    e = deformations(model, x)
    ed = jac.full @ xd
    sigma = elastic_stresses(model, e, ed)
    reduced_mass = F_q.T @ M @ F_q
    generalized_force = F_q.T @ (f - h - M @ convective) - E_q.T @ sigma
    return DynamicTerms(time, x, xd, jac, F_q, E_q, convective, M, h, f, e, ed, sigma,
                        reduced_mass, generalized_force)


def generalized_accelerations(model: Model, terms: DynamicTerms, qdd_prescribed: np.ndarray
                              ) -> np.ndarray:
    """``qddot`` ``(nq,)``: dynamic entries from ``Mbar_dd qdd_d = g_d - Mbar_dr qdd_r``.

    Raises:
        SingularConfigurationError: ``Mbar_dd`` is singular (a massless degree of freedom).
    """
    d, r = ~model.q_is_input, model.q_is_input
    qdd = np.zeros(model.n_dof)
    qdd[r] = qdd_prescribed
    if not np.any(d):
        return qdd
    Mbar = terms.reduced_mass
    rhs = terms.generalized_force[d] - Mbar[np.ix_(d, r)] @ qdd[r]
    # Cholesky doubles as the positive-definiteness check (numpy: no scipy at import)
    try:
        factor = np.linalg.cholesky(Mbar[np.ix_(d, d)])
    except np.linalg.LinAlgError:
        dofs = ", ".join(model.describe_q(j) for j in np.flatnonzero(d))
        at = "" if terms.time is None else f" at t = {terms.time:.6g} s"
        raise SingularConfigurationError(
            f"the reduced mass matrix of the dynamic degrees of freedom ({dofs}) is not "
            f"positive definite{at}: give every dynamic degree of freedom mass or inertia",
            terms.time) from None
    qdd[d] = np.linalg.solve(factor.T, np.linalg.solve(factor, rhs))
    return qdd


def driving_forces(model: Model, terms: DynamicTerms, qdd: np.ndarray) -> np.ndarray:
    """Inverse dynamics: ``tau = Mbar qddot - g``, the generalized force the drives supply.

    Returns an array over all entries of ``q`` (``model.q_labels``) [N, N m]: the
    driving forces of the prescribed entries; on dynamic entries it is the force
    that would be needed beyond the model's own loads, zero for a motion that
    solves the equations of motion.
    """
    return terms.reduced_mass @ qdd - terms.generalized_force


@dataclass(frozen=True, eq=False)
class Reactions:
    """Stresses of all deformations and the support and driving loads (THEORY 8).

    Attributes:
        sigma: generalized stresses ``(ne,)``: constraint stresses on rigid
            deformations, actuator stresses on input deformations, the elastic law
            elsewhere (on dynamic deformations the solved value agrees with it).
        nodal: loads ``(nx,)`` the supports exert on fixed coordinates and the drives on
            input coordinates [N, N m]; zero on dependent and dynamic coordinates.
    """

    sigma: np.ndarray
    nodal: np.ndarray


def reactions(model: Model, terms: DynamicTerms, qdd: np.ndarray) -> Reactions:
    """Constraint stresses and support reactions once ``qddot`` is known (THEORY 8).

    Nodal equilibrium ``f + f_support - M xddot - h = D_x^T sigma`` holds on every
    coordinate; the dependent rows give ``D_c^T [sigma(o); sigma(m)] = (f - M xddot
    - h)(c) - (de(c)/dx(c))^T sigma(c)``, then the fixed and input rows give the loads.
    """
    xdd = terms.F_q @ qdd + terms.convective
    D_x = terms.jacobian.full
    unbalanced = terms.f - terms.M @ xdd - terms.h
    dep, rows, released = model.dependent, model.constrained, model.released
    rhs = unbalanced[dep] - D_x[np.ix_(released, dep)].T @ terms.sigma[released]
    sigma = terms.sigma.copy()
    if len(rows):
        sigma[rows] = np.linalg.solve(terms.jacobian.D_c.T, rhs)
    nodal = D_x.T @ sigma - unbalanced
    supported = np.concatenate([model.fixed, model.input_coordinates])
    out = np.zeros(model.n_coordinates)
    out[supported] = nodal[supported]
    return Reactions(sigma, out)
