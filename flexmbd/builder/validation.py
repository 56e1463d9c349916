"""What is wrong with a description, with names, and the model it makes.

The builder's records (:class:`~flexmbd.builder.recording.Records`, what the user said)
are checked here all at once: the nodes' kinds from their use, a planar or spatial model,
element numbers and nodes, element data and lengths, properties against what each type
takes, nodal loads and masses, and the classification requests. Every problem is
collected, each naming the nodes, elements, coordinates or deformations involved
(:class:`~flexmbd.errors.Problem`), and :func:`assemble_checked` raises them together or
returns the immutable :class:`~flexmbd.model.Model`.
"""

from __future__ import annotations

import warnings
from collections import defaultdict
from collections.abc import Sequence
from contextlib import nullcontext
from typing import TYPE_CHECKING, Any

import numpy as np

from ..elements import (
    ELEMENT_TYPES,
    SPATIAL_ROTATIONAL,
    SPATIAL_TRANSLATIONAL,
    TRANSLATIONAL,
    WARPING,
    Beam,
    ElementType,
    EulerNormalization,
    SpatialBeam,
    WarpingBeam,
)
from ..elements.base import ROTATIONAL, is_translational
from ..engine import workspace_of
from ..engine.diagnosis import mass_is_regular, massless_message
from ..errors import ModelError, ModelWarning, Problem
from ..frozen import FrozenMap
from ..model import (
    DIRECTION_NAMES,
    CoordinateClass,
    DeformationClass,
    Element,
    ElementProperties,
    Model,
    Node,
    direction_number,
    frozen_array,
)
from ..motion import Law, shifted

if TYPE_CHECKING:
    from .recording import Records

#: elements shorter than this, relative to the size of their nodes' positions, have none
_ZERO_LENGTH = 1e-12


def assemble_checked(records: Records) -> Model:
    """The model of ``records``.

    Raises:
        ModelError: every problem found; problems of the structure (node kinds, element
            numbers, planar and spatial mixed) stop before the rest is checked.
    """
    structural = element_problems(records) + family_problems(records)
    kinds = node_kinds(records, structural)
    if structural:
        raise ModelError(records.problems + structural)
    problems = list(records.problems)
    model = assemble(records, kinds, problems)
    if problems:
        raise ModelError(problems)
    return model


def node_kinds(records: Records, problems: list[str]) -> dict[int, str]:
    """Kind of every node from its use by elements; reports conflicts."""
    users: dict[int, dict[str, list[str]]] = defaultdict(lambda: defaultdict(list))
    for number, etype, nodes, _ in records.elements:
        for node, kind in zip(nodes, etype.node_kinds(), strict=True):
            users[node][kind].append(f"{etype.name} {number}")
    kinds: dict[int, str] = {}
    for node, by_kind in users.items():
        if len(by_kind) > 1:
            problems.append(f"node {node} is used as " + " and as ".join(
                f"{kind} by {', '.join(names)}" for kind, names in by_kind.items()))
            continue
        kind = next(iter(by_kind))
        kinds[node] = kind
        position = records.positions.get(node)
        width = 3 if kind == SPATIAL_TRANSLATIONAL else 2
        if is_translational(kind) and position is None:
            problems.append(
                f"node {node} (used by {', '.join(by_kind[kind])}) has no position: "
                f"give it one with add_node({node}, x, y{', z' if width == 3 else ''})"
            )
        elif is_translational(kind) and position is not None and len(position) != width:
            problems.append(Problem(
                f"node {node} is {kind} (used by {', '.join(by_kind[kind])}) and needs "
                f"{width} coordinates, got the position {position}", ("node", node)))
        if not is_translational(kind) and position is not None:
            problems.append(Problem(
                f"node {node} is {kind} (used by {', '.join(by_kind[kind])}) "
                f"but was given a position", ("node", node)))
    for node, position in records.positions.items():  # a free point mass, say
        kinds.setdefault(node, SPATIAL_TRANSLATIONAL if len(position) == 3
                         else TRANSLATIONAL)
    for node in kinds:
        if not isinstance(node, (int, np.integer)) or isinstance(node, bool) or node < 1:
            problems.append(f"node number {node!r} is not a positive integer")
    return kinds


