"""The engine: a model compiled for the core, and every run on it.

Every analysis of flexmbd runs on one pipeline, the compiled core
(``flexmbd.engine._core``: C with a Cython binding, built by ``pip install``):
kinematic analysis, inverse dynamics, forward simulation and the single evaluations
of the per-state functions. This module is its Python side:

* :func:`compile_model` turns an immutable :class:`~flexmbd.model.Model` into the
  flat arrays of the core (a :class:`~flexmbd.engine.spec.CoreSpec`): element data
  and index maps, the classification, and the orderings of the two square systems
  (``D_c`` and the saddle-point matrix of the accelerations and the Newton matrix),
  chosen once by reverse Cuthill-McKee so that their banded LU costs grow linearly
  along a chain of beams;
* :class:`Engine` is a workspace on the core built from those arrays: the laws and
  loads of a run, and the translation of the core's failures into flexmbd's errors,
  named after the model's coordinates and deformations. It is the only code that
  calls the core.

A model is compiled once: its spec and a workspace per thread for evaluations at one
state (:func:`workspace_of`) are kept with it; each run over a time grid takes an
engine of its own.
"""

from __future__ import annotations

import threading
from collections import deque
from collections.abc import Callable, Mapping
from functools import cached_property
from typing import Any

import numpy as np

from .. import checks
from ..elements import ELEMENT_TYPES
from ..elements.base import SPATIAL_ROTATIONAL, ElementType, is_translational
from ..errors import (
    ArgumentError,
    ConvergenceError,
    FlexmbdError,
    ModelError,
    SimulationError,
    SingularConfigurationError,
)
from ..model import CoordinateClass, DeformationClass, Model
from ..motion import Law, Polynomial, as_law
from .assembly import Assembly
from .diagnosis import at_time, massless_message, singular_message
from .spec import Classification, CoreSpec, Elements, Loads, Reference, Sizes, SquareSystems

_core: Any
try:
    from . import _core
except ImportError as error:  # no fallback: the core is the engine (see check_core)
    _core, _CORE_MISSING = None, str(error)


def check_core() -> None:
    """Refuse to run without the compiled core, or on kernels compiled for other element
    types than the package's (the package itself imports without it, so that
    ``python -m flexmbd.engine.codegen`` can make the kernels the core is built from)."""
    if _core is None:
        raise ImportError(
            f"flexmbd's compiled core (flexmbd.engine._core) is not built or cannot be loaded "
            f"({_CORE_MISSING}); install flexmbd with `pip install -e .` from its folder, "
            f"which compiles it (needs a C compiler and the Python headers)")
    if tuple(ELEMENT_TYPES) != _core.KEYWORDS:
        raise ImportError(
            f"flexmbd's compiled core has the element types {_core.KEYWORDS}, the package "
            f"{tuple(ELEMENT_TYPES)}: regenerate the kernels (python -m "
            f"flexmbd.engine.codegen) and reinstall (pip install -e .)")


#: default Newton tolerance relative to the model's characteristic length (THEORY 3)
RELATIVE_TOLERANCE = 1e-10
#: Newton iterations of a position solve before giving up
MAX_ITERATIONS = 25
#: the core's description of itself, e.g. ``"C, gcc -O3 ..."`` (``flexmbd --version``)
CORE_BUILD = _core.BUILD if _core is not None else "not built"

_TYPE_NUMBER = {cls: k for k, cls in enumerate(ELEMENT_TYPES.values())}


def write_rows(fd: int, columns: list[np.ndarray]) -> None:
    """Write equally long float64 columns ``(n,)`` as CSV rows on the file descriptor
    ``fd``, every number as ``"%.17g"`` writes it, by the core in 64 kB pieces.

    Raises:
        OSError: the file cannot take them (a full disk).
    """
    check_core()
    _core.csv_write(fd, [np.asarray(v, dtype=float).reshape(-1) for v in columns])


# --- element values of a model before it is compiled (the builder's checks) --------------
def element_kernel(element, name: str, x: np.ndarray, size: int,
                   xd: np.ndarray | None = None) -> np.ndarray:
    """One generated kernel (``"deform_jac"``, ``"hessian"``, ``"quadratic"``, ...) of one
    element at the coordinates ``x`` ``(nx,)`` (and rates ``xd``): its ``size`` values."""
    check_core()
    out = np.empty(size)
    coords = list(element.coordinates)
    _core.kernel(_TYPE_NUMBER[element.type], name, np.ascontiguousarray(x[coords]),
                 np.asarray(element.reference, dtype=float),
                 None if xd is None else np.ascontiguousarray(xd[coords]), None, out)
    return out


