"""Saying in words what a singular or rank-deficient ``D_c`` leaves free (THEORY 3).

The right null space of ``D_c`` holds the dependent-coordinate motions that leave
every constrained deformation unchanged; the left null space holds combinations
of constraint equations that are redundant. Both are named by their largest
entries, with angles scaled by the model size so that the words do not depend on
units.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..errors import FlexmbdError
from ..model import Model


def _largest(vector: np.ndarray, share: float = 0.1) -> np.ndarray:
    """Indices of the entries of at least ``share`` of the largest, largest first."""
    a = np.abs(vector)
    chosen = np.flatnonzero(a >= share * a.max())
    return chosen[np.argsort(-a[chosen], kind="stable")]


def _names(describe, indices, shown: int = 8) -> str:
    """The first ``shown`` of ``indices`` in words, and how many more there are."""
    names = ", ".join(describe(int(i)) for i in indices[:shown])
    return names + (f" and {len(indices) - shown} more" if len(indices) > shown else "")


def weakest_direction(model: Model, D_c: np.ndarray) -> str:
    """Name the coordinates and deformations of the smallest singular value of ``D_c``
    ``(nr, nr)``."""
    if not np.all(np.isfinite(D_c)):
        return "the configuration is not finite"
    scaled = D_c * model.coordinate_scale[model.dependent]
    norms = np.linalg.norm(scaled, axis=1, keepdims=True)
    u, _, vt = np.linalg.svd(scaled / np.maximum(norms, 1e-300))
    constraints = _names(model.describe_deformation, model.constrained[_largest(u[:, -1])])
    coordinates = _names(model.describe_coordinate, model.dependent[_largest(vt[-1])])
    return f"the constraints {constraints} no longer determine {coordinates}"


class RankDiagnosis(NamedTuple):
    """What a rank-deficient ``D_c`` leaves free, in words (``text``, ``""`` when it is
    regular) and as global indices of the coordinates and deformations involved."""

    text: str
    coordinates: np.ndarray
    deformations: np.ndarray


def diagnose_rank(model: Model, D_c: np.ndarray, rtol: float = 1e-10) -> RankDiagnosis:
    """Explain a rank-deficient or non-square ``D_c`` ``(nr, nc)``."""
    rows, cols = D_c.shape
    none = np.zeros(0, dtype=int)
    if rows == cols:  # the usual, regular case: an LU probe, else the singular values only
        if clearly_regular(D_c, rtol):
            return RankDiagnosis("", none, none)
        s = np.linalg.svd(D_c, compute_uv=False)
        if np.sum(s > rtol * (s[0] if s.size else 0.0)) == rows:
            return RankDiagnosis("", none, none)
    u, s, vt = np.linalg.svd(D_c)
    rank = int(np.sum(s > rtol * (s[0] if s.size else 0.0)))
    parts = [f"rank {rank} for {rows} equations in {cols} dependent coordinates"]
    free, redundant = vt[rank:], u[:, rank:]
    coordinates = np.asarray(model.dependent)[
        np.flatnonzero(np.abs(free).max(axis=0) > 1e-8)] if len(free) else none
    deformations = np.asarray(model.constrained)[
        np.flatnonzero(np.abs(redundant).max(axis=1) > 1e-8)] if redundant.shape[1] else none
    if len(coordinates):
        parts.append(f"the coordinates {_names(model.describe_coordinate, coordinates)} can "
                     f"move without changing any rigid or independent deformation")
    if len(deformations):
        parts.append(f"the equations of {_names(model.describe_deformation, deformations)} "
                     f"are linearly dependent")
    return RankDiagnosis("; ".join(parts), coordinates, deformations)


#: matrices of ``D_c`` from this many rows are factorised sparse (SciPy's SuperLU): a
#: chain of beams gives ``D_c`` a few dozen entries per row, where a dense factorisation
#: costs the cube of the rows (the inverse and complete QR of 1500 rows 1 s on one core);
#: below, the dense ones cost less than importing SciPy's sparse solvers (0.35 s)
SPARSE_FROM = 800


def factorised(A: np.ndarray):
    """A solver of the square ``A``: ``solve(b, transposed=False)`` for ``b`` ``(n,)`` or
    ``(n, k)``; ``None`` when ``A`` is exactly singular. Dense LU below
    :data:`SPARSE_FROM` rows, sparse from there."""
    if len(A) < SPARSE_FROM:  # small: the inverse, once, for the repeated solves
        try:
            with np.errstate(all="ignore"):
                inverse = np.linalg.inv(A)
        except np.linalg.LinAlgError:
            return None

        def solve_dense(b: np.ndarray, transposed: bool = False) -> np.ndarray:
            with np.errstate(all="ignore"):
                return (inverse.T if transposed else inverse) @ b
        return solve_dense
    from scipy.sparse import csc_matrix
    from scipy.sparse.linalg import splu

    try:
        lu = splu(csc_matrix(A))
    except RuntimeError:  # SuperLU's "Factor is exactly singular"
        return None

    def solve_sparse(b: np.ndarray, transposed: bool = False) -> np.ndarray:
        with np.errstate(all="ignore"):
            return lu.solve(np.asarray(b, dtype=float), trans="T" if transposed else "N")
    return solve_sparse


def clearly_regular(A: np.ndarray, rtol: float, solve=None) -> bool:
    """Whether the square ``A`` is regular far within ``rtol`` (its condition below
    ``0.1/rtol``), from one LU factorisation (a sixth of the SVD's cost; sparse for large
    ``A``, :func:`factorised`). Solved for three fixed random right-hand sides,
    ``||A|| ||x|| / ||b||`` is a lower bound of the condition that random vectors miss by
    more than ``1e3`` only with a probability of about ``(1e-3 sqrt(n))^3``; a singular
    ``A`` gives a zero pivot or ``x`` of the size of ``1/eps``. Below ``1e-3/rtol`` it is
    regular. Between, as in a long chain of beams, whose condition grows with the square
    of the beams, the power iteration of :func:`condition` on the same factorisation
    decides. ``solve``: ``A``'s :func:`factorised`, when the caller has it."""
    solve = solve or factorised(A)
    if solve is None:
        return False
    b = np.random.default_rng(0).standard_normal((len(A), 3))
    x = solve(b)
    size = np.abs(A).sum(axis=0).max()
    estimate = size * np.abs(x).sum(axis=0) / np.abs(b).sum(axis=0)
    if not np.all(np.isfinite(estimate)) or estimate.max() > 1e3 / rtol:
        return False
    return bool(estimate.max() < 1e-3 / rtol or condition(A, solve) < 0.1 / rtol)


