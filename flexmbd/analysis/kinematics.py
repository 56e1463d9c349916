"""Kinematic analysis (THEORY sections 3 and 4): one configuration, or a time grid.

Every function here runs on the compiled core through :class:`flexmbd.engine.Workspace`:

* :func:`deformations`, :func:`jacobian`, :func:`hessian` and
  :func:`quadratic_velocity` evaluate the generated element kernels;
* :func:`solve_position` is the Newton-Raphson position solve;
  :func:`partition_jacobian` splits ``D_x`` into the ``x(o)``, ``x(c)``, ``x(m)``
  columns with ``D_c`` factorised;
* :func:`velocities`, :func:`accelerations` and the transfer functions are the
  core's kinematics of one state: ``F_q`` column by column for unit rates, ``F_qq``
  and ``E_qq`` from its quadratic velocity terms (a quadratic form in ``qdot``);
* :func:`kinematic_analysis` runs the prescribed motion over a time grid.

Shapes: ``nx`` coordinates, ``ne`` deformations, ``nq = model.n_dof`` generalized
coordinates ``q = [x(m); e(m)]``. Units: m and rad, seconds for time.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Literal

import numpy as np

from .. import checks
from .. import engine as _engine
from ..engine import KINEMATIC_OUTPUTS, Workspace, initial_q, resolve_laws, workspace_of
from ..errors import SingularConfigurationError
from ..model import Model
from ..motion import Law
from ..progress import progress_bar
from ..results import KinematicResult, check_on_failure, check_times, conclude, first_rows
from ..summary import dataclass_repr

__all__ = ["accelerations", "deformation_transfer", "deformations", "first_order_transfer",
           "hessian", "initial_q", "jacobian", "kinematic_analysis", "partition_jacobian",
           "position_analysis", "quadratic_velocity", "second_order_transfer",
           "solve_position", "velocities"]


# --- element values --------------------------------------------------------------------
def coordinates(model: Model, x, name: str = "x") -> np.ndarray:
    """``x`` checked to be the model's coordinates: finite, shape ``(nx,)``."""
    return checks.vector(x, model.n_coordinates, name, f"the coordinates {name[0]}<node>.<k> "
                         f"of {model.name!r}")


def generalized(model: Model, q, name: str = "q") -> np.ndarray:
    """``q`` (or a rate of it) checked: finite, shape ``(nq,)``."""
    return checks.vector(q, model.n_dof, name, f"one per entry of q: "
                         f"{', '.join(model.q_labels[:6])}{', ...' if model.n_dof > 6 else ''}")


def deformations(model: Model, x: np.ndarray) -> np.ndarray:
    """Deformation parameters ``e = D(x)`` [m, rad], shape ``(ne,)``, at the coordinates
    ``x`` [m, rad] ``(nx,)``."""
    return workspace_of(model).assembly.deformations(coordinates(model, x))


def jacobian(model: Model, x: np.ndarray) -> np.ndarray:
    """``D_x = dD/dx``, shape ``(ne, nx)`` (dense), at ``x`` [m, rad] ``(nx,)``; an entry is
    [m/m], [m/rad], [rad/m] or [rad/rad] by the deformation and the coordinate."""
    return workspace_of(model).assembly.deformations_and_jacobian(coordinates(model, x))[1]


def hessian(model: Model, x: np.ndarray) -> np.ndarray:
    """``D_xx``, shape ``(ne, nx, nx)``, at ``x`` [m, rad] ``(nx,)`` (dense; meant for small
    models and checks)."""
    return workspace_of(model).assembly.hessian(coordinates(model, x))


def quadratic_velocity(model: Model, x: np.ndarray, xd: np.ndarray) -> np.ndarray:
    """``(D_xx xdot) xdot`` per deformation [m/s^2, rad/s^2], shape ``(ne,)``, at ``x``
    ``(nx,)`` [m, rad] with rates ``xd`` ``(nx,)`` [m/s, rad/s] (THEORY section 2)."""
    return workspace_of(model).assembly.quadratic_velocity(coordinates(model, x),
                                                        coordinates(model, xd, "xd"))


