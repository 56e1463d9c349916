"""Recording a mechanism: :class:`ModelBuilder`, what the user said, in any order.

Every call records its values (:class:`Records`) and notes the problems of the call
itself; :meth:`ModelBuilder.build` has them checked all at once
(:mod:`flexmbd.builder.validation`) and the constraints examined
(:mod:`flexmbd.builder.constraints`), and raises one
:class:`~flexmbd.errors.ModelError` that lists every problem, naming the nodes,
elements and coordinates involved.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np

from .. import checks
from ..elements import (
    ELEMENT_TYPES,
    Beam,
    ElementType,
    Hinge,
    RigidBeam,
    SecondOrderBeam,
    SpatialBeam,
    SpatialHinge,
    SpatialTruss,
    Truss,
    WarpingBeam,
)
from ..engine import workspace_of
from ..engine.diagnosis import negative_mass_problem
from ..errors import ArgumentError, ModelError, ModelWarning, Problem
from ..model import CoordinateClass, DeformationClass, Model
from ..motion import Law, as_law
from . import validation
from .constraints import check_solvability, overconstraint_releases

#: the releases a design keeps while its parameters change (:func:`kept_releases`)
_KEPT_RELEASES: ContextVar[dict | None] = ContextVar("kept_releases", default=None)


@contextmanager
def kept_releases() -> Iterator[dict]:
    """Within this context the first :meth:`ModelBuilder.release_overconstraints` chooses
    its releases and every later one makes the same: the designs of one sensitivity
    analysis (:mod:`flexmbd.design`) keep one structure, where a choice among equally
    valid sets could otherwise change with a small change of the geometry."""
    holder: dict = {"releases": None}
    token = _KEPT_RELEASES.set(holder)
    try:
        yield holder
    finally:
        _KEPT_RELEASES.reset(token)


#: whether a build is a design's neighbour (:func:`neighbour_builds`)
_NEIGHBOURS: ContextVar[bool] = ContextVar("neighbour_builds", default=False)


@contextmanager
def neighbour_builds() -> Iterator[None]:
    """Within this context :meth:`ModelBuilder.build` checks the values only (as
    :func:`~flexmbd.builder.validation.assemble_checked` does), not the constraints'
    solvability, the masses or missing stiffness: the builds of a design's neighbours
    (``theta + h``, :mod:`flexmbd.design`), whose data alone are read, of a design that
    passed every check."""
    token = _NEIGHBOURS.set(True)
    try:
        yield
    finally:
        _NEIGHBOURS.reset(token)


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
class Request:
    """One classification request: class ``what`` for entry ``k`` of node/element ``number``."""

    what: CoordinateClass | DeformationClass
    number: int
    k: int | str | None
    law: Law | None
    command: str
    #: the law gives a planar node's absolute angle, not the increment from the drawn one
    absolute: bool = False


@dataclass
class Records:
    """What the user said, as :class:`ModelBuilder` records it: every call's values, in any
    order, and the problems found in the calls themselves (a position that is not
    numbers); the rest is checked at :meth:`ModelBuilder.build`
    (:mod:`flexmbd.builder.validation`)."""

    name: str
    positions: dict[int, tuple[float, ...]] = field(default_factory=dict)
    #: (number, type, nodes, element data) in the order added
    elements: list[tuple[int, type[ElementType], tuple[int, ...], dict]] = field(
        default_factory=list)
    coordinate_requests: list[Request] = field(default_factory=list)
    deformation_requests: list[Request] = field(default_factory=list)
    #: element -> (mass per length [kg/m], lumped)
    masses: dict[int, tuple[float, bool]] = field(default_factory=dict)
    #: (element, "stiffness" or "damping") -> values by name
    values: dict[tuple[int, str], dict[str, float]] = field(default_factory=dict)
    prestress: dict[int, dict[int, float]] = field(default_factory=dict)
    nodal_masses: dict[int, float] = field(default_factory=dict)
    nodal_inertias: dict[int, tuple[float, ...]] = field(default_factory=dict)
    section_inertias: dict[int, tuple[float, ...]] = field(default_factory=dict)
    sections: dict[int, tuple[Any, Any]] = field(default_factory=dict)
    #: elements whose stiffness came from set_section (consistent by construction)
    from_section: set[int] = field(default_factory=set)
    #: the beams of a chain (add_spatial_beams) but its last
    not_last: set[int] = field(default_factory=set)
    nodal_forces: dict[int, tuple[float, ...]] = field(default_factory=dict)
    gravity: tuple[float, ...] = ()
    problems: list[str] = field(default_factory=list)


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
        self._records = Records(name)
        #: what :meth:`build` does with a property the classification needs but that was
        #: left out (a flexible beam's stiffness): ``"raise"`` it with the other problems,
        #: or ``"note"`` it in :attr:`notes` (a SPACAR file, which cannot say a zero is
        #: meant)
        self.missing_properties: Literal["raise", "note"] = "raise"
        #: whether set_section warns about a material whose numbers point at another unit
        #: (flexmbd.light says it itself, in its fields' names)
        self.unit_doubts: Literal["warn", "off"] = "warn"
        self.notes: list[str] = []

    def _problem(self, problem: str) -> None:
        """Note a problem of a call, for :meth:`build` to raise with the others."""
        self._records.problems.append(problem)

    @property
    def name(self) -> str:
        """The model's name, for messages and plots."""
        return self._records.name

    @name.setter
    def name(self, value: str) -> None:
        self._records.name = value

    # --- nodes and elements -----------------------------------------------------
    def add_node(self, number: int, x: float, y: float, z: float | None = None
                 ) -> ModelBuilder:
        """Translational node ``number`` at ``(x, y)`` [m] in the initial configuration, or
        at ``(x, y, z)`` for a spatial model."""
        if number in self._records.positions:
            self._problem(Problem(f"node {number} is given a position twice",
                                          ("node", number)))
        given = (x, y) if z is None else (x, y, z)
        try:
            position = tuple(float(v) for v in given)
        except (TypeError, ValueError):
            self._problem(Problem(f"node {number}: position {given!r} is not "
                                          f"{len(given)} numbers", ("node", number)))
            return self
        if not all(abs(v) <= LARGEST_POSITION for v in position):
            self._problem(Problem(f"node {number}: position {position} is not finite "
                                          f"or beyond {LARGEST_POSITION:g} m",
                                          ("node", number)))
        self._records.positions[number] = position
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
            self._problem(f"add_element {number}: the {etype.name} elements "
                                  f"are added by the builder, one per spatial rotational node")
            return self
        if etype is None:
            known = ", ".join(f"{t.name!r}" for t in ELEMENT_TYPES.values() if not t.automatic)
            self._problem(f"add_element {number}: the element type must be one of "
                                  f"{known} (or its class or keyword)")
            return self
        try:
            nodes = tuple(nodes)
        except TypeError:
            self._problem(f"add_element {number}: nodes must be a sequence of node "
                                  f"numbers, got {nodes!r}")
            return self
        if len(nodes) != len(etype.roles):
            roles = ", ".join(r.name for r in etype.roles)
            self._problem(
                f"{etype.name} {number} needs {len(etype.roles)} nodes "
                f"({roles}), got {len(nodes)}"
            )
            return self
        values: dict[str, tuple[float, ...]] = {}
        for name, default in etype.element_data.items():
            value = data.pop(name, default)
            if value is None:
                self._problem(f"{etype.name} {number} needs its {name}")
                return self
            try:
                values[name] = tuple(float(v) for v in np.ravel(value))
            except (TypeError, ValueError):
                values[name] = ()
            # a direction's size only scales it; beyond this it would overflow its norm
            if not values[name] or not all(abs(v) <= LARGEST_POSITION for v in values[name]):
                self._problem(Problem(
                    f"{etype.name} {number}: {name} {value!r} is not finite numbers "
                    f"of at most {LARGEST_POSITION:g}", ("element", number)))
                return self
        if data:
            takes = ", ".join(etype.element_data) or "nothing besides its nodes"
            self._problem(f"{etype.name} {number}: unknown data "
                                  f"{', '.join(data)}; it takes {takes}")
            return self
        self._records.elements.append((number, etype, nodes, values))
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
        if p not in self._records.positions or q not in self._records.positions:
            self._problem(f"add_spatial_beams {first}: nodes {p} and {q} need their "
                                  f"positions (add_node) first")
            return self
        start, end = np.array(self._records.positions[p]), np.array(self._records.positions[q])
        chain: list[tuple[int, ...]] = [(p, lam_p, warping[0]) if warping else (p, lam_p)]
        for k in range(1, count):
            node = new_nodes + step * (k - 1)
            self.add_node(node, *(start + (end - start) * k / count))
            chain.append((node, node + 1, node + 2) if warping else (node, node + 1))
        chain.append((q, lam_q, warping[1]) if warping else (q, lam_q))
        self._records.not_last |= set(range(first, first + count - 1))
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
            self._problem(f"{command} {number}: {error}")
            return None
        if law is not None and not callable(law):
            self._problem(f"{command} {number}: law {law!r} is not a law (Polynomial, "
                                  f"Custom, a function of t or an expression in t)")
            return None
        return law

    def _coordinates(self, what, node, directions, law=None, command="", absolute=False):
        law = self._law(law, command, node)
        if law is not None and len(directions) > 1:
            self._problem(
                f"{command} node {node}: a law needs exactly one direction, got {len(directions)}"
            )
            law = None
        for k in directions or (None,):
            self._records.coordinate_requests.append(Request(what, node, k, law, command,
                                                             absolute))
        return self

    def _deformations(self, what, element, ks, law=None, command=""):
        law = self._law(law, command, element)
        if law is not None and len(ks) > 1:
            self._problem(
                f"{command} element {element}: a law needs exactly one deformation, got {len(ks)}"
            )
            law = None
        for k in ks or (None,):
            self._records.deformation_requests.append(Request(what, element, k, law, command))
        return self

    def fix(self, node: int, *directions: int | str) -> ModelBuilder:
        """Fix coordinates of ``node`` (FIX): all of them when no direction is given."""
        return self._coordinates(CoordinateClass.FIXED, node, directions, command="fix")

    def input_coordinate(self, node: int, *directions: int | str, law: Law | None = None,
                         absolute: bool = False) -> ModelBuilder:
        """Prescribe coordinates of ``node`` as kinematic inputs (INPUTX).

        ``law`` (for one direction) is the default motion, e.g.
        :class:`~flexmbd.motion.Polynomial`; analyses may override it. A law gives the
        coordinate's value: a position is absolute [m], but a planar node's angle counts
        from the drawn orientation [rad] (the elements hold the drawn angles), so a crank
        drawn at 90 degrees starts as drawn with ``Polynomial(0, omega)``;
        ``Polynomial(pi/2, omega)`` would start it at 180 degrees (the build warns when a
        law starts at the drawn angle itself, the likely slip). With ``absolute=True`` the
        law gives the angle of the node's elements instead, ``Polynomial(pi/2, omega)``
        starting the crank as drawn: the model keeps the increment (a ``Polynomial``
        stays one, so its ``.dat`` file says the same); the elements on the node must be
        drawn at one angle. Positions and spatial rotations are absolute already.
        """
        return self._coordinates(CoordinateClass.INPUT, node, directions, law,
                                 "input_coordinate", checks.flag(absolute, "absolute"))

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
        Cw`` [kg m^3], lumped on its warping nodes; a planar beam one, ``(rhoI,)`` [kg m],
        the rotary inertia of its cross-section, half of ``l0 rhoI`` on each rotational
        node.
        """
        if section_inertia is not None:
            try:
                inertia = tuple(float(v) for v in section_inertia)
            except (TypeError, ValueError):
                inertia = ()
            if len(inertia) not in (1, 4, 5) or not all(map(math.isfinite, inertia)):
                self._problem(f"set_mass element {element}: section_inertia "
                                      f"{section_inertia!r} is not four finite numbers "
                                      f"(Jxx, Jyy, Jzz, Jyz), five with a warping "
                                      f"beam's Jw, or a planar beam's one (rhoI)")
                return self
            self._records.section_inertias[element] = inertia
        if formulation not in MASS_FORMULATIONS:
            self._problem(f"set_mass element {element}: formulation {formulation!r} "
                                  f"is not 'consistent' or 'lumped'")
        elif not _finite_number(mass_per_length):
            self._problem(f"set_mass element {element}: mass_per_length = "
                                  f"{mass_per_length!r} is not a finite number")
        else:
            self._records.masses[element] = (float(mass_per_length), formulation == "lumped")
        return self

    def _set_values(self, element: int, what: str, values: dict) -> ModelBuilder:
        for name, value in values.items():
            if value is None:
                continue
            if not _finite_number(value):
                self._problem(f"set_{what} element {element}: {name} = {value!r} is "
                                      f"not a finite number")
                continue
            self._records.values.setdefault((element, what), {})[name] = float(value)
        return self

    def set_stiffness(self, element: int, **values: float) -> ModelBuilder:
        """Stiffness values (ESTIFF) by the names the element type takes
        (:attr:`~flexmbd.elements.base.ElementType.stiffness_values`): a truss or rigid
        beam ``axial = EA`` [N]; a beam also ``bending = EI`` [N m^2] and ``shear = G
        A_s`` [N] (Timoshenko correction); a hinge ``hinge`` [N m/rad]; a spring-damper
        ``spring`` [N/m]."""
        return self._set_values(element, "stiffness", values)

    def set_section(self, element: int, section, material) -> ModelBuilder:
        """A beam's stiffness (ESTIFF), mass (EM) and section inertia from its
        cross-section and material (:mod:`flexmbd.sections`: ``Rectangle(w, t)`` with ``w``
        along the orientation vector, ``Circle(d)``, ``Tube(outer, inner)``;
        ``Material(E, G, rho)``), as SPACAR Light computes them. A massless material sets
        no mass; a rigid one (``Material.rigid(rho)``) no stiffness. The warping values
        ``ECw``, ``rhoCw`` go to a warping beam (added before), not to a spatial beam.

        A planar beam (added before) bends in its plane, so ``Rectangle(w, t)`` has its
        width ``w`` across the plane and its thickness ``t`` in it: ``axial = E A``,
        ``bending = E w t^3 / 12``, ``shear = k G A`` [N] (SPACAR's planar shear
        stiffness ``G A_s``, ``k`` the section's shear factor), ``rhoA`` and the rotary
        inertia ``rho w t^3 / 12`` per length.

        A truss or a rigid beam takes ``axial = E A`` and ``rhoA`` (a spatial rigid beam
        also its section inertia); a hinge or a spring has no section, and is refused."""
        from ..sections import beam_values

        try:
            values = beam_values(section, material)
        except ArgumentError as error:
            self._problem(f"set_section element {element}: {error}")
            return self
        if self.unit_doubts == "warn":
            for doubt in material.doubts():   # said once per material (same message)
                warnings.warn(f"set_section: {material}: {doubt}", ModelWarning, stacklevel=2)
        etype = self._type_of(element)
        takes = {v.name for v in etype.stiffness_values} if etype is not None else set()
        if etype is not None and not (etype.has_mass or "axial" in takes):
            self._problem(f"set_section element {element}: a {etype.name} has no "
                          f"cross-section; give its stiffness with set_stiffness("
                          f"{', '.join(f'{name}=...' for name in sorted(takes))})")
            return self
        self._records.from_section.add(element)
        if etype is not None and takes <= {"axial"}:   # a truss or rigid beam: E A, rho A
            if not material.is_rigid and takes:
                self.set_stiffness(element, axial=values.estiff[0])
            if values.mass_per_length:
                self.set_mass(element, values.mass_per_length, section_inertia=(
                    values.section_inertia if etype.takes_section_inertia else None))
            return self
        if etype is not None and issubclass(etype, Beam):   # planar: bending about z
            if not material.is_rigid:
                bending, flexibility = values.estiff[2], values.estiff[4]
                self.set_stiffness(element, axial=values.estiff[0], bending=bending,
                                   shear=bending / flexibility if flexibility else 0.0)
            if values.mass_per_length:
                self.set_mass(element, values.mass_per_length,
                              section_inertia=(values.em[2],))
            return self
        self._records.sections[element] = (section, material)
        warping = etype is WarpingBeam
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
        return next((t for n, t, _, _ in self._records.elements if n == element), None)

    def set_damping(self, element: int, **values: float) -> ModelBuilder:
        """Viscous damping (EDAMP), the twins of the stiffnesses: ``axial`` [N s] acts as
        ``axial / l0 * e1dot``, ``bending`` [N m^2 s] with the bending matrix of ``EI``,
        ``hinge`` [N m s/rad], ``spring`` [N s/m]."""
        return self._set_values(element, "damping", values)

    def set_prestress(self, element: int, k: int, sigma0: float) -> ModelBuilder:
        """Pre-stress ``sigma0`` [N or N m] of deformation ``k`` (1-based) of ``element`` (ESIG)."""
        if not _finite_number(sigma0):
            self._problem(f"set_prestress element {element}: {sigma0!r} is not a "
                                  f"finite number")
            return self
        self._records.prestress.setdefault(element, {})[k] = float(sigma0)
        return self

    def add_point_mass(self, node: int, mass: float) -> ModelBuilder:
        """Point mass [kg] on a translational node, or rotary inertia [kg m^2] on a
        rotational node (XM); repeated calls add up."""
        if not _finite_number(mass):
            self._problem(f"add_point_mass node {node}: {mass!r} is not a finite number")
            return self
        self._records.nodal_masses[node] = self._records.nodal_masses.get(node, 0.0) + float(mass)
        return self

    def add_rotary_inertia(self, node: int, Ixx: float, Ixy: float, Ixz: float, Iyy: float,
                           Iyz: float, Izz: float) -> ModelBuilder:
        """Inertia tensor [kg m^2] of a rigid body on a spatial rotational node (XM with six
        values), in the node's body frame, which is the global frame in the reference
        configuration. Off-diagonal entries are tensor components (minus the products of
        inertia), as SPACAR prints them. Repeated calls add up."""
        values = (Ixx, Ixy, Ixz, Iyy, Iyz, Izz)
        if not all(_finite_number(v) for v in values):
            self._problem(f"add_rotary_inertia node {node}: {values!r} are not six "
                                  f"finite numbers")
            return self
        old = self._records.nodal_inertias.get(node, (0.0,) * 6)
        self._records.nodal_inertias[node] = tuple(a + float(b) for a, b in zip(old, values,
                                                                       strict=True))
        return self

    def add_force(self, node: int, *components: float) -> ModelBuilder:
        """Constant applied load (XF): ``(Fx, Fy)`` [N] on a translational node or a
        torque ``M`` [N m] on a rotational node; in space ``(Fx, Fy, Fz)`` or a moment
        ``(Mx, My, Mz)`` [N m] in global axes, constant in direction while the node turns
        (its generalized force ``2 E(lam)^T M`` is formed at every state). Repeated calls
        add up."""
        if not all(_finite_number(c) for c in components):
            self._problem(f"add_force node {node}: {components!r} are not finite numbers")
            return self
        old = self._records.nodal_forces.get(node)
        if old is not None and len(old) == len(components):
            components = tuple(a + b for a, b in zip(old, components, strict=True))
        self._records.nodal_forces[node] = tuple(float(c) for c in components)
        return self

    def set_gravity(self, gx: float, gy: float, gz: float | None = None) -> ModelBuilder:
        """Gravitational acceleration ``(gx, gy)`` [m/s^2] (GRAVITY), e.g. ``(0, -9.81)``;
        ``(gx, gy, gz)`` for a spatial model."""
        given = (gx, gy) if gz is None else (gx, gy, gz)
        if not all(_finite_number(g) for g in given):
            self._problem(f"set_gravity: {given!r} is not {len(given)} finite numbers")
            return self
        self._records.gravity = tuple(float(g) for g in given)
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
        kept = _KEPT_RELEASES.get()
        if kept is not None and kept["releases"] is not None:
            releases = list(kept["releases"])   # the design's first choice (kept_releases)
        else:
            model = validation.assemble_checked(self._records)
            releases = overconstraint_releases(model, self._records.not_last)
            if kept is not None:
                kept["releases"] = list(releases)
        for number, k in releases:
            self._reclassify(number, k)
        return releases

    def _reclassify(self, element: int, k: int) -> None:
        """Release deformation ``k`` of ``element``, taking it out of its dynamic request."""
        kept = []
        for request in self._records.deformation_requests:
            if request.number == element and request.what == DeformationClass.DYNAMIC and \
                    request.k in (None, k):
                if request.k is None:   # all of them: the others stay dynamic
                    etype = self._type_of(element)
                    assert etype is not None
                    kept += [Request(request.what, element, j, None, request.command)
                             for j in range(1, etype.n_deformations() + 1)
                             if j != k and j not in etype.calculable]
                continue
            kept.append(request)
        self._records.deformation_requests = kept
        self.release(element, k)

    def assemble(self) -> tuple[Model, list[str]]:
        """The model as described, with the problems of its constraints (a
        degree-of-freedom count that does not close, a singular ``D_c``) listed instead
        of refused: what SPACAR's mode 0 stores to show them (``D_x`` at the initial
        configuration). Use :meth:`build` for a model to analyse.

        Raises:
            ModelError: any other problem of the description.
        """
        model = validation.assemble_checked(self._records)
        return model, [str(problem) for problem in check_solvability(model)]

    def build(self) -> Model:
        """Check the description and return the immutable :class:`Model`.

        Raises:
            ModelError: listing every problem found (unknown nodes, zero-length
                elements, conflicting classes, a degree-of-freedom count that
                does not close, a singular ``D_c`` in the initial configuration).
        """
        model = validation.assemble_checked(self._records)
        if _NEIGHBOURS.get():   # a checked design's neighbour: its data only are read
            return model
        problems: list[str] = list(check_solvability(model))
        missing = validation.flexible_without_stiffness(self._records, model)
        hinges = validation.flexible_without_stiffness(self._records, model, released=True)
        if self.missing_properties == "raise":
            problems += missing
        else:
            self.notes += missing + hinges
            hinges = []
        if problems:
            raise ModelError(problems)
        for hinge in hinges:   # the model builds: say what is probably meant, once
            warnings.warn(str(hinge), ModelWarning, stacklevel=2)
        for slip in validation.absolute_slips(self._records, model):
            warnings.warn(slip, ModelWarning, stacklevel=2)
        negative = negative_mass_problem(workspace_of(model)) if any(
            mass < 0 for mass in model.nodal_masses.values()) else None
        if negative:
            raise ModelError([Problem(negative[0], *(("nodal mass", n) for n in negative[1]))])
        validation.warn_massless(model)
        return model
