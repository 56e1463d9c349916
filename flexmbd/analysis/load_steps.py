"""The linearized analyses at every load step of a static equilibrium, as a flexure
designer follows them: frequencies, buckling load factors and support compliance, each
linearized at that step's equilibrium (never at the unloaded state: a loaded structure's
buckling load and frequencies are those of its loaded state).

Every cell is the public analysis of the step's linearization
(:meth:`~flexmbd.StaticResult.linearization`: :func:`~flexmbd.vibration_modes`,
:func:`~flexmbd.buckling`, :func:`~flexmbd.node_compliance`), so the table and a loop a
user writes give the same numbers by the same path: the engine's banded tangent for a
large model (a few modes by ARPACK, the compliance by its solves), the reduced matrices
otherwise. A cell a step cannot have is NaN with its reason in the table's notes: fewer
modes than asked, a state without stresses (buckling), a singular tangent (a
mechanism, or past buckling). Any other error propagates.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Literal

import numpy as np

from ..errors import ArgumentError
from ..progress import progress_bar
from ..summary import Columns
from .modes import NO_VALUE, buckling, compliance_labels, node_compliance, vibration_modes
from .statics import StaticResult

__all__ = ["StepTable", "load_step_table"]

class StepTable(Columns):
    """Columns over the load steps (a ``dict`` of arrays), with why a cell is NaN and how
    each analysis ran.

    Attributes:
        notes: one line per NaN cell group: the columns, the step and the reason.
        paths: per analysis (``"modes"``, ``"buckling"``, ``"compliance"``), the ways it
            ran over the steps (:class:`~flexmbd.analysis.eigen.EigenPath` as text).
    """

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.notes: list[str] = []
        self.paths: dict[str, list[str]] = {}

    def __repr__(self) -> str:
        lines = [super().__repr__()]
        lines += [f"  {name}: {'; '.join(ways)}" for name, ways in self.paths.items()]
        lines += [f"  note: {note}" for note in self.notes[:5]]
        if len(self.notes) > 5:
            lines.append(f"  ... {len(self.notes) - 5} more notes (table.notes)")
        return "\n".join(lines)

    __str__ = __repr__

    def ran(self, analysis: str, path) -> None:
        """Record that ``analysis`` ran by ``path`` (once per distinct way)."""
        ways = self.paths.setdefault(analysis, [])
        if str(path) not in ways:
            ways.append(str(path))


def load_step_table(statics: StaticResult, *, modes: int = 0, buckle: int = 0,
                    compliance: Sequence[tuple[int, int | None]] = (),
                    frame: Literal["global", "body"] = "global",
                    drive: Literal["held", "free"] = "held",
                    progress: bool | None = None) -> StepTable:
    """Columns over the load steps of a static equilibrium: ``load`` (the load factor);
    ``f1`` to ``f<modes>`` the lowest vibration frequencies [Hz]; ``buckling1``, ... the load
    factors of the step's loads at which it buckles, smallest in size first, with their
    sign (a negative one buckles with the loads reversed); for each ``(node, rotational)``
    of ``compliance`` the entries ``C<node>.<i><j>`` of its compliance
    (:func:`~flexmbd.analysis.modes.node_compliance`, ``frame`` and ``drive`` as there).

    Returns a :class:`StepTable`: the columns, and in ``notes`` the reason of every NaN
    (a value a step cannot have: fewer modes than asked, a state without stresses for
    buckling, a mechanism or a state past buckling for compliance); ``paths`` says how
    each analysis ran.

    Examples:
        The cantilever's lowest frequency falls as a compressive tip load grows towards
        buckling (4.93 N), each step linearized at its own equilibrium:

        >>> import flexmbd as fm
        >>> b = fm.ModelBuilder("cantilever")   # 1 m, four beams, EI = 2 N m^2, clamped at 1
        >>> for k in range(5):
        ...     _ = b.add_node(2 * k + 1, 0.25 * k, 0.0)
        >>> for k in range(4):
        ...     _ = (b.add_beam(k + 1, 2 * k + 1, 2 * k + 2, 2 * k + 3, 2 * k + 4)
        ...          .dynamic_deformation(k + 1).set_mass(k + 1, 0.5)
        ...          .set_stiffness(k + 1, axial=1e6, bending=2.0))
        >>> column = b.fix(1).fix(2).build()
        >>> statics = fm.static_equilibrium(column, load_increment={"x9.1": -2.0}, steps=2)
        >>> table = fm.load_step_table(statics, modes=1)
        >>> print(", ".join(f"{f:.3f}" for f in table["f1"]))
        1.119, 1.009, 0.880
    """
    if not isinstance(statics, StaticResult):
        raise ArgumentError("statics", f"must be a static_equilibrium result, got "
                                       f"{type(statics).__name__}")
    for name, count in (("modes", modes), ("buckle", buckle)):
        if isinstance(count, bool) or not isinstance(count, int | np.integer) or count < 0:
            raise ArgumentError(name, f"must be a whole number >= 0, got {count!r}")
    rows = len(statics.t)
    columns = StepTable({"load": np.asarray(statics.t, dtype=float).copy()})
    for k in range(modes):
        columns[f"f{k + 1}"] = np.full(rows, np.nan)
    for k in range(buckle):
        columns[f"buckling{k + 1}"] = np.full(rows, np.nan)
    names = {}
    for node, rotational in compliance:
        labels = compliance_labels(statics.model, node, rotational, frame, drive)
        size = len(labels) if rows else 0
        names[node] = [[f"C{node}.{i + 1}{j + 1}" for j in range(size)] for i in range(size)]
        for name in np.ravel(names[node]):
            columns[name] = np.full(rows, np.nan)
    with progress_bar(statics.t, "linearized load steps", progress) as advance:
        for row in range(rows):
            lin = statics.linearization(row)
            where = f"step {row} (load {statics.load[row]:.6g})"
            if modes:
                _series(columns, "modes", vibration_modes, lin, modes, row, where)
            if buckle:
                _series(columns, "buckling", buckling, lin, buckle, row, where)
            for node, rotational in compliance:
                try:
                    C = node_compliance(lin, node, rotational, frame=frame, drive=drive)
                except NO_VALUE as error:
                    columns.notes.append(f"C{node}.* at {where}: {error}")
                    continue
                columns.ran("compliance", "the engine's banded tangent" if drive == "held"
                            and lin.tangent is not None else "the reduced tangent")
                for i, line in enumerate(names[node]):
                    for j, name in enumerate(line):
                        columns[name][row] = C[i, j]
            if advance is not None:
                advance(statics.t[row])
    return columns


#: per analysis of a series of columns: its columns' prefix, the result's field, what
#: a state has fewer of than asked
SERIES = {"modes": ("f", "frequencies", "degrees of freedom"),
          "buckling": ("buckling", "factors", "load factors (modes with geometric stiffness)")}


def _series(columns: StepTable, analysis: str, analyse, lin, asked: int, row: int,
            where: str) -> None:
    """Put the ``asked`` lowest values of ``analyse(lin, asked)`` (frequencies, load
    factors: :data:`SERIES`) into the columns ``<prefix>1..`` of ``row``; a physical
    failure, or fewer values than asked, leaves NaN and a note."""
    prefix, field, what = SERIES[analysis]
    try:
        result = analyse(lin, asked)
    except NO_VALUE as error:
        columns.notes.append(f"{prefix}1..{prefix}{asked} at {where}: {error}")
        return
    columns.ran(analysis, result.path)
    found = getattr(result, field)
    for k, value in enumerate(found[:asked]):
        columns[f"{prefix}{k + 1}"][row] = value
    if len(found) < asked:
        columns.notes.append(f"{prefix}{len(found) + 1}..{prefix}{asked} at {where}: the "
                             f"state has {len(found)} {what}")
