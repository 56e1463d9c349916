"""The linearized analyses at every load step of a static equilibrium, as a flexure
designer follows them: frequencies, buckling load factors and support compliance, each
linearized at that step's equilibrium (never at the unloaded state: a loaded structure's
buckling load and frequencies are those of its loaded state).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Literal

import numpy as np

from ..errors import ArgumentError
from ..progress import progress_bar
from .modes import buckling, node_compliance, vibration_modes
from .statics import StaticResult

__all__ = ["load_step_table"]


def load_step_table(statics: StaticResult, *, modes: int = 0, buckle: int = 0,
                    compliance: Sequence[tuple[int, int | None]] = (),
                    frame: Literal["global", "body"] = "global",
                    drive: Literal["held", "free"] = "held",
                    progress: bool | None = None) -> dict[str, np.ndarray]:
    """Columns over the load steps of a static equilibrium: ``load`` (the load factor);
    ``f1`` to ``f<modes>`` the lowest vibration frequencies [Hz]; ``buckling1``, ... the load
    factors of the step's loads at which it buckles, smallest in size first, with their
    sign (a negative one buckles with the loads reversed); for each ``(node, rotational)``
    of ``compliance`` the entries ``C<node>.<i><j>`` of its compliance
    (:func:`~flexmbd.analysis.modes.node_compliance`, ``frame`` and ``drive`` as there).

    A value a step cannot have (fewer modes than asked, a state without stresses for
    buckling, a mechanism for compliance) is NaN.
    """
    if not isinstance(statics, StaticResult):
        raise ArgumentError("statics", f"must be a static_equilibrium result, got "
                                       f"{type(statics).__name__}")
    for name, count in (("modes", modes), ("buckle", buckle)):
        if isinstance(count, bool) or not isinstance(count, int | np.integer) or count < 0:
            raise ArgumentError(name, f"must be a whole number >= 0, got {count!r}")
    rows = len(statics.t)
    columns: dict[str, np.ndarray] = {"load": np.asarray(statics.t, dtype=float).copy()}
    for k in range(modes):
        columns[f"f{k + 1}"] = np.full(rows, np.nan)
    for k in range(buckle):
        columns[f"buckling{k + 1}"] = np.full(rows, np.nan)
    sizes = {}
    for node, rotational in compliance:
        probe = statics.linearization(0) if rows else None
        size = 0 if probe is None else len(node_compliance(probe, node, rotational))
        sizes[node] = size
        for i in range(size):
            for j in range(size):
                columns[f"C{node}.{i + 1}{j + 1}"] = np.full(rows, np.nan)
    with progress_bar(statics.t, "linearized load steps", progress) as advance:
        for row in range(rows):
            lin = statics.linearization(row)
            if modes:
                _fill(columns, "f", row, lambda lin=lin: vibration_modes(lin, modes).frequencies)
            if buckle:
                _fill(columns, "buckling", row, lambda lin=lin: buckling(lin, buckle).factors)
            for node, rotational in compliance:
                try:
                    C = node_compliance(lin, node, rotational, frame=frame, drive=drive)
                except (ArithmeticError, ValueError, RuntimeError):
                    continue
                for i in range(sizes[node]):
                    for j in range(sizes[node]):
                        columns[f"C{node}.{i + 1}{j + 1}"][row] = C[i, j]
            if advance is not None:
                advance(statics.t[row])
    return columns


def _fill(columns: dict, prefix: str, row: int, values) -> None:
    """Put ``values()`` into the columns ``<prefix>1, ..`` of ``row``; NaN where the step
    has fewer or none (its analysis refused)."""
    try:
        found = np.asarray(values(), dtype=float)
    except (ArithmeticError, ValueError, RuntimeError):
        return
    for k, value in enumerate(found):
        if f"{prefix}{k + 1}" in columns:
            columns[f"{prefix}{k + 1}"][row] = value
