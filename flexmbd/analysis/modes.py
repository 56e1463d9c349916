"""Eigenfrequencies and mode shapes, buckling load factors and compliance (THEORY 9).

All three are eigen- or linear problems of one
:class:`~flexmbd.analysis.linearization.Linearization` over the dynamic degrees of freedom
``d`` (prescribed entries held):

* vibration: ``(K0 + N0 + G0) phi = omega^2 M0 phi``, shapes mass-normalized
  (``phi^T M0 phi = 1``); the gyroscopic ``C0`` and the damping are left out, as in
  SPACAR;
* buckling: ``(K0 + lambda G0) phi = 0``, the load factors ``lambda`` of the loads that
  set the stresses of ``G0``;
* compliance at chosen coordinates: ``F_sel (K0 + G0)^-1 F_sel^T`` with ``F_sel`` the rows
  of ``F_q`` of those coordinates (SPACAR Light's definition).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from threadpoolctl import threadpool_limits

from .. import checks
from ..elements.base import SPATIAL_ROTATIONAL
from ..engine import workspace_of
from ..engine.diagnosis import MASS_ADVICE
from ..errors import ArgumentError, SingularConfigurationError
from ..orientation import rotation_matrix
from ..progress import progress_bar
from ..results import KinematicResult
from ..summary import dataclass_repr
from .linearization import Linearization, linearize

__all__ = ["Buckling", "Modes", "ModesAlong", "buckling", "compliance", "modes_along",
           "node_compliance",
           "vibration_modes"]

#: relative asymmetry below which a stiffness block counts as symmetric (rounding of the
#: products that make it); above it, as along a motion with N0, the general solver runs
SYMMETRIC = 1e-9

#: a generalized eigensolver's eigenvalues carry rounding of about ``n eps`` times the
#: largest; this many times that is taken as zero (a rigid-body mode), so that rounding
#: never reads as an unstable direction whatever the CPU's BLAS kernels
ROUNDING_MARGIN = 100.0

#: a few lowest modes of a model this large take ARPACK's iterations on the factored
#: stiffness (O(n^2) per step) instead of the whole spectrum (O(n^3)): at most this share
#: of the degrees of freedom, from this many on
FEW_MODES_SHARE, FEW_MODES_FROM = 0.25, 60
#: the extra modes ARPACK iterates for, so that a multiple eigenvalue is found whole
FEW_MODES_EXTRA = 4


@dataclass(frozen=True, eq=False)
class Modes:
    """Vibration modes at one state.

    Attributes:
        linearization: the state and its matrices.
        omega2: eigenvalues ``omega^2`` [rad^2/s^2] ``(k,)``, ascending.
        frequencies: ``sign(omega^2) sqrt(|omega^2|) / (2 pi)`` [Hz] ``(k,)``: a negative
            value marks an unstable direction (its growth rate in 1/s over ``2 pi``).
        shapes: mass-normalized shapes over the dynamic entries of ``q`` ``(nd, k)``.
        motion: the shapes as coordinate motions ``F_q phi`` ``(nx, k)`` [m, rad]; on a
            spatial rotational node the global rotations ``dtheta`` in the entries of
            ``lam1..lam3`` (:attr:`~flexmbd.Linearization.motion_transfer`).
    """

    __repr__ = dataclass_repr

    linearization: Linearization
    omega2: np.ndarray
    frequencies: np.ndarray
    shapes: np.ndarray
    motion: np.ndarray


@dataclass(frozen=True, eq=False)
class Buckling:
    """Buckling load factors of the loads of a state.

    Attributes:
        linearization: the loaded state.
        factors: load factors ``lambda`` ``(k,)``, smallest magnitude first; the state's
            loads times ``lambda`` make ``K0 + lambda G0`` singular.
        shapes: buckled shapes over the dynamic entries of ``q`` ``(nd, k)``, largest entry 1.
        motion: the shapes as coordinate motions ``(nx, k)`` (rotations as in
            :class:`Modes`).
    """

    __repr__ = dataclass_repr

    linearization: Linearization
    factors: np.ndarray
    shapes: np.ndarray
    motion: np.ndarray


def vibration_modes(linearization: Linearization, count: int | None = None) -> Modes:
    """The ``count`` lowest vibration modes (all by default) of a linearized state: a
    :class:`Modes` with ``frequencies`` ``(k,)`` [Hz] and ``shapes`` ``(nd, k)`` over the
    ``nd`` dynamic degrees of freedom.

    Raises:
        SingularConfigurationError: the reduced mass matrix is not positive definite (a
            degree of freedom without mass).

    Examples:
        A rod pendulum's frequency, ``sqrt(3 g / (2 L)) / (2 pi)``:

        >>> import numpy as np
        >>> import flexmbd as fm
        >>> pendulum = (fm.ModelBuilder("pendulum").add_node(1, 0, 0).add_node(3, 0, -1)
        ...             .add_rigid_beam(1, 1, 2, 3).set_mass(1, 1.0).fix(1)
        ...             .dynamic_coordinate(2).set_gravity(0, -9.81).build())
        >>> modes = fm.vibration_modes(fm.linearize(pendulum), 1)
        >>> print(f"{modes.frequencies[0]:.4f} Hz")
        0.6105 Hz
    """
    lin = linearization
    K, M = lin.block("K"), lin.block("M0")
    count = _count(count, len(K))
    if not len(K):
        empty = np.zeros(0)
        return Modes(lin, empty, empty, np.zeros((0, 0)), np.zeros((len(lin.x), 0)))
    omega2, shapes = _eigen(lin, K, M, count, vectors=True)
    assert shapes is not None  # asked for: vectors=True
    frequencies = np.sign(omega2) * np.sqrt(np.abs(omega2)) / (2 * np.pi)
    return Modes(lin, omega2, frequencies, shapes, lin.motion_transfer[:, lin.dynamic] @ shapes)


def _eigen(lin: Linearization, K: np.ndarray, M: np.ndarray, count: int, vectors: bool
           ) -> tuple[np.ndarray, np.ndarray | None]:
    """The ``count`` lowest ``omega^2`` of ``K phi = omega^2 M phi``, with mass-normalized
    shapes ``phi`` when ``vectors``.

    A symmetric positive definite ``K`` (a structure at rest, a stable equilibrium) gives
    the largest ``mu = 1/omega^2`` of ``L^-1 M L^-T`` with ``K = L L^T``: rounding then
    scales with the lowest frequencies, where reducing by ``M`` (the generalized
    solvers) scales it with the highest, the stiff axial ones of flexures (1e-5 of a
    200-beam column's first frequency). An unsymmetric ``K`` (``N0`` and ``C0`` in
    motion) gives ``mu`` of ``K^-1 M`` likewise. Only a symmetric indefinite ``K``
    (mechanisms, unstable states) or a singular one takes SciPy's generalized solvers."""
    _check_mass(lin, M)
    asymmetry = np.abs(K - K.T).max() / max(np.abs(K).max(), np.finfo(float).tiny)
    few = len(K) >= FEW_MODES_FROM and count <= FEW_MODES_SHARE * len(K)
    if asymmetry <= SYMMETRIC:
        K = 0.5 * (K + K.T)
        factor = _cholesky(K)
        if factor is not None and _well_posed(factor, K) and few:
            return _few_symmetric(factor, M, count, vectors)
        if factor is not None and _well_posed(factor, K):
            reduced, inverse = _reduced(factor, M)
            mu, y = np.linalg.eigh(reduced)
            mu, y = mu[::-1][:count], y[:, ::-1][:, :count]
            resolved = mu > ROUNDING_MARGIN * len(K) * np.finfo(float).eps * mu[0]
            if not np.all(resolved):   # modes too stiff for this reduction: see below
                return _stiffest(K, M, mu[resolved], inverse.T @ y[:, resolved], count,
                                 vectors)
            # phi = L^-T y has phi^T K phi = 1 and phi^T M phi = mu
            return 1.0 / mu, (inverse.T @ y / np.sqrt(mu) if vectors else None)
    else:
        if few:
            found = _few_unsymmetric(K, M, count)
            if found is not None:
                return found if vectors else (found[0], None)
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


