"""The one eigen path of the linearized analyses: the lowest ``omega^2`` of ``K phi =
omega^2 M phi`` (vibration) and, by the same means, of other pencils.

Two ways, chosen by size alone (:func:`arpack_pays`):

* **dense** (LAPACK) for small problems or many modes. A symmetric positive definite
  ``K`` (a structure at rest, a stable equilibrium) gives the largest ``mu =
  1/omega^2`` of ``L^-1 M L^-T`` with ``K = L L^T``: rounding then scales with the
  lowest frequencies, where reducing by ``M`` (the generalized solvers) scales it with
  the highest, the stiff axial ones of flexures (1e-5 of a 200-beam column's first
  frequency). An unsymmetric regular ``K`` (``N0`` and ``C0`` in motion, a global
  moment's load stiffness) gives ``mu`` of ``K^-1 M`` likewise. A symmetric
  indefinite or singular ``K`` (mechanisms, unstable states) takes SciPy's generalized
  solvers, whose values within their rounding are rigid-body modes (exactly 0).
* **ARPACK in shift-invert at 0** for a few lowest modes of a large problem, with the
  factorisation the caller already holds (the engine's banded tangent, or an LU of the
  reduced one): ``O(n b^2)`` per iteration instead of the whole spectrum's ``O(n^3)``.
  Lanczos in the ``M`` inner product for a symmetric ``K``, Arnoldi on ``K^-1 M`` for
  an unsymmetric one; deflated runs then look for further copies of a multiple
  eigenvalue (:func:`lowest_arpack`). The values come from Rayleigh-Ritz on the basis
  found, with exact products of ``K`` and ``M``: solves lose digits to the stiffness
  contrast of thin leaves (axial against bending stiffness), the quotients take them
  back.

Where ARPACK cannot tell the modes (a singular tangent, no convergence, a complex pair
among the lowest) the caller falls back to the dense way and warns: never silently.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

__all__ = ["EigenPath", "arpack_pays", "lowest_arpack", "lowest_arpack_dense", "lowest_dense",
           "ritz_values"]

#: relative asymmetry below which a stiffness block counts as symmetric (rounding of the
#: products that make it); above it, as along a motion with N0, the general solver runs
SYMMETRIC = 1e-9

#: a generalized eigensolver's eigenvalues carry rounding of about ``n eps`` times the
#: largest; this many times that is taken as zero (a rigid-body mode), so that rounding
#: never reads as an unstable direction whatever the CPU's BLAS kernels
ROUNDING_MARGIN = 100.0

#: a few lowest modes of a problem this large take ARPACK (``O(n b^2)`` per iteration on a
#: factorisation) instead of the whole spectrum (``O(n^3)``): at most this share of the
#: unknowns, from this many on. Below, LAPACK on the reduced matrices is cheaper than
#: ARPACK with its import (SciPy's sparse and dense linear algebra, 0.15 s once): on a
#: cross-spring pivot, 0.10 s against 0.22 s for 21 load steps at 90 degrees of freedom,
#: 0.35 s against 0.25 s at 186
FEW_MODES_SHARE, FEW_MODES_FROM = 0.25, 120
#: the extra modes ARPACK iterates for, so that a multiple eigenvalue is found whole
FEW_MODES_EXTRA = 4
#: deflated ARPACK runs that look for further copies of a multiple eigenvalue
MAX_DEFLATIONS = 8
#: a basis vector whose part independent of the others is below this share of the
#: largest is dropped (:func:`_orthonormal`): the constraints' rounding grows by at most
#: its inverse, to 1e-10 of a vector
INDEPENDENT = 1e-6
#: a Ritz value whose imaginary part exceeds this share of its size is complex (a
#: flutter-like state): the result is then not a set of vibration modes
COMPLEX = 1e-8


class EigenError(ArithmeticError):
    """ARPACK could not tell the lowest modes; the message says why (the caller falls
    back to the dense way, with a warning)."""


@dataclass(frozen=True)
class EigenPath:
    """Which way an eigenproblem was solved, and why.

    Attributes:
        method: ``"dense"`` (LAPACK, the whole spectrum) or ``"arpack"`` (shift-invert on
            a factorisation).
        system: ``"reduced"`` (the tangent over the degrees of freedom) or ``"banded"``
            (the engine's saddle-point tangent in all coordinates).
        reason: a sentence: the sizes that chose it, or the failure that forced it.
    """

    method: str
    system: str
    reason: str

    def __str__(self) -> str:
        return f"{self.method} on the {self.system} tangent: {self.reason}"


def arpack_pays(n: int, count: int) -> bool:
    """Whether ``count`` lowest modes of ``n`` unknowns take ARPACK: at least
    :data:`FEW_MODES_FROM` unknowns and at most :data:`FEW_MODES_SHARE` of them asked."""
    return n >= FEW_MODES_FROM and count <= FEW_MODES_SHARE * n


def size_reason(n: int, count: int) -> str:
    """Why :func:`arpack_pays` chose as it did, in words."""
    if arpack_pays(n, count):
        return (f"{count} lowest of {n} unknowns (ARPACK from {FEW_MODES_FROM} unknowns "
                f"and at most {FEW_MODES_SHARE:.0%} of them)")
    if n < FEW_MODES_FROM:
        return f"{n} unknowns (the whole spectrum below {FEW_MODES_FROM})"
    return f"{count} of {n} modes asked (the whole spectrum above {FEW_MODES_SHARE:.0%})"


# --- ARPACK -----------------------------------------------------------------------------
def start_vector(n: int) -> np.ndarray:
    """ARPACK's start vector: fixed, so runs repeat, and with every mode in it (a vector
    of ones misses the antisymmetric modes of a symmetric structure)."""
    return np.random.default_rng(0).standard_normal(n)


def _arpack(operator_times: Callable[[np.ndarray], np.ndarray], n: int, k: int,
            v0: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The ``k`` eigenpairs of largest magnitude of ``v -> operator_times(v)`` (ARPACK's
    ``eigs``, to machine precision): ``mu`` ``(k,)`` and their vectors ``(n, k)``.

    Raises:
        EigenError: no convergence, or a failure of the solves.
    """
    from scipy.sparse.linalg import LinearOperator, eigs

    operator = LinearOperator((n, n), matvec=operator_times, dtype=float)
    return _converged(lambda: eigs(operator, k=k, which="LM", tol=0.0, v0=v0), k)


