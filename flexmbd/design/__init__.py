"""Design sensitivities and optimisation: a design's outputs with their exact gradients.

``evaluate(build, params, outputs)`` runs the static analysis of ``build(**params)`` and
gives each output's value at the last load step and its derivative to every parameter,
from one factorisation of the engine's tangent (:mod:`flexmbd.design.state`).
"""

from .evaluate import DesignResult, evaluate
from .outputs import KS_RHO

__all__ = ["KS_RHO", "DesignResult", "evaluate"]