def family_problems(records: Records) -> list[str]:
    """A model is planar or spatial: name one element (or position) of each kind."""
    planar = [(n, t) for n, t, _, _ in records.elements if not t.is_spatial()]
    spatial = [(n, t) for n, t, _, _ in records.elements if t.is_spatial()]
    if planar and spatial:
        (n1, t1), (n2, t2) = min(planar), min(spatial)
        return [f"the model mixes planar and spatial elements ({t1.name} {n1}, "
                f"{t2.name} {n2}): build it of one kind"]
    dims = {len(p) for p in records.positions.values()} | (
        {len(records.gravity)} if records.gravity else set())
    if len(dims) > 1:
        return ["positions and gravity mix two and three coordinates: a model is planar "
                "(x, y) or spatial (x, y, z)"]
    return []


def element_problems(records: Records) -> list[str]:
    """Element numbers that are not positive or used twice; an element on a node twice."""
    problems = []
    seen: dict[int, str] = {}
    for number, etype, nodes, _ in records.elements:
        if not isinstance(number, (int, np.integer)) or isinstance(number, bool) or number < 1:
            problems.append(f"element number {number!r} is not a positive integer")
        if number in seen:
            problems.append(f"element number {number} is used twice ({seen[number]} and "
                            f"{etype.name})")
        seen[number] = etype.name
        if len(set(nodes)) != len(nodes):
            problems.append(Problem(f"{etype.name} {number} uses a node twice: nodes "
                                    f"{nodes}", ("element", number)))
    return problems


