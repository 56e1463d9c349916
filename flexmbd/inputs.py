"""Resolving the prescribed motions of a model for an analysis."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from .errors import ModelError
from .kinematics import initial_q
from .model import Model
from .motion import Law, Polynomial


def q_index(model: Model, label: str) -> int:
    """Position in ``q`` of an independent coordinate (``"x2.1"``) or deformation (``"e3.2"``)."""
    labels = model.q_labels
    try:
        if label.strip().lower().startswith("e"):
            i = model.deformation_index(label)
            wanted = model.deformation_labels[i]
        else:
            i = model.coordinate_index(label)
            wanted = model.coordinate_labels[i]
    except KeyError as err:
        raise ModelError(str(err.args[0])) from None
    if wanted not in labels:
        raise ModelError(f"{label} is not an input or dynamic degree of freedom of the model "
                         f"(those are: {', '.join(labels) or 'none'})")
    return labels.index(wanted)


def resolve_laws(model: Model, inputs: Mapping[str, Law] | None = None) -> list[Law]:
    """One law per entry of ``q``: ``inputs`` first, then the model's defaults.

    Dynamic degrees of freedom without a law are held at their initial value
    (a kinematic analysis moves only what is prescribed).

    Raises:
        ModelError: an unknown label, or an input without any law.
    """
    laws: list[Law | None] = [None] * model.n_dof
    for source in (model.input_laws, inputs or {}):
        for label, law in source.items():
            if not callable(law):
                raise ModelError(f"the motion given for {label} is not callable: {law!r}")
            laws[q_index(model, label)] = law
    q0 = initial_q(model)
    missing = []
    for j, (law, is_input) in enumerate(zip(laws, model.q_is_input, strict=True)):
        if law is None and is_input:
            missing.append(model.describe_q(j))
        elif law is None:
            laws[j] = Polynomial(float(q0[j]))
    if missing:
        raise ModelError(
            f"no motion given for the input(s) {', '.join(missing)}: pass "
            f"inputs={{label: Polynomial(x0, v0, a0)}} or give law= when classifying"
        )
    return laws  # type: ignore[return-value]


def evaluate_laws(laws: list[Law], t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``q, qdot, qddot`` at time ``t`` [s] from one law per entry."""
    values = np.array([law(t) for law in laws], dtype=float).reshape(len(laws), 3)
    return values[:, 0], values[:, 1], values[:, 2]
