"""Spatial hinge (HINGE): the rotation about an axis, continuous through any number of
turns, and two misalignments, between two spatial rotational nodes (THEORY-SPATIAL 3).

With the hinge frame ``ex0`` (the axis), ``ey0``, ``ez0`` turned by each node's Euler
parameters, ``S = ez_p . ey_q - ey_p . ez_q`` and ``C = ey_p . ey_q + ez_p . ez_q``:

* ``e1 = atan2(S, C)`` (plus the multiple of ``2 pi`` that keeps it continuous, chosen
  by the engine),
* ``e2 = -ez_p . ex_q`` and ``e3 = ey_p . ex_q``: the tilt of q's axis seen in p's
  frame. Unlike the symmetric form they keep full rank at every hinge angle.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from .base import ElementType, Value, spatial_rotational
from .rotations import dot, frame_columns, rotate
from .spatial_beam import default_orientation


def hinge_frame(axis: np.ndarray) -> np.ndarray:
    """Reference frames ``(n, 3, 3)`` (columns ``ex0, ey0, ez0``) of ``n`` hinges with axes
    ``(n, 3)``, as SPACAR sets them: ``ex0`` the unit axis, ``ey0 = unit(ex0 x e_k)`` with
    ``e_k`` the global axis along which the axis has its smallest component (the last of
    equal ones, :func:`~flexmbd.elements.spatial_beam.default_orientation`), ``ez0 = ex0
    x ey0``. A hinge about z has ``ey0 = -x``, ``ez0 = y``."""
    ex = axis / np.linalg.norm(axis, axis=1, keepdims=True)
    ey = np.cross(ex, default_orientation(ex))
    ey = ey / np.linalg.norm(ey, axis=1, keepdims=True)
    return np.stack([ex, ey, np.cross(ex, ey)], axis=2)


class SpatialHinge(ElementType):
    """Two spatial rotational nodes; coordinates ``[lam_p (4), lam_q (4)]``. No mass (put
    rotary inertia on its nodes with ``XM``).

    Element data: ``axis``, the hinge axis [-] in the reference configuration.

    Properties: ``ESTIFF`` springs ``k1`` [N m/rad] on the rotation and ``k2, k3`` [N m/rad]
    on the misalignments, ``EDAMP`` dampers ``c1, c2, c3`` [N m s/rad].
    """

    name = "spatial hinge"
    keyword = "HINGE"
    roles = (spatial_rotational("lam_p"), spatial_rotational("lam_q"))
    deformation_names = ("rotation", "misalignment about y", "misalignment about z")
    deformation_units = ("rad", "rad", "rad")
    reference = 9   # the frame ex0, ey0, ez0
    element_data: ClassVar[dict[str, tuple[float, ...] | None]] = {"axis": (0.0, 0.0, 1.0)}
    periodic = (0,)
    stiffness_values = (Value("hinge", "k1", "N m/rad"), Value("tilt_y", "k2", "N m/rad"),
                        Value("tilt_z", "k3", "N m/rad"))
    damping_values = (Value("hinge", "c1", "N m s/rad"), Value("tilt_y", "c2", "N m s/rad"),
                      Value("tilt_z", "c3", "N m s/rad"))

    @classmethod
    def reference_parameters(cls, xe0, data=None):
        """``(n, 9)``: the hinge frame ``ex0, ey0, ez0`` from the axis."""
        n = len(np.atleast_2d(xe0))
        axis = np.asarray((data or {}).get("axis", np.tile([0.0, 0.0, 1.0], (n, 1))),
                          dtype=float).reshape(n, 3)
        return hinge_frame(axis).transpose(0, 2, 1).reshape(n, 9)

    @classmethod
    def check_data(cls, xe0, data):
        """The axis must be three finite numbers, not all zero."""
        axis = np.asarray(data.get("axis", (0.0, 0.0, 1.0)), dtype=float)
        if axis.shape != (3,) or not np.all(np.isfinite(axis)) or not np.any(axis):
            return [f"axis {tuple(axis.ravel().tolist())} is not three finite numbers, not all "
                    f"zero"]
        return []

    @staticmethod
    def deformations(c, p, m):
        ex0, ey0, ez0 = frame_columns(p, 0)
        lam_p, lam_q = c[0:4], c[4:8]
        ey_p, ez_p = rotate(lam_p, ey0), rotate(lam_p, ez0)
        ex_q, ey_q, ez_q = rotate(lam_q, ex0), rotate(lam_q, ey0), rotate(lam_q, ez0)
        sine = dot(ez_p, ey_q) - dot(ey_p, ez_q)
        cosine = dot(ey_p, ey_q) + dot(ez_p, ez_q)
        return [m.atan2(sine, cosine), -dot(ez_p, ex_q), dot(ey_p, ex_q)]

    @classmethod
    def elastic_law(cls, p, stiffness, damping):
        """Diagonal springs ``k1, k2, k3`` and dampers ``c1, c2, c3``, ``(n, 3, 3)``."""
        names = ("hinge", "tilt_y", "tilt_z")
        S = np.stack([np.diag([stiffness[k][i] for k in names]) for i in range(len(p))])
        C = np.stack([np.diag([damping[k][i] for k in names]) for i in range(len(p))])
        return S.reshape(len(p), 3, 3), C.reshape(len(p), 3, 3)
