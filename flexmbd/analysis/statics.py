"""Static equilibrium with load steps (SPACAR's static mode, THEORY 9).

The dynamic degrees of freedom ``q_d`` solve ``F_q^T f - E_q^T sigma = 0`` (the driving
load ``tau_d`` of the engine's inverse dynamics at rest) by Newton's method with the
tangent ``K0 + G0``, exact for large deflections. As SPACAR does, row 0 is the
equilibrium under the model's loads (``XF``, gravity) with the inputs at their initial
values; rows ``k = 1..n`` add ``k/n`` of the load increments (``DELXF``) and the input
increments (``DELINPX``, ``DELINPE``). Every stretch is first tried in one step and
halved while Newton fails; row 0 is reached from the unloaded reference configuration
by the same continuation of its loads.
"""

from __future__ import annotations

import sys
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Literal

import numpy as np

from .. import checks
from ..engine import (
    MAX_ITERATIONS,
    OUTPUTS,
    Workspace,
    initial_q,
    load_vector,
    output_bytes,
    output_sizes,
    q_index,
    q_scale,
    workspace_of,
)
from ..errors import (
    AnalysisWarning,
    ArgumentError,
    ConvergenceError,
    FlexmbdError,
    SimulationError,
)
from ..model import Model
from ..progress import progress_bar
from ..results import SimulationResult, check_on_failure, conclude, first_rows
from ..settings import RunSettings
from ..summary import Columns, clip
from .banded import BANDED_FROM, BandedStatics
from .linearization import Linearization, equilibrium_state, linearize, static_tangent

__all__ = ["StaticResult", "static_equilibrium"]

#: halvings of a load step before a static analysis gives up
MAX_HALVINGS = 12
#: halvings of a load step after which the banded solver lets the reduced one try: a
#: smaller step in all coordinates costs less than a reduced Newton on a large model
REDUCED_AFTER = 2



@dataclass(eq=False)
class StaticResult(SimulationResult):
    """Equilibria along load steps: the columns of a :class:`SimulationResult` (rates zero)
    with the load factor in place of time.

    The column ``"load"`` (also ``t``) is the load factor, 0 for the model's loads and 1
    with the full increments.

    Attributes:
        applied: loads on top of the model's own at each row ``(n, nx)`` [N, N m].
    """

    applied: np.ndarray | None = None

    @property
    def load(self) -> np.ndarray:
        """The load factor of each row ``(n,)``: 0 for the model's own loads, 1 with the
        full increments (also the column ``"load"``)."""
        return self.__dict__["t"]

    def _rows(self) -> np.ndarray:
        # ``t``, a time in every other result, is the load factor here. flexmbd's generic
        # code (tables, plots, files) reads the rows of any result by ``t``; read from
        # outside flexmbd it is the old spelling of ``load``
        if not sys._getframe(1).f_globals.get("__name__", "").startswith("flexmbd."):
            checks.deprecated("StaticResult.t is the load factor: read it as .load")
        return self.__dict__["t"]

    def _set_rows(self, value: np.ndarray) -> None:
        self.__dict__["t"] = value

    t = property(_rows, _set_rows)

    def __repr__(self) -> str:
        rows = len(self.t)
        span = f"{rows} load step{'s' if rows != 1 else ''}" + (
            f", load factor {self.t[0]:.6g} to {self.t[-1]:.6g}" if rows else "")
        return clip(self._headline(span) + "\n  columns: load, " +
                    self._column_groups().removeprefix("t, ") +
                    "\n  one: res['x3.1'] (an array over the steps); all: res.columns(); "
                    "linearized at a step: res.linearization(row)")

    __str__ = __repr__

    def __getitem__(self, name: str) -> np.ndarray:
        return self.t if name.strip() == "load" else super().__getitem__(name)

    def columns(self) -> dict[str, np.ndarray]:
        out = super().columns()
        return Columns({("load" if name == "t" else name): values
                        for name, values in out.items()})

    def linearization(self, row: int = -1) -> Linearization:
        """The linearized equations at one row (default the last): for its vibration
        modes, buckling loads and compliance (:mod:`flexmbd.analysis.modes`)."""
        if not len(self.t):
            raise ArgumentError("row", "the static analysis has no converged row")
        if self.applied is None or self.e is None:
            raise ArgumentError("row", "the static analysis recorded no loads or deformations")
        return linearize(self.model, self.x[row], loads=self.applied[row], e=self.e[row])


