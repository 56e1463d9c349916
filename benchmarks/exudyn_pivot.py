"""Issue 37's flexure job in Exudyn, the peer of ``flexure_pivot.py``.

Benchmark-only: needs ``pip install exudyn`` (never a dependency of flexmbd).
The same cross-spring pivot as flexmbd's side: two steel leaves (L = 0.1 m, 30 x 0.5 mm)
of ``ObjectBeamGeometricallyExact`` on ``NodeRigidBodyRxyz``, crossing at 90 degrees,
0.04 m apart along the pivot axis (y), clamped below by coordinate constraints, joined
at their tops by fixed generic joints to a rigid 0.25 kg stage (rotary inertia
1e-4 kg m^2), which a torque about y turns to about 0.3 rad in 20 load steps. The
section is the one flexmbd's ``Rectangle`` uses (shear factor 10(1+nu)/(12+11nu),
torsion ``w t^3/3 (1 - 0.63 t/w)``).

At every load step: ``SolveStatic`` from the previous step's solution (Exudyn's default
tolerances; ``relativeTolerance = 1e-10`` does not converge on these leaves), then the
tangent of the whole static system (coordinates and multipliers) by central
differences of ``ComputeNewtonResidual``, the six lowest frequencies with the stage's
mass on the null space of the constraint Jacobian, and the stage's 6x6 compliance
(forces and torques in the global frame, the Rxyz rates turned into angles by ``G``).
Exudyn's own static Jacobian (``--own-tangent``) is cheaper but inexact at the loaded
states: the lowest frequency from it is 2 % low at the last step (8.805 Hz against 8.992
Hz from the differences, 8.987 Hz from flexmbd at 8 beams per leaf).

Run: ``python benchmarks/exudyn_pivot.py [--beams 8]`` (one job, its times as JSON).
"""

from __future__ import annotations

import argparse
import itertools
import json
import math
import time
import warnings

import numpy as np

LENGTH, WIDTH, THICKNESS, GAP = 0.1, 0.03, 0.5e-3, 0.04   #: [m]
E, NU, RHO = 210e9, 0.3, 7800.0
STAGE_MASS, STAGE_INERTIA, ROTATION, STEPS = 0.25, 1e-4, 0.3, 20


