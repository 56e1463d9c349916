"""Rigid beam with one rotational node (THEORY section 2, as in the exercises).

Coordinates ``[x_p, y_p, phi_p, x_q, y_q]``; deformations ``e1 = l - l0`` and
``e2 = n_p . d`` (note the sign, opposite to the beam's ``e2``). Both are
normally rigid: the element fixes the distance of p and q and ties the angle
``phi_p`` to the direction of the chord.
"""

from __future__ import annotations

import numpy as np

from .base import (
    ROTATIONAL,
    TRANSLATIONAL,
    ElementType,
    Reference,
    chord,
    chord_of,
    cos_sin,
    dot,
    elongation_hessian,
    elongation_matrices,
    elongation_rate2,
    elongation_row,
    normal_distance_hessian,
    rod_gravity_load,
    rod_inertia_force,
    rod_mass_matrix,
    unit_and_normal,
)

_RP, _PHI_P, _RQ = [0, 1], 2, [3, 4]
_TRANS = np.array(_RP + _RQ)


class RigidBeam(ElementType):
    """Beam with rotational node at p only; two deformations."""

    name = "rigid beam"
    keyword = "PLRBEAM"
    node_kinds = (TRANSLATIONAL, ROTATIONAL, TRANSLATIONAL)
    node_roles = ("p", "phi_p", "q")
    deformation_names = ("elongation", "normal offset")
    ends = ((0, 1), (3, 4))
    mass_varies = False

    @staticmethod
    def formula(c, length, angle, m):
        xp, yp, php, xq, yq = c
        dx, dy = xq - xp, yq - yp
        bp = angle + php
        return [m.sqrt(dx**2 + dy**2) - length, -m.sin(bp) * dx + m.cos(bp) * dy]

    @classmethod
    def _frames(cls, xe, ref):
        d, length, e_l = chord(xe, cls.ends)
        e_p, n_p = unit_and_normal(ref.angle + xe[..., _PHI_P])
        return d, length, e_l, e_p, n_p

    @classmethod
    def geometry(cls, xe, ref):
        """The chord and ``cos, sin`` of the end angle, shared by the hot kernels."""
        return (chord_of(xe, 0, 3), *cos_sin(ref.angle + xe[..., _PHI_P]))

    @staticmethod
    def _deformations_of(ch, c, s, ref):
        e = np.empty((*ch.length.shape, 2))
        e[..., 0], e[..., 1] = ch.length - ref.length, c * ch.dy - s * ch.dx  # n_p . d
        return e

    @classmethod
    def deformations(cls, xe: np.ndarray, ref: Reference) -> np.ndarray:
        return cls._deformations_of(*cls.geometry(xe, ref), ref)

    @classmethod
    def jacobian(cls, xe: np.ndarray, ref: Reference) -> np.ndarray:
        return cls.deformations_and_jacobian(xe, ref)[1]

    @classmethod
    def deformations_and_jacobian(cls, xe, ref, geometry=None):
        ch, c, s = geometry or cls.geometry(xe, ref)
        e = cls._deformations_of(ch, c, s, ref)
        jac = np.zeros((*xe.shape[:-1], 2, 5))
        elongation_row(jac[..., 0, :], ch, 0, 3)
        row = jac[..., 1, :]  # d e2 = n_p . (d r_q - d r_p) - (e_p . d) d phi_p
        row[..., 0], row[..., 1], row[..., 3], row[..., 4] = s, -c, -s, c
        row[..., 2] = -(c * ch.dx + s * ch.dy)
        return e, jac

    @classmethod
    def hessian(cls, xe: np.ndarray, ref: Reference) -> np.ndarray:
        d, length, e_l, e_p, n_p = cls._frames(xe, ref)
        hess = np.zeros((*xe.shape[:-1], 2, 5, 5))
        hess[..., 0, _TRANS[:, None], _TRANS] = elongation_hessian(length, e_l)
        normal_distance_hessian(hess[..., 1, :, :], cls.ends, _PHI_P, dot(n_p, d), e_p,
                                sign=1.0)
        return hess

    @classmethod
    def quadratic_velocity(cls, xe: np.ndarray, xde: np.ndarray, ref: Reference,
                           geometry=None) -> np.ndarray:
        ch, c, s = geometry or cls.geometry(xe, ref)
        dvx, dvy = xde[..., 3] - xde[..., 0], xde[..., 4] - xde[..., 1]
        w_p = xde[..., _PHI_P]
        out = np.empty((*xe.shape[:-1], 2))
        out[..., 0] = elongation_rate2(ch, dvx, dvy)
        # -w_p^2 (n_p . d) - 2 w_p (e_p . dv)
        out[..., 1] = -w_p * (w_p * (c * ch.dy - s * ch.dx) + 2.0 * (c * dvx + s * dvy))
        return out

    @classmethod
    def mass_matrix(cls, xe, ref, mass, lumped):
        """Consistent: the rod matrix on ``r_p, r_q``. Lumped: ``m/2`` at each end plus
        the rotary inertia ``J = m l0^2/12 - m l0^2/4 = -m l0^2/6`` at ``phi_p``, so that
        both give the same reduced mass matrix for a rigid link (THEORY section 5)."""
        out = rod_mass_matrix(5, cls.ends, mass, lumped)
        out[:, _PHI_P, _PHI_P] = _rotary_inertia(ref, mass, lumped)
        return np.broadcast_to(out, (*xe.shape, 5))

    @classmethod
    def inertia_force(cls, xe, xde, xdde, ref, mass, lumped, geometry=None):
        out = rod_inertia_force(xdde, cls.ends, mass, lumped)
        out[..., _PHI_P] = _rotary_inertia(ref, mass, lumped) * xdde[..., _PHI_P]
        return out

    @classmethod
    def gravity_load(cls, xe, ref, mass, lumped, gravity):
        return rod_gravity_load(xe, cls.ends, mass, gravity)

    @classmethod
    def elastic_matrices(cls, ref, props):
        """Only the elongation has a stiffness (``EA / l0``, ``c_A / l0``); the normal
        offset has pre-stress only."""
        return elongation_matrices(ref, props, 2)


def _rotary_inertia(ref: Reference, mass: np.ndarray, lumped: np.ndarray) -> np.ndarray:
    """``-m l0^2 / 6`` at ``phi_p`` of a lumped rigid beam, 0 for a consistent one."""
    return np.where(lumped, -mass * ref.length**2 / 6.0, 0.0)
