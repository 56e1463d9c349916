"""The energy of a motion, row by row: kinetic, elastic and gravitational (THEORY 5, 6).

* kinetic: ``1/2 xdot^T M(x) xdot`` with the engine's mass matrix (consistent and lumped
  element masses, point masses, rotary inertia);
* elastic: ``1/2 e^T S e + sigma0^T e`` over the deformations that carry the elastic law;
* gravitational: ``-m g . r`` of every mass: an element's consistent mass integrated
  over its material point (:meth:`~flexmbd.elements.base.ElementType.material_point`,
  Gauss-Legendre with enough points for its cubic shape), lumped and point masses at
  their nodes (rotary inertia has no weight).

Their sum stays constant in a motion that nothing drives, damps or loads otherwise (no
prescribed inputs that move, no damping, no applied loads besides gravity): its drift is
the integrator's error, the check of a simulation. Otherwise it changes by the work of
the drives and the loads less what damping takes out (:mod:`flexmbd.analysis.work`), and
the balance of the two is that check.
"""

from __future__ import annotations

import numpy as np

from ..elements.base import is_translational
from ..engine import workspace_of
from ..engine.laws import Forces
from ..errors import ArgumentError
from ..results import KinematicResult, SimulationResult
from ..summary import Columns
from .integrate import RTOL
from .statics import StaticResult
from .work import warn_if_unresolved, work_done

__all__ = ["energy"]

#: Gauss-Legendre points over [0, 1] for the weight of a material point: exact for its
#: cubic (Hermite) shape, and to rounding for the small rotations within an element
_POINTS, _WEIGHTS = np.polynomial.legendre.leggauss(6)
_POINTS, _WEIGHTS = 0.5 * (_POINTS + 1.0), 0.5 * _WEIGHTS


def energy(result: KinematicResult, forces: Forces | None = None) -> Columns:
    """The energies of a result's rows and the work done on it [J]: columns ``t``,
    ``kinetic``, ``elastic``, ``gravity`` and ``total``, each ``(nt,)``; for a simulation
    or an inverse-dynamics run (not load steps, whose rows are no motion in time) also,
    from its first row:

    * ``input_work``: the work of the drives, ``int tau . qdot dt`` over the prescribed
      entries of ``q`` (a driven crank's torque times its speed, an actuator's force
      times its stroke rate);
    * ``load_work``: the work of the applied loads besides gravity, the model's constant
      ones and the run's ``forces(t, x, xdot)`` (a force against its node's velocity, a
      moment against its node's angular velocity);
    * ``dissipated``: the energy damping took out, ``int edot^T C edot dt`` (>= 0);
    * ``balance``: ``total - total[0] - input_work - load_work + dissipated``, zero but
      for the integrator's error.

    The works are integrals over the output rows (Simpson's rule), so the balance checks
    the integrator only where the rows resolve the power: give output times as dense as
    the motion's fastest visible vibration. Where the quadrature's own error (estimated
    from the rule over every other row) is a tenth of the balance or more, and more
    than the integrator's ``rtol`` of the largest energy, an
    :class:`~flexmbd.AccuracyWarning` says so.

    Args:
        result: a run with velocities (``outputs`` ``"all"``, or ``"velocities"`` when its
            drives do not move).
        forces: the function the run applied besides the model's loads; by default the
            one the run kept (:attr:`~flexmbd.results.SimulationResult.applied_forces`).

    Raises:
        ArgumentError: the result has no velocities (``simulate(..., outputs=
            "positions")``) or no deformations, or its drives move and it has no driving
            loads.

    Examples:
        A free swing keeps its energy to the integrator's accuracy:

        >>> import numpy as np
        >>> import flexmbd as fm
        >>> pendulum = (fm.ModelBuilder("pendulum").add_node(1, 0, 0).add_node(3, 0, -1)
        ...             .add_rigid_beam(1, 1, 2, 3).set_mass(1, 1.0).fix(1)
        ...             .dynamic_coordinate(2).set_gravity(0, -9.81).build())
        >>> run = fm.simulate(pendulum, np.linspace(0.0, 1.0, 11), initial={"x2.1": (0.1, 0.0)},
        ...                   rtol=1e-10, atol=1e-12)
        >>> energy = fm.energy(run)
        >>> bool(np.ptp(energy["total"]) < 1e-8 * energy["kinetic"].max())
        True
    """
    if not isinstance(result, KinematicResult):
        raise ArgumentError("result", f"must be a simulation or kinematic result, got "
                                      f"{type(result).__name__}")
    if result.xd is None or result.e is None:
        raise ArgumentError("result", "has no velocities or deformations: simulate with "
                                      "outputs='all' (the default) or 'velocities'")
    model, x, xd = result.model, np.asarray(result.x), np.asarray(result.xd)
    engine = workspace_of(model)
    kinetic = np.array([0.5 * v @ engine.mass(row)[0] @ v for row, v in zip(x, xd,
                                                                            strict=True)])
    e = np.asarray(result.e)
    stress = engine.assembly.law_times("S", e.T).T             # S e, (nt, ne)
    elastic = np.sum(0.5 * e * stress + engine.compiled.elements.sigma0 * e, axis=1)
    columns = Columns({"t": np.asarray(result.t, dtype=float), "kinetic": kinetic,
                       "elastic": elastic, "gravity": _weight(model, engine, x)})
    columns["total"] = columns["kinetic"] + columns["elastic"] + columns["gravity"]
    if isinstance(result, SimulationResult) and not isinstance(result, StaticResult):
        done = work_done(result, engine.assembly,
                         result.applied_forces if forces is None else forces)
        columns.update(input_work=done.inputs, load_work=done.loads,
                       dissipated=done.dissipated)
        columns["balance"] = (columns["total"] - columns["total"][0] - done.inputs
                              - done.loads + done.dissipated)
        scale = float(np.max(np.abs([kinetic, elastic, columns["gravity"]]), initial=0.0))
        warn_if_unresolved(done.error, columns["balance"], scale,
                           result.stats.get("rtol", RTOL))
    return columns


def _weight(model, engine, x: np.ndarray) -> np.ndarray:
    """``-sum m g . r`` at every row of ``x`` ``(nt, nx)``: consistent element masses over
    their material points, and the masses the engine puts on coordinates (lumped element
    masses, point masses) times gravity along those coordinates."""
    gravity = np.zeros(3)
    gravity[:len(model.gravity)] = model.gravity
    out = np.zeros(len(x))
    if not np.any(gravity):
        return out
    spec = engine.compiled.elements
    width = len(model.gravity)
    for k, (_, element) in enumerate(sorted(model.elements.items())):
        if spec.emass[k]:
            c = [x[:, i] for i in element.coordinates]
            p = list(element.reference)
            height = sum(w * np.dot(gravity[:width], np.array(
                element.type.material_point(c, p, xi, np), dtype=float).reshape(width, -1))
                for xi, w in zip(_POINTS, _WEIGHTS, strict=True))
            out -= spec.emass[k] * height
    # per coordinate: its mass on it, and gravity along it (zero off translational nodes,
    # so rotary inertia has no weight)
    on_coordinates = np.array(engine.compiled.loads.nodal_mass, dtype=float)
    np.add.at(on_coordinates, spec.c_idx, spec.lumped_diag)
    along = np.zeros(model.n_coordinates)
    for node in model.nodes.values():
        if is_translational(node.kind):
            along[list(node.coordinates)] = gravity[:len(node.coordinates)]
    return out - x @ (on_coordinates * along)
