"""The linearized analyses at every load step of a static equilibrium, as a flexure
designer follows them: frequencies, buckling load factors and support compliance, each
linearized at that step's equilibrium (never at the unloaded state: a loaded structure's
buckling load and frequencies are those of its loaded state).

From :data:`~flexmbd.analysis.statics.BANDED_FROM` degrees of freedom the frequencies and
the compliance with the drives held come from the banded tangent in all coordinates
(:mod:`flexmbd.analysis.banded`; the lowest modes by subspace iteration, each step
starting from the last step's shapes), whose cost grows linearly with the elements;
buckling, free drives and whatever the banded path cannot tell take the dense
linearization of the reduced equations.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Literal

import numpy as np

from ..engine import workspace_of
from ..errors import ArgumentError
from ..progress import progress_bar
from ..summary import Columns
from .banded import BandedStatics
from .modes import buckling, compliance_labels, in_frame, node_compliance, vibration_modes
from .statics import BANDED_FROM, StaticResult

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
    columns = Columns({"load": np.asarray(statics.t, dtype=float).copy()})
    for k in range(modes):
        columns[f"f{k + 1}"] = np.full(rows, np.nan)
    for k in range(buckle):
        columns[f"buckling{k + 1}"] = np.full(rows, np.nan)
    sizes = {}
    for node, rotational in compliance:
        labels = compliance_labels(statics.model, node, rotational, frame, drive)
        size = len(labels) if rows else 0
        sizes[node] = size
        for i in range(size):
            for j in range(size):
                columns[f"C{node}.{i + 1}{j + 1}"] = np.full(rows, np.nan)
    steps = _Steps(statics, banded=drive == "held" and (modes > 0 or bool(compliance)))
    with progress_bar(statics.t, "linearized load steps", progress) as advance:
        for row in range(rows):
            steps.go_to(row)
            if modes:
                _fill(columns, "f", row, lambda: steps.frequencies(modes))
            if buckle:
                _fill(columns, "buckling", row, lambda: buckling(steps.dense(), buckle).factors)
            for node, rotational in compliance:
                try:
                    C = steps.compliance(node, rotational, frame, drive)
                except (ArithmeticError, ValueError, RuntimeError):
                    continue
                for i in range(sizes[node]):
                    for j in range(sizes[node]):
                        columns[f"C{node}.{i + 1}{j + 1}"][row] = C[i, j]
            if advance is not None:
                advance(statics.t[row])
    return columns


class _Steps:
    """The linearizations of a static result's rows, one row at a time: the banded tangent
    when the model is large enough and the row has its stresses (``banded``), the dense
    reduced linearization when asked or needed."""

    def __init__(self, statics: StaticResult, banded: bool):
        model = statics.model
        self.statics, self.row = statics, 0
        self.banded = (BandedStatics(model, workspace_of(model)) if banded
                       and model.n_dof >= BANDED_FROM and statics.sigma is not None
                       and statics.applied is not None else None)
        self.factored = False
        self.shapes: np.ndarray | None = None   # the last step's modes: the next one's start
        self._dense = None

    def go_to(self, row: int) -> None:
        self.row, self._dense, self.factored = row, None, False
        if self.banded is not None:
            s = self.statics
            assert s.sigma is not None and s.applied is not None  # checked in __init__
            try:
                self.banded.factor(s.x[row], s.q[row], s.sigma[row][self.banded.constrained],
                                   s.applied[row])
                self.factored = True
            except np.linalg.LinAlgError:
                self.shapes = None

    def dense(self):
        if self._dense is None:
            self._dense = self.statics.linearization(self.row)
        return self._dense

    def frequencies(self, count: int) -> np.ndarray:
        if self.factored:
            assert self.banded is not None
            found = self.banded.lowest_modes(count, self.shapes)
            if found is not None:
                omega2, self.shapes = found
                return np.sqrt(omega2) / (2 * np.pi)
            self.shapes = None
        return vibration_modes(self.dense(), count).frequencies

    def compliance(self, node: int, rotational: int | None, frame, drive) -> np.ndarray:
        if not self.factored or drive != "held":
            return node_compliance(self.dense(), node, rotational, frame=frame, drive=drive)
        assert self.banded is not None
        model, x = self.statics.model, self.statics.x[self.row]
        labels = compliance_labels(model, node, rotational, frame, drive)
        return in_frame(model, x, rotational, self.banded.compliance(x, labels), frame)


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
