"""The constraints of a model: the counts of ``D_c``, over-constraints released as SPACAR
Light releases them, and what makes ``D_c`` singular, in words.

``D_c`` (rows: rigid and independent deformations; columns: dependent coordinates) must
be square and regular (THEORY 3). :func:`check_solvability` names what closes the count
or not; :func:`overconstraint_releases` finds the deformations to release for each
over-constraint (FLEXURES 5) from one factorisation.
"""

from __future__ import annotations

import numpy as np

from ..elements import SpatialBeam, WarpingBeam
from ..engine import deformations_and_jacobian
from ..engine.diagnosis import SPARSE_FROM, clearly_regular, diagnose_rank, factorised
from ..errors import ModelError, Problem
from ..model import DeformationClass, Model

#: singular values of ``D_c`` below this share of the largest are zero: an over- or
#: under-constraint (FLEXURES 5)
RANK_RTOL = float(np.sqrt(np.finfo(float).eps))


def overconstraint_releases(model: Model, not_last: set[int]) -> list[tuple[int, int]]:
    """The releases ``(element, deformation)`` that take away every over-constraint of
    ``model`` in its initial configuration: for each, in the left singular vector of the
    smallest singular value, the largest dynamic (flexible) deformation of the last beam
    of a leaf (``not_last``: the beams of a chain but its last) not yet released.

    Raises:
        ModelError: the model is under-constrained, or no deformation qualifies for an
            over-constraint.
    """
    D_x = deformations_and_jacobian(model, np.asarray(model.x0))[1]
    rows = list(model.constrained)
    D_c = D_x[np.ix_(rows, model.dependent)]
    element_of = {i: (number, k + 1) for number, element in model.elements.items()
                  for k, i in enumerate(element.deformations)}
    over, under, null = _over_constraints(D_c)
    if under:
        raise ModelError([f"the model is under-constrained ({under} coordinate(s) free): "
                          f"check the connections, the supports and the releases"])
    releases: list[tuple[int, int]] = []
    while over:
        u = null[:, 0]
        order = np.argsort(-u**2)
        needed = int(np.searchsorted(np.cumsum(u[order] ** 2), np.sqrt(1 - 1e-6))) + 1
        chosen = None
        for at in order[:needed]:
            number, _ = element_of[rows[at]]
            element = model.elements[number]
            if (element.type in (SpatialBeam, WarpingBeam) and number not in not_last
                    and model.deformation_class[rows[at]] == DeformationClass.DYNAMIC):
                chosen = at
                break
        if chosen is None:
            involved = ", ".join(model.describe_deformation(rows[at])
                                 for at in order[:needed])
            raise ModelError([f"{over} over-constraint(s) left that no flexible "
                              f"deformation of a leaf's last beam can release (they "
                              f"involve {involved}); release deformations yourself"])
        releases.append(element_of[rows[chosen]])
        del rows[chosen]
        null = _without_row(null, int(chosen))
        over -= 1
    return releases


def _over_constraints(D_c: np.ndarray) -> tuple[int, int, np.ndarray]:
    """Over- and under-constraints of ``D_c`` ``(m, n)`` (:func:`_constraint_counts`) and an
    orthonormal basis of its left null space ``(m, over)``, from one factorisation:
    releasing a row keeps the null vectors that vanish on it (:func:`_without_row`; a
    factorisation per release would cost the cube of the rows each time). With full
    column rank (the usual case) :func:`_left_null_space` gives the basis from one LU
    factorisation (sparse for a large model: linear in its beams); otherwise the SVD
    decides."""
    rows, cols = D_c.shape
    if rows >= cols > 0:
        null = _left_null_space(D_c)
        if null is not None:
            return rows - cols, 0, null
    if not D_c.size:
        return *_constraint_counts(D_c), np.eye(rows)[:, :max(rows - cols, 0)]
    U, values = np.linalg.svd(D_c)[:2]
    over, under = _constraint_counts(D_c, values)
    return over, under, U[:, rows - over:]


