"""Building a :class:`~flexmbd.model.Model` and checking it.

:class:`ModelBuilder` records nodes, elements and classification in any order;
:meth:`ModelBuilder.build` checks everything at once and raises one
:class:`~flexmbd.errors.ModelError` that lists every problem it found, naming
the nodes, elements and coordinates involved.
"""

from __future__ import annotations

import math
import warnings
from collections import defaultdict
from collections.abc import Sequence
from contextlib import nullcontext
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from . import checks
from .elements import (
    ELEMENT_TYPES,
    SPATIAL_ROTATIONAL,
    SPATIAL_TRANSLATIONAL,
    TRANSLATIONAL,
    WARPING,
    Beam,
    ElementType,
    EulerNormalization,
    Hinge,
    RigidBeam,
    SecondOrderBeam,
    SpatialBeam,
    SpatialHinge,
    SpatialTruss,
    Truss,
    WarpingBeam,
)
from .elements.base import is_translational
from .engine import deformations_and_jacobian, workspace_of
from .engine.diagnosis import (
    clearly_regular,
    diagnose_rank,
    mass_is_regular,
    massless_message,
    negative_mass_problem,
)
from .errors import ArgumentError, ModelError, ModelWarning, Problem
from .frozen import FrozenMap
from .model import (
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
from .motion import Law, as_law

_ZERO_LENGTH = 1e-12  # relative to the size of the nodes' positions
#: positions farther from the origin [m] are refused: squared lengths would overflow
LARGEST_POSITION = 1e100
MASS_FORMULATIONS = ("consistent", "lumped")


def _finite_number(value) -> bool:
    try:
        return math.isfinite(float(value)) and not isinstance(value, bool)
    except (TypeError, ValueError):
        return False


def _element_type(given) -> type[ElementType] | None:
    """An element type from its class, name or SPACAR keyword; ``None`` if it is none."""
    if isinstance(given, type) and issubclass(given, ElementType):
        return given
    if isinstance(given, str):
        wanted = " ".join(given.lower().replace("_", " ").split())
        for keyword, etype in ELEMENT_TYPES.items():
            if wanted in (keyword.lower(), etype.name.lower()):
                return etype
    return None


@dataclass(frozen=True)
class _Request:
    """One classification request: class ``what`` for entry ``k`` of node/element ``number``."""

    what: CoordinateClass | DeformationClass
    number: int
    k: int | str | None
    law: Law | None
    command: str


class ModelBuilder:
    """Describe a mechanism, planar or spatial, in SPACAR terms, then :meth:`build` it.

    Example (the sliding bar of EXERCISES 1 as a truss)::

        b = ModelBuilder("sliding bar")
        b.add_node(1, -math.sqrt(3), 0.0).add_node(2, 0.0, 1.0)
        b.add_truss(1, 1, 2)
        b.fix(1, "y").fix(2, "x")
        b.input_coordinate(1, "x", law=Polynomial(-2.0, 4.0))
        model = b.build()

    Node and element numbers are positive integers of your choice. A node's
    kind (translational or rotational) follows from the elements that use it;
    translational nodes need a position, rotational nodes start at angle 0.
    Spatial models use the spatial types (:meth:`add_spatial_beam`, ...): their
    translational nodes have a position ``(x, y, z)`` and their rotational nodes four
    Euler parameters, ``(1, 0, 0, 0)`` at the start, each normalized by an Euler element
    the builder adds after the user's elements. A model is planar or spatial, not both.
    Directions are SPACAR numbers (1, 2) or names (``"x"``, ``"y"``, ``"phi"``;
    ``"z"``, ``"lam0"`` .. ``"lam3"`` in space);
    without directions a request covers all coordinates of the node (all
    deformations of the element). Coordinates not classified are dependent;
    deformations not classified are rigid. All methods return the builder.
    """

    def __init__(self, name: str = "model"):
        self.name = name
        self._positions: dict[int, tuple[float, ...]] = {}
        self._elements: list[tuple[int, type[ElementType], tuple[int, ...], dict]] = []
        self._coordinate_requests: list[_Request] = []
        self._deformation_requests: list[_Request] = []
        self._masses: dict[int, tuple[float, bool]] = {}
        self._values: dict[tuple[int, str], dict[str, float]] = {}  # (element, what) -> values
        self._prestress: dict[int, dict[int, float]] = {}
        self._nodal_masses: dict[int, float] = {}
        self._nodal_inertias: dict[int, tuple[float, ...]] = {}
        self._section_inertias: dict[int, tuple[float, ...]] = {}
        self._sections: dict[int, tuple[Any, Any]] = {}  # element -> (section, material)
        self._not_last: set[int] = set()   # beams of a chain (add_spatial_beams) but its last
        self._nodal_forces: dict[int, tuple[float, ...]] = {}
        self._gravity: tuple[float, ...] = ()
        self._problems: list[str] = []
        #: what :meth:`build` does with a property the classification needs but that was
        #: left out (a flexible beam's stiffness): ``"raise"`` it with the other problems,
        #: or ``"note"`` it in :attr:`notes` (a SPACAR file, which cannot say a zero is
        #: meant)
        self.missing_properties: Literal["raise", "note"] = "raise"
        self.notes: list[str] = []

    # --- nodes and elements -----------------------------------------------------
    def add_node(self, number: int, x: float, y: float, z: float | None = None
                 ) -> ModelBuilder:
        """Translational node ``number`` at ``(x, y)`` [m] in the initial configuration, or
        at ``(x, y, z)`` for a spatial model."""
        if number in self._positions:
            self._problems.append(Problem(f"node {number} is given a position twice",
                                          ("node", number)))
        given = (x, y) if z is None else (x, y, z)
        try:
            position = tuple(float(v) for v in given)
        except (TypeError, ValueError):
            self._problems.append(Problem(f"node {number}: position {given!r} is not "
                                          f"{len(given)} numbers", ("node", number)))
            return self
        if not all(abs(v) <= LARGEST_POSITION for v in position):
            self._problems.append(Problem(f"node {number}: position {position} is not finite "
                                          f"or beyond {LARGEST_POSITION:g} m",
                                          ("node", number)))
        self._positions[number] = position
        return self

    def add_element(self, number: int, element_type: type[ElementType] | str, nodes,
                    **data) -> ModelBuilder:
        """Element ``number`` of ``element_type`` on ``nodes`` (in the type's node order).
        The type is a class (:class:`~flexmbd.Truss`, ...) or its name or SPACAR keyword
        (``"truss"``, ``"PLTRUSS"``, ``"rigid beam"``, ``"BEAM"``). ``data`` are the
        type's :attr:`~flexmbd.elements.base.ElementType.element_data` (a spatial beam's
        ``orientation``, a spatial hinge's ``axis``)."""
        etype = _element_type(element_type)
        if etype is not None and etype.automatic:
            self._problems.append(f"add_element {number}: the {etype.name} elements "
                                  f"are added by the builder, one per spatial rotational node")
            return self
        if etype is None:
            known = ", ".join(f"{t.name!r}" for t in ELEMENT_TYPES.values() if not t.automatic)
            self._problems.append(f"add_element {number}: the element type must be one of "
                                  f"{known} (or its class or keyword)")
            return self
        try:
            nodes = tuple(nodes)
        except TypeError:
            self._problems.append(f"add_element {number}: nodes must be a sequence of node "
                                  f"numbers, got {nodes!r}")
            return self
        if len(nodes) != len(etype.roles):
            roles = ", ".join(r.name for r in etype.roles)
            self._problems.append(
                f"{etype.name} {number} needs {len(etype.roles)} nodes "
                f"({roles}), got {len(nodes)}"
            )
            return self
        values: dict[str, tuple[float, ...]] = {}
        for name, default in etype.element_data.items():
            value = data.pop(name, default)
            if value is None:
                self._problems.append(f"{etype.name} {number} needs its {name}")
                return self
            try:
                values[name] = tuple(float(v) for v in np.ravel(value))
            except (TypeError, ValueError):
                values[name] = ()
            # a direction's size only scales it; beyond this it would overflow its norm
            if not values[name] or not all(abs(v) <= LARGEST_POSITION for v in values[name]):
                self._problems.append(Problem(
                    f"{etype.name} {number}: {name} {value!r} is not finite numbers "
                    f"of at most {LARGEST_POSITION:g}", ("element", number)))
                return self
        if data:
            takes = ", ".join(etype.element_data) or "nothing besides its nodes"
            self._problems.append(f"{etype.name} {number}: unknown data "
                                  f"{', '.join(data)}; it takes {takes}")
            return self
        self._elements.append((number, etype, nodes, values))
        return self

    def add_truss(self, number: int, p: int, q: int) -> ModelBuilder:
        """Truss between translational nodes ``p`` and ``q`` (PLTRUSS)."""
        return self.add_element(number, Truss, (p, q))

    def add_beam(self, number: int, p: int, phi_p: int, q: int, phi_q: int, *,
                 second_order: bool = False) -> ModelBuilder:
        """Beam from ``p`` to ``q`` with rotational nodes ``phi_p``, ``phi_q`` (PLBEAM).

        With ``second_order`` the large-deflection beam (:class:`~flexmbd.SecondOrderBeam`,
        PLBEAM2): the elongation includes the arc length of the bending and the bending
        deformations are the exact end rotations, needed for accurate buckling loads,
        stiffening by axial load and large deflections; the course's beam otherwise."""
        etype = SecondOrderBeam if checks.flag(second_order, "second_order") else Beam
        return self.add_element(number, etype, (p, phi_p, q, phi_q))

    def add_rigid_beam(self, number: int, p: int, phi_p: int, q: int) -> ModelBuilder:
        """Beam from ``p`` to ``q`` with one rotational node ``phi_p`` at ``p``."""
        return self.add_element(number, RigidBeam, (p, phi_p, q))

    def add_hinge(self, number: int, phi_p: int, phi_q: int) -> ModelBuilder:
        """Hinge between rotational nodes ``phi_p`` and ``phi_q`` (PLHINGE)."""
        return self.add_element(number, Hinge, (phi_p, phi_q))

    def add_spatial_truss(self, number: int, p: int, q: int) -> ModelBuilder:
        """Spatial truss between translational nodes ``p`` and ``q`` (TRUSS)."""
        return self.add_element(number, SpatialTruss, (p, q))

    def add_spatial_beam(self, number: int, p: int, lam_p: int, q: int, lam_q: int,
                         orientation, *, bending_linked: bool = True) -> ModelBuilder:
        """Spatial beam from ``p`` to ``q`` with rotational nodes ``lam_p``, ``lam_q``
        (BEAM). ``orientation`` (3 numbers) is a vector across the beam that fixes its
        local ``y`` axis (``EIy`` bends about it). ``bending_linked`` keeps SPACAR's
        second-order terms of the bending on the elongation and the torsion
        (THEORY-SPATIAL 3); off, the deformations are the basic ones."""
        linked = 1.0 if checks.flag(bending_linked, "bending_linked") else 0.0
        return self.add_element(number, SpatialBeam, (p, lam_p, q, lam_q),
                                orientation=orientation, bending_linked=linked)

    def add_warping_beam(self, number: int, p: int, lam_p: int, w_p: int, q: int, lam_q: int,
                         w_q: int, orientation, *, bending_linked: bool = True
                         ) -> ModelBuilder:
        """Warping beam (BEAMW): a spatial beam (:meth:`add_spatial_beam`) with warping
        nodes ``w_p``, ``w_q``, whose rate of twist ``psi`` [rad/m] is free unless fixed
        (``fix(w_p)`` restrains the warping there). Its warping deformations ``e7``, ``e8``
        are always computed; ``set_stiffness(..., warping=ECw)`` [N m^4] stiffens them."""
        linked = 1.0 if checks.flag(bending_linked, "bending_linked") else 0.0
        return self.add_element(number, WarpingBeam, (p, lam_p, w_p, q, lam_q, w_q),
                                orientation=orientation, bending_linked=linked)

    def add_spatial_beams(self, first: int, p: int, lam_p: int, q: int, lam_q: int,
                          nbeams: int, orientation, *, new_nodes: int, section=None,
                          material=None, dynamic=(1, 2, 3, 4, 5, 6), node_step: int = 2,
                          warping: tuple[int, int] | None = None) -> ModelBuilder:
        """``nbeams`` spatial beams in a row from ``p`` to ``q`` (a leaf spring, a wire),
        elements ``first`` to ``first + nbeams - 1``. The nodes between them are equally spaced
        on the line from ``p`` to ``q`` and numbered from ``new_nodes`` on, a translational
        node and then its rotational node for each, ``node_step`` numbers apart (3 leaves
        a number free for a warping node, as SPACAR Light numbers them). With ``section``
        and ``material`` (:mod:`flexmbd.sections`) each beam gets their stiffness, mass and
        section inertia (:meth:`set_section`); the deformations ``dynamic`` (default all
        six) of each are dynamic degrees of freedom. With ``warping = (w_p, w_q)`` they are
        warping beams (:meth:`add_warping_beam`) from warping node ``w_p`` to ``w_q``, each
        node between them with its warping node two numbers after its translational one
        (``node_step`` 3). ``p`` and ``q`` need their positions first."""
        count = checks.whole(nbeams, "nbeams", 1, 10_000)
        step = checks.whole(node_step, "node_step", 3 if warping else 2, 1_000)
        if p not in self._positions or q not in self._positions:
            self._problems.append(f"add_spatial_beams {first}: nodes {p} and {q} need their "
                                  f"positions (add_node) first")
            return self
        start, end = np.array(self._positions[p]), np.array(self._positions[q])
        chain: list[tuple[int, ...]] = [(p, lam_p, warping[0]) if warping else (p, lam_p)]
        for k in range(1, count):
            node = new_nodes + step * (k - 1)
            self.add_node(node, *(start + (end - start) * k / count))
            chain.append((node, node + 1, node + 2) if warping else (node, node + 1))
        chain.append((q, lam_q, warping[1]) if warping else (q, lam_q))
        self._not_last |= set(range(first, first + count - 1))
        for k in range(count):
            number = first + k
            if warping:
                (a, b, c), (d, f, g) = chain[k], chain[k + 1]
                self.add_warping_beam(number, a, b, c, d, f, g, orientation)
            else:
                (a, b), (d, f) = chain[k], chain[k + 1]
                self.add_spatial_beam(number, a, b, d, f, orientation)
            if section is not None or material is not None:
                self.set_section(number, section, material)
            if dynamic:
                self.dynamic_deformation(number, *dynamic)
        return self

    def add_spatial_hinge(self, number: int, lam_p: int, lam_q: int, axis=(0.0, 0.0, 1.0)
                          ) -> ModelBuilder:
        """Spatial hinge between rotational nodes ``lam_p`` and ``lam_q`` about ``axis``
        (3 numbers, in the reference configuration; HINGE): its rotation ``e1`` and two
        misalignments ``e2, e3``."""
        return self.add_element(number, SpatialHinge, (lam_p, lam_q), axis=axis)

    # --- classification -----------------------------------------------------------
    def _law(self, law, command: str, number: int):
        """A law as given, an expression in t made a law; a bad one is a problem."""
        try:
            law = as_law(law)
        except ArgumentError as error:
            self._problems.append(f"{command} {number}: {error}")
            return None
        if law is not None and not callable(law):
            self._problems.append(f"{command} {number}: law {law!r} is not a law (Polynomial, "
                                  f"Custom, a function of t or an expression in t)")
            return None
        return law

    def _coordinates(self, what, node, directions, law=None, command=""):
        law = self._law(law, command, node)
        if law is not None and len(directions) > 1:
            self._problems.append(
                f"{command} node {node}: a law needs exactly one direction, got {len(directions)}"
            )
            law = None
        for k in directions or (None,):
            self._coordinate_requests.append(_Request(what, node, k, law, command))
        return self

    def _deformations(self, what, element, ks, law=None, command=""):
        law = self._law(law, command, element)
        if law is not None and len(ks) > 1:
            self._problems.append(
                f"{command} element {element}: a law needs exactly one deformation, got {len(ks)}"
            )
            law = None
        for k in ks or (None,):
            self._deformation_requests.append(_Request(what, element, k, law, command))
        return self

    def fix(self, node: int, *directions: int | str) -> ModelBuilder:
        """Fix coordinates of ``node`` (FIX): all of them when no direction is given."""
        return self._coordinates(CoordinateClass.FIXED, node, directions, command="fix")

    def input_coordinate(self, node: int, *directions: int | str, law: Law | None = None
                         ) -> ModelBuilder:
        """Prescribe coordinates of ``node`` as kinematic inputs (INPUTX).

        ``law`` (for one direction) is the default motion, e.g.
        :class:`~flexmbd.motion.Polynomial`; analyses may override it.
        """
        return self._coordinates(CoordinateClass.INPUT, node, directions, law, "input_coordinate")

    def dynamic_coordinate(self, node: int, *directions: int | str) -> ModelBuilder:
        """Make coordinates of ``node`` dynamic degrees of freedom (DYNX)."""
        return self._coordinates(CoordinateClass.DYNAMIC, node, directions,
                                 command="dynamic_coordinate")

    def input_deformation(self, element: int, *ks: int, law: Law | None = None) -> ModelBuilder:
        """Prescribe deformations ``ks`` (1-based) of ``element`` (INPUTE)."""
        return self._deformations(DeformationClass.INPUT, element, ks, law, "input_deformation")

    def dynamic_deformation(self, element: int, *ks: int) -> ModelBuilder:
        """Make deformations ``ks`` of ``element`` dynamic degrees of freedom (DYNE)."""
        return self._deformations(DeformationClass.DYNAMIC, element, ks,
                                  command="dynamic_deformation")

    def release(self, element: int, *ks: int) -> ModelBuilder:
        """Release deformations ``ks`` of ``element`` (RLSE): computed, not constrained."""
        return self._deformations(DeformationClass.RELEASED, element, ks, command="release")

    # --- properties (SPACAR block 2) ------------------------------------------------
    def set_mass(self, element: int, mass_per_length: float,
                 formulation: Literal["consistent", "lumped"] = "consistent", *,
                 section_inertia=None) -> ModelBuilder:
        """Distributed mass ``rhoA`` [kg/m] of an element that has mass: truss, beam, rigid
        beam (EM). ``formulation`` is ``"consistent"`` (default) or ``"lumped"`` (THEORY 5).

        A spatial beam also takes ``section_inertia = (Jxx, Jyy, Jzz, Jyz)`` [kg m] per
        unit length (torsional ``rho (Iy + Iz)``, ``rho Iy``, ``rho Iz``, ``rho Iyz``), lumped
        on its two rotational nodes (THEORY-SPATIAL 4); a warping beam a fifth, ``Jw = rho
        Cw`` [kg m^3], lumped on its warping nodes.
        """
        if section_inertia is not None:
            try:
                inertia = tuple(float(v) for v in section_inertia)
            except (TypeError, ValueError):
                inertia = ()
            if len(inertia) not in (4, 5) or not all(map(math.isfinite, inertia)):
                self._problems.append(f"set_mass element {element}: section_inertia "
                                      f"{section_inertia!r} is not four finite numbers "
                                      f"(Jxx, Jyy, Jzz, Jyz), or five with a warping "
                                      f"beam's Jw")
                return self
            self._section_inertias[element] = inertia
        if formulation not in MASS_FORMULATIONS:
            self._problems.append(f"set_mass element {element}: formulation {formulation!r} "
                                  f"is not 'consistent' or 'lumped'")
        elif not _finite_number(mass_per_length):
            self._problems.append(f"set_mass element {element}: mass_per_length = "
                                  f"{mass_per_length!r} is not a finite number")
        else:
            self._masses[element] = (float(mass_per_length), formulation == "lumped")
        return self

    def _set_values(self, element: int, what: str, values: dict) -> ModelBuilder:
        for name, value in values.items():
            if value is None:
                continue
            if not _finite_number(value):
                self._problems.append(f"set_{what} element {element}: {name} = {value!r} is "
                                      f"not a finite number")
                continue
            self._values.setdefault((element, what), {})[name] = float(value)
        return self

    def set_stiffness(self, element: int, **values: float) -> ModelBuilder:
        """Stiffness values (ESTIFF) by the names the element type takes
        (:attr:`~flexmbd.elements.base.ElementType.stiffness_values`): a truss or rigid
        beam ``axial = EA`` [N]; a beam also ``bending = EI`` [N m^2] and ``shear = G
        A_s`` [N] (Timoshenko correction); a hinge ``hinge`` [N m/rad]; a spring-damper
        ``spring`` [N/m]."""
        return self._set_values(element, "stiffness", values)

    def set_section(self, element: int, section, material) -> ModelBuilder:
        """A spatial beam's stiffness (ESTIFF), mass (EM) and section inertia from its
        cross-section and material (:mod:`flexmbd.sections`: ``Rectangle(w, t)`` with ``w``
        along the orientation vector, ``Circle(d)``, ``Tube(outer, inner)``;
        ``Material(E, G, rho)``), as SPACAR Light computes them. A massless material sets
        no mass; a rigid one (``Material.rigid(rho)``) no stiffness. The warping values
        ``ECw``, ``rhoCw`` go to a warping beam (added before), not to a spatial beam."""
        from .sections import beam_values

        try:
            values = beam_values(section, material)
        except ArgumentError as error:
            self._problems.append(f"set_section element {element}: {error}")
            return self
        self._sections[element] = (section, material)
        warping = self._type_of(element) is WarpingBeam
        if not material.is_rigid:
            self.set_stiffness(element, **values.stiffness,
                               **({"warping": values.estiff[6]} if warping else {}))
        if values.mass_per_length:
            self.set_mass(element, values.mass_per_length,
                          section_inertia=values.section_inertia +
                          ((values.em[5],) if warping else ()))
        return self

    def _type_of(self, element: int) -> type[ElementType] | None:
        """The type of an element added so far (None if not yet added)."""
        return next((t for n, t, _, _ in self._elements if n == element), None)

    def set_damping(self, element: int, **values: float) -> ModelBuilder:
        """Viscous damping (EDAMP), the twins of the stiffnesses: ``axial`` [N s] acts as
        ``axial / l0 * e1dot``, ``bending`` [N m^2 s] with the bending matrix of ``EI``,
        ``hinge`` [N m s/rad], ``spring`` [N s/m]."""
        return self._set_values(element, "damping", values)

    def set_prestress(self, element: int, k: int, sigma0: float) -> ModelBuilder:
        """Pre-stress ``sigma0`` [N or N m] of deformation ``k`` (1-based) of ``element`` (ESIG)."""
        if not _finite_number(sigma0):
            self._problems.append(f"set_prestress element {element}: {sigma0!r} is not a "
                                  f"finite number")
            return self
        self._prestress.setdefault(element, {})[k] = float(sigma0)
        return self

    def add_point_mass(self, node: int, mass: float) -> ModelBuilder:
        """Point mass [kg] on a translational node, or rotary inertia [kg m^2] on a
        rotational node (XM); repeated calls add up."""
        if not _finite_number(mass):
            self._problems.append(f"add_point_mass node {node}: {mass!r} is not a finite number")
            return self
        self._nodal_masses[node] = self._nodal_masses.get(node, 0.0) + float(mass)
        return self

    def add_rotary_inertia(self, node: int, Ixx: float, Ixy: float, Ixz: float, Iyy: float,
                           Iyz: float, Izz: float) -> ModelBuilder:
        """Inertia tensor [kg m^2] of a rigid body on a spatial rotational node (XM with six
        values), in the node's body frame, which is the global frame in the reference
        configuration. Off-diagonal entries are tensor components (minus the products of
        inertia), as SPACAR prints them. Repeated calls add up."""
        values = (Ixx, Ixy, Ixz, Iyy, Iyz, Izz)
        if not all(_finite_number(v) for v in values):
            self._problems.append(f"add_rotary_inertia node {node}: {values!r} are not six "
                                  f"finite numbers")
            return self
        old = self._nodal_inertias.get(node, (0.0,) * 6)
        self._nodal_inertias[node] = tuple(a + float(b) for a, b in zip(old, values,
                                                                       strict=True))
        return self

    def add_force(self, node: int, *components: float) -> ModelBuilder:
        """Constant applied load (XF): ``(Fx, Fy)`` [N] on a translational node or a
        torque ``M`` [N m] on a rotational node; in space ``(Fx, Fy, Fz)`` or a moment
        ``(Mx, My, Mz)`` [N m] in global axes, constant in direction while the node turns
        (its generalized force ``2 E(lam)^T M`` is formed at every state). Repeated calls
        add up."""
        if not all(_finite_number(c) for c in components):
            self._problems.append(f"add_force node {node}: {components!r} are not finite numbers")
            return self
        old = self._nodal_forces.get(node)
        if old is not None and len(old) == len(components):
            components = tuple(a + b for a, b in zip(old, components, strict=True))
        self._nodal_forces[node] = tuple(float(c) for c in components)
        return self

    def set_gravity(self, gx: float, gy: float, gz: float | None = None) -> ModelBuilder:
        """Gravitational acceleration ``(gx, gy)`` [m/s^2] (GRAVITY), e.g. ``(0, -9.81)``;
        ``(gx, gy, gz)`` for a spatial model."""
        given = (gx, gy) if gz is None else (gx, gy, gz)
        if not all(_finite_number(g) for g in given):
            self._problems.append(f"set_gravity: {given!r} is not {len(given)} finite numbers")
            return self
        self._gravity = tuple(float(g) for g in given)
        return self

    # --- building -------------------------------------------------------------------
    def release_overconstraints(self) -> list[tuple[int, int]]:
        """Release over-constraints as SPACAR Light does (FLEXURES 5) and return the
        releases made, ``(element, deformation)``.

        In the initial configuration the SVD of ``D_c`` (rows: rigid, input and dynamic
        deformations; columns: dependent coordinates) counts the over- and
        under-constraints. For each over-constraint, the left singular vector of the
        smallest singular value names the deformations involved, largest first; the first
        that is a dynamic (flexible) deformation of the last beam of a leaf
        (:meth:`add_spatial_beams`; any other beam is its own leaf) and not yet released
        is released. A released deformation keeps its stiffness, so statics and
        compliance do not change. Several valid sets exist; this picks one.

        Raises:
            ModelError: the description has problems other than its count, it is
                under-constrained, or no deformation qualifies for an over-constraint.
        """
        structural = self._element_problems() + self._family_problems()
        kinds = self._node_kinds(structural)
        problems = list(self._problems)
        if structural:
            raise ModelError(problems + structural)
        model = self._assemble(kinds, problems)
        if problems:
            raise ModelError(problems)
        D_x = deformations_and_jacobian(model, np.asarray(model.x0))[1]
        rows = list(model.constrained)
        D_c = D_x[np.ix_(rows, model.dependent)]
        element_of = {i: (number, k + 1) for number, element in model.elements.items()
                      for k, i in enumerate(element.deformations)}
        over, under, null = _over_constraints(D_c)
        if under:
            raise ModelError([f"the model is under-constrained ({under} coordinate(s) free): "
                              f"check the connections, the supports and the releases"])
        releases: list[tuple[int, int]] = []
        while over:
            u = null[:, 0]
            order = np.argsort(-u**2)
            needed = int(np.searchsorted(np.cumsum(u[order] ** 2), np.sqrt(1 - 1e-6))) + 1
            chosen = None
            for at in order[:needed]:
                number, k = element_of[rows[at]]
                element = model.elements[number]
                if (element.type in (SpatialBeam, WarpingBeam) and number not in self._not_last
                        and model.deformation_class[rows[at]] == DeformationClass.DYNAMIC):
                    chosen = at
                    break
            if chosen is None:
                involved = ", ".join(model.describe_deformation(rows[at])
                                     for at in order[:needed])
                raise ModelError([f"{over} over-constraint(s) left that no flexible "
                                  f"deformation of a leaf's last beam can release (they "
                                  f"involve {involved}); release deformations yourself"])
            releases.append(element_of[rows[chosen]])
            del rows[chosen]
            null = _without_row(null, int(chosen))
            over -= 1
        for number, k in releases:
            self._reclassify(number, k)
        return releases

    def _reclassify(self, element: int, k: int) -> None:
        """Release deformation ``k`` of ``element``, taking it out of its dynamic request."""
        kept = []
        for request in self._deformation_requests:
            if request.number == element and request.what == DeformationClass.DYNAMIC and \
                    request.k in (None, k):
                if request.k is None:   # all of them: the others stay dynamic
                    etype = self._type_of(element)
                    assert etype is not None
                    kept += [_Request(request.what, element, j, None, request.command)
                             for j in range(1, etype.n_deformations() + 1)
                             if j != k and j not in etype.calculable]
                continue
            kept.append(request)
        self._deformation_requests = kept
        self.release(element, k)

    def build(self) -> Model:
        """Check the description and return the immutable :class:`Model`.

        Raises:
            ModelError: listing every problem found (unknown nodes, zero-length
                elements, conflicting classes, a degree-of-freedom count that
                does not close, a singular ``D_c`` in the initial configuration).
        """
        # structural problems stop the assembly; every other one is collected with them
        structural: list[str] = []
        structural += self._element_problems()
        structural += self._family_problems()
        kinds = self._node_kinds(structural)
        if structural:
            raise ModelError(self._problems + structural)
        problems = list(self._problems)
        model = self._assemble(kinds, problems)
        if problems:
            raise ModelError(problems)
        problems += check_solvability(model)
        missing = self._flexible_without_stiffness(model)
        hinges = self._flexible_without_stiffness(model, released=True)
        if self.missing_properties == "raise":
            problems += missing
        else:
            self.notes += missing + hinges
            hinges = []
        if problems:
            raise ModelError(problems)
        for hinge in hinges:   # the model builds: say what is probably meant, once
            warnings.warn(str(hinge), ModelWarning, stacklevel=2)
        negative = negative_mass_problem(workspace_of(model)) if any(
            mass < 0 for mass in model.nodal_masses.values()) else None
        if negative:
            raise ModelError([Problem(negative[0], *(("nodal mass", n) for n in negative[1]))])
        self._check_mass(model)
        return model

    def _check_mass(self, model: Model) -> None:
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

    def _flexible_without_stiffness(self, model: Model, released: bool = False
                                    ) -> list[Problem]:
        """A beam's deformation that is a degree of freedom (dynamic: the link is flexible)
        while no stiffness value that sets it was given, neither by ``set_stiffness`` nor
        ``set_section``: it would fold without resistance (a beam's bending at ``e2 ->
        -l``). An explicit zero (``set_stiffness(k, bending=0.0)``) says it is meant.
        With ``released``, the released deformations instead: without stiffness they are
        SPACAR's hinges at a beam's end, often meant, so :meth:`build` only warns."""
        wanted = DeformationClass.RELEASED if released else DeformationClass.DYNAMIC
        problems = []
        for number, element in model.elements.items():
            etype = element.type
            names = [value.name for value in etype.stiffness_values]
            if not any(name.startswith("bending") for name in names):
                continue
            given = self._values.get((number, "stiffness"), {})
            setters = _stiffness_setters(etype, np.asarray(element.reference, dtype=float))
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

    def _node_kinds(self, problems: list[str]) -> dict[int, str]:
        """Kind of every node from its use by elements; reports conflicts."""
        users: dict[int, dict[str, list[str]]] = defaultdict(lambda: defaultdict(list))
        for number, etype, nodes, _ in self._elements:
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
            position = self._positions.get(node)
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
        for node, position in self._positions.items():  # a free point mass, say
            kinds.setdefault(node, SPATIAL_TRANSLATIONAL if len(position) == 3
                             else TRANSLATIONAL)
        for node in kinds:
            if not isinstance(node, (int, np.integer)) or isinstance(node, bool) or node < 1:
                problems.append(f"node number {node!r} is not a positive integer")
        return kinds

    def _family_problems(self) -> list[str]:
        """A model is planar or spatial: name one element (or position) of each kind."""
        planar = [(n, t) for n, t, _, _ in self._elements if not t.is_spatial()]
        spatial = [(n, t) for n, t, _, _ in self._elements if t.is_spatial()]
        if planar and spatial:
            (n1, t1), (n2, t2) = min(planar), min(spatial)
            return [f"the model mixes planar and spatial elements ({t1.name} {n1}, "
                    f"{t2.name} {n2}): build it of one kind"]
        dims = {len(p) for p in self._positions.values()} | (
            {len(self._gravity)} if self._gravity else set())
        if len(dims) > 1:
            return ["positions and gravity mix two and three coordinates: a model is planar "
                    "(x, y) or spatial (x, y, z)"]
        return []

    def _element_problems(self) -> list[str]:
        problems = []
        seen: dict[int, str] = {}
        for number, etype, nodes, _ in self._elements:
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

    def _assemble(self, kinds: dict[int, str], problems: list[str]) -> Model:
        nodes: dict[int, Node] = {}
        labels: list[str] = []
        x0: list[float] = []
        for number in sorted(kinds):
            kind = kinds[number]
            first = len(x0)
            position = self._positions.get(number)
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
        for number, etype, element_nodes, data in sorted(self._elements, key=lambda e: e[0]):
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
        self._check_lengths(elements, self._positions, problems)
        element_properties = self._element_properties(elements, problems)
        first_euler = max(elements, default=0) + 1
        euler_nodes = [n for n in sorted(nodes) if nodes[n].kind == SPATIAL_ROTATIONAL]
        inertias = self._node_inertias(elements)
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
        self._classify(self._coordinate_requests, nodes, "node", self._coordinates_named,
                       labels, coordinate_class, laws, problems)
        self._classify(self._deformation_requests, elements, "element",
                       self._deformations_named, deformation_labels, deformation_class, laws,
                       problems)
        self._check_nodal_loads(nodes, problems)
        return Model(
            name=self.name,
            nodes=FrozenMap(nodes),
            elements=FrozenMap(elements),
            x0=frozen_array(x0_array),
            coordinate_class=frozen_array(coordinate_class),
            deformation_class=frozen_array(deformation_class),
            coordinate_labels=tuple(labels),
            deformation_labels=tuple(deformation_labels),
            input_laws=FrozenMap(laws),
            element_properties=FrozenMap(element_properties),
            nodal_masses=FrozenMap(dict(self._nodal_masses)),
            warping_inertias=FrozenMap(self._warping_masses(elements, nodes)),
            nodal_inertias=FrozenMap(dict(self._nodal_inertias)),
            nodal_forces=FrozenMap(dict(self._nodal_forces)),
            gravity=self._gravity or ((0.0,) * (3 if self._spatial() else 2)),
        )

    def _warping_masses(self, elements, nodes) -> dict[int, float]:
        """The lumped warping inertia ``(l0/2) Jw`` on warping nodes of the warping beams
        with a section inertia, by node."""
        masses: dict[int, float] = {}
        for number, inertia in self._section_inertias.items():
            element = elements.get(number)
            if element is None or not element.type.takes_section_inertia or \
                    len(inertia) < 5:
                continue
            for role, lumped in element.type.section_inertia_on_nodes(element.reference,
                                                                      inertia):
                node = element.nodes[role]
                if lumped.shape == (1, 1) and nodes[node].kind == WARPING and lumped[0, 0]:
                    masses[node] = masses.get(node, 0.0) + float(lumped[0, 0])
        return masses

    def _spatial(self) -> bool:
        return any(t.is_spatial() for _, t, _, _ in self._elements) or any(
            len(p) == 3 for p in self._positions.values())

    def _node_inertias(self, elements) -> dict[int, tuple[float, ...]]:
        """``Jb`` of every spatial rotational node with inertia: its ``XM`` plus the lumped
        rotary inertia ``(l0/2) R0 Jsec R0^T`` of each spatial beam with a section inertia
        (THEORY-SPATIAL 4), as ``(Jxx, Jxy, Jxz, Jyy, Jyz, Jzz)``."""
        tensors: dict[int, np.ndarray] = defaultdict(lambda: np.zeros((3, 3)))
        for node, values in self._nodal_inertias.items():
            tensors[node] += np.array(EulerNormalization.inertia_tensor(values))
        for number, inertia in self._section_inertias.items():
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

    @staticmethod
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

    def _element_properties(self, elements, problems) -> dict[int, ElementProperties]:
        """Properties by element, each checked against what the element's type takes."""
        out = {}
        numbers = {*self._masses, *self._prestress, *(n for n, _ in self._values),
                   *self._section_inertias, *self._sections}
        for number in sorted(numbers):
            if number not in elements:
                problems.append(f"properties given for element {number}, which is not in "
                                f"the model")
                continue
            etype = elements[number].type
            fields: dict[str, Any] = {}
            if number in self._masses:
                rho_a, lumped = self._masses[number]
                if not etype.has_mass:
                    problems.append(f"set_mass element {number}: a {etype.name} has no mass; "
                                    f"put point masses or rotary inertias on its nodes")
                elif rho_a < 0:
                    problems.append(f"set_mass element {number}: mass per length {rho_a} is "
                                    f"negative")
                fields.update(mass_per_length=rho_a, lumped=lumped)
            if number in self._section_inertias:
                if not etype.takes_section_inertia:
                    takers = [t.name for t in ELEMENT_TYPES.values() if t.takes_section_inertia]
                    problems.append(f"set_mass element {number}: a {etype.name} takes no "
                                    f"section inertia (a {' or '.join(takers)} does)")
                fields["section_inertia"] = self._section_inertias[number]
                if len(fields["section_inertia"]) == 5 and not etype.calculable:
                    problems.append(f"set_mass element {number}: a {etype.name} takes four "
                                    f"section inertias (Jxx, Jyy, Jzz, Jyz); Jw is a warping "
                                    f"beam's")
            for what, declared in (("stiffness", etype.stiffness_values),
                                   ("damping", etype.damping_values)):
                values = self._values.get((number, what), {})
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
            nd = etype.n_deformations()
            prestress = [0.0] * nd
            for k, sigma0 in self._prestress.get(number, {}).items():
                if isinstance(k, (int, np.integer)) and 1 <= k <= nd:
                    prestress[k - 1] = sigma0
                else:
                    problems.append(f"set_prestress element {number}: deformation {k!r} does "
                                    f"not exist; a {etype.name} has deformations 1 to {nd}")
            if number in self._prestress:
                fields["prestress"] = tuple(prestress)
            if number in self._sections:
                fields["section"], fields["material"] = self._sections[number]
            out[number] = ElementProperties(**fields)
        return out

    def _check_nodal_loads(self, nodes, problems) -> None:
        tables: tuple[tuple[str, dict[int, Any]], ...] = (
            ("add_point_mass", self._nodal_masses), ("add_force", self._nodal_forces),
            ("add_rotary_inertia", self._nodal_inertias))
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

    @staticmethod
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

    @staticmethod
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

    @staticmethod
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


def _over_constraints(D_c: np.ndarray) -> tuple[int, int, np.ndarray]:
    """Over- and under-constraints of ``D_c`` ``(m, n)`` (:func:`_constraint_counts`) and an
    orthonormal basis of its left null space ``(m, over)``, from one factorisation:
    releasing a row keeps the null vectors that vanish on it (:func:`_without_row`; a
    factorisation per release would cost the cube of the rows each time). With full
    column rank (the usual case, shown by ``R`` clearly regular) the complete QR gives
    the basis at a quarter of the SVD's cost; otherwise the SVD decides."""
    rows, cols = D_c.shape
    if rows >= cols > 0:
        Q, R = np.linalg.qr(D_c, mode="complete")
        if clearly_regular(R[:cols], float(np.sqrt(np.finfo(float).eps))):
            return rows - cols, 0, Q[:, cols:]
    if not D_c.size:
        return *_constraint_counts(D_c), np.eye(rows)[:, :max(rows - cols, 0)]
    U, values = np.linalg.svd(D_c)[:2]
    over, under = _constraint_counts(D_c, values)
    return over, under, U[:, rows - over:]


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


def _without_row(null: np.ndarray, row: int) -> np.ndarray:
    """An orthonormal basis ``(m - 1, k - 1)`` of the left null space of ``D_c`` without
    ``row``, from one of ``D_c``'s ``(m, k)``: the combinations of ``null`` that vanish on
    ``row``, that entry dropped. The column largest on ``row`` eliminates it from the
    others."""
    pivot = int(np.argmax(np.abs(null[row])))
    rest = np.delete(null, pivot, axis=1)
    rest = rest - np.outer(null[:, pivot], rest[row] / null[row, pivot])
    return np.linalg.qr(np.delete(rest, row, axis=0))[0]


def _constraint_counts(D_c: np.ndarray, values: np.ndarray | None = None
                       ) -> tuple[int, int]:
    """Over- and under-constraints of ``D_c`` (FLEXURES 5): singular values below
    ``sqrt(eps)`` of the largest count in both (``values``, when the caller has them),
    and a surplus of rows (columns) adds to the over- (under-) constraints."""
    rows, cols = D_c.shape
    if not rows or not cols:
        return rows, cols
    if values is None:
        values = np.linalg.svd(D_c, compute_uv=False)
    singular = int(np.sum(values < np.sqrt(np.finfo(float).eps) * values[0])) + \
        (min(rows, cols) - len(values))
    return max(rows - cols, 0) + singular, max(cols - rows, 0) + singular


def check_solvability(model: Model) -> list[Problem]:
    """Problems with the square, nonsingular ``D_c`` required by THEORY section 3.

    Counts rows (rigid and independent deformations) against columns (dependent
    coordinates) and, through the singular value decomposition of ``D_c`` in the
    initial configuration, names the coordinates that the constraints leave
    free and the deformations whose equations are redundant.
    """

    rows, cols = len(model.constrained), len(model.dependent)
    if rows == cols == 0:
        return []
    if rows and cols:
        D_x = deformations_and_jacobian(model, np.asarray(model.x0))[1]
        text, free, redundant = diagnose_rank(model, D_x[np.ix_(model.constrained,
                                                                model.dependent)])
    elif rows:
        free, redundant = np.zeros(0, dtype=int), model.constrained
        names = ", ".join(model.describe_deformation(i) for i in model.constrained)
        text = f"the equations of {names} have no dependent coordinate to solve for"
    else:
        free, redundant = model.dependent, np.zeros(0, dtype=int)
        names = ", ".join(model.describe_coordinate(i) for i in model.dependent)
        text = f"nothing determines the coordinates {names}"
    about = [*(("coordinate", model.coordinate_labels[i]) for i in free),
             *(("deformation", model.deformation_labels[i]) for i in redundant)]
    if rows == cols:
        return [Problem(f"D_c is singular in the initial configuration: {text}", *about)] \
            if text else []
    excess = abs(rows - cols)
    if rows > cols:
        advice = (f"{excess} equation(s) too many; release {excess} deformation(s) or make "
                  f"{excess} fixed/input coordinate(s) dependent")
    else:
        advice = (f"{excess} equation(s) too few; fix {excess} coordinate(s), make them inputs "
                  f"or dynamic, or add elements")
    count = (f"the degree-of-freedom count does not close: {rows} constraint equations (rigid "
             f"and independent deformations) for {cols} dependent coordinates, {advice}")
    return [Problem(f"{count} ({text})" if text else count, *about)]
