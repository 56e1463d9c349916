"""A student's numbers against flexmbd's: the tolerance, the first entry that differs,
and the hint for a typical mistake.

An answer passes when every entry is within ``rtol`` of the answer's own size, its
largest entry, plus an absolute :data:`ABSOLUTE` for answers that are zero up to
round-off. So an entry near zero is held to what the quantity allows, not to a stricter
floor, and an accurate finite difference passes there as it does elsewhere.
"""

from __future__ import annotations

import math
import re

import numpy as np

from .parts import Part

#: the absolute tolerance besides the relative one (for answers that are zero up to
#: round-off, such as the deformations of a consistent configuration)
ABSOLUTE = 1e-9


def conform(got, expected):
    """``got`` in the shape of ``expected`` where that is unambiguous, else ``got``: a flat
    vector ``(n,)`` for a column ``(n, 1)`` or row ``(1, n)``, and any vector for a flat
    one. A row for a column (a transpose) stays, and fails with its hint."""
    if isinstance(expected, tuple) or isinstance(got, tuple):
        return got
    expected = np.asarray(expected, dtype=float)
    if got.shape == expected.shape or got.size != expected.size:
        return got
    vector = expected.ndim <= 1 or 1 in expected.shape
    flat_given = got.ndim <= 1
    flat_wanted = expected.ndim <= 1 and (got.ndim <= 1 or 1 in got.shape)
    if (vector and flat_given) or flat_wanted:
        return got.reshape(expected.shape)
    return got


def off(got: np.ndarray, expected: np.ndarray, rtol: float) -> np.ndarray:
    """Where ``got`` differs from ``expected`` (same shapes): by more than ``rtol`` times
    the answer's largest entry plus :data:`ABSOLUTE`; NaN is always off."""
    scale = float(np.max(np.abs(expected), initial=0.0))
    return ~(np.abs(got - expected) <= rtol * scale + ABSOLUTE)


def close(got, expected, rtol: float) -> bool:
    """Whether ``got`` is ``expected`` (arrays, or tuples of them) within ``rtol``."""
    if isinstance(expected, tuple):
        return isinstance(got, tuple) and len(got) == len(expected) and all(
            close(g, e, rtol) for g, e in zip(got, expected, strict=True))
    if isinstance(got, tuple):
        return False
    expected = np.asarray(expected, dtype=float)
    got = conform(got, expected)
    if got.shape != expected.shape:
        return False
    return not np.any(off(got, expected, rtol))


def first_difference(got, expected, rtol: float) -> str:
    """The first entry that differs, or the shapes when they do."""
    if isinstance(expected, tuple):
        if not isinstance(got, tuple) or len(got) != len(expected):
            return f"expected a tuple of {len(expected)} arrays"
        for k, (g, e) in enumerate(zip(got, expected, strict=True)):
            if not close(g, e, rtol):
                return f"item {k}: " + first_difference(g, e, rtol)
        return ""
    expected = np.asarray(expected, dtype=float)
    if isinstance(got, tuple):
        return f"expected an array of shape {expected.shape}, got a tuple"
    got = conform(got, expected)
    if got.shape != expected.shape:
        return f"shape {got.shape}, expected {expected.shape}"
    bad = np.argwhere(off(got, expected, rtol))
    if expected.ndim and not len(bad):
        return "differs"
    index = tuple(int(i) for i in bad[0]) if expected.ndim else ()
    where = f"entry {list(index)}" if index else "value"
    return f"{where}: expected {expected[index]:.10g}, got {got[index]:.10g}"


def unwrapped(got, expected, angles) -> np.ndarray:
    """``got`` with its angle entries ``angles`` turned by whole turns to the nearest of
    ``expected``'s."""
    if isinstance(got, tuple) or isinstance(expected, tuple):
        return got
    expected = np.asarray(expected, dtype=float)
    got = conform(got, expected)
    if got.shape != expected.shape:
        return got
    flat, wanted = got.astype(float).ravel().copy(), expected.ravel()
    for i in angles:
        if i < flat.size and np.isfinite(flat[i]):
            flat[i] -= 2 * np.pi * np.round((flat[i] - wanted[i]) / (2 * np.pi))
    return flat.reshape(got.shape)


#: how a file asks NumPy for single (or half) precision
SINGLE_PRECISION = re.compile(rb"float32|float16|\bhalf\b|\bsingle\b|['\"]f[24]['\"]")


