"""Record-by-record differences between two SPACAR result files (``flexmbd compare``)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .binary import SpacarFile


@dataclass(frozen=True)
class RecordDifference:
    """How one record differs between a reference file and another.

    Attributes:
        name: the record.
        largest: the largest absolute difference over its values and the common steps
            (``nan`` when the record cannot be compared).
        scale: the largest absolute value of the reference record (0 for an all-zero one).
        step: the step (1-based) of the largest difference; ``None`` for a table.
        note: why the record was not compared, or what was compared of it (``""``).
    """

    name: str
    largest: float
    scale: float
    step: int | None = None
    note: str = ""

    @property
    def relative(self) -> float:
        """``largest`` over ``scale`` (``largest`` itself when the record is all zero)."""
        return self.largest / self.scale if self.scale > 0 else self.largest


def compare(reference: SpacarFile, other: SpacarFile) -> list[RecordDifference]:
    """The difference of every record of ``reference`` against ``other``, in the
    reference's order, then the records only ``other`` has."""
    out = []
    common_steps = min(reference.n_steps, other.n_steps)
    for name in reference:
        if name not in other:
            out.append(RecordDifference(name, np.nan, 0.0, note=f"not in {_label(other)}"))
            continue
        mine, theirs = reference[name], other[name]
        per_step = name in reference.steps
        if per_step != (name in other.steps):
            out.append(RecordDifference(name, np.nan, 0.0, note="a table in one file and per "
                                                                "step in the other"))
            continue
        if per_step:
            mine, theirs = mine[:common_steps], theirs[:common_steps]
        if mine.shape[-2:] != theirs.shape[-2:]:
            out.append(RecordDifference(name, np.nan, 0.0, note=f"shape {mine.shape[-2:]} "
                                                                f"against {theirs.shape[-2:]}"))
            continue
        out.append(_difference(name, mine.astype(float), theirs.astype(float), per_step,
                               reference.n_steps, other.n_steps))
    out += [RecordDifference(name, np.nan, 0.0, note=f"only in {_label(other)}")
            for name in other if name not in reference]
    return out


def _difference(name: str, mine: np.ndarray, theirs: np.ndarray, per_step: bool,
                steps_mine: int, steps_theirs: int) -> RecordDifference:
    scale = float(np.max(np.abs(mine))) if mine.size else 0.0
    if not mine.size:
        return RecordDifference(name, 0.0, 0.0, None, "empty")
    gap = np.abs(mine - theirs)
    gap = np.where(np.isnan(mine) & np.isnan(theirs), 0.0, gap)
    gap = np.where(np.isnan(gap), np.inf, gap)
    where = np.unravel_index(int(np.argmax(gap)), gap.shape)
    note = ""
    if per_step and steps_mine != steps_theirs:
        note = f"first {min(steps_mine, steps_theirs)} steps ({steps_mine} against " \
               f"{steps_theirs})"
    return RecordDifference(name, float(gap[where]), scale,
                            int(where[0]) + 1 if per_step else None, note)


def _label(file: SpacarFile) -> str:
    return str(file.path) if file.path is not None else f"the {file.kind.lower()} run"