def assemble(records: Records, kinds: dict[int, str], problems: list[str]) -> Model:
    """The model of ``records`` with node kinds ``kinds``; its problems added to
    ``problems``."""
    nodes: dict[int, Node] = {}
    labels: list[str] = []
    x0: list[float] = []
    for number in sorted(kinds):
        kind = kinds[number]
        first = len(x0)
        position = records.positions.get(number)
        values = (list(position) if is_translational(kind) and position is not None
                  else [1.0, 0.0, 0.0, 0.0] if kind == SPATIAL_ROTATIONAL else [0.0])
        x0 += values
        labels += [f"x{number}.{k}" for k in range(1, len(values) + 1)]
        nodes[number] = Node(number, kind, position,
                             tuple(range(first, first + len(values))))
    x0_array = np.array(x0, dtype=float)

    elements: dict[int, Element] = {}
    deformation_labels: list[str] = []
    default_class: list[DeformationClass] = []
    for number, etype, element_nodes, data in sorted(records.elements, key=lambda e: e[0]):
        coords = tuple(i for n in element_nodes for i in nodes[n].coordinates)
        first = len(deformation_labels)
        nd = etype.n_deformations()
        deformation_labels += [f"e{number}.{k}" for k in range(1, nd + 1)]
        default_class += [DeformationClass.RELEASED if etype.released_by_default
                          or k in etype.calculable else DeformationClass.RIGID
                          for k in range(1, nd + 1)]
        refused = etype.check_data(x0_array[list(coords)], data)
        problems += [Problem(f"{etype.name} {number}: {text}", ("element", number))
                     for text in refused]
        arrays = {name: np.array([value]) for name, value in data.items()}
        # refused data (an orientation along the beam) make a reference that is never used
        with np.errstate(invalid="ignore", divide="ignore") if refused else nullcontext():
            reference = tuple(float(v) for v in
                              etype.reference_parameters(x0_array[list(coords)], arrays)[0])
        elements[number] = Element(number, etype, element_nodes, coords,
                                   tuple(range(first, first + nd)), reference,
                                   FrozenMap(dict(data)))
    _check_lengths(elements, records.positions, problems)
    element_properties = _element_properties(records, elements, problems)
    first_euler = max(elements, default=0) + 1
    euler_nodes = [n for n in sorted(nodes) if nodes[n].kind == SPATIAL_ROTATIONAL]
    inertias = _node_inertias(records, elements)
    for number, node in enumerate(euler_nodes, start=first_euler):
        data = {"inertia": inertias.get(node, (0.0,) * 6)}
        elements[number] = Element(number, EulerNormalization, (node,),
                                   nodes[node].coordinates,
                                   (len(deformation_labels),), data["inertia"],
                                   FrozenMap(data))
        deformation_labels.append(f"e{number}.1")
        default_class.append(DeformationClass.RIGID)

    # a warping node's psi is free unless fixed or prescribed (FLEXURES 1)
    coordinate_class = np.array([CoordinateClass.DYNAMIC if nodes[n].kind == WARPING
                                 else CoordinateClass.DEPENDENT
                                 for n in sorted(nodes) for _ in nodes[n].coordinates],
                                dtype=int).reshape(len(x0))
    deformation_class = np.array(default_class, dtype=int)
    laws: dict[str, Law] = {}
    _classify(records.coordinate_requests, nodes, "node", _coordinates_named,
                   labels, coordinate_class, laws, problems)
    _absolute_laws(records.coordinate_requests, nodes, elements, labels, laws, problems)
    _classify(records.deformation_requests, elements, "element",
                   _deformations_named, deformation_labels, deformation_class, laws,
                   problems)
    _check_nodal_loads(records, nodes, problems)
    return Model(
        name=records.name,
        nodes=FrozenMap(nodes),
        elements=FrozenMap(elements),
        x0=frozen_array(x0_array),
        coordinate_class=frozen_array(coordinate_class),
        deformation_class=frozen_array(deformation_class),
        coordinate_labels=tuple(labels),
        deformation_labels=tuple(deformation_labels),
        input_laws=FrozenMap(laws),
        element_properties=FrozenMap(element_properties),
        nodal_masses=FrozenMap(dict(records.nodal_masses)),
        section_masses=FrozenMap(_section_masses(records, elements, nodes)),
        nodal_inertias=FrozenMap(dict(records.nodal_inertias)),
        nodal_forces=FrozenMap(dict(records.nodal_forces)),
        gravity=records.gravity or ((0.0,) * (3 if _spatial(records) else 2)),
    )


def _section_masses(records: Records, elements, nodes) -> dict[int, float]:
    """The section inertias lumped on single-coordinate nodes, by node: a warping beam's
    ``(l0/2) Jw`` on its warping nodes, a planar beam's ``(l0/2) rhoI`` on its rotational
    nodes."""
    masses: dict[int, float] = {}
    for number, inertia in records.section_inertias.items():
        element = elements.get(number)
        if element is None or not element.type.takes_section_inertia:
            continue
        for role, lumped in element.type.section_inertia_on_nodes(element.reference,
                                                                  inertia):
            node = element.nodes[role]
            if lumped.shape == (1, 1) and nodes[node].kind in (WARPING, ROTATIONAL) \
                    and lumped[0, 0]:
                masses[node] = masses.get(node, 0.0) + float(lumped[0, 0])
    return masses


def _spatial(records: Records) -> bool:
    """Whether the description is of a spatial model."""
    return any(t.is_spatial() for _, t, _, _ in records.elements) or any(
        len(p) == 3 for p in records.positions.values())


