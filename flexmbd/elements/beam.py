"""Planar beam (PLBEAM): elongation and two bending deformations (THEORY sections 2, 5, 6).

``e1 = l - l0``, ``e2 = -n_p . d``, ``e3 = n_q . d`` with ``d = r_q - r_p`` and
``n_p = n(beta0 + phi_p)``, ``n_q = n(beta0 + phi_q)``; its mass follows the cubic
Hermite interpolation of the centre line.
"""

from __future__ import annotations

import numpy as np

from .base import (
    AXIAL_DAMPING,
    AXIAL_STIFFNESS,
    ElementType,
    Value,
    chord,
    elongation_law,
    rotational,
    translational,
)
from .truss import elongation


def hermite(xi):
    """The cubic Hermite functions ``H1 .. H4`` at ``xi`` (THEORY section 5)."""
    return (1 - 3 * xi**2 + 2 * xi**3, xi - 2 * xi**2 + xi**3, 3 * xi**2 - 2 * xi**3,
            -(xi**2) + xi**3)


def deflection(xi, e_p, e_q):
    """The transverse deflection ``v(xi) = H2 e_p - H4 e_q`` of a bend whose deformations
    at p and q are ``e_p ~ l theta_p`` and ``e_q ~ -l theta_q`` (THEORY section 2)."""
    _, h2, _, h4 = hermite(xi)
    return h2 * e_p - h4 * e_q


def arc_beyond_chord(e_p, e_q, l0):
    """``(2 e_p^2 + e_p e_q + 2 e_q^2) / (30 l0)``: how much longer the Hermite centre line
    of that bend is than its chord, ``1/2 int v'^2 dx`` (the second-order beams' term)."""
    return (2 * e_p**2 + e_p * e_q + 2 * e_q**2) / (30 * l0)


def bending_pair(bending: np.ndarray, phi: np.ndarray, l0: np.ndarray) -> np.ndarray:
    """The bending stiffness of a pair of end deformations, ``EI/((1+Phi) l0^3) [[4+Phi,
    Phi-2], [Phi-2, 4+Phi]]`` ``(n, 2, 2)``, with the shear parameter ``Phi`` (0:
    Euler-Bernoulli; also the damping matrix with ``c_I`` for ``EI``)."""
    factor = bending / ((1 + phi) * l0**3)
    diagonal, off = factor * (4 + phi), factor * (phi - 2)
    return np.stack([np.stack([diagonal, off], -1), np.stack([off, diagonal], -1)], -2)


class Beam(ElementType):
    """Coordinates ``[x_p, y_p, phi_p, x_q, y_q, phi_q]``.

    Properties: ``EM`` (``rhoA`` [kg/m], consistent Hermite mass), ``ESTIFF`` ``EA``
    [N], ``EI`` [N m^2] and optionally ``G A_s`` [N] (Timoshenko shear correction),
    ``EDAMP`` ``c_A`` [N s] and ``c_I`` [N m^2 s].
    """

    name = "beam"
    keyword = "PLBEAM"
    roles = (translational("p"), rotational("phi_p"), translational("q"), rotational("phi_q"))
    deformation_names = ("elongation", "bending at p", "bending at q")
    deformation_units = ("m", "m", "m")  # e2 ~ l theta_p: a length, its stress a force
    stiffness_values = (AXIAL_STIFFNESS, Value("bending", "EI", "N m^2"),
                        Value("shear", "GA_s", "N"))
    damping_values = (AXIAL_DAMPING, Value("bending", "c_I", "N m^2 s"))
    has_mass = True
    takes_section_inertia = True

    @classmethod
    def section_inertia_on_nodes(cls, p: np.ndarray, section: tuple[float, ...]
                                 ) -> list[tuple[int, np.ndarray]]:
        """The rotary inertia of the cross-section, ``rhoI`` [kg m] per length, half of
        ``l0 rhoI`` on each rotational node, as a spatial beam lumps its section inertia
        (exact for the beam turning as a body)."""
        lumped = np.array([[0.5 * p[0] * section[0]]])
        return [(1, lumped), (3, lumped)]

    @classmethod
    def mass_line(cls, extra: tuple[float, ...]) -> tuple[dict[str, object], list[str]]:
        """``EM e rhoA [rhoI]``: the rotary inertia per length ``rhoI`` [kg m] lumped on the
        rotational nodes (:meth:`section_inertia_on_nodes`)."""
        if len(extra) > 1:
            raise ValueError(f"EM takes rhoA [rhoI] for a planar beam, got {len(extra) + 1} "
                             f"values")
        return ({"section_inertia": (float(extra[0]),)} if extra and extra[0] else {}), []

    @staticmethod
    def deformations(c, p, m):
        dx, dy = chord(c, 0, 3)
        beta_p, beta_q = p[1] + c[2], p[1] + c[5]
        return [elongation(c, 0, 3, p[0], m),
                m.sin(beta_p) * dx - m.cos(beta_p) * dy,  # -n_p . d
                -m.sin(beta_q) * dx + m.cos(beta_q) * dy]  # n_q . d

    @staticmethod
    def material_point(c, p, xi, m):
        """``H1 r_p + H2 l0 e_p + H3 r_q + H4 l0 e_q`` with ``e = (cos, sin)`` of
        ``beta0 + phi`` at each end."""
        h1, h2, h3, h4 = hermite(xi)
        beta_p, beta_q = p[1] + c[2], p[1] + c[5]
        return [h1 * c[0] + h2 * p[0] * m.cos(beta_p) + h3 * c[3] + h4 * p[0] * m.cos(beta_q),
                h1 * c[1] + h2 * p[0] * m.sin(beta_p) + h3 * c[4] + h4 * p[0] * m.sin(beta_q)]

    @classmethod
    def elastic_law(cls, p, stiffness, damping):
        """Elongation ``EA/l0``; bending ``EI/((1+Phi) l0^3) [[4+Phi, Phi-2], [Phi-2,
        4+Phi]]`` on ``(e2, e3)`` with ``Phi = 12 EI / (G A_s l0^2)`` (0 without shear).
        Damping: ``c_A / l0`` and the Euler-Bernoulli matrix with ``c_I`` for ``EI``."""
        S, C = elongation_law(p, 3, stiffness["axial"], damping["axial"])
        l0, bending, shear = p[:, 0], stiffness["bending"], stiffness["shear"]
        with np.errstate(divide="ignore", invalid="ignore"):
            phi = np.where(shear > 0, 12 * bending / (shear * l0**2), 0.0)
        S[:, 1:3, 1:3] = bending_pair(bending, phi, l0)
        C[:, 1:3, 1:3] = bending_pair(damping["bending"], np.zeros_like(l0), l0)
        return S, C

    @classmethod
    def outline(cls, xe, p, e, exaggeration=1.0):
        """The chord plus the transverse deflection of THEORY 2, ``v(xi) = (xi - 2 xi^2 +
        xi^3) e2 + (xi^2 - xi^3) e3``, times ``exaggeration``."""
        xi = np.linspace(0.0, 1.0, 21)
        lines = []
        for x, ek in zip(xe, e, strict=True):
            rp, d = x[0:2], x[3:5] - x[0:2]
            normal = np.array([-d[1], d[0]]) / np.hypot(d[0], d[1])
            v = exaggeration * deflection(xi, ek[1], ek[2])
            lines.append(rp + np.outer(xi, d) + np.outer(v, normal))
        return lines
