"""Short representations: what a user sees by typing a variable's name (as MATLAB users
do). A model or result prints a few lines, with sizes, columns, span and status and how
to see more, never its arrays or its whole model: a 201-point run used to print 64 kB.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping

import numpy as np

__all__ = ["LIMIT", "Columns", "brief", "dataclass_repr"]

#: the longest representation [characters]; longer ones are cut with a note
LIMIT = 1500


def brief(value) -> str:
    """One short phrase for a value: an array's shape, a mapping's or list's length, a
    model's name, a short scalar or text as it is."""
    if isinstance(value, np.ndarray):
        if value.size <= 6 and value.ndim <= 1 and value.dtype.kind in "fiub":
            return np.array2string(value, precision=6, separator=", ")
        return f"<{'x'.join(map(str, value.shape))} array>"
    if hasattr(value, "n_coordinates") and hasattr(value, "name"):   # a Model
        return f"Model({value.name!r})"
    if isinstance(value, Mapping):
        return f"{{{len(value)} entries}}"
    if isinstance(value, (list, tuple)) and len(value) > 4:
        return f"[{len(value)} items]"
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return f"{type(value).__name__}(...)"
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def clip(text: str) -> str:
    """``text`` cut to :data:`LIMIT` characters, saying so."""
    if len(text) <= LIMIT:
        return text
    return text[:LIMIT - 40].rstrip() + " ... (cut; see its attributes)"


def dataclass_repr(self) -> str:
    """``Name(field=brief, ...)``: a dataclass's fields in a line or a few, each as
    :func:`brief` gives it; the ``__repr__`` of flexmbd's results."""
    parts = [f"{field.name}={brief(getattr(self, field.name))}"
             for field in dataclasses.fields(self) if field.repr]
    return clip(f"{type(self).__name__}({', '.join(parts)})")


class Columns(dict):
    """Columns by name (``{"t": (n,) array, "x3.1": ...}``), a ``dict`` that prints as a
    few lines: how many columns and rows, the first names and how to get one."""

    def __repr__(self) -> str:
        names = list(self)
        rows = len(next(iter(self.values()))) if names else 0
        shown = ", ".join(names[:8]) + (f", ... ({len(names) - 8} more)"
                                        if len(names) > 8 else "")
        return clip(f"{len(names)} columns of {rows} rows: {shown}\n  one: "
                    f"table[{names[0]!r}] (an array); all names: list(table)" if names
                    else "no columns")

    __str__ = __repr__
