"""flexmbd: flexible multibody dynamics with the finite-element approach, planar and
spatial.

A mechanism is a set of nodes and elements whose deformation parameters are
functions of the nodal coordinates. Build a :class:`Model` with
:class:`ModelBuilder` (or read a SPACAR file with :func:`read_dat`), then analyse
it with the functions below; every analysis runs on the compiled core
(:mod:`flexmbd.engine`).

The names load with their module on first use (``import flexmbd`` itself loads only
the errors): a command or script pays for what it uses, the symbolic path, SciPy's
linearized analyses and parameter studies for instance only when it uses them.
"""

from .errors import (
    AccuracyWarning,
    AnalysisWarning,
    ArgumentError,
    ColumnError,
    ConvergenceError,
    FlexmbdError,
    InputFileError,
    LabelError,
    ModelError,
    ModelWarning,
    ResultFileWarning,
    SimulationError,
    SingularConfigurationError,
    StiffnessError,
    UnstressedError,
)

__version__ = "0.2.0"

#: the public names besides the errors, by the module that defines them
_NAMES = {
    "builder": ("ModelBuilder",),
    "elements": ("Beam", "EulerNormalization", "Hinge", "RigidBeam", "SecondOrderBeam",
                 "SpatialBeam", "SpatialHinge", "SpatialRigidBeam", "SpatialTruss",
                 "SpringDamper", "Truss"),
    "model": ("CoordinateClass", "DeformationClass", "Model"),
    "engine.workspace": ("Workspace",),
    "motion": ("Custom", "Expression", "Polynomial"),
    "orientation": ("angular_velocity", "axis_angle", "euler_parameters", "euler_rates",
                    "rotation_matrix"),
    "results": ("KinematicResult", "SimulationResult"),
    "sections": ("Circle", "Material", "Rectangle", "Tube", "beam_values"),
    "settings": ("RunSettings",),
    "analysis.dynamics": ("inverse_dynamics", "mass_matrix", "reduced_mass_matrix",
                          "simulate"),
    "analysis.kinematics": ("accelerations", "deformation_transfer", "deformations",
                            "first_order_transfer", "hessian", "initial_q", "jacobian",
                            "kinematic_analysis", "partition_jacobian", "position_analysis",
                            "quadratic_velocity", "second_order_transfer", "solve_position",
                            "velocities"),
    "analysis.energy": ("energy",),
    "analysis.eigen": ("EigenPath",),
    "analysis.linearization": ("Linearization", "linearize"),
    "analysis.load_steps": ("StepTable", "load_step_table"),
    "analysis.modes": ("Buckling", "Modes", "ModesAlong", "buckling", "compliance",
                       "modes_along", "node_compliance", "vibration_modes"),
    "analysis.statespace": ("StateSpace", "state_space"),
    "analysis.stresses": ("BeamStress", "StressHistory", "beam_stresses", "stress_history"),
    "analysis.statics": ("StaticResult", "static_equilibrium"),
    "io.dat": ("read_dat", "write_dat"),
    "io.sbd": ("SpacarFile", "read_sbd", "write_ltv", "write_sbd", "write_sbm"),
    "studies": ("sweep",),
}
_MODULE_OF = {name: module for module, names in _NAMES.items() for name in names}

__all__ = ["AccuracyWarning", "AnalysisWarning", "ArgumentError", "ColumnError", "ConvergenceError",
           "FlexmbdError", "InputFileError", "LabelError", "ModelError", "ModelWarning",
           "ResultFileWarning", "SimulationError", "SingularConfigurationError", "StiffnessError",
           "UnstressedError", "__version__"]
__all__ += sorted(_MODULE_OF)


def __getattr__(name: str):
    """A public name of :data:`_NAMES`, imported from its module on first use and kept
    (in place of a submodule of the same name, which the import binds here); a
    submodule (``flexmbd.engine``) likewise."""
    import importlib

    if name in _MODULE_OF:
        module = importlib.import_module(f".{_MODULE_OF[name]}", __name__)
        value = globals()[name] = getattr(module, name)
        return value
    if name.startswith("__"):  # what tools probe for (__wrapped__, ...): not a module
        raise AttributeError(f"module 'flexmbd' has no attribute {name!r}")
    try:
        return importlib.import_module(f".{name}", __name__)
    except ModuleNotFoundError as error:
        if error.name != f"{__name__}.{name}":
            raise
    raise AttributeError(f"module 'flexmbd' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *__all__})
