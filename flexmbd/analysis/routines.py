"""SPACAR's user routines (``USERSIG``, ``USERINP``) as Python functions beside the file.

SPACAR calls a MATLAB function named in the input file; flexmbd calls a Python function of
that name in a module of that name (``FFESFVA.py`` for ``USERSIG FFESFVA``) in the input
file's directory, with SPACAR's arguments, so that a routine ports line by line:

``USERSIG name``: ``time, sig, f = name(t, ne, le, e, ep, nx, lnp, x, xp)``

* ``t`` [s]; ``ne`` and ``nx`` the numbers of deformations and coordinates;
* ``le`` ``(elements, 8)`` and ``lnp`` ``(nodes, 4)``: SPACAR's tables of the numbers of
  each element's deformations and each node's coordinates, 1-based as in MATLAB
  (``x[lnp[n - 1, 0:3] - 1]`` is ``x(lnp(n, 1:3))``);
* ``e``, ``ep`` ``(ne,)`` and ``x``, ``xp`` ``(nx,)``: deformations, coordinates and their
  rates, in SPACAR's numbering (:mod:`flexmbd.model.numbering`).

It returns ``f``, rows ``[node, direction, load]`` [N, or on a rotational node in space
the generalized force on Euler parameter ``direction`` (1 to 4, ``lam0`` to ``lam3``), a
planar one's moment], applied on top of the file's loads, and ``sig``, rows ``[element,
deformation, stress]``: generalized stresses added to the element's, which load the nodes
with ``-D_x^T sig``. Either may be empty; ``time`` is not used.

``USERINP name``: ``time, e, x = name(t, is)`` gives the input motions: rows ``[element,
deformation, value, rate, acceleration]`` of input deformations and ``[node, direction,
value, rate, acceleration]`` of input coordinates. flexmbd passes ``is = 0``.
"""

from __future__ import annotations

import importlib.util
from collections.abc import Callable
from pathlib import Path

import numpy as np

from ..elements.base import SPATIAL_ROTATIONAL
from ..errors import InputFileError, SimulationError
from ..model import Model
from ..model.numbering import SpacarNumbering
from ..motion import Law
from ..orientation import moment_of
from ..settings import RunSettings
from .kinematics import deformations, jacobian

__all__ = ["routine_inputs", "routine_loads"]


def load_routine(settings: RunSettings, name: str, keyword: str) -> Callable:
    """The function ``name`` of the module ``name.py`` in the file's directory."""
    path = Path(settings.routine_dir or ".") / f"{name}.py"
    spec = importlib.util.spec_from_file_location(f"flexmbd_routine_{name}", path)
    if spec is None or spec.loader is None:
        raise InputFileError(f"{keyword} {name}: cannot load {path}")
    module = importlib.util.module_from_spec(spec)
    try:
        spec.loader.exec_module(module)
    except Exception as error:  # the user's module: its failure is named, not lost
        raise InputFileError(f"{keyword} {name}: loading {path} raised "
                             f"{type(error).__name__}: {error}") from error
    function = getattr(module, name, None)
    if not callable(function):
        raise InputFileError(f"{keyword} {name}: {path} defines no function {name}")
    return function


def _rows(value, width: int, what: str, routine: str, t: float) -> np.ndarray:
    """A routine's table as ``(n, width)`` floats (``[]`` and ``None`` are no rows)."""
    if value is None:
        return np.zeros((0, width))
    try:
        rows = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise SimulationError(f"{routine} returned {what} that are not numbers at t = {t:.6g} s",
                              t) from None
    if rows.size == 0:
        return np.zeros((0, width))
    rows = rows.reshape(1, -1) if rows.ndim == 1 else rows
    if rows.ndim != 2 or rows.shape[1] != width:
        raise SimulationError(f"{routine} returned {what} of shape {np.shape(value)} at "
                              f"t = {t:.6g} s; rows of {width} values are expected", t)
    return rows


def _entry(model: Model, kind: str, number: int, k: int, routine: str, t: float) -> int:
    """flexmbd's index of coordinate ``k`` of node ``number`` (``kind`` "x") or of
    deformation ``k`` of element ``number`` ("e")."""
    if kind == "x":
        node = model.nodes.get(int(number))
        entries = node.coordinates if node is not None else ()
    else:
        element = model.elements.get(int(number))
        entries = element.deformations if element is not None else ()
    if int(number) != number or int(k) != k or not 1 <= k <= len(entries):
        what = "node" if kind == "x" else "element"
        raise SimulationError(f"{routine} names {what} {number:g} direction {k:g} at "
                              f"t = {t:.6g} s, which the model does not have", t)
    return entries[int(k) - 1]


def routine_loads(model: Model, settings: RunSettings
                  ) -> Callable[[float, np.ndarray, np.ndarray], np.ndarray] | None:
    """The loads of the file's ``USERSIG`` routine as ``forces(t, x, xd)`` ``(nx,)`` in
    flexmbd's form (a global moment on a spatial rotational node), or ``None``."""
    if not settings.user_loads:
        return None
    name = settings.user_loads
    routine = load_routine(settings, name, "USERSIG")
    number = SpacarNumbering(model)
    lnp, le = number.node_table(), number.element_table()
    rotational = [list(n.coordinates) for n in model.nodes.values()
                  if n.kind == SPATIAL_ROTATIONAL]

    def forces(t: float, x: np.ndarray, xd: np.ndarray) -> np.ndarray:
        D = jacobian(model, x)
        e, ed = deformations(model, x), D @ xd
        _, sig, f = routine(t, model.n_deformations, le.copy(), e[number.e], ed[number.e],
                            model.n_coordinates, lnp.copy(), x[number.x], xd[number.x])
        load = np.zeros(model.n_coordinates)
        for node, k, value in _rows(f, 3, "loads f", name, t):
            load[_entry(model, "x", node, k, name, t)] += value
        stress = np.zeros(model.n_deformations)
        for element, k, value in _rows(sig, 3, "stresses sig", name, t):
            stress[_entry(model, "e", element, k, name, t)] += value
        load -= D.T @ stress
        for at in rotational:   # Euler-parameter forces -> the global moment
            load[at[1:]], load[at[0]] = moment_of(x[at], load[at]), 0.0
        return load

    return forces


def routine_inputs(model: Model, settings: RunSettings) -> dict[str, Law]:
    """The laws of the file's ``USERINP`` routine by label of the input entries of ``q``
    (empty without one)."""
    if not settings.user_inputs:
        return {}
    name = settings.user_inputs
    routine = load_routine(settings, name, "USERINP")
    last: dict[str, object] = {}

    def values_at(t: float) -> dict[str, tuple[float, float, float]]:
        if last.get("t") != t:
            _, e_rows, x_rows = routine(t, 0)
            table = {}
            for kind, rows in (("e", e_rows), ("x", x_rows)):
                for number, k, value, rate, acceleration in _rows(rows, 5, f"{kind} motions",
                                                                  name, t):
                    table[f"{kind}{number:g}.{k:g}"] = (value, rate, acceleration)
            last.update(t=t, table=table)
        return last["table"]  # type: ignore[return-value]

    def law_of(label: str) -> Law:
        def law(t: float) -> tuple[float, float, float]:
            table = values_at(t)
            if label not in table:
                raise SimulationError(f"{name} gives no motion of the input {label} at "
                                      f"t = {t:.6g} s (it gives {', '.join(table) or 'none'})",
                                      t)
            return table[label]
        return law

    return {label: law_of(label)
            for label, given in zip(model.q_labels, model.q_is_input, strict=True) if given}
