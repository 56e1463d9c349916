"""What a flexmbd run writes into SPACAR's binary data file ``.sbd``: the records, their
names, shapes and meaning, in SPACAR's numbering (:mod:`.numbering`).

Tables: ``NX NE NDOF NDDO NKDO NKDD NXP NEP LNP LE LN IT MODE RL0 RXYZ RQ STIF ESIG``
(``RQ`` zeros, as SPACAR writes it for beams, hinges and pin bodies). Per
step: ``T X XD XDD E ED EDD FX FXT SIG DX DE`` and, for static runs and files of one
step, ``BIGD`` (the rates and loads a run did not record are left out).
``docs/guide/spacar-files.md`` gives every record's meaning; the records SPACAR writes and
flexmbd does not (``KDEF DR0 EINI DAMP EM FXG XCL``) are there too, with the
reason. The linearized equations (``.sbm``, ``.ltv``) are :mod:`.linear`'s.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from ... import checks
from ...analysis.kinematics import first_order_transfer, jacobian, quadratic_velocity
from ...analysis.linearization import Linearization
from ...analysis.statics import StaticResult
from ...elements.base import SPATIAL_ROTATIONAL
from ...engine import deformations_and_jacobian
from ...engine.laws import own_loads
from ...errors import ArgumentError
from ...model import CoordinateClass, Model
from ...model.numbering import ELEMENT_CODES, LE_WIDTH, LN_WIDTH, SpacarNumbering
from ...orientation import euler_forces, moment_of
from ...results import KinematicResult, SimulationResult
from .binary import write_records

#: where each spatial type's reference parameters hold its frame ``ex0, ey0, ez0`` (the
#: ``RXYZ`` row SPACAR writes); planar types have none
FRAME_AT = {"BEAM": 1, "BEAMW": 1, "RBEAM": 1, "HINGE": 0}
#: SPACAR's modes by what they compute (``MODE`` record); flexmbd's run kinds map onto them
SPACAR_MODES = {"kinematic": 1, "dynamic": 1, "inverse": 2, "linear": 3, "static": 10}


def model_tables(model: Model, mode: int) -> dict[str, np.ndarray]:
    """The ``.sbd`` tables of ``model`` for a run of SPACAR ``mode``."""
    number = SpacarNumbering(model)
    nxp, nep = number.class_counts()
    n_dynamic = len(model.dynamic_q_labels)
    largest_element = max(model.elements)
    ln = np.zeros((largest_element, LN_WIDTH), dtype=np.int32)
    it = np.zeros((1, largest_element), dtype=np.int32)
    rl0 = np.zeros((largest_element, 1))
    rxyz = np.zeros((largest_element, 9))
    esig = np.zeros((largest_element, LE_WIDTH))
    for k, element in model.elements.items():
        ln[k - 1, :len(element.nodes)] = element.nodes
        it[0, k - 1] = ELEMENT_CODES.get(element.type.keyword, 0)
        if element.type.ends() is not None and element.reference:
            rl0[k - 1, 0] = element.reference[0]
        frame = FRAME_AT.get(element.type.keyword)
        if frame is not None:   # the reference frame's axes ex0, ey0, ez0
            rxyz[k - 1] = element.reference[frame:frame + 9]
        properties = model.element_properties.get(k)
        if properties is not None and properties.prestress is not None:
            esig[k - 1, :len(properties.prestress)] = properties.prestress
    count = {"NX": model.n_coordinates, "NE": model.n_deformations, "NDOF": model.n_dof,
             "NDDO": n_dynamic, "NKDO": model.n_dof, "NKDD": n_dynamic}
    tables: dict[str, np.ndarray] = {name: np.array([[value]], dtype=np.int32)
                                     for name, value in count.items()}
    tables.update(NXP=nxp, NEP=nep, LNP=number.node_table(), LE=number.element_table(),
                  LN=ln, IT=it, MODE=np.array([[mode]], dtype=np.int32), RL0=rl0, RXYZ=rxyz,
                  RQ=np.zeros((largest_element, 9)), STIF=stiffness_table(model), ESIG=esig)
    return tables


def stiffness_table(model: Model) -> np.ndarray:
    """``STIF`` ``(elements, 12)``: SPACAR's stiffness parameters of a spatial beam,
    ``EA/l0, GIt/l0^3, EIy/l0^3, EIz/l0^3, 12 sy/l0^2, 12 sz/l0^2`` and for a ``BEAMW``
    ``ECw/l0^5`` after them (read off SPACAR's output); zero rows for the other types,
    whose layout in SPACAR's table is not established (SPACAR's tools read only the
    beams' rows: their shear coefficients)."""
    table = np.zeros((max(model.elements), 12))
    for k, element in model.elements.items():
        properties = model.element_properties.get(k)
        values = dict(properties.stiffness) if properties is not None else {}
        if element.type.keyword not in ("BEAM", "BEAMW") or not any(values.values()):
            continue
        l0 = element.reference[0]
        table[k - 1, :7] = [values.get("axial", 0.0) / l0, values.get("torsion", 0.0) / l0**3,
                            values.get("bending_y", 0.0) / l0**3,
                            values.get("bending_z", 0.0) / l0**3,
                            12 * values.get("shear_y", 0.0) / l0**2,
                            12 * values.get("shear_z", 0.0) / l0**2,
                            values.get("warping", 0.0) / l0**5]
    return table


def generalized_loads(model: Model, x: np.ndarray, loads: np.ndarray,
                      reactions: bool = False) -> np.ndarray:
    """Loads as SPACAR stores them, ``(n, nx)`` from ``(n, nx)`` at coordinates ``x``: on a
    spatial rotational node the generalized forces on its Euler parameters in place of
    the global moment flexmbd gives, ``f = 2 E(lam)^T M`` (``FX``, SPACAR's to 3e-17); for
    ``reactions`` (``FXT``) plus ``c lam``, with ``c`` such that the force is zero on the
    node's calculable parameter, where a load of supports and drives acts not. Either
    gives the moment back (:func:`moment_loads`): ``E(lam) lam = 0``."""
    out = np.array(loads, dtype=float)
    for node in model.nodes.values():
        if node.kind != SPATIAL_ROTATIONAL:
            continue
        at = list(node.coordinates)
        lam = x[:, at]
        force = euler_forces(lam, out[:, at[1:]])
        free = [a for a, i in enumerate(at)
                if model.coordinate_class[i] in (CoordinateClass.DEPENDENT,
                                                 CoordinateClass.DYNAMIC)]
        if free and reactions:
            rows = np.arange(len(lam))
            pick = np.asarray(free)[np.argmax(np.abs(lam[:, free]), axis=1)]
            force -= (force[rows, pick] / lam[rows, pick])[:, None] * lam
        out[:, at] = force
    return out


def moment_loads(model: Model, x: np.ndarray, loads: np.ndarray) -> np.ndarray:
    """The inverse of :func:`generalized_loads`: loads ``(n, nx)`` in flexmbd's form, the
    global moment ``M = 1/2 E(lam) f`` on a spatial rotational node's ``lam1..lam3``."""
    out = np.array(loads, dtype=float)
    for node in model.nodes.values():
        if node.kind == SPATIAL_ROTATIONAL:
            at = list(node.coordinates)
            out[:, at[1:]] = moment_of(x[:, at], out[:, at])
            out[:, at[0]] = 0.0
    return out


def step_records(result: KinematicResult) -> dict[str, np.ndarray]:
    """The ``.sbd`` per-step records of a run, each ``(n_steps, rows, cols)``."""
    model = result.model
    n = len(result.t)
    static = isinstance(result, StaticResult)
    states: dict[str, np.ndarray | None] = {
        name: getattr(result, name) for name in ("x", "xd", "xdd", "e", "ed", "edd")}
    if static:   # a static state does not move
        states.update({name: np.zeros_like(result.x if name.startswith("x") else result.e)
                       for name in ("xd", "xdd", "ed", "edd")})
    states["t"] = np.zeros(n) if static else np.asarray(result.t)
    applied = getattr(result, "applied", None)   # a static result's loads
    # a motion's: the constant XF (SPACAR stores FX per step in mode 1 too; a USERSIG
    # routine's loads are not among them)
    states["loads"] = (np.tile(own_loads(model), (n, 1)) if applied is None else
                       applied + own_loads(model))
    if isinstance(result, SimulationResult):
        states["reactions"], states["sigma"] = result.reactions, result.sigma
    return state_records(model, states, slopes=static or n == 1)


def linearization_records(linearizations: Sequence[Linearization], times: np.ndarray
                          ) -> dict[str, np.ndarray]:
    """The ``.sbd`` per-step records of the states of linearizations (SPACAR's modes 3 and
    4 rewrite the ``.sbd`` with them)."""
    model = linearizations[0].model
    states: dict[str, np.ndarray | None] = {"t": np.asarray(times, dtype=float)}
    for name in ("x", "xd", "xdd", "e", "sigma", "reactions"):
        states[name] = np.array([getattr(lin, name) for lin in linearizations])
    states["ed"] = np.array([lin.E_q @ lin.qd for lin in linearizations])
    states["loads"] = np.tile(own_loads(model), (len(linearizations), 1))
    states["edd"] = np.array([jacobian(model, lin.x) @ lin.xdd
                              + quadratic_velocity(model, lin.x, lin.xd)
                              for lin in linearizations])
    return state_records(model, states, slopes=False)


def state_records(model: Model, states: Mapping[str, np.ndarray | None], slopes: bool,
                  transfers: bool = True) -> dict[str, np.ndarray]:
    """Per-step records from arrays over the steps: ``t`` ``(n,)``; ``x xd xdd``
    ``(n, nx)``; ``e ed edd sigma`` ``(n, ne)``; ``loads`` and ``reactions`` ``(n, nx)``
    in flexmbd's form (moments on rotational nodes). Missing or ``None`` arrays are left
    out; ``BIGD`` (``D_x`` per step) is written when ``slopes``; ``DX`` and ``DE`` unless
    ``transfers`` is off (a model whose constraints do not determine its coordinates)."""
    number = SpacarNumbering(model)
    x = np.asarray(states["x"])
    n = len(x)
    nx, ne, nq = model.n_coordinates, model.n_deformations, model.n_dof
    per_step = 6 * nx + 4 * ne + nq * (nx + ne) + (nx * ne if slopes else 0)
    checks.output_memory(n, 8 * per_step, "steps of the .sbd")

    def column(values: np.ndarray, order: np.ndarray) -> np.ndarray:
        return np.asarray(values)[:, order][:, :, None]

    records = {"T": np.asarray(states["t"], dtype=float).reshape(n, 1, 1)}
    for name, key, order in (("X", "x", number.x), ("XD", "xd", number.x),
                             ("XDD", "xdd", number.x), ("E", "e", number.e),
                             ("ED", "ed", number.e), ("EDD", "edd", number.e)):
        values = states.get(key)
        if values is not None:
            records[name] = column(values, order)
    for name, key in (("FX", "loads"), ("FXT", "reactions")):
        loads = states.get(key)
        if loads is not None:
            records[name] = column(generalized_loads(model, x, loads, name == "FXT"),
                                   number.x)
    sigma = states.get("sigma")
    if sigma is not None:
        records["SIG"] = column(sigma, number.e)
    # a model whose constraints do not close cannot be compiled: element by element
    jacobians = ([jacobian(model, row) for row in x] if transfers else
                 [deformations_and_jacobian(model, row)[1] for row in x])
    if transfers:
        F_q = [first_order_transfer(model, row) for row in x]
        records["DX"] = np.array([F[np.ix_(number.x, number.q)] for F in F_q]
                                 ).reshape(n, model.n_coordinates, model.n_dof)
        records["DE"] = np.array([(D @ F)[np.ix_(number.e, number.q)]
                                  for D, F in zip(jacobians, F_q, strict=True)]
                                 ).reshape(n, model.n_deformations, model.n_dof)
    if slopes:
        records["BIGD"] = np.array([D[np.ix_(number.e, number.x)] for D in jacobians]
                                   ).reshape(n, model.n_deformations, model.n_coordinates)
    return records


def sbd_records(result: KinematicResult, mode: int | None = None
                ) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """The tables and per-step records of a run's ``.sbd`` (module docstring).

    Args:
        result: a kinematic, dynamic, inverse-dynamics or static result.
        mode: SPACAR's mode stored in ``MODE``; default 10 for a static result, 1 otherwise.
    """
    if not isinstance(result, KinematicResult):
        raise ArgumentError("result", f"must be a flexmbd result, got {type(result).__name__}")
    if mode is None:
        mode = SPACAR_MODES["static" if isinstance(result, StaticResult) else "dynamic"]
    return model_tables(result.model, mode), step_records(result) if len(result.t) else {}


def write_sbd(path: str | os.PathLike, result: KinematicResult, mode: int | None = None
              ) -> Path:
    """Write a run as SPACAR's binary data file ``.sbd``: the model's tables and every
    stored step (module docstring), in SPACAR's numbering.

    Args:
        path: the file to write.
        result: a kinematic, dynamic, inverse-dynamics or static result.
        mode: SPACAR's mode stored in ``MODE``; default 10 for a static result, 1 otherwise.
    """
    return write_records(path, "SBD", *sbd_records(result, mode))
