"""The element contract.

An element type is a tiny class with declarative attributes and vectorised
kernels. Every kernel takes the coordinates of *all* elements of that type at
once, ``xe`` of shape ``(..., n, n_coordinates)`` in the element's coordinate
order (THEORY section 2), and the reference data from
:meth:`ElementType.reference` (arrays of shape ``(n,)``). Leading axes are
batches (e.g. output times): a run evaluates many states in one call.

The deformation functions are written once, in :meth:`ElementType.formula`,
with the math functions passed in as a module (``numpy`` or ``sympy``); the
numeric value and the symbolic path both evaluate that one definition. The
derivatives are hand-written for speed and checked against finite differences
and against symbolic differentiation of ``formula`` in the tests.
"""

from __future__ import annotations

from dataclasses import dataclass
from types import ModuleType
from typing import Any, ClassVar, NamedTuple

import numpy as np

TRANSLATIONAL = "translational"
ROTATIONAL = "rotational"
#: number of coordinates carried by a node of each kind
COORDINATES_PER_NODE = {TRANSLATIONAL: 2, ROTATIONAL: 1}


class JacobianPattern(NamedTuple):
    """Where the Jacobian features of an element type go: entry ``k`` of ``D_x`` at
    ``(rows[k], columns[k])`` is ``signs[k]`` times feature ``features[k]``."""

    rows: np.ndarray
    columns: np.ndarray
    features: np.ndarray
    signs: np.ndarray


@dataclass(frozen=True)
class Reference:
    """Reference (initial) geometry of ``n`` elements of one type.

    Attributes:
        length: ``l0``, distance between the translational end nodes [m], shape ``(n,)``.
        angle: ``beta0``, orientation of ``r_q - r_p`` [rad], shape ``(n,)``.
    """

    length: np.ndarray
    angle: np.ndarray


