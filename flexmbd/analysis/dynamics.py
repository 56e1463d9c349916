"""Dynamics (THEORY sections 5-8): forward simulation, inverse dynamics, the mass matrix.

With ``xdot = F_q qdot`` and ``edot = E_q qdot`` the virtual power of inertia,
applied and elastic forces reduces to

    Mbar qddot = F_q^T (f - h - M (F_qq qdot) qdot) - E_q^T sigma,   Mbar = F_q^T M F_q.

``q`` splits into dynamic entries and prescribed (rheonomic) ones. The compiled
core solves these equations without forming ``F_q`` or ``Mbar``: the accelerations
from the saddle-point system over the free coordinates and the multipliers of the
rigid and input deformations, the constraint stresses and reactions from the nodal
equilibrium of the dependent coordinates (THEORY 8), and an implicit integrator's
Newton matrix ``Mbar + c_q K + c_v C`` as the same saddle-point system with the
element stiffness and damping added to the mass.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from typing import Literal

import numpy as np

from .. import checks
from ..engine import (
    MAX_ITERATIONS,
    Forces,
    Workspace,
    initial_q,
    q_index,
    resolve_laws,
    workspace_of,
)
from ..errors import (
    AccuracyWarning,
    ArgumentError,
    ModelError,
    SimulationError,
    SingularConfigurationError,
    StiffnessError,
    UnstressedError,
)
from ..model import Model
from ..motion import Law
from ..progress import progress_bar
from ..results import SimulationResult, check_on_failure, check_times, conclude, first_rows
from .eigen import EigenError
from .free_rotations import (
    dynamic_state,
    partition_spent,
    relabelled,
    repartitioned,
    watched_positions,
)
from .integrate import (
    ATOL,
    DEFAULT_METHOD,
    EXPLICIT,
    RTOL,
    AlphaOptions,
    Method,
    ScipyOptions,
    check_method,
    check_options,
    integrate,
)
from .kinematics import coordinates, first_order_transfer
from .modes import vibration_modes
from .watch import StepsCollapsedError

#: generalized-alpha's position solves take D_x within this share of the model size: its
#: residual need not be exact below its truncation error, and this saves chord steps
GA_JACOBIAN_POINT = 1e-6

__all__ = ["Forces", "initial_state", "inverse_dynamics", "mass_matrix",
           "reduced_mass_matrix", "simulate"]


def mass_matrix(model: Model, x: np.ndarray) -> np.ndarray:
    """The system mass matrix ``M(x)`` [kg, kg m, kg m^2] (THEORY 5): the inertia force is
    ``M xddot + h``. ``x`` is one configuration ``(nx,)`` (gives ``(nx, nx)``) or a batch
    ``(nt, nx)`` (gives ``(nt, nx, nx)``)."""
    try:
        x = np.asarray(x, dtype=float)
    except (TypeError, ValueError):
        raise ArgumentError("x", "must be an array of coordinates") from None
    engine = workspace_of(model)
    if x.ndim == 1:
        return engine.mass(coordinates(model, x))[0]
    if x.ndim != 2 or x.shape[1] != model.n_coordinates or not np.all(np.isfinite(x)):
        raise ArgumentError("x", f"must be finite, of shape ({model.n_coordinates},) or "
                                 f"(nt, {model.n_coordinates}), got shape {x.shape}")
    checks.output_memory(len(x), 8 * model.n_coordinates**2, "x")
    return engine.masses(x)


def reduced_mass_matrix(model: Model, x: np.ndarray) -> np.ndarray:
    """``Mbar = F_q^T M F_q`` ``(nq, nq)`` [kg, kg m, kg m^2] at the configuration ``x``
    ``(nx,)`` [m, rad] (THEORY 7): the mass
    matrix of the generalized coordinates ``q = [x(m); e(m)]``."""
    x = coordinates(model, x)
    F_q = first_order_transfer(model, x)
    return F_q.T @ mass_matrix(model, x) @ F_q


def _check_input_laws(model: Model, inputs: Mapping[str, Law] | None) -> None:
    """Refuse a law given to a simulation for a dynamic degree of freedom: the integrator
    moves it, so the law would not be used."""
    if not isinstance(inputs, Mapping):
        return          # resolve_laws says what inputs must be
    for label in inputs:
        j = q_index(model, label, "inputs")
        if not model.q_is_input[j]:
            raise ArgumentError("inputs", f"{label} is a dynamic degree of freedom, which the "
                                          f"simulation integrates, so a law for it would not "
                                          f"be used: give its start as initial={{{label!r}: "
                                          f"(value, rate)}}, or make it an input in the model "
                                          f"(input_coordinate / input_deformation) to "
                                          f"prescribe it")


def initial_state(model: Model, initial: Mapping[str, tuple[float, float]] | None
                  ) -> tuple[np.ndarray, np.ndarray]:
    """``q_d(0), qdot_d(0)`` of the dynamic entries: the initial configuration at rest
    unless ``initial`` says otherwise (``{"e2.2": (value, rate)}`` [m or rad, per s])."""
    if initial is not None and not isinstance(initial, Mapping):
        raise ArgumentError("initial", f"must map labels to (value, rate), e.g. {{'e2.2': "
                                       f"(0.01, 0.0)}}, got {type(initial).__name__}")
    d = ~model.q_is_input
    q0, qd0 = initial_q(model), np.zeros(model.n_dof)
    for label, pair in (initial or {}).items():
        j = q_index(model, label, "initial")
        if not d[j]:
            raise ArgumentError("initial", f"{label} is prescribed, not dynamic: its law "
                                           f"sets its value (inputs={{{label!r}: law}} "
                                           f"changes it)")
        try:
            q0[j], qd0[j] = (float(v) for v in pair)
        except (TypeError, ValueError):
            raise ArgumentError("initial", f"{label} takes (value, rate) [m or rad, per s], "
                                           f"got {pair!r}") from None
        if not (np.isfinite(q0[j]) and np.isfinite(qd0[j])):
            raise ArgumentError("initial", f"{label}: {pair!r} is not finite")
    return q0[d], qd0[d]


#: the steps per output beyond which a failure of an explicit method is reported as the
#: likely result of stiffness
STIFF_STEPS = 10

#: the columns of :func:`simulate`'s ``outputs`` settings
RECORDED = {"positions": ("x", "e", "q"), "velocities": ("x", "e", "q", "xd", "ed", "qd"),
            "all": None}


def simulate(
    model: Model,
    times,
    *,
    inputs: Mapping[str, Law] | None = None,
    forces: Forces | None = None,
    initial: Mapping[str, tuple[float, float]] | None = None,
    method: str = DEFAULT_METHOD,
    rtol: float = RTOL,
    atol: float = ATOL,
    tolerance: float | None = None,
    max_iterations: int = MAX_ITERATIONS,
    with_reactions: bool = False,
    outputs: Literal["all", "velocities", "positions"] = "all",
    on_failure: Literal["raise", "return"] = "raise",
    progress: bool | None = None,
    **options,
) -> SimulationResult:
    """Forward simulation of the dynamic degrees of freedom.

    Args:
        model: a model with dynamic degrees of freedom and mass.
        times: output times [s], increasing; the run starts at ``times[0]``.
        inputs: laws of prescribed entries by label, overriding the model's.
        forces: applied loads ``forces(t, x, xdot)`` -> array ``(nx,)`` or
            ``{"x2.1": torque}`` [N, N m], on top of the model's constant loads.
        initial: ``{label: (value, rate)}`` for dynamic entries of ``q``; the others
            start at rest in the initial configuration.
        method: ``"GeneralizedAlpha"`` (default: implicit, in the compiled core, its
            steps controlled by the local error, stepping over the stiff modes of
            flexible bodies with numerical damping), or SciPy's error-controlled
            ``"RK45"`` (as MATLAB's ode45), ``"DOP853"``, ``"RK23"`` (explicit: they must
            resolve every mode), ``"Radau"``, ``"BDF"``, ``"LSODA"``.
        rtol, atol: the integrator's tolerances, relative and absolute [m, rad]: each
            step's local error estimate, in the root mean square of its entries weighted
            by ``atol + rtol |y|``, stays below 1, as in ``solve_ivp``. SciPy's methods
            estimate the error of ``y = [q_d, qdot_d]``; GeneralizedAlpha that of the
            positions ``q_d`` (its velocities follow them to the same order) and iterates
            Newton to a tenth of it. With fixed GeneralizedAlpha steps they are the
            Newton iteration's only.
        tolerance: Newton tolerance of the position solve [m, rad].
        max_iterations: Newton iterations of a position solve before giving up.
        with_reactions: keep the loads of supports and drives (``f<node>.<k>`` columns);
            off by default, as they cost a solve at each output (on in
            :func:`inverse_dynamics`, whose purpose they are).
        outputs: what each output time records: ``"all"`` (default: positions, rates,
            accelerations, stresses, driving loads), ``"velocities"`` (``x, e, q`` and
            their rates) or ``"positions"`` (``x, e, q``). Each output solves for these
            alone: positions skip the rates, the accelerations and the factorisations
            of each output, the larger part of a run that outputs every step.
        on_failure: ``"raise"`` the :class:`SimulationError` (with the output so far
            as ``error.partial_result``) or ``"return"`` it with ``success=False``.
        progress: progress bar (default: long interactive runs only).
        **options: the method's own (:data:`flexmbd.analysis.integrate.METHODS`); a
            method refuses, by name, an option it does not take.

            SciPy's methods: ``max_step`` [s], the largest step, and ``first_step`` [s].

            GeneralizedAlpha: by default its steps follow the local error estimate of
            ``q_d`` (Zienkiewicz and Xie's, ``(beta + delta/2 - 1/6) h^2 (a_new - a)``),
            the first ``first_step`` [s] (default: chosen from the initial state), at most
            ``max_step`` [s]; outputs between steps are interpolated (cubic Hermite) and
            then evaluated. ``step`` [s] gives fixed steps instead (``max_step`` bounds it
            too): a step that resolves the lowest vibration period (in the reference
            configuration) in fewer than :data:`STEPS_PER_PERIOD` steps, or lets it lag by
            more than :data:`LAG` of a period over the run, is warned about
            (:class:`~flexmbd.AccuracyWarning`), naming the step that would.
            ``iterations``, its Newton corrections per step: ``None`` (default) iterates
            to ``rtol``/``atol`` and, with ``rho_inf = 1``, keeps the energy of a
            conservative system (1e-5 of its kinetic energy over 100 periods of a flexible
            rotor); ``1`` is the linearly implicit method, one evaluation and one Newton
            correction per step, as accurate for a driven slow motion at about half the
            cost, but it needs numerical damping (``rho_inf <= 0.8``) to stay stable and
            does not keep the energy: check it with an energy balance. ``renew_every``:
            with ``iterations`` and ``step`` set, steps between renewals of the Newton
            matrix (default 1: every step). ``rho_inf``: the spectral radius at infinite
            frequency, 0 (strongest damping of unresolved modes) to 1 (none, energy
            kept); default :data:`ADAPTIVE_RHO_INF` (0.8) with error-controlled steps, 1
            with fixed ones when Newton iterates, 0.8 with ``iterations`` set. Damping
            dissipates the energy of modes the step does not resolve (6e-4 of a flexible
            rotor's over 100 periods of its first mode at 40 steps per period, rho_inf =
            0.8).

    Returns:
        :class:`~flexmbd.results.SimulationResult` with ``stats`` of the integrator.

    Examples:
        A rod pendulum released at 0.1 rad swings back through the bottom in about a
        quarter of its 1.64 s period:

        >>> import numpy as np
        >>> import flexmbd as fm
        >>> pendulum = (fm.ModelBuilder("pendulum").add_node(1, 0, 0).add_node(3, 0, -1)
        ...             .add_rigid_beam(1, 1, 2, 3).set_mass(1, 1.0).fix(1)
        ...             .dynamic_coordinate(2).set_gravity(0, -9.81).build())
        >>> run = fm.simulate(pendulum, np.linspace(0.0, 1.0, 11), initial={"x2.1": (0.1, 0.0)})
        >>> print(f"{run['x2.1'][-1]:.4f} rad at t = {run.t[-1]:g} s")
        -0.0770 rad at t = 1 s
    """
    times = check_times(times)
    if len(times) < 2:
        raise ArgumentError("times", "a simulation needs at least two times (a start and an "
                                     "end)")
    check_on_failure(on_failure)
    if not np.any(~model.q_is_input):
        raise ModelError("the model has no dynamic degree of freedom to simulate; use "
                         "kinematic_analysis or inverse_dynamics for prescribed motion")
    if not model.has_mass:
        raise ModelError("the model has no mass: give elements set_mass() or nodes "
                         "add_point_mass() before simulating")
    spec = check_method(method)
    options = check_options(spec, options)
    if not isinstance(outputs, str) or outputs not in RECORDED:
        raise ArgumentError("outputs", f"must be one of {', '.join(map(repr, RECORDED))}, "
                                       f"not {outputs!r}")
    if checks.flag(with_reactions, "with_reactions") and outputs != "all":
        raise ArgumentError("with_reactions", "needs outputs='all' (reactions come with the "
                                              "accelerations)")
    rtol, atol = checks.integrator_tolerances(rtol, atol, model.characteristic_length)
    span = float(times[-1] - times[0])
    settings: AlphaOptions | ScipyOptions
    if spec.in_core:
        settings = alpha = _alpha_options(rtol, atol, **options)
        if alpha.adaptive:
            checks.step_count(span, alpha.max_step, "max_step")
        else:
            checks.step_count(span, alpha.step, "step")
            check_resolution(model, alpha.step, span)
        work = round(span / alpha.step) if not alpha.adaptive else len(times)
    else:
        settings = ScipyOptions(rtol, atol, **options)
        checks.step_count(span, settings.max_step, "max_step")
        work = len(times)
    q0, qd0 = initial_state(model, initial)
    _check_input_laws(model, inputs)
    with progress_bar(times, f"simulating ({method})", progress, work) as advance:
        run = _Run(model, inputs, forces, (tolerance, max_iterations), RECORDED[outputs],
                   spec, settings, advance)
        arrays, done, error, stats = run.through(times, q0, qd0)
    if not with_reactions:
        arrays.pop("reactions", None)
    result = SimulationResult(model, times[:done], **first_rows(arrays, done),
                              applied_forces=forces)
    result.stats = {**stats, "method": method, "rtol": rtol, "atol": atol}
    return conclude(result, error, on_failure,
                    f"completed {len(times)} points to t = {times[-1]:.6g} s "
                    f"({stats['nsteps']} steps, {stats['nfev']} evaluations)")


#: fixed generalized-alpha steps per period of the lowest vibration mode below which a run
#: is warned about: at 20, with rho_inf = 1, each period lengthens by 0.8 %, and damping
#: adds to that for rho_inf < 1
STEPS_PER_PERIOD = 20
#: the phase lag of the lowest vibration mode over a run [periods] beyond which fixed steps
#: are warned about: each period lengthens by about (omega h)^2 / 12, so a hundred periods
#: at 20 steps each lose most of one
LAG = 0.1


def resolving_step(period: float, span: float) -> float:
    """The largest fixed step [s] that takes :data:`STEPS_PER_PERIOD` steps per ``period``
    [s] and lags by at most :data:`LAG` of a period over ``span`` [s]."""
    periods = max(span / period, 1.0)
    return min(period / STEPS_PER_PERIOD, period * np.sqrt(12 * LAG / periods) / (2 * np.pi))


def check_resolution(model: Model, step: float, span: float) -> None:
    """Warn (:class:`AccuracyWarning`) when fixed steps of ``step`` [s] over ``span`` [s]
    resolve the lowest vibration period of ``model`` (in its reference configuration)
    too coarsely (:func:`resolving_step`), naming the step that would. A model whose modes
    cannot be told there (a singular configuration, a mode without stiffness) is not
    checked."""
    try:
        frequencies = vibration_modes(model, 1).frequencies
    except (SingularConfigurationError, UnstressedError, EigenError):
        return
    frequencies = frequencies[np.isfinite(frequencies) & (frequencies > 0)]
    if not len(frequencies):
        return
    period = 1.0 / float(frequencies[0])
    enough = resolving_step(period, span)
    if step <= enough * (1 + 1e-9):
        return
    phase = 2 * np.pi * step / period     # per step [rad]; squared, a huge step overflows
    lag = span / period * phase**2 / 12 if phase < 1e100 else float("inf")
    warnings.warn(
        f"GeneralizedAlpha's fixed step {step:.3g} s resolves the lowest vibration mode "
        f"({frequencies[0]:.4g} Hz, a period of {period:.3g} s) in {period / step:.3g} "
        f"steps: over the run's {span / period:.3g} periods it lags by about {lag:.2g} of "
        f"one (and fades for rho_inf < 1); give step <= {enough:.3g} s, or no step, for "
        f"steps controlled by rtol and atol", AccuracyWarning, stacklevel=3)


#: the largest rho_inf at which a fixed number of Newton corrections per step is stable: the
#: error such a step leaves is quadratic in the change of acceleration, which unresolved
#: modes keep large unless numerical damping takes their amplitude (a conservative
#: flexible pendulum gains or loses most of its energy over a hundred swings at 0.9)
FIXED_ITERATIONS_RHO_INF = 0.8


def _alpha_options(rtol: float, atol: float, *, step: float | None = None,
                   rho_inf: float | None = None, iterations: int | None = None,
                   renew_every: int = 1, max_step: float = np.inf,
                   first_step: float | None = None) -> AlphaOptions:
    """GeneralizedAlpha's settings: fixed steps of ``step`` [s] (bounded by ``max_step``)
    when it is given, else steps controlled by the local error to ``rtol``, ``atol``,
    starting at ``first_step`` (default: chosen from the initial state), at most
    ``max_step``."""
    if step is not None and not checks.real(step, "step") > 0:
        raise ArgumentError("step", f"must be positive, got {step!r}")
    bounds = ScipyOptions(max_step=max_step, first_step=first_step)  # checked as SciPy's
    adaptive = step is None
    if not adaptive and first_step is not None:
        raise ArgumentError("first_step", "applies to error-controlled steps; with a fixed "
                                          "step every step is `step`")
    if adaptive and checks.whole(renew_every, "renew_every", 1, checks.LARGEST_STEPS) != 1:
        raise ArgumentError("renew_every", "applies to fixed steps (give step=...); "
                                           "error-controlled steps renew the Newton matrix "
                                           "when their size changes")
    first = (first_step or 0.0) if adaptive else step  # 0: the core chooses the first step
    return AlphaOptions(min(float(first), float(bounds.max_step)) if first else 0.0,
                        _rho_inf(rho_inf, iterations, adaptive), rtol, atol, iterations,
                        renew_every, adaptive, float(bounds.max_step))


#: generalized-alpha's default spectral radius at infinite frequency with error-controlled
#: steps: enough numerical damping to take out, in a few steps, the stiff modes that the
#: steps do not resolve (else their undamped oscillation would hold the step), little
#: enough to keep the resolved ones
ADAPTIVE_RHO_INF = 0.8


def _rho_inf(rho_inf: float | None, iterations: int | None, adaptive: bool) -> float:
    """GeneralizedAlpha's spectral radius: by default 1 (no numerical damping: energy kept)
    when Newton iterates with fixed steps, 0.8 with a fixed number of corrections, which
    needs damping, and :data:`ADAPTIVE_RHO_INF` with error-controlled steps."""
    if rho_inf is None:
        if iterations is not None:
            return FIXED_ITERATIONS_RHO_INF
        return ADAPTIVE_RHO_INF if adaptive else 1.0
    rho_inf = checks.real(rho_inf, "rho_inf")
    if iterations is not None and rho_inf > FIXED_ITERATIONS_RHO_INF:
        raise ArgumentError("rho_inf", f"{rho_inf:g} with iterations={iterations}: a fixed "
                            f"number of Newton corrections is unstable without numerical "
                            f"damping (a conservative system gains or loses most of its "
                            f"energy); use rho_inf <= {FIXED_ITERATIONS_RHO_INF:g}, or "
                            f"iterations=None (Newton to convergence) to keep the energy")
    return rho_inf


class _Run:
    """A simulation through its segments. A free rotation whose calculable Euler parameter
    gets small ends a segment; the next continues from the same state with another
    parameter calculable (:mod:`flexmbd.analysis.free_rotations`). Outputs are in the labels of
    the model the user gave."""

    def __init__(self, model: Model, inputs, forces, solve: tuple[float | None, int], columns,
                 method: Method, settings: AlphaOptions | ScipyOptions, advance):
        #: the position solve's tolerance [m, rad] and iteration limit
        self.model, self.inputs, self.forces, self.solve = model, inputs, forces, solve
        self.columns, self.method, self.settings = columns, method, settings
        self.advance = advance
        self.laws = resolve_laws(model, inputs)  # bad inputs are reported before any work

    def through(self, times: np.ndarray, q0: np.ndarray, qd0: np.ndarray):
        """Integrate from ``(q0, qd0)`` at ``times[0]``: the output arrays, the outputs
        reached, the error that ended the run (or ``None``) and the integrator's counters."""
        segment, y, start, k = self.model, np.concatenate([q0, qd0]), None, 0
        t_end = times[0]  # where the last segment ended
        pieces, stats = [], dict.fromkeys(("nfev", "njev", "nlu", "nsteps"), 0)
        if self.model.free_rotations:
            stats["repartitions"] = 0
        while True:
            # a segment after the first starts at the time it took over; that row is the
            # last segment's last state again and is dropped
            seg_times = times[k:] if start is None else np.concatenate([[t_end], times[k:]])
            engine = Workspace(segment, *self.solve)
            laws = self.laws if segment is self.model else resolve_laws(segment, self.inputs)
            arrays = engine.prepare(laws, len(seg_times), integrated=True, dynamics=True,
                                    forces=self.forces, progress=self.advance,
                                    columns=self.columns)
            engine.start(laws, seg_times[0], y[:len(y) // 2], configuration=start)
            done, error, counts, end = self._segment(engine, laws, seg_times, y,
                                                     watched_positions(segment), start)
            for name in counts:
                stats[name] = stats.get(name, 0) + counts[name]
            skip = 0 if start is None else 1
            pieces.append(relabelled({name: a[skip:done] for name, a in arrays.items()},
                                     segment, self.model))
            k += max(done - skip, 0)
            if error is not None or end is None:
                break
            t_end, y_end = end
            try:
                state = engine.integrated_state(laws, t_end, y_end, engine.configuration())
            except SimulationError as failure:
                error = failure
                break
            segment = repartitioned(segment, state["x"])
            y, start = dynamic_state(segment, state), state["x"]
            stats["repartitions"] += 1
        if len(pieces) == 1:  # no copy of outputs that may fill half the memory
            return pieces[0], k, error, stats
        arrays = {name: np.concatenate([piece[name] for piece in pieces])
                  for name in pieces[0]}
        return arrays, k, error, stats

    def _segment(self, engine: Workspace, laws, times, y, watched, start):
        """One integration on ``engine``'s partition from the configuration ``start``
        (``None``: the model's own): outputs reached, error, counters, and ``(t, y)``
        where a free rotation's partition was spent (else ``None``)."""
        n = len(y) // 2
        if isinstance(self.settings, AlphaOptions):
            end = np.empty(2 * n)
            status = engine.alpha_run(
                times, y[:n], y[n:], end, watched.ravel() if len(watched) else None,
                GA_JACOBIAN_POINT * engine.model.characteristic_length,
                self.settings.core_arguments())
            counts = {name: int(status[name])
                      for name in ("nfev", "njev", "nlu", "nsteps", "nrejected")}
            if engine.stopped_for_partition(status):
                return status["reached"], None, counts, (float(status["time"]), end)
            return status["reached"], engine.error(status), counts, None
        return _scipy_run(engine, laws, times, y, self.method.name, self.settings,
                          advance=self.advance, watched=watched, start=start)


def _scipy_run(engine: Workspace, laws, times, y0, method: str, settings: ScipyOptions, *,
               advance, watched, start=None):
    """A scipy integrator over the core's accelerations; each output evaluated as soon as
    it is reached, from the solution of the evaluation before it. It stops where a
    ``watched`` free rotation's partition is spent. A rejected trial step restarts the
    position solves from ``start`` when given (a re-partitioned segment's first
    configuration: the model's reference may be singular in its partition)."""
    n = len(y0) // 2
    accelerations = np.empty(n)

    def fun(t, y):
        engine.accelerations(t, y, accelerations)
        return np.concatenate([y[n:], accelerations])

    def restart(t, y):  # after a rejected trial step: continue from the state it left
        engine.start(laws, t, y[:n], configuration=start)

    def spent(t, y):
        return partition_spent(watched, y[:n])

    scipy_options = {"max_step": settings.max_step}
    if settings.first_step is not None:
        scipy_options["first_step"] = settings.first_step
    run = integrate(fun, y0, times, method=method, rtol=settings.rtol, atol=settings.atol,
                    progress=advance or False, on_output=engine.output, on_reject=restart,
                    stop=spent if len(watched) else None, **scipy_options)
    error = run.error
    if error is None and not run.success:
        error = SimulationError(run.message, float(run.t[-1]) if len(run.t) else None)
    if isinstance(error, SimulationError) and \
            not isinstance(error, (StepsCollapsedError, StiffnessError)) and \
            method in EXPLICIT and run.stats["nsteps"] > STIFF_STEPS * max(len(run.t), 1):
        error.args = (f"{error.args[0]}; {method} took {run.stats['nsteps']} steps for "
                      f"{len(run.t)} outputs: the model is stiff for an explicit method "
                      f"(fast modes such as flexible elongations), try "
                      f"method='GeneralizedAlpha' (flexmbd run --method GeneralizedAlpha)",)
    counts = {name: run.stats[name] for name in ("nfev", "njev", "nlu", "nsteps")}
    return len(run.t), error, counts, run.end if run.stopped else None


@checks.keyword_only("inputs")
def inverse_dynamics(
    model: Model,
    times,
    *,
    inputs: Mapping[str, Law] | None = None,
    forces: Forces | None = None,
    tolerance: float | None = None,
    max_iterations: int = MAX_ITERATIONS,
    with_reactions: bool = True,
    on_failure: Literal["raise", "return"] = "raise",
    progress: bool | None = None,
) -> SimulationResult:
    """Driving forces, constraint stresses and support reactions along a prescribed motion.

    Every entry of ``q`` follows a law: the model's input laws, overridden by
    ``inputs``; dynamic entries without a law are held at their initial value
    (their ``driving`` column is then the load that holds them).

    Args:
        model: a model with mass (elements or point masses).
        times: increasing output times [s], shape ``(nt,)``.
        inputs: laws by label (``{"x2.1": Polynomial(0, 150)}``).
        forces: applied loads ``forces(t, x, xdot)`` [N, N m] as in :func:`simulate`.
        tolerance: Newton tolerance of the position solve [m, rad].
        max_iterations: Newton iterations of a position solve before giving up.
        with_reactions: keep the loads of supports and drives (THEORY 8); default on.
        on_failure: ``"raise"`` (with ``error.partial_result``) or ``"return"``.
        progress: progress bar (default: long interactive runs only).

    Returns:
        :class:`~flexmbd.results.SimulationResult` whose ``driving`` holds
        ``tau = Mbar qddot - g`` per entry of ``q`` and ``reactions`` the loads on
        fixed and input coordinates (columns ``f<node>.<k>``).
    """
    times = check_times(times)
    check_on_failure(on_failure)
    if not model.has_mass:
        raise ModelError("the model has no mass: give elements set_mass() or nodes "
                         "add_point_mass() before inverse dynamics")
    checks.flag(with_reactions, "with_reactions")
    laws = resolve_laws(model, inputs)
    engine = Workspace(model, tolerance, max_iterations)
    with progress_bar(times, "inverse dynamics", progress) as advance:
        arrays = engine.prepare(laws, len(times), dynamics=True, forces=forces,
                                progress=advance)
        engine.start(laws, times[0])
        status = engine.kinematic_run(times)
    if not with_reactions:
        arrays.pop("reactions")
    done = status["reached"]
    result = SimulationResult(model, times[:done], **first_rows(arrays, done),
                              applied_forces=forces)
    return conclude(result, engine.error(status), on_failure,
                    f"completed {len(times)} points from t = {times[0]:.6g} s to "
                    f"{times[-1]:.6g} s")
