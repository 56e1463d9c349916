"""Runs of a SPACAR input file the way ``spacar(mode, file)`` runs it, with the result
files it writes (``flexmbd spacar MODE FILE``).

=====  =====================================================  ==========================
mode   what                                                   files
=====  =====================================================  ==========================
0      the input checked: kinematics at the initial            ``.sbd`` (one step, BIGD)
       configuration; also when the constraints do not
       determine the coordinates (then as drawn, and the
       run says what is wrong)
1      the motion over TIMESTEP: forward dynamics, or          ``.sbd``
       kinematics when every degree of freedom is prescribed
2      inverse dynamics over TIMESTEP                          ``.sbd``
3, 4   linearization along the path stored in the file's       ``.sbd``, ``.sbm``, ``.ltv``
       ``.sbd`` by an earlier run (its states and loads
       ``FX``), at the accelerations of the free motion of
       the model read now
7      static equilibrium at ITERSTEP's load steps             ``.sbd``
10     as 7, with the linearized equations of every step       ``.sbd``, ``.sbm``
9      as 10, with the state space of the third block's        ``.sbd``, ``.sbm``, ``.ltv``
       inputs and outputs at every step
=====  =====================================================  ==========================

A negative mode runs as the positive one (SPACAR's negative modes only draw nothing).
SPACAR makes no difference between modes 3 and 4 that flexmbd models; both run as 3.
"""

from __future__ import annotations

import dataclasses
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...analysis.kinematics import deformations, initial_q, jacobian, solve_position
from ...analysis.linearization import Linearization, linearize_free
from ...analysis.runs import analyse, default_mode
from ...analysis.statespace import StateSpace, state_space
from ...analysis.statics import StaticResult, refuse_routines, static_equilibrium
from ...engine import MAX_ITERATIONS, deformations_and_jacobian
from ...engine.laws import own_loads
from ...errors import ArgumentError, InputFileError
from ...model import Model
from ...progress import progress_bar
from ...results import KinematicResult
from ...settings import RunSettings
from ...summary import dataclass_repr
from ..dat import read_dat
from ..dat.reader import read_unchecked
from .binary import SpacarFile, read_records, write_records
from .linear import ltv_records, sbm_records
from .records import (
    linearization_records,
    model_tables,
    moment_loads,
    sbd_records,
    state_records,
)

#: the modes flexmbd runs, by what they do
MODES = {0: "check", 1: "motion", 2: "inverse dynamics", 3: "linearization",
         4: "linearization", 7: "statics", 9: "state space", 10: "statics"}


@dataclass(eq=False)
class SpacarRun:
    """What ``spacar(mode, file)`` computes, as the files it writes.

    Attributes:
        mode: the SPACAR mode run (as given, negative or not).
        base: the path of the input file without ``.dat``; the files are ``base.sbd``, ...
        files: the result files in memory by kind (``"SBD"``, ``"SBM"``, ``"LTV"``).
        success: ``False`` when the analysis stopped early; the files then hold the steps
            computed before.
        message: what happened, one line.
        interrupted: the analysis was interrupted (Ctrl-C); the files hold the steps
            computed before.
    """

    __repr__ = dataclass_repr

    mode: int
    base: Path
    files: dict[str, SpacarFile] = field(default_factory=dict)
    success: bool = True
    message: str = "completed"
    interrupted: bool = False

    def write(self) -> list[Path]:
        """Write every file next to the input file; returns their paths."""
        written = []
        for kind, file in self.files.items():
            path = self.base.with_name(self.base.name + "." + kind.lower())
            written.append(write_records(path, kind, file.tables, file.steps))
        return written


def input_path(name: str | os.PathLike) -> Path:
    """The input file of ``spacar(mode, name)``: ``name`` itself, or ``name.dat``."""
    path = Path(name)
    if path.suffix.lower() != ".dat" and not path.is_file():
        path = path.with_name(path.name + ".dat")
    if not path.is_file():
        raise ArgumentError("FILE", f"no input file {str(path)!r}")
    return path


