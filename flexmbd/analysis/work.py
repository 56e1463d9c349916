"""The work done on a motion, row by row: by its drives, its applied loads and its dampers.

The energy of a motion changes by exactly what these do to it (THEORY 5, 6)::

    d(T + U + V)/dt = tau . qdot_in + f . v - edot^T C edot

with ``tau`` the driving loads on the prescribed entries of ``q`` (what the drives
supply, conjugate to their rates), ``f`` the applied loads besides gravity (a moment
against the angular velocity of its node, a force against the velocity of its node) and
``C`` the elastic law's damping. The powers are known at the output rows only; their
integrals are formed there by Simpson's rule, whose own error is estimated by Richardson
extrapolation (the rule over every other row against the rule over all): with outputs
that resolve the power, what is left of the balance is the integrator's error.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
from scipy.integrate import cumulative_simpson

from ..elements.base import SPATIAL_ROTATIONAL
from ..engine.assembly import Assembly
from ..engine.laws import Forces, load_vector, own_loads
from ..errors import AccuracyWarning, ArgumentError, SimulationError
from ..results import SimulationResult

__all__ = ["Work", "work_done"]

#: the share of the balance that the work's quadrature error may reach before it is
#: warned about: beyond it the balance measures the output grid, not the integrator
QUADRATURE_SHARE = 0.1


@dataclass(frozen=True)
class Work:
    """Work done on a motion from its first row [J], each ``(nt,)``: by the drives of
    the prescribed entries (``inputs``), by the applied loads (``loads``) and taken out by
    damping (``dissipated``, positive); ``error`` estimates the quadrature error of their
    sum, the largest over the rows [J]."""

    inputs: np.ndarray
    loads: np.ndarray
    dissipated: np.ndarray
    error: float


def work_done(result: SimulationResult, assembly: Assembly, forces: Forces | None = None
              ) -> Work:
    """The work of the drives, the applied loads (the model's constant ones and
    ``forces(t, x, xdot)``, as given to :func:`~flexmbd.simulate`) and the dampers along
    ``result``'s rows.

    Raises:
        ArgumentError: the result has no driving loads (``outputs`` other than ``"all"``)
            while its drives move, or ``forces`` is not a function.
        SimulationError: ``forces`` fails at a row (its time named).
    """
    model = result.model
    t = np.asarray(result.t, dtype=float)
    inputs = np.flatnonzero(model.q_is_input)
    rates = np.asarray(result.qd)[:, inputs] if result.qd is not None else None
    if rates is not None and np.any(rates) and result.driving is None:
        raise ArgumentError("result", "has no driving loads, so the work of its moving "
                                      "drives is unknown: simulate with outputs='all' (the "
                                      "default)")
    drive_power = (np.sum(np.asarray(result.driving)[:, inputs] * rates, axis=1)
                   if rates is not None and result.driving is not None else np.zeros(len(t)))
    load_power = _load_power(result, forces)
    ed = np.asarray(result.ed)
    damping_power = np.sum(ed * assembly.law_times("C", ed.T).T, axis=1)
    return Work(inputs=_integral(t, drive_power), loads=_integral(t, load_power),
                dissipated=_integral(t, damping_power),
                error=_quadrature_error(t, drive_power + load_power - damping_power))


def _integral(t: np.ndarray, power: np.ndarray) -> np.ndarray:
    """``int power dt`` from the first row, ``(nt,)`` [J]: Simpson's rule over the rows
    (the trapezoid over two)."""
    if len(t) < 3:
        return np.concatenate([[0.0], np.cumsum(0.5 * (power[1:] + power[:-1]) * np.diff(t))])
    return cumulative_simpson(power, x=t, initial=0.0)


def _quadrature_error(t: np.ndarray, power: np.ndarray) -> float:
    """Richardson's estimate of the largest quadrature error of ``int power dt`` over the
    rows [J]: the rule over all rows against the rule over every other one, at the rows
    both reach, divided by ``2^4 - 1``."""
    if len(t) < 5:
        return float("inf") if np.any(power) else 0.0
    end = len(t) - 1 - (len(t) - 1) % 2          # the last row both rules reach
    fine = _integral(t[:end + 1], power[:end + 1])[::2]
    coarse = _integral(t[:end + 1:2], power[:end + 1:2])
    return float(np.max(np.abs(fine - coarse))) / 15.0


def _load_power(result: SimulationResult, forces: Forces | None) -> np.ndarray:
    """``f . v`` at every row [W]: the model's constant loads and ``forces``' ``(nt,)``."""
    model = result.model
    power = np.zeros(len(result.t))
    if model.nodal_forces:
        power += _power_of(result, np.tile(own_loads(model), (len(result.t), 1)))
    if forces is None:
        return power
    if not callable(forces):
        raise ArgumentError("forces", f"must be the function forces(t, x, xdot) the run "
                                      f"applied, got {forces!r}")
    rows = np.empty((len(result.t), model.n_coordinates))
    for k, (t, x, xd) in enumerate(zip(result.t, result.x, np.asarray(result.xd),
                                       strict=True)):
        try:
            rows[k] = load_vector(model, forces(float(t), x.copy(), xd.copy()), "forces")
        except (ArgumentError, SimulationError):
            raise
        except Exception as error:   # the user's function: named, with its time
            raise SimulationError(f"forces raised {type(error).__name__}: {error} at t = "
                                  f"{t:.6g} s while its work was formed", float(t)) from error
    return power + _power_of(result, rows)


def _power_of(result: SimulationResult, loads: np.ndarray) -> np.ndarray:
    """The power ``(nt,)`` [W] of loads ``(nt, nx)`` given as :func:`load_vector` gives
    them: a force or a planar torque times its coordinate's rate, a spatial moment times
    its node's angular velocity."""
    model, xd = result.model, np.asarray(result.xd)
    power = np.zeros(len(loads))
    for node in model.nodes.values():
        at = list(node.coordinates)
        if not at or not np.any(loads[:, at]):
            continue
        if node.kind == SPATIAL_ROTATIONAL:
            power += np.sum(loads[:, at[1:]] * result.angular_velocity(node.number), axis=1)
        else:
            power += np.sum(loads[:, at] * xd[:, at], axis=1)
    return power


def warn_if_unresolved(error: float, balance: np.ndarray, scale: float, rtol: float) -> None:
    """Warn (:class:`~flexmbd.AccuracyWarning`) when the quadrature error of the work
    ``error`` [J] is more than :data:`QUADRATURE_SHARE` of the largest ``|balance|`` [J]
    and more than the integrator's relative tolerance ``rtol`` of the energies' ``scale``
    [J]: the balance then measures the output grid rather than the integrator."""
    largest = float(np.max(np.abs(balance))) if len(balance) else 0.0
    if error <= max(QUADRATURE_SHARE * largest, rtol * scale):
        return
    warnings.warn(
        f"the work over the output rows is uncertain by about {error:.2g} J (Simpson's rule "
        f"against itself over every other row), {error / max(scale, 1e-300):.2g} of the "
        f"largest energy and {error / max(largest, 1e-300):.2g} of the largest imbalance: "
        f"the balance measures the output grid rather than the integrator; output at more "
        f"times (the power changes faster than the rows)", AccuracyWarning, stacklevel=3)
