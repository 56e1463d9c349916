"""``flexmbd run FILE.dat``: run a SPACAR input file and write, plot and animate its results."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import numpy as np

from .. import checks
from ..analysis.integrate import DEFAULT_METHOD, METHODS
from ..analysis.runs import MODES, analyse, check_mode, default_mode
from ..engine import KINEMATIC_OUTPUTS, output_bytes, output_sizes
from ..errors import ArgumentError
from ..io.dat import read_dat
from ..io.dat.syntax import LARGEST_INTEGER
from ..io.outputs import check_output
from ..io.sbd.records import SPACAR_MODES
from ..model import CoordinateClass, Model
from ..results import KinematicResult, SimulationResult
from ..settings import RunSettings


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The options of ``flexmbd run``."""
    parser.add_argument("file", metavar="FILE.dat", help="SPACAR input file (planar or spatial)")
    parser.add_argument("--mode", choices=MODES,
                        help="analysis (default: dynamic when the model has dynamic degrees "
                             "of freedom, kinematic otherwise)")
    parser.add_argument("--out", metavar="FILE.csv",
                        help="write the results (.csv, .npz, .h5, or SPACAR's .sbd); also "
                             "what an interrupted or failed run computed")
    parser.add_argument("--plot", metavar="FILE.png", help="plot columns against time")
    parser.add_argument("--columns", nargs="+", metavar="NAME",
                        help="columns to plot (default: the degrees of freedom of the run)")
    parser.add_argument("--against", default="t", metavar="NAME",
                        help="column of the plot's horizontal axis (default t)")
    parser.add_argument("--movie", metavar="FILE.mp4", help="animate the mechanism (.mp4, .gif)")
    parser.add_argument("--steps", type=int, help="output intervals (default: TIMESTEP)")
    parser.add_argument("--t-end", type=float, help="end time [s] (default: TIMESTEP)")
    parser.add_argument("--release", action="store_true",
                        help="release over-constraints as SPACAR Light does (they are "
                             "printed)")
    parser.add_argument("--method", choices=sorted(METHODS),
                        help=f"integrator of the dynamic mode (default {DEFAULT_METHOD}, "
                             f"its steps controlled by the file's (or the default) rtol "
                             f"and atol)")


def output_times(settings: RunSettings, steps: int | None, t_end: float | None) -> np.ndarray:
    """``steps + 1`` times from 0 to ``t_end``, each defaulting to the file's TIMESTEP."""
    steps = settings.steps if steps is None else steps
    t_end = settings.t_end if t_end is None else t_end
    if steps is None or t_end is None:
        raise ArgumentError("--t-end", "the file has no TIMESTEP line: give --t-end and --steps")
    if not 1 <= steps <= LARGEST_INTEGER:
        raise ArgumentError("--steps", f"must lie in 1 .. {LARGEST_INTEGER}, got {steps}")
    if not 0 < t_end < np.inf:
        raise ArgumentError("--t-end", f"must be a finite time > 0 [s], got {t_end:g}")
    return np.linspace(0.0, t_end, steps + 1)


def empty_result(model: Model, mode: str) -> KinematicResult:
    """A result of ``mode`` with no rows: the columns a run will have, known before it."""
    arrays: dict[str, Any] = {name: np.zeros((0, size))
                              for name, size in output_sizes(model).items()}
    if mode == "kinematic":
        return KinematicResult(model, np.zeros(0), **{k: arrays[k] for k in KINEMATIC_OUTPUTS})
    return SimulationResult(model, np.zeros(0), **arrays)


def default_columns(result: KinematicResult, mode: str) -> list[str]:
    """What to plot: driving loads (inverse), dynamic degrees of freedom (dynamic), the
    first dependent coordinates (kinematic)."""
    model = result.model
    if mode == "inverse":
        return ["f" + model.coordinate_labels[i][1:] for i in model.input_coordinates] or \
               [label for label in result.columns() if label.startswith("sig")][:4]
    if mode == "dynamic":
        return list(model.dynamic_q_labels)
    dependent = np.flatnonzero(model.coordinate_class == CoordinateClass.DEPENDENT)
    return [model.coordinate_labels[i] for i in dependent[:4]]


