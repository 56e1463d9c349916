"""flexmbd: planar flexible multibody dynamics with the finite-element approach.

A mechanism is a set of nodes and elements whose deformation parameters are
functions of the nodal coordinates (THEORY.md). Build a :class:`Model` with
:class:`ModelBuilder`, then analyse it with the functions below.
"""

from .builder import ModelBuilder
from .dat import read_dat, write_dat
from .elements import Beam, Hinge, RigidBeam, Truss
from .errors import (
    ConvergenceError,
    FlexmbdError,
    InputFileError,
    ModelError,
    SimulationError,
    SingularConfigurationError,
)
from .inverse import inverse_dynamics
from .kinematic_run import kinematic_analysis
from .kinematics import (
    accelerations,
    deformation_transfer,
    deformations,
    first_order_transfer,
    hessian,
    initial_q,
    jacobian,
    partition_jacobian,
    position_analysis,
    quadratic_velocity,
    second_order_transfer,
    solve_position,
    velocities,
)
from .model import CoordinateClass, DeformationClass, Model
from .motion import Custom, Polynomial
from .results import KinematicResult, SimulationResult
from .simulation import simulate

__version__ = "0.1.0"

__all__ = [
    "Beam",
    "ConvergenceError",
    "CoordinateClass",
    "Custom",
    "DeformationClass",
    "FlexmbdError",
    "Hinge",
    "InputFileError",
    "KinematicResult",
    "Model",
    "ModelBuilder",
    "ModelError",
    "Polynomial",
    "RigidBeam",
    "SimulationError",
    "SimulationResult",
    "SingularConfigurationError",
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
    "partition_jacobian",
    "position_analysis",
    "quadratic_velocity",
    "read_dat",
    "second_order_transfer",
    "simulate",
    "solve_position",
    "velocities",
    "write_dat",
]
