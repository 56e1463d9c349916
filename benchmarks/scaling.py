"""Benchmark: cost per time step of the flexible slider-crank against the number of beams.

For each number of beams (default 10, 20, 50, 100, 200) along the rod, with a
flexible elongation, it times a short run of the linearly implicit
generalized-alpha method (``--steps`` steps at 800 per turn, the example's
setting; output at every step, included) and reports the cost per step, its
ratio to the smallest model's and the local log-log slope between successive
sizes (1: linear growth). Models past ``flexmbd.factor.SPARSE_SIZE`` unknowns use
the sparse backend (SuperLU), which the table names. A log-log plot goes to
``--plot`` (matplotlib).

Run: ``python benchmarks/scaling.py [--nbeams 10 20 50 100 200] [--plot scaling.png]``.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
from flexmbd.examples import slider_crank_flex as example


def cost_per_step(nbeams: int, steps: int, repeat: int) -> dict:
    """Median wall time per step [ms] of ``steps`` steps (model building excluded)."""
    model = example.build_model(nbeams, eps1flex=True)
    revolutions = steps / example.STEPS_PER_REVOLUTION
    walls = []
    for _ in range(repeat):
        start = time.perf_counter()
        result = example.run(model, revolutions, progress=False)
        walls.append(time.perf_counter() - start)
    if not result.success:
        raise SystemExit(f"{nbeams} beams: {result.message}")
    nsteps = result.stats["nsteps"]
    return {"nbeams": nbeams, "dof": model.n_dof, "coordinates": model.n_coordinates,
            "backend": "sparse" if model.assembly.sparse else "dense", "steps": nsteps,
            "ms/step": 1e3 * float(np.median(walls)) / nsteps}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--nbeams", type=int, nargs="+", default=[10, 20, 50, 100, 200])
    parser.add_argument("--steps", type=int, default=200, help="steps per run (default 200)")
    parser.add_argument("--repeat", type=int, default=3, help="runs per size (median)")
    parser.add_argument("--plot", metavar="FILE.png", help="write a log-log plot")
    args = parser.parse_args()
    rows = []
    for nbeams in args.nbeams:
        rows.append(cost_per_step(nbeams, args.steps, args.repeat))
        print(f"  {nbeams} beams: {rows[-1]['ms/step']:.3f} ms per step", flush=True)
    base = rows[0]
    print(f"\nflexible slider-crank, flexible elongation, {args.steps} steps "
          f"(800 per turn, linearly implicit generalized-alpha), median of {args.repeat}\n")
    print("| beams | DOF | coordinates | backend | ms per step | per step / smallest "
          "| beams / smallest | local slope |")
    print("|---|---|---|---|---|---|---|---|")
    previous = None
    for row in rows:
        slope = ""
        if previous is not None:
            slope = (math.log(row["ms/step"] / previous["ms/step"])
                     / math.log(row["nbeams"] / previous["nbeams"]))
            slope = f"{slope:.2f}"
        print(f"| {row['nbeams']} | {row['dof']} | {row['coordinates']} | {row['backend']} "
              f"| {row['ms/step']:.3f} | {row['ms/step'] / base['ms/step']:.2f} "
              f"| {row['nbeams'] / base['nbeams']:.0f} | {slope} |")
        previous = row
    n = np.array([r["nbeams"] for r in rows], dtype=float)
    cost = np.array([r["ms/step"] for r in rows])
    overall = np.polyfit(np.log(n), np.log(cost), 1)[0]
    print(f"\nleast-squares log-log slope {overall:.2f} (1 = linear growth)")
    if args.plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from matplotlib.ticker import ScalarFormatter

        fig, ax = plt.subplots(figsize=(5, 4))
        ax.loglog(n, cost, "-", color="C0")
        for backend, marker in (("dense", "o"), ("sparse", "s")):
            pick = np.array([r["backend"] == backend for r in rows])
            if pick.any():
                ax.loglog(n[pick], cost[pick], marker, color="C0", label=f"flexmbd ({backend})")
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
