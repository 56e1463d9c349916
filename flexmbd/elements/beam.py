"""Planar beam (PLBEAM): elongation and two bending deformations (THEORY section 2).

``e1 = l - l0``, ``e2 = -n_p . d``, ``e3 = n_q . d`` with ``d = r_q - r_p`` and
``n_p = n(beta0 + phi_p)``, ``n_q = n(beta0 + phi_q)``.
"""

from __future__ import annotations

import numpy as np

from .base import (
    ROTATIONAL,
    TRANSLATIONAL,
    ElementType,
    Reference,
    chord,
    dot,
    elongation_hessian,
    elongation_jacobian,
    elongation_quadratic_velocity,
    elongation_stress,
    normal_distance_hessian,
    rod_gravity_load,
    rod_mass_matrix,
    unit_and_normal,
)

_RP, _PHI_P, _RQ, _PHI_Q = [0, 1], 2, [3, 4], 5
_TRANS = np.array(_RP + _RQ)

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


class Beam(ElementType):
    """Coordinates ``[x_p, y_p, phi_p, x_q, y_q, phi_q]``."""

    name = "beam"
    keyword = "PLBEAM"
    node_kinds = (TRANSLATIONAL, ROTATIONAL, TRANSLATIONAL, ROTATIONAL)
    node_roles = ("p", "phi_p", "q", "phi_q")
    deformation_names = ("elongation", "bending at p", "bending at q")
    ends = ((0, 1), (3, 4))

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

    @classmethod
    def _frames(cls, xe, ref):
        d, length, e_l = chord(xe, cls.ends)
        e_p, n_p = unit_and_normal(ref.angle + xe[:, _PHI_P])
        e_q, n_q = unit_and_normal(ref.angle + xe[:, _PHI_Q])
        return d, length, e_l, e_p, n_p, e_q, n_q

    @classmethod
    def jacobian(cls, xe: np.ndarray, ref: Reference) -> np.ndarray:
        d, _, e_l, e_p, n_p, e_q, n_q = cls._frames(xe, ref)
        jac = np.zeros((len(xe), 3, 6))
        jac[:, 0, _RP + _RQ] = elongation_jacobian(e_l)
        jac[:, 1, _RP], jac[:, 1, _RQ], jac[:, 1, _PHI_P] = n_p, -n_p, dot(e_p, d)
        jac[:, 2, _RP], jac[:, 2, _RQ], jac[:, 2, _PHI_Q] = -n_q, n_q, -dot(e_q, d)
        return jac

    @classmethod
    def hessian(cls, xe: np.ndarray, ref: Reference) -> np.ndarray:
        d, length, e_l, e_p, n_p, e_q, n_q = cls._frames(xe, ref)
        hess = np.zeros((len(xe), 3, 6, 6))
        hess[:, 0, _TRANS[:, None], _TRANS] = elongation_hessian(length, e_l)
        # e2 = -n_p . d and e3 = +n_q . d
        normal_distance_hessian(hess[:, 1], cls.ends, _PHI_P, dot(n_p, d), e_p, sign=-1.0)
        normal_distance_hessian(hess[:, 2], cls.ends, _PHI_Q, dot(n_q, d), e_q, sign=1.0)
        return hess

    @classmethod
    def quadratic_velocity(cls, xe: np.ndarray, xde: np.ndarray, ref: Reference) -> np.ndarray:
        d, length, e_l, e_p, n_p, e_q, n_q = cls._frames(xe, ref)
        dv = xde[:, _RQ] - xde[:, _RP]
        w_p, w_q = xde[:, _PHI_P], xde[:, _PHI_Q]
        return np.stack(
            [
                elongation_quadratic_velocity(length, e_l, dv),
                w_p**2 * dot(n_p, d) + 2.0 * w_p * dot(e_p, dv),
                -(w_q**2) * dot(n_q, d) - 2.0 * w_q * dot(e_q, dv),
            ],
            axis=1,
        )


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
    @classmethod
    def _shape_blocks(cls, xe, ref):
        """``A_i`` ``(4, n, 2, 6)`` with ``N(xi) = sum_i H_i(xi) A_i`` and the
        convective accelerations ``c_i`` ``(4, n, 2)`` with ``a = sum_i H_i c_i``."""
        n = len(xe)
        e_p, n_p = unit_and_normal(ref.angle + xe[:, _PHI_P])
        e_q, n_q = unit_and_normal(ref.angle + xe[:, _PHI_Q])
        length = ref.length[:, None]
        blocks = np.zeros((4, n, 2, 6))
        blocks[0, :, :, 0:2] = blocks[2, :, :, 3:5] = np.eye(2)  # r_p and r_q columns
        blocks[1, :, :, _PHI_P] = length * n_p
        blocks[3, :, :, _PHI_Q] = length * n_q
        return blocks, e_p, e_q, length

    @classmethod
    def mass_matrix(cls, xe, ref, mass, lumped):
        """Consistent: ``m int N^T N dxi``; lumped: ``m/2`` at each end, no rotary inertia."""
        blocks, *_ = cls._shape_blocks(xe, ref)
        consistent = np.einsum("ij,inak,jnal->nkl", HERMITE_PRODUCTS, blocks, blocks)
        consistent *= mass[:, None, None]
        return np.where(lumped[:, None, None], rod_mass_matrix(6, cls.ends, mass, lumped),
                        consistent)

    @classmethod
    def inertia_velocity(cls, xe, xde, ref, mass, lumped):
        """``h = m int N^T a dxi`` with ``a = -l0 (w_p^2 H2 e_p + w_q^2 H4 e_q)``."""
        blocks, e_p, e_q, length = cls._shape_blocks(xe, ref)
        convective = np.zeros((4, len(xe), 2))
        convective[1] = -length * xde[:, [_PHI_P]] ** 2 * e_p
        convective[3] = -length * xde[:, [_PHI_Q]] ** 2 * e_q
        h = np.einsum("ij,inak,jna->nk", HERMITE_PRODUCTS, blocks, convective)
        return np.where(lumped[:, None], 0.0, h * mass[:, None])

    @classmethod
    def gravity_load(cls, xe, ref, mass, lumped, gravity):
        """Consistent: ``m int N^T g dxi = m [g/2, l0 (n_p.g)/12, g/2, -l0 (n_q.g)/12]``;
        lumped: ``m g / 2`` at each end."""
        blocks, *_ = cls._shape_blocks(xe, ref)
        consistent = np.einsum("i,inak,a->nk", HERMITE_INTEGRALS, blocks, gravity)
        return np.where(lumped[:, None], rod_gravity_load(6, cls.ends, mass, gravity),
                        consistent * mass[:, None])

    @classmethod
    def stress(cls, e, ed, ref, props):
        """Elongation ``EA/l0 e1``; bending ``EI/((1+Phi) l0^3) [[4+Phi, Phi-2], [Phi-2, 4+Phi]]``
        on ``(e2, e3)`` with ``Phi = 12 EI / (G A_s l0^2)`` (0 without shear), THEORY 6.
        Damping uses the Euler-Bernoulli matrix with ``c_I`` for ``EI``."""
        sigma = props.prestress.copy()
        sigma[:, 0] += elongation_stress(e[:, 0], ed[:, 0], ref, props)
        l0 = ref.length
        with np.errstate(divide="ignore"):
            phi = np.where(props.shear_stiffness > 0,
                           12 * props.bending_stiffness / (props.shear_stiffness * l0**2), 0.0)
        factor = props.bending_stiffness / ((1 + phi) * l0**3)
        diag, off = factor * (4 + phi), factor * (phi - 2)
        damping = props.bending_damping / l0**3
        sigma[:, 1] += diag * e[:, 1] + off * e[:, 2] + damping * (4 * ed[:, 1] - 2 * ed[:, 2])
        sigma[:, 2] += off * e[:, 1] + diag * e[:, 2] + damping * (4 * ed[:, 2] - 2 * ed[:, 1])
        return sigma
