"""SPACAR's numbering of a model's coordinates, deformations and degrees of freedom.

flexmbd indexes coordinates by node and deformations by element. SPACAR numbers them by
class first, as its log shows (``NXO``, ``NXC``, ``NXMM``, ``NXM``):

* position parameters: fixed ``x(o)``, calculable ``x(c)``, input ``x(m)``, dynamic
  ``x(m)``; within a class by node number, then by direction;
* deformation parameters: rigid ``e(o)``, input ``e(m)``, dynamic ``e(m)``, calculable
  (released) ``e(c)``; within a class by element number, then by deformation, except
  the calculable warping deformations of ``BEAMW`` elements, which come after all other
  calculable ones;
* degrees of freedom: the input coordinates, the dynamic coordinates, the input
  deformations, the dynamic deformations.

The orders were read off SPACAR 2018's output for a spatial model (its ``.log`` and
``.sbd``), where flexmbd's positions in this numbering agree with SPACAR's to 1e-12 m.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .model import CoordinateClass, DeformationClass, Model

#: rank of each class in SPACAR's numbering
_X_RANK = {CoordinateClass.FIXED: 0, CoordinateClass.DEPENDENT: 1, CoordinateClass.INPUT: 2,
           CoordinateClass.DYNAMIC: 3}
_E_RANK = {DeformationClass.RIGID: 0, DeformationClass.INPUT: 1, DeformationClass.DYNAMIC: 2,
           DeformationClass.RELEASED: 3}

#: SPACAR's element type codes (record ``IT``), as SPACAR's drawing and stress routines read
#: them: ``BEAMW`` 18 read off SPACAR's own output; HINGE's 3 follows from codes below 4
#: being the spatial elements, PLHINGE's 6 from the order of SPACAR's planar types
#: (PLBEAM 5, PLHINGE, PLTRUSS 7). flexmbd's own types take the code of the SPACAR type
#: they are drawn as (a rigid beam as a beam, a spring as a truss), so that SPACAR's
#: tools tell a planar model from a spatial one.
ELEMENT_CODES = {"BEAM": 1, "TRUSS": 2, "HINGE": 3, "EULER": 4, "PLBEAM": 5, "PLHINGE": 6,
                 "PLTRUSS": 7, "BEAMW": 18, "RBEAM": 1, "PLRBEAM": 5, "PLBEAM2": 5,
                 "PLSPRING": 7}
#: the deformations SPACAR numbers after all other calculable ones: a BEAMW's warping
#: (read off SPACAR's output: its released ``e7, e8`` come after every other element's)
LAST_CALCULABLE = {"BEAMW": (6, 7)}
#: widths of the tables LNP (coordinates per node), LE (deformations per element) and LN
#: (nodes per element), as SPACAR writes them
LNP_WIDTH, LE_WIDTH, LN_WIDTH = 4, 8, 6


@dataclass(frozen=True, eq=False)
class SpacarNumbering:
    """The permutations between flexmbd's indices and SPACAR's numbers.

    Attributes:
        model: the model numbered.
        x: flexmbd's coordinate index of SPACAR's position parameter ``k + 1``, ``(nx,)``.
        e: flexmbd's deformation index of SPACAR's deformation parameter ``k + 1``, ``(ne,)``.
        q: flexmbd's index in ``q`` of SPACAR's degree of freedom ``k + 1``, ``(nq,)``.
    """

    model: Model

    @cached_property
    def x(self) -> np.ndarray:
        ranks = [_X_RANK[CoordinateClass(c)] for c in self.model.coordinate_class]
        return np.argsort(np.asarray(ranks, dtype=int), kind="stable")

    @cached_property
    def e(self) -> np.ndarray:
        ranks = np.array([_E_RANK[DeformationClass(c)] for c in self.model.deformation_class],
                         dtype=int)
        released = _E_RANK[DeformationClass.RELEASED]
        for element in self.model.elements.values():
            for k in LAST_CALCULABLE.get(element.type.keyword, ()):
                index = element.deformations[k]
                if ranks[index] == released:
                    ranks[index] = released + 1
        return np.argsort(ranks, kind="stable")

    @cached_property
    def q(self) -> np.ndarray:
        model = self.model
        is_deformation = np.arange(model.n_dof) >= len(model.independent_coordinates)
        ranks = 2 * is_deformation + ~np.asarray(model.q_is_input, dtype=bool)
        return np.argsort(ranks.astype(int), kind="stable")

    @cached_property
    def dynamic_q(self) -> np.ndarray:
        """Indices in ``q`` of the dynamic degrees of freedom, in SPACAR's order (which is
        flexmbd's order of the dynamic entries: coordinates by node, then deformations)."""
        return self.q[~np.asarray(self.model.q_is_input, dtype=bool)[self.q]]

    def x_number(self) -> np.ndarray:
        """SPACAR's number (1-based) of each flexmbd coordinate, ``(nx,)``."""
        number = np.empty(len(self.x), dtype=np.int32)
        number[self.x] = np.arange(1, len(self.x) + 1)
        return number

    def e_number(self) -> np.ndarray:
        """SPACAR's number (1-based) of each flexmbd deformation, ``(ne,)``."""
        number = np.empty(len(self.e), dtype=np.int32)
        number[self.e] = np.arange(1, len(self.e) + 1)
        return number

    def node_table(self) -> np.ndarray:
        """``LNP`` ``(largest node number, 4)`` int32: row ``n - 1`` holds the SPACAR numbers
        of node ``n``'s coordinates, 0 after them and for unused node numbers."""
        x_number = self.x_number()
        lnp = np.zeros((max(self.model.nodes), LNP_WIDTH), dtype=np.int32)
        for n, node in self.model.nodes.items():
            lnp[n - 1, :len(node.coordinates)] = x_number[list(node.coordinates)]
        return lnp

    def element_table(self) -> np.ndarray:
        """``LE`` ``(largest element number, 8)`` int32: row ``e - 1`` holds the SPACAR
        numbers of element ``e``'s deformations."""
        e_number = self.e_number()
        le = np.zeros((max(self.model.elements), LE_WIDTH), dtype=np.int32)
        for k, element in self.model.elements.items():
            le[k - 1, :len(element.deformations)] = e_number[list(element.deformations)]
        return le

    def class_counts(self) -> tuple[np.ndarray, np.ndarray]:
        """``NXP`` and ``NEP``: the number of coordinates (deformations) per class, in the
        order SPACAR stores them: fixed (rigid), calculable (released), input, dynamic, and
        a fifth class flexmbd does not have (0)."""
        x = np.bincount(self.model.coordinate_class, minlength=4)
        e = np.bincount(self.model.deformation_class, minlength=4)
        c, d = CoordinateClass, DeformationClass
        nxp = [x[c.FIXED], x[c.DEPENDENT], x[c.INPUT], x[c.DYNAMIC], 0]
        nep = [e[d.RIGID], e[d.RELEASED], e[d.INPUT], e[d.DYNAMIC], 0]
        return np.array([nxp], dtype=np.int32), np.array([nep], dtype=np.int32)
