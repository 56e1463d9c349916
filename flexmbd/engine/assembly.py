"""Model-wide arrays and products from the element kernels, for the linearized analyses
(THEORY 9).

The compiled core evaluates one generated kernel for every element in one call
(``Core.element_values``). :class:`Assembly` takes the element blocks by element type
(one block size each) with index maps made once per engine, and gives

* ``e`` ``(ne,)`` and ``D_x`` ``(ne, nx)``, and the product ``D_x A``;
* the product ``(sum_i sigma_i D_xx,i) A`` with the stress-weighted Hessian of ``G0``;
* products with the block-diagonal elastic law ``S`` or ``C`` ``(ne, ne)``.

The products go block by block, so they cost ``O(n_elements)`` per column of ``A``
instead of a dense matrix product. The per-state functions of
:mod:`flexmbd.analysis.kinematics` take their dense ``D_x``, ``D_xx`` and quadratic
velocity terms from here too; the tests hold them against the kernels evaluated one
element at a time.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .spec import Elements


@dataclass(frozen=True)
class _Group:
    """The ``n`` elements of one type: their coordinates ``(n, nc)`` and deformations
    ``(n, nd)``, where their values start in the kernels' outputs ``(n,)``, and their
    elastic law's blocks ``{"S", "C"}`` ``(n, nd, nd)``."""

    coords: np.ndarray
    defs: np.ndarray
    jac_at: np.ndarray
    hess_at: np.ndarray
    slope_at: np.ndarray
    law: dict[str, np.ndarray]

    layers: list[np.ndarray]

    def add_rows(self, out: np.ndarray, rows: np.ndarray) -> None:
        """``out[coords] += rows`` ``(n, nc, k)``, adding where elements share a coordinate:
        layer by layer, each holding a coordinate at most once (``np.add.at`` is slower)."""
        coords, flat = self.coords.ravel(), rows.reshape(self.coords.size, -1)
        for layer in self.layers:
            out[coords[layer]] += flat[layer]

    def jacobian(self, out: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``e`` ``(n, nd)`` and ``D_x`` ``(n, nd, nc)`` from the output of "deform_jac"
        (per element ``e`` then ``D_x`` row-major)."""
        n, nd = self.defs.shape
        nc = self.coords.shape[1]
        values = out[self.jac_at[:, None] + np.arange(nd * (1 + nc))]
        return values[:, :nd], values[:, nd:].reshape(n, nd, nc)

    def hessians(self, out: np.ndarray) -> np.ndarray:
        """``D_xx`` ``(n, nd, nc, nc)`` from the output of "hessian"."""
        n, nd = self.defs.shape
        nc = self.coords.shape[1]
        return out[self.hess_at[:, None] + np.arange(nd * nc * nc)].reshape(n, nd, nc, nc)


class Assembly:
    """Index maps of one compiled model's elements (``Workspace.compiled.elements``), and
    its workspace's evaluations of every element at once: ``element_values(name, x,
    out)`` and ``gravity_slopes(x, out)`` (:class:`~flexmbd.engine.workspace.Workspace`'s
    methods)."""

    def __init__(self, element_values: Callable[[str, np.ndarray, np.ndarray], None],
                 gravity_slopes: Callable[[np.ndarray, np.ndarray], None],
                 elements: Elements, n_coordinates: int, n_deformations: int):
        self.element_values, self.gravity_slopes = element_values, gravity_slopes
        self.nx, self.ne = n_coordinates, n_deformations
        c_off, c_idx = elements.c_off, elements.c_idx
        d_off, d_idx = elements.d_off, elements.d_idx
        nc, nd = np.diff(c_off), np.diff(d_off)
        # where each element's values start in the kernels' outputs (element after element)
        jac_at = np.concatenate([[0], np.cumsum(nd * (1 + nc))])
        hess_at = np.concatenate([[0], np.cumsum(nd * nc * nc)])
        slope_at = np.concatenate([[0], np.cumsum(nc * nc)])
        self.jac_out, self.hess_out = np.empty(jac_at[-1]), np.empty(hess_at[-1])
        self.slope_out = np.empty(slope_at[-1])
        etype = elements.etype
        self.groups = []
        for kind in np.unique(etype):
            ks = np.flatnonzero(etype == kind)
            n_c, n_d = int(nc[ks[0]]), int(nd[ks[0]])
            at = elements.law_off[ks][:, None] + np.arange(n_d * n_d)
            coords = c_idx[c_off[ks][:, None] + np.arange(n_c)]
            self.groups.append(_Group(
                coords=coords, defs=d_idx[d_off[ks][:, None] + np.arange(n_d)],
                jac_at=jac_at[ks], hess_at=hess_at[ks], slope_at=slope_at[ks],
                law={"S": elements.S[at].reshape(len(ks), n_d, n_d),
                     "C": elements.C[at].reshape(len(ks), n_d, n_d)},
                layers=_layers(coords.ravel())))

    def _evaluate(self, name: str, x: np.ndarray) -> np.ndarray:
        out = self.jac_out if name == "deform_jac" else self.hess_out
        self.element_values(name, x, out)
        return out

    def deformations(self, x: np.ndarray) -> np.ndarray:
        """``e = D(x)`` ``(ne,)`` at ``x`` ``(nx,)``."""
        out = self._evaluate("deform_jac", x)
        e = np.zeros(self.ne)
        for group in self.groups:
            e[group.defs] = group.jacobian(out)[0]
        return e

    def deformations_and_jacobian(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``e = D(x)`` ``(ne,)`` and ``D_x`` ``(ne, nx)`` at ``x`` ``(nx,)``."""
        out = self._evaluate("deform_jac", x)
        e, D_x = np.zeros(self.ne), np.zeros((self.ne, self.nx))
        for group in self.groups:
            values, jacobians = group.jacobian(out)
            e[group.defs] = values
            D_x[group.defs[:, :, None], group.coords[:, None, :]] = jacobians
        return e, D_x

    def hessian(self, x: np.ndarray) -> np.ndarray:
        """``D_xx`` ``(ne, nx, nx)`` at ``x`` ``(nx,)`` (dense: for inspection and small
        models)."""
        out = self._evaluate("hessian", x)
        H = np.zeros((self.ne, self.nx, self.nx))
        for group in self.groups:
            coords = group.coords
            H[group.defs[:, :, None, None], coords[:, None, :, None],
              coords[:, None, None, :]] = group.hessians(out)
        return H

    def quadratic_velocity(self, x: np.ndarray, xd: np.ndarray) -> np.ndarray:
        """``(D_xx xdot) xdot`` ``(ne,)`` at ``x`` with rates ``xd`` ``(nx,)`` (THEORY 2),
        from the elements' Hessians."""
        out = self._evaluate("hessian", x)
        terms = np.zeros(self.ne)
        for group in self.groups:
            rates = xd[group.coords]
            terms[group.defs] = np.einsum("ndab,na,nb->nd", group.hessians(out), rates, rates)
        return terms

    def jacobian_times(self, x: np.ndarray, A: np.ndarray) -> np.ndarray:
        """``D_x A`` ``(ne, k)`` at ``x`` for ``A`` ``(nx, k)``."""
        out = self._evaluate("deform_jac", x)
        product = np.zeros((self.ne, A.shape[1]))
        for group in self.groups:
            product[group.defs] = group.jacobian(out)[1] @ A[group.coords]
        return product

    def stress_hessian_times(self, x: np.ndarray, sigma: np.ndarray, A: np.ndarray
                             ) -> np.ndarray:
        """``(sum_i sigma_i D_xx,i) A`` ``(nx, k)`` at ``x`` for stresses ``sigma``
        ``(ne,)`` and ``A`` ``(nx, k)``."""
        out = self._evaluate("hessian", x)
        product = np.zeros((self.nx, A.shape[1]))
        for group in self.groups:
            weights = sigma[group.defs]
            if np.any(weights):
                hessian = np.einsum("ni,niab->nab", weights, group.hessians(out))
                group.add_rows(product, hessian @ A[group.coords])
        return product

    def gravity_slopes_times(self, x: np.ndarray, A: np.ndarray) -> np.ndarray | None:
        """``(df/dx) A`` ``(nx, k)`` for ``A`` ``(nx, k)``, ``f`` the gravity loads of the
        elements whose gravity turns with them (a consistent mass that varies with the
        configuration: a beam's weight has moments on its rotations), at ``x``; ``None``
        when no element's gravity turns (no gravity, or constant masses)."""
        self.gravity_slopes(x, self.slope_out)
        if not np.any(self.slope_out):
            return None
        product = np.zeros((self.nx, A.shape[1]))
        for group in self.groups:
            n, nc = group.coords.shape
            blocks = self.slope_out[group.slope_at[:, None] + np.arange(nc * nc)]
            group.add_rows(product, blocks.reshape(n, nc, nc) @ A[group.coords])
        return product

    def law_times(self, name: str, A: np.ndarray) -> np.ndarray:
        """``S @ A`` (``name="S"``) or ``C @ A`` for ``A`` ``(ne, k)``: the elastic law's
        stiffness or damping over all deformations, nonzero on those that carry elastic
        stress, applied block by block."""
        product = np.zeros_like(A, dtype=float)
        for group in self.groups:
            product[group.defs] = group.law[name] @ A[group.defs]
        return product


def _layers(indices: np.ndarray) -> list[np.ndarray]:
    """Positions in ``indices`` split so that no index repeats within a part: the ``r``-th
    occurrence of every index goes to part ``r``."""
    order = np.argsort(indices, kind="stable")
    ranked = indices[order]
    first = np.flatnonzero(np.diff(ranked, prepend=-1))          # where each run starts
    occurrence = np.empty(len(indices), dtype=np.intp)
    occurrence[order] = np.arange(len(indices)) - np.repeat(first, np.diff(
        np.append(first, len(indices))))
    return [np.flatnonzero(occurrence == r) for r in range(occurrence.max(initial=-1) + 1)]
