"""flexmbd against Exudyn on the flexible slider-crank of EXERCISES 4, in one session.

Both tools simulate two revolutions of the rod of ``--nbeams`` elements with
fixed-step generalized-alpha (Exudyn's ANCF cables are always axially flexible;
flexmbd runs the flexible and, for the rigid-versus-flexible target, the rigid
elongation). Each configuration is a tool and its steps per turn; Exudyn runs
at the issue's 4000 steps per turn and at the fewest steps that keep its
accuracy within the threshold (``--exudyn-steps``), flexmbd linearly implicit
at ``--flexmbd-steps``. Reported per configuration:

* solver time: the simulation alone in this process, outputs included (median
  of ``--runs``);
* process time: a fresh interpreter that imports, builds, solves and writes
  ``v/l2`` to a file, timed from outside (median of ``--runs``). Both packages'
  modules are imported from bytecode, as on any installation: pip compiles an
  installed package (Exudyn) and Python caches an editable one (flexmbd) at its
  first import, unless ``PYTHONDONTWRITEBYTECODE`` is set, as on some CI and
  sandbox machines; there the benchmark compiles flexmbd once itself;
* accuracy: the largest deviation of ``v/l2`` over the two revolutions from a
  converged reference (flexmbd, ``--reference-nbeams`` beams, flexible
  elongation, ``--reference-steps`` steps per turn, Newton iterated to
  convergence), against the threshold ``--threshold``;

The configurations take turns run by run (all solver runs first, then all
processes), not all runs of one and then the next: the machine's speed drifts
within minutes, and a block of runs would catch one phase of it. Then the ratios
flexmbd / Exudyn for every Exudyn configuration, both as the ratio of the
medians and as the median of the run-by-run ratios (each run's configurations
ran within seconds of each other, so the latter cancels slow drifts), and the
start-up times of ``import flexmbd`` and ``flexmbd --version`` (median of
``--runs`` fresh processes). Needs ``pip install exudyn`` (benchmark only).

Run: ``python benchmarks/compare_exudyn.py [--runs 5] [--nbeams 8]``.
"""

from __future__ import annotations

import argparse
import compileall
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent


@dataclass(frozen=True)
class Config:
    """One tool at one setting."""

    tool: str  #: "flexmbd" or "exudyn"
    steps: int  #: generalized-alpha steps per crank turn
    flexible: bool = True  #: flexible elongation (Exudyn's cables always are)

    @property
    def label(self) -> str:
        elongation = "" if self.tool == "exudyn" else (
            ", flexible" if self.flexible else ", rigid")
        return f"{self.tool}{elongation} @ {self.steps}"


def flexmbd_run(nbeams: int, steps: int, flexible: bool = True,
                iterations: int | None = 1) -> tuple[np.ndarray, float]:
    """``v/l2`` at 400 points per turn and the solver time [s] of flexmbd (linearly
    implicit with ``iterations=1``, the example's setting; ``None``: Newton to
    convergence)."""
    from flexmbd.examples import slider_crank_flex as example

    model = example.build_model(nbeams, flexible)
    start = time.perf_counter()
    result = example.run(model, 2.0, steps_per_revolution=steps, iterations=iterations,
                         progress=False)
    solve = time.perf_counter() - start
    return example.midpoint_deflection(model, result.x), solve


def exudyn_run(nbeams: int, steps: int, flexible: bool = True) -> tuple[np.ndarray, float]:
    """``v/l2`` at 400 points per turn and the solver time [s] of Exudyn."""
    sys.path.insert(0, str(HERE))
    from exudyn_slider_crank import simulate

    _, v, solve = simulate(nbeams, steps)
    return v, solve


RUNNERS = {"flexmbd": flexmbd_run, "exudyn": exudyn_run}


def process_time(config: Config, nbeams: int, out: Path) -> float:
    """Wall time of a fresh interpreter doing the whole job [s]."""
    command = [sys.executable, __file__, "--worker", config.tool, "--nbeams", str(nbeams),
               "--steps", str(config.steps), "--out", str(out)]
    if not config.flexible:
        command.append("--rigid")
    start = time.perf_counter()
    subprocess.run(command, check=True)
    return time.perf_counter() - start


def startup_times(runs: int) -> dict[str, float]:
    """Median wall times [s] of fresh processes that only start up."""
    commands = {"python -c pass": [sys.executable, "-c", "pass"],
                "import flexmbd": [sys.executable, "-c", "import flexmbd"],
                "import exudyn": [sys.executable, "-c", "import exudyn"]}
    cli = shutil.which("flexmbd")
    if cli:
        commands["flexmbd --version"] = [cli, "--version"]
    medians = {}
    for name, command in commands.items():
        walls = []
        for _ in range(runs):
            start = time.perf_counter()
            subprocess.run(command, check=True, capture_output=True)
            walls.append(time.perf_counter() - start)
        medians[name] = float(np.median(walls))
    return medians