def static_equilibrium(
    model: Model,
    *,
    loads=None,
    load_increment=None,
    input_increment: Mapping[str, float] | None = None,
    steps: int | None = None,
    tolerance: float | None = None,
    max_iterations: int = MAX_ITERATIONS,
    on_failure: Literal["raise", "return"] = "raise",
    progress: bool | None = None,
    method: Literal["auto", "reduced", "banded"] = "auto",
) -> StaticResult:
    """Static equilibria under the model's loads and load steps.

    Args:
        model: the mechanism; its dynamic degrees of freedom are solved for.
        loads: loads on top of the model's ``XF`` and gravity ``(nx,)`` or
            ``{"x5.2": -10.0}`` [N, N m], applied from row 0.
        load_increment: the total load increment reached at the last row (``DELXF``).
        input_increment: total increments of prescribed inputs by label
            (``{"x2.1": 0.5}``, ``DELINPX``/``DELINPE``) [m, rad].
        steps: load steps ``n`` (``ITERSTEP``); rows ``0..n``. Default 1 with an
            increment, 0 without.
        tolerance: Newton tolerance on the degrees of freedom [m, rad]; default
            ``1e-10`` of the model size.
        max_iterations: Newton iterations per attempt before the step is halved.
        on_failure: ``"raise"`` (with the converged rows as ``error.partial_result``) or
            ``"return"`` them with ``success=False``.
        progress: progress bar over the load steps (default: many steps on a terminal).
        method: ``"reduced"``: Newton on the degrees of freedom with the tangent ``K0 +
            G0``; ``"banded"``: Newton in all coordinates and the constraint stresses on
            the banded saddle-point system (:mod:`flexmbd.analysis.banded`), whose cost
            grows linearly with the number of elements; ``"auto"``: banded from
            :data:`BANDED_FROM` degrees of freedom. Both reach the same equilibria. Where
            the banded Newton fails on a stretch halved :data:`REDUCED_AFTER` times, the
            reduced one tries it: the result's ``message`` counts those stretches, and
            ``method="banded"`` warns (:class:`~flexmbd.AnalysisWarning`).

    Returns:
        :class:`StaticResult`, one row per load step.

    Raises:
        ConvergenceError: a step did not converge even after halving; it names the last
            converged load factor and the degree of freedom with the largest residual.

    Examples:
        A cantilever under a small tip load bends by ``P L^3 / (3 EI)``:

        >>> import flexmbd as fm
        >>> b = fm.ModelBuilder("cantilever")   # 1 m, four beams, EI = 2 N m^2, clamped at 1
        >>> for k in range(5):
        ...     _ = b.add_node(2 * k + 1, 0.25 * k, 0.0)
        >>> for k in range(4):
        ...     _ = (b.add_beam(k + 1, 2 * k + 1, 2 * k + 2, 2 * k + 3, 2 * k + 4)
        ...          .dynamic_deformation(k + 1).set_mass(k + 1, 0.5)
        ...          .set_stiffness(k + 1, axial=1e6, bending=2.0))
        >>> column = b.fix(1).fix(2).build()
        >>> statics = fm.static_equilibrium(column, load_increment={"x9.2": -0.01}, steps=2)
        >>> print(f"{statics['x9.2'][-1]:.6f} m, closed form {-0.01 / (3 * 2.0):.6f} m")
        -0.001667 m, closed form -0.001667 m
    """
    check_on_failure(on_failure)
    checks.choice(method, "method", ("auto", "reduced", "banded"))
    base = np.zeros(model.n_coordinates) if loads is None else load_vector(model, loads,
                                                                           "loads")
    increment = (np.zeros(model.n_coordinates) if load_increment is None
                 else load_vector(model, load_increment, "load_increment"))
    inputs = np.zeros(model.n_dof)
    given_inputs = {} if input_increment is None else checks.number_map(input_increment,
                                                                         "input_increment")
    for label, value in given_inputs.items():
        j = q_index(model, label, "input_increment")
        if not model.q_is_input[j]:
            raise ArgumentError("input_increment", f"{label} is a dynamic degree of freedom, "
                                                   f"not a prescribed input")
        inputs[j] = value
    given = bool(np.any(increment) or np.any(inputs))
    steps = (1 if given else 0) if steps is None else steps
    steps = checks.whole(steps, "steps", 0, checks.LARGEST_STEPS)
    rows = steps + 1
    # the applied loads are one more row of nx values
    checks.output_memory(rows, output_bytes(model, integrated=False) +
                         8 * model.n_coordinates, "steps")
    banded = method == "banded" or (method == "auto" and model.n_dof >= BANDED_FROM)
    solver = (_BandedSolver if banded else _Solver)(model, workspace_of(model), tolerance,
                                                   checks.iteration_limit(max_iterations))
    own = solver.engine.constant_loads
    sizes = output_sizes(model)
    arrays = {name: np.empty((rows, sizes[name])) for name in OUTPUTS}
    factors, applied = np.arange(rows) / max(steps, 1), np.empty((rows, model.n_coordinates))
    done, error = 0, None

    def keep(load: np.ndarray) -> None:
        nonlocal done
        state = solver.state
        for name, values in arrays.items():
            values[done] = state[name]
        applied[done] = load
        done += 1

    try:
        with progress_bar(factors, "load steps", progress) as advance:
            # row 0: the model's and the given loads, switched on from the unloaded reference
            solver.follow(lambda s: ((s - 1.0) * own + s * base, initial_q(model)),
                          lambda s: f"the initial loads (row 0) at {s:.6g} of their value")
            keep(base)
            for k in range(1, steps + 1):
                def target(s, k=k):
                    factor = (k - 1 + s) / steps
                    return base + factor * increment, initial_q(model) + factor * inputs
                solver.follow(target, lambda s, k=k: f"load factor {(k - 1 + s) / steps:.6g} "
                                                     f"(step {k} of {steps})")
                keep(base + k / steps * increment)
                if advance is not None:
                    advance(factors[k])
    except (FlexmbdError, KeyboardInterrupt) as caught:
        error = caught
    result = StaticResult(model, factors[:done], applied=applied[:done],
                          **first_rows(arrays, done))
    how = ""
    rescued = getattr(solver, "rescued", 0)
    if rescued:   # never silent: the banded Newton failed where the reduced one converged
        how = (f"; {rescued} stretch{'es' if rescued != 1 else ''} by the reduced Newton, "
               f"where the banded one failed after {REDUCED_AFTER} halvings")
        if method == "banded":
            warnings.warn(f"static_equilibrium(method='banded'){how[1:]}", AnalysisWarning,
                          stacklevel=2)
    return conclude(result, error, on_failure,
                    f"converged {done} load step{'s' if done != 1 else ''}{how}")


