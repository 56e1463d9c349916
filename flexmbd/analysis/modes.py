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

import warnings
from dataclasses import dataclass
from typing import Literal

import numpy as np
from threadpoolctl import threadpool_limits

from .. import checks
from ..elements.base import SPATIAL_ROTATIONAL
from ..engine import workspace_of
from ..engine.diagnosis import MASS_ADVICE
from ..errors import (
    AnalysisWarning,
    ArgumentError,
    SingularConfigurationError,
    UnstressedError,
)
from ..model import Model
from ..orientation import rotation_matrix
from ..progress import progress_bar
from ..results import KinematicResult
from ..summary import dataclass_repr
from .banded import BandedTangent
from .eigen import (
    EigenError,
    EigenPath,
    arpack_pays,
    cholesky,
    lowest_arpack,
    lowest_arpack_dense,
    lowest_dense,
    reduced_by,
    size_reason,
    well_posed,
)
from .linearization import (
    Linearization,
    coordinate_motions,
    linearize,
    motion_rates,
    stiffness_products,
    turning_moments,
)
from .statics import StaticResult

#: the physical failures that leave a linearized analysis without a value at a state (a
#: singular tangent: a mechanism, a state past buckling; a state without stresses for
#: buckling): a table over many states records them as NaN with the reason
NO_VALUE = (SingularConfigurationError, UnstressedError)

#: omega^2 below minus this share of the largest |omega^2| is a growing mode, not rounding
UNSTABLE_ROUNDING = 1e-9

__all__ = ["Buckling", "Modes", "ModesAlong", "buckling", "compliance", "frequencies_of",
           "linearization_of", "modes_along", "node_compliance", "vibration_modes"]

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
        path: how they were found and why (:class:`~flexmbd.analysis.eigen.EigenPath`).
    """

    linearization: Linearization
    omega2: np.ndarray
    frequencies: np.ndarray
    shapes: np.ndarray
    motion: np.ndarray
    path: EigenPath

    @property
    def unstable(self) -> np.ndarray:
        """Positions of the modes that grow instead of vibrating (``omega^2 < 0`` beyond
        the rounding of the largest ``|omega^2|``): the state lies past a buckling point
        (or on a maximum of its potential energy). Their ``frequencies`` are negative."""
        scale = float(np.max(np.abs(self.omega2), initial=0.0))
        return np.flatnonzero(self.omega2 < -UNSTABLE_ROUNDING * scale)

    def __repr__(self) -> str:
        text = dataclass_repr(self)
        growing = self.unstable
        if len(growing):
            many = len(growing) > 1
            text += (f"\n  unstable: mode{'s' if many else ''} "
                     f"{', '.join(str(k + 1) for k in growing)} grow{'' if many else 's'} "
                     f"instead of vibrating (omega^2 < 0, listed as negative frequencies: "
                     f"growth rate / 2 pi): the state lies past a buckling point")
        return text


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
        path: how they were found (:class:`~flexmbd.analysis.eigen.EigenPath`).
    """

    __repr__ = dataclass_repr

    linearization: Linearization
    factors: np.ndarray
    shapes: np.ndarray
    motion: np.ndarray
    path: EigenPath


def vibration_modes(linearization, count: int | None = None, *, row: int | None = None
                    ) -> Modes:
    """The ``count`` lowest vibration modes (all by default) of a linearized state: a
    :class:`Modes` with ``frequencies`` ``(k,)`` [Hz] and ``shapes`` ``(nd, k)`` over the
    ``nd`` dynamic degrees of freedom.

    Args:
        linearization: the state: a :class:`~flexmbd.Linearization`, a ``Model`` (its
            reference configuration), a static result (its last row, or ``row``) or a
            motion's result with its rates (:func:`linearization_of`).
        count: modes wanted; default all.
        row: the result's row, for a result.

    The way is chosen by size alone (:mod:`flexmbd.analysis.eigen`): a few modes of a
    large model come from ARPACK on the engine's banded tangent (at an equilibrium) or on
    the reduced one; the rest from LAPACK. ``Modes.path`` says which ran and why; where
    ARPACK cannot tell the modes, LAPACK runs and a :class:`~flexmbd.AnalysisWarning`
    says so.

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
        >>> modes = fm.vibration_modes(pendulum, 1)
        >>> print(f"{modes.frequencies[0]:.4f} Hz")
        0.6105 Hz
    """
    lin = linearization_of(linearization, row)
    nd = len(lin.dynamic)
    count = _count(count, nd)
    if not nd:
        empty = np.zeros(0)
        return Modes(lin, empty, empty, np.zeros((0, 0)), np.zeros((len(lin.x), 0)),
                     EigenPath("dense", "reduced", "no degrees of freedom"))
    omega2, shapes, motion, path = _lowest_modes(lin, count)
    return Modes(lin, omega2, frequencies_of(omega2), shapes, motion, path)


