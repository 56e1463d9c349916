"""The flexible slider-crank of EXERCISES 4 in Exudyn, the peer of the speed comparison.

Benchmark-only: needs ``pip install exudyn`` (never a dependency of flexmbd).
The rod is ``nbeams`` ANCF Cable2D elements (axially flexible, like flexmbd's
``eps1flex``; ``EA``, ``EI`` and ``rhoA`` as in the exercise). The massless rigid
crank is represented by prescribing the crank pin A on its circle; B slides
on the x axis and carries the slider mass ``m2/2`` through a point mass joined
to the rod's end. The start is the exercise's: rod straight along x, rigid-body
velocities (A moving up at ``l1 omega``, B at rest, the rod turning at
``-l1 omega / l2``). Time integration: Exudyn's generalized-alpha, fixed steps.

Run: ``python benchmarks/exudyn_slider_crank.py [--nbeams 8] [--steps-per-revolution 4000]``.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

L1, L2, M2, EI = 0.15, 0.30, 0.06676, 12.72
EA = 2e11 * math.pi * 0.003**2
OMEGA = 150.0
POINTS_PER_REVOLUTION = 400


def simulate(nbeams: int = 8, steps_per_revolution: int = 4000, revolutions: float = 2.0,
             rho_inf: float = 0.8) -> tuple[np.ndarray, np.ndarray, float]:
    """Times [s], ``v/l2`` at 400 points per turn, and the solver time [s]."""
    import exudyn as exu
    from exudyn import itemInterface as Items
    from exudyn.beams import GenerateBeamElementsAlongLine

    mbs = exu.SystemContainer().AddSystem()
    mbs.AddObject(Items.ObjectGround(referencePosition=[0, 0, 0]))
    ground = mbs.AddNode(Items.NodePointGround(referenceCoordinates=[0, 0, 0]))
    m_ground = mbs.AddMarker(Items.MarkerNodeCoordinate(nodeNumber=ground, coordinate=0))
    template = Items.ObjectANCFCable2D(massPerLength=M2 / L2, bendingStiffness=EI,
                                    axialStiffness=EA)
    nodes = GenerateBeamElementsAlongLine(mbs, [L1, 0, 0], [L1 + L2, 0, 0], nbeams,
                                          template)["nodes"]
    a, b = nodes[0], nodes[-1]

    # the crank pin's displacement from its reference position (L1, 0)
    def pin_x(mbs, t, item, offset):
        return L1 * math.cos(OMEGA * t) - L1

    def pin_y(mbs, t, item, offset):
        return L1 * math.sin(OMEGA * t)

    for k, law in ((0, pin_x), (1, pin_y)):
        marker = mbs.AddMarker(Items.MarkerNodeCoordinate(nodeNumber=a, coordinate=k))
        mbs.AddObject(Items.CoordinateConstraint(markerNumbers=[m_ground, marker],
                                              offsetUserFunction=law))
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
    middle = _middle_sensor_node(nodes, nbeams)
    sensors = [mbs.AddSensor(Items.SensorNode(nodeNumber=k, storeInternal=True, writeToFile=False,
                                           outputVariableType=exu.OutputVariableType.Position))
               for k in (a, middle, b)]
    mbs.Assemble()

    t_end = revolutions * 2 * math.pi / OMEGA
    settings = exu.SimulationSettings()
    settings.timeIntegration.numberOfSteps = round(revolutions * steps_per_revolution)
    settings.timeIntegration.endTime = t_end
    settings.timeIntegration.generalizedAlpha.spectralRadius = rho_inf
    settings.timeIntegration.verboseMode = 0
    settings.solution.file.write = False
    settings.solution.sensors.writePeriod = t_end / (POINTS_PER_REVOLUTION * revolutions)
    start = time.perf_counter()
    exu.SolveDynamic(mbs, settings)
    solve = time.perf_counter() - start
    pa, pm, pb = (mbs.GetSensorStoredData(s) for s in sensors)
    d = pb[:, 1:3] - pa[:, 1:3]
    normal = np.stack([-d[:, 1], d[:, 0]], axis=1) / np.hypot(d[:, 0], d[:, 1])[:, None]
    v = np.einsum("ij,ij->i", pm[:, 1:3] - pa[:, 1:3], normal) / L2
    return pa[:, 0], v, solve


def _middle_sensor_node(nodes, nbeams: int) -> int:
    if nbeams % 2:
        raise ValueError("the Exudyn model measures v/l2 at a node: use an even nbeams")
    return nodes[nbeams // 2]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--nbeams", type=int, default=8)
    parser.add_argument("--steps-per-revolution", type=int, default=4000)
    args = parser.parse_args()
    t, v, solve = simulate(args.nbeams, args.steps_per_revolution)
    print(f"Exudyn, {args.nbeams} ANCF cables, {args.steps_per_revolution} steps per turn: "
          f"solver {solve:.3f} s; v/l2 max {v.max():+.5f}, min {v.min():+.5f} "
          f"({len(t)} points)")


if __name__ == "__main__":
    main()
