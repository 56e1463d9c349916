"""The elements' terms of the static equations and their derivatives along a design
change, exact, from the one definition of each element type.

The engine's static equations (:mod:`flexmbd.analysis.banded`) sum element terms: the
internal loads ``D_x^T sigma`` and, in the tangent, ``D_x^T S D_x + sum_i sigma_i
D_xx,i``. A design change moves the coordinates (``u``), the reference parameters
(``dp``: lengths and frames), the elastic law (``dS``) and the stresses (``dsigma``).
Their derivatives need the deformations' mixed second and third derivatives, which the
compiled kernels do not hold; here the element definitions
(:meth:`~flexmbd.elements.base.ElementType.deformations`) run on hyper-dual numbers
(:mod:`flexmbd.design.hyperdual`), all elements of a type at once, so every derivative
is exact to rounding and comes from the same lines as the kernels.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..elements import ELEMENT_TYPES
from ..elements.base import ElementType
from ..engine.spec import CoreSpec
from .hyperdual import MATH, HyperDual, seed

__all__ = ["Change", "ElementGroup", "groups_of"]

_TYPES = list(ELEMENT_TYPES.values())


@dataclass(frozen=True)
class ElementGroup:
    """The elements of one type, in the core's arrays.

    Attributes:
        etype: the element type.
        coords: each element's coordinates ``(n, nc)`` (indices into ``x``).
        defs: each element's deformations ``(n, nd)`` (indices into ``e``).
        param: reference parameters ``(n, np)``.
        S: elastic laws ``(n, nd, nd)``.
        elastic: whether each element carries an elastic law ``(n,)``.
        at: each element's position in the core's order ``(n,)``.
    """

    etype: type[ElementType]
    coords: np.ndarray
    defs: np.ndarray
    param: np.ndarray
    S: np.ndarray
    elastic: np.ndarray
    at: np.ndarray


def groups_of(spec: CoreSpec) -> list[ElementGroup]:
    """The model's elements grouped by type (``spec``: the compiled model)."""
    el = spec.elements
    groups = []
    for number in np.unique(el.etype):
        ks = np.flatnonzero(el.etype == number)
        etype = _TYPES[int(number)]
        nc, nd, npar = etype.n_coordinates(), etype.n_deformations(), etype.reference
        groups.append(ElementGroup(
            etype=etype,
            coords=el.c_idx[el.c_off[ks][:, None] + np.arange(nc)],
            defs=el.d_idx[el.d_off[ks][:, None] + np.arange(nd)],
            param=el.param[el.p_off[ks][:, None] + np.arange(npar)].reshape(len(ks), npar),
            S=el.S[el.law_off[ks][:, None] + np.arange(nd * nd)].reshape(len(ks), nd, nd),
            elastic=el.elastic[ks].astype(bool), at=ks))
    return groups


@dataclass(frozen=True)
class Change:
    """A change of the design and state along one direction ``theta``, per element data
    (zeros where nothing moves).

    Attributes:
        u: coordinate change ``(nx,)`` [m, rad, ...].
        dp: reference-parameter change per group ``[(n, np)]``.
        dlaw: elastic-law change per group ``[(n, nd, nd)]``.
        dsigma: stress change ``(ne,)``: the constraint stresses' (solved for) and the
            pre-stress change; the elastic stresses' own change ``S de + dS e`` is added
            here.
    """

    u: np.ndarray
    dp: list[np.ndarray]
    dlaw: list[np.ndarray]
    dsigma: np.ndarray


def deformations(group: ElementGroup, x: np.ndarray, coordinate_seeds: list,
                 parameter_seeds: list) -> np.ndarray:
    """The group's deformations on hyper-dual numbers: ``parts`` ``(2^n, nd, n_el, *K)``.

    Args:
        x: coordinates ``(nx,)``.
        coordinate_seeds: per infinitesimal, its direction on the element coordinates
            ``(n_el, *K, nc)`` (the axes ``K`` hold directions evaluated at once, sizes 1
            broadcast) or ``None``.
        parameter_seeds: per infinitesimal, its direction on the reference parameters
            ``(n_el, np)`` (the same for every direction), ``(n_el, *K, np)``, or ``None``.
    """
    xe = x[group.coords]
    n_el = len(xe)
    axes = max([d.ndim - 1 for d in (*coordinate_seeds, *parameter_seeds)
                if d is not None] + [1])

    def along(d: np.ndarray | None, j: int) -> np.ndarray | None:
        """Column ``j`` of a seed, shaped ``(n_el, *K)``."""
        if d is None:
            return None
        column = d[..., j]
        return column.reshape(n_el, *(1,) * (axes - 1)) if d.ndim == 2 else column

    rest = (1,) * (axes - 1)
    c = [seed(xe[:, j].reshape(n_el, *rest), [along(d, j) for d in coordinate_seeds])
         for j in range(xe.shape[1])]
    p = [seed(group.param[:, j].reshape(n_el, *rest), [along(d, j) for d in parameter_seeds])
         for j in range(group.param.shape[1])]
    shape = np.broadcast_shapes(*(part.parts.shape[1:] for part in c))
    out = np.zeros((1 << len(coordinate_seeds), group.defs.shape[1], *shape))
    for i, value in enumerate(group.etype.deformations(c, p, MATH)):
        if isinstance(value, HyperDual):
            out[:, i] = value.parts
        else:   # a deformation that does not depend on the coordinates
            out[0, i] = value
    return out


