"""The element contract: an element type is one small class, written once.

A type declares

* its nodes (:attr:`ElementType.roles`: kind and name in connection order) and the
  names of its deformations;
* its deformation functions, in :meth:`ElementType.deformations`, once, with the
  math functions passed in (SymPy for the code generator and the symbolic path,
  numpy where a test evaluates them directly);
* its reference parameters (``length``, ``angle`` of the initial chord);
* its properties: which stiffness and damping values it takes, in the order of
  the ``.dat`` keywords ``ESTIFF`` and ``EDAMP``, and the linear elastic law
  they make (:meth:`ElementType.elastic_law`);
* its mass: the material point of a consistent mass
  (:meth:`ElementType.material_point`) and the lumped nodal masses;
* how it is drawn (:meth:`ElementType.outline`).

Everything else follows from these: the compiled kernels (deformations with their
Jacobian, the quadratic velocity terms, the Hessians, the mass matrix, the
velocity-dependent inertia and the gravity load) are generated from
:meth:`~ElementType.deformations` and :meth:`~ElementType.material_point` by
:mod:`flexmbd.codegen`; the builder, the ``.dat`` reader and writer and the plots
ask the class. A new type is one file and a line in :mod:`flexmbd.elements`.
"""

from __future__ import annotations

from dataclasses import dataclass
from types import ModuleType
from typing import Any, ClassVar

import numpy as np

TRANSLATIONAL = "translational"
ROTATIONAL = "rotational"
#: number of coordinates carried by a node of each kind
COORDINATES_PER_NODE = {TRANSLATIONAL: 2, ROTATIONAL: 1}
#: names of the reference parameters an element type may use, in storage order
REFERENCE_NAMES = ("length", "angle")


@dataclass(frozen=True)
class Role:
    """A node of an element: its kind and its name in messages (``"p"``, ``"phi_p"``)."""

    name: str
    kind: str


def translational(name: str) -> Role:
    """A translational node ``(x, y)`` [m]."""
    return Role(name, TRANSLATIONAL)


def rotational(name: str) -> Role:
    """A rotational node: one angle [rad] from the reference configuration."""
    return Role(name, ROTATIONAL)


@dataclass(frozen=True)
class Value:
    """A stiffness or damping value an element type takes.

    Attributes:
        name: the keyword of :meth:`flexmbd.ModelBuilder.set_stiffness` or
            ``set_damping`` (``"axial"``, ``"bending"``, ...).
        symbol: the usual symbol (``"EA"``), for messages and the ``.dat`` syntax.
        unit: SI unit of the value.
    """

    name: str
    symbol: str
    unit: str


