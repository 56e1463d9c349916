"""A spatial slider-crank: the crank turns about a tilted axis, the slider runs on a
line offset from the crank's pivot; kinematics and driving torque against the closed
form.

The crank ``O-A`` (``r = 0.15 m``, a rigid spatial beam) turns about the axis ``a =
(sin beta, 0, cos beta)`` through ``O``, tilted by ``beta = 30`` degrees from Z; a
spatial hinge between the ground's rotational node and the crank's drives it at
``omega = 150 rad/s``. The rod ``A-B`` (``l = 0.30 m``) is a rigid spatial truss, so
both its ends are spherical joints (the rod's spin about its own axis is not a
coordinate). The slider ``B`` runs along the line ``y = 0, z = h = 0.05 m`` parallel to
X. With ``A(phi) = r (cos phi e1 + sin phi e2)``, ``e1 = (cos beta, 0, -sin beta)``,
``e2 = (0, 1, 0)``, the slider is at

    x_B = A_x + sqrt(l^2 - A_y^2 - (h - A_z)^2),

and, the crank pin's speed being constant, the driving torque at constant speed is
``m_B x_B' x_B'' omega^2`` (``'`` a derivative with respect to the crank angle).

Computed over one revolution, each against that closed form: the slider's position,
velocity and acceleration, the driving torque (inverse dynamics, point masses 0.2 kg at
``A`` and 0.3 kg at ``B``), and the crank's orientation read as axis and angle (the
axis ``a``, the angle the hinge's).

Nodes: 1 ``O`` (fixed), 2 ``A``, 3 ``B`` (``y``, ``z`` fixed); rotational 11 (ground,
fixed), 12 and 13 (the crank's ends). Elements: crank 1, rod 2, hinge 3 (driven).

Run: ``flexmbd example spatial-slider-crank --plot slider.png --movie crank.gif``.
"""

from __future__ import annotations

import math
import sys

import numpy as np
from flexmbd.examples._support import (
    Check,
    add_output_options,
    count,
    example_parser,
    finish_outputs,
    parse,
    print_checks,
)

import flexmbd as fm
from flexmbd import plot

CRANK, ROD = 0.15, 0.30  #: lengths r and l [m]
TILT = math.radians(30.0)  #: the crank axis' tilt from Z, beta [rad]
OFFSET = 0.05  #: the slider line's height above the crank pivot, h [m]
OMEGA = 150.0  #: crank speed [rad/s]
MASSES = (0.2, 0.3)  #: point masses at the crank pin A and the slider B [kg]
AXIS = np.array([math.sin(TILT), 0.0, math.cos(TILT)])  #: the crank axis a
E1 = np.array([math.cos(TILT), 0.0, -math.sin(TILT)])  #: the crank at phi = 0
E2 = np.cross(AXIS, E1)  #: the crank at phi = 90 degrees


def crank_pin(phi) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``A(phi)`` and its first two derivatives with respect to ``phi``, each ``(3, n)``."""
    c, s = np.cos(phi), np.sin(phi)
    a = CRANK * (np.outer(E1, c) + np.outer(E2, s))
    da = CRANK * (np.outer(E1, -s) + np.outer(E2, c))
    return a, da, -a


def closed_form(phi) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``x_B`` and its first two derivatives with respect to the crank angle."""
    (ax, ay, az), (dx, dy, dz), (ddx, ddy, ddz) = crank_pin(np.atleast_1d(phi))
    s = ROD**2 - ay**2 - (OFFSET - az) ** 2
    ds = -2 * ay * dy + 2 * (OFFSET - az) * dz
    dds = -2 * (dy**2 + ay * ddy) + 2 * (-(dz**2) + (OFFSET - az) * ddz)
    root = np.sqrt(s)
    return ax + root, dx + ds / (2 * root), ddx + dds / (2 * root) - ds**2 / (4 * root**3)