def _node_inertias(records: Records, elements) -> dict[int, tuple[float, ...]]:
    """``Jb`` of every spatial rotational node with inertia: its ``XM`` plus the lumped
    rotary inertia ``(l0/2) R0 Jsec R0^T`` of each spatial beam with a section inertia
    (THEORY-SPATIAL 4), as ``(Jxx, Jxy, Jxz, Jyy, Jyz, Jzz)``."""
    tensors: dict[int, np.ndarray] = defaultdict(lambda: np.zeros((3, 3)))
    for node, values in records.nodal_inertias.items():
        tensors[node] += np.array(EulerNormalization.inertia_tensor(values))
    for number, inertia in records.section_inertias.items():
        element = elements.get(number)
        if element is None or not element.type.takes_section_inertia:
            continue
        for role, lumped in element.type.section_inertia_on_nodes(element.reference,
                                                                  inertia):
            if lumped.shape == (3, 3):
                tensors[element.nodes[role]] += lumped
    return {node: tuple(float(t[i, j]) for i, j in ((0, 0), (0, 1), (0, 2), (1, 1),
                                                    (1, 2), (2, 2)))
            for node, t in tensors.items()}


def _check_lengths(elements: dict[int, Element], positions, problems: list[str]) -> None:
    """Elements between translational nodes need a length: coinciding nodes make
    their chord direction undefined."""
    for number, element in elements.items():
        ends = element.type.ends()
        # coinciding to round-off of the nodes' own positions; an element that is merely
        # short against the rest of the model shows as an ill-conditioned D_c instead
        size = max((abs(v) for n in element.nodes if (p := positions.get(n)) for v in p),
                   default=0.0)
        if ends and element.reference and element.reference[0] <= _ZERO_LENGTH * size:
            translational = [n for n, r in zip(element.nodes, element.type.roles,
                                               strict=True) if is_translational(r.kind)]
            problems.append(Problem(f"{element.type.name} {number} has zero length: its "
                                    f"nodes {translational[0]} and {translational[1]} "
                                    f"coincide", ("element", number)))


def _element_properties(records: Records, elements, problems) -> dict[int, ElementProperties]:
    """Properties by element, each checked against what the element's type takes."""
    out = {}
    numbers = {*records.masses, *records.prestress, *(n for n, _ in records.values),
               *records.section_inertias, *records.sections}
    for number in sorted(numbers):
        if number not in elements:
            problems.append(f"properties given for element {number}, which is not in "
                            f"the model")
            continue
        etype = elements[number].type
        fields: dict[str, Any] = {}
        if number in records.masses:
            rho_a, lumped = records.masses[number]
            if not etype.has_mass:
                problems.append(f"set_mass element {number}: a {etype.name} has no mass; "
                                f"put point masses or rotary inertias on its nodes")
            elif rho_a < 0:
                problems.append(f"set_mass element {number}: mass per length {rho_a} is "
                                f"negative")
            fields.update(mass_per_length=rho_a, lumped=lumped)
        if number in records.section_inertias:
            if not etype.takes_section_inertia:
                takers = [t.name for t in ELEMENT_TYPES.values() if t.takes_section_inertia]
                problems.append(f"set_mass element {number}: a {etype.name} takes no "
                                f"section inertia (a {' or '.join(takers)} does)")
            fields["section_inertia"] = records.section_inertias[number]
            count = len(fields["section_inertia"])
            if not etype.takes_section_inertia:
                pass
            elif not etype.is_spatial() and count != 1:
                problems.append(f"set_mass element {number}: a {etype.name} takes one "
                                f"section inertia, its rotary inertia per length (rhoI,) "
                                f"[kg m]")
            elif etype.is_spatial() and count == 1:
                problems.append(f"set_mass element {number}: a {etype.name} takes four "
                                f"section inertias (Jxx, Jyy, Jzz, Jyz) [kg m]")
            elif count == 5 and not etype.calculable:
                problems.append(f"set_mass element {number}: a {etype.name} takes four "
                                f"section inertias (Jxx, Jyy, Jzz, Jyz); Jw is a warping "
                                f"beam's")
        for what, declared in (("stiffness", etype.stiffness_values),
                               ("damping", etype.damping_values)):
            values = records.values.get((number, what), {})
            names = {v.name: v for v in declared}
            for name, value in values.items():
                if name not in names:
                    takes = ", ".join(f"{v.name} ({v.symbol} [{v.unit}])"
                                      for v in declared) or "none"
                    problems.append(f"set_{what} element {number}: a {etype.name} has no "
                                    f"{name} {what}; it takes {takes}")
                elif value < 0:
                    problems.append(f"set_{what} element {number}: {name} {value} is "
                                    f"negative")
            if values:
                fields[what] = FrozenMap(dict(values))
        if number not in records.from_section:   # the user's own values
            problems += _shear_convention(number, etype, elements[number],
                                          records.values.get((number, "stiffness"), {}))
        nd = etype.n_deformations()
        prestress = [0.0] * nd
        for k, sigma0 in records.prestress.get(number, {}).items():
            if isinstance(k, (int, np.integer)) and 1 <= k <= nd:
                prestress[k - 1] = sigma0
            else:
                problems.append(f"set_prestress element {number}: deformation {k!r} does "
                                f"not exist; a {etype.name} has deformations 1 to {nd}")
        if number in records.prestress:
            fields["prestress"] = tuple(prestress)
        if number in records.sections:
            fields["section"], fields["material"] = records.sections[number]
        out[number] = ElementProperties(**fields)
    return out


