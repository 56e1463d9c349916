"""A model compiled for the core: the flat arrays of a :class:`~flexmbd.engine.spec.CoreSpec`.

:func:`compile_model` turns an immutable :class:`~flexmbd.model.Model` into the core's
arrays in four steps, one function each:

* the elements' index maps (:func:`_element_maps`): where each element's coordinates,
  deformations, parameters, Jacobian blocks, element matrices and laws sit;
* the classification (:func:`_classification`): rigid, prescribed and dynamic, the
  free coordinates and the constrained deformations, and where each lands in ``D_c``
  and in the saddle-point matrix;
* the element laws, masses and the entries of the two square systems, type by type
  with the types' vectorised laws (:func:`_element_laws`), then the nodal masses and
  loads (:func:`_nodal_loads`);
* the orderings of the two square systems (:func:`_orderings`), chosen once by reverse
  Cuthill-McKee so that their banded LU costs grow linearly along a chain of beams.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass

import numpy as np

from ..elements.base import SPATIAL_ROTATIONAL, ElementType, is_translational
from ..errors import ModelError
from ..model import CoordinateClass, DeformationClass, Element, Model
from .core import TYPE_NUMBER, check_core, native
from .laws import coordinate_kinds, coordinate_size, own_loads, periodic_deformations
from .spec import Classification, CoreSpec, Elements, Loads, Reference, Sizes, SquareSystems

_I32 = np.int32


def reverse_cuthill_mckee(neighbours: list[set[int]]) -> list[int]:
    """An ordering of a graph's nodes with a small bandwidth: breadth-first from a node of
    least degree in each component, neighbours by increasing degree, then reversed."""
    n = len(neighbours)
    degree = [len(s) for s in neighbours]
    seen = [False] * n
    order: list[int] = []
    for start in sorted(range(n), key=degree.__getitem__):
        if seen[start]:
            continue
        seen[start] = True
        queue = deque([start])
        while queue:
            node = queue.popleft()
            order.append(node)
            for other in sorted(neighbours[node], key=degree.__getitem__):
                if not seen[other]:
                    seen[other] = True
                    queue.append(other)
    return order[::-1]


def _positions(index, size: int) -> np.ndarray:
    """Position of each global index within ``index`` (``-1`` where absent), ``(size,)``."""
    where = np.full(size, -1, dtype=_I32)
    where[np.asarray(index, dtype=int)] = np.arange(len(index))
    return where


def _band_of(n_nodes: int, edges: list[tuple[int, int]]) -> np.ndarray:
    """Band position of each node of the graph ``edges`` (reverse Cuthill-McKee)."""
    neighbours: list[set[int]] = [set() for _ in range(n_nodes)]
    for a, b in edges:
        if a != b:
            neighbours[a].add(b)
            neighbours[b].add(a)
    band = np.empty(n_nodes, dtype=_I32)
    band[reverse_cuthill_mckee(neighbours)] = np.arange(n_nodes)
    return band


def _offsets(sizes) -> np.ndarray:
    return np.concatenate([[0], np.cumsum(sizes)]).astype(_I32)


@dataclass(frozen=True)
class _Maps:
    """The elements' offsets and index maps (fields of :class:`~.spec.Elements`)."""

    c_off: np.ndarray
    d_off: np.ndarray
    p_off: np.ndarray
    j_off: np.ndarray
    b_off: np.ndarray
    law_off: np.ndarray
    c_idx: np.ndarray
    d_idx: np.ndarray


def _element_maps(elements: list[Element]) -> _Maps:
    """Where each element's values sit in the core's element arrays."""
    nc = np.array([e.type.n_coordinates() for e in elements], dtype=int)
    nd = np.array([e.type.n_deformations() for e in elements], dtype=int)
    npar = np.array([len(e.reference) for e in elements], dtype=int)
    return _Maps(c_off=_offsets(nc), d_off=_offsets(nd), p_off=_offsets(npar),
                 j_off=_offsets(nd * nc), b_off=_offsets(nc * nc), law_off=_offsets(nd * nd),
                 c_idx=np.array([i for e in elements for i in e.coordinates], dtype=_I32),
                 d_idx=np.array([i for e in elements for i in e.deformations], dtype=_I32))


