"""The workspace: a model compiled onto the core, and every evaluation and run on it.

Every analysis of flexmbd runs on one pipeline, the compiled core
(``flexmbd.engine._core``: C with a Cython binding, built by ``pip install``):
kinematic analysis, inverse dynamics, forward simulation, statics and the single
evaluations of the per-state functions. A :class:`Workspace` (Pinocchio's ``Data`` beside
its ``Model``) holds a model compiled once (:func:`~flexmbd.engine.compile.compile_model`)
on the core, a run's laws, loads and output arrays, the last configuration and
factorisation, and translates the core's failures into flexmbd's errors, named after
the model's coordinates and deformations. It is the only code that calls the core.

A workspace is made from a model by whoever needs one: a run over a time grid makes
its own; a caller may hold one (``Workspace(model)``). The per-state functions use the
model's default workspace (:func:`workspace_of`), one per thread, kept beside the model
(not in it: the model stays immutable and pickles) for the models used last.
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from collections.abc import Callable, Mapping
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import checks
from ..errors import (
    ArgumentError,
    ConvergenceError,
    FlexmbdError,
    SimulationError,
    SingularConfigurationError,
)
from ..model import Model
from ..motion import Law, Polynomial
from .assembly import Assembly
from .compile import compile_model
from .core import TYPE_NUMBER, check_core, native
from .diagnosis import at_time, massless_message, singular_message
from .laws import Forces, initial_q, law_values, load_vector, q_scale
from .spec import CoreSpec

if TYPE_CHECKING:
    from .core import RunStatus

#: default Newton tolerance relative to the model's characteristic length (THEORY 3)
RELATIVE_TOLERANCE = 1e-10
#: Newton iterations of a position solve before giving up
MAX_ITERATIONS = 25


def write_rows(fd: int, columns: list[np.ndarray]) -> None:
    """Write equally long float64 columns ``(n,)`` as CSV rows on the file descriptor
    ``fd``, every number as ``"%.17g"`` writes it, by the core in 64 kB pieces.

    Raises:
        OSError: the file cannot take them (a full disk).
    """
    check_core()
    native.csv_write(fd, [np.asarray(v, dtype=float).reshape(-1) for v in columns])


# --- element values of a model before it is compiled (the builder's checks) --------------
def element_kernel(element, name: str, x: np.ndarray, size: int,
                   xd: np.ndarray | None = None) -> np.ndarray:
    """One generated kernel (``"deform_jac"``, ``"hessian"``, ``"quadratic"``, ...) of one
    element at the coordinates ``x`` ``(nx,)`` (and rates ``xd``): its ``size`` values."""
    check_core()
    out = np.empty(size)
    coords = list(element.coordinates)
    native.kernel(TYPE_NUMBER[element.type], name, np.ascontiguousarray(x[coords]),
                 np.asarray(element.reference, dtype=float),
                 None if xd is None else np.ascontiguousarray(xd[coords]), None, out)
    return out


def deformations_and_jacobian(model: Model, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``e = D(x)`` ``(ne,)`` and ``D_x`` ``(ne, nx)`` element by element, for a model that
    cannot be compiled yet (the builder diagnoses a ``D_c`` that is not square with it);
    a compiled model's :class:`~flexmbd.engine.assembly.Assembly` gives the same."""
    x = np.asarray(x, dtype=float)
    e, D_x = np.zeros(model.n_deformations), np.zeros((model.n_deformations, len(x)))
    for element in model.elements.values():
        nd, nc = len(element.deformations), len(element.coordinates)
        out = element_kernel(element, "deform_jac", x, nd * (1 + nc))
        rows = list(element.deformations)
        e[rows] = out[:nd]
        D_x[np.ix_(rows, list(element.coordinates))] = out[nd:].reshape(nd, nc)
    return e, D_x


#: the columns a run fills, with their sizes as functions of the model
OUTPUTS = {"x": "nx", "xd": "nx", "xdd": "nx", "e": "ne", "ed": "ne", "edd": "ne",
           "q": "nq", "qd": "nq", "qdd": "nq", "sigma": "ne", "reactions": "nx",
           "driving": "nq"}


#: the kinematic ones among :data:`OUTPUTS`: coordinates and deformations, their rates and
#: accelerations
KINEMATIC_OUTPUTS = ("x", "xd", "xdd", "e", "ed", "edd")


