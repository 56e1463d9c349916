"""Planar beam (PLBEAM): elongation and two bending deformations (THEORY section 2).

``e1 = l - l0``, ``e2 = -n_p . d``, ``e3 = n_q . d`` with ``d = r_q - r_p`` and
``n_p = n(beta0 + phi_p)``, ``n_q = n(beta0 + phi_q)``.
"""

from __future__ import annotations

import itertools

import numpy as np

from .base import (
    ROTATIONAL,
    TRANSLATIONAL,
    AngledRod,
    Reference,
    chord,
    dot,
    elongation_entries,
    elongation_hessian,
    elongation_matrices,
    normal_distance_hessian,
    rod_gravity_load,
    rod_inertia_force,
    rod_mass_matrix,
    unit_and_normal,
)

_RP, _PHI_P, _RQ, _PHI_Q = [0, 1], 2, [3, 4], 5
_ANGLES = slice(_PHI_P, None, 3)  # columns 2 and 5: both node angles as one view
_TRANS = np.array(_RP + _RQ)
_BENDING_SIGNS = np.array([-1.0, 1.0])  # e2 = -n_p . d, e3 = n_q . d

# Integrals over xi in [0, 1] of products of the cubic Hermite functions
# H1 = 1 - 3xi^2 + 2xi^3, H2 = xi - 2xi^2 + xi^3, H3 = 3xi^2 - 2xi^3, H4 = -xi^2 + xi^3
# (THEORY section 5), and of the functions themselves.
HERMITE_PRODUCTS = np.array([
    [13 / 35, 11 / 210, 9 / 70, -13 / 420],
    [11 / 210, 1 / 105, 13 / 420, -1 / 140],
    [9 / 70, 13 / 420, 13 / 35, -11 / 210],
    [-13 / 420, -1 / 140, -11 / 210, 1 / 105],
])
HERMITE_INTEGRALS = np.array([1 / 2, 1 / 12, 1 / 2, -1 / 12])
# N(xi) = sum_i H_i(xi) A_i with A_i (2 x 6) stacked into (8, 6): rows 0-1 pick r_p,
# rows 4-5 pick r_q; rows 2-3 and 6-7 hold l0 n_p and l0 n_q in the angle columns
_SHAPE_TEMPLATE = np.zeros((8, 6))
_SHAPE_TEMPLATE[[0, 1, 4, 5], [0, 1, 3, 4]] = 1.0
_HERMITE_BLOCKS = np.kron(HERMITE_PRODUCTS, np.eye(2))


