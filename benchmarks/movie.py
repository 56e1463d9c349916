"""Benchmark: writing a movie of a planar run (issue 48's target: 60 frames of the 8-beam
flexible slider-crank in at most 3 s).

The fast path (:func:`flexmbd.plot.animate` with a filename: the axes, ticks and legend
drawn once, each frame redrawing only the mechanism and its arrows) against
matplotlib's full redraw per frame (:func:`flexmbd.plot.save_animation` of the same
animation), for ``.gif`` and ``.mp4``, taking turns, median of ``--repeat`` runs.

Run: ``python benchmarks/movie.py [--repeat 3]``.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from flexmbd.examples.slider_crank_flex import build_model
from flexure_pivot import _cpu

import flexmbd as fm
from flexmbd import plot


def full_redraw(run, path: Path) -> None:
    """The same picture through matplotlib's FuncAnimation.save (a full draw per frame)."""
    animation = plot.animate(run, None)
    plot.save_animation(animation, path)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    run = fm.simulate(build_model(nbeams=8), np.linspace(0.0, 0.0838, 60))
    print(f"CPU: {_cpu()}; 60 frames of the 8-beam slider-crank, median of {args.repeat}")
    print("| file | fast path [s] | full redraw [s] | ratio |")
    print("|---|---|---|---|")
    with tempfile.TemporaryDirectory() as folder:
        for suffix in (".gif", ".mp4"):
            fast, full = [], []
            for _ in range(args.repeat):
                start = time.perf_counter()
                plot.animate(run, Path(folder) / f"fast{suffix}")
                fast.append(time.perf_counter() - start)
                start = time.perf_counter()
                full_redraw(run, Path(folder) / f"full{suffix}")
                full.append(time.perf_counter() - start)
            ratio = np.median([b / a for a, b in zip(fast, full, strict=True)])
            print(f"| {suffix} | {np.median(fast):.2f} | {np.median(full):.2f} | "
                  f"{ratio:.1f} |")


if __name__ == "__main__":
    main()
