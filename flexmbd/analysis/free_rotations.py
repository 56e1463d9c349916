"""Free rotations: the calculable Euler parameter chosen again while a body tumbles
(the spatial theory, section 1).

A rotational node with three dynamic Euler parameters (a free body, a spherical joint)
leaves the fourth to the normalization ``lam . lam = 1``. Its ``D_c`` entry is
``2 lam_c``, singular where ``lam_c = 0`` (a half turn away from the reference for
``lam0``). Whenever ``|lam_c|`` drops below 0.5 the run stops, the parameter of largest
magnitude (always at least 0.5) becomes the calculable one, and the integration restarts
from the same state ``(x, xdot)`` in the new partition. Only the classification
changes: the coordinates, deformations and the model's other tables stay as they are.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..model import CoordinateClass, Model

#: the calculable Euler parameter of a free rotation is changed below this magnitude
PARTITION_LIMIT = 0.5


def watched_positions(model: Model) -> np.ndarray:
    """``(k, 3)`` int32: where each free rotation's dynamic Euler parameters sit in the
    integrated state ``q_d`` (the dynamic entries of ``q``, in order)."""
    dynamic = [label for label, is_input in zip(model.q_labels, model.q_is_input,
                                                strict=True) if not is_input]
    rows = [[dynamic.index(model.coordinate_labels[i]) for i in lam
             if model.coordinate_class[i] == CoordinateClass.DYNAMIC]
            for lam in model.free_rotations]
    return np.array(rows, dtype=np.int32).reshape(-1, 3)


def partition_spent(watched: np.ndarray, q_d: np.ndarray) -> bool:
    """Whether a free rotation's calculable Euler parameter is below the limit in magnitude
    at the integrated state ``q_d``: with ``|lam| = 1``, when the squares of its three
    dynamic ones add up to more than ``1 - PARTITION_LIMIT^2``."""
    if not len(watched):
        return False
    squares = np.sum(np.asarray(q_d)[watched] ** 2, axis=1)
    return bool(np.any(squares > 1.0 - PARTITION_LIMIT**2))


def repartitioned(model: Model, x: np.ndarray) -> Model:
    """``model`` with, in every free rotation whose calculable Euler parameter is below the
    limit at the configuration ``x``, the parameter of largest magnitude made calculable
    and the old one dynamic. Returns ``model`` itself when none needs it."""
    classes = np.array(model.coordinate_class)
    for entries in model.free_rotations:
        lam = np.asarray(entries)
        calculable = lam[classes[lam] == CoordinateClass.DEPENDENT][0]
        if abs(x[calculable]) >= PARTITION_LIMIT:
            continue
        largest = lam[np.argmax(np.abs(x[lam]))]
        classes[calculable], classes[largest] = CoordinateClass.DYNAMIC, \
            CoordinateClass.DEPENDENT
    if np.array_equal(classes, model.coordinate_class):
        return model
    classes.flags.writeable = False
    return dataclasses.replace(model, coordinate_class=classes)


def dynamic_state(model: Model, state: dict[str, np.ndarray]) -> np.ndarray:
    """``[q_d, qdot_d]`` of ``model``'s dynamic entries read off a solved ``state`` (with
    ``x, xd, e, ed``)."""
    dynamic = ~np.asarray(model.q_is_input)
    q = np.concatenate([state["x"][model.independent_coordinates],
                        state["e"][model.independent_deformations]])
    qd = np.concatenate([state["xd"][model.independent_coordinates],
                         state["ed"][model.independent_deformations]])
    return np.concatenate([q[dynamic], qd[dynamic]])


#: the output columns per entry of q, and where a coordinate's value is found otherwise
Q_COLUMNS = {"q": "x", "qd": "xd", "qdd": "xdd", "driving": None}


def relabelled(arrays: dict[str, np.ndarray], segment: Model, model: Model
               ) -> dict[str, np.ndarray]:
    """The output ``arrays`` of a run of the re-partitioned ``segment`` with their columns
    per entry of ``q`` in ``model``'s labels: an Euler parameter that is dynamic in
    ``model`` but calculable in ``segment`` is read from ``x`` (``xd``, ``xdd``), and its
    driving load is zero, as on every dynamic entry."""
    if segment is model:
        return arrays
    out = dict(arrays)
    position = {label: j for j, label in enumerate(segment.q_labels)}
    for name, source in Q_COLUMNS.items():
        if name not in arrays:
            continue
        rows = len(arrays[name])
        out[name] = np.column_stack([
            arrays[name][:, position[label]] if label in position else
            np.zeros(rows) if source is None else
            arrays[source][:, model.coordinate_index(label)]
            for label in model.q_labels]).reshape(rows, model.n_dof)
    return out