def linearization_of(what, row: int | None = None, name: str = "linearization"
                     ) -> Linearization:
    """The linearized state a linearized analysis was given, from what a user holds:

    * a :class:`Linearization`: itself;
    * a :class:`~flexmbd.Model`: its reference configuration at rest (:func:`linearize`);
    * a :class:`~flexmbd.StaticResult`: its row ``row`` (default the last), linearized at
      that equilibrium with its loads;
    * a kinematic, dynamic or inverse-dynamics result: its row ``row`` (default the last)
      with its rates and accelerations (``outputs='all'``), inertia terms included.

    Raises:
        ArgumentError: anything else (naming ``name``, and saying what to pass), a row
            outside the result, ``row`` with a model or a linearization, or a motion
            without its rates.
    """
    if isinstance(what, Linearization | Model):
        if row is not None:
            raise ArgumentError("row", f"is for a result's rows; a {type(what).__name__} is "
                                       f"one state already")
        return what if isinstance(what, Linearization) else linearize(what)
    if not isinstance(what, KinematicResult):
        raise ArgumentError(name, f"must be a linearized state (fm.linearize(model) or "
                                  f"statics.linearization(row)), a Model (its reference "
                                  f"configuration), a static_equilibrium result or a row of "
                                  f"a motion's result (row=...), got {type(what).__name__}")
    rows = len(what.x)
    if not rows:
        raise ArgumentError(name, "the result has no rows to linearize at")
    row = -1 if row is None else checks.whole(row, "row", -rows, rows - 1)
    if isinstance(what, StaticResult):
        return what.linearization(row)
    return linearize(what.model, what.x[row], *motion_rates(what, row),
                     e=None if what.e is None else what.e[row])


def frequencies_of(omega2: np.ndarray) -> np.ndarray:
    """``sign(omega^2) sqrt(|omega^2|) / (2 pi)`` [Hz]: negative for an unstable
    direction."""
    return np.sign(omega2) * np.sqrt(np.abs(omega2)) / (2 * np.pi)


def _lowest_modes(lin: Linearization, count: int
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray, EigenPath]:
    """``omega2`` ``(k,)``, shapes over the dynamic entries of ``q`` ``(nd, k)``, their
    coordinate motions ``(nx, k)`` and the path (:func:`vibration_modes`)."""
    nd = len(lin.dynamic)
    system, why = "reduced", ""
    if arpack_pays(nd, count):
        tangent = lin.tangent
        system = "banded" if tangent is not None else "reduced"
        try:
            if tangent is not None:
                return _banded_modes(lin, tangent, count)
            omega2, shapes = lowest_arpack_dense(lin.block("K"), _mass(lin), count)
            return (omega2, shapes, lin.motion_transfer[:, lin.dynamic] @ shapes,
                    EigenPath("arpack", "reduced", size_reason(nd, count)))
        except EigenError as failure:
            why = f"ARPACK on the {system} tangent failed ({failure}); LAPACK instead"
            warnings.warn(f"vibration modes: {why}", AnalysisWarning, stacklevel=3)
    omega2, found = lowest_dense(lin.block("K"), _mass(lin), count, vectors=True)
    assert found is not None  # asked for: vectors=True
    return (omega2, found, lin.motion_transfer[:, lin.dynamic] @ found,
            EigenPath("dense", "reduced", why or size_reason(nd, count)))


def _banded_modes(lin: Linearization, tangent: BandedTangent, count: int
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray, EigenPath]:
    """:func:`_lowest_modes` by ARPACK on the banded tangent and Rayleigh-Ritz with the
    exact element products: shapes ``z`` over the free coordinates, then as entries of
    ``q`` (the dynamic coordinates and deformations they move) and as coordinate
    motions."""
    model, free = lin.model, tangent.banded.free

    def in_all(z: np.ndarray) -> np.ndarray:
        Z = np.zeros((model.n_coordinates, z.shape[1]))
        Z[free] = z
        return Z

    omega2, z = lowest_arpack(tangent.inverse_times_mass, tangent.mass_times,
                              lambda z: stiffness_products(lin, in_all(z)), len(free),
                              count, tangent.inverse_times
                              if _conservative(lin) else None)
    Z = in_all(z)
    moved = np.concatenate([Z[model.independent_coordinates],
                            lin.workspace().assembly.jacobian_times(lin.x, Z)[
                                model.independent_deformations]])
    return (omega2, moved[lin.dynamic], coordinate_motions(model, lin.x, Z),
            EigenPath("arpack", "banded", size_reason(len(lin.dynamic), count)))


def _conservative(lin: Linearization) -> bool:
    """Whether the state's tangent is symmetric: its loads derive from a potential, all
    but a global moment on a spatial rotational node (it keeps its axis while the node
    turns, and its load stiffness is not symmetric)."""
    return not turning_moments(lin.workspace(), lin.loads)