def _left_null_space(D_c: np.ndarray) -> np.ndarray | None:
    """An orthonormal basis ``(m, m - n)`` of the left null space of ``D_c`` ``(m, n)``,
    ``m >= n``, when ``D_c`` has clearly full column rank, else ``None``. With its columns
    scaled to unit length (which keeps the left null space, and the condition of a
    chain of beams from growing with the square of the beams), ``A = [D_c, R]`` with
    ``m - n`` random unit columns ``R`` is then regular, and ``A^T u_k = [0; e_k]`` gives
    ``D_c^T u_k = 0`` for ``m - n`` independent ``u_k``: one factorisation of ``A`` and
    ``m - n`` transposed solves."""
    rows, cols = D_c.shape
    if rows < SPARSE_FROM:  # the complete QR: cheap, and the releases of before
        Q, R = np.linalg.qr(D_c, mode="complete")
        regular = clearly_regular(R[:cols], RANK_RTOL)
        return Q[:, cols:] if regular else None
    lengths = np.linalg.norm(D_c, axis=0)
    if not np.all(lengths > 0):
        return None
    extra = np.random.default_rng(0).standard_normal((rows, rows - cols))
    A = np.hstack([D_c / lengths, extra / np.linalg.norm(extra, axis=0)])
    solve = factorised(A)
    if solve is None or not clearly_regular(A, RANK_RTOL, solve):
        return None
    right = np.zeros((rows, rows - cols))
    right[cols:] = np.eye(rows - cols)
    return np.linalg.qr(solve(right, transposed=True))[0]


def _without_row(null: np.ndarray, row: int) -> np.ndarray:
    """An orthonormal basis ``(m - 1, k - 1)`` of the left null space of ``D_c`` without
    ``row``, from one of ``D_c``'s ``(m, k)``: the combinations of ``null`` that vanish on
    ``row``, that entry dropped. The column largest on ``row`` eliminates it from the
    others."""
    pivot = int(np.argmax(np.abs(null[row])))
    rest = np.delete(null, pivot, axis=1)
    rest = rest - np.outer(null[:, pivot], rest[row] / null[row, pivot])
    return np.linalg.qr(np.delete(rest, row, axis=0))[0]


def _constraint_counts(D_c: np.ndarray, values: np.ndarray | None = None
                       ) -> tuple[int, int]:
    """Over- and under-constraints of ``D_c`` (FLEXURES 5): singular values below
    ``sqrt(eps)`` of the largest count in both (``values``, when the caller has them),
    and a surplus of rows (columns) adds to the over- (under-) constraints."""
    rows, cols = D_c.shape
    if not rows or not cols:
        return rows, cols
    if values is None:
        values = np.linalg.svd(D_c, compute_uv=False)
    singular = int(np.sum(values < RANK_RTOL * values[0])) + \
        (min(rows, cols) - len(values))
    return max(rows - cols, 0) + singular, max(cols - rows, 0) + singular


def check_solvability(model: Model) -> list[Problem]:
    """Problems with the square, nonsingular ``D_c`` required by THEORY section 3.

    Counts rows (rigid and independent deformations) against columns (dependent
    coordinates) and, through the singular value decomposition of ``D_c`` in the
    initial configuration, names the coordinates that the constraints leave
    free and the deformations whose equations are redundant.
    """

    rows, cols = len(model.constrained), len(model.dependent)
    if rows == cols == 0:
        return []
    if rows and cols:
        D_x = deformations_and_jacobian(model, np.asarray(model.x0))[1]
        text, free, redundant = diagnose_rank(model, D_x[np.ix_(model.constrained,
                                                                model.dependent)])
    elif rows:
        free, redundant = np.zeros(0, dtype=int), model.constrained
        names = ", ".join(model.describe_deformation(i) for i in model.constrained)
        text = f"the equations of {names} have no dependent coordinate to solve for"
    else:
        free, redundant = model.dependent, np.zeros(0, dtype=int)
        names = ", ".join(model.describe_coordinate(i) for i in model.dependent)
        text = f"nothing determines the coordinates {names}"
    about = [*(("coordinate", model.coordinate_labels[i]) for i in free),
             *(("deformation", model.deformation_labels[i]) for i in redundant)]
    if rows == cols:
        return [Problem(f"D_c is singular in the initial configuration: {text}", *about)] \
            if text else []
    excess = abs(rows - cols)
    if rows > cols:
        advice = (f"{excess} equation(s) too many; release {excess} deformation(s) or make "
                  f"{excess} fixed/input coordinate(s) dependent")
    else:
        advice = (f"{excess} equation(s) too few; fix {excess} coordinate(s), make them inputs "
                  f"or dynamic, or add elements")
    count = (f"the degree-of-freedom count does not close: {rows} constraint equations (rigid "
             f"and independent deformations) for {cols} dependent coordinates, {advice}")
    return [Problem(f"{count} ({text})" if text else count, *about)]
