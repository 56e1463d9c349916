"""Planar large-deflection beam (PLBEAM2, a flexmbd keyword): second-order elongation
and bending measured by the end rotations themselves.

With ``theta_p``, ``theta_q`` the rotations of the end tangents from the chord
(counter-clockwise positive, THEORY 2):

* ``e2 = l0 theta_p`` and ``e3 = -l0 theta_q``, where the course's beam has
  ``l sin theta_p`` and ``-l sin theta_q``. The sine softens a bend by
  ``theta^2/6``, a relative error of ``(kappa l)^2/24`` in curvature ``kappa``: the
  tip of a cantilever under a tip load then follows the elastica only to ``O(n^-2)``.
* ``e1 = l - l0 + (2 e2^2 + e2 e3 + 2 e3^2) / (30 l0)``: the length of the Hermite
  centre line ``v(xi)`` of THEORY 2 instead of its chord, ``1/2 int v'^2 dx`` beyond
  it. Its stress times the Hessian of that term is the consistent geometric
  stiffness, so buckling loads and the stiffening by axial load (centrifugal,
  pre-stress) converge as ``n^-4`` instead of the chord's ``n^-2``, and a
  constant-curvature bend (``e2 = e3``) no longer shortens a beam of rigid
  elongation. SPACAR's spatial beam carries the same terms.

Together the two make the beam co-rotational: large deflections, the elastica
included, converge as ``n^-4``. To first order in the rotations the deformations are
the :class:`Beam`'s, so are the stiffness, mass and properties. ``theta`` is taken
in ``(-pi, pi]``: an end turned half a revolution from its chord is not a beam.
"""

from __future__ import annotations

from .base import chord
from .beam import Beam, arc_beyond_chord
from .truss import elongation


class SecondOrderBeam(Beam):
    """A :class:`Beam` with exact end rotations and the arc length of its bending."""

    name = "second-order beam"
    keyword = "PLBEAM2"

    @staticmethod
    def deformations(c, p, m):
        dx, dy = chord(c, 0, 3)
        beta_p, beta_q = p[1] + c[2], p[1] + c[5]
        # theta = atan2(sin, cos) of the angle between the end tangent e(beta) and d
        theta_p = m.atan2(m.sin(beta_p) * dx - m.cos(beta_p) * dy,   # -n_p . d
                          m.cos(beta_p) * dx + m.sin(beta_p) * dy)   # e_p . d
        theta_q = m.atan2(m.sin(beta_q) * dx - m.cos(beta_q) * dy,   # -n_q . d
                          m.cos(beta_q) * dx + m.sin(beta_q) * dy)   # e_q . d
        e2, e3 = p[0] * theta_p, -p[0] * theta_q
        return [elongation(c, 0, 3, p[0], m) + arc_beyond_chord(e2, e3, p[0]), e2, e3]
