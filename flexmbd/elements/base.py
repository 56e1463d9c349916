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
:mod:`flexmbd.engine.codegen`; the builder, the ``.dat`` reader and writer and the plots
ask the class. A new type is one file and a line in :mod:`flexmbd.elements`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

#: what the definitions compute with: a namespace of ``sqrt``, ``sin``, ``cos`` and ``atan2``
#: (``sympy`` for the kernels and the symbolic path, numpy, the code generator's jets)
Math = Any

TRANSLATIONAL = "translational"
ROTATIONAL = "rotational"
SPATIAL_TRANSLATIONAL = "spatial translational"
SPATIAL_ROTATIONAL = "spatial rotational"
WARPING = "warping"
#: number of coordinates carried by a node of each kind: ``(x, y)``, ``phi``,
#: ``(x, y, z)``, the Euler parameters ``(lam0, lam1, lam2, lam3)`` and the rate of
#: twist ``psi`` of a warping node
COORDINATES_PER_NODE = {TRANSLATIONAL: 2, ROTATIONAL: 1, SPATIAL_TRANSLATIONAL: 3,
                        SPATIAL_ROTATIONAL: 4, WARPING: 1}
#: the kinds of spatial models; a model holds kinds of one family only
SPATIAL_KINDS = (SPATIAL_TRANSLATIONAL, SPATIAL_ROTATIONAL, WARPING)


def is_translational(kind: str) -> bool:
    """Whether nodes of ``kind`` carry a position (planar or spatial)."""
    return kind in (TRANSLATIONAL, SPATIAL_TRANSLATIONAL)


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


def spatial_translational(name: str) -> Role:
    """A spatial translational node ``(x, y, z)`` [m]."""
    return Role(name, SPATIAL_TRANSLATIONAL)


def spatial_rotational(name: str) -> Role:
    """A spatial rotational node: four Euler parameters ``lam`` [-] of its rotation from
    the reference configuration, where ``lam = (1, 0, 0, 0)``."""
    return Role(name, SPATIAL_ROTATIONAL)


