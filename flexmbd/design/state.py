"""A converged static state and its exact sensitivity to the design.

At an equilibrium the engine's static residual in all coordinates
(:mod:`flexmbd.analysis.banded`) vanishes:

    R(x, mu; theta) = [ D_x^T (sigma_el + mu) - f ]   on the free coordinates,
                      [ e_c - e_c,target ]             on the constrained deformations,

with ``z = (x_free, mu)`` the unknowns and ``theta`` a design parameter. Its total
derivative is zero, so ``A dz/dtheta = -dR/dtheta`` with ``A = dR/dz`` the banded
tangent ``[[K, D_c^T], [D_c, 0]]`` the engine factorises (the direct method: one solve
per parameter on that one factorisation); an output ``J(z)`` takes ``A^T xi = dJ/dz``
instead (the adjoint: one transposed solve per output).

``dR/dtheta`` at fixed ``z`` comes from what the design moves (:class:`DataChange`):
the fixed coordinates and prescribed inputs, the elements' reference parameters and
elastic laws (their terms exact, :mod:`flexmbd.design.elements`), and the loads.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..analysis.banded import BandedStatics
from ..analysis.linearization import turning_moments
from ..engine import Workspace
from ..errors import SingularConfigurationError
from ..model import CoordinateClass, Model
from ..orientation import euler_forces
from .elements import Change, force_change, groups_of, internal_force

__all__ = ["DataChange", "Equilibrium"]

#: iterative refinements of the state's change at most
REFINEMENTS = 3



@dataclass(frozen=True)
class DataChange:
    """The derivative of a model's data to one design parameter (per unit of it).

    Attributes:
        x_held: of the fixed coordinates' and prescribed inputs' values ``(nx,)``, zero on
            the free coordinates.
        dp: of the reference parameters, per element group ``[(n, np)]``.
        dlaw: of the elastic laws, per group ``[(n, nd, nd)]``.
        dsigma0: of the pre-stresses ``(ne,)``.
        df: of the loads, the model's constant ones and the applied ``(nx,)`` (on a
            spatial rotational node, the global moment in the entries of ``lam1..lam3``).
        dweight: of the element masses' weight at the state ``(nx,)`` (generalized
            forces).
        dtarget: of the constrained deformations' targets ``(n_constrained,)``.
        dmass: ``theta -> M`` terms are taken by :meth:`Equilibrium.mass_change` from the
            models either side, not here.
    """

    x_held: np.ndarray
    dp: list[np.ndarray]
    dlaw: list[np.ndarray]
    dsigma0: np.ndarray
    df: np.ndarray
    dweight: np.ndarray
    dtarget: np.ndarray


class Equilibrium:
    """A converged static state (one row of a :class:`~flexmbd.StaticResult`) on the
    engine's banded saddle-point system, factorised once for the sensitivities.

    Args:
        model: the mechanism.
        x: the converged coordinates ``(nx,)``.
        q: its ``q`` ``(nq,)`` (the inputs' targets).
        sigma: its stresses ``(ne,)``: elastic, and the constraint stresses ``mu``.
        loads: the applied loads on top of the model's ``(nx,)``.
    """

    def __init__(self, model: Model, x: np.ndarray, q: np.ndarray, sigma: np.ndarray,
                 loads: np.ndarray):
        self.model = model
        # a workspace of its own: the linearized analyses of the same model re-factorise
        # the default workspace's static tangent
        self.engine = Workspace(model)
        self.spec = self.engine.compiled
        self.groups = groups_of(self.spec)
        self.banded = BandedStatics(model, self.engine)
        self.x, self.q = np.asarray(x, float), np.asarray(q, float)
        self.sigma, self.loads = np.asarray(sigma, float), np.asarray(loads, float)
        self.mu = self.sigma[self.banded.constrained]
        self.free, self.constrained = self.banded.free, self.banded.constrained
        self.elastic_def = self.spec.classification.elastic_def.astype(bool)
        self.ne = model.n_deformations
        try:
            self.core_residual = self.banded.factor(self.x, self.q, self.mu, self.loads)
        except np.linalg.LinAlgError:
            raise SingularConfigurationError(
                "the static tangent [[K, D_c^T], [D_c, 0]] at the design's equilibrium "
                "does not factorise (a mechanism, a buckled state, or a contrast of "
                "stiffness beyond its pivots' test): the design has no sensitivities "
                "there") from None
        self.engine.static_owner = self

    # --- the residual, as the engine's ----------------------------------------------------
    def applied(self, x: np.ndarray) -> np.ndarray:
        """The loads ``f`` ``(nx,)`` of the static residual at ``x``: the model's constant
        loads and the applied ones (on a spatial rotational node a global moment, whose
        generalized force ``2 E(lam)^T M`` turns with it), and the weight of the element
        masses (generalized forces as they are)."""
        constant = self.engine.constant_loads
        return self.load_change(x, constant + self.loads) + weights(self.engine, x)

    def residual(self, x: np.ndarray, mu: np.ndarray) -> np.ndarray:
        """``R(x, mu)`` ``(nfree + nc,)`` from the element definitions (module docstring):
        the engine's own residual, which the tests compare it with."""
        sigma = self._stresses(x, mu)
        force, e, _ = internal_force(self.groups, x, sigma, self.ne)
        r_free = (force - self.applied(x))[self.free]
        return np.concatenate([r_free, e[self.constrained] - self.targets()])

    def _stresses(self, x: np.ndarray, mu: np.ndarray) -> np.ndarray:
        """Elastic stresses at ``x`` and the constraint stresses ``mu`` ``(ne,)``."""
        _, e, _ = internal_force(self.groups, x, np.zeros(self.ne), self.ne)
        sigma = np.array(self.spec.elements.sigma0, dtype=float)
        for group in self.groups:
            law = np.einsum("kij,kj->ki", group.S, e[group.defs])
            rows = group.elastic[:, None] & self.elastic_def[group.defs]
            sigma[group.defs] = np.where(rows, sigma[group.defs] + law, 0.0)
        sigma[self.constrained] = mu
        return sigma

    def targets(self) -> np.ndarray:
        """The constrained deformations' targets ``(nc,)``: 0 for the rigid ones, the
        input's value for the prescribed ones."""
        cls = self.spec.classification
        rows = cls.row_of_def[self.constrained]
        nrigid, nxm = self.spec.sizes.nrigid, self.spec.sizes.nxm
        return np.where(rows < nrigid, 0.0, self.q[np.clip(nxm + rows - nrigid, 0,
                                                              len(self.q) - 1)])

    # --- sensitivities --------------------------------------------------------------------
    def residual_change(self, data: DataChange) -> np.ndarray:
        """``dR/dtheta`` at fixed ``(x_free, mu)`` ``(nfree + nc,)`` for the data change."""
        change = Change(u=data.x_held, dp=data.dp, dlaw=data.dlaw, dsigma=data.dsigma0)
        force, de, _ = force_change(self.groups, self.x, self.sigma, change,
                                    self.elastic_def, self.ne)
        df = self.load_change(self.x, data.df) + data.dweight
        return np.concatenate([(force - df)[self.free],
                               de[self.constrained] - data.dtarget])

    def load_change(self, x: np.ndarray, df: np.ndarray) -> np.ndarray:
        """The change of ``f`` of :meth:`applied` at ``x`` for a change ``df`` ``(nx,)`` of
        the loads: a global moment's change as its generalized force."""
        out = np.array(df, dtype=float)
        for at in self.engine.rotation_coordinates:
            out[at] = euler_forces(x[at], df[at[1:]])
        return out

    def gravity_times(self, v: np.ndarray, x: np.ndarray | None = None,
                      engine: Workspace | None = None, transposed: bool = False
                      ) -> np.ndarray:
        """``(dg/dx) v`` ``(nx,)`` (or its transpose's): the load stiffness of the weight
        of element masses that turn with the elements, at ``x`` (default the state's) on
        ``engine`` (default the state's: another design's for the data's change)."""
        engine = self.engine if engine is None else engine
        x = self.x if x is None else x
        el = self.spec.elements
        slopes = np.empty(int(el.b_off[-1]))
        engine.gravity_slopes(x, slopes)
        out = np.zeros(len(v))
        if not np.any(slopes):
            return out
        for group in self.groups:
            nc = group.coords.shape[1]
            blocks = slopes[el.b_off[group.at][:, None] + np.arange(nc * nc)].reshape(-1, nc, nc)
            if transposed:
                blocks = blocks.transpose(0, 2, 1)
            np.add.at(out, group.coords, np.einsum("kab,kb->ka", blocks, v[group.coords]))
        return out

    def tangent_times(self, dz: np.ndarray, transposed: bool = False) -> np.ndarray:
        """``A dz`` (``A^T dz``) ``(nfree + nc, k)`` for the columns of ``dz`` ``(nfree +
        nc, k)``, element by element from the definitions: accurate to rounding of each
        element's terms, where a solve on the factorisation is accurate to rounding of
        the whole matrix (whose axial stiffness dwarfs the bending of thin leaves)."""
        nf, k = len(self.free), dz.shape[1]
        dx = np.zeros((len(self.x), k))
        dx[self.free] = dz[:nf]
        dsigma = np.zeros((self.ne, k))
        dsigma[self.constrained] = dz[nf:]
        change = Change(u=dx, dp=[np.zeros((*g.param.shape, k)) for g in self.groups],
                        dlaw=[np.zeros((*g.S.shape, k)) for g in self.groups], dsigma=dsigma)
        force, de, _ = force_change(self.groups, self.x, self.sigma, change,
                                    self.elastic_def, self.ne)
        for at, block in turning_moments(self.engine, self.loads):   # df/dx of moments
            force[at] -= (block.T if transposed else block) @ dx[at]
        for j in range(k):
            force[:, j] -= self.gravity_times(dx[:, j], transposed=transposed)
        return np.vstack([force[self.free], de[self.constrained]])

    def solve(self, rhs: np.ndarray, transposed: bool = False, refine: bool = False
              ) -> np.ndarray:
        """``A^-1 rhs`` (``A^-T rhs``) ``(n, k)`` on the factorised tangent; with ``refine``,
        improved (:data:`REFINEMENTS` steps at most) with the exact products of
        :meth:`tangent_times`. The state's change needs it: its right-hand side holds the
        axial stiffness's large terms, which the factorisation's rounding, amplified by
        the contrast of axial and bending stiffness of thin leaves, would leave at 1e-5
        of a soft direction's change."""
        if self.engine.static_owner is not self:
            self.banded.factor(self.x, self.q, self.mu, self.loads)
            self.engine.static_owner = self
        rhs = np.asarray(rhs, dtype=float).reshape(self.banded.size, -1)
        z = self.banded.solve(rhs, transposed)
        for _ in range(REFINEMENTS if refine else 0):
            residual = rhs - self.tangent_times(z, transposed)
            step = self.banded.solve(residual, transposed)
            z += step
            if np.abs(step).max(initial=0.0) <= 1e-13 * np.abs(z).max(initial=0.0):
                break
        return z

    def full(self, dz: np.ndarray, held: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """A solution ``dz`` ``(nfree + nc,)`` as a change of all coordinates ``(nx,)``
        (``held`` on the fixed and input ones) and of the constraint stresses ``(nc,)``."""
        dx = np.array(held, dtype=float)
        dx[self.free] = dz[:len(self.free)]
        return dx, dz[len(self.free):]


def weights(engine: Workspace, x: np.ndarray) -> np.ndarray:
    """The weight of the element masses at ``x`` ``(nx,)``: generalized forces on the
    elements' coordinates (the core's gravity loads less the constant loads, which hold
    the point masses' weight)."""
    return engine.mass(x)[2] - engine.constant_loads


def held_coordinates(model: Model) -> np.ndarray:
    """The coordinates a static state does not solve for ``(k,)``: fixed ones and
    prescribed inputs."""
    classes = np.asarray(model.coordinate_class)
    return np.flatnonzero((classes != CoordinateClass.DEPENDENT)
                          & (classes != CoordinateClass.DYNAMIC))