# --- positions -------------------------------------------------------------------------
def solve_position(model: Model, q: np.ndarray, x_guess: np.ndarray | None = None, *,
                   time: float | None = None, tolerance: float | None = None,
                   max_iterations: int = _engine.MAX_ITERATIONS) -> np.ndarray:
    """Solve ``e(o)(x) = 0``, ``e(m)(x) = e(m)`` for ``x(c)`` by Newton-Raphson (THEORY 3).

    Once the residual is below the tolerance, one more correction makes the error of
    ``x`` second order in the residual, so positions are accurate far below the
    tolerance and do not depend on the starting guess.

    Args:
        model: the mechanism.
        q: generalized coordinates ``[x(m); e(m)]``, shape ``(nq,)``.
        x_guess: start for ``x(c)`` (warm start), shape ``(nx,)``; default ``model.x0``.
        time: only used in messages [s].
        tolerance: on the largest residual [m, rad]; default
            ``1e-10 * model.characteristic_length``.
        max_iterations: Newton iterations before giving up.

    Returns:
        All coordinates ``x``, shape ``(nx,)``.

    Raises:
        ConvergenceError: no convergence (names time, iterations and residual).
        SingularConfigurationError: ``D_c`` singular on the way or at the solution.
    """
    return position_analysis(model, q, x_guess, time=time, tolerance=tolerance,
                             max_iterations=max_iterations).x


@dataclass(frozen=True, eq=False)
class PartitionedJacobian:
    """``D_x`` at one configuration, split by coordinate class, with ``D_c`` factorised.

    Attributes:
        full: ``D_x``, ``(ne, nx)``.
        fixed: columns ``x(o)``, ``(ne, n_fixed)``.
        dependent: columns ``x(c)``, ``(ne, n_dependent)``.
        independent: columns ``x(m)``, ``(ne, n_xm)``.
        D_c: rows ``e(o), e(m)`` of ``dependent``, square.
        conditioning: estimate of the smallest singular value of ``D_c`` after scaling
            angles by the model size and normalising each row in the reference
            configuration (1 for a well-conditioned mechanism, 0 at a singular one).
    """

    __repr__ = dataclass_repr

    full: np.ndarray
    fixed: np.ndarray
    dependent: np.ndarray
    independent: np.ndarray
    D_c: np.ndarray
    conditioning: float
    _engine: Workspace

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """``D_c^-1 rhs`` for ``rhs`` of shape ``(n_dependent,)`` or ``(n_dependent, k)``."""
        return self._engine.solve(rhs) if len(self.D_c) else np.zeros_like(rhs)


@dataclass(frozen=True, eq=False)
class PositionSolution:
    """Result of :func:`position_analysis`: ``x`` ``(nx,)`` and the partitioned Jacobian
    there (ready for velocities)."""

    __repr__ = dataclass_repr

    x: np.ndarray
    jacobian: PartitionedJacobian


def partition_jacobian(model: Model, x: np.ndarray, time: float | None = None
                       ) -> PartitionedJacobian:
    """Split ``D_x`` at ``x`` ``(nx,)`` [m, rad] into ``x(o)``, ``x(c)``, ``x(m)`` columns
    and factorise ``D_c``: a :class:`PartitionedJacobian` whose blocks have one row per
    deformation ``(ne, ...)`` and one column per coordinate of their class.

    Raises:
        SingularConfigurationError: ``D_c`` is singular at ``x``.
    """
    return _partition(workspace_of(model), coordinates(model, x), time)


def _partition(engine: Workspace, x: np.ndarray, time: float | None) -> PartitionedJacobian:
    model = engine.model
    D_x = engine.assembly.deformations_and_jacobian(x)[1]
    dependent = D_x[:, model.dependent]
    D_c = dependent[model.constrained]
    conditioning = engine.factor(x)
    if len(D_c) and not conditioning > 0.0:
        from ..engine.diagnosis import singular_message

        raise SingularConfigurationError(singular_message(model, D_c, time, "D_c is singular"),
                                         time)
    return PartitionedJacobian(D_x, D_x[:, model.fixed], dependent,
                               D_x[:, model.independent_coordinates], D_c, conditioning, engine)