def _classification(model: Model) -> Classification:
    """Rigid, prescribed and dynamic; the rows and columns of ``D_c``, the free
    coordinates and the constrained deformations (the unknowns of the saddle-point
    system).

    Raises:
        ModelError: ``D_c`` is not square.
    """
    nx, ne = model.n_coordinates, model.n_deformations
    cclass, dclass = model.coordinate_class, model.deformation_class
    rows, dep = np.asarray(model.constrained), np.asarray(model.dependent)
    if len(rows) != len(dep):
        raise ModelError(f"D_c is not square: {len(rows)} constraint equations for "
                         f"{len(dep)} dependent coordinates")
    q_dynamic = np.flatnonzero(~np.asarray(model.q_is_input))
    nxm = len(model.independent_coordinates)
    free = np.flatnonzero((cclass == CoordinateClass.DEPENDENT)
                          | (cclass == CoordinateClass.DYNAMIC))
    multipliers = np.flatnonzero((dclass == DeformationClass.RIGID)
                                 | (dclass == DeformationClass.INPUT))
    rotational = np.array([i for node in model.nodes.values()
                           if node.kind == SPATIAL_ROTATIONAL for i in node.coordinates], int)
    return Classification(
        fixed=model.fixed, x_fixed=np.asarray(model.x0, float)[model.fixed],
        q_coord=model.independent_coordinates, q_def=model.independent_deformations,
        q_input=model.q_is_input, q_dyn=q_dynamic, rows=rows,
        row_of_def=_positions(rows, ne), dep=dep, free_of=_positions(free, nx),
        dyn_coord=np.asarray(model.independent_coordinates)[q_dynamic[q_dynamic < nxm]],
        dyn_def=np.asarray(model.independent_deformations)[q_dynamic[q_dynamic >= nxm] - nxm],
        supported=np.sort(np.concatenate([model.fixed, model.input_coordinates])),
        elastic_def=np.asarray(model.carries_elastic_stress),
        periodic=periodic_deformations(model), rotations=rotational,
        mult_of_def=_positions(multipliers, ne))


