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

_RP, _PHI_P, _RQ = [0, 1], 2, [3, 4]
_ANGLE = slice(_PHI_P, _PHI_P + 1)
_TRANS = np.array(_RP + _RQ)


class RigidBeam(AngledRod):
    """Beam with rotational node at p only; two deformations."""

    name = "rigid beam"
    keyword = "PLRBEAM"
    node_kinds = (TRANSLATIONAL, ROTATIONAL, TRANSLATIONAL)
    node_roles = ("p", "phi_p", "q")
    deformation_names = ("elongation", "normal offset")
    ends = ((0, 1), (3, 4))
    mass_varies = False
    angles = _ANGLE
    normal_signs = np.array([1.0])  # e2 = +n_p . d

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

    # features: e_l (0, 1), cos beta_p (2), sin beta_p (3), e_p . d (4);
    # d e2 = n_p . (d r_q - d r_p) - (e_p . d) d phi_p with n_p = (-sin, cos)
    jacobian_entries = (*elongation_entries(0, 3), (1, 0, 3, 1.0), (1, 1, 2, -1.0),
                        (1, 2, 4, -1.0), (1, 3, 3, -1.0), (1, 4, 2, 1.0))

    @classmethod
    def hessian(cls, xe: np.ndarray, ref: Reference) -> np.ndarray:
        d, length, e_l, e_p, n_p = cls._frames(xe, ref)
        hess = np.zeros((*xe.shape[:-1], 2, 5, 5))
        hess[..., 0, _TRANS[:, None], _TRANS] = elongation_hessian(length, e_l)
        normal_distance_hessian(hess[..., 1, :, :], cls.ends, _PHI_P, dot(n_p, d), e_p,
                                sign=1.0)
        return hess

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
