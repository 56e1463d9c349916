"""flexmbd against Exudyn on the flexible slider-crank, each at its cheapest setting.

Both tools simulate two revolutions of the rod of ``--nbeams`` elements with fixed-step
generalized-alpha (Exudyn's ANCF cables are always axially flexible; flexmbd runs the
flexible elongation), recording ``v/l2`` at every step. The comparison has three parts:

1. **Search.** Every setting of a grid (steps per turn, spectral radius and each tool's
   own cost options: for flexmbd the Newton-matrix renewal, for Exudyn Newmark, Newton
   tolerance, reduced integration of the cables and the sparse solver) is run once for
   its accuracy, the largest deviation of ``v/l2`` from a converged reference (flexmbd
   with ``--reference-nbeams`` beams at ``--reference-steps`` steps per turn, Newton
   iterated to convergence, at the same output times), and timed (best of
   ``--search-runs``). Each tool's cheapest setting within ``--threshold`` wins;
   Exudyn's cheapest options at 4000 steps per turn are found the same way.
2. **Solver time**, in this process: the winners (flexmbd recording every column, as
   ``simulate`` does by default, and recording positions only, all the job needs)
   take turns run by run, ``--runs`` times.
3. **Whole process**: a fresh interpreter that imports, builds, solves and writes a CSV
   of ``t, phi, v/l2`` (the worker imports no more of the benchmark's own plumbing than
   it needs), timed from outside, the winners taking turns; and the README's
   first command (``flexmbd example slider-crank-flex --nbeams 8 --eps1flex --out
   f.csv``, every column at the example's default 400 steps per turn) against Exudyn's
   winning process.

Ratios flexmbd / Exudyn are the medians of the run-by-run ratios (each run's
configurations ran within seconds of each other, which cancels the machine's slow
drifts), with the ratios of the medians beside them. Both packages are imported from
bytecode, as on any installation (the benchmark compiles flexmbd's once where
``PYTHONDONTWRITEBYTECODE`` is set). Needs ``pip install exudyn`` (benchmark only).

Run: ``python benchmarks/compare_exudyn.py [--nbeams 8] [--runs 7]``; for 64 beams,
``--nbeams 64 --reference-nbeams 128 --search-runs 1``.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from exudyn_slider_crank import OMEGA, ExudynSetting  # noqa: E402

REVOLUTIONS = 2.0


@dataclass(frozen=True)
class FlexmbdSetting:
    """flexmbd's generalized-alpha options of one run (linearly implicit)."""

    steps: int  #: steps per crank turn (outputs at every step)
    rho_inf: float = 0.8
    renew_every: int = 2  #: steps between Newton matrices
    outputs: str = "all"  #: what simulate records ("all" or "positions")

    @property
    def label(self) -> str:
        return (f"{self.steps} steps, rho {self.rho_inf:g}, Newton matrix every "
                f"{self.renew_every}, outputs {self.outputs}")


# --- the two tools ------------------------------------------------------------------------
def flexmbd_job(nbeams: int, setting: FlexmbdSetting, csv: str | None = None,
                model=None) -> tuple[np.ndarray, float]:
    """The user's job in flexmbd: ``v/l2`` at every step and the solver time [s]; with
    ``csv``, also the model, import aside, and the file of ``t, phi, v/l2``."""
    from flexmbd.examples import slider_crank_flex as example

    import flexmbd as fm
    from flexmbd import results

    model = model or example.build_model(nbeams, eps1flex=True)
    turn = example.turn_time(1.0)
    times = np.linspace(0.0, REVOLUTIONS * turn, round(REVOLUTIONS * setting.steps) + 1)
    start = time.perf_counter()
    result = fm.simulate(model, times, method="GeneralizedAlpha", step=turn / setting.steps,
                         iterations=1, renew_every=setting.renew_every,
                         rho_inf=setting.rho_inf, outputs=setting.outputs, progress=False)
    solve = time.perf_counter() - start
    v = example.midpoint_deflection(model, result.x)
    if csv:
        results.write_csv(csv, {"t": result.t, "phi": result["x2.1"], "v_over_l2": v})
    return v, solve


def exudyn_job(nbeams: int, setting: ExudynSetting, csv: str | None = None,
               model=None) -> tuple[np.ndarray, float]:
    """The same job in Exudyn."""
    from exudyn_slider_crank import simulate

    t, v, solve = simulate(nbeams, setting, REVOLUTIONS)
    if csv:
        np.savetxt(csv, np.column_stack([t, OMEGA * t, v]), delimiter=",",
                   header="t,phi,v_over_l2", comments="")
    return v, solve


JOBS = {"flexmbd": (flexmbd_job, FlexmbdSetting), "exudyn": (exudyn_job, ExudynSetting)}


