"""Model-wide arrays from the element kernels, for the linearized analyses (THEORY 9).

The compiled core evaluates one generated kernel for every element in one call
(``Core.element_values``); :class:`Assembly` scatters the element blocks into the
model's dense arrays with index maps made once per engine:

* ``e`` ``(ne,)`` and ``D_x`` ``(ne, nx)``;
* the stress-weighted Hessian ``sum_i sigma_i D_xx,i`` ``(nx, nx)`` of ``G0``;
* products with the block-diagonal elastic law ``S`` or ``C`` ``(ne, ne)``.

The per-element functions of :mod:`flexmbd.engine` (``deformations_and_jacobian``,
``dense_hessian``) give the same values one element at a time, for any model without an
engine; a test holds the two together.
"""

from __future__ import annotations

import numpy as np


class Assembly:
    """Index maps of one compiled model (``Engine.compiled``) and its core."""

    def __init__(self, core, compiled: dict, n_coordinates: int, n_deformations: int):
        self.core, self.nx, self.ne = core, n_coordinates, n_deformations
        c_off, c_idx = compiled["c_off"], compiled["c_idx"]
        d_off, d_idx = compiled["d_off"], compiled["d_idx"]
        jac = {"e_at": [], "e_def": [], "value": [], "def": [], "coord": []}
        hess = {"def": [], "row": [], "col": []}
        jac_size, hess_size = 0, 0
        by_type: dict[int, list[int]] = {}
        for k in range(int(compiled["nel"])):
            coords = c_idx[c_off[k]:c_off[k + 1]]
            defs = d_idx[d_off[k]:d_off[k + 1]]
            nd, nc = len(defs), len(coords)
            # the kernel "deform_jac" gives e (nd) then D_x row-major (nd x nc)
            jac["e_at"].append(jac_size + np.arange(nd))
            jac["e_def"].append(defs)
            jac["value"].append(jac_size + nd + np.arange(nd * nc))
            jac["def"].append(np.repeat(defs, nc))
            jac["coord"].append(np.tile(coords, nd))
            jac_size += nd * (1 + nc)
            # the kernel "hessian" gives D_xx row-major (nd x nc x nc)
            hess["def"].append(np.repeat(defs, nc * nc))
            hess["row"].append(np.tile(np.repeat(coords, nc), nd))
            hess["col"].append(np.tile(coords, nd * nc))
            hess_size += nd * nc * nc
            by_type.setdefault(int(compiled["etype"][k]), []).append(k)

        def joined(parts):
            return np.concatenate(parts) if parts else np.zeros(0, dtype=np.intp)

        self.jac = {name: joined(parts) for name, parts in jac.items()}
        self.hess = {name: joined(parts) for name, parts in hess.items()}
        self.hess["flat"] = self.hess["row"] * n_coordinates + self.hess["col"]
        self.jac_out, self.hess_out = np.empty(jac_size), np.empty(hess_size)
        # the elastic law's blocks (n, nd, nd) per element type, with their deformations
        self.law_groups = []
        for ks in map(np.asarray, by_type.values()):
            nd = int(d_off[ks[0] + 1] - d_off[ks[0]])
            at = compiled["law_off"][ks][:, None] + np.arange(nd * nd)
            self.law_groups.append((d_idx[d_off[ks][:, None] + np.arange(nd)],
                                    {name: compiled[name][at].reshape(len(ks), nd, nd)
                                     for name in ("S", "C")}))

    def deformations_and_jacobian(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``e = D(x)`` ``(ne,)`` and ``D_x`` ``(ne, nx)`` at ``x`` ``(nx,)``."""
        self.core.element_values("deform_jac", np.ascontiguousarray(x, dtype=float),
                                 self.jac_out)
        e, D_x = np.zeros(self.ne), np.zeros((self.ne, self.nx))
        e[self.jac["e_def"]] = self.jac_out[self.jac["e_at"]]
        D_x[self.jac["def"], self.jac["coord"]] = self.jac_out[self.jac["value"]]
        return e, D_x

    def stress_hessian(self, x: np.ndarray, sigma: np.ndarray) -> np.ndarray:
        """``sum_i sigma_i D_xx,i`` ``(nx, nx)`` at ``x`` for stresses ``sigma`` ``(ne,)``."""
        self.core.element_values("hessian", np.ascontiguousarray(x, dtype=float),
                                 self.hess_out)
        weighted = sigma[self.hess["def"]] * self.hess_out
        return np.bincount(self.hess["flat"], weighted, minlength=self.nx * self.nx
                           ).reshape(self.nx, self.nx)

    def law_times(self, name: str, A: np.ndarray) -> np.ndarray:
        """``S @ A`` (``name="S"``) or ``C @ A`` for ``A`` ``(ne, k)``: the elastic law's
        stiffness or damping over all deformations, nonzero on those that carry elastic
        stress, applied block by block."""
        out = np.zeros_like(A, dtype=float)
        for defs, blocks in self.law_groups:
            out[defs] = np.einsum("nij,njk->nik", blocks[name], A[defs])
        return out
