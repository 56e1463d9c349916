"""Static equilibrium and its linearization in all coordinates, on the banded
saddle-point system of the core (THEORY 9).

The reduced static solver forms the tangent ``K0 + G0`` over the degrees of freedom,
which is dense (``F_q`` is): on a flexure of many beams its cost grows with the cube of
their number. Here the unknowns are the free coordinates ``x`` (calculable and dynamic)
and the stresses ``mu`` of the constrained deformations (rigid and prescribed):

    D^T (sigma(e) + mu) - f(x) = 0      on the free coordinates,
    e_c(x) - e_c,target = 0             on the constrained deformations,

with ``sigma`` the elastic law's stresses (and pre-stress) and ``f`` the applied loads (a
global moment's generalized force ``2 E(lam)^T M`` turning with its node). Newton's
matrix is ``[[K, D_c^T], [D_c, 0]]`` with ``K = D^T S D + sum_i (sigma_i + mu_i) D_xx,i -
df/dx``: every term element by element, banded in the core's ordering, so one
factorisation costs ``O(n b^2)`` for ``n`` unknowns and band ``b``.

On the null space of ``D_c`` this ``K`` is the reduced tangent ``K0 + G0`` (``T^T K T``
with ``T = F_q`` restricted to the dynamic entries), so the same factorisation gives the
linearized analyses at an equilibrium (:class:`BandedTangent`): the compliance solves it
for unit loads, and the vibration modes ``K z = omega^2 M z`` with ``D_c z = 0`` are the
largest ``1/omega^2`` of its inverse times ``M``, found by ARPACK
(:mod:`flexmbd.analysis.eigen`). Both agree with the reduced path to rounding.
"""

from __future__ import annotations

import numpy as np

from ..elements.base import SPATIAL_ROTATIONAL
from ..engine import CoreError, Workspace
from ..errors import ArgumentError, ConvergenceError, SingularConfigurationError
from ..model import CoordinateClass, DeformationClass, Model
from ..orientation import angular_velocity

__all__ = ["BANDED_FROM", "BandedStatics", "BandedTangent"]

#: degrees of freedom from which the static analyses and the linearized ones at an
#: equilibrium work in all coordinates on the banded saddle-point system: the reduced
#: tangent is dense, and its cost grows with the cube of the degrees of freedom (at 90, a
#: flexure pivot of 16 beams, already 7 times the banded)
BANDED_FROM = 40

#: a state counts as an equilibrium when one Newton step from it moves no free coordinate
#: by more than this share of the model size: the banded tangent (elastic stresses on the
#: released deformations) is then the reduced one (balancing stresses)
EQUILIBRIUM = 1e-7


