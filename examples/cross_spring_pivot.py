"""A spatial flexure: a cross-spring pivot of two leaf springs; its stiffness in all
directions, its first frequencies and a large rotation in load steps.

Two steel leaf springs (length ``L = 40 mm``, thickness 0.2 mm, width 10 mm, ``E =
210 GPa``, ``G = 80 GPa``, ``rho = 7850 kg/m^3``) cross at their middles on the pivot
axis Z, at 45 degrees to it, 10 mm apart along Z so that they pass each other. They are
clamped to the ground at the bottom and carry a rigid body (a rigid spatial beam between
the leaves' tops, rotary inertia ``Jz = 2e-5 kg m^2``) at the top. Each leaf is
``--nbeams`` spatial beams with all six deformations flexible; the loop of leaves and
body has six deformations more than coordinates: the top beam of the second leaf is
released (RLSE), its stiffness kept. The thin direction of each leaf is in the XY plane
(its orientation vector is Z), so the pivot is compliant about Z and stiff otherwise.

Computed, each against a value this example computes on its own:

* the rotational stiffness about the pivot axis, ``2 EI/L`` (each leaf, with its end
  turned by ``theta`` about its middle, is in pure bending: its end force vanishes and
  its moment is ``EI theta/L``, exactly for Hermite beams);
* the 6 x 6 compliance of the body (translations at the first leaf's top, rotations);
  the stiffness about Z with the other directions free, ``1/C_66``, is the pivot's;
* the first frequency, the body turning about Z, against ``sqrt(2 EI/(L J))/(2 pi)``
  with the body's inertia about the axis (the leaves' own lowers it by a fraction of a
  percent);
* the body turned by 30 degrees in 30 load steps of its Euler parameter ``lam3 =
  sin(theta/2)``: the moment-rotation curve starts at ``2 EI/L`` and is smooth (a
  polynomial of degree 6 in the angle follows it to 1e-6 of its largest value); the
  stiffness grows by 4 % at 30 degrees.

Nodes: first leaf 1, 3, ..., top ``2n+1`` (rotations 2, 4, ..., top ``2n+2``, the body's
rotation), second leaf 101, ... (rotations 102, ...). Elements: leaves 1..n and
101..100+n, the body 200.

Run: ``flexmbd example cross-spring-pivot --plot moment.png --movie pivot.gif``.
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

LENGTH = 0.04  #: leaf length L [m]
THICKNESS = 0.2e-3  #: leaf thickness [m]
WIDTH = 0.01  #: leaf width [m]
YOUNG, SHEAR = 210e9, 80e9  #: moduli [Pa]
DENSITY = 7850.0  #: [kg/m^3]
GAP = 0.01  #: distance between the leaves along the pivot axis [m]
EI = YOUNG * WIDTH * THICKNESS**3 / 12  #: bending stiffness in the compliant plane [N m^2]
EI_STIFF = YOUNG * THICKNESS * WIDTH**3 / 12  #: bending stiffness across it [N m^2]
GIT = SHEAR * WIDTH * THICKNESS**3 / 3  #: torsional stiffness [N m^2]
EA = YOUNG * WIDTH * THICKNESS  #: axial stiffness [N]
RHO_A = DENSITY * WIDTH * THICKNESS  #: mass per length [kg/m]
#: the section's rotary inertias per length [kg m]: torsional, about the local y axis (the
#: width, along Z: the thin direction bends) and about the local z axis
SECTION_INERTIA = (DENSITY * (WIDTH * THICKNESS**3 + THICKNESS * WIDTH**3) / 12,
                   DENSITY * WIDTH * THICKNESS**3 / 12, DENSITY * THICKNESS * WIDTH**3 / 12, 0.0)
BODY_INERTIA = 2e-5  #: the body's rotary inertia about the pivot axis [kg m^2]
BODY_MASS = 0.02  #: the body's mass, half at each leaf top [kg]
ROTATION = 30.0  #: the large rotation [degrees]
STEPS = 30  #: its load steps
NBEAMS = 4  #: beams per leaf
SECOND = 100  #: what the second leaf adds to the first leaf's node and element numbers
BODY = 200  #: the body's element


def top_nodes(nbeams: int) -> tuple[int, int]:
    """The first leaf's top node and the body's rotational node."""
    return 2 * nbeams + 1, 2 * nbeams + 2


def build_model(nbeams: int = NBEAMS, driven: bool = True) -> fm.Model:
    """The pivot of ``nbeams`` beams per leaf; ``driven``: the body's rotation about Z is
    an input (its ``lam3``), for load steps; otherwise the body moves freely on the
    leaves, for its stiffness and frequencies."""
    b = fm.ModelBuilder(f"cross-spring pivot, {nbeams} beams per leaf")
    half = LENGTH / (2 * math.sqrt(2))  # the leaves' ends at (+-half, +-half)
    leaves = ((0, (-half, -half), (half, half), GAP / 2),
              (SECOND, (half, -half), (-half, half), -GAP / 2))
    for offset, start, end, z in leaves:
        for k in range(nbeams + 1):
            s = k / nbeams
            b.add_node(offset + 2 * k + 1, (1 - s) * start[0] + s * end[0],
                       (1 - s) * start[1] + s * end[1], z)
        for k in range(nbeams):
            element = offset + k + 1
            b.add_spatial_beam(element, offset + 2 * k + 1, offset + 2 * k + 2,
                               offset + 2 * k + 3, offset + 2 * k + 4, orientation=(0, 0, 1))
            b.set_stiffness(element, axial=EA, torsion=GIT, bending_y=EI, bending_z=EI_STIFF)
            b.set_mass(element, RHO_A, section_inertia=SECTION_INERTIA)
            if offset == SECOND and k == nbeams - 1:
                b.release(element)        # closes the loop
            elif driven and element == 1:  # the input takes over one degree of freedom
                b.dynamic_deformation(element, 1, 2, 4, 5, 6).release(element, 3)
            else:
                b.dynamic_deformation(element)
        b.fix(offset + 1).fix(offset + 2)
    top, body = top_nodes(nbeams)
    b.add_spatial_beam(BODY, top, body, SECOND + top, SECOND + body, orientation=(0, 1, 0))
    b.add_rotary_inertia(body, 0.0, 0.0, 0.0, 0.0, 0.0, BODY_INERTIA)
    b.add_point_mass(top, BODY_MASS / 2).add_point_mass(SECOND + top, BODY_MASS / 2)
    if driven:
        b.input_coordinate(body, 4)
    return b.build()


def pivot_stiffness() -> float:
    """``2 EI/L`` [N m/rad]: the rotational stiffness of the pivot about its axis."""
    return 2 * EI / LENGTH


def body_labels(nbeams: int) -> list[str]:
    """The body's translations (at the first leaf's top) and rotations."""
    top, body = top_nodes(nbeams)
    return [f"x{top}.{k}" for k in (1, 2, 3)] + [f"x{body}.{k}" for k in (2, 3, 4)]


def turn(model: fm.Model, degrees: float = ROTATION, steps: int = STEPS) -> fm.StaticResult:
    """The driven body turned about Z by ``degrees`` in ``steps`` load steps."""
    body = top_nodes(nbeams_of(model))[1]
    increment = {f"x{body}.4": math.sin(math.radians(degrees) / 2)}
    return fm.static_equilibrium(model, input_increment=increment, steps=steps)


def nbeams_of(model: fm.Model) -> int:
    return sum(1 for n in model.elements if n < SECOND)


def moment_curve(statics: fm.StaticResult) -> tuple[np.ndarray, np.ndarray]:
    """Rotation angle [rad] and the moment about Z that holds it [N m], per load step."""
    body = top_nodes(nbeams_of(statics.model))[1]
    _, angle = statics.axis_angle(body)
    return angle, statics[f"f{body}.4"]


def smoothness(angle: np.ndarray, moment: np.ndarray, degree: int = 6) -> float:
    """The largest deviation of the moment from its least-squares polynomial of
    ``degree`` in the angle, relative to the largest moment."""
    fit = np.polynomial.Polynomial.fit(angle, moment, degree)
    return float(np.max(np.abs(fit(angle) - moment)) / np.max(np.abs(moment)))


def analyse(nbeams: int = NBEAMS) -> dict:
    """Stiffness, frequencies and the large rotation of the pivot."""
    free = build_model(nbeams, driven=False)
    lin = fm.linearize(free)
    compliance = fm.compliance(lin, body_labels(nbeams))
    statics = turn(build_model(nbeams))
    if not statics.success:
        raise fm.ConvergenceError(statics.message)
    return {"compliance": compliance,
            "modes": fm.vibration_modes(lin, 4), "statics": statics,
            "curve": moment_curve(statics)}


def first_frequency_estimate() -> float:
    """``sqrt(2 EI/(L J))/(2 pi)`` [Hz] with ``J`` the body's rotary inertia and its two
    point masses at ``L/2`` from the axis (the leaves' own inertia, about 0.6 % of ``J``,
    left out)."""
    inertia = BODY_INERTIA + BODY_MASS * (LENGTH / 2) ** 2
    return math.sqrt(pivot_stiffness() / inertia) / (2 * math.pi)


def checks(found: dict) -> list[Check]:
    """The pivot against its closed forms (module docstring)."""
    angle, moment = found["curve"]
    C = found["compliance"]
    return [
        Check("stiffness about Z, 1/C_66 [N m/rad]", 1.0 / C[5, 5], pivot_stiffness(),
              rtol=1e-9),
        Check("first frequency [Hz]", found["modes"].frequencies[0],
              first_frequency_estimate(), rtol=1e-2),
        Check("initial slope of the moment [N m/rad]", moment[1] / angle[1],
              pivot_stiffness(), rtol=1e-3),
        Check("moment curve off a degree-6 polynomial", smoothness(angle, moment), 0.0,
              rtol=1e-6),
    ]


def describe(found: dict) -> None:
    """Print the stiffness, the frequencies and the moment-rotation table."""
    names = ["x", "y", "z", "theta_x", "theta_y", "theta_z"]
    print("stiffness of the body in each direction, the others free (1/C_ii) "
          "[N/m, N m/rad]:")
    for name, value in zip(names, 1.0 / np.diag(found["compliance"]), strict=True):
        print(f"  {name:>8}: {value:.6g}")
    frequencies = ", ".join(f"{f:.5g}" for f in found["modes"].frequencies)
    print(f"first frequencies [Hz]: {frequencies}")
    angle, moment = found["curve"]
    print(f"large rotation in {len(angle) - 1} load steps:")
    print(f"  {'angle [deg]':>12} {'moment [N m]':>14} {'secant [N m/rad]':>17}")
    for a, m in list(zip(angle, moment, strict=True))[::5]:
        print(f"  {math.degrees(a):>12.4f} {m:>14.6g} {m / a if a else pivot_stiffness():>17.6g}")


def main(argv: list[str] | None = None, prog: str | None = None) -> int:
    """Run the example with command-line arguments ``argv``; returns the exit code."""
    parser = example_parser(__doc__, prog)
    parser.add_argument("--nbeams", type=count(1), default=NBEAMS,
                        help=f"beams per leaf (default {NBEAMS})")
    add_output_options(parser, table=True)
    args = parse(parser, argv)
    found = analyse(args.nbeams)
    print(found["statics"].model.summary())
    if args.out:
        found["statics"].save(args.out)
        print(f"{len(found['statics'].load)} load steps written to {args.out}")
    describe(found)
    ok = print_checks("\nchecks:", checks(found))

    def draw(filename, window):
        angle, moment = found["curve"]
        linear = pivot_stiffness() * angle
        plot.plot_curves(np.degrees(angle), {"flexmbd": moment, "2 EI/L theta": linear},
                         xlabel="rotation [deg]", ylabel="moment [N m]",
                         title="cross-spring pivot: moment against rotation",
                         filename=filename, window=window)

    finish_outputs(args, found["statics"], draw, movie_title="cross-spring pivot: 30 degrees")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
