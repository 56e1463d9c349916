"""What a design parameter changes in a model's data, from the user's build on either side.

A ``build(**params)`` is the user's own code: a parameter reaches the model through
node positions, sections, materials, masses and loads, in ways only that code knows. Its
derivative is taken on the compiled data (:class:`~flexmbd.engine.spec.CoreSpec`), not
on the analysis: a fourth-order central difference of the models built at ``theta +
(-2, -1, 1, 2) h`` with ``h = 1e-3 |theta|``. The data are smooth (polynomial, rational,
square roots) in the parameters, so the difference is exact for polynomials up to the
fourth degree (a thickness cubed) and accurate to about ``1e-12`` otherwise, and needs no
Newton solve. That accuracy matters: in a flexure driven to a set rotation, the load's
change and the stiffness's change nearly cancel (a change of thickness barely turns the
stage), and an error of ``1e-10`` in either (a second-order difference's rounding) is
``1e-5`` of the rotation's derivative. The state's and the outputs' derivatives then
follow exactly (:mod:`flexmbd.design.state`).
A design whose structure differs on either side (another number of elements, other
releases) is refused by name.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ..builder.recording import neighbour_builds
from ..engine import Workspace, compiled_of, initial_q, load_vector, q_index
from ..engine.spec import CoreSpec
from ..errors import ArgumentError
from ..model import Model
from ..settings import RunSettings
from ..studies.case import split_build
from .state import DataChange, Equilibrium, held_coordinates, weights

__all__ = ["DATA_STEP", "STENCIL", "Built", "build_design", "data_change", "rate"]

#: the relative step of the central differences of the data
DATA_STEP = 1e-3
#: the fourth-order central difference: ``f' h = sum w f(theta + k h)`` over ``(k, w)``
STENCIL = ((-2, 1.0 / 12.0), (-1, -8.0 / 12.0), (1, 8.0 / 12.0), (2, -1.0 / 12.0))

#: the compiled arrays that fix a design's structure: equal on both sides of a difference
_STRUCTURE = ("etype", "c_idx", "d_idx", "elastic")
_CLASSIFICATION = ("fixed", "q_coord", "q_def", "rows", "dep", "free_of", "mult_of_def",
                   "elastic_def")


@dataclass(frozen=True)
class Built:
    """A design's model and what its static analysis applies at the last load step.

    Attributes:
        model: the mechanism.
        settings: the run settings ``build`` returned (or the defaults).
        loads: the applied loads at the last step ``(nx,)`` [N, N m].
        q_target: ``q`` with the inputs at their last targets ``(nq,)``.
    """

    model: Model
    settings: RunSettings
    loads: np.ndarray
    q_target: np.ndarray


def build_design(build: Callable, params: Mapping[str, float], neighbour: bool = False
                 ) -> Built:
    """Call ``build(**params)`` and read its settings' last load step; a ``neighbour`` of
    a checked design has its values checked only (:func:`neighbour_builds`).

    Raises:
        ArgumentError: ``build`` failed or returned neither a model nor a ``(model,
            settings)`` pair.
    """
    try:
        if neighbour:
            with neighbour_builds():
                built = build(**params)
        else:
            built = build(**params)
    except Exception as error:  # the user's code: its failure named with the design
        raise ArgumentError("build", f"failed at {dict(params)}: {type(error).__name__}: "
                                     f"{error}") from error
    try:
        model, settings = split_build(built)
    except Exception as error:
        raise ArgumentError("build", str(error).removeprefix("build: ")) from None
    loads = (np.zeros(model.n_coordinates) if not settings.load_increment
             else load_vector(model, dict(settings.load_increment), "load_increment"))
    q = initial_q(model)
    for label, value in dict(settings.input_increment).items():
        q[q_index(model, label, "input_increment")] += value
    return Built(model, settings, loads, q)


class Neighbours(Sequence):
    """The workspaces of a design's neighbours, made when first asked for (the data need
    only the compiled arrays; the mass's and the weight's changes need the core)."""

    def __init__(self, models: list[Model]):
        self.models = models
        self._made: dict[int, Workspace] = {}

    def __len__(self) -> int:
        return len(self.models)

    def __getitem__(self, k):
        if isinstance(k, slice):
            return [self[j] for j in range(len(self))[k]]
        if k not in self._made:
            self._made[k] = Workspace(self.models[k])
        return self._made[k]


def _check_structure(a: CoreSpec, b: CoreSpec, name: str) -> None:
    same = all(np.array_equal(getattr(a.elements, f), getattr(b.elements, f))
               for f in _STRUCTURE) and all(
        np.array_equal(getattr(a.classification, f), getattr(b.classification, f))
        for f in _CLASSIFICATION)
    if not same:
        raise ArgumentError("params", f"a small change of {name!r} changes the model's "
                                      f"structure (its elements, supports, inputs or "
                                      f"releases): a design parameter may change numbers "
                                      f"only; keep the structure fixed in build")


def rate(values, h: float) -> np.ndarray:
    """The derivative from the values at the :data:`STENCIL`'s points, step ``h``."""
    total = sum(w * np.asarray(v, dtype=float) for (_, w), v in
                zip(STENCIL, values, strict=True))
    return np.asarray(total) / h


