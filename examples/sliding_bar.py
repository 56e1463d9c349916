"""EXERCISES 1: the sliding bar, a rigid bar with one end on each axis.

Two models of the same mechanism (one degree of freedom, bar length ``l0 = 2 m``):

* **truss** (1a-d): one truss p-q; ``x_p(t) = -l0 + v t`` prescribed, ``y_q``
  dependent. Singular where the bar lies flat (``y_q = 0``, at ``t = 0`` and
  ``t = 2 l0 / v``); the run stops there and says why.
* **rigid beam** (1e-j): one rigid beam with a rotational node at p;
  ``phi_p(t) = omega t`` prescribed, ``x_p`` and ``y_q`` dependent.

Checked in the drawn configuration ``x_p = -sqrt(3)``, ``y_q = 1`` (30 degrees):
``ydot_q = 4 sqrt(3)``, ``yddot_q = -64`` (truss, ``v = 4``); ``xdot_p = 4`` and
``xddot_p = 0`` with ``omega = 4``, ``omegadot = -16 sqrt(3)`` (rigid beam).

Run: ``flexmbd example sliding-truss --movie bar.gif`` or
``python examples/sliding_bar.py --variant beam --plot bar.png``.
"""

from __future__ import annotations

import math
import sys

import numpy as np
from flexmbd.examples._support import (
    POSITIVE,
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

L0 = 2.0  #: bar length [m]
SPEED = 4.0  #: speed of end p in the truss model [m/s]
OMEGA = 4.0  #: angular speed in the rigid-beam model [rad/s]
ANGLE = math.radians(30.0)  #: the drawn configuration


def truss_model(l0: float = L0, speed: float = SPEED) -> fm.Model:
    """Truss model: node 1 = p on the x axis, node 2 = q on the y axis, drawn at 30 degrees."""
    b = fm.ModelBuilder("sliding bar (truss)")
    b.add_node(1, -l0 * math.cos(ANGLE), 0.0)
    b.add_node(2, 0.0, l0 * math.sin(ANGLE))
    b.add_truss(1, 1, 2)
    b.fix(1, "y").fix(2, "x")
    b.input_coordinate(1, "x", law=fm.Polynomial(-l0, speed))
    return b.build()


def rigid_beam_model(l0: float = L0, omega: float = OMEGA) -> fm.Model:
    """Rigid-beam model: p = node 1, its rotation = node 2, q = node 3; horizontal at t = 0."""
    b = fm.ModelBuilder("sliding bar (rigid beam)")
    b.add_node(1, -l0, 0.0)
    b.add_node(3, 0.0, 0.0)
    b.add_rigid_beam(1, 1, 2, 3)
    b.fix(1, "y").fix(3, "x")
    b.input_coordinate(2, law=fm.Polynomial(0.0, omega))
    return b.build()


def truss_checks(model: fm.Model, l0: float = L0, speed: float = SPEED) -> list[Check]:
    """Values at ``x_p = -l0 cos 30deg`` against ``y_q = sqrt(l0^2 - x_p^2)`` and derivatives."""
    x_p = -l0 * math.cos(ANGLE)
    t = (x_p + l0) / speed
    r = fm.kinematic_analysis(model, [t])
    y = math.sqrt(l0**2 - x_p**2)
    yd = -x_p * speed / y
    ydd = -(speed**2 + yd**2) / y
    return [
        Check("t [s]", float(r.t[0]), t),
        Check("x_p [m]", float(r["x1.1"][0]), x_p),
        Check("y_q [m]", float(r["x2.2"][0]), y),
        Check("ydot_q [m/s] (4 sqrt 3)", float(r["xd2.2"][0]), yd),
        Check("yddot_q [m/s^2] (-64)", float(r["xdd2.2"][0]), ydd),
        Check("elongation e1 [m]", float(r["e1.1"][0]), 0.0, scale=l0),
    ]


def rigid_beam_checks(model: fm.Model, l0: float = L0, omega: float = OMEGA) -> list[Check]:
    """Values at 30 degrees for constant ``omega``, and with the ``omegadot`` that stops p."""
    t = ANGLE / omega
    r = fm.kinematic_analysis(model, [t])
    # omegadot that keeps p from accelerating: l0 (cos b omega^2 + sin b omegadot) = 0
    omegadot = -omega**2 / math.tan(ANGLE)
    r2 = fm.kinematic_analysis(model, [0.0],
                               inputs={"x2.1": fm.Polynomial(ANGLE, omega, omegadot)})
    return [
        Check("x_p [m]", float(r["x1.1"][0]), -l0 * math.cos(ANGLE)),
        Check("y_q [m]", float(r["x3.2"][0]), l0 * math.sin(ANGLE)),
        Check("xdot_p [m/s] (4)", float(r["xd1.1"][0]), l0 * math.sin(ANGLE) * omega),
        Check("ydot_q [m/s] (4 sqrt 3)", float(r["xd3.2"][0]), l0 * math.cos(ANGLE) * omega),
        Check("xddot_p [m/s^2], omega const", float(r["xdd1.1"][0]),
              l0 * math.cos(ANGLE) * omega**2),
        Check("omegadot [rad/s^2] (-16 sqrt 3)", omegadot, -16.0 * math.sqrt(3.0)),
        Check("xddot_p [m/s^2] with omegadot", float(r2["xdd1.1"][0]), 0.0, scale=l0 * omega**2),
    ]


def run(variant: str, t_end: float | None = None, points: int = 200) -> fm.KinematicResult:
    """The motion over the quarter turn (returns partial results if it must stop early)."""
    if variant == "truss":
        model, t_start, t_stop = truss_model(), 0.005, 0.995 * 2 * L0 / SPEED
    else:
        model, t_start, t_stop = rigid_beam_model(), 0.0, (math.pi / 2) / OMEGA
    times = np.linspace(t_start, t_stop if t_end is None else t_end, points)
    return fm.kinematic_analysis(model, times, on_failure="return")


def main(argv: list[str] | None = None, prog: str | None = None) -> int:
    """Run the example with command-line arguments ``argv``; returns the exit code."""
    parser = example_parser(__doc__, prog)
    parser.add_argument("--variant", choices=("truss", "beam"), default="truss")
    parser.add_argument("--t-end", type=POSITIVE, default=None,
                        help="end time [s] (the truss stops at its singular end point 1 s)")
    parser.add_argument("--points", type=count(2), default=200, help="output times")
    add_output_options(parser)
    args = parse(parser, argv)

    if args.variant == "truss":
        model = truss_model()
        ok = print_checks("EXERCISES 1a-d, truss model, x_p = -2 + 4 t, at x_p = -sqrt(3):",
                          truss_checks(model))
        columns, labels = ["x2.2"], ["y_q"]
    else:
        model = rigid_beam_model()
        ok = print_checks("EXERCISES 1e-j, rigid beam model, phi_p = 4 t, at 30 degrees:",
                          rigid_beam_checks(model))
        columns, labels = ["x1.1", "x3.2"], ["x_p", "y_q"]
    result = run(args.variant, args.t_end, args.points)
    if result.success:
        print(f"run: {result.message}")

    def draw(filename, window):
        plot.plot_motion(result, columns, labels=labels, filename=filename, window=window,
                            title=result.model.name)

    finish_outputs(args, result, draw, movie_title=result.model.name)
    if not result.success:
        print(f"sliding bar: stopped early: {result.message}", file=sys.stderr)
    return 0 if ok and result.success else 1


if __name__ == "__main__":
    sys.exit(main())
