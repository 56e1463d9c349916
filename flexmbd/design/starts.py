"""Several starts of one optimisation, run as the cases of a study.

A flexure's objective is rarely convex over its whole design space (a frequency whose
mode changes character, a stress maximum that moves from beam to beam), so a
gradient-based optimiser finds the optimum nearest its start. Starting it from designs
spread over the bounds, each start one case of a study (:func:`~flexmbd.studies.sweep.
run_cases`: in this process, or on a Dask cluster as :func:`~flexmbd.sweep` runs its
cases), and keeping the best, finds the others too.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from ..errors import ArgumentError
from ..studies.case import describe

__all__ = ["LATIN_SEED", "spread_starts"]

#: the seed of the Latin hypercube that spreads a number of starts over the bounds: the
#: same starts on every run
LATIN_SEED = 46


def spread_starts(first: dict[str, float], starts, ranges: Mapping[str, tuple]
                  ) -> list[dict[str, float]]:
    """The designs an optimisation starts from: ``first``, then ``starts``: a number of
    designs in all (``first`` and the rest of a Latin hypercube over the bounds, every
    parameter bounded on both sides), or a list of designs (each ``{name: value}``,
    parameters left out taking ``first``'s values).

    Raises:
        ArgumentError: a number below 1, a parameter without both bounds, an unknown
            parameter, a value that is not a finite number.
    """
    if isinstance(starts, (int, np.integer)) and not isinstance(starts, bool):
        if starts < 1:
            raise ArgumentError("starts", f"give 1 or more starts, got {starts}")
        unbounded = [n for n in first if None in ranges.get(n, (None, None))]
        if starts > 1 and unbounded:
            raise ArgumentError("starts", f"{int(starts)} starts are spread over the bounds: "
                                          f"give {unbounded} a (low, high) in bounds, or "
                                          f"list the starts as designs")
        from scipy.stats import qmc

        names = list(first)
        if starts == 1:
            return [first]
        unit = qmc.LatinHypercube(d=len(names), seed=LATIN_SEED).random(int(starts) - 1)
        low = np.array([ranges[n][0] for n in names])
        high = np.array([ranges[n][1] for n in names])
        return [first, *({n: float(v) for n, v in zip(names, low + u * (high - low),
                                                       strict=True)} for u in unit)]
    if not isinstance(starts, Sequence) or isinstance(starts, str) or not starts:
        raise ArgumentError("starts", f"give a number of starts or a list of designs "
                                      f"({{name: value}}), got {starts!r}")
    designs = [first]
    for k, start in enumerate(starts):
        if not isinstance(start, Mapping):
            raise ArgumentError("starts", f"start {k} must be a dict {{name: value}}, got "
                                          f"{start!r}")
        unknown = [n for n in start if n not in first]
        if unknown:
            raise ArgumentError("starts", f"start {k}: {unknown} are not parameters of the "
                                          f"design (its parameters: {list(first)})")
        for name, value in start.items():
            if isinstance(value, bool) or not isinstance(value, (int, float, np.floating,
                                                                 np.integer)) \
                    or not math.isfinite(value):
                raise ArgumentError("starts", f"start {k}: {name!r} must be a finite number, "
                                              f"got {value!r}")
        designs.append({**first, **{n: float(v) for n, v in start.items()}})
    return designs


@dataclass(frozen=True)
class Starts:
    """One optimisation from several starts: a study whose case is a start (sent to the
    workers with every case, so ``build`` must be a module's function on Dask)."""

    optimize: Callable
    build: Callable
    options: dict = field(default_factory=dict)
    outputs: tuple = ("fun",)

    def run(self, index: int, start: dict[str, float]) -> dict[str, object]:
        """The row of start ``index``: ``case``, the start, ``fun``, ``x``, ``success``,
        ``nfev``, ``message``, ``status`` (``"ok"`` or ``"failed"``, an analysis that
        failed), ``error`` and ``wall_time`` [s]."""
        begin = time.perf_counter()
        row: dict[str, object] = {"case": index, **start, "fun": math.nan, "x": None,
                                  "success": False, "nfev": 0, "message": "",
                                  "status": "ok", "error": ""}
        try:
            found = self.optimize(self.build, start, **self.options)
        except Exception as failure:   # a start that fails is the start's result
            row.update(status="failed", error=describe(failure))
            partial = getattr(failure, "partial_result", None)
            if partial is not None:
                row["nfev"] = partial.nfev
        else:
            row.update(fun=found.fun, x=found.x, success=found.success, nfev=found.nfev,
                       message=str(found.message))
        row["wall_time"] = time.perf_counter() - begin
        return row
