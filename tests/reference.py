"""THEORY's per-state formulas in dense numpy: a test-only reference for the engine.

The library runs every analysis on its compiled core (banded factorisations, a
saddle-point system, no ``F_q``). Here the same quantities are computed the way
THEORY writes them, with dense matrices and numpy's solvers, from the element
values alone (the kernels are checked on their own against finite differences,
SymPy and quadrature in test_elements.py and test_inertia.py):

* ``F_q`` from ``D_c F_c = [-D_m | [0; I]]`` (THEORY 4), ``E_q = D_x F_q``;
* the convective acceleration ``(F_qq qdot) qdot`` from the quadratic velocity terms;
* ``Mbar = F_q^T M F_q`` and the generalized force
  ``g = F_q^T (f - h - M (F_qq qdot) qdot) - E_q^T sigma`` (THEORY 7);
* the stresses of the constrained deformations and the support loads from the nodal
  equilibrium of the dependent coordinates (THEORY 8).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import flexmbd as fm
from flexmbd.engine import Workspace, compile_model

from .elementwise import deformations_and_jacobian


def elastic_law(model: fm.Model) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``S``, ``C`` ``(ne, ne)`` and ``sigma0`` ``(ne,)`` of the dynamic and released
    deformations, from the element types' laws."""
    elements, ne = compile_model(model).elements, model.n_deformations
    S, C = np.zeros((ne, ne)), np.zeros((ne, ne))
    for k, number in enumerate(sorted(model.elements)):
        element = model.elements[number]
        nd, start = len(element.deformations), elements.law_off[k]
        block = np.ix_(element.deformations, element.deformations)
        S[block] = elements.S[start:start + nd * nd].reshape(nd, nd)
        C[block] = elements.C[start:start + nd * nd].reshape(nd, nd)
    return S, C, elements.sigma0


@dataclass(frozen=True)
class Terms:
    """The reduced equations at one state (THEORY 7)."""

    x: np.ndarray
    xd: np.ndarray
    D_x: np.ndarray
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


def terms(model: fm.Model, q: np.ndarray, qd: np.ndarray, x_guess=None, forces=None,
          t: float = 0.0) -> Terms:
    """Solve the positions at ``q`` and evaluate the reduced equations there."""
    x = fm.solve_position(model, q, x_guess)
    e, D_x = deformations_and_jacobian(model, x)
    rows, dep = model.constrained, model.dependent
    D_c = D_x[np.ix_(rows, dep)]
    nq, nxm = model.n_dof, len(model.independent_coordinates)
    rhs = np.zeros((len(rows), nq))
    rhs[:, :nxm] = -D_x[np.ix_(rows, model.independent_coordinates)]
    rhs[len(model.rigid):, nxm:] = np.eye(nq - nxm)
    F_q = np.zeros((model.n_coordinates, nq))
    F_q[model.independent_coordinates, np.arange(nxm)] = 1.0
    if len(dep):
        F_q[dep] = np.linalg.solve(D_c, rhs)
    xd = F_q @ qd
    E_q = D_x @ F_q
    quadratic = fm.quadratic_velocity(model, x, xd)
    convective = np.zeros(model.n_coordinates)
    if len(dep):
        convective[dep] = np.linalg.solve(D_c, -quadratic[rows])
    M, h, f = Workspace(model).mass(x, xd)
    if forces is not None:
        f = f + fm.engine.load_vector(model, forces(t, x, xd))
    ed = D_x @ xd
    S, C, sigma0 = elastic_law(model)
    sigma = np.where(model.carries_elastic_stress, S @ e + C @ ed + sigma0, 0.0)
    reduced_mass = F_q.T @ M @ F_q
    generalized_force = F_q.T @ (f - h - M @ convective) - E_q.T @ sigma
    return Terms(x, xd, D_x, F_q, E_q, convective, M, h, f, e, ed, sigma, reduced_mass,
                 generalized_force)


def newton_matrix(model: fm.Model, t: Terms, qdd: np.ndarray, c_q: float, c_v: float
                  ) -> np.ndarray:
    """``S = Mbar + c_q (K + G) + c_v D`` ``(nq, nq)`` at a state with accelerations ``qdd``:
    ``K = E_q^T S E_q``, ``D = E_q^T C E_q`` and the geometric stiffness ``G = F_q^T (sum_i
    sigma_i D_xx,i) F_q`` of all stresses, the elastic ones and those the constraints need
    at these accelerations (THEORY 8 away from equilibrium: ``D_c^T sigma = -y(c)``)."""
    S, C, _ = elastic_law(model)
    xdd = t.F_q @ qdd + t.convective
    y = t.M @ xdd + t.h - t.f + t.D_x.T @ t.sigma
    rows, dep = model.constrained, model.dependent
    sigma = t.sigma.copy()
    if len(rows):
        sigma[rows] -= np.linalg.solve(t.D_x[np.ix_(rows, dep)].T, y[dep])
    geometric = np.einsum("i,iab->ab", sigma, fm.hessian(model, t.x))
    return (t.reduced_mass + c_q * (t.E_q.T @ S @ t.E_q + t.F_q.T @ geometric @ t.F_q)
            + c_v * t.E_q.T @ C @ t.E_q)


def accelerations(model: fm.Model, t: Terms, qdd_prescribed: np.ndarray) -> np.ndarray:
    """``qddot`` with the dynamic entries from ``Mbar_dd qdd_d = g_d - Mbar_dr qdd_r``."""
    d, r = ~model.q_is_input, model.q_is_input
    qdd = np.zeros(model.n_dof)
    qdd[r] = qdd_prescribed
    if np.any(d):
        Mbar = t.reduced_mass
        qdd[d] = np.linalg.solve(Mbar[np.ix_(d, d)],
                                 t.generalized_force[d] - Mbar[np.ix_(d, r)] @ qdd[r])
    return qdd


def driving_forces(t: Terms, qdd: np.ndarray) -> np.ndarray:
    """``tau = Mbar qddot - g`` over all of ``q`` (inverse dynamics, THEORY 7)."""
    return t.reduced_mass @ qdd - t.generalized_force


def reactions(model: fm.Model, t: Terms, qdd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Stresses of all deformations and the loads on fixed and input coordinates (THEORY 8):
    ``D_c^T [sigma(o); sigma(m)] = (f - M xdd - h)(c) - (de(c)/dx(c))^T sigma(c)``."""
    xdd = t.F_q @ qdd + t.convective
    unbalanced = t.f - t.M @ xdd - t.h
    dep, rows, released = model.dependent, model.constrained, model.released
    sigma = t.sigma.copy()
    if len(rows):
        rhs = unbalanced[dep] - t.D_x[np.ix_(released, dep)].T @ t.sigma[released]
        sigma[rows] = np.linalg.solve(t.D_x[np.ix_(rows, dep)].T, rhs)
    nodal = t.D_x.T @ sigma - unbalanced
    supported = np.concatenate([model.fixed, model.input_coordinates]).astype(int)
    out = np.zeros(model.n_coordinates)
    out[supported] = nodal[supported]
    return sigma, out
