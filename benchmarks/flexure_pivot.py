"""Benchmark: issue 37's flexure job, flexmbd's side.

A spatial cross-spring pivot turned to 0.3 rad in 20 load steps, and at every step the
equilibrium, the first six frequencies with the stage's mass and the stage's 6x6
compliance. Two steel leaves, L = 0.1 m, 30 x 0.5 mm, cross at their middles at 90
degrees, side by side along the pivot axis (y), clamped below; a rigid 0.25 kg stage
across their tops is turned by a moment about the axis (``2 EI/L`` times 0.3 rad).
Over-constraints are released as SPACAR Light does.

Each configuration runs in a fresh process with one BLAS thread, ``--repeat`` times,
paired with Exudyn's side of the same job (``exudyn_pivot.py``: geometrically exact beams
on ``NodeRigidBodyRxyz``, its tangent by central differences of its static residual, and
for reference with its own, inexact, Jacobian) and OpenSees's (``opensees_pivot.py``:
force-based corotational beams, frequencies and compliance from its exact tangent), the
runs alternating. The table gives the
medians of the whole processes and of flexmbd's parts: building (with the releases), the
static equilibrium over the steps, and the per-step table
(:func:`flexmbd.load_step_table`); ``--alone`` sizes run flexmbd only (the growth with the
beams).

Run: ``python benchmarks/flexure_pivot.py [--beams 8 16 32] [--alone 64 128]
[--repeat 3] [--door table|per-step]``.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import subprocess
import sys
import time

import numpy as np

LENGTH, WIDTH, THICKNESS, GAP = 0.1, 0.03, 0.5e-3, 0.04   #: [m]
STAGE_MASS, ROTATION, STEPS = 0.25, 0.3, 20
E = 210e9   #: steel [Pa]


def build_pivot(nbeams: int, thickness: float = THICKNESS, width: float = WIDTH,
                length: float = LENGTH, stage_mass: float = STAGE_MASS):
    """The pivot (module docstring) with ``nbeams`` beams per leaf, its over-constraints
    released; dimensions [m], mass [kg]."""
    import flexmbd as fm

    steel = fm.Material.from_poisson(E, 0.3, 7800.0)
    leaf = fm.Rectangle(width, thickness)
    b = fm.ModelBuilder("cross-spring pivot")
    h = length / math.sqrt(2)
    b.add_node(1, -h / 2, 0, 0).add_node(3, h / 2, 0, h)
    b.add_node(5, h / 2, GAP, 0).add_node(7, -h / 2, GAP, h)
    b.add_spatial_beams(1, 1, 2, 3, 4, nbeams, (0, 1, 0), new_nodes=1000, section=leaf,
                        material=steel)
    b.add_spatial_beams(201, 5, 6, 7, 8, nbeams, (0, 1, 0), new_nodes=2000, section=leaf,
                        material=steel)
    b.add_node(9, 0, GAP / 2, h)
    b.add_spatial_beam(401, 3, 4, 9, 10, (0, 0, 1)).add_spatial_beam(402, 9, 10, 7, 8,
                                                                     (0, 0, 1))
    b.fix(1).fix(2).fix(5).fix(6)
    b.add_point_mass(9, stage_mass).add_rotary_inertia(10, 1e-4, 0, 0, 1e-4, 0, 1e-4)
    b.release_overconstraints()
    return b.build()


def turning_moment(rotation: float, thickness: float = THICKNESS, width: float = WIDTH,
                   length: float = LENGTH) -> float:
    """The moment [N m] that turns the pivot by about ``rotation`` [rad] at its small-angle
    stiffness ``2 EI/L``."""
    return rotation * 2 * E * width * thickness**3 / 12 / length


def job(nbeams: int, door: str = "table") -> dict[str, float]:
    """The job at ``nbeams`` beams per leaf, its linearized analyses through ``door``:
    ``"table"`` (:func:`flexmbd.load_step_table`) or ``"per-step"`` (a loop over the
    steps with the public analyses, as the linearized-analyses guide writes it); wall
    times [s] of its parts."""
    start = time.perf_counter()
    import flexmbd as fm

    imported = time.perf_counter()
    model = build_pivot(nbeams)
    built = time.perf_counter()
    stiffness = turning_moment(1.0)
    statics = fm.static_equilibrium(model, load_increment={"x10.3": ROTATION * stiffness},
                                    steps=STEPS, progress=False)
    solved = time.perf_counter()
    if door == "table":
        table = fm.load_step_table(statics, modes=6, compliance=[(9, 10)], progress=False)
        f1 = float(table["f1"][-1])
    else:
        for row in range(len(statics.load)):
            lin = statics.linearization(row)
            f1 = float(fm.vibration_modes(lin, 6).frequencies[0])
            fm.node_compliance(lin, 9, 10)
    done = time.perf_counter()
    return {"import": imported - start, "build": built - imported, "statics": solved - built,
            "table": done - solved, "compute": done - imported, "dof": model.n_dof,
            "f1": f1, "angle": 2 * math.asin(statics["x10.3"][-1])}


def _cpu() -> str:
    """The CPU's model name, family and model (``/proc/cpuinfo``), else the platform's."""
    try:
        with open("/proc/cpuinfo") as info:
            fields = dict(line.split(":", 1) for line in info if ":" in line)
    except OSError:
        return platform.processor() or platform.machine()
    get = {key.strip(): value.strip() for key, value in fields.items()}.get
    return f"{get('model name', '?')} (family {get('cpu family', '?')}, model {get('model', '?')})"


def _process(command: list[str], env: dict[str, str]) -> dict[str, float]:
    """One fresh process's JSON report and its wall time [s]."""
    start = time.perf_counter()
    out = subprocess.run(command, env=env, capture_output=True, text=True, check=True)
    # the report's line (OpenSees adds its own lines to stdout)
    found = json.loads(next(line for line in out.stdout.splitlines() if line.startswith("{")))
    found["process"] = time.perf_counter() - start
    return found


