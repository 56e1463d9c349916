"""``flexmbd run FILE.dat``: run a SPACAR input file and write, plot and animate its results."""

from __future__ import annotations

import argparse
from importlib.util import find_spec
from pathlib import Path

import numpy as np

from .dat import read_dat
from .dat.syntax import LARGEST_INTEGER
from .dynamics import inverse_dynamics, simulate
from .errors import ModelError, OptionalDependencyError
from .integrate import METHODS
from .kinematics import kinematic_analysis
from .model import CoordinateClass, Model
from .results import KinematicResult
from .settings import RunSettings

MODES = ("kinematic", "dynamic", "inverse")
RESULT_TYPES = (".csv", ".npz", ".h5", ".hdf5")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The options of ``flexmbd run``."""
    parser.add_argument("file", metavar="FILE.dat", help="SPACAR input file (planar subset)")
    parser.add_argument("--mode", choices=MODES,
                        help="analysis (default: dynamic when the model has dynamic degrees "
                             "of freedom, kinematic otherwise)")
    parser.add_argument("--out", metavar="FILE.csv", help="write the results (.csv, .npz, .h5)")
    parser.add_argument("--plot", metavar="FILE.png", help="plot columns against time")
    parser.add_argument("--columns", nargs="+", metavar="NAME",
                        help="columns to plot (default: the degrees of freedom of the run)")
    parser.add_argument("--against", default="t", metavar="NAME",
                        help="column of the plot's horizontal axis (default t)")
    parser.add_argument("--movie", metavar="FILE.mp4", help="animate the mechanism (.mp4, .gif)")
    parser.add_argument("--steps", type=int, help="output intervals (default: TIMESTEP)")
    parser.add_argument("--t-end", type=float, help="end time [s] (default: TIMESTEP)")
    parser.add_argument("--method", default="RK45", choices=sorted(METHODS),
                        help="integrator of the dynamic mode (default RK45)")


def default_mode(model: Model) -> str:
    """Dynamic when the model has dynamic degrees of freedom, kinematic otherwise."""
    return "dynamic" if np.any(~model.q_is_input) else "kinematic"


def output_times(settings: RunSettings, steps: int | None, t_end: float | None) -> np.ndarray:
    """``steps + 1`` times from 0 to ``t_end``, each defaulting to the file's TIMESTEP."""
    steps = settings.steps if steps is None else steps
    t_end = settings.t_end if t_end is None else t_end
    if steps is None or t_end is None:
        raise ModelError("the file has no TIMESTEP line: give --t-end and --steps")
    if not 1 <= steps <= LARGEST_INTEGER or not 0 < t_end < np.inf:
        raise ModelError(f"need 1 <= --steps <= {LARGEST_INTEGER} and a finite --t-end > 0, "
                         f"got {steps} and {t_end:g}")
    return np.linspace(0.0, t_end, steps + 1)


def analyse(model: Model, settings: RunSettings, mode: str, times: np.ndarray,
            method: str = "RK45") -> KinematicResult:
    """Run ``mode`` on ``model`` with the file's settings; failures are returned."""
    s = settings
    if mode == "kinematic":
        return kinematic_analysis(model, times, tolerance=s.tolerance,
                                  max_iterations=s.max_iterations or 25, on_failure="return")
    if mode == "inverse":
        return inverse_dynamics(model, times, tolerance=s.tolerance, on_failure="return")
    return simulate(model, times, initial=s.initial, method=method, rtol=s.rtol or 1e-6,
                    atol=s.atol or 1e-9, tolerance=s.tolerance, with_reactions=True,
                    on_failure="return")


def default_columns(result: KinematicResult, mode: str) -> list[str]:
    """What to plot: driving loads (inverse), dynamic degrees of freedom (dynamic), the
    first dependent coordinates (kinematic)."""
    model = result.model
    if mode == "inverse":
        return ["f" + model.coordinate_labels[i][1:] for i in model.input_coordinates] or \
               [label for label in result.columns() if label.startswith("sig")][:4]
    if mode == "dynamic":
        return [label for label, given in zip(model.q_labels, model.q_is_input, strict=True)
                if not given]
    dependent = np.flatnonzero(model.coordinate_class == CoordinateClass.DEPENDENT)
    return [model.coordinate_labels[i] for i in dependent[:4]]


def run(args: argparse.Namespace) -> int:
    """``flexmbd run``: returns 0 when the run completed, 1 when it stopped early."""
    for name, types in (("--out", RESULT_TYPES), ("--movie", (".mp4", ".gif")),
                        ("--plot", (".png", ".pdf", ".svg", ".jpg"))):
        value = getattr(args, name[2:])
        if value and not value.lower().endswith(types):
            raise ModelError(f"{name} {value!r} must end in {', '.join(types)}")
    if args.out and args.out.lower().endswith((".h5", ".hdf5")) and not find_spec("h5py"):
        # refuse before the run, not after it: results are never computed to be lost
        raise OptionalDependencyError("writing .h5 needs h5py: pip install 'flexmbd[hdf5]' "
                                      "(or write .csv or .npz)")
    model, settings = read_dat(args.file)
    mode = args.mode or default_mode(model)
    times = output_times(settings, args.steps, args.t_end)
    print(model.summary())
    print(f"{mode} analysis of {Path(args.file).name}: {len(times)} output times to "
          f"t = {times[-1]:.6g} s")
    result = analyse(model, settings, mode, times, args.method)
    print(result.message)
    if args.out:  # written even after a failure: the rows before it
        result.save(args.out)
        print(f"{len(result.t)} rows written to {args.out}")
    if len(result.t) >= 2:
        if args.plot:
            columns = args.columns or default_columns(result, mode)
            _check_columns(result, [*columns, args.against])
            result.plot(columns, args.against, filename=args.plot, title=f"{model.name} ({mode})")
            print(f"plot saved to {args.plot}")
        if args.movie:
            from .plot import animate

            animate(result, args.movie, title=f"{model.name} ({mode})")
            print(f"movie saved to {args.movie}")
    return 0 if result.success else 1


def _check_columns(result: KinematicResult, columns: list[str]) -> None:
    """Unknown column names are a usage error naming what exists."""
    for name in columns:
        try:
            result[name]
        except KeyError:
            known = ", ".join(list(result.columns())[:8])
            raise ModelError(f"--columns: {name!r} is not a result column (they are "
                             f"{known}, ...)") from None
