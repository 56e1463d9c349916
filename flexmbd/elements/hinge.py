"""Planar hinge (PLHINGE): relative rotation ``e1 = phi_q - phi_p`` (THEORY section 2)."""

from __future__ import annotations

from .base import ElementType, Value, rotational


class Hinge(ElementType):
    """Two rotational nodes; coordinates ``[phi_p, phi_q]``. No mass (put rotary inertia
    on its nodes with ``XM``).

    Properties: ``ESTIFF`` a torsional spring ``k`` [N m/rad], ``EDAMP`` a rotational
    damper ``c`` [N m s/rad]: torque ``k e1 + c e1dot + sigma0`` [N m].
    """

    name = "hinge"
    keyword = "PLHINGE"
    roles = (rotational("phi_p"), rotational("phi_q"))
    deformation_names = ("relative rotation",)
    deformation_units = ("rad",)
    reference = 0
    stiffness_values = (Value("hinge", "k", "N m/rad"),)
    damping_values = (Value("hinge", "c", "N m s/rad"),)

    @staticmethod
    def deformations(c, p, m):
        return [c[1] - c[0]]

    @classmethod
    def elastic_law(cls, p, stiffness, damping):
        """The torsional spring ``k`` [N m/rad] and damper ``c`` [N m s/rad], ``(n, 1, 1)``."""
        return stiffness["hinge"][:, None, None].copy(), damping["hinge"][:, None, None].copy()
