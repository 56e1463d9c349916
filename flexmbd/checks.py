"""Checking what a user hands in, where it enters: numbers, tolerances, iteration and step
limits, output times and the memory of a run's output.

Every refusal is an :class:`~flexmbd.errors.ArgumentError` that names the argument and
says what would work, so that a setting that cannot work fails at once instead of
after minutes of computing (or never).
"""

from __future__ import annotations

import functools
import inspect
import math
import os
import warnings
from collections.abc import Iterable, Mapping

import numpy as np

from .errors import ArgumentError, LabelError

EPS = float(np.finfo(float).eps)
#: Newton converges in a handful of iterations or not at all: more than this cannot help
LARGEST_ITERATIONS = 1000
#: integration steps beyond this would run for hours (each takes microseconds at best)
LARGEST_STEPS = 10**9
#: a run's output may take at most this share of the memory available when it starts
MEMORY_SHARE = 0.5
#: integrator tolerances: below ``SMALLEST_RTOL`` round-off dominates (scipy clips there);
#: above ``LARGEST_RTOL`` no digit of the result is controlled
SMALLEST_RTOL, LARGEST_RTOL = 100 * EPS, 0.1


def real(value, name: str, finite: bool = True) -> float:
    """``value`` as a float, finite unless ``finite`` is false, or an error naming
    ``name``."""
    if isinstance(value, (bool, str, bytes)) or value is None:
        raise ArgumentError(name, f"must be a number, got {value!r}")
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ArgumentError(name, f"must be a number, got {value!r}") from None
    if finite and not math.isfinite(number):
        raise ArgumentError(name, f"must be finite, got {value!r}")
    return number


