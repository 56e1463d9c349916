"""Planar truss (PLTRUSS): one elongation ``e1 = l - l0`` (THEORY section 2)."""

from __future__ import annotations

from .base import AXIAL_DAMPING, AXIAL_STIFFNESS, ElementType, chord, elongation_law, translational


def elongation(c, p_at: int, q_at: int, length, m, width: int = 2):
    """``l - l0``: the distance of ``r_p`` (at ``c[p_at]``) and ``r_q`` less ``length``, in
    the plane or (``width = 3``) in space."""
    return m.sqrt(sum(d**2 for d in chord(c, p_at, q_at, width))) - length


def along_chord(c, p_at: int, q_at: int, xi, width: int = 2):
    """The point ``(1 - xi) r_p + xi r_q``: a rod's linear interpolation."""
    return [(1 - xi) * c[p_at + k] + xi * c[q_at + k] for k in range(width)]


class Truss(ElementType):
    """Two translational nodes ``p, q``; coordinates ``[x_p, y_p, x_q, y_q]``.

    Properties: ``EM`` (``rhoA`` [kg/m]), ``ESTIFF`` ``EA`` [N], ``EDAMP`` ``c_A`` [N s].
    """

    name = "truss"
    keyword = "PLTRUSS"
    roles = (translational("p"), translational("q"))
    deformation_names = ("elongation",)
    deformation_units = ("m",)
    reference = 1
    stiffness_values = (AXIAL_STIFFNESS,)
    damping_values = (AXIAL_DAMPING,)
    has_mass = True

    @classmethod
    def deformations(cls, c, p, m):
        """The elongation, in the plane or in space (:class:`SpatialTruss`)."""
        width = cls.dimension()
        return [elongation(c, 0, width, p[0], m, width)]

    @classmethod
    def material_point(cls, c, p, xi, m):
        """The rod's linear interpolation ``(1 - xi) r_p + xi r_q``."""
        width = cls.dimension()
        return along_chord(c, 0, width, xi, width)

    @classmethod
    def elastic_law(cls, p, stiffness, damping):
        """``EA / l0`` and ``c_A / l0`` on the elongation."""
        return elongation_law(p, 1, stiffness["axial"], damping["axial"])
