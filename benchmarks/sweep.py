"""Benchmark: parameter studies on Dask (issue 17's targets).

1. Speed-up: 64 cases of EXERCISES 4's flexible slider-crank, 1 to 8 beams times 8 crank
   speeds (100 to 170 rad/s), two revolutions each with the course's integrator (RK45,
   rtol 1e-6, as ode45). ``fm.sweep`` on its default local cluster (one worker per core,
   started and stopped inside the call, as a user runs it) against the serial loop a
   user would write in one process. Also the user's commands: ``flexmbd sweep`` of
   ``slider_crank_flex.dat`` over EI and crank speed (8 x 8 cases) against the same
   command with ``--serial``, each a fresh process.
2. Overhead per case: 2000 cases that do almost nothing (build a one-beam model, keep
   its number of degrees of freedom) on a running local cluster, with the Parquet table
   written as cases finish: ``(wall - sum of case times / workers) / cases``. And the
   fixed cost of the local cluster, its start and stop, shared by a study's cases.

Runs alternate (serial, Dask, serial, ...); the speed-up is the median of the run-by-run
ratios. Run: ``python benchmarks/sweep.py [--repeat 3]``; run nothing else meanwhile.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd
from _tables import table  # benchmarks/_tables.py, beside the script
from flexmbd.examples import EXAMPLES_DIR
from flexmbd.examples import slider_crank_flex as flex

import flexmbd as fm
from flexmbd.studies.cluster import local_client

GRID = {"nbeams": list(range(1, 9)), "omega": [100.0 + 10 * k for k in range(8)]}
OUTPUTS = {"peak": flex.peak_deflection}


def build(nbeams: int, omega: float) -> fm.Model:
    return flex.build_model(nbeams, omega=omega)


def crank_speed(model: fm.Model) -> float:
    """The constant crank speed [rad/s] the model was built with."""
    return float(model.input_laws["x2.1"].v0)


def course_analysis(model: fm.Model) -> fm.SimulationResult:
    """Two revolutions with RK45 at rtol 1e-6 (the course's ode45)."""
    return flex.run(model, 2.0, omega=crank_speed(model), method="RK45", rtol=1e-6)


def serial_loop() -> float:
    """The loop a user writes: every case in this process, one after the other [s]."""
    start = time.perf_counter()
    for case in fm.studies.cases(GRID):
        OUTPUTS["peak"](course_analysis(build(**case)))
    return time.perf_counter() - start


def on_dask() -> tuple[float, object]:
    """``fm.sweep`` on its own local cluster, started and stopped in the call [s]."""
    start = time.perf_counter()
    data = fm.sweep(build, GRID, course_analysis, OUTPUTS)
    return time.perf_counter() - start, data


def command(arguments: list[str]) -> float:
    """Wall time [s] of ``flexmbd ARGUMENTS`` in a fresh process."""
    program = shutil.which("flexmbd", path=str(Path(sys.executable).parent)) or "flexmbd"
    start = time.perf_counter()
    subprocess.run([program, *arguments], check=False, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)
    return time.perf_counter() - start


def speedup(repeat: int, folder: Path) -> list[dict]:
    serial, dask, ratios = [], [], []
    for _ in range(repeat):
        serial.append(serial_loop())
        wall, data = on_dask()
        dask.append(wall)
        ratios.append(serial[-1] / wall)
        assert (data["status"] == "ok").all(), data[data["status"] != "ok"]
    rows = [{"study": "64 cases, fm.sweep vs the serial loop", "serial [s]": np.median(serial),
             "Dask [s]": np.median(dask), "speed-up (median of ratios)": np.median(ratios),
             "sum of case times [s]": float(data["wall_time"].sum())}]
    vary = ["--vary", "ESTIFF:2:2=log:2..100/8", "--vary", "INPUTX:2:3=100..170/8"]
    base = ["sweep", str(EXAMPLES_DIR / "slider_crank_flex.dat"), *vary, "--restart"]
    serial, dask, ratios = [], [], []
    for _ in range(repeat):
        serial.append(command([*base, "--out", str(folder / "s.parquet"), "--serial"]))
        dask.append(command([*base, "--out", str(folder / "d.parquet")]))
        ratios.append(serial[-1] / dask[-1])
    rows.append({"study": "64 cases, flexmbd sweep vs --serial (commands)",
                 "serial [s]": np.median(serial), "Dask [s]": np.median(dask),
                 "speed-up (median of ratios)": np.median(ratios),
                 "sum of case times [s]": float(pd.read_parquet(folder / "d.parquet")
                                                ["wall_time"].sum())})
    return rows


def nothing(model: fm.Model) -> fm.Model:
    return model


def overhead(cases: int, folder: Path) -> list[dict]:
    grid = {"nbeams": [1] * cases}
    outputs = {"dof": lambda model: model.n_dof}
    start = time.perf_counter()
    client = local_client()
    started = time.perf_counter() - start
    workers = len(client.scheduler_info()["workers"])
    try:
        fm.sweep(flex.build_model, {"nbeams": [1] * 8}, nothing, outputs, client)  # warm-up
        start = time.perf_counter()
        data = fm.sweep(flex.build_model, grid, nothing, outputs, client,
                        out=folder / "overhead.parquet", restart=True)
        wall = time.perf_counter() - start
    finally:
        start = time.perf_counter()
        cluster = client.cluster
        client.close()
        cluster.close()
        stopped = time.perf_counter() - start
    work = float(data["wall_time"].sum())
    return [{"cases": cases, "workers": workers, "wall [s]": wall, "sum of case times [s]": work,
             "overhead per case [ms]": 1e3 * (wall - work / workers) / cases,
             "cluster start + stop [s]": started + stopped}]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--cases", type=int, default=2000, help="cases of the overhead run")
    args = parser.parse_args()
    print(f"Python {sys.version.split()[0]}, {os.cpu_count()} cores")
    with tempfile.TemporaryDirectory() as folder:
        print(table(overhead(args.cases, Path(folder))))
        print()
        print(table(speedup(args.repeat, Path(folder))))


if __name__ == "__main__":
    main()
