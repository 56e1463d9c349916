"""Issue 37's flexure job in OpenSees (OpenSeesPy 3.7.1.2), a second peer of
``flexure_pivot.py``.

Benchmark-only: needs ``pip install openseespy==3.7.1.2`` (never a dependency of
flexmbd). Its module needs the ``libblas.so.3`` bundled in its wheel loaded first
(OpenSeesPyDoc issue 319), which :func:`_import_opensees` does.

The same cross-spring pivot as flexmbd's and Exudyn's sides: two steel leaves (L = 0.1 m,
30 x 0.5 mm) of ``forceBeamColumn`` elements (three Gauss-Lobatto points, exact for the
linear moments of end loads) with an elastic section that includes shear (the shear
factor ``10(1+nu)/(12+11nu)`` and the torsion constant ``w t^3/3 (1 - 0.63 t/w)`` of
flexmbd's ``Rectangle``) and a ``Corotational`` transformation, clamped below; their tops
joined by stiff beams (OpenSees's rigid links are linear in the rotations) to the
stage node (0.25 kg, rotary inertia 1e-4 kg m^2), which a
moment about the pivot axis turns to about 0.3 rad in 20 load steps. The leaves carry
their mass per length, lumped.

At every load step: Newton (sparse UMFPACK, displacement increments to 1e-12) from the
previous step, then the six lowest frequencies by OpenSees's ``eigen`` on its tangent
(forceBeamColumn with a corotational transformation has the geometric stiffness;
``elasticForceBeamColumn`` lacks it), and the stage's 6x6 compliance from the tangent at
that state, which OpenSees hands out only from its dense system (``printA`` of
``FullGeneral``, formed by one linear step of zero load). Displacements of the stage
in OpenSees's global frame: forces and moments in, translations and rotations out.

Run: ``python benchmarks/opensees_pivot.py [--beams 8]`` (one job, its times as JSON).
"""

from __future__ import annotations

import argparse
import json
import math
import time

import numpy as np

LENGTH, WIDTH, THICKNESS, GAP = 0.1, 0.03, 0.5e-3, 0.04   #: [m]
E, NU, RHO = 210e9, 0.3, 7800.0
STAGE_MASS, STAGE_INERTIA, ROTATION, STEPS = 0.25, 1e-4, 0.3, 20
STAGE = 9  #: the stage's node
#: the stage's stiff beams to the leaves' tops: A [m^2], E, G [Pa], J, Iy, Iz [m^4], far
#: stiffer than the leaves (flexmbd's rigid beams 401 and 402)
STIFF = (1e-4, 210e9, 81e9, 1e-8, 1e-8, 1e-8)


def _import_opensees():
    """OpenSeesPy's module, its bundled BLAS loaded first."""
    import ctypes
    import glob
    import os
    import site

    for root in site.getsitepackages():
        for library in glob.glob(os.path.join(root, "openseespylinux", "lib", "libblas.so.3")):
            ctypes.CDLL(library, mode=ctypes.RTLD_GLOBAL)
    import openseespy.opensees as ops

    return ops


def _static_analysis(ops, increment: float, system: str = "UmfPack",
                     algorithm: str = "Newton") -> None:
    ops.system(system)
    ops.test("NormDispIncr", 1e-12, 50)
    ops.algorithm(algorithm)
    ops.integrator("LoadControl", increment)
    ops.analysis("Static")


def job(nbeams: int) -> dict[str, float]:
    """The job at ``nbeams`` beams per leaf; wall times [s] of its parts."""
    start = time.perf_counter()
    ops = _import_opensees()
    imported = time.perf_counter()
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    shear = E / (2 * (1 + NU))
    area, i_y, i_z = WIDTH * THICKNESS, \
        WIDTH * THICKNESS**3 / 12, THICKNESS * WIDTH**3 / 12
    torsion = WIDTH * THICKNESS**3 / 3 * (1 - 0.63 * THICKNESS / WIDTH)
    kappa = 10 * (1 + NU) / (12 + 11 * NU)
    # local y along the pivot axis (the leaf bends about it: i_y), local z across the leaf
    ops.section("Elastic", 1, E, area, i_z, i_y, shear, torsion, kappa, kappa)
    ops.beamIntegration("Lobatto", 1, 1, 3)
    h = LENGTH / math.sqrt(2)
    centre = (0.0, GAP / 2, h)
    ops.node(STAGE, *centre)
    ops.mass(STAGE, *[STAGE_MASS] * 3, *[STAGE_INERTIA] * 3)

    def leaf(first: int, bottom, top) -> None:
        bottom, top = np.array(bottom), np.array(top)
        axis = (top - bottom) / LENGTH
        ops.geomTransf("Corotational", first, *np.cross(axis, [0.0, 1.0, 0.0]))
        nodes = [first + k for k in range(nbeams + 1)]
        for k, node in enumerate(nodes):
            ops.node(node, *(bottom + axis * LENGTH * k / nbeams))
        ops.fix(nodes[0], 1, 1, 1, 1, 1, 1)
        for k in range(nbeams):
            ops.element("forceBeamColumn", first + k, nodes[k], nodes[k + 1], first, 1,
                        "-mass", RHO * area)
        # a stiff beam to the stage: OpenSees's rigid links are linear in the rotations
        ops.geomTransf("Corotational", first + nbeams + 1, 0.0, 0.0, 1.0)
        ops.element("elasticBeamColumn", first + nbeams, nodes[-1], STAGE, *STIFF,
                    first + nbeams + 1)

    leaf(1000, (-h / 2, 0, 0), (h / 2, 0, h))
    leaf(2000, (h / 2, GAP, 0), (-h / 2, GAP, h))
    torque = ROTATION * 2 * E * i_y / LENGTH
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(STAGE, 0, 0, 0, 0, torque, 0)
    ops.constraints("Transformation")
    ops.numberer("RCM")
    built = time.perf_counter()

    statics = linearization = 0.0
    f1 = angle = 0.0
    for step in range(1, STEPS + 1):
        t0 = time.perf_counter()
        _static_analysis(ops, 1.0 / STEPS)
        if ops.analyze(1) != 0:
            raise RuntimeError(f"OpenSees's static analysis failed at step {step}")
        t1 = time.perf_counter()
        omega2 = np.array(ops.eigen("-genBandArpack", 6))
        # the tangent at this state: one linear step of zero load in the dense system
        _static_analysis(ops, 0.0, "FullGeneral", "Linear")
        ops.analyze(1)
        n = ops.systemSize()
        tangent = np.array(ops.printA("-ret")).reshape(n, n)
        dofs = [d for d in ops.nodeDOFs(STAGE)]
        loads = np.zeros((n, 6))
        loads[dofs, range(6)] = 1.0
        compliance = np.linalg.solve(tangent, loads)[dofs]
        t2 = time.perf_counter()
        statics += t1 - t0
        linearization += t2 - t1
        f1 = math.sqrt(omega2[0]) / (2 * math.pi)
        angle = float(ops.nodeDisp(STAGE, 5))
    assert compliance.shape == (6, 6)
    done = time.perf_counter()
    return {"import": imported - start, "build": built - imported, "statics": statics,
            "table": linearization, "compute": done - imported, "dof": n,
            "f1": f1, "angle": angle, "c_rot": float(compliance[4, 4])}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--beams", type=int, default=8)
    args = parser.parse_args()
    print(json.dumps(job(args.beams)))


if __name__ == "__main__":
    main()