def job(nbeams: int, own_tangent: bool = False) -> dict[str, float]:
    """The job at ``nbeams`` beams per leaf; wall times [s] of its parts.

    ``own_tangent``: the tangent from Exudyn's ``ComputeNewtonJacobian`` instead of
    central differences of its residual. It is cheaper but inexact at loaded states: its
    lowest frequency at the last step is about 2 % low (``f1_own_tangent``).
    """
    start = time.perf_counter()
    warnings.simplefilter("ignore", DeprecationWarning)   # 1.13's renamed parameters
    import exudyn as exu
    import scipy.linalg
    from exudyn.itemInterface import (
        CoordinateConstraint,
        GenericJoint,
        LoadTorqueVector,
        MarkerBodyRigid,
        MarkerNodeCoordinate,
        MarkerNodeRigid,
        NodePointGround,
        NodeRigidBodyRxyz,
        ObjectBeamGeometricallyExact,
        ObjectRigidBody,
    )
    from exudyn.rigidBodyUtilities import RotationMatrix2RotXYZ, RotXYZ2G

    imported = time.perf_counter()
    shear = E / (2 * (1 + NU))
    area, i_y, i_z = WIDTH * THICKNESS, WIDTH * THICKNESS**3 / 12, THICKNESS * WIDTH**3 / 12
    torsion = WIDTH * THICKNESS**3 / 3 * (1 - 0.63 * THICKNESS / WIDTH)
    kappa = 10 * (1 + NU) / (12 + 11 * NU)
    section = exu.BeamSection()
    section.stiffnessMatrix = np.diag([E * area, kappa * shear * area, kappa * shear * area,
                                       shear * torsion, E * i_y, E * i_z])
    section.inertia = RHO * np.diag([i_y + i_z, i_y, i_z])
    section.massPerLength = RHO * area

    container = exu.SystemContainer()
    mbs = container.AddSystem()
    ground = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=mbs.AddNode(NodePointGround()),
                                                coordinate=0))
    h = LENGTH / math.sqrt(2)
    centre = np.array([0.0, GAP / 2, h])

    def leaf(bottom: list[float], top: list[float]) -> tuple[int, np.ndarray]:
        axis = (np.array(top) - np.array(bottom)) / LENGTH
        frame = np.column_stack([axis, [0, 1, 0], np.cross(axis, [0, 1, 0])])
        angles = list(RotationMatrix2RotXYZ(frame))
        nodes = [mbs.AddNode(NodeRigidBodyRxyz(
            referenceCoordinates=list(np.array(bottom) + axis * LENGTH * i / nbeams) + angles))
            for i in range(nbeams + 1)]
        for p, q in itertools.pairwise(nodes):
            mbs.AddObject(ObjectBeamGeometricallyExact(nodeNumbers=[p, q],
                                                       physicsLength=LENGTH / nbeams,
                                                       sectionData=section))
        for c in range(6):
            clamp = mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=nodes[0], coordinate=c))
            mbs.AddObject(CoordinateConstraint(markerNumbers=[ground, clamp]))
        return nodes[-1], frame

    tops = [(leaf([-h / 2, 0, 0], [h / 2, 0, h]), [h / 2, 0, h]),
            (leaf([h / 2, GAP, 0], [-h / 2, GAP, h]), [-h / 2, GAP, h])]
    stage_node = mbs.AddNode(NodeRigidBodyRxyz(referenceCoordinates=[*centre, 0, 0, 0]))
    stage = mbs.AddObject(ObjectRigidBody(nodeNumber=stage_node, physicsMass=STAGE_MASS,
                                          physicsInertia=[STAGE_INERTIA] * 3 + [0, 0, 0]))
    for (node, frame), at in tops:
        on_stage = mbs.AddMarker(MarkerBodyRigid(bodyNumber=stage,
                                                 localPosition=list(np.array(at) - centre)))
        mbs.AddObject(GenericJoint(markerNumbers=[on_stage, mbs.AddMarker(
            MarkerNodeRigid(nodeNumber=node))], constrainedAxes=[1] * 6,
            rotationMarker0=np.eye(3), rotationMarker1=frame.T))
    torque = ROTATION * 2 * E * i_y / LENGTH
    load = mbs.AddLoad(LoadTorqueVector(markerNumber=mbs.AddMarker(
        MarkerNodeRigid(nodeNumber=stage_node)), loadVector=[0, 0, 0]))
    mbs.Assemble()
    settings = exu.SimulationSettings()
    settings.solutionSettings.writeSolutionToFile = False
    settings.staticSolver.verboseMode = 0
    built = time.perf_counter()

    solver = exu.MainSolverStatic()
    solver.InitializeSolver(mbs, settings)
    n_q = solver.GetODE2size()
    solver.ComputeMassMatrix(mbs)
    mass = solver.GetSystemMassMatrix().copy()   # constant for these elements
    data = mbs.systemData
    statics = linearization = 0.0
    f1 = angle = 0.0
    for step in range(1, STEPS + 1):
        t0 = time.perf_counter()
        mbs.SetLoadParameter(load, "loadVector", [0, step / STEPS * torque, 0])
        if not mbs.SolveStatic(settings):
            raise RuntimeError(f"Exudyn's static solver failed at step {step}")
        q, lam = data.GetODE2Coordinates(), data.GetAECoordinates()
        data.SetODE2Coordinates(q, exu.ConfigurationType.Initial)
        data.SetAECoordinates(lam, exu.ConfigurationType.Initial)
        t1 = time.perf_counter()
        if own_tangent:
            solver.ComputeNewtonJacobian(mbs, settings)
            jac = solver.GetSystemJacobian()
        else:
            jac = _central_tangent(exu, mbs, solver, settings, np.concatenate([q, lam]), n_q)
        basis, stiff, omega2 = _modes(scipy.linalg, jac, mass, n_q)
        to_loads = np.zeros((n_q, 6))                 # unit forces and torques -> loads
        to_loads[n_q - 6:n_q - 3, :3] = np.eye(3)
        to_loads[n_q - 3:, 3:] = RotXYZ2G(q[n_q - 3:] + mbs.GetNodeParameter(
            stage_node, "referenceCoordinates")[3:]).T
        reduced = basis.T @ to_loads
        compliance = reduced.T @ np.linalg.solve(stiff, reduced)
        t2 = time.perf_counter()
        statics += t1 - t0
        linearization += t2 - t1
        f1 = math.sqrt(omega2[0]) / (2 * math.pi)
        angle = float(q[n_q - 2])
    assert compliance.shape == (6, 6)
    done = time.perf_counter()
    solver.ComputeNewtonJacobian(mbs, settings)
    own = _modes(scipy.linalg, solver.GetSystemJacobian(), mass, n_q)[2][0]
    return {"import": imported - start, "build": built - imported, "statics": statics,
            "table": linearization, "compute": done - imported, "dof": n_q,
            "f1": f1, "angle": angle, "f1_own_tangent": math.sqrt(own) / (2 * math.pi)}


def _modes(linalg, jac: np.ndarray, mass: np.ndarray, n_q: int) -> tuple:
    """Null-space basis, reduced stiffness and the six lowest omega^2 [rad^2/s^2]."""
    basis = linalg.null_space(jac[n_q:, :n_q])
    stiff = -basis.T @ jac[:n_q, :n_q] @ basis   # the residual is minus the forces
    stiff = (stiff + stiff.T) / 2
    omega2 = linalg.eigh(stiff, basis.T @ mass @ basis, eigvals_only=True,
                         subset_by_index=[0, 5])
    return basis, stiff, omega2


def _central_tangent(exu, mbs, solver, settings, state: np.ndarray, n_q: int) -> np.ndarray:
    """The static system's Jacobian over coordinates and multipliers, central differences."""
    data = mbs.systemData

    def residual(z: np.ndarray) -> np.ndarray:
        data.SetODE2Coordinates(z[:n_q], exu.ConfigurationType.Current)
        data.SetAECoordinates(z[n_q:], exu.ConfigurationType.Current)
        solver.ComputeNewtonResidual(mbs, settings)
        return solver.GetSystemResidual().copy()

    jac = np.empty((len(state), len(state)))
    for j in range(len(state)):
        step = (1e-6 if j < n_q else 1e-3) * max(1.0, abs(state[j]))
        up, down = state.copy(), state.copy()
        up[j] += step
        down[j] -= step
        jac[:, j] = (residual(up) - residual(down)) / (2 * step)
    residual(state)
    return jac


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--beams", type=int, default=8)
    parser.add_argument("--own-tangent", action="store_true",
                        help="Exudyn's own static Jacobian instead of central differences")
    args = parser.parse_args()
    print(json.dumps(job(args.beams, own_tangent=args.own_tangent)))


if __name__ == "__main__":
    main()
