"""Factorisations of the square systems of a run: ``D_c`` and the saddle-point matrices.

Two backends behind one interface (``solve``, ``conditioning``):

* :class:`DenseFactor` for the small systems of most mechanisms: the explicit
  inverse of a whole batch of matrices (e.g. every output time at once) with
  numpy. Each later solve is then one matrix-vector product, which matters
  because a time step solves with the same ``D_c`` several times; and numpy's
  ``inv`` needs no SciPy, whose import alone costs more than a whole run of a
  small model.
* :class:`SparseFactor` for long chains (hundreds of coordinates): SuperLU
  from ``scipy.sparse`` (imported only then), whose cost grows linearly with
  the number of elements of a chain instead of cubically.

Rows and columns are scaled before factorising (rows to unit norm, angles by
the model size), so :attr:`conditioning`, an estimate of the smallest singular
value of the scaled matrix, is free of units: near 1 for a well-posed
mechanism, near 0 at a singular configuration.
"""

from __future__ import annotations

import numpy as np

#: systems larger than this use the sparse backend
SPARSE_SIZE = 120


class DenseFactor:
    """The inverse of a batch of scaled square matrices.

    Args:
        matrices: ``(nb, n, n)``.
        row_scale: ``(nb, n)`` or ``(n,)``; column_scale: ``(n,)``. The matrix
            factorised is ``diag(row_scale) A diag(column_scale)``.

    Attributes:
        inverse: ``A^-1`` ``(nb, n, n)``.
        conditioning: ``1 / ||(scaled A)^-1||_1`` per matrix ``(nb,)``: 0 (or NaN)
            for a singular one.
    """

    def __init__(self, matrices: np.ndarray, row_scale, column_scale):
        # one scale matrix each way: two multiplications instead of four per factorisation
        row_scale, column_scale = np.asarray(row_scale), np.asarray(column_scale)
        scale = row_scale[..., :, None] * column_scale
        try:
            inverse = np.linalg.inv(matrices * scale)  # non-finite in, non-finite out
        except np.linalg.LinAlgError:  # an exactly singular member: invert one by one
            inverse = np.stack([_inverse_or_nan(a) for a in matrices * scale])
        with np.errstate(divide="ignore", invalid="ignore"):
            self.conditioning = 1.0 / np.abs(inverse).sum(axis=-2).max(axis=-1)
        inverse *= np.swapaxes(scale, -1, -2)
        self.inverse = inverse

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """``A^-1 rhs`` for ``rhs`` ``(nb, n)`` or ``(nb, n, k)``."""
        if rhs.ndim == self.inverse.ndim - 1:
            return np.einsum("bij,bj->bi", self.inverse, rhs)
        return self.inverse @ rhs

    def solve_transposed(self, rhs: np.ndarray) -> np.ndarray:
        """``A^-T rhs`` for ``rhs`` ``(nb, n)``."""
        return np.einsum("bji,bj->bi", self.inverse, rhs)


def _inverse_or_nan(a: np.ndarray) -> np.ndarray:
    try:
        return np.linalg.inv(a)
    except np.linalg.LinAlgError:
        return np.full_like(a, np.nan)


class SparseFactor:
    """SuperLU factorisations of a batch of scaled sparse matrices (one per member).

    Args:
        matrices: a list of ``scipy.sparse`` matrices ``(n, n)``, one per member.
        row_scale: ``(nb, n)``; column_scale: ``(n,)`` as for :class:`DenseFactor`.

    Attributes:
        conditioning: per member, the smallest pivot of the scaled factorisation
            relative to the largest, a cheap indicator of near-singularity
            (SuperLU keeps no condition estimate); 0 for a singular matrix.
    """

    def __init__(self, matrices, row_scale, column_scale):
        from scipy.sparse import diags
        from scipy.sparse.linalg import splu

        row_scale = np.broadcast_to(row_scale, (len(matrices), len(column_scale)))
        self.row_scale, self.column_scale = row_scale, column_scale
        self.factors, conditioning = [], []
        for a, rows in zip(matrices, row_scale, strict=True):
            scaled = (diags(rows) @ a @ diags(column_scale)).tocsc()
            try:
                if not np.all(np.isfinite(scaled.data)):
                    raise RuntimeError("not finite")
                lu = splu(scaled, permc_spec="COLAMD")
            except RuntimeError:  # exactly singular
                self.factors.append(None)
                conditioning.append(0.0)
                continue
            pivots = np.abs(lu.U.diagonal())
            self.factors.append(lu)
            conditioning.append(float(pivots.min() / pivots.max()) if pivots.size else 1.0)
        self.conditioning = np.array(conditioning)

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """``A^-1 rhs`` for ``rhs`` ``(nb, n)`` or ``(nb, n, k)``."""
        shape = (-1,) + (1,) * (rhs.ndim - 2)
        out = np.empty_like(rhs, dtype=float)
        for b, lu in enumerate(self.factors):
            if lu is None:
                out[b] = np.nan
                continue
            out[b] = self.column_scale.reshape(shape) * lu.solve(
                np.ascontiguousarray(self.row_scale[b].reshape(shape) * rhs[b]))
        return out

    def solve_transposed(self, rhs: np.ndarray) -> np.ndarray:
        """``A^-T rhs`` for ``rhs`` ``(nb, n)``."""
        out = np.empty_like(rhs, dtype=float)
        for b, lu in enumerate(self.factors):
            out[b] = (np.nan if lu is None else
                      self.row_scale[b] * lu.solve(self.column_scale * rhs[b], trans="T"))
        return out
