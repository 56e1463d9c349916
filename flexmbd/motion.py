"""Prescribed motions (kinematic inputs) as functions of time.

A law returns the value, rate and second derivative of one prescribed
coordinate or deformation at time ``t``. Values are absolute: a rotational
input is the node angle relative to the reference configuration [rad], a
translational input the coordinate itself [m].
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass


@dataclass(frozen=True)
class Polynomial:
    """SPACAR's input law ``value(t) = x0 + v0 t + a0 t^2 / 2``.

    Args:
        x0: value at ``t = 0`` [m or rad].
        v0: rate at ``t = 0`` [m/s or rad/s].
        a0: constant second derivative [m/s^2 or rad/s^2].
    """

    x0: float
    v0: float = 0.0
    a0: float = 0.0

    def __call__(self, t: float) -> tuple[float, float, float]:
        return (self.x0 + self.v0 * t + 0.5 * self.a0 * t * t, self.v0 + self.a0 * t, self.a0)


@dataclass(frozen=True)
class Custom:
    """A law from three user functions of time (value, rate, second derivative).

    The derivatives are taken as given; a mismatch between them makes the
    velocities and accelerations of the analysis wrong, so derive them exactly
    (e.g. with SymPy) rather than by finite differences.
    """

    value: Callable[[float], float]
    rate: Callable[[float], float]
    acceleration: Callable[[float], float]

    def __call__(self, t: float) -> tuple[float, float, float]:
        return (float(self.value(t)), float(self.rate(t)), float(self.acceleration(t)))


#: anything that maps time to (value, rate, second derivative)
Law = Callable[[float], tuple[float, float, float]]
