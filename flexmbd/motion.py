"""Prescribed motions (kinematic inputs) as functions of time.

A law returns the value, rate and second derivative of one prescribed
coordinate or deformation at time ``t``. Values are absolute: a rotational
input is the node angle relative to the reference configuration [rad], a
translational input the coordinate itself [m].
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from . import checks
from .errors import ArgumentError


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

    def __post_init__(self):
        for name in ("x0", "v0", "a0"):
            checks.real(getattr(self, name), f"Polynomial {name}")

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


@dataclass(frozen=True)
class Expression:
    """A law from one expression in ``t`` [s]: a string such as ``"0.5 * sin(3 * t)"`` or a
    SymPy expression; its rate and second derivative are derived symbolically (SymPy, on
    first use). The string is read by SymPy, so give only text you trust.
    """

    expression: object
    _functions: tuple = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        import sympy

        t = sympy.Symbol("t", real=True)
        try:
            value = sympy.sympify(self.expression, locals={"t": t})
        except (sympy.SympifyError, SyntaxError, TypeError, ValueError) as error:
            raise ArgumentError("law", f"{self.expression!r} is not an expression in t: "
                                       f"{error}") from None
        value = value.subs({s: t for s in value.free_symbols if s.name == "t"})
        others = sorted(s.name for s in value.free_symbols if s != t)
        if others:
            raise ArgumentError("law", f"{self.expression!r} may depend on t only, not on "
                                       f"{', '.join(others)}")
        derivatives = (value, sympy.diff(value, t), sympy.diff(value, t, 2))
        object.__setattr__(self, "_functions",
                           tuple(sympy.lambdify(t, d, modules="math") for d in derivatives))

    def __call__(self, t: float) -> tuple[float, float, float]:
        return tuple(float(f(t)) for f in self._functions)  # type: ignore[return-value]


@dataclass(frozen=True)
class Shifted:
    """A law less a constant ``offset``: ``law(t)`` with its value lowered by ``offset``
    (its rate and second derivative unchanged). The builder makes one of an absolute
    angle (``input_coordinate(..., absolute=True)``): the increment from the drawn one."""

    law: Callable[[float], tuple[float, float, float]]
    offset: float

    def __call__(self, t: float) -> tuple[float, float, float]:
        value, rate, acceleration = self.law(t)
        return (value - self.offset, rate, acceleration)


def shifted(law, offset: float):
    """``law`` less ``offset`` [m or rad]: a :class:`Polynomial` stays one (SPACAR files
    write only those), any other law becomes :class:`Shifted`."""
    if isinstance(law, Polynomial):
        return Polynomial(law.x0 - offset, law.v0, law.a0)
    return Shifted(law, offset)


#: anything that maps time to (value, rate, second derivative)
Law = Callable[[float], tuple[float, float, float]]


def as_law(law) -> Law:
    """A law as given, or :class:`Expression` of a string or SymPy expression."""
    if isinstance(law, str) or type(law).__module__.startswith("sympy"):
        return Expression(law)
    return law
