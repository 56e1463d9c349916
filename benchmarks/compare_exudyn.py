"""flexmbd against Exudyn on the flexible slider-crank of EXERCISES 4, in one session.

Both tools simulate two revolutions of the rod of ``--nbeams`` elements with a
flexible elongation (Exudyn's ANCF cables are always axially flexible), with
fixed-step generalized-alpha. Reported per tool:

* solver time: the time integration alone, in this process (median of ``--runs``);
* process time: a fresh interpreter that imports, builds, solves and writes
  ``v/l2`` to a file, timed from outside (median of ``--runs``);
* accuracy: the largest deviation of ``v/l2`` over the two revolutions from a
  converged reference (flexmbd, ``--reference-nbeams`` beams, ``--reference-steps``
  steps per turn);

and the ratios flexmbd / Exudyn. Needs ``pip install exudyn`` (benchmark only).

Run: ``python benchmarks/compare_exudyn.py [--runs 5] [--nbeams 8]``.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent


def flexmbd_run(nbeams: int, steps: int, eps1flex: bool = True) -> tuple[np.ndarray, float]:
    """``v/l2`` at 400 points per turn and the solver time [s] of flexmbd."""
    from flexmbd.examples import slider_crank_flex as example

    model = example.build_model(nbeams, eps1flex)
    start = time.perf_counter()
    result = example.run(model, 2.0, steps_per_revolution=steps)
    solve = time.perf_counter() - start
    return example.midpoint_deflection(model, result.x), solve


def exudyn_run(nbeams: int, steps: int) -> tuple[np.ndarray, float]:
    """``v/l2`` at 400 points per turn and the solver time [s] of Exudyn."""
    sys.path.insert(0, str(HERE))
    from exudyn_slider_crank import simulate

    _, v, solve = simulate(nbeams, steps)
    return v, solve


RUNNERS = {"flexmbd": flexmbd_run, "exudyn": exudyn_run}


def process_time(tool: str, nbeams: int, steps: int, out: Path) -> float:
    """Wall time of a fresh interpreter doing the whole job [s]."""
    start = time.perf_counter()
    subprocess.run([sys.executable, __file__, "--worker", tool, "--nbeams", str(nbeams),
                    "--steps", str(steps), "--out", str(out)], check=True)
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--nbeams", type=int, default=8)
    parser.add_argument("--flexmbd-steps", type=int, default=800,
                        help="flexmbd generalized-alpha steps per turn")
    parser.add_argument("--exudyn-steps", type=int, default=4000,
                        help="Exudyn generalized-alpha steps per turn")
    parser.add_argument("--reference-nbeams", type=int, default=16)
    parser.add_argument("--reference-steps", type=int, default=3200)
    parser.add_argument("--worker", choices=sorted(RUNNERS), help=argparse.SUPPRESS)
    parser.add_argument("--steps", type=int, help=argparse.SUPPRESS)
    parser.add_argument("--out", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.worker:  # one whole job in a fresh process
        v, _ = RUNNERS[args.worker](args.nbeams, args.steps)
        np.save(args.out, v)
        return

    print(f"reference: flexmbd, {args.reference_nbeams} beams, {args.reference_steps} steps "
          f"per turn ...", flush=True)
    reference, _ = flexmbd_run(args.reference_nbeams, args.reference_steps)
    steps = {"flexmbd": args.flexmbd_steps, "exudyn": args.exudyn_steps}
    rows = {}
    with tempfile.TemporaryDirectory() as folder:
        for tool, runner in RUNNERS.items():
            solves, processes = [], []
            for k in range(args.runs):
                v, solve = runner(args.nbeams, steps[tool])
                solves.append(solve)
                processes.append(process_time(tool, args.nbeams, steps[tool],
                                              Path(folder) / f"{tool}{k}.npy"))
            rows[tool] = (float(np.median(solves)), float(np.median(processes)),
                          float(np.max(np.abs(v - reference))))
            print(f"  {tool}: done", flush=True)
    print(f"\nflexible slider-crank, {args.nbeams} elements, flexible elongation, 2 "
          f"revolutions; medians of {args.runs} runs\n")
    print("| tool | steps per turn | solver [s] | whole process [s] | max abs dev v/l2 |")
    print("|---|---|---|---|---|")
    for tool, (solve, process, deviation) in rows.items():
        print(f"| {tool} | {steps[tool]} | {solve:.3f} | {process:.3f} | {deviation:.2e} |")
    f, e = rows["flexmbd"], rows["exudyn"]
    print(f"\nflexmbd / Exudyn: solver {f[0] / e[0]:.2f}, whole process {f[1] / e[1]:.2f}")


if __name__ == "__main__":
    main()