class BandedStatics:
    """The static equilibrium of ``model`` in all coordinates on the core's banded
    saddle-point system (module docstring). Its last factorised tangent is kept for
    :meth:`solve` and :meth:`mass_times`.

    Attributes:
        free: the free coordinates (calculable and dynamic), the first unknowns ``(nf,)``.
        constrained: the constrained deformations (rigid and prescribed), whose stresses
            ``mu`` are the other unknowns ``(nc,)``.
    """

    def __init__(self, model: Model, engine: Workspace):
        self.model, self.engine = model, engine
        classes = np.asarray(model.coordinate_class)
        self.free = np.flatnonzero((classes == CoordinateClass.DEPENDENT)
                                   | (classes == CoordinateClass.DYNAMIC))
        kinds = np.asarray(model.deformation_class)
        self.constrained = np.flatnonzero((kinds == DeformationClass.RIGID)
                                          | (kinds == DeformationClass.INPUT))
        #: per free coordinate: metres per unit (1 for lengths, the model size for angles
        #: and Euler parameters), to judge a Newton step against a tolerance in metres
        self.metres = 1.0 / np.asarray(model.coordinate_scale, dtype=float)[self.free]
        nxm = len(model.independent_coordinates)
        inputs = np.asarray(model.q_is_input, dtype=bool)
        self._input_slots = np.flatnonzero(inputs[:nxm])
        self._input_coordinates = np.asarray(model.independent_coordinates)[self._input_slots]

    @property
    def size(self) -> int:
        """Unknowns of the saddle-point system: free coordinates and constraint stresses."""
        return len(self.free) + len(self.constrained)

    def factor(self, x: np.ndarray, q: np.ndarray, mu: np.ndarray, loads: np.ndarray
               ) -> np.ndarray:
        """Factorise the tangent at ``x`` ``(nx,)`` with the constraint stresses ``mu``
        ``(nc,)`` [N, N m] under the applied ``loads`` ``(nx,)`` (besides the model's),
        ``q`` ``(nq,)`` holding the targets of the inputs; returns the residual ``(n,)``
        (out-of-balance loads on the free coordinates, then the constraint errors).

        Raises:
            numpy.linalg.LinAlgError: the tangent is singular (a mechanism, buckling) or
                not finite.
        """
        self.engine.static_owner = None   # the core's kept factorisation changes hands
        try:
            return self.engine.static_residual(x, q, mu, loads)
        except CoreError:
            raise np.linalg.LinAlgError("the static tangent [[K, D_c^T], [D_c, 0]] is "
                                        "singular or not finite") from None

    def solve(self, rhs: np.ndarray, transposed: bool = False) -> np.ndarray:
        """The factorised tangent's solution for the columns of ``rhs`` ``(n, k)`` (loads on
        the free coordinates, then constraint changes): ``(n, k)`` (coordinate changes,
        then stress changes); with the transposed tangent when ``transposed`` (the
        adjoint solves of design sensitivities)."""
        rows = np.array(np.asarray(rhs, dtype=float).reshape(self.size, -1).T, order="C")
        self.engine.static_solve(rows, transposed)
        return rows.T.reshape(np.shape(rhs))

    def mass_times(self, V: np.ndarray) -> np.ndarray:
        """``M V`` over the free coordinates, ``V`` ``(nf, k)``, at the factorised state."""
        rows = np.ascontiguousarray(np.asarray(V, dtype=float).T)
        out = np.empty_like(rows)
        self.engine.free_mass_times(rows, out)
        return out.T

    def equilibrium(self, x: np.ndarray, q: np.ndarray, mu: np.ndarray, loads: np.ndarray,
                    tolerance: float, max_iterations: int) -> tuple[np.ndarray, np.ndarray]:
        """Newton's method from ``x``, ``mu`` to the equilibrium under ``loads`` with the
        inputs at their targets in ``q`` (module docstring); returns ``(x, mu)``.

        Raises:
            ConvergenceError: no convergence to ``tolerance`` [m] (a change of the free
                coordinates, angles times the model size) in ``max_iterations``.
            numpy.linalg.LinAlgError: a singular tangent on the way.
        """
        x, mu = np.array(x, dtype=float), np.array(mu, dtype=float)
        x[self._input_coordinates] = q[self._input_slots]
        nf, residual = len(self.free), np.inf
        for _ in range(max_iterations):
            r = self.factor(x, q, mu, loads)
            residual = float(np.max(np.abs(r[:nf]), initial=0.0))
            step = -self.solve(r)
            if not np.all(np.isfinite(step)):
                raise np.linalg.LinAlgError("the static tangent is singular")
            x[self.free] += step[:nf]
            mu += step[nf:]
            if np.max(np.abs(step[:nf]) * self.metres, initial=0.0) <= tolerance:
                return x, mu
        raise ConvergenceError(f"Newton did not converge in {max_iterations} iterations "
                               f"(largest out-of-balance load {residual:.3g})",
                               iterations=max_iterations, residual=residual)

    def compliance(self, x: np.ndarray, labels) -> np.ndarray:
        """The compliance ``(k, k)`` seen at the coordinates ``labels`` at the factorised
        state ``x`` (:func:`flexmbd.analysis.modes.compliance`'s meaning: on a spatial
        rotational node the labels of ``lam1..lam3`` stand for its global rotations and
        the moments about x, y and z; the prescribed inputs held): ``P K^-1 P^T`` with
        ``P`` the rows that read those motions from the free coordinates (``2 E(lam)``
        for a rotation), whose transposes are the loads of unit forces and moments. Like
        ``K``, it is unsymmetric under a global moment's load stiffness.

        Raises:
            SingularConfigurationError: the compliance is not positive definite (the loads
                buckle the structure).
        """
        model, nf = self.model, len(self.free)
        rows = np.zeros((len(labels), model.n_coordinates))
        for k, label in enumerate(labels):
            i = model.coordinate_index(label)
            node = model.nodes[int(model.coordinate_labels[i][1:].split(".")[0])]
            if node.kind != SPATIAL_ROTATIONAL:
                rows[k, i] = 1.0
                continue
            at = list(node.coordinates)
            if i == at[0]:
                raise ArgumentError("labels", f"{label} is lam0 of a spatial rotational "
                                              f"node; its rotations are lam1 to lam3")
            rows[k, at] = angular_velocity(x[at], np.eye(4))[:, at.index(i) - 1]
        rhs = np.zeros((self.size, len(labels)))
        rhs[:nf] = rows[:, self.free].T
        C = rhs[:nf].T @ self.solve(rhs)[:nf]
        moving = np.flatnonzero(np.any(rhs[:nf] != 0.0, axis=0))   # held inputs do not
        try:
            np.linalg.cholesky(0.5 * (C + C.T)[np.ix_(moving, moving)])
        except np.linalg.LinAlgError:
            raise SingularConfigurationError(
                "the compliance is not positive definite: the dynamic degrees of freedom "
                "include a mechanism (no stiffness) or the loads buckle the structure"
            ) from None
        return C