def _start(n: int) -> np.ndarray:
    """ARPACK's start vector: fixed, so runs repeat, and with every mode in it (a vector
    of ones misses the antisymmetric modes of a symmetric structure)."""
    return np.random.default_rng(0).standard_normal(n)


def _few_symmetric(factor: np.ndarray, M: np.ndarray, count: int, vectors: bool
                   ) -> tuple[np.ndarray, np.ndarray | None]:
    """The ``count`` largest ``mu = 1/omega^2`` of ``L^-1 M L^-T`` by Lanczos (ARPACK's
    ``eigsh``), the operator applied with two triangular solves: the lowest modes of a
    symmetric positive definite ``K = L L^T`` to machine precision."""
    from scipy.linalg import solve_triangular
    from scipy.sparse.linalg import LinearOperator, eigsh

    n = len(M)

    def apply(v):
        return solve_triangular(factor, M @ solve_triangular(factor, v, trans="T",
                                                             lower=True), lower=True)

    k = min(count + FEW_MODES_EXTRA, n - 1)
    mu, y = eigsh(LinearOperator((n, n), matvec=apply, dtype=float), k=k, which="LA",
                  tol=0.0, v0=_start(n))
    order = np.argsort(mu)[::-1][:count]
    mu, y = mu[order], y[:, order]
    if not vectors:
        return 1.0 / mu, None
    return 1.0 / mu, solve_triangular(factor, y, trans="T", lower=True) / np.sqrt(mu)