def spacar_run(mode: int, name: str | os.PathLike, progress: bool | None = None
               ) -> SpacarRun:
    """Run a SPACAR input file in SPACAR's ``mode`` (module docstring); nothing is written
    (:meth:`SpacarRun.write` does).

    Raises:
        ArgumentError: a mode flexmbd does not run, or no such input file.
        InputFileError: the input file cannot be read; for modes 3 and 4 also a missing
            or foreign ``.sbd`` of the path.
    """
    if abs(mode) not in MODES:
        known = ", ".join(str(m) for m in MODES)
        raise ArgumentError("MODE", f"flexmbd runs SPACAR's modes {known} (and their "
                                    f"negatives), got {mode}")
    path = input_path(name)
    base = path.with_suffix("")
    run = SpacarRun(mode, base)
    if mode == 0:   # the input checked: its constraints' problems are the result
        (model, settings), problems = read_unchecked(path)
        _check(run, model, settings, problems)
        return run
    model, settings = read_dat(path)
    try:
        _analyse(run, model, settings, path, progress)
    except KeyboardInterrupt as interrupt:
        partial = getattr(interrupt, "partial_result", None)
        if partial is None:
            raise
        run.files["SBD"] = _file("SBD", *sbd_records(partial, abs(mode)))
        run.success, run.interrupted = False, True
        run.message = f"interrupted after {len(partial.t)} steps"
    return run


def _analyse(run: SpacarRun, model: Model, settings: RunSettings, path: Path,
             progress: bool | None) -> None:
    kind, base = abs(run.mode), run.base
    if kind in (1, 2):
        times = settings.output_times()
        if times is None:
            raise InputFileError(f"mode {kind} runs over the file's TIMESTEP, and it has none",
                                 str(path))
        analysis = "inverse" if kind == 2 else default_mode(model)
        result = analyse(model, settings, analysis, times, progress=progress)
        _conclude(run, result)
        run.files["SBD"] = _file("SBD", *sbd_records(result, kind))
    elif kind in (3, 4):
        _linearize_path(run, model, base.with_name(base.name + ".sbd"), kind, progress)
    else:
        _statics(run, model, settings, kind, progress)


def _check(run: SpacarRun, model: Model, settings: RunSettings, problems: list[str]
           ) -> None:
    """Mode 0: the model's tables and its initial configuration with ``D_x`` (``BIGD``);
    where its constraints do not determine its coordinates (``problems``), as drawn
    (SPACAR writes the file then too, and SPACAR Light's automatic releases read its
    ``BIGD``), without the transfer functions, which do not exist, and the run says
    why: a finding of the check, which completes (SPACAR Light reads the file after it)."""
    if problems:
        x = np.asarray(model.x0, dtype=float)
        e = deformations_and_jacobian(model, x)[0]
    else:
        x = solve_position(model, initial_q(model), tolerance=settings.tolerance)
        e = deformations(model, x)
    states = {"t": np.zeros(1), "x": x[None, :], "e": e[None, :]}
    run.files["SBD"] = _file("SBD", model_tables(model, 0),
                             state_records(model, states, slopes=True,
                                           transfers=not problems))
    if problems:   # the check's finding, not a failure: SPACAR's mode 0 returns normally
        run.message = ("; ".join(problems) + " (the .sbd holds D_x at the initial "
                       "configuration, BIGD, to find them)")


def _file(kind: str, tables: dict, steps: dict) -> SpacarFile:
    n_steps = len(next(iter(steps.values()))) if steps else 0
    return SpacarFile(None, kind, "", tables, steps, n_steps)


def _conclude(run: SpacarRun, result: KinematicResult) -> None:
    run.success, run.message = result.success, result.message


