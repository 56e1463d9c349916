"""The equations of motion evaluated for time integration: batched, linear in model size.

This is the fast path of :func:`flexmbd.simulate`. It evaluates the same
reduced equations as :mod:`flexmbd.dynamics` (THEORY section 7),

    F_q^T (M xddot + h - f + D_x^T sigma) = 0   on the dynamic entries of q,

but never forms ``F_q`` or ``Mbar = F_q^T M F_q``. Instead:

* the kinematics are solved with ``D_c`` alone (positions by Newton-Raphson
  from a warm start, velocities and accelerations by one solve each);
* the nodal force ``y = M xddot + h - f + D_x^T sigma`` is summed element by
  element;
* the accelerations follow from the saddle-point system over the free
  coordinates (dependent and dynamic) and the multipliers (the stresses of
  rigid and input deformations),

      [[M, C^T], [C, 0]] [z; lambda] = [y0; 0],   qddot_d = -Q z,

  where ``y0`` is the force at ``qddot_d = 0``, ``C`` the rows of ``D_x`` of
  the multipliers and ``Q`` maps free-coordinate motions to the dynamic entries
  of ``q``. Because ``z`` lies in the null space of ``C``, which ``F_q`` spans,
  this is ``Mbar_dd qddot_d = g_d - Mbar_dr qddot_r`` solved without forming
  ``Mbar``; ``lambda`` are minus the constraint stresses (THEORY section 8).
* an implicit integrator's Newton matrix ``Mbar + c_q K + c_v C`` is the same
  saddle-point system with ``M`` replaced by ``M + c_q (D^T S D + sum sigma_i
  D_xx,i) + c_v D^T C D`` built from the element stiffness and damping.

All of it works on a batch of states (leading axis ``nb``), so the output pass
of a run evaluates every output time in one call.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .assembly import SystemJacobian
from .dynamics import Forces, load_vector
from .errors import ConvergenceError, SingularConfigurationError
from .factor import DenseFactor, SparseFactor
from .kinematics import RELATIVE_TOLERANCE, SINGULAR_RCOND, regularity_limit, singular_error
from .model import Model
from .motion import Law

#: residuals below this share of the tolerance are round-off: no new Jacobian for them
_ROUND_OFF = 1e-6
#: a chord iteration that reduces the residual by less than this gets a fresh D_c
_SLOW_CHORD = 0.1


@dataclass(eq=False)
class State:
    """Kinematics of a batch of ``nb`` states at times ``t`` ``(nb,)``.

    Attributes:
        q, qd, qdd: generalized coordinates and derivatives ``(nb, nq)``.
        x, xd, xdd: nodal coordinates and derivatives ``(nb, nx)``.
        e, ed: deformations and rates ``(nb, ne)``.
        quadratic: ``(D_xx xdot) xdot`` ``(nb, ne)``.
        elements: per element group, ``(xe, xde, xdde)`` each ``(nb, n, nc)``.
        jacobian: ``D_x`` at ``x`` (:class:`~flexmbd.assembly.SystemJacobian`).
        factor: the factorisation of ``D_c`` at ``x``.
    """

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    x: np.ndarray
    xd: np.ndarray
    xdd: np.ndarray
    e: np.ndarray
    ed: np.ndarray
    quadratic: np.ndarray
    elements: list
    jacobian: SystemJacobian
    factor: DenseFactor | SparseFactor | None


class EquationsOfMotion:
    """The reduced equations of a model with its prescribed motions and loads.

    Args:
        model: the mechanism (with mass and dynamic degrees of freedom).
        laws: one law per entry of ``q`` (only those of the inputs are used).
        forces: optional applied loads ``forces(t, x, xdot)``, see :data:`flexmbd.dynamics.Forces`.
        tolerance: Newton tolerance of the position solve [m, rad]; default
            ``1e-10`` times the model size.
        max_iterations: Newton iterations of a position solve before giving up.
    """

    def __init__(self, model: Model, laws: list[Law], forces: Forces | None = None,
                 tolerance: float | None = None, max_iterations: int = 25):
        self.model, self.asm = model, model.assembly
        self.input_laws = [laws[j] for j in self.asm.q_input]
        self.forces = forces
        self.tolerance = (RELATIVE_TOLERANCE * model.characteristic_length
                          if tolerance is None else float(tolerance))
        self.max_iterations = max_iterations
        self._regularity_limit = regularity_limit(model, self.tolerance)
        self._fixed_values = np.asarray(model.x0, dtype=float)[model.fixed]
        self.n_xm = len(model.independent_coordinates)
        self.constant_load = _constant_load(model)
        self.loaded = bool(np.any(self.constant_load))
        self.gravity = np.asarray(model.gravity, dtype=float)
        self.gravity_on = bool(np.any(self.gravity))
        self.prestressed = any(g.prestressed for g in self.asm.groups)
        self._law_for, self._law_matrix = None, None
        #: accelerations by the reduced equations (see :meth:`solve_accelerations`);
        #: measured on the slider-crank of 8 beams, 128 states: rigid elongations (16
        #: degrees of freedom, 36 saddle unknowns) 0.8 against 1.4 ms, flexible (24, 28)
        #: 1.2 against 1.0 ms
        self.reduced_accelerations = (not self.asm.sparse
                                      and 2 * len(self.asm.q_dynamic) <= self.asm.n_saddle)

    # --- q from the integrated state and the laws -------------------------------------------
    def compose(self, t: np.ndarray, q_d: np.ndarray, qd_d: np.ndarray,
                qdd_d: np.ndarray | None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Full ``q, qdot, qddot`` ``(nb, nq)`` from the dynamic entries ``(nb, nd)`` and the
        laws of the inputs at times ``t`` ``(nb,)``; ``qdd_d = None`` means zero."""
        nb, asm = len(t), self.asm
        out = np.zeros((3, nb, self.model.n_dof))
        if self.input_laws:
            values = np.array([[law(float(tk)) for law in self.input_laws] for tk in t])
            out[:, :, asm.take.q_input] = values.transpose(2, 0, 1)
        dynamic = asm.take.q_dynamic
        out[0][:, dynamic], out[1][:, dynamic] = q_d, qd_d
        if qdd_d is not None:
            out[2][:, dynamic] = qdd_d
        return out[0], out[1], out[2]

    # --- kinematics (THEORY 3, 4) -----------------------------------------------------------
    def factorize(self, jacobian: SystemJacobian, t: np.ndarray):
        """Factorise ``D_c``; raise at a singular configuration.

        The rows are scaled as in :func:`flexmbd.kinematics.partition_jacobian`, with the
        row norms of the reference configuration (:attr:`Assembly.constraint_row_scale`).
        """
        asm = self.asm
        if not len(asm.dependent):
            return None
        if asm.sparse:
            factor = SparseFactor(asm.sparse_constraint_pattern,
                                  asm.constraint_entries(jacobian.elements),
                                  asm.constraint_row_scale, asm.row_scale_columns)
        else:
            factor = DenseFactor.of_scaled(jacobian.scaled_constraint_matrix(),
                                           asm.constraint_unscale)
        if not factor.conditioning.min() > SINGULAR_RCOND:  # also NaN
            bad = np.flatnonzero(~(factor.conditioning > SINGULAR_RCOND))
            raise self._singular(jacobian, t, bad[0], "D_c is singular")
        return factor

    def _singular(self, jacobian: SystemJacobian, t, member: int, what: str
                  ) -> SingularConfigurationError:
        D_c = jacobian.member(member).constraint_matrix()[0]
        return singular_error(self.model, D_c, float(t[member]), what)

    def _deformations(self, elements: list[np.ndarray]) -> np.ndarray:
        return self.asm.per_deformation([g.type.deformations(xe, g.reference)
                                         for g, xe in zip(self.asm.groups, elements, strict=True)])

    def _deformations_and_jacobian(self, elements: list[np.ndarray]):
        """``e`` ``(nb, ne)``, ``D_x`` and the element geometry per group at ``elements``."""
        geometry = [g.type.geometry(xe, g.reference)
                    for g, xe in zip(self.asm.groups, elements, strict=True)]
        pairs = [g.type.deformations_and_features(xe, g.reference, shared)
                 for g, xe, shared in zip(self.asm.groups, elements, geometry, strict=True)]
        return (self.asm.per_deformation([e for e, _ in pairs]),
                SystemJacobian(self.asm, [f for _, f in pairs], geometry))

    def positions(self, t: np.ndarray, q: np.ndarray, guess: np.ndarray,
                  near: float | None = None, factor: DenseFactor | None = None):
        """Solve the position problem for every member of the batch (THEORY 3).

        Newton-Raphson from ``guess`` ``(nb, nx)``, whose ``D_c`` then serves for chord
        steps as long as they converge fast. Once the residual is below ``near`` [m, rad]
        (default: the tolerance), the Jacobian is evaluated there and one Newton step
        makes ``x`` accurate to second order in that residual. ``D_x`` is thus taken
        within ``near`` of the solution: a time integrator whose guesses are that good
        may pass a small share of the model size and solve with one evaluation of the
        Jacobian; ``D_x`` and the velocities are then accurate to about that relative
        size, far below the integrator's own error.

        ``factor``, a factorisation of ``D_c`` taken near ``guess`` (e.g. by the
        integrator, kept for the output pass), serves the chord steps instead of a new
        one at ``guess``; ``D_c`` is then factorised once, at the solution.

        Returns:
            ``(x, elements, jacobian, factor, e)``: coordinates ``(nb, nx)``, element
            coordinates per group, ``D_x`` and ``D_c`` factorised at ``x`` (to within
            the last step) and the deformations ``(nb, ne)``.
        """
        asm, model = self.asm, self.model
        x = np.array(guess, dtype=float)
        x[:, model.fixed] = self._fixed_values
        x[:, asm.take.q_coordinates] = q[:, :self.n_xm]
        target = np.zeros((len(t), len(asm.rows)))
        target[:, asm.n_rigid:] = q[:, self.n_xm:]
        near = self.tolerance if near is None else max(self.tolerance, near)
        elements = asm.element_values(x)
        previous = None
        if factor is None or not len(asm.dependent):
            e, jacobian = self._deformations_and_jacobian(elements)
            factor, fresh = self.factorize(jacobian, t), True
            if factor is None:  # no dependent coordinates: nothing to solve
                return x, elements, jacobian, factor, e
        else:  # D_c from near the guess: chord steps, then the Jacobian at the solution
            e, fresh = self._deformations(elements), False
        for iteration in range(self.max_iterations + 1):
            residual = e[:, asm.take.rows] - target
            norm = np.abs(residual).max(axis=1)
            if norm.max() <= near:
                break
            if not np.isfinite(norm).all() or iteration == self.max_iterations:
                raise self._not_converged(t, residual, norm, iteration)
            x[:, asm.take.dependent] -= factor.solve(residual)
            elements = asm.element_values(x)
            slow = previous is not None and np.any(norm > _SLOW_CHORD * previous)
            fresh, previous = slow, (None if slow else norm)
            if slow:  # the chord steps have stalled: a new D_c here
                e, jacobian = self._deformations_and_jacobian(elements)
                factor = self.factorize(jacobian, t)
            else:
                e = self._deformations(elements)
        if not fresh:  # the Jacobian at the last point
            e, jacobian = self._deformations_and_jacobian(elements)
            residual = e[:, asm.take.rows] - target
            norm = np.abs(residual).max(axis=1)
            factor = self.factorize(jacobian, t)
        limit = self._regularity_limit
        if factor.conditioning.min() < limit:
            weak = np.flatnonzero(factor.conditioning < limit)
            raise self._singular(
                jacobian, t, weak[0],
                f"D_c is singular within the position tolerance (scaled smallest singular "
                f"value {factor.conditioning[weak[0]]:.2g} < {limit:.2g})")
        if norm.max() > _ROUND_OFF * self.tolerance:
            change = np.zeros(x.shape)
            change[:, asm.take.dependent] = -factor.solve(residual)
            x += change
            # the deformations there, to first order (the rest is second order: negligible)
            e = e + jacobian.times(change)
            elements = asm.element_values(x)
        return x, elements, jacobian, factor, e

    def _not_converged(self, t, residual, norm, iteration) -> ConvergenceError:
        member = int(np.argmax(np.where(np.isfinite(norm), norm, np.inf)))
        r, time = residual[member], float(t[member])
        worst = (self.model.describe_deformation(self.asm.rows[int(np.argmax(np.abs(r)))])
                 if np.all(np.isfinite(r)) else "a non-finite configuration")
        return ConvergenceError(
            f"position solve did not converge at t = {time:.6g} s: residual "
            f"{norm[member]:.3g} after {iteration} iterations (tolerance {self.tolerance:.3g}), "
            f"largest in {worst}; the inputs may ask for a configuration the constraints "
            f"cannot reach (e.g. beyond an element's length) or the step from the previous "
            f"solution is too large", time, iterations=iteration, residual=float(norm[member]))

    def dependent_rates(self, rates: np.ndarray, jacobian: SystemJacobian, factor,
                        targets: np.ndarray, extra: np.ndarray | None = None) -> np.ndarray:
        """Fill the dependent entries of ``rates`` ``(nb, nx)`` (given on the independent
        coordinates, zero elsewhere) so that the constrained rows of ``D_x rates + extra``
        equal ``[0; targets]`` (THEORY 4); returns ``rates``."""
        asm = self.asm
        if factor is None:
            return rates
        rhs = -jacobian.constrained_times(rates)
        if extra is not None:
            rhs -= extra[:, asm.take.rows]
        rhs[:, asm.n_rigid:] += targets
        rates[:, asm.take.dependent] = factor.solve(rhs)
        return rates

    def kinematics(self, t, q, qd, qdd, guess, near: float | None = None,
                   factor: DenseFactor | None = None) -> State:
        """Positions, velocities and accelerations of a batch (see :class:`State` and
        :meth:`positions` for ``guess``, ``near`` and ``factor``)."""
        asm = self.asm
        x, elements, jacobian, factor, e = self.positions(t, q, guess, near, factor)
        xd = np.zeros(x.shape)
        xd[:, asm.take.q_coordinates] = qd[:, :self.n_xm]
        xd = self.dependent_rates(xd, jacobian, factor, qd[:, self.n_xm:])
        rates = asm.element_values(xd)
        # the velocity terms from the geometry of D_x, as accurate as D_x itself
        quadratic = asm.per_deformation([
            g.type.quadratic_velocity(xe, xde, g.reference, shared)
            for g, xe, xde, shared in zip(asm.groups, elements, rates, jacobian.geometry,
                                          strict=True)])
        xdd = np.zeros(x.shape)
        xdd[:, asm.take.q_coordinates] = qdd[:, :self.n_xm]
        xdd = self.dependent_rates(xdd, jacobian, factor, qdd[:, self.n_xm:], quadratic)
        groups = list(zip(elements, rates, asm.element_values(xdd), strict=True))
        return State(t, q, qd, qdd, x, xd, xdd, e, jacobian.times(xd), quadratic, groups,
                     jacobian, factor)

    # --- forces (THEORY 5-7) ----------------------------------------------------------------
    def stresses(self, state: State) -> np.ndarray:
        """Elastic stresses ``S e + C edot + sigma0`` ``(nb, ne)`` (zero on rigid and input
        deformations)."""
        asm = self.asm
        if not asm.sparse:
            return state.e @ asm.stiffness.T + state.ed @ asm.damping.T + asm.prestress
        sigma = np.zeros_like(state.e)
        for g in asm.groups:
            e, ed = state.e[:, g.deformations], state.ed[:, g.deformations]
            sigma[:, g.deformations] = ((g.stiffness @ e[..., None])[..., 0]
                                        + (g.damping @ ed[..., None])[..., 0] + g.prestress)
        return sigma

    def nodal_force(self, state: State, stresses: np.ndarray | None = None) -> np.ndarray:
        """``y = M xddot + h - f + D_x^T sigma`` ``(nb, nx)`` [N, N m] with the elastic
        stresses or ``stresses`` ``(nb, ne)``."""
        asm, nb = self.asm, len(state.t)
        whole_mass = asm.constant_mass is not None  # constant-mass inertia in one product
        loads = []
        for g, constant, (xe, xde, xdde), shared in zip(
                asm.groups, asm.constant_mass_blocks, state.elements, state.jacobian.geometry,
                strict=True):
            load = None
            if g.has_mass and not (whole_mass and constant is not None):
                load = g.type.inertia_force(xe, xde, xdde, g.reference, g.mass, g.lumped,
                                            shared)
            if g.has_mass and self.gravity_on:
                weight = g.type.gravity_load(xe, g.reference, g.mass, g.lumped, self.gravity)
                load = -weight if load is None else load - weight
            loads.append(load)
        y = asm.nodal_sum(loads, nb)
        y += state.jacobian.transpose_times(self.stresses(state) if stresses is None
                                            else stresses)
        if whole_mass:
            y += state.xdd @ asm.constant_mass  # symmetric
        elif len(asm.nodal_mass_coordinates):
            y[:, asm.nodal_mass_coordinates] += asm.nodal_mass_values * state.xdd[
                :, asm.nodal_mass_coordinates]
        if self.loaded:
            y -= self.constant_load
        if self.forces is not None:
            for k in range(nb):
                y[k] -= load_vector(self.model, self.forces, float(state.t[k]), state.x[k],
                                    state.xd[k])
        return y

    # --- accelerations from the saddle-point system -----------------------------------------
    def _mass_blocks(self, state: State) -> list[np.ndarray | None]:
        """Element mass matrices ``(nb, n, nc, nc)`` per group (``None`` without mass)."""
        blocks = []
        for g, constant, (xe, _, _) in zip(self.asm.groups, self.asm.constant_mass_blocks,
                                           state.elements, strict=True):
            if not g.has_mass:
                blocks.append(None)
            elif constant is None:
                blocks.append(g.type.mass_matrix(xe, g.reference, g.mass, g.lumped))
            else:
                blocks.append(np.broadcast_to(constant, (*xe.shape, xe.shape[-1])))
        return blocks

    def _solve_saddle(self, blocks, state: State, force: np.ndarray) -> np.ndarray:
        """``[[A, C^T], [C, 0]]^-1 [force_free; 0]`` per member ``(nb, ns)``."""
        asm = self.asm
        rhs = np.zeros((len(state.t), asm.n_saddle))
        rhs[:, :asm.n_free] = force[:, asm.free]
        elements = state.jacobian.elements
        try:
            if asm.sparse:
                factor = SparseFactor(asm.sparse_saddle_pattern,
                                      asm.sparse_saddle_entries(blocks, elements)[1],
                                      np.ones(asm.n_saddle), np.ones(asm.n_saddle))
                solution = factor.solve(rhs)
            else:
                solution = np.linalg.solve(asm.saddle_matrix(blocks, elements),
                                           rhs[..., None])[..., 0]
        except np.linalg.LinAlgError:
            solution = np.full_like(rhs, np.nan)
        bad = np.flatnonzero(~np.all(np.isfinite(solution), axis=1))
        if len(bad):
            raise self._massless(float(state.t[bad[0]]))
        return solution

    def _massless(self, time: float) -> SingularConfigurationError:
        dofs = ", ".join(self.model.describe_q(j) for j in self.asm.q_dynamic)
        return SingularConfigurationError(
            f"the reduced mass matrix of the dynamic degrees of freedom ({dofs}) is singular "
            f"at t = {time:.6g} s: give every dynamic degree of freedom mass or inertia", time)

    def dynamic_part(self, state: State, z: np.ndarray) -> np.ndarray:
        """``Q z`` ``(nb, nd)``: the dynamic entries of ``q``'s rate for a free-coordinate
        motion ``z`` ``(nb, n_free)`` (coordinates directly, deformations through ``D_x``)."""
        asm = self.asm
        motion = np.zeros((len(state.t), asm.nx))
        motion[:, asm.free] = z
        rates = state.jacobian.times(motion)
        return np.concatenate([motion[:, asm.dynamic_coordinates],
                               rates[:, asm.dynamic_deformations]], axis=1)

    def solve_accelerations(self, state: State, force: np.ndarray
                            ) -> tuple[np.ndarray, np.ndarray]:
        """Accelerations of a state evaluated at ``qddot_d = 0`` with nodal force ``force``.

        Returns ``(qdd_d, multipliers)``: the dynamic accelerations ``(nb, nd)`` and the
        saddle-point multipliers ``(nb, n_multipliers)`` (minus the stresses of the rigid
        and input deformations).

        Small models with at most half as many dynamic degrees of freedom as saddle-point
        unknowns (many rigid constraints) solve the reduced equations instead
        (:meth:`_reduced_accelerations`); otherwise the saddle-point system over the
        free coordinates and the multipliers is the smaller one.
        """
        asm = self.asm
        if self.reduced_accelerations and state.factor is not None:
            return self._reduced_accelerations(state, force)
        solution = self._solve_saddle(self._mass_blocks(state), state, force)
        z = solution[:, :asm.n_free]
        return -self.dynamic_part(state, z), solution[:, asm.n_free:]

    def _reduced_accelerations(self, state: State, force: np.ndarray
                               ) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`solve_accelerations` by the reduced equations ``F^T M F qdd_d = -F^T y0``
        (THEORY 7, ``F`` from :meth:`transfer`), then the multipliers from equilibrium:
        with ``y = y0 + M F qdd_d``, ``D_c^T w = y(c)`` and the multipliers are ``w`` on
        their rows (on the dynamic rows ``w`` vanishes, as the reduced residual does)."""
        asm, nb = self.asm, len(state.t)
        F = self.transfer(state)
        MF = self._mass_matrix(state) @ F
        reduced = F.swapaxes(-1, -2) @ MF
        try:
            qdd = -np.linalg.solve(reduced, (force[:, None, :] @ F).swapaxes(-1, -2))[..., 0]
        except np.linalg.LinAlgError:
            qdd = np.full((nb, F.shape[-1]), np.nan)
        bad = np.flatnonzero(~np.isfinite(qdd).all(axis=1))
        if len(bad):
            raise self._massless(float(state.t[bad[0]]))
        loads = force + (MF @ qdd[..., None])[..., 0]
        w = state.factor.solve_transposed(loads[:, asm.take.dependent])
        return qdd, w[:, asm.multiplier_rows]

    # --- everything a result holds -------------------------------------------------------
    def outputs(self, t: np.ndarray, q_d: np.ndarray, qd_d: np.ndarray, guesses: np.ndarray,
                factor: DenseFactor | None = None) -> dict[str, np.ndarray]:
        """The full dynamic state at a batch of times ``t`` ``(nb,)`` from the integrated
        ``q_d``, ``qdot_d`` ``(nb, nd)``, with position guesses ``(nb, nx)`` (and a
        factorisation of ``D_c`` near them, see :meth:`positions`).

        Returns arrays by name, each with a leading axis ``nb``: ``x, xd, xdd, e, ed,
        edd, q, qd, qdd`` as in :class:`~flexmbd.results.SimulationResult`; ``sigma``,
        the elastic stresses plus the constraint and actuator stresses of rigid and input
        deformations (THEORY 8); ``reactions``, the loads of supports and drives on fixed
        and input coordinates (zero elsewhere); ``driving``, the generalized force each
        prescribed entry of ``q`` needs (zero on dynamic entries, which move freely).
        """
        asm = self.asm
        q, qd, qdd = self.compose(t, q_d, qd_d, None)
        state = self.kinematics(t, q, qd, qdd, guesses, factor=factor)
        qdd_d, multipliers = self.solve_accelerations(state, self.nodal_force(state))
        qdd[:, asm.q_dynamic] = qdd_d
        xdd = np.zeros_like(state.x)
        xdd[:, asm.q_coordinates] = qdd[:, :self.n_xm]
        xdd = self.dependent_rates(xdd, state.jacobian, state.factor, qdd[:, self.n_xm:],
                                   state.quadratic)
        state.xdd = xdd
        state.elements = [(xe, xde, xdde) for (xe, xde, _), xdde in
                          zip(state.elements, asm.element_values(xdd), strict=True)]
        sigma = self.stresses(state)
        sigma[:, asm.multipliers] = -multipliers
        # nodal equilibrium with every stress: what remains are support and drive loads
        loads = self.nodal_force(state, sigma)
        supported = np.concatenate([self.model.fixed, self.model.input_coordinates])
        reactions = np.zeros_like(loads)
        reactions[:, supported] = loads[:, supported]
        driving = np.zeros_like(q)
        q_inputs = asm.q_input
        driving[:, q_inputs[q_inputs < self.n_xm]] = loads[:, self.model.input_coordinates]
        driving[:, q_inputs[q_inputs >= self.n_xm]] = -sigma[:, asm.input_deformations]
        return {"x": state.x, "xd": state.xd, "xdd": xdd, "e": state.e, "ed": state.ed,
                "edd": state.jacobian.times(xdd) + state.quadratic, "q": q, "qd": qd,
                "qdd": qdd, "sigma": sigma, "reactions": reactions, "driving": driving}

    # --- the residual of the reduced equations and the Newton matrix of an integrator -----
    def reduced_residual(self, state: State, force: np.ndarray) -> np.ndarray:
        """``R = F_q^T y`` on the dynamic entries of ``q`` ``(nb, nd)`` for the nodal force
        ``y`` ``(nb, nx)``: zero when the state solves the equations of motion.

        With ``w = D_c^-T y(c)`` on the constrained deformations, ``F_q^T y`` is ``y -
        (D_x^T w)`` on the independent coordinates and ``w`` on ``e(m)`` (THEORY 4).
        """
        asm = self.asm
        w = np.zeros((len(state.t), asm.ne))
        if state.factor is not None:
            w[:, asm.take.rows] = state.factor.solve_transposed(force[:, asm.take.dependent])
        if not len(asm.dynamic_coordinates):
            return w[:, asm.take.dynamic_deformations]
        pulled = state.jacobian.transpose_times(w)
        return np.concatenate([(force - pulled)[:, asm.dynamic_coordinates],
                               w[:, asm.take.dynamic_deformations]], axis=1)

    def iteration_operator(self, state: State, c_q: float, c_v: float
                           ) -> Callable[[np.ndarray], np.ndarray]:
        """The Newton correction of an implicit integrator at a single state.

        For an integrator whose ``q`` and ``qdot`` move by ``c_q`` and ``c_v`` times a
        change of ``qddot`` (e.g. generalized-alpha: ``beta h^2`` and ``gamma h``), the
        Newton matrix of ``R`` (:meth:`reduced_residual`) is ``S = Mbar + c_q K + c_v C``
        on the dynamic entries of ``q``. Returns ``op`` with ``op(R) = -S^-1 R``
        ``(1, nd) -> (nd,)``. The geometric stiffness ``sum sigma_i D_xx,i`` is
        included for pre-stressed elements only; elsewhere it is smaller than ``D^T S
        D`` by the order of the strains. Left out, as of order ``h`` relative to
        ``Mbar``, are the velocity terms of the inertia (gyroscopic and centrifugal)
        and the geometric stiffness of the constraint stresses: the Newton iteration
        converges with them missing, and a linearly implicit method keeps its order
        (see :mod:`flexmbd.generalized_alpha`).

        Small models form ``S = F^T A F + G^T (c_q S + c_v C) G`` with the transfer
        function ``F`` (:meth:`transfer`), ``G = D_x F`` and ``A`` the mass matrix
        (plus ``c_q`` times the geometric stiffness), assembled from the few mass
        features of the elements whose mass varies (:meth:`Assembly.mass_matrix`);
        large ones never form ``F`` and
        solve the saddle-point system with ``A = M + c_q (D^T S D + sum sigma_i
        D_xx,i) + c_v D^T C D`` instead (``S^-1 R = Q z`` for the right-hand side
        ``Q^T R``), whose cost grows linearly with the number of elements.
        """
        if self.asm.sparse:
            return self._saddle_operator(state, c_q, c_v)
        asm = self.asm
        A = self._mass_matrix(state)
        if self.prestressed:
            A = A + asm.coordinate_matrix(
                self._stiffness_blocks(state, c_q, c_v, elastic=False, mass=False),
                len(state.t))
        F = self.transfer(state)
        G = state.jacobian.dense @ F
        law = self._law(c_q, c_v)
        S = np.swapaxes(F, -1, -2) @ A @ F + np.swapaxes(G, -1, -2) @ law @ G
        inverse = np.linalg.inv(S[0])
        return lambda residual: -(inverse @ residual[0])

    def _mass_matrix(self, state: State) -> np.ndarray:
        """The dense mass matrix ``(nb, nx, nx)`` at the state's coordinates (small
        models), from the mass features of the elements whose mass varies; at ``x``
        itself, not at the nearby point of ``D_x``'s geometry, so that it is the matrix
        of the element kernels (and of the sparse forms)."""
        asm = self.asm
        return asm.mass_matrix([g.type.mass_features(xe, g.reference)
                                for g, (xe, _, _) in zip(asm.groups, state.elements, strict=True)
                                if g in asm.varying_mass_groups], len(state.t))

    def _law(self, c_q: float, c_v: float) -> np.ndarray:
        """``c_q S + c_v C`` ``(ne, ne)`` of the whole model, kept while the step is."""
        if self._law_for != (c_q, c_v):
            self._law_for = (c_q, c_v)
            self._law_matrix = c_q * self.asm.stiffness + c_v * self.asm.damping
        return self._law_matrix

    def transfer(self, state: State) -> np.ndarray:
        """``F_d`` ``(nb, nx, nd)``: the motion of every coordinate per unit motion of each
        dynamic entry of ``q`` with the inputs held, the dynamic columns of ``F_q``
        (THEORY 4), from the inverse of ``D_c`` (small models only)."""
        asm, nb = self.asm, len(state.t)
        n_coord, nd = len(asm.dynamic_coordinates), len(asm.q_dynamic)
        F = np.zeros((nb, asm.nx, nd))
        if n_coord:
            F[:, asm.dynamic_coordinates, np.arange(n_coord)] = 1.0
        if state.factor is None:
            return F
        # D_c x(c) = [0; e(m)] - D_m x(m) on the constrained rows
        inverse = state.factor.inverse
        F[:, asm.dependent, n_coord:] = inverse[:, :, asm.take.dynamic_deformation_rows]
        if n_coord:
            D_m = state.jacobian.dense[:, asm.rows][:, :, asm.dynamic_coordinates]
            F[:, asm.dependent, :n_coord] = -(inverse @ D_m)
        return F

    def _stiffness_blocks(self, state: State, c_q: float, c_v: float, elastic: bool,
                          mass: bool = True) -> list[np.ndarray | None]:
        """Element matrices ``M + c_q sum sigma_i D_xx,i`` (pre-stressed groups) and, with
        ``elastic``, ``+ c_q D^T S D + c_v D^T C D`` ``(nb, n, nc, nc)`` per group
        (``M`` as in :meth:`_mass_blocks`, left out without ``mass``; ``None`` = none)."""
        asm = self.asm
        blocks = self._mass_blocks(state) if mass else [None] * len(asm.groups)
        sigma = self.stresses(state) if self.prestressed else None
        for k, (g, (xe, _, _), jac) in enumerate(zip(asm.groups, state.elements,
                                                     state.jacobian.elements, strict=True)):
            stiffness = None
            if elastic and g.is_elastic:
                law = c_q * g.stiffness + c_v * g.damping if g.damped else c_q * g.stiffness
                stiffness = np.swapaxes(jac, -1, -2) @ law @ jac
            if g.prestressed:
                # geometric stiffness sum sigma_i D_xx,i: the whole stiffness of a
                # pre-stressed string; elsewhere only of the order of the strains
                geometric = c_q * np.einsum("bnd,bndij->bnij", sigma[:, g.deformations],
                                            g.type.hessian(xe, g.reference))
                stiffness = geometric if stiffness is None else stiffness + geometric
            if stiffness is not None:
                blocks[k] = stiffness if blocks[k] is None else blocks[k] + stiffness
        return blocks

    def _saddle_operator(self, state: State, c_q: float, c_v: float):
        """:meth:`iteration_operator` of a large model, by the sparse saddle-point system."""
        asm = self.asm
        elements = state.jacobian.elements
        blocks = self._stiffness_blocks(state, c_q, c_v, elastic=True)
        Q = asm.dynamic_rows(elements)[0]  # sparse in its columns: products stay linear
        factor = SparseFactor(asm.sparse_saddle_pattern,
                              asm.sparse_saddle_entries(blocks, elements)[1],
                              np.ones(asm.n_saddle), np.ones(asm.n_saddle))

        def op(residual):
            rhs = np.zeros((1, asm.n_saddle))
            rhs[0, :asm.n_free] = residual[0] @ Q
            return -(Q @ factor.solve(rhs)[0, :asm.n_free])
        return op


def _constant_load(model: Model) -> np.ndarray:
    """Constant nodal loads and the weight of point masses ``(nx,)`` [N, N m]."""
    f = np.zeros(model.n_coordinates)
    for number, load in model.nodal_forces.items():
        f[list(model.nodes[number].coordinates)] += load
    gravity = np.asarray(model.gravity, dtype=float)
    for number, mass in model.nodal_masses.items():
        node = model.nodes[number]
        if node.kind == "translational":
            f[list(node.coordinates)] += mass * gravity
    return f