def position_analysis(model: Model, q: np.ndarray, x_guess: np.ndarray | None = None, *,
                      time: float | None = None, tolerance: float | None = None,
                      max_iterations: int = _engine.MAX_ITERATIONS) -> PositionSolution:
    """:func:`solve_position` that also returns the partitioned Jacobian at the solution:
    a :class:`PositionSolution` with ``x`` ``(nx,)`` [m, rad] and its ``jacobian``."""
    engine = workspace_of(model, tolerance, max_iterations)
    guess = None if x_guess is None else coordinates(model, x_guess, "x_guess")
    x = engine.positions(generalized(model, q), guess, time)
    return PositionSolution(x, _partition(engine, x, time))


# --- velocities, accelerations, transfer functions (THEORY 4) ---------------------------
def _q_at(model: Model, x: np.ndarray) -> np.ndarray:
    """``q = [x(m); e(m)]`` of a configuration."""
    e = workspace_of(model).assembly.deformations(x)
    return np.concatenate([np.asarray(x)[model.independent_coordinates],
                           e[model.independent_deformations]])


def _rates(model: Model, x: np.ndarray, qd: np.ndarray, qdd: np.ndarray
           ) -> dict[str, np.ndarray]:
    """The core's kinematics at the configuration ``x`` for rates ``qd``, ``qdd``."""
    return workspace_of(model).state(_q_at(model, x), qd, qdd, x)


def velocities(model: Model, x: np.ndarray, qd: np.ndarray) -> np.ndarray:
    """``xdot`` ``(nx,)`` [m/s, rad/s] at ``x`` ``(nx,)`` [m, rad] from
    ``qdot = [xdot(m); edot(m)]`` ``(nq,)`` by the partitioned solve
    ``D_c xdot(c) = [0; edot(m)] - [de(o)/dx(m); de(m)/dx(m)] xdot(m)`` (THEORY 4)."""
    qd = generalized(model, qd, "qd")
    return _rates(model, coordinates(model, x), qd, np.zeros(model.n_dof))["xd"]


def accelerations(model: Model, x: np.ndarray, xd: np.ndarray, qdd: np.ndarray) -> np.ndarray:
    """``xddot`` ``(nx,)`` [m/s^2, rad/s^2] at ``x`` ``(nx,)`` [m, rad] from ``qddot``
    ``(nq,)`` with the quadratic velocity terms of the velocities ``xd`` ``(nx,)``
    [m/s, rad/s] (THEORY 4)."""
    x, xd = coordinates(model, x), coordinates(model, xd, "xd")
    e_rates = workspace_of(model).assembly.jacobian_times(x, xd[:, None])[:, 0]
    qd = np.concatenate([xd[model.independent_coordinates],
                         e_rates[model.independent_deformations]])
    return _rates(model, x, qd, generalized(model, qdd, "qdd"))["xdd"]


def first_order_transfer(model: Model, x: np.ndarray) -> np.ndarray:
    """``F_q = dx/dq`` ``(nx, nq)``: ``xdot = F_q qdot``; column ``j`` is the velocity for
    a unit rate of ``q_j`` (THEORY 4). ``x`` ``(nx,)`` [m, rad]; an entry has the unit of its
    coordinate per unit of its entry of ``q`` (m/m, m/rad, rad/rad, ...)."""
    return workspace_of(model).transfer(coordinates(model, x))


def deformation_transfer(model: Model, x: np.ndarray, F_q: np.ndarray | None = None
                         ) -> np.ndarray:
    """``E_q = D_x F_q`` ``(ne, nq)`` at ``x`` ``(nx,)`` [m, rad]: ``edot = E_q qdot``; an
    entry has the unit of its deformation per unit of its entry of ``q``."""
    x = coordinates(model, x)
    if F_q is None:
        F_q = first_order_transfer(model, x)
    return jacobian(model, x) @ F_q