def _statics(run: SpacarRun, model: Model, settings: RunSettings, kind: int,
             progress: bool | None) -> None:
    """Modes 7, 9 and 10: ITERSTEP's load steps, each stored (also without increments,
    as SPACAR stores them)."""
    refuse_routines(settings)
    steps = settings.load_steps or 0
    increments = bool(settings.load_increment or settings.input_increment)
    if not increments and settings.iteration_options[1:2] == (1,):
        steps = 0   # ITERSTEP .. 1 1 n: SPACAR stores the one equilibrium of the loads
    result: StaticResult = static_equilibrium(
        model, load_increment=dict(settings.load_increment) or None,
        input_increment=settings.input_increment, steps=steps,
        tolerance=settings.tolerance, max_iterations=settings.max_iterations or MAX_ITERATIONS,
        on_failure="return", progress=progress)
    _conclude(run, result)
    run.files["SBD"] = _file("SBD", *sbd_records(result, kind))
    if kind == 7 or not len(result.t):
        return
    linearizations = [result.linearization(k) for k in range(len(result.t))]
    systems = [_state_space(lin, settings) for lin in linearizations] if kind == 9 else None
    run.files["SBM"] = _file("SBM", *sbm_records(linearizations, systems=systems))
    if systems is not None:
        run.files["LTV"] = _file("LTV", *ltv_records(linearizations, systems))


def _state_space(lin: Linearization, settings: RunSettings) -> StateSpace:
    if not settings.force_inputs or not (settings.outputs or settings.rate_outputs):
        raise ArgumentError("MODE", "mode 9 needs the third block's INPUTF and OUTX or OUTXP "
                                    "lines (after END HALT)")
    system = state_space(lin, settings.force_inputs, settings.outputs, settings.rate_outputs)
    if settings.output_order:   # the file's numbering of the outputs
        rows = [system.outputs.index(name) for name in settings.output_order]
        system = dataclasses.replace(system, C=system.C[rows], D=system.D[rows],
                                     outputs=tuple(settings.output_order))
    return system


def _linearize_path(run: SpacarRun, model: Model, stored: Path, kind: int,
                    progress: bool | None) -> None:
    """Modes 3 and 4: the states of the stored path, linearized at the accelerations of
    the model's free motion."""
    if not stored.is_file():
        raise InputFileError(f"mode {kind} linearizes along the path of an earlier run: run "
                             f"mode 1, 2, 7 or 10 first, as in SPACAR", str(stored))
    path = read_records(stored)
    t = path["T"][:, 0, 0]
    x = states_of(model, path, "X", stored)
    xd = states_of(model, path, "XD", stored) if "XD" in path else np.zeros_like(x)
    # the loads of the path, on top of the file's own
    extra = (moment_loads(model, x, states_of(model, path, "FX", stored)) - own_loads(model)
             if "FX" in path else np.zeros_like(x))
    linearizations = []
    with progress_bar(t, "linearizations", progress) as advance:
        for k in range(len(t)):
            ed = jacobian(model, x[k]) @ xd[k]
            qd = np.concatenate([xd[k, model.independent_coordinates],
                                 ed[model.independent_deformations]])
            linearizations.append(linearize_free(model, x[k], qd, loads=extra[k]))
            if advance is not None:
                advance(t[k])
    records = linearization_records(linearizations, t)
    records["FX"] = path["FX"] if "FX" in path else records["FX"]
    run.files["SBD"] = _file("SBD", model_tables(model, kind), records)
    run.files["SBM"] = _file("SBM", *sbm_records(linearizations, t))
    run.files["LTV"] = _file("LTV", *ltv_records(linearizations, times=t))
    run.message = f"linearized along {len(t)} stored steps"


def states_of(model: Model, stored: SpacarFile, name: str, where: Path) -> np.ndarray:
    """A per-step record of coordinates (``X``, ``XD``, ``XDD``) of a stored ``.sbd`` in
    flexmbd's order ``(n_steps, nx)``, through the file's own node table ``LNP`` (the file
    may number its coordinates for another classification of the same nodes)."""
    lnp = stored["LNP"]
    values = stored[name][:, :, 0]
    x = np.empty((len(values), model.n_coordinates))
    for number, node in model.nodes.items():
        size = len(node.coordinates)
        numbers = lnp[number - 1, :size] if number <= len(lnp) else np.zeros(0, dtype=int)
        if (len(numbers) != size or np.any(numbers < 1) or np.any(numbers > values.shape[1])
                or (size < lnp.shape[1] and np.any(lnp[number - 1, size:]))):
            raise InputFileError(f"holds another model: its node {number} does not have the "
                                 f"{size} coordinates of the input file's", str(where))
        x[:, list(node.coordinates)] = values[:, numbers - 1]
    return x