def condition(A: np.ndarray, solve, iterations: int = 30) -> float:
    """The 2-norm condition of the square ``A`` from its :func:`factorised` ``solve``:
    ``||A||`` and ``||A^-1||`` by power iteration on ``A^T A`` and its inverse (two
    solves per iteration), each a lower bound that converges from below."""
    rng = np.random.default_rng(1)
    v, w = rng.standard_normal(len(A)), rng.standard_normal(len(A))
    largest = smallest = 0.0
    for _ in range(iterations):
        v = A.T @ (A @ v)
        largest = float(np.linalg.norm(v))
        v /= largest
        w = solve(solve(w, transposed=True))
        smallest = float(np.linalg.norm(w))
        if not np.isfinite(smallest) or smallest == 0.0:
            return np.inf
        w /= smallest
    return float(np.sqrt(largest * smallest))


def at_time(time: float | None) -> str:
    """``"at t = 0.5 s"``, or ``"in the given configuration"`` without a time."""
    return "in the given configuration" if time is None else f"at t = {time:.6g} s"


def singular_message(model: Model, D_c: np.ndarray, time: float | None, what: str,
                     integrated: bool = False) -> str:
    """The message of a singular ``D_c`` at ``time``, naming what no longer holds and the
    likely cause: for a motion prescribed by inputs a dead point or the end of the range of
    motion; for an integrated motion also a state that left the physical range."""
    if integrated:
        cause = ("the simulated motion reached a configuration where the constraints become "
                 "dependent: a dead point, the end of the range of motion, or an integration "
                 "that left the physical range; where consistent constraints only line up "
                 "(aligned parallelogram bars) the motion passes with smaller steps or "
                 "tighter tolerances, and with GeneralizedAlpha with Newton to convergence "
                 "(iterations=None, the default)")
    elif np.any(model.q_is_input):
        cause = ("the mechanism is at a dead point or at the end of its range of motion, "
                 "where the inputs cannot drive it further")
    else:
        cause = "the constraints do not determine the configuration there"
    return (f"singular configuration {at_time(time)}: {what}; {weakest_direction(model, D_c)}; "
            f"{cause}")


