"""Benchmark: the flexible slider-crank of EXERCISES 4 over two revolutions.

For each number of beams (default 1, 2, 4, 8, 10) and each elongation (rigid,
flexible) it times ``flexmbd.simulate`` (model building excluded, output at 400
points per turn; median of ``--repeat`` runs) and prints a Markdown table with
the wall time, right-hand-side evaluations, steps and Jacobians, and the
extremes of ``v/l2``.

Run: ``python benchmarks/slider_crank_flex.py [--nbeams 1 2 4 8 10] [--method RK45]``.
Numbers depend on the machine; run nothing else meanwhile.
"""

from __future__ import annotations

import argparse
import platform
import time

import numpy as np
from _tables import table  # benchmarks/_tables.py, beside the script
from flexmbd.examples import slider_crank_flex as example

import flexmbd as fm


def run_case(nbeams: int, eps1flex: bool, method: str, steps_per_revolution: int,
             rtol: float, revolutions: float, repeat: int = 1) -> dict:
    """Timed simulations (the median wall time of ``repeat`` runs); the row of the table."""
    model = example.build_model(nbeams, eps1flex)
    walls = []
    for _ in range(repeat):
        start = time.perf_counter()
        result = example.run(model, revolutions, method=method,
                             steps_per_revolution=steps_per_revolution, rtol=rtol,
                             on_failure="return")
        walls.append(time.perf_counter() - start)
    wall = float(np.median(walls))
    v = example.midpoint_deflection(model, result.x)
    return {"nbeams": nbeams, "elongation": "flexible" if eps1flex else "rigid",
            "dof": model.n_dof, "wall [s]": wall, **{k: result.stats[k] for k in
                                                      ("nsteps", "nfev", "njev")},
            "ms/step": 1e3 * wall / max(result.stats["nsteps"], 1),
            "max v/l2": v.max(), "min v/l2": v.min(), "ok": result.success}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--nbeams", type=int, nargs="+", default=[1, 2, 4, 8, 10])
    parser.add_argument("--method", default="GeneralizedAlpha")
    parser.add_argument("--steps-per-revolution", type=int,
                        default=example.STEPS_PER_REVOLUTION)
    parser.add_argument("--rtol", type=float, default=1e-6)
    parser.add_argument("--revolutions", type=float, default=2.0)
    parser.add_argument("--repeat", type=int, default=3, help="runs per case (median time)")
    args = parser.parse_args()
    rows = []
    for eps1flex in (False, True):
        for nbeams in args.nbeams:
            rows.append(run_case(nbeams, eps1flex, args.method, args.steps_per_revolution,
                                 args.rtol, args.revolutions, args.repeat))
            print(f"  done: {rows[-1]['nbeams']} beams, {rows[-1]['elongation']} elongation, "
                  f"{rows[-1]['wall [s]']:.2f} s", flush=True)
    setting = (f"{args.steps_per_revolution} steps per turn, linearly implicit"
               if args.method == "GeneralizedAlpha" else f"rtol {args.rtol:g}")
    setting += f", median of {args.repeat} runs"
    print(f"\nflexible slider-crank, {args.revolutions:g} revolutions, {args.method} ({setting}); "
          f"flexmbd {fm.__version__}, numpy {np.__version__}, Python "
          f"{platform.python_version()}, {platform.machine()}\n")
    print(table(rows))


if __name__ == "__main__":
    main()
