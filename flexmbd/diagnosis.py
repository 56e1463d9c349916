"""Saying in words what a singular or rank-deficient ``D_c`` leaves free (THEORY 3).

The right null space of ``D_c`` holds the dependent-coordinate motions that leave
every constrained deformation unchanged; the left null space holds combinations
of constraint equations that are redundant. Both are named by their largest
entries, with angles scaled by the model size so that the words do not depend on
units.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .model import Model


def _largest(vector: np.ndarray, share: float = 0.1) -> np.ndarray:
    """Indices of the entries of at least ``share`` of the largest, largest first."""
    a = np.abs(vector)
    chosen = np.flatnonzero(a >= share * a.max())
    return chosen[np.argsort(-a[chosen], kind="stable")]


def _names(describe, indices, shown: int = 8) -> str:
    """The first ``shown`` of ``indices`` in words, and how many more there are."""
    names = ", ".join(describe(int(i)) for i in indices[:shown])
    return names + (f" and {len(indices) - shown} more" if len(indices) > shown else "")


def weakest_direction(model: Model, D_c: np.ndarray) -> str:
    """Name the coordinates and deformations of the smallest singular value of ``D_c``
    ``(nr, nr)``."""
    if not np.all(np.isfinite(D_c)):
        return "the configuration is not finite"
    scaled = D_c * model.coordinate_scale[model.dependent]
    norms = np.linalg.norm(scaled, axis=1, keepdims=True)
    u, _, vt = np.linalg.svd(scaled / np.maximum(norms, 1e-300))
    constraints = _names(model.describe_deformation, model.constrained[_largest(u[:, -1])])
    coordinates = _names(model.describe_coordinate, model.dependent[_largest(vt[-1])])
    return f"the constraints {constraints} no longer determine {coordinates}"


class RankDiagnosis(NamedTuple):
    """What a rank-deficient ``D_c`` leaves free, in words (``text``, ``""`` when it is
    regular) and as global indices of the coordinates and deformations involved."""

    text: str
    coordinates: np.ndarray
    deformations: np.ndarray


def diagnose_rank(model: Model, D_c: np.ndarray, rtol: float = 1e-10) -> RankDiagnosis:
    """Explain a rank-deficient or non-square ``D_c`` ``(nr, nc)``."""
    rows, cols = D_c.shape
    u, s, vt = np.linalg.svd(D_c)
    rank = int(np.sum(s > rtol * (s[0] if s.size else 0.0)))
    none = np.zeros(0, dtype=int)
    if rank == rows == cols:
        return RankDiagnosis("", none, none)
    parts = [f"rank {rank} for {rows} equations in {cols} dependent coordinates"]
    free, redundant = vt[rank:], u[:, rank:]
    coordinates = np.asarray(model.dependent)[
        np.flatnonzero(np.abs(free).max(axis=0) > 1e-8)] if len(free) else none
    deformations = np.asarray(model.constrained)[
        np.flatnonzero(np.abs(redundant).max(axis=1) > 1e-8)] if redundant.shape[1] else none
    if len(coordinates):
        parts.append(f"the coordinates {_names(model.describe_coordinate, coordinates)} can "
                     f"move without changing any rigid or independent deformation")
    if len(deformations):
        parts.append(f"the equations of {_names(model.describe_deformation, deformations)} "
                     f"are linearly dependent")
    return RankDiagnosis("; ".join(parts), coordinates, deformations)


def at_time(time: float | None) -> str:
    """``"at t = 0.5 s"``, or ``"in the given configuration"`` without a time."""
    return "in the given configuration" if time is None else f"at t = {time:.6g} s"


def singular_message(model: Model, D_c: np.ndarray, time: float | None, what: str) -> str:
    """The message of a singular ``D_c`` at ``time``, naming what no longer holds."""
    return (f"singular configuration {at_time(time)}: {what}; {weakest_direction(model, D_c)}; "
            f"the mechanism is at a dead point or at the end of its range of motion, where "
            f"the inputs cannot drive it further")
