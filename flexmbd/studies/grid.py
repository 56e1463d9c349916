"""The cases of a parameter study: a product of value lists, or an explicit list of cases,
and the value syntax of the command line (lists, ranges, log ranges)."""

from __future__ import annotations

import itertools
import math
import numbers
from collections.abc import Mapping, Sequence

import numpy as np

from ..errors import ArgumentError

#: columns every study table has; parameters and outputs may not take these names
RESERVED = ("case", "status", "error", "wall_time")
#: a study larger than this is refused as a likely typo (a range with a wrong bound)
LARGEST_STUDY = 10**6


def cases(grid) -> list[dict[str, object]]:
    """The cases of ``grid``, each a ``{name: value}`` dict, in order.

    ``grid`` is a mapping ``{name: values}`` (every combination, the last name varying
    fastest, as :func:`itertools.product`) or a sequence of mappings (the cases as
    given; all must name the same parameters). Values are numbers, strings or
    booleans, so that they fit a table column.

    Raises:
        ArgumentError: an empty grid, a value list that is empty or not a list, cases
            naming different parameters, a name that is not an identifier or is one of
            the table's own columns (:data:`RESERVED`), a value that is not a scalar.
    """
    if isinstance(grid, Mapping):
        names = list(grid)
        columns = []
        for name in names:
            values = grid[name]
            if isinstance(values, (str, bytes)) or not isinstance(values, (Sequence, np.ndarray)):
                raise ArgumentError("grid", f"{name!r} must map to a list of values, got "
                                            f"{values!r}")
            if len(values) == 0:
                raise ArgumentError("grid", f"{name!r} has no values")
            columns.append(list(values))
        size = math.prod(len(c) for c in columns)
        if size > LARGEST_STUDY:
            raise ArgumentError("grid", f"{size} cases is more than {LARGEST_STUDY}")
        out = [dict(zip(names, combination, strict=True))
               for combination in itertools.product(*columns)]
    elif isinstance(grid, Sequence) and not isinstance(grid, (str, bytes)):
        out = [dict(case) if isinstance(case, Mapping) else _not_a_case(case) for case in grid]
        names = list(out[0]) if out else []
        for k, case in enumerate(out):
            if set(case) != set(names):
                raise ArgumentError("grid", f"case {k} names {sorted(case)}, case 0 names "
                                            f"{sorted(names)}; every case names the same "
                                            f"parameters")
    else:
        raise ArgumentError("grid", f"must be a mapping {{name: values}} or a list of "
                                    f"{{name: value}} cases, got {type(grid).__name__}")
    if not out or not names:
        raise ArgumentError("grid", "has no cases: name at least one parameter and its values")
    for name in names:
        check_name(name, "grid")
    return [{name: _scalar(case[name], name) for name in names} for case in out]


def check_name(name: object, argument: str) -> str:
    """A parameter or output name: a non-empty string that is not a reserved column."""
    if not isinstance(name, str) or not name.strip():
        raise ArgumentError(argument, f"names must be non-empty strings, got {name!r}")
    if name in RESERVED:
        raise ArgumentError(argument, f"{name!r} is a column of every study table "
                                      f"({', '.join(RESERVED)}); choose another name")
    return name


def _not_a_case(case):
    raise ArgumentError("grid", f"a list of cases holds {{name: value}} mappings, got {case!r}")


def _scalar(value, name: str):
    """A parameter value as a plain Python scalar (NumPy scalars included)."""
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, (bool, str)):
        return value
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, numbers.Real):
        if not math.isfinite(value):
            raise ArgumentError("grid", f"{name} = {value!r} is not finite")
        return float(value)
    raise ArgumentError("grid", f"{name} = {value!r}: values are numbers, strings or booleans")


def parse_values(text: str, option: str = "--vary") -> list[int | float]:
    """The values of a command-line text.

    * ``1,2,5.5``: a list;
    * ``1..10``: the whole numbers from 1 to 10;
    * ``0.1..0.5/5``: 5 values evenly spaced from 0.1 to 0.5, both included;
    * ``log:1e-3..1e3/7``: 7 values evenly spaced in the logarithm (a geometric series).

    Raises:
        ArgumentError: naming ``option`` and the form it expects.
    """
    forms = "a list 1,2,5, a range 1..10, 0.1..0.5/5 (5 values) or log:1e-3..1e3/7"
    body, logarithmic = (text[4:], True) if text.lower().startswith("log:") else (text, False)
    try:
        if ".." not in body:
            if logarithmic:
                raise ValueError
            values = [_number(word) for word in body.split(",")]
        else:
            span, _, count = body.partition("/")
            low, high = (_number(word) for word in span.split("..", 1))
            if count:
                n = int(count)
                if n < 1:
                    raise ValueError
                if logarithmic:
                    if low <= 0 or high <= 0:
                        raise ArgumentError(option, f"{text}: a log range needs positive "
                                                    f"bounds")
                    values = list(np.geomspace(low, high, n))
                else:
                    values = list(np.linspace(low, high, n))
                values = [float(v) for v in values]
            elif isinstance(low, int) and isinstance(high, int) and not logarithmic:
                if high < low:
                    raise ArgumentError(option, f"{text}: the range is empty ({low} > {high})")
                values = list(range(low, high + 1))
            else:
                raise ArgumentError(option, f"{text}: a range of non-whole numbers needs its "
                                            f"number of values, e.g. {span}/5")
    except ArgumentError:
        raise
    except (ValueError, OverflowError):  # a word that is not a number
        raise ArgumentError(option, f"{text!r} is not {forms}") from None
    if len(values) > LARGEST_STUDY:
        raise ArgumentError(option, f"{text}: {len(values)} values is more than {LARGEST_STUDY}")
    return values


def _number(word: str) -> int | float:
    """A whole number as int, else a finite float."""
    word = word.strip()
    try:
        return int(word)
    except ValueError:
        value = float(word)
    if not math.isfinite(value):
        raise ValueError(word)
    return value
