"""flexmbd: planar flexible multibody dynamics with the finite-element approach.

A mechanism is a set of nodes and elements whose deformation parameters are
functions of the nodal coordinates. Build a :class:`Model` with
:class:`ModelBuilder` (or read a SPACAR file with :func:`read_dat`), then analyse
it with the functions below; every analysis runs on the compiled core
(:mod:`flexmbd.engine`).
"""

from .builder import ModelBuilder
from .dynamics import inverse_dynamics, mass_matrix, reduced_mass_matrix, simulate
from .elements import Beam, Hinge, RigidBeam, SecondOrderBeam, SpringDamper, Truss
from .errors import (
    ArgumentError,
    ColumnError,
    ConvergenceError,
    FlexmbdError,
    InputFileError,
    LabelError,
    ModelError,
    SimulationError,
    SingularConfigurationError,
)
from .kinematics import (
    accelerations,
    deformation_transfer,
    deformations,
    first_order_transfer,
    hessian,
    initial_q,
    jacobian,
    kinematic_analysis,
    partition_jacobian,
    position_analysis,
    quadratic_velocity,
    second_order_transfer,
    solve_position,
    velocities,
)
from .model import CoordinateClass, DeformationClass, Model
from .motion import Custom, Expression, Polynomial
from .results import KinematicResult, SimulationResult
from .settings import RunSettings

__version__ = "0.2.0"


def __getattr__(name: str):
    """``read_dat`` and ``write_dat``, whose SPACAR syntax tables load on first use."""
    if name in ("read_dat", "write_dat"):
        from . import dat

        return getattr(dat, name)
    raise AttributeError(f"module 'flexmbd' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *__all__})

__all__ = [
    "ArgumentError",
    "Beam",
    "ColumnError",
    "ConvergenceError",
    "CoordinateClass",
    "Custom",
    "DeformationClass",
    "Expression",
    "FlexmbdError",
    "Hinge",
    "InputFileError",
    "KinematicResult",
    "LabelError",
    "Model",
    "ModelBuilder",
    "ModelError",
    "Polynomial",
    "RigidBeam",
    "RunSettings",
    "SecondOrderBeam",
    "SimulationError",
    "SimulationResult",
    "SingularConfigurationError",
    "SpringDamper",
    "Truss",
    "__version__",
    "accelerations",
    "deformation_transfer",
    "deformations",
    "first_order_transfer",
    "hessian",
    "initial_q",
    "inverse_dynamics",
    "jacobian",
    "kinematic_analysis",
    "mass_matrix",
    "partition_jacobian",
    "position_analysis",
    "quadratic_velocity",
    "read_dat",
    "reduced_mass_matrix",
    "second_order_transfer",
    "simulate",
    "solve_position",
    "velocities",
    "write_dat",
]
