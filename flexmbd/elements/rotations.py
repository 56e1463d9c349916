"""Euler parameters and frames on rotational nodes, written once for every spatial type
(THEORY-SPATIAL in the project's theory page, sections 1 and 2).

The functions take plain sequences and the math module ``m`` like the deformation
functions, so the same lines serve the code generator (SymPy) and numpy. ``lam`` is
``(lam0, lam1, lam2, lam3)``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

#: components of a vector or of Euler parameters: numbers, SymPy symbols or arrays along
#: the first axis (a batch)
Components = Sequence[Any] | np.ndarray


def dot(a: Components, b: Components) -> Any:
    """``a . b`` of two 3-vectors."""
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a: Components, b: Components) -> list[Any]:
    """``a x b`` of two 3-vectors."""
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def rotate(lam: Components, a0: Components) -> list[Any]:
    """``R(lam) a0`` with the homogeneous quadratic form ``R = (lam0^2 - lamv.lamv) I +
    2 lamv lamv^T + 2 lam0 [lamv x]``: a rotation on the unit sphere, ``|lam|^2`` times
    one off it (SPACAR's extension, whose nodal forces it reproduces)."""
    lamv = lam[1:4]
    scale, along, turn = lam[0] ** 2 - dot(lamv, lamv), 2 * dot(lamv, a0), cross(lamv, a0)
    return [scale * a0[k] + along * lamv[k] + 2 * lam[0] * turn[k] for k in range(3)]


def body_rates(lam: Components) -> list[list[Any]]:
    """``G(lam)`` (3 x 4): the body angular velocity is ``omega' = 2 G(lam) lamdot``."""
    l0, l1, l2, l3 = lam
    return [[-l1, l0, l3, -l2], [-l2, -l3, l0, l1], [-l3, l2, -l1, l0]]


def global_rates(lam: Components) -> list[list[Any]]:
    """``E(lam)`` (3 x 4): the global angular velocity is ``omega = 2 E(lam) lamdot``."""
    l0, l1, l2, l3 = lam
    return [[-l1, l0, -l3, l2], [-l2, l3, l0, -l1], [-l3, -l2, l1, l0]]


def frame_columns(p: Components, at: int) -> tuple[list[Any], list[Any], list[Any]]:
    """The reference frame ``ex0, ey0, ez0`` stored as nine parameters from ``p[at]``."""
    return list(p[at:at + 3]), list(p[at + 3:at + 6]), list(p[at + 6:at + 9])