def reference(nbeams: int, steps_per_turn: int, points_per_turn: int,
              cache: dict = {}) -> np.ndarray:  # noqa: B006 (a cache across calls)
    """``v/l2`` of the converged reference at ``points_per_turn`` outputs per turn."""
    key = (nbeams, steps_per_turn, points_per_turn)
    if key not in cache:
        from flexmbd.examples import slider_crank_flex as example

        import flexmbd as fm

        model = example.build_model(nbeams, eps1flex=True)
        turn = example.turn_time(1.0)
        times = np.linspace(0.0, REVOLUTIONS * turn, round(REVOLUTIONS * points_per_turn) + 1)
        result = fm.simulate(model, times, method="GeneralizedAlpha", step=turn / steps_per_turn,
                             iterations=None, rho_inf=0.8, progress=False)
        cache[key] = example.midpoint_deflection(model, result.x)
    return cache[key]


# --- 1. search ----------------------------------------------------------------------------
def candidates(tool: str, steps: list[int]) -> list:
    """The grid of settings of a tool."""
    import itertools

    if tool == "flexmbd":
        # one Newton correction per step needs rho_inf <= 0.8 (flexmbd refuses more)
        return [FlexmbdSetting(n, rho, renew, "positions")
                for n, rho, renew in itertools.product(steps, (0.7, 0.8), (1, 2, 3))]
    return [ExudynSetting(n, rho, newmark, rtol, reduced, sparse)
            for n, rho, newmark, rtol, reduced, sparse in itertools.product(
                steps, (0.8, 0.9), (False, True), (1e-8, 1e-6, 1e-4), (0, 2), (False, True))]


def search(tool: str, settings: list, nbeams: int, args) -> tuple[object, list[tuple]]:
    """The cheapest setting within the threshold, and every row (setting, deviation,
    best time)."""
    job = JOBS[tool][0]
    model = None
    if tool == "flexmbd":
        from flexmbd.examples import slider_crank_flex as example

        model = example.build_model(nbeams, eps1flex=True)
    rows = []
    for setting in settings:
        times, v = [], None
        try:
            for _ in range(args.search_runs):
                v, solve = job(nbeams, setting, model=model)
                times.append(solve)
        except Exception as error:  # a setting the solver fails with does not qualify
            print(f"  {tool}, {setting.label}: failed ({type(error).__name__})", flush=True)
            continue
        deviation = float(np.max(np.abs(v - reference(args.reference_nbeams,
                                                      args.reference_steps, setting.steps))))
        rows.append((setting, deviation, min(times)))
    good = [row for row in rows if row[1] <= args.threshold]
    if not good:
        raise SystemExit(f"no {tool} setting meets {args.threshold:g}")
    return min(good, key=lambda row: row[2])[0], rows


# --- 2. and 3. paired runs ------------------------------------------------------------------
def solver_times(configs: dict[str, tuple[str, object]], nbeams: int, runs: int
                 ) -> dict[str, list[float]]:
    """Solver times [s] of each configuration, the configurations taking turns."""
    models = {}
    from flexmbd.examples import slider_crank_flex as example

    models["flexmbd"] = example.build_model(nbeams, eps1flex=True)
    times: dict[str, list[float]] = {name: [] for name in configs}
    for _ in range(runs):
        for name, (tool, setting) in configs.items():
            times[name].append(JOBS[tool][0](nbeams, setting, model=models.get(tool))[1])
    return times


def process_command(tool: str, setting, nbeams: int, out: Path) -> list[str]:
    """A fresh interpreter running the whole job."""
    return [sys.executable, __file__, "--worker", tool, "--nbeams", str(nbeams),
            "--setting", json.dumps(asdict(setting)), "--out", str(out)]


def readme_command(out: Path) -> list[str]:
    """The README's first command, without plots or movies."""
    import shutil

    flexmbd = shutil.which("flexmbd") or str(Path(sys.executable).parent / "flexmbd")
    return [flexmbd, "example", "slider-crank-flex", "--nbeams", "8", "--eps1flex", "--out",
            str(out)]


def wall_times(commands: dict[str, list[str]], runs: int) -> dict[str, list[float]]:
    """Wall times [s] of fresh processes, the commands taking turns."""
    import subprocess

    times: dict[str, list[float]] = {name: [] for name in commands}
    for _ in range(runs):
        for name, command in commands.items():
            start = time.perf_counter()
            subprocess.run(command, check=True, capture_output=True)
            times[name].append(time.perf_counter() - start)
    return times


def ratio(a: list[float], b: list[float]) -> str:
    """``a / b``: median of the run-by-run ratios (ratio of the medians)."""
    return (f"{float(np.median(np.divide(a, b))):.2f} "
            f"({float(np.median(a)) / float(np.median(b)):.2f})")