def deformations_and_jacobian(model: Model, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``e = D(x)`` ``(ne,)`` and ``D_x`` ``(ne, nx)`` element by element, for a model that
    cannot be compiled yet (the builder diagnoses a ``D_c`` that is not square with it);
    a compiled model's :class:`~flexmbd.engine.assembly.Assembly` gives the same."""
    x = np.asarray(x, dtype=float)
    e, D_x = np.zeros(model.n_deformations), np.zeros((model.n_deformations, len(x)))
    for element in model.elements.values():
        nd, nc = len(element.deformations), len(element.coordinates)
        out = element_kernel(element, "deform_jac", x, nd * (1 + nc))
        rows = list(element.deformations)
        e[rows] = out[:nd]
        D_x[np.ix_(rows, list(element.coordinates))] = out[nd:].reshape(nd, nc)
    return e, D_x


# --- compiling a model ----------------------------------------------------------------------
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
    where = np.full(size, -1, dtype=np.int32)
    where[np.asarray(index, dtype=int)] = np.arange(len(index))
    return where


def _band_of(n_nodes: int, edges: list[tuple[int, int]]) -> np.ndarray:
    """Band position of each node of the graph ``edges`` (reverse Cuthill-McKee)."""
    neighbours: list[set[int]] = [set() for _ in range(n_nodes)]
    for a, b in edges:
        if a != b:
            neighbours[a].add(b)
            neighbours[b].add(a)
    band = np.empty(n_nodes, dtype=np.int32)
    band[reverse_cuthill_mckee(neighbours)] = np.arange(n_nodes)
    return band


def compile_model(model: Model) -> CoreSpec:
    """The sizes and arrays of ``flexmbd.engine._core.Core`` for ``model``, checked
    (:mod:`flexmbd.engine.spec`).

    Elements are taken in the order of their numbers and evaluated type by type with
    the types' vectorised laws; the entries of ``D_c`` and of the saddle-point matrix
    are located once, and the two systems ordered for narrow bands."""
    check_core()
    i32 = np.int32
    nx, ne = model.n_coordinates, model.n_deformations
    elements = [model.elements[n] for n in sorted(model.elements)]
    cclass, dclass = model.coordinate_class, model.deformation_class
    nc = np.array([e.type.n_coordinates() for e in elements], dtype=int)
    nd = np.array([e.type.n_deformations() for e in elements], dtype=int)
    npar = np.array([len(e.reference) for e in elements], dtype=int)

    def offsets(sizes):
        return np.concatenate([[0], np.cumsum(sizes)]).astype(i32)

    c_off, d_off, p_off = offsets(nc), offsets(nd), offsets(npar)
    j_off, b_off, law_off = offsets(nd * nc), offsets(nc * nc), offsets(nd * nd)
    c_idx = np.array([i for e in elements for i in e.coordinates], dtype=i32)
    d_idx = np.array([i for e in elements for i in e.deformations], dtype=i32)

    # classification and index maps
    rows = np.asarray(model.constrained)
    dep = np.asarray(model.dependent)
    if len(rows) != len(dep):
        raise ModelError(f"D_c is not square: {len(rows)} constraint equations for "
                         f"{len(dep)} dependent coordinates")
    q_dynamic = np.flatnonzero(~np.asarray(model.q_is_input))
    nxm = len(model.independent_coordinates)
    dyn_coord = np.asarray(model.independent_coordinates)[q_dynamic[q_dynamic < nxm]]
    dyn_def = np.asarray(model.independent_deformations)[q_dynamic[q_dynamic >= nxm] - nxm]
    free = np.flatnonzero((cclass == CoordinateClass.DEPENDENT)
                          | (cclass == CoordinateClass.DYNAMIC))
    multipliers = np.flatnonzero((dclass == DeformationClass.RIGID)
                                 | (dclass == DeformationClass.INPUT))
    row_of_def, dep_at = _positions(rows, ne), _positions(dep, nx)
    free_of, mult_of_def = _positions(free, nx), _positions(multipliers, ne)
    nfree = len(free)

    # per type: properties, the elastic law on dynamic and released deformations, and
    # where the entries of its Jacobian blocks and element matrices land
    elastic_def = np.asarray(model.carries_elastic_stress)
    gravity = np.zeros(3)  # the core takes three components; a planar model has two
    gravity[:len(model.gravity)] = model.gravity
    kinds = _coordinate_kinds(model)
    translational = np.array([is_translational(kinds[i][0]) for i in range(nx)], dtype=bool)
    # gravity on each coordinate of a translational node (what lumped masses weigh)
    gravity_of = np.array([gravity[kinds[i][1]] if translational[i] else 0.0
                           for i in range(nx)])
    emass, consistent = np.zeros(len(elements)), np.zeros(len(elements), dtype=i32)
    lumped_diag, S, C = np.zeros(c_off[-1]), np.zeros(law_off[-1]), np.zeros(law_off[-1])
    sigma0, f_const = np.zeros(ne), np.zeros(nx)
    elastic = np.zeros(len(elements), dtype=i32)
    dc: tuple[list, list, list] = ([], [], [])
    sc: tuple[list, list, list] = ([], [], [])
    sa: tuple[list, list, list] = ([], [], [])
    by_type: dict[type[ElementType], list[int]] = {}
    for k, element in enumerate(elements):
        by_type.setdefault(element.type, []).append(k)
    for etype, members in by_type.items():
        ks = np.array(members)
        n_c, n_d = etype.n_coordinates(), etype.n_deformations()
        coords = c_idx[c_off[ks][:, None] + np.arange(n_c)]          # (n, nc)
        defs = d_idx[d_off[ks][:, None] + np.arange(n_d)]            # (n, nd)
        p = np.array([elements[k].reference for k in ks]).reshape(len(ks), -1)
        props = [model.element_properties.get(elements[k].number) for k in ks]

        def values(attribute, declared, props=props):
            return {v.name: np.array([getattr(q, attribute).get(v.name, 0.0) if q else 0.0
                                      for q in props]) for v in declared}

        law_s, law_c = etype.elastic_law(p, values("stiffness", etype.stiffness_values),
                                         values("damping", etype.damping_values))
        mask = elastic_def[defs]
        both = mask[:, :, None] & mask[:, None, :]
        at = law_off[ks][:, None] + np.arange(n_d * n_d)
        S[at] = np.where(both, law_s, 0.0).reshape(len(ks), -1)
        C[at] = np.where(both, law_c, 0.0).reshape(len(ks), -1)
        given = np.array([q.prestress if q and q.prestress is not None else (0.0,) * n_d
                          for q in props]).reshape(len(ks), n_d)
        sigma0[defs] = np.where(mask, given, 0.0)
        elastic[ks] = (np.any(S[at] != 0.0, axis=1) | np.any(C[at] != 0.0, axis=1)
                       | np.any(sigma0[defs] != 0.0, axis=1))
        rho = np.array([q.mass_per_length if q else 0.0 for q in props])
        lumped = np.array([bool(q and q.lumped) for q in props])
        mass = etype.element_mass(p, rho) if etype.has_mass else np.zeros(len(ks))
        emass[ks] = np.where(lumped, 0.0, mass)
        consistent[ks] = (mass != 0.0) & ~lumped
        if np.any(lumped & (mass != 0.0)):
            diag = np.where(lumped[:, None], etype.lumped_masses(p, np.where(lumped, mass, 0.0)),
                            0.0)
            lumped_diag[c_off[ks][:, None] + np.arange(n_c)] = diag
            weight = diag * gravity_of[coords]
            np.add.at(f_const, coords, weight)
        # entries of the Jacobian blocks (n, nd, nc) and element matrices (n, nc, nc)
        src = j_off[ks][:, None, None] + np.arange(n_d)[:, None] * n_c + np.arange(n_c)
        _collect(dc, src, row_of_def[defs][:, :, None], dep_at[coords][:, None, :])
        _collect(sc, src, mult_of_def[defs][:, :, None], free_of[coords][:, None, :],
                 row_offset=nfree)
        block = b_off[ks][:, None, None] + np.arange(n_c)[:, None] * n_c + np.arange(n_c)
        _collect(sa, block, free_of[coords][:, :, None], free_of[coords][:, None, :])
    dc_src, dc_row, dc_col = (np.concatenate(a) if a else np.zeros(0, int) for a in dc)
    sc_src, sc_u, sc_v = (np.concatenate(a) if a else np.zeros(0, int) for a in sc)
    sa_src, sa_u, sa_v = (np.concatenate(a) if a else np.zeros(0, int) for a in sa)

    nodal_mass = np.zeros(nx)
    for number, point_mass in model.point_masses.items():
        node = model.nodes[number]
        nodal_mass[list(node.coordinates)] += point_mass
        if is_translational(node.kind):
            f_const[list(node.coordinates)] += point_mass * gravity[:len(node.coordinates)]
    for number, load in model.nodal_forces.items():
        f_const[load_slots(model.nodes[number])] += load
    sm_coord = np.flatnonzero((free_of >= 0) & (nodal_mass != 0.0))

    # orderings: D_c's rows and columns as one bipartite graph; the saddle's unknowns
    nr, ns = len(rows), nfree + len(multipliers)
    both = _band_of(2 * nr, list(zip(dc_row.tolist(), (nr + dc_col).tolist(), strict=True)))
    dc_rowband = np.argsort(np.argsort(both[:nr], kind="stable")).astype(i32)
    dc_colband = np.argsort(np.argsort(both[nr:], kind="stable")).astype(i32)
    sd_band = _band_of(ns, list(zip(sa_u.tolist(), sa_v.tolist(), strict=True))
                       + list(zip(sc_u.tolist(), sc_v.tolist(), strict=True)))

    supported = np.sort(np.concatenate([model.fixed, model.input_coordinates]))
    rotational = np.array([i for node in model.nodes.values()
                           if node.kind == SPATIAL_ROTATIONAL for i in node.coordinates], int)
    sizes = Sizes(
        nx=nx, ne=ne, nel=len(elements), nq=model.n_dof, nxm=nxm, nr=nr,
        nrigid=len(model.rigid), nfree=nfree, nmult=len(multipliers), nd_dyn=len(q_dynamic),
        ndc=len(dyn_coord), total_j=int(j_off[-1]), total_b=int(b_off[-1]),
        nfixed=len(model.fixed), nsupported=len(supported), nrot=len(rotational) // 4,
        ndc_map=len(dc_src), nsd_a=len(sa_src), nsd_m=len(sm_coord), nsd_c=len(sc_src))
    return CoreSpec(
        sizes=sizes,
        elements=Elements(
            etype=np.array([_TYPE_NUMBER[e.type] for e in elements]), c_off=c_off, c_idx=c_idx,
            d_off=d_off, d_idx=d_idx, p_off=p_off, j_off=j_off, b_off=b_off, law_off=law_off,
            param=np.array([v for e in elements for v in e.reference]), emass=emass,
            consistent=consistent, lumped_diag=lumped_diag, S=S, C=C, elastic=elastic,
            sigma0=sigma0),
        classification=Classification(
            fixed=model.fixed, x_fixed=np.asarray(model.x0, float)[model.fixed],
            q_coord=model.independent_coordinates, q_def=model.independent_deformations,
            q_input=model.q_is_input, q_dyn=q_dynamic, rows=rows, row_of_def=row_of_def,
            dep=dep, free_of=free_of, dyn_coord=dyn_coord, dyn_def=dyn_def,
            supported=supported, elastic_def=elastic_def, periodic=_periodic(model),
            rotations=rotational, mult_of_def=mult_of_def),
        loads=Loads(nodal_mass=nodal_mass, f_const=f_const, gravity=gravity),
        reference=Reference(x0=model.x0, coord_scale=model.coordinate_scale,
                            coord_size=_coordinate_size(model)),
        systems=SquareSystems(
            dc_src=dc_src, dc_row=dc_row, dc_col=dc_col, dc_rowband=dc_rowband,
            dc_colband=dc_colband, dc_colscale=np.asarray(model.coordinate_scale, float)[dep],
            sd_band=sd_band, sd_a_src=sa_src, sd_a_u=sa_u, sd_a_v=sa_v, sd_m_coord=sm_coord,
            sd_m_u=free_of[sm_coord], sd_c_src=sc_src, sd_c_u=sc_u, sd_c_v=sc_v),
        kernels=_core.KERNEL_SIZES)


def _collect(lists: tuple[list, list, list], src: np.ndarray, rows: np.ndarray,
             cols: np.ndarray, row_offset: int = 0) -> None:
    """Append to ``lists`` (sources, rows, columns) the entries ``src`` of element blocks
    whose row and column (broadcast to ``src``'s shape, ``-1`` where absent) both exist in
    a square system; rows shifted by ``row_offset``."""
    rows, cols = np.broadcast_to(rows, src.shape), np.broadcast_to(cols, src.shape)
    keep = (rows >= 0) & (cols >= 0)
    for target, values in zip(lists, (src, rows + row_offset, cols), strict=True):
        target.append(values[keep])


def load_slots(node) -> list[int]:
    """The coordinates whose load entries hold a node's load components: all of them, but
    on a spatial rotational node ``lam1..lam3``, which hold the global moment ``(Mx, My,
    Mz)`` (the core turns it into ``2 E(lam)^T M``); ``lam0`` takes no load."""
    coordinates = list(node.coordinates)
    return coordinates[1:] if node.kind == SPATIAL_ROTATIONAL else coordinates


def _periodic(model: Model) -> np.ndarray:
    """Mask ``(ne,)`` of the deformations that are angles modulo ``2 pi``."""
    mask = np.zeros(model.n_deformations, dtype=bool)
    for element in model.elements.values():
        mask[[element.deformations[k] for k in element.type.periodic]] = True
    return mask


def unwrap_near(model: Model, q: np.ndarray, near: np.ndarray | None) -> np.ndarray:
    """``q`` ``(nq,)`` with its periodic deformations (a spatial hinge's rotation, computed
    by ``atan2`` within half a turn) shifted by whole turns to lie nearest ``near``
    ``(nq,)``: the value a continuous motion or load path has reached."""
    if near is None:
        return q
    periodic = np.concatenate([np.zeros(len(model.independent_coordinates), dtype=bool),
                               _periodic(model)[model.independent_deformations]])
    if not np.any(periodic):
        return q
    q = np.array(q, dtype=float)
    turns = np.round((near[periodic] - q[periodic]) / (2 * np.pi))
    q[periodic] += 2 * np.pi * turns
    return q


def _coordinate_size(model: Model) -> np.ndarray:
    """Per coordinate the size a change of it is measured against (a predicted move, a
    continuation step): the model size for a translation, 1 rad for an angle."""
    scale = np.ones(model.n_coordinates)
    for node in model.nodes.values():
        if is_translational(node.kind):
            scale[list(node.coordinates)] = model.characteristic_length
    return scale


def _coordinate_kinds(model: Model) -> dict[int, tuple[str, int]]:
    """Kind of node and direction (0-based) of every coordinate."""
    return {i: (node.kind, k) for node in model.nodes.values()
            for k, i in enumerate(node.coordinates)}


# --- laws ---------------------------------------------------------------------------------
def q_index(model: Model, label: str, argument: str = "label") -> int:
    """Position in ``q`` of an independent coordinate (``"x2.1"``) or deformation (``"e3.2"``);
    an error names the ``argument`` the label came from."""
    labels = model.q_labels
    try:
        if str(label).strip().lower().startswith("e"):
            wanted = model.deformation_labels[model.deformation_index(label)]
        else:
            wanted = model.coordinate_labels[model.coordinate_index(label)]
    except KeyError as err:
        raise ArgumentError(argument, str(err)) from None
    if wanted not in labels:
        raise ArgumentError(argument, f"{label} is not an input or dynamic degree of freedom of "
                                      f"the model (those are: {', '.join(labels) or 'none'})")
    return labels.index(wanted)


def initial_q(model: Model) -> np.ndarray:
    """``q`` ``(nq,)`` [m, rad] of the initial configuration: ``x(m)`` from ``x0``,
    ``e(m) = 0``."""
    return np.concatenate([np.asarray(model.x0)[model.independent_coordinates],
                           np.zeros(len(model.independent_deformations))])


def resolve_laws(model: Model, inputs: Mapping[str, Law] | None = None) -> list[Law]:
    """One law per entry of ``q``: ``inputs`` first, then the model's defaults.

    Dynamic degrees of freedom without a law are held at their initial value
    (a kinematic analysis moves only what is prescribed).

    Raises:
        ModelError: an unknown label, or an input without any law.
    """
    laws: list[Law | None] = [None] * model.n_dof
    if inputs is not None and not isinstance(inputs, Mapping):
        raise ArgumentError("inputs", f"must map labels to laws, e.g. {{'x2.1': "
                                      f"Polynomial(0, 150)}}, got {type(inputs).__name__}")
    for source in (model.input_laws, inputs or {}):
        for label, given in source.items():
            try:
                law = as_law(given)
            except ArgumentError as error:
                raise ArgumentError("inputs", f"the motion given for {label}: {error}") from None
            if not callable(law):
                raise ArgumentError("inputs", f"the motion given for {label} is not a law "
                                              f"(Polynomial, Custom, a function of t or an "
                                              f"expression in t): {law!r}")
            laws[q_index(model, label, "inputs")] = law
    q0 = initial_q(model)
    missing: list[str] = []
    for j, (given_law, is_input) in enumerate(zip(laws, model.q_is_input, strict=True)):
        if given_law is None and is_input:
            missing.append(model.describe_q(j))
        elif given_law is None:
            laws[j] = Polynomial(float(q0[j]))
    if missing:
        raise ModelError(
            f"no motion given for the input(s) {', '.join(missing)}: pass "
            f"inputs={{label: Polynomial(x0, v0, a0)}} or give law= when classifying"
        )
    return laws  # type: ignore[return-value]


def q_scale(model: Model) -> np.ndarray:
    """Per entry of ``q``: 1 for angles, one over the model size for lengths."""
    length = model.characteristic_length
    coordinates = list(1.0 / _coordinate_size(model)[model.independent_coordinates])
    lengths = {d for e in model.elements.values() if e.type.ends() is not None
               for d in e.deformations}  # deformations of elements with a chord
    deformations = [1.0 / length if d in lengths else 1.0
                    for d in model.independent_deformations]
    return np.array(coordinates + deformations)


#: applied loads as a function of time and state: ``forces(t, x, xdot)`` returning an
#: array ``(nx,)`` or a mapping from coordinate labels (``"x2.1"``) to values [N, N m]
Forces = Callable[[float, np.ndarray, np.ndarray], "np.ndarray | Mapping[str, float]"]


def load_vector(model: Model, value) -> np.ndarray:
    """User loads (array or label mapping, see :data:`Forces`) as an array ``(nx,)``. On a
    spatial rotational node the entries of ``lam1..lam3`` (labels ``x<n>.2`` to
    ``x<n>.4``) are the global moment ``(Mx, My, Mz)`` [N m] and ``lam0``'s must be 0."""
    if isinstance(value, Mapping):
        f = np.zeros(model.n_coordinates)
        for label, v in value.items():
            try:
                f[model.coordinate_index(label)] += v
            except KeyError as err:
                raise ModelError(f"forces: {err.args[0]}") from None
    else:
        f = np.asarray(value, dtype=float)
        if f.shape != (model.n_coordinates,):
            raise ModelError(f"forces must return an array of shape ({model.n_coordinates},) "
                             f"or a mapping of coordinate labels, got shape {f.shape}")
    scalar = model.euler_scalars
    if np.any(f[scalar] != 0.0):
        label = model.coordinate_labels[scalar[np.flatnonzero(f[scalar])[0]]]
        raise ModelError(f"a load on {label}, lam0 of a spatial rotational node: the loads "
                         f"of such a node are its global moment (Mx, My, Mz) on "
                         f"{label[:-1]}2 to {label[:-1]}4")
    return f


#: the columns a run fills, with their sizes as functions of the model
OUTPUTS = {"x": "nx", "xd": "nx", "xdd": "nx", "e": "ne", "ed": "ne", "edd": "ne",
           "q": "nq", "qd": "nq", "qdd": "nq", "sigma": "ne", "reactions": "nx",
           "driving": "nq"}


#: the kinematic ones among :data:`OUTPUTS`: coordinates and deformations, their rates and
#: accelerations
KINEMATIC_OUTPUTS = ("x", "xd", "xdd", "e", "ed", "edd")


def output_sizes(model: Model) -> dict[str, int]:
    """Values per output time of each column group of :data:`OUTPUTS`."""
    counts = {"nx": model.n_coordinates, "ne": model.n_deformations, "nq": model.n_dof}
    return {name: counts[size] for name, size in OUTPUTS.items()}


def output_bytes(model: Model, columns: tuple[str, ...] | None = None,
                 integrated: bool = True) -> int:
    """Bytes a run holds per output time [B]: its output arrays (``columns`` of
    :data:`OUTPUTS`, all by default) and the time; an ``integrated`` run also keeps the
    integrator's state ``[q_d, qdot_d]`` at each output, and one of free rotations
    joins its segments' arrays into new ones at the end."""
    sizes = output_sizes(model)
    values = sum(sizes[name] for name in (columns or OUTPUTS))
    if integrated and model.free_rotations:
        values *= 2
    if integrated:
        values += 2 * int(np.sum(~np.asarray(model.q_is_input)))
    return 8 * (values + 1)


def _cache(model: Model) -> dict:
    """What is computed once per model, kept on the model itself so that it goes with it:
    its compiled arrays, the conditioning of its reference configuration and each
    thread's workspace. The model stays immutable: none of it is part of its value."""
    return model.__dict__.setdefault("_engine_cache", {})


def _compiled(model: Model) -> tuple[CoreSpec, float | None]:
    """The model's compiled arrays (computed on first use; the core copies them) and the
    conditioning of ``D_c`` at its reference configuration when known."""
    entry = _cache(model)
    if "compiled" not in entry:
        entry["compiled"] = compile_model(model)
    return entry["compiled"], entry.get("reference")


def workspace_of(model: Model, tolerance: float | None = None,
              max_iterations: int = MAX_ITERATIONS) -> Engine:
    """The model's workspace for evaluations at one state (Pinocchio's ``Data`` of a
    ``Model``): an :class:`Engine` compiled on first use and kept for the model's life,
    one per thread (its core holds the last configuration and factorisation), with the
    position solve's ``tolerance`` and ``max_iterations`` set as asked. Runs over a time
    grid take an engine of their own."""
    local = _cache(model).setdefault("local", threading.local())
    engine = getattr(local, "engine", None)
    if engine is None:
        engine = local.engine = Engine(model, tolerance, max_iterations)
    else:
        engine.configure(tolerance, max_iterations)
    return engine


class Engine:
    """A run's workspace on the core: the model compiled once, a run's laws and loads,
    its output arrays and the translation of failures into flexmbd's errors.

    Args:
        model: the mechanism.
        tolerance: Newton tolerance of the position solve [m, rad]; default ``1e-10``
            times the model size.
        max_iterations: Newton iterations of a position solve before giving up.
    """

    def __init__(self, model: Model, tolerance: float | None = None,
                 max_iterations: int = MAX_ITERATIONS):
        check_core()
        self.model = model
        length = model.characteristic_length
        self.tolerance = (RELATIVE_TOLERANCE * length if tolerance is None else
                          checks.position_tolerance(tolerance, length,
                                                    float(np.abs(model.x0).max(initial=0))))
        self.max_iterations = checks.iteration_limit(max_iterations)
        #: the model's arrays as the core has them (element laws, index maps, orderings),
        #: compiled once per model
        self.compiled, reference = _compiled(model)
        self.core = _core.Core(self.compiled)
        #: scaled conditioning of D_c below which a converged position counts as singular:
        #: near a singular root Newton converges only linearly and stops about
        #: sqrt(tolerance) away from it, where D_c still looks regular. Relative to the
        #: reference configuration's conditioning where that is below 1: a long chain of
        #: beams is regular but less well conditioned than one link.
        if reference is None:
            reference = self.core.factor(np.asarray(model.x0, dtype=float))
            _cache(model)["reference"] = reference
        self.reference_conditioning = min(1.0, reference)
        self.regularity_limit = 10.0 * float(np.sqrt(
            self.tolerance / model.characteristic_length)) * self.reference_conditioning
        self.arrays: dict[str, np.ndarray] = {}
        self.integrated = False  #: whether the run integrates dynamic degrees of freedom
        self.core.settings(self.tolerance, self.max_iterations, self.regularity_limit,
                           self.reference_conditioning)

    def configure(self, tolerance: float | None = None,
                  max_iterations: int = MAX_ITERATIONS) -> None:
        """Set the position solve's tolerance [m, rad] (default ``1e-10`` times the model
        size) and iteration limit, for evaluations at one state."""
        length = self.model.characteristic_length
        wanted = (RELATIVE_TOLERANCE * length if tolerance is None else
                  checks.position_tolerance(tolerance, length,
                                            float(np.abs(self.model.x0).max(initial=0))))
        max_iterations = checks.iteration_limit(max_iterations)
        if (wanted, max_iterations, self.integrated) == (self.tolerance, self.max_iterations,
                                                         False):
            return
        self.tolerance, self.max_iterations, self.integrated = wanted, max_iterations, False
        self.regularity_limit = 10.0 * float(np.sqrt(
            wanted / length)) * self.reference_conditioning
        self.core.settings(self.tolerance, self.max_iterations, self.regularity_limit,
                           self.reference_conditioning)

    @cached_property
    def assembly(self) -> Assembly:
        """Model-wide arrays from the element kernels in one call each (``D_x``, the
        stress Hessian, the elastic law): :class:`~flexmbd.engine.assembly.Assembly`."""
        return Assembly(self.core, self.compiled.elements, self.model.n_coordinates,
                        self.model.n_deformations)

    # --- preparing a run ------------------------------------------------------------------
    def prepare(self, laws: list[Law], n_outputs: int, *, integrated: bool = False,
                dynamics: bool = False, forces: Forces | None = None,
                progress: Callable[[float], None] | None = None,
                columns: tuple[str, ...] | None = None) -> dict[str, np.ndarray]:
        """Hand a run's laws (one per entry of ``q``; with ``integrated`` the dynamic
        entries come from the integrator instead), loads and output arrays to the core.
        Returns the output arrays ``{name: (n_outputs, size)}`` the run fills."""
        model = self.model
        self.integrated = integrated
        # A simulation's position solves start from the extrapolated last solution and keep
        # converging quadratically through configurations where redundant but consistent
        # constraints make D_c nearly singular (a parallelogram whose bars align): the
        # dynamics carry the mechanism through, so the dead-point test of driven runs is
        # off. A real dead end still stops the run: Newton fails, or D_c is singular.
        self.core.settings(self.tolerance, self.max_iterations,
                           0.0 if integrated else self.regularity_limit,
                           self.reference_conditioning)
        nq = model.n_dof
        kind = np.zeros(nq, dtype=np.int32)
        coef = np.zeros((nq, 3))
        python: list[int] = []
        for j, law in enumerate(laws):
            if integrated and not model.q_is_input[j]:
                kind[j] = 2
            elif isinstance(law, Polynomial):
                coef[j] = law.x0, law.v0, law.a0
            else:
                kind[j] = 1
                python.append(j)
        values = np.zeros((nq, 3))

        def fill_laws(t):
            for j in python:
                values[j] = _law_values(laws[j], t, model.describe_q(j))

        sizes = output_sizes(model)
        wanted = columns or tuple(OUTPUTS)
        checks.output_memory(n_outputs, output_bytes(model, wanted, integrated))
        self.arrays = {name: np.zeros((n_outputs, sizes[name])) for name in wanted}
        options: dict[str, Any] = {}
        if python:
            options.update(law_callback=fill_laws, law_values=values)
        if forces is not None and not callable(forces):
            raise ArgumentError("forces", f"must be a function forces(t, x, xdot), got "
                                          f"{forces!r}")
        if forces is not None:
            x, xd, f = np.zeros(model.n_coordinates), np.zeros(model.n_coordinates), \
                np.zeros(model.n_coordinates)

            def apply_forces(t):
                try:
                    given = forces(t, x.copy(), xd.copy())
                except FlexmbdError:
                    raise
                except Exception as error:  # the user's function: named, not lost
                    raise SimulationError(f"forces raised {type(error).__name__}: {error} "
                                          f"{at_time(t)}", t) from error
                f[:] = load_vector(model, given)

            options.update(forces=apply_forces, force_x=x, force_xd=xd, force_f=f)
        if progress is not None:
            options["progress"] = progress
        self.core.prepare(kind, coef, self.arrays, n_outputs, int(dynamics), **options)
        return self.arrays

    def start(self, laws: list[Law], t: float, dynamic: np.ndarray | None = None,
              configuration: np.ndarray | None = None) -> None:
        """Start the next run at time ``t`` [s] from ``configuration`` ``(nx,)`` when given,
        else from the configuration :meth:`continued` to ``q``: the laws' values, and the
        integrated entries ``dynamic`` when given. A start the continuation cannot reach
        is left to the run, which reports its failure."""
        if configuration is not None:
            self.reset(configuration)
            return
        q = self.law_values(laws, t)[0]
        if dynamic is not None:
            q[~np.asarray(self.model.q_is_input)] = dynamic
        try:
            self.core.reset(self.continued(q, t))
        except SimulationError:
            self.core.reset()

    def law_values(self, laws: list[Law], t: float) -> np.ndarray:
        """``(3, nq)``: the values, rates and accelerations of ``laws`` at time ``t``."""
        return np.array([_law_values(law, t, self.model.describe_q(j))
                         for j, law in enumerate(laws)], dtype=float).reshape(-1, 3).T.copy()

    def integrated_state(self, laws: list[Law], t: float, y: np.ndarray,
                         guess: np.ndarray) -> dict[str, np.ndarray]:
        """:meth:`state` at time ``t`` of the integrated ``y = [q_d, qdot_d]`` with the
        prescribed entries from their ``laws`` (accelerations zero), solved from
        ``guess``."""
        q, qd, _ = self.law_values(laws, t)
        dynamic, n = ~np.asarray(self.model.q_is_input), len(y) // 2
        q[dynamic], qd[dynamic] = y[:n], y[n:]
        return self.state(q, qd, np.zeros_like(q), guess, t)

    # --- failures -------------------------------------------------------------------------
    def error(self, status: Mapping[str, Any]) -> BaseException | None:
        """The exception of a run's ``status`` (``None`` when it completed): flexmbd's
        errors with the time and the coordinates and deformations involved, or the
        exception a Python callback raised."""
        code, Status = status["code"], _core.FmStatus
        if code == Status.FM_OK:
            return None
        if code == Status.FM_PYTHON:
            return status["exception"] or KeyboardInterrupt()
        model, time = self.model, float(status["time"])
        time_or_none = None if np.isnan(time) else time
        if code == Status.FM_NOT_CONVERGED:
            worst = status["worst"]
            where = (model.describe_deformation(worst) if worst >= 0
                     else "a non-finite configuration")
            return ConvergenceError(
                f"position solve did not converge {at_time(time_or_none)}: residual "
                f"{status['residual']:.3g} after {status['iterations']} iterations (tolerance "
                f"{self.tolerance:.3g}), largest in {where}; the inputs may ask for a "
                f"configuration the constraints cannot reach (e.g. beyond an element's "
                f"length) or the step from the previous solution is too large",
                time_or_none, iterations=int(status["iterations"]),
                residual=float(status["residual"]))
        if code in (Status.FM_SINGULAR, Status.FM_SINGULAR_TOLERANCE, Status.FM_MASSLESS):
            x = self.configuration()
            if not np.all(np.isfinite(x)):  # not a property of the mechanism: a blow-up
                return SimulationError(self._diverged(time_or_none), time_or_none)
        if code in (Status.FM_SINGULAR, Status.FM_SINGULAR_TOLERANCE):
            what = "D_c is singular"
            if code == Status.FM_SINGULAR_TOLERANCE:
                what = (f"D_c is singular within the position tolerance (scaled smallest "
                        f"singular value {status['conditioning']:.2g} < "
                        f"{status['limit']:.2g})")
            D_x = self.assembly.deformations_and_jacobian(x)[1]
            D_c = D_x[np.ix_(model.constrained, model.dependent)]
            return SingularConfigurationError(
                singular_message(model, D_c, time_or_none, what, self.integrated), time_or_none)
        if code == Status.FM_MASSLESS:
            text, singular = massless_message(self, x, time_or_none)
            return (SingularConfigurationError if singular else SimulationError)(
                text, time_or_none)
        if code == Status.FM_NOT_FINITE:
            worst = int(status["worst"])
            what = (f"the law of {model.describe_q(worst)}" if worst >= 0 else
                    f"the applied load on {model.describe_coordinate(-2 - worst)}")
            return SimulationError(f"{what} is not finite {at_time(time_or_none)}",
                                   time_or_none)
        if code == Status.FM_STEP_FAILED:
            return SimulationError(
                f"the GeneralizedAlpha integrator failed {at_time(time_or_none)}: its Newton "
                f"iteration did not converge even with step {status['step']:.3g} s",
                time_or_none)
        if code == Status.FM_NO_MEMORY:
            return MemoryError(f"the core ran out of memory {at_time(time_or_none)}")
        return SimulationError(f"the core stopped with {Status(code).name} "
                               f"{at_time(time_or_none)}", time_or_none)

    @staticmethod
    def stopped_for_partition(status: Mapping[str, Any]) -> bool:
        """Whether a generalized-alpha run stopped because a free rotation's calculable
        Euler parameter got small (:mod:`flexmbd.analysis.free_rotations`)."""
        return status["code"] == _core.FmStatus.FM_PARTITION

    def _diverged(self, time: float | None) -> str:
        """The message of a run whose configuration stopped being finite."""
        cause = ("the applied loads or the laws are out of range, or the integrator's step "
                 "is too large for the model's fastest motion (GeneralizedAlpha: a smaller "
                 "step, or iterations=None to iterate Newton to convergence)"
                 if self.integrated else "the laws or the applied loads are out of range")
        return f"the motion diverged {at_time(time)}: the configuration is no longer " \
               f"finite; {cause}"

    # --- runs over a time grid (after prepare and start) --------------------------------------
    def kinematic_run(self, times: np.ndarray) -> dict[str, Any]:
        """Every output time of a prepared run whose ``q`` all follow laws (kinematic
        analysis, inverse dynamics, a state of the static analysis): the core's status
        (``reached``, ``code``, ...), for :meth:`error`."""
        return self.core.kinematic_run(np.ascontiguousarray(times, dtype=float))

    def alpha_run(self, times: np.ndarray, q: np.ndarray, qd: np.ndarray,
                  end: np.ndarray, watch: np.ndarray | None, near: float,
                  options: Mapping[str, float | int]) -> dict[str, Any]:
        """A prepared, integrated run by generalized-alpha in the core from the dynamic
        ``q``, ``qdot`` ``(nd,)``, stopping where a ``watch``-ed free rotation's partition
        is spent (its state then in ``end`` ``(2 nd,)``); the core's status and
        counters (``nfev``, ``njev``, ``nlu``, ``nsteps``)."""
        return self.core.alpha_run(times, q, qd, near=near, watch=watch, end=end, **options)

    def accelerations(self, t: float, y: np.ndarray, out: np.ndarray) -> None:
        """The dynamic entries of ``qddot`` into ``out`` ``(nd,)`` at time ``t`` [s] and
        state ``y = [q_d; qdot_d]`` of a prepared, integrated run."""
        self.call(self.core.accelerations, t, np.ascontiguousarray(y), out)

    def output(self, k: int, t: float, y: np.ndarray) -> None:
        """Record output ``k`` of a prepared run at time ``t`` [s] and state ``y``."""
        self.call(self.core.output, k, float(t), np.ascontiguousarray(y))

    def configuration(self) -> np.ndarray:
        """The configuration ``x`` ``(nx,)`` of the last evaluation (of the last failure)."""
        x = np.empty(self.model.n_coordinates)
        self.core.configuration(x)
        return x

    def reset(self, x: np.ndarray) -> None:
        """Start the next position solve from the configuration ``x`` ``(nx,)``."""
        self.core.reset(np.ascontiguousarray(x, dtype=float))

    @property
    def constant_loads(self) -> np.ndarray:
        """The model's constant loads and moments (XF) ``(nx,)`` [N, N m] as the core
        applies them."""
        return self.compiled.loads.f_const

    @property
    def rotation_coordinates(self) -> np.ndarray:
        """The Euler parameters ``(k, 4)`` (coordinate indices) of the spatial rotational
        nodes."""
        return self.compiled.classification.rotations.reshape(-1, 4)

    def call(self, method: Callable, *args):
        """Call a single evaluation of the core; its failure as flexmbd's error."""
        try:
            return method(*args)
        except _core.CoreError as failure:
            error = self.error(failure.args[0])
            if error is None:  # a failure always has a code; this would be the core's bug
                raise
            raise error from None

    # --- single evaluations -----------------------------------------------------------------
    def positions(self, q: np.ndarray, guess: np.ndarray | None = None,
                  time: float | None = None) -> np.ndarray:
        """Solve the position problem for ``q`` (THEORY 3) from ``guess``: ``x`` ``(nx,)``.
        Without a guess, the configuration on the branch of the reference one
        (:meth:`continued`)."""
        if guess is None:
            return self.continued(q, time)
        zero = np.zeros(self.model.n_dof)
        return self.state(q, zero, zero, guess, time)["x"]

    def continued(self, q: np.ndarray, time: float | None = None) -> np.ndarray:
        """The configuration ``x`` ``(nx,)`` at ``q`` that the reference configuration turns
        into when ``q`` moves there from its reference value (``x0``'s): solved in steps
        of at most 0.1 rad of an angle or 0.1 of the model size, each from the last. A
        position problem has several solutions (a bar pointing either way along its
        line); this keeps the one the model was drawn in."""
        model = self.model
        q = np.asarray(q, dtype=float)
        start = initial_q(model)
        change = np.abs(q - start) * q_scale(model)
        steps = int(np.ceil(np.max(change, initial=0.0) / 0.1)) if np.all(
            np.isfinite(change)) else 1
        x, zero = np.asarray(model.x0, dtype=float), np.zeros(model.n_dof)
        for s in np.linspace(0.0, 1.0, min(steps, 10_000) + 1)[1:]:
            x = self.state(start + s * (q - start), zero, zero, x, time)["x"]
        return x

    def state(self, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray,
              guess: np.ndarray | None = None, time: float | None = None
              ) -> dict[str, np.ndarray]:
        """Positions, velocities and accelerations of coordinates and deformations for
        ``q, qdot, qddot`` ``(nq,)`` (THEORY 3, 4): ``{"x", "xd", "xdd", "e", "ed",
        "edd"}``, from the position solve started at ``guess`` (default ``x0``)."""
        model = self.model
        sizes = output_sizes(model)
        out = {name: np.empty(sizes[name]) for name in KINEMATIC_OUTPUTS}
        guess = np.asarray(model.x0 if guess is None else guess, dtype=float)
        vectors = [np.ascontiguousarray(v, dtype=float) for v in (q, qd, qdd)]
        self.call(self.core.state, np.nan if time is None else float(time), *vectors,
                  np.ascontiguousarray(guess), *out.values())
        return out

    def equilibrium(self, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, guess: np.ndarray,
                    loads: np.ndarray | None = None) -> dict[str, np.ndarray]:
        """Inverse dynamics at one state (THEORY 8), as a run's output at ``t = 0``: every
        column of :data:`OUTPUTS` (one row each) for ``q, qdot, qddot`` ``(nq,)`` with the
        applied ``loads`` ``(nx,)`` [N, N m] besides the model's, the positions solved
        from ``guess``. One core call on this workspace (the static Newton iterations)."""
        model = self.model
        if self.integrated:  # a simulation's settings (no dead-point test) do not apply
            self.configure(self.tolerance, self.max_iterations)
        applied = np.zeros(model.n_coordinates) if loads is None else \
            load_vector(model, loads)
        sizes = output_sizes(model)
        out = {name: np.empty((1, size)) for name, size in sizes.items()}
        vectors = [np.ascontiguousarray(v, dtype=float) for v in (q, qd, qdd, guess)]
        self.call(self.core.equilibrium, 0.0, *vectors, applied, out)
        return out

    def inertia_slopes(self, x: np.ndarray, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray,
                       step: np.ndarray, rates: bool = False) -> np.ndarray:
        """Central differences ``(nx + ne, nq)`` of the inertia forces ``M xddot + h`` [N,
        N m] stacked on the deformation rates ``edot`` along each entry ``j`` of ``q``
        (of ``qdot`` with ``rates``), ``step[j]`` either side, at the state ``(q, qdot,
        qddot)`` with positions solved from ``x``: column ``j`` is the slope along
        ``q_j``. All states in one core call."""
        model = self.model
        out = np.empty((model.n_coordinates + model.n_deformations, model.n_dof))
        vectors = [np.ascontiguousarray(v, dtype=float) for v in (x, q, qd, qdd, step)]
        self.call(self.core.inertia_slopes, *vectors, bool(rates), out)
        return out

    def transfer(self, x: np.ndarray, D_x: np.ndarray | None = None) -> np.ndarray:
        """``F_q = dx/dq`` ``(nx, nq)`` at the configuration ``x`` ``(nx,)`` from one
        factorisation of ``D_c``: the rows of ``x(c)`` solve ``D_c F_c = [0; I_e(m)] -
        D_x[rows, x(m)]`` (THEORY 4); ``D_x`` ``(ne, nx)`` when the caller has it. An entry
        has the unit of its coordinate per unit of its entry of ``q``.

        Raises:
            SingularConfigurationError: ``D_c`` is singular at ``x``.
        """
        model = self.model
        nxm = len(model.independent_coordinates)
        rows, dependent = np.asarray(model.constrained), np.asarray(model.dependent)
        F_q = np.zeros((model.n_coordinates, model.n_dof))
        F_q[model.independent_coordinates, np.arange(nxm)] = 1.0
        if len(rows):
            if D_x is None:
                D_x = self.assembly.deformations_and_jacobian(x)[1]
            rhs = np.zeros((len(rows), model.n_dof))
            rhs[:, :nxm] = -D_x[np.ix_(rows, model.independent_coordinates)]
            own = np.arange(len(model.independent_deformations))  # D_c's rows: e(o), e(m)
            rhs[len(model.rigid) + own, nxm + own] = 1.0
            if not self.factor(x) > 0.0:
                D_c = D_x[np.ix_(rows, dependent)]
                raise SingularConfigurationError(singular_message(
                    model, D_c, None, "D_c is singular"))
            F_q[dependent] = self.solve(rhs)
        return F_q

    def factor(self, x: np.ndarray) -> float:
        """Factorise ``D_c`` at ``x``; returns its scaled conditioning, 0 when singular (a
        zero pivot, or the core's singular threshold)."""
        return self.core.factor(np.ascontiguousarray(x, dtype=float))

    def solve(self, rhs: np.ndarray, transposed: bool = False) -> np.ndarray:
        """``D_c^-1 rhs`` (or ``D_c^-T rhs``) with the last factorisation, for ``rhs`` of
        shape ``(nr,)`` or ``(nr, k)``."""
        rhs = np.asarray(rhs, dtype=float)
        columns = np.array(rhs.reshape(rhs.shape[0], -1).T, order="C")  # solved in place
        self.core.solve(columns, transposed)
        return columns.T.reshape(rhs.shape)

    def mass(self, x: np.ndarray, xd: np.ndarray | None = None, out: np.ndarray | None = None
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The mass matrix ``M`` ``(nx, nx)`` [kg, kg m, kg m^2] (written into ``out``, a
        C-contiguous array, when given), the velocity-dependent inertia ``h`` ``(nx,)``
        (inertia force ``M xddot + h``) and the constant loads and gravity ``f`` ``(nx,)``
        [N, N m] at ``(x, xd)`` (THEORY 5)."""
        nx = self.model.n_coordinates
        M = np.empty((nx, nx)) if out is None else out
        h, f = np.empty(nx), np.empty(nx)
        xd = np.zeros(nx) if xd is None else xd
        self.core.mass_matrix(np.ascontiguousarray(x, dtype=float),
                              np.ascontiguousarray(xd, dtype=float), M, h, f)
        return M, h, f


    def masses(self, x: np.ndarray) -> np.ndarray:
        """The mass matrices ``(nt, nx, nx)`` at the configurations ``x`` ``(nt, nx)``,
        finite and checked by the caller, in one call of the core."""
        nx = self.model.n_coordinates
        x = np.ascontiguousarray(x, dtype=float).reshape(-1, nx)
        batch = np.empty((len(x), nx, nx))
        self.core.masses(x, batch)
        return batch


def _law_values(law: Law, t: float, what: str) -> tuple[float, float, float]:
    try:
        given = law(t)
    except FlexmbdError:
        raise
    except Exception as error:  # the user's function: its failure is named, not lost
        raise SimulationError(f"the law of {what} raised {type(error).__name__}: {error} "
                              f"{at_time(t)}", t) from error
    try:
        values = tuple(float(v) for v in given)
    except (TypeError, ValueError) as error:
        raise ModelError(f"the law of {what} must return (value, rate, acceleration) as "
                         f"numbers: {error}") from None
    if len(values) != 3:
        raise ModelError(f"the law of {what} must return (value, rate, acceleration), got "
                         f"{len(values)} values")
    return values