def warping(name: str) -> Role:
    """A warping node: the rate of twist ``psi`` [rad/m] of the section there, 0 in the
    reference; free (a degree of freedom) unless fixed or prescribed."""
    return Role(name, WARPING)


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
    """Base class of the element types, planar and spatial (see the module docstring).

    Class attributes:
        name: short name used in messages (``"truss"``).
        keyword: the SPACAR input-file keyword (``"PLTRUSS"``).
        roles: the nodes in connection order.
        deformation_names: one name per deformation parameter.
        deformation_units: the SI unit of each (``"m"`` or ``"rad"``); a stress of a
            length is a force [N], of an angle a moment [N m].
        reference: how many reference parameters the definition uses: planar types
            up to two (``l0``, ``beta0``), spatial ones their own layout (see
            :meth:`reference_parameters`).
        element_data: the values given with each element besides its nodes, by name,
            with their defaults (``None``: required): the ``"orientation"`` vector of a
            spatial beam, the ``"axis"`` of a spatial hinge. :meth:`reference_parameters`
            turns them into parameters.
        optional_data: the :attr:`element_data` an input-file line may leave off (then its
            default holds).
        periodic: deformations that are angles modulo ``2 pi`` (a spatial hinge's
            rotation); the engine keeps them continuous through any number of turns.
        automatic: added by the builder, never by a user (the Euler normalization).
        stiffness_values, damping_values: the values of ``ESTIFF`` and ``EDAMP``, in
            their order in a ``.dat`` line.
        has_mass: whether the type takes a distributed mass (``EM``).
        released_by_default: deformations are released, not rigid, unless classified
            (force elements such as springs).
        calculable: deformations (1-based) that are always computed, never constrained
            (SPACAR's calculable ones, the warping beam's ``e7``, ``e8``): released, and only
            a release may name them.
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
    calculable: ClassVar[tuple[int, ...]] = ()
    element_data: ClassVar[dict[str, tuple[float, ...] | None]] = {}
    optional_data: ClassVar[tuple[str, ...]] = ()
    periodic: ClassVar[tuple[int, ...]] = ()
    automatic: ClassVar[bool] = False

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
    def is_spatial(cls) -> bool:
        """Whether the type belongs to spatial models (its nodes are spatial)."""
        return any(r.kind in SPATIAL_KINDS for r in cls.roles)

    @classmethod
    def dimension(cls) -> int:
        """Coordinates of a position: 2 (planar) or 3 (spatial)."""
        return 3 if cls.is_spatial() else 2

    @classmethod
    def ends(cls) -> tuple[int, int] | None:
        """Columns of ``r_p`` and ``r_q`` (each :meth:`dimension` wide) in the element
        coordinates, or ``None`` for a type with fewer than two translational nodes."""
        columns, at = [], 0
        for role in cls.roles:
            if is_translational(role.kind):
                columns.append(at)
            at += COORDINATES_PER_NODE[role.kind]
        return (columns[0], columns[1]) if len(columns) >= 2 else None

    @classmethod
    def reference_parameters(cls, xe0: np.ndarray,
                             data: dict[str, np.ndarray] | None = None) -> np.ndarray:
        """The reference parameters ``(n, reference)`` from the initial element
        coordinates ``xe0`` ``(n, nc)`` and the :attr:`element_data` (arrays ``(n, k)``
        by name). Here, for planar types: the length ``l0`` [m] and the angle ``beta0``
        [rad] of the chord from ``r_p`` to ``r_q``."""
        xe0 = np.atleast_2d(np.asarray(xe0, dtype=float))
        ends = cls.ends()
        if ends is None:
            return np.zeros((len(xe0), cls.reference))
        d = xe0[:, ends[1]:ends[1] + 2] - xe0[:, ends[0]:ends[0] + 2]
        both = np.stack([np.hypot(d[:, 0], d[:, 1]), np.arctan2(d[:, 1], d[:, 0])], axis=1)
        return both[:, :cls.reference]

    @classmethod
    def check_data(cls, xe0: np.ndarray, data: dict[str, np.ndarray]) -> list[str]:
        """Problems of one element's :attr:`element_data` at its initial coordinates
        ``xe0`` ``(nc,)`` (an orientation vector along the chord, say); none here."""
        return []

    # --- the single definition --------------------------------------------------------
    @staticmethod
    def deformations(c: list[Any], p: list[Any], m: Math) -> list[Any]:
        """Deformation parameters as expressions of the element coordinates ``c`` and the
        reference parameters ``p`` (``[l0, beta0]``, as many as :attr:`reference`).

        ``m`` supplies ``sqrt``, ``sin``, ``cos`` and ``atan2`` (:data:`Math`): ``sympy``
        for the kernel generator and the symbolic path, the generator's jets for the
        quadratic velocity terms.
        """
        raise NotImplementedError

    @staticmethod
    def material_point(c: list[Any], p: list[Any], xi: Any, m: Math) -> list[Any]:
        """Position ``(x, y)`` (``(x, y, z)`` for spatial types) of the material point at
        ``xi`` in [0, 1] from ``r_p`` to ``r_q``, from which the consistent mass, the
        velocity-dependent inertia and the gravity load follow (``M = m int N^T N dxi``
        with ``N`` its derivative with respect to ``c``, THEORY 5). Types with a
        distributed mass define it."""
        raise NotImplementedError

    @staticmethod
    def body_angular_velocity(c: list[Any], m: Math) -> list[list[Any]] | None:
        """For a type that carries a rigid body's rotary inertia (the Euler element of a
        spatial rotational node): the matrix ``W`` (3 x nc) of its body angular velocity
        ``omega' = W cdot``. The inertia tensor comes from :meth:`inertia_tensor`; the
        kernels then hold the mass ``W^T J W`` and the velocity term ``W^T (J Wdot cdot +
        omega' x J omega')`` (THEORY-SPATIAL 4). ``None`` for the other types."""
        return None

    @staticmethod
    def inertia_tensor(p: list[Any]) -> list[list[Any]]:
        """The body-frame inertia tensor ``J`` (3 x 3) [kg m^2] in the reference parameters
        of a type with :meth:`body_angular_velocity`."""
        raise NotImplementedError

    @classmethod
    def element_mass(cls, p: np.ndarray, mass_per_length: np.ndarray) -> np.ndarray:
        """The factor ``(n,)`` [kg] of the kernels' mass, per unit mass: ``rhoA l0``."""
        return mass_per_length * p[:, 0]

    @classmethod
    def lumped_masses(cls, p: np.ndarray, mass: np.ndarray) -> np.ndarray:
        """Diagonal of the lumped mass matrix ``(n, nc)`` [kg, kg m^2] for element masses
        ``mass`` ``(n,)``: half the mass at each translational end node."""
        out = np.zeros((len(mass), cls.n_coordinates()))
        ends, width = cls.ends(), cls.dimension()
        if ends is not None:
            for column in (*range(ends[0], ends[0] + width), *range(ends[1], ends[1] + width)):
                out[:, column] = 0.5 * mass
        return out

    #: whether a section inertia per length (``set_mass(..., section_inertia=...)``, a
    #: ``.dat`` EM line's values after ``rhoA``) is lumped on the type's rotational nodes
    takes_section_inertia: ClassVar[bool] = False

    @classmethod
    def section_inertia_on_nodes(cls, p: np.ndarray, section: tuple[float, ...]
                                 ) -> list[tuple[int, np.ndarray]]:
        """The rotary inertias ``(3, 3)`` [kg m^2] that a section inertia per length
        ``section`` lumps on the type's rotational nodes, by the node's position in
        :attr:`roles`, for one element of reference parameters ``p``; types with
        :attr:`takes_section_inertia` define it."""
        raise NotImplementedError

    # --- the .dat file's lines of a type (SPACAR's syntax) ----------------------------------
    @classmethod
    def mass_line(cls, extra: tuple[float, ...]) -> tuple[dict[str, object], list[str]]:
        """What the values after ``rhoA`` on an ``EM`` line mean for the type: keyword
        arguments of :meth:`~flexmbd.ModelBuilder.set_mass` and the values read but not
        used (for a note). A planar type takes a rotary inertia per length ``rhoI`` that
        must be 0; a spatial one nothing.

        Raises:
            ValueError: what is wrong with the line, in words.
        """
        if cls.is_spatial():
            if extra:
                raise ValueError(f"a {cls.keyword} takes its mass per length rhoA only, got "
                                 f"{len(extra) + 1} values")
        elif len(extra) > 1:
            raise ValueError(f"EM takes rhoA [rhoI] for a planar element, got "
                             f"{len(extra) + 1} values")
        elif any(extra):
            raise ValueError("a rotary inertia per length (rhoI) is not supported for "
                             "planar elements; set it to 0 or put rotary inertia on nodes "
                             "with XM")
        return {}, []

    @classmethod
    def stiffness_line(cls, values: tuple[float, ...]) -> tuple[tuple[float, ...], list[str]]:
        """The values of an ``ESTIFF`` line that set :attr:`stiffness_values`, in their
        order, and the values read but not used (for a note)."""
        return values, []

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
        """Polylines ``(k, 2)`` (``(k, 3)`` for spatial types) [m] that draw ``n``
        elements at coordinates ``xe`` ``(n, nc)`` with deformations ``e`` ``(n, nd)``:
        by default the chord from ``r_p`` to ``r_q``; nothing for types without two
        translational nodes."""
        ends, width = cls.ends(), cls.dimension()
        if ends is None:
            return []
        return [np.stack([x[ends[0]:ends[0] + width], x[ends[1]:ends[1] + width]]) for x in xe]


def chord(c: list[Any], p_at: int, q_at: int, width: int = 2) -> list[Any]:
    """``d = r_q - r_p`` for ``r_p`` at ``c[p_at:p_at + width]`` and ``r_q`` likewise (a
    planar chord, or ``width = 3`` a spatial one)."""
    return [c[q_at + k] - c[p_at + k] for k in range(width)]


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
