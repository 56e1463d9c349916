"""Building a :class:`~flexmbd.model.Model` and checking it, in three parts:

* :mod:`~flexmbd.builder.recording`: :class:`ModelBuilder`, what the user said (nodes,
  elements, classification, properties, in any order);
* :mod:`~flexmbd.builder.validation`: what is wrong with it, every problem at once and
  named, and the immutable model it makes;
* :mod:`~flexmbd.builder.constraints`: the constraints' count and rank (``D_c``), and
  over-constraints released as SPACAR Light releases them.
"""

from .constraints import check_solvability
from .recording import LARGEST_POSITION, MASS_FORMULATIONS, ModelBuilder

__all__ = ["LARGEST_POSITION", "MASS_FORMULATIONS", "ModelBuilder", "check_solvability"]