def _converged(call: Callable[[], tuple[np.ndarray, np.ndarray]], k: int
               ) -> tuple[np.ndarray, np.ndarray]:
    """``call()``, an ARPACK run for ``k`` eigenpairs, with its failures as
    :class:`EigenError` and its results checked finite.

    Raises:
        EigenError: no convergence, a failure of the solves, or values not finite.
    """
    from scipy.sparse.linalg import ArpackError, ArpackNoConvergence

    try:
        values, vectors = call()
    except ArpackNoConvergence:
        raise EigenError(f"ARPACK did not converge to the {k} lowest modes") from None
    except ArpackError as error:
        raise EigenError(f"ARPACK failed ({error}): the tangent is singular or not "
                         f"finite") from None
    if not np.all(np.isfinite(values)) or not np.all(np.isfinite(vectors)):
        raise EigenError("ARPACK found values that are not finite")
    return values, vectors


def _refuse_complex(mu: np.ndarray, reach: float) -> None:
    """Raise where a value ``mu`` of at least ``reach`` is complex: a multiple eigenvalue
    that rounding split into a complex pair, whose vectors come from an ill-conditioned
    eigenproblem of ARPACK's small matrix and may lie far from the modes (LAPACK then
    tells them, with a warning).

    Raises:
        EigenError: such a value.
    """
    wanted = np.abs(mu) >= reach * (1.0 - 1e-6)
    if np.any(mu.imag[wanted] != 0.0):
        raise EigenError("a multiple eigenvalue among the lowest came out of ARPACK as a "
                         "complex pair")


def _orthonormal(parts: np.ndarray) -> np.ndarray:
    """An orthonormal basis of the columns of ``parts``, nearly dependent ones dropped:
    ARPACK may return two copies of a multiple eigenvalue's vector that differ by
    rounding, and their difference, normalized, would blow the rounding of the
    constraints up by the inverse of that difference (a vector that breaks the
    constraints has too little strain energy, and would pull a Ritz value down)."""
    basis, triangle = np.linalg.qr(parts)
    diagonal = np.abs(np.diag(triangle))
    return basis[:, diagonal > INDEPENDENT * diagonal.max(initial=0.0)]


