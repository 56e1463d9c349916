"""The analyses a SPACAR file asks for, with its run settings: kinematic analysis,
inverse dynamics or a forward simulation over a time grid (``flexmbd run``, studies of
a file, the linearization along a file's motion), with the file's user routines
(``USERSIG``, ``USERINP``)."""

from __future__ import annotations

import numpy as np

from ..engine import MAX_ITERATIONS
from ..errors import ArgumentError
from ..model import Model
from ..results import KinematicResult
from ..settings import RunSettings
from .dynamics import inverse_dynamics, simulate
from .integrate import ATOL, DEFAULT_METHOD, RTOL
from .kinematics import kinematic_analysis
from .routines import routine_inputs, routine_loads

#: the analyses of a run over time
MODES = ("kinematic", "dynamic", "inverse")


def default_mode(model: Model) -> str:
    """Dynamic when the model has dynamic degrees of freedom, kinematic otherwise."""
    return "dynamic" if np.any(~model.q_is_input) else "kinematic"


def check_mode(model: Model, mode: str) -> None:
    """A kinematic analysis moves only what is prescribed: it would hold the dynamic
    degrees of freedom of a model frozen, which is never what ``--mode kinematic`` means."""
    dynamic = model.dynamic_q_labels
    if mode == "kinematic" and dynamic:
        shown = ", ".join(dynamic[:6]) + (f" and {len(dynamic) - 6} more" if len(dynamic) > 6
                                          else "")
        raise ArgumentError("--mode", f"kinematic analysis prescribes every degree of freedom, "
                            f"but {shown} are dynamic (DYNX/DYNE); use --mode dynamic to "
                            f"simulate them or --mode inverse to hold them at their initial "
                            f"values")


def analyse(model: Model, settings: RunSettings, mode: str, times: np.ndarray,
            method: str = DEFAULT_METHOD, progress: bool | None = None) -> KinematicResult:
    """Run ``mode`` on ``model`` with the file's settings; failures are returned."""
    s = settings
    inputs = routine_inputs(model, s) or None   # USERINP
    forces = routine_loads(model, s)            # USERSIG
    if mode == "kinematic":
        if forces is not None:
            raise ArgumentError("--mode", f"a kinematic analysis applies no loads: USERSIG "
                                          f"{s.user_loads} acts in --mode dynamic or inverse")
        return kinematic_analysis(model, times, inputs=inputs, tolerance=s.tolerance,
                                  max_iterations=s.max_iterations or MAX_ITERATIONS,
                                  on_failure="return", progress=progress)
    if mode == "inverse":
        return inverse_dynamics(model, times, inputs=inputs, forces=forces, tolerance=s.tolerance,
                                max_iterations=s.max_iterations or MAX_ITERATIONS,
                                on_failure="return", progress=progress)
    return simulate(model, times, inputs=inputs, forces=forces, initial=s.initial,
                    method=method, rtol=s.rtol or RTOL, atol=s.atol or ATOL,
                    tolerance=s.tolerance, with_reactions=True, on_failure="return",
                    progress=progress)
