"""Benchmark: design sensitivities and optimisation (:mod:`flexmbd.design`).

1. **Cost of the gradients.** The cross-spring pivot of the flexure benchmark
   (``flexure_pivot.py``: two steel leaves, a 0.25 kg stage turned 0.3 rad by a moment in
   20 load steps) at ``--beams`` beams per leaf, five parameters (thickness, width,
   length, stage mass, the turn) and eight outputs (three frequencies, three compliance
   entries, the stage's rotation, the largest stress): ``evaluate(..., gradient=False)``
   against ``gradient=True``, median of ``--repeat`` runs.
2. **Accuracy.** The same gradients against central differences of the analyses
   (relative steps 2e-2, 1e-2 and 5e-3, extrapolated twice by Richardson; Newton
   tolerance 5e-14 m).
3. **Optimisation.** A parallel leaf-spring guide (two steel leaves, 20 mm wide, a
   stage driven 4 mm across them): the stiffest support along the leaves (the stage's
   compliance along z) with its largest stress at most 300 MPa and its drive force at
   most 5 N, over the leaves' thickness and length (0.1-3 mm, 30-200 mm).
   ``design.optimize`` (SLSQP on the exact gradients) against SciPy's SLSQP on
   two-point finite differences of ``evaluate(gradient=False)``; the true optimum (the
   length at its bound, the drive force at its limit) from a root search on the
   analyses alone.

4. **The floor under the cost.** One call of the pivot's build against one whole
   analysis, taking turns (at least 7): every parameter's data derivative needs at
   least one build.

Run: ``python benchmarks/design_gradients.py [--beams 8 32] [--repeat 3]``.
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from flexure_pivot import _cpu, build_pivot, turning_moment

import flexmbd as fm
from flexmbd import design

OUTPUTS = ["f1", "f2", "f3", "C[9,10][4,4]", "C[9,10][2,2]", "C[9,10][0,4]", "x10.3",
           "stress_max"]
PARAMS = {"t": 0.5e-3, "w": 0.03, "L": 0.1, "mass": 0.25, "turn": 0.3}


def pivot(t, w, L, mass, turn, beams=8, tolerance=None):
    """The flexure benchmark's pivot with its dimensions as parameters."""
    model = build_pivot(beams, thickness=t, width=w, length=L, stage_mass=mass)
    moment = turning_moment(turn, thickness=t, width=w, length=L)
    return model, fm.RunSettings(load_increment={"x10.3": moment}, load_steps=20,
                                 tolerance=tolerance)


def parallel_guide(t=0.3e-3, L=0.06, w=0.02, gap=0.04, stroke=4e-3, beams=8):
    """Two steel leaves (``w`` x ``t``, length ``L``, upright along z, thin along x)
    ``gap`` apart along x; a rigid stage across their tops driven ``stroke`` along x."""
    steel = fm.Material.from_poisson(210e9, 0.3, 7800.0)
    leaf = fm.Rectangle(w, t)
    b = fm.ModelBuilder("parallel guide")
    b.add_node(1, 0, 0, 0).add_node(3, 0, 0, L).add_node(5, gap, 0, 0).add_node(7, gap, 0, L)
    b.add_spatial_beams(1, 1, 2, 3, 4, beams, (0, 1, 0), new_nodes=1000, section=leaf,
                        material=steel)
    b.add_spatial_beams(101, 5, 6, 7, 8, beams, (0, 1, 0), new_nodes=2000, section=leaf,
                        material=steel)
    b.add_node(9, gap / 2, 0, L)
    b.add_spatial_beam(201, 3, 4, 9, 10, (0, 1, 0)).add_spatial_beam(202, 9, 10, 7, 8,
                                                                     (0, 1, 0))
    b.fix(1).fix(2).fix(5).fix(6).input_coordinate(9, 1)
    b.add_point_mass(9, 0.1)
    b.release_overconstraints()
    return b.build(), fm.RunSettings(input_increment={"x9.1": stroke}, load_steps=4)


