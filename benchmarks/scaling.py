"""Benchmark: cost per time step of the flexible slider-crank against the number of beams.

For each number of beams along the rod (default 10, 20, 50, 100, 200), with a
flexible elongation, it times a short run of the example's setting (linearly
implicit generalized-alpha at 400 steps per turn, every step an output recording
every column; model building excluded; best of ``--repeat``) and reports the cost
per step, its ratio to the smallest model's, the local log-log slope between
successive sizes (1: linear growth) and the bands of the two square systems the
core factorises (``D_c`` and the saddle-point matrix, lower + upper bandwidth). A
log-log plot goes to ``--plot`` (matplotlib).

Run: ``python benchmarks/scaling.py [--nbeams 10 20 50 100 200] [--plot scaling.png]``.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
from flexmbd.examples import slider_crank_flex as example

import flexmbd as fm
from flexmbd.engine import Workspace


def cost_per_step(nbeams: int, steps: int, repeat: int) -> dict:
    """Best wall time per step [ms] of ``steps`` steps, and the model's sizes and bands."""
    model = example.build_model(nbeams, eps1flex=True)
    turn = example.turn_time(1.0)
    step = turn / example.STEPS_PER_REVOLUTION
    times = np.linspace(0.0, steps * step, steps + 1)
    walls = []
    for _ in range(repeat):
        start = time.perf_counter()
        result = fm.simulate(model, times, method="GeneralizedAlpha", step=step, iterations=1,
                             renew_every=2, progress=False)
        walls.append(time.perf_counter() - start)
    bands = Workspace(model).core.bands()
    return {"nbeams": nbeams, "dof": model.n_dof, "coordinates": model.n_coordinates,
            "D_c band": bands["dc_kl"] + bands["dc_ku"],
            "saddle band": bands["saddle_kl"] + bands["saddle_ku"],
            "steps": result.stats["nsteps"], "ms/step": 1e3 * min(walls) / steps}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--nbeams", type=int, nargs="+", default=[10, 20, 50, 100, 200])
    parser.add_argument("--steps", type=int, default=200, help="steps per run (default 200)")
    parser.add_argument("--repeat", type=int, default=5, help="runs per size (best of)")
    parser.add_argument("--plot", metavar="FILE.png", help="write a log-log plot")
    args = parser.parse_args()
    rows = []
    for nbeams in args.nbeams:
        rows.append(cost_per_step(nbeams, args.steps, args.repeat))
        print(f"  {nbeams} beams: {rows[-1]['ms/step']:.4f} ms per step", flush=True)
    base = rows[0]
    print(f"\nflexible slider-crank, flexible elongation, {args.steps} steps at "
          f"{example.STEPS_PER_REVOLUTION} per turn (linearly implicit generalized-alpha, "
          f"every step an output), best of {args.repeat}\n")
    print("| beams | DOF | coordinates | D_c band | saddle band | ms per step "
          "| per step / smallest | beams / smallest | local slope |")
    print("|---|---|---|---|---|---|---|---|---|")
    previous = None
    for row in rows:
        slope = ""
        if previous is not None:
            growth = math.log(row["ms/step"] / previous["ms/step"])
            slope = f"{growth / math.log(row['nbeams'] / previous['nbeams']):.2f}"
        print(f"| {row['nbeams']} | {row['dof']} | {row['coordinates']} | {row['D_c band']} "
              f"| {row['saddle band']} | {row['ms/step']:.4f} "
              f"| {row['ms/step'] / base['ms/step']:.2f} | {row['nbeams'] / base['nbeams']:.0f} "
              f"| {slope} |")
        previous = row
    n = np.array([r["nbeams"] for r in rows], dtype=float)
    cost = np.array([r["ms/step"] for r in rows])
    print(f"\nleast-squares log-log slope {np.polyfit(np.log(n), np.log(cost), 1)[0]:.2f} "
          f"(1 = linear growth)")
    if args.plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from matplotlib.ticker import ScalarFormatter

        fig, ax = plt.subplots(figsize=(5, 4))
        ax.loglog(n, cost, "o-", color="C0", label="flexmbd (banded LU)")
        ax.loglog(n, cost[0] * n / n[0], "k--", label="linear growth")
        ax.set_xlabel("beams along the rod")
        ax.set_ylabel("wall time per step [ms]")
        ax.set_title("flexible slider-crank: cost per step")
        ax.legend()
        ax.grid(True, which="both", alpha=0.3)
        for axis in (ax.xaxis, ax.yaxis):
            axis.set_major_formatter(ScalarFormatter())
        fig.tight_layout()
        fig.savefig(args.plot, dpi=120)
        print(f"plot written to {args.plot}")


if __name__ == "__main__":
    main()
