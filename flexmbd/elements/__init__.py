"""Planar element types: one file each (see :mod:`flexmbd.elements.base`).

A new type is a file defining an :class:`ElementType` and one entry in
:data:`ELEMENT_TYPES`; run ``python -m flexmbd.codegen`` to generate its compiled
kernels.
"""

from .base import ROTATIONAL, TRANSLATIONAL, ElementType
from .beam import Beam
from .hinge import Hinge
from .rigid_beam import RigidBeam
from .second_order_beam import SecondOrderBeam
from .spring_damper import SpringDamper
from .truss import Truss

#: the element types by SPACAR keyword; the order is the compiled core's type numbers
ELEMENT_TYPES: dict[str, type[ElementType]] = {
    cls.keyword: cls for cls in (Truss, Beam, RigidBeam, Hinge, SpringDamper,
                                SecondOrderBeam)
}

__all__ = [
    "ELEMENT_TYPES",
    "ROTATIONAL",
    "TRANSLATIONAL",
    "Beam",
    "ElementType",
    "Hinge",
    "RigidBeam",
    "SecondOrderBeam",
    "SpringDamper",
    "Truss",
]