def check_columns(result: KinematicResult, columns: list[str], against: str) -> None:
    """Unknown column names are a usage error naming the option and what exists."""
    for option, names in (("--columns", columns), ("--against", [against])):
        for name in names:
            try:
                result[name]
            except KeyError:
                known = ", ".join(list(result.columns())[:8])
                raise ArgumentError(option, f"{name!r} is not a result column (they are "
                                            f"{known}, ...)") from None


def check_arguments(args: argparse.Namespace) -> None:
    """What can be checked before reading the file: output files, and options that only
    mean something together with another."""
    for option, what in (("--out", "results"), ("--plot", "plot"), ("--movie", "movie")):
        if getattr(args, option[2:]):
            check_output(getattr(args, option[2:]), what, option)
    for option, given in (("--columns", args.columns), ("--against", args.against != "t")):
        if given and not args.plot:
            raise ArgumentError(option, "chooses what --plot draws; add --plot FILE.png")


def read_input(path, release: bool = False) -> tuple[Model, RunSettings]:
    """Read a SPACAR file for a command, printing its notes (values read but not used, the
    over-constraints released with ``release``)."""
    model, settings = read_dat(path, release=release)
    for note in settings.notes:
        print(f"note: {note}", file=sys.stderr)
    return model, settings


def run(args: argparse.Namespace) -> int:
    """``flexmbd run``: 0 when the run completed, 1 when it stopped early, 130 when it was
    interrupted. Everything computed is written, also after a failure or an interrupt."""
    check_arguments(args)
    model, settings = read_input(args.file, args.release)
    mode = args.mode or default_mode(model)
    check_mode(model, mode)
    times = output_times(settings, args.steps, args.t_end)
    empty = empty_result(model, mode)
    checks.output_memory(len(times), output_bytes(model, integrated=mode == "dynamic"),
                         "--steps (or TIMESTEP)")
    columns = args.columns or default_columns(empty, mode)
    check_columns(empty, columns, args.against)
    print(model.summary())
    print(f"{mode} analysis of {Path(args.file).name}: {len(times)} output times to "
          f"t = {times[-1]:.6g} s")
    try:
        result = analyse(model, settings, mode, times, args.method or DEFAULT_METHOD,
                         progress=True)
    except KeyboardInterrupt as interrupt:
        partial = getattr(interrupt, "partial_result", None)
        if partial is None:
            raise
        result = partial
        print(f"interrupted at t = {result.t[-1] if len(result.t) else times[0]:.6g} s")
        write_outputs(args, result, mode, columns)
        return 130
    print(result.message)
    write_outputs(args, result, mode, columns)
    return 0 if result.success else 1


def save_result(result: KinematicResult, path: str, mode: int) -> None:
    """Write a result in the format of the file name: SPACAR's ``.sbd`` (of SPACAR
    ``mode``), or the columns (``.csv``, ``.npz``, ``.h5``)."""
    if Path(path).suffix.lower() == ".sbd":
        from ..io.sbd import write_sbd

        write_sbd(path, result, mode)
    else:
        result.save(path)


def write_outputs(args: argparse.Namespace, result: KinematicResult, mode: str,
                  columns: list[str]) -> None:
    """Write the result file, the plot and the movie of what was computed."""
    if args.out:
        save_result(result, args.out, SPACAR_MODES[mode])
        print(f"{len(result.t)} rows written to {args.out}")
    if len(result.t) < 2:
        return
    title = f"{result.model.name} ({mode})"
    if args.plot:
        result.plot(columns, args.against, filename=args.plot, title=title)
        print(f"plot saved to {args.plot}")
    if args.movie:
        from ..plot import animate

        animate(result, args.movie, title=title)
        print(f"movie saved to {args.movie}")