def _few_unsymmetric(K: np.ndarray, M: np.ndarray, count: int
                     ) -> tuple[np.ndarray, np.ndarray] | None:
    """The ``count`` largest ``mu = 1/omega^2`` of ``K^-1 M`` by Arnoldi (ARPACK's
    ``eigs``) on the LU factors of ``K``; None for a singular ``K``."""
    from scipy.linalg import lu_factor, lu_solve
    from scipy.sparse.linalg import LinearOperator, eigs

    n = len(K)
    with np.errstate(all="ignore"):
        lu = lu_factor(K, check_finite=False)
    if not np.all(np.isfinite(lu[0])) or np.any(np.abs(np.diag(lu[0])) <= n * np.finfo(
            float).eps * np.abs(K).max()):
        return None
    k = min(count + FEW_MODES_EXTRA, n - 2)
    mu, right = eigs(LinearOperator((n, n), matvec=lambda v: lu_solve(lu, M @ v),
                                    dtype=float), k=k, which="LM", tol=0.0, v0=_start(n))
    return _lowest(1.0 / mu, right, M, count)


def _rounded_to_zero(omega2: np.ndarray, n: int, spectrum: np.ndarray | None = None
                     ) -> np.ndarray:
    """``omega2`` with the values within the rounding of a generalized eigensolver of size
    ``n`` (``ROUNDING_MARGIN n eps`` times the largest magnitude of ``spectrum``, by
    default ``omega2`` itself) set to exactly 0: a rigid-body mode, not a tiny
    unstable or stable one."""
    largest = np.abs(omega2 if spectrum is None else spectrum).max(initial=0.0)
    zero = np.abs(omega2) <= ROUNDING_MARGIN * n * np.finfo(float).eps * largest
    return np.where(zero, 0.0, omega2)


