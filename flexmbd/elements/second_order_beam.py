"""Planar beam with the bending-linked second-order elongation (PLBEAM2, a flexmbd keyword).

The elongation is measured along the bent centre line instead of the chord:
``e1 = l - l0 + (2 e2^2 + e2 e3 + 2 e3^2) / (30 l0)``, the arc length of the Hermite
deflection ``v(xi)`` of THEORY 2 beyond the chord, ``1/2 int v'^2 dx``. Its stress
times the Hessian of that term is the consistent geometric stiffness of the beam, so
buckling loads and the stiffening by axial load (centrifugal, pre-stress) converge
as ``n^-4`` instead of the chord's ``n^-2``; a constant-curvature bend (``e2 = e3``)
no longer shortens a beam of rigid elongation. SPACAR's spatial beam carries the same
terms. The bending deformations, mass and properties are the :class:`Beam`'s.
"""

from __future__ import annotations

from .beam import Beam


class SecondOrderBeam(Beam):
    """A :class:`Beam` whose elongation includes the arc length of its bending."""

    name = "second-order beam"
    keyword = "PLBEAM2"

    @staticmethod
    def deformations(c, p, m):
        chord_elongation, e2, e3 = Beam.deformations(c, p, m)
        return [chord_elongation + (2 * e2**2 + e2 * e3 + 2 * e3**2) / (30 * p[0]), e2, e3]