class _Entries:
    """Entries of element blocks that land in a square system: their sources in the
    element arrays, their rows and their columns."""

    def __init__(self) -> None:
        self.lists: tuple[list, list, list] = ([], [], [])

    def add(self, src: np.ndarray, rows: np.ndarray, cols: np.ndarray,
            row_offset: int = 0) -> None:
        """The entries ``src`` whose row and column (broadcast to ``src``'s shape, ``-1``
        where absent) both exist in the system; rows shifted by ``row_offset``."""
        rows, cols = np.broadcast_to(rows, src.shape), np.broadcast_to(cols, src.shape)
        keep = (rows >= 0) & (cols >= 0)
        for target, values in zip(self.lists, (src, rows + row_offset, cols), strict=True):
            target.append(values[keep])

    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(sources, rows, columns)."""
        a, b, c = (np.concatenate(x) if x else np.zeros(0, int) for x in self.lists)
        return a, b, c


@dataclass
class _Laws:
    """What the elements give: their laws, masses and loads, and the entries of ``D_c``
    (``dc``), of the constraint block (``sc``) and of the mass block (``sa``) of the
    saddle-point matrix."""

    emass: np.ndarray
    consistent: np.ndarray
    lumped_diag: np.ndarray
    S: np.ndarray
    C: np.ndarray
    sigma0: np.ndarray
    elastic: np.ndarray
    f_const: np.ndarray
    dc: _Entries
    sc: _Entries
    sa: _Entries


def _gravity(model: Model) -> np.ndarray:
    """Gravity ``(3,)`` [m/s^2]: the core takes three components, a planar model has two."""
    gravity = np.zeros(3)
    gravity[:len(model.gravity)] = model.gravity
    return gravity


def _element_laws(model: Model, elements: list[Element], maps: _Maps,
                  classes: Classification) -> _Laws:
    """Per element type, with the type's vectorised laws: the elastic law on the
    deformations that carry elastic stress, pre-stress, consistent and lumped masses (a
    lumped mass's weight), and where the entries of its Jacobian blocks and element
    matrices land in the two square systems."""
    nx, ne, n = model.n_coordinates, model.n_deformations, len(elements)
    gravity = _gravity(model)
    kinds = coordinate_kinds(model)
    # gravity on each coordinate of a translational node (what lumped masses weigh)
    gravity_of = np.array([gravity[kinds[i][1]] if is_translational(kinds[i][0]) else 0.0
                           for i in range(nx)])
    out = _Laws(emass=np.zeros(n), consistent=np.zeros(n, dtype=_I32),
                lumped_diag=np.zeros(maps.c_off[-1]), S=np.zeros(maps.law_off[-1]),
                C=np.zeros(maps.law_off[-1]), sigma0=np.zeros(ne), elastic=np.zeros(n, _I32),
                f_const=np.zeros(nx), dc=_Entries(), sc=_Entries(), sa=_Entries())
    nfree = int(np.sum(classes.free_of >= 0))
    dep_at = _positions(classes.dep, nx)
    by_type: dict[type[ElementType], list[int]] = {}
    for k, element in enumerate(elements):
        by_type.setdefault(element.type, []).append(k)
    for etype, members in by_type.items():
        ks = np.array(members)
        n_c, n_d = etype.n_coordinates(), etype.n_deformations()
        coords = maps.c_idx[maps.c_off[ks][:, None] + np.arange(n_c)]          # (n, nc)
        defs = maps.d_idx[maps.d_off[ks][:, None] + np.arange(n_d)]            # (n, nd)
        p = np.array([elements[k].reference for k in ks]).reshape(len(ks), -1)
        props = [model.element_properties.get(elements[k].number) for k in ks]
        _type_laws(etype, ks, defs, p, props, maps, classes.elastic_def, out)
        _type_masses(etype, ks, coords, p, props, maps, gravity_of, out)
        # entries of the Jacobian blocks (n, nd, nc) and element matrices (n, nc, nc)
        src = maps.j_off[ks][:, None, None] + np.arange(n_d)[:, None] * n_c + np.arange(n_c)
        out.dc.add(src, classes.row_of_def[defs][:, :, None], dep_at[coords][:, None, :])
        out.sc.add(src, classes.mult_of_def[defs][:, :, None],
                   classes.free_of[coords][:, None, :], row_offset=nfree)
        block = maps.b_off[ks][:, None, None] + np.arange(n_c)[:, None] * n_c + np.arange(n_c)
        out.sa.add(block, classes.free_of[coords][:, :, None],
                   classes.free_of[coords][:, None, :])
    return out


def _type_laws(etype, ks, defs, p, props, maps: _Maps, elastic_def, out: _Laws) -> None:
    """The elastic law and pre-stress of the elements ``ks`` of one type, on the
    deformations that carry elastic stress only."""
    n_d = etype.n_deformations()

    def values(attribute, declared):
        return {v.name: np.array([getattr(q, attribute).get(v.name, 0.0) if q else 0.0
                                  for q in props]) for v in declared}

    law_s, law_c = etype.elastic_law(p, values("stiffness", etype.stiffness_values),
                                     values("damping", etype.damping_values))
    mask = elastic_def[defs]
    both = mask[:, :, None] & mask[:, None, :]
    at = maps.law_off[ks][:, None] + np.arange(n_d * n_d)
    out.S[at] = np.where(both, law_s, 0.0).reshape(len(ks), -1)
    out.C[at] = np.where(both, law_c, 0.0).reshape(len(ks), -1)
    given = np.array([q.prestress if q and q.prestress is not None else (0.0,) * n_d
                      for q in props]).reshape(len(ks), n_d)
    out.sigma0[defs] = np.where(mask, given, 0.0)
    out.elastic[ks] = (np.any(out.S[at] != 0.0, axis=1) | np.any(out.C[at] != 0.0, axis=1)
                       | np.any(out.sigma0[defs] != 0.0, axis=1))


def _type_masses(etype, ks, coords, p, props, maps: _Maps, gravity_of, out: _Laws) -> None:
    """The consistent or lumped masses of the elements ``ks`` of one type, and the weight
    of the lumped ones."""
    rho = np.array([q.mass_per_length if q else 0.0 for q in props])
    lumped = np.array([bool(q and q.lumped) for q in props])
    mass = etype.element_mass(p, rho) if etype.has_mass else np.zeros(len(ks))
    out.emass[ks] = np.where(lumped, 0.0, mass)
    out.consistent[ks] = (mass != 0.0) & ~lumped
    if np.any(lumped & (mass != 0.0)):
        diag = np.where(lumped[:, None],
                        etype.lumped_masses(p, np.where(lumped, mass, 0.0)), 0.0)
        out.lumped_diag[maps.c_off[ks][:, None] + np.arange(etype.n_coordinates())] = diag
        np.add.at(out.f_const, coords, diag * gravity_of[coords])


def _nodal_loads(model: Model, f_const: np.ndarray) -> np.ndarray:
    """The point masses ``(nx,)`` [kg, kg m^2]; their weight and the constant nodal loads
    (XF) added to ``f_const``."""
    gravity = _gravity(model)
    nodal_mass = np.zeros(model.n_coordinates)
    for number, point_mass in model.point_masses.items():
        node = model.nodes[number]
        nodal_mass[list(node.coordinates)] += point_mass
        if is_translational(node.kind):
            f_const[list(node.coordinates)] += point_mass * gravity[:len(node.coordinates)]
    f_const += own_loads(model)
    return nodal_mass


def _orderings(model: Model, classes: Classification, laws: _Laws,
               nodal_mass: np.ndarray, like: SquareSystems | None = None) -> SquareSystems:
    """The two square systems located and ordered: ``D_c``'s rows and columns as one
    bipartite graph, the saddle-point matrix's unknowns as another. The orderings follow
    from the entries' places alone: those of ``like`` (another model's systems) serve
    when its entries sit in the same places."""
    dc_src, dc_row, dc_col = laws.dc.arrays()
    sc_src, sc_u, sc_v = laws.sc.arrays()
    sa_src, sa_u, sa_v = laws.sa.arrays()
    free_of = classes.free_of
    sm_coord = np.flatnonzero((free_of >= 0) & (nodal_mass != 0.0))
    nr = len(classes.rows)
    ns = int(np.sum(free_of >= 0)) + int(np.sum(classes.mult_of_def >= 0))
    placed = (dc_row, dc_col, sa_u, sa_v, sc_u, sc_v)
    if like is not None and all(
            np.array_equal(a, b) for a, b in zip(placed, (like.dc_row, like.dc_col, like.sd_a_u,
                                                          like.sd_a_v, like.sd_c_u, like.sd_c_v),
                                                 strict=True)):
        rowband, colband, sd_band = like.dc_rowband, like.dc_colband, like.sd_band
    else:
        both = _band_of(2 * nr, list(zip(dc_row.tolist(), (nr + dc_col).tolist(),
                                         strict=True)))
        rowband = np.argsort(np.argsort(both[:nr], kind="stable")).astype(_I32)
        colband = np.argsort(np.argsort(both[nr:], kind="stable")).astype(_I32)
        sd_band = _band_of(ns, list(zip(sa_u.tolist(), sa_v.tolist(), strict=True))
                           + list(zip(sc_u.tolist(), sc_v.tolist(), strict=True)))
    return SquareSystems(
        dc_src=dc_src, dc_row=dc_row, dc_col=dc_col, dc_rowband=rowband, dc_colband=colband,
        dc_colscale=np.asarray(model.coordinate_scale, float)[classes.dep],
        sd_band=sd_band, sd_a_src=sa_src, sd_a_u=sa_u, sd_a_v=sa_v, sd_m_coord=sm_coord,
        sd_m_u=free_of[sm_coord], sd_c_src=sc_src, sd_c_u=sc_u, sd_c_v=sc_v)


def compile_model(model: Model, like: CoreSpec | None = None) -> CoreSpec:
    """The sizes and arrays of ``flexmbd.engine._core.Core`` for ``model``, checked
    (:mod:`flexmbd.engine.spec`); see the module docstring for the steps. ``like``, the
    compiled arrays of a model of the same structure (a design's neighbour), lends its
    band orderings where its entries sit in the same places.

    Raises:
        ModelError: ``D_c`` is not square.
        ImportError: the core is not built (:func:`~flexmbd.engine.core.check_core`).
    """
    check_core()
    elements = [model.elements[n] for n in sorted(model.elements)]
    maps = _element_maps(elements)
    classes = _classification(model)
    laws = _element_laws(model, elements, maps, classes)
    nodal_mass = _nodal_loads(model, laws.f_const)
    systems = _orderings(model, classes, laws, nodal_mass,
                         None if like is None else like.systems)
    sizes = Sizes(
        nx=model.n_coordinates, ne=model.n_deformations, nel=len(elements), nq=model.n_dof,
        nxm=len(model.independent_coordinates), nr=len(classes.rows),
        nrigid=len(model.rigid), nfree=int(np.sum(classes.free_of >= 0)),
        nmult=int(np.sum(classes.mult_of_def >= 0)), nd_dyn=len(classes.q_dyn),
        ndc=len(classes.dyn_coord), total_j=int(maps.j_off[-1]), total_b=int(maps.b_off[-1]),
        nfixed=len(model.fixed), nsupported=len(classes.supported),
        nrot=len(classes.rotations) // 4, ndc_map=len(systems.dc_src),
        nsd_a=len(systems.sd_a_src), nsd_m=len(systems.sd_m_coord),
        nsd_c=len(systems.sd_c_src))
    return CoreSpec(
        sizes=sizes,
        elements=Elements(
            etype=np.array([TYPE_NUMBER[e.type] for e in elements]), c_off=maps.c_off,
            c_idx=maps.c_idx, d_off=maps.d_off, d_idx=maps.d_idx, p_off=maps.p_off,
            j_off=maps.j_off, b_off=maps.b_off, law_off=maps.law_off,
            param=np.array([v for e in elements for v in e.reference]), emass=laws.emass,
            consistent=laws.consistent, lumped_diag=laws.lumped_diag, S=laws.S, C=laws.C,
            elastic=laws.elastic, sigma0=laws.sigma0),
        classification=classes,
        loads=Loads(nodal_mass=nodal_mass, f_const=laws.f_const, gravity=_gravity(model)),
        reference=Reference(x0=model.x0, coord_scale=model.coordinate_scale,
                            coord_size=coordinate_size(model)),
        systems=systems,
        kernels=native.KERNEL_SIZES)
