"""How a model is meant to be run: the run part of a SPACAR input file, kept apart from
the model (which describes the mechanism alone)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from .frozen import FrozenMap


@dataclass(frozen=True)
class RunSettings:
    """How a model is meant to be run; every field is optional.

    Attributes:
        t_end: end time of the run [s] (TIMESTEP); ``None`` when not given.
        steps: number of output intervals from 0 to ``t_end`` (TIMESTEP), so
            ``steps + 1`` output times.
        initial: initial value and rate of dynamic degrees of freedom by label,
            ``{"e2.2": (value, rate)}`` (STARTDE, STARTDX) [m or rad, per s].
        atol, rtol: integrator tolerances (ERROR).
        max_iterations: Newton iterations of the position solve (ITERSTEP).
        load_steps: load steps of a static analysis (ITERSTEP's second value).
        tolerance: Newton tolerance of the position solve [m, rad] (ITERSTEP).
        iteration_options: ITERSTEP's values after the tolerance, SPACAR's options of its
            solver and storage (SPACAR Light writes ``1 3 n`` for loads with increments,
            ``1 1 n`` for loads without: then SPACAR stores one step, the equilibrium of
            those loads, which ``flexmbd spacar`` follows); kept to write the file back.
        load_increment: total load increments of a static analysis by coordinate label,
            ``{"x5.2": -10.0}`` [N, N m] (DELXF).
        input_increment: total increments of prescribed inputs by label (DELINPX,
            DELINPE) [m, rad].
        force_inputs: coordinates loaded by the inputs of a state-space model (INPUTF).
        outputs, rate_outputs: coordinates whose values (OUTX) or rates (OUTXP) are its
            outputs.
        output_order: the outputs in the order a transfer-function file numbers them,
            ``"x5.2"`` for a position and ``"xd5.2"`` for a rate; empty: ``outputs`` then
            ``rate_outputs``.
        notes: what the file gives that flexmbd reads but does not use (SPACAR's
            ``OUTLEVEL``, a beam's warping values), one line each with the lines it was on.
        user_loads: the routine of loads and stresses (USERSIG), a function of that name
            in a module of that name in ``routine_dir``.
        user_inputs: the routine of input motions (USERINP), found as ``user_loads``.
        routine_dir: the directory of the user routines (the input file's).
    """

    t_end: float | None = None
    steps: int | None = None
    initial: Mapping[str, tuple[float, float]] = field(
        default_factory=lambda: FrozenMap({}))
    atol: float | None = None
    rtol: float | None = None
    max_iterations: int | None = None
    load_steps: int | None = None
    tolerance: float | None = None
    iteration_options: tuple[float, ...] = ()
    load_increment: Mapping[str, float] = field(default_factory=lambda: FrozenMap({}))
    input_increment: Mapping[str, float] = field(default_factory=lambda: FrozenMap({}))
    force_inputs: tuple[str, ...] = ()
    outputs: tuple[str, ...] = ()
    rate_outputs: tuple[str, ...] = ()
    output_order: tuple[str, ...] = ()
    notes: tuple[str, ...] = ()
    user_loads: str | None = None
    user_inputs: str | None = None
    routine_dir: str | None = None

    def output_times(self) -> np.ndarray | None:
        """``steps + 1`` equally spaced times from 0 to ``t_end`` [s], or ``None`` when unset."""
        if self.t_end is None or self.steps is None:
            return None
        return np.linspace(0.0, self.t_end, self.steps + 1)
