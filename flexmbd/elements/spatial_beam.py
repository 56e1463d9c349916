"""Spatial beam (BEAM): elongation, torsion and four bending deformations between two
spatial translational nodes with their rotational nodes (THEORY-SPATIAL 2-4).

With the chord ``d = r_q - r_p``, ``l = |d|``, ``u = d / l`` and the frame vectors
``ex, ey, ez`` of each end node (the reference frame turned by the node's Euler
parameters), the basic deformations are

* ``e1 = l - l0``, ``e2 = (l0/2) (ez_p . ey_q - ey_p . ez_q)`` (torsion),
* ``e3 = -l0 ez_p . u``, ``e4 = l0 ez_q . u`` (bending about the local y axes),
* ``e5 = l0 ey_p . u``, ``e6 = -l0 ey_q . u`` (bending about the local z axes),

and, as in SPACAR, the bending-linked second-order terms are added (an element option,
on by default): the arc length of the bent centre line on ``e1``, and the couplings of
torsion and bending on ``e2 .. e6``.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from .base import (
    AXIAL_DAMPING,
    AXIAL_STIFFNESS,
    ElementType,
    Value,
    chord,
    elongation_law,
    spatial_rotational,
    spatial_translational,
)
from .beam import arc_beyond_chord, bending_pair, deflection, hermite
from .rotations import dot, frame_columns, rotate
from .spatial_truss import chord_lengths

#: an orientation vector closer to the chord than this angle [rad] gives no frame
PARALLEL_LIMIT = 1e-5


def bending_linked_terms(e: list, l0) -> list:
    """The second-order terms ``c(e)`` SPACAR adds to the basic deformations ``e``
    (THEORY-SPATIAL 3): quadratic forms in ``e``."""
    _, e2, e3, e4, e5, e6 = e
    c1 = arc_beyond_chord(e3, e4, l0) + arc_beyond_chord(e5, e6, l0)
    c3 = e2 * (e5 + e6) / (6 * l0)
    c5 = -e2 * (e3 + e4) / (6 * l0)
    return [c1, (e4 * e5 - e3 * e6) / l0, c3, -c3, c5, -c5]


def beam_frame(chord: np.ndarray, orientation: np.ndarray) -> np.ndarray:
    """Reference frames ``(n, 3, 3)`` (columns ``ex0, ey0, ez0``) of ``n`` beams: ``ex0``
    along the chord ``(n, 3)``, ``ey0`` the orientation vector ``(n, 3)`` made
    perpendicular to it, ``ez0 = ex0 x ey0``."""
    with np.errstate(invalid="ignore", divide="ignore"):  # a zero chord: NaN, which the
        ex = chord / np.linalg.norm(chord, axis=1, keepdims=True)  # builder refuses by name
        ey = orientation - np.sum(orientation * ex, axis=1, keepdims=True) * ex
        ey = ey / np.linalg.norm(ey, axis=1, keepdims=True)
    return np.stack([ex, ey, np.cross(ex, ey)], axis=2)


def default_orientation(directions: np.ndarray) -> np.ndarray:
    """SPACAR's choice for an element given no orientation vector: for each direction
    ``(n, 3)``, the global unit axis ``(n, 3)`` along which it has its smallest component,
    the last of equal ones (SPACAR 2019 stores ``ey0`` = global y for a beam along z, where
    x and y tie; the first of them would give x)."""
    magnitude = np.abs(np.atleast_2d(directions))
    last_smallest = 2 - np.argmin(magnitude[:, ::-1], axis=1)
    axes = np.zeros_like(magnitude)
    axes[np.arange(len(magnitude)), last_smallest] = 1.0
    return axes


class SpatialBeam(ElementType):
    """Coordinates ``[x_p, y_p, z_p, lam_p (4), x_q, y_q, z_q, lam_q (4)]``.

    Element data: ``orientation``, a vector [-] not along the beam that fixes the local
    ``y`` axis (``(0, 0, 0)`` or none on a ``BEAM`` line: SPACAR's choice,
    :func:`default_orientation` made perpendicular to the beam), and ``bending_linked``
    (1: the second-order terms on, as SPACAR; 0: off).

    Properties: ``EM`` ``rhoA`` [kg/m] (consistent Hermite mass of the centre line),
    ``ESTIFF`` ``EA`` [N], ``GIt`` [N m^2], ``EIy``, ``EIz`` [N m^2] and the shear
    flexibilities ``sy = EIy/(G A k_y)``, ``sz`` [m^2]; ``EDAMP`` the same six as
    damping values [.. s].
    """

    name = "spatial beam"
    keyword = "BEAM"
    roles = (spatial_translational("p"), spatial_rotational("lam_p"),
             spatial_translational("q"), spatial_rotational("lam_q"))
    deformation_names = ("elongation", "torsion", "bending about y at p",
                         "bending about y at q", "bending about z at p",
                         "bending about z at q")
    deformation_units = ("m",) * 6
    reference = 11   # l0, the frame ex0, ey0, ez0, the bending-linked switch
    element_data: ClassVar[dict[str, tuple[float, ...] | None]] = {
        "orientation": (0.0, 0.0, 0.0), "bending_linked": (1.0,)}
    optional_data: ClassVar[tuple[str, ...]] = ("orientation",)
    stiffness_values = (AXIAL_STIFFNESS, Value("torsion", "GIt", "N m^2"),
                        Value("bending_y", "EIy", "N m^2"), Value("bending_z", "EIz", "N m^2"),
                        Value("shear_y", "sy", "m^2"), Value("shear_z", "sz", "m^2"))
    damping_values = (AXIAL_DAMPING, Value("torsion", "c_T", "N m^2 s"),
                      Value("bending_y", "c_Iy", "N m^2 s"),
                      Value("bending_z", "c_Iz", "N m^2 s"))
    has_mass = True
    takes_section_inertia = True

    @classmethod
    def section_inertia_on_nodes(cls, p: np.ndarray, section: tuple[float, ...]
                                 ) -> list[tuple[int, np.ndarray]]:
        """Half of ``l0 R0 Jsec R0^T`` on each rotational node (THEORY-SPATIAL 4), with
        ``Jsec`` of ``(Jxx, Jyy, Jzz, Jyz)`` [kg m] in the beam's reference frame ``R0``."""
        jxx, jyy, jzz, jyz = section[:4]   # a fifth value is refused by the builder
        frame = np.array(p[1:10]).reshape(3, 3).T  # columns ex0, ey0, ez0
        local = np.array([[jxx, 0.0, 0.0], [0.0, jyy, jyz], [0.0, jyz, jzz]])
        lumped = 0.5 * p[0] * frame @ local @ frame.T
        return [(1, lumped), (3, lumped)]

    @classmethod
    def mass_line(cls, extra: tuple[float, ...]) -> tuple[dict[str, object], list[str]]:
        """``EM e rhoA [Jxx [Jyy [Jzz [Jyz [Jw]]]]]``: the section inertias per length [kg m],
        those left off 0 as SPACAR takes them; the warping inertia ``Jw`` is read and not
        used."""
        if len(extra) > 5:
            raise ValueError(f"a BEAM takes rhoA and then Jxx Jyy Jzz Jyz [Jw] per length, "
                             f"got {len(extra) + 1} values")
        notes = ["the warping inertia Jw (EM's 6th value)"] if len(extra) == 5 and \
            extra[4] else []
        inertia = (tuple(extra[:4]) + (0.0,) * 4)[:4]
        return ({"section_inertia": inertia} if extra else {}), notes

    @classmethod
    def stiffness_line(cls, values: tuple[float, ...]) -> tuple[tuple[float, ...], list[str]]:
        """``ESTIFF e EA GIt EIy EIz sy sz [ECw]``: the warping stiffness ``ECw`` is read and
        not used."""
        if len(values) == 7:
            return values[:6], ["the warping stiffness ECw (ESTIFF's 7th value)"] if \
                values[6] else []
        return values, []

    @classmethod
    def reference_parameters(cls, xe0, data=None):
        """``(n, 11)``: ``l0`` [m], the frame ``ex0, ey0, ez0`` and the switch of the
        bending-linked terms."""
        xe0 = np.atleast_2d(np.asarray(xe0, dtype=float))
        d, length = chord_lengths(xe0, 0, 7)
        data = data or {}
        given = np.asarray(data.get("orientation", np.zeros((len(xe0), 3))),
                           dtype=float).reshape(len(xe0), 3)
        missing = ~np.any(given, axis=1, keepdims=True)   # none: SPACAR's choice
        orientation = np.where(missing, default_orientation(d), given)
        linked = np.asarray(data.get("bending_linked", np.ones(len(xe0))),
                            dtype=float).reshape(len(xe0), 1)
        frame = beam_frame(d, orientation).transpose(0, 2, 1).reshape(len(xe0), 9)
        return np.hstack([length[:, None], frame, linked])

    @classmethod
    def check_data(cls, xe0, data):
        """The orientation vector must be finite and not (nearly) along the chord."""
        d = np.asarray(xe0[7:10], dtype=float) - np.asarray(xe0[0:3], dtype=float)
        o = np.asarray(data.get("orientation", (0.0, 0.0, 0.0)), dtype=float)
        if o.shape != (3,) or not np.all(np.isfinite(o)):
            return [f"orientation vector {tuple(o.ravel().tolist())} is not three finite "
                    f"numbers"]
        if not np.any(o) or not np.linalg.norm(d) > 0.0:  # none given: SPACAR's choice;
            return []                                   # a zero length: the builder says
        sine = np.linalg.norm(np.cross(d, o)) / (np.linalg.norm(d) * np.linalg.norm(o))
        if sine < PARALLEL_LIMIT:
            return [f"orientation vector {tuple(o.tolist())} lies along the beam "
                    f"{tuple(d.tolist())}: give one across it (it fixes the local y axis)"]
        return []

    @staticmethod
    def deformations(c, p, m):
        l0 = p[0]
        _, ey0, ez0 = frame_columns(p, 1)
        d = chord(c, 0, 7, width=3)
        length = m.sqrt(dot(d, d))
        u = [dk / length for dk in d]
        lam_p, lam_q = c[3:7], c[10:14]
        ey_p, ez_p = rotate(lam_p, ey0), rotate(lam_p, ez0)
        ey_q, ez_q = rotate(lam_q, ey0), rotate(lam_q, ez0)
        basic = [length - l0,
                 l0 / 2 * (dot(ez_p, ey_q) - dot(ey_p, ez_q)),
                 -l0 * dot(ez_p, u), l0 * dot(ez_q, u),
                 l0 * dot(ey_p, u), -l0 * dot(ey_q, u)]
        linked = bending_linked_terms(basic, l0)
        return [b + p[10] * t for b, t in zip(basic, linked, strict=True)]

    @staticmethod
    def material_point(c, p, xi, m):
        """``H1 r_p + H2 l0 ex_p + H3 r_q + H4 l0 ex_q``: the Hermite centre line with
        the end tangents ``ex`` of the two rotational nodes (THEORY-SPATIAL 4)."""
        h1, h2, h3, h4 = hermite(xi)
        ex0 = p[1:4]
        ex_p, ex_q = rotate(c[3:7], ex0), rotate(c[10:14], ex0)
        return [h1 * c[k] + h2 * p[0] * ex_p[k] + h3 * c[7 + k] + h4 * p[0] * ex_q[k]
                for k in range(3)]

    @classmethod
    def elastic_law(cls, p, stiffness, damping):
        """Block diagonal over ``(e1, e2, (e3, e4), (e5, e6))``: ``EA/l0``, ``GIt/l0^3``
        and for each bending pair ``EI/((1+Phi) l0^3) [[4+Phi, Phi-2], [Phi-2, 4+Phi]]``
        with ``Phi = 12 s/l0^2`` (``EIy, sy`` on ``e3, e4``; ``EIz, sz`` on ``e5, e6``).
        Damping: the same with the damping values and no shear."""
        l0 = p[:, 0]
        S, C = elongation_law(p, 6, stiffness["axial"], damping["axial"])
        S[:, 1, 1], C[:, 1, 1] = stiffness["torsion"] / l0**3, damping["torsion"] / l0**3
        for at, bending, flexibility in ((2, "bending_y", "shear_y"),
                                         (4, "bending_z", "shear_z")):
            phi = 12 * stiffness[flexibility] / l0**2
            S[:, at:at + 2, at:at + 2] = bending_pair(stiffness[bending], phi, l0)
            C[:, at:at + 2, at:at + 2] = bending_pair(damping[bending], np.zeros_like(l0), l0)
        return S, C

    @classmethod
    def outline(cls, xe, p, e, exaggeration=1.0):
        """The chord plus the Hermite deflections of the planar beam, ``v(e3, e4)`` along
        ``ez`` and ``-v(e5, e6)`` along ``ey`` of the mean frame of the two end nodes, times
        ``exaggeration``."""
        xi = np.linspace(0.0, 1.0, 21)
        lines = []
        for x, pk, ek in zip(xe, p, e, strict=True):
            rp, d = x[0:3], x[7:10] - x[0:3]
            u = d / np.linalg.norm(d)
            axes = []
            for column in (pk[4:7], pk[7:10]):
                a = np.add(rotate(x[3:7], column), rotate(x[10:14], column))
                a = a - np.dot(a, u) * u
                axes.append(a / max(np.linalg.norm(a), 1e-300))
            ey, ez = axes
            w = exaggeration * (np.outer(deflection(xi, ek[2], ek[3]), ez)
                                - np.outer(deflection(xi, ek[4], ek[5]), ey))
            lines.append(rp + np.outer(xi, d) + w)
        return lines
