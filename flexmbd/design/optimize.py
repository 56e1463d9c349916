"""``optimize``: the best design by SciPy's gradient-based optimisers on exact gradients.

Each iterate is one :func:`~flexmbd.design.evaluate` with ``gradient=True``: the
objective, every constrained output and all their derivatives from one analysis, kept
for the optimiser's calls at the same point. The parameters are scaled by their start
(or their bounds' width) and the objective by its value at the start, so that a
thickness of 5e-4 m and a length of 0.1 m weigh alike in SLSQP's steps.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Mapping

import numpy as np

from ..errors import ArgumentError, FlexmbdError, SimulationError
from ..studies.runner import check_client, run_cases
from .evaluate import DesignResult, _checked_params, evaluate
from .starts import Starts, spread_starts

__all__ = ["optimize"]

METHODS = ("SLSQP", "trust-constr")


def _pairs(given, name: str, what: str) -> dict[str, tuple[float | None, float | None]]:
    """``{key: (low, high)}`` checked: numbers or ``None``, low below high."""
    if given is None:
        return {}
    if not isinstance(given, Mapping):
        raise ArgumentError(name, f"must be a dict of {what} and (low, high) pairs")
    out = {}
    for key, pair in given.items():
        try:
            low, high = pair
        except (TypeError, ValueError):
            raise ArgumentError(name, f"{key!r}: give a (low, high) pair, None for no "
                                      f"limit; got {pair!r}") from None
        for value in (low, high):
            if value is not None and (isinstance(value, bool) or not isinstance(
                    value, (int, float, np.floating, np.integer)) or math.isnan(value)):
                raise ArgumentError(name, f"{key!r}: limits are numbers or None, got "
                                          f"{value!r}")
        if low is not None and high is not None and low > high:
            raise ArgumentError(name, f"{key!r}: the low limit {low} is above the high "
                                      f"{high}")
        out[key] = (None if low is None else float(low), None if high is None else float(high))
    return out


def optimize(build: Callable, params: Mapping[str, float], objective,
             constraints: Mapping[str, tuple] | None = None,
             bounds: Mapping[str, tuple] | None = None, *, method: str = "SLSQP",
             maximize: bool = False, tol: float = 1e-8, max_iterations: int = 100,
             options: Mapping | None = None, starts=None, client="serial",
             progress: bool | None = None):
    """The design that minimises (or maximises) an output, within bounds on the parameters
    and limits on other outputs, by SciPy's ``minimize`` with exact gradients; from
    several starts, the best of their optima.

    Args:
        build: ``build(**params)``, as for :func:`~flexmbd.design.evaluate`.
        params: the starting design, ``{name: value}``.
        objective: the output minimised (its names as for ``evaluate``: ``"f1"``,
            ``"C[9,10][4,4]"``, ``"stress_ks"``, ...), or a weighted sum of outputs,
            in one string (``"2*f1 - f2"``, the signs with a space either side) or as
            ``{"f1": 2.0, "f2": -1.0}``.
        constraints: ``{output: (low, high)}``, ``None`` for no limit on a side; ``low ==
            high`` holds the output at that value. A key may be a sum of outputs as for
            the objective (``"C[5,4][2,2] - C[105,104][2,2]": (0.0, 0.0)``).
        bounds: ``{param: (low, high)}`` on the parameters.
        method: ``"SLSQP"`` (default) or ``"trust-constr"``.
        maximize: maximise the objective instead.
        tol: the optimiser's tolerance on the objective relative to its start (the
            analyses' rounding, about 1e-10, sets its floor).
        max_iterations: iterations before the optimiser stops.
        options: further options of the SciPy method.
        starts: ``None`` (one start, ``params``); a number of starts in all (``params``
            and the rest spread over the bounds by a Latin hypercube, the same on every
            run: every parameter needs both bounds); or a list of further designs to
            start from (parameters left out keep ``params``' values). The starts run as
            the cases of a study (:func:`~flexmbd.sweep`'s machinery): a start whose
            analysis fails is reported, not the end of the search.
        client: where the starts run, as for :func:`~flexmbd.sweep`: ``"serial"`` (this
            process, the default), ``None`` (a new local Dask cluster, one worker per
            core; ``build`` must then be a module's function), a scheduler address or a
            ``dask.distributed.Client``.
        progress: with ``starts``, a bar counting them (``None``: on a terminal only).

    Returns:
        ``scipy.optimize.OptimizeResult``: ``x`` (a dict in the parameters' names),
        ``fun`` (the objective there), ``nfev`` (analyses run: each gives the objective,
        the constraints and their gradients; over all starts), ``nit``, ``success``,
        ``message``, ``outputs`` (every output at ``x``), ``history`` (each analysis's
        design and objective; with ``starts``, the best start's) and ``result`` (the
        :class:`DesignResult` at ``x``); with ``starts``, also ``starts``: one dict per
        start (``case``, the start, ``x``, ``fun``, ``success``, ``nfev``, ``message``,
        ``status``, ``error``, ``wall_time``), in the starts' order.

    Raises:
        ArgumentError: unknown outputs or parameters in the limits, or bad limits or
            starts.
        FlexmbdError: an analysis failed (a design the structure cannot carry); its
            ``partial_result`` holds the optimisation so far. With ``starts``: every
            start failed.
    """
    start = _checked_params(params)
    ranges = _pairs(bounds, "bounds", "parameters")
    unknown = [key for key in ranges if key not in start]
    if unknown:
        raise ArgumentError("bounds", f"{unknown} are not parameters of the design "
                                      f"(its parameters: {list(start)})")
    if method not in METHODS:
        raise ArgumentError("method", f"must be one of {METHODS}, got {method!r}")
    settings = dict(objective=objective, constraints=constraints, bounds=bounds,
                    method=method, maximize=maximize, tol=tol,
                    max_iterations=max_iterations, options=options)
    if starts is None:
        return _optimize_once(build, start, **settings)
    return _best_of(build, spread_starts(start, starts, ranges), settings, client, progress)


def _best_of(build: Callable, designs: list[dict[str, float]], settings: dict, client,
             progress: bool | None):
    """The best of the optimisations from ``designs``, run as a study's cases."""
    check_client(client)
    rows: list[dict] = []
    run_cases(Starts(_optimize_once, build, settings), list(enumerate(designs)), client,
              rows.append, progress, len(designs))
    rows.sort(key=lambda row: row["case"])
    finished = [row for row in rows if row["status"] == "ok"]
    if not finished:
        failure = SimulationError(f"optimize: every one of the {len(rows)} starts failed; "
                                  f"the first: {rows[0]['error']}")
        failure.partial_result = rows
        raise failure
    pick = max if settings["maximize"] else min
    # a converged optimum before one stopped by its iteration limit
    best = pick([r for r in finished if r["success"]] or finished, key=lambda r: r["fun"])
    found = _optimize_once(build, best["x"], **settings)   # its result, at its optimum
    found.nfev += sum(row["nfev"] for row in rows)
    found.starts = rows
    return found


def _optimize_once(build: Callable, start: dict[str, float], objective, constraints,
                   bounds, method: str, maximize: bool, tol: float, max_iterations: int,
                   options: Mapping | None):
    """One optimisation from ``start`` (:func:`optimize`'s arguments checked)."""
    from scipy.optimize import NonlinearConstraint, OptimizeResult, minimize

    names = list(start)
    limits = _pairs(constraints, "constraints", "outputs")
    ranges = _pairs(bounds, "bounds", "parameters")
    weights = combination(objective, "objective")
    sums = {key: combination(key, "constraints") for key in limits}
    outputs = list(dict.fromkeys([*weights, *(n for terms in sums.values() for n in terms)]))
    scale = np.array([_scale(start[n], ranges.get(n)) for n in names])
    history: list[dict] = []
    kept: dict[bytes, DesignResult] = {}

    def design_at(u: np.ndarray) -> DesignResult:
        key = np.asarray(u, dtype=float).tobytes()
        if key not in kept:
            values = dict(zip(names, (u * scale).tolist(), strict=True))
            try:
                kept[key] = evaluate(build, values, outputs)
            except FlexmbdError as error:
                error.partial_result = _result(history, maximize)   # type: ignore[attr-defined]
                raise
            history.append({"params": values, "objective": combined(kept[key].values)})
        return kept[key]

    def combined(values: Mapping[str, float], terms: Mapping[str, float] = weights) -> float:
        return sum(w * values[name] for name, w in terms.items())

    def slope_of(result: DesignResult, terms: Mapping[str, float]) -> np.ndarray:
        gradient = result.gradient
        assert gradient is not None
        return np.array([sum(w * gradient[out][n] for out, w in terms.items())
                         for n in names])

    u0 = np.ones(len(names))
    first = design_at(u0)
    sign = -1.0 if maximize else 1.0
    # the objective's unit: its start (a weighted sum of near-equal outputs is far
    # smaller than its terms), else its largest term
    size = abs(combined(first.values)) or max(
        abs(w * first.values[name]) for name, w in weights.items()) or 1.0

    def fun(u):
        return sign * combined(design_at(u).values) / size

    def jac(u):
        return sign * slope_of(design_at(u), weights) * scale / size

    constraint_list = []
    for key, (low, high) in limits.items():
        terms = sums[key]
        # a limit's unit: the largest of its bounds and of its terms at the start (a
        # difference held at zero is measured against its terms)
        magnitude = max([abs(v) for v in (low, high) if v is not None] +
                        [abs(w * first.values[n]) for n, w in terms.items()]) or 1.0

        def value(u, terms=terms, magnitude=magnitude):
            return np.array([combined(design_at(u).values, terms) / magnitude])

        def slope(u, terms=terms, magnitude=magnitude):
            return (slope_of(design_at(u), terms) * scale / magnitude)[None, :]

        lower = -np.inf if low is None else low / magnitude
        upper = np.inf if high is None else high / magnitude
        constraint_list.append(NonlinearConstraint(value, lower, upper, jac=slope))
    box = [tuple(None if v is None else v / s for v in ranges.get(n, (None, None)))
           for n, s in zip(names, scale, strict=True)]
    if method == "SLSQP":
        constraint_list = _slsqp_constraints(constraint_list)
    found = minimize(fun, u0, jac=jac, method=method, bounds=box, constraints=constraint_list,
                     tol=tol, options={"maxiter": max_iterations, **dict(options or {})})
    best = design_at(found.x)
    return OptimizeResult(
        x=dict(zip(names, (found.x * scale).tolist(), strict=True)),
        fun=combined(best.values), nfev=len(kept), nit=found.get("nit"),
        success=bool(found.success), status=found.status, message=found.message,
        outputs=best.values, history=history, result=best)


#: the sign between two terms of a combination of outputs, with a space either side
_BETWEEN = re.compile(r"\s+([+-])\s+")
_WEIGHTED = re.compile(r"^([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*\*\s*(\S+)$")


def combination(given, argument: str) -> dict[str, float]:
    """Outputs and their weights, ``{output: weight}``, of an objective or a limited
    quantity: an output name (``"f1"``), a sum of them in one string (``"C[5,4][2,2] -
    C[105,104][2,2]"``, ``"2*f1 + f2"``, the signs with a space either side), or a dict of
    names and weights.

    Raises:
        ArgumentError: anything else, named by ``argument``.
    """
    if isinstance(given, Mapping) and given:
        out: dict[str, float] = {}
        for name, weight in given.items():
            if not isinstance(name, str) or isinstance(weight, bool) or not isinstance(
                    weight, (int, float, np.floating, np.integer)) or not math.isfinite(weight):
                raise ArgumentError(argument, f"a weighted sum maps output names to "
                                              f"finite numbers, got {name!r}: {weight!r}")
            out[name.strip()] = out.get(name.strip(), 0.0) + float(weight)
        return out
    if isinstance(given, str) and given.strip():
        parts = _BETWEEN.split(" " + given.strip())
        terms: dict[str, float] = {}
        signs = ["+", *parts[1::2]]
        for sign, term in zip(signs, parts[0::2], strict=True):
            term = term.strip()
            weighted = _WEIGHTED.match(term)
            weight, name = (float(weighted.group(1)), weighted.group(2)) if weighted \
                else (1.0, term)
            if not weighted and name[:1] in "+-" and len(name) > 1:   # "-f1": a sign, no weight
                weight, name = (-1.0 if name[0] == "-" else 1.0), name[1:]
            terms[name] = terms.get(name, 0.0) + (weight if sign == "+" else -weight)
        return terms
    raise ArgumentError(argument, f"give an output name, a sum of them (\"f1 - f2\"), or a "
                                  f"dict of output names and weights, got {given!r}")


def _scale(value: float, bounds: tuple | None) -> float:
    """A parameter's unit in the optimiser: its start, or its bounds' width at zero."""
    if value:
        return abs(value)
    if bounds and None not in bounds and bounds[1] > bounds[0]:
        return bounds[1] - bounds[0]
    return 1.0


def _slsqp_constraints(constraints: list) -> list[dict]:
    """SLSQP's dictionaries for two-sided limits: ``fun >= 0`` each side, ``eq`` where the
    two meet."""
    out = []
    for c in constraints:
        low, high = float(np.ravel(c.lb)[0]), float(np.ravel(c.ub)[0])
        if low == high:
            out.append({"type": "eq", "fun": lambda u, c=c, v=low: c.fun(u) - v,
                        "jac": c.jac})
            continue
        if np.isfinite(low):
            out.append({"type": "ineq", "fun": lambda u, c=c, v=low: c.fun(u) - v,
                        "jac": c.jac})
        if np.isfinite(high):
            out.append({"type": "ineq", "fun": lambda u, c=c, v=high: v - c.fun(u),
                        "jac": lambda u, c=c: -c.jac(u)})
    return out


def _result(history: list[dict], maximize: bool):
    """The optimisation so far, its best design first, for a failed analysis's error."""
    from scipy.optimize import OptimizeResult

    pick = max if maximize else min
    best = pick(history, key=lambda h: h["objective"]) if history else None
    return OptimizeResult(x=None if best is None else best["params"],
                          fun=None if best is None else best["objective"],
                          nfev=len(history), history=history, success=False,
                          message="an analysis failed")