class ElementType:
    """Base class of the planar element types.

    Class attributes:
        name: short name used in messages (``"truss"``).
        keyword: the SPACAR input-file keyword (``"PLTRUSS"``).
        node_kinds: kind of each node in connection order.
        node_roles: name of each node in connection order (``"p"``, ``"phi_p"``, ...).
        deformation_names: one name per deformation parameter.
        ends: column pairs of ``xe`` holding ``r_p`` and ``r_q``, or ``None``
            for elements without translational nodes.
        jacobian_entries: where the Jacobian features go (see below).
        mass_varies: whether :meth:`mass_matrix` depends on the configuration; a
            constant one has no velocity-dependent inertia, so the inertia force is
            ``M xddot`` alone.
    """

    name: ClassVar[str]
    keyword: ClassVar[str]
    node_kinds: ClassVar[tuple[str, ...]]
    node_roles: ClassVar[tuple[str, ...]]
    deformation_names: ClassVar[tuple[str, ...]]
    ends: ClassVar[tuple[tuple[int, int], tuple[int, int]] | None] = None
    #: whether the mass matrix depends on the configuration (else it is computed once)
    mass_varies: ClassVar[bool] = True
    #: the non-zero entries of the element Jacobian as ``(deformation, coordinate,
    #: feature, sign)``: ``D_x[d, c] = sign * features[f]`` with the features of
    #: :meth:`deformations_and_features`. Every entry of a planar element's Jacobian is
    #: a component of a unit vector or a lever arm, up to sign; the assembly scatters
    #: the few features of all elements straight into ``D_x`` and ``D_c`` (one gather
    #: per matrix instead of an element Jacobian per type and a copy per matrix).
    jacobian_entries: ClassVar[tuple[tuple[int, int, int, float], ...]] = ()

    #: :attr:`jacobian_entries` as arrays (set for each type)
    jacobian_pattern: ClassVar[JacobianPattern]
    #: number of Jacobian features (set for each type)
    n_features: ClassVar[int]

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        entries = np.array(cls.jacobian_entries, dtype=float).reshape(-1, 4)
        rows, columns, features = entries[:, :3].T.astype(int)
        cls.jacobian_pattern = JacobianPattern(rows, columns, features, entries[:, 3])
        cls.n_features = int(features.max()) + 1 if len(features) else 0

    @classmethod
    def n_coordinates(cls) -> int:
        return sum(COORDINATES_PER_NODE[k] for k in cls.node_kinds)

    @classmethod
    def n_deformations(cls) -> int:
        return len(cls.deformation_names)

    @classmethod
    def reference(cls, xe0: np.ndarray) -> Reference:
        """Reference length and angle from the initial coordinates ``xe0`` ``(n, nc)``."""
        xe0 = np.atleast_2d(xe0)
        if cls.ends is None:
            zero = np.zeros(len(xe0))
            return Reference(length=zero, angle=zero.copy())
        d = xe0[:, list(cls.ends[1])] - xe0[:, list(cls.ends[0])]
        return Reference(length=np.hypot(d[:, 0], d[:, 1]), angle=np.arctan2(d[:, 1], d[:, 0]))

    # --- the single definition -------------------------------------------------
    @staticmethod
    def formula(c: list[Any], length: Any, angle: Any, m: ModuleType) -> list[Any]:
        """Deformation parameters as expressions of the coordinate list ``c``.

        ``m`` supplies ``sqrt``, ``sin`` and ``cos`` (``numpy`` or ``sympy``).
        """
        raise NotImplementedError

    # --- numeric kernels --------------------------------------------------------
    @classmethod
    def deformations(cls, xe: np.ndarray, ref: Reference) -> np.ndarray:
        """Deformation parameters ``e = D(x)``, shape ``(..., n, nd)``."""
        columns = [xe[..., k] for k in range(xe.shape[-1])]
        return np.stack(cls.formula(columns, ref.length, ref.angle, np), axis=-1)

    @classmethod
    def deformations_and_features(cls, xe: np.ndarray, ref: Reference, geometry: Any = None
                                  ) -> tuple[np.ndarray, np.ndarray]:
        """``e`` ``(..., n, nd)`` and the Jacobian features ``(..., n, nf)`` (see
        :attr:`jacobian_entries`), from :meth:`geometry` of ``xe`` when given."""
        raise NotImplementedError

    @classmethod
    def jacobian_of(cls, features: np.ndarray) -> np.ndarray:
        """The element Jacobians ``(..., n, nd, nc)`` from their ``features`` ``(..., n, nf)``."""
        p = cls.jacobian_pattern
        jac = np.zeros((*features.shape[:-1], cls.n_deformations(), cls.n_coordinates()))
        jac[..., p.rows, p.columns] = features[..., p.features] * p.signs
        return jac

    @classmethod
    def jacobian(cls, xe: np.ndarray, ref: Reference) -> np.ndarray:
        """``D_x = dD/dx`` per element, shape ``(..., n, nd, nc)``."""
        return cls.jacobian_of(cls.deformations_and_features(xe, ref)[1])

    @classmethod
    def geometry(cls, xe: np.ndarray, ref: Reference) -> Any:
        """What the hot kernels of one configuration share (the chord, the cosines of
        the end angles), computed once and passed to them as ``geometry``; ``None``
        for types with nothing to share. Opaque outside the type."""
        return None

    @classmethod
    def deformations_and_jacobian(cls, xe: np.ndarray, ref: Reference, geometry: Any = None
                                  ) -> tuple[np.ndarray, np.ndarray]:
        """``e`` and ``D_x`` together, from :meth:`geometry` of ``xe`` when given."""
        e, features = cls.deformations_and_features(xe, ref, geometry)
        return e, cls.jacobian_of(features)

    @classmethod
    def hessian(cls, xe: np.ndarray, ref: Reference) -> np.ndarray:
        """``D_xx`` per element, shape ``(..., n, nd, nc, nc)``, symmetric in the last two axes."""
        raise NotImplementedError

    @classmethod
    def quadratic_velocity(cls, xe: np.ndarray, xde: np.ndarray, ref: Reference,
                           geometry: Any = None) -> np.ndarray:
        """``(D_xx xdot) xdot`` per deformation, shape ``(..., n, nd)`` (THEORY section 2),
        from :meth:`geometry` of ``xe`` when given."""
        raise NotImplementedError


    # --- inertia (THEORY section 5); elements without mass keep these defaults ---------
    @classmethod
    def mass_matrix(cls, xe: np.ndarray, ref: Reference, mass: np.ndarray,
                    lumped: np.ndarray) -> np.ndarray:
        """Element mass matrices ``(..., n, nc, nc)`` [kg, kg m, kg m^2] for element masses
        ``mass`` ``(n,)``."""
        return np.zeros((*xe.shape, cls.n_coordinates()))

    @classmethod
    def mass_terms(cls, ref: Reference, mass: np.ndarray, lumped: np.ndarray
                   ) -> tuple[np.ndarray, np.ndarray]:
        """The mass matrix as ``M = M0 + sum_k phi_k M_k`` with the configuration-dependent
        :meth:`mass_features` ``phi``: ``M0`` ``(n, nc, nc)`` and ``M_k`` ``(n, k, nc, nc)``
        [kg, kg m, kg m^2]. Lets the assembly build the system mass matrix from a few
        features. The default serves types of constant mass (``k = 0``)."""
        if cls.mass_varies:
            raise NotImplementedError(f"{cls.name}: a varying mass needs its mass_terms")
        nc = cls.n_coordinates()
        M0 = cls.mass_matrix(np.zeros((len(mass), nc)), ref, mass, lumped)
        return M0, np.zeros((len(mass), 0, nc, nc))

    @classmethod
    def mass_features(cls, xe: np.ndarray, ref: Reference, geometry: Any = None
                      ) -> np.ndarray:
        """``phi`` of :meth:`mass_terms` ``(..., n, k)``, from :meth:`geometry` of ``xe``
        when given."""
        return np.zeros((*xe.shape[:-1], 0))

    @classmethod
    def inertia_velocity(cls, xe: np.ndarray, xde: np.ndarray, ref: Reference,
                         mass: np.ndarray, lumped: np.ndarray) -> np.ndarray:
        """Velocity-dependent inertia ``h`` ``(..., n, nc)``: inertia force ``M xddot + h``."""
        return np.zeros(xe.shape)

    @classmethod
    def inertia_force(cls, xe: np.ndarray, xde: np.ndarray, xdde: np.ndarray, ref: Reference,
                      mass: np.ndarray, lumped: np.ndarray, geometry: Any = None) -> np.ndarray:
        """The inertia force ``M xddot + h`` ``(..., n, nc)`` [N, N m] without forming ``M``
        (types override this with a cheaper closed form, using :meth:`geometry` of ``xe``
        when given)."""
        M = cls.mass_matrix(xe, ref, mass, lumped)
        return (M @ xdde[..., None])[..., 0] + cls.inertia_velocity(xe, xde, ref, mass, lumped)

    @classmethod
    def gravity_load(cls, xe: np.ndarray, ref: Reference, mass: np.ndarray,
                     lumped: np.ndarray, gravity: np.ndarray) -> np.ndarray:
        """Nodal loads ``(..., n, nc)`` of gravity ``g`` [m/s^2] on the element's own mass."""
        return np.zeros(xe.shape)

    # --- generalized stresses (THEORY section 6) -------------------------------------
    @classmethod
    def elastic_matrices(cls, ref: Reference, props) -> tuple[np.ndarray, np.ndarray]:
        """Stiffness ``S`` and damping ``C`` of the linear law ``sigma = S e + C edot +
        sigma0``, each ``(n, nd, nd)`` [N/m, N m/rad, ...; times s for ``C``].

        ``props`` is the group's :class:`~flexmbd.properties.GroupProperties`. This
        is the one definition of the law: the stresses and the stiffness of the
        implicit integrator both use it.
        """
        nd = cls.n_deformations()
        return np.zeros((len(ref.length), nd, nd)), np.zeros((len(ref.length), nd, nd))

    @classmethod
    def stress(cls, e: np.ndarray, ed: np.ndarray, ref: Reference, props) -> np.ndarray:
        """``sigma = S e + C edot + sigma0`` per deformation, shape ``(..., n, nd)`` [N, N m]."""
        S, C = cls.elastic_matrices(ref, props)
        return (S @ e[..., None] + C @ ed[..., None])[..., 0] + props.prestress


