"""Planar spring-damper (PLSPRING, flexmbd's keyword): a massless force element.

Its one deformation is the elongation ``e1 = l - l0`` of the line between its
translational nodes ``p`` and ``q`` (``l0`` their initial distance). The force
along that line is ``sigma = k e1 + c e1dot + sigma0`` [N], positive in tension,
with the stiffness ``k`` (``ESTIFF e k`` [N/m]), the damping ``c`` (``EDAMP e c``
[N s/m]) and the pre-load ``sigma0`` (``ESIG e sigma0`` [N]). Unlike the other
elements its deformation is *released* unless classified otherwise: a spring
exerts a force, it does not constrain.

A file line: ``PLSPRING 7 3 9`` in the kinematics block.
"""

from __future__ import annotations

import numpy as np

from .base import ElementType, Value, translational
from .truss import elongation


class SpringDamper(ElementType):
    """Two translational nodes ``p, q``; coordinates ``[x_p, y_p, x_q, y_q]``."""

    name = "spring-damper"
    keyword = "PLSPRING"
    roles = (translational("p"), translational("q"))
    deformation_names = ("elongation",)
    deformation_units = ("m",)
    reference = 1
    stiffness_values = (Value("spring", "k", "N/m"),)
    damping_values = (Value("spring", "c", "N s/m"),)
    released_by_default = True

    @staticmethod
    def deformations(c, p, m):
        return [elongation(c, 0, 2, p[0], m)]

    @classmethod
    def elastic_law(cls, p, stiffness, damping):
        """The spring ``k`` [N/m] and damper ``c`` [N s/m], each ``(n, 1, 1)``."""
        return stiffness["spring"][:, None, None].copy(), damping["spring"][:, None, None].copy()

    @classmethod
    def outline(cls, xe, p, e, exaggeration=1.0):
        """A zigzag of six turns between the end nodes."""
        s = np.linspace(0.0, 1.0, 15)
        side = np.zeros_like(s)
        side[2:-2:2], side[3:-2:2] = 1.0, -1.0
        lines = []
        for x, length in zip(xe, p[:, 0], strict=True):
            rp, d = x[0:2], x[2:4] - x[0:2]
            normal = np.array([-d[1], d[0]]) / np.hypot(d[0], d[1])
            lines.append(rp + np.outer(s, d) + np.outer(0.08 * length * side, normal))
        return lines