# --- mass --------------------------------------------------------------------------------
#: masses farther apart than this ratio cannot be resolved together in double precision
MASS_SPAN = 1e14


def mass_sources(model: Model) -> list[tuple[str, float]]:
    """``(what, mass)`` for every element [kg] and node [kg or kg m^2] that carries mass."""
    sources = [(f"element {number} ({model.elements[number].type.name})",
                props.mass_per_length * model.elements[number].reference[0])
               for number, props in model.element_properties.items() if props.mass_per_length]
    sources += [(f"node {node}", mass) for node, mass in model.nodal_masses.items() if mass]
    return sources


#: how to give a degree of freedom mass, by the builder's keywords and a file's
MASS_ADVICE = ("give the elements that move with it mass (set_mass(element, mass_per_length, "
               "section_inertia=...) or set_section; EM in a file; section inertia for a "
               "spatial beam's twist) or its nodes point masses or rotary inertia "
               "(add_point_mass, add_rotary_inertia; XM in a file)")

#: a reduced mass matrix better conditioned than this is no cause of a failed solve
REGULAR_MASS = 1e-12


def massless_message(engine, x: np.ndarray, time: float | None) -> tuple[str, bool]:
    """Why the accelerations could not be solved at the configuration ``x`` ``(nx,)``, and
    whether the reduced mass matrix of the dynamic degrees of freedom is singular there:
    no mass moving with some of them, a mass matrix that is not finite or not positive
    definite, or masses too far apart to be resolved. A regular one leaves the velocities
    or the loads (a motion that diverges)."""
    model = engine.model
    dynamic = np.flatnonzero(~np.asarray(model.q_is_input))
    where = at_time(time)
    try:
        reduced = _reduced_mass(engine, x)[np.ix_(dynamic, dynamic)]
    except FlexmbdError:  # e.g. D_c singular there too: the matrix is not known
        reduced = np.full((len(dynamic), len(dynamic)), np.nan)
    if not np.all(np.isfinite(reduced)):
        return (f"the mass matrix is not finite {where}: the masses or the configuration "
                f"overflow"), True
    diagonal = np.diag(reduced)
    empty = dynamic[diagonal <= 1e-14 * np.abs(diagonal).max(initial=0.0)]
    if len(empty):
        return (f"no mass moves with {_names(model.describe_q, empty)} {where}: "
                f"{MASS_ADVICE}"), True
    eigenvalues = np.linalg.eigvalsh(reduced)
    if not len(eigenvalues):  # nothing to accelerate: the failure is not the masses'
        return (f"the accelerations could not be solved {where}: the velocities or the "
                f"applied loads are out of range"), False
    smallest = float(eigenvalues[0])
    if smallest <= 0:
        return (f"the reduced mass matrix is not positive definite {where} (smallest "
                f"eigenvalue {smallest:.3g}): negative masses outweigh the others"), True
    sources = sorted(mass_sources(model), key=lambda s: abs(s[1]))
    heavy, light = sources[-1], next(s for s in sources if s[1] != 0)
    if abs(heavy[1]) > MASS_SPAN * abs(light[1]):
        return (f"the masses span {heavy[1]:.3g} ({heavy[0]}) to {light[1]:.3g} ({light[0]}), "
                f"more than double precision resolves together ({MASS_SPAN:.0e}); check "
                f"their units"), True
    if smallest > REGULAR_MASS * float(eigenvalues[-1]):
        return (f"the accelerations could not be solved {where}, though the reduced mass "
                f"matrix is regular there: the velocities or the applied loads are out of "
                f"range (the motion diverges; check the loads, or take smaller steps)"), False
    return (f"the reduced mass matrix of {_names(model.describe_q, dynamic)} is singular "
            f"{where}"), True


