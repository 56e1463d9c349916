"""Benchmark: the flexible slider-crank of EXERCISES 4 of planar and of spatial elements
on the same engine (issue 20's target: the spatial model within 2 times the planar).

For each number of beams it times ``flexmbd.simulate`` of the planar model
(:mod:`flexmbd.examples.slider_crank_flex`) and of the same mechanism of spatial beams
and hinges (:mod:`flexmbd.examples.slider_crank_flex_spatial`, bending-linked terms on,
as SPACAR's ``BEAM``) over two revolutions with the example's default integration
(generalized-alpha, 400 steps per turn), ``--repeat`` runs each taking turns, model
building excluded. It prints a Markdown table with the median times, the median of the
run-by-run ratios, the model sizes, and
the largest midpoint deflection of each (they agree to the bending-linked terms' order).

Run: ``python benchmarks/spatial_slider_crank.py [--nbeams 2 8] [--repeat 7]``. Numbers
depend on the machine; run nothing else meanwhile.
"""

from __future__ import annotations

import argparse
import platform
import time

import numpy as np
from _tables import table  # benchmarks/_tables.py, beside the script
from flexmbd.examples import slider_crank_flex as planar
from flexmbd.examples import slider_crank_flex_spatial as spatial

import flexmbd as fm


def timed_pairs(models: dict[str, fm.Model], repeat: int):
    """``repeat`` runs of two revolutions of each model, taking turns run by run (the
    machine's speed drifts): the wall times by model, the run-by-run ratios spatial /
    planar, and each model's last run."""
    walls: dict[str, list[float]] = {name: [] for name in models}
    results = {}
    for _ in range(repeat):
        for name, model in models.items():
            start = time.perf_counter()
            results[name] = planar.run(model, 2.0)
            walls[name].append(time.perf_counter() - start)
    ratios = np.array(walls["spatial"]) / np.array(walls["planar"])
    return walls, ratios, results


def largest_deflection(model: fm.Model, result: fm.SimulationResult, nbeams: int) -> float:
    """The rod's largest midpoint deflection over the run [m]: the deflection of its middle
    node from the chord (even ``nbeams``)."""
    positions, _ = planar.rod_nodes(nbeams)
    middle, ends = positions[nbeams // 2], (positions[0], positions[-1])
    def xy(node):
        return np.stack([result[f"x{node}.1"], result[f"x{node}.2"]], axis=1)
    a, b, m = xy(ends[0]), xy(ends[1]), xy(middle)
    chord = (b - a) / np.linalg.norm(b - a, axis=1)[:, None]
    offset = m - a
    return float(np.max(np.abs(offset[:, 0] * chord[:, 1] - offset[:, 1] * chord[:, 0])))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--nbeams", type=int, nargs="+", default=[2, 8])
    parser.add_argument("--repeat", type=int, default=7, help="runs per case (best time)")
    args = parser.parse_args()
    rows = []
    for nbeams in args.nbeams:
        models = {"planar": planar.build_model(nbeams), "spatial": spatial.build_model(nbeams)}
        walls, ratios, results = timed_pairs(models, args.repeat)
        rows.append({
            "nbeams": nbeams,
            "planar nx": models["planar"].n_coordinates,
            "spatial nx": models["spatial"].n_coordinates,
            "planar [s]": float(np.median(walls["planar"])),
            "spatial [s]": float(np.median(walls["spatial"])),
            "ratio (median of pairs)": float(np.median(ratios)),
            "steps": results["spatial"].stats["nsteps"],
            **{f"{name} max v [m]": largest_deflection(models[name], results[name], nbeams)
               for name in models},
        })
    print(f"flexmbd {fm.__version__}, Python {platform.python_version()}, "
          f"{platform.machine()}; medians of {args.repeat} runs taking turns")
    print(table(rows))


if __name__ == "__main__":
    main()
