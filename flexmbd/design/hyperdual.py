"""Hyper-dual numbers over NumPy arrays: exact first, second and third derivatives of the
element definitions along chosen directions, with no step size.

A hyper-dual number with ``n`` infinitesimal parts ``eps_1 .. eps_n`` (``eps_i^2 = 0``,
products of different ones kept) has ``2^n`` components, indexed by the bitmask of the
infinitesimals they carry: component ``0`` is the value, ``1`` the factor of ``eps_1``,
``3`` that of ``eps_1 eps_2``, ``7`` that of ``eps_1 eps_2 eps_3``. Evaluating a
function on ``x + eps_1 a + eps_2 b + eps_3 c`` gives its value, its derivatives along
``a``, ``b``, ``c``, the second derivatives ``f''[a, b]`` ... and the third ``f'''[a, b,
c]``, each exact to rounding (Fike and Alonso's hyper-dual numbers, generalised to three
parts). Every component is an array, so one evaluation runs over all elements of a type
at once.

:data:`MATH` is the math module (``sqrt``, ``sin``, ``cos``, ``atan2``) the element
definitions (:meth:`flexmbd.elements.base.ElementType.deformations`) take: the same one
definition as the generated kernels and the symbolic path.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["MATH", "HyperDual", "seed"]


def _pairs(size: int) -> list[tuple[int, int, int]]:
    """``(k, i, j)`` with ``i | j == k`` and ``i & j == 0``: the products of components
    ``i`` and ``j`` that land on component ``k``."""
    return [(i | j, i, j) for i in range(size) for j in range(size) if not i & j]


class HyperDual:
    """A hyper-dual number (module docstring): ``parts`` ``(2^n, ...)``, the value first."""

    __slots__ = ("parts",)
    __array_priority__ = 1000   # numpy scalars and arrays defer to these operators

    def __init__(self, parts: np.ndarray):
        self.parts = parts

    @property
    def value(self) -> np.ndarray:
        return self.parts[0]

    def part(self, mask: int) -> np.ndarray:
        """The component of the infinitesimals in ``mask`` (bit ``i``: ``eps_{i+1}``)."""
        return self.parts[mask]

    def _of(self, other: Any) -> HyperDual:
        if isinstance(other, HyperDual):
            return other
        parts = np.zeros_like(self.parts, dtype=np.result_type(self.parts, other))
        parts[0] = other
        return HyperDual(parts)

    # --- arithmetic ----------------------------------------------------------------------
    def __add__(self, other: Any) -> HyperDual:
        if isinstance(other, HyperDual):
            return HyperDual(self.parts + other.parts)
        parts = self.parts.copy()
        parts[0] = parts[0] + other
        return HyperDual(parts)

    __radd__ = __add__

    def __neg__(self) -> HyperDual:
        return HyperDual(-self.parts)

    def __pos__(self) -> HyperDual:
        return self

    def __sub__(self, other: Any) -> HyperDual:
        return self + (-other)

    def __rsub__(self, other: Any) -> HyperDual:
        return (-self) + other

    def __mul__(self, other: Any) -> HyperDual:
        if not isinstance(other, HyperDual):
            return HyperDual(self.parts * other)
        a, b = self.parts, other.parts
        out = np.zeros(np.broadcast_shapes(a.shape, b.shape))
        for k, i, j in _pairs(len(a)):
            out[k] += a[i] * b[j]
        return HyperDual(out)

    __rmul__ = __mul__

    def __truediv__(self, other: Any) -> HyperDual:
        if not isinstance(other, HyperDual):
            return HyperDual(self.parts / other)
        return self * other._apply(_reciprocal)

    def __rtruediv__(self, other: Any) -> HyperDual:
        return self._apply(_reciprocal) * other

    def __pow__(self, n: Any) -> HyperDual:
        if isinstance(n, (int, np.integer)) and n >= 0:
            out = self._of(1.0)
            for _ in range(int(n)):
                out = out * self
            return out
        return self._apply(lambda x: _power(x, float(n)))

    # --- functions -----------------------------------------------------------------------
    def _apply(self, derivatives) -> HyperDual:
        """``f(self)`` from ``derivatives(value)``, the list ``[f, f', f'', f''']`` at the
        value: the Taylor series in the infinitesimal part, exact to its third power."""
        values = derivatives(self.parts[0])
        delta = HyperDual(self.parts.copy())
        delta.parts[0] = 0.0
        power = delta
        out = HyperDual(np.zeros_like(self.parts))
        out.parts[0] = values[0]
        factorial = 1.0
        for order in range(1, min(4, len(self.parts))):
            factorial *= order
            out = out + power * (values[order] / factorial)
            power = power * delta
        return out


def _reciprocal(x: np.ndarray) -> list[np.ndarray]:
    return [1.0 / x, -1.0 / x**2, 2.0 / x**3, -6.0 / x**4]


def _power(x: np.ndarray, n: float) -> list[np.ndarray]:
    return [x**n, n * x ** (n - 1), n * (n - 1) * x ** (n - 2),
            n * (n - 1) * (n - 2) * x ** (n - 3)]


class _Math:
    """``sqrt``, ``sin``, ``cos`` and ``atan2`` on hyper-dual numbers (and on plain numbers,
    as NumPy computes them)."""

    @staticmethod
    def sqrt(x: Any) -> Any:
        if not isinstance(x, HyperDual):
            return np.sqrt(x)
        return x._apply(lambda v: [np.sqrt(v), 0.5 / np.sqrt(v), -0.25 / v**1.5,
                                   0.375 / v**2.5])

    @staticmethod
    def sin(x: Any) -> Any:
        if not isinstance(x, HyperDual):
            return np.sin(x)
        return x._apply(lambda v: [np.sin(v), np.cos(v), -np.sin(v), -np.cos(v)])

    @staticmethod
    def cos(x: Any) -> Any:
        if not isinstance(x, HyperDual):
            return np.cos(x)
        return x._apply(lambda v: [np.cos(v), -np.sin(v), -np.cos(v), np.sin(v)])

    @staticmethod
    def atan2(y: Any, x: Any) -> Any:
        """The angle of ``(x, y)``: its value from ``arctan2``, its infinitesimal part as
        the angle between ``(x0, y0)`` and ``(x, y)``, ``atan(d)`` with ``d = (x0 y - y0
        x) / (x0 x + y0 y)`` (no value part), ``d - d^3/3`` exactly."""
        if not isinstance(y, HyperDual) and not isinstance(x, HyperDual):
            return np.arctan2(y, x)
        like = y if isinstance(y, HyperDual) else x
        y, x = like._of(y), like._of(x)
        x0, y0 = x.value, y.value
        d = (y * x0 - x * y0) / (x * x0 + y * y0)
        d.parts[0] = 0.0
        out = d - d * d * d * (1.0 / 3.0)
        out.parts[0] = np.arctan2(y0, x0)
        return out


#: the math module of the element definitions on hyper-dual numbers
MATH = _Math()


def seed(value: np.ndarray, directions: list[np.ndarray | None]) -> HyperDual:
    """The hyper-dual number ``value + sum_i eps_i directions[i]`` (``None``: no part of
    ``eps_i``), with ``len(directions)`` infinitesimals; all arrays broadcast together."""
    size = 1 << len(directions)
    shape = np.broadcast_shapes(np.shape(value), *(np.shape(d) for d in directions
                                                   if d is not None))
    parts = np.zeros((size, *shape))
    parts[0] = value
    for i, direction in enumerate(directions):
        if direction is not None:
            parts[1 << i] = direction
    return HyperDual(parts)