def _mass(lin: Linearization) -> np.ndarray:
    """The reduced mass over the dynamic entries, checked positive definite.

    Raises:
        SingularConfigurationError: naming a degree of freedom without mass.
    """
    M = lin.block("M0")
    if cholesky(M) is None:
        weak = int(lin.dynamic[np.argmin(np.diag(M))])
        raise SingularConfigurationError(
            f"the reduced mass matrix M0 is not positive definite: "
            f"{lin.model.describe_q(weak)} moves without mass; {MASS_ADVICE}")
    return M


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
    if result.e is None:
        raise ArgumentError("result", "needs the deformations of the motion: simulate(..., "
                                      "outputs='all')")
    count = _count(count, int(np.sum(~np.asarray(model.q_is_input))))
    engine = workspace_of(model)
    nt = len(result.t)
    omega2 = np.full((nt, count), np.nan)
    # many small problems: BLAS threads would cost more in hand-over than they gain
    with progress_bar(result.t, "modes", progress) as advance, threadpool_limits(1, "blas"):
        for k in range(nt):
            qd, qdd = motion_rates(result, k)
            lin = linearize(model, result.x[k], qd, qdd, workspace=engine, e=result.e[k])
            omega2[k] = _lowest_values(lin, count)
            if advance is not None:
                advance(result.t[k])
    return ModesAlong(result, result.t.copy(), frequencies_of(omega2), omega2)


def _lowest_values(lin: Linearization, count: int) -> np.ndarray:
    """The ``count`` lowest ``omega^2`` of a state, as :func:`vibration_modes` finds them,
    without the shapes where LAPACK runs."""
    if arpack_pays(len(lin.dynamic), count):
        return _lowest_modes(lin, count)[0]
    return lowest_dense(lin.block("K"), _mass(lin), count, vectors=False)[0]


def buckling(linearization, count: int | None = None, *, row: int | None = None
             ) -> Buckling:
    """Load factors ``lambda`` with ``(K0 + lambda G0) phi = 0`` (``eig(-K0, G0)``): the
    multiples of the state's loads at which the structure buckles: a :class:`Buckling`
    with ``count`` factors ``(k,)`` [-], ascending, and their shapes. ``linearization``
    and ``row`` as for :func:`vibration_modes`. It pairs ``K0`` with ``G0``, so it runs
    on the reduced matrices (LAPACK, the whole spectrum).

    Raises:
        UnstressedError: the state has no geometric stiffness (no loads, no stresses).

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
    lin = linearization_of(linearization, row)
    K, G = lin.block("K0"), lin.block("G0")
    if not len(K) or not np.any(G):
        raise UnstressedError("loads", "the state carries no stresses, so no load factor "
                                       "makes it buckle: apply loads (XF, gravity, loads=...)")
    # 1/lambda are the eigenvalues of (G, K): finite for every mode even where G0 vanishes
    K = 0.5 * (K + K.T)
    factor = cholesky(K)
    # a stable state: a symmetric problem L^-1 G L^-T y = y / lambda
    if factor is not None and well_posed(factor, K):
        reduced, inverse_factor = reduced_by(factor, 0.5 * (G + G.T))
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
    return Buckling(lin, factors[order], shapes, lin.motion_transfer[:, lin.dynamic] @ shapes,
                    EigenPath("dense", "reduced", f"buckling pairs K0 with G0 "
                                                  f"({len(K)} degrees of freedom)"))


def compliance(linearization, labels, *, row: int | None = None) -> np.ndarray:
    """The compliance ``F_sel (K0 + G0)^-1 F_sel^T`` ``(k, k)`` [m/N, rad/(N m), ...] seen at
    the coordinates ``labels`` (``["x5.1", "x5.2"]``): entry ``(i, j)`` is the static
    displacement of coordinate ``i`` per unit load on coordinate ``j``. It is symmetric
    but under a global moment on a spatial rotational node, whose load stiffness is not
    (the moment keeps its axis while the node turns). On a spatial
    rotational node the labels of ``lam1..lam3`` stand for its global rotations about x,
    y and z and the moments about them (``T = diag(I, 2 E)``, the spatial theory,
    section 6). The prescribed entries of ``q`` are held. ``linearization`` and ``row``
    as for :func:`vibration_modes`; a large model at an equilibrium solves on the
    engine's banded tangent, the others on the reduced one.

    Raises:
        SingularConfigurationError: ``K0 + G0`` is singular (a mechanism, or buckling).
    """
    return _compliance(linearization_of(linearization, row), labels, held=True)


def _compliance(lin: Linearization, labels, held: bool) -> np.ndarray:
    """``T F_sel K^-1 F_sel^T T^T`` over the dynamic entries of ``q`` (``held``) or all."""
    if held and lin.tangent is not None:
        named = [lin.model.coordinate_labels[i] for i in lin.rows_of(labels)]
        return lin.tangent.compliance(named)
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
    factor = cholesky(symmetric)
    if factor is None or not well_posed(factor, symmetric):
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


def node_compliance(linearization, node: int, rotational: int | None = None,
                    *, frame: Literal["global", "body"] = "global",
                    drive: Literal["held", "free"] = "held", row: int | None = None
                    ) -> np.ndarray:
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
        row: the result's row, when ``linearization`` is a result (as for
            :func:`vibration_modes`).

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
    lin = linearization_of(linearization, row)
    labels = compliance_labels(lin.model, node, rotational, frame, drive)
    C = _compliance(lin, labels, held=drive == "held")
    return in_frame(lin.model, lin.x, rotational, C, frame)


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