def file_equilibrium(model: Model, settings: RunSettings, steps: int | None = None
                     ) -> StaticResult:
    """The static equilibrium a SPACAR input file asks for: its loads, the load and input
    increments of ``DELXF``, ``DELINPX``, ``DELINPE`` in ``steps`` load steps (default
    ``ITERSTEP``'s), its tolerance and iteration limit; failures are returned.

    Raises:
        ArgumentError: ``steps`` below 0 (named ``--steps``, as the command line gives it).
    """
    refuse_routines(settings)
    steps = settings.load_steps if steps is None else steps
    if steps is not None and steps < 0:
        raise ArgumentError("--steps", f"must be 0 or more, got {steps}")
    given = settings.load_increment or settings.input_increment
    return static_equilibrium(model, load_increment=dict(settings.load_increment) or None,
                              input_increment=settings.input_increment,
                              steps=steps if given else 0, tolerance=settings.tolerance,
                              max_iterations=settings.max_iterations or MAX_ITERATIONS,
                              on_failure="return")


def refuse_routines(settings: RunSettings) -> None:
    """A static analysis takes the loads and inputs of ``XF``, ``DELXF`` and ``DELINPX``;
    a file's user routines are functions of time, which a static analysis has not."""
    for keyword, name in (("USERSIG", settings.user_loads), ("USERINP", settings.user_inputs)):
        if name:
            raise ArgumentError(keyword, f"{name} is a routine of time, which static analyses "
                                         f"do not call: they take XF, DELXF and DELINPX; run "
                                         f"the file over its TIMESTEP (flexmbd run, or "
                                         f"flexmbd spacar 1 or 2)")


