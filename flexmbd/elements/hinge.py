"""Planar hinge (PLHINGE): relative rotation ``e1 = phi_q - phi_p``."""

from __future__ import annotations

import numpy as np

from .base import ROTATIONAL, ElementType, Reference


class Hinge(ElementType):
    """Two rotational nodes; coordinates ``[phi_p, phi_q]``. Linear, so ``D_xx = 0``."""

    name = "hinge"
    keyword = "PLHINGE"
    node_kinds = (ROTATIONAL, ROTATIONAL)
    node_roles = ("phi_p", "phi_q")
    deformation_names = ("relative rotation",)
    mass_varies = False

    @staticmethod
    def formula(c, length, angle, m):
        php, phq = c
        return [phq - php]

    jacobian_entries = ((0, 0, 0, -1.0), (0, 1, 0, 1.0))  # feature: the constant 1

    @classmethod
    def deformations_and_features(cls, xe, ref, geometry=None):
        return xe[..., 1:] - xe[..., :1], np.ones((*xe.shape[:-1], 1))

    @classmethod
    def hessian(cls, xe: np.ndarray, ref: Reference) -> np.ndarray:
        return np.zeros((*xe.shape[:-1], 1, 2, 2))

    @classmethod
    def quadratic_velocity(cls, xe: np.ndarray, xde: np.ndarray, ref: Reference,
                           geometry=None) -> np.ndarray:
        return np.zeros((*xe.shape[:-1], 1))

    @classmethod
    def elastic_matrices(cls, ref, props):
        """Torsional spring ``k`` [N m/rad] and damper ``c`` [N m s/rad]: torque
        ``k e1 + c e1dot + sigma0`` [N m]."""
        return (props.hinge_stiffness[:, None, None].copy(),
                props.hinge_damping[:, None, None].copy())
