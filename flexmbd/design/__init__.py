"""Design sensitivities and optimisation: a design's outputs with their exact gradients.

``evaluate(build, params, outputs)`` runs the static analysis of ``build(**params)`` and
gives each output's value at the last load step and its derivative to every parameter,
from one factorisation of the engine's tangent (:mod:`flexmbd.design.state`);
``optimize(build, params, objective, constraints, bounds)`` searches the best design
with them (SciPy's SLSQP or trust-constr); ``check_gradient`` sets them beside central
differences of the analyses and a Taylor test.
"""

from .check import GradientCheck, check_gradient
from .evaluate import DesignResult, evaluate
from .optimize import optimize
from .outputs import KS_RHO as KS_RHO  # the stress aggregate's parameter

__all__ = ["DesignResult", "GradientCheck", "check_gradient", "evaluate", "optimize"]