def second_order_transfer(model: Model, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``F_qq`` ``(nx, nq, nq)`` and ``E_qq`` ``(ne, nq, nq)``, the derivatives of F_q, E_q,
    at ``x`` ``(nx,)`` [m, rad]; units of ``x`` (``e``) per unit of ``q`` squared.

    ``xddot = F_q qddot + (F_qq qdot) qdot``: the accelerations at ``qddot = 0`` are the
    quadratic form ``(F_qq qdot) qdot`` (and ``(E_qq qdot) qdot``), whose entries follow
    by polarization, ``B(u, v) = (Q(u + v) - Q(u - v)) / 4``. Meant for inspection and
    small models: the analyses use the quadratic velocity terms directly.
    """
    x = coordinates(model, x)
    engine, q, nq = workspace_of(model), _q_at(model, x), model.n_dof
    zero = np.zeros(nq)
    F_qq = np.zeros((model.n_coordinates, nq, nq))
    E_qq = np.zeros((model.n_deformations, nq, nq))
    unit = np.eye(nq)
    for j in range(nq):
        for k in range(j, nq):
            plus = engine.state(q, unit[j] + unit[k], zero, x)
            minus = engine.state(q, unit[j] - unit[k], zero, x)
            F_qq[:, j, k] = F_qq[:, k, j] = (plus["xdd"] - minus["xdd"]) / 4
            E_qq[:, j, k] = E_qq[:, k, j] = (plus["edd"] - minus["edd"]) / 4
    return F_qq, E_qq


# --- a time grid --------------------------------------------------------------------------
@checks.keyword_only("inputs")
def kinematic_analysis(
    model: Model,
    times,
    *,
    inputs: Mapping[str, Law] | None = None,
    tolerance: float | None = None,
    max_iterations: int = _engine.MAX_ITERATIONS,
    on_failure: Literal["raise", "return"] = "raise",
    progress: bool | None = None,
) -> KinematicResult:
    """Positions, velocities and accelerations of all coordinates and deformations.

    At each time the prescribed ``q`` comes from the laws; the position solve
    starts from the previous solution plus its velocity times the time step.

    Args:
        model: the mechanism.
        times: increasing output times [s], shape ``(nt,)``.
        inputs: laws by label (``{"x2.1": Polynomial(0, 4)}``), overriding the
            model's defaults. Dynamic degrees of freedom without a law stay at
            their initial values.
        tolerance: Newton tolerance [m, rad] (default ``1e-10`` times the model size).
        max_iterations: Newton iteration limit per time.
        on_failure: ``"raise"`` (default) raises the :class:`SimulationError`
            with the points computed so far as ``error.partial_result``;
            ``"return"`` returns them with ``success=False``.
        progress: show a progress bar (default: only for long interactive runs).

    Returns:
        :class:`~flexmbd.results.KinematicResult`.

    Examples:
        A bar of 2 m sliding with one end along x (driven at 4 m/s) and the other along
        y: the second end's height is ``sqrt(4 - x^2)``:

        >>> import numpy as np
        >>> import flexmbd as fm
        >>> bar = (fm.ModelBuilder("sliding bar").add_node(1, -1.6, 0.0).add_node(2, 0.0, 1.2)
        ...        .add_truss(1, 1, 2).fix(1, "y").fix(2, "x")
        ...        .input_coordinate(1, "x", law=fm.Polynomial(-1.6, 4.0)).build())
        >>> run = fm.kinematic_analysis(bar, [0.0, 0.2])
        >>> print(f"{run['x2.2'][-1]:.6f} {np.sqrt(4 - 0.8**2):.6f}")
        1.833030 1.833030
    """
    times = check_times(times)
    check_on_failure(on_failure)
    laws = resolve_laws(model, inputs)
    engine = Workspace(model, tolerance, max_iterations)
    with progress_bar(times, "kinematics", progress) as bar:
        arrays = engine.prepare(laws, len(times), progress=bar,
                                columns=KINEMATIC_OUTPUTS)
        engine.start(laws, times[0])
        status = engine.kinematic_run(times)
    done = status["reached"]
    result = KinematicResult(model, times[:done], **first_rows(arrays, done))
    return conclude(result, engine.error(status), on_failure,
                    f"completed {len(times)} points from t = {times[0]:.6g} s to "
                    f"{times[-1]:.6g} s")
