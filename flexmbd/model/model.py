"""The model: nodes, elements, classification of coordinates and deformations, properties.

A :class:`Model` is immutable once built (its arrays are read-only, its tables
mapping proxies); analyses are functions of ``(model, state)`` with the state in
plain numpy arrays, and every run builds its own workspace
(:class:`flexmbd.engine.Workspace`). Build one with :class:`flexmbd.ModelBuilder`.

Numbering follows SPACAR: node and element numbers are the user's; coordinate
``k`` of node ``n`` is labelled ``x<n>.<k>`` (``k = 1, 2`` for ``x, y`` of a
translational node, ``k = 1`` for the angle of a rotational node; in space
``k = 1, 2, 3`` for ``x, y, z`` and ``k = 1 .. 4`` for the Euler parameters
``lam0 .. lam3`` of a rotational node) and
deformation ``k`` of element ``e`` is labelled ``e<e>.<k>``. Internally every
array is indexed from 0 in the order of increasing node (element) number.
"""

from __future__ import annotations

import builtins
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from enum import IntEnum

import numpy as np

from ..elements import ElementType
from ..elements.base import ROTATIONAL, SPATIAL_KINDS, SPATIAL_ROTATIONAL, is_translational
from ..errors import LabelError
from ..frozen import FrozenMap
from ..motion import Law
from ..sections import Material, Section
from .naming import suggestion


class CoordinateClass(IntEnum):
    """Class of a nodal coordinate (THEORY section 1)."""

    FIXED = 0  #: ``x(o)``, constant
    INPUT = 1  #: ``x(m)``, prescribed function of time
    DYNAMIC = 2  #: ``x(m)``, dynamic degree of freedom
    DEPENDENT = 3  #: ``x(c)``, solved from the constraints


class DeformationClass(IntEnum):
    """Class of a deformation parameter (THEORY section 2)."""

    RIGID = 0  #: ``e(o)``, held at zero
    INPUT = 1  #: ``e(m)``, prescribed function of time
    DYNAMIC = 2  #: ``e(m)``, dynamic degree of freedom (flexible)
    RELEASED = 3  #: ``e(c)``, computed from the coordinates


DIRECTION_NAMES = {"translational": ("x", "y"), "rotational": ("phi",),
                   "spatial translational": ("x", "y", "z"),
                   "spatial rotational": ("lam0", "lam1", "lam2", "lam3"),
                   "warping": ("psi",)}


@dataclass(frozen=True)
class Node:
    """A node: SPACAR number, kind, initial position [m] and global coordinate indices."""

    number: int
    kind: str
    position: tuple[float, ...] | None
    coordinates: tuple[int, ...]


@dataclass(frozen=True)
class Element:
    """An element: number, type, node numbers in connection order, global coordinate and
    deformation indices, its reference parameters (``l0`` [m], ``beta0`` [rad], as
    many as the type uses; see :meth:`ElementType.reference_parameters`) and the data it
    was given besides its nodes (a spatial beam's ``orientation``, by name)."""

    number: int
    type: builtins.type[ElementType]
    nodes: tuple[int, ...]
    coordinates: tuple[int, ...]
    deformations: tuple[int, ...]
    reference: tuple[float, ...]
    data: Mapping[str, tuple[float, ...]] = field(default_factory=lambda: FrozenMap({}))


@dataclass(frozen=True)
class ElementProperties:
    """Properties of one element; every field defaults to 'none'.

    Attributes:
        mass_per_length: ``rhoA`` [kg/m]; the element mass is ``rhoA * l0``.
        lumped: lumped instead of consistent mass (THEORY section 5).
        stiffness: the type's stiffness values by name (``{"axial": EA}``), see
            :attr:`ElementType.stiffness_values` for names and units.
        damping: the type's damping values by name, see
            :attr:`ElementType.damping_values`.
        prestress: ``sigma0`` per deformation [N or N m] (tuple of the element's
            length), or ``None``.
        section_inertia: a spatial beam's ``(Jxx, Jyy, Jzz, Jyz)`` [kg m] per unit
            length, lumped on its rotational nodes, or ``None``.
        section, material: the cross-section and material the values came from
            (:mod:`flexmbd.sections`, ``ModelBuilder.set_section``), for stresses; ``None``
            when the values were given as numbers.
    """

    mass_per_length: float = 0.0
    lumped: bool = False
    stiffness: Mapping[str, float] = field(default_factory=dict)
    damping: Mapping[str, float] = field(default_factory=dict)
    prestress: tuple[float, ...] | None = None
    section_inertia: tuple[float, ...] | None = None
    section: Section | None = None
    material: Material | None = None