def _lanczos(inverse_times: Callable[[np.ndarray], np.ndarray],
             mass_times: Callable[[np.ndarray], np.ndarray], n: int, k: int,
             v0: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The ``k`` eigenpairs of ``K x = omega^2 M x`` with ``omega^2`` nearest 0 by
    ARPACK's Lanczos in shift-invert mode (``eigsh``, the ``M`` inner product, ``M``
    positive semidefinite): ``mu = 1/omega^2`` ``(k,)`` and the vectors ``(n, k)``.

    Raises:
        EigenError: no convergence, or a failure of the solves.
    """
    from scipy.sparse.linalg import LinearOperator, eigsh

    def unused(v):   # shift-invert mode applies K^-1 and M only
        raise AssertionError("K itself is not needed")

    def operator(matvec):
        return LinearOperator((n, n), matvec=matvec, dtype=float)

    omega2, vectors = _converged(lambda: eigsh(
        operator(unused), k=k, M=operator(mass_times), sigma=0.0,
        OPinv=operator(inverse_times), which="LM", tol=0.0, v0=v0), k)
    if np.any(omega2 == 0.0):
        raise EigenError("ARPACK found a mode without stiffness (omega^2 = 0)")
    return 1.0 / omega2, vectors


def lowest_arpack(inverse_times_mass: Callable[[np.ndarray], np.ndarray],
                  mass_times: Callable[[np.ndarray], np.ndarray],
                  stiffness_products: Callable[[np.ndarray], np.ndarray], n: int, count: int,
                  inverse_times: Callable[[np.ndarray], np.ndarray] | None = None
                  ) -> tuple[np.ndarray, np.ndarray]:
    """The ``count`` lowest ``omega^2`` ``(count,)`` and their shapes ``(n, count)``
    (``phi^T M phi = 1``): ARPACK in shift-invert at 0, then Rayleigh-Ritz with exact
    products. A symmetric ``K`` (``inverse_times`` given) takes Lanczos in the ``M``
    inner product (``eigsh``), whose vectors are accurate in a cluster of equal
    frequencies; an unsymmetric one Arnoldi on ``K^-1 M`` (``eigs``), which hands a
    complex pair among the lowest (a multiple eigenvalue split by rounding, its vectors
    unreliable) to the caller's LAPACK.

    A Krylov space grown from one vector holds one vector per distinct eigenvalue: the
    further copies of a multiple one (the sway pairs of a symmetric structure) enter
    only by rounding, so whether ARPACK finds them depends on the CPU's BLAS kernels.
    So ARPACK runs again with the modes found taken out (``P K^-1 M P``, ``P`` the
    ``M``-orthogonal complement), until its largest ``1/omega^2`` lies below the
    ``count``-th found: every copy among the lowest is then in the basis.

    Args:
        inverse_times_mass: ``v -> K^-1 M v`` for ``v`` ``(n,)`` (the caller's
            factorisation; on a constrained system its result keeps the constraints).
        mass_times: ``Z -> M Z`` for ``Z`` ``(n, k)``.
        stiffness_products: ``Z -> Z^T K Z`` ``(k, k)``, exact (no solve).
        n: unknowns.
        count: modes wanted, at most ``n - FEW_MODES_EXTRA - 2``.
        inverse_times: ``v -> K^-1 v`` for a symmetric ``K``.

    Raises:
        EigenError: no convergence, a failure of the solves, complex values among the
            lowest, or a mode without mass.
    """
    k = min(count + FEW_MODES_EXTRA, n - 2)

    def mass_of(v: np.ndarray) -> np.ndarray:
        return mass_times(v[:, None])[:, 0]

    def run(found: np.ndarray, k: int, v0: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """ARPACK with the modes ``found`` (M-orthonormal) taken out."""
        weighted = mass_times(found)

        def deflated_inverse(x):
            assert inverse_times is not None
            w = inverse_times(x - weighted @ (found.T @ x))
            return w - found @ (weighted.T @ w)

        def deflated(v):
            w = inverse_times_mass(v - found @ (weighted.T @ v))
            return w - found @ (weighted.T @ w)

        if inverse_times is not None:
            return _lanczos(deflated_inverse, mass_of, n, k, v0)
        return _arpack(deflated, n, k, v0)

    # in the operator's range: on a constrained system a start vector that breaks the
    # constraints would stay in the Krylov basis, and in the Ritz vectors
    v0 = inverse_times_mass(start_vector(n))
    mu, right = run(np.zeros((n, 0)), k, v0)
    _refuse_complex(mu, np.sort(np.abs(mu))[::-1][count - 1])
    basis = _orthonormal(right.real)
    for _ in range(MAX_DEFLATIONS):
        omega2, y = ritz_values(stiffness_products(basis),
                                basis.T @ mass_times(basis), basis.shape[1])
        found = basis @ y   # M-orthonormal
        room = n - basis.shape[1] - 2
        if room < 1:
            break
        mu, more = run(found, min(FEW_MODES_EXTRA, room), v0)
        reach = (1.0 - 1e-6) / omega2[count - 1]
        if np.abs(mu).max(initial=0.0) < reach:
            break   # nothing the basis lacks reaches the count lowest
        _refuse_complex(mu, reach)
        basis = _orthonormal(np.hstack([basis, more.real]))
    else:
        raise EigenError(f"a multiple eigenvalue kept adding copies after "
                         f"{MAX_DEFLATIONS} deflated runs")
    return omega2[:count], found[:, :count]


def ritz_values(stiffness: np.ndarray, mass: np.ndarray, count: int
                ) -> tuple[np.ndarray, np.ndarray]:
    """The ``count`` lowest ``omega^2`` ``(count,)`` of the projected pencil ``Z^T K Z y =
    omega^2 Z^T M Z y`` (``(m, m)`` each) and their ``y`` ``(m, count)`` with ``y^T (Z^T M
    Z) y = 1`` (Rayleigh-Ritz: with exact products ``K Z`` and ``M Z`` the values are good
    to the square of the basis's error).

    Raises:
        EigenError: complex values among the lowest (not a set of vibration modes), or
            a basis vector without mass.
    """
    import scipy.linalg as linalg

    mass = 0.5 * (mass + mass.T)
    if cholesky(mass) is None:
        raise EigenError("a mode without mass among the lowest")
    asymmetry = np.abs(stiffness - stiffness.T).max() / max(np.abs(stiffness).max(),
                                                            np.finfo(float).tiny)
    if asymmetry <= SYMMETRIC:
        omega2, y = linalg.eigh(0.5 * (stiffness + stiffness.T), mass)
        return omega2[:count], y[:, :count]
    values, y = linalg.eig(stiffness, mass)
    order = np.argsort(values.real)[:count]
    values, y = values[order], y[:, order]
    if np.any(np.abs(values.imag) > COMPLEX * np.abs(values)):
        raise EigenError("complex eigenvalues among the lowest (not a set of vibration "
                           "modes)")
    y = y.real
    return values.real, y / np.sqrt(np.einsum("ik,ik->k", y, mass @ y))


def lowest_arpack_dense(K: np.ndarray, M: np.ndarray, count: int
                        ) -> tuple[np.ndarray, np.ndarray]:
    """:func:`lowest_arpack` on the LU factors of a dense ``K`` ``(n, n)`` with mass ``M``.

    Raises:
        EigenError: ``K`` is singular to working precision, or as :func:`lowest_arpack`.
    """
    from scipy.linalg import lu_factor, lu_solve

    n = len(K)
    with np.errstate(all="ignore"):
        lu = lu_factor(K, check_finite=False)
    pivots = np.abs(np.diag(lu[0]))
    if not np.all(np.isfinite(lu[0])) or np.any(
            pivots <= n * np.finfo(float).eps * np.abs(K).max()):
        raise EigenError("the tangent is singular (a mechanism or a rigid-body mode)")
    symmetric = np.abs(K - K.T).max() <= SYMMETRIC * np.abs(K).max()
    return lowest_arpack(lambda v: lu_solve(lu, M @ v), lambda Z: M @ Z,
                         lambda Z: Z.T @ K @ Z, n, count,
                         inverse_times=(lambda v: lu_solve(lu, v)) if symmetric else None)


# --- LAPACK -----------------------------------------------------------------------------
def lowest_dense(K: np.ndarray, M: np.ndarray, count: int, vectors: bool
                 ) -> tuple[np.ndarray, np.ndarray | None]:
    """The ``count`` lowest ``omega^2`` of ``K phi = omega^2 M phi`` ``(count,)``, with
    mass-normalized shapes ``(n, count)`` when ``vectors`` (module docstring); ``M``
    symmetric positive definite."""
    asymmetry = np.abs(K - K.T).max() / max(np.abs(K).max(), np.finfo(float).tiny)
    if asymmetry <= SYMMETRIC:
        K = 0.5 * (K + K.T)
        factor = cholesky(K)
        if factor is not None and well_posed(factor, K):
            reduced, inverse = reduced_by(factor, M)
            mu, y = np.linalg.eigh(reduced)
            mu, y = mu[::-1][:count], y[:, ::-1][:, :count]
            resolved = mu > ROUNDING_MARGIN * len(K) * np.finfo(float).eps * mu[0]
            if not np.all(resolved):   # modes too stiff for this reduction: see below
                return _stiffest(K, M, mu[resolved], inverse.T @ y[:, resolved], count,
                                 vectors)
            # phi = L^-T y has phi^T K phi = 1 and phi^T M phi = mu
            return 1.0 / mu, (inverse.T @ y / np.sqrt(mu) if vectors else None)
    else:
        try:  # K regular: the eigenvalues mu = 1/omega^2 of K^-1 M, as above
            inverse = np.linalg.solve(K, M)
        except np.linalg.LinAlgError:
            inverse = None
        if inverse is not None and np.all(np.isfinite(inverse)):
            if not vectors:
                return np.sort((1.0 / np.linalg.eigvals(inverse)).real)[:count], None
            mu, right = np.linalg.eig(inverse)
            return _lowest(1.0 / mu, right, M, count)
    import scipy.linalg as linalg  # only here: its import alone costs 0.2 s

    # all eigenvalues: the largest sets the rounding level of the lowest
    if asymmetry <= SYMMETRIC:
        if not vectors:
            return _rounded_to_zero(linalg.eigh(K, M, eigvals_only=True), len(K))[:count], None
        omega2, shapes = linalg.eigh(K, M)
        return _rounded_to_zero(omega2, len(K))[:count], shapes[:, :count]
    if not vectors:
        return np.sort(_rounded_to_zero(linalg.eigvals(K, M).real, len(K)))[:count], None
    values, right = linalg.eig(K, M)
    omega2, shapes = _lowest(values, right, M, count)
    return _rounded_to_zero(omega2, len(K), linalg.eigvals(K, M).real), shapes


def _stiffest(K: np.ndarray, M: np.ndarray, mu: np.ndarray, phi: np.ndarray, count: int,
              vectors: bool) -> tuple[np.ndarray, np.ndarray | None]:
    """The ``count`` lowest modes when the highest lie below the rounding of ``mu =
    1/omega^2`` (stiff axial modes of thin leaves, ``omega`` ratios beyond 1e7): the
    resolved ones ``mu`` (shapes ``phi = L^-T y``) as they are, the rest from SciPy's
    generalized solver, whose rounding scales with the highest frequency instead; never
    a stable structure's mode turned into a negative ``omega^2`` by rounding."""
    import scipy.linalg as linalg

    omega2, shapes = linalg.eigh(K, M)
    kept = len(mu)
    values = np.concatenate([1.0 / mu, omega2[kept:count]])
    if not vectors:
        return values, None
    return values, np.hstack([phi / np.sqrt(mu), shapes[:, kept:count]])


def _rounded_to_zero(omega2: np.ndarray, n: int, spectrum: np.ndarray | None = None
                     ) -> np.ndarray:
    """``omega2`` with the values within the rounding of a generalized eigensolver of size
    ``n`` (``ROUNDING_MARGIN n eps`` times the largest magnitude of ``spectrum``, by
    default ``omega2`` itself) set to exactly 0: a rigid-body mode, not a tiny
    unstable or stable one."""
    largest = np.abs(omega2 if spectrum is None else spectrum).max(initial=0.0)
    zero = np.abs(omega2) <= ROUNDING_MARGIN * n * np.finfo(float).eps * largest
    return np.where(zero, 0.0, omega2)


def _lowest(values: np.ndarray, right: np.ndarray, M: np.ndarray, count: int
            ) -> tuple[np.ndarray, np.ndarray]:
    """The ``count`` eigenpairs of lowest real ``omega^2``, shapes mass-normalized."""
    order = np.argsort(values.real)[:count]
    shapes = right.real[:, order]
    return values.real[order], shapes / np.sqrt(np.einsum("ik,ik->k", shapes, M @ shapes))


def well_posed(factor: np.ndarray, A: np.ndarray) -> bool:
    """Whether the Cholesky factor ``L`` of ``A`` shows ``A`` regular to working precision:
    no pivot ``L_ii^2`` collapsed to rounding of its diagonal ``A_ii``. A singular ``A``
    (a rigid-body mode) can factor with a pivot of rounding size, by chance of the BLAS
    kernels; its inverse would then swamp every other eigenvalue."""
    pivots = np.diag(factor) ** 2
    return bool(np.all(pivots > len(A) * np.finfo(float).eps * np.abs(np.diag(A))))


def cholesky(A: np.ndarray) -> np.ndarray | None:
    """The lower Cholesky factor of a symmetric ``A``, or ``None`` when ``A`` is not
    positive definite."""
    try:
        return np.linalg.cholesky(A)
    except np.linalg.LinAlgError:
        return None


def reduced_by(factor: np.ndarray, A: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``L^-1 A L^-T`` (symmetrized) for a Cholesky factor ``L`` and a symmetric ``A``,
    and ``L^-1``, which turns the reduced problem's vectors back (``L^-T y``)."""
    inverse = np.linalg.inv(factor)
    reduced = inverse @ A @ inverse.T
    return 0.5 * (reduced + reduced.T), inverse