def output_sizes(model: Model) -> dict[str, int]:
    """Values per output time of each column group of :data:`OUTPUTS`."""
    counts = {"nx": model.n_coordinates, "ne": model.n_deformations, "nq": model.n_dof}
    return {name: counts[size] for name, size in OUTPUTS.items()}


def output_bytes(model: Model, columns: tuple[str, ...] | None = None,
                 integrated: bool = True) -> int:
    """Bytes a run holds per output time [B]: its output arrays (``columns`` of
    :data:`OUTPUTS`, all by default) and the time; an ``integrated`` run also keeps the
    integrator's state ``[q_d, qdot_d]`` at each output, and one of free rotations
    joins its segments' arrays into new ones at the end."""
    sizes = output_sizes(model)
    values = sum(sizes[name] for name in (columns or OUTPUTS))
    if integrated and model.free_rotations:
        values *= 2
    if integrated:
        values += 2 * int(np.sum(~np.asarray(model.q_is_input)))
    return 8 * (values + 1)


#: how many models keep their default workspaces and compiled arrays, the last used
KEPT_MODELS = 64
_KEPT: OrderedDict[int, tuple[Model, dict]] = OrderedDict()
_KEPT_LOCK = threading.Lock()


def _kept(model: Model) -> dict:
    """What is computed once per model, kept beside it for the :data:`KEPT_MODELS` models
    used last: its compiled arrays, the conditioning of its reference configuration and
    each thread's default workspace. The model holds none of it, so it stays immutable
    and pickles."""
    with _KEPT_LOCK:
        entry = _KEPT.get(id(model))
        if entry is None or entry[0] is not model:
            entry = _KEPT[id(model)] = (model, {"local": threading.local()})
        _KEPT.move_to_end(id(model))
        while len(_KEPT) > KEPT_MODELS:
            _KEPT.popitem(last=False)
        return entry[1]


def _compiled(model: Model) -> tuple[CoreSpec, float | None]:
    """The model's compiled arrays (computed on first use; the core copies them) and the
    conditioning of ``D_c`` at its reference configuration when known."""
    entry = _kept(model)
    if "compiled" not in entry:
        entry["compiled"] = compile_model(model)
    return entry["compiled"], entry.get("reference")


def compiled_of(model: Model, like: CoreSpec | None = None) -> CoreSpec:
    """The model's compiled arrays (:func:`~flexmbd.engine.compile.compile_model`, with
    the band orderings of ``like`` where they fit), made once and kept beside the model
    with its workspaces."""
    entry = _kept(model)
    if "compiled" not in entry:
        entry["compiled"] = compile_model(model, like)
    return entry["compiled"]


def workspace_of(model: Model, tolerance: float | None = None,
              max_iterations: int = MAX_ITERATIONS) -> Workspace:
    """The model's default workspace for evaluations at one state, one per thread (its
    core holds the last configuration and factorisation), made on first use and kept
    beside the model (module docstring), with the position solve's ``tolerance``
    [m, rad] and ``max_iterations`` set as asked. Runs over a time grid make their own."""
    local = _kept(model)["local"]
    workspace = getattr(local, "workspace", None)
    if workspace is None:
        workspace = local.workspace = Workspace(model, tolerance, max_iterations)
    else:
        workspace.configure(tolerance, max_iterations)
    return workspace


def workspace_for(model: Model, workspace, tolerance: float | None = None,
                  max_iterations: int = MAX_ITERATIONS) -> Workspace:
    """The workspace an evaluation at one state asked for: the caller's ``workspace`` (of
    this ``model``) or, when that is ``None``, the model's default one; either set to the
    position solve's ``tolerance`` [m, rad] and ``max_iterations``.

    Raises:
        ArgumentError: ``workspace`` is not a :class:`Workspace` of ``model``.
    """
    if workspace is None:
        return workspace_of(model, tolerance, max_iterations)
    if not isinstance(workspace, Workspace):
        raise ArgumentError("workspace", f"must be a flexmbd.Workspace of the model, got "
                                         f"{type(workspace).__name__}")
    if workspace.model is not model:
        raise ArgumentError("workspace", f"is a workspace of {workspace.model.name!r}, not "
                                         f"of {model.name!r}: make one with "
                                         f"fm.Workspace(model)")
    workspace.configure(tolerance, max_iterations)
    return workspace


