"""Kinematic analysis over a time grid for prescribed inputs."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Literal

import numpy as np

from .errors import SimulationError
from .inputs import evaluate_laws, resolve_laws
from .kinematics import (
    accelerations,
    deformations,
    position_analysis,
    quadratic_velocity,
    velocities,
)
from .model import Model
from .motion import Law
from .progress import progress_bar
from .results import KinematicResult, check_on_failure, check_times, conclude
from .threads import blas_threads_for


def kinematic_analysis(
    model: Model,
    times,
    inputs: Mapping[str, Law] | None = None,
    *,
    tolerance: float | None = None,
    max_iterations: int = 25,
    on_failure: Literal["raise", "return"] = "raise",
    progress: bool | None = None,
) -> KinematicResult:
    """Positions, velocities and accelerations of all coordinates and deformations.

    At each time the prescribed ``q`` comes from the laws; the position solve
    starts from the previous solution plus its velocity times the time step.

    Args:
        model: the mechanism.
        times: increasing output times [s], shape ``(nt,)``.
        inputs: laws by label (``{"x2.1": Polynomial(0, 4)}``), overriding the
            model's defaults. Dynamic degrees of freedom without a law stay at
            their initial values.
        tolerance: Newton tolerance [m, rad] (default ``1e-10`` times the model size).
        max_iterations: Newton iteration limit per time.
        on_failure: ``"raise"`` (default) raises the :class:`SimulationError`
            with the points computed so far as ``error.partial_result``;
            ``"return"`` returns them with ``success=False``.
        progress: show a progress bar (default: only for long interactive runs).

    Returns:
        :class:`~flexmbd.results.KinematicResult`.
    """
    times = check_times(times)
    check_on_failure(on_failure)
    laws = resolve_laws(model, inputs)
    nt, nx, ne = len(times), model.n_coordinates, model.n_deformations
    out = {name: np.empty((nt, n)) for name, n in
           (("x", nx), ("xd", nx), ("xdd", nx), ("e", ne), ("ed", ne), ("edd", ne))}

    x_guess = np.array(model.x0, dtype=float)
    done, error = 0, None
    with progress_bar(nt, "kinematics", progress) as bar, blas_threads_for(nx):
        for k, t in enumerate(times):
            try:
                q, qd, qdd = evaluate_laws(laws, t)
                if k:
                    dt = t - times[k - 1]
                    # first-order predictor x + F_q dq (THEORY 3); a second-order one
                    # overshoots near singular points and can jump to another branch
                    x_guess = out["x"][k - 1] + dt * out["xd"][k - 1]
                solution = position_analysis(model, q, x_guess, time=t, tolerance=tolerance,
                                             max_iterations=max_iterations)
                x, jac = solution.x, solution.jacobian
                xd = velocities(model, x, qd, jac)
                xdd = accelerations(model, x, xd, qdd, jac)
            except SimulationError as err:
                error = err
                break
            out["x"][k], out["xd"][k], out["xdd"][k] = x, xd, xdd
            out["e"][k] = deformations(model, x)
            out["ed"][k] = jac.full @ xd
            out["edd"][k] = jac.full @ xdd + quadratic_velocity(model, x, xd)
            done = k + 1
            bar.update(1)

    result = KinematicResult(model, times[:done], **{k: v[:done] for k, v in out.items()})
    return conclude(result, error, on_failure,
                    f"completed {nt} points from t = {times[0]:.6g} s to {times[-1]:.6g} s")

