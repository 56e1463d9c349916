"""Benchmark: ``simulate``'s default integrator against fixed generalized-alpha steps, on a
four-bar with a flexible coupler.

The crank (0.1 m, rigid, massless) turns at 2 rev/s about the origin; the coupler (0.35 m)
is four beams of 6 mm round steel whose bending is dynamic; the rocker (0.3 m, rigid, of
the same rod) turns about (0.3, 0); 1 s, 2001 outputs. The coupler's lowest bending mode is
near 100 Hz, its highest near 8 kHz: a hundred periods of free vibration ride on the
motion, and explicit methods must resolve the fastest mode.

The error is that of the coupler's mid-point deflection from its chord, its largest
deviation from a reference over the second relative to its largest value. The reference is
SciPy's DOP853 at rtol 1e-10 (resolving every mode; about 40 s); fixed generalized-alpha
steps converge to it at second order (1e-5 s: 0.25 %). The defaults and the largest
fixed step within 2.6 % then take turns ``--repeat`` times in this process (one BLAS
thread); the medians and the median of the run-by-run ratios are printed.

Run: ``python benchmarks/flexible_four_bar.py [--repeat 5]``.
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np
from flexure_pivot import _cpu

import flexmbd as fm

GROUND, CRANK, COUPLER, ROCKER = 0.3, 0.1, 0.35, 0.3  #: lengths [m]
E, RADIUS, DENSITY = 2.1e11, 0.003, 7850.0  #: steel rod of 6 mm [Pa, m, kg/m^3]
SPEED = 4 * math.pi  #: crank speed [rad/s] (2 rev/s)
NBEAMS = 4
TIMES = np.linspace(0.0, 1.0, 2001)
MIDDLE = 9  #: the coupler's middle node (of four beams)


def build(nbeams: int = NBEAMS) -> fm.Model:
    """The four-bar, crank upright at t = 0, coupler straight."""
    a, d = np.array([0.0, CRANK]), np.array([GROUND, 0.0])
    chord = np.linalg.norm(d - a)
    along = (COUPLER**2 - ROCKER**2 + chord**2) / (2 * chord)
    u = (d - a) / chord
    b_point = a + along * u + math.sqrt(COUPLER**2 - along**2) * np.array([-u[1], u[0]])
    area, inertia = math.pi * RADIUS**2, math.pi * RADIUS**4 / 4
    b = fm.ModelBuilder("flexible four-bar")
    b.add_node(1, 0.0, 0.0).add_node(3, *a).add_node(20, *d).add_node(5, *b_point)
    b.add_rigid_beam(1, 1, 2, 3)
    positions = [3, *(7 + 2 * k for k in range(nbeams - 1)), 5]
    angles = [4, *(8 + 2 * k for k in range(nbeams - 1)), 6]
    for k in range(1, nbeams):
        b.add_node(positions[k], *(a + (b_point - a) * k / nbeams))
    for k in range(nbeams):
        b.add_beam(k + 2, positions[k], angles[k], positions[k + 1], angles[k + 1])
        b.set_mass(k + 2, DENSITY * area)
        b.set_stiffness(k + 2, axial=E * area, bending=E * inertia)
        b.dynamic_deformation(k + 2, 2, 3)
    b.add_rigid_beam(nbeams + 2, 20, 21, 5).set_mass(nbeams + 2, DENSITY * area)
    b.fix(1).fix(20)
    b.input_coordinate(2, law=fm.Polynomial(math.pi / 2, SPEED))
    return b.build()


def deflection(model: fm.Model, x: np.ndarray) -> np.ndarray:
    """The coupler's mid-point deflection from its chord [m], ``(nt,)``."""
    ends = [x[:, list(model.nodes[n].coordinates)] for n in (3, 5, MIDDLE)]
    chord = ends[1] - ends[0]
    normal = np.stack([-chord[:, 1], chord[:, 0]], axis=1) / np.linalg.norm(
        chord, axis=1)[:, None]
    return np.einsum("ij,ij->i", ends[2] - ends[0], normal)


def timed(model: fm.Model, **options) -> tuple[float, fm.SimulationResult]:
    """The wall time [s] of one simulation and its result."""
    start = time.perf_counter()
    result = fm.simulate(model, TIMES, outputs="positions", **options)
    return time.perf_counter() - start, result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    model = build()
    print(f"CPU: {_cpu()}, Python {platform.python_version()}, one BLAS thread")
    start = time.perf_counter()
    reference = deflection(model, fm.simulate(model, TIMES, method="DOP853", rtol=1e-10,
                                              atol=1e-14, outputs="positions").x)
    print(f"reference (DOP853, rtol 1e-10): {time.perf_counter() - start:.1f} s, largest "
          f"deflection {np.abs(reference).max():.3g} m, lowest mode "
          f"{fm.vibration_modes(model, 1).frequencies[0]:.4g} Hz")

    def error(result: fm.SimulationResult) -> float:
        return float(np.abs(deflection(model, result.x) - reference).max()
                     / np.abs(reference).max())

    print("| run | steps | wall, one run [s] | error |\n|---|---:|---:|---:|")
    runs = {"simulate() defaults": {}} | {
        f"GeneralizedAlpha, step {h:g} s": {"method": "GeneralizedAlpha", "step": h}
        for h in (1e-4, 8e-5, 6e-5, 5e-5, 4e-5, 2e-5)}
    errors = {}
    for name, options in runs.items():
        seconds, result = timed(model, **options)
        errors[name] = error(result)
        print(f"| {name} | {result.stats['nsteps']} | {seconds:.3f} | "
              f"{100 * errors[name]:.2f} % |")
    # the largest fixed step within 2.6 % (the generalized-alpha reference point),
    # then the defaults and it taking turns
    fixed = next(name for name in list(runs)[1:] if errors[name] <= 0.026)
    pairs = [(timed(model)[0], timed(model, **runs[fixed])[0]) for _ in range(args.repeat)]
    ratios = sorted(default / step for default, step in pairs)
    defaults, steps = zip(*pairs, strict=True)
    print(f"\n{args.repeat} rounds, the defaults and '{fixed}' taking turns: medians "
          f"{np.median(defaults):.3f} s and {np.median(steps):.3f} s; defaults / fixed "
          f"{np.median(ratios):.2f} run by run ({np.median(defaults) / np.median(steps):.2f} "
          f"of the medians; target <= 3); the defaults' error "
          f"{100 * errors['simulate() defaults']:.2f} % (target <= 5 %)")


if __name__ == "__main__":
    main()