class BandedTangent:
    """The banded tangent at one static equilibrium, for its linearized analyses: the
    compliance and the lowest vibration modes over the free coordinates. The workspace's
    core keeps one factorisation at a time; this one is made again when another state
    has taken it.

    Args:
        banded: the model's saddle-point system on a workspace.
        x: the equilibrium's coordinates ``(nx,)``; ``q`` ``(nq,)`` with the inputs.
        mu: the constraint stresses ``(nc,)`` [N, N m]; ``loads`` applied on top of the
            model's ``(nx,)``.
    """

    def __init__(self, banded: BandedStatics, x: np.ndarray, q: np.ndarray, mu: np.ndarray,
                 loads: np.ndarray):
        self.banded, self.x, self.q, self.mu, self.loads = banded, x, q, mu, loads
        self._residual: np.ndarray | None = None

    def ready(self) -> None:
        """Factorise (again, when another state holds the workspace's factorisation).

        Raises:
            numpy.linalg.LinAlgError: the tangent is singular or not finite.
        """
        engine = self.banded.engine
        if engine.static_owner is not self:
            self._residual = self.banded.factor(self.x, self.q, self.mu, self.loads)
            engine.static_owner = self

    def off_balance(self) -> float:
        """How far the state is from an equilibrium: the largest change of a free
        coordinate of one Newton step from it, in model sizes (angles times the size)."""
        self.ready()
        assert self._residual is not None
        step = self.banded.solve(self._residual)[:len(self.banded.free)]
        size = self.banded.model.characteristic_length
        return float(np.max(np.abs(step) * self.banded.metres, initial=0.0)) / size

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """:meth:`BandedStatics.solve` on this state's factorisation."""
        self.ready()
        return self.banded.solve(rhs)

    def mass_times(self, V: np.ndarray) -> np.ndarray:
        """``M V`` over the free coordinates at this state, ``V`` ``(nf, k)``."""
        self.ready()
        return self.banded.mass_times(V)

    def compliance(self, labels) -> np.ndarray:
        """:meth:`BandedStatics.compliance` at this state."""
        self.ready()
        return self.banded.compliance(self.x, labels)

    def inverse_times(self, v: np.ndarray) -> np.ndarray:
        """``K^-1 v`` over the free coordinates with ``D_c`` held: the displacement ``z``
        ``(nf,)`` under the loads ``v`` with the constraints kept (``D_c z = 0``)."""
        nf = len(self.banded.free)
        rhs = np.zeros(self.banded.size)
        rhs[:nf] = v
        return self.solve(rhs)[:nf]

    def inverse_times_mass(self, v: np.ndarray) -> np.ndarray:
        """``K^-1 M v`` over the free coordinates with ``D_c`` held: the displacement
        ``z`` ``(nf,)`` under the loads ``M v`` with the constraints kept (``D_c z = 0``)."""
        nf = len(self.banded.free)
        return self.inverse_times(
            self.mass_times(np.asarray(v, dtype=float).reshape(nf, 1))[:, 0])
