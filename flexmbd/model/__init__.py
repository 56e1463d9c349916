"""The model: a mechanism described once, immutable, and how its parts are named.

* :mod:`~flexmbd.model.model`: :class:`Model` (nodes, elements, the classification of
  coordinates and deformations, properties), its labels and directions;
* :mod:`~flexmbd.model.numbering`: SPACAR's numbering of a model's coordinates,
  deformations and degrees of freedom (for result files and user routines);
* :mod:`~flexmbd.model.naming`: the closest names to one that names nothing.

Build a model with :class:`flexmbd.ModelBuilder` (:mod:`flexmbd.builder`).
"""

from .model import (
    DIRECTION_NAMES,
    CoordinateClass,
    DeformationClass,
    Element,
    ElementProperties,
    Model,
    Node,
    direction_number,
    frozen_array,
)

__all__ = ["DIRECTION_NAMES", "CoordinateClass", "DeformationClass", "Element",
           "ElementProperties", "Model", "Node", "direction_number", "frozen_array"]
