"""The core's banded LU (``csrc/band.c``, a port of LAPACK's ``dgbtf2``/``dgbtrs``) against
LAPACK itself through SciPy: the same pivots, the same factors to round-off, solutions
as ``solve_banded`` gives them, with and without the transpose and for many right-hand
sides, a zero pivot named where LAPACK names it, and an estimate of ``||A^-1||_1`` that
never exceeds the norm and is usually it."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
from scipy.linalg import lapack

from flexmbd.engine._core import banded_lu


def banded(rng, n: int, kl: int, ku: int, diagonal: float = 1.0) -> np.ndarray:
    """A random ``(n, n)`` matrix with ``kl`` sub- and ``ku`` super-diagonals; ``diagonal``
    scales its diagonal (small: every column pivots)."""
    a = rng.standard_normal((n, n))
    i, j = np.indices((n, n))
    a[(j - i > ku) | (i - j > kl)] = 0.0
    a[i == j] *= diagonal
    return a


def band_storage(a: np.ndarray, kl: int, ku: int) -> np.ndarray:
    """``a`` in LAPACK's storage for ``dgbtrf`` (``kl`` rows of fill-in on top)."""
    n = len(a)
    ab = np.zeros((2 * kl + ku + 1, n))
    for j in range(n):
        for i in range(max(0, j - ku), min(n, j + kl + 1)):
            ab[kl + ku + i - j, j] = a[i, j]
    return ab


SIZES = [(1, 0, 0), (2, 1, 1), (5, 0, 2), (5, 3, 0), (17, 2, 3), (40, 5, 1), (120, 4, 7),
         (500, 3, 3), (500, 12, 9)]


@pytest.mark.parametrize("n, kl, ku", SIZES)
@pytest.mark.parametrize("diagonal", [1.0, 1e-3])
def test_the_factors_and_pivots_are_lapack_s(n, kl, ku, diagonal):
    rng = np.random.default_rng(n + 31 * kl + 7 * ku)
    a = banded(rng, n, kl, ku, diagonal)
    info, pivots, factors, _, _ = banded_lu(a, kl, ku, np.zeros((0, n)))
    lu, ipiv, lapack_info = lapack.dgbtrf(band_storage(a, kl, ku), kl, ku)
    assert info == lapack_info == 0
    np.testing.assert_array_equal(pivots, ipiv)   # both 0-based as SciPy returns them
    scale = np.abs(lu).max()
    np.testing.assert_allclose(factors, lu, rtol=0, atol=1e-12 * scale * n)


@pytest.mark.parametrize("n, kl, ku", SIZES)
@pytest.mark.parametrize("how", ["each", "many", "transposed"])
def test_solutions_are_those_of_solve_banded(n, kl, ku, how):
    rng = np.random.default_rng(3 * n + kl)
    a = banded(rng, n, kl, ku, diagonal=1e-2)
    rhs = rng.standard_normal((3, n))
    solved = rhs.copy()
    info, *_ = banded_lu(a, kl, ku, solved, how)
    assert info == 0
    matrix = a.T if how == "transposed" else a
    expected = scipy.linalg.solve(matrix, rhs.T).T
    condition = np.linalg.cond(a, 1)
    np.testing.assert_allclose(solved, expected, rtol=0,
                               atol=1e-13 * condition * np.abs(expected).max())
    if how != "transposed":   # the same numbers as LAPACK's banded solver
        ab = band_storage(a, kl, ku)[kl:]
        lapack_solution = scipy.linalg.solve_banded((kl, ku), ab, rhs.T).T
        np.testing.assert_allclose(solved, lapack_solution, rtol=0,
                                   atol=1e-13 * condition * np.abs(expected).max())


def test_a_zero_pivot_is_named_where_lapack_names_it():
    rng = np.random.default_rng(8)
    a = banded(rng, 30, 2, 2)
    a[:, 11] = 0.0     # column 11 empty: no pivot there
    info, _, _, smallest, estimate = banded_lu(a, 2, 2, np.zeros((0, 30)))
    lapack_info = lapack.dgbtrf(band_storage(a, 2, 2), 2, 2)[2]
    assert info == lapack_info == 12 and smallest == 0.0 and estimate == np.inf


@pytest.mark.parametrize("n, kl, ku", SIZES[1:])
def test_near_singular_systems_keep_their_accuracy_bound(n, kl, ku):
    """A = L U with a pivot of 1e-10 in U (so A is banded and nearly singular): the
    solution's residual is what backward stability allows, and the estimate of
    ||A^-1||_1 sees the near singularity."""
    rng = np.random.default_rng(n * kl + ku)
    lower = np.eye(n) + np.tril(banded(rng, n, kl, 0), -1) * 0.1 / max(kl, 1)
    upper = np.triu(banded(rng, n, 0, ku), 1) * 0.1 / max(ku, 1) + np.eye(n)
    upper[n // 2, n // 2] = 1e-10
    a = lower @ upper
    b = rng.standard_normal(n)
    x = b[None].copy()
    info, _, _, _, estimate = banded_lu(a, kl, ku, x)
    exact = np.abs(np.linalg.inv(a)).sum(axis=0).max()
    assert info == 0 and exact > 1e8
    assert exact / 10 <= estimate <= exact * (1 + 1e-6)
    residual = np.abs(a @ x[0] - b).max()
    assert residual <= 1e-12 * n * np.abs(a).max() * np.abs(x).max()


@pytest.mark.parametrize("n, kl, ku", SIZES)
def test_the_inverse_norm_estimate_is_a_lower_bound_and_usually_exact(n, kl, ku):
    exact_hits = 0
    for seed in range(5):
        a = banded(np.random.default_rng(seed + n), n, kl, ku, diagonal=0.1)
        info, _, _, _, estimate = banded_lu(a, kl, ku, np.zeros((0, n)))
        exact = np.abs(np.linalg.inv(a)).sum(axis=0).max()
        assert info == 0 and estimate <= exact * (1 + 1e-10)
        exact_hits += estimate >= exact * (1 - 1e-10)
    assert exact_hits >= 3
