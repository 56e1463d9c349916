"""The linearized equations in SPACAR's files: ``.sbm`` (``M0 C0 D0 K0 N0 G0`` per step)
and ``.ltv`` (the state-space form ``A B C D`` per step, with ``M0 C0B K0B``), over the
dynamic degrees of freedom in SPACAR's order (:mod:`.numbering`: the dynamic coordinates
by node, then the dynamic deformations by element, which is flexmbd's order of them).

In ``.ltv`` the states are the dynamic degrees of freedom and then their rates,
``A = [[0, I], [-M0^-1 K0B, -M0^-1 C0B]]`` with ``K0B = K0 + N0 + G0`` and
``C0B = C0 + D0``, as SPACAR writes them.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ...analysis.linearization import Linearization
from ...analysis.statespace import StateSpace, mass_solver
from ...errors import ArgumentError
from .binary import write_records


def _times(linearizations: Sequence[Linearization], times) -> np.ndarray:
    if not linearizations:
        raise ArgumentError("linearizations", "give at least one linearization")
    model = linearizations[0].model
    if any(lin.model is not model for lin in linearizations):
        raise ArgumentError("linearizations", "must all be of one model")
    n = len(linearizations)
    t = np.zeros(n) if times is None else np.asarray(times, dtype=float)
    if t.shape != (n,):
        raise ArgumentError("times", f"must have one time per linearization ({n}), got "
                                     f"shape {t.shape}")
    return t


def _stack(matrices: list[np.ndarray]) -> np.ndarray:
    """``(n, rows, cols)`` from ``n`` matrices, also when they have no rows."""
    return np.array(matrices, dtype=float).reshape(len(matrices), *np.shape(matrices[0]))


def write_sbm(path: str | os.PathLike, linearizations: Sequence[Linearization],
              times: Sequence[float] | None = None) -> Path:
    """Write linearized equations as SPACAR's ``.sbm`` (:func:`sbm_records`)."""
    return write_records(path, "SBM", *sbm_records(linearizations, times))


#: a file's tables and per-step records, by name
Records = tuple[dict[str, np.ndarray], dict[str, np.ndarray]]


def sbm_records(linearizations: Sequence[Linearization], times=None,
                systems: Sequence[StateSpace] | None = None) -> Records:
    """The tables and per-step records of SPACAR's ``.sbm``: ``M0 C0 D0 K0 N0 G0`` over the
    dynamic degrees of freedom (SPACAR's order) at each step, with its time ``T`` (default
    0, as SPACAR's static modes store); with the state-space ``systems`` of mode 9, as
    SPACAR writes that mode's: tables ``NDOF NKDO`` (the degrees of freedom of ``M0``) and
    ``NNOM`` (the inputs) in place of ``NDDO NKDD``, and per step ``B0``, the generalized
    forces of the inputs on the degrees of freedom ``(nd, nu)``.

    Args:
        linearizations: one :class:`~flexmbd.analysis.linearization.Linearization` per step,
            all of one model.
        times: the step times [s], as many as ``linearizations``.
        systems: the state-space model of each step (mode 9).
    """
    t = _times(linearizations, times)
    n_dynamic = len(linearizations[0].model.dynamic_q_labels)
    steps = {"T": t[:, None, None]}
    for name in ("M0", "C0", "D0", "K0", "N0", "G0"):
        steps[name] = _stack([lin.block(name) for lin in linearizations])
    if systems is None:
        return {"NDDO": _count(n_dynamic), "NKDD": _count(n_dynamic)}, steps
    tables = {"NDOF": _count(n_dynamic), "NKDO": _count(n_dynamic),
              "NNOM": _count(systems[0].B.shape[1])}
    # B = [0; M0^-1 B0]: the inputs' generalized forces
    steps["B0"] = _stack([lin.block("M0") @ system.B[n_dynamic:]
                          for lin, system in zip(linearizations, systems, strict=True)])
    return tables, steps