def mass_is_regular(engine, x: np.ndarray) -> bool:
    """Whether every degree of freedom moves mass at ``x`` ``(nx,)``: the banded
    saddle-point matrix of the mass and the constraints factorises, or else the reduced
    mass matrix of the dynamic entries does (its Cholesky factor, as vibration modes
    take it; the banded pivots are judged against the largest mass, so they may fail
    where masses span many decades)."""
    if engine.mass_regular(x):
        return True
    dynamic = np.flatnonzero(~np.asarray(engine.model.q_is_input))
    try:
        np.linalg.cholesky(_reduced_mass(engine, x)[np.ix_(dynamic, dynamic)])
    except (np.linalg.LinAlgError, FlexmbdError):
        return False
    return True


def _reduced_mass(engine, x: np.ndarray) -> np.ndarray:
    """``F_q^T M F_q`` ``(nq, nq)`` at ``x`` on ``engine`` (an :class:`~flexmbd.engine.Workspace`,
    given, not imported: the engine's errors are worded here)."""
    F_q = engine.transfer(x)
    return F_q.T @ engine.mass(x)[0] @ F_q


def negative_mass_problem(engine) -> tuple[str, list[int]] | None:
    """A negative point mass or rotary inertia (the correction of a rigid body lumped into
    point masses, ``J = i - m c (l - c)``, as SPACAR's own lumped rigid beam carries) is
    allowed while no motion of the mechanism has a negative kinetic energy: the reduced
    mass matrix ``F_q^T M F_q`` of the degrees of freedom, which moves only as the rigid
    deformations and the fixed coordinates allow, must be positive semidefinite at the
    reference configuration (element mass matrices only turn with their elements).
    Returns the problem in words, naming that motion, and the nodes whose negative
    masses take part in it, or ``None``."""
    model = engine.model
    negative = {node for node, mass in model.nodal_masses.items() if mass < 0}
    if not negative or not model.n_dof:
        return None
    x0 = np.asarray(model.x0, dtype=float)
    try:
        F_q = engine.transfer(x0)
    except FlexmbdError:  # the constraints' own problem is reported by its check
        return None
    values, vectors = np.linalg.eigh(F_q.T @ engine.mass(x0)[0] @ F_q)
    if values[0] >= -1e-12 * max(abs(values[-1]), 1e-300):
        return None
    motion = F_q @ vectors[:, 0]
    moving = np.flatnonzero(np.abs(motion) > 1e-6 * np.abs(motion).max())
    nodes = sorted(node for node in negative
                   if set(model.nodes[node].coordinates) & set(moving)) or sorted(negative)
    elements = sorted(number for number, element in model.elements.items()
                      if set(element.nodes) & set(nodes))
    theirs = [i for i in moving if any(i in model.nodes[n].coordinates for n in nodes)]
    return (f"the negative mass of node(s) {', '.join(map(str, nodes))} outweighs the mass of "
            f"element(s) {', '.join(map(str, elements)) or 'none'} there: the motion along "
            f"{_names(model.describe_q, _largest(vectors[:, 0]))}, which moves "
            f"{_names(model.describe_coordinate, theirs or moving)}, would have negative "
            f"kinetic energy (reduced mass matrix eigenvalue {values[0]:.3g} at the reference "
            f"configuration)", nodes)