@dataclass
class Timings:
    """The runs of one configuration: solver and process times [s], deviation of ``v/l2``."""

    solves: list[float]
    processes: list[float]
    deviation: float = float("nan")

    @property
    def solve(self) -> float:
        return float(np.median(self.solves))

    @property
    def process(self) -> float:
        return float(np.median(self.processes))


def measure(configs: list[Config], nbeams: int, runs: int, reference: np.ndarray,
            folder: Path) -> dict[Config, Timings]:
    """The solver runs of all configurations, then their processes, each in turns, run by
    run: the machine's speed drifts (by tens of percent within minutes), and turns let
    the drift reach all configurations alike and make each run's ratios comparable."""
    timings = {config: Timings([], []) for config in configs}
    for _ in range(runs):
        for config in configs:
            v, solve = RUNNERS[config.tool](nbeams, config.steps, config.flexible)
            timings[config].solves.append(solve)
            timings[config].deviation = float(np.max(np.abs(v - reference)))
    print("  solver runs: done", flush=True)
    for k in range(runs):
        for config in configs:
            timings[config].processes.append(process_time(config, nbeams,
                                                          folder / f"{k}.npy"))
    print("  process runs: done", flush=True)
    return timings


def ratios(a: Timings, b: Timings) -> str:
    """``a / b``: ratio of the medians and median of the run-by-run ratios, solver and
    process."""
    paired = [float(np.median(np.divide(x, y))) for x, y in
              ((a.solves, b.solves), (a.processes, b.processes))]
    return (f"solver {a.solve / b.solve:.2f} (run by run {paired[0]:.2f}), "
            f"whole process {a.process / b.process:.2f} (run by run {paired[1]:.2f})")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--nbeams", type=int, default=8)
    parser.add_argument("--flexmbd-steps", type=int, default=400,
                        help="flexmbd steps per turn (linearly implicit generalized-alpha)")
    parser.add_argument("--exudyn-steps", type=int, nargs="+", default=[4000, 400],
                        help="Exudyn generalized-alpha steps per turn, one row each")
    parser.add_argument("--threshold", type=float, default=2e-4,
                        help="accuracy every configuration must meet (max |delta v/l2|)")
    parser.add_argument("--reference-nbeams", type=int, default=16)
    parser.add_argument("--reference-steps", type=int, default=3200)
    parser.add_argument("--worker", choices=sorted(RUNNERS), help=argparse.SUPPRESS)
    parser.add_argument("--steps", type=int, help=argparse.SUPPRESS)
    parser.add_argument("--rigid", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--out", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.worker:  # one whole job in a fresh process
        v, _ = RUNNERS[args.worker](args.nbeams, args.steps, not args.rigid)
        np.save(args.out, v)
        return

    import flexmbd

    # bytecode for flexmbd as a normal first import leaves it (see the docstring)
    compileall.compile_dir(Path(flexmbd.__file__).parent, quiet=1)
    print(f"reference: flexmbd, {args.reference_nbeams} beams, {args.reference_steps} steps "
          f"per turn, Newton to convergence ...", flush=True)
    reference, _ = flexmbd_run(args.reference_nbeams, args.reference_steps, iterations=None)
    configs = [Config("flexmbd", args.flexmbd_steps, True),
               Config("flexmbd", args.flexmbd_steps, False)]
    configs += [Config("exudyn", steps) for steps in args.exudyn_steps]
    with tempfile.TemporaryDirectory() as folder:
        rows = measure(configs, args.nbeams, args.runs, reference, Path(folder))
    startup = startup_times(args.runs)

    print(f"\nflexible slider-crank, {args.nbeams} elements, 2 revolutions, fixed-step "
          f"generalized-alpha; medians of {args.runs} runs; accuracy against flexmbd with "
          f"{args.reference_nbeams} beams at {args.reference_steps} steps per turn\n")
    print("| tool | elongation | steps per turn | solver [s] | whole process [s] "
          "| max abs dev v/l2 | within threshold |")
    print("|---|---|---|---|---|---|---|")
    for config, row in rows.items():
        print(f"| {config.tool} | {'flexible' if config.flexible else 'rigid'} "
              f"| {config.steps} | {row.solve:.3f} | {row.process:.3f} | {row.deviation:.2e} "
              f"| {'yes' if row.deviation <= args.threshold else 'NO'} |")
    flexible, rigid = rows[configs[0]], rows[configs[1]]
    print(f"\nflexmbd rigid / flexible elongation: {ratios(rigid, flexible)}")
    for config in configs[2:]:
        print(f"flexmbd (flexible) / {config.label}: {ratios(flexible, rows[config])}")
    print("\nstart-up (fresh process, median):")
    for name, wall in startup.items():
        print(f"  {name}: {wall:.3f} s")


if __name__ == "__main__":
    main()