def data_change(state: Equilibrium, nominal: Built, sides: tuple[Built, ...], h: float,
                name: str) -> tuple[DataChange, Neighbours]:
    """The data change per unit of the parameter ``name`` from the designs ``sides`` built
    at the :data:`STENCIL`'s points ``theta + k h``, and their workspaces (for the mass's
    change).

    Raises:
        ArgumentError: the structure differs on either side.
    """
    engines = Neighbours([side.model for side in sides])
    compiled = [compiled_of(side.model, like=state.spec) for side in sides]
    for spec in compiled:
        _check_structure(state.spec, spec, name)

    held = held_coordinates(nominal.model)
    x_held = np.zeros(nominal.model.n_coordinates)
    x_held[held] = rate([side.model.x0 for side in sides], h)[held]
    slots = np.asarray(nominal.model.independent_coordinates)
    inputs = np.asarray(nominal.model.q_is_input, dtype=bool)
    dq = rate([side.q_target for side in sides], h)
    x_held[slots[inputs[:len(slots)]]] = dq[:len(slots)][inputs[:len(slots)]]
    dp, dS = [], []
    for group in state.groups:
        nd, npar = group.defs.shape[1], group.param.shape[1]
        el = [c.elements for c in compiled]
        params = [e.param[e.p_off[group.at][:, None] + np.arange(npar)] for e in el]
        laws = [e.S[e.law_off[group.at][:, None] + np.arange(nd * nd)] for e in el]
        dp.append(rate(params, h).reshape(len(group.at), npar))
        dS.append(rate(laws, h).reshape(len(group.at), nd, nd))
    # the loads, and the weights at the state's coordinates, held ones as each side has them
    forces, weighing = [], []
    weighed = bool(np.any(state.spec.loads.gravity) and np.any(state.spec.elements.emass))
    for k, (side, spec) in enumerate(zip(sides, compiled, strict=True)):
        x = state.x.copy()
        x[held] = side.model.x0[held]
        x[slots[inputs[:len(slots)]]] = side.q_target[:len(slots)][inputs[:len(slots)]]
        forces.append(spec.loads.f_const + side.loads)
        weighing.append(weights(engines[k], x) if weighed else np.zeros(len(x)))
    cls = state.spec.classification
    rows = cls.row_of_def[state.constrained]
    nrigid, nxm = state.spec.sizes.nrigid, state.spec.sizes.nxm
    dtarget = np.where(rows < nrigid, 0.0, dq[np.clip(nxm + rows - nrigid, 0, len(dq) - 1)])
    change = DataChange(x_held=x_held, dp=dp, dlaw=dS,
                        dsigma0=rate([c.elements.sigma0 for c in compiled], h),
                        df=rate(forces, h), dweight=rate(weighing, h), dtarget=dtarget)
    return change, engines