def _median(runs: list[dict[str, float]]) -> dict[str, float]:
    return {key: float(np.median([r[key] for r in runs])) for key in runs[0]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--beams", type=int, nargs="*", default=[8, 16, 32])
    parser.add_argument("--alone", type=int, nargs="*", default=[64, 128])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--door", choices=("table", "per-step"), default="table",
                        help="flexmbd's linearized analyses: load_step_table, or the "
                             "public analyses step by step")
    parser.add_argument("--child", type=int, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        print(json.dumps(job(args.child, args.door)))
        return
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1",
               MKL_NUM_THREADS="1")
    peer = os.path.join(os.path.dirname(os.path.abspath(__file__)), "exudyn_pivot.py")
    opensees = os.path.join(os.path.dirname(os.path.abspath(__file__)), "opensees_pivot.py")
    print(f"CPU: {_cpu()}, Python "
          f"{platform.python_version()}, one BLAS thread, median of {args.repeat}, "
          f"flexmbd's door: {args.door}")
    print("| beams per leaf | flexmbd [s] | Exudyn [s] | ratio (run by run; of medians) | "
          "Exudyn, own Jacobian [s] | OpenSees [s] | ratio to OpenSees (run by run; of "
          "medians) | flexmbd build / statics / table [s] | f1 flexmbd / Exudyn / OpenSees "
          "[Hz] |")
    print("|---|---|---|---|---|---|---|---|---|")
    for n in args.beams:
        ours, theirs, own, third = [], [], [], []
        for _ in range(args.repeat):
            ours.append(_process([sys.executable, __file__, "--child", str(n), "--door",
                                  args.door], env))
            theirs.append(_process([sys.executable, peer, "--beams", str(n)], env))
            own.append(_process([sys.executable, peer, "--beams", str(n), "--own-tangent"],
                                env))
            third.append(_process([sys.executable, opensees, "--beams", str(n)], env))
        a, b, c, d = _median(ours), _median(theirs), _median(own), _median(third)
        paired = np.median([o["process"] / t["process"] for o, t in zip(ours, theirs,
                                                                          strict=True)])
        against = np.median([o["process"] / t["process"] for o, t in zip(ours, third,
                                                                           strict=True)])
        print(f"| {n} | {a['process']:.3f} | {b['process']:.3f} | "
              f"{paired:.2f}; {a['process'] / b['process']:.2f} | {c['process']:.3f} | "
              f"{d['process']:.3f} | {against:.2f}; {a['process'] / d['process']:.2f} | "
              f"{a['build']:.3f} / {a['statics']:.3f} / {a['table']:.3f} | "
              f"{a['f1']:.4f} / {b['f1']:.4f} / {d['f1']:.4f} |")
    if args.alone:
        print()
        print("| beams per leaf | dof | process [s] | build [s] | statics [s] | table [s] | "
              "f1 [Hz] |")
        print("|---|---|---|---|---|---|---|")
    for n in args.alone:
        a = _median([_process([sys.executable, __file__, "--child", str(n), "--door",
                                  args.door], env)
                     for _ in range(args.repeat)])
        print(f"| {n} | {int(a['dof'])} | {a['process']:.3f} | {a['build']:.3f} | "
              f"{a['statics']:.3f} | {a['table']:.3f} | {a['f1']:.4f} |")


if __name__ == "__main__":
    main()
