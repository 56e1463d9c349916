"""Benchmark: what a call into the compiled core costs, paired between two checkouts.

The binding (``flexmbd/engine/_core.pyx``, Cython) matters where Python calls the core
often: scipy's integrators call ``accelerations`` at every stage, the per-state
functions call ``state``, ``factor`` and ``solve``, ``mass_matrix`` builds a batch row
by row. Runs over a time grid (kinematic analysis, generalized-alpha) are one call and
are measured by ``compare_exudyn.py``. Timed on EXERCISES 4's slider-crank with
flexible elongation and 8 beams (the benchmark of ``compare_exudyn.py``):

* ``accelerations``: one evaluation of scipy's right-hand side (position solve from
  the predictor, accelerations) [us];
* ``state``: the kinematics of one state, exact position solve [us];
* ``transfer``: ``first_order_transfer``, once the model's workspace exists [us];
* ``mass``: the mass matrix at one configuration [us];
* ``solve_position``, ``velocities``, ``mass_matrix``: the public per-state functions
  around those calls, as a user calls them [us];
* ``mass batch``: ``mass_matrix`` of 100 configurations, per configuration [us];
* ``RK45``: ``simulate`` with RK45 over 2 ms (the elongation makes it stiff), the whole call [ms].

``python benchmarks/binding.py`` prints the medians of one checkout (the one on
``PYTHONPATH``, or the installed one); ``--pair BEFORE AFTER`` runs it in fresh
processes alternately with each checkout on ``PYTHONPATH`` and prints both and their
ratio (each checkout's core built in place: ``python setup.py build_ext --inplace``).
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


def median_us(work, repeat: int = 2000) -> float:
    """Median time of one call of ``work()`` [us], timed in batches of 50."""
    work()
    batches = []
    for _ in range(max(1, repeat // 50)):
        start = time.perf_counter()
        for _ in range(50):
            work()
        batches.append((time.perf_counter() - start) / 50)
    return float(np.median(batches)) * 1e6


def measure() -> dict[str, float]:
    """The per-call costs of one checkout (the flexmbd imported)."""
    from flexmbd.examples import slider_crank_flex

    import flexmbd as fm
    from flexmbd.engine import resolve_laws, workspace_of

    model = slider_crank_flex.build_model(8, eps1flex=True)
    engine = workspace_of(model)
    laws = resolve_laws(model)
    nq = model.n_dof
    q = fm.initial_q(model)
    zero = np.zeros(nq)
    x = engine.state(q, zero, zero)["x"]
    times = {}
    times["state"] = median_us(lambda: engine.state(q, zero, zero, x))
    times["transfer"] = median_us(lambda: fm.first_order_transfer(model, x))
    times["mass"] = median_us(lambda: engine.mass(x))
    qd = np.ones(nq)
    times["solve_position"] = median_us(lambda: fm.solve_position(model, q, x))
    times["velocities"] = median_us(lambda: fm.velocities(model, x, qd))
    times["mass_matrix"] = median_us(lambda: fm.mass_matrix(model, x))
    many = np.repeat(x[None], 100, axis=0)
    times["mass batch"] = median_us(lambda: fm.mass_matrix(model, many), 200) / 100
    engine.prepare(laws, 1, integrated=True, dynamics=True)
    nd = int(np.sum(~np.asarray(model.q_is_input)))
    y, out = np.zeros(2 * nd), np.empty(nd)
    y[:nd] = q[~np.asarray(model.q_is_input)]
    times["accelerations"] = median_us(lambda: engine.accelerations(0.0, y, out))
    walls = []
    for _ in range(7):
        start = time.perf_counter()
        fm.simulate(model, np.linspace(0.0, 0.002, 11), method="RK45")
        walls.append(time.perf_counter() - start)
    times["RK45 [ms]"] = float(np.median(walls)) * 1e3
    return times


def pair(before: str, after: str, rounds: int) -> None:
    """Alternate fresh processes on the two checkouts; print medians and ratios."""
    results: dict[str, list[dict[str, float]]] = {before: [], after: []}
    for _ in range(rounds):
        for checkout in (before, after):
            done = subprocess.run([sys.executable, __file__], capture_output=True, text=True,
                                  env={**os.environ, "PYTHONPATH": checkout}, check=True)
            results[checkout].append(json.loads(done.stdout))
    print(f"{platform.processor() or platform.machine()}, {rounds} rounds, paired\n")
    print("| call | before | after | after / before |\n|---|---|---|---|")
    for name in results[before][0]:
        b = float(np.median([r[name] for r in results[before]]))
        a = float(np.median([r[name] for r in results[after]]))
        ratios = [ra[name] / rb[name] for ra, rb in zip(results[after], results[before],
                                                         strict=True)]
        unit = "" if "[" in name else " [us]"
        print(f"| {name}{unit} | {b:.2f} | {a:.2f} | {np.median(ratios):.3f} |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--pair", nargs=2, metavar=("BEFORE", "AFTER"),
                        help="two checkouts, each with its core built in place")
    parser.add_argument("--rounds", type=int, default=7)
    args = parser.parse_args()
    if args.pair:
        pair(*args.pair, args.rounds)
    else:
        print(json.dumps(measure()))


if __name__ == "__main__":
    main()