class Beam(AngledRod):
    """Coordinates ``[x_p, y_p, phi_p, x_q, y_q, phi_q]``."""

    name = "beam"
    keyword = "PLBEAM"
    node_kinds = (TRANSLATIONAL, ROTATIONAL, TRANSLATIONAL, ROTATIONAL)
    node_roles = ("p", "phi_p", "q", "phi_q")
    deformation_names = ("elongation", "bending at p", "bending at q")
    ends = ((0, 1), (3, 4))
    angles = _ANGLES
    normal_signs = _BENDING_SIGNS

    @staticmethod
    def formula(c, length, angle, m):
        xp, yp, php, xq, yq, phq = c
        dx, dy = xq - xp, yq - yp
        bp, bq = angle + php, angle + phq
        return [
            m.sqrt(dx**2 + dy**2) - length,
            m.sin(bp) * dx - m.cos(bp) * dy,  # -n_p . d
            -m.sin(bq) * dx + m.cos(bq) * dy,  # n_q . d
        ]

    # features: e_l (0, 1), cos beta_p, cos beta_q (2, 3), sin beta_p, sin beta_q (4, 5),
    # e_p . d, e_q . d (6, 7); d e2 = n_p . (d r_p - d r_q) + (e_p . d) d phi_p and
    # d e3 = n_q . (d r_q - d r_p) - (e_q . d) d phi_q with n = (-sin, cos)
    jacobian_entries = (*elongation_entries(0, 3),
                        (1, 0, 4, -1.0), (1, 1, 2, 1.0), (1, 2, 6, 1.0), (1, 3, 4, 1.0),
                        (1, 4, 2, -1.0),
                        (2, 0, 5, 1.0), (2, 1, 3, -1.0), (2, 3, 5, -1.0), (2, 4, 3, 1.0),
                        (2, 5, 7, -1.0))

    @classmethod
    def _frames(cls, xe, ref):
        d, length, e_l = chord(xe, cls.ends)
        e_p, n_p = unit_and_normal(ref.angle + xe[..., _PHI_P])
        e_q, n_q = unit_and_normal(ref.angle + xe[..., _PHI_Q])
        return d, length, e_l, e_p, n_p, e_q, n_q

    @classmethod
    def hessian(cls, xe: np.ndarray, ref: Reference) -> np.ndarray:
        d, length, e_l, e_p, n_p, e_q, n_q = cls._frames(xe, ref)
        hess = np.zeros((*xe.shape[:-1], 3, 6, 6))
        hess[..., 0, _TRANS[:, None], _TRANS] = elongation_hessian(length, e_l)
        # e2 = -n_p . d and e3 = +n_q . d
        normal_distance_hessian(hess[..., 1, :, :], cls.ends, _PHI_P, dot(n_p, d), e_p,
                                sign=-1.0)
        normal_distance_hessian(hess[..., 2, :, :], cls.ends, _PHI_Q, dot(n_q, d), e_q,
                                sign=1.0)
        return hess

    @classmethod
    def interpolate(cls, xe: np.ndarray, ref: Reference, xi: float) -> np.ndarray:
        """Point at ``xi`` in [0, 1] along each beam by the cubic Hermite interpolation
        of THEORY section 5: ``H1 r_p + H2 l0 e_p + H3 r_q + H4 l0 e_q``, shape ``(n, 2)`` [m].

        ``xe`` has shape ``(n, 6)`` (or ``(6,)`` for one beam)."""
        xe = np.atleast_2d(xe)
        e_p, _ = unit_and_normal(ref.angle + xe[:, _PHI_P])
        e_q, _ = unit_and_normal(ref.angle + xe[:, _PHI_Q])
        h1, h2 = 1 - 3 * xi**2 + 2 * xi**3, xi - 2 * xi**2 + xi**3
        h3, h4 = 3 * xi**2 - 2 * xi**3, -(xi**2) + xi**3
        length = ref.length[:, None]
        return h1 * xe[:, _RP] + h2 * length * e_p + h3 * xe[:, _RQ] + h4 * length * e_q

    # --- inertia: cubic Hermite interpolation r(xi) = sum_i H_i(xi) A_i x (THEORY 5) ------
    # A_1, A_3 pick r_p, r_q; A_2 = l0 n_p on phi_p and A_4 = l0 n_q on phi_q. With
    # P_ij = int H_i H_j the consistent mass matrix is m sum_ij P_ij A_i^T A_j and the
    # inertia force m sum_ij P_ij A_i^T c_j, c_j = A_j xddot + (convective part of
    # the acceleration of the interpolation points).
    @classmethod
    def mass_matrix(cls, xe, ref, mass, lumped):
        """Consistent: ``m int N^T N dxi = m A^T (P x I) A`` with ``A`` the stacked
        ``A_i`` ``(8, 6)``; lumped: ``m/2`` at each end, no rotary inertia."""
        _, n_p = unit_and_normal(ref.angle + xe[..., _PHI_P])
        _, n_q = unit_and_normal(ref.angle + xe[..., _PHI_Q])
        shape = np.broadcast_to(_SHAPE_TEMPLATE, (*xe.shape[:-1], 8, 6)).copy()
        shape[..., 2:4, _PHI_P] = ref.length[:, None] * n_p
        shape[..., 6:8, _PHI_Q] = ref.length[:, None] * n_q
        consistent = np.swapaxes(shape, -1, -2) @ (_HERMITE_BLOCKS @ shape)
        consistent *= mass[:, None, None]
        if not np.any(lumped):
            return consistent
        return np.where(lumped[:, None, None], rod_mass_matrix(6, cls.ends, mass, lumped),
                        consistent)

    @classmethod
    def mass_terms(cls, ref, mass, lumped):
        """The consistent ``m A^T (P x I) A`` is affine in ``phi = (sin beta_p, sin beta_q,
        cos beta_p, cos beta_q, n_p . n_q)``: ``A`` holds ``l0 n`` (``n = (-sin, cos)``)
        in the angle columns, and ``n . n = 1``. ``M0``: the translational blocks ``P_ij
        I`` and ``l0^2 P_22``, ``l0^2 P_44`` at the angles; ``M_k``: ``l0 P_i2`` (``P_i4``)
        times a component of ``n_p`` (``n_q``) between ``r_p, r_q`` and the angle, and
        ``l0^2 P_24`` between the angles. Lumped: the constant rod matrix."""
        n, P, l0 = len(mass), HERMITE_PRODUCTS, ref.length
        M0, terms = np.zeros((n, 6, 6)), np.zeros((n, 5, 6, 6))
        for (a, i), (b, j) in itertools.product(((0, 0), (3, 2)), repeat=2):  # r_p, r_q
            M0[:, [a, a + 1], [b, b + 1]] = P[i, j]
        M0[:, _PHI_P, _PHI_P], M0[:, _PHI_Q, _PHI_Q] = l0**2 * P[1, 1], l0**2 * P[3, 3]
        for angle, k_sin, k_cos, shape in ((_PHI_P, 0, 2, 1), (_PHI_Q, 1, 3, 3)):
            for r, i in ((0, 0), (3, 2)):  # n = (-sin, cos) against r_p (H1) and r_q (H3)
                terms[:, k_sin, r, angle] = terms[:, k_sin, angle, r] = -l0 * P[i, shape]
                terms[:, k_cos, r + 1, angle] = terms[:, k_cos, angle, r + 1] = l0 * P[i, shape]
        terms[:, 4, _PHI_P, _PHI_Q] = terms[:, 4, _PHI_Q, _PHI_P] = l0**2 * P[1, 3]
        M0 *= mass[:, None, None]
        terms *= np.where(lumped, 0.0, mass)[:, None, None, None]
        return np.where(lumped[:, None, None], rod_mass_matrix(6, cls.ends, mass, lumped),
                        M0), terms

    @classmethod
    def mass_features(cls, xe, ref, geometry=None):
        cos, sin = _end_cos_sin(xe, ref, geometry)
        turn = cos[..., 0] * cos[..., 1] + sin[..., 0] * sin[..., 1]  # n_p . n_q
        return np.concatenate([sin, cos, turn[..., None]], axis=-1)

    @classmethod
    def inertia_velocity(cls, xe, xde, ref, mass, lumped):
        """``h = m int N^T a dxi`` with ``a = -l0 (w_p^2 H2 e_p + w_q^2 H4 e_q)``."""
        return cls.inertia_force(xe, xde, np.zeros(xe.shape), ref, mass, lumped)

    @classmethod
    def inertia_force(cls, xe, xde, xdde, ref, mass, lumped, geometry=None):
        """``M xddot + h = m sum_ij P_ij A_i^T c_j`` with ``c = (a_p, l0 (phidd_p n_p -
        phid_p^2 e_p), a_q, l0 (phidd_q n_q - phid_q^2 e_q))``; lumped: ``m/2 (a_p, a_q)``."""
        cos, sin = _end_cos_sin(xe, ref, geometry)
        l0 = ref.length[:, None]
        alpha, omega2 = xdde[..., _ANGLES], xde[..., _ANGLES] ** 2  # both ends, (..., n, 2)
        c = np.empty((*xe.shape[:-1], 4, 2))
        c[..., 0, :], c[..., 2, :] = xdde[..., 0:2], xdde[..., 3:5]
        c[..., 1::2, 0] = -l0 * (alpha * sin + omega2 * cos)
        c[..., 1::2, 1] = l0 * (alpha * cos - omega2 * sin)
        b = HERMITE_PRODUCTS @ c  # (..., n, 4, 2): sum_j P_ij c_j
        out = np.empty(xe.shape)
        out[..., 0:2], out[..., 3:5] = b[..., 0, :], b[..., 2, :]
        out[..., _ANGLES] = l0 * (cos * b[..., 1::2, 1] - sin * b[..., 1::2, 0])  # l0 n . b
        out *= mass[:, None]
        if lumped.any():
            out = np.where(lumped[:, None], rod_inertia_force(xdde, cls.ends, mass, lumped), out)
        return out

    @classmethod
    def gravity_load(cls, xe, ref, mass, lumped, gravity):
        """Consistent: ``m int N^T g dxi = m [g/2, l0 (n_p.g)/12, g/2, -l0 (n_q.g)/12]``;
        lumped: ``m g / 2`` at each end."""
        _, n_p = unit_and_normal(ref.angle + xe[..., _PHI_P])
        _, n_q = unit_and_normal(ref.angle + xe[..., _PHI_Q])
        H = HERMITE_INTEGRALS
        out = np.empty(xe.shape)
        out[..., _RP] = H[0] * gravity
        out[..., _PHI_P] = H[1] * ref.length * dot(n_p, gravity)
        out[..., _RQ] = H[2] * gravity
        out[..., _PHI_Q] = H[3] * ref.length * dot(n_q, gravity)
        return np.where(lumped[:, None], rod_gravity_load(xe, cls.ends, mass, gravity),
                        out * mass[:, None])

    @classmethod
    def elastic_matrices(cls, ref, props):
        """Elongation ``EA/l0``; bending ``EI/((1+Phi) l0^3) [[4+Phi, Phi-2], [Phi-2, 4+Phi]]``
        on ``(e2, e3)`` with ``Phi = 12 EI / (G A_s l0^2)`` (0 without shear), THEORY 6.
        Damping: ``c_A / l0`` and the Euler-Bernoulli matrix with ``c_I`` for ``EI``."""
        S, C = elongation_matrices(ref, props, 3)
        l0 = ref.length
        with np.errstate(divide="ignore", invalid="ignore"):
            phi = np.where(props.shear_stiffness > 0,
                           12 * props.bending_stiffness / (props.shear_stiffness * l0**2), 0.0)
        factor = props.bending_stiffness / ((1 + phi) * l0**3)
        S[:, 1, 1] = S[:, 2, 2] = factor * (4 + phi)
        S[:, 1, 2] = S[:, 2, 1] = factor * (phi - 2)
        damping = props.bending_damping / l0**3
        C[:, 1, 1] = C[:, 2, 2] = 4 * damping
        C[:, 1, 2] = C[:, 2, 1] = -2 * damping
        return S, C


def _end_cos_sin(xe, ref, geometry=None) -> tuple[np.ndarray, np.ndarray]:
    """``cos beta, sin beta`` at both ends ``(..., n, 2)``, from ``geometry`` when given
    (the inertia kernels need the angles alone, not the chord)."""
    if geometry is not None:
        return geometry.cos, geometry.sin
    beta = xe[..., _ANGLES] + ref.angle[:, None]
    return np.cos(beta), np.sin(beta)
