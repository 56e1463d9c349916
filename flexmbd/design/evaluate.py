"""``evaluate``: a design's outputs at the last load step, with their exact gradients.

The analysis is the public one (:func:`~flexmbd.static_equilibrium` over the load steps
of the build's settings, then the linearized analyses at the last step). The gradients
come from one factorisation of the engine's banded tangent at that equilibrium
(:mod:`flexmbd.design.state`): the direct method, one solve for all parameters, and the
outputs' own exact derivatives (:mod:`flexmbd.design.outputs`).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from ..analysis.linearization import turning_moments
from ..analysis.statics import StaticResult, static_equilibrium
from ..builder.recording import kept_releases
from ..errors import ArgumentError
from ..orientation import euler_forces
from ..summary import clip
from .data import DATA_STEP, STENCIL, build_design, data_change, rate
from .elements import (
    Change,
    constraint_change,
    force_change,
    internal_force,
    stacked,
    tangent_change,
)
from .outputs import Evaluator, Output, Sensitivity, moment_loads, parse
from .state import Equilibrium

__all__ = ["DesignResult", "evaluate"]


@dataclass(frozen=True, eq=False)
class DesignResult:
    """A design's outputs.

    Attributes:
        params: the design parameters, by name.
        values: each output's value at the last load step, by name (units as the output's:
            Hz, m, Pa, ...).
        gradient: ``gradient[output][param]``, the derivative of the output to the
            parameter (per unit of the parameter); ``None`` without ``gradient=True``.
        statics: the static analysis.
        notes: what the evaluation noticed (a maximum with competing points, ...).
        wall: wall times [s]: ``"analysis"`` (build, statics, outputs) and
            ``"gradient"``.
    """

    params: dict[str, float]
    values: dict[str, float]
    gradient: dict[str, dict[str, float]] | None
    statics: StaticResult
    notes: list[str] = field(default_factory=list)
    wall: dict[str, float] = field(default_factory=dict)

    def __repr__(self) -> str:
        lines = [f"DesignResult at {self.params}"]
        for name, value in self.values.items():
            grad = "" if self.gradient is None else ", d/d: " + ", ".join(
                f"{p} {g:.6g}" for p, g in self.gradient[name].items())
            lines.append(f"  {name} = {value:.10g}{grad}")
        lines += [f"  note: {note}" for note in self.notes]
        return clip("\n".join(lines))

    __str__ = __repr__


def _checked_params(params) -> dict[str, float]:
    if not isinstance(params, Mapping) or not params:
        raise ArgumentError("params", "must be a dict of parameter names and numbers, e.g. "
                                      "{'t': 0.5e-3}")
    out = {}
    for name, value in params.items():
        if not isinstance(name, str):
            raise ArgumentError("params", f"names are strings, got {name!r}")
        if isinstance(value, bool) or not isinstance(value, (int, float, np.floating,
                                                             np.integer)) \
                or not math.isfinite(value):
            raise ArgumentError("params", f"{name!r} must be a finite number, got {value!r}")
        out[name] = float(value)
    return out


def _outputs(outputs) -> list[Output]:
    names = [outputs] if isinstance(outputs, str) else outputs
    if not isinstance(names, Sequence) or not names:
        raise ArgumentError("outputs", "give an output name or a list of them, e.g. "
                                       "['f1', 'C[9,10][5,5]']")
    parsed = [parse(name) for name in names]
    seen = set()
    for out in parsed:
        if out.name in seen:
            raise ArgumentError("outputs", f"{out.name!r} is named twice")
        seen.add(out.name)
    return parsed


class Design:
    """One design's analysis and, on demand, its state's sensitivities."""

    def __init__(self, build: Callable, params: dict[str, float]):
        self.build, self.params = build, params
        self.nominal = build_design(build, params)
        self.model = self.nominal.model
        settings = self.nominal.settings
        self.statics = static_equilibrium(
            self.model, load_increment=dict(settings.load_increment) or None,
            input_increment=dict(settings.input_increment) or None,
            steps=settings.load_steps, tolerance=settings.tolerance, progress=False)
        self.lin = self.statics.linearization(-1)
        self.x, self.sigma = self.statics.x[-1], self.statics.sigma[-1]

    # --- the state's sensitivities ----------------------------------------------------------
    def sensitivities(self) -> list[Sensitivity]:
        """``dz/dtheta`` for every parameter: the data either side, then one solve."""
        statics = self.statics
        assert statics.q is not None and statics.applied is not None   # a static result's
        state = self.state = Equilibrium(self.model, self.x, statics.q[-1], self.sigma,
                                         statics.applied[-1])
        self.sides, changes, sens = [], [], []
        for name, value in self.params.items():
            h = DATA_STEP * (abs(value) if value else 1.0)
            sides = tuple(build_design(self.build, {**self.params, name: value + k * h},
                                       neighbour=True) for k, _ in STENCIL)
            change, engines = data_change(state, self.nominal, sides, h, name)
            self.sides.append(sides)
            changes.append(change)
            sens.append(Sensitivity(name, h, change, np.empty(0), np.empty(0), engines))
        rhs = -np.column_stack([state.residual_change(c) for c in changes])
        dz = state.solve(rhs, refine=True)
        nc = len(state.constrained)
        self.dx = np.empty((len(sens), self.model.n_coordinates))
        self.dmu = np.empty((len(sens), nc))
        self.changes: list[Change] = []
        self.data = changes
        for n, s in enumerate(sens):
            s.dx, s.dmu = state.full(dz[:, n], changes[n].x_held)
            self.dx[n], self.dmu[n] = s.dx, s.dmu
            dsigma = np.array(changes[n].dsigma0, dtype=float)
            dsigma[state.constrained] += s.dmu
            self.changes.append(Change(u=s.dx, dp=changes[n].dp, dlaw=changes[n].dlaw,
                                       dsigma=dsigma))
        self.all_changes = stacked(self.changes)
        self.forces, de, dsigma = force_change(state.groups, self.x, self.sigma,
                                               self.all_changes, state.elastic_def, state.ne)
        self.de, self.dsigma = de.T, dsigma.T
        self.sens = sens
        return sens

    def tangent_changes(self, left: np.ndarray, right: np.ndarray, nu_left: np.ndarray,
                        nu_right: np.ndarray, geometric_weight: np.ndarray) -> np.ndarray:
        """``[l_q; nu_l,q]^T dA [r_q; nu_r,q]`` ``(Q, k_params)`` for the columns of
        ``left``, ``right`` ``(nx, Q)`` and their constraint parts ``(nc, Q)``: the
        bordered tangent's change along each parameter's change of state and data; the
        geometric stiffness (stresses and the load stiffness) weighted by
        ``geometric_weight`` ``(Q,)``. All pairs in one evaluation of the elements."""
        state, c = self.state, self.state.constrained
        weight = np.asarray(geometric_weight, dtype=float)
        value = tangent_change(state.groups, self.x, self.sigma, self.all_changes,
                               state.elastic_def, left, right, weight)
        value += np.einsum("cq,cqP->qP", nu_left, constraint_change(
            state.groups, self.x, self.all_changes, right, state.ne)[c])
        value += np.einsum("cq,cqP->qP", nu_right, constraint_change(
            state.groups, self.x, self.all_changes, left, state.ne)[c])
        for n in range(len(self.changes)):
            for at in state.engine.rotation_coordinates:   # the load stiffness -df/dx
                dM = self.data[n].df[at[1:]]                 # a global moment's change
                value[:, n] -= weight * np.array([
                    left[at, q] @ euler_forces(right[at, q], dM) for q in range(len(weight))])
            value[:, n] -= weight * self.gravity_changes(n, left, right)
        return value

    def gravity_changes(self, n: int, left: np.ndarray, right: np.ndarray) -> np.ndarray:
        """``l_q^T d(dg/dx) r_q`` ``(Q,)`` for the columns of ``left``, ``right`` ``(nx, Q)``
        along parameter ``n``'s change: the turning weight's load stiffness, on the
        designs around at the state moved alike (the data's central differences); zero
        without gravity on element masses."""
        state, s = self.state, self.sens[n]
        if not (np.any(state.spec.loads.gravity) and np.any(state.spec.elements.emass)):
            return np.zeros(left.shape[1])
        values = [np.einsum("iq,iq->q", left, np.column_stack([
            state.gravity_times(r, self.x + k * s.h * s.dx, engine) for r in right.T]))
            for (k, _), engine in zip(STENCIL, s.engines, strict=True)]
        return rate(values, s.h)

    def mass_changes(self, left: np.ndarray, right: np.ndarray) -> np.ndarray:
        """``l_q^T dM r_q`` ``(Q, k_params)`` for the columns of ``left``, ``right``
        ``(nx, Q)``: the mass's change along each parameter's change (the data's central
        differences, on the designs around, at the state moved alike)."""
        out = np.empty((left.shape[1], len(self.sens)))
        for n, s in enumerate(self.sens):
            masses = [np.einsum("iq,ij,jq->q", left, engine.mass(self.x + k * s.h * s.dx)[0],
                                right)
                      for (k, _), engine in zip(STENCIL, s.engines, strict=True)]
            out[:, n] = rate(masses, s.h)
        return out

    def bordered_mode(self, phi: np.ndarray, omega2: float, transposed: bool = False
                      ) -> np.ndarray:
        """The constraint stresses ``nu`` ``(nc,)`` of a mode ``phi`` ``(nx,)`` on the
        bordered tangent, ``A [phi; nu] = omega^2 [M phi; 0]`` (``A^T`` for a left mode):
        one solve."""
        state = self.state
        m_phi = state.engine.mass(self.x)[0] @ phi
        rhs = np.concatenate([omega2 * m_phi[state.free], np.zeros(len(state.constrained))])
        return state.solve(rhs[:, None], transposed)[len(state.free):, 0]

    def buckling_border(self, phi: np.ndarray, factor: float) -> np.ndarray:
        """The constraint stresses ``nu`` ``(nc,)`` of a buckled shape ``phi`` ``(nx,)``:
        ``(K0 + lambda G0) phi + D_c^T nu = 0`` on the free coordinates with the symmetric
        part of ``G0``, as :func:`~flexmbd.buckling` pairs them (least squares on
        ``D_c^T``, with exact products)."""
        state = self.state
        still = [np.zeros_like(g.param) for g in state.groups]
        laws = [np.zeros_like(g.S) for g in state.groups]
        along = Change(u=phi, dp=still, dlaw=laws, dsigma=np.zeros(state.ne))
        total, _, _ = force_change(state.groups, self.x, self.sigma, along,
                                   state.elastic_def, state.ne)
        elastic, _, _ = force_change(state.groups, self.x, np.zeros(state.ne), along,
                                     state.elastic_def, state.ne)
        for at, block in turning_moments(state.engine, state.loads):   # the symmetric part
            total[at] -= 0.5 * (block + block.T) @ phi[at]
        total -= 0.5 * (state.gravity_times(phi) + state.gravity_times(phi, transposed=True))
        product = elastic + factor * (total - elastic)
        _, _, D = internal_force(state.groups, self.x, self.sigma, state.ne)
        c, free = state.constrained, state.free
        return np.linalg.lstsq(D[np.ix_(c, free)].T, -product[free], rcond=None)[0]

    def left_mode(self, shape: np.ndarray, omega2: float) -> np.ndarray:
        """The left eigenvector ``psi`` ``(nd,)`` over the dynamic entries of ``q`` of the
        mode ``shape`` ``(nd,)``: ``(K^T - omega^2 M) psi = 0``. A global moment's load
        stiffness makes ``K`` unsymmetric, and an eigenvalue's derivative is then
        ``psi^T (dK - omega^2 dM) phi / psi^T M phi``; a symmetric ``K`` has ``psi = phi``.
        Two steps of inverse iteration on the transposed pencil, shifted to the value."""
        K, M = self.lin.block("K"), self.lin.block("M0")
        if np.abs(K - K.T).max() <= 1e-14 * np.abs(K).max():
            return shape
        pencil = (K - omega2 * (1.0 + 1e-10) * M).T   # not singular to the last digit
        psi = shape
        for _ in range(2):
            psi = np.linalg.solve(pencil, M @ psi)
            psi /= np.linalg.norm(psi)
        return psi

    def unit_loads(self, node: int, rot: int | None) -> np.ndarray:
        """The unit loads of :func:`~flexmbd.node_compliance` ``(nx, m)``: forces on the
        node's coordinates, then moments on the rotational node (their generalized
        forces on its Euler parameters in space)."""
        model = self.model
        columns = []
        for i in model.nodes[node].coordinates:
            t = np.zeros(model.n_coordinates)
            t[i] = 1.0
            columns.append(t)
        if rot is not None:
            at = list(model.nodes[rot].coordinates)
            if len(at) == 4:
                for axis in range(3):
                    t = np.zeros(model.n_coordinates)
                    t[at] = moment_loads(self.x[at])[:, axis]
                    columns.append(t)
            else:
                t = np.zeros(model.n_coordinates)
                t[at[0]] = 1.0
                columns.append(t)
        return np.column_stack(columns)

    def unit_load_changes(self, node: int, rot: int | None) -> np.ndarray:
        """The change of :meth:`unit_loads` ``(k_params, nx, m)``: a moment's generalized
        force turns with the node."""
        T = self.unit_loads(node, rot)
        out = np.zeros((len(self.sens), *T.shape))
        if rot is not None and len(self.model.nodes[rot].coordinates) == 4:
            at = list(self.model.nodes[rot].coordinates)
            width = len(self.model.nodes[node].coordinates)
            for n in range(len(self.sens)):
                out[n][np.ix_(at, range(width, width + 3))] = moment_loads(self.dx[n][at])
        return out

    def bordered_solve(self, T: np.ndarray, transposed: bool) -> tuple[np.ndarray, np.ndarray]:
        """``A^-1 [T; 0]`` (``A^-T``) as coordinate changes ``(nx, m)`` (zero on the held
        ones) and constraint stresses ``(nc, m)``."""
        state = self.state
        rhs = np.vstack([T[state.free], np.zeros((len(state.constrained), T.shape[1]))])
        z = state.solve(rhs, transposed)
        W = np.zeros_like(T)
        W[state.free] = z[:len(state.free)]
        return W, z[len(state.free):]

    def reaction_changes(self) -> np.ndarray:
        """The change of the reactions ``(k_params, nx)`` (the result's ``f`` columns:
        ``D_x^T sigma - f`` on the held coordinates)."""
        state = self.state
        return np.array([self.forces[:, n] - state.load_change(self.x, data.df)
                         - data.dweight for n, data in enumerate(self.data)])


def evaluate(build: Callable, params: Mapping[str, float], outputs, gradient: bool = True
             ) -> DesignResult:
    """A design's outputs at the last load step of its static analysis, with their exact
    derivatives to the design parameters.

    Args:
        build: ``build(**params)`` returns a :class:`~flexmbd.Model`, or ``(model,
            RunSettings)`` with the run's ``load_increment``, ``input_increment`` and
            ``load_steps`` (as :func:`~flexmbd.sweep`'s case functions do). A parameter
            may change numbers only (positions, sections, materials, masses, loads), not
            the model's structure.
        params: the design, ``{name: value}``.
        outputs: an output name or a list of them: a result column (``"x10.3"``,
            ``"e4.2"``, ``"sig4.2"``, the reaction ``"f1.2"``), ``"f<k>"`` (the k-th
            frequency [Hz]), ``"buckling<k>"``, ``"C[<node>,<rot>][i,j]"`` (an entry of
            :func:`~flexmbd.node_compliance` in global axes), ``"stress_max"`` (the
            largest von Mises stress over the beams with a section [Pa]) or
            ``"stress_ks"`` (its Kreisselmeier-Steinhauser aggregate, :data:`KS_RHO`).
        gradient: also the derivatives (:mod:`flexmbd.design.outputs` says how).

    Returns:
        :class:`DesignResult`: ``values[name]``, ``gradient[name][param]``.

    Raises:
        ArgumentError: an unknown output, a bad parameter, a build that fails or changes
            the structure with a parameter, a repeated frequency's gradient.
        ConvergenceError: the static analysis did not converge.

    Examples:
        A cantilever's tip deflection and its derivative to the bending stiffness
        (``-P L^3 / (3 EI^2)``):

        >>> import flexmbd as fm
        >>> from flexmbd import design
        >>> def cantilever(EI):
        ...     b = fm.ModelBuilder("cantilever")
        ...     for k in range(5):
        ...         _ = b.add_node(2 * k + 1, 0.25 * k, 0.0)
        ...     for k in range(4):
        ...         _ = (b.add_beam(k + 1, 2 * k + 1, 2 * k + 2, 2 * k + 3, 2 * k + 4)
        ...              .dynamic_deformation(k + 1).set_mass(k + 1, 0.5)
        ...              .set_stiffness(k + 1, axial=1e6, bending=EI))
        ...     return b.fix(1).fix(2).build(), fm.RunSettings(
        ...         load_increment={"x9.2": -1e-3}, load_steps=1)
        >>> r = design.evaluate(cantilever, {"EI": 2.0}, "x9.2")
        >>> print(f"{r.gradient['x9.2']['EI']:.6e}  closed form {1e-3 / (3 * 2.0**2):.6e}")
        8.333333e-05  closed form 8.333333e-05
    """
    values = _checked_params(params)
    wanted = _outputs(outputs)
    start = time.perf_counter()
    with kept_releases():   # one structure for the design and its neighbours
        design = Design(build, values)
        evaluator = Evaluator(design)
        results = {out.name: evaluator.value(out) for out in wanted}
        analysed = time.perf_counter()
        grads: dict[str, dict[str, float]] | None = None
        notes: list[str] = []
        if gradient:
            sens = design.sensitivities()
            found, notes = evaluator.gradients(wanted, sens)
            grads = {name: {s.name: float(v) for s, v in zip(sens, g, strict=True)}
                     for name, g in found.items()}
    done = time.perf_counter()
    return DesignResult(values, results, grads, design.statics, notes,
                        {"analysis": analysed - start, "gradient": done - analysed})

