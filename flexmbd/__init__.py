"""flexmbd: planar flexible multibody dynamics with the finite-element approach.

A mechanism is a set of nodes and elements whose deformation parameters are
functions of the nodal coordinates. Build a :class:`Model` with
:class:`ModelBuilder` (or read a SPACAR file with :func:`read_dat`), then analyse
it with the functions below; every analysis runs on the compiled core
(:mod:`flexmbd.engine`).
"""

from .builder import ModelBuilder
from .dynamics import inverse_dynamics, mass_matrix, reduced_mass_matrix, simulate
from .elements import (
    Beam,
    EulerNormalization,
    Hinge,
    RigidBeam,
    SecondOrderBeam,
    SpatialBeam,
    SpatialHinge,
    SpatialTruss,
    SpringDamper,
    Truss,
)
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
from .orientation import (
    angular_velocity,
    axis_angle,
    euler_parameters,
    euler_rates,
    rotation_matrix,
)
from .results import KinematicResult, SimulationResult
from .settings import RunSettings

__version__ = "0.2.0"


#: names loaded on first use, by module: the SPACAR syntax tables, the linearized
#: analyses, which need SciPy, and parameter studies (``import flexmbd`` loads numpy only)
_LAZY = {
    "dat": ("read_dat", "write_dat"),
    "linearization": ("Linearization", "linearize"),
    "modes": ("Buckling", "Modes", "ModesAlong", "buckling", "compliance", "modes_along",
              "vibration_modes"),
    "statespace": ("StateSpace", "state_space"),
    "statics": ("StaticResult", "static_equilibrium"),
    "studies": ("sweep",),
}


def __getattr__(name: str):
    """The names of :data:`_LAZY`, imported from their module on first use."""
    import importlib

    for module, names in _LAZY.items():
        if name in names:
            return getattr(importlib.import_module(f".{module}", __name__), name)
    raise AttributeError(f"module 'flexmbd' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *__all__})

__all__ = [
    "ArgumentError",
    "Beam",
    "Buckling",
    "ColumnError",
    "ConvergenceError",
    "CoordinateClass",
    "Custom",
    "DeformationClass",
    "EulerNormalization",
    "Expression",
    "FlexmbdError",
    "Hinge",
    "InputFileError",
    "KinematicResult",
    "LabelError",
    "Linearization",
    "Model",
    "ModelBuilder",
    "ModelError",
    "Modes",
    "ModesAlong",
    "Polynomial",
    "RigidBeam",
    "RunSettings",
    "SecondOrderBeam",
    "SimulationError",
    "SimulationResult",
    "SingularConfigurationError",
    "SpatialBeam",
    "SpatialHinge",
    "SpatialTruss",
    "SpringDamper",
    "StateSpace",
    "StaticResult",
    "Truss",
    "__version__",
    "accelerations",
    "angular_velocity",
    "axis_angle",
    "buckling",
    "compliance",
    "deformation_transfer",
    "deformations",
    "euler_parameters",
    "euler_rates",
    "first_order_transfer",
    "hessian",
    "initial_q",
    "inverse_dynamics",
    "jacobian",
    "kinematic_analysis",
    "linearize",
    "mass_matrix",
    "modes_along",
    "partition_jacobian",
    "position_analysis",
    "quadratic_velocity",
    "read_dat",
    "reduced_mass_matrix",
    "rotation_matrix",
    "second_order_transfer",
    "simulate",
    "solve_position",
    "state_space",
    "static_equilibrium",
    "sweep",
    "velocities",
    "vibration_modes",
    "write_dat",
]
