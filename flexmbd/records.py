"""Collecting the full dynamic state of a run, one output time at a time."""

from __future__ import annotations

import numpy as np

from .dynamics import DynamicTerms, driving_forces, reactions
from .kinematics import quadratic_velocity
from .model import Model
from .results import SimulationResult


class DynamicRecord:
    """Rows of a :class:`~flexmbd.results.SimulationResult` for ``nt`` output times.

    Each :meth:`add` takes the reduced-equation terms at one time with the
    generalized accelerations and stores kinematics, stresses, driving forces
    and (optionally) reactions.
    """

    def __init__(self, model: Model, nt: int, with_reactions: bool):
        nx, ne, nq = model.n_coordinates, model.n_deformations, model.n_dof
        self.model, self.with_reactions, self.count = model, with_reactions, 0
        self.times = np.zeros(nt)
        self.arrays = {name: np.zeros((nt, n)) for name, n in (
            ("x", nx), ("xd", nx), ("xdd", nx), ("e", ne), ("ed", ne), ("edd", ne),
            ("q", nq), ("qd", nq), ("qdd", nq), ("sigma", ne), ("driving", nq))}
        if with_reactions:
            self.arrays["reactions"] = np.zeros((nt, nx))

    def add(self, t: float, terms: DynamicTerms, q: np.ndarray, qd: np.ndarray,
            qdd: np.ndarray) -> None:
        """Store the state at time ``t`` [s]."""
        model, k = self.model, self.count
        xdd = terms.F_q @ qdd + terms.convective
        row = {"x": terms.x, "xd": terms.xd, "xdd": xdd, "e": terms.e, "ed": terms.ed,
               "edd": terms.jacobian.full @ xdd + quadratic_velocity(model, terms.x, terms.xd),
               "q": q, "qd": qd, "qdd": qdd, "sigma": terms.sigma,
               "driving": driving_forces(model, terms, qdd)}
        if self.with_reactions:
            found = reactions(model, terms, qdd)
            row["sigma"], row["reactions"] = found.sigma, found.nodal
        for name, value in row.items():
            self.arrays[name][k] = value
        self.times[k] = t
        self.count += 1

    def result(self) -> SimulationResult:
        """The rows stored so far."""
        n = self.count
        return SimulationResult(self.model, self.times[:n],
                                **{name: a[:n] for name, a in self.arrays.items()})
