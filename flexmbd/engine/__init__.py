"""The compiled engine: the model as the core's arrays, the workspace every analysis runs
on, and what the core is made of.

* :mod:`~flexmbd.engine.workspace`: :class:`Engine`, a model compiled once onto the C core
  with its run state; the only code that calls the core. The generalized coordinates
  ``q`` by label, the laws and loads in the core's terms, and the core's errors in
  flexmbd's.
* :mod:`~flexmbd.engine.spec`: what a model hands the core, declared and checked.
* :mod:`~flexmbd.engine.assembly`: model-wide arrays from the element kernels.
* :mod:`~flexmbd.engine.diagnosis`: what a singular ``D_c`` or mass matrix leaves free, in
  words.
* :mod:`~flexmbd.engine.codegen`: the C kernels generated from the element types'
  definitions (``python -m flexmbd.engine.codegen``); ``csrc/`` holds the core's C and
  ``_core.pyx`` its binding (Cython).
"""

from .workspace import (
    CORE_BUILD,
    KINEMATIC_OUTPUTS,
    MAX_ITERATIONS,
    OUTPUTS,
    Engine,
    Forces,
    check_core,
    compile_model,
    deformations_and_jacobian,
    element_kernel,
    initial_q,
    load_slots,
    load_vector,
    output_bytes,
    output_sizes,
    q_index,
    q_scale,
    resolve_laws,
    unwrap_near,
    workspace_of,
    write_rows,
)

__all__ = ["CORE_BUILD", "KINEMATIC_OUTPUTS", "MAX_ITERATIONS", "OUTPUTS", "Engine", "Forces",
           "check_core", "compile_model", "deformations_and_jacobian", "element_kernel",
           "initial_q", "load_slots", "load_vector", "output_bytes", "output_sizes", "q_index",
           "q_scale", "resolve_laws", "unwrap_near", "workspace_of", "write_rows"]