def build_model(omega: float = OMEGA) -> fm.Model:
    """The mechanism at ``phi = 0``, the crank driven at ``omega`` [rad/s]."""
    pin = CRANK * E1
    slider = closed_form(0.0)[0][0]
    b = fm.ModelBuilder("spatial slider-crank")
    b.add_node(1, 0.0, 0.0, 0.0).add_node(2, *pin).add_node(3, slider, 0.0, OFFSET)
    b.add_spatial_beam(1, 1, 12, 2, 13, orientation=AXIS)   # crank O-A
    b.add_spatial_truss(2, 2, 3)                            # rod A-B, spherical ends
    b.add_spatial_hinge(3, 11, 12, axis=AXIS)               # the driven crank bearing
    b.fix(1).fix(11).fix(3, "y", "z")
    b.input_deformation(3, 1, law=fm.Polynomial(0.0, omega))
    b.add_point_mass(2, MASSES[0]).add_point_mass(3, MASSES[1])
    return b.build()


def revolution(model: fm.Model, points: int, omega: float = OMEGA) -> fm.SimulationResult:
    """Inverse dynamics over one revolution (kinematics, torque and reactions)."""
    return fm.inverse_dynamics(model, np.linspace(0.0, 2 * math.pi / omega, points),
                               on_failure="return")


def checks(result: fm.SimulationResult, omega: float = OMEGA) -> list[Check]:
    """The revolution against the closed form (module docstring)."""
    phi = result["e3.1"]
    x, dx, ddx = closed_form(phi)
    torque = MASSES[1] * dx * ddx * omega**2
    axis, angle = result.axis_angle(12)
    turning = (angle > 0.1) & (angle < math.pi - 0.1)   # where the axis is well defined
    wrapped = np.where(np.mod(phi, 2 * math.pi) <= math.pi, np.mod(phi, 2 * math.pi),
                       2 * math.pi - np.mod(phi, 2 * math.pi))
    sense = np.where(np.mod(phi, 2 * math.pi) <= math.pi, 1.0, -1.0)
    return [
        Check("x_B, largest error [m]", float(np.max(np.abs(result["x3.1"] - x))), 0.0,
              rtol=1e-12),
        Check("xdot_B, largest error [m/s]", float(np.max(np.abs(result["xd3.1"] - dx * omega))),
              0.0, rtol=1e-10, scale=CRANK * omega),
        Check("xddot_B, largest error [m/s^2]",
              float(np.max(np.abs(result["xdd3.1"] - ddx * omega**2))), 0.0, rtol=1e-10,
              scale=CRANK * omega**2),
        Check("driving torque, largest error [N m]",
              float(np.max(np.abs(result.driving[:, 0] - torque))), 0.0, rtol=1e-10,
              scale=float(np.max(np.abs(torque)))),
        Check("largest driving torque [N m]", float(np.max(np.abs(result.driving[:, 0]))),
              float(np.max(np.abs(torque))), rtol=1e-10),
        Check("crank rotation axis, largest error", float(np.max(np.abs(
            axis[turning] - sense[turning, None] * AXIS))), 0.0, rtol=1e-10),
        Check("crank rotation angle, largest error [rad]",
              float(np.max(np.abs(angle - wrapped))), 0.0, rtol=1e-10),
    ]


def main(argv: list[str] | None = None, prog: str | None = None) -> int:
    """Run the example with command-line arguments ``argv``; returns the exit code."""
    parser = example_parser(__doc__, prog)
    parser.add_argument("--points", type=count(2), default=361, help="output times")
    add_output_options(parser, table=True)
    args = parse(parser, argv)
    model = build_model()
    print(model.summary())
    result = revolution(model, args.points)
    print(f"revolution: {result.message}")
    if args.out:
        result.save(args.out)
        print(f"{len(result.t)} rows written to {args.out}")
    print(f"slider stroke {result['x3.1'].min():.6f} .. {result['x3.1'].max():.6f} m, "
          f"largest driving torque {np.abs(result.driving[:, 0]).max():.6g} N m")
    ok = print_checks("\nchecks against the closed form:", checks(result)) and result.success

    def draw(filename, window):
        phi = np.degrees(result["e3.1"])
        x, _, _ = closed_form(result["e3.1"])
        plot.plot_curves(phi, {"flexmbd": result["x3.1"], "closed form": x},
                         xlabel="crank angle [deg]", ylabel="x_B [m]",
                         title="spatial slider-crank: slider position", filename=filename,
                         window=window)

    finish_outputs(args, result, draw, movie_title="spatial slider-crank")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
