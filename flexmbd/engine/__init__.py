"""The compiled engine: the model as the core's arrays, the workspace every analysis runs
on, and what the core is made of.

* :mod:`~flexmbd.engine.workspace`: :class:`Workspace`, a model compiled once onto the C
  core with its run state; the only code that calls the core.
* :mod:`~flexmbd.engine.compile`: a model as the core's arrays (:func:`compile_model`).
* :mod:`~flexmbd.engine.laws`: the generalized coordinates ``q`` by label, their laws and
  the loads by label.
* :mod:`~flexmbd.engine.core`: the binding, loaded (:func:`check_core` says what is
  missing).
* :mod:`~flexmbd.engine.spec`: what a model hands the core, declared and checked.
* :mod:`~flexmbd.engine.assembly`: model-wide arrays from the element kernels.
* :mod:`~flexmbd.engine.diagnosis`: what a singular ``D_c`` or mass matrix leaves free, in
  words.
* :mod:`~flexmbd.engine.codegen`: the C kernels generated from the element types'
  definitions (``python -m flexmbd.engine.codegen``); ``csrc/`` holds the core's C and
  ``_core.pyx`` its binding (Cython, typed for checkers by ``_core.pyi``).
"""

from .compile import compile_model, reverse_cuthill_mckee
from .core import CORE_BUILD, CoreError, check_core
from .laws import (
    Forces,
    initial_q,
    load_slots,
    load_vector,
    q_index,
    q_scale,
    resolve_laws,
    unwrap_near,
)
from .workspace import (
    KINEMATIC_OUTPUTS,
    MAX_ITERATIONS,
    OUTPUTS,
    Workspace,
    compiled_of,
    deformations_and_jacobian,
    element_kernel,
    output_bytes,
    output_sizes,
    workspace_for,
    workspace_of,
    write_rows,
)

__all__ = ["CORE_BUILD", "KINEMATIC_OUTPUTS", "MAX_ITERATIONS", "OUTPUTS", "CoreError",
           "Forces", "Workspace", "check_core", "compile_model", "compiled_of",
           "deformations_and_jacobian",
           "element_kernel", "initial_q", "load_slots", "load_vector", "output_bytes",
           "output_sizes", "q_index", "q_scale", "resolve_laws", "reverse_cuthill_mckee",
           "unwrap_near", "workspace_for", "workspace_of", "write_rows"]
