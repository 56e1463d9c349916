"""``check_gradient``: a design's exact gradients against central differences of its
analyses, and a Taylor test, for a user who wants to see them agree on their own model."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import ArgumentError
from ..summary import clip
from .evaluate import _checked_params, _outputs, evaluate

__all__ = ["GradientCheck", "check_gradient"]

#: the relative steps of the central differences, and of the Taylor test
STEPS = (1e-2, 1e-3, 1e-4)


@dataclass(frozen=True)
class GradientCheck:
    """The exact gradients beside central differences of the analyses.

    Attributes:
        exact: ``exact[output][param]``, the gradient :func:`evaluate` gives.
        central: ``central[output][param]``, Richardson's extrapolation of the central
            differences at the two smallest steps.
        differences: ``differences[output][param]``, the central difference at each step
            of :attr:`steps` (relative to the parameter).
        error: ``error[output][param]``, ``|exact - central|`` relative to the larger of
            them (0 where both vanish).
        taylor: per output, the rates at which ``|J(p + h d) - J(p) - h dJ.d|`` falls
            between the steps for a random direction ``d``: 2 where the gradient is right
            (1 where it is wrong), ``nan`` where the remainder is already at rounding.
        steps: the relative steps.
    """

    exact: dict[str, dict[str, float]]
    central: dict[str, dict[str, float]]
    differences: dict[str, dict[str, list[float]]]
    error: dict[str, dict[str, float]]
    taylor: dict[str, list[float]]
    steps: tuple[float, ...]

    @property
    def worst(self) -> float:
        """The largest relative error over every output and parameter."""
        return max(e for per in self.error.values() for e in per.values())

    def __repr__(self) -> str:
        lines = ["GradientCheck (exact against central differences, Richardson)"]
        for out, per in self.error.items():
            for name, err in per.items():
                lines.append(f"  d {out} / d {name}: exact {self.exact[out][name]:.10g}, "
                             f"differences {self.central[out][name]:.10g}, relative "
                             f"error {err:.1e}")
            rates = ", ".join(f"{r:.2f}" for r in self.taylor[out])
            lines.append(f"  {out}: Taylor rates {rates} (2 where the gradient is right)")
        return clip("\n".join(lines))

    __str__ = __repr__


def check_gradient(build: Callable, params: Mapping[str, float], outputs,
                   steps: Sequence[float] = STEPS, seed: int = 0) -> GradientCheck:
    """Compare :func:`evaluate`'s gradients with central differences of the analyses at
    several ``steps`` (relative to each parameter; a parameter at 0 takes them as they
    are) and run a Taylor test along a random direction.

    Args:
        build, params, outputs: as for :func:`evaluate`.
        steps: relative steps, largest first, at least two.
        seed: the random direction's seed.

    Returns:
        :class:`GradientCheck`; its ``worst`` relative error and ``taylor`` rates say
        whether the gradients hold.

    Raises:
        ArgumentError: fewer than two steps, or a step that is not a positive number.
    """
    values = _checked_params(params)
    names = [out.name for out in _outputs(outputs)]
    steps = tuple(float(s) for s in steps)
    if len(steps) < 2 or any(not s > 0 for s in steps):
        raise ArgumentError("steps", f"give two or more positive relative steps, got {steps}")
    exact = evaluate(build, values, names)
    assert exact.gradient is not None

    def run(point: dict[str, float]) -> dict[str, float]:
        return evaluate(build, point, names, gradient=False).values

    differences: dict[str, dict[str, list[float]]] = {o: {p: [] for p in values} for o in names}
    for name, value in values.items():
        for step in steps:
            h = step * (abs(value) or 1.0)
            low, high = run({**values, name: value - h}), run({**values, name: value + h})
            for out in names:
                differences[out][name].append((high[out] - low[out]) / (2.0 * h))
    central = {o: {p: (4.0 * d[-1] - d[-2]) / 3.0 for p, d in per.items()}
               for o, per in differences.items()}
    error = {o: {p: _relative(exact.gradient[o][p], central[o][p]) for p in values}
             for o in names}
    direction = np.random.default_rng(seed).standard_normal(len(values))
    scale = np.array([abs(v) or 1.0 for v in values.values()])
    remainders: dict[str, list[float]] = {o: [] for o in names}
    for step in steps:
        moved = run({n: v + step * d * s for (n, v), d, s in
                     zip(values.items(), direction, scale, strict=True)})
        for out in names:
            slope = sum(exact.gradient[out][n] * d * s for n, d, s in
                        zip(values, direction, scale, strict=True))
            remainders[out].append(abs(moved[out] - exact.values[out] - step * slope))
    taylor = {o: [_rate(r[k], r[k + 1], steps[k], steps[k + 1], exact.values[o])
                  for k in range(len(steps) - 1)] for o, r in remainders.items()}
    return GradientCheck({o: dict(exact.gradient[o]) for o in names}, central, differences,
                         error, taylor, steps)


def _relative(a: float, b: float) -> float:
    size = max(abs(a), abs(b))
    return 0.0 if size == 0.0 else abs(a - b) / size


def _rate(r1: float, r2: float, h1: float, h2: float, value: float) -> float:
    """The order of the remainder between two steps; ``nan`` at rounding level."""
    floor = 1e-12 * max(abs(value), 1e-300)
    if r1 <= floor or r2 <= floor:
        return float("nan")
    return float(np.log(r1 / r2) / np.log(h1 / h2))
