"""The flexible slider-crank of the course's fourth exercise in Exudyn, the peer of the
speed comparison.

Benchmark-only: needs ``pip install exudyn`` (never a dependency of flexmbd).
The rod is ``nbeams`` ANCF Cable2D elements (axially flexible, like flexmbd's
``--eps1flex``; ``EA``, ``EI`` and ``rhoA`` as in the exercise). The massless
rigid crank is represented by prescribing the crank pin A on its circle, with
Exudyn's symbolic user functions (evaluated in C++, no Python call per step); B
slides on the x axis and carries the slider mass ``m2/2`` through a point mass
joined to the rod's end. The start is the exercise's: rod straight along x,
rigid-body velocities (A moving up at ``l1 omega``, B at rest, the rod turning
at ``-l1 omega / l2``). Time integration: Exudyn's generalized-alpha with fixed
steps; every option that trades cost for accuracy is a field of
:class:`ExudynSetting`, so that the comparison can look for Exudyn's cheapest
setting that meets an accuracy.

Run: ``python benchmarks/exudyn_slider_crank.py [--nbeams 8] [--steps 400]``.
"""

from __future__ import annotations

import argparse
import math
import time
from dataclasses import dataclass

import numpy as np

L1, L2, M2, EI = 0.15, 0.30, 0.06676, 12.72
EA = 2e11 * math.pi * 0.003**2
OMEGA = 150.0


@dataclass(frozen=True)
class ExudynSetting:
    """Exudyn's solver options of one run."""

    steps: int  #: generalized-alpha steps per crank turn (outputs at every step)
    rho_inf: float = 0.8  #: spectral radius at infinite frequency
    newmark: bool = False  #: Newmark instead of generalized-alpha
    newton_rtol: float = 1e-8  #: Newton's relative tolerance (Exudyn's default 1e-8)
    reduced_integration: int = 0  #: ANCFCable2D useReducedOrderIntegration (0, 1, 2)
    sparse: bool = False  #: Eigen's sparse LU (pattern analysed once) instead of dense LU

    @property
    def label(self) -> str:
        return (f"{self.steps} steps, rho {self.rho_inf:g}"
                f"{', Newmark' if self.newmark else ''}, Newton rtol {self.newton_rtol:g}, "
                f"reduced integration {self.reduced_integration}, "
                f"{'sparse' if self.sparse else 'dense'}")