#: a shear value that makes the beam this many times softer in shear than in bending (or
#: stiffer) is the other convention's: a flexibility given for a stiffness, or the reverse
SHEAR_CONTRAST = 1e4


def _shear_convention(number: int, etype, element, values: dict) -> list[str]:
    """A planar beam's ``shear`` is the stiffness ``G A_s`` [N], a spatial beam's
    ``shear_y``, ``shear_z`` the flexibility ``EI/(G A k)`` [m^2]; a value whose size
    suggests the other (the shear parameter ``Phi = 12 EI/(G A_s l0^2)`` above
    :data:`SHEAR_CONTRAST`) is refused, naming both."""
    l0 = element.reference[0] if element.reference else 0.0
    if not l0:
        return []
    if issubclass(etype, Beam) and values.get("shear") and values.get("bending"):
        phi = 12 * values["bending"] / (values["shear"] * l0**2)
        if phi > SHEAR_CONTRAST:
            return [f"set_stiffness element {number}: shear = {values['shear']:g} N makes the "
                    f"beam {phi:.3g} times softer in shear than in bending: a planar beam's "
                    f"shear is the stiffness G A_s [N] (a spatial beam's shear_y is the "
                    f"flexibility EI/(G A k) [m^2])"]
    if etype in (SpatialBeam, WarpingBeam):
        for name in ("shear_y", "shear_z"):
            phi = 12 * values.get(name, 0.0) / l0**2
            if phi > SHEAR_CONTRAST:
                return [f"set_stiffness element {number}: {name} = {values[name]:g} m^2 "
                        f"makes the beam {phi:.3g} times softer in shear than in bending: "
                        f"a spatial beam's {name} is the flexibility EI/(G A k) [m^2] (a "
                        f"planar beam's shear is the stiffness G A_s [N])"]
    return []


def _check_nodal_loads(records: Records, nodes, problems) -> None:
    """Point masses, loads and inertia tensors on nodes that exist and take them."""
    tables: tuple[tuple[str, dict[int, Any]], ...] = (
        ("add_point_mass", records.nodal_masses), ("add_force", records.nodal_forces),
        ("add_rotary_inertia", records.nodal_inertias))
    for what, table in tables:
        for number, value in table.items():
            if number not in nodes:
                problems.append(f"{what}: node {number} is not in the model")
                continue
            kind = nodes[number].kind
            wanted = 3 if kind == SPATIAL_ROTATIONAL else len(nodes[number].coordinates)
            if what == "add_force" and len(value) != wanted:
                problems.append(
                    f"add_force node {number}: a {kind} node takes "
                    f"{wanted} component(s), got {len(value)}")
            elif what == "add_point_mass" and kind == SPATIAL_ROTATIONAL:
                problems.append(f"add_point_mass node {number}: a spatial rotational node "
                                f"takes an inertia tensor: use add_rotary_inertia")
            elif what == "add_rotary_inertia" and kind != SPATIAL_ROTATIONAL:
                problems.append(f"add_rotary_inertia node {number}: only spatial rotational "
                                f"nodes take an inertia tensor; this one is {kind}")


