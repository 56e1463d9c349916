"""Benchmark: ``flexmbd.light.run`` as the beams grow, on SPACAR Light's own cross hinge.

SPACAR Light's shipped example (its ``spex.m``: two crossing leaves of 50 x 0.2 mm, warping
on, a 0.1 kg body loaded by a force and a moment over 10 load steps under gravity), its
leaves meshed with ``--beams`` beams each, run as a user runs it: ``light.run(...)`` with
its defaults (every step's equilibrium, frequencies, compliance of every node and largest
stress). Each size runs in a fresh process with one BLAS thread, ``--repeat`` times; the
table gives the medians of the whole ``light.run`` call and its cost relative to the
smallest size.

Run: ``python benchmarks/light_scaling.py [--beams 6 12 24] [--repeat 5]``.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import time

import numpy as np
from flexure_pivot import _cpu


def job(nbeams: int) -> dict[str, float]:
    """SPACAR Light's cross hinge at ``nbeams`` beams per leaf: the wall time [s] of
    ``light.run`` and what it found."""
    from flexmbd.examples import flexures

    from flexmbd import light

    leaf = dict(flexures.HINGE_LEAF, nbeams=nbeams)
    nprops = {1: {"fix": True}, 4: {"fix": True},
              3: {"force": [0, 1, 0], "moment_initial": [0, 0, -0.025],
                  "moment": [0, 0, 0.05], "mass": 0.1}}
    opt = {"silent": True, "gravity": [0, 0, -9.81]}
    start = time.perf_counter()
    res = light.run(flexures.HINGE_NODES, flexures.HINGE_ELEMENTS, nprops,
                    [leaf, flexures.HINGE_BODY], opt)
    return {"run": time.perf_counter() - start, "ndof": res.ndof,
            "f1": float(res.freq[0, -1]), "modes": res.freq.shape[0]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--beams", type=int, nargs="*", default=[6, 12, 24])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--child", type=int, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        print(json.dumps(job(args.child)))
        return
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1",
               MKL_NUM_THREADS="1")
    print(f"CPU: {_cpu()}, Python {platform.python_version()}, one BLAS thread, "
          f"median of {args.repeat}")
    print("| beams per leaf | dof | frequencies | light.run [s] | relative to the first | "
          "f1 at the last step [Hz] |")
    print("|---|---|---|---|---|---|")
    first = None
    for n in args.beams:
        runs = [json.loads(subprocess.run([sys.executable, __file__, "--child", str(n)],
                                          env=env, capture_output=True, text=True,
                                          check=True).stdout) for _ in range(args.repeat)]
        run = float(np.median([r["run"] for r in runs]))
        first = first or run
        print(f"| {n} | {runs[0]['ndof']} | {runs[0]['modes']} | {run:.3f} | "
              f"{run / first:.2f} | {runs[0]['f1']:.4f} |")


if __name__ == "__main__":
    main()