def _well_posed(factor: np.ndarray, A: np.ndarray) -> bool:
    """Whether the Cholesky factor ``L`` of ``A`` shows ``A`` regular to working precision:
    no pivot ``L_ii^2`` collapsed to rounding of its diagonal ``A_ii``. A singular ``A``
    (a rigid-body mode) can factor with a pivot of rounding size, by chance of the BLAS
    kernels; its inverse would then swamp every other eigenvalue."""
    pivots = np.diag(factor) ** 2
    return bool(np.all(pivots > len(A) * np.finfo(float).eps * np.abs(np.diag(A))))


def _lowest(values: np.ndarray, right: np.ndarray, M: np.ndarray, count: int
            ) -> tuple[np.ndarray, np.ndarray]:
    """The ``count`` eigenpairs of lowest real ``omega^2``, shapes mass-normalized."""
    order = np.argsort(values.real)[:count]
    shapes = right.real[:, order]
    return values.real[order], shapes / np.sqrt(np.einsum("ik,ij,jk->k", shapes, M, shapes))


def _check_mass(lin: Linearization, M: np.ndarray) -> None:
    """Raise, naming the degree of freedom, when ``M0`` is not positive definite."""
    if _cholesky(M) is None:
        weak = int(lin.dynamic[np.argmin(np.diag(M))])
        raise SingularConfigurationError(
            f"the reduced mass matrix M0 is not positive definite: "
            f"{lin.model.describe_q(weak)} moves without mass; {MASS_ADVICE}")


def _cholesky(A: np.ndarray) -> np.ndarray | None:
    """The lower Cholesky factor of a symmetric ``A``, or ``None`` when ``A`` is not
    positive definite."""
    try:
        return np.linalg.cholesky(A)
    except np.linalg.LinAlgError:
        return None


