"""The Euler element of a spatial rotational node: its normalization ``e1 = lam . lam - 1``,
always rigid, and the node's rotary inertia (THEORY-SPATIAL 1 and 4).

The builder adds one for every spatial rotational node, after the user's elements (as
SPACAR numbers them), so that the four Euler parameters stay ordinary, additive
coordinates. Its reference parameters hold the node's inertia tensor ``Jb`` in the body
frame (``XM`` plus the lumped rotary inertia of the beams at the node), and its kernels
the mass ``4 G^T Jb G`` and the velocity term ``2 G^T (omega' x Jb omega')``.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from .base import ElementType, spatial_rotational
from .rotations import body_rates


class EulerNormalization(ElementType):
    """One spatial rotational node; coordinates ``[lam0, lam1, lam2, lam3]``."""

    name = "Euler normalization"
    keyword = "EULER"
    roles = (spatial_rotational("lam"),)
    deformation_names = ("normalization",)
    deformation_units = ("-",)
    reference = 6   # Jb: Jxx, Jxy, Jxz, Jyy, Jyz, Jzz
    element_data: ClassVar[dict[str, tuple[float, ...] | None]] = {"inertia": (0.0,) * 6}
    has_mass = True
    automatic = True

    @classmethod
    def reference_parameters(cls, xe0, data=None):
        """``(n, 6)``: the inertia tensor ``Jxx, Jxy, Jxz, Jyy, Jyz, Jzz`` [kg m^2]."""
        n = len(np.atleast_2d(xe0))
        return np.asarray((data or {}).get("inertia", np.zeros((n, 6))),
                          dtype=float).reshape(n, 6)

    @staticmethod
    def deformations(c, p, m):
        return [c[0] ** 2 + c[1] ** 2 + c[2] ** 2 + c[3] ** 2 - 1]

    @staticmethod
    def body_angular_velocity(c, m):
        """``W = 2 G(lam)``: ``omega' = 2 G(lam) lamdot``."""
        return [[2 * g for g in row] for row in body_rates(c)]

    @staticmethod
    def inertia_tensor(p):
        return [[p[0], p[1], p[2]], [p[1], p[3], p[4]], [p[2], p[4], p[5]]]

    @classmethod
    def element_mass(cls, p, mass_per_length):
        """1 where the node has rotary inertia (the kernels carry ``Jb``), else 0."""
        return np.any(p != 0.0, axis=1).astype(float)