class _Solver:
    """Newton's method on the dynamic degrees of freedom along a path of loads and inputs,
    from the last converged state."""

    def __init__(self, model: Model, engine: Workspace, tolerance: float | None,
                 max_iterations: int):
        self.model, self.engine, self.max_iterations = model, engine, max_iterations
        self.tolerance = (engine.tolerance if tolerance is None else
                          checks.position_tolerance(tolerance, model.characteristic_length,
                                                    float(np.abs(model.x0).max(initial=0))))
        self.scale = q_scale(model) * model.characteristic_length
        self.dynamic = np.flatnonzero(~np.asarray(model.q_is_input))
        self.x = np.asarray(model.x0, dtype=float)
        self.state: dict[str, np.ndarray] = {}
        self.halvings = 0   #: of the stretch being followed, so far

    def follow(self, target, where) -> None:
        """Converge at ``target(1)`` (loads ``(nx,)``, ``q`` with the prescribed entries)
        from the state at ``target(0)``, halving the step while Newton fails;
        ``where(s)`` names the point ``s`` of the path in messages."""
        s, step, halvings = 0.0, 1.0, 0
        while s < 1.0:
            trial = min(1.0, s + step)
            self.halvings = halvings
            try:
                self.solve(*target(trial))
            except (SimulationError, np.linalg.LinAlgError) as failure:
                halvings += 1
                if halvings > MAX_HALVINGS:
                    raise ConvergenceError(
                        f"static equilibrium did not converge towards {where(trial)}: "
                        f"{failure}; last converged: {where(s)} (step halved {MAX_HALVINGS} "
                        f"times to {step:.3g}); the loads may exceed what the "
                        f"structure carries (buckling, a limit point), or it is a mechanism "
                        f"without stiffness in some direction") from None
                step /= 2
                continue
            s = trial
            step = min(1.0 - s, 2 * step) if s < 1.0 else step

    def solve(self, loads: np.ndarray, q_target: np.ndarray) -> None:
        """Newton at fixed loads and inputs from the last converged configuration; on
        success the state becomes the new last one, else it raises and nothing changes."""
        engine, model = self.engine, self.model
        q = self.state["q"].copy() if self.state else q_target.copy()
        inputs = np.asarray(model.q_is_input, dtype=bool)
        q[inputs] = q_target[inputs]
        x = engine.positions(q, self.x)
        residual = np.inf
        dynamic = np.ix_(self.dynamic, self.dynamic)
        for _ in range(self.max_iterations):
            state, tangent = static_tangent(engine, x, loads, near=q)
            residual_vector = state["driving"][self.dynamic]
            step = -np.linalg.solve(tangent[dynamic], residual_vector)
            if not np.all(np.isfinite(step)):
                raise np.linalg.LinAlgError("the tangent K0 + G0 is singular")
            q = state["q"].copy()
            q[self.dynamic] += step
            x = engine.positions(q, state["x"])
            size = np.abs(step) * self.scale[self.dynamic]
            residual = float(np.max(np.abs(residual_vector), initial=0.0))
            if np.max(size, initial=0.0) <= self.tolerance:
                zero = np.zeros(model.n_dof)
                self.state = _row(equilibrium_state(engine, x, zero, zero, loads, near=q))
                self.x = self.state["x"]
                return
        worst = int(self.dynamic[np.argmax(np.abs(residual_vector))]) if len(self.dynamic) \
            else 0
        raise ConvergenceError(f"Newton did not converge in {self.max_iterations} iterations "
                               f"(residual {residual:.3g} largest on "
                               f"{model.describe_q(worst)})",
                               iterations=self.max_iterations, residual=residual)


class _BandedSolver(_Solver):
    """Newton's method in all coordinates and the constraint stresses
    (:class:`~flexmbd.analysis.banded.BandedStatics`), each solve from the last converged
    coordinates and stresses; a converged state is the reduced solver's (the engine's
    equilibrium at its ``q``)."""

    def __init__(self, model: Model, engine: Workspace, tolerance: float | None,
                 max_iterations: int):
        super().__init__(model, engine, tolerance, max_iterations)
        self.banded = BandedStatics(model, engine)
        self.mu = np.zeros(len(self.banded.constrained))
        self.rescued = 0   #: stretches the reduced Newton took (the result says so)

    def solve(self, loads: np.ndarray, q_target: np.ndarray) -> None:
        """Newton in all coordinates; where it fails (a step too large for constraints
        linearized in all coordinates), the caller halves the step, and from
        :data:`REDUCED_AFTER` halvings on the reduced solver's Newton, which solves the
        constraints at every iteration (but costs the cube of the degrees of freedom),
        takes the step before the next halving."""
        model = self.model
        q = self.state["q"].copy() if self.state else q_target.copy()
        inputs = np.asarray(model.q_is_input, dtype=bool)
        q[inputs] = q_target[inputs]
        try:
            x, mu = self.banded.equilibrium(self.x, q, self.mu, loads, self.tolerance,
                                            self.max_iterations)
        except (SimulationError, np.linalg.LinAlgError):
            if self.halvings < REDUCED_AFTER:
                raise
            super().solve(loads, q_target)   # raises as the reduced solver does
            self.rescued += 1
            self.mu = self.state["sigma"][self.banded.constrained]
            return
        zero = np.zeros(model.n_dof)
        self.state = _row(equilibrium_state(self.engine, x, zero, zero, loads, near=q))
        self.x, self.mu = self.state["x"], mu


def _row(state: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The columns of a result row from a converged state at rest
    (:func:`~flexmbd.analysis.linearization.equilibrium_state`)."""
    return {key: state[key] for key in OUTPUTS}