def _elastic_rows(group: ElementGroup, elastic_def: np.ndarray) -> np.ndarray:
    """Which deformations of the group's elements carry an elastic stress ``(n, nd)``."""
    return group.elastic[:, None] & elastic_def[group.defs]


def force_change(groups: list[ElementGroup], x: np.ndarray, sigma: np.ndarray,
                 change: Change, elastic_def: np.ndarray, ne: int
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The change of the internal loads ``D_x^T sigma`` ``(nx,)`` along ``change`` at ``x``
    with the stresses ``sigma`` ``(ne,)``, and the changes of the deformations and of the
    stresses ``(ne,)`` each; for :func:`stacked` changes each with a last axis over them
    (``(nx, P)``, ``(ne, P)``), in one evaluation."""
    many = change.u.ndim == 2
    changes = change if many else stacked([change])
    P = changes.u.shape[1]
    force, de_all, dsig_all = np.zeros((len(x), P)), np.zeros((ne, P)), np.zeros((ne, P))
    for group, dp, dS in zip(groups, changes.dp, changes.dlaw, strict=True):
        nc, n = group.coords.shape[1], len(group.at)
        unit = np.broadcast_to(np.eye(nc)[None, :, None, :], (n, nc, 1, nc))
        along = changes.u[group.coords].transpose(0, 2, 1)[:, None, :, :]   # (n, 1, P, nc)
        parts = deformations(group, x, [unit, along],
                             [None, dp.transpose(0, 2, 1)[:, None, :, :]])
        # parts (4, nd, n, nc, P): 0 e, 1 D_x (per unit direction), 2 de, 3 dD_x
        e, de = parts[0][:, :, 0, 0], parts[2][:, :, 0, :]
        rows = _elastic_rows(group, elastic_def).T[:, :, None]
        own = (np.einsum("kij,jkP->ikP", group.S, de) + np.einsum("kijP,jk->ikP", dS, e))
        dsig = np.where(rows, own, 0.0) + changes.dsigma[group.defs].transpose(1, 0, 2)
        sig = sigma[group.defs].T
        local = (np.einsum("ikcP,ik->kcP", parts[3], sig)
                 + np.einsum("ikc,ikP->kcP", parts[1][:, :, :, 0], dsig))
        np.add.at(force, group.coords, local)
        de_all[group.defs] = de.transpose(1, 0, 2)
        dsig_all[group.defs] = dsig.transpose(1, 0, 2)
    if many:
        return force, de_all, dsig_all
    return force[:, 0], de_all[:, 0], dsig_all[:, 0]


def internal_force(groups: list[ElementGroup], x: np.ndarray, sigma: np.ndarray, ne: int
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``D_x^T sigma`` ``(nx,)``, the deformations ``e`` ``(ne,)`` and ``D_x`` ``(ne, nx)`` at
    ``x`` (element by element, from the definitions)."""
    force, e_all = np.zeros(len(x)), np.zeros(ne)
    D = np.zeros((ne, len(x)))
    for group in groups:
        nc = group.coords.shape[1]
        unit = np.broadcast_to(np.eye(nc), (len(group.at), nc, nc))
        parts = deformations(group, x, [unit], [None])
        sig = sigma[group.defs].T
        np.add.at(force, group.coords, np.einsum("ikc,ik->kc", parts[1], sig))
        e_all[group.defs] = parts[0][:, :, 0].T
        rows = np.broadcast_to(group.defs[:, :, None], (*group.defs.shape, nc))
        cols = np.broadcast_to(group.coords[:, None, :], rows.shape)
        np.add.at(D, (rows, cols), parts[1].transpose(1, 0, 2))
    return force, e_all, D


def stacked(changes: list[Change]) -> Change:
    """Several changes as one, each array with a last axis over them (``u`` ``(nx, P)``,
    ``dp`` ``[(n, np, P)]``, ``dlaw`` ``[(n, nd, nd, P)]``, ``dsigma`` ``(ne, P)``): the
    tangent's and the constraints' changes of every parameter in one evaluation."""
    return Change(u=np.stack([c.u for c in changes], axis=-1),
                  dp=[np.stack(parts, axis=-1)
                      for parts in zip(*(c.dp for c in changes), strict=True)],
                  dlaw=[np.stack(parts, axis=-1)
                        for parts in zip(*(c.dlaw for c in changes), strict=True)],
                  dsigma=np.stack([c.dsigma for c in changes], axis=-1))


def tangent_change(groups: list[ElementGroup], x: np.ndarray, sigma: np.ndarray,
                   changes: Change, elastic_def: np.ndarray, left: np.ndarray,
                   right: np.ndarray, geometric_weight: np.ndarray) -> np.ndarray:
    """``l_q^T dK r_q`` ``(Q, P)`` for the pairs of columns of ``left`` and ``right``
    ``(nx, Q)`` along each of the :func:`stacked` ``changes``: the change of the elements'
    tangent ``K = D_x^T S D_x + g_q sum_i sigma_i D_xx,i`` (the elastic law wherever an
    element has one, the stresses ``sigma`` ``(ne,)`` of the state, elastic and
    constraint, ``g`` the ``geometric_weight`` ``(Q,)``: 1 for the tangent, a load factor
    for buckling), by the third derivatives of the deformations; all pairs and parameters
    in one evaluation per element type."""
    out = np.zeros((left.shape[1], changes.u.shape[1]))
    for group, dp, dS in zip(groups, changes.dp, changes.dlaw, strict=True):
        along = changes.u[group.coords].transpose(0, 2, 1)[:, None]     # (n, 1, P, nc)
        parts = deformations(group, x, [left[group.coords].transpose(0, 2, 1)[:, :, None],
                                        right[group.coords].transpose(0, 2, 1)[:, :, None],
                                        along],
                             [None, None, dp.transpose(0, 2, 1)[:, None]])
        # parts (8, nd, n, Q, P): 1 dl e, 2 dr e, 3 dl dr e, 4 de, 5 dl de, 6 dr de, 7 dl dr de
        e, de = parts[0], parts[4]
        rows = _elastic_rows(group, elastic_def).T[:, :, None, None]
        own = (np.einsum("kij,jkQP->ikQP", group.S, de)
               + np.einsum("kijP,jkQP->ikQP", dS, e))
        dsig = (np.where(rows, own, 0.0)
                + changes.dsigma[group.defs].transpose(1, 0, 2)[:, :, None])
        sig = sigma[group.defs].T
        S = np.where(group.elastic[:, None, None], group.S, 0.0)
        dSe = np.where(group.elastic[:, None, None, None], dS, 0.0)
        elastic = (np.einsum("ikQP,kij,jkQP->QP", parts[5], S, parts[2])
                   + np.einsum("ikQP,kij,jkQP->QP", parts[1], S, parts[6])
                   + np.einsum("ikQP,kijP,jkQP->QP", parts[1], dSe, parts[2]))
        geometric = (np.einsum("ikQP,ikQP->QP", dsig, parts[3])
                     + np.einsum("ik,ikQP->QP", sig, parts[7]))
        out += elastic + np.asarray(geometric_weight)[:, None] * geometric
    return out


def constraint_change(groups: list[ElementGroup], x: np.ndarray, changes: Change,
                      directions: np.ndarray, ne: int) -> np.ndarray:
    """``d(D_x v_q)`` ``(ne, Q, P)`` along each of the :func:`stacked` ``changes`` for the
    columns ``v_q`` of ``directions`` ``(nx, Q)``: how their deformation rates change."""
    out = np.zeros((ne, directions.shape[1], changes.u.shape[1]))
    for group, dp in zip(groups, changes.dp, strict=True):
        parts = deformations(group, x, [directions[group.coords].transpose(0, 2, 1)[:, :, None],
                                        changes.u[group.coords].transpose(0, 2, 1)[:, None]],
                             [None, dp.transpose(0, 2, 1)[:, None]])
        out[group.defs] = parts[3].transpose(1, 0, 2, 3)
    return out
