"""Benchmark: the linearized analyses (issue 15's targets).

1. Eigenfrequencies of 200-beam models: a clamped column of 200 second-order beams
   (600 degrees of freedom) at rest, and the parallel leaf-spring guide of
   ``flexmbd example parallel-guide`` with 100 beams per leaf under its payload
   (static equilibrium first). Timed through the API (``linearize`` or
   ``static_equilibrium`` and ``vibration_modes``, model building excluded) and as
   the user's command ``flexmbd modes FILE.dat`` in a fresh process (start-up,
   imports, reading the file, the analysis and the table included).
2. 100 configurations along a motion: EXERCISES 4's slider-crank with flexible
   elongation and 8, 16, 32 beams, its nominal revolution (``inverse_dynamics``) and
   ``modes_along``; and the user's command ``flexmbd example slider-crank-modes``.

Each time is the median of ``--repeat`` runs. Run: ``python benchmarks/linearized.py``;
run nothing else meanwhile.
"""

from __future__ import annotations

import argparse
import platform
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from _tables import table  # benchmarks/_tables.py, beside the script
from flexmbd.examples import parallel_guide, slider_crank_flex

import flexmbd as fm


def median_time(work, repeat: int) -> tuple[float, object]:
    """Median wall time [s] of ``repeat`` calls of ``work()`` and the last result."""
    walls, result = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        result = work()
        walls.append(time.perf_counter() - start)
    return float(np.median(walls)), result


def column(nbeams: int) -> fm.Model:
    """A column of ``nbeams`` second-order steel beams (1 m), clamped at node 1, all
    deformations flexible."""
    b = fm.ModelBuilder(f"column of {nbeams} beams")
    for k in range(nbeams + 1):
        b.add_node(2 * k + 1, k / nbeams, 0.0)
    for k in range(nbeams):
        b.add_beam(k + 1, 2 * k + 1, 2 * k + 2, 2 * k + 3, 2 * k + 4, second_order=True)
        b.dynamic_deformation(k + 1, 1, 2, 3)
        b.set_stiffness(k + 1, axial=2.1e8, bending=175.0).set_mass(k + 1, 7.85)
    return b.fix(1).fix(2).build()


def command_time(arguments: list[str], repeat: int) -> float:
    """Median wall time [s] of ``flexmbd ARGUMENTS`` in a fresh process."""
    program = shutil.which("flexmbd", path=str(Path(sys.executable).parent)) or "flexmbd"

    def work():
        subprocess.run([program, *arguments], check=True, stdout=subprocess.DEVNULL)
    return median_time(work, repeat)[0]


def eigenfrequencies(repeat: int, folder: Path) -> list[dict]:
    """Target 1: the 200-beam models."""
    model, guide = column(200), parallel_guide.build_model(100)

    def at_rest():
        return fm.vibration_modes(fm.linearize(model), 6)

    def loaded():
        return fm.vibration_modes(fm.static_equilibrium(guide).linearization(0), 6)

    cases = [("column, 200 beams, at rest", model, at_rest, "column200.dat"),
             ("parallel guide, 2 x 100 beams, payload", guide, loaded, "guide200.dat")]
    rows = []
    for name, case, work, filename in cases:
        wall, modes = median_time(work, repeat)
        fm.write_dat(case, folder / filename)
        rows.append({"model": name, "dof": case.n_dof, "API [s]": wall,
                     "command [s]": command_time(["modes", str(folder / filename)], repeat),
                     "f1 [Hz]": modes.frequencies[0]})
    return rows


def along_a_motion(repeat: int, beams: list[int]) -> list[dict]:
    """Target 2: 100 configurations of the flexible slider-crank's revolution."""
    rows = []
    for nbeams in beams:
        model = slider_crank_flex.build_model(nbeams, eps1flex=True)
        times = np.linspace(0.0, 2 * np.pi / slider_crank_flex.OMEGA, 100)

        def work(model=model, times=times):
            return fm.modes_along(fm.inverse_dynamics(model, times), 6)
        wall, along = median_time(work, repeat)
        command = ["example", "slider-crank-modes", "--nbeams", str(nbeams), "--eps1flex",
                   "--points", "100", "--count", "6"]
        rows.append({"model": f"slider-crank, {nbeams} beams, flexible elongation",
                     "dof": model.n_dof, "API [s]": wall,
                     "command [s]": command_time(command, repeat),
                     "f1 [Hz]": f"{along.frequencies[:, 0].min():.4g} to "
                                f"{along.frequencies[:, 0].max():.4g}"})
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=5, help="runs per case (median)")
    parser.add_argument("--nbeams", type=int, nargs="+", default=[8, 16, 32],
                        help="beams of the slider-crank's rod")
    args = parser.parse_args()
    print(f"Python {platform.python_version()}, numpy {np.__version__}, "
          f"median of {args.repeat} runs\n")
    with tempfile.TemporaryDirectory() as folder:
        print("Eigenfrequencies (6 lowest) of 200-beam models (target < 0.5 s):\n")
        print(table(eigenfrequencies(args.repeat, Path(folder))))
    print("\n100 configurations along a revolution, 6 frequencies each (target < 2 s):\n")
    print(table(along_a_motion(args.repeat, args.nbeams)))


if __name__ == "__main__":
    main()
