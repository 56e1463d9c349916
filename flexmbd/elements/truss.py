"""Planar truss (PLTRUSS): one elongation ``e1 = l - l0`` (THEORY section 2)."""

from __future__ import annotations

import numpy as np

from .base import (
    TRANSLATIONAL,
    ElementType,
    Reference,
    chord,
    elongation_entries,
    elongation_hessian,
    elongation_matrices,
    elongation_rate2,
    rod_geometry,
    rod_gravity_load,
    rod_inertia_force,
    rod_mass_matrix,
)


class Truss(ElementType):
    """Two translational nodes ``p, q``; coordinates ``[x_p, y_p, x_q, y_q]``."""

    name = "truss"
    keyword = "PLTRUSS"
    node_kinds = (TRANSLATIONAL, TRANSLATIONAL)
    node_roles = ("p", "q")
    deformation_names = ("elongation",)
    ends = ((0, 1), (2, 3))
    mass_varies = False

    @staticmethod
    def formula(c, length, angle, m):
        xp, yp, xq, yq = c
        return [m.sqrt((xq - xp) ** 2 + (yq - yp) ** 2) - length]

    jacobian_entries = elongation_entries(0, 2)  # features: e_l

    @classmethod
    def deformations(cls, xe: np.ndarray, ref: Reference) -> np.ndarray:
        return (cls.geometry(xe, ref).length - ref.length)[..., None]

    @classmethod
    def geometry(cls, xe, ref):
        """The chord, as a :class:`~flexmbd.elements.base.RodGeometry` without angles."""
        return rod_geometry(xe, ref, 0, 2)

    @classmethod
    def deformations_and_features(cls, xe, ref, geometry=None):
        g = geometry or cls.geometry(xe, ref)
        return (g.length - ref.length)[..., None], g.unit

    @classmethod
    def hessian(cls, xe: np.ndarray, ref: Reference) -> np.ndarray:
        _, length, e_l = chord(xe, cls.ends)
        return elongation_hessian(length, e_l)[..., None, :, :]

    @classmethod
    def quadratic_velocity(cls, xe: np.ndarray, xde: np.ndarray, ref: Reference,
                           geometry=None) -> np.ndarray:
        g = geometry or cls.geometry(xe, ref)
        return elongation_rate2(g, xde[..., 2:4] - xde[..., 0:2])[..., None]

    @classmethod
    def mass_matrix(cls, xe, ref, mass, lumped):
        return np.broadcast_to(rod_mass_matrix(4, cls.ends, mass, lumped), (*xe.shape, 4))

    @classmethod
    def inertia_force(cls, xe, xde, xdde, ref, mass, lumped, geometry=None):
        """``m/6 (2 a_p + a_q, a_p + 2 a_q)`` (consistent) or ``m/2 (a_p, a_q)`` (lumped)."""
        return rod_inertia_force(xdde, cls.ends, mass, lumped)

    @classmethod
    def gravity_load(cls, xe, ref, mass, lumped, gravity):
        return rod_gravity_load(xe, cls.ends, mass, gravity)

    @classmethod
    def elastic_matrices(cls, ref, props):
        """``EA / l0`` and ``c_A / l0`` on the elongation."""
        return elongation_matrices(ref, props, 1)
