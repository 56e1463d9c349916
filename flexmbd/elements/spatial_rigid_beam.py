"""Spatial rigid beam (RBEAM): a body carried by one spatial rotational node, from its
translational node p to a point q (SPACAR's ``RBEAM e p rp q [ox oy oz]``).

With the chord ``d = r_q - r_p``, ``l = |d|``, ``u = d / l`` and the frame vectors
``ey, ez`` of the rotational node (the reference frame turned by its Euler parameters),
the deformations are the spatial beam's at its p end (THEORY-SPATIAL 3):

* ``e1 = l - l0``,
* ``e2 = -l0 ez_p . u`` and ``e3 = l0 ey_p . u``: the chord leaving the body's x axis.

All three are normally rigid: q then moves with the body of ``rp``. SPACAR's manual does
not say in which order its RBEAM numbers the two offsets, so an input file may classify
only the elongation of an RBEAM (the reader refuses the others by line).
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from .base import (
    AXIAL_DAMPING,
    AXIAL_STIFFNESS,
    ElementType,
    chord,
    elongation_law,
    spatial_rotational,
    spatial_translational,
)
from .rotations import dot, frame_columns, rotate
from .spatial_beam import PARALLEL_LIMIT, beam_frame, default_orientation
from .spatial_truss import chord_lengths
from .truss import along_chord


class SpatialRigidBeam(ElementType):
    """A spatial translational node ``p``, its rotational node and a translational node
    ``q``: coordinates ``[x_p, y_p, z_p, lam_p (4), x_q, y_q, z_q]``.

    Element data: ``orientation``, a vector [-] across the chord that fixes the body's y
    axis; optional (``(0, 0, 0)``: SPACAR's choice, the global axis in which the chord is
    smallest, the last of equal ones, made perpendicular to it). It
    orients only the section inertia.

    Properties: ``EM`` ``rhoA`` [kg/m] (the rod's linear velocity field, exact for a rigid
    body) and the section inertias per length ``Jxx Jyy Jzz Jyz`` [kg m] (on the rotational
    node, in the body frame); ``ESTIFF`` ``EA`` [N]; ``EDAMP`` ``c_A`` [N s].
    """

    name = "spatial rigid beam"
    keyword = "RBEAM"
    roles = (spatial_translational("p"), spatial_rotational("lam_p"),
             spatial_translational("q"))
    deformation_names = ("elongation", "offset along z at p", "offset along y at p")
    deformation_units = ("m", "m", "m")
    reference = 10   # l0 and the frame ex0, ey0, ez0
    element_data: ClassVar[dict[str, tuple[float, ...] | None]] = {
        "orientation": (0.0, 0.0, 0.0)}
    optional_data: ClassVar[tuple[str, ...]] = ("orientation",)
    stiffness_values = (AXIAL_STIFFNESS,)
    damping_values = (AXIAL_DAMPING,)
    has_mass = True
    takes_section_inertia = True

    @classmethod
    def reference_parameters(cls, xe0, data=None):
        """``(n, 10)``: ``l0`` [m] and the frame ``ex0, ey0, ez0``."""
        xe0 = np.atleast_2d(np.asarray(xe0, dtype=float))
        d, length = chord_lengths(xe0, 0, 7)
        given = np.asarray((data or {}).get("orientation", np.zeros((len(xe0), 3))),
                           dtype=float).reshape(len(xe0), 3)
        missing = ~np.any(given, axis=1, keepdims=True)
        orientation = np.where(missing, default_orientation(d), given)
        frame = beam_frame(d, orientation).transpose(0, 2, 1).reshape(len(xe0), 9)
        return np.hstack([length[:, None], frame])

    @classmethod
    def check_data(cls, xe0, data):
        """A given orientation vector must be finite and not (nearly) along the chord."""
        d = np.asarray(xe0[7:10], dtype=float) - np.asarray(xe0[0:3], dtype=float)
        o = np.asarray(data.get("orientation", (0.0, 0.0, 0.0)), dtype=float)
        if o.shape != (3,) or not np.all(np.isfinite(o)):
            return [f"orientation vector {tuple(o.ravel().tolist())} is not three finite "
                    f"numbers"]
        if not np.any(o) or not np.linalg.norm(d) > 0.0:
            return []
        sine = np.linalg.norm(np.cross(d, o)) / (np.linalg.norm(d) * np.linalg.norm(o))
        if sine < PARALLEL_LIMIT:
            return [f"orientation vector {tuple(o.tolist())} lies along the chord "
                    f"{tuple(d.tolist())}: give one across it, or none"]
        return []

    @staticmethod
    def deformations(c, p, m):
        l0 = p[0]
        _, ey0, ez0 = frame_columns(p, 1)
        d = chord(c, 0, 7, width=3)
        length = m.sqrt(dot(d, d))
        u = [dk / length for dk in d]
        lam = c[3:7]
        return [length - l0, -l0 * dot(rotate(lam, ez0), u), l0 * dot(rotate(lam, ey0), u)]

    @staticmethod
    def material_point(c, p, xi, m):
        """``(1 - xi) r_p + xi r_q``: a rigid rod's velocity field is linear."""
        return along_chord(c, 0, 7, xi, 3)

    @classmethod
    def section_inertia_on_nodes(cls, p: np.ndarray, section: tuple[float, ...]
                                 ) -> list[tuple[int, np.ndarray]]:
        """``l0 R0 Jsec R0^T`` on the rotational node: the body's rotation about its own
        axis, which the rod's centre line does not carry."""
        jxx, jyy, jzz, jyz = section
        frame = np.array(p[1:10]).reshape(3, 3).T  # columns ex0, ey0, ez0
        local = np.array([[jxx, 0.0, 0.0], [0.0, jyy, jyz], [0.0, jyz, jzz]])
        return [(1, p[0] * frame @ local @ frame.T)]

    @classmethod
    def mass_line(cls, extra: tuple[float, ...]) -> tuple[dict[str, object], list[str]]:
        """``EM e rhoA [Jxx [Jyy [Jzz [Jyz]]]]``: those left off are 0."""
        if len(extra) > 4:
            raise ValueError(f"an RBEAM takes rhoA and then Jxx Jyy Jzz Jyz per length, got "
                             f"{len(extra) + 1} values")
        return ({"section_inertia": (tuple(extra) + (0.0,) * 4)[:4]} if extra else {}), []

    @classmethod
    def elastic_law(cls, p, stiffness, damping):
        """Only the elongation has a stiffness (``EA/l0``) and damping."""
        return elongation_law(p, 3, stiffness["axial"], damping["axial"])