def flexible_without_stiffness(records: Records, model: Model, released: bool = False
                                ) -> list[Problem]:
    """A beam's deformation that is a degree of freedom (dynamic: the link is flexible)
    while no stiffness value that sets it was given, neither by ``set_stiffness`` nor
    ``set_section``: it would fold without resistance (a beam's bending at ``e2 ->
    -l``). An explicit zero (``set_stiffness(k, bending=0.0)``) says it is meant.
    With ``released``, the released deformations instead: without stiffness they are
    SPACAR's hinges at a beam's end, often meant, so :meth:`build` only warns."""
    wanted = DeformationClass.RELEASED if released else DeformationClass.DYNAMIC
    problems = []
    known: dict[tuple, dict[int, list[str]]] = {}  # the setters of elements alike (a mesh)
    for number, element in model.elements.items():
        etype = element.type
        names = [value.name for value in etype.stiffness_values]
        if not any(name.startswith("bending") for name in names):
            continue
        given = records.values.get((number, "stiffness"), {})
        if all(name in given for name in names):  # a section and material give them all
            continue
        reference = np.asarray(element.reference, dtype=float)
        key = (etype, reference.tobytes())
        setters = known.get(key)
        if setters is None:
            setters = known[key] = _stiffness_setters(etype, reference)
        loose = [i for k, i in enumerate(element.deformations)
                 if model.deformation_class[i] == wanted
                 and setters.get(k) and not any(name in given for name in setters[k])]
        if not loose:
            continue
        keywords = list(dict.fromkeys(setters[element.deformations.index(i)][0]
                                      for i in loose))
        what = ", ".join(model.describe_deformation(i) for i in loose)
        values = ", ".join(f"{name}=..." for name in keywords)
        zeros = ", ".join(f"{name}=0.0" for name in keywords)
        text = (f"{etype.name} {number} has released deformations without stiffness, "
                f"hinges at its ends: {what}; give set_stiffness({number}, {values}) "
                f"(ESTIFF in a file) if they are to resist, or say set_stiffness("
                f"{number}, {zeros}) if the hinges are meant" if released else
                f"{etype.name} {number} is flexible without stiffness, so it would "
                f"fold freely: {what} {'is a degree' if len(loose) == 1 else 'are degrees'}"
                f" of freedom; give set_stiffness({number}, {values}) (ESTIFF in a file) "
                f"or set_section({number}, section, material), and 0.0 to a value meant "
                f"to be zero")
        problems.append(Problem(text, *(("deformation", model.deformation_labels[i])
                                         for i in loose)))
    return problems


def warn_massless(model: Model) -> None:
    """Warn (:class:`~flexmbd.ModelWarning`) when a model with mass has a degree of
    freedom that moves none: a simulation or its modes would refuse it, while its
    statics need no mass (a model without any mass is taken as a static one)."""
    if not model.n_dof or not model.has_mass:
        return
    engine = workspace_of(model)
    x = np.asarray(model.x0, dtype=float)
    if mass_is_regular(engine, x):
        return
    message, massless = massless_message(engine, x, None)
    if massless:
        warnings.warn(f"{message}; a simulation or vibration modes would refuse the "
                      f"model (its statics need no mass)", ModelWarning, stacklevel=3)


#: drawn angles closer than this [rad] are one angle (and a law's start at one is "at" it)
SAME_ANGLE = 1e-9


