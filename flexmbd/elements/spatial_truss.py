"""Spatial truss (TRUSS): one elongation ``e1 = l - l0`` between two spatial
translational nodes (THEORY-SPATIAL 3), the planar truss's definition with three
coordinates per node."""

from __future__ import annotations

import numpy as np

from .base import spatial_translational
from .truss import Truss


def chord_lengths(xe0: np.ndarray, p_at: int, q_at: int) -> tuple[np.ndarray, np.ndarray]:
    """The reference chords ``d`` ``(n, 3)`` [m] and their lengths ``(n,)`` of ``n``
    elements at coordinates ``xe0`` ``(n, nc)``."""
    d = xe0[:, q_at:q_at + 3] - xe0[:, p_at:p_at + 3]
    return d, np.linalg.norm(d, axis=1)


class SpatialTruss(Truss):
    """Two spatial translational nodes; coordinates ``[x_p, y_p, z_p, x_q, y_q, z_q]``.

    Properties: ``EM`` (``rhoA`` [kg/m]), ``ESTIFF`` ``EA`` [N], ``EDAMP`` ``c_A`` [N s].
    """

    name = "spatial truss"
    keyword = "TRUSS"
    roles = (spatial_translational("p"), spatial_translational("q"))

    @classmethod
    def reference_parameters(cls, xe0, data=None):
        """The length ``l0`` [m] of the initial chord, ``(n, 1)``."""
        return chord_lengths(np.atleast_2d(np.asarray(xe0, dtype=float)), 0, 3)[1][:, None]