# --- planar geometry shared by the kernels (all shapes with leading batch axes) -----
def unit_and_normal(beta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``e(beta) = (cos, sin)`` and ``n(beta) = (-sin, cos)``, each shape ``(..., 2)``."""
    # filled in place: np.stack costs more than the trigonometry for small n
    e, n = np.empty((*beta.shape, 2)), np.empty((*beta.shape, 2))
    np.cos(beta, out=e[..., 0])
    np.sin(beta, out=e[..., 1])
    n[..., 0], n[..., 1] = -e[..., 1], e[..., 0]
    return e, n


class RodGeometry(NamedTuple):
    """The planar geometry of a rod element (truss, beams) in one configuration, computed
    once and shared by its kernels. ``k`` is the number of rotational nodes (0 to 2).

    Attributes:
        d: the chord ``r_q - r_p`` ``(..., 2)``; length: ``l = |d|`` ``(...,)``;
        unit: ``e_l = d / l`` ``(..., 2)``.
        cos, sin: of ``beta = beta0 + phi`` at the rotational nodes ``(..., k)``:
            ``e(beta) = (cos, sin)``, ``n(beta) = (-sin, cos)``.
        along, normal: ``e(beta) . d`` and ``n(beta) . d`` ``(..., k)``.
    """

    d: np.ndarray
    length: np.ndarray
    unit: np.ndarray
    cos: np.ndarray | None
    sin: np.ndarray | None
    along: np.ndarray | None
    normal: np.ndarray | None


def rod_geometry(xe: np.ndarray, ref: Reference, p: int, q: int,
                 angles: slice | None = None) -> RodGeometry:
    """The :class:`RodGeometry` with ``r_p`` at columns ``p, p+1``, ``r_q`` at ``q, q+1``
    and the node angles at columns ``angles`` of ``xe``.

    Both ends are handled in one array each: on the small arrays of a mechanism every
    numpy call costs about the same, so fewer calls is faster."""
    d = xe[..., q:q + 2] - xe[..., p:p + 2]
    dx, dy = d[..., :1], d[..., 1:]
    length = np.hypot(dx[..., 0], dy[..., 0])
    unit = d / length[..., None]
    if angles is None:
        return RodGeometry(d, length, unit, None, None, None, None)
    beta = xe[..., angles] + ref.angle[:, None]
    cos, sin = np.cos(beta), np.sin(beta)
    return RodGeometry(d, length, unit, cos, sin, cos * dx + sin * dy, cos * dy - sin * dx)


def elongation_entries(p: int, q: int) -> tuple[tuple[int, int, int, float], ...]:
    """:attr:`ElementType.jacobian_entries` of ``d l / d(r_p, r_q) = (-e_l, e_l)`` as
    deformation 0, with ``e_l`` as features 0 and 1."""
    return ((0, p, 0, -1.0), (0, p + 1, 1, -1.0), (0, q, 0, 1.0), (0, q + 1, 1, 1.0))


def elongation_rate2(geometry: RodGeometry, dv: np.ndarray) -> np.ndarray:
    """``(d2 l / dr2 rdot) rdot = (dv.dv - (e_l.dv)^2) / l = (e_l x dv)^2 / l`` (in the
    plane) for ``dv = rdot_q - rdot_p`` ``(..., 2)``."""
    unit = geometry.unit
    across = unit[..., 0] * dv[..., 1] - unit[..., 1] * dv[..., 0]
    return across * across / geometry.length


def end_rates(geometry: RodGeometry, dv: np.ndarray, w: np.ndarray) -> np.ndarray:
    """``w^2 (n . d) + 2 w (e . dv)`` at the rotational nodes ``(..., k)``: minus the
    quadratic velocity term of ``n(beta) . d`` for node rates ``w`` ``(..., k)`` and
    ``dv = rdot_q - rdot_p`` ``(..., 2)`` (``dn/dbeta = -e``, ``de/dbeta = n``)."""
    g = geometry
    return w * (w * g.normal + 2.0 * (g.cos * dv[..., :1] + g.sin * dv[..., 1:]))


class AngledRod(ElementType):
    """A rod from ``r_p`` (columns 0, 1) to ``r_q`` (columns 3, 4) with rotational nodes
    at :attr:`angles`: its deformations are the elongation and ``normal_signs`` times
    ``n(beta) . d`` at each of them (the beams). Supplies the geometry, the deformations
    with their Jacobian features (``e_l``, ``cos beta``, ``sin beta``, ``e(beta) . d``,
    in that order) and the quadratic velocity terms."""

    #: columns of the node angles in ``xe``
    angles: ClassVar[slice]
    #: sign of ``n(beta) . d`` in each deformation after the elongation
    normal_signs: ClassVar[np.ndarray]

    @classmethod
    def geometry(cls, xe, ref):
        """The :class:`RodGeometry` with the angles of :attr:`angles`."""
        return rod_geometry(xe, ref, 0, 3, cls.angles)

    @classmethod
    def _deformations_of(cls, g, ref):
        return np.concatenate([(g.length - ref.length)[..., None], cls.normal_signs * g.normal],
                              axis=-1)

    @classmethod
    def deformations(cls, xe: np.ndarray, ref: Reference) -> np.ndarray:
        return cls._deformations_of(cls.geometry(xe, ref), ref)

    @classmethod
    def deformations_and_features(cls, xe, ref, geometry=None):
        g = geometry or cls.geometry(xe, ref)
        return (cls._deformations_of(g, ref),
                np.concatenate([g.unit, g.cos, g.sin, g.along], axis=-1))

    @classmethod
    def quadratic_velocity(cls, xe: np.ndarray, xde: np.ndarray, ref: Reference,
                           geometry=None) -> np.ndarray:
        g = geometry or cls.geometry(xe, ref)
        dv = xde[..., 3:5] - xde[..., 0:2]
        out = np.empty((*xe.shape[:-1], 1 + len(cls.normal_signs)))
        out[..., 0] = elongation_rate2(g, dv)
        out[..., 1:] = -cls.normal_signs * end_rates(g, dv, xde[..., cls.angles])
        return out


def chord(xe: np.ndarray, ends) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``d = r_q - r_p`` ``(..., 2)``, its length ``l`` ``(...,)`` and direction ``e_l``."""
    (px, py), (qx, qy) = ends
    d = np.empty((*xe.shape[:-1], 2))
    np.subtract(xe[..., qx], xe[..., px], out=d[..., 0])
    np.subtract(xe[..., qy], xe[..., py], out=d[..., 1])
    length = np.hypot(d[..., 0], d[..., 1])
    return d, length, d / length[..., None]


def dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Dot product over the last axis of ``(..., 2)`` arrays."""
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1]


def elongation_hessian(length: np.ndarray, e_l: np.ndarray) -> np.ndarray:
    """Hessian of ``l`` with respect to ``(r_p, r_q)``, shape ``(..., 4, 4)``."""
    a = (np.eye(2) - e_l[..., :, None] * e_l[..., None, :]) / length[..., None, None]
    h = np.empty((*a.shape[:-2], 4, 4))
    h[..., :2, :2] = a
    h[..., 2:, 2:] = a
    h[..., :2, 2:] = -a
    h[..., 2:, :2] = -a
    return h


def normal_distance_hessian(hess, ends, phi, n_d, e_r, sign):
    """Write the Hessian of ``sign * n(beta0 + phi) . d`` into ``hess`` ``(..., nc, nc)``.

    ``d = r_q - r_p`` with ``r_p, r_q`` at the column pairs ``ends``; ``phi`` is
    the column of the node angle; ``n_d = n . d`` and ``e_r = e(beta0 + phi)``.
    Since ``dn/dbeta = -e`` and ``de/dbeta = n``, the only non-zero entries are
    ``d2/dphi2 = -sign n.d``, ``d2/dphi dr_p = sign e`` and ``d2/dphi dr_q = -sign e``.
    """
    rp, rq = list(ends[0]), list(ends[1])
    hess[..., phi, phi] = -sign * n_d
    hess[..., phi, rp] = hess[..., rp, phi] = sign * e_r
    hess[..., phi, rq] = hess[..., rq, phi] = -sign * e_r


# --- inertia of a rod with a linear velocity field (truss, rigid beam) ----------------
_ROD_CONSISTENT = np.kron(np.array([[2.0, 1.0], [1.0, 2.0]]) / 6.0, np.eye(2))
_ROD_LUMPED = 0.5 * np.eye(4)


def rod_mass_matrix(n_coordinates: int, ends, mass: np.ndarray, lumped: np.ndarray
                    ) -> np.ndarray:
    """``m/6 [[2I, I], [I, 2I]]`` (consistent) or ``m/2 I`` (lumped) on ``r_p, r_q``,
    shape ``(n, nc, nc)``."""
    cols = np.array(list(ends[0]) + list(ends[1]))
    blocks = np.where(lumped[:, None, None], _ROD_LUMPED, _ROD_CONSISTENT) * mass[:, None, None]
    out = np.zeros((len(mass), n_coordinates, n_coordinates))
    out[:, cols[:, None], cols] = blocks
    return out


def rod_gravity_load(xe: np.ndarray, ends, mass: np.ndarray, gravity: np.ndarray
                     ) -> np.ndarray:
    """Half the weight ``m g`` at each end node, shape ``(..., n, nc)``."""
    out = np.zeros(xe.shape)
    out[..., list(ends[0])] = out[..., list(ends[1])] = 0.5 * mass[:, None] * gravity
    return out


def rod_inertia_force(xdde: np.ndarray, ends, mass: np.ndarray, lumped: np.ndarray
                      ) -> np.ndarray:
    """Inertia force ``M xddot`` of a rod with a linear velocity field, ``(..., n, nc)``:
    consistent ``m/6 (2 a_p + a_q, a_p + 2 a_q)``, lumped ``m/2 (a_p, a_q)``."""
    rp, rq = list(ends[0]), list(ends[1])
    a_p, a_q = xdde[..., rp], xdde[..., rq]
    m = mass[:, None]
    own = np.where(lumped[:, None], 0.5, 1.0 / 3.0) * m  # weight of the node's own end
    other = np.where(lumped[:, None], 0.0, 1.0 / 6.0) * m  # and of the other end
    out = np.zeros(xdde.shape)
    out[..., rp] = own * a_p + other * a_q
    out[..., rq] = other * a_p + own * a_q
    return out


def elongation_matrices(ref: Reference, props, nd: int) -> tuple[np.ndarray, np.ndarray]:
    """``S``, ``C`` ``(n, nd, nd)`` with ``EA / l0`` and ``c_A / l0`` on the elongation
    (deformation 1) and zeros elsewhere."""
    S, C = np.zeros((2, len(ref.length), nd, nd))
    S[:, 0, 0] = props.axial_stiffness / ref.length
    C[:, 0, 0] = props.axial_damping / ref.length
    return S, C