def frozen_array(a) -> np.ndarray:
    """A read-only copy of ``a``: the arrays of a model never change."""
    a = np.array(a)
    a.flags.writeable = False
    return a


@dataclass(frozen=True, eq=False)
class Model:
    """An immutable mechanism, planar or spatial (build it with
    :class:`flexmbd.ModelBuilder`).

    Attributes:
        name: a name for messages and plots.
        nodes: nodes by number.
        elements: elements by number.
        x0: initial (reference) coordinates, shape ``(nx,)`` [m, rad].
        coordinate_class: :class:`CoordinateClass` of each coordinate, ``(nx,)``.
        deformation_class: :class:`DeformationClass` of each deformation, ``(ne,)``.
        coordinate_labels: ``x<node>.<k>`` for each coordinate.
        deformation_labels: ``e<element>.<k>`` for each deformation.
        input_laws: default law of each prescribed coordinate or deformation, by label.
        element_properties: mass, stiffness, damping and pre-stress by element number.
        nodal_masses: point mass [kg] of a translational node or rotary inertia
            [kg m^2] of a planar rotational node, by node number.
        section_masses: beams' section inertias lumped on single-coordinate nodes, by
            node number: a warping beam's ``(l0/2) Jw`` [kg m^3] on its warping nodes, a
            planar beam's rotary inertia ``(l0/2) rhoI`` [kg m^2] on its rotational nodes
            (the engine adds them to the point masses; a ``.dat`` file gives them on the
            EM lines).
        nodal_inertias: inertia tensor ``(Ixx, Ixy, Ixz, Iyy, Iyz, Izz)`` [kg m^2] of a
            spatial rotational node as given (``XM``); the Euler elements carry it with
            the beams' rotary inertia.
        nodal_forces: constant applied force ``(Fx, Fy)`` [N] or torque ``(M,)`` [N m]
            by node number; in space ``(Fx, Fy, Fz)`` or a global moment ``(Mx, My, Mz)``.
        gravity: ``(gx, gy)`` [m/s^2], ``(gx, gy, gz)`` for a spatial model.

    The index sets below (``fixed``, ``dependent``, ...) are computed once, when the
    model is made, and are read-only like everything else.
    """

    name: str
    nodes: Mapping[int, Node]
    elements: Mapping[int, Element]
    x0: np.ndarray
    coordinate_class: np.ndarray
    deformation_class: np.ndarray
    coordinate_labels: tuple[str, ...]
    deformation_labels: tuple[str, ...]
    input_laws: Mapping[str, Law] = field(default_factory=dict)
    element_properties: Mapping[int, ElementProperties] = field(default_factory=dict)
    nodal_masses: Mapping[int, float] = field(default_factory=dict)
    nodal_forces: Mapping[int, tuple[float, ...]] = field(default_factory=dict)
    gravity: tuple[float, ...] = (0.0, 0.0)
    nodal_inertias: Mapping[int, tuple[float, ...]] = field(default_factory=dict)
    section_masses: Mapping[int, float] = field(default_factory=dict)

    #: ``x(o)``
    fixed: np.ndarray = field(init=False, repr=False)
    #: ``x(c)``: the columns of ``D_c``
    dependent: np.ndarray = field(init=False, repr=False)
    #: ``x(m)`` (inputs and dynamic coordinates), in coordinate order
    independent_coordinates: np.ndarray = field(init=False, repr=False)
    #: the prescribed coordinates (the inputs among ``x(m)``)
    input_coordinates: np.ndarray = field(init=False, repr=False)
    #: ``e(o)``
    rigid: np.ndarray = field(init=False, repr=False)
    #: ``e(m)`` (input and dynamic deformations), in deformation order
    independent_deformations: np.ndarray = field(init=False, repr=False)
    #: ``e(c)``
    released: np.ndarray = field(init=False, repr=False)
    #: rows of ``D_c``: ``e(o)`` followed by ``e(m)`` (THEORY section 3)
    constrained: np.ndarray = field(init=False, repr=False)
    #: mask ``(ne,)`` of the deformations whose stress follows the elastic law
    carries_elastic_stress: np.ndarray = field(init=False, repr=False)
    #: labels of ``q = [x(m); e(m)]``
    q_labels: tuple[str, ...] = field(init=False, repr=False)
    #: mask over ``q``: prescribed (rheonomic) entries; the rest are dynamic
    q_is_input: np.ndarray = field(init=False, repr=False)
    #: largest element reference length [m] (1 when no element has a length)
    characteristic_length: float = field(init=False, repr=False)
    #: per coordinate 1 for translations, ``1 / characteristic_length`` for angles: makes
    #: an angle count like a displacement of the model's size in conditioning checks
    coordinate_scale: np.ndarray = field(init=False, repr=False)
    #: the coordinates ``lam0`` of the spatial rotational nodes (they take no load)
    euler_scalars: np.ndarray = field(init=False, repr=False)

    def __setstate__(self, state: dict) -> None:
        """A model unpickled: its arrays read-only again (pickle gives writable copies)."""
        for name, value in state.items():
            if isinstance(value, np.ndarray):
                value.flags.writeable = False
            object.__setattr__(self, name, value)

    def __post_init__(self):
        def coordinates_of(*classes):
            return frozen_array(np.flatnonzero(np.isin(self.coordinate_class, classes)))

        def deformations_of(*classes):
            return frozen_array(np.flatnonzero(np.isin(self.deformation_class, classes)))

        c, d = CoordinateClass, DeformationClass
        sets = {
            "fixed": coordinates_of(c.FIXED),
            "dependent": coordinates_of(c.DEPENDENT),
            "independent_coordinates": coordinates_of(c.INPUT, c.DYNAMIC),
            "input_coordinates": coordinates_of(c.INPUT),
            "rigid": deformations_of(d.RIGID),
            "independent_deformations": deformations_of(d.INPUT, d.DYNAMIC),
            "released": deformations_of(d.RELEASED),
            "carries_elastic_stress": frozen_array(
                np.isin(self.deformation_class, (d.DYNAMIC, d.RELEASED))),
        }
        sets["constrained"] = frozen_array(np.concatenate(
            [sets["rigid"], sets["independent_deformations"]]))
        sets["q_labels"] = tuple(
            [self.coordinate_labels[i] for i in sets["independent_coordinates"]]
            + [self.deformation_labels[i] for i in sets["independent_deformations"]])
        sets["q_is_input"] = frozen_array(np.concatenate([
            self.coordinate_class[sets["independent_coordinates"]] == c.INPUT,
            self.deformation_class[sets["independent_deformations"]] == d.INPUT]))
        lengths = [e.reference[0] for e in self.elements.values()
                   if e.type.ends() is not None and e.reference]
        length = max(lengths, default=0.0)
        sets["characteristic_length"] = float(length) if length > 0 else 1.0
        scale = np.ones(len(self.x0))
        for node in self.nodes.values():
            if not is_translational(node.kind):
                scale[list(node.coordinates)] = 1.0 / sets["characteristic_length"]
        sets["coordinate_scale"] = frozen_array(scale)
        sets["euler_scalars"] = frozen_array(np.array(
            [node.coordinates[0] for node in self.nodes.values()
             if node.kind == SPATIAL_ROTATIONAL], dtype=int))
        for name, value in sets.items():
            object.__setattr__(self, name, value)

    # --- sizes --------------------------------------------------------------------------
    @property
    def n_coordinates(self) -> int:
        """``nx``, the number of nodal coordinates."""
        return len(self.x0)

    @property
    def n_deformations(self) -> int:
        """``ne``, the number of deformation parameters."""
        return len(self.deformation_class)

    @property
    def n_dof(self) -> int:
        """Number of generalized coordinates ``q = [x(m); e(m)]``."""
        return len(self.q_labels)

    @property
    def dynamic_q_labels(self) -> tuple[str, ...]:
        """Labels of the entries of ``q`` that are not prescribed: the dynamic degrees of
        freedom, in the order of ``q``."""
        return tuple(label for label, given in zip(self.q_labels, self.q_is_input, strict=True)
                     if not given)

    @property
    def free_rotations(self) -> list[tuple[int, ...]]:
        """The coordinate indices ``(lam0, ..., lam3)`` of every rotational node whose Euler
        parameters are three dynamic and one dependent (a free body, a spherical joint),
        in node order: their calculable parameter is chosen again while they turn
        (:mod:`flexmbd.analysis.free_rotations`)."""
        found = []
        for node in sorted(self.nodes.values(), key=lambda n: n.number):
            if node.kind != SPATIAL_ROTATIONAL:
                continue
            classes = list(self.coordinate_class[list(node.coordinates)])
            if classes.count(CoordinateClass.DYNAMIC) == 3 and \
                    classes.count(CoordinateClass.DEPENDENT) == 1:
                found.append(tuple(node.coordinates))
        return found

    @property
    def is_spatial(self) -> bool:
        """Whether the model is spatial (its nodes have ``x, y, z`` and Euler parameters)."""
        return any(node.kind in SPATIAL_KINDS for node in self.nodes.values())

    @property
    def point_masses(self) -> dict[int, float]:
        """The masses on single nodes the engine adds: ``nodal_masses`` and the
        ``section_masses``, by node number [kg, kg m^2, kg m^3]."""
        masses = dict(self.nodal_masses)
        for node, value in self.section_masses.items():
            masses[node] = masses.get(node, 0.0) + value
        return masses

    @property
    def has_mass(self) -> bool:
        """Whether any element or node carries mass (dynamics needs it)."""
        return bool(self.nodal_masses) or any(
            p.mass_per_length or p.section_inertia for p in self.element_properties.values()
        ) or any(any(v != 0.0 for v in inertia) for inertia in self.nodal_inertias.values())

    # --- labels and look-up ---------------------------------------------------------------
    def coordinate_index(self, label: str | tuple[int, int | str]) -> int:
        """Global index of a coordinate given as ``"x3.2"``, ``(3, 2)`` or ``(3, "y")``.

        Raises:
            LabelError: no such coordinate; the closest labels and the naming scheme.
        """
        try:
            return self._coordinate_index(label)
        except LabelError as error:
            tail = suggestion(_label_text(label), self.coordinate_labels, self.directions)
            raise LabelError(f"{error}{tail}") from None

    def deformation_index(self, label: str | tuple[int, int]) -> int:
        """Global index of a deformation given as ``"e2.1"`` or ``(2, 1)``.

        Raises:
            LabelError: no such deformation; the closest labels and the naming scheme.
        """
        try:
            return self._deformation_index(label)
        except LabelError as error:
            tail = suggestion(_label_text(label), self.deformation_labels)
            raise LabelError(f"{error}{tail}") from None

    @property
    def directions(self) -> dict[int, tuple[str, ...]]:
        """Per node number, the names of its coordinates' directions in order."""
        return {number: DIRECTION_NAMES[node.kind] for number, node in self.nodes.items()}

    def _coordinate_index(self, label: str | tuple[int, int | str]) -> int:
        node, k = _parse_label(label, "x")
        if node not in self.nodes:
            raise LabelError(f"{_label_text(label)}: node {node} is not in the model")
        coords = self.nodes[node].coordinates
        number = direction_number(self.nodes[node].kind, k)
        if number is None or not 1 <= number <= len(coords):
            raise LabelError(f"{_label_text(label)}: node {node} has no coordinate {k}")
        return coords[number - 1]

    def _deformation_index(self, label: str | tuple[int, int]) -> int:
        elem, k = _parse_label(label, "e")
        if elem not in self.elements:
            raise LabelError(f"{_label_text(label)}: element {elem} is not in the model")
        defs = self.elements[elem].deformations
        if not isinstance(k, int) or not 1 <= k <= len(defs):
            raise LabelError(f"{_label_text(label)}: element {elem} has no deformation {k}")
        return defs[k - 1]

    def describe_coordinate(self, i: int) -> str:
        """``"x3.1 (node 3, x)"``: label with node and direction."""
        label = self.coordinate_labels[i]
        node, k = _parse_label(label, "x")
        return f"{label} (node {node}, {DIRECTION_NAMES[self.nodes[node].kind][int(k) - 1]})"

    def describe_deformation(self, i: int) -> str:
        """``"e2.1 (rigid beam 2, elongation)"``: label with element type and meaning."""
        label = self.deformation_labels[i]
        elem, k = _parse_label(label, "e")
        etype = self.elements[elem].type
        return f"{label} ({etype.name} {elem}, {etype.deformation_names[int(k) - 1]})"

    def describe_q(self, j: int) -> str:
        """Description of entry ``j`` of ``q``."""
        nxm = len(self.independent_coordinates)
        if j < nxm:
            return self.describe_coordinate(self.independent_coordinates[j])
        return self.describe_deformation(self.independent_deformations[j - nxm])

    def __repr__(self) -> str:
        """:meth:`summary` and where to see more (never the nodes and elements in full)."""
        from ..summary import clip

        return clip(self.summary() + "\n  more: model.nodes, model.elements, "
                    "model.coordinate_labels, model.deformation_labels, model.q_labels")

    __str__ = __repr__

    def summary(self) -> str:
        """A few lines describing sizes and classification, for printing. Lists longer
        than six entries give their count and the first and last labels."""
        def names(idx, describe):
            if len(idx) > 6:
                return f"{len(idx)} ({describe(idx[0])}, ..., {describe(idx[-1])})"
            return ", ".join(describe(i) for i in idx) or "none"

        x_in = self.coordinate_class == CoordinateClass.INPUT
        x_dyn = self.coordinate_class == CoordinateClass.DYNAMIC
        e_in = self.deformation_class == DeformationClass.INPUT
        e_dyn = self.deformation_class == DeformationClass.DYNAMIC
        return "\n".join(
            [
                f"model {self.name!r}: {len(self.nodes)} nodes, {len(self.elements)} elements, "
                f"{self.n_coordinates} coordinates, {self.n_deformations} deformations, "
                f"{self.n_dof} degrees of freedom",
                f"  inputs: coordinates "
                f"{names(np.flatnonzero(x_in), self.describe_coordinate)}; deformations "
                f"{names(np.flatnonzero(e_in), self.describe_deformation)}"
                + (" (an input angle counts from the drawn orientation: 0 is as drawn)"
                   if any(self.nodes[_parse_label(self.coordinate_labels[i], "x")[0]].kind
                          == ROTATIONAL for i in np.flatnonzero(x_in)) else ""),
                f"  dynamic: coordinates "
                f"{names(np.flatnonzero(x_dyn), self.describe_coordinate)}; deformations "
                f"{names(np.flatnonzero(e_dyn), self.describe_deformation)}",
            ]
        )


_LABEL = re.compile(r"^\s*([xe])\s*(\d+)\s*(?:\.\s*(\d+))?\s*$", re.IGNORECASE)


def _label_text(label) -> str:
    return label if isinstance(label, str) else repr(label)


def _parse_label(label, prefix: str) -> tuple[int, int | str]:
    """``"x3.2" -> (3, 2)``; ``(3, "y") -> (3, "y")``; a missing ``k`` means 1."""
    if isinstance(label, str):
        match = _LABEL.match(label)
        if not match or match.group(1).lower() != prefix:
            what = "coordinate" if prefix == "x" else "deformation"
            raise LabelError(f"{label!r} is not a {what} label like '{prefix}3.1'")
        return int(match.group(2)), int(match.group(3) or 1)
    number, k = label
    return int(number), k


def direction_number(kind: str, direction: int | str) -> int | None:
    """SPACAR direction number (1-based) of ``direction`` for a node of ``kind``."""
    if isinstance(direction, str):
        names = DIRECTION_NAMES[kind]
        return names.index(direction.lower()) + 1 if direction.lower() in names else None
    if isinstance(direction, (int, np.integer)) and not isinstance(direction, bool):
        return int(direction)
    return None
