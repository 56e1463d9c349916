"""The linearized reduced equations of motion at one state (THEORY 9).

Around a state ``(q, qdot, qddot)`` the reduced equations
``Mbar qddot - F_q^T (f - h - M (F_qq qdot) qdot) + E_q^T sigma = 0`` linearize to

    M0 dq'' + (C0 + D0) dq' + (K0 + N0 + G0) dq = F_q^T df

over all entries of ``q = [x(m); e(m)]`` (dynamic and prescribed):

* ``M0 = F_q^T M F_q``, the reduced mass matrix;
* ``K0 = E_q^T S E_q`` and ``D0 = E_q^T C E_q``, the elastic law's stiffness and
  damping seen by ``q``;
* ``G0 = F_q^T (sum_i sigma_i D_xx,i) F_q``, the geometric stiffness, with ``sigma`` the
  stresses of *all* deformations from the nodal equilibrium of the state (THEORY 8: the
  constraint, actuator and, for the ``e(m)``, the balancing stresses; the elastic
  law's on released deformations). It equals ``sum_i sigma_i E_qq,i - F_qq^T (f - M
  xddot - h)`` (the stresses' and the loads' share of the tangent): differentiating
  ``e(o) = const`` twice along ``q`` turns the loads' ``F_qq`` term into the constraint
  stresses' ``D_xx``. Away from an equilibrium (the undeformed column under its
  buckling load) these stresses balance the loads, which keeps the tangent exact.
  A global moment on a spatial rotational node adds ``- F_q^T (df/dx) F_q``: its
  generalized force ``2 E(lam)^T M`` turns with the node (:func:`load_stiffness`); so does
  the weight of an element whose consistent mass turns with its rotations (a beam's
  weight has moments on its rotational nodes);
* ``N0`` and ``C0``, the derivatives of the reduced inertia forces ``F_q^T (M xddot + h)``
  with respect to ``q`` and ``qdot`` (``N0`` also holds the damping stresses' change
  ``E_q^T C dedot/dq``). They vanish at rest; in motion they are taken by central
  differences of the engine's exact inertia forces, whose error is ``1e-10`` of
  their size (the third derivatives of the deformation functions they need exist
  only as those differences).

Everything comes from the engine: ``F_q`` from the factorised ``D_c``, the stresses
from its nodal equilibrium, ``M``, ``h`` and the Hessians from the element kernels,
``S`` and ``C`` from the compiled elastic laws. Shapes: ``nq = model.n_dof``; units
follow ``q`` (m, rad), forces N and N m.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .. import checks
from ..elements.base import SPATIAL_ROTATIONAL
from ..engine import (
    MAX_ITERATIONS,
    Workspace,
    load_vector,
    q_scale,
    unwrap_near,
    workspace_for,
    workspace_of,
)
from ..errors import ArgumentError
from ..model import DeformationClass, Model
from ..orientation import angular_velocity, euler_forces
from ..results import KinematicResult
from ..summary import dataclass_repr
from .banded import BANDED_FROM, EQUILIBRIUM, BandedStatics, BandedTangent
from .kinematics import coordinates, generalized

#: central-difference step of N0, relative to a coordinate's size (model size or 1 rad):
#: the cube root of the rounding error balances truncation (1e-10 relative in all)
DIFFERENCE_STEP = 5e-6

__all__ = ["Linearization", "linearize", "linearize_free", "motion_rates"]


@dataclass(frozen=True, eq=False)
class Linearization:
    """The linearized reduced equations at one state (module docstring).

    The state is solved at once; the matrices are formed when first read, so an
    analysis that needs only the engine's banded tangent (:attr:`tangent`: the
    compliance and a few lowest modes of a large model at an equilibrium) never forms
    them.

    Attributes:
        model: the mechanism.
        x, xd, xdd: the state's coordinates and their rates ``(nx,)``.
        e: its deformations ``(ne,)``.
        q, qd, qdd: ``q = [x(m); e(m)]`` and its rates ``(nq,)``.
        sigma: stresses of all deformations ``(ne,)`` [N, N m] (elastic law, constraint
            and actuator stresses).
        driving: ``tau = Mbar qddot - g`` ``(nq,)``: the load each entry of ``q`` needs to
            follow the state; zero on dynamic entries at an equilibrium or along a solution.
        reactions: loads of supports and drives ``(nx,)`` (THEORY 8).
        loads: the loads applied on top of the model's own ``(nx,)`` [N, N m].

    The matrices (properties, formed on first read): ``F_q = dx/dq`` ``(nx, nq)``,
    ``E_q = de/dq`` ``(ne, nq)``, and ``M0``, ``C0``, ``D0``, ``K0``, ``N0``, ``G0``
    ``(nq, nq)`` (module docstring).
    """

    __repr__ = dataclass_repr

    model: Model
    x: np.ndarray
    xd: np.ndarray
    xdd: np.ndarray
    e: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    sigma: np.ndarray
    driving: np.ndarray
    reactions: np.ndarray
    loads: np.ndarray

    # --- the matrices, formed on first use ------------------------------------------------
    @cached_property
    def _matrices(self) -> dict[str, np.ndarray]:
        engine = self.workspace()
        F_q, E_q, G0 = geometric_stiffness(engine, self.x, self.sigma, self.loads)
        state = {"x": self.x, "q": self.q, "qd": self.qd, "qdd": self.qdd}
        N0, C0 = inertia_derivatives(engine, state, F_q, E_q)
        M = engine.mass(self.x, self.xd)[0]
        law = engine.assembly.law_times
        damped = law("C", E_q)   # an undamped model (most) skips its product
        nq = self.model.n_dof
        return {"F_q": F_q, "E_q": E_q, "M0": F_q.T @ M @ F_q, "C0": C0,
                "D0": E_q.T @ damped if np.any(damped) else np.zeros((nq, nq)),
                "K0": E_q.T @ law("S", E_q), "N0": N0, "G0": G0}

    F_q = property(lambda self: self._matrices["F_q"], doc="``dx/dq`` ``(nx, nq)``.")
    E_q = property(lambda self: self._matrices["E_q"], doc="``de/dq`` ``(ne, nq)``.")
    M0 = property(lambda self: self._matrices["M0"], doc="Reduced mass ``(nq, nq)``.")
    C0 = property(lambda self: self._matrices["C0"], doc="Gyroscopic matrix ``(nq, nq)``.")
    D0 = property(lambda self: self._matrices["D0"], doc="Damping matrix ``(nq, nq)``.")
    K0 = property(lambda self: self._matrices["K0"], doc="Elastic stiffness ``(nq, nq)``.")
    N0 = property(lambda self: self._matrices["N0"], doc="Dynamic stiffness ``(nq, nq)``.")
    G0 = property(lambda self: self._matrices["G0"], doc="Geometric stiffness ``(nq, nq)``.")

    def workspace(self) -> Workspace:
        """The workspace the state was solved in (``linearize(..., workspace=)``), or the
        model's own (also after unpickling): where the matrices and the banded tangent
        are formed."""
        return self.__dict__.get("_given_workspace") or workspace_of(self.model)

    def __getstate__(self) -> dict:
        # a workspace holds the compiled core, which stays in its process
        return {key: value for key, value in self.__dict__.items()
                if key not in ("_given_workspace", "_banded_choice")}

    @property
    def at_rest(self) -> bool:
        """Whether the state has no rates (a static state: ``N0 = C0 = 0``)."""
        return not (np.any(self.qd) or np.any(self.qdd))

    @property
    def tangent(self) -> BandedTangent | None:
        """The engine's banded tangent ``[[K, D_c^T], [D_c, 0]]`` in all coordinates at
        this state, factorised (:class:`~flexmbd.analysis.banded.BandedTangent`), or
        ``None`` where the reduced matrices serve: a model below
        :data:`~flexmbd.analysis.banded.BANDED_FROM` degrees of freedom, a state in
        motion, a state that is not an equilibrium, or a singular tangent
        (:attr:`tangent_reason` says which)."""
        return self._banded()[0]

    @property
    def tangent_reason(self) -> str:
        """Why :attr:`tangent` is or is not the banded one, in words."""
        return self._banded()[1]

    def _banded(self) -> tuple[BandedTangent | None, str]:
        known = self.__dict__.get("_banded_choice")
        if known is not None:
            return known
        choice: tuple[BandedTangent | None, str]
        model = self.model
        if model.n_dof < BANDED_FROM:
            choice = (None, f"{model.n_dof} degrees of freedom: the reduced tangent "
                            f"(banded from {BANDED_FROM})")
        elif not self.at_rest:
            choice = (None, "a state in motion: the reduced tangent with its inertia terms")
        else:
            banded = BandedStatics(model, self.workspace())
            tangent = BandedTangent(banded, self.x, self.q, self.sigma[banded.constrained],
                                    self.loads)
            try:
                off = tangent.off_balance()
            except np.linalg.LinAlgError:
                choice = (None, "the banded tangent is singular here: the reduced tangent")
            else:
                choice = ((tangent, f"{model.n_dof} degrees of freedom at an equilibrium: "
                                    f"the banded tangent") if off <= EQUILIBRIUM else
                          (None, f"not an equilibrium (one Newton step moves {off:.2g} of "
                                 f"the model size): the reduced tangent"))
        self.__dict__["_banded_choice"] = choice
        return choice

    @property
    def dynamic(self) -> np.ndarray:
        """Indices of the dynamic entries of ``q`` (not inputs), shape ``(nd,)``."""
        return np.flatnonzero(~np.asarray(self.model.q_is_input))

    def block(self, name: str, rows: str = "d", columns: str = "d") -> np.ndarray:
        """A block of one matrix (``"M0"``, ..., or ``"K"`` for ``K0 + N0 + G0``, ``"C"``
        for ``C0 + D0``) over the dynamic (``"d"``) or prescribed (``"r"``) entries."""
        parts = {"K": ("K0", "N0", "G0"), "C": ("C0", "D0")}.get(name, (name,))
        known = ("M0", "C0", "D0", "K0", "N0", "G0", "K", "C")
        if name not in known:
            raise ArgumentError("name", f"must be one of {', '.join(known)}, got {name!r}")
        given = ~np.asarray(self.model.q_is_input)
        picks = {"d": np.flatnonzero(given), "r": np.flatnonzero(~given)}
        if rows not in picks or columns not in picks:
            raise ArgumentError("rows", "rows and columns are 'd' (dynamic) or 'r' (prescribed)")
        at = np.ix_(picks[rows], picks[columns])
        return sum(getattr(self, part)[at] for part in parts)

    @cached_property
    def motion_transfer(self) -> np.ndarray:
        """``T F_q`` ``(nx, nq)``: how the coordinates move with ``q``, as a user reads
        them [m, rad]. On a spatial rotational node the rows of ``lam1..lam3`` are its
        global rotation ``dtheta = 2 E(lam) dlam`` (the spatial theory, section 6), the
        conjugate of a moment on those entries, and the row of ``lam0`` is zero."""
        return coordinate_motions(self.model, self.x, self.F_q)

    def transfer(self, labels, name: str = "labels") -> np.ndarray:
        """Rows of :attr:`motion_transfer` over the dynamic entries for coordinate labels
        (``"x3.2"``): how those coordinates (a rotational node's global rotations) move
        with the degrees of freedom ``(len(labels), nd)``. ``name`` is the argument the
        labels came by, for an error."""
        return self.motion_transfer[np.ix_(self.rows_of(labels, name), self.dynamic)]

    def rows_of(self, labels, name: str = "labels") -> np.ndarray:
        """The coordinate indices ``(k,)`` of the labels (``"x3.2"``) of coordinates with
        a transfer: not the ``lam0`` of a spatial rotational node.

        Raises:
            ArgumentError: a label the model lacks, or a ``lam0``; naming ``name``.
        """
        labels, rows = checks.coordinates_named(self.model, labels, name)
        for label, row in zip(labels, rows, strict=True):
            if row in self.model.euler_scalars:
                raise ArgumentError(name, f"{label} is lam0 of a spatial rotational node; "
                                          f"its rotations are {label[:-1]}2 to "
                                          f"{label[:-1]}4 (about x, y and z)")
        return np.asarray(rows, dtype=int)


def linearize(model: Model, x=None, qd=None, qdd=None, *, loads=None,
              tolerance: float | None = None, max_iterations: int = MAX_ITERATIONS,
              workspace: Workspace | None = None, e=None,
              engine: Workspace | None = None) -> Linearization:
    """Linearize the reduced equations at the configuration ``x`` with rates ``qd`` and
    accelerations ``qdd`` of ``q``.

    Args:
        model: the mechanism.
        x: coordinates ``(nx,)`` [m, rad]; default the initial configuration. They are
            solved again for their own ``q``, so a near solution (a result row) is exact.
        qd, qdd: rates and accelerations of ``q`` ``(nq,)``; default zero (a static state).
        loads: applied loads ``(nx,)`` [N, N m] or ``{"x3.2": value}``, on top of the
            model's own (``XF``, gravity); they set the stresses of ``G0``.
        tolerance: Newton tolerance of the position solve [m, rad].
        max_iterations: Newton iterations of the position solve before giving up.
        workspace: a :class:`~flexmbd.Workspace` of ``model`` to use (repeated calls along
            a motion); default the model's own.
        engine: the old name of ``workspace`` (deprecated).
        e: the deformations ``(ne,)`` at ``x`` when known (a result row): a hinge turned
            beyond half a turn keeps its rotation (from ``x`` alone it is known only
            within half a turn, and its spring's stress with it).

    Returns:
        :class:`Linearization`.

    Examples:
        The pendulum hanging at rest: its stiffness ``K0 + G0`` is ``m g L / 2``:

        >>> import numpy as np
        >>> import flexmbd as fm
        >>> pendulum = (fm.ModelBuilder("pendulum").add_node(1, 0, 0).add_node(3, 0, -1)
        ...             .add_rigid_beam(1, 1, 2, 3).set_mass(1, 1.0).fix(1)
        ...             .dynamic_coordinate(2).set_gravity(0, -9.81).build())
        >>> lin = fm.linearize(pendulum)
        >>> print(f"{lin.block('K')[0, 0]:.4f} N m/rad, {lin.block('M0')[0, 0]:.4f} kg m^2")
        4.9050 N m/rad, 0.3333 kg m^2
    """
    if engine is not None:
        checks.deprecated("linearize: give workspace=..., not engine=...")
        workspace = workspace or engine
    engine = workspace_for(model, workspace, tolerance, max_iterations)
    x = coordinates(model, model.x0 if x is None else x)
    zero = np.zeros(model.n_dof)
    qd = zero if qd is None else generalized(model, qd, "qd")
    qdd = zero if qdd is None else generalized(model, qdd, "qdd")
    extra = np.zeros(model.n_coordinates) if loads is None else load_vector(model, loads,
                                                                            "loads")
    near = None
    if e is not None:
        e = checks.vector(e, model.n_deformations, "e", "the deformations at x")
        near = np.concatenate([x[model.independent_coordinates],
                               e[model.independent_deformations]])
    state = equilibrium_state(engine, x, qd, qdd, extra, near)
    lin = Linearization(
        model=model, x=state["x"], xd=state["xd"], xdd=state["xdd"], e=state["e"],
        q=state["q"], qd=qd, qdd=qdd, sigma=state["sigma"], driving=state["driving"],
        reactions=state["reactions"], loads=extra)
    if workspace is not None:
        lin.__dict__["_given_workspace"] = engine
    return lin


def motion_rates(result: KinematicResult, row: int) -> tuple[np.ndarray, np.ndarray]:
    """``qd`` and ``qdd`` ``(nq,)`` of a motion's row, from its coordinates' and
    deformations' rates.

    Raises:
        ArgumentError: the result has no rates (``outputs='all'`` keeps them).
    """
    model = result.model
    if result.xd is None or result.xdd is None or result.ed is None or result.edd is None:
        raise ArgumentError("result", "needs the rates of the motion: simulate(..., "
                                      "outputs='all')")
    nxm, emd = model.independent_coordinates, model.independent_deformations
    return (np.concatenate([result.xd[row, nxm], result.ed[row, emd]]),
            np.concatenate([result.xdd[row, nxm], result.edd[row, emd]]))


def linearize_free(model: Model, x, qd=None, *, loads=None, workspace: Workspace | None = None,
                   e=None) -> Linearization:
    """:func:`linearize` at the accelerations of the free motion: the dynamic entries of
    ``qddot`` are those the equations of motion give at ``(x, qd)`` (the prescribed ones
    zero). This is the linearization of SPACAR's mode 3 along a stored path, whose
    states need not be equilibria of the model analysed.

    Args:
        model: the mechanism.
        x: coordinates ``(nx,)`` [m, rad].
        qd: rates of ``q`` ``(nq,)`` (default zero).
        loads, workspace, e: as for :func:`linearize`.
    """
    workspace = workspace_for(model, workspace)
    at_rest = linearize(model, x, qd, loads=loads, workspace=workspace, e=e)
    dynamic = at_rest.dynamic
    qdd = np.zeros(model.n_dof)
    # Mbar qdd - g = driving, zero on the dynamic entries of the free motion
    qdd[dynamic] = -np.linalg.solve(at_rest.block("M0"), at_rest.driving[dynamic])
    return linearize(model, at_rest.x, at_rest.qd, qdd, loads=loads, workspace=workspace, e=e)


def static_tangent(engine: Workspace, x: np.ndarray, loads: np.ndarray,
                   near: np.ndarray | None = None
                   ) -> tuple[dict[str, np.ndarray], np.ndarray]:
    """The state at rest at ``x`` under ``loads`` ``(nx,)`` (:func:`equilibrium_state`:
    its ``driving`` entries are the out-of-balance loads on ``q``; hinge rotations near
    ``near``) and the tangent stiffness ``K0 + G0`` ``(nq, nq)``: what static Newton needs
    of :func:`linearize`, without the mass and inertia terms."""
    zero = np.zeros(engine.model.n_dof)
    state = equilibrium_state(engine, x, zero, zero, loads, near)
    _, E_q, G0 = geometric_stiffness(engine, state["x"], state["sigma"], loads)
    return state, E_q.T @ engine.assembly.law_times("S", E_q) + G0


# --- the pieces ---------------------------------------------------------------------------
def geometric_stiffness(engine: Workspace, x: np.ndarray, sigma: np.ndarray,
                        loads: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``F_q``, ``E_q = D_x F_q`` and the geometric stiffness ``G0 = F_q^T (sum_i sigma_i
    D_xx,i - df/dx) F_q`` at ``x`` with the stresses ``sigma`` ``(ne,)`` under ``loads``
    ``(nx,)`` on top of the model's."""
    assembly = engine.assembly
    F_q = engine.transfer(x, assembly.deformations_and_jacobian(x)[1])
    G0 = F_q.T @ geometric_times(engine, x, sigma, loads, F_q)
    return F_q, assembly.jacobian_times(x, F_q), G0


def geometric_times(engine: Workspace, x: np.ndarray, sigma: np.ndarray, loads: np.ndarray,
                    Z: np.ndarray) -> np.ndarray:
    """``(sum_i sigma_i D_xx,i - df/dx) Z`` ``(nx, k)`` for coordinate changes ``Z`` ``(nx,
    k)``: the stresses' and the loads' share of the tangent in all coordinates, element
    by element (``df/dx``: a global moment's and a turning weight's load stiffness)."""
    assembly = engine.assembly
    slopes = load_stiffness_times(engine, loads, Z)
    weight = assembly.gravity_slopes_times(x, Z)
    if weight is not None:
        slopes += weight
    return assembly.stress_hessian_times(x, sigma, Z) - slopes


def stiffness_products(lin: Linearization, Z: np.ndarray) -> np.ndarray:
    """``Z^T (K0 + G0) Z`` ``(k, k)`` for coordinate changes ``Z`` ``(nx, k)`` that keep the
    constraints (``Z = F_q Phi``): ``(D Z)^T S (D Z) + Z^T (sum sigma D_xx - df/dx) Z``,
    element by element. Exact products with no solve: with them a basis found to
    ``delta`` gives values good to ``delta^2`` (Rayleigh-Ritz), however poorly
    conditioned the factorisation that found it."""
    engine, model = lin.workspace(), lin.model
    strain = engine.assembly.jacobian_times(lin.x, Z)
    kinds = np.asarray(model.deformation_class)
    # E_q's rows of the rigid and the prescribed deformations are zero (inputs held)
    strain[(kinds == DeformationClass.RIGID) | (kinds == DeformationClass.INPUT)] = 0.0
    return strain.T @ engine.assembly.law_times("S", strain) + Z.T @ geometric_times(
        engine, lin.x, lin.sigma, lin.loads, Z)


def coordinate_motions(model: Model, x: np.ndarray, Z: np.ndarray) -> np.ndarray:
    """Coordinate changes ``Z`` ``(nx, k)`` at ``x`` as a user reads them [m, rad]: on a
    spatial rotational node the rows of ``lam1..lam3`` become its global rotation
    ``dtheta = 2 E(lam) dlam`` (the spatial theory, section 6) and the row of ``lam0``
    zero."""
    Z = np.array(Z, dtype=float)
    at = np.array([list(node.coordinates) for node in model.nodes.values()
                   if node.kind == SPATIAL_ROTATIONAL], dtype=int).reshape(-1, 4)
    if len(at) and Z.shape[1]:   # all nodes at once: (nodes, k, 3) from (nodes, k, 4)
        turned = angular_velocity(x[at][:, None, :], Z[at].transpose(0, 2, 1))
        Z[at[:, 1:]] = turned.transpose(0, 2, 1)
    Z[at[:, 0]] = 0.0
    return Z


def load_stiffness(engine: Workspace, loads: np.ndarray) -> np.ndarray:
    """``df/dx`` ``(nx, nx)`` of the applied loads (the model's and ``loads``). Only a
    global moment ``M`` on a spatial rotational node depends on the configuration: its
    generalized force ``2 E(lam)^T M`` is linear in ``lam``, so its block is the matrix of
    that map, column ``k`` the force at the unit vector ``lam = e_k``. The static
    tangent subtracts ``F_q^T (df/dx) F_q`` (the spatial theory, section 6)."""
    nx = engine.model.n_coordinates
    slopes = np.zeros((nx, nx))
    for at, block in turning_moments(engine, loads):
        slopes[np.ix_(at, at)] = block
    return slopes


def load_stiffness_times(engine: Workspace, loads: np.ndarray, A: np.ndarray) -> np.ndarray:
    """``(df/dx) A`` ``(nx, k)`` for ``A`` ``(nx, k)``: :func:`load_stiffness` applied block
    by block, on the rotational nodes that carry a moment only."""
    product = np.zeros((engine.model.n_coordinates, A.shape[1]))
    for at, block in turning_moments(engine, loads):
        product[at] = block @ A[at]
    return product


def turning_moments(engine: Workspace, loads: np.ndarray
                    ) -> list[tuple[np.ndarray, np.ndarray]]:
    """The global moments on spatial rotational nodes under the model's loads and
    ``loads`` ``(nx,)``, the only loads whose generalized force turns with the
    configuration: per node that carries one, its coordinates ``(4,)`` and its block
    ``(4, 4)`` of ``df/dx`` (:func:`load_stiffness`). Empty: the loads derive from a
    potential and the tangent is symmetric."""
    total = engine.constant_loads + loads
    return [(at, euler_forces(np.eye(4), total[at[1:]]).T)
            for at in engine.rotation_coordinates if np.any(total[at[1:]])]


def equilibrium_state(engine: Workspace, x: np.ndarray, qd: np.ndarray, qdd: np.ndarray,
                      loads: np.ndarray, near: np.ndarray | None = None
                      ) -> dict[str, np.ndarray]:
    """The engine's inverse dynamics at one state: ``{"x", "xd", "xdd", "q", "sigma",
    "driving", "reactions", ...}`` (one row each), started from the configuration ``x``.
    A hinge's rotation in ``q`` is taken the whole number of turns nearest ``near``
    ``(nq,)`` when given (``x`` alone knows it only within half a turn)."""
    model = engine.model
    q = unwrap_near(model, np.concatenate([
        x[model.independent_coordinates],
        engine.assembly.deformations(x)[model.independent_deformations]]), near)
    return {name: values[0] for name, values in engine.equilibrium(q, qd, qdd, x, loads).items()}


def inertia_derivatives(engine: Workspace, state: dict[str, np.ndarray], F_q: np.ndarray,
                        E_q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``N0``, ``C0`` ``(nq, nq)``: central differences of the inertia forces ``M xddot + h``
    (and of ``edot`` for the damping stresses) along each ``q`` and ``qdot`` at the state;
    exactly zero at rest, where those forces vanish near the state."""
    model, nq = engine.model, engine.model.n_dof
    q, qd, qdd, x = state["q"], state["qd"], state["qdd"], state["x"]
    if not (np.any(qd) or np.any(qdd)):
        return np.zeros((nq, nq)), np.zeros((nq, nq))
    nx, size = model.n_coordinates, 1.0 / q_scale(model)
    change = engine.inertia_slopes(x, q, qd, qdd, DIFFERENCE_STEP * size)
    N0 = F_q.T @ change[:nx] + E_q.T @ engine.assembly.law_times("C", change[nx:])
    # the inertia forces are quadratic in qdot: a central difference is exact
    C0 = F_q.T @ engine.inertia_slopes(x, q, qd, qdd, size, rates=True)[:nx]
    return N0, C0


def central_differences(engine: Workspace, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray,
                        x: np.ndarray, value, columns=None) -> np.ndarray:
    """``d value / dq_j`` at the state ``(q, qd, qdd)`` (configuration solved from ``x``) by
    central differences with a step of :data:`DIFFERENCE_STEP` of ``q_j``'s size, one column
    per entry ``j`` of ``columns`` (default all of ``q``); ``value`` maps the engine's
    state (:meth:`Workspace.state`) to a vector."""
    size = 1.0 / q_scale(engine.model)
    columns = range(len(q)) if columns is None else columns
    out = []
    for j in columns:
        step = np.zeros(len(q))
        step[j] = DIFFERENCE_STEP * size[j]
        plus = value(engine.state(q + step, qd, qdd, x))
        minus = value(engine.state(q - step, qd, qdd, x))
        out.append((plus - minus) / (2 * step[j]))
    return np.stack(out, axis=1) if out else np.zeros((0, 0))