def cost(beams: int, repeat: int) -> dict[str, float]:
    build = lambda **p: pivot(**p, beams=beams)  # noqa: E731
    design.evaluate(build, PARAMS, OUTPUTS)       # warm: kernels, imports
    plain, full, parts = [], [], []
    for _ in range(repeat):
        start = time.perf_counter()
        design.evaluate(build, PARAMS, OUTPUTS, gradient=False)
        plain.append(time.perf_counter() - start)
        start = time.perf_counter()
        r = design.evaluate(build, PARAMS, OUTPUTS)
        full.append(time.perf_counter() - start)
        parts.append(r.wall["gradient"])
    return {"analysis": float(np.median(plain)), "with": float(np.median(full)),
            "gradient": float(np.median(parts))}


def accuracy(beams: int) -> list[tuple[float, float, str]]:
    """Per output and parameter: the exact gradient's relative difference from the
    central differences, the differences' own spread (between their two first-level
    extrapolations), and the pair's name; worst first."""
    build = lambda **p: pivot(**p, beams=beams)  # noqa: E731
    tight = lambda **p: pivot(**p, beams=beams, tolerance=5e-14)  # noqa: E731
    found = design.evaluate(build, PARAMS, OUTPUTS)
    exact = found.gradient
    rows = []
    for name, value in PARAMS.items():
        estimates = []
        # steps large enough that the analyses' rounding (5e-10 of a compliance) stays
        # below 1e-7 of a difference; two Richardson levels take the h^2 and h^4 errors
        for rel in (2e-2, 1e-2, 5e-3):
            h = rel * value
            sides = [design.evaluate(tight, {**PARAMS, name: value + s * h}, OUTPUTS,
                                     gradient=False).values for s in (-1.0, 1.0)]
            estimates.append({k: (sides[1][k] - sides[0][k]) / (2 * h) for k in OUTPUTS})
        for k in OUTPUTS:
            first = [(4 * estimates[i + 1][k] - estimates[i][k]) / 3 for i in (0, 1)]
            reference = (16 * first[1] - first[0]) / 15
            # a derivative that vanishes (the stage mass's of a stress) against the
            # output's own scale
            scale = max(abs(reference), 1e-4 * abs(found.values[k]) / abs(value))
            rows.append((abs(exact[k][name] - reference) / scale,
                         abs(first[0] - first[1]) / scale, f"{k} / {name}"))
    return sorted(rows, reverse=True)


def optimisation() -> dict[str, dict[str, float]]:
    from scipy.optimize import brentq, minimize

    start, limits = {"t": 0.3e-3, "L": 0.06}, {"stress_max": (None, 300e6),
                                               "f9.1": (None, 5.0)}
    bounds = {"t": (0.1e-3, 3e-3), "L": (0.03, 0.2)}
    began = time.perf_counter()
    ours = design.optimize(parallel_guide, start, "C[9,10][2,2]", constraints=limits,
                           bounds=bounds)
    ours_time = time.perf_counter() - began
    # the true optimum: the length at its bound, the drive force at its limit
    force = lambda t: design.evaluate(parallel_guide, {"t": t, "L": 0.2}, "f9.1",  # noqa
                                      gradient=False).values["f9.1"] - 5.0
    true_t = brentq(force, 0.3e-3, 3e-3, xtol=1e-16, rtol=1e-15)
    # SciPy's SLSQP on finite differences of the analyses, scaled alike
    names, scale = list(start), np.array(list(start.values()))
    calls = {"n": 0}

    def values(u):
        calls["n"] += 1
        return design.evaluate(parallel_guide, dict(zip(names, u * scale, strict=True)),
                               ["C[9,10][2,2]", "stress_max", "f9.1"], gradient=False).values

    first = values(np.ones(2))["C[9,10][2,2]"]
    began = time.perf_counter()
    fd = minimize(lambda u: values(u)["C[9,10][2,2]"] / first, np.ones(2), method="SLSQP",
                  bounds=[(b[0] / s, b[1] / s) for b, s in zip(bounds.values(), scale,
                                                                strict=True)],
                  constraints=[{"type": "ineq", "fun": lambda u: 1 - values(u)["stress_max"]
                                / 300e6},
                               {"type": "ineq", "fun": lambda u: 1 - values(u)["f9.1"] / 5.0}],
                  tol=1e-10, options={"maxiter": 100})
    fd_time = time.perf_counter() - began
    return {"exact": {"t": ours.x["t"], "L": ours.x["L"], "analyses": ours.nfev,
                      "seconds": ours_time, "success": ours.success},
            "differences": {"t": fd.x[0] * scale[0], "L": fd.x[1] * scale[1],
                            "analyses": calls["n"] - 1, "seconds": fd_time,
                            "success": fd.success},
            "true": {"t": true_t, "L": 0.2}}