def drawn_angles(elements, node: int) -> dict[int, float]:
    """The drawn chord angles [rad] of the planar elements turning with rotational
    ``node``, by element (a hinge has none)."""
    return {number: float(e.reference[1]) for number, e in elements.items()
            if len(e.reference) >= 2 and not e.type.is_spatial() and any(
                n == node and role.kind == ROTATIONAL
                for n, role in zip(e.nodes, e.type.roles, strict=True))}


def _one_angle(angles: dict[int, float]) -> float | None:
    """The common angle of ``angles`` (equal modulo 2 pi), or None."""
    values = list(angles.values())
    if not values:
        return None
    turns = [(v - values[0] + np.pi) % (2 * np.pi) - np.pi for v in values]
    return values[0] if max(abs(d) for d in turns) <= SAME_ANGLE else None


def _absolute_laws(requests, nodes, elements, labels, laws, problems) -> None:
    """Make the laws of ``input_coordinate(..., absolute=True)`` on planar rotational nodes
    increments from the drawn angle of the node's elements (positions and spatial
    rotations are absolute already)."""
    for req in requests:
        node = nodes.get(req.number)
        if not req.absolute or req.law is None or node is None or node.kind != ROTATIONAL:
            continue
        label = labels[node.coordinates[0]]
        angles = drawn_angles(elements, req.number)
        common = _one_angle(angles)
        if common is not None:
            laws[label] = shifted(req.law, common)
            continue
        drawn = ", ".join(f"element {e} at {np.degrees(a):.6g} deg" for e, a in angles.items())
        problems.append(Problem(
            f"{req.command} node {req.number} absolute=True: "
            + (f"its elements are drawn at different angles ({drawn}), so an absolute angle "
               f"is not one turn of the node" if angles else
               "no element with a drawn chord turns with it (a hinge alone)")
            + "; give the law as the increment from the drawn orientation (absolute=False)",
            ("node", req.number)))


def absolute_slips(records: Records, model: Model) -> list[str]:
    """Input laws of planar rotational nodes given as increments (not ``absolute``) that
    start at the drawn angle of the node's elements (not 0): most likely an absolute angle
    given where an increment is meant, turning the node twice as far."""
    found = []
    for req in records.coordinate_requests:
        node = model.nodes.get(req.number)
        if req.absolute or req.law is None or node is None or node.kind != ROTATIONAL:
            continue
        common = _one_angle(drawn_angles(model.elements, req.number))
        try:
            start = float(req.law(0.0)[0])
        except Exception:   # a law that fails at 0 is reported where it is used
            continue
        if common is None or abs(common) <= SAME_ANGLE or abs(start - common) > SAME_ANGLE:
            continue
        label = model.coordinate_labels[node.coordinates[0]]
        found.append(
            f"input_coordinate node {req.number}: its law starts at {start:.6g} rad, the drawn "
            f"angle of its elements, but an input angle counts from the drawn orientation, so "
            f"{label} starts {np.degrees(start):.6g} deg beyond it ({np.degrees(2 * start):.6g}"
            f" deg); give the law's start as 0 to start as drawn, or absolute=True to give "
            f"angles as drawn")
    return found


def _classify(requests, owners, what: str, named, labels, classes, laws, problems):
    """Apply the classification ``requests`` to the coordinates of nodes or the
    deformations of elements (``owners`` by number, ``what`` they are): ``named(req,
    owner)`` gives the indices a request names, or a problem in words; a law goes with
    the one index it names."""
    assigned: dict[int, str] = {}
    for req in requests:
        owner = owners.get(req.number)
        if owner is None:
            problems.append(f"{req.command}: {what} {req.number} is not in the model")
            continue
        indices = named(req, owner)
        if isinstance(indices, str):
            problems.append(indices)
            continue
        for i in indices:
            _assign(i, labels[i], req, classes, assigned, problems)
            if req.law is not None:
                laws[labels[i]] = req.law

