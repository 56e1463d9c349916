"""SymPy answers compared in the grader, without running any of the student's text.

A part that has a symbolic form is also called with SymPy symbols; a student who writes
the formula in SymPy returns an expression. The runner sends it as a tree of its
operations (:func:`flexmbd.course.runner.sympy_tree`); here the tree is evaluated with
complex floating-point numbers, at random points, beside flexmbd's reference turned into
a tree the same way. Equal values at every point (to :data:`RTOL` of the largest) make
the answers equal; two different elementary expressions agree at random points with
probability zero. Nothing is parsed or simplified: an operation outside
:data:`OPERATIONS` makes the answer not comparable, never a risk to the grader.
"""

from __future__ import annotations

import cmath
import math
from collections.abc import Callable

import numpy as np

#: relative tolerance of the values at a point, to the largest of the reference's
RTOL = 1e-9
#: the points at which the expressions are compared
POINTS = 5


def _atan2(y: complex, x: complex) -> complex:
    if abs(y.imag) > 1e-12 or abs(x.imag) > 1e-12:
        raise ValueError("atan2 of complex numbers")
    return complex(math.atan2(y.real, x.real))


def _sign(x: complex) -> complex:
    return 0j if x == 0 else x / abs(x)


def _product(*values: complex) -> complex:
    result = 1 + 0j
    for value in values:
        result *= value
    return result


#: the operations an answer may use, by SymPy's class name
OPERATIONS: dict[str, Callable[..., complex]] = {
    "Add": lambda *a: sum(a, 0j), "Mul": _product, "Pow": lambda a, b: a ** b,
    "sin": cmath.sin, "cos": cmath.cos, "tan": cmath.tan,
    "cot": lambda x: 1 / cmath.tan(x), "sec": lambda x: 1 / cmath.cos(x),
    "csc": lambda x: 1 / cmath.sin(x), "asin": cmath.asin, "acos": cmath.acos,
    "atan": cmath.atan, "acot": lambda x: cmath.atan(1 / x), "atan2": _atan2,
    "sinh": cmath.sinh, "cosh": cmath.cosh, "tanh": cmath.tanh, "exp": cmath.exp,
    "log": cmath.log, "Abs": lambda x: complex(abs(x)), "sign": _sign,
    "re": lambda x: complex(x.real), "im": lambda x: complex(x.imag),
    "conjugate": lambda x: x.conjugate()}
#: the constants, by SymPy's class name
CONSTANTS = {"Pi": math.pi, "Exp1": math.e, "ImaginaryUnit": 1j,
             "GoldenRatio": (1 + math.sqrt(5)) / 2, "EulerGamma": 0.5772156649015329}


class UncomparableError(ValueError):
    """An answer's tree holds something this module does not evaluate."""


def _integer(digits: object) -> int:
    if not isinstance(digits, str) or len(digits.lstrip("-")) > 30:
        raise UncomparableError("an integer of more than 30 digits")
    return int(digits)


def _value(node: object, values: dict[str, complex]) -> complex:
    if not isinstance(node, dict):
        raise UncomparableError("not a tree of operations")
    if "s" in node:
        if node["s"] not in values:
            raise UncomparableError(f"a symbol {str(node['s'])[:30]!r} the part does not give")
        return values[node["s"]]
    if "i" in node:
        return complex(_integer(node["i"]))
    if "q" in node and isinstance(node["q"], list) and len(node["q"]) == 2:
        return complex(_integer(node["q"][0]) / _integer(node["q"][1]))
    if "f" in node and isinstance(node["f"], int | float):
        return complex(node["f"])
    if "c" in node and node["c"] in CONSTANTS:
        return complex(CONSTANTS[node["c"]])
    operation = OPERATIONS.get(node.get("o"))   # type: ignore[arg-type]
    arguments = node.get("a")
    if operation is None or not isinstance(arguments, list):
        raise UncomparableError(f"the operation {str(node.get('o', node.get('c')))[:30]!r}")
    return complex(operation(*[_value(a, values) for a in arguments]))


def evaluate(tree: dict, values: dict[str, complex]) -> np.ndarray:
    """The tree's value at ``values`` (symbol name -> number): a complex array, of the
    matrix's shape or 0-dimensional.

    Raises:
        UncomparableError: the tree has an operation, constant or symbol not known here.
        ArithmeticError, ValueError, RecursionError: it has no value there.
    """
    if "matrix" in tree:
        shape, entries = tree["matrix"], tree.get("entries")
        if not (isinstance(shape, list) and len(shape) == 2 and isinstance(entries, list)
                and all(isinstance(n, int) for n in shape) and shape[0] * shape[1]
                == len(entries)):
            raise UncomparableError("a matrix whose shape and entries disagree")
        return np.array([_value(e, values) for e in entries], dtype=complex).reshape(shape)
    return np.array(_value(tree, values), dtype=complex)


def _conform(got: np.ndarray, expected: np.ndarray) -> np.ndarray | None:
    """``got`` in ``expected``'s shape where it is the same vector or number, else None."""
    if got.shape == expected.shape:
        return got
    vectors = (got.ndim < 2 or 1 in got.shape) and (expected.ndim < 2 or 1 in expected.shape)
    return got.reshape(expected.shape) if vectors and got.size == expected.size else None


def equal(answer: dict, reference: dict, names: list[str], rng) -> bool | None:
    """Whether the trees ``answer`` and ``reference`` have the same values at
    :data:`POINTS` random points of the symbols ``names`` (each in [-2, 2]); ``None``
    when the answer cannot be compared."""
    compared = 0
    for _ in range(4 * POINTS):
        point = rng.uniform(-2.0, 2.0, len(names))
        values = {name: complex(v) for name, v in zip(names, point, strict=True)}
        try:
            expected = evaluate(reference, values)
        except (ArithmeticError, ValueError):
            continue
        if not np.all(np.isfinite(expected)):
            continue
        try:
            got = _conform(evaluate(answer, values), expected)
        except UncomparableError:
            return None
        except (ArithmeticError, ValueError, RecursionError, TypeError):
            return False
        if got is None:
            return False
        scale = max(float(np.max(np.abs(expected), initial=0.0)), 1e-300)
        if not np.all(np.abs(got - expected) <= RTOL * scale):
            return False
        compared += 1
        if compared == POINTS:
            return True
    return None