def build_share(beams: int, repeat: int) -> tuple[float, float, float]:
    """One call of the pivot's build and one whole ``evaluate(..., gradient=False)``
    (which includes a build), taking turns: their medians and the median of their
    run-by-run ratios. The data's derivatives need at least one build per parameter."""
    build = lambda **p: pivot(**p, beams=beams)  # noqa: E731
    design.evaluate(build, PARAMS, OUTPUTS, gradient=False)
    builds, analyses = [], []
    for _ in range(repeat):
        start = time.perf_counter()
        build(**PARAMS)
        builds.append(time.perf_counter() - start)
        start = time.perf_counter()
        design.evaluate(build, PARAMS, OUTPUTS, gradient=False)
        analyses.append(time.perf_counter() - start)
    ratio = float(np.median([b / a for b, a in zip(builds, analyses, strict=True)]))
    return float(np.median(builds)), float(np.median(analyses)), ratio


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--beams", type=int, nargs="*", default=[8, 32])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    print(f"CPU: {_cpu()}, Python {platform.python_version()}, "
          f"BLAS threads {os.environ.get('OPENBLAS_NUM_THREADS', 'default')}, median of "
          f"{args.repeat}")
    print("| beams per leaf | evaluate, no gradient [s] | with 8 x 5 gradients [s] | "
          "ratio | gradients alone / analysis | worst three differences from central "
          "differences (their spread) |")
    print("|---|---|---|---|---|---|")
    for beams in args.beams:
        c = cost(beams, args.repeat)
        worst = "; ".join(f"{name} {err:.1e} ({spread:.1e})"
                          for err, spread, name in accuracy(beams)[:3])
        print(f"| {beams} | {c['analysis']:.3f} | {c['with']:.3f} | "
              f"{c['with'] / c['analysis']:.2f} | {c['gradient'] / c['analysis']:.2f} | "
              f"{worst} |")
    print("\n| beams per leaf | one build [s] | one analysis [s] | build / analysis |")
    print("|---|---|---|---|")
    for beams in args.beams:
        built, analysed, ratio = build_share(beams, max(args.repeat, 7))
        print(f"| {beams} | {built:.3f} | {analysed:.3f} | {ratio:.2f} |")
    o = optimisation()
    true = o["true"]
    print("\n| method | analyses | time [s] | t [mm] | L [mm] | error of t | converged |")
    print("|---|---|---|---|---|---|---|")
    for name in ("exact", "differences"):
        r = o[name]
        print(f"| {name} | {r['analyses']} | {r['seconds']:.2f} | {1e3 * r['t']:.6f} | "
              f"{1e3 * r['L']:.4f} | {abs(r['t'] - true['t']) / true['t']:.1e} | "
              f"{r['success']} |")
    print(f"| true optimum (root search) | | | {1e3 * true['t']:.6f} | 200 | | |")


if __name__ == "__main__":
    main()
