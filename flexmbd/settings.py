"""Analysis settings a model can carry (the run part of a SPACAR input file)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType


@dataclass(frozen=True)
class AnalysisSettings:
    """How a model is meant to be run; every field is optional.

    Attributes:
        t_end: end time of the run [s] (TIMESTEP); ``None`` when not given.
        steps: number of output intervals from 0 to ``t_end`` (TIMESTEP), so
            ``steps + 1`` output times.
        initial: initial value and rate of dynamic degrees of freedom by label,
            ``{"e2.2": (value, rate)}`` (STARTDE) [m or rad, per s].
        atol, rtol: integrator tolerances (ERROR).
        max_iterations: Newton iterations of the position solve (ITERSTEP).
        tolerance: Newton tolerance of the position solve [m, rad] (ITERSTEP).
    """

    t_end: float | None = None
    steps: int | None = None
    initial: Mapping[str, tuple[float, float]] = field(
        default_factory=lambda: MappingProxyType({}))
    atol: float | None = None
    rtol: float | None = None
    max_iterations: int | None = None
    tolerance: float | None = None

    def output_times(self):
        """``steps + 1`` equally spaced times from 0 to ``t_end``, or ``None`` when unset."""
        import numpy as np

        if self.t_end is None or self.steps is None:
            return None
        return np.linspace(0.0, self.t_end, self.steps + 1)
