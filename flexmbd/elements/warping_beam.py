"""Warping beam (BEAMW): the spatial beam with a warping node at each end, for torsion
with restrained warping (FLEXURES 1).

A warping node carries one coordinate, ``psi``: the rate of twist ``dphi/ds`` [rad/m] of
the section there, 0 in the reference. It does not depend on the element's direction
(reversing p and q flips both the twist and ``s``), so elements meeting at a node share
it. Besides the six deformations of :class:`~flexmbd.elements.spatial_beam.SpatialBeam`,

* ``e7 = e2 - l0^2 psi_p``, ``e8 = l0^2 psi_q - e2``,

which vanish in rigid motion and in uniform torsion (``psi_p = psi_q = e2 / l0^2``) and
follow from a cubic Hermite twist ``phi(xi) = phi_p + (e2/l0) xi - H2 e7/l0 + H4 e8/l0``.
They are always computed (SPACAR's calculable deformations): released, never rigid,
dynamic or prescribed. Their stiffness, exact for the cubic twist, is
``ECw/l0^5 [[4, -2], [-2, 4]] + GIt/(30 l0^3) [[4, 1], [1, 4]]``, uncoupled from ``e2``.
An element whose warping is free minimizes to ``e7 = e8 = 0``: St Venant's ``GIt/l0``.
The warping inertia ``Jw = rho Cw`` per length is lumped, ``(l0/2) Jw``, on each ``psi``.

These definitions are flexmbd's own (a Vlasov-type twist): SPACAR's are not public. They
have the closed-form limits of non-uniform torsion (FLEXURES 2).
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from .base import ElementType, Value, spatial_rotational, spatial_translational, warping
from .spatial_beam import SpatialBeam

#: the columns of the element coordinates that are the spatial beam's
#: ``[r_p, lam_p, r_q, lam_q]`` (the warping coordinates are columns 7 and 15)
BEAM_COLUMNS = (*range(0, 7), *range(8, 15))


def _beam_part(c):
    return [c[k] for k in BEAM_COLUMNS]


class WarpingBeam(ElementType):
    """Coordinates ``[x_p, y_p, z_p, lam_p (4), psi_p, x_q, y_q, z_q, lam_q (4), psi_q]``.

    Element data and the first six deformations as :class:`SpatialBeam`; ``e7``, ``e8``
    the warping deformations (module docstring).

    Properties: ``EM`` ``rhoA`` [kg/m] and the section inertias ``Jxx Jyy Jzz Jyz Jw``
    [kg m, kg m^3]; ``ESTIFF`` the beam's six values and the warping stiffness ``ECw``
    [N m^4].
    """

    name = "warping beam"
    keyword = "BEAMW"
    roles = (spatial_translational("p"), spatial_rotational("lam_p"), warping("w_p"),
             spatial_translational("q"), spatial_rotational("lam_q"), warping("w_q"))
    deformation_names = (*SpatialBeam.deformation_names, "warping at p", "warping at q")
    deformation_units = ("m",) * 8
    calculable = (7, 8)
    reference = SpatialBeam.reference
    element_data: ClassVar[dict[str, tuple[float, ...] | None]] = SpatialBeam.element_data
    stiffness_values = (*SpatialBeam.stiffness_values, Value("warping", "ECw", "N m^4"))
    damping_values = SpatialBeam.damping_values
    has_mass = True
    takes_section_inertia = True

    @classmethod
    def section_inertia_on_nodes(cls, p: np.ndarray, section: tuple[float, ...]
                                 ) -> list[tuple[int, np.ndarray]]:
        """The beam's rotary inertias on ``lam_p``, ``lam_q`` and ``(l0/2) Jw`` ``(1, 1)`` on
        each warping node."""
        lumped = SpatialBeam.section_inertia_on_nodes(p, section[:4])
        jw = np.array([[0.5 * p[0] * (section[4] if len(section) > 4 else 0.0)]])
        return [(1, lumped[0][1]), (4, lumped[1][1]), (2, jw), (5, jw)]

    @classmethod
    def mass_line(cls, extra: tuple[float, ...]) -> tuple[dict[str, object], list[str]]:
        """``EM e rhoA [Jxx [Jyy [Jzz [Jyz [Jw]]]]]``, those left off 0 as SPACAR takes them."""
        if len(extra) > 5:
            raise ValueError(f"a BEAMW takes rhoA and then Jxx Jyy Jzz Jyz Jw per length, "
                             f"got {len(extra) + 1} values")
        inertia = (tuple(extra) + (0.0,) * 5)[:5]
        return ({"section_inertia": inertia} if extra else {}), []

    @classmethod
    def stiffness_line(cls, values: tuple[float, ...]) -> tuple[tuple[float, ...], list[str]]:
        return values, []

    @classmethod
    def reference_parameters(cls, xe0, data=None):
        xe0 = np.atleast_2d(np.asarray(xe0, dtype=float))
        return SpatialBeam.reference_parameters(xe0[:, list(BEAM_COLUMNS)], data)

    @classmethod
    def check_data(cls, xe0, data):
        return SpatialBeam.check_data(np.asarray(xe0, dtype=float)[list(BEAM_COLUMNS)], data)

    @staticmethod
    def deformations(c, p, m):
        beam = SpatialBeam.deformations(_beam_part(c), p, m)
        l0, e2 = p[0], beam[1]
        return [*beam, e2 - l0**2 * c[7], l0**2 * c[15] - e2]

    @staticmethod
    def material_point(c, p, xi, m):
        return SpatialBeam.material_point(_beam_part(c), p, xi, m)

    @classmethod
    def lumped_masses(cls, p: np.ndarray, mass: np.ndarray) -> np.ndarray:
        out = np.zeros((len(mass), cls.n_coordinates()))
        out[:, list(BEAM_COLUMNS)] = SpatialBeam.lumped_masses(p, mass)
        return out

    @classmethod
    def elastic_law(cls, p, stiffness, damping):
        """The spatial beam's law on ``e1..e6``; on ``(e7, e8)`` ``ECw/l0^5 [[4, -2], [-2,
        4]] + GIt/(30 l0^3) [[4, 1], [1, 4]]`` (module docstring), no damping."""
        n, l0 = len(p), p[:, 0]
        S, C = np.zeros((2, n, 8, 8))
        S[:, :6, :6], C[:, :6, :6] = SpatialBeam.elastic_law(p, stiffness, damping)
        warp = stiffness["warping"] / l0**5
        twist = stiffness["torsion"] / (30 * l0**3)
        S[:, 6, 6] = S[:, 7, 7] = 4 * warp + 4 * twist
        S[:, 6, 7] = S[:, 7, 6] = -2 * warp + twist
        return S, C

    @classmethod
    def outline(cls, xe, p, e, exaggeration=1.0):
        xe = np.asarray(xe)
        return SpatialBeam.outline(xe[:, list(BEAM_COLUMNS)], p, np.asarray(e)[:, :6],
                                   exaggeration)