class ElementType:
    """Base class of the planar element types (see the module docstring).

    Class attributes:
        name: short name used in messages (``"truss"``).
        keyword: the SPACAR input-file keyword (``"PLTRUSS"``).
        roles: the nodes in connection order.
        deformation_names: one name per deformation parameter.
        deformation_units: the SI unit of each (``"m"`` or ``"rad"``); a stress of a
            length is a force [N], of an angle a moment [N m].
        reference: how many of :data:`REFERENCE_NAMES` the definition uses (0 to 2).
        stiffness_values, damping_values: the values of ``ESTIFF`` and ``EDAMP``, in
            their order in a ``.dat`` line.
        has_mass: whether the type takes a distributed mass (``EM``).
        released_by_default: deformations are released, not rigid, unless classified
            (force elements such as springs).
    """

    name: ClassVar[str]
    keyword: ClassVar[str]
    roles: ClassVar[tuple[Role, ...]]
    deformation_names: ClassVar[tuple[str, ...]]
    deformation_units: ClassVar[tuple[str, ...]]
    reference: ClassVar[int] = 2
    stiffness_values: ClassVar[tuple[Value, ...]] = ()
    damping_values: ClassVar[tuple[Value, ...]] = ()
    has_mass: ClassVar[bool] = False
    released_by_default: ClassVar[bool] = False

    # --- sizes -------------------------------------------------------------------------
    @classmethod
    def n_coordinates(cls) -> int:
        return sum(COORDINATES_PER_NODE[r.kind] for r in cls.roles)

    @classmethod
    def n_deformations(cls) -> int:
        return len(cls.deformation_names)

    @classmethod
    def node_kinds(cls) -> tuple[str, ...]:
        return tuple(r.kind for r in cls.roles)

    @classmethod
    def ends(cls) -> tuple[int, int] | None:
        """Columns of ``r_p`` and ``r_q`` (each two wide) in the element coordinates, or
        ``None`` for a type with fewer than two translational nodes."""
        columns, at = [], 0
        for role in cls.roles:
            if role.kind == TRANSLATIONAL:
                columns.append(at)
            at += COORDINATES_PER_NODE[role.kind]
        return (columns[0], columns[1]) if len(columns) >= 2 else None

    @classmethod
    def reference_parameters(cls, xe0: np.ndarray) -> np.ndarray:
        """The reference parameters ``(n, reference)`` from the initial element
        coordinates ``xe0`` ``(n, nc)``: the length ``l0`` [m] and the angle ``beta0``
        [rad] of the chord from ``r_p`` to ``r_q``."""
        xe0 = np.atleast_2d(np.asarray(xe0, dtype=float))
        ends = cls.ends()
        if ends is None:
            return np.zeros((len(xe0), cls.reference))
        d = xe0[:, ends[1]:ends[1] + 2] - xe0[:, ends[0]:ends[0] + 2]
        both = np.stack([np.hypot(d[:, 0], d[:, 1]), np.arctan2(d[:, 1], d[:, 0])], axis=1)
        return both[:, :cls.reference]

    # --- the single definition --------------------------------------------------------
    @staticmethod
    def deformations(c: list[Any], p: list[Any], m: ModuleType) -> list[Any]:
        """Deformation parameters as expressions of the element coordinates ``c`` and the
        reference parameters ``p`` (``[l0, beta0]``, as many as :attr:`reference`).

        ``m`` is the module that supplies ``sqrt``, ``sin``, ``cos`` and ``atan2``:
        ``sympy``, for the kernel generator and the symbolic path.
        """
        raise NotImplementedError

    @staticmethod
    def material_point(c: list[Any], p: list[Any], xi: Any, m: ModuleType) -> list[Any]:
        """Position ``(x, y)`` of the material point at ``xi`` in [0, 1] from ``r_p`` to
        ``r_q``, from which the consistent mass, the velocity-dependent inertia and
        the gravity load follow (``M = m int N^T N dxi`` with ``N`` its derivative
        with respect to ``c``, THEORY 5). Types with mass define it."""
        raise NotImplementedError

    @classmethod
    def lumped_masses(cls, p: np.ndarray, mass: np.ndarray) -> np.ndarray:
        """Diagonal of the lumped mass matrix ``(n, nc)`` [kg, kg m^2] for element masses
        ``mass`` ``(n,)``: half the mass at each translational end node."""
        out = np.zeros((len(mass), cls.n_coordinates()))
        ends = cls.ends()
        if ends is not None:
            for column in (*range(ends[0], ends[0] + 2), *range(ends[1], ends[1] + 2)):
                out[:, column] = 0.5 * mass
        return out

    # --- properties ---------------------------------------------------------------------
    @classmethod
    def elastic_law(cls, p: np.ndarray, stiffness: dict[str, np.ndarray],
                    damping: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
        """Stiffness ``S`` and damping ``C`` of the law ``sigma = S e + C edot + sigma0``,
        each ``(n, nd, nd)``, for reference parameters ``p`` ``(n, reference)`` and the
        values of :attr:`stiffness_values` and :attr:`damping_values` by name (arrays
        ``(n,)``, zero where not given)."""
        n, nd = len(p), cls.n_deformations()
        return np.zeros((n, nd, nd)), np.zeros((n, nd, nd))

    # --- drawing ------------------------------------------------------------------------
    @classmethod
    def outline(cls, xe: np.ndarray, p: np.ndarray, e: np.ndarray,
                exaggeration: float = 1.0) -> list[np.ndarray]:
        """Polylines ``(k, 2)`` [m] that draw ``n`` elements at coordinates ``xe``
        ``(n, nc)`` with deformations ``e`` ``(n, nd)``: by default the chord from
        ``r_p`` to ``r_q``; nothing for types without two translational nodes."""
        ends = cls.ends()
        if ends is None:
            return []
        return [np.stack([x[ends[0]:ends[0] + 2], x[ends[1]:ends[1] + 2]]) for x in xe]


def chord(c: list[Any], p_at: int, q_at: int) -> tuple[Any, Any]:
    """``d = r_q - r_p`` for ``r_p`` at ``c[p_at], c[p_at + 1]`` and ``r_q`` likewise."""
    return c[q_at] - c[p_at], c[q_at + 1] - c[p_at + 1]


def elongation_law(p: np.ndarray, nd: int, axial: np.ndarray, axial_damping: np.ndarray
                   ) -> tuple[np.ndarray, np.ndarray]:
    """``S``, ``C`` ``(n, nd, nd)`` with ``EA / l0`` and ``c_A / l0`` on the elongation
    (deformation 1) and zeros elsewhere (THEORY 6)."""
    S, C = np.zeros((2, len(p), nd, nd))
    S[:, 0, 0] = axial / p[:, 0]
    C[:, 0, 0] = axial_damping / p[:, 0]
    return S, C


#: the axial values of the rods (truss, rigid beam, beam), in .dat order
AXIAL_STIFFNESS = Value("axial", "EA", "N")
AXIAL_DAMPING = Value("axial", "c_A", "N s")