def _coordinates_named(req, node) -> list[int] | str:
    """The coordinates of ``node`` a request names: its direction, or all (the Euler
    parameters lam1 .. lam3 of a spatial rotational node, as SPACAR: lam0 follows from
    the norm)."""
    ks: Sequence[int]
    if req.k is None:
        ks = range(2, 5) if node.kind == SPATIAL_ROTATIONAL else \
            range(1, len(node.coordinates) + 1)
        if req.law is not None and len(ks) > 1:
            return (f"{req.command} node {req.number}: a law needs exactly one direction "
                    f"of this {node.kind} node")
    else:
        k = direction_number(node.kind, req.k)
        if k is None or not 1 <= k <= len(node.coordinates):
            names = DIRECTION_NAMES[node.kind]
            valid = " and ".join(f"{i + 1} ({n})" for i, n in enumerate(names))
            return (f"{req.command} node {req.number}: direction {req.k!r} does not "
                    f"exist; a {node.kind} node has direction {valid}")
        ks = [k]
    return [node.coordinates[k - 1] for k in ks]

def _deformations_named(req, element) -> list[int] | str:
    """The deformations of ``element`` a request names: one, or all."""
    if element.type.automatic:
        return (f"{req.command}: element {req.number} is the {element.type.name} of node "
                f"{element.nodes[0]}, rigid always")
    nd = len(element.deformations)
    calculable = element.type.calculable
    ks: Sequence[int]
    if req.k is None:
        if req.law is not None and nd > 1:
            return (f"{req.command} element {req.number}: a law needs exactly one "
                    f"deformation of this {element.type.name}")
        ks = [k for k in range(1, nd + 1) if k not in calculable]
    elif isinstance(req.k, (int, np.integer)) and 1 <= req.k <= nd:
        ks = [int(req.k)]
    else:
        return (f"{req.command} element {req.number}: deformation {req.k!r} does not "
                f"exist; a {element.type.name} has deformations 1 to {nd}")
    if any(k in calculable for k in ks) and req.what != DeformationClass.RELEASED:
        return (f"{req.command} element {req.number}: deformations "
                f"{' and '.join(map(str, calculable))} of a {element.type.name} are always "
                f"computed from its nodes (released); they cannot be "
                f"{_CLASS_WORDS[req.what.name]}")
    return [element.deformations[k - 1] for k in ks]


# keyed by name: members of the two IntEnums with equal values compare equal
_CLASS_WORDS = {"FIXED": "fixed", "INPUT": "an input", "DYNAMIC": "dynamic",
                "RIGID": "rigid", "RELEASED": "released"}


def _assign(i, label, req, classes, assigned, problems):
    """Put entry ``i`` in class ``req.what``; a second, different class is a problem."""
    word = _CLASS_WORDS[req.what.name]
    if i in assigned and assigned[i] != word:
        kind = "coordinate" if label.startswith("x") else "deformation"
        problems.append(Problem(f"{label} is put in two classes: {assigned[i]} and {word}",
                                (kind, label)))
        return
    assigned[i] = word
    classes[i] = req.what


def _stiffness_setters(etype: type[ElementType], reference: np.ndarray
                       ) -> dict[int, list[str]]:
    """For each deformation of ``etype`` (by position), the names of its stiffness values
    that give it stiffness: those whose law alone, at the element's ``reference``
    parameters, puts a nonzero value on its diagonal."""
    names = [value.name for value in etype.stiffness_values]
    damping = {value.name: np.zeros(1) for value in etype.damping_values}
    setters: dict[int, list[str]] = {}
    for name in names:
        unit = {other: np.array([1.0 if other == name else 0.0]) for other in names}
        with np.errstate(all="ignore"):
            S = etype.elastic_law(reference[None], unit, damping)[0][0]
        for k in np.flatnonzero(np.isfinite(np.diag(S)) & (np.diag(S) != 0.0)):
            setters.setdefault(int(k), []).append(name)
    return setters
