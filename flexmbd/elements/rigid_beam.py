"""Rigid beam with one rotational node (PLRBEAM, flexmbd's keyword; THEORY section 2).

Coordinates ``[x_p, y_p, phi_p, x_q, y_q]``; deformations ``e1 = l - l0`` and
``e2 = n_p . d`` (note the sign, opposite to the beam's ``e2``). Both are normally
rigid: the element fixes the distance of p and q and ties the angle ``phi_p`` to
the direction of the chord.
"""

from __future__ import annotations

from .base import (
    AXIAL_DAMPING,
    AXIAL_STIFFNESS,
    ElementType,
    chord,
    elongation_law,
    rotational,
    translational,
)
from .truss import along_chord, elongation


class RigidBeam(ElementType):
    """Beam with a rotational node at p only; two deformations.

    Properties: ``EM`` (``rhoA`` [kg/m]; consistent: the rod's linear velocity field,
    exact for a rigid link), ``ESTIFF`` ``EA`` [N], ``EDAMP`` ``c_A`` [N s].
    """

    name = "rigid beam"
    keyword = "PLRBEAM"
    roles = (translational("p"), rotational("phi_p"), translational("q"))
    deformation_names = ("elongation", "normal offset")
    deformation_units = ("m", "m")
    stiffness_values = (AXIAL_STIFFNESS,)
    damping_values = (AXIAL_DAMPING,)
    has_mass = True

    @staticmethod
    def deformations(c, p, m):
        dx, dy = chord(c, 0, 3)
        beta = p[1] + c[2]
        return [elongation(c, 0, 3, p[0], m), -m.sin(beta) * dx + m.cos(beta) * dy]  # n_p . d

    @staticmethod
    def material_point(c, p, xi, m):
        return along_chord(c, 0, 3, xi)

    @classmethod
    def lumped_masses(cls, p, mass):
        """``m/2`` at each end plus the rotary inertia ``J = m l0^2/12 - m l0^2/4 =
        -m l0^2/6`` at ``phi_p``, so that lumped and consistent give the same reduced
        mass matrix for a rigid link (THEORY section 5)."""
        out = super().lumped_masses(p, mass)
        out[:, 2] = -mass * p[:, 0] ** 2 / 6.0
        return out

    @classmethod
    def elastic_law(cls, p, stiffness, damping):
        """Only the elongation has a stiffness; the normal offset has pre-stress only."""
        return elongation_law(p, 2, stiffness["axial"], damping["axial"])


