"""Inverse dynamics over a time grid: the loads that make a prescribed motion happen."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Literal

import numpy as np

from .dynamics import Forces, dynamic_terms
from .errors import ModelError, SimulationError
from .inputs import evaluate_laws, resolve_laws
from .model import Model
from .motion import Law
from .progress import progress_bar
from .records import DynamicRecord
from .results import SimulationResult, check_on_failure, check_times, conclude
from .threads import blas_threads_for


def inverse_dynamics(
    model: Model,
    times,
    inputs: Mapping[str, Law] | None = None,
    *,
    forces: Forces | None = None,
    tolerance: float | None = None,
    with_reactions: bool = True,
    on_failure: Literal["raise", "return"] = "raise",
    progress: bool | None = None,
) -> SimulationResult:
    """Driving forces, constraint stresses and support reactions along a prescribed motion.

    Every entry of ``q`` follows a law: the model's input laws, overridden by
    ``inputs``; dynamic entries without a law are held at their initial value
    (their ``driving`` column is then the load that holds them).

    Args:
        model: a model with mass (elements or point masses).
        times: increasing output times [s], shape ``(nt,)``.
        inputs: laws by label (``{"x2.1": Polynomial(0, 150)}``).
        forces: applied loads ``forces(t, x, xdot)`` [N, N m] as in :func:`flexmbd.simulate`.
        tolerance: Newton tolerance of the position solve [m, rad].
        with_reactions: compute constraint stresses and the loads of supports and
            drives (THEORY 8); default on.
        on_failure: ``"raise"`` (with ``error.partial_result``) or ``"return"``.
        progress: progress bar (default: long interactive runs only).

    Returns:
        :class:`~flexmbd.results.SimulationResult` whose ``driving`` holds
        ``tau = Mbar qddot - g`` per entry of ``q`` and ``reactions`` the loads on
        fixed and input coordinates (columns ``f<node>.<k>``).
    """
    times = check_times(times)
    check_on_failure(on_failure)
    if not model.has_mass:
        raise ModelError("the model has no mass: give elements set_mass() or nodes "
                         "add_point_mass() before inverse dynamics")
    laws = resolve_laws(model, inputs)
    record = DynamicRecord(model, len(times), with_reactions)
    x_guess, xd_last, error = np.array(model.x0, dtype=float), None, None
    with progress_bar(len(times), "inverse dynamics", progress) as bar, \
            blas_threads_for(model.n_coordinates):
        for k, t in enumerate(times):
            q, qd, qdd = evaluate_laws(laws, t)
            if k:  # first-order predictor, as in kinematic_analysis
                x_guess = record.arrays["x"][k - 1] + (t - times[k - 1]) * xd_last
            try:
                terms = dynamic_terms(model, q, qd, t, x_guess=x_guess, forces=forces,
                                      tolerance=tolerance)
            except SimulationError as err:
                error = err
                break
            record.add(t, terms, q, qd, qdd)
            xd_last = terms.xd
            bar.update(1)
    return conclude(record.result(), error, on_failure,
                    f"completed {len(times)} points from t = {times[0]:.6g} s to "
                    f"{times[-1]:.6g} s")