def simulate(nbeams: int, setting: ExudynSetting, revolutions: float = 2.0
             ) -> tuple[np.ndarray, np.ndarray, float]:
    """Times [s] and ``v/l2`` at every step, and the solver time [s]."""
    import exudyn as exu
    from exudyn import itemInterface as Items
    from exudyn.advancedUtilities import CreateSymbolicUserFunction
    from exudyn.beams import GenerateBeamElementsAlongLine

    if nbeams % 2:
        raise ValueError("the Exudyn model measures v/l2 at a node: use an even nbeams")
    esym = exu.symbolic
    mbs = exu.SystemContainer().AddSystem()
    mbs.AddObject(Items.ObjectGround(referencePosition=[0, 0, 0]))
    ground = mbs.AddNode(Items.NodePointGround(referenceCoordinates=[0, 0, 0]))
    m_ground = mbs.AddMarker(Items.MarkerNodeCoordinate(nodeNumber=ground, coordinate=0))
    template = Items.ObjectANCFCable2D(massPerLength=M2 / L2, bendingStiffness=EI,
                                       axialStiffness=EA,
                                       useReducedOrderIntegration=setting.reduced_integration)
    nodes = GenerateBeamElementsAlongLine(mbs, [L1, 0, 0], [L1 + L2, 0, 0], nbeams,
                                          template)["nodes"]
    a, b = nodes[0], nodes[-1]

    # the crank pin's displacement from its reference position (L1, 0) and its rate
    def pin_x(mbs, t, itemNumber, lOffset):
        return L1 * esym.cos(OMEGA * t) - L1

    def pin_y(mbs, t, itemNumber, lOffset):
        return L1 * esym.sin(OMEGA * t)

    def pin_x_t(mbs, t, itemNumber, lOffset):
        return -L1 * OMEGA * esym.sin(OMEGA * t)

    def pin_y_t(mbs, t, itemNumber, lOffset):
        return L1 * OMEGA * esym.cos(OMEGA * t)

    symbolic = []  # Exudyn's expression trees must outlive the simulation
    for k, (law, rate) in enumerate(((pin_x, pin_x_t), (pin_y, pin_y_t))):
        symbolic += [CreateSymbolicUserFunction(mbs, f, name,
                                                itemTypeName="ObjectConnectorCoordinate")
                     for f, name in ((law, "offsetUserFunction"),
                                     (rate, "offsetUserFunction_t"))]
        marker = mbs.AddMarker(Items.MarkerNodeCoordinate(nodeNumber=a, coordinate=k))
        mbs.AddObject(Items.CoordinateConstraint(markerNumbers=[m_ground, marker],
                                                 offsetUserFunction=symbolic[-2],
                                                 offsetUserFunction_t=symbolic[-1]))
    slide = mbs.AddMarker(Items.MarkerNodeCoordinate(nodeNumber=b, coordinate=1))
    mbs.AddObject(Items.CoordinateConstraint(markerNumbers=[m_ground, slide]))
    slider = mbs.AddNode(Items.NodePoint2D(referenceCoordinates=[L1 + L2, 0]))
    mbs.AddObject(Items.MassPoint2D(mass=M2 / 2, nodeNumber=slider))
    mbs.AddObject(Items.RevoluteJoint2D(markerNumbers=[
        mbs.AddMarker(Items.MarkerNodePosition(nodeNumber=b)),
        mbs.AddMarker(Items.MarkerNodePosition(nodeNumber=slider))]))
    psi_dot = -L1 * OMEGA / L2  # the rod's rigid-body rotation rate at phi = 0
    for i, node in enumerate(nodes):
        mbs.SetNodeParameter(node, "initialVelocities",
                             [0.0, L1 * OMEGA * (1 - i / nbeams), 0.0, psi_dot])
    sensors = [mbs.AddSensor(Items.SensorNode(
        nodeNumber=k, storeInternal=True, writeToFile=False,
        outputVariableType=exu.OutputVariableType.Position))
        for k in (a, nodes[nbeams // 2], b)]
    mbs.Assemble()

    t_end = revolutions * 2 * math.pi / OMEGA
    settings = exu.SimulationSettings()
    integration = settings.timeIntegration
    integration.numberOfSteps = round(revolutions * setting.steps)
    integration.endTime = t_end
    integration.generalizedAlpha.spectralRadius = setting.rho_inf
    integration.generalizedAlpha.useNewmark = setting.newmark
    integration.newton.relativeTolerance = setting.newton_rtol
    integration.verboseMode = 0
    settings.solution.file.write = False
    settings.solution.sensors.writePeriod = t_end / integration.numberOfSteps
    settings.linearSolver.solverType = (exu.LinearSolverType.EigenSparse if setting.sparse
                                        else exu.LinearSolverType.EXUdense)
    settings.linearSolver.reuseAnalyzedPattern = setting.sparse
    start = time.perf_counter()
    exu.SolveDynamic(mbs, settings)
    solve = time.perf_counter() - start
    pa, pm, pb = (mbs.GetSensorStoredData(s) for s in sensors)
    del symbolic
    d = pb[:, 1:3] - pa[:, 1:3]
    normal = np.stack([-d[:, 1], d[:, 0]], axis=1) / np.hypot(d[:, 0], d[:, 1])[:, None]
    v = np.einsum("ij,ij->i", pm[:, 1:3] - pa[:, 1:3], normal) / L2
    return pa[:, 0], v, solve


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--nbeams", type=int, default=8)
    parser.add_argument("--steps", type=int, default=400, help="steps per crank turn")
    args = parser.parse_args()
    t, v, solve = simulate(args.nbeams, ExudynSetting(args.steps))
    print(f"Exudyn, {args.nbeams} ANCF cables, {args.steps} steps per turn: solver "
          f"{solve:.3f} s; v/l2 max {v.max():+.5f}, min {v.min():+.5f} ({len(t)} points)")


if __name__ == "__main__":
    main()
