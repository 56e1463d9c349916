"""Planar element types; each is a small class with vectorised kernels."""

from .base import ROTATIONAL, TRANSLATIONAL, ElementType, Reference
from .beam import Beam
from .hinge import Hinge
from .rigid_beam import RigidBeam
from .truss import Truss

#: element types by SPACAR keyword
ELEMENT_TYPES: dict[str, type[ElementType]] = {
    cls.keyword: cls for cls in (Truss, Beam, RigidBeam, Hinge)
}

__all__ = [
    "ELEMENT_TYPES",
    "ROTATIONAL",
    "TRANSLATIONAL",
    "Beam",
    "ElementType",
    "Hinge",
    "Reference",
    "RigidBeam",
    "Truss",
]