def single_precision_in(content: bytes) -> str | None:
    """The single-precision type a file's text names, if any (``"float32"``)."""
    match = SINGLE_PRECISION.search(content)
    return match.group(0).decode("ascii", "replace").strip("'\"") if match else None


def _single_precision(got) -> bool:
    """Whether every entry of ``got`` is a single-precision number, and not all of them
    small integers (which every precision holds)."""
    arrays = got if isinstance(got, tuple) else (got,)
    values = np.concatenate([np.ravel(a) for a in arrays])
    finite = values[np.isfinite(values)]
    return bool(finite.size) and bool(np.all(finite.astype(np.float32) == finite)) and \
        not np.all(finite == np.round(finite))


def _agreeing_digits(got, expected) -> int:
    """How many significant digits ``got`` shares with ``expected`` (same shapes)."""
    expected = np.asarray(expected, dtype=float)
    scale = float(np.max(np.abs(expected), initial=0.0)) or 1.0
    worst = float(np.max(np.abs(np.asarray(got, dtype=float) - expected), initial=0.0))
    return max(0, int(-math.log10(max(worst / scale, 1e-16))))


def _closeness(part: Part, got, expected, precision: str | None) -> str:
    """The hint for an answer near the right one: what limits its accuracy."""
    if not close(got, expected, 1e-3):
        return ""
    if precision or _single_precision(got):
        kind = precision or "float32"
        return (f"your answer is computed in single precision ({kind}, about 7 significant "
                f"digits); compute in float64, NumPy's default (no dtype=np.float32)")
    if isinstance(got, tuple) or got.shape != np.shape(expected):
        return ""
    digits = _agreeing_digits(got, expected)
    if part.iterative:
        return (f"close to the answer ({digits} digits) but not within the check's "
                f"{part.rtol:g} of its size: the part iterates (Newton-Raphson); tighten "
                f"its tolerance (|e| < 1e-12)")
    return (f"close to the answer ({digits} digits) but not within the check's "
            f"{part.rtol:g} of its size: a derivative by finite differences with a large "
            f"step, or a constant with few digits? Use the exact formula, or central "
            f"differences with a step near 1e-6")


def diagnose(part: Part, args: tuple, got, expected, precision: str | None = None) -> str:
    """The hint for a wrong answer that matches a typical mistake, or ``""``;
    ``precision`` names the single precision the answer (or the file) computes in, if
    any."""
    def matches(wrong):
        try:
            mine = got if part.wrapped is None else unwrapped(got, wrong, part.wrapped(*args))
            return close(mine, wrong, part.rtol)
        except (TypeError, ValueError):
            return False

    for mistake in part.mistakes:
        if matches(mistake.wrong(*args)):
            return mistake.hint
    names = [n.strip() for n in part.arguments.split(",")]
    for i in part.angles:
        for factor, read in ((math.pi / 180, "as degrees"), (180 / math.pi, "in radians "
                                                                               "twice")):
            shifted = list(args)
            shifted[i] = args[i] * factor
            try:
                wrong = part.answer(*shifted)
            except Exception:
                continue
            if matches(wrong):
                return (f"angles are in radians: your answer is right for {names[i]} read "
                        f"{read} (no np.radians/np.deg2rad on an angle that is already in "
                        f"radians)")
    if isinstance(expected, tuple) or isinstance(got, tuple):
        return _closeness(part, got, expected, precision)
    expected = np.asarray(expected, dtype=float)
    if expected.ndim == 2 and got.shape == expected.T.shape and got.shape != expected.shape \
            and close(got.T, expected, part.rtol):
        return (f"transposed: the answer has shape {expected.shape}, one row per "
                f"deformation (or coordinate) and one column per coordinate (or q)")
    if expected.ndim == 2 and min(expected.shape) > 1 and got.shape == expected.shape:
        order = []
        for column in got.T:
            found = [k for k, e in enumerate(expected.T) if close(column, e, part.rtol)]
            order.append(found[0] if found else None)
        if None not in order and order != list(range(len(order))):
            return (f"columns out of order: your columns are the answer's columns "
                    f"{order}; order them as the coordinates ({part.arguments}) are")
    if matches(-expected):
        return "the sign is reversed: check the direction of d = r_q - r_p and of the normals"
    return _closeness(part, conform(got, expected), expected, precision)