def _count(n: int) -> np.ndarray:
    return np.array([[n]], dtype=np.int32)


def write_ltv(path: str | os.PathLike, linearizations: Sequence[Linearization],
              systems: Sequence[StateSpace] | None = None,
              times: Sequence[float] | None = None) -> Path:
    """Write linearized equations as SPACAR's ``.ltv`` (:func:`ltv_records`)."""
    return write_records(path, "LTV", *ltv_records(linearizations, systems, times))


def ltv_records(linearizations: Sequence[Linearization],
                systems: Sequence[StateSpace] | None = None, times=None) -> Records:
    """The tables and per-step records of SPACAR's ``.ltv``: per step the state-space matrices
    ``A B C`` with ``M0 C0B K0B``; with ``systems`` (mode 9) also ``D`` (table ``DFT`` 1),
    as SPACAR writes them. Tables ``NNOM`` (the nominal inputs: the systems' inputs, none
    in mode 3), ``NYS`` (0) and ``X0`` (the states' offsets, zero); per step ``U0`` (the
    inputs' values, zero: an input is a load on top of the state's) and ``Y0`` (the
    outputs' values at the state).

    Args:
        linearizations: one linearization per step.
        systems: the state-space model of each step (:func:`~flexmbd.analysis.statespace.
            state_space`, inputs and outputs of the file's third block); default: the
            generalized forces on the dynamic degrees of freedom as inputs and no outputs,
            as SPACAR's mode 3 writes.
        times: the step times [s] (default 0).
    """
    t = _times(linearizations, times)
    blocks: dict[str, list[np.ndarray]] = {name: [] for name in
                                           ("M0", "C0B", "K0B", "A", "B", "C", "D", "Y0")}
    for k, lin in enumerate(linearizations):
        M, C, K = lin.block("M0"), lin.block("C"), lin.block("K")
        blocks["M0"].append(M)
        blocks["C0B"].append(C)
        blocks["K0B"].append(K)
        if systems is None:
            nd = len(M)
            inverse = mass_solver(M, [lin.model.q_labels[j] for j in lin.dynamic])(np.eye(nd))
            blocks["A"].append(np.block([[np.zeros((nd, nd)), np.eye(nd)],
                                         [-inverse @ K, -inverse @ C]]))
            blocks["B"].append(np.vstack([np.zeros((nd, nd)), inverse]))
            blocks["C"].append(np.zeros((0, 2 * nd)))
            blocks["D"].append(np.zeros((0, nd)))
            blocks["Y0"].append(np.zeros((0, 1)))
        else:
            for name in ("A", "B", "C", "D"):
                blocks[name].append(getattr(systems[k], name))
            blocks["Y0"].append(np.array([[_value(lin, label)]
                                          for label in systems[k].outputs]).reshape(-1, 1))
    first = blocks["B"][0]
    nominal = first.shape[1] if systems is not None else 0
    tables = {"NX": _count(first.shape[0]), "NU": _count(first.shape[1]),
              "NY": _count(blocks["C"][0].shape[0]), "NNOM": _count(nominal),
              "NYS": _count(0), "DFT": _count(int(systems is not None)),
              "X0": np.zeros((first.shape[0], 1))}
    steps = {"T": t[:, None, None]}
    for name in ("A", "B", "C", "D", "M0", "C0B", "K0B"):
        if name != "D" or systems is not None:
            steps[name] = _stack(blocks[name])
    steps["U0"] = np.zeros((len(t), nominal, 1))
    steps["Y0"] = _stack(blocks["Y0"])
    return tables, steps


def _value(lin: Linearization, label: str) -> float:
    """An output's value at a linearization's state: a coordinate ``"x5.2"`` or its rate
    ``"xd5.2"``."""
    rate = label.startswith("xd")
    index = lin.model._coordinate_index("x" + label[2:] if rate else label)
    return float((lin.xd if rate else lin.x)[index])
