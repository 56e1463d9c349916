"""Index maps of a model for vectorised, batched assembly (computed once per model).

Every quantity of a run is assembled from the element kernels of each element
type (:mod:`flexmbd.elements`), evaluated for all elements of that type and a
whole batch of states at once: arrays have a leading batch axis ``nb`` (one
state while time stepping, all output times when post-processing). The maps
here scatter element values straight into the arrays the algorithms need
(``D_c``, the saddle-point matrix, nodal force vectors) without forming the full
``D_x`` or mass matrix, so the cost of a right-hand side grows linearly with
the number of elements.

Index sets (THEORY sections 1-3): coordinates are fixed ``x(o)``, inputs,
dynamic or dependent ``x(c)``; deformations rigid ``e(o)``, inputs, dynamic or
released ``e(c)``. The rows of ``D_c`` are ``e(o)`` then ``e(m)`` (the
constrained deformations), its columns ``x(c)``. The *free* coordinates are
``x(c)`` and the dynamic coordinates; the *multipliers* belong to the rigid and
input deformations, whose stresses are reactions rather than elastic.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import NamedTuple

import numpy as np

from .elements import ElementType, Reference
from .factor import SPARSE_SIZE, SparsePattern
from .model import CoordinateClass, DeformationClass, Model


@dataclass(frozen=True, eq=False)
class GroupData:
    """One element type of the model with its properties as arrays.

    Attributes:
        type: the element type.
        coordinates: global coordinate indices ``(n, nc)``.
        deformations: global deformation indices ``(n, nd)``.
        reference: reference lengths and angles.
        mass, lumped: element masses [kg] and mass formulation ``(n,)``.
        stiffness, damping: the elastic law ``(n, nd, nd)``, zero on rows and
            columns of deformations without elastic stress (rigid and input ones).
        prestress: ``sigma0`` ``(n, nd)``, likewise zero there.
        scale: the model's coordinate scale at each element coordinate ``(n, nc)``.
        has_mass, is_elastic, prestressed, damped: whether any element of the group
            has mass, an elastic law, pre-stress, damping.
    """

    type: type[ElementType]
    coordinates: np.ndarray
    deformations: np.ndarray
    reference: Reference
    mass: np.ndarray
    lumped: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray
    prestress: np.ndarray
    scale: np.ndarray

    def __post_init__(self):
        # flags asked on every evaluation: computed once (the dataclass is frozen)
        flags = {"has_mass": bool(np.any(self.mass)), "damped": bool(np.any(self.damping)),
                 "prestressed": bool(np.any(self.prestress))}
        flags["is_elastic"] = bool(np.any(self.stiffness)) or flags["damped"] or \
            flags["prestressed"]
        for name, value in flags.items():
            object.__setattr__(self, name, value)


class Scatter(NamedTuple):
    """Entries ``weights * values[:, index]`` written to the flat ``positions`` (distinct)
    of a target of ``size`` entries per batch member."""

    positions: np.ndarray
    index: np.ndarray
    weights: np.ndarray
    size: int

    def apply(self, values: np.ndarray) -> np.ndarray:
        """The targets ``(nb, size)``, zero elsewhere, for ``values`` ``(nb, k)``."""
        out = np.zeros((values.shape[0], self.size))
        out[:, self.positions] = values[:, self.index] * self.weights
        return out


def as_selector(index: np.ndarray) -> slice | np.ndarray:
    """``index`` as a slice when it is a contiguous increasing range, else itself: a slice
    indexes as a view, several times cheaper than an index array on small arrays."""
    index = np.asarray(index, dtype=int)
    if not len(index):
        return slice(0, 0)
    start = int(index[0])
    if np.array_equal(index, np.arange(start, start + len(index))):
        return slice(start, start + len(index))
    return index


class Selectors(NamedTuple):
    """The index sets of :class:`Assembly` the per-step code indexes with, each a slice
    where contiguous (see :func:`as_selector`). Indexing by a slice gives a view: use
    them for reading into new arrays and for assigning, as the index arrays."""

    rows: slice | np.ndarray
    dependent: slice | np.ndarray
    free: slice | np.ndarray
    multipliers: slice | np.ndarray
    q_coordinates: slice | np.ndarray
    q_input: slice | np.ndarray
    q_dynamic: slice | np.ndarray
    dynamic_deformations: slice | np.ndarray
    dynamic_deformation_rows: slice | np.ndarray


def _positions(index: np.ndarray, size: int) -> np.ndarray:
    """Position of each global index within ``index`` (``-1`` where absent), ``(size,)``."""
    where = np.full(size, -1)
    where[index] = np.arange(len(index))
    return where


def _pattern(rows: np.ndarray, cols: np.ndarray, ncols: int):
    """Entries of an element array ``(n, a, b)`` with row map ``rows`` ``(n, a)`` and
    column map ``cols`` ``(n, b)`` (``-1`` = not in the target): the flat indices of
    the entries that land, and their flat positions in a target of ``ncols`` columns."""
    r = np.broadcast_to(rows[:, :, None], (*rows.shape, cols.shape[1]))
    c = np.broadcast_to(cols[:, None, :], r.shape)
    keep = ((r >= 0) & (c >= 0)).ravel()
    return np.flatnonzero(keep), (r.ravel() * ncols + c.ravel())[keep]


class Assembly:
    """Index maps of one model (see the module docstring); ``model.assembly`` caches it."""

    def __init__(self, model: Model):
        self.model = model
        nx, ne = model.n_coordinates, model.n_deformations
        self.nx, self.ne = nx, ne
        cclass, dclass = model.coordinate_class, model.deformation_class
        self.rows = np.asarray(model.constrained)
        self.dependent = np.asarray(model.dependent)
        self.free = np.flatnonzero((cclass == CoordinateClass.DEPENDENT)
                                   | (cclass == CoordinateClass.DYNAMIC))
        self.multipliers = np.flatnonzero((dclass == DeformationClass.RIGID)
                                          | (dclass == DeformationClass.INPUT))
        self.n_free, self.n_saddle = len(self.free), len(self.free) + len(self.multipliers)
        self.n_rigid = len(model.rigid)

        # q = [x(m); e(m)]: its dynamic entries (the integrated state) and inputs
        q_coords, q_defs = model.independent_coordinates, model.independent_deformations
        dynamic = ~np.asarray(model.q_is_input)
        nxm = len(q_coords)
        self.q_dynamic = np.flatnonzero(dynamic)
        self.q_input = np.flatnonzero(~dynamic)
        self.q_coordinates, self.q_deformations = np.asarray(q_coords), np.asarray(q_defs)
        self.dynamic_coordinates = self.q_coordinates[dynamic[:nxm]]
        self.dynamic_deformations = self.q_deformations[dynamic[nxm:]]
        self.input_deformations = self.q_deformations[~dynamic[nxm:]]

        row_at = _positions(self.rows, ne)
        dependent_at = _positions(self.dependent, nx)
        free_at = _positions(self.free, nx)
        saddle_row_at = np.where(_positions(self.multipliers, ne) >= 0,
                                 self.n_free + _positions(self.multipliers, ne), -1)
        dynamic_def_at = _positions(self.dynamic_deformations, ne)
        #: positions of the dynamic deformations among the rows of ``D_c``
        self.dynamic_deformation_rows = row_at[self.dynamic_deformations]
        #: positions of the multipliers (rigid and input deformations) among those rows
        self.multiplier_rows = row_at[self.multipliers]
        #: the index sets as slices where contiguous, for the per-step paths
        self.take = Selectors(*(as_selector(getattr(self, name)) for name in Selectors._fields))
        self._deformations_of_groups = [as_selector(g.deformations.ravel())
                                        for g in model.groups]
        self.groups: list[GroupData] = []
        self._constraint_pattern, self._saddle_mass, self._saddle_jacobian = [], [], []
        self._dynamic_rows = []
        for g, props in zip(model.groups, model.group_properties, strict=True):
            elastic = np.asarray(model.carries_elastic_stress)[g.deformations]
            S, C = g.type.elastic_matrices(g.reference, props)
            mask = elastic[:, :, None] & elastic[:, None, :]
            self.groups.append(GroupData(
                type=g.type, coordinates=g.coordinates, deformations=g.deformations,
                reference=g.reference, mass=props.mass, lumped=props.lumped,
                stiffness=np.where(mask, S, 0.0), damping=np.where(mask, C, 0.0),
                prestress=np.where(elastic, props.prestress, 0.0),
                scale=np.asarray(model.coordinate_scale)[g.coordinates]))
            # D_c: rows e(o), e(m); columns x(c)
            self._constraint_pattern.append(_pattern(
                row_at[g.deformations], dependent_at[g.coordinates], len(self.dependent)))
            # saddle matrix [[A, C^T], [C, 0]] over free coordinates and multipliers
            self._saddle_mass.append(_pattern(
                free_at[g.coordinates], free_at[g.coordinates], self.n_saddle))
            select, position = _pattern(saddle_row_at[g.deformations],
                                        free_at[g.coordinates], self.n_saddle)
            rows, cols = np.divmod(position, self.n_saddle)
            self._saddle_jacobian.append((select, position, cols * self.n_saddle + rows))
            # rows of D_x for the dynamic deformations, over the free coordinates
            self._dynamic_rows.append(_pattern(dynamic_def_at[g.deformations],
                                               free_at[g.coordinates], self.n_free))
        masses = [(node, mass) for node, mass in model.nodal_masses.items()]
        self.nodal_mass_coordinates = np.array(
            [c for node, _ in masses for c in model.nodes[node].coordinates], dtype=int)
        self.nodal_mass_values = np.array(
            [mass for node, mass in masses for _ in model.nodes[node].coordinates], dtype=float)
        self._nodal_mass_saddle = (free_at[self.nodal_mass_coordinates] * (self.n_saddle + 1))
        self._nodal_mass_on_free = self._nodal_mass_saddle >= 0
        self.dynamic_coordinate_at = free_at[self.dynamic_coordinates]
        self.row_scale_columns = np.asarray(model.coordinate_scale)[self.dependent]
        #: row scales of D_c for its conditioning estimate: one over the norm of each
        #: D_x row (angles scaled by the model size) in the reference configuration.
        #: Those norms change little with the motion (sqrt 2 for an elongation, between
        #: sqrt 2 and sqrt 3 for a beam's bending), so they are taken once.
        self.constraint_row_scale = 1.0 / np.maximum(self.row_norms(
            [g.type.jacobian(model.x0[g.coordinates], g.reference)[None]
             for g in self.groups])[0, self.rows], 1e-300)
        #: whether the systems of this model are large enough for the sparse backend
        self.sparse = max(len(self.dependent), self.n_saddle) > SPARSE_SIZE
        # small models hold D_x as a dense matrix: one product per use instead of one
        # per element group (numpy's cost per call dominates at this size); it and the
        # scaled D_c are scattered from the Jacobian features of all groups at once
        self._nodal_index: dict[tuple[int, tuple[bool, ...]], np.ndarray] = {}
        self._jacobian_scatter, self._constraint_scatter = self._feature_scatter(
            row_at, dependent_at)
        #: ``c r^T`` of the scales of ``D_c``: undoes them on its inverse
        self.constraint_unscale = self.row_scale_columns[:, None] * self.constraint_row_scale
        self._constraint_flat = (self.rows[:, None] * nx + self.dependent[None, :]).ravel()
        self._coordinate_flat = [(g.coordinates[:, :, None] * nx + g.coordinates[:, None, :])
                                 .ravel() for g in self.groups]
        #: per group, the element mass matrices ``(n, nc, nc)`` if they never change
        #: (then the inertia force is ``M xddot`` alone), else ``None``
        self.constant_mass_blocks = [
            g.type.mass_matrix(model.x0[g.coordinates][None], g.reference, g.mass, g.lumped)[0]
            if g.has_mass and not g.type.mass_varies else None for g in self.groups]
        #: the groups whose element mass matrices change with the configuration
        self.varying_mass_groups = [
            g for g, constant in zip(self.groups, self.constant_mass_blocks, strict=True)
            if g.has_mass and constant is None]
        #: the part of ``M`` that never changes (dense models): nodal masses and the
        #: constant-mass elements
        self.constant_mass = None if self.sparse else self._constant_mass()
        #: dense models: ``M = mass_base + `` the varying terms of
        #: :meth:`~flexmbd.elements.ElementType.mass_terms`, see :meth:`mass_matrix`
        self.mass_base, self._mass_scatter = (None, None) if self.sparse else self._mass_terms()
        self.stiffness, self.damping, self.prestress = self._elastic_law()

    def _feature_scatter(self, row_at: np.ndarray, dependent_at: np.ndarray
                         ) -> tuple[Scatter, Scatter]:
        """Where the Jacobian features (:attr:`ElementType.jacobian_entries`) of all groups,
        concatenated per batch member, land in ``D_x`` and in the scaled ``D_c`` (there
        with the signs times the scales of ``D_c`` as weights)."""
        rows, cols, features, signs, offset = [], [], [], [], 0
        for g in self.groups:
            pattern, n = g.type.jacobian_pattern, len(g.coordinates)
            rows.append(g.deformations[:, pattern.rows].ravel())
            cols.append(g.coordinates[:, pattern.columns].ravel())
            features.append((offset + np.arange(n)[:, None] * g.type.n_features
                             + pattern.features).ravel())
            signs.append(np.tile(pattern.signs, n))
            offset += n * g.type.n_features
        rows, cols = np.concatenate(rows), np.concatenate(cols)
        features, signs = np.concatenate(features), np.concatenate(signs)
        in_c = (row_at[rows] >= 0) & (dependent_at[cols] >= 0)
        r, c = row_at[rows[in_c]], dependent_at[cols[in_c]]
        n = len(self.dependent)
        return (Scatter(rows * self.nx + cols, features, signs, self.ne * self.nx),
                Scatter(r * n + c, features[in_c],
                        signs[in_c] * self.constraint_row_scale[r] * self.row_scale_columns[c],
                        n * n))

    def jacobian_matrix(self, features: np.ndarray) -> np.ndarray:
        """``D_x`` ``(nb, ne, nx)`` from the Jacobian features of all groups concatenated
        per member ``(nb, k)`` (dense models)."""
        return self._jacobian_scatter.apply(features).reshape(-1, self.ne, self.nx)

    def scaled_constraint_matrix(self, features: np.ndarray) -> np.ndarray:
        """``diag(r) D_c diag(c)`` ``(nb, nr, nr)`` with the scales
        :attr:`constraint_row_scale` and :attr:`row_scale_columns`, from the features as
        for :meth:`jacobian_matrix` (dense models)."""
        n = len(self.dependent)
        return self._constraint_scatter.apply(features).reshape(-1, n, n)

    def _elastic_law(self):
        """``S``, ``C`` ``(ne, ne)`` and ``sigma0`` ``(ne,)`` of the whole model (dense
        models only; ``None`` for the sparse ones, which use the groups')."""
        if self.sparse:
            return None, None, None
        S, C, sigma0 = np.zeros((self.ne, self.ne)), np.zeros((self.ne, self.ne)), np.zeros(self.ne)
        for g in self.groups:
            rows, cols = g.deformations[:, :, None], g.deformations[:, None, :]
            S[rows, cols], C[rows, cols] = g.stiffness, g.damping
            sigma0[g.deformations] = g.prestress
        return S, C, sigma0

    # --- gathering and scattering ------------------------------------------------------
    def element_values(self, X: np.ndarray) -> list[np.ndarray]:
        """``X`` ``(nb, nx)`` at the coordinates of each group: ``(nb, n, nc)`` per group."""
        return [X[:, g.coordinates] for g in self.groups]

    def per_deformation(self, values: list[np.ndarray]) -> np.ndarray:
        """Element values ``(nb, n, nd)`` per group into one array ``(nb, ne)``."""
        nb = values[0].shape[0]
        out = np.empty((nb, self.ne))
        for where, v in zip(self._deformations_of_groups, values, strict=True):
            out[:, where] = v.reshape(nb, -1)
        return out

    def nodal_sum(self, values: list[np.ndarray | None], nb: int) -> np.ndarray:
        """Sum element loads ``(nb, n, nc)`` per group (``None`` = none) into ``(nb, nx)``."""
        weights = [v.reshape(nb, -1) for v in values if v is not None]
        if not weights:
            return np.zeros((nb, self.nx))
        present = tuple(v is not None for v in values)
        index = self._nodal_index.get((nb, present))
        if index is None:  # the same few layouts every step: computed once each
            coordinates = np.concatenate([g.coordinates.ravel() for g, p in
                                          zip(self.groups, present, strict=True) if p])
            index = (np.arange(nb)[:, None] * self.nx + coordinates).ravel()
            if len(self._nodal_index) > 32:  # batch sizes vary between runs: stay bounded
                self._nodal_index.clear()
            self._nodal_index[(nb, present)] = index
        flat = weights[0] if len(weights) == 1 else np.concatenate(weights, axis=1)
        return np.bincount(index, flat.ravel(), minlength=nb * self.nx).reshape(nb, self.nx)

    @staticmethod
    def contract(jacobians: list[np.ndarray], values: list[np.ndarray]) -> list[np.ndarray]:
        """``D_e v_e`` per element: ``(nb, n, nd, nc) x (nb, n, nc) -> (nb, n, nd)``."""
        return [(j @ v[..., None])[..., 0] for j, v in zip(jacobians, values, strict=True)]

    @staticmethod
    def contract_transposed(jacobians: list[np.ndarray], stresses: list[np.ndarray]
                            ) -> list[np.ndarray]:
        """``D_e^T s_e`` per element: ``(nb, n, nd, nc) x (nb, n, nd) -> (nb, n, nc)``."""
        return [(s[..., None, :] @ j)[..., 0, :] for j, s in zip(jacobians, stresses, strict=True)]

    # --- matrices ------------------------------------------------------------------------
    def constraint_matrix(self, jacobians: list[np.ndarray]) -> np.ndarray:
        """Dense ``D_c`` ``(nb, nr, nr)`` from the element Jacobians."""
        nb, n = jacobians[0].shape[0], len(self.dependent)
        out = np.zeros((nb, n * n))
        for j, (select, position) in zip(jacobians, self._constraint_pattern, strict=True):
            out[:, position] = j.reshape(nb, -1)[:, select]
        return out.reshape(nb, n, n)

    @cached_property
    def sparse_constraint_pattern(self) -> SparsePattern:
        """The sparsity of ``D_c`` (the entries of :meth:`constraint_entries`)."""
        return SparsePattern(np.concatenate([p for _, p in self._constraint_pattern]),
                             len(self.dependent))

    def constraint_entries(self, jacobians: list[np.ndarray]) -> np.ndarray:
        """The entries of ``D_c`` ``(nb, k)`` at :attr:`sparse_constraint_pattern`."""
        return np.concatenate([j.reshape(j.shape[0], -1)[:, s]
                               for j, (s, _) in zip(jacobians, self._constraint_pattern,
                                                    strict=True)], axis=1)

    def row_norms(self, jacobians: list[np.ndarray]) -> np.ndarray:
        """Norm of each row of ``D_x`` with angles scaled by the model size ``(nb, ne)``."""
        return np.sqrt(self.per_deformation(
            [np.sum((j * g.scale[:, None, :]) ** 2, axis=-1)
             for g, j in zip(self.groups, jacobians, strict=True)]))

    def saddle_entries(self, blocks: list[np.ndarray | None], jacobians: list[np.ndarray]):
        """Flat positions and values of ``[[A, C^T], [C, 0]]`` for each batch member.

        ``blocks`` are element matrices ``(nb, n, nc, nc)`` of ``A`` per group (``None``
        = none); nodal masses are added to ``A``; ``C`` are the rows of ``D_x`` of the
        multipliers over the free coordinates. Returns ``(positions, values)`` with
        values ``(nb, k)`` for a target of ``n_saddle**2`` entries.
        """
        nb = jacobians[0].shape[0]
        positions, values = [], []
        for block, j, (m_select, m_position), (c_select, c_position, c_transposed) in zip(
                blocks, jacobians, self._saddle_mass, self._saddle_jacobian, strict=True):
            if block is not None:
                positions.append(m_position)
                values.append(block.reshape(nb, -1)[:, m_select])
            c = j.reshape(nb, -1)[:, c_select]
            positions += [c_position, c_transposed]
            values += [c, c]
        on_free = self._nodal_mass_on_free
        positions.append(self._nodal_mass_saddle[on_free])
        values.append(np.broadcast_to(self.nodal_mass_values[on_free], (nb, on_free.sum())))
        return np.concatenate(positions), np.concatenate(values, axis=1)

    def saddle_matrix(self, blocks: list[np.ndarray | None], jacobians: list[np.ndarray]
                      ) -> np.ndarray:
        """Dense ``[[A, C^T], [C, 0]]`` ``(nb, ns, ns)`` (see :meth:`saddle_entries`)."""
        positions, values = self.saddle_entries(blocks, jacobians)
        nb, ns = values.shape[0], self.n_saddle
        flat = (np.arange(nb)[:, None] * ns * ns + positions).ravel()
        return np.bincount(flat, values.ravel(), minlength=nb * ns * ns).reshape(nb, ns, ns)

    def coordinate_matrix(self, blocks: list[np.ndarray | None], nb: int) -> np.ndarray:
        """Dense ``(nb, nx, nx)`` sum of element matrices ``(nb, n, nc, nc)`` per group
        (``None`` = none)."""
        present = [k for k, b in enumerate(blocks) if b is not None]
        nx = self.nx
        if not present:
            return np.zeros((nb, nx, nx))
        flat = np.concatenate([self._coordinate_flat[k] for k in present])
        if nb > 1:
            flat = (np.arange(nb)[:, None] * nx * nx + flat).ravel()
        values = np.concatenate([np.broadcast_to(blocks[k], (nb, *blocks[k].shape[1:]))
                                 .reshape(nb, -1) for k in present], axis=1)
        return np.bincount(flat, values.ravel(), minlength=nb * nx * nx).reshape(nb, nx, nx)

    def _constant_mass(self) -> np.ndarray:
        blocks = [None if b is None else b[None] for b in self.constant_mass_blocks]
        M = self.coordinate_matrix(blocks, 1)[0]
        M[self.nodal_mass_coordinates, self.nodal_mass_coordinates] += self.nodal_mass_values
        return M

    def _mass_terms(self) -> tuple[np.ndarray, tuple[np.ndarray, ...]]:
        """``M0`` of the varying-mass groups added to :attr:`constant_mass`, and where the
        entries of their ``phi_k M_k`` land: their flat positions in ``M``, the distinct
        ones among those and each entry's place there, indices into the concatenated
        features, weights."""
        base, nx = self.constant_mass.copy(), self.nx
        positions, index, weights, offset = [], [], [], 0
        for g in self.varying_mass_groups:
            M0, terms = g.type.mass_terms(g.reference, g.mass, g.lumped)
            np.add.at(base, (g.coordinates[:, :, None], g.coordinates[:, None, :]), M0)
            element, k, a, b = np.nonzero(terms)
            positions.append(g.coordinates[element, a] * nx + g.coordinates[element, b])
            index.append(offset + element * terms.shape[1] + k)
            weights.append(terms[element, k, a, b])
            offset += terms.shape[0] * terms.shape[1]
        if not positions:
            empty = np.zeros(0, dtype=int)
            return base, (empty, empty, empty, empty, np.zeros(0))
        # elements sharing a node add to the same entries: summed over the few distinct
        # positions, not over the whole matrix (a batch of 128 matrices: 0.2 ms, not 1 ms)
        positions = np.concatenate(positions)
        distinct, slot = np.unique(positions, return_inverse=True)
        return base, (positions, distinct, slot.ravel(), np.concatenate(index),
                      np.concatenate(weights))

    def mass_matrix(self, features: list[np.ndarray], nb: int) -> np.ndarray:
        """The dense mass matrix ``(nb, nx, nx)`` from the
        :meth:`~flexmbd.elements.ElementType.mass_features` ``(nb, n, k)`` of each of
        :attr:`varying_mass_groups` (dense models)."""
        positions, distinct, slot, index, weights = self._mass_scatter
        flat = np.concatenate([f.reshape(nb, -1) for f in features] + [np.zeros((nb, 0))],
                              axis=1)
        values = flat[:, index] * weights
        if nb == 1:  # one matrix (the integrator's): summed straight into all its entries
            varying = np.bincount(positions, values[0], minlength=self.nx * self.nx)
            return varying.reshape(1, self.nx, self.nx) + self.mass_base
        # a batch: summed over the distinct positions only, then added there
        slot = (np.arange(nb)[:, None] * len(distinct) + slot).ravel()
        varying = np.bincount(slot, values.ravel(), minlength=nb * len(distinct))
        M = np.empty((nb, self.nx * self.nx))
        M[:] = self.mass_base.reshape(-1)
        M[:, distinct] += varying.reshape(nb, -1)
        return M.reshape(nb, self.nx, self.nx)

    @cached_property
    def sparse_saddle_pattern(self) -> SparsePattern:
        """The sparsity of the saddle-point matrix: the positions of
        :meth:`sparse_saddle_entries`, every group with a block."""
        jacobians = [np.zeros((1, *g.deformations.shape, g.coordinates.shape[1]))
                     for g in self.groups]
        return SparsePattern(self.sparse_saddle_entries([None] * len(self.groups),
                                                        jacobians)[0], self.n_saddle)

    def sparse_saddle_entries(self, blocks: list[np.ndarray | None],
                              jacobians: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`saddle_entries` with a (zero) block for every group, so that the
        positions are always those of :attr:`sparse_saddle_pattern`."""
        nb = jacobians[0].shape[0]
        blocks = [np.zeros((nb, *g.coordinates.shape, g.coordinates.shape[1]))
                  if b is None else b for g, b in zip(self.groups, blocks, strict=True)]
        return self.saddle_entries(blocks, jacobians)

    def dynamic_rows(self, jacobians: list[np.ndarray]) -> np.ndarray:
        """``Q`` ``(nb, nd, n_free)``: the map from free-coordinate motions to the dynamic
        entries of ``q`` (unit rows for dynamic coordinates, ``D_x`` rows for dynamic
        deformations), in the order of ``q``'s dynamic entries."""
        nb, nf = jacobians[0].shape[0], self.n_free
        n_coord, n_def = len(self.dynamic_coordinates), len(self.dynamic_deformations)
        out = np.zeros((nb, n_coord + n_def, nf))
        out[:, np.arange(n_coord), self.dynamic_coordinate_at] = 1.0
        rows = np.zeros((nb, n_def * nf))
        for j, (select, position) in zip(jacobians, self._dynamic_rows, strict=True):
            rows[:, position] = j.reshape(nb, -1)[:, select]
        out[:, n_coord:] = rows.reshape(nb, n_def, nf)
        return out


class SystemJacobian:
    """``D_x`` of a batch of states, from the Jacobian features of the element types.

    Small models keep it as a dense array ``(nb, ne, nx)``; large (sparse) ones work
    element by element, so that products stay linear in the number of elements.

    Args:
        assembly: the model's :class:`Assembly`.
        features: per group, the features of
            :meth:`~flexmbd.elements.ElementType.deformations_and_features` ``(nb, n, nf)``.
        geometry: per group, the element types'
            :meth:`~flexmbd.elements.ElementType.geometry` at the coordinates of ``D_x``
            (``None`` entries where unknown), for the other kernels of the same
            configuration.

    Attributes:
        dense: ``D_x`` ``(nb, ne, nx)``, or ``None`` for a sparse model.
    """

    def __init__(self, assembly: Assembly, features: list[np.ndarray],
                 geometry: list | None = None):
        self.assembly, self.features = assembly, features
        self.geometry = geometry if geometry is not None else [None] * len(features)
        self.nb = features[0].shape[0] if features else 0
        self.dense = self._flat = self._constrained = None
        if not assembly.sparse:
            self._flat = np.concatenate([f.reshape(self.nb, -1) for f in features], axis=1)
            self.dense = assembly.jacobian_matrix(self._flat)

    @cached_property
    def elements(self) -> list[np.ndarray]:
        """The element Jacobians per group ``(nb, n, nd, nc)``."""
        return [g.type.jacobian_of(f)
                for g, f in zip(self.assembly.groups, self.features, strict=True)]

    def times(self, v: np.ndarray) -> np.ndarray:
        """``D_x v`` ``(nb, ne)`` for coordinate rates ``v`` ``(nb, nx)``."""
        if self.dense is not None:
            return (self.dense @ v[:, :, None])[:, :, 0]
        asm = self.assembly
        return asm.per_deformation(asm.contract(self.elements, asm.element_values(v)))

    def constrained_times(self, v: np.ndarray) -> np.ndarray:
        """The rows of ``D_c`` (constrained deformations, in ``D_c``'s order) of ``D_x v``
        ``(nb, nr)``: a position or velocity solve needs only those."""
        if self.dense is None:
            return self.times(v)[:, self.assembly.take.rows]
        if self._constrained is None:  # a view where the rows are contiguous
            self._constrained = self.dense[:, self.assembly.take.rows]
        return (self._constrained @ v[:, :, None])[:, :, 0]

    def transpose_times(self, s: np.ndarray) -> np.ndarray:
        """``D_x^T s`` ``(nb, nx)`` for deformation values ``s`` ``(nb, ne)``."""
        if self.dense is not None:
            return (s[:, None, :] @ self.dense)[:, 0, :]
        asm = self.assembly
        return asm.nodal_sum(asm.contract_transposed(
            self.elements, [s[:, g.deformations] for g in asm.groups]), self.nb)

    def constraint_matrix(self) -> np.ndarray:
        """Dense ``D_c`` ``(nb, nr, nr)``."""
        asm = self.assembly
        if self.dense is None:
            return asm.constraint_matrix(self.elements)
        n = len(asm.dependent)
        return self.dense.reshape(self.nb, -1)[:, asm._constraint_flat].reshape(self.nb, n, n)

    def scaled_constraint_matrix(self) -> np.ndarray:
        """``diag(r) D_c diag(c)`` ``(nb, nr, nr)`` with the scales of :class:`Assembly`
        (dense models)."""
        return self.assembly.scaled_constraint_matrix(self._flat)

    def member(self, k: int) -> SystemJacobian:
        """The Jacobian of batch member ``k`` alone."""
        return SystemJacobian(self.assembly, [f[k:k + 1] for f in self.features])

