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
  the number of elements of a chain instead of cubically. The matrices are
  filled into a constant :class:`SparsePattern`, so a step pays for the
  factorisation and not for SciPy's format conversions.

Rows and columns are scaled before factorising (rows to unit norm, angles by
the model size), so :attr:`conditioning`, an estimate of the smallest singular
value of the scaled matrix, is free of units: near 1 for a well-posed
mechanism, near 0 at a singular configuration.
"""

from __future__ import annotations

import numpy as np

#: systems larger than this use the sparse backend (the measured crossover of the cost
#: per step on the flexible slider-crank lies between 60 and 110 unknowns)
SPARSE_SIZE = 80


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
        self._invert(matrices * scale, np.swapaxes(scale, -1, -2))

    @classmethod
    def of_scaled(cls, scaled: np.ndarray, unscale: np.ndarray) -> DenseFactor:
        """From matrices already scaled, ``diag(r) A diag(c)`` ``(nb, n, n)``, and
        ``unscale = c r^T`` ``(n, n)`` (e.g. assembled with their scales, constant in a
        run)."""
        factor = cls.__new__(cls)
        factor._invert(scaled, unscale)
        return factor

    def _invert(self, scaled: np.ndarray, unscale: np.ndarray) -> None:
        try:
            inverse = np.linalg.inv(scaled)  # non-finite in, non-finite out
        except np.linalg.LinAlgError:  # an exactly singular member: invert one by one
            inverse = np.stack([_inverse_or_nan(a) for a in scaled])
        with np.errstate(divide="ignore", invalid="ignore"):
            self.conditioning = 1.0 / np.abs(inverse).sum(axis=-2).max(axis=-1)
        inverse *= unscale  # A^-1 = diag(c) (diag(r) A diag(c))^-1 diag(r)
        self.inverse = inverse

    @classmethod
    def from_inverse(cls, inverse: np.ndarray, conditioning: np.ndarray) -> DenseFactor:
        """A factorisation kept from earlier: ``inverse`` ``(nb, n, n)`` and its
        ``conditioning`` ``(nb,)``."""
        factor = cls.__new__(cls)
        factor.inverse, factor.conditioning = inverse, conditioning
        return factor

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """``A^-1 rhs`` for ``rhs`` ``(nb, n)`` or ``(nb, n, k)``."""
        # matmul, not einsum: half the cost on these small stacks
        if rhs.ndim == self.inverse.ndim - 1:
            return (self.inverse @ rhs[..., None])[..., 0]
        return self.inverse @ rhs

    def solve_transposed(self, rhs: np.ndarray) -> np.ndarray:
        """``A^-T rhs`` for ``rhs`` ``(nb, n)``."""
        return (rhs[:, None, :] @ self.inverse)[:, 0]


def _inverse_or_nan(a: np.ndarray) -> np.ndarray:
    try:
        return np.linalg.inv(a)
    except np.linalg.LinAlgError:
        return np.full_like(a, np.nan)


class SparsePattern:
    """The constant sparsity of a matrix assembled from entries at fixed positions.

    The element matrices of a model land at the same places at every step; only
    their values change. This maps the entries (duplicates summed) straight into
    the data array of one compressed-column matrix, so a new matrix costs a
    ``bincount`` instead of SciPy's format conversions.

    Args:
        positions: flat positions ``row * n + column`` of the entries ``(k,)``.
        n: the matrix size.
    """

    def __init__(self, positions: np.ndarray, n: int):
        from scipy.sparse import csc_matrix

        rows, cols = np.divmod(np.asarray(positions), n)
        order = cols * n + rows  # column-major, as compressed columns store them
        unique, self.slot = np.unique(order, return_inverse=True)
        self.columns, self.rows = np.divmod(unique, n)
        self.n = n
        indptr = np.searchsorted(self.columns, np.arange(n + 1))
        self.template = csc_matrix((np.ones(len(unique)), self.rows, indptr), shape=(n, n))

    def values(self, entries: np.ndarray, scale: np.ndarray) -> np.ndarray:
        """Data arrays ``(nb, nnz)`` of the matrices with ``entries`` ``(nb, k)``, each
        stored entry multiplied by ``scale`` ``(nb, nnz)``."""
        nb, nnz = entries.shape[0], len(self.rows)
        flat = (np.arange(nb)[:, None] * nnz + self.slot).ravel()
        return np.bincount(flat, entries.ravel(), minlength=nb * nnz).reshape(nb, nnz) * scale


class SparseFactor:
    """SuperLU factorisations of a batch of scaled sparse matrices (one per member).

    Args:
        pattern: the :class:`SparsePattern` of the matrices.
        entries: their entries ``(nb, k)`` at ``pattern``'s positions.
        row_scale: ``(nb, n)`` or ``(n,)``; column_scale: ``(n,)`` as for
            :class:`DenseFactor`.

    Attributes:
        conditioning: per member, the smallest pivot of the scaled factorisation
            relative to the largest, a cheap indicator of near-singularity
            (SuperLU keeps no condition estimate); 0 for a singular matrix.
    """

    def __init__(self, pattern: SparsePattern, entries: np.ndarray, row_scale, column_scale):
        from scipy.sparse.linalg import splu

        nb = entries.shape[0]
        row_scale = np.broadcast_to(row_scale, (nb, pattern.n))
        self.row_scale, self.column_scale = row_scale, column_scale
        data = pattern.values(entries, row_scale[:, pattern.rows]
                              * column_scale[pattern.columns])
        self.factors, conditioning = [], []
        matrix = pattern.template
        for values in data:
            matrix.data = values  # the same structure each time: no format checks
            try:
                if not np.all(np.isfinite(values)):
                    raise RuntimeError("not finite")
                lu = splu(matrix, permc_spec="COLAMD")
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