def whole(value, name: str, low: int, high: int) -> int:
    """``value`` as an int in ``[low, high]``, or an error naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise ArgumentError(name, f"must be a whole number, got {value!r}")
    if not low <= value <= high:
        raise ArgumentError(name, f"must lie in {low} .. {high}, got {value}")
    return int(value)


def position_tolerance(tolerance, length: float, size: float) -> float:
    """Newton tolerance of the position solve [m, rad] for a model of characteristic
    length ``length`` and largest coordinate ``size`` [m]: above round-off of the
    coordinates, and small against the model."""
    tolerance = real(tolerance, "tolerance")
    smallest = 8 * EPS * max(length, size)
    if tolerance < smallest:
        raise ArgumentError("tolerance", f"{tolerance:g} is below the round-off of the "
                            f"coordinates ({smallest:.1g} for a model of size "
                            f"{max(length, size):.3g} m): Newton could never meet it")
    if tolerance > 1e-2 * length:
        raise ArgumentError("tolerance", f"{tolerance:g} is not small against the model's "
                            f"size {length:.3g} m: the configurations would be wrong by "
                            f"that much; use at most {1e-2 * length:.1g}, typically "
                            f"{1e-10 * length:.1g}")
    return tolerance


def iteration_limit(value) -> int:
    """Newton iterations of a position solve before giving up."""
    return whole(value, "max_iterations", 1, LARGEST_ITERATIONS)


def integrator_tolerances(rtol, atol, length: float) -> tuple[float, float]:
    """``rtol`` and ``atol`` of an integrator for a model of characteristic length
    ``length`` [m]: ``rtol`` between round-off and 0.1, ``atol`` positive and small
    against the model."""
    rtol, atol = real(rtol, "rtol"), real(atol, "atol")
    if not SMALLEST_RTOL <= rtol <= LARGEST_RTOL:
        raise ArgumentError("rtol", f"{rtol:g} must lie in {SMALLEST_RTOL:.1g} .. "
                            f"{LARGEST_RTOL:g}: below, round-off makes the steps shrink "
                            f"without end; above, no digit is controlled")
    if not 0 < atol <= 0.1 * length:
        raise ArgumentError("atol", f"{atol:g} must be positive and small against the "
                            f"model's size {length:.3g} m (at most {0.1 * length:.2g})")
    return rtol, atol


def time_grid(times, name: str = "times") -> np.ndarray:
    """Output times as a float array ``(nt,)``: one-dimensional, finite, increasing."""
    try:
        grid = np.asarray(times, dtype=float)
    except (TypeError, ValueError):
        raise ArgumentError(name, "must be a sequence of numbers [s]") from None
    if grid.ndim != 1:
        raise ArgumentError(name, f"must be one-dimensional, got shape {grid.shape}")
    if grid.size == 0 or not np.all(np.isfinite(grid)):
        raise ArgumentError(name, "must be a non-empty sequence of finite times [s]")
    if np.any(np.diff(grid) <= 0):
        k = int(np.flatnonzero(np.diff(grid) <= 0)[0])
        raise ArgumentError(name, f"must increase strictly; entry {k + 1} ({grid[k + 1]:g}) "
                            f"does not exceed entry {k} ({grid[k]:g})")
    return grid


def step_count(span: float, step: float, name: str) -> int:
    """Steps of size ``step`` over ``span`` [s], refused beyond :data:`LARGEST_STEPS`."""
    steps = span / step
    if steps > LARGEST_STEPS:
        raise ArgumentError(name, f"{step:g} s over {span:g} s makes {steps:.3g} steps, more "
                            f"than {LARGEST_STEPS:.0e} (hours of computing); take a larger "
                            f"step")
    return math.ceil(steps)


def available_memory() -> int:
    """Bytes of memory available to a new allocation (MemAvailable on Linux)."""
    try:
        with open("/proc/meminfo") as info:
            for line in info:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return 2**63  # unknown: do not refuse


def output_memory(rows: int, bytes_per_row: int, name: str = "times") -> None:
    """Refuse, before any work, a run of ``rows`` output times holding ``bytes_per_row``
    each (:func:`flexmbd.engine.output_bytes`) that cannot fit in memory."""
    need = float(rows) * bytes_per_row
    have = available_memory()
    if need > MEMORY_SHARE * have:
        raise ArgumentError(name, f"{rows} output times of {bytes_per_row // 8} values need "
                            f"{need / 2**30:.3g} GiB, more than half of the "
                            f"{have / 2**30:.3g} GiB of memory available; ask for fewer "
                            f"output times (at most {int(MEMORY_SHARE * have / bytes_per_row)} "
                            f"here), or record fewer columns")


def vector(value, size: int, name: str, what: str) -> np.ndarray:
    """``value`` as a finite float array of shape ``(size,)`` (``what`` says what its entries
    are, for the message), or an error naming ``name``."""
    try:
        array = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ArgumentError(name, f"must be an array of {size} numbers ({what})") from None
    if array.shape != (size,):
        raise ArgumentError(name, f"must have shape ({size},) ({what}), got shape "
                            f"{array.shape}")
    if not np.all(np.isfinite(array)):
        k = int(np.flatnonzero(~np.isfinite(array))[0])
        raise ArgumentError(name, f"entry {k} is {array[k]} ({what}); every entry must be "
                            f"finite")
    return array


def choice(value, name: str, options: tuple[str, ...]) -> str:
    """``value`` if it is one of the strings ``options``, or an error naming ``name``."""
    if not isinstance(value, str) or value not in options:
        raise ArgumentError(name, f"must be {_either(options)}, got {value!r}")
    return value


def _either(options: tuple[str, ...]) -> str:
    quoted = [repr(option) for option in options]
    return quoted[0] if len(quoted) == 1 else f"{', '.join(quoted[:-1])} or {quoted[-1]}"


def number_map(value, name: str) -> dict:
    """``value``, a mapping of labels to numbers (``{"x2.1": 0.5}``), with each number a
    finite float; or an error naming ``name`` (and the label)."""
    if not isinstance(value, Mapping):
        raise ArgumentError(name, f"must be a mapping of labels to numbers such as "
                                  f"{{'x2.1': 0.5}}, got {value!r}")
    return {label: real(number, f"{name} {label}") for label, number in value.items()}


def coordinates_named(model, values, name: str) -> tuple[list[str], list[int]]:
    """The coordinates named by ``values``, one label (``"x5.2"``, ``(5, 2)``) or a sequence
    of them, as the model's labels and indices; or an error naming ``name`` with the
    closest labels."""
    one = isinstance(values, str) or (isinstance(values, tuple) and len(values) == 2 and
                                      isinstance(values[0], (int, np.integer)))
    if one:
        values = [values]
    elif isinstance(values, (Mapping, bytes)) or not isinstance(values, Iterable):
        raise ArgumentError(name, f"must be coordinate labels such as ['x5.1', 'x5.2'], got "
                                  f"{values!r}")
    indices = []
    for label in values:
        try:
            indices.append(model.coordinate_index(label))
        except LabelError as error:
            raise ArgumentError(name, str(error.args[0])) from None
        except (TypeError, ValueError):
            raise ArgumentError(name, f"{label!r} is not a coordinate label such as "
                                      f"'x5.2'") from None
    return [model.coordinate_labels[i] for i in indices], indices


def flag(value, name: str, allow_none: bool = False) -> bool | None:
    """``value`` as a bool (``None`` too with ``allow_none``), or an error naming ``name``."""
    if value is None and allow_none:
        return None
    if not isinstance(value, (bool, np.bool_)):
        raise ArgumentError(name, f"must be True or False{' or None' if allow_none else ''}, "
                            f"got {value!r}")
    return bool(value)


#: the release that refuses what is deprecated now
REFUSED_FROM = "flexmbd 0.4"


def deprecated(text: str, stacklevel: int = 3) -> None:
    """Say that a spelling is deprecated: ``text`` says what to write instead; it goes on
    working until :data:`REFUSED_FROM`."""
    warnings.warn(f"{text} (the old spelling works until {REFUSED_FROM})",
                  DeprecationWarning, stacklevel=stacklevel)


def keyword_only(*names: str):
    """Decorator of a public function whose parameters ``names``, once positional, are
    keyword-only now: given by position after the function's positional parameters they
    still arrive, in that order, with a :class:`DeprecationWarning` (flexmbd's convention:
    the model and the grid or state are positional, everything else by name)."""
    def decorate(function):
        positional = sum(p.kind is inspect.Parameter.POSITIONAL_OR_KEYWORD
                         for p in inspect.signature(function).parameters.values())

        @functools.wraps(function)
        def call(*args, **kwargs):
            extra = args[positional:]
            if extra:
                if len(extra) > len(names):
                    raise TypeError(f"{function.__name__}() takes {positional} positional "
                                    f"arguments but {len(args)} were given")
                for name, value in zip(names, extra, strict=False):
                    if name in kwargs:
                        raise TypeError(f"{function.__name__}() got {name} twice")
                    kwargs[name] = value
                given = ", ".join(f"{name}=..." for name in names[:len(extra)])
                deprecated(f"{function.__name__}: give {given} by name, not by position")
            return function(*args[:positional], **kwargs)
        return call
    return decorate
