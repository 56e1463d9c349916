"""The generalized coordinates ``q`` and what moves them: laws by label, loads by label,
and the quantities a position solve measures its steps in.

``q`` holds the independent coordinates ``x(m)`` and then the independent deformations
``e(m)`` (THEORY 3), in the model's order; :func:`q_index` finds an entry by label,
:func:`resolve_laws` gives every entry a law, :func:`load_vector` turns loads given by
label into an array over the coordinates.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

import numpy as np

from .. import checks
from ..elements.base import SPATIAL_ROTATIONAL, is_translational
from ..errors import ArgumentError, FlexmbdError, ModelError, SimulationError
from ..model import Model
from ..motion import Law, Polynomial, as_law
from .diagnosis import at_time


def load_slots(node) -> list[int]:
    """The coordinates whose load entries hold a node's load components: all of them, but
    on a spatial rotational node ``lam1..lam3``, which hold the global moment ``(Mx, My,
    Mz)`` (the core turns it into ``2 E(lam)^T M``); ``lam0`` takes no load."""
    coordinates = list(node.coordinates)
    return coordinates[1:] if node.kind == SPATIAL_ROTATIONAL else coordinates


def own_loads(model: Model) -> np.ndarray:
    """The model's constant nodal loads (``XF``, ``add_force``) ``(nx,)`` [N, N m] in
    flexmbd's form (a global moment on a spatial rotational node's ``lam1..lam3``, as
    :func:`load_slots` places it)."""
    loads = np.zeros(model.n_coordinates)
    for number, load in model.nodal_forces.items():
        loads[load_slots(model.nodes[number])] += load
    return loads


def periodic_deformations(model: Model) -> np.ndarray:
    """Mask ``(ne,)`` of the deformations that are angles modulo ``2 pi``."""
    mask = np.zeros(model.n_deformations, dtype=bool)
    for element in model.elements.values():
        mask[[element.deformations[k] for k in element.type.periodic]] = True
    return mask


def unwrap_near(model: Model, q: np.ndarray, near: np.ndarray | None) -> np.ndarray:
    """``q`` ``(nq,)`` with its periodic deformations (a spatial hinge's rotation, computed
    by ``atan2`` within half a turn) shifted by whole turns to lie nearest ``near``
    ``(nq,)``: the value a continuous motion or load path has reached."""
    if near is None:
        return q
    periodic = np.concatenate([np.zeros(len(model.independent_coordinates), dtype=bool),
                               periodic_deformations(model)[model.independent_deformations]])
    if not np.any(periodic):
        return q
    q = np.array(q, dtype=float)
    turns = np.round((near[periodic] - q[periodic]) / (2 * np.pi))
    q[periodic] += 2 * np.pi * turns
    return q


def coordinate_size(model: Model) -> np.ndarray:
    """Per coordinate the size a change of it is measured against (a predicted move, a
    continuation step): the model size for a translation, 1 rad for an angle."""
    scale = np.ones(model.n_coordinates)
    for node in model.nodes.values():
        if is_translational(node.kind):
            scale[list(node.coordinates)] = model.characteristic_length
    return scale


def coordinate_kinds(model: Model) -> dict[int, tuple[str, int]]:
    """Kind of node and direction (0-based) of every coordinate."""
    return {i: (node.kind, k) for node in model.nodes.values()
            for k, i in enumerate(node.coordinates)}


def q_index(model: Model, label: str, argument: str = "label") -> int:
    """Position in ``q`` of an independent coordinate (``"x2.1"``) or deformation (``"e3.2"``);
    an error names the ``argument`` the label came from."""
    labels = model.q_labels
    try:
        if str(label).strip().lower().startswith("e"):
            wanted = model.deformation_labels[model.deformation_index(label)]
        else:
            wanted = model.coordinate_labels[model.coordinate_index(label)]
    except KeyError as err:
        raise ArgumentError(argument, str(err)) from None
    if wanted not in labels:
        raise ArgumentError(argument, f"{label} is not an input or dynamic degree of freedom of "
                                      f"the model (those are: {', '.join(labels) or 'none'})")
    return labels.index(wanted)


def initial_q(model: Model) -> np.ndarray:
    """``q`` ``(nq,)`` [m, rad] of the initial configuration: ``x(m)`` from ``x0``,
    ``e(m) = 0``."""
    return np.concatenate([np.asarray(model.x0)[model.independent_coordinates],
                           np.zeros(len(model.independent_deformations))])


def resolve_laws(model: Model, inputs: Mapping[str, Law] | None = None) -> list[Law]:
    """One law per entry of ``q``: ``inputs`` first, then the model's defaults.

    Dynamic degrees of freedom without a law are held at their initial value
    (a kinematic analysis moves only what is prescribed).

    Raises:
        ModelError: an unknown label, or an input without any law.
    """
    laws: list[Law | None] = [None] * model.n_dof
    if inputs is not None and not isinstance(inputs, Mapping):
        raise ArgumentError("inputs", f"must map labels to laws, e.g. {{'x2.1': "
                                      f"Polynomial(0, 150)}}, got {type(inputs).__name__}")
    for source in (model.input_laws, inputs or {}):
        for label, given in source.items():
            try:
                law = as_law(given)
            except ArgumentError as error:
                raise ArgumentError("inputs", f"the motion given for {label}: {error}") from None
            if not callable(law):
                raise ArgumentError("inputs", f"the motion given for {label} is not a law "
                                              f"(Polynomial, Custom, a function of t or an "
                                              f"expression in t): {law!r}")
            laws[q_index(model, label, "inputs")] = law
    q0 = initial_q(model)
    missing: list[str] = []
    for j, (given_law, is_input) in enumerate(zip(laws, model.q_is_input, strict=True)):
        if given_law is None and is_input:
            missing.append(model.describe_q(j))
        elif given_law is None:
            laws[j] = Polynomial(float(q0[j]))
    if missing:
        raise ModelError(
            f"no motion given for the input(s) {', '.join(missing)}: pass "
            f"inputs={{label: Polynomial(x0, v0, a0)}} or give law= when classifying"
        )
    return laws  # type: ignore[return-value]


def q_scale(model: Model) -> np.ndarray:
    """Per entry of ``q``: 1 for angles, one over the model size for lengths."""
    length = model.characteristic_length
    coordinates = list(1.0 / coordinate_size(model)[model.independent_coordinates])
    lengths = {d for e in model.elements.values() if e.type.ends() is not None
               for d in e.deformations}  # deformations of elements with a chord
    deformations = [1.0 / length if d in lengths else 1.0
                    for d in model.independent_deformations]
    return np.array(coordinates + deformations)


#: applied loads as a function of time and state: ``forces(t, x, xdot)`` returning an
#: array ``(nx,)`` or a mapping from coordinate labels (``"x2.1"``) to values [N, N m]
Forces = Callable[[float, np.ndarray, np.ndarray], "np.ndarray | Mapping[str, float]"]


def load_vector(model: Model, value, argument: str = "forces", finite: bool = True
                ) -> np.ndarray:
    """User loads (array or label mapping, see :data:`Forces`) as an array ``(nx,)``. On a
    spatial rotational node the entries of ``lam1..lam3`` (labels ``x<n>.2`` to
    ``x<n>.4``) are the global moment ``(Mx, My, Mz)`` [N m] and ``lam0``'s must be 0.
    ``finite=False`` lets a load that is not finite through: the core refuses those of a
    run itself, naming the coordinate and the time.

    Raises:
        ArgumentError: a label the model lacks, an array of another shape, a load that is
            not finite, or a load on a ``lam0``; the message starts with ``argument``, the
            name the loads came by.
    """
    n = model.n_coordinates
    if isinstance(value, Mapping):
        f = np.zeros(n)
        for label, v in value.items():
            f[checks.coordinates_named(model, label, argument)[1][0]] += checks.real(
                v, f"{argument} {label}", finite=False)
    else:
        spelled = f"an array ({n},) or a mapping such as {{'x5.2': -10.0}}"
        try:
            f = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            raise ArgumentError(argument, f"must be loads [N, N m], {spelled}; got "
                                          f"{value!r}") from None
        if f.shape != (n,):
            raise ArgumentError(argument, f"must be loads [N, N m], {spelled}; got shape "
                                          f"{f.shape}")
    if finite and not np.all(np.isfinite(f)):
        k = int(np.flatnonzero(~np.isfinite(f))[0])
        raise ArgumentError(argument, f"the load on {model.describe_coordinate(k)} is "
                                      f"{f[k]}; every load must be finite")
    scalar = model.euler_scalars
    if np.any(f[scalar] != 0.0):
        label = model.coordinate_labels[scalar[np.flatnonzero(f[scalar])[0]]]
        raise ArgumentError(argument, f"a load on {label}, lam0 of a spatial rotational node: "
                                      f"the loads of such a node are its global moment (Mx, "
                                      f"My, Mz) on {label[:-1]}2 to {label[:-1]}4")
    return f


def law_values(law: Law, t: float, what: str) -> tuple[float, float, float]:
    """``(value, rate, acceleration)`` of ``law`` at time ``t`` [s]; ``what`` names the
    entry of ``q`` in an error.

    Raises:
        SimulationError: the law (a user's function) raised.
        ModelError: it returned something else than three numbers.
    """
    try:
        given = law(t)
    except FlexmbdError:
        raise
    except Exception as error:  # the user's function: its failure is named, not lost
        raise SimulationError(f"the law of {what} raised {type(error).__name__}: {error} "
                              f"{at_time(t)}", t) from error
    try:
        values = tuple(float(v) for v in given)
    except (TypeError, ValueError) as error:
        raise ModelError(f"the law of {what} must return (value, rate, acceleration) as "
                         f"numbers: {error}") from None
    if len(values) != 3:
        raise ModelError(f"the law of {what} must return (value, rate, acceleration), got "
                         f"{len(values)} values")
    return values