class Workspace:
    """A model's workspace on the core (module docstring): the model compiled once, a
    run's laws and loads, its output arrays, the last configuration and factorisation,
    and the translation of failures into flexmbd's errors.

    Args:
        model: the mechanism.
        tolerance: Newton tolerance of the position solve [m, rad]; default ``1e-10``
            times the model size.
        max_iterations: Newton iterations of a position solve before giving up.
    """

    def __init__(self, model: Model, tolerance: float | None = None,
                 max_iterations: int = MAX_ITERATIONS):
        check_core()
        self.model = model
        length = model.characteristic_length
        self.tolerance = (RELATIVE_TOLERANCE * length if tolerance is None else
                          checks.position_tolerance(tolerance, length,
                                                    float(np.abs(model.x0).max(initial=0))))
        self.max_iterations = checks.iteration_limit(max_iterations)
        #: the model's arrays as the core has them (element laws, index maps, orderings),
        #: compiled once per model
        self.compiled, reference = _compiled(model)
        self._core = native.Core(self.compiled)  # only this class calls it
        #: scaled conditioning of D_c below which a converged position counts as singular:
        #: near a singular root Newton converges only linearly and stops about
        #: sqrt(tolerance) away from it, where D_c still looks regular. Relative to the
        #: reference configuration's conditioning where that is below 1: a long chain of
        #: beams is regular but less well conditioned than one link.
        if reference is None:
            reference = self._core.factor(np.asarray(model.x0, dtype=float))
            _kept(model)["reference"] = reference
        self.reference_conditioning = min(1.0, reference)
        self.regularity_limit = 10.0 * float(np.sqrt(
            self.tolerance / model.characteristic_length)) * self.reference_conditioning
        self.arrays: dict[str, np.ndarray] = {}
        self.integrated = False  #: whether the run integrates dynamic degrees of freedom
        #: the holder of the static saddle-point factorisation the core keeps (one at a
        #: time): a banded tangent re-factorises when another state has taken it
        self.static_owner: object | None = None
        self._core.settings(self.tolerance, self.max_iterations, self.regularity_limit,
                           self.reference_conditioning)

    def configure(self, tolerance: float | None = None,
                  max_iterations: int = MAX_ITERATIONS) -> None:
        """Set the position solve's tolerance [m, rad] (default ``1e-10`` times the model
        size) and iteration limit, for evaluations at one state."""
        length = self.model.characteristic_length
        wanted = (RELATIVE_TOLERANCE * length if tolerance is None else
                  checks.position_tolerance(tolerance, length,
                                            float(np.abs(self.model.x0).max(initial=0))))
        max_iterations = checks.iteration_limit(max_iterations)
        if (wanted, max_iterations, self.integrated) == (self.tolerance, self.max_iterations,
                                                         False):
            return
        self.tolerance, self.max_iterations, self.integrated = wanted, max_iterations, False
        self.regularity_limit = 10.0 * float(np.sqrt(
            wanted / length)) * self.reference_conditioning
        self._core.settings(self.tolerance, self.max_iterations, self.regularity_limit,
                           self.reference_conditioning)

    @cached_property
    def assembly(self) -> Assembly:
        """Model-wide arrays from the element kernels in one call each (``D_x``, the
        stress Hessian, the elastic law): :class:`~flexmbd.engine.assembly.Assembly`."""
        return Assembly(self.element_values, self.gravity_slopes, self.compiled.elements,
                        self.model.n_coordinates, self.model.n_deformations)

    # --- preparing a run ------------------------------------------------------------------
    def prepare(self, laws: list[Law], n_outputs: int, *, integrated: bool = False,
                dynamics: bool = False, forces: Forces | None = None,
                progress: Callable[[float], None] | None = None,
                columns: tuple[str, ...] | None = None) -> dict[str, np.ndarray]:
        """Hand a run's laws (one per entry of ``q``; with ``integrated`` the dynamic
        entries come from the integrator instead), loads and output arrays to the core.
        Returns the output arrays ``{name: (n_outputs, size)}`` the run fills."""
        model = self.model
        self.integrated = integrated
        # A simulation's position solves start from the extrapolated last solution and keep
        # converging quadratically through configurations where redundant but consistent
        # constraints make D_c nearly singular (a parallelogram whose bars align): the
        # dynamics carry the mechanism through, so the dead-point test of driven runs is
        # off. A real dead end still stops the run: Newton fails, or D_c is singular.
        self._core.settings(self.tolerance, self.max_iterations,
                           0.0 if integrated else self.regularity_limit,
                           self.reference_conditioning)
        nq = model.n_dof
        Kind = native.FmLawKind
        kind = np.full(nq, Kind.FM_LAW_POLYNOMIAL, dtype=np.int32)
        coef = np.zeros((nq, 3))
        python: list[int] = []
        for j, law in enumerate(laws):
            if integrated and not model.q_is_input[j]:
                kind[j] = Kind.FM_LAW_INTEGRATED
            elif isinstance(law, Polynomial):
                coef[j] = law.x0, law.v0, law.a0
            else:
                kind[j] = Kind.FM_LAW_CALLBACK
                python.append(j)
        values = np.zeros((nq, 3))

        def fill_laws(t):
            for j in python:
                values[j] = law_values(laws[j], t, model.describe_q(j))

        sizes = output_sizes(model)
        wanted = columns or tuple(OUTPUTS)
        checks.output_memory(n_outputs, output_bytes(model, wanted, integrated))
        self.arrays = {name: np.zeros((n_outputs, sizes[name])) for name in wanted}
        options: dict[str, Any] = {}
        if python:
            options.update(law_callback=fill_laws, law_values=values)
        if forces is not None and not callable(forces):
            raise ArgumentError("forces", f"must be a function forces(t, x, xdot), got "
                                          f"{forces!r}")
        if forces is not None:
            x, xd, f = np.zeros(model.n_coordinates), np.zeros(model.n_coordinates), \
                np.zeros(model.n_coordinates)

            def apply_forces(t):
                try:
                    given = forces(t, x.copy(), xd.copy())
                except FlexmbdError:
                    raise
                except Exception as error:  # the user's function: named, not lost
                    raise SimulationError(f"forces raised {type(error).__name__}: {error} "
                                          f"{at_time(t)}", t) from error
                try:
                    # one that is not finite the core reports, with its label and time
                    f[:] = load_vector(model, given, finite=False)
                except ArgumentError as error:  # what it returned, and when
                    raise SimulationError(f"{error}, returned {at_time(t)}", t) from None

            options.update(forces=apply_forces, force_x=x, force_xd=xd, force_f=f)
        if progress is not None:
            options["progress"] = progress
        self._core.prepare(kind, coef, self.arrays, n_outputs, bool(dynamics), **options)
        return self.arrays

    def start(self, laws: list[Law], t: float, dynamic: np.ndarray | None = None,
              configuration: np.ndarray | None = None) -> None:
        """Start the next run at time ``t`` [s] from ``configuration`` ``(nx,)`` when given,
        else from the configuration :meth:`continued` to ``q``: the laws' values, and the
        integrated entries ``dynamic`` when given. A start the continuation cannot reach
        is left to the run, which reports its failure."""
        if configuration is not None:
            self.reset(configuration)
            return
        q = self.law_values(laws, t)[0]
        if dynamic is not None:
            q[~np.asarray(self.model.q_is_input)] = dynamic
        try:
            self._core.reset(self.continued(q, t))
        except SimulationError:
            self._core.reset()

    def law_values(self, laws: list[Law], t: float) -> np.ndarray:
        """``(3, nq)``: the values, rates and accelerations of ``laws`` at time ``t``."""
        return np.array([law_values(law, t, self.model.describe_q(j))
                         for j, law in enumerate(laws)], dtype=float).reshape(-1, 3).T.copy()

    def integrated_state(self, laws: list[Law], t: float, y: np.ndarray,
                         guess: np.ndarray) -> dict[str, np.ndarray]:
        """:meth:`state` at time ``t`` of the integrated ``y = [q_d, qdot_d]`` with the
        prescribed entries from their ``laws`` (accelerations zero), solved from
        ``guess``."""
        q, qd, _ = self.law_values(laws, t)
        dynamic, n = ~np.asarray(self.model.q_is_input), len(y) // 2
        q[dynamic], qd[dynamic] = y[:n], y[n:]
        return self.state(q, qd, np.zeros_like(q), guess, t)

    # --- failures -------------------------------------------------------------------------
    def error(self, status: RunStatus) -> BaseException | None:
        """The exception of a run's ``status`` (``None`` when it completed): flexmbd's
        errors with the time and the coordinates and deformations involved, or the
        exception a Python callback raised."""
        code, Status = status["code"], native.FmStatus
        if code == Status.FM_OK:
            return None
        if code == Status.FM_PYTHON:
            return status["exception"] or KeyboardInterrupt()
        model, time = self.model, float(status["time"])
        time_or_none = None if np.isnan(time) else time
        if code == Status.FM_NOT_CONVERGED:
            worst = status["worst"]
            where = (model.describe_deformation(worst) if worst >= 0
                     else "a non-finite configuration")
            return ConvergenceError(
                f"position solve did not converge {at_time(time_or_none)}: residual "
                f"{status['residual']:.3g} after {status['iterations']} iterations (tolerance "
                f"{self.tolerance:.3g}), largest in {where}; the inputs may ask for a "
                f"configuration the constraints cannot reach (e.g. beyond an element's "
                f"length) or the step from the previous solution is too large",
                time_or_none, iterations=int(status["iterations"]),
                residual=float(status["residual"]))
        if code in (Status.FM_SINGULAR, Status.FM_SINGULAR_TOLERANCE, Status.FM_MASSLESS):
            x = self.configuration()
            if not np.all(np.isfinite(x)):  # not a property of the mechanism: a blow-up
                return SimulationError(self._diverged(time_or_none), time_or_none)
        if code in (Status.FM_SINGULAR, Status.FM_SINGULAR_TOLERANCE):
            what = "D_c is singular"
            if code == Status.FM_SINGULAR_TOLERANCE:
                what = (f"D_c is singular within the position tolerance (scaled smallest "
                        f"singular value {status['conditioning']:.2g} < "
                        f"{status['limit']:.2g})")
            D_x = self.assembly.deformations_and_jacobian(x)[1]
            D_c = D_x[np.ix_(model.constrained, model.dependent)]
            return SingularConfigurationError(
                singular_message(model, D_c, time_or_none, what, self.integrated), time_or_none)
        if code == Status.FM_MASSLESS:
            text, singular = massless_message(self, x, time_or_none)
            return (SingularConfigurationError if singular else SimulationError)(
                text, time_or_none)
        if code == Status.FM_NOT_FINITE:
            worst = int(status["worst"])
            what = (f"the law of {model.describe_q(worst)}" if worst >= 0 else
                    f"the applied load on {model.describe_coordinate(-2 - worst)}")
            return SimulationError(f"{what} is not finite {at_time(time_or_none)}",
                                   time_or_none)
        if code == Status.FM_STEP_FAILED:
            return SimulationError(
                f"the GeneralizedAlpha integrator failed {at_time(time_or_none)}: its Newton "
                f"iteration did not converge even with step {status['step']:.3g} s",
                time_or_none)
        if code == Status.FM_STEP_TOO_SMALL:
            return SimulationError(
                f"the GeneralizedAlpha integrator's step shrank to {status['step']:.3g} s "
                f"{at_time(time_or_none)} without meeting rtol and atol: the motion is not "
                f"smooth enough there for them (an impact, a singular configuration); loosen "
                f"them, or give a fixed step", time_or_none)
        if code == Status.FM_NO_MEMORY:
            return MemoryError(f"the core ran out of memory {at_time(time_or_none)}")
        return SimulationError(f"the core stopped with {Status(code).name} "
                               f"{at_time(time_or_none)}", time_or_none)

    @staticmethod
    def stopped_for_partition(status: RunStatus) -> bool:
        """Whether a generalized-alpha run stopped because a free rotation's calculable
        Euler parameter got small (:mod:`flexmbd.analysis.free_rotations`)."""
        return status["code"] == native.FmStatus.FM_PARTITION

    def _diverged(self, time: float | None) -> str:
        """The message of a run whose configuration stopped being finite."""
        cause = ("the applied loads or the laws are out of range, or the integrator's step "
                 "is too large for the model's fastest motion (GeneralizedAlpha: a smaller "
                 "step, or iterations=None to iterate Newton to convergence)"
                 if self.integrated else "the laws or the applied loads are out of range")
        return f"the motion diverged {at_time(time)}: the configuration is no longer " \
               f"finite; {cause}"

    # --- runs over a time grid (after prepare and start) --------------------------------------
    def kinematic_run(self, times: np.ndarray) -> RunStatus:
        """Every output time of a prepared run whose ``q`` all follow laws (kinematic
        analysis, inverse dynamics, a state of the static analysis): the core's status
        (``reached``, ``code``, ...), for :meth:`error`."""
        return self._core.kinematic_run(np.ascontiguousarray(times, dtype=float))

    def alpha_run(self, times: np.ndarray, q: np.ndarray, qd: np.ndarray,
                  end: np.ndarray, watch: np.ndarray | None, near: float,
                  options: Mapping[str, float | int]) -> RunStatus:
        """A prepared, integrated run by generalized-alpha in the core from the dynamic
        ``q``, ``qdot`` ``(nd,)``, stopping where a ``watch``-ed free rotation's partition
        is spent (its state then in ``end`` ``(2 nd,)``); the core's status and
        counters (``nfev``, ``njev``, ``nlu``, ``nsteps``, ``nrejected``)."""
        return self._core.alpha_run(
            times, q, qd, step=float(options["step"]), rho_inf=float(options["rho_inf"]),
            rtol=float(options["rtol"]), atol=float(options["atol"]),
            iterations=int(options["iterations"]), renew_every=int(options["renew_every"]),
            adaptive=bool(options["adaptive"]), max_step=float(options["max_step"]),
            near=near, watch=watch, end=end)

    def accelerations(self, t: float, y: np.ndarray, out: np.ndarray) -> None:
        """The dynamic entries of ``qddot`` into ``out`` ``(nd,)`` at time ``t`` [s] and
        state ``y = [q_d; qdot_d]`` of a prepared, integrated run."""
        self.call(self._core.accelerations, t, np.ascontiguousarray(y), out)

    def output(self, k: int, t: float, y: np.ndarray) -> None:
        """Record output ``k`` of a prepared run at time ``t`` [s] and state ``y``."""
        self.call(self._core.output, k, float(t), np.ascontiguousarray(y))

    def configuration(self) -> np.ndarray:
        """The configuration ``x`` ``(nx,)`` of the last evaluation (of the last failure)."""
        x = np.empty(self.model.n_coordinates)
        self._core.configuration(x)
        return x

    def reset(self, x: np.ndarray) -> None:
        """Start the next position solve from the configuration ``x`` ``(nx,)``."""
        self._core.reset(np.ascontiguousarray(x, dtype=float))

    @property
    def constant_loads(self) -> np.ndarray:
        """The model's constant loads and moments (XF) ``(nx,)`` [N, N m] as the core
        applies them."""
        return self.compiled.loads.f_const

    @property
    def rotation_coordinates(self) -> np.ndarray:
        """The Euler parameters ``(k, 4)`` (coordinate indices) of the spatial rotational
        nodes."""
        return self.compiled.classification.rotations.reshape(-1, 4)

    def call(self, method: Callable, *args):
        """Call a single evaluation of the core; its failure as flexmbd's error."""
        try:
            return method(*args)
        except native.CoreError as failure:
            error = self.error(failure.args[0])
            if error is None:  # a failure always has a code; this would be the core's bug
                raise
            raise error from None

    # --- single evaluations -----------------------------------------------------------------
    def positions(self, q: np.ndarray, guess: np.ndarray | None = None,
                  time: float | None = None) -> np.ndarray:
        """Solve the position problem for ``q`` (THEORY 3) from ``guess``: ``x`` ``(nx,)``.
        Without a guess, the configuration on the branch of the reference one
        (:meth:`continued`)."""
        if guess is None:
            return self.continued(q, time)
        zero = np.zeros(self.model.n_dof)
        return self.state(q, zero, zero, guess, time)["x"]

    def continued(self, q: np.ndarray, time: float | None = None) -> np.ndarray:
        """The configuration ``x`` ``(nx,)`` at ``q`` that the reference configuration turns
        into when ``q`` moves there from its reference value (``x0``'s): solved in steps
        of at most 0.1 rad of an angle or 0.1 of the model size, each from the last. A
        position problem has several solutions (a bar pointing either way along its
        line); this keeps the one the model was drawn in."""
        model = self.model
        q = np.asarray(q, dtype=float)
        start = initial_q(model)
        change = np.abs(q - start) * q_scale(model)
        steps = int(np.ceil(np.max(change, initial=0.0) / 0.1)) if np.all(
            np.isfinite(change)) else 1
        x, zero = np.asarray(model.x0, dtype=float), np.zeros(model.n_dof)
        for s in np.linspace(0.0, 1.0, min(steps, 10_000) + 1)[1:]:
            x = self.state(start + s * (q - start), zero, zero, x, time)["x"]
        return x

    def state(self, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray,
              guess: np.ndarray | None = None, time: float | None = None
              ) -> dict[str, np.ndarray]:
        """Positions, velocities and accelerations of coordinates and deformations for
        ``q, qdot, qddot`` ``(nq,)`` (THEORY 3, 4): ``{"x", "xd", "xdd", "e", "ed",
        "edd"}``, from the position solve started at ``guess`` (default ``x0``)."""
        model = self.model
        sizes = output_sizes(model)
        out = {name: np.empty(sizes[name]) for name in KINEMATIC_OUTPUTS}
        guess = np.asarray(model.x0 if guess is None else guess, dtype=float)
        vectors = [np.ascontiguousarray(v, dtype=float) for v in (q, qd, qdd)]
        self.call(self._core.state, np.nan if time is None else float(time), *vectors,
                  np.ascontiguousarray(guess), *out.values())
        return out

    def equilibrium(self, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, guess: np.ndarray,
                    loads: np.ndarray | None = None) -> dict[str, np.ndarray]:
        """Inverse dynamics at one state (THEORY 8), as a run's output at ``t = 0``: every
        column of :data:`OUTPUTS` (one row each) for ``q, qdot, qddot`` ``(nq,)`` with the
        applied ``loads`` ``(nx,)`` [N, N m] besides the model's, the positions solved
        from ``guess``. One core call on this workspace (the static Newton iterations)."""
        model = self.model
        if self.integrated:  # a simulation's settings (no dead-point test) do not apply
            self.configure(self.tolerance, self.max_iterations)
        applied = np.zeros(model.n_coordinates) if loads is None else \
            load_vector(model, loads, "loads")
        sizes = output_sizes(model)
        out = {name: np.empty((1, size)) for name, size in sizes.items()}
        vectors = [np.ascontiguousarray(v, dtype=float) for v in (q, qd, qdd, guess)]
        self.call(self._core.equilibrium, 0.0, *vectors, applied, out)
        return out

    def inertia_slopes(self, x: np.ndarray, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray,
                       step: np.ndarray, rates: bool = False) -> np.ndarray:
        """Central differences ``(nx + ne, nq)`` of the inertia forces ``M xddot + h`` [N,
        N m] stacked on the deformation rates ``edot`` along each entry ``j`` of ``q``
        (of ``qdot`` with ``rates``), ``step[j]`` either side, at the state ``(q, qdot,
        qddot)`` with positions solved from ``x``: column ``j`` is the slope along
        ``q_j``. All states in one core call."""
        model = self.model
        out = np.empty((model.n_coordinates + model.n_deformations, model.n_dof))
        vectors = [np.ascontiguousarray(v, dtype=float) for v in (x, q, qd, qdd, step)]
        self.call(self._core.inertia_slopes, *vectors, bool(rates), out)
        return out

    def transfer(self, x: np.ndarray, D_x: np.ndarray | None = None) -> np.ndarray:
        """``F_q = dx/dq`` ``(nx, nq)`` at the configuration ``x`` ``(nx,)`` from one
        factorisation of ``D_c``: the rows of ``x(c)`` solve ``D_c F_c = [0; I_e(m)] -
        D_x[rows, x(m)]`` (THEORY 4); ``D_x`` ``(ne, nx)`` when the caller has it. An entry
        has the unit of its coordinate per unit of its entry of ``q``.

        Raises:
            SingularConfigurationError: ``D_c`` is singular at ``x``.
        """
        model = self.model
        nxm = len(model.independent_coordinates)
        rows, dependent = np.asarray(model.constrained), np.asarray(model.dependent)
        F_q = np.zeros((model.n_coordinates, model.n_dof))
        F_q[model.independent_coordinates, np.arange(nxm)] = 1.0
        if len(rows):
            if D_x is None:
                D_x = self.assembly.deformations_and_jacobian(x)[1]
            rhs = np.zeros((len(rows), model.n_dof))
            rhs[:, :nxm] = -D_x[np.ix_(rows, model.independent_coordinates)]
            own = np.arange(len(model.independent_deformations))  # D_c's rows: e(o), e(m)
            rhs[len(model.rigid) + own, nxm + own] = 1.0
            if not self.factor(x) > 0.0:
                D_c = D_x[np.ix_(rows, dependent)]
                raise SingularConfigurationError(singular_message(
                    model, D_c, None, "D_c is singular"))
            F_q[dependent] = self.solve(rhs)
        return F_q

    def factor(self, x: np.ndarray) -> float:
        """Factorise ``D_c`` at ``x``; returns its scaled conditioning, 0 when singular (a
        zero pivot, or the core's singular threshold)."""
        return self._core.factor(np.ascontiguousarray(x, dtype=float))

    def solve(self, rhs: np.ndarray, transposed: bool = False) -> np.ndarray:
        """``D_c^-1 rhs`` (or ``D_c^-T rhs``) with the last factorisation, for ``rhs`` of
        shape ``(nr,)`` or ``(nr, k)``."""
        rhs = np.asarray(rhs, dtype=float)
        columns = np.array(rhs.reshape(rhs.shape[0], -1).T, order="C")  # solved in place
        self._core.solve(columns, transposed)
        return columns.T.reshape(rhs.shape)

    def mass(self, x: np.ndarray, xd: np.ndarray | None = None, out: np.ndarray | None = None
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The mass matrix ``M`` ``(nx, nx)`` [kg, kg m, kg m^2] (written into ``out``, a
        C-contiguous array, when given), the velocity-dependent inertia ``h`` ``(nx,)``
        (inertia force ``M xddot + h``) and the constant loads and gravity ``f`` ``(nx,)``
        [N, N m] at ``(x, xd)`` (THEORY 5)."""
        nx = self.model.n_coordinates
        M = np.empty((nx, nx)) if out is None else out
        h, f = np.empty(nx), np.empty(nx)
        xd = np.zeros(nx) if xd is None else xd
        self._core.mass_matrix(np.ascontiguousarray(x, dtype=float),
                              np.ascontiguousarray(xd, dtype=float), M, h, f)
        return M, h, f


    def bands(self) -> dict[str, int]:
        """Sizes and bands of the two square systems the core factorises, ``D_c`` and the
        saddle-point matrix: ``dc_n``, ``dc_kl``, ``dc_ku``, ``saddle_n``, ``saddle_kl``,
        ``saddle_ku``."""
        return self._core.bands()

    def element_values(self, name: str, x: np.ndarray, out: np.ndarray) -> None:
        """The kernel ``"deform_jac"`` or ``"hessian"`` of every element at ``x`` ``(nx,)``,
        element after element, into ``out`` (sized by the elements)."""
        self._core.element_values(name, np.ascontiguousarray(x, dtype=float), out)

    def gravity_slopes(self, x: np.ndarray, out: np.ndarray) -> None:
        """Per element, ``m d(int N^T g)/dc`` ``(nc, nc)`` at ``x`` ``(nx,)`` where its
        gravity turns with it, else zeros, element after element, into ``out``."""
        self._core.gravity_slopes(np.ascontiguousarray(x, dtype=float), out)

    def mass_regular(self, x: np.ndarray) -> bool:
        """Whether every motion the constraints allow at ``x`` ``(nx,)`` moves mass (the
        saddle-point matrix of the mass and the constraints factorises)."""
        return self._core.mass_regular(np.ascontiguousarray(x, dtype=float))

    def static_residual(self, x: np.ndarray, q: np.ndarray, mu: np.ndarray,
                        loads: np.ndarray) -> np.ndarray:
        """The static equilibrium in all coordinates at ``x`` ``(nx,)`` with the constraint
        stresses ``mu`` ``(nmult,)`` [N, N m] under the applied ``loads`` ``(nx,)``, ``q``
        ``(nq,)`` holding the inputs' targets: its residual ``(nfree + nmult,)``; the
        factorised tangent is kept for :meth:`static_solve`.

        Raises:
            CoreError: the tangent is singular or not finite.
        """
        residual = np.empty(self.compiled.sizes.ns)
        x, q, mu, loads = (np.ascontiguousarray(v, dtype=float) for v in (x, q, mu, loads))
        self._core.static_saddle(x, q, mu, loads, residual)
        return residual

    def static_solve(self, rows: np.ndarray, transposed: bool = False) -> None:
        """The kept static tangent's solutions of the rows of ``rows`` ``(k, nfree +
        nmult)``, in place; with its transpose when ``transposed`` (adjoint solves: a
        global moment's load stiffness makes the tangent unsymmetric)."""
        self._core.static_solve(rows, transposed)

    def free_mass_times(self, rows: np.ndarray, out: np.ndarray) -> None:
        """``M v`` over the free coordinates for the rows ``v`` of ``rows`` ``(k, nfree)``
        into ``out``, at the configuration of the kept static tangent."""
        self._core.free_mass_times(rows, out)

    def masses(self, x: np.ndarray) -> np.ndarray:
        """The mass matrices ``(nt, nx, nx)`` at the configurations ``x`` ``(nt, nx)``,
        finite and checked by the caller, in one call of the core."""
        nx = self.model.n_coordinates
        x = np.ascontiguousarray(x, dtype=float).reshape(-1, nx)
        batch = np.empty((len(x), nx, nx))
        self._core.masses(x, batch)
        return batch