def print_search(tool: str, rows: list[tuple], best, threshold: float, shown: int = 8) -> None:
    ok = sorted((row for row in rows if row[1] <= threshold), key=lambda row: row[2])
    print(f"\n{tool}: {len(rows)} settings, {len(ok)} within {threshold:g}; the cheapest:\n")
    print("| setting | max abs dev v/l2 | solver [ms] |")
    print("|---|---|---|")
    for setting, deviation, solve in ok[:shown]:
        mark = " (chosen)" if setting == best else ""
        print(f"| {setting.label}{mark} | {deviation:.2e} | {1e3 * solve:.1f} |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--nbeams", type=int, default=8)
    parser.add_argument("--runs", type=int, default=7, help="paired solver runs (default 7)")
    parser.add_argument("--process-runs", type=int, default=21,
                        help="paired process runs (default 21: start-up times scatter)")
    parser.add_argument("--search-runs", type=int, default=3,
                        help="timed runs per searched setting (best of)")
    parser.add_argument("--steps", type=int, nargs="+",
                        default=[250, 300, 325, 350, 375, 400, 450, 500],
                        help="steps per turn to search")
    parser.add_argument("--threshold", type=float, default=2e-4,
                        help="accuracy every setting must meet (max |delta v/l2|)")
    parser.add_argument("--reference-nbeams", type=int, default=16)
    parser.add_argument("--reference-steps", type=int, default=3200)
    parser.add_argument("--no-process", action="store_true", help="solver times only")
    parser.add_argument("--no-4000", action="store_true",
                        help="leave out Exudyn at 4000 steps per turn")
    parser.add_argument("--worker", choices=sorted(JOBS), help=argparse.SUPPRESS)
    parser.add_argument("--setting", help=argparse.SUPPRESS)
    parser.add_argument("--out", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.worker:  # one whole job in a fresh process
        job, setting_type = JOBS[args.worker]
        job(args.nbeams, setting_type(**json.loads(args.setting)), csv=args.out)
        return

    import compileall
    import tempfile

    import exudyn

    import flexmbd

    compileall.compile_dir(Path(flexmbd.__file__).parent, quiet=1)
    compileall.compile_file(HERE / "exudyn_slider_crank.py", quiet=1)
    print(f"flexmbd {flexmbd.__version__} (core: {flexmbd.engine.CORE_BUILD}), Exudyn "
          f"{exudyn.__version__}; {args.nbeams} elements, flexible elongation, "
          f"{REVOLUTIONS:g} revolutions; reference: flexmbd, {args.reference_nbeams} beams, "
          f"{args.reference_steps} steps per turn, Newton to convergence", flush=True)
    fm_best, fm_rows = search("flexmbd", candidates("flexmbd", args.steps), args.nbeams, args)
    print_search("flexmbd", fm_rows, fm_best, args.threshold)
    ex_best, ex_rows = search("exudyn", candidates("exudyn", args.steps), args.nbeams, args)
    print_search("Exudyn", ex_rows, ex_best, args.threshold)
    fm_all = FlexmbdSetting(fm_best.steps, fm_best.rho_inf, fm_best.renew_every, "all")
    configs = {"flexmbd, all outputs": ("flexmbd", fm_all),
               "flexmbd, positions": ("flexmbd", fm_best), "Exudyn": ("exudyn", ex_best)}
    if not args.no_4000:
        ex_4000, rows_4000 = search("exudyn", candidates("exudyn", [4000]), args.nbeams, args)
        print_search("Exudyn at 4000 steps per turn", rows_4000, ex_4000, args.threshold, 3)
        configs["Exudyn @ 4000"] = ("exudyn", ex_4000)
    solves = solver_times(configs, args.nbeams, args.runs)
    print(f"\nsolver time, paired runs (median of {args.runs}):\n")
    print("| configuration | setting | solver [ms] |")
    print("|---|---|---|")
    for name, (_, setting) in configs.items():
        print(f"| {name} | {setting.label} | {1e3 * float(np.median(solves[name])):.1f} |")
    for name in ("flexmbd, all outputs", "flexmbd, positions"):
        print(f"\n{name} / Exudyn: solver {ratio(solves[name], solves['Exudyn'])}" + (
            "" if args.no_4000 else
            f"; / Exudyn @ 4000: {ratio(solves[name], solves['Exudyn @ 4000'])}"))
    if args.no_process:
        return
    with tempfile.TemporaryDirectory() as folder:
        out = Path(folder)
        commands = {name: process_command(tool, setting, args.nbeams, out / f"{k}.csv")
                    for k, (name, (tool, setting)) in enumerate(configs.items())}
        if args.nbeams == 8:
            commands["README command"] = readme_command(out / "readme.csv")
        walls = wall_times(commands, args.process_runs)
        startup = wall_times({"python -c pass": [sys.executable, "-c", "pass"],
                              "import numpy": [sys.executable, "-c", "import numpy"],
                              "import flexmbd": [sys.executable, "-c", "import flexmbd"],
                              "import exudyn": [sys.executable, "-c", "import exudyn"]},
                             args.process_runs)
    print(f"\nwhole process, paired runs (median of {args.process_runs}):\n")
    print("| command | wall [s] | / Exudyn's process |")
    print("|---|---|---|")
    for name, values in walls.items():
        print(f"| {name} | {float(np.median(values)):.3f} | "
              f"{ratio(values, walls['Exudyn'])} |")
    print("\nstart-up (median): " + ", ".join(
        f"{name} {float(np.median(values)):.3f} s" for name, values in startup.items()))
    numpy, flexmbd_import = startup["import numpy"], startup["import flexmbd"]
    print(f"import flexmbd above import numpy: "
          f"{float(np.median(np.subtract(flexmbd_import, numpy))):.3f} s")


if __name__ == "__main__":
    main()