def _reduced(factor: np.ndarray, A: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``L^-1 A L^-T`` (symmetrized) for a Cholesky factor ``L`` and a symmetric ``A``,
    and ``L^-1``, which turns the reduced problem's vectors back (``L^-T y``)."""
    inverse = np.linalg.inv(factor)
    reduced = inverse @ A @ inverse.T
    return 0.5 * (reduced + reduced.T), inverse


@dataclass(frozen=True, eq=False)
class ModesAlong:
    """Vibration frequencies along a motion, one row per output time.

    Attributes:
        result: the motion.
        t: its times [s] ``(nt,)``.
        frequencies: ``(nt, k)`` [Hz], ascending in each row (negative: unstable, see
            :class:`Modes`).
        omega2: ``(nt, k)`` [rad^2/s^2].
    """

    __repr__ = dataclass_repr

    result: KinematicResult
    t: np.ndarray
    frequencies: np.ndarray
    omega2: np.ndarray

    def columns(self) -> dict[str, np.ndarray]:
        """The columns ``t`` [s] and ``f1`` to ``fk`` [Hz], for a table or a result file."""
        return {"t": self.t, **{f"f{k + 1}": self.frequencies[:, k]
                                for k in range(self.frequencies.shape[1])}}


@checks.keyword_only("progress")
def modes_along(result: KinematicResult, count: int = 6, *, progress: bool | None = None
                ) -> ModesAlong:
    """The ``count`` lowest vibration frequencies at every row of a motion (a simulation,
    an inverse-dynamics or a kinematic result): the linearization about each state
    ``(x, qdot, qddot)`` with its inertia terms ``N0`` (SPACAR's linearization along a
    trajectory). Returns a :class:`ModesAlong` with ``frequencies`` ``(nt, count)`` [Hz]."""
    if not isinstance(result, KinematicResult):
        raise ArgumentError("result", f"must be a flexmbd result (simulate, "
                                      f"kinematic_analysis, ...), got {type(result).__name__}")
    model = result.model
    if result.xd is None or result.xdd is None or result.ed is None or result.edd is None \
            or result.e is None:
        raise ArgumentError("result", "needs the rates of the motion: simulate(..., "
                                      "outputs='all')")
    count = _count(count, int(np.sum(~np.asarray(model.q_is_input))))
    nxm = model.independent_coordinates
    emd = model.independent_deformations
    engine = workspace_of(model)
    nt = len(result.t)
    omega2 = np.full((nt, count), np.nan)
    # many small problems: BLAS threads would cost more in hand-over than they gain
    with progress_bar(result.t, "modes", progress) as advance, threadpool_limits(1, "blas"):
        e, xd, xdd, ed, edd = result.e, result.xd, result.xdd, result.ed, result.edd  # there
        for k in range(nt):
            qd = np.concatenate([xd[k, nxm], ed[k, emd]])
            qdd = np.concatenate([xdd[k, nxm], edd[k, emd]])
            lin = linearize(model, result.x[k], qd, qdd, workspace=engine, e=e[k])
            omega2[k] = _eigen(lin, lin.block("K"), lin.block("M0"), count, vectors=False)[0]
            if advance is not None:
                advance(result.t[k])
    frequencies = np.sign(omega2) * np.sqrt(np.abs(omega2)) / (2 * np.pi)
    return ModesAlong(result, result.t.copy(), frequencies, omega2)


def buckling(linearization: Linearization, count: int | None = None) -> Buckling:
    """Load factors ``lambda`` with ``(K0 + lambda G0) phi = 0`` (``eig(-K0, G0)``): the
    multiples of the state's loads at which the structure buckles: a :class:`Buckling`
    with ``count`` factors ``(k,)`` [-], ascending, and their shapes.

    Raises:
        ArgumentError: the state has no geometric stiffness (no loads, no stresses).

    Examples:
        The cantilever pressed by 1 N along its axis buckles at about ``pi^2 EI /
        (4 L^2) = 4.93`` times that (four beams: 1.3 % above):

        >>> import flexmbd as fm
        >>> b = fm.ModelBuilder("cantilever")   # 1 m, four beams, EI = 2 N m^2, clamped at 1
        >>> for k in range(5):
        ...     _ = b.add_node(2 * k + 1, 0.25 * k, 0.0)
        >>> for k in range(4):
        ...     _ = (b.add_beam(k + 1, 2 * k + 1, 2 * k + 2, 2 * k + 3, 2 * k + 4)
        ...          .dynamic_deformation(k + 1).set_mass(k + 1, 0.5)
        ...          .set_stiffness(k + 1, axial=1e6, bending=2.0))
        >>> column = b.fix(1).fix(2).build()
        >>> statics = fm.static_equilibrium(column, loads={"x9.1": -1.0})
        >>> print(f"{fm.buckling(statics.linearization(), 1).factors[0]:.2f}")
        5.00
    """
    lin = linearization
    K, G = lin.block("K0"), lin.block("G0")
    if not len(K) or not np.any(G):
        raise ArgumentError("loads", "the state carries no stresses, so no load factor makes "
                                     "it buckle: apply loads (XF, gravity, loads=...)")
    # 1/lambda are the eigenvalues of (G, K): finite for every mode even where G0 vanishes
    K = 0.5 * (K + K.T)
    factor = _cholesky(K)
    # a stable state: a symmetric problem L^-1 G L^-T y = y / lambda
    if factor is not None and _well_posed(factor, K):
        reduced, inverse_factor = _reduced(factor, 0.5 * (G + G.T))
        inverse, y = np.linalg.eigh(reduced)
        vectors = inverse_factor.T @ y
    else:
        import scipy.linalg as linalg  # only here: its import alone costs 0.2 s

        inverse, vectors = linalg.eig(G, K)
        inverse, vectors = inverse.real, vectors.real
    keep = np.abs(inverse) > 1e-12 * np.abs(inverse).max()
    factors = -1.0 / inverse[keep]
    order = np.argsort(np.abs(factors))[:_count(count, int(keep.sum()))]
    shapes = vectors[:, keep][:, order]
    shapes = shapes / shapes[np.abs(shapes).argmax(axis=0), np.arange(shapes.shape[1])]
    return Buckling(lin, factors[order], shapes, lin.motion_transfer[:, lin.dynamic] @ shapes)


def compliance(linearization: Linearization, labels) -> np.ndarray:
    """The compliance ``F_sel (K0 + G0)^-1 F_sel^T`` ``(k, k)`` [m/N, rad/(N m), ...] seen at
    the coordinates ``labels`` (``["x5.1", "x5.2"]``): entry ``(i, j)`` is the static
    displacement of coordinate ``i`` per unit load on coordinate ``j``. It is symmetric
    but under a global moment on a spatial rotational node, whose load stiffness is not
    (the moment keeps its axis while the node turns). On a spatial
    rotational node the labels of ``lam1..lam3`` stand for its global rotations about x,
    y and z and the moments about them (``T = diag(I, 2 E)``, the spatial theory,
    section 6). The prescribed entries of ``q`` are held.

    Raises:
        SingularConfigurationError: ``K0 + G0`` is singular (a mechanism, or buckling).
    """
    return _compliance(linearization, labels, held=True)


def _compliance(lin: Linearization, labels, held: bool) -> np.ndarray:
    """``T F_sel K^-1 F_sel^T T^T`` over the dynamic entries of ``q`` (``held``) or all."""
    columns = lin.dynamic if held else np.arange(lin.model.n_dof)
    F = lin.motion_transfer[np.ix_(lin.rows_of(labels), columns)]
    K = (lin.K0 + lin.G0)[np.ix_(columns, columns)]
    symmetric = 0.5 * (K + K.T)
    if not held:   # a free drive that nothing resists: name it (its pivot may round > 0)
        scale = np.abs(K).max(initial=0.0)
        for j in np.flatnonzero(lin.model.q_is_input):
            if np.abs(K[j]).max() <= 1e-12 * scale:
                raise SingularConfigurationError(
                    f"with the drives free, the drive of {lin.model.q_labels[j]} has no "
                    f"stiffness: a drive without stiffness is a mechanism (its compliance "
                    f"is infinite)")
    factor = _cholesky(symmetric)
    if factor is None or not _well_posed(factor, symmetric):
        what = ("the dynamic degrees of freedom include a mechanism (no stiffness) or the "
                "loads buckle the structure" if held else
                "with the drives free, a drive without stiffness is a mechanism (its "
                "compliance is infinite), or the loads buckle the structure")
        raise SingularConfigurationError(f"the stiffness K0 + G0 is not positive definite: "
                                         f"{what}")
    if np.array_equal(K, K.T):
        half = np.linalg.solve(factor, F.T)  # L^-1 F^T: F K^-1 F^T = half^T half
        return half.T @ half
    # a global moment's load stiffness makes K unsymmetric (the moment keeps its axis while
    # the node turns): the response to a small load is K^-1 of that K, not of its
    # symmetric part (which would differ by about 1e-6 of a loaded flexure's compliance)
    return F @ np.linalg.solve(K, F.T)


def node_compliance(linearization: Linearization, node: int, rotational: int | None = None,
                    *, frame: Literal["global", "body"] = "global",
                    drive: Literal["held", "free"] = "held") -> np.ndarray:
    """The compliance of a node (and its rotational node): its displacement and rotation
    per unit force and moment on it, ``(6, 6)`` in space (``(3, 3)`` in the plane; the
    translations only without ``rotational``) [m/N, m/(N m), rad/(N m)], FLEXURES 6.
    ``1 / C[i, i]`` is the support stiffness in direction ``i`` with the node free
    otherwise; ``inv(C)`` the stiffness with its other motions held.

    Args:
        node: the translational node.
        rotational: its rotational node, for rotations and moments.
        frame: ``"global"`` axes, or ``"body"``: the axes of ``rotational`` as it has turned
            (``C_body = diag(R^T, R^T) C diag(R, R)``).
        drive: ``"held"``: the prescribed inputs stay (SPACAR Light's static mode);
            ``"free"``: they become degrees of freedom, loaded by their drive force as a
            dead load (``C_free - C_held`` is positive semidefinite).

    Raises:
        SingularConfigurationError: a mechanism, buckling, or a free drive without
            stiffness (infinite compliance).

    Examples:
        The cantilever's tip: ``L^3/(3 EI)``, ``L^2/(2 EI)`` and ``L/EI`` in its y and
        rotation entries:

        >>> import flexmbd as fm
        >>> b = fm.ModelBuilder("cantilever")   # 1 m, four beams, EI = 2 N m^2, clamped at 1
        >>> for k in range(5):
        ...     _ = b.add_node(2 * k + 1, 0.25 * k, 0.0)
        >>> for k in range(4):
        ...     _ = (b.add_beam(k + 1, 2 * k + 1, 2 * k + 2, 2 * k + 3, 2 * k + 4)
        ...          .dynamic_deformation(k + 1).set_mass(k + 1, 0.5)
        ...          .set_stiffness(k + 1, axial=1e6, bending=2.0))
        >>> column = b.fix(1).fix(2).build()
        >>> C = fm.node_compliance(fm.linearize(column), 9, 10)
        >>> print(f"{C[1, 1]:.4f} {C[1, 2]:.4f} {C[2, 2]:.4f}")
        0.1667 0.2500 0.5000
    """
    labels = compliance_labels(linearization.model, node, rotational, frame, drive)
    C = _compliance(linearization, labels, held=drive == "held")
    return in_frame(linearization.model, linearization.x, rotational, C, frame)


def compliance_labels(model, node: int, rotational: int | None, frame: str, drive: str
                      ) -> list[str]:
    """The coordinate labels of :func:`node_compliance` (``node``'s translations, then
    ``rotational``'s rotations), its arguments checked."""
    if frame not in ("global", "body"):
        raise ArgumentError("frame", f"must be 'global' or 'body', got {frame!r}")
    if drive not in ("held", "free"):
        raise ArgumentError("drive", f"must be 'held' or 'free', got {drive!r}")
    for number, kind in ((node, "translational"), (rotational, "rotational")):
        if number is not None and (number not in model.nodes or
                                   kind not in model.nodes[number].kind):
            raise ArgumentError("node" if kind == "translational" else "rotational",
                                f"{number} is not a {kind} node of the model")
    if frame == "body" and rotational is None:
        raise ArgumentError("frame", "the body frame is a rotational node's: give rotational")
    width = len(model.nodes[node].coordinates)
    labels = [f"x{node}.{k}" for k in range(1, width + 1)]
    if rotational is not None:
        spatial = model.nodes[rotational].kind == SPATIAL_ROTATIONAL
        labels += [f"x{rotational}.{k}" for k in ((2, 3, 4) if spatial else (1,))]
    return labels


def in_frame(model, x: np.ndarray, rotational: int | None, C: np.ndarray, frame: str
             ) -> np.ndarray:
    """A node's compliance ``C`` (global axes) in ``frame``: unchanged for ``"global"``,
    ``diag(R^T, R^T) C diag(R, R)`` with ``R`` the rotation of ``rotational`` at ``x`` for
    ``"body"``."""
    if frame != "body" or rotational is None:
        return C
    at = list(model.nodes[rotational].coordinates)
    lam = x[at]
    if model.nodes[rotational].kind == SPATIAL_ROTATIONAL:
        R = rotation_matrix(lam)
        turn = np.block([[R, np.zeros((3, 3))], [np.zeros((3, 3)), R]])
    else:
        c, s = np.cos(lam[0]), np.sin(lam[0])
        turn = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    return turn.T @ C @ turn


def _count(count: int | None, available: int) -> int:
    if count is None:
        return available
    if isinstance(count, bool) or not isinstance(count, (int, np.integer)) or count < 1:
        raise ArgumentError("count", f"must be a positive whole number, got {count!r}")
    return min(int(count), available)
