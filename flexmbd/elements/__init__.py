"""Element types, planar and spatial: one file each (see :mod:`flexmbd.elements.base`).

A new type is a file defining an :class:`ElementType` and one entry in
:data:`ELEMENT_TYPES`; run ``python -m flexmbd.engine.codegen`` to generate its compiled
kernels.
"""

from .base import (
    ROTATIONAL,
    SPATIAL_ROTATIONAL,
    SPATIAL_TRANSLATIONAL,
    TRANSLATIONAL,
    WARPING,
    ElementType,
)
from .beam import Beam
from .euler import EulerNormalization
from .hinge import Hinge
from .rigid_beam import RigidBeam
from .second_order_beam import SecondOrderBeam
from .spatial_beam import SpatialBeam
from .spatial_hinge import SpatialHinge
from .spatial_rigid_beam import SpatialRigidBeam
from .spatial_truss import SpatialTruss
from .spring_damper import SpringDamper
from .truss import Truss
from .warping_beam import WarpingBeam

#: the element types by SPACAR keyword; the order is the compiled core's type numbers
ELEMENT_TYPES: dict[str, type[ElementType]] = {
    cls.keyword: cls for cls in (Truss, Beam, RigidBeam, Hinge, SpringDamper,
                                SecondOrderBeam, SpatialTruss, SpatialBeam, SpatialHinge,
                                SpatialRigidBeam, EulerNormalization, WarpingBeam)
}

__all__ = [
    "ELEMENT_TYPES",
    "ROTATIONAL",
    "SPATIAL_ROTATIONAL",
    "SPATIAL_TRANSLATIONAL",
    "TRANSLATIONAL",
    "WARPING",
    "Beam",
    "ElementType",
    "EulerNormalization",
    "Hinge",
    "RigidBeam",
    "SecondOrderBeam",
    "SpatialBeam",
    "SpatialHinge",
    "SpatialRigidBeam",
    "SpatialTruss",
    "SpringDamper",
    "Truss",
    "WarpingBeam",
]
